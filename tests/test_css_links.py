""":link and :any-link on SVG's ``a`` (Selectors 4 §9.2 leaves which elements are hyperlinks
to the document language; SVG 2 §16.2: an ``a`` with ``href`` or ``xlink:href``), with the
specificity of one pseudo-class (Selectors 4 §17); :visited never matches (a renderer has no
history; Selectors 4 §9.3 lets a user agent treat every link as unvisited). Chromium 150
draws every case as asserted (an empty href is no link there)."""
import pytest

from vecmsaa import render_svg_array

SVG = "http://www.w3.org/2000/svg"
XLINK = "http://www.w3.org/1999/xlink"
GREEN = (0, 128, 0, 255)
RED = (255, 0, 0, 255)


def colour(body):
    svg = (f'<svg xmlns="{SVG}" xmlns:xlink="{XLINK}" width="20" height="20">{body}</svg>')
    return tuple(int(c) for c in render_svg_array(svg.encode(), width=20, height=20)[10, 10])


@pytest.mark.parametrize("body, expected", [
    ('<style>:link rect{fill:green}</style><a href="#x"><rect width="20" height="20" '
     'fill="red"/></a>', GREEN),
    ('<style>a:link > rect{fill:green}</style><a xlink:href="#x"><rect width="20" height="20" '
     'fill="red"/></a>', GREEN),
    ('<style>:any-link{fill:green}</style><a href="https://example.org/"><rect width="20" '
     'height="20" fill="red"/></a>', RED),       # fill is the a's; the rect's own red stays
    ('<style>:any-link{fill:green}</style><a href="https://example.org/"><rect width="20" '
     'height="20"/></a>', GREEN),                # inherited from the a
    ('<style>a:LINK rect{fill:green}</style><a href="#x"><rect width="20" height="20" '
     'fill="red"/></a>', GREEN),                 # pseudo-class names are ASCII case-insensitive
    ('<style>a:link rect{fill:red}</style><a><rect width="20" height="20" fill="green"/></a>',
     GREEN),                                     # no href: no link
    ('<style>a:link rect{fill:red}</style><a href=""><rect width="20" height="20" '
     'fill="green"/></a>', GREEN),               # an empty one neither (Chromium)
    ('<style>a:link rect{fill:red}</style><a href="" xlink:href="#x"><rect width="20" '
     'height="20" fill="green"/></a>', GREEN),   # href overrides xlink:href
    ('<style>a:link rect{fill:green}</style><a href="#x" xlink:href=""><rect width="20" '
     'height="20" fill="red"/></a>', GREEN),
    ('<style>:link{fill:red}</style><rect href="#x" width="20" height="20" fill="green"/>',
     GREEN),                                     # only a is a hyperlink
    ('<style>a:visited rect{fill:red}</style><a href="#x"><rect width="20" height="20" '
     'fill="green"/></a>', GREEN),
    ('<style>rect:not(:link){fill:green}</style><a href="#x"><rect width="20" height="20" '
     'fill="red"/></a>', GREEN),
    ('<style>a:not(:link) rect{fill:red}</style><a href="#x"><rect width="20" height="20" '
     'fill="green"/></a>', GREEN),
    ('<style>@namespace url(http://www.w3.org/2000/svg); a:link rect{fill:green}</style>'
     '<a href="#x"><rect width="20" height="20" fill="red"/></a>', GREEN),
    ('<style>:link{fill:green}</style><defs><a id="t" href="#x"><rect width="20" height="20"/>'
     '</a></defs><use href="#t"/>', GREEN),
])
def test_link_pseudo_classes(body, expected):
    assert colour(body) == expected


@pytest.mark.parametrize("sheet, expected", [
    (":link rect{fill:green} a rect{fill:red}", GREEN),         # (0,1,1) over (0,0,2)
    ("a rect{fill:red} :link rect{fill:green}", GREEN),
    (":link rect{fill:red} .c{fill:green}", RED),                # (0,1,1) over (0,1,0),
    (".c{fill:red} :link rect{fill:green}", GREEN),              # before or after
    ("a:link rect{fill:green} :link rect{fill:red}", GREEN),    # (0,1,2) over (0,1,1)
    (":link rect{fill:red} rect.c{fill:green}", GREEN),          # (0,1,1) equal: later wins
    ("rect.c{fill:red} :link rect{fill:green}", GREEN),
    (":link rect{fill:red} [fill] rect{fill:green}", GREEN),
])
def test_link_specificity_is_one_pseudo_class(sheet, expected):
    """The specificity of :link is (0,1,0), whatever it is matched through: the cases order
    it against types, classes and attributes, before and after."""
    body = f'<style>{sheet}</style><a href="#x" fill="x"><rect class="c" width="20" height="20"/></a>'
    assert colour(body) == expected
