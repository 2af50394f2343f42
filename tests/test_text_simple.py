"""A <text> of characters alone (svg.text.line.simple_text): recognised from the element, its
white space collapsed on the string (CSS Text white-space, as collapse_white_space does it on
characters), its position lists' first values, its one font spec and face, then laid out as
the plain line's arrays. It must give the general route's fills bit for bit, and take no
per-character step (collect_chars, assign_faces) where it applies."""
from __future__ import annotations

import os
import re

import pytest
from fontTools.ttLib import TTFont
from hypothesis import given, settings, strategies as st

from test_text_line import FONTS, GRADIENT, _doc, _escaped, _scene, plain_lines
from vecmsaa.api import load_svg
from vecmsaa.diagnostics import collecting
from vecmsaa.svg.text import layout, line
from vecmsaa.tools.suite import suite_from_environment

SUITE = suite_from_environment(os.path.join(os.path.dirname(__file__), "..", "..", "shared",
                                            "resvg-suite"))
SUITE_FONT_DIR = os.path.join(SUITE, "fonts")
SUITE_FONTS = dict(use_fonts_dir=SUITE_FONT_DIR, skip_system_fonts=True)
needs_suite_fonts = pytest.mark.skipif(
    not os.path.isfile(os.path.join(SUITE_FONT_DIR, "NotoSansDevanagari-Regular.ttf")),
    reason="needs the suite's fonts")


def per_character_route(monkeypatch):
    """A list that gets one entry per text the per-character route lays out (collect_chars)
    and one per face assignment (assign_faces), as ('chars', n) and ('faces', n)."""
    calls = []
    real_collect, real_assign = layout.collect_chars, layout.assign_faces

    def collect_chars(*args):
        calls.append("chars")
        return real_collect(*args)

    def assign_faces(*args):
        calls.append("faces")
        return real_assign(*args)
    monkeypatch.setattr(layout, "collect_chars", collect_chars)
    monkeypatch.setattr(layout, "assign_faces", assign_faces)
    return calls


# -- the suite's fonts: each with characters of a script its cmap has (fontTools) -----------
#: (family, file, code point ranges of its script), all left to right but Amiri's Arabic
SCRIPTS = [
    ("Noto Sans", "NotoSans-Regular.ttf", [(0x21, 0x7E), (0xC0, 0x17F), (0x391, 0x3C9),
                                           (0x410, 0x44F)]),
    ("Noto Serif", "NotoSerif-Regular.ttf", [(0x21, 0x7E), (0xC0, 0xFF), (0x410, 0x44F)]),
    ("Noto Sans Devanagari", "NotoSansDevanagari-Regular.ttf", [(0x905, 0x94D)]),
    ("Noto Sans Malayalam", "NotoSansMalayalam-Regular.ttf", [(0xD05, 0xD4D)]),
    ("'Mplus 1p'", "MPLUS1p-Regular.ttf", [(0x3041, 0x30FA), (0x4E00, 0x4FFF)]),
    ("Source Sans Pro", "SourceSansPro-Regular.ttf", [(0x21, 0x7E), (0xC0, 0xFF)]),
    ("Yellowtail", "Yellowtail-Regular.ttf", [(0x21, 0x7E)]),
    ("Noto Mono", "NotoMono-Regular.ttf", [(0x21, 0x7E)]),
    ("Amiri", "Amiri-Regular.ttf", [(0x621, 0x64A)]),
]
_ALPHABETS = {}


def alphabet(family):
    """The characters of the family's script ranges that its font's cmap maps (fontTools)."""
    if family not in _ALPHABETS:
        _, name, ranges = next(s for s in SCRIPTS if s[0] == family)
        cmap = TTFont(os.path.join(SUITE_FONT_DIR, name), lazy=True).getBestCmap()
        _ALPHABETS[family] = [chr(c) for lo, hi in ranges for c in range(lo, hi + 1)
                              if c in cmap]
    return _ALPHABETS[family]


#: white space as documents have it between and around words
SPACES = st.sampled_from([" ", " ", " ", "  ", "\n", "\t", "\n    ", " \n\t "])


def numbers(lo, hi):
    return st.floats(min_value=lo, max_value=hi, allow_nan=False).map(lambda v: round(v, 3))


#: user units in a unit (at most: em at the largest size, % of the 16000 wide viewport)
_UNIT = {"": 1, "px": 1, "mm": 3.8, "em": 120, "%": 160}


@st.composite
def lengths(draw, most):
    """A length of at most ``most`` user units either way."""
    unit = draw(st.sampled_from(["", "", "px", "mm", "em", "%"]))
    return f"{draw(numbers(-most / _UNIT[unit], most / _UNIT[unit]))}{unit}"


@st.composite
def simple_texts(draw):
    """(a <text> of characters alone, whether it is a plain line by construction: every
    character in its font, left to right, nothing but what the plain line lays out)."""
    family = draw(st.sampled_from([s[0] for s in SCRIPTS]))
    letters = st.sampled_from(alphabet(family))
    words = draw(st.lists(st.text(letters, min_size=1, max_size=6), min_size=1, max_size=5))
    text = draw(st.sampled_from(["", " ", "\n  "]))
    for i, w in enumerate(words):
        text += (draw(SPACES) if i else "") + w
    text += draw(st.sampled_from(["", " ", "\n"]))
    plain = family != "Amiri"
    if draw(st.integers(0, 9)) == 0:
        # a character from another script: a fallback face or the missing glyph
        text += draw(st.sampled_from(["\u0915", "\u3042", "\u0416", "\U0001F600", "\u05d0"]))
        plain = False
    preserve = draw(st.booleans())
    # (the characters after white space processing: a single text node's)
    n = len(text) if preserve else len(re.sub("[ \t\n]+", " ", text).strip(" "))
    attrs = [f'font-family="{family}"',
             f'font-size="{draw(st.sampled_from([1, 7.5, 10, 13.333, 48, 120]))}"',
             f'text-anchor="{draw(st.sampled_from(["start", "middle", "end"]))}"']
    if draw(st.booleans()):
        attrs.append(f'font-weight="{draw(st.sampled_from([300, 400, 700, 900]))}"')
    where = draw(st.integers(0, 5))
    if where == 5:
        # lists: a value after the first applies to a second character (another chunk, an
        # offset) unless there is one character
        attrs.append(f'x="{draw(numbers(0, 400))} {draw(numbers(0, 400))}" y="50"')
        plain = plain and n == 1
    elif where:
        attrs.append(f'x="{draw(lengths(500))}" y="{draw(lengths(500))}"')
    if draw(st.booleans()):
        attrs.append(f'dx="{draw(lengths(100))}" dy="{draw(lengths(100))}"')
    if draw(st.integers(0, 5)) == 0:
        angle = draw(st.sampled_from(["0", "0 0", "-0", "10", "0 10"]))
        attrs.append(f'rotate="{angle}"')
        plain = plain and (angle in ("0", "0 0", "-0") or angle == "0 10" and n == 1)
    if draw(st.integers(0, 3)) == 0:
        attrs.append(f'transform="{draw(st.sampled_from(["rotate(30)", "scale(1.5 0.5)", "skewX(20)", "matrix(0.5 0.2 -0.3 1.5 40 10)"]))}"')
    if draw(st.booleans()):
        attrs.append('fill="url(#g)"')
    if preserve:
        attrs.append('xml:space="preserve"')
    return f"<text {' '.join(attrs)}>{_escaped(text)}</text>", plain


@needs_suite_fonts
@settings(max_examples=150, deadline=None)
@given(st.lists(simple_texts(), min_size=1, max_size=5))
def test_simple_text_is_the_general_route_bit_for_bit(texts):
    # the same fills (verbs, points, fill rule, paint: the em box sets the gradient's matrix)
    # by the element's route and by the per-character one, for the suite's fonts and their
    # scripts, sizes, anchors, transforms, white space and position lists; a text that is a
    # plain line by construction takes no per-character step
    with pytest.MonkeyPatch.context() as mp:
        # (in the middle of a large image: no glyph culled, which takes the general route)
        doc = _doc(['<g transform="translate(8000 8000)">'] + [t for t, _ in texts]
                   + ["</g>"], GRADIENT, (16000, 16000))
        simple = []
        plain_lines(mp, simple)
        calls = per_character_route(mp)
        mp.setattr(line, "ENABLED", True)
        fast = load_svg(doc, **SUITE_FONTS)
        assert len(simple) == len(texts)
        for (_, plain), taken in zip(texts, simple):
            assert taken or not plain
        # the per-character route only for the texts the element's route left
        assert calls.count("chars") == simple.count(False)
        general = _scene(doc, False, mp, fonts=SUITE_FONTS)
        assert _scene(doc, True, mp, fonts=SUITE_FONTS) == general
        assert len(list(fast.fills())) == len(general)


def test_white_space_collapses_on_the_string(monkeypatch):
    # CSS Text 4 §4.1.1 as SVG applies it to one text node: newlines and tabs are spaces, a
    # run of spaces is one, the text's first and last spaces go (unless xml:space="preserve",
    # which keeps every space, newlines and tabs as spaces): the same fills as the text
    # written collapsed, and as the per-character route's
    def doc(body, attrs=""):
        return _doc([f'<text x="10" y="40" font-family="Noto Sans" font-size="20" {attrs}>'
                     f'{body}</text>'])
    simple = []
    plain_lines(monkeypatch, simple)
    collapsed = _scene(doc("a b c"), True, monkeypatch)
    assert _scene(doc(" \n\ta  \n b\t\tc \n"), True, monkeypatch) == collapsed
    assert _scene(doc(" \n\ta  \n b\t\tc \n"), False, monkeypatch) == collapsed
    kept = _scene(doc(" a  b c  ", 'xml:space="preserve"'), True, monkeypatch)
    assert kept == _scene(doc("\na \tb\nc \t", 'xml:space="preserve"'), True, monkeypatch)
    assert kept == _scene(doc(" a  b c  ", 'xml:space="preserve"'), False, monkeypatch)
    assert kept != collapsed
    assert simple == [True] * 4


def test_rotate_values_that_turn_nothing(monkeypatch):
    # rotate's values that apply are the first n (n characters; the last repeats); zeros and
    # an invalid list (ignored, as resvg) turn no character: a plain line
    simple = []
    plain_lines(monkeypatch, simple)
    texts = ['<text x="10" y="20" font-family="Noto Sans" rotate="0">abc</text>',
             '<text x="10" y="40" font-family="Noto Sans" rotate="-0 0 0 30">abc</text>',
             '<text x="10" y="60" font-family="Noto Sans" rotate="10 x">abc</text>',
             '<text x="10" y="80" font-family="Noto Sans" rotate="0 20">a</text>']
    assert _scene(_doc(texts), True, monkeypatch) == _scene(_doc(texts), False, monkeypatch)
    assert simple == [True] * 4


GENERAL = [
    # (each of these needs the per-character route: the element's route leaves it)
    '<text x="10" y="20" font-family="Noto Sans">ab<tspan>cd</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans">ab<title>t</title> cd</text>',
    '<text x="10 20" y="20" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20 30" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" dx="1 2" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" dy="0 0" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" rotate="5" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" rotate="0 5" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" textLength="90" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" style="text-transform:uppercase" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" letter-spacing="2" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" word-spacing="2" font-family="Noto Sans">a bc</text>',
    '<text x="10" y="20" writing-mode="tb" font-family="Noto Sans">abc</text>',
    '<text x="10" y="20" text-decoration="underline" font-family="Noto Sans">abc</text>',
    '<g text-decoration="line-through"><text x="10" y="20" font-family="Noto Sans">abc</text>'
    '</g>',
    '<text x="10" y="20" font-family="Noto Sans">ab \u05d0\u05d1</text>',
    '<text x="10" y="20" font-family="Roboto Flex">Hen\u00e9</text>',   # é: Noto Sans draws it
    '<text x="10" y="20" font-family="No Such Family">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans" font-size="0">abc</text>',
    '<text x="10" y="20" font-family="Noto Sans"> \n </text>',
    '<text x="350" y="40" font-family="Noto Sans" font-size="30">across the edge</text>',
]


@pytest.mark.parametrize("text", GENERAL)
def test_texts_the_element_route_leaves(text, monkeypatch):
    # the same fills and warnings as the per-character route, which lays each of them out
    simple = []
    plain_lines(monkeypatch, simple)
    calls = per_character_route(monkeypatch)
    warned = {}
    for enabled in (True, False):
        monkeypatch.setattr(line, "ENABLED", enabled)
        with collecting([]) as sink:
            load_svg(_doc([text]), **FONTS)
        warned[enabled] = sink
    assert simple == [False]
    assert calls.count("chars") == 2
    assert warned[True] == warned[False]
    assert _scene(_doc([text]), True, monkeypatch) == _scene(_doc([text]), False, monkeypatch)


def test_a_page_and_labels_take_no_per_character_step(monkeypatch):
    # the lines of a page, chart ticks and labels: no character list, no face assignment,
    # one font face lookup per font spec (not per text), one kernel call a text
    calls = per_character_route(monkeypatch)
    queries = []
    real_face = line._face

    def face(spec, ctx):
        queries.append(id(spec) not in ctx.cache.get("plain faces", {}))
        return real_face(spec, ctx)
    monkeypatch.setattr(line, "_face", face)
    kernel_calls = []
    real_kernel = line.line_glyphs

    def kernel(*args):
        kernel_calls.append(1)
        return real_kernel(*args)
    monkeypatch.setattr(line, "line_glyphs", kernel)
    page = [f'<text x="5" y="{10 + 10 * i}" font-family="Noto Sans" font-size="8">\n  '
            f'line {i:03d} of a page  of text\n</text>' for i in range(20)]
    ticks = [f'<text x="{20 + 18 * i}" y="280" dy="0.71em" font-family="Noto Sans" '
             f'text-anchor="middle">{("0.5", "1.0")[i % 2]}</text>' for i in range(20)]
    labels = [f'<text x="{20 + 18 * i}" y="200" font-family="Roboto Flex" font-weight="700">'
              f'Hen</text>' for i in range(10)]
    load_svg(_doc(page + ticks + labels), **FONTS)
    assert calls == []
    assert len(kernel_calls) == 50
    assert queries.count(True) == 3          # three specs: the page's, the ticks', the labels'


def test_characters_are_counted(monkeypatch):
    # the document's character budget (MAX_TEXT_CHARS) is charged the collapsed characters
    from vecmsaa.svg import builder
    counted = []
    real = builder.TextContext.count_characters

    def count(self, n):
        counted.append(n)
        return real(self, n)
    monkeypatch.setattr(builder.TextContext, "count_characters", count)
    load_svg(_doc(['<text x="1" y="9" font-family="Noto Sans">  a \n b  </text>',
                   '<text x="1" y="29" font-family="Noto Sans" xml:space="preserve"> a  b'
                   '</text>']), **FONTS)
    assert counted == [3, 5]
    monkeypatch.setattr(builder, "MAX_TEXT_CHARS", 6)
    with pytest.raises(Exception, match="longer than"):
        load_svg(_doc(['<text x="1" y="9" font-family="Noto Sans">abcd</text>',
                       '<text x="1" y="29" font-family="Noto Sans">efg</text>']), **FONTS)


@settings(max_examples=500, deadline=None)
@given(st.one_of(st.text("0123456789.+-e ", max_size=8),
                 st.floats(allow_nan=False).map(repr), st.integers().map(str)))
def test_a_plain_number_is_read_as_the_length_list_reads_it(value):
    # the shortcut for x="166.0" gives parse_length_list's one unitless value, sign included,
    # or leaves the value to it
    from vecmsaa.svg.text.line import _plain_number
    from vecmsaa.svg.units import parse_length_list
    v = _plain_number(value)
    if v is not None:
        assert [(struct_bits(v), "")] == [(struct_bits(a), u) for a, u in
                                          parse_length_list(value)]


def struct_bits(v):
    import struct
    return struct.pack("<d", v)


def test_characters_a_face_draws_are_kept_per_face(monkeypatch):
    # (line._draws_all keeps the characters found in a face for the document) a character
    # the face lacks, met after texts of characters it draws, still sends its text to the
    # per-character route
    simple = []
    plain_lines(monkeypatch, simple)
    texts = ['<text x="10" y="20" font-family="Roboto Flex">Hen</text>',
             '<text x="10" y="40" font-family="Roboto Flex">neH</text>',
             '<text x="10" y="60" font-family="Roboto Flex">Hen\u00e9</text>']
    assert _scene(_doc(texts), True, monkeypatch) == _scene(_doc(texts), False, monkeypatch)
    assert simple == [True, True, False]
