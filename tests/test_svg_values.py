"""Property values as CSS reads them (CSS Syntax 3, CSS Values 4, CSS Color 4): rendered
pixels of flat regions compared with the value the grammar gives, computed here."""
from __future__ import annotations

import numpy as np
import pytest

from vecmsaa.api import render_svg_array

NS = 'xmlns="http://www.w3.org/2000/svg"'


def alpha_at_centre(body):
    image = render_svg_array(f'<svg {NS} width="20" height="20">{body}</svg>')
    return image[10, 10, 3] / 255


# an <alpha-value> is one token, a <number> or a <percentage> (the % right after the digits);
# None: invalid, so no declared value, and these elements have no parent to inherit from
OPACITIES = [("0.5", 0.5), ("50%", 0.5), (" 0.25 ", 0.25), ("+.5", 0.5), ("5e-1", 0.5),
             ("150%", 1.0), ("-20%", 0.0), ("50 %", None), ("0.5px", None), ("1_0", None),
             ("nan", None), ("inf", None), ("0.5 0.5", None)]


@pytest.mark.parametrize("prop", ["opacity", "fill-opacity"])
@pytest.mark.parametrize("value,want", OPACITIES)
@pytest.mark.parametrize("as_style", [False, True])
def test_opacity_values_follow_the_alpha_value_grammar(prop, value, want, as_style):
    decl = f'style="{prop}: {value}"' if as_style else f'{prop}="{value}"'
    got = alpha_at_centre(f'<rect width="20" height="20" fill="green" {decl}/>')
    assert got == pytest.approx(1.0 if want is None else want, abs=1 / 255)


def render(body):
    return render_svg_array(f'<svg {NS} width="60" height="60">{body}</svg>')


STAR = '<path d="M30,2 L12,58 L57,21 L3,21 L48,58 Z" fill="green" {}/>'
LINE = '<path d="M10,30 L50,30 L30,50" fill="none" stroke="green" stroke-width="12" {}/>'
# (element with one property, its value in lower case): each value changes the drawing
KEYWORDS = [
    ('<rect width="60" height="60" fill="green" {}/>', "visibility", "hidden"),
    ('<rect width="60" height="60" fill="green" {}/>', "display", "none"),
    (STAR, "fill-rule", "evenodd"),
    ('<clipPath id="c"><path d="M30,2 L12,58 L57,21 L3,21 L48,58 Z" {}/></clipPath>'
     '<rect width="60" height="60" fill="green" clip-path="url(#c)"/>', "clip-rule", "evenodd"),
    (LINE, "stroke-linecap", "round"),
    (LINE, "stroke-linejoin", "bevel"),
    (LINE.replace('fill="none"', 'fill="blue"'), "paint-order", "stroke"),
    ('<mask id="m" {}><rect width="60" height="60" fill="blue" fill-opacity="0.5"/></mask>'
     '<rect width="60" height="60" fill="green" mask="url(#m)"/>', "mask-type", "alpha"),
]


@pytest.mark.parametrize("element,prop,value", KEYWORDS)
@pytest.mark.parametrize("case", [str.upper, str.title])
@pytest.mark.parametrize("as_style", [False, True])
def test_keywords_are_ascii_case_insensitive(element, prop, value, case, as_style):
    """CSS Values 4 §2.1: keywords are ASCII case-insensitive, and SVG 2 parses presentation
    attributes as CSS values: ``HIDDEN`` is ``hidden``, not an invalid value."""
    def decl(v):
        return f'style="{prop}: {v}"' if as_style else f'{prop}="{v}"'
    lower = render(element.format(decl(value)))
    assert not np.array_equal(lower, render(element.format(""))), "the value must matter"
    assert np.array_equal(render(element.format(decl(case(value)))), lower)


def test_hidden_and_evenodd_in_capitals_draw_what_the_keywords_mean():
    assert render('<rect width="60" height="60" fill="green" visibility="HIDDEN"/>')[..., 3].max() == 0
    # the star's centre is wound twice: inside for nonzero, outside for evenodd
    assert render(STAR.format('fill-rule="EVENODD"'))[30, 30, 3] == 0
    assert render(STAR.format(''))[30, 30, 3] == 255


@pytest.mark.parametrize("decl", ['color="currentColor"', 'style="color: currentColor"'])
def test_current_color_as_the_colour_property_is_inherit(decl):
    """CSS Color 4 §4.4: ``color: currentColor`` is ``color: inherit``, so the shape's
    currentColor fill is its parent's colour, blue."""
    image = render(f'<g color="blue"><rect width="60" height="60" {decl} fill="currentColor"/>'
                   '</g>')
    assert tuple(image[30, 30]) == (0, 0, 255, 255)
