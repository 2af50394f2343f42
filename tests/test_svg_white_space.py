"""The ``white-space`` property in SVG text (SVG 2 §11.7, CSS Text 3 §4, CSS Text 4 §3) against
the specifications' rules: the shorthand's table of longhand values, the characters that
collapsing keeps, the cascade against ``xml:space``, and the glyphs' positions from the
font's advances (fontTools' reading of the hmtx table)."""
from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.svg.document import Style, load_document
from vecmsaa.svg.text import content

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
TTF = os.path.join(FIXTURES, "NotoSans-Subset.ttf")
FONTS = dict(use_fonts_dir=FIXTURES, skip_system_fonts=True, font_family="Noto Sans")
SVG = 'xmlns="http://www.w3.org/2000/svg"'


@pytest.mark.parametrize("value, collapse", [
    # CSS Text 4 §3.3's table: the shorthand's keywords and the longhand values they set
    ("normal", "collapse"), ("pre", "preserve"), ("nowrap", "collapse"),
    ("pre-wrap", "preserve"), ("break-spaces", "break-spaces"), ("pre-line", "preserve-breaks"),
    # <'white-space-collapse'> || <'text-wrap-mode'>, either order, either alone
    ("preserve nowrap", "preserve"), ("nowrap preserve", "preserve"), ("wrap", "collapse"),
    ("collapse", "collapse"), ("preserve-breaks wrap", "preserve-breaks"),
    ("  PRE  ", "preserve"), ("Break-Spaces", "break-spaces"),
    # invalid: a keyword twice, two of one longhand, a keyword with another, unknown words
    ("pre pre", None), ("wrap nowrap", None), ("preserve collapse", None), ("pre nowrap", None),
    ("bogus", None), ("", None), ("normal wrap", None)])
def test_the_white_space_shorthand_sets_white_space_collapse_as_css_text_4_lists(value, collapse):
    assert content.parse_white_space(value) == collapse


def _chars(body, root=""):
    """The characters of each <text> after white space processing, in document order."""
    class Ctx:
        style = None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        doc = load_document(f"<svg {SVG}{root}>{body}</svg>".encode())
    out = []

    def walk(el):
        if el.tag == "text":
            ctx = Ctx()
            ctx.style = Style(el.specified)
            chars = content.collapse_white_space(content.collect_chars(el, ctx, {}))
            out.append("".join(c.ch for c in chars))
        for child in el.children:
            walk(child)
    walk(doc.root)
    return out


RAW = "  a \t\n b  "


@pytest.mark.parametrize("value, kept", [
    # collapse (CSS Text 3 §4.1.1): the segment break and tab become spaces, a run of spaces
    # is one, and the line's leading and trailing spaces go (§4.1.2)
    ("normal", "a b"), ("nowrap", "a b"),
    # preserve: every space stays; without line boxes a segment break or a tab is one space
    # (SVG 1.1 xml:space="preserve", to which SVG 2 maps the preserved values)
    ("pre", "  a    b  "), ("pre-wrap", "  a    b  "), ("break-spaces", "  a    b  "),
    # preserve-breaks keeps segment breaks for line boxes SVG text does not have: the break
    # is a space like the others, and collapses with them
    ("pre-line", "a b")])
def test_each_value_keeps_the_spaces_css_text_says(value, kept):
    assert _chars(f'<text style="white-space:{value}">{RAW}</text>') == [kept]
    assert _chars(f'<text style="white-space-collapse:{content.parse_white_space(value)}">'
                  f'{RAW}</text>') == [kept]


@pytest.mark.parametrize("body, kept", [
    # SVG 2 §11.7.3: the property set on an element makes its xml:space ignored
    ('<text xml:space="preserve" style="white-space:normal">{}</text>', False),
    ('<text xml:space="default" style="white-space:pre">{}</text>', True),
    # xml:space is mapped by the user agent style sheet: over the inherited value
    ('<text style="white-space:pre"><tspan xml:space="default">{}</tspan></text>', False),
    ('<text style="white-space:normal"><tspan xml:space="preserve">{}</tspan></text>', True),
    ('<text xml:space="preserve"><tspan style="white-space:normal">{}</tspan></text>', False),
    # white-space is inherited (CSS Text 3 §3's property table), also from a group
    ('<g style="white-space:pre"><text>{}</text></g>', True),
    ('<text style="white-space:pre"><tspan>{}</tspan></text>', True),
    ('<text style="white-space:pre"><tspan style="white-space:inherit">{}</tspan></text>',
     True),
    ('<text style="white-space:pre"><tspan style="white-space:unset">{}</tspan></text>', True),
    ('<text style="white-space:pre"><tspan style="white-space:initial">{}</tspan></text>',
     False),
    # style sheets, and the order of declarations: a later longhand overrides the shorthand's
    ('<style>text {{ white-space: pre }}</style><text>{}</text>', True),
    ('<text style="white-space:pre; white-space-collapse:collapse">{}</text>', False),
    ('<text style="white-space-collapse:collapse; white-space:pre">{}</text>', True),
    ('<text style="white-space:pre !important; white-space:normal">{}</text>', True),
    # an invalid declaration is dropped (CSS Syntax 3): xml:space decides
    ('<text xml:space="preserve" style="white-space:bogus">{}</text>', True),
    ('<text xml:space="preserve" style="white-space-collapse:discarded">{}</text>', True),
    ('<style>text {{ white-space: pre }}</style><text style="white-space-collapse:x">{}</text>',
     True),
    # the presentation attribute (SVG 2 §6.6 lists white-space), under any CSS declaration
    ('<text white-space="pre">{}</text>', True),
    ('<text white-space="pre" style="white-space:normal">{}</text>', False),
    ('<text white-space="normal" xml:space="preserve">{}</text>', False),
    # through a custom property (CSS Variables 1): substituted, then expanded and checked
    ('<text style="--ws: pre; white-space: var(--ws)">{}</text>', True),
    ('<g style="--ws: pre"><text style="white-space-collapse: var(--ws, collapse)">{}</text>'
     '</g>', False),
    ('<text style="--c: preserve; white-space-collapse: var(--c)">{}</text>', True),
    # a var() invalid at computed-value time unsets the property (CSS Variables 1 §3.1):
    # the parent's value, not xml:space's (Chromium 150 collapses too)
    ('<text xml:space="preserve" style="white-space: var(--missing)">{}</text>', False),
    ('<text xml:space="preserve" style="--w: bogus; white-space: var(--w)">{}</text>', False),
])
def test_the_cascade_decides_between_white_space_and_xml_space(body, kept):
    assert _chars(body.format("  a  b  ")) == ["  a  b  " if kept else "a b"]


def test_collapsing_across_elements_takes_only_a_space_after_a_collapsible_one():
    # CSS Text 3 §4.1.1: a collapsible space collapses after another collapsible space,
    # across inline element boundaries; a preserved space is not collapsible
    assert _chars('<text>a <tspan style="white-space:pre"> b</tspan></text>') == ["a  b"]
    assert _chars('<text style="white-space:pre">a  <tspan style="white-space:normal">b  c'
                  '</tspan></text>') == ["a  b c"]
    assert _chars('<text>a <tspan> b</tspan></text>') == ["a b"]



@pytest.mark.parametrize("body, kept", [
    # CSS Text 3 §4.1.2: the spaces at the ends of the text (its one line) are removed; a span
    # that is not rendered (display: none, a failing conditional attribute) takes no part, so
    # the ends are those of the rendered text around it
    (' a<tspan display="none">b</tspan>c ', "ac"),
    ('\n  Text<tspan display="none">Text</tspan>Text\n  ', "TextText"),
    (' a<tspan systemLanguage="x-none">b</tspan>c ', "ac"),
    ('<tspan display="none">b</tspan> a ', "a"),
    (' a <tspan display="none">b</tspan>', "a"),
    # §4.1.1: the spaces on both sides of it collapse into one (recorded: resvg keeps both)
    ('a <tspan display="none">b</tspan> c', "a c"),
])
def test_a_span_not_rendered_leaves_the_text_s_end_spaces_removed(body, kept):
    assert _chars(f"<text>{body}</text>") == [kept]

def _advances():
    from fontTools.ttLib import TTFont
    font = TTFont(TTF)
    hmtx, cmap = font["hmtx"], font.getBestCmap()
    return font["head"].unitsPerEm, (lambda ch: hmtx[cmap[ord(ch)]][0])


def _centroids(img, bands):
    """The alpha-weighted x centroid of the ink between each pair of columns."""
    a = img[..., 3].astype(np.float64)
    cols = a.sum(axis=0)
    xs = np.arange(a.shape[1]) + 0.5
    return [float((cols[x0:x1] * xs[x0:x1]).sum() / cols[x0:x1].sum()) for x0, x1 in bands]


def _render(body):
    svg = (f'<svg {SVG} width="400" height="60" font-size="40" font-family="Noto Sans">'
           f'{body}</svg>').encode()
    return render_svg_array(svg, mode="analytic", **FONTS)


def test_preserved_spaces_advance_the_glyphs_by_the_font_s_space_advance():
    """'W', two preserved spaces and 'W' against 'W W' collapsed: the second W moves right by
    one space's advance (hmtx), and its first W stays."""
    upem, adv = _advances()
    space = adv(" ") * 40 / upem
    kept = _render('<text x="10" y="45" style="white-space:pre">W  W</text>')
    collapsed = _render('<text x="10" y="45">W  W</text>')
    w = adv("W") * 40 / upem
    split = int(10 + w + space / 2)       # between the Ws in both
    (a1, b1), (a2, b2) = (_centroids(img, [(0, split), (split, 400)])
                          for img in (kept, collapsed))
    assert a1 == pytest.approx(a2, abs=1e-6)
    assert b1 - b2 == pytest.approx(space, abs=1e-3)


def test_a_tab_and_a_segment_break_in_preserved_text_are_each_one_space():
    spaces = _render('<text x="10" y="45" style="white-space:pre">W  W</text>')
    assert np.array_equal(_render('<text x="10" y="45" style="white-space:pre">W\t\nW</text>'),
                          spaces)
    assert np.array_equal(_render('<text x="10" y="45" style="white-space:break-spaces">'
                                  'W\r\n W</text>'), spaces)


def test_preserved_spaces_are_addressed_by_x_lists_and_anchored_with_the_chunk():
    """Character indices count the preserved spaces (SVG 2 addressable characters): the
    fourth x goes to the second W of 'W  W'; and trailing preserved spaces are part of the
    anchored chunk's advance (SVG 2 text-anchor over all its characters)."""
    upem, adv = _advances()
    space = adv(" ") * 40 / upem
    img = _render('<text x="10 100 200 300" y="45" style="white-space:pre">W  W</text>')
    single = _render('<text x="300" y="45">W</text>')
    assert _centroids(img, [(250, 400)]) == pytest.approx(_centroids(single, [(250, 400)]),
                                                          abs=1e-6)
    end = _render('<text x="390" y="45" text-anchor="end" style="white-space:pre">W  </text>')
    plain = _render(f'<text x="{390 - 2 * space!r}" y="45" text-anchor="end">W</text>')
    assert _centroids(end, [(0, 400)]) == pytest.approx(_centroids(plain, [(0, 400)]), abs=1e-4)


def test_white_space_no_longer_warns_as_unsupported():
    from vecmsaa.diagnostics import RenderWarning, as_python_warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", RenderWarning)
        with as_python_warnings():
            _render('<text x="10" y="45" style="white-space:pre-wrap">W  W</text>')
