"""Documents of many short texts (chart ticks, map and graph labels: Graphviz writes one
``<text>`` per node): what a text costs is decided once per document where it can be (its
font settings per style), and the shortcuts for plain ASCII text give what the general
route gives."""
from __future__ import annotations

import math
import os
import struct

import pytest
from hypothesis import given, settings, strategies as st

from test_text_chunks import face_choices, shape_calls
from vecmsaa.api import load_svg

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
FONTS = dict(use_fonts_dir=FIXTURES, skip_system_fonts=True)


def labels(n, styles, extra=""):
    body = "".join(f'<text x="{10 + i % 20 * 19}" y="{20 + i // 20 * 12}" '
                   f'font-size="{styles[i % len(styles)]}"{extra}>n{i}</text>'
                   for i in range(n))
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" '
            f'font-family="Noto Sans">{body}</svg>').encode()


def specs_made(monkeypatch):
    """A list that gets (viewport, spec) for each font spec build_text makes."""
    from vecmsaa.svg.text import layout
    made = []
    real = layout.font_spec

    def font_spec(style, ctx, el=None):
        spec = real(style, ctx, el)
        made.append((ctx.viewport, spec))
        return spec
    monkeypatch.setattr(layout, "font_spec", font_spec)
    return made


def test_font_settings_made_once_per_style(monkeypatch):
    # 300 labels in two font sizes: two font specs for the document (one per text before)
    made = specs_made(monkeypatch)
    load_svg(labels(300, (10, 12)), **FONTS)
    assert len(made) == 2


def test_font_settings_follow_each_viewport(monkeypatch):
    # letter-spacing in percent is of the viewport's normalized diagonal (SVG 2 §8.9): the
    # same style in two viewports gives two spacings, so two specs, each its own
    seen = specs_made(monkeypatch)
    text = '<text x="0" y="20" letter-spacing="10%">ab</text>'
    doc = ('<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" '
           'font-family="Noto Sans">'
           f'<svg width="100" height="100">{text}{text}</svg>'
           f'<svg width="300" height="300">{text}{text}</svg></svg>').encode()
    load_svg(doc, **FONTS)
    assert len(seen) == 2
    for (w, h), spec in seen:
        assert math.isclose(spec.letter_spacing, 0.1 * math.sqrt((w * w + h * h) / 2),
                            rel_tol=1e-12)


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=st.characters(max_codepoint=0x7F), max_size=40))
def test_ascii_bidi_levels_are_the_crates(text):
    # no ASCII character can raise a level in a left-to-right paragraph: the shortcut gives
    # the levels python-bidi's unicode-bidi crate resolves (then rule L1, which resets to
    # the paragraph level anyway)
    from bidi import get_display
    from vecmsaa.fonts.shape import _crate_levels, bidi_levels
    crate = _crate_levels(get_display(text, base_dir="L", debug=True), text) if text else []
    assert bidi_levels(text) == [0] * len(text) == crate


def _bits(values):
    return [struct.pack("<d", v) for v in values]


finite = st.floats(allow_nan=False, allow_infinity=False)


@settings(max_examples=500, deadline=None)
@given(finite, finite)
def test_cluster_frame_shortcut_is_the_composition(x, y):
    # position_linear writes out the frame of a cluster neither shifted nor squeezed:
    # bit for bit what composing the identity, the translation and the unit squeeze gives
    from vecmsaa.scene.transform import IDENTITY, compose, translate
    from vecmsaa.svg.text.content import Char
    from vecmsaa.svg.text.layout import Cluster, position_linear
    c = Cluster(0, [], None, 10.0, 0.0, 0.0)
    ch = Char("a", None, False)
    ch.dx = x
    ch.dy = y
    position_linear([c], [ch], "start", False)
    want = compose(compose(IDENTITY, translate(x, y)), (1.0, 0.0, 0.0, 1.0, 0.0, 0.0))
    assert _bits(c.frame) == _bits(want)


def test_repeated_labels_shaped_once_per_document(monkeypatch):
    # 200 texts of the same two labels (an axis's ticks in each of many small charts): two
    # HarfBuzz calls and, by the per-character route, two face choices for the document (one
    # per text before); the element's route (line.simple_text) chooses no face per chunk
    from vecmsaa.svg.text import line
    body = "".join(f'<text x="{i % 20 * 19}" y="{10 + i // 20 * 12}">{("0.5", "1.0")[i % 2]}'
                   f'</text>' for i in range(200))
    doc = (f'<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" '
           f'font-family="Noto Sans">{body}</svg>').encode()
    for enabled, choices in ((False, 2), (True, 0)):
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(line, "ENABLED", enabled)
            calls = shape_calls(mp)
            chosen = face_choices(mp)
            load_svg(doc, **FONTS)
            assert len(calls) == 2 and len(chosen) == choices


def test_repeated_labels_keep_their_own_fonts(monkeypatch):
    # the same characters in two fonts, texts alternating: each text's glyphs are its own
    # font's (cmap truth from fontTools), not the first text's
    from fontTools.ttLib import TTFont
    from vecmsaa.svg.text import layout, line
    got = []
    real = layout.draw_clusters
    # (the general route's clusters; plain lines draw the same, test_text_line.py)
    monkeypatch.setattr(line, "ENABLED", False)

    def draw(text_el, chars, clusters, *rest):
        got.append([g.gid for c in clusters for g in c.glyphs])
        return real(text_el, chars, clusters, *rest)
    monkeypatch.setattr(layout, "draw_clusters", draw)
    fonts = {"Noto Sans": "NotoSans-Subset.ttf", "Roboto Flex": "RobotoFlex-Subset.ttf"}
    truth = {}
    for family, name in fonts.items():
        font = TTFont(os.path.join(FIXTURES, name))
        cmap, order = font.getBestCmap(), font.getGlyphOrder()
        truth[family] = [order.index(cmap[ord(ch)]) for ch in "Hen"]
    assert truth["Noto Sans"] != truth["Roboto Flex"]
    families = list(fonts) * 3
    body = "".join(f'<text x="10" y="{20 + 20 * i}" font-family="{f}">Hen</text>'
                   for i, f in enumerate(families))
    load_svg((f'<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">{body}'
              f'</svg>').encode(), **FONTS)
    assert got == [truth[f] for f in families]


def test_labels_in_styles_of_equal_fonts_shaped_once(monkeypatch):
    # each chart's axis is a group of its own (its own Style), their fonts equal: the same
    # tick label in 50 of them is shaped once
    calls = shape_calls(monkeypatch)
    body = "".join(f'<g fill="#{i:06x}" transform="translate({i},0)" font-size="10">'
                   f'<text x="0" y="20">0.5</text></g>' for i in range(50))
    load_svg((f'<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" '
              f'font-family="Noto Sans">{body}</svg>').encode(), **FONTS)
    assert len(calls) == 1


def test_tick_labels_in_their_own_groups_share_one_style(monkeypatch):
    # D3's ticks: each label in a translated group with an opacity of its own, which a text
    # does not inherit: one font spec for the 100 labels (one per group before), and the
    # groups' opacities still apply (half the ink under opacity 0.5, truth: the same label
    # drawn without it)
    from vecmsaa.api import render_svg_array
    made = specs_made(monkeypatch)
    body = "".join(f'<g class="tick" opacity="{0.5 if i == 0 else 1}" '
                   f'transform="translate({i % 10 * 40},{i // 10 * 40})">'
                   f'<text y="20" fill="black">{i}</text></g>' for i in range(100))
    doc = (f'<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" '
           f'font-family="Noto Sans" font-size="20">{body}</svg>').encode()
    load_svg(doc, **FONTS)
    assert len(made) == 1
    half = render_svg_array(doc, **FONTS)[:40, :40, 3].astype(float).sum()
    whole = render_svg_array(doc.replace(b'opacity="0.5"', b'opacity="1"'),
                             **FONTS)[:40, :40, 3].astype(float).sum()
    assert whole > 0 and abs(half / whole - 0.5) < 0.01
