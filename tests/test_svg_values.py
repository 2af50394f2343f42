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
