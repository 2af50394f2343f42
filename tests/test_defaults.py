"""The defaults that depend on what is drawn: 16 samples for small outputs (docs/modes.md) and
exact-area coverage for font sheets whose shapes do not overlap (docs/fonts.md), each checked
against brute-force coverage."""
from __future__ import annotations

import os

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.fonts import load_face
from vecmsaa.fonts.sheets import analytic_is_exact, line_scene, shapes_overlap
from vecmsaa.raster.modes import coverage, default_samples
from vecmsaa.raster.render import render_scene_rgba8
from vecmsaa.scene.nodes import Fill, Group, Scene
from vecmsaa.scene.path import Path, rect_path

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
SUITE_FONTS = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "resvg-suite",
                           "fonts")
#: sub-samples per pixel side of the brute-force coverage (error below 1/64 per edge pixel)
FINE = 64


def test_small_outputs_default_to_16_samples():
    assert default_samples(16, 16) == 16
    assert default_samples(128, 128) == 16
    assert default_samples(256, 64) == 16        # by pixel count, not by side
    assert default_samples(129, 128) == 8
    assert default_samples(2048, 2048) == 8
    assert coverage(None, 4, 16, 16) == {"mode": "approx", "samples": 4}   # explicit wins
    assert coverage(None, None, 16, 16, analytic_exact=True)["mode"] == "analytic"


def _inside_polygon(px, py, poly):
    """Point-in-convex-polygon (counter-clockwise in y-down pixels: all cross products <= 0)."""
    inside = np.ones(px.shape, bool)
    for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
        inside &= (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0) >= 0
    return inside


#: icon-like shapes at 16 px: (SVG body, brute-force point test on pixel coordinates)
ICONS = {
    "disc": ('<circle cx="8.3" cy="7.8" r="5.4"/>',
             lambda x, y: (x - 8.3) ** 2 + (y - 7.8) ** 2 <= 5.4 ** 2),
    "ring": ('<path fill-rule="evenodd" d="M 8 1.7 A 6.3 6.3 0 1 1 7.99 1.7 Z '
             'M 8 4.1 A 3.9 3.9 0 1 0 8.01 4.1 Z"/>',
             lambda x, y: (6.3 ** 2 >= (x - 8) ** 2 + (y - 8) ** 2) &
                          ((x - 8) ** 2 + (y - 8) ** 2 >= 3.9 ** 2)),
    "diamond": ('<path d="M 8.2 1.3 L 14.6 8.1 L 7.9 14.7 L 1.4 7.7 Z"/>',
                lambda x, y: _inside_polygon(x, y, [(8.2, 1.3), (14.6, 8.1), (7.9, 14.7),
                                                    (1.4, 7.7)])),
    "slash": ('<path d="M 2.3 12.6 L 12.1 2.2 L 13.7 3.6 L 3.8 14.1 Z"/>',
              lambda x, y: _inside_polygon(x, y, [(2.3, 12.6), (12.1, 2.2), (13.7, 3.6),
                                                  (3.8, 14.1)])),
    "thin bar": ('<path d="M 4.02 5.01 L 13.26 11.36 L 12.72 12.14 L 3.48 5.79 Z"/>',
                 lambda x, y: _inside_polygon(x, y, [(4.02, 5.01), (13.26, 11.36),
                                                     (12.72, 12.14), (3.48, 5.79)])),
}


def brute_force_alpha(inside, size=16):
    """Coverage of each pixel by FINE x FINE point tests, x 255."""
    c = (np.arange(size * FINE) + 0.5) / FINE
    x, y = np.meshgrid(c, c)
    return inside(x, y).reshape(size, FINE, size, FINE).mean(axis=(1, 3)) * 255


@pytest.mark.parametrize("name", ICONS)
def test_small_icons_at_the_default_match_brute_force_coverage(name):
    """The suite's criterion at 16 px: no pixel off by more than 48/255. 8 samples miss it on
    these shapes (a pixel's coverage is quantised to 1/8); the default must not."""
    body, inside = ICONS[name]
    svg = f'<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16">{body}</svg>'
    truth = brute_force_alpha(inside)
    default = render_svg_array(svg)[..., 3].astype(float)
    assert np.abs(default - truth).max() <= 48, name
    assert np.array_equal(default, render_svg_array(svg, samples=16)[..., 3])


def test_eight_samples_would_fail_some_icon():
    """The test above could fail: with 8 samples some of these icons have a pixel off."""
    worst = 0.0
    for body, inside in ICONS.values():
        svg = f'<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16">{body}</svg>'
        worst = max(worst, np.abs(render_svg_array(svg, samples=8)[..., 3]
                                  - brute_force_alpha(inside)).max())
    assert worst > 48


# --- overlap detection, which decides the font default -------------------------------------------

def _path(*rects, reverse=()):
    path = Path()
    for i, r in enumerate(rects):
        p = rect_path(*r)
        if i in reverse:
            v, pts = p.verbs, p.points
            # the same rectangle the other way round: corners in reverse order
            p = Path.from_arrays(v, np.concatenate([pts[:1], pts[1:4][::-1], pts[4:]]))
        path.extend(p)
    return path


def test_shapes_overlap_by_winding():
    assert not shapes_overlap([_path((1, 1, 4, 4))])
    assert not shapes_overlap([_path((1, 1, 4, 4), (6, 1, 4, 4))])      # apart
    assert not shapes_overlap([_path((1, 1, 4, 4), (5, 1.5, 4, 4))])    # touching, one path
    assert not shapes_overlap([_path((1, 1, 4, 4)), _path((5, 1, 4, 4))])  # shared edge
    assert not shapes_overlap([_path((1, 1, 8, 8), (3, 3, 2, 2), reverse=(1,))])   # a hole
    assert shapes_overlap([_path((1, 1, 8, 8), (3, 3, 2, 2))])          # winding 2
    assert shapes_overlap([_path((1, 1, 4, 4), (4.3, 1.5, 4, 4))])     # one path, overlapping
    assert shapes_overlap([_path((1, 1, 4, 4)), _path((4.3, 1.5, 4, 4))])   # two paths


def test_analytic_is_wrong_exactly_where_shapes_overlap():
    """Two squares in one path overlapping by 0.6 px: exact area per path over-counts the
    pixels both edges cross (so the font default must not use it there); apart, it is exact."""
    def alpha(rects, mode):
        scene = Scene(12, 8, Group([Fill(_path(*rects))]), (0.0, 0.0, 0.0, 0.0))
        return render_scene_rgba8(scene, mode=mode, samples=16)[..., 3].astype(float), scene

    def truth(rects):
        c = (np.arange(12 * FINE) + 0.5) / FINE
        x, y = np.meshgrid(c, c[:8 * FINE])
        inside = np.zeros(x.shape, bool)
        for rx, ry, w, h in rects:
            inside |= (x >= rx) & (x < rx + w) & (y >= ry) & (y < ry + h)
        return inside.reshape(8, FINE, 12, FINE).mean(axis=(1, 3)) * 255

    overlapping = [(1.3, 1.3, 5.0, 5.4), (5.7, 1.8, 5.0, 5.4)]
    a, scene = alpha(overlapping, "analytic")
    assert shapes_overlap([f.path for f in scene.fills()])
    assert np.abs(a - truth(overlapping)).max() > 48
    apart = [(1.3, 1.3, 4.0, 5.4), (5.7, 1.8, 5.0, 5.4)]
    a, scene = alpha(apart, "analytic")
    assert not shapes_overlap([f.path for f in scene.fills()])
    assert np.abs(a - truth(apart)).max() <= 2


def test_font_default_is_analytic_for_latin_lines():
    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    scene = line_scene(face, "The quick brown fox jumps over the lazy dog", 10)
    assert analytic_is_exact(scene, face)


@pytest.mark.parametrize("font, text", [
    ("Amiri-Regular.ttf", "بسم الله الرحمن الرحيم"),          # joined: letters overlap
    ("NotoSans-Regular.ttf", "a\u0301\u0323 x\u0336y o\u0303\u0330"),   # stacked marks
])
def test_font_default_is_msaa_where_glyphs_overlap(font, text):
    path = os.path.join(SUITE_FONTS, font)
    if not os.path.exists(path):
        pytest.skip("../shared is not present")
    face = load_face(path)
    assert not analytic_is_exact(line_scene(face, text, 10), face)


def test_goldens_made_at_the_default_follow_the_size_default(tmp_path):
    """A manifest made without --samples records none, so check renders at the size's default:
    a 16 px icon's golden is its 16-sample render and keeps matching it."""
    from vecmsaa.output.png import encode_png
    from vecmsaa.tools import golden

    svgs, goldens = tmp_path / "svgs", tmp_path / "goldens"
    svgs.mkdir()
    body = ICONS["thin bar"][0]
    (svgs / "bar.svg").write_text(
        f'<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16">{body}</svg>')
    golden.update_goldens(svgs, goldens, {})
    assert golden.read_manifest(goldens)["render_options"]["samples"] is None
    assert (goldens / "bar.png").read_bytes() == encode_png(
        render_svg_array(str(svgs / "bar.svg"), samples=16))
    outcomes = list(golden.check_goldens(golden.plan_check(svgs, goldens)))
    assert [o.status for o in outcomes] == [golden.PASS]
    assert outcomes[0].comparison.max_diff == 0


def test_glyph_grid_rules_do_not_overlap_but_composite_glyphs_do():
    """The grid's guide lines tile without crossing (exact area stays exact there); Aring's
    ring and ccedilla's cedilla are components overlapping their base, which exact area per
    path would over-count, so the grid of this font keeps the MSAA default."""
    from vecmsaa.fonts.layout import glyphs_path, placement
    from vecmsaa.fonts.sheets import glyph_grid_scene

    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    scene = glyph_grid_scene(face, face)
    rules = scene.fills()[0]
    assert not shapes_overlap([rules.path])
    scale = 40 / face.units_per_em
    overlapping = [face.glyph_order[g] for g in range(face.num_glyphs)
                   if shapes_overlap([glyphs_path(face, (), [g], placement([(10, 50)], scale))])]
    assert {"Aring", "ccedilla"} <= set(overlapping) and "A" not in overlapping
    assert not analytic_is_exact(scene, face)
