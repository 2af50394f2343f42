"""The plain line (svg.text.line): a <text> of one font, one element and one chunk, laid out as
arrays by one kernel. It must give what the general route (clusters and glyphs as objects,
svg.text.layout) gives, bit for bit, and take the general route wherever it does not apply."""
from __future__ import annotations

import os
import struct

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from test_text_chunks import shape_calls
from vecmsaa.api import load_svg
from vecmsaa.svg.text import layout, line

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
FONTS = dict(use_fonts_dir=FIXTURES, skip_system_fonts=True)


def _doc(texts, defs="", size=(400, 300)):
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]}" height="{size[1]}">{defs}'
            f'{"".join(texts)}</svg>').encode()


def _escaped(s):
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _bits(values):
    return b"".join(struct.pack("<d", float(v)) for v in values)


def _scene(doc, enabled, monkeypatch, width=None, fonts=FONTS):
    """Every fill of the document's scene as bytes: verbs, points, rule, antialiasing and
    paint (a gradient on the object bounding box holds the text's em box)."""
    monkeypatch.setattr(line, "ENABLED", enabled)
    scene = load_svg(doc, width=width, **fonts)
    out = []
    for f in scene.fills():
        out.append((f.path.verbs.tobytes(), np.ascontiguousarray(f.path.points).tobytes(),
                    f.rule, f.antialias, repr(f.paint)))
    return out


def recording(monkeypatch, name, record):
    """line.<name> replaced by itself calling ``record(nodes)`` with what it returns."""
    real = getattr(line, name)

    def recorded(*args):
        nodes = real(*args)
        record(nodes)
        return nodes
    monkeypatch.setattr(line, name, recorded)


def plain_lines(monkeypatch, simple=None):
    """A list that gets True for each text the plain line drew (from its characters, from
    the element: simple_text, or as lines of one element each: span_lines), False for each
    it left; ``simple``: a list that gets True for each text simple_text drew."""
    got = []

    def drawn(nodes):
        if nodes is not None:
            got.append(True)

    def simple_drawn(nodes):
        drawn(nodes)
        if simple is not None:
            simple.append(nodes is not None)
    recording(monkeypatch, "plain_line", lambda nodes: got.append(nodes is not None))
    recording(monkeypatch, "simple_text", simple_drawn)
    recording(monkeypatch, "span_lines", drawn)
    return got


# Noto Sans' subset (fixtures/make_fixtures.py): ASCII and a few Latin-1 letters; Roboto
# Flex's: AHOaeno (a variable font: weights are variation locations); combining marks and
# characters no face has go through the fallback (other faces) and missing glyphs
ALPHABET = st.sampled_from(list("AHOaeno fi ffl.,-0123456789WAVAToyÅßçéñü—…") + ["e\u0301"])
def numbers(lo, hi):
    return st.floats(min_value=lo, max_value=hi, allow_nan=False).map(lambda v: round(v, 3))


@st.composite
def text_elements(draw):
    # (a character that is no space: a text of spaces collapses to nothing)
    text = draw(st.sampled_from("AaeHo.é")) + "".join(draw(st.lists(ALPHABET, max_size=30)))
    family = draw(st.sampled_from(["Noto Sans", "Roboto Flex"]))
    size = draw(st.sampled_from([1, 7.5, 10, 13.333, 48, 120]))
    weight = draw(st.sampled_from([400, 700, 250]))
    anchor = draw(st.sampled_from(["start", "middle", "end"]))
    attrs = f'font-family="{family}" font-size="{size}" font-weight="{weight}" ' \
            f'text-anchor="{anchor}"'
    if draw(st.integers(0, 4)):     # (without: at 0, 0, across the image's edge)
        attrs += f' x="{draw(numbers(-100, 4000))}" y="{draw(numbers(-100, 4000))}"'
    if draw(st.booleans()):
        attrs += f' dx="{draw(numbers(-100, 100))}" dy="{draw(numbers(-100, 100))}"'
    if draw(st.booleans()):
        attrs += ' fill="url(#g)"'
    if draw(st.booleans()):
        attrs += ' xml:space="preserve"'
    return f"<text {attrs}>{_escaped(text)}</text>"


GRADIENT = ('<defs><linearGradient id="g"><stop offset="0" stop-color="red"/>'
            '<stop offset="1" stop-color="blue"/></linearGradient></defs>')


@settings(max_examples=300, deadline=None)
@given(st.lists(text_elements(), min_size=1, max_size=6))
def test_plain_line_is_the_general_route_bit_for_bit(texts):
    # the same fills (verbs, points, rule, paint: the em box sets the gradient's matrix)
    # from both routes, for strings, fonts, sizes, anchors and first-character offsets
    with pytest.MonkeyPatch.context() as mp:
        # (a large image: most texts inside it; those across its edge culled, by the
        # general route)
        doc = _doc(texts, GRADIENT, (8000, 8000))
        drawn = plain_lines(mp)
        fast = _scene(doc, True, mp)
        general = _scene(doc, False, mp)
        assert fast == general
        assert len(drawn) == len(texts)


def test_plain_lines_are_taken(monkeypatch):
    # labels and ticks as charts write them, a line of a page: all plain lines
    drawn = plain_lines(monkeypatch)
    texts = ['<text x="10" y="20" font-family="Noto Sans">Label one</text>',
             '<text x="50" y="40" font-family="Noto Sans" text-anchor="middle" '
             'dy="0.71em">0.25</text>',
             '<text x="5" y="60" font-family="Noto Sans" font-size="3">' + "word " * 20
             + '</text>',
             '<text x="5" y="80" font-family="Noto Sans"><tspan>in a tspan</tspan></text>',
             '<text x="5" y="99" font-family="Noto Sans" visibility="hidden">hidden</text>']
    load_svg(_doc(texts), **FONTS)
    assert drawn == [True] * 5
    assert _scene(_doc(texts), True, monkeypatch) == _scene(_doc(texts), False, monkeypatch)


GENERAL = [
    '<text x="10" y="20" font-family="Noto Sans">ab<tspan fill="red">cd</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans" letter-spacing="2">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans" word-spacing="2">a bc</text>',
    '<text x="10" y="20" font-family="Noto Sans" text-decoration="underline">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans" rotate="10">abc</text>',
    '<text x="10 20" y="20" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" dx="0 3" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans" textLength="80">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans" writing-mode="tb">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans">ab \u05d0\u05d1</text>',
    '<text x="10" y="20" font-family="Noto Sans">ab<tspan font-family="Roboto Flex">Hen'
    '</tspan></text>',
]


@pytest.mark.parametrize("text", GENERAL)
def test_other_texts_take_the_general_route(text, monkeypatch):
    drawn = plain_lines(monkeypatch)
    load_svg(_doc([text]), **FONTS)
    assert drawn in ([], [False])
    assert _scene(_doc([text]), True, monkeypatch) == _scene(_doc([text]), False, monkeypatch)


def test_a_line_reaching_past_the_image_is_culled_by_the_general_route(monkeypatch):
    # glyphs that cannot reach the image are left out glyph by glyph (draw._reaching_runs):
    # a line crossing the image's edge goes that way, one inside it does not
    drawn = plain_lines(monkeypatch)
    inside = '<text x="10" y="20" font-family="Noto Sans">inside</text>'
    across = '<text x="350" y="40" font-family="Noto Sans" font-size="30">' \
             'across the edge</text>'
    doc = _doc([inside, across])
    load_svg(doc, **FONTS)
    assert drawn == [True, False]
    assert _scene(doc, True, monkeypatch) == _scene(doc, False, monkeypatch)


def test_a_plain_line_makes_no_object_per_glyph(monkeypatch):
    # a page of lines and labels: no Cluster or Glyph made, one kernel call a text, one
    # HarfBuzz call a distinct text, each glyph's outline looked up once a text (once a
    # document for a repeated short label)
    made = []
    for name in ("Cluster", "Glyph"):
        real = getattr(layout, name)

        def counted(*args, _real=real, **kws):
            made.append(1)
            return _real(*args, **kws)
        monkeypatch.setattr(layout, name, counted)
    kernel_calls = []
    real_kernel = line.line_glyphs

    def kernel(*args):
        kernel_calls.append(len(args[2]))
        return real_kernel(*args)
    monkeypatch.setattr(line, "line_glyphs", kernel)
    outlines = []
    real_outlines = line.glyph_outlines

    def glyph_outlines(face, loc, gids):
        outlines.append(len(gids))
        return real_outlines(face, loc, gids)
    monkeypatch.setattr(line, "glyph_outlines", glyph_outlines)
    calls = shape_calls(monkeypatch)
    page = [f'<text x="5" y="{10 + 10 * i}" font-family="Noto Sans" font-size="8">'
            f'line {i:03d} of a page of text set in one font</text>' for i in range(20)]
    ticks = [f'<text x="{20 + 18 * i}" y="280" font-family="Noto Sans" text-anchor="middle">'
             f'{("0.5", "1.0")[i % 2]}</text>' for i in range(20)]
    load_svg(_doc(page + ticks), **FONTS)
    assert made == []
    assert len(kernel_calls) == 40
    # 20 distinct lines (over 16 characters: not kept) and 2 distinct ticks
    assert len(calls) == 22
    assert len(outlines) == 22


def test_labels_alternating_fonts_keep_their_own_glyphs(monkeypatch):
    # the plain lines' memo is per font: the same characters alternating between two fonts
    # draw as the general route draws them (whose glyphs test_text_labels checks against
    # the fonts' cmaps)
    texts = [f'<text x="10" y="{20 + 20 * i}" font-family="{f}">Hen</text>'
             for i, f in enumerate(["Noto Sans", "Roboto Flex"] * 3)]
    doc = _doc(texts)
    fast = _scene(doc, True, monkeypatch)
    assert fast == _scene(doc, False, monkeypatch)
    assert fast[0] != fast[1] and fast[0][0] == fast[2][0]
