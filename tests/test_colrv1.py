"""COLR v1 colour glyphs against the OpenType specification's formulas (OpenType 1.9, COLR
version 1): each glyph of a font built here with fontTools is one paint graph over a
1000-unit square, drawn at 100 px per em so that font unit (x, y) is device pixel
(x / 10, 100 - y / 10); the expected colour of every pixel is computed from the spec's
definition of the paint, not from the renderer."""

import numpy as np
import pytest
from fontTools.colorLib.builder import buildCOLR, buildCPAL
from fontTools.fontBuilder import FontBuilder
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib.tables.otTables import CompositeMode, PaintFormat

from vecmsaa import render_svg_array
from vecmsaa.diagnostics import RenderWarning

SVG = 'xmlns="http://www.w3.org/2000/svg"'
RED, BLUE, YELLOW, CYAN, GREEN = (1, 0, 0, 1), (0, 0, 1, 1), (1, 1, 0, 1), (0, 1, 1, 1), (0, 1, 0, 1)
PALETTE = [RED, BLUE, YELLOW, CYAN, GREEN]


def _square(x0, y0, x1, y1):
    pen = TTGlyphPen(None)
    pen.moveTo((x0, y0))
    pen.lineTo((x0, y1))
    pen.lineTo((x1, y1))
    pen.lineTo((x1, y0))
    pen.closePath()
    return pen.glyph()


def _solid(index, alpha=1.0):
    return {"Format": PaintFormat.PaintSolid, "PaletteIndex": index, "Alpha": alpha}


def _line(*stops, extend="pad"):
    return {"Extend": extend, "ColorStop": [{"StopOffset": o, "PaletteIndex": i, "Alpha": 1.0}
                                            for o, i in stops]}


def _fill(glyph, paint):
    return {"Format": PaintFormat.PaintGlyph, "Glyph": glyph, "Paint": paint}


LINEAR_SKEWED = _fill("sq", {"Format": PaintFormat.PaintLinearGradient,
                             "ColorLine": _line((0, 0), (1, 1)),
                             "x0": 0, "y0": 0, "x1": 1000, "y1": 0, "x2": 1000, "y2": 1000})
SWEEP = _fill("sq", {"Format": PaintFormat.PaintSweepGradient,
                     "ColorLine": _line((0, 0), (1, 1)),
                     "centerX": 500, "centerY": 500, "startAngle": 0, "endAngle": 360})
ROTATED = _fill("sq", {"Format": PaintFormat.PaintRotateAroundCenter, "angle": 90,
                       "centerX": 500, "centerY": 500,
                       "Paint": {"Format": PaintFormat.PaintLinearGradient,
                                 "ColorLine": _line((0, 0), (1, 1)),
                                 "x0": 0, "y0": 0, "x1": 1000, "y1": 0, "x2": 0, "y2": 1000}})
RADIAL = _fill("sq", {"Format": PaintFormat.PaintRadialGradient,
                      "ColorLine": _line((0, 0), (1, 1)),
                      "x0": 500, "y0": 500, "r0": 0, "x1": 500, "y1": 500, "r1": 500})
# stops at 0.25 and 0.75 of the axis, repeated: a sawtooth of period 500 units
REPEAT = _fill("sq", {"Format": PaintFormat.PaintLinearGradient,
                      "ColorLine": _line((0.25, 0), (0.75, 1), extend="repeat"),
                      "x0": 0, "y0": 0, "x1": 1000, "y1": 0, "x2": 0, "y2": 1000})
SRC_IN = {"Format": PaintFormat.PaintComposite, "CompositeMode": CompositeMode.SRC_IN,
          "SourcePaint": _fill("sq", _solid(0)), "BackdropPaint": _fill("small", _solid(1, 0.5))}
DEST_OUT = {"Format": PaintFormat.PaintComposite, "CompositeMode": CompositeMode.DEST_OUT,
            "SourcePaint": _fill("small", _solid(0)), "BackdropPaint": _fill("sq", _solid(4))}
MULTIPLY = {"Format": PaintFormat.PaintComposite, "CompositeMode": CompositeMode.MULTIPLY,
            "SourcePaint": _fill("sq", _solid(3)), "BackdropPaint": _fill("sq", _solid(2))}
CLIPPED = _fill("sq", _solid(0))
FOREGROUND = {"Format": PaintFormat.PaintColrLayers, "Layers": [
    _fill("sq", _solid(1)), _fill("small", _solid(0xFFFF))]}
SELF_REFERENCE = {"Format": PaintFormat.PaintColrLayers, "Layers": [
    _fill("sq", _solid(4)), {"Format": PaintFormat.PaintColrGlyph, "Glyph": "selfref"}]}

V0_GLYPH = [("sq", 1), ("small", 0)]       # COLR v0 layers: blue square, red inner square

BASES = {"L": ("v0", V0_GLYPH), "A": ("linear", LINEAR_SKEWED), "B": ("sweep", SWEEP), "C": ("rotated", ROTATED),
         "D": ("radial", RADIAL), "E": ("repeat", REPEAT), "F": ("srcin", SRC_IN),
         "G": ("destout", DEST_OUT), "H": ("multiply", MULTIPLY), "I": ("clipped", CLIPPED),
         "J": ("fg", FOREGROUND), "K": ("selfref", SELF_REFERENCE)}


@pytest.fixture(scope="module")
def colr_font(tmp_path_factory):
    folder = tmp_path_factory.mktemp("colr")
    names = [name for name, _ in BASES.values()]
    order = [".notdef", "space", "sq", "small"] + names
    glyphs = {n: _square(0, 0, 0, 0) for n in order}
    glyphs["sq"] = _square(0, 0, 1000, 1000)
    glyphs["small"] = _square(250, 250, 750, 750)
    for n in [".notdef", "space"] + names:
        glyphs[n] = TTGlyphPen(None).glyph()
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", **{ord(c): n for c, (n, _) in BASES.items()}})
    fb.setupGlyf(glyphs)
    # left side bearings equal to xMin: fontTools moves a glyph to its lsb
    fb.setupHorizontalMetrics({n: (1000, 250 if n == "small" else 0) for n in order})
    fb.setupHorizontalHeader(ascent=1000, descent=0)
    fb.setupNameTable({"familyName": "ColrTest", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    # version chosen by fontTools: 1, with the layer list glyph as a version 0 record
    fb.font["COLR"] = buildCOLR({n: p for n, p in BASES.values()},
                                clipBoxes={"clipped": (0, 0, 500, 1000)})
    fb.font["CPAL"] = buildCPAL([PALETTE])
    fb.save(str(folder / "colr.ttf"))
    return folder


def draw(folder, char, fill="black"):
    svg = (f'<svg {SVG} width="100" height="100"><text x="0" y="100" font-size="100" '
           f'font-family="ColrTest" fill="{fill}">{char}</text></svg>')
    img = render_svg_array(svg, use_fonts_dir=str(folder), skip_system_fonts=True)
    return img.astype(np.float64) / 255.0


def font_coords():
    """Font units (x, y) at each pixel centre."""
    j, i = np.mgrid[0:100, 0:100]
    return (i + 0.5) * 10.0, 1000.0 - (j + 0.5) * 10.0


def ramp(t, c0=RED, c1=BLUE):
    t = np.clip(t, 0.0, 1.0)[..., None]
    return (1 - t) * np.asarray(c0, float) + t * np.asarray(c1, float)


INNER = (slice(2, 98), slice(2, 98))      # pixels off the square's anti-aliased edge


def assert_close(got, want, where=None, tol=4 / 255):
    where = np.ones(got.shape[:2], bool) if where is None else where
    err = np.abs(got - want)[where].max()
    assert err <= tol, err


def test_linear_gradient_is_constant_along_p0_p2(colr_font):
    # p2 = (1000, 1000): colour lines run along the diagonal; p1 projected onto its normal
    # gives the axis p0 -> (500, -500), so t = (x - y) / 1000
    x, y = font_coords()
    assert_close(draw(colr_font, "A")[INNER], ramp((x - y) / 1000)[INNER])


def test_sweep_gradient_runs_counter_clockwise_from_the_x_axis(colr_font):
    x, y = font_coords()
    angle = np.degrees(np.arctan2(y - 500, x - 500)) % 360
    away = (np.hypot(x - 500, y - 500) > 40) & ~((np.abs(y - 500) < 40) & (x > 500))
    assert_close(draw(colr_font, "B"), ramp(angle / 360), away[..., None].repeat(4, -1)
                 & np.pad(np.ones((96, 96, 4), bool), ((2, 2), (2, 2), (0, 0))))


def test_rotate_around_centre_turns_the_paint_counter_clockwise(colr_font):
    # the horizontal red -> blue ramp turned 90 degrees about the centre runs bottom -> top
    x, y = font_coords()
    assert_close(draw(colr_font, "C")[INNER], ramp(y / 1000)[INNER])


def test_radial_gradient_between_two_circles(colr_font):
    x, y = font_coords()
    assert_close(draw(colr_font, "D")[INNER], ramp(np.hypot(x - 500, y - 500) / 500)[INNER])


def test_colour_line_outside_unit_interval_repeats(colr_font):
    x, _ = font_coords()
    u = (x / 1000 - 0.25) / 0.5
    t = u - np.floor(u)
    seam = np.abs(t - np.round(t)) < 0.03         # the sawtooth's jumps
    assert_close(draw(colr_font, "E"), ramp(t), ~seam[..., None].repeat(4, -1))


def test_porter_duff_composites(colr_font):
    x, y = font_coords()
    inside = (np.abs(x - 500) < 240) & (np.abs(y - 500) < 240)
    outside = (np.abs(x - 500) > 260) | (np.abs(y - 500) > 260)
    src_in = draw(colr_font, "F")            # red kept where the half-opaque blue square is
    assert_close(src_in[inside], np.array([1.0, 0.0, 0.0, 0.5]), tol=2 / 255)
    assert src_in[outside][:, 3].max() == 0
    dest_out = draw(colr_font, "G")          # the green square with the small one cut out
    assert dest_out[inside][:, 3].max() == 0
    ring = outside & (np.abs(x - 500) < 480) & (np.abs(y - 500) < 480)
    assert_close(dest_out[ring], np.array(GREEN, float))


def test_blend_mode_composite(colr_font):
    # multiply: cyan (0, 1, 1) over yellow (1, 1, 0) is green
    assert_close(draw(colr_font, "H")[INNER], np.array(GREEN, float))


def test_clip_box_cuts_the_glyph(colr_font):
    x, _ = font_coords()
    img = draw(colr_font, "I")
    assert_close(img[INNER][(x < 480)[INNER]], np.array(RED, float))
    assert img[INNER][(x > 520)[INNER]][:, 3].max() == 0


def test_foreground_entry_is_the_text_colour(colr_font):
    x, y = font_coords()
    inside = (np.abs(x - 500) < 240) & (np.abs(y - 500) < 240)
    img = draw(colr_font, "J", fill="#00ff00")
    assert_close(img[inside], np.array(GREEN, float))
    ring = (np.abs(x - 500) > 260) & (np.abs(x - 500) < 480) & (np.abs(y - 500) < 480)
    assert_close(img[ring], np.array(BLUE, float))


def test_a_glyph_referencing_itself_draws_the_rest(colr_font, recwarn):
    img = draw(colr_font, "K")
    assert_close(img[INNER], np.array(GREEN, float))
    assert not [w for w in recwarn if issubclass(w.category, RenderWarning)
                and "COLR" in str(w.message)]


def test_exponential_paint_graph_is_cut_with_a_warning(tmp_path):
    # glyph Lk draws L(k-1) twice: 2^25 paints if expanded (nesting within MAX_DEPTH)
    levels = 25
    names = [f"L{k}" for k in range(levels + 1)]
    order = [".notdef", "sq"] + names
    glyphs = {n: TTGlyphPen(None).glyph() for n in order}
    glyphs["sq"] = _square(0, 0, 1000, 1000)
    paints = {"L0": _fill("sq", _solid(4))}
    for k in range(1, levels + 1):
        ref = {"Format": PaintFormat.PaintColrGlyph, "Glyph": f"L{k - 1}"}
        paints[f"L{k}"] = {"Format": PaintFormat.PaintColrLayers, "Layers": [ref, ref]}
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({ord("A"): f"L{levels}"})
    fb.setupGlyf(glyphs)
    fb.setupHorizontalMetrics({n: (1000, 0) for n in order})
    fb.setupHorizontalHeader(ascent=1000, descent=0)
    fb.setupNameTable({"familyName": "ColrTest", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    fb.font["COLR"] = buildCOLR(paints, version=1)
    fb.font["CPAL"] = buildCPAL([PALETTE])
    fb.save(str(tmp_path / "deep.ttf"))
    with pytest.warns(RenderWarning, match="more than"):
        img = draw(tmp_path, "A")
    assert_close(img[INNER], np.array(GREEN, float))       # what was drawn is the square


def test_version_0_records_of_a_version_1_table(colr_font):
    x, y = font_coords()
    inside = (np.abs(x - 500) < 240) & (np.abs(y - 500) < 240)
    ring = (np.abs(x - 500) > 260) & (np.abs(x - 500) < 480) & (np.abs(y - 500) < 480)
    img = draw(colr_font, "L")
    assert_close(img[inside], np.array(RED, float))
    assert_close(img[ring], np.array(BLUE, float))
