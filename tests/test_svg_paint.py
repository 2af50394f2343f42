"""Paint servers and compositing against the specifications' formulas, computed here by hand
(Compositing and Blending 1, SVG 2 paint servers, CSS Transforms 1): rendered pixels of flat
regions, away from edges."""
from __future__ import annotations

import numpy as np
import pytest

from vecmsaa.api import render_svg_array

NS = 'xmlns="http://www.w3.org/2000/svg"'


def render(body, width=100, height=100):
    return render_svg_array(f'<svg {NS} width="{width}" height="{height}">{body}</svg>'
                            ).astype(np.float64)


# -- mix-blend-mode: Compositing and Blending Level 1, section 10 ------------------------------
def _soft_light(cb, cs):
    if cs <= 0.5:
        return cb - (1 - 2 * cs) * cb * (1 - cb)
    d = ((16 * cb - 12) * cb + 4) * cb if cb <= 0.25 else cb ** 0.5
    return cb + (2 * cs - 1) * (d - cb)


def _hard_light(cb, cs):
    return cb * 2 * cs if cs <= 0.5 else cb + (2 * cs - 1) - cb * (2 * cs - 1)


SEPARABLE = {
    "normal": lambda cb, cs: cs,
    "multiply": lambda cb, cs: cb * cs,
    "screen": lambda cb, cs: cb + cs - cb * cs,
    "overlay": lambda cb, cs: _hard_light(cs, cb),
    "darken": min,
    "lighten": max,
    "color-dodge": lambda cb, cs: 0.0 if cb == 0 else (1.0 if cs == 1 else min(1, cb / (1 - cs))),
    "color-burn": lambda cb, cs: 1.0 if cb == 1 else (0.0 if cs == 0 else
                                                       1 - min(1, (1 - cb) / cs)),
    "hard-light": _hard_light,
    "soft-light": _soft_light,
    "difference": lambda cb, cs: abs(cb - cs),
    "exclusion": lambda cb, cs: cb + cs - 2 * cb * cs,
}


def _lum(c):
    return 0.3 * c[0] + 0.59 * c[1] + 0.11 * c[2]


def _clip(c):
    lum, n, x = _lum(c), min(c), max(c)
    if n < 0:
        c = [lum + (v - lum) * lum / (lum - n) for v in c]
    if x > 1:
        c = [lum + (v - lum) * (1 - lum) / (x - lum) for v in c]
    return c


def _set_lum(c, lum):
    d = lum - _lum(c)
    return _clip([v + d for v in c])


def _set_sat(c, s):
    mx, mn = max(c), min(c)
    return [0.0 if mx == mn else (v - mn) * s / (mx - mn) for v in c]


def _sat(c):
    return max(c) - min(c)


NON_SEPARABLE = {
    "hue": lambda cb, cs: _set_lum(_set_sat(cs, _sat(cb)), _lum(cb)),
    "saturation": lambda cb, cs: _set_lum(_set_sat(cb, _sat(cs)), _lum(cb)),
    "color": lambda cb, cs: _set_lum(cs, _lum(cb)),
    "luminosity": lambda cb, cs: _set_lum(cb, _lum(cs)),
}


def blended(mode, cb, cs, alpha):
    """An opaque backdrop cb under a source cs of opacity alpha (section 5.1 with an opaque
    backdrop: Cr = (1 - αs)·Cb + αs·B(Cb, Cs))."""
    cb = [v / 255 for v in cb]
    cs = [v / 255 for v in cs]
    if mode in NON_SEPARABLE:
        mix = NON_SEPARABLE[mode](cb, cs)
    else:
        mix = [SEPARABLE[mode](b, s) for b, s in zip(cb, cs)]
    return [255 * ((1 - alpha) * b + alpha * m) for b, m in zip(cb, mix)]


@pytest.mark.parametrize("mode", list(SEPARABLE) + list(NON_SEPARABLE))
@pytest.mark.parametrize("cb, cs, alpha", [
    ((200, 30, 120), (90, 60, 200), 1.0),
    ((20, 180, 240), (240, 200, 10), 0.6),
    ((128, 128, 128), (255, 64, 0), 1.0),
])
def test_blend_modes_follow_the_compositing_formulas(mode, cb, cs, alpha):
    img = render(f'<rect width="100" height="100" fill="rgb{cb}"/>'
                 f'<rect x="50" width="50" height="100" fill="rgb{cs}" fill-opacity="{alpha}" '
                 f'style="mix-blend-mode: {mode}"/>')
    assert img[50, 25, :3] == pytest.approx(cb, abs=1)           # the backdrop alone
    assert img[50, 75, :3] == pytest.approx(blended(mode, cb, cs, alpha), abs=2)
    assert img[50, 75, 3] == 255


def test_isolated_group_blends_with_nothing_below_it():
    # Compositing 1 section 3.2: an isolated group's backdrop is transparent, and a source
    # over a transparent backdrop is the source whatever the mode.
    body = ('<rect width="100" height="100" fill="rgb(200,30,120)"/>'
            '<g style="isolation: {}"><rect width="100" height="100" fill="rgb(90,60,200)" '
            'style="mix-blend-mode: difference"/></g>')
    assert render(body.format("isolate"))[50, 50, :3] == pytest.approx((90, 60, 200), abs=1)
    assert render(body.format("auto"))[50, 50, :3] == pytest.approx((110, 30, 80), abs=1)


# -- gradients ---------------------------------------------------------------------------------
def test_gradient_href_chain_takes_each_attribute_from_the_nearest_element():
    # SVG 2 14.2: an attribute the element lacks comes from the referenced element, through
    # the whole chain; stops come from the first element that has any. Here c takes y2 from
    # b, spreadMethod and the stops from a: a vertical ramp over y in [0, 50], reflected.
    img = render('<linearGradient id="a" x2="0" y2="1" spreadMethod="reflect">'
                 '<stop offset="0" stop-color="black"/><stop offset="1" stop-color="white"/>'
                 '</linearGradient><linearGradient id="b" href="#a" y2="0.5"/>'
                 '<linearGradient id="c" href="#b"/>'
                 '<rect width="100" height="100" fill="url(#c)"/>')
    for y in (5, 20, 45, 55, 80, 95):
        t = (y + 0.5) / 50
        t = t if t <= 1 else 2 - t
        assert img[y, 10, 0] == pytest.approx(255 * t, abs=2)
        assert img[y, 90, 0] == pytest.approx(img[y, 10, 0], abs=1)


@pytest.mark.parametrize("link", ['href', 'xmlns:xlink="http://www.w3.org/1999/xlink" xlink:href'])
@pytest.mark.parametrize("kind", ["linearGradient", "radialGradient"])
def test_gradient_transform_comes_through_href(link, kind):
    """SVG 2 14.2.2 (linearGradient's href): the attributes copied from the template are x1,
    y1, x2, y2, gradientTransform, gradientUnits and spreadMethod, from a linear or a radial
    template. a runs its ramp down y from 0 to 0.5 of the box; rotate(90) about the box's
    origin (x, y) -> (-y, x) turns it to run along -x from x = 0 to -0.5. b takes that
    transform, and sets reflect: at x (pixel centre) t = -2 (x + 0.5) / 100, reflected into
    [0, 1]: a horizontal ramp, black at x = 0, white at 50, black at 100, the same in every
    row (without the transform it would be vertical)."""
    img = render(f'<linearGradient id="a" x1="0" y1="0" x2="0" y2="0.5" '
                 'gradientTransform="rotate(90)"><stop offset="0" stop-color="black"/>'
                 '<stop offset="1" stop-color="white"/></linearGradient>'
                 f'<{kind} id="b" {link}="#a" spreadMethod="reflect"/>'
                 '<rect width="100" height="100" fill="url(#b)"/>')
    if kind == "radialGradient":
        # coordinates come from gradients of the same kind only: b is the default circle
        # (centre (0.5, 0.5), r 0.5) turned about the box origin to centre (-0.5, 0.5)
        for x, y in ((10, 50), (40, 20), (70, 90)):
            d = np.hypot((x + 0.5) / 100 + 0.5, (y + 0.5) / 100 - 0.5) / 0.5
            t = d % 2 if d % 2 <= 1 else 2 - d % 2
            assert img[y, x, 0] == pytest.approx(255 * t, abs=2)
        return
    for x in (5, 20, 45, 55, 80, 95):
        t = abs(-2 * (x + 0.5) / 100)
        t = t if t <= 1 else 2 - t
        for y in (10, 50, 90):
            assert img[y, x, 0] == pytest.approx(255 * t, abs=2)


def test_own_gradient_transform_overrides_the_template():
    # an element that defines the attribute keeps its own (here the identity): a vertical ramp
    img = render('<linearGradient id="a" x2="0" y2="1" gradientTransform="rotate(90)">'
                 '<stop offset="0" stop-color="black"/><stop offset="1" stop-color="white"/>'
                 '</linearGradient><linearGradient id="b" href="#a" gradientTransform="scale(1)"/>'
                 '<rect width="100" height="100" fill="url(#b)"/>')
    for y in (10, 50, 90):
        assert img[y, 20, 0] == pytest.approx(255 * (y + 0.5) / 100, abs=2)
        assert img[y, 80, 0] == pytest.approx(img[y, 20, 0], abs=1)


def test_pattern_transform_comes_through_href():
    """SVG 2 14.3 (pattern's href): patternTransform is one of the attributes copied from the
    template, with x, y, width, height and the tile's content. a's 20x20 tile is blue in its
    left half; translate(10) moves the tile's origin to x = 10, so b is blue where
    (x - 10) mod 20 < 10: pixels 10-19, 30-39, ... and green in 0-9, 20-29, ..."""
    img = render('<pattern id="a" patternUnits="userSpaceOnUse" width="20" height="20" '
                 'patternTransform="translate(10)"><rect width="10" height="20" fill="#00f"/>'
                 '<rect x="10" width="10" height="20" fill="#0f0"/></pattern>'
                 '<pattern id="b" href="#a"/><rect width="100" height="100" fill="url(#b)"/>')
    for x in range(2, 100, 5):
        want = (0, 0, 255) if (x - 10) % 20 < 10 else (0, 255, 0)
        assert (img[50, x, :3] == want).all(), x


@pytest.mark.parametrize("pattern_attrs, sheet, shift", [
    ('style="transform: translate(10px)"', "", 10),
    ('patternTransform="translate(5)" style="transform: translate(10px)"', "", 10),
    ('patternTransform="translate(5)"', "#a { transform: translate(10px) }", 10),
    ('patternTransform="translate(10)" style="transform: none"', "", 0),
    ('transform="translate(10)"', "", 0),
])
def test_css_transform_property_is_the_pattern_transform(pattern_attrs, sheet, shift):
    """SVG 2 (the transform presentation attribute): patternTransform is the pattern's
    presentation attribute for the CSS transform property, so a style attribute or sheet
    overrides it (also through href, b using a's) and `none` removes it; the `transform`
    attribute is no presentation attribute there. a's 20x20 tile is blue in its left half:
    moved by ``shift``, b is blue where (x - shift) mod 20 < 10, green elsewhere."""
    img = render(f'<style>{sheet}</style>'
                 f'<pattern id="a" patternUnits="userSpaceOnUse" width="20" height="20" '
                 f'{pattern_attrs}><rect width="10" height="20" fill="#00f"/>'
                 '<rect x="10" width="10" height="20" fill="#0f0"/></pattern>'
                 '<pattern id="b" href="#a"/><rect width="100" height="100" fill="url(#b)"/>')
    for x in range(2, 100, 5):
        want = (0, 0, 255) if (x - shift) % 20 < 10 else (0, 255, 0)
        assert (img[50, x, :3] == want).all(), x


@pytest.mark.parametrize("viewbox, drawn", [("0 0 10 0", False), ("0 0 0 10", False),
                                            ("0 0 0 0", False), ("0 0 -10 10", True),
                                            ("0 0 10 -0", False)])
def test_pattern_viewbox_of_zero_size_disables_it(viewbox, drawn):
    """SVG 2 viewBox: a zero width or height disables rendering, so the paint's fallback
    applies (green, or nothing without one); a negative one is an error that only voids the
    attribute, and the 20-unit tile's 10-unit blue square is drawn as without a viewBox:
    blue where x mod 20 < 10 and y mod 20 < 10."""
    img = render(f'<pattern id="p" patternUnits="userSpaceOnUse" width="20" height="20" '
                 f'viewBox="{viewbox}"><rect width="10" height="10" fill="#00f"/></pattern>'
                 '<rect width="50" height="100" fill="url(#p) #008000"/>'
                 '<rect x="50" width="50" height="100" fill="url(#p)"/>')
    for y in range(2, 100, 5):
        for x in range(2, 100, 5):
            if drawn:
                want = (0, 0, 255, 255) if x % 20 < 10 and y % 20 < 10 else (0, 0, 0, 0)
            else:
                want = (0, 128, 0, 255) if x < 50 else (0, 0, 0, 0)
            assert tuple(img[y, x]) == want, (x, y)


@pytest.mark.parametrize("offsets, colour_at", [
    # SVG 2 14.3.4: offsets clamp to [0, 1], and one below its predecessor takes the
    # predecessor's value
    (("-0.5", "0.5", "1.5"), lambda t: (255 * max(0, 1 - t / 0.5), 255 * min(1, t / 0.5), 0)
     if t < 0.5 else (0, 255 * (1 - (t - 0.5) / 0.5), 255 * (t - 0.5) / 0.5)),
    (("60%", "0.2", "1"), lambda t: (255, 0, 0) if t < 0.6 else
     (0, 255 * (1 - (t - 0.6) / 0.4), 255 * (t - 0.6) / 0.4)),
])
def test_stop_offsets_are_clamped_and_never_decrease(offsets, colour_at):
    a, b, c = offsets
    img = render(f'<linearGradient id="g"><stop offset="{a}" stop-color="rgb(255,0,0)"/>'
                 f'<stop offset="{b}" stop-color="rgb(0,255,0)"/>'
                 f'<stop offset="{c}" stop-color="rgb(0,0,255)"/></linearGradient>'
                 '<rect width="100" height="100" fill="url(#g)"/>')
    for x in (10, 30, 45, 58, 70, 85, 97):
        assert img[50, x, :3] == pytest.approx(colour_at((x + 0.5) / 100), abs=2), x


@pytest.mark.parametrize("offset, value", [
    ("50%", 0.5), ("+.5", 0.5), ("5e-1", 0.5), ("5E1%", 0.5),
    # attributes take CSS syntax (SVG 2), which allows whitespace around a value
    (" 0.5", 0.5), ("0.5 ", 0.5), ("\t50%\n", 0.5),
    # not a <number> or a <percentage>: invalid, so the initial value 0
    ("50 %", 0.0), ("0.5px", 0.0), ("half", 0.0), ("0.5.", 0.0), ("", 0.0),
])
def test_stop_offset_is_a_number_or_a_percentage(offset, value):
    img = render('<linearGradient id="g"><stop offset="0" stop-color="rgb(255,0,0)"/>'
                 f'<stop offset="{offset}" stop-color="rgb(0,255,0)"/>'
                 '<stop offset="1" stop-color="rgb(0,0,255)"/></linearGradient>'
                 '<rect width="100" height="100" fill="url(#g)"/>')
    t = 24.5 / 100
    want = ((255 * (1 - t / value), 255 * t / value, 0) if value else
            (0, 255 * (1 - t), 255 * t))
    assert img[50, 24, :3] == pytest.approx(want, abs=2)


def test_stop_color_current_color_is_the_stops_and_inherit_the_gradients():
    # stop-color is not inherited: "inherit" takes the gradient element's value (its parent),
    # not the painted element's; currentColor is the stop's own 'color', which inherits.
    img = render('<linearGradient id="g" stop-color="rgb(0,0,255)" color="rgb(0,255,0)">'
                 '<stop offset="0" stop-color="inherit"/>'
                 '<stop offset="0.5" stop-color="inherit"/>'
                 '<stop offset="0.5" stop-color="currentColor"/>'
                 '<stop offset="1" stop-color="currentColor" color="rgb(255,0,0)"/>'
                 '</linearGradient><g stop-color="black" color="black">'
                 '<rect width="100" height="100" fill="url(#g)"/></g>')
    assert img[50, 20, :3] == pytest.approx((0, 0, 255), abs=1)
    u = (75.5 - 50) / 50                            # from the third stop to the fourth
    assert img[50, 75, :3] == pytest.approx((255 * u, 255 * (1 - u), 0), abs=2)


@pytest.mark.parametrize("units, equivalent", [
    ("rotate(0.25turn)", "rotate(90)"), ("rotate(100grad)", "rotate(90)"),
    ("skewX(0.5rad)", "skewX(28.64788976)"), ("translate(10px) scale(50%)",
                                                "translate(10) scale(0.5)"),
    ("skew(30)", "skewX(30)"), ("translateX(10)", "translate(10)"),
    ("translate(10),,scale(0.5)", "translate(10),scale(0.5)"),
    (",translate(10)", "translate(10)"),
])
def test_paint_transform_attributes_have_svgs_grammar(units, equivalent):
    """gradientTransform and patternTransform take SVG's transform grammar: units, CSS-only
    functions, two commas between functions and a leading one make the list malformed, so the
    paint is drawn untransformed (resvg 0.48.1 and Chromium 150 both; CSS Transforms 1 would
    let the attributes take the property's syntax, neither renderer does)."""
    def draw(t):
        return render(f'<linearGradient id="g" gradientTransform="{t}" spreadMethod="reflect">'
                      '<stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/>'
                      '</linearGradient><pattern id="p" width="20" height="30" '
                      f'patternUnits="userSpaceOnUse" patternTransform="{t}">'
                      '<rect width="10" height="10" fill="green"/></pattern>'
                      '<rect width="100" height="50" fill="url(#g)"/>'
                      '<rect y="50" width="100" height="50" fill="url(#p)"/>')
    assert np.array_equal(draw(units), draw(""))
    assert not np.array_equal(draw(equivalent), draw(""))


# -- patterns ----------------------------------------------------------------------------------
@pytest.mark.parametrize("par, sx, sy, tx, ty", [
    # viewBox 0 0 20 20 into a 60 x 40 tile (SVG 2 8.2, the viewBox-to-viewport transform)
    ("xMinYMin meet", 2, 2, 0, 0),
    ("xMaxYMax meet", 2, 2, 20, 0),
    ("xMidYMid meet", 2, 2, 10, 0),
    ("xMidYMid slice", 3, 3, 0, -10),
    ("xMinYMax slice", 3, 3, 0, -20),
    ("none", 3, 2, 0, 0),
])
def test_pattern_viewbox_maps_by_preserve_aspect_ratio(par, sx, sy, tx, ty):
    # Content outside the viewBox but inside the tile shows (the tile is the clip), so a
    # yellow frame around the viewBox shows where "meet" leaves room.
    img = render('<pattern id="p" patternUnits="userSpaceOnUse" width="60" height="40" '
                 f'viewBox="0 0 20 20" preserveAspectRatio="{par}">'
                 '<rect x="-10" y="-10" width="40" height="40" fill="yellow"/>'
                 '<rect width="10" height="10" fill="lime"/>'
                 '<rect x="10" y="10" width="10" height="10" fill="blue"/></pattern>'
                 '<rect width="120" height="80" fill="url(#p)"/>', 120, 80)
    checked = 0
    for py in range(80):
        for px in range(120):
            u = ((px % 60 + 0.5 - tx) / sx, (py % 40 + 0.5 - ty) / sy)
            # skip pixels within a pixel of a region's edge in the tile
            edges = [tx + sx * e for e in (-10, 0, 10, 20, 30)], [ty + sy * e for e in
                                                                (-10, 0, 10, 20, 30)]
            if (min(abs(px % 60 + 0.5 - e) for e in edges[0]) < 1.5 or
                    min(abs(py % 40 + 0.5 - e) for e in edges[1]) < 1.5):
                continue
            if 0 <= u[0] < 10 and 0 <= u[1] < 10:
                want = (0, 255, 0, 255)
            elif 10 <= u[0] < 20 and 10 <= u[1] < 20:
                want = (0, 0, 255, 255)
            elif -10 <= u[0] < 30 and -10 <= u[1] < 30:
                want = (255, 255, 0, 255)
            else:
                want = (0, 0, 0, 0)
            got = img[py, px] if want[3] else img[py, px, 3:]
            assert got == pytest.approx(want if want[3] else (0,), abs=1), (px, py)
            checked += 1
    assert checked > 3000




def test_an_arc_ending_where_it_starts_is_a_zero_length_segment():
    # SVG omits the arc, but the subpath has a drawing command, so it is a zero-length
    # subpath: a round cap is a disc of the stroke's radius (SVG 2 stroke-linecap), and the
    # segment's end is a marker vertex, so the path has a start, two mids and an end
    img = render('<path d="M30 30 A10 10 0 0 0 30 30" stroke="black" stroke-width="20" '
                 'stroke-linecap="round"/>')
    area = img[..., 3].sum() / 255
    assert area == pytest.approx(np.pi * 10 ** 2, rel=0.01)
    assert img[30, 30, 3] == 255 and img[30, 42, 3] == 0 and img[18, 30, 3] == 0
    img = render('<marker id="m" markerWidth="4" markerHeight="4" refX="2" refY="2" '
                 'markerUnits="userSpaceOnUse"><rect width="4" height="4" fill-opacity="0.5"/>'
                 '</marker><path d="M10 50 L50 50 A5 5 0 0 0 50 50 L90 50" fill="none" '
                 'marker-start="url(#m)" marker-mid="url(#m)" marker-end="url(#m)"/>')
    # two half-transparent marks at the middle vertex: 1 - 0.5 * 0.5
    assert img[49, 49, 3] == pytest.approx(0.75 * 255, abs=1)
    assert img[49, 9, 3] == pytest.approx(0.5 * 255, abs=1)

@pytest.mark.parametrize("x, y, w, h, cx, cy, r", [
    (4, -1, 7, 15, 5, 5, 4),           # a circle cut by the tile's right edge
    (0, 0, 9, 6, 4.5, 3, 2.7),
    (3, 2, 5, 5, 2.5, 2.5, 2.5),
])
def test_small_pattern_tiles_have_exact_coverage(x, y, w, h, cx, cy, r):
    # Every pixel is a copy of one texel of the tile (whole-pixel tiles at scale 1, the tile's
    # corner on a pixel corner), so each must be the area of the circle in that texel,
    # computed here by supersampling the circle 64 x 64 per texel. A tile's texel error repeats
    # in every copy, so the default 8 samples (1/8 = 32 levels per sample) would be far off.
    img = render(f'<pattern id="p" patternUnits="userSpaceOnUse" x="{x}" y="{y}" '
                 f'width="{w}" height="{h}"><circle cx="{cx}" cy="{cy}" r="{r}"/></pattern>'
                 '<rect width="200" height="200" fill="url(#p)"/>', 200, 200)
    n = 64
    sy, sx = np.mgrid[0:h * n, 0:w * n]
    inside = ((sx + 0.5) / n - cx) ** 2 + ((sy + 0.5) / n - cy) ** 2 <= r * r
    texel = inside.reshape(h, n, w, n).mean(axis=(1, 3)) * 255
    py, px = np.mgrid[0:200, 0:200]
    want = texel[(py - y) % h, (px - x) % w]
    assert np.abs(img[..., 3] - want).max() <= 8


def test_only_small_tiles_of_the_multisample_modes_take_the_reference_mode():
    from vecmsaa.raster.render import EXACT_TILE_PIXELS, RenderOptions, tile_options

    opts = RenderOptions("approx", 8)
    assert tile_options(opts, 7, 15).mode == "reference"
    assert tile_options(opts, 7, 15) is tile_options(opts, 20, 20)   # made once per render
    assert tile_options(opts, EXACT_TILE_PIXELS + 1, 1) is opts
    for mode in ("none", "alpha", "analytic"):
        own = RenderOptions(mode, 1 if mode != "alpha" else 8)
        assert tile_options(own, 7, 15) is own

def test_a_reference_to_an_id_given_twice_takes_the_first_element():
    # URL fragments resolve to the first element in tree order with the id (SVG 2 linking,
    # as in the DOM's getElementById)
    img = render('<linearGradient id="g"><stop stop-color="rgb(0,128,0)"/></linearGradient>'
                 '<linearGradient id="g"><stop stop-color="red"/></linearGradient>'
                 '<pattern id="p" width="10" height="10" patternUnits="userSpaceOnUse">'
                 '<rect width="10" height="10" fill="blue"/></pattern>'
                 '<pattern id="p" width="10" height="10" patternUnits="userSpaceOnUse">'
                 '<rect width="10" height="10" fill="red"/></pattern>'
                 '<rect width="100" height="50" fill="url(#g)"/>'
                 '<rect y="50" width="100" height="50" fill="url(#p)"/>')
    assert img[25, 50, :3] == pytest.approx((0, 128, 0), abs=1)
    assert img[75, 50, :3] == pytest.approx((0, 0, 255), abs=1)


def test_context_paint_keeps_its_colours_alpha():
    # The context element's fill paint is the colour rgba(0, 0, 255, 0.4), alpha and all (CSS
    # Color 4: the alpha is part of the <color>); its fill-opacity is not part of the paint.
    img = render('<marker id="m" markerWidth="20" markerHeight="20" refX="10" refY="10" '
                 'markerUnits="userSpaceOnUse"><rect width="20" height="20" '
                 'fill="context-fill"/></marker>'
                 '<path d="M 10 80 L 50 80 L 90 80" fill="rgba(0, 0, 255, 0.4)" '
                 'fill-opacity="0.5" stroke="none" marker-mid="url(#m)"/>')
    assert img[80, 50, 2] == 255
    assert img[80, 50, 3] == pytest.approx(0.4 * 255, abs=1)


@pytest.mark.parametrize("prop, child", [
    ('stroke-width="1em"', 'stroke-width="inherit"'), ('stroke-width="2ex"', ''),
    ('style="stroke-width: 1em"', ''), ('stroke-dasharray="1em"', 'stroke-width="10"')])
def test_em_lengths_inherit_as_the_parents_absolute_length(prop, child):
    # CSS Values 4 §6.1.1: em and ex are computed to absolute lengths where specified, and the
    # computed value is what children inherit; the group's font size is 10 px, the line's 40:
    # the stroke is 10 px wide (rows 45-54) and a dashed line is on for 10 px, off for 10 px
    img = render(f'<g {prop} font-size="10"><line x1="0" y1="50" x2="100" y2="50" '
                 f'stroke="black" font-size="40" {child}/></g>')
    rows = np.nonzero(img[:, 5, 3] > 127)[0]
    assert rows.min() == 45 and rows.max() == 54
    cols = np.nonzero(img[50, :, 3] > 127)[0]
    if "dasharray" in prop:
        assert list(cols) == [x for x in range(100) if x % 20 < 10]
    else:
        assert len(cols) == 100


def test_letter_spacing_in_em_inherits_as_the_parents_absolute_length():
    # letter-spacing 0.5em on a group of font size 10 is 5 px in a text of font size 20:
    # the same text as letter-spacing="5", not as letter-spacing="10"
    text = '<text x="5" y="60" font-family="Noto Sans" font-size="20" {}>Ab cd</text>'
    inherited = render(f'<g letter-spacing="0.5em" font-size="10">{text.format("")}</g>')
    assert np.array_equal(inherited, render(text.format('letter-spacing="5"')))
    assert not np.array_equal(inherited, render(text.format('letter-spacing="10"')))


def test_context_fill_pattern_keeps_the_use_elements_cells_under_a_child_transform():
    # SVG 2 (context-fill): a paint server referenced through a context paint is in the
    # context element's (the use's) user space (as the web platform test
    # svg/painting/reftests/paint-context-008 draws it), so the child's scale(0.8) does not move the
    # 10-unit cells: at 1.5 px a unit every cell is 15 whole pixels and each pixel inside the
    # rect is one cell's colour exactly (resvg resamples a tile drawn at the child's scale and
    # bleeds up to 95% of a neighbouring cell into some rows)
    svg = ('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
           'viewBox="0 0 200 200"><pattern id="p" patternUnits="userSpaceOnUse" width="20" height="20">'
           '<rect width="10" height="10" fill="grey"/><rect x="10" y="10" width="10" height="10" '
           'fill="green"/></pattern><defs><g id="g"><rect x="50" y="50" width="100" height="100" '
           'transform-origin="100 100" transform="scale(0.8)" fill="context-fill"/></g></defs>'
           '<use xlink:href="#g" fill="url(#p)"/></svg>')
    img = render_svg_array(svg.encode(), width=300).astype(int)
    # the rect is 60..140 units: pixels 90..210, cells of 15 px
    ys, xs = np.mgrid[90:210, 90:210]
    col, row = xs // 15, ys // 15
    want = np.zeros((120, 120, 4), int)
    want[(col % 2 == 0) & (row % 2 == 0)] = (128, 128, 128, 255)
    want[(col % 2 == 1) & (row % 2 == 1)] = (0, 128, 0, 255)
    got = img[90:210, 90:210]
    assert np.abs(got - want).max() <= 1


@pytest.mark.parametrize("attrs", ['width="10" height="10" patternTransform="matrix(1e308 0 0 1e308 0 0)"',
                                   'width="1e38" height="10" patternTransform="scale(1e10)"'])
def test_pattern_tile_beyond_f32_is_not_drawn(attrs):
    """A tile whose pixel size overflows f32 (resvg's precision) has no size: the paint draws
    nothing instead of raising OverflowError (found by the session 13 attribute sweep)."""
    img = render(f'<pattern id="p" patternUnits="userSpaceOnUse" {attrs}>'
                 '<rect width="5" height="5" fill="red"/></pattern>'
                 '<rect width="40" height="40" fill="url(#p)"/>')
    assert not img[..., 3].any()


# -- paint-server and masking attributes (session 14) -------------------------------------------
RAMP = '<stop offset="0" stop-color="#000"/><stop offset="1" stop-color="#fff"/>'


@pytest.mark.parametrize("units, user", [("userSpaceOnUse", True), (" userSpaceOnUse", False),
                                         ("userSpaceOnUse ", False), ("userspaceonuse", False),
                                         ("objectBoundingBox", False)])
def test_gradient_units_keyword_is_matched_exactly(units, user):
    """gradientUnits is an attribute, not a property: its keywords match exactly (no CSS
    whitespace trimming or case folding), anything else is the default objectBoundingBox.
    x2="1" is then one user unit (a step to white) or the box's width (a ramp)."""
    img = render(f'<linearGradient id="g" gradientUnits="{units}" x2="1">{RAMP}</linearGradient>'
                 '<rect width="100" height="10" fill="url(#g)"/>', height=10)
    # pixel 50's centre is 50.5 units, a fraction 0.505 of the box
    want = 255 if user else 0.505 * 255
    assert abs(img[5, 50, 0] - want) <= 1.5


@pytest.mark.parametrize("attr, value, inside", [
    ("clipPathUnits", "objectBoundingBox", True), ("clipPathUnits", " objectBoundingBox", False),
    ("maskContentUnits", "objectBoundingBox", True), ("maskContentUnits", "objectBoundingBox ", False)])
def test_clip_and_mask_units_keywords_are_matched_exactly(attr, value, inside):
    """A rect of 0.5 x 1 units covers the left half of a 100 x 10 box in bounding-box units,
    and half a unit of it in user space (an invalid keyword is the default userSpaceOnUse)."""
    content = '<rect width="0.5" height="1" fill="white"/>'
    el = (f'<clipPath id="c" {attr}="{value}">{content}</clipPath>' if attr == "clipPathUnits"
          else f'<mask id="c" {attr}="{value}">{content}</mask>')
    ref = "clip-path" if attr == "clipPathUnits" else "mask"
    img = render(el + f'<rect width="100" height="10" fill="#00f" {ref}="url(#c)"/>', height=10)
    assert img[5, 25, 3] == (255 if inside else 0)
    assert img[5, 75, 3] == 0


@pytest.mark.parametrize("value, boxes", [("2mm", 2 * 96 / 25.4), ("0.1in", 9.6), ("50%", 0.5),
                                          ("0.5", 0.5), ("3px", 3.0)])
def test_bounding_box_units_take_lengths_as_user_units(value, boxes):
    """In objectBoundingBox units a percentage is a fraction of the box and a length is its
    number of user units in the unit box (2mm = 7.559 boxes), as in browsers' length
    resolution: the ramp from x1 = 0 to x2 = value puts pixel 50 (0.505 boxes) at
    0.505 / boxes of the way."""
    img = render(f'<linearGradient id="g" x2="{value}">{RAMP}</linearGradient>'
                 '<rect width="100" height="10" fill="url(#g)"/>', height=10)
    assert abs(img[5, 50, 0] - 255 * min(1.0, 0.505 / boxes)) <= 1.5


def test_mask_region_in_bounding_box_units_takes_lengths_as_user_units():
    """x="0.1mm" on a mask in objectBoundingBox units is 0.378 boxes, not 0.1: the region
    of a 100-unit-wide box starts at 37.8."""
    img = render('<mask id="m" x="0.1mm" y="0" width="2" height="1">'
                 '<rect width="100" height="10" fill="white"/></mask>'
                 '<rect width="100" height="10" fill="#00f" mask="url(#m)"/>', height=10)
    assert img[5, 36, 3] == 0 and img[5, 39, 3] == 255


def test_gradient_transform_origin_in_bounding_box_units():
    """transform-origin resolves as on any element (percentages of the viewport, CSS
    transform-box: view-box), and in objectBoundingBox units the point is one of the unit
    box: "50% 0" in a 100-wide viewport is x = 50 boxes. scale(2) about it maps gradient x to
    box x = 2x - 50, so the box (x in 0..1) sees gradient x about 25: past x2 = 1, white."""
    img = render('<linearGradient id="g" gradientTransform="scale(2)" transform-origin="50% 0">'
                 f'{RAMP}</linearGradient><rect width="100" height="10" fill="url(#g)"/>',
                 height=10)
    assert (img[5, ::10, :3] == 255).all()


def test_pattern_content_percentages_are_of_the_referencing_viewport():
    """A pattern establishes no viewport (SVG 2 §8.2), also with a viewBox: width="5%" in a
    100 x 100 document is 5 viewBox units, half the 10-unit tile (10 px of 20)."""
    img = render('<pattern id="p" patternUnits="userSpaceOnUse" width="20" height="20" '
                 'viewBox="0 0 10 10"><rect width="5%" height="100%" fill="#00f"/></pattern>'
                 '<rect width="100" height="100" fill="url(#p)"/>')
    row = img[10, :, 3]
    assert (row[0:10] == 255).all() and (row[10:20] == 0).all() and (row[20:30] == 255).all()


@pytest.mark.parametrize("content, fallback", [
    ("", True), ("<desc>d</desc>", True), ("<foo/>", True), ('<rect width="0" height="5"/>', True),
    ('<rect width="5" height="5" display="none"/>', True), ("<text> </text>", True),
    ('<rect width="5" height="5" fill="none"/>', False),
    ('<rect width="5" height="5" visibility="hidden"/>', False),
    ('<rect width="5" height="5" opacity="0"/>', False), ("<g/>", False)])
def test_pattern_without_content_uses_the_fallback(content, fallback):
    """A pattern with nothing to draw is no paint server, so the fallback colour applies; one
    whose content is there but paints nothing (hidden, unpainted, transparent, an empty
    group) is a paint server that paints transparent (resvg's reading; SVG 2 leaves it)."""
    img = render('<pattern id="p" patternUnits="userSpaceOnUse" width="10" height="10">'
                 f'{content}</pattern><rect width="100" height="100" fill="url(#p) #00f"/>')
    assert (img[..., 3] == (255 if fallback else 0)).all()


def test_pattern_content_units_on_an_empty_box_paint_nothing():
    """patternContentUnits="objectBoundingBox" on a horizontal line (a box without height):
    the content cannot be laid out, and the paint is none, not the fallback (as resvg)."""
    img = render('<pattern id="p" patternUnits="userSpaceOnUse" width="10" height="10" '
                 'patternContentUnits="objectBoundingBox"><rect width="1" height="1"/></pattern>'
                 '<line x1="0" y1="50" x2="100" y2="50" stroke="url(#p) #00f" stroke-width="20"/>')
    assert not img[..., 3].any()


@pytest.mark.parametrize("ref, first, second, keeps", [
    ("clip-path", '<clipPath id="a" clip-path="url(#b)"><rect width="50" height="100"/></clipPath>',
     '<clipPath id="b" clip-path="url(#a)"><rect width="100" height="50"/></clipPath>', "b"),
    ("mask", '<mask id="a" mask="url(#b)"><rect width="50" height="100" fill="white"/></mask>',
     '<mask id="b" mask="url(#a)"><rect width="100" height="50" fill="white"/></mask>', "b"),
    ("mask", '<mask id="a"><rect width="50" height="100" fill="white" mask="url(#b)"/></mask>',
     '<mask id="b"><rect width="100" height="50" fill="white" mask="url(#a)"/></mask>', "b")])
@pytest.mark.parametrize("target", ["a", "b"])
def test_mutual_clip_and_mask_references_break_at_the_later_element(ref, first, second, keeps,
                                                                      target):
    """Two clip paths or masks referencing each other: the cycle is broken as usvg breaks it
    (SVG makes it an error without saying what is drawn): the first one in document order
    keeps its reference, the later one loses it, whichever the element uses. So a (left half)
    is always clipped by b (top half); b alone is the top half."""
    img = render(first + second + f'<rect width="100" height="100" fill="#00f" {ref}="url(#{target})"/>')
    a = img[..., 3] > 127
    want = np.zeros((100, 100), bool)
    want[:50, :50 if target == "a" else 100] = True
    assert (a == want).all()


@pytest.mark.parametrize("child, inherits", [("<desc>d</desc>", True), ("<title>t</title>", True),
                                             ("<metadata/>", True), ("<foo/>", True),
                                             ("<g/>", False), ("<linearGradient/>", False)])
def test_pattern_children_via_href_skip_non_rendering_elements(child, inherits):
    """SVG 2: a pattern without children takes its href's. Descriptive elements (desc, title,
    metadata) and unknown ones are no content (usvg drops them from its tree): the pattern
    still takes the referenced one's blue tile. A g or a gradient are children: an empty g
    paints nothing, a gradient converts to no content, so the fallback."""
    img = render('<pattern id="b" patternUnits="userSpaceOnUse" width="10" height="10">'
                 '<rect width="10" height="10" fill="#00f"/></pattern>'
                 f'<pattern id="p" href="#b">{child}</pattern>'
                 '<rect width="100" height="100" fill="url(#p) #0f0"/>')
    want = (0, 0, 255, 255) if inherits else (0, 0, 0, 0) if child == "<g/>" else (0, 255, 0, 255)
    assert (img[50, 50] == want).all()


@pytest.mark.parametrize("fx", ['fx="bogus"', 'fx=""', 'fx="1e400"', ""])
def test_radial_focus_that_does_not_parse_is_the_centre(fx):
    """SVG 2: fx not given coincides with cx, and an invalid value is as if not given. With
    the focus at the centre (30, 50) of r = 40 in user space, a pixel at distance d from the
    centre is at t = d / 40 of the ramp whatever its direction: (10, 50) and (50, 50) are both
    t = 0.5 (a focus at the default 50% would put them at different t)."""
    img = render('<radialGradient id="g" gradientUnits="userSpaceOnUse" cx="30" cy="50" r="40" '
                 f'{fx}>{RAMP}</radialGradient><rect width="100" height="100" fill="url(#g)"/>')
    # pixel (x, 49) has its centre at (x + 0.5, 49.5)
    for x in (9, 50):
        d = np.hypot(x + 0.5 - 30, 49.5 - 50)
        assert abs(img[49, x, 0] - 255 * d / 40) <= 1.5


def test_reference_cycles_look_only_at_elements_references_reach():
    """Of two clip paths with one id, references reach the first (the left half); the second
    is never drawn, so its clip-path to b closes no cycle, and b (the top half) keeps its
    clip-path to a: the element is the top-left quadrant."""
    img = render('<clipPath id="a"><rect width="50" height="100"/></clipPath>'
                 '<clipPath id="b" clip-path="url(#a)"><rect width="100" height="50"/></clipPath>'
                 '<clipPath id="a" clip-path="url(#b)"><rect width="100" height="100"/></clipPath>'
                 '<rect width="100" height="100" fill="#00f" clip-path="url(#b)"/>')
    want = np.zeros((100, 100), bool)
    want[:50, :50] = True
    assert ((img[..., 3] > 127) == want).all()


# -- single-colour gradients: SVG 2 §14.2/§14.3 -------------------------------------------------
# "A value of zero [for r] will cause the area to be painted as a single color using the color
# and opacity of the last gradient stop"; x1 = x2 and y1 = y2 paints likewise. That colour needs
# neither the object bounding box nor the gradientTransform: a zero radius on an element whose
# box has no width, and either kind through a singular transform, paint the last stop.
_STOPS = '<stop offset="0" stop-color="#00f"/><stop offset="1" stop-color="#f00"/>'


@pytest.mark.parametrize("grad, shape, at", [
    ('<radialGradient id="g" r="0">', '<line x1="50" y1="5" x2="50" y2="95" stroke="url(#g) #0f0" '
     'stroke-width="40"/>', (50, 40)),
    ('<radialGradient id="g" r="-0.2">', '<line x1="5" y1="50" x2="95" y2="50" stroke="url(#g) #0f0" '
     'stroke-width="40"/>', (50, 40)),
    ('<radialGradient id="g" r="0" gradientTransform="matrix(1 2 2 4 0 0)">',
     '<rect x="10" y="10" width="80" height="80" fill="url(#g) #0f0"/>', (50, 50)),
    ('<linearGradient id="g" x1="0.3" x2="0.3" y1="0.6" y2="0.6" gradientTransform="matrix(1 2 2 4 0 0)">',
     '<rect x="10" y="10" width="80" height="80" fill="url(#g) #0f0"/>', (50, 50)),
])
def test_single_colour_gradient_needs_no_box_or_transform(grad, shape, at):
    tag = grad[1:grad.index(" ")]
    img = render(f'<defs>{grad}{_STOPS}</{tag}></defs>{shape}')
    assert tuple(img[at[1], at[0]]) == (255, 0, 0, 255)


# -- singular paint-server transforms: CSS Transforms 1 §6 (a non-invertible matrix renders
# nothing). The matrix is singular whatever the element's transform is; under a skew or
# rotation the product's rounded determinant is not zero, and must not paint a smear.
@pytest.mark.parametrize("element_transform", ["", "skewX(15)", "rotate(23 50 50)", "scale(1 0.6)"])
@pytest.mark.parametrize("server", [
    '<pattern id="s" patternUnits="userSpaceOnUse" width="10" height="10" '
    'patternTransform="matrix(1 1 1 1 0 0)"><rect width="10" height="10" fill="#00f"/></pattern>',
    '<linearGradient id="s" gradientTransform="matrix(1 2 2 4 0 0)"><stop stop-color="#00f"/>'
    '<stop offset="1" stop-color="#f00"/></linearGradient>',
    '<radialGradient id="s" gradientTransform="matrix(1 2 2 4 0 0)"><stop stop-color="#00f"/>'
    '<stop offset="1" stop-color="#f00"/></radialGradient>',
])
def test_singular_server_transform_paints_nothing_under_any_element_transform(server, element_transform):
    img = render(f'<defs>{server}</defs><rect x="10" y="10" width="80" height="80" '
                 f'fill="url(#s)" transform="{element_transform}"/>')
    assert img[..., 3].max() == 0


# A pattern tile without area is no pattern, whatever its content units: a zero width with
# patternContentUnits="objectBoundingBox" on a line's empty box paints as it does without them.
def test_zero_size_pattern_tile_ignores_content_units():
    def draw(units):
        return render(f'<defs><pattern id="p" patternUnits="userSpaceOnUse" width="0" height="20"{units}>'
                      '<rect width="1" height="1" fill="#00f"/></pattern></defs>'
                      '<line x1="10" y1="50" x2="90" y2="50" stroke="url(#p) #f00" stroke-width="20"/>')
    plain = draw("")
    assert tuple(plain[50, 50]) == (255, 0, 0, 255)
    assert np.array_equal(draw(' patternContentUnits="objectBoundingBox"'), plain)


# Two equal circles (focal circle = end circle) with reflect or repeat paint nothing (canvas's
# two-point conical gradient: no circle of the family but the one passes through a pixel);
# the gradient is a valid paint server, so the paint's fallback does not apply either.
@pytest.mark.parametrize("spread", ["reflect", "repeat"])
def test_equal_circles_reflect_repeat_paint_nothing_not_fallback(spread):
    img = render(f'<defs><radialGradient id="g" spreadMethod="{spread}" fr="0.5">{_STOPS}'
                 '</radialGradient></defs><rect x="10" y="10" width="80" height="80" fill="url(#g) #0f0"/>')
    assert img[..., 3].max() == 0


# A focal point a ten-thousandth of r outside the end circle: the largest root of the two-point
# conical gradient runs off to thousands of periods there (numerically the circle is touched, as
# tiny-skia and Skia decide within 1/4096), so it paints as the focal point on the circle, which
# SVG 2 defines: one root. Compared with that drawing away from the tangent line through the
# focal point (x = 10), where t grows without bound in both.
@pytest.mark.parametrize("spread", ["pad", "reflect", "repeat"])
def test_focal_point_just_outside_paints_as_on_the_circle(spread):
    def draw(fx):
        return render(f'<defs><radialGradient id="g" gradientUnits="userSpaceOnUse" cx="50" cy="50" '
                      f'r="40" fx="{fx}" fy="50" spreadMethod="{spread}">{_STOPS}</radialGradient></defs>'
                      '<rect width="100" height="100" fill="url(#g)"/>')
    on, off = draw(10), draw(9.996)
    far = np.abs(np.arange(100) + 0.5 - 10) > 3
    assert np.abs(on - off)[:, far].max() <= 8


@pytest.mark.parametrize("mask_type", [None, "alpha", "luminance"])
@pytest.mark.parametrize("mode", [None, "alpha", "luminance", "match-source", "Alpha, luminance"])
def test_mask_mode_of_the_masked_element_overrides_mask_type(mask_type, mode):
    """CSS Masking 1, mask-mode: on the element with the mask, alpha or luminance decides how
    the mask element's content is read; match-source (the initial value) takes the mask
    element's mask-type. Truth: the same drawing with mask-mode left out and mask-type set to
    the kind the specification picks, on a masked element and inside another mask."""
    from vecmsaa.api import render_svg_array

    want = mode.split(",")[0].strip().lower() if mode else None
    if want not in ("alpha", "luminance"):
        want = mask_type or "luminance"

    def doc(kind, mode):
        own = f' style="mask-type: {kind}"' if kind else ""
        css = f' style="mask-mode: {mode}"' if mode else ""
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="20">'
                f'<mask id="m"{own}><rect width="40" height="20" fill="#804020" '
                'fill-opacity="0.6"/></mask>'
                '<mask id="outer"><rect width="40" height="20" fill="white" '
                f'mask="url(#m)"{css}/></mask>'
                f'<rect width="20" height="20" fill="blue" mask="url(#m)"{css}/>'
                '<rect x="20" width="20" height="20" fill="blue" mask="url(#outer)"/></svg>')
    got = render_svg_array(doc(mask_type, mode))
    truth = render_svg_array(doc(want, None))
    assert np.array_equal(got, truth)
    if want == "alpha":     # and the two kinds do differ here
        assert not np.array_equal(got, render_svg_array(doc("luminance", None)))


@pytest.mark.parametrize("how", ['mask-type="ALPHA"', 'mask-type="Alpha"',
                                 'style="mask-type: ALPHA"', 'mask-type=" alpha "'])
def test_mask_type_keywords_are_case_insensitive(how):
    """mask-type is a CSS property (a presentation attribute too) and CSS keywords match
    ASCII case-insensitively (CSS Values 4 §2.1). Truth: an alpha mask of a colour at
    opacity 0.6 lets 0.6 of the element through, whatever the colour (a luminance mask of
    #804020 would let 0.6 × its luminance, about 0.16, through)."""
    from vecmsaa.api import render_svg_array

    img = render_svg_array(
        '<svg xmlns="http://www.w3.org/2000/svg" width="20" height="20">'
        f'<mask id="m" {how}><rect width="20" height="20" fill="#804020" fill-opacity="0.6"/>'
        '</mask><rect width="20" height="20" fill="blue" mask="url(#m)"/></svg>')
    assert abs(int(img[10, 10, 3]) - round(0.6 * 255)) <= 1


# -- pattern tiles past the size caps: laid out only where the element samples them -----------
# An objectBoundingBox tile of width 20 on a 160-unit rect is 3200 x 3200 px in a 200 px
# render, past MAX_TILE_PIXELS; laid out whole it was scaled down and its edges blurred.
_BIG_TILE = ('<pattern id="p" {attrs}><rect width="10" height="10" fill="#808080"/>'
             '<rect x="10" y="10" width="10" height="10" fill="#008000"/>'
             '<rect x="{far}" y="0" width="30" height="60" fill="#0000ff"/></pattern>')


def test_big_pattern_tile_keeps_its_contents_edges_exact():
    body = (_BIG_TILE.format(attrs='width="20" height="20"', far=3170)
            + '<rect x="20" y="20" width="160" height="160" fill="url(#p)"/>')
    img = render(body, 200, 200)
    # the squares' edges fall on pixel edges (SVG geometry: x 20-30 grey, 30-40 green)
    assert np.allclose(img[20:30, 20:30], (128, 128, 128, 255))
    assert np.allclose(img[30:40, 30:40], (0, 128, 0, 255))
    assert np.all(img[20:30, 30:40, 3] == 0) and np.all(img[30:40, 20:30, 3] == 0)
    assert np.all(img[40:180, 40:180, 3] == 0)


@pytest.mark.parametrize("attrs, shape", [
    # one copy of the tile, a fill
    ('width="20" height="20"', '<rect x="20" y="20" width="160" height="160" fill="url(#p)"/>'),
    # the window straddles copies: a wide stroke reaches before the tile's start
    ('width="20" height="20"', '<rect x="20" y="20" width="160" height="160" fill="none" '
     'stroke="url(#p)" stroke-width="30"/>'),
    ('patternUnits="userSpaceOnUse" x="100" y="-50" width="3200" height="3000"',
     '<circle cx="100" cy="100" r="80" fill="url(#p)" stroke="url(#p)" stroke-width="9"/>'),
    # rotated and skewed: smooth sampling, the window a rotated box's bounds
    ('patternUnits="userSpaceOnUse" x="3" width="3200" height="3000" '
     'patternTransform="rotate(30 100 100)"',
     '<path d="M20 100 L100 20 L180 100 L100 180" fill="none" stroke="url(#p)" '
     'stroke-width="25" stroke-miterlimit="10"/>'),
    ('patternUnits="userSpaceOnUse" width="3200" height="3000" patternTransform="rotate(180 100 100)"',
     '<g transform="translate(100 100) scale(0.5) skewX(20)"><rect x="-150" y="-150" '
     'width="300" height="300" fill="url(#p)"/></g>'),
])
def test_big_pattern_tile_window_equals_the_whole_tile(monkeypatch, attrs, shape):
    """Brute force: the same document with the caps raised so that the tile is laid out
    whole at full scale; equal in premultiplied RGBA (a fully transparent pixel's straight
    colour is float residue)."""
    import vecmsaa.svg.paint as paint

    gradients = ('<linearGradient id="g" gradientUnits="userSpaceOnUse" x2="37" '
                 'spreadMethod="repeat"><stop offset="0.5" stop-color="red"/>'
                 '<stop offset="0.5" stop-color="teal"/></linearGradient>')
    body = (gradients + _BIG_TILE.format(attrs=attrs, far=3170).replace(
        '<rect width="10"', '<rect x="-10" y="-10" width="3300" height="3300" '
        'fill="url(#g)" opacity="0.5"/><rect width="10"') + shape)
    windowed = render(body, 200, 200)
    monkeypatch.setattr(paint, "MAX_TILE_PIXELS", 4000 * 4000)
    whole = render(body, 200, 200)
    premultiplied = [im[..., :3] * im[..., 3:] / 255 for im in (windowed, whole)]
    assert np.abs(premultiplied[0] - premultiplied[1]).max() <= 0.5
    assert np.array_equal(windowed[..., 3], whole[..., 3])
    assert (whole[..., 3] > 0).sum() > 3000


# A paint server's transform is invalid only where it has no inverse (CSS Transforms 1 §6):
# skewX(90) is [[1, tan 90°], [0, 1]] with tan 90° = 1.6e16 in floats, determinant exactly 1,
# so it is invertible and the gradient paints. Every point of the box with v > 0 maps back to
# u - 1.6e16 v, far before the start of the vector: a linear gradient pads with its first
# stop there, a radial one (distance past its radius) with its last. (Chromium and resvg
# paint so; the test before took the determinant relative to the largest entry squared,
# 4e-33, for singular and painted nothing.)
# (skewX(-90) maps back to u + 1.6e16 v, past the end: the last stop; skewY(90) to
# v - 1.6e16 u, which a radial gradient's distance sees.)
@pytest.mark.parametrize("tag, skew, colour", [
    ("linearGradient", "skewX(90)", (0, 0, 255, 255)),
    ("linearGradient", "skewX(-90)", (255, 0, 0, 255)),
    ("radialGradient", "skewX(90)", (255, 0, 0, 255)),
    ("radialGradient", "skewY(90)", (255, 0, 0, 255)),
])
def test_huge_skew_server_transform_is_invertible(tag, skew, colour):
    img = render(f'<defs><{tag} id="g" gradientTransform="{skew}">{_STOPS}</{tag}></defs>'
                 '<rect x="10" y="10" width="80" height="80" fill="url(#g) #0f0"/>')
    assert tuple(img[60, 60]) == colour


# Singular is ad - bc = 0 up to the rounding of the two products, whatever the scale: rank-one
# matrices u vᵀ (rows parallel in exact arithmetic, rounded when formed) are singular, and
# matrices whose determinant is far from the rounding of ad and bc are not, however unequal
# their entries.
def test_singular_linear_against_rank():
    from vecmsaa.svg.paint import singular_linear

    rng = np.random.default_rng(34)
    for _ in range(2000):
        u, v = rng.normal(size=2), rng.normal(size=2)
        scale = 10.0 ** rng.uniform(-150, 150)
        a, c, b, d = (np.outer(u, v) * scale).ravel()      # [[a, c], [b, d]] = s u vᵀ
        assert singular_linear(a, b, c, d)
    for _ in range(2000):
        a, b, c, d = rng.normal(size=4) * 10.0 ** rng.uniform(-20, 20, size=4)
        exact = abs(float(a) * float(d) - float(b) * float(c))
        if exact > 1e-6 * (abs(a * d) + abs(b * c)):
            assert not singular_linear(a, b, c, d)
    assert singular_linear(1, 2, 2, 4) and singular_linear(0, 0, 0, 0)
    assert not singular_linear(1, 0, 1.633123935319537e16, 1)
