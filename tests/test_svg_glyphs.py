"""SVG-in-OpenType glyphs against the OpenType 'SVG ' table specification: the element with
id ``glyph<gid>`` is drawn in font units with y down and the origin at the glyph origin. A
font built here with fontTools holds three such glyphs; at 100 px per em on a baseline at
y = 100, font unit (x, y) is device pixel (x / 10, 100 + y / 10)."""
import os

import numpy as np
import pytest
from fontTools.fontBuilder import FontBuilder
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import newTable
from fontTools.ttLib.tables.S_V_G_ import SVGDocument

from vecmsaa import render_svg_array
from vecmsaa.diagnostics import RenderWarning

SVG = 'xmlns="http://www.w3.org/2000/svg"'


def _square():
    pen = TTGlyphPen(None)
    pen.moveTo((0, 0))
    pen.lineTo((0, 1000))
    pen.lineTo((1000, 1000))
    pen.lineTo((1000, 0))
    pen.closePath()
    return pen.glyph()


@pytest.fixture(scope="module")
def svg_font(tmp_path_factory):
    folder = tmp_path_factory.mktemp("svgfont")
    order = [".notdef", "space", "inner", "root", "broken"]
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", ord("A"): "inner", ord("B"): "root",
                          ord("C"): "broken"})
    fb.setupGlyf({".notdef": TTGlyphPen(None).glyph(), "space": TTGlyphPen(None).glyph(),
                  "inner": _square(), "root": _square(), "broken": _square()})
    fb.setupHorizontalMetrics({n: (1000, 0) for n in order})
    fb.setupHorizontalHeader(ascent=1000, descent=0)
    fb.setupNameTable({"familyName": "SvgGlyphTest", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    table = newTable("SVG ")
    table.docList = [
        # glyph 2: an element inside a document (a gradient def shows the document is whole)
        SVGDocument(f'<svg {SVG}><defs><linearGradient id="g"><stop stop-color="#0000ff"/>'
                    '</linearGradient></defs><rect id="glyph2" x="0" y="-1000" width="500" '
                    'height="1000" fill="url(#g)"/></svg>', 2, 2, False),
        # glyph 3: the document's root is the glyph
        SVGDocument(f'<svg {SVG} id="glyph3"><rect x="500" y="-500" width="500" height="500" '
                    'fill="#00ff00"/></svg>', 3, 3, False),
        SVGDocument('<svg not xml', 4, 4, False),
    ]
    fb.font["SVG "] = table
    fb.save(str(folder / "svg.ttf"))
    return folder


def draw(folder, text):
    svg = (f'<svg {SVG} width="100" height="100"><text x="0" y="100" font-size="100" '
           f'font-family="SvgGlyphTest">{text}</text></svg>')
    return render_svg_array(svg, use_fonts_dir=str(folder), skip_system_fonts=True)


def test_glyph_element_in_font_units_y_down(svg_font):
    img = draw(svg_font, "A")
    assert (img[:, :49] == [0, 0, 255, 255]).all()        # x 0..500, y -1000..0
    assert img[:, 51:, 3].max() == 0


def test_document_root_as_the_glyph(svg_font):
    img = draw(svg_font, "B")
    assert (img[:49, :].reshape(-1, 4)[:, 3] == 0).all()
    assert (img[51:, :49, 3] == 0).all()
    assert (img[51:, 51:] == [0, 255, 0, 255]).all()       # x 500..1000, y -500..0


def test_unreadable_document_leaves_the_outline(svg_font):
    with pytest.warns(RenderWarning, match="cannot be read"):
        img = draw(svg_font, "C")
    assert (img[1:99, 1:99] == [0, 0, 0, 255]).all()


def test_clip_path_of_svg_glyph_text_is_its_shape(svg_font):
    svg = (f'<svg {SVG} width="100" height="100"><clipPath id="c"><text x="0" y="100" '
           'font-size="100" font-family="SvgGlyphTest">A</text></clipPath>'
           '<rect width="100" height="100" fill="#ff0000" clip-path="url(#c)"/></svg>')
    img = render_svg_array(svg, use_fonts_dir=str(svg_font), skip_system_fonts=True)
    assert (img[:, :49] == [255, 0, 0, 255]).all()
    assert img[:, 51:, 3].max() == 0


SUITE_FONTS = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "resvg-suite",
                           "fonts")


@pytest.mark.skipif(not os.path.isfile(os.path.join(SUITE_FONTS, "TwitterColorEmoji.subset.ttf")),
                    reason="../shared/resvg-suite not present")
@pytest.mark.parametrize("family", ["Twitter Color Emoji", "Noto Sans, Twitter Color Emoji"])
def test_emoji_zwj_sequence_is_one_colour_glyph(family):
    # UTS #51: a supported ZWJ sequence shows as one glyph; the font's GSUB ligates
    # white flag + VS16 + ZWJ + rainbow into the rainbow flag (one em wide, in colour)
    svg = (f'<svg {SVG} width="100" height="40"><text x="10" y="30" font-size="20" '
           f'font-family="{family}">\U0001F3F3\uFE0F\u200D\U0001F308</text></svg>')
    img = render_svg_array(svg, use_fonts_dir=SUITE_FONTS, skip_system_fonts=True)
    xs = np.nonzero(img[..., 3].max(axis=0) > 0)[0]
    assert xs.min() >= 10 and xs.max() < 31                # one 20 px em
    ink = img[img[..., 3] == 255][:, :3].astype(int)
    hues = {tuple(c) for c in ink if c.max() - c.min() > 100}
    assert len(hues) >= 5                                  # the rainbow's stripes
