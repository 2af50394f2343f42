"""The defaults that depend on what is drawn: 16 samples for small outputs (docs/modes.md) and
exact-area coverage for font sheets, their overlapping contours united, whose fills do not
overlap one another (docs/fonts.md), each checked against brute-force coverage."""
from __future__ import annotations

import os

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.fonts import load_face
from vecmsaa.fonts.sheets import exact_area_sheet, line_scene
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
    assert default_samples(300, 300) == 16       # the resvg suite's size
    assert default_samples(512, 512) == 16
    assert default_samples(1024, 256) == 16      # by pixel count, not by side
    assert default_samples(513, 512) == 8
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


def _truth(rects, reverse=(), w=12, h=8):
    """Brute-force nonzero coverage of the rectangles (those in ``reverse`` wound the other
    way), x 255."""
    c = (np.arange(w * FINE) + 0.5) / FINE
    x, y = np.meshgrid(c, c[:h * FINE])
    winding = np.zeros(x.shape)
    for i, (rx, ry, rw, rh) in enumerate(rects):
        winding += ((x >= rx) & (x < rx + rw) & (y >= ry) & (y < ry + rh)) * (
            -1 if i in reverse else 1)
    return (winding != 0).reshape(h, FINE, w, FINE).mean(axis=(1, 3)) * 255


@pytest.mark.parametrize("rects, reverse", [
    ([(1.3, 1.3, 5.0, 5.4), (5.7, 1.8, 5.0, 5.4)], ()),     # overlapping by 0.6 px
    ([(1.3, 1.3, 5.0, 5.4), (5.7, 1.8, 5.0, 5.4)], (1,)),   # opposite windings: a gap
    ([(1.3, 1.2, 9.1, 6.2), (1.6, 1.5, 2.2, 2.5)], ()),     # one inside the other: winding 2
])
def test_exact_area_sheet_unites_overlapping_contours(rects, reverse):
    """Exact area per path over-counts the pixels where contours of one path overlap (so the
    raw outline must not be drawn with it); the sheet's united outline is exact there."""
    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    scene = Scene(12, 8, Group([Fill(_path(*rects, reverse=reverse))]), (0.0, 0.0, 0.0, 0.0))
    raw = render_scene_rgba8(scene, mode="analytic")[..., 3].astype(float)
    truth = _truth(rects, reverse)
    if not reverse:
        assert np.abs(raw - truth).max() > 48
    united = exact_area_sheet(scene, face)
    assert np.abs(render_scene_rgba8(united, mode="analytic")[..., 3] - truth).max() <= 2


def _against_reference(scene, face):
    """(worst pixel, pixels off by more than 48/255, ink ratio - 1) of the default's exact-area
    render against 1024-sample coverage of the original sheet."""
    truth = render_scene_rgba8(scene, mode="reference", samples=1024)[..., 3] / 255
    united = exact_area_sheet(scene, face)
    assert united is not None
    a = render_scene_rgba8(united, mode="analytic")[..., 3] / 255
    return np.abs(a - truth).max(), (np.abs(a - truth) > 48 / 255).sum(), a.sum() / truth.sum() - 1


@pytest.mark.parametrize("text, size", [("The quick brown fox jumps over the lazy dog", 10),
                                         ("ÅçÅç", 12), ("Åç", 16)])
def test_font_default_is_exact_area_for_latin_lines(text, size):
    """Å's ring and ç's cedilla are components overlapping their base glyph: exact area on the
    raw outlines is +1% ink with pixels off by 0.22-0.31; united, within the reference's noise."""
    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    worst, off, ink = _against_reference(line_scene(face, text, size, background=(0, 0, 0, 0)),
                                         face)
    assert worst < 0.03 and off == 0 and abs(ink) < 0.002


@pytest.mark.parametrize("font, text", [
    ("Amiri-Regular.ttf", "بسم الله الرحمن الرحيم"),          # joined: letters overlap
    ("Yellowtail-Regular.ttf", "Handwriting flows"),
    ("NotoSans-Regular.ttf", "a\u0301\u0323 x\u0336y o\u0303\u0330"),   # stacked marks
])
def test_font_default_is_exact_where_glyphs_overlap(font, text):
    """Raw exact area is +2-3% ink here with pixels off by up to 0.3 (docs/fonts.md)."""
    path = os.path.join(SUITE_FONTS, font)
    if not os.path.exists(path):
        pytest.skip("../shared is not present")
    face = load_face(path)
    worst, off, ink = _against_reference(line_scene(face, text, 10, background=(0, 0, 0, 0)),
                                         face)
    assert worst < 0.03 and off == 0 and abs(ink) < 0.003


def test_specimen_is_exact_area_with_guide_lines_under_glyphs():
    """A specimen's guide lines run under its glyphs: two fills cover those pixels, and per-
    pixel compositing of exact areas is off only where a line's edge and a glyph's edge cross
    one pixel. Against 256-sample ground truth in every channel: at most 16/255 (8 samples
    are off by 71/255 on such sheets)."""
    from vecmsaa.fonts.sheets import specimen_scene

    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    scene = specimen_scene(face, face)
    truth = render_scene_rgba8(scene, mode="reference", samples=256).astype(float)
    united = render_scene_rgba8(exact_area_sheet(scene, face), mode="analytic").astype(float)
    assert np.abs(united - truth).max() <= 16


def test_colour_fonts_keep_the_msaa_default():
    """Colour glyph layers abut one another: exact area per layer would seam them."""
    path = os.path.join(SUITE_FONTS, "NotoColorEmojiCOLR.subset.ttf")
    if not os.path.exists(path):
        pytest.skip("../shared is not present")
    face = load_face(path)
    text = "".join(chr(c) for c in sorted(face.ttfont.getBestCmap())[:3])
    assert exact_area_sheet(line_scene(face, text, 16), face) is None


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


def test_glyph_grid_is_exact_area():
    """The grid's crossing guide lines and its composite glyphs (Aring, ccedilla) are united:
    no pixel off by more than 48/255 against 1024 samples, ink within 0.2%."""
    from vecmsaa.fonts.sheets import glyph_grid_scene

    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    worst, off, ink = _against_reference(
        glyph_grid_scene(face, face, glyph_size=16, per_page=64, background=(0, 0, 0, 0)), face)
    assert off == 0 and abs(ink) < 0.002


def test_stacked_copies_are_not_united():
    """64 copies of one contour on top of each other (composite fan-out fonts, marks without
    mark-to-mark offsets) would take Skia's simplify over a minute: the sheet keeps the MSAA
    default instead, which is exact per sample there."""
    face = load_face(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    stacked = Path()
    for _ in range(64):
        stacked.moveTo((1.0, 1.0))
        stacked.qCurveTo((4.0, 7.0), (7.0, 1.0))
        stacked.closePath()
    scene = Scene(8, 8, Group([Fill(stacked)]), (0.0, 0.0, 0.0, 0.0))
    assert exact_area_sheet(scene, face) is None
    two = Path()
    for dx in (0.0, 0.3):
        two.moveTo((1.0 + dx, 1.0))
        two.qCurveTo((4.0 + dx, 7.0), (7.0 + dx, 1.0))
        two.closePath()
    assert exact_area_sheet(Scene(8, 8, Group([Fill(two)]), (0.0, 0.0, 0.0, 0.0)), face)
