"""The computed exact references of vecmsaa.tools.suite_truth, checked against closed forms:
a rectangle's pixel coverage sums to its area."""
import pytest

from vecmsaa.tools.suite_truth import exact_reference, rect_coverage


def test_rect_coverage_sums_to_area():
    cov = rect_coverage(112.5, 112.5, 187.5, 187.25, 300, 300)
    assert cov.sum() == pytest.approx(75 * 74.75)
    assert cov[112, 150] == 0.5 and cov[187, 150] == 0.25 and cov[150, 150] == 1


def test_frame_and_colours():
    img = exact_reference("structure/use/href-precedence-over-xlink", 300, 300)
    assert tuple(img[150, 150]) == (0, 128, 0, 255)
    assert tuple(img[1, 150]) == (0, 0, 0, 255)       # frame stroke: 0.75..2.25 px
    assert img[150, 20, 3] == 0
    assert exact_reference("shapes/rect/simple-case", 300, 300) is None
