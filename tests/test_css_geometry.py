"""SVG 2's geometry properties given in CSS (SVG 2 §"Geometry Properties", ``d`` §9.3.1):
``x y width height rx ry cx cy r`` and ``d`` are properties whose attributes are presentation
attributes (SVG 2 §6.6's table: on rect, circle, ellipse, image, path, use ...), so a ``<style>`` rule or a ``style`` declaration overrides the attribute (CSS
Cascade 4 §6.4), ``!important`` last; an invalid declaration is dropped (CSS Syntax 3 §8).
Expected pixels are worked out by hand from the geometry each case asks for (Chromium 150
draws every case so); a document that says it is SVG 1.1 keeps the attributes (the resvg
suite's ``structure/style/non-presentational-attribute`` and its ``style-attribute`` twin)."""
import pytest

from vecmsaa import render_svg_array
from vecmsaa.svg import document
from vecmsaa.svg.document import GEOMETRY_KEY, load_document

SVG = "http://www.w3.org/2000/svg"
GREEN = (0, 128, 0, 255)
NONE = (0, 0, 0, 0)


def draw(body, version=""):
    svg = (f'<svg xmlns="{SVG}" width="200" height="200" viewBox="0 0 200 200"{version}>'
           f'{body}</svg>')
    return render_svg_array(svg.encode(), width=200, height=200)


def at(img, x, y):
    return tuple(int(c) for c in img[y, x])


#: (body, points inside the shape CSS makes, points inside the shape the attributes make)
CASES = {
    "sheet x": ('<style>rect{x:100px}</style><rect width="50" height="50" fill="green"/>',
                [(125, 25)], [(25, 25)]),
    "sheet height (the suite's case)": (
        '<style>#r{height:160px}</style><rect id="r" x="20" y="20" width="160" fill="green"/>',
        [(100, 100), (25, 175)], []),
    "style x": ('<rect style="x:100px" width="50" height="50" fill="green"/>',
                [(125, 25)], [(25, 25)]),
    "unitless, as SVG's CSS reads lengths": (
        '<rect style="x:100" width="50" height="50" fill="green"/>', [(125, 25)], [(25, 25)]),
    "percentage of the viewport width": (
        '<rect style="width:50%" width="20" height="50" fill="green"/>', [(90, 25)], []),
    "em of the element's font size": (
        '<rect style="x:5em; font-size:20px" width="50" height="50" fill="green"/>',
        [(125, 25)], [(25, 25)]),
    "calc()": ('<rect style="x:calc(50px + 5em)" font-size="10" width="50" height="50" '
               'fill="green"/>', [(125, 25)], [(25, 25)]),
    "style over sheet": ('<style>rect{x:100px}</style><rect style="x:0px" x="50" width="50" '
                         'height="50" fill="green"/>', [(25, 25)], [(75, 25), (125, 25)]),
    "sheet !important over style": (
        '<style>rect{x:100px !important}</style><rect style="x:0px" x="50" width="50" '
        'height="50" fill="green"/>', [(125, 25)], [(25, 25), (75, 25)]),
    "style !important over sheet !important": (
        '<style>rect{x:100px !important}</style><rect style="x:0px !important" width="50" '
        'height="50" fill="green"/>', [(25, 25)], [(125, 25)]),
    "invalid: the attribute stays": (
        '<rect style="x:bogus" x="100" width="50" height="50" fill="green"/>',
        [(125, 25)], [(25, 25)]),
    "invalid after valid: the valid one stays": (
        '<rect style="x:100px; x:bogus" width="50" height="50" fill="green"/>',
        [(125, 25)], [(25, 25)]),
    "negative width invalid": ('<rect style="width:-5px" width="100" height="50" '
                               'fill="green"/>', [(90, 25)], []),
    "inherit from a group's declaration": (
        '<g style="x:100px"><rect style="x:inherit" width="50" height="50" fill="green"/></g>',
        [(125, 25)], [(25, 25)]),
    "not inherited without inherit": (
        '<g style="x:100px"><rect width="50" height="50" fill="green"/></g>',
        [(25, 25)], [(125, 25)]),
    "rx": ('<rect style="rx:50px" x="0" y="0" width="100" height="100" fill="green"/>',
           [(50, 50)], [(3, 3)]),      # a circle of radius 50: its box's corner is outside
    "rx auto takes ry": ('<rect style="rx:auto" rx="1" ry="50" width="100" height="100" '
                         'fill="green"/>', [(50, 50)], [(3, 3)]),
    "circle r and centre": ('<style>circle{cx:150px; cy:150px; r:40px}</style>'
                            '<circle cx="30" cy="30" r="10" fill="green"/>',
                            [(150, 150), (150, 115)], [(30, 30)]),
    "circle r percentage of the normalized diagonal": (
        '<circle style="r:25%" cx="100" cy="100" r="5" fill="green"/>', [(100, 55)], [(100, 45)]),
    "negative r invalid": ('<circle style="r:-5px" cx="100" cy="100" r="50" fill="green"/>',
                           [(100, 55)], []),
    "ellipse ry auto takes rx": ('<ellipse style="ry:auto" cx="100" cy="100" rx="80" ry="10" '
                                 'fill="green"/>', [(100, 30)], []),
    "d path()": ("<path style=\"d:path('M100 0 H200 V100 H100 Z')\" d=\"M0 0 H50 V50 H0 Z\" "
                 'fill="green"/>', [(150, 50)], [(25, 25)]),
    "d none": ('<style>path{d:none}</style><path d="M0 0 H100 V100 H0 Z" fill="green"/>',
               [], [(50, 50)]),
    "d not a path(): invalid": ('<path style="d:M0 0 H9 V9 Z" d="M0 0 H100 V100 H0 Z" '
                                'fill="green"/>', [(50, 50)], []),
    "image": ('<style>image{x:100px; width:100px; height:100px}</style><image width="20" '
              'height="20" href="data:image/svg+xml;utf8,%3Csvg xmlns=%22http://www.w3.org/'
              '2000/svg%22 viewBox=%220 0 10 10%22%3E%3Crect width=%2210%22 height=%2210%22 '
              'fill=%22green%22/%3E%3C/svg%3E"/>', [(150, 50), (195, 95)], [(10, 10)]),
    "in a clip path": ('<clipPath id="c"><rect style="width:100px; height:100px"/></clipPath>'
                       '<rect width="200" height="200" fill="green" clip-path="url(#c)"/>',
                       [(50, 50)], [(150, 150)]),
    "through use": ('<defs><rect id="a" style="x:100px" width="50" height="50" fill="green"/>'
                    '</defs><use href="#a"/>', [(125, 25)], [(25, 25)]),
    "use x and y": ('<defs><rect id="a" width="50" height="50" fill="green"/></defs>'
                    '<use href="#a" style="x:100px; y:50px" x="10"/>', [(125, 75)], [(35, 25)]),
    "use y from a sheet": ('<style>use{y:100px}</style><defs><rect id="a" width="50" '
                           'height="50" fill="green"/></defs><use href="#a" y="10"/>',
                           [(25, 125)], [(25, 25)]),
    "stroked": ('<style>rect{width:100px; height:100px}</style><rect x="50" y="50" '
                'fill="none" stroke="green" stroke-width="10"/>', [(150, 100), (50, 52)], []),
}


@pytest.mark.parametrize("name", list(CASES))
def test_geometry_properties_from_css(name):
    body, inside, outside = CASES[name]
    img = draw(body)
    for x, y in inside:
        assert at(img, x, y) == GREEN, (name, x, y)
    for x, y in outside:
        assert at(img, x, y) == NONE, (name, x, y)


def test_shape_runs_take_the_css_geometry():
    """Circles and rects drawn together (the builder's shape runs read the attributes of a
    run at once) take the CSS values of the members that have them, the attributes of the
    others."""
    m = ' class="m"'
    circles = "".join(f'<circle{m if i % 2 else ""} cx="20" cy="{10 + 20 * i}" '
                      f'r="8" fill="green"/>' for i in range(10))
    rects = "".join(f'<rect{m if i % 3 == 0 else ""} x="40" y="{4 + 20 * i}" '
                    f'width="12" height="12" fill="green"/>' for i in range(10))
    img = draw(f'<style>circle.m{{cx:150px}} rect.m{{x:100px; width:20px}}</style>'
               f'{circles}{rects}')
    for i in range(10):
        y = 10 + 20 * i
        moved = i % 2 == 1
        assert at(img, 150, y) == (GREEN if moved else NONE)
        assert at(img, 20, y) == (NONE if moved else GREEN)
        wide = i % 3 == 0
        assert at(img, 115, y) == (GREEN if wide else NONE)
        assert at(img, 46, y) == (NONE if wide else GREEN)


def test_use_runs_take_the_css_geometry():
    """<use>s drawn together (the builder's use runs) take each one's CSS x."""
    uses = "".join(f'<use href="#a"{" class=%s" % chr(34) + "m" + chr(34) if i % 2 else ""} '
                   f'y="{20 * i}"/>' for i in range(10))
    img = draw('<style>.m{x:100px}</style><defs><rect id="a" width="10" height="10" '
               f'fill="green"/></defs>{uses}')
    for i in range(10):
        moved = i % 2 == 1
        assert at(img, 105, 20 * i + 5) == (GREEN if moved else NONE)
        assert at(img, 5, 20 * i + 5) == (NONE if moved else GREEN)


def test_bounding_box_takes_the_css_geometry():
    """An objectBoundingBox clip on a rect sized by CSS: the box is the CSS one (a clip
    of its left half keeps x < 100 of a 200-wide rect)."""
    img = draw('<clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="0.5" '
               'height="1"/></clipPath><style>#r{width:200px}</style>'
               '<rect id="r" width="20" height="100" fill="green" clip-path="url(#c)"/>')
    assert at(img, 90, 50) == GREEN
    assert at(img, 110, 50) == NONE


@pytest.mark.parametrize("body", [
    '<style>#r{height:160px}</style><rect id="r" x="20" y="20" width="160" fill="green"/>',
    '<rect x="20" y="20" width="160" style="height:160px" fill="green"/>'])
def test_svg_1_1_documents_keep_the_attributes(body):
    """version="1.1" on the root: SVG 1.1, where x ... r are attributes only and the
    declaration names no property (the resvg suite's two non-presentational-attribute
    tests: nothing drawn)."""
    assert at(draw(body, ' version="1.1"'), 100, 100) == NONE
    assert at(draw(body), 100, 100) == GREEN


def test_geometry_declarations_leave_the_specified_styles():
    """The declarations are read into the attributes and leave no key in any element's
    specified style (which the builder compares and copies)."""
    doc = load_document(f'<svg xmlns="{SVG}" version="1.1"><rect style="x:1px; fill:red"/>'
                        f'</svg>'.encode())
    assert GEOMETRY_KEY not in doc.root.children[0].specified
    assert doc.root.children[0].attrs.get("x") is None
    doc = load_document(f'<svg xmlns="{SVG}"><style>.a{{x:2px}}</style><rect class="a" '
                        f'style="y:1px; fill:red"/></svg>'.encode())
    rect = doc.root.children[1]
    assert GEOMETRY_KEY not in rect.specified and rect.specified["fill"] == "red"
    assert (rect.attrs["x"], rect.attrs["y"]) == ("2px", "1px")


@pytest.mark.parametrize("text, walks", [
    ('<style>.a{fill:red} rect{stroke:blue}</style><rect class="a" x="1"/>', 0),
    ('<rect style="fill:red; stroke-width:2" x="1"/><circle style="opacity:.5"/>', 0),
    ('<rect x="1" width="2"/>', 0),
    ('<style>.a{fill:red}</style><rect class="a" style="x:1px"/>', 1),
    ('<rect style="r:1px"/>', 1)])
def test_the_tree_is_walked_only_where_css_sets_geometry(monkeypatch, text, walks):
    """Decided once per document while its styles are made: a document whose CSS sets no
    geometry property is not walked for them."""
    calls = []
    real = document.apply_geometry_properties
    monkeypatch.setattr(document, "apply_geometry_properties",
                        lambda doc: calls.append(doc) or real(doc))
    load_document(f'<svg xmlns="{SVG}">{text}</svg>'.encode())
    assert len(calls) == walks
