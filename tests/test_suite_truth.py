"""The computed exact references of vecmsaa.tools.suite_truth, checked against closed forms:
a butt-capped dash of a circle's stroke is an annulus sector of area (dash length) x (stroke
width); a rectangle's pixel coverage sums to its area; SVG's circle starts at (cx + r, cy) and
runs towards +y; and the pass criterion tells a one-unit dash phase error from the truth."""
import math

import numpy as np
import pytest

from vecmsaa.tools.compare import compare_images
from vecmsaa.tools.suite_truth import dashed_circle_coverage, exact_reference, rect_coverage


def ink_length(r, dashes, offset):
    """Total dash length along a circle of radius r, by walking the pattern (closed form)."""
    if len(dashes) % 2:
        dashes = tuple(dashes) * 2
    total, pos, i = 0.0, -(offset % sum(dashes)), 0
    end = 2 * math.pi * r
    while pos < end:
        d = dashes[i % len(dashes)]
        if i % 2 == 0:
            total += max(0.0, min(pos + d, end) - max(pos, 0.0))
        pos += d
        i += 1
    return total


@pytest.mark.parametrize("r,dashes,offset", [(60, (10, 20), 0), (70, (10, 20), 15),
                                             (70, (30, 20, 10, 30, 20, 10), 0), (50, (7,), 3)])
def test_dashed_circle_area_is_dash_length_times_width(r, dashes, offset):
    scale = 1.5
    cov = dashed_circle_coverage(100, 100, r, 10, dashes, offset, scale, 300, 300)
    expected = ink_length(r, dashes, offset) * 10 * scale * scale
    assert cov.sum() == pytest.approx(expected, rel=2e-3)


def test_circle_dashes_start_at_cx_plus_r_and_run_towards_positive_y():
    cov = dashed_circle_coverage(100, 100, 60, 10, (10, 20), 0, 1.0, 200, 200)
    assert cov[104, 160] == 1.0         # 4 units along the path: in the first dash
    assert cov[95, 160] == 0.0          # 5 units before its end (372 of 377): in a gap


def test_rect_coverage_sums_to_area():
    cov = rect_coverage(112.5, 112.5, 187.5, 187.25, 300, 300)
    assert cov.sum() == pytest.approx(75 * 74.75)
    assert cov[112, 150] == 0.5 and cov[187, 150] == 0.25 and cov[150, 150] == 1


def test_one_unit_of_dash_phase_fails_the_criterion():
    def image(offset):
        a = np.zeros((300, 300, 4), np.uint8)
        a[..., 1] = 128
        a[..., 3] = np.round(255 * dashed_circle_coverage(100, 100, 70, 10, (10, 20), offset,
                                                          1.5, 300, 300))
        return a
    assert compare_images(image(15), image(15)).passed()
    assert not compare_images(image(16), image(15)).passed()


def test_frame_and_colours():
    img = exact_reference("structure/use/href-precedence-over-xlink", 300, 300)
    assert tuple(img[150, 150]) == (0, 128, 0, 255)
    assert tuple(img[1, 150]) == (0, 0, 0, 255)       # frame stroke: 0.75..2.25 px
    assert img[150, 20, 3] == 0
    assert exact_reference("shapes/rect/simple-case", 300, 300) is None
