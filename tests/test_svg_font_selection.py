"""Font selection for SVG text against CSS Fonts 4 and the fonts' own tables (session 24,
helper chrfont24): font-style's grammar and oblique angles, variation selectors, the
font-optical-sizing property, and the font feature properties that are no presentation
attributes. Each case was drawn three ways (vecmsaa, resvg 0.48.1, Chromium 150); where
vecmsaa differed, the other two agreed with the specification as asserted here."""
import os

import numpy as np
import pytest
from fontTools.ttLib import TTFont

from test_svg_text import SUITE, render_with_suite_fonts

from vecmsaa.svg.text.font_match import parse_font_style

FONTS = os.path.join(SUITE, "fonts")
needs_suite = pytest.mark.skipif(not os.path.isdir(SUITE),
                                 reason="../shared/resvg-suite not present")


def _text(attrs, text="Typo", family="Noto Sans"):
    return render_with_suite_fonts(f'<text x="10" y="60" font-family="{family}" {attrs}>'
                                   f'{text}</text>')


@pytest.mark.parametrize("value, parsed", [
    ("normal", ("normal", None)), ("italic", ("italic", None)), ("ITALIC", ("italic", None)),
    ("oblique", ("oblique", 14.0)),                # CSS Fonts 4 §2.4: 14deg when omitted
    ("oblique 10deg", ("oblique", 10.0)), ("oblique 0.25turn", ("oblique", 90.0)),
    ("oblique 100grad", ("oblique", 90.0)),
    # normal faces are oblique 0deg in §5.2's matching; a negative angle checks oblique
    # values from 0deg up before any italic (the steps negated)
    ("oblique 0deg", ("normal", 0.0)), ("oblique -20deg", ("normal", -20.0)),
    # invalid: italic takes no angle, the angle is within [-90deg, 90deg] and has a unit
    ("italic 10deg", None), ("oblique 91deg", None), ("oblique 10", None),
    ("oblique 10deg 20deg", None), ("slanted", None)])
def test_font_style_grammar(value, parsed):
    assert parse_font_style(value) == parsed


@needs_suite
def test_oblique_at_zero_or_backwards_takes_the_normal_face():
    # CSS Fonts 4 §5.2 step 4b: `oblique 0deg` is matched by normal faces (oblique 0deg);
    # a negative angle (no face here slants backwards) by them before italic ones. Noto
    # Sans has an italic face, so the oblique default takes it.
    normal = _text('font-style="normal"')
    assert not np.array_equal(normal, _text('font-style="oblique"'))
    for value in ("oblique 0deg", "oblique -5deg", "oblique -20deg"):
        assert np.array_equal(_text(f'font-style="{value}"'), normal), value
    # ... with the weight kept: the bold face is normal too
    assert np.array_equal(_text('font-weight="900" font-style="oblique -20deg"'),
                          _text('font-weight="900"'))


@needs_suite
def test_an_invalid_font_style_is_ignored_and_the_parents_applies():
    italic = render_with_suite_fonts('<g font-style="italic"><text x="10" y="60" '
                                     'font-family="Noto Sans">Typo</text></g>')
    assert np.array_equal(_text('font-style="italic 10deg"'), _text(""))
    assert np.array_equal(render_with_suite_fonts(
        '<g font-style="italic"><text x="10" y="60" font-family="Noto Sans" '
        'font-style="italic 10deg">Typo</text></g>'), italic)


@needs_suite
def test_an_oblique_angle_sets_the_slant_axis():
    # CSS Fonts 4 §5.2: a variable font's slnt axis is set to the oblique angle, counted the
    # other way (OpenType slnt is counter-clockwise); Roboto Flex's axis is read from fvar
    axes = {a.axisTag: a for a in TTFont(os.path.join(FONTS, "RobotoFlex.subset.ttf"))["fvar"].axes}
    slnt = axes["slnt"]
    assert slnt.minValue < -5 < slnt.maxValue == 0
    flex = "Roboto Flex"
    upright = _text("", family=flex)
    assert np.array_equal(_text('font-style="oblique 5deg"', family=flex),
                          _text("style=\"font-variation-settings: 'slnt' -5\"", family=flex))
    assert not np.array_equal(_text('font-style="oblique 5deg"', family=flex), upright)
    # a backward slant is past the axis's maximum (0): clamped upright; so is 0deg
    for value in ("oblique 0deg", "oblique -20deg"):
        assert np.array_equal(_text(f'font-style="{value}"', family=flex), upright), value


@needs_suite
def test_a_variation_selector_the_face_lacks_picks_no_other_face():
    # U+FE0F asks for the emoji presentation; a face without the selector draws its base's
    # default glyph (Unicode §23.4, a default ignorable): the CBDT face, not the Twitter face
    # that has both characters
    cbdt = TTFont(os.path.join(FONTS, "NotoColorEmojiCBDT.subset.ttf")).getBestCmap()
    twitter = TTFont(os.path.join(FONTS, "TwitterColorEmoji.subset.ttf")).getBestCmap()
    assert 0x1F600 in cbdt and 0xFE0F not in cbdt
    assert 0x1F600 in twitter and 0xFE0F in twitter
    alone = _text("", "&#x1F600;", "Noto Color Emoji")
    assert np.array_equal(_text("", "&#x1F600;&#xFE0F;", "Noto Color Emoji"), alone)
    assert not np.array_equal(_text("", "&#x1F600;", "Twitter Color Emoji"), alone)


@needs_suite
def test_font_optical_sizing_none_keeps_the_default_optical_size():
    # CSS Fonts 4 §7.4: auto sets opsz to the font size (24 here), none leaves the axis at
    # its default, read from fvar
    axes = {a.axisTag: a for a in TTFont(os.path.join(FONTS, "RobotoFlex.subset.ttf"))["fvar"].axes}
    default = axes["opsz"].defaultValue
    assert default != 24 and axes["opsz"].minValue <= 24 <= axes["opsz"].maxValue
    flex = "Roboto Flex"
    at = lambda v: _text(f"style=\"font-variation-settings: 'opsz' {v:g}\"", family=flex)
    assert np.array_equal(_text("", family=flex), at(24))
    assert np.array_equal(_text('font-optical-sizing="none"', family=flex), at(default))
    assert np.array_equal(_text('style="font-optical-sizing: none"', family=flex), at(default))
    assert np.array_equal(render_with_suite_fonts(
        f'<g style="font-optical-sizing: none"><text x="10" y="60" font-family="{flex}" '
        f'style="font-optical-sizing: auto">Typo</text></g>'), at(24))


@needs_suite
@pytest.mark.parametrize("prop, value", [
    ("font-variant-numeric", "oldstyle-nums"), ("font-variant-caps", "small-caps"),
    ("font-variant-position", "sub"), ("font-feature-settings", "'onum'")])
def test_font_feature_properties_are_no_presentation_attributes(prop, value):
    # SVG 2 §6.6's list of presentation attributes has font-variant but none of CSS Fonts
    # 4's font-variant-* longhands nor font-feature-settings: as attributes they are ignored,
    # from CSS they apply
    text = "Hx 1234"
    plain = _text("", text, "Noto Serif")
    attr = value.replace("'", "&apos;")
    assert np.array_equal(_text(f'{prop}="{attr}"', text, "Noto Serif"), plain)
    assert not np.array_equal(_text(f'style="{prop}: {value}"', text, "Noto Serif"), plain)


@needs_suite
def test_a_modifier_no_face_has_is_drawn_as_the_missing_glyph_after_its_emoji():
    # U+1F3FD (a skin tone) is in none of the suite's fonts; after the COLR dog it is drawn as
    # the first family's missing glyph, as an unassigned character (U+0378, no extender) is:
    # not dropped into the dog's cluster of the COLR face (whose missing glyph is empty)
    for name in os.listdir(FONTS):
        if name.endswith((".ttf", ".otf")):
            assert 0x1F3FD not in TTFont(os.path.join(FONTS, name)).getBestCmap(), name
    family = "Noto Sans, Noto Color Emoji COLR"
    dog = _text("", "&#x1F436;", family)
    with_modifier = _text("", "&#x1F436;&#x1F3FD;", family)
    assert not np.array_equal(with_modifier, dog)
    assert np.array_equal(with_modifier, _text("", "&#x1F436;&#x378;", family))
