"""Text whose every character has its own absolute position (PDF converters' and Inkscape's
``x="x1 x2 ..."`` lists: each character starts an anchored text chunk, SVG 2 §11.8): the work
is per distinct chunk, not per chunk, and the glyphs land where the x list and the font's
advances (fontTools' hmtx) put them."""
from __future__ import annotations

import os

import numpy as np
import pytest

from vecmsaa.api import load_svg, render_svg_array
from vecmsaa.tools.suite import suite_from_environment

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
TTF = os.path.join(FIXTURES, "NotoSans-Subset.ttf")
FONTS = dict(use_fonts_dir=FIXTURES, skip_system_fonts=True)
SUITE = suite_from_environment(os.path.join(os.path.dirname(__file__), "..", "..", "shared",
                                            "resvg-suite"))
SUITE_FONTS = dict(use_fonts_dir=os.path.join(SUITE, "fonts"), skip_system_fonts=True)
needs_suite_fonts = pytest.mark.skipif(
    not os.path.isfile(os.path.join(SUITE, "fonts", "TwitterColorEmoji.subset.ttf")),
    reason="needs the suite's fonts")


def svg_doc(body, size=400):
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" '
            f'viewBox="0 0 {size} {size}" font-family="Noto Sans">{body}</svg>').encode()


def font_truth():
    """{char: (glyph id, advance in font units)} and units per em, from fontTools' tables."""
    from fontTools.ttLib import TTFont
    font = TTFont(TTF)
    cmap = font.getBestCmap()
    order = font.getGlyphOrder()
    hmtx = font["hmtx"]
    return ({chr(cp): (order.index(name), hmtx[name][0]) for cp, name in cmap.items()},
            font["head"].unitsPerEm)


class Captured:
    """The clusters build_text hands to draw_clusters (the layout's result)."""

    def __init__(self, monkeypatch):
        from vecmsaa.svg.text import layout, line
        self.clusters = []
        real = layout.draw_clusters
        # (the general route's clusters: plain lines make none, test_text_line.py)
        monkeypatch.setattr(line, "ENABLED", False)

        def draw(text_el, chars, clusters, *rest):
            self.clusters.extend(clusters)
            return real(text_el, chars, clusters, *rest)
        monkeypatch.setattr(layout, "draw_clusters", draw)


def shape_calls(monkeypatch):
    """A list that gets one entry per HarfBuzz shape call."""
    import uharfbuzz
    calls = []
    real = uharfbuzz.shape

    def shape(font, buf, features=None):
        calls.append(1)
        return real(font, buf, features)
    monkeypatch.setattr(uharfbuzz, "shape", shape)
    return calls


def face_choices(monkeypatch):
    """A list that gets one entry per chunk whose faces assign_faces chooses."""
    from vecmsaa.svg.text import font_match
    chosen = []
    real = font_match._chunk_faces

    def chunk_faces(*args):
        chosen.append(1)
        return real(*args)
    monkeypatch.setattr(font_match, "_chunk_faces", chunk_faces)
    return chosen


def test_one_character_chunks_shape_once_per_distinct_character(monkeypatch):
    # 10,000 one-character chunks of 3 distinct characters: 3 HarfBuzz calls (one per
    # distinct chunk), 3 face choices; each of them was made once per chunk
    n = 10_000
    text = "".join("abc"[(i * 7) % 3] for i in range(n))
    xs = " ".join(str(i % 390) for i in range(n))
    calls = shape_calls(monkeypatch)
    chosen = face_choices(monkeypatch)
    load_svg(svg_doc(f'<text y="20" font-size="10" x="{xs}">{text}</text>'), width=400,
             **FONTS)
    assert len(calls) == 3
    assert len(chosen) == 3


def test_chunks_that_differ_in_face_or_size_are_shaped_apart(monkeypatch):
    # the same character in another font size (its own spec) or weight is its own chunk
    # kind: 'a' at two sizes and 'a' bold, each repeated, makes three shapings
    calls = shape_calls(monkeypatch)
    spans = "".join(f'<tspan x="{i * 12}" font-size="{10 if i % 2 else 12}">a</tspan>'
                    for i in range(20))
    spans += "".join(f'<tspan x="{i * 12}" y="60" font-weight="bold">a</tspan>'
                     for i in range(20))
    load_svg(svg_doc(f'<text y="20">{spans}</text>'), width=400, **FONTS)
    assert len(calls) == 3


def test_positions_of_one_character_chunks_are_the_x_list(monkeypatch):
    # every glyph at its own x (and the text's y), at font size / units per em, its glyph
    # the cmap's and its cluster as wide as hmtx says; the last chunk ("cab", beyond the
    # list) continues from the list's last x by the hmtx advances (the subset font has no
    # kerning between these letters)
    truth, upem = font_truth()
    got = Captured(monkeypatch)
    text = "abcabcbbaccab"
    xs = [3.5, 40.0, 17.25, 100.0, 61.0, 5.0, 250.5, 80.0, 120.0, 7.0]
    size = 16.0
    load_svg(svg_doc(f'<text y="30" font-size="{size}" x="{" ".join(map(str, xs))}">'
                     f'{text}</text>'), width=400, **FONTS)
    scale = size / upem
    by_char = sorted(got.clusters, key=lambda c: c.char)
    assert [c.char for c in by_char] == list(range(len(text)))
    pen = None
    for i, c in enumerate(by_char):
        gid, advance = truth[text[i]]
        assert [g.gid for g in c.glyphs] == [gid]
        assert c.width == pytest.approx(advance * scale, abs=1e-9)
        m = c.glyphs[0].matrix
        assert m[:4] == pytest.approx((scale, 0.0, 0.0, -scale), abs=1e-12)
        assert m[4] == pytest.approx(xs[i] if i < len(xs) else pen, abs=1e-9)
        assert m[5] == pytest.approx(30.0, abs=1e-9)
        pen = m[4] + advance * scale


def test_copies_of_a_shaped_chunk_are_laid_out_apart(monkeypatch):
    # repeated chunks get their own clusters and glyphs: each takes its own rotate and
    # letter-spacing (two-character chunks "ab": the spacing after the first cluster only)
    truth, upem = font_truth()
    got = Captured(monkeypatch)
    n = 12
    spans = "".join(f'<tspan x="{10 + 30 * i}">ab</tspan>' for i in range(n))
    rotate = " ".join(str(5 * k) for k in range(2 * n))
    size = 10.0
    load_svg(svg_doc(f'<text y="50" font-size="{size}" letter-spacing="3" '
                     f'rotate="{rotate}">{spans}</text>'), width=400, **FONTS)
    scale = size / upem
    a_width, b_width = truth["a"][1] * scale, truth["b"][1] * scale
    by_char = sorted(got.clusters, key=lambda c: c.char)
    assert len(by_char) == 2 * n
    assert len({id(g) for c in by_char for g in c.glyphs}) == 2 * n   # none shared
    for k, c in enumerate(by_char):
        chunk_x = 10 + 30 * (k // 2)
        if k % 2 == 0:
            assert c.advance == pytest.approx(a_width + 3.0, abs=1e-9)
            x = chunk_x
        else:
            assert c.advance == pytest.approx(b_width, abs=1e-9)
            x = chunk_x + a_width + 3.0
        assert [g.gid for g in c.glyphs] == [truth["ab"[k % 2]][0]]
        angle = np.radians(5 * k)
        m = c.glyphs[0].matrix
        assert m[0] == pytest.approx(np.cos(angle) * scale, abs=1e-9)
        assert m[1] == pytest.approx(np.sin(angle) * scale, abs=1e-9)
        assert m[4] == pytest.approx(x, abs=1e-9)
        assert m[5] == pytest.approx(50.0, abs=1e-9)


@needs_suite_fonts
@pytest.mark.parametrize("font, text, upright", [
    ("NotoSans-Regular.ttf", "office fjord", False),
    ("NotoSans-Regular.ttf", "e\u0301a\u0308\u0323 x", False),
    ("Amiri-Regular.ttf", "\u0645\u0631\u062d\u0628\u0627 abc \u0644\u0644\u0647", False),
    ("NotoSansDevanagari-Regular.ttf", "\u0915\u094d\u0937\u093f \u0939\u093f", False),
    ("TwitterColorEmoji.subset.ttf", "\U0001F3F3\ufe0f\u200d\U0001F308\U0001F1EB\U0001F1F7",
     False),
    ("MPLUS1p-Regular.ttf", "\u7e26\u66f8\u304dAB", True),
])
def test_memo_copies_are_the_shaped_clusters(font, text, upright):
    # shape_chunk with its memo: the first call of a chunk and every later copy (moved to
    # another place in the text) are the clusters a shaping without the memo gives there
    from vecmsaa.fonts.face import load_face
    from vecmsaa.svg.text import layout
    from vecmsaa.svg.text.font_match import FontSpec
    face = load_face(os.path.join(SUITE, "fonts", font))
    spec = FontSpec(("x",), 400, "normal", 100.0, 20.0, (), (), 0.0, 0.0, False)
    whole = text * 3
    n = len(text)
    faces, specs = [face] * len(whole), [spec] * len(whole)
    marks = [upright] * len(whole) if upright else None
    memo = {}
    for start in (0, n, 2 * n):
        for a, b in ((start, start + 1), (start, start + n), (start + 1, start + n)):
            got = layout.shape_chunk(None, faces, specs, a, b, whole, marks, memo)
            fresh = layout.shape_chunk(None, faces, specs, a, b, whole, marks)
            assert got == fresh
            assert all(g is not h for c, d in zip(got, fresh)
                       for g, h in zip(c.glyphs, d.glyphs))
    assert n <= layout.MEMO_CHUNK and len(memo) == 3      # (chunks 1, n and n - 1 long)


@needs_suite_fonts
def test_zero_width_joiner_in_a_chunk_of_its_own_under_letter_spacing():
    # an x per character puts a ZWJ sequence's joiner in a chunk of its own; under
    # letter-spacing (ligatures off, except across joiners) that chunk has a joiner at its
    # ends only, which joins nothing: it was an IndexError (no piece to shape)
    from vecmsaa.svg.text import layout
    assert layout._joined_ligatures((("liga", 0),), "\u200d", 0, 1) == \
        [(0, 1, {"liga": 0})]
    emoji = "\U0001F3F3\ufe0f\u200d\U0001F308"
    xs = " ".join(str(10 + 40 * i) for i in range(len(emoji)))
    svg = svg_doc(f'<text y="60" font-family="Twitter Color Emoji" font-size="30" '
                  f'letter-spacing="2" x="{xs}">{emoji}</text>', size=200)
    img = render_svg_array(svg, width=200, **SUITE_FONTS)
    # without letter-spacing the same chunks draw the same (one-character chunks take no
    # spacing: it goes between characters of a chunk)
    plain = render_svg_array(svg.replace(b'letter-spacing="2" ', b''), width=200,
                             **SUITE_FONTS)
    assert img[..., 3].any()
    assert np.array_equal(img, plain)


def test_list_lengths_in_user_units_and_other_units():
    # x list values: numbers and px as they stand, physical units at 96 dpi, em of the font
    # size, percentages of the viewport width
    from vecmsaa.svg.text import layout
    seen = []
    real = layout.apply_positions

    def spy(text_el, chars, ctx, styles):
        real(text_el, chars, ctx, styles)
        seen.extend((c.x, c.dx) for c in chars)
    layout.apply_positions = spy
    try:
        load_svg(svg_doc('<text y="20" font-size="10" x="1e-05 2px 3 1in 2em 50% -0 7.25" '
                         'dx="1.5 0.5pt">abcdefgh</text>'), width=400, **FONTS)
    finally:
        layout.apply_positions = real
    xs = [x for x, _ in seen]
    assert xs == [1e-05, 2.0, 3.0, 96.0, 20.0, 200.0, 0.0, 7.25]
    assert [dx for _, dx in seen][:2] == [1.5, pytest.approx(0.5 * 4 / 3)]
