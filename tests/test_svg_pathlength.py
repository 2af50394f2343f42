"""pathLength against SVG 2: the author's length of a path or basic shape, which distances along
it are scaled by (SVG 2 paths, "The pathLength attribute"; painting, the stroke shape: dash
positions; text, text on a path: startOffset). The truth is the dash geometry computed here by
hand from the shapes' lengths, and equivalent documents without pathLength."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

from vecmsaa.api import render_svg_array

NS = 'xmlns="http://www.w3.org/2000/svg"'
FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")


def alpha(body, width=200, height=100):
    svg = f'<svg {NS} width="{width}" height="{height}">{body}</svg>'
    return render_svg_array(svg, mode="analytic")[..., 3].astype(np.int64)


LINE = '<path d="M 0 50 H 200" stroke="black" stroke-width="20" fill="none" {}/>'


@pytest.mark.parametrize("attrs, on, off", [
    # 200 user units of path, 4 author units: a dash of 1 is 50 units long
    ('pathLength="4" stroke-dasharray="1"', (25, 125), (75, 175)),
    # the offset is in author units too: 0.5 is 25 units
    ('pathLength="4" stroke-dasharray="1" stroke-dashoffset="0.5"', (10, 90, 110), (40, 60, 140)),
    # 2 author units: dashes 0.25 long are 25 units
    ('pathLength="2" stroke-dasharray="0.25 0.75"', (12, 112), (37, 62, 87, 137)),
    # zero: an infinite scale, the first dash covers the whole path (SVG 2: a positive length
    # becomes +infinity)
    ('pathLength="0" stroke-dasharray="1 1"', (5, 60, 110, 190), ()),
    # a negative pathLength is an error: no scaling, dashes of 50 user units
    ('pathLength="-4" stroke-dasharray="50"', (25, 125), (75, 175)),
    # and so is one that is no number
    ('pathLength="4px" stroke-dasharray="50"', (25, 125), (75, 175)),
])
def test_path_length_scales_dashes_on_a_path(attrs, on, off):
    a = alpha(LINE.format(attrs))
    for x in on:
        assert a[50, x] == 255, (x, a[50, ::5].tolist())
    for x in off:
        assert a[50, x] == 0, (x, a[50, ::5].tolist())


@pytest.mark.parametrize("d", ["M 10 10 L 10 10", "M 10 10 L 50 10"])
@pytest.mark.parametrize("path_length", ["2", "0", "1e-320", "1e300"])
def test_path_length_extremes_draw_as_their_dash_pattern_allows(d, path_length):
    """A zero-length path has no distance to scale (drawn as without pathLength); a scale
    past floats (pathLength 1e-320) or 0 makes the first dash cover the path: solid."""
    body = (f'<path d="{d}" {{}} stroke="black" stroke-width="6" stroke-linecap="butt" '
            f'stroke-dasharray="1" stroke-dashoffset="0.5"/>')
    got = alpha(body.format(f'pathLength="{path_length}"'), 60, 20)
    if d.endswith("10 10"):
        assert np.array_equal(got, alpha(body.format(""), 60, 20))
    elif path_length in ("0", "1e-320"):
        assert np.array_equal(got, alpha(body.format("").replace('stroke-dasharray="1"', ""),
                                         60, 20))
    else:
        assert got.any()


def test_path_length_on_a_rect():
    """SVG 2 gives basic shapes pathLength too. A 60 x 60 square from (20, 20) clockwise has
    240 units of perimeter: with pathLength 8, dashes of 1 are 30 units, so each side is half
    on (its first half), half off."""
    a = alpha('<rect x="20" y="20" width="60" height="60" pathLength="8" fill="none" '
              'stroke="black" stroke-width="6" stroke-dasharray="1"/>', 100, 100)
    assert a[20, 35] == 255 and a[20, 65] == 0          # top, left to right
    assert a[35, 80] == 255 and a[65, 80] == 0          # right, downwards
    assert a[80, 65] == 255 and a[80, 35] == 0          # bottom, right to left
    assert a[65, 20] == 255 and a[35, 20] == 0          # left, upwards


def test_path_length_on_a_circle():
    """A circle's path starts at (cx + r, cy) and runs clockwise (SVG 2 shapes). With
    pathLength 8 a dash of 1 spans an eighth of the circle: on from 0° to 45°, off to 90°..."""
    cx = cy = 50
    r = 40
    a = alpha(f'<circle cx="{cx}" cy="{cy}" r="{r}" pathLength="8" fill="none" '
              f'stroke="black" stroke-width="6" stroke-dasharray="1"/>', 100, 100)
    for k in range(8):
        t = math.radians(45 * k + 22.5)
        x, y = cx + r * math.cos(t), cy + r * math.sin(t)
        assert a[int(y), int(x)] == (255 if k % 2 == 0 else 0), k


def test_path_length_scales_dashes_of_a_use_and_leaves_plain_paths_alone():
    """The attribute is on the element: a <use> of the path keeps it, and so does a path
    among siblings with the same style (which are drawn together when nothing sets them
    apart); those siblings do not scale."""
    body = ('<defs><path id="p" d="M 0 20 H 200" pathLength="4"/></defs>'
            '<g stroke="black" stroke-width="10" stroke-dasharray="1" fill="none">'
            '<use href="#p"/><path d="M 0 60 H 200"/><path d="M 0 40 H 200" pathLength="4"/>'
            '<path d="M 0 80 H 200"/></g>')
    a = alpha(body)
    assert a[20, 25] == 255 and a[20, 75] == 0
    assert a[40, 25] == 255 and a[40, 75] == 0
    # dashes of one unit: half the pixels along the line covered
    assert abs(a[60, 10:190].mean() - 127.5) < 5 and abs(a[80, 10:190].mean() - 127.5) < 5


def _text(offset, path_length=None):
    pl = f' pathLength="{path_length}"' if path_length is not None else ""
    svg = (f'<svg {NS} width="300" height="100" font-family="Noto Sans" font-size="20">'
           f'<path id="p" d="M 20 60 H 220"{pl} fill="none"/>'
           f'<text><textPath href="#p" startOffset="{offset}">Hxg</textPath></text></svg>')
    return render_svg_array(svg, use_fonts_dir=FIXTURES, skip_system_fonts=True,
                            font_family="Noto Sans", mode="analytic")


def test_text_path_start_offset_in_path_length_units():
    """startOffset "adjusted due to any pathLength" (SVG 2 text on a path): 1 of 2 author
    units on a 200-unit path is 100 units; percentages are not scaled."""
    assert np.array_equal(_text("1", 2), _text("100"))
    assert np.array_equal(_text("0.5", 4), _text("25"))
    assert np.array_equal(_text("50%", 4), _text("50%"))
    assert not np.array_equal(_text("1", 2), _text("1"))


def test_text_path_start_offset_with_zero_path_length():
    """pathLength 0 scales by infinity: an offset of 0 stays at the start, any other puts the
    text off the path (not rendered)."""
    assert np.array_equal(_text("0", 0), _text("0"))
    assert _text("1", 0)[..., 3].max() == 0
    assert _text("-1", 0)[..., 3].max() == 0
