"""A <text> whose characters are lines of one element each (svg.text.line.span_lines):
Inkscape's `<tspan sodipodi:role="line" x=.. y=..>` lines, a label inside one tspan. Each line
is laid out as a plain line; the result must be the general route's fills bit for bit (verbs,
points, rule, antialiasing, paint: an objectBoundingBox gradient holds the whole text's em
box), whatever the tspans hold, and the lines must take no per-character step past white
space (no position lists written, no face assignment, no clusters)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from test_text_line import FONTS, GRADIENT, _doc, _escaped, _scene, recording
from test_text_simple import SCRIPTS, SUITE_FONTS, alphabet, needs_suite_fonts, numbers
from vecmsaa.api import load_svg
from vecmsaa.svg.text import layout


def span_lines_taken(monkeypatch):
    """A list that gets True for each text span_lines drew, False for each it left."""
    got = []
    recording(monkeypatch, "span_lines", lambda nodes: got.append(nodes is not None))
    return got


def steps_after_white_space(monkeypatch):
    """A list that gets 'positions' and 'faces' for each per-character step the general
    route takes after white space (apply_positions, assign_faces)."""
    calls = []
    for name, tag in (("apply_positions", "positions"), ("assign_faces", "faces")):
        real = getattr(layout, name)

        def step(*args, real=real, tag=tag):
            calls.append(tag)
            return real(*args)
        monkeypatch.setattr(layout, name, step)
    return calls


#: what a tspan's own attributes may be: most leave it a line, the rest send the text to the
#: general route (or change nothing)
TSPAN_STYLES = ["", "", "", 'font-size="13"', 'fill="url(#g)"', 'text-anchor="end"',
                'text-anchor="middle"', 'font-weight="700"', 'baseline-shift="super"',
                'baseline-shift="-3"', 'visibility="hidden"', 'dx="3"', 'dy="-2.5"',
                'style="stroke:black;stroke-width:0.5"', 'text-decoration="underline"',
                'rotate="0"', 'rotate="20"', 'display="none"', 'textLength="40"',
                'xml:space="preserve"', 'letter-spacing="2"', 'font-family="Noto Serif"',
                'systemLanguage="xx"', 'dx="1 2"', 'dy="0 4"']
#: TSPAN_STYLES' first ones: a tspan of these is a line
LINE_STYLES = 14
SPACES = st.sampled_from(["", "", "", " ", "\n  ", "  \n\t"])


@st.composite
def tspan_texts(draw):
    """A <text> of tspans (and at times its own characters, a title, a nested tspan)."""
    family = draw(st.sampled_from([s[0] for s in SCRIPTS]))
    letters = st.sampled_from(alphabet(family))
    words = st.lists(st.text(letters, min_size=1, max_size=5), min_size=0, max_size=3).map(
        " ".join)
    attrs = [f'font-family="{family}"', f'font-size="{draw(st.sampled_from([7.5, 10, 24]))}"',
             f'text-anchor="{draw(st.sampled_from(["start", "middle", "end"]))}"']
    where = draw(st.integers(0, 6))
    if where == 6:
        attrs.append(f'x="{draw(numbers(0, 300))} {draw(numbers(0, 300))}" y="40"')
    elif where:
        attrs.append(f'x="{draw(numbers(-300, 300))}" y="{draw(numbers(-300, 300))}"')
    if draw(st.integers(0, 3)) == 0:
        attrs.append(f'dx="{draw(numbers(-20, 20))}" dy="{draw(numbers(-20, 20))}"')
    if draw(st.integers(0, 5)) == 0:
        attrs.append(f'rotate="{draw(st.sampled_from(["0", "10", "0 0 0 0 0 0 9"]))}"')
    if draw(st.booleans()):
        attrs.append('xml:space="preserve"')
    if draw(st.integers(0, 4)) == 0:
        attrs.append('fill="url(#g)"')
    if draw(st.integers(0, 4)) == 0:
        attrs.append(f'transform="{draw(st.sampled_from(["rotate(30)", "scale(1.5 0.5)"]))}"')
    # (half of them lines by construction but for white space and what the text has)
    lines = draw(st.booleans())
    body = _escaped(draw(SPACES) + (draw(words) if not lines and draw(st.integers(0, 4)) == 0
                                    else ""))
    y = 0.0
    for k in range(draw(st.integers(1, 4))):
        own = []
        position = draw(st.integers(0, 7 if lines else 9))
        y += 12
        if position < 7:        # Inkscape's lines: both
            own.append(f'x="{draw(numbers(-300, 300))}" y="{y}"')
        elif position == 7:
            own.append(f'x="{draw(numbers(-300, 300))}"')
        elif position == 8:
            own.append(f'y="{y}"')
        own.append(draw(st.sampled_from(TSPAN_STYLES[:LINE_STYLES if lines else None])))
        inner = _escaped(draw(SPACES) + draw(words) + draw(SPACES))
        if not lines and draw(st.integers(0, 12)) == 0:
            inner += f'<tspan fill="blue">{_escaped(draw(words))}</tspan>'
        body += f'<tspan {" ".join(own)}>{inner}</tspan>'
        if draw(st.integers(0, 8)) == 0:
            body += "<title>a title</title>"
        tail = draw(SPACES)
        if not lines and draw(st.integers(0, 8)) == 0:
            tail += draw(words)
        body += _escaped(tail)
    return f"<text {' '.join(attrs)}>{body}</text>"


@needs_suite_fonts
@settings(max_examples=200, deadline=None)
@given(st.lists(tspan_texts(), min_size=1, max_size=5))
def test_lines_are_the_general_route_bit_for_bit(texts):
    # the same fills by span_lines (where it takes a text) and by the general route, for the
    # suite's fonts and scripts, white space in and between the tspans, positions on the text
    # and its tspans, tspans' own styles, titles, nested tspans
    with pytest.MonkeyPatch.context() as mp:
        doc = _doc(['<g transform="translate(8000 8000)">'] + texts + ["</g>"], GRADIENT,
                   (16000, 16000))
        assert _scene(doc, True, mp, fonts=SUITE_FONTS) == \
            _scene(doc, False, mp, fonts=SUITE_FONTS)


def test_inkscape_lines_take_no_per_character_step(monkeypatch):
    # Inkscape's texts (xml:space="preserve", a tspan a line with its own x and y), a label in
    # a tspan with white space around it, a text with a title: each laid out as lines, no
    # position list written and no face assigned per character, with the general route's
    # fills
    def ink(i, lines):
        spans = "".join(f'<tspan sodipodi:role="line" x="{20 + i}" y="{30 + 12 * k + i}" '
                        f'style="stroke-width:0.26">line {k} of {i}</tspan>'
                        for k in range(lines))
        return (f'<text xml:space="preserve" style="font-size:10px;line-height:1.25;'
                f'font-family:\'Noto Sans\'" x="{20 + i}" y="{30 + i}">{spans}</text>')
    texts = [ink(i, 1 + i % 3) for i in range(6)] + [
        '<text x="10" y="200" font-family="Noto Sans">\n  <tspan>a label</tspan>\n</text>',
        '<text x="10" y="220" font-family="Noto Sans" text-anchor="middle">'
        '<title>t</title>titled</text>',
        '<text font-family="Noto Sans"><tspan x="50" y="240" fill="url(#g)">one</tspan>'
        '<tspan x="50" y="252" font-size="14" text-anchor="end">two</tspan></text>']
    doc = _doc(texts, GRADIENT).replace(
        b"<svg ", b'<svg xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd" ')
    taken = span_lines_taken(monkeypatch)
    steps = steps_after_white_space(monkeypatch)
    fast = _scene(doc, True, monkeypatch)
    assert taken == [True] * len(texts)
    assert steps == []
    assert fast == _scene(doc, False, monkeypatch)
    assert len(fast) == sum(1 + i % 3 for i in range(6)) + 4


LEFT = [
    # (each needs the general route: span_lines leaves it, with the same fills)
    '<text x="10" y="20" font-family="Noto Sans">ab<tspan>cd</tspan></text>',
    '<text font-family="Noto Sans"><tspan x="1" y="20">a</tspan><tspan y="30">b</tspan></text>',
    '<text font-family="Noto Sans" font-size="20"><tspan x="1" y="20" font-size="10">a</tspan>'
    '\n<tspan x="1" y="30" font-size="10">b</tspan></text>',
    '<text font-family="Noto Sans"><tspan x="1" y="20" baseline-shift="2">a</tspan>\n'
    '<tspan x="1" y="30">b</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><tspan><tspan>a</tspan></tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><a><tspan>a</tspan></a></text>',
    '<text x="10 30" y="20" font-family="Noto Sans"><tspan>ab</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><tspan rotate="0 9">ab</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><tspan textLength="50">ab</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><tspan text-decoration="underline">ab'
    '</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans" writing-mode="tb"><tspan writing-mode="lr">'
    'ab</tspan></text>',
    '<text x="10" y="20" font-family="Noto Sans"><tspan>ab \u05d0\u05d1</tspan></text>',
]


@pytest.mark.parametrize("text", LEFT)
def test_texts_span_lines_leaves(text, monkeypatch):
    taken = span_lines_taken(monkeypatch)
    assert _scene(_doc([text]), True, monkeypatch) == _scene(_doc([text]), False, monkeypatch)
    assert taken == [False]


def test_the_lines_share_the_text_bounding_box(monkeypatch):
    # an objectBoundingBox gradient spans the whole text (SVG: the text's bounding box), not
    # each line: the second, shorter line's fill starts red at the text's left, not its own
    doc = _doc(['<text font-family="Noto Sans" font-size="20" fill="url(#g)">'
                '<tspan x="10" y="30">a long first line</tspan>'
                '<tspan x="100" y="60">b</tspan></text>'], GRADIENT)
    scene = load_svg(doc, **FONTS)
    first, second = list(scene.fills())
    assert repr(first.paint) == repr(second.paint)


def test_lines_of_x_alone_go_down_by_their_dy(monkeypatch):
    # a tspan with an x and no y starts a chunk at the y where the chunk before ends (SVG 2
    # text layout: the current text position), so dy="1.2em" puts each line 1.2 em (24 at
    # font-size 20) below the one before; pretty-printed, the text's line breaks between the
    # tspans are spaces at the lines' ends, which draw nothing
    taken = span_lines_taken(monkeypatch)
    doc = _doc(['<text x="30" y="40" font-family="Noto Sans" font-size="20">\n  '
                '<tspan x="30" dy="0">ab</tspan>\n  <tspan x="30" dy="1.2em">ab</tspan>\n  '
                '<tspan x="30" dy="1.2em">ab</tspan>\n</text>'])
    fills = list(load_svg(doc, **FONTS).fills())
    assert taken == [True] and len(fills) == 3
    points = [f.path.points for f in fills]
    for k in (1, 2):
        assert np.allclose(points[k], points[0] + [0.0, 24.0 * k], atol=1e-9)
    assert _scene(doc, True, monkeypatch) == _scene(doc, False, monkeypatch)
