"""SVG front end: XML safety, CSS cascade, colours, units and transforms."""
import math

import numpy as np
import pytest

from vecmsaa.svg import SvgError
from vecmsaa.svg.color import parse_color, parse_svg_color
from vecmsaa.svg.document import load_document
from vecmsaa.svg.units import parse_transform, split_length, to_px, viewbox_transform

SVG = 'xmlns="http://www.w3.org/2000/svg"'


def doc(body, attrs='width="100" height="100"'):
    return load_document(f'<svg {SVG} {attrs}>{body}</svg>'.encode())


# -- colours ----------------------------------------------------------------------------------
@pytest.mark.parametrize("text, expected", [
    ("red", (1, 0, 0, 1)),
    ("ReD", (1, 0, 0, 1)),
    ("#0f0", (0, 1, 0, 1)),
    ("#00ff0080", (0, 1, 0, 128 / 255)),
    ("#1234", (0x11 / 255, 0x22 / 255, 0x33 / 255, 0x44 / 255)),
    ("rgb(255, 0, 0)", (1, 0, 0, 1)),
    ("rgb(100%, 50%, 0%)", (1, 0.5, 0, 1)),
    ("rgba(0, 0, 255, 0.25)", (0, 0, 1, 0.25)),
    ("rgb(0 0 255 / 50%)", (0, 0, 1, 0.5)),
    ("transparent", (0, 0, 0, 0)),
    # hsl(120, 100%, 25%) is CSS's rgb(0, 127.5, 0)
    ("hsl(120, 100%, 25%)", (0, 0.5, 0, 1)),
    ("hsla(240, 100%, 50%, 0.5)", (0, 0, 1, 0.5)),
    ("rgb(300, -5, 0)", (1, 0, 0, 1)),
])
def test_colours(text, expected):
    got = parse_color(text)
    assert got == pytest.approx(expected, abs=1e-9)


# a percentage alpha after commas is invalid in resvg (svgtypes)
@pytest.mark.parametrize("text", ["#12", "#ggg", "rgb(1,2)", "notacolour", "", "url(#a)",
                                  "rgba(0, 127, 0, 50%)"])
def test_invalid_colours(text):
    assert parse_color(text) is None


def test_current_color_keyword():
    assert parse_color("currentColor") == "currentColor"


# CSS Color 4 against independent implementations: the standard library's colorsys for the
# sRGB cylinders, ColorAide (a CSS Color 4 implementation) for the wide spaces and their gamut
# mapping to sRGB (its minde-chroma fit is the specification's §13.2 algorithm).
@pytest.mark.parametrize("h, s, light", [(0, 100, 50), (75, 40, 30), (200, 100, 85),
                                         (330, 10, 60), (-30, 60, 40), (725, 80, 50)])
def test_hsl_matches_colorsys(h, s, light):
    import colorsys
    expected = colorsys.hls_to_rgb((h % 360) / 360, light / 100, s / 100)
    for text in (f"hsl({h}, {s}%, {light}%)", f"hsl({h}deg {s}% {light}%)",
                 f"hsl({h / 360}turn {s} {light} / 1)", f"hsla({h * math.pi / 180}rad,{s}%,{light}%,1)"):
        assert parse_color(text) == pytest.approx((*expected, 1), abs=1e-9), text


@pytest.mark.parametrize("text", [
    "hwb(120 30% 20%)", "hwb(0 0% 0%)", "hwb(250 60% 60%)", "hwb(90deg 0 100 / 0.5)",
    "lab(54.29 80.82 69.88)", "lab(50% 40 -20)", "lab(50 200 0)", "lab(120 0 0)",
    "lch(80 150 200)", "lch(40% 30 90deg / 25%)", "oklab(0.627955 0.224863 0.125846)",
    "oklab(40% -0.3 0.3)", "oklch(0.7 0.4 30)", "oklch(60% 50% 0.5turn)", "oklch(1.2 0.1 0)",
    "color(display-p3 1 0 0)", "color(display-p3 0.2 0.6 0.4 / 0.8)", "color(a98-rgb 0.5 0.1 0.9)",
    "color(prophoto-rgb 0.3 0.7 0.2)", "color(rec2020 0 1 0)", "color(srgb-linear 0.2 0.5 1)",
    "color(srgb 50% 20% 80%)", "color(xyz-d50 0.3 0.4 0.2)", "color(xyz-d65 0.2 0.1 0.5)",
    "color(xyz 0.9505 1 1.089)",
])
def test_wide_gamut_colours_match_coloraide(text):
    coloraide = pytest.importorskip("coloraide")
    c = coloraide.Color(text)
    expected = c.convert("srgb").fit("srgb", method="minde-chroma").coords()
    got = parse_color(text)
    assert got[:3] == pytest.approx(expected, abs=1e-5)   # a fiftieth of an 8-bit level
    assert got[3] == pytest.approx(c.alpha(), abs=1e-9)


@pytest.mark.parametrize("text, expected", [
    ("rgb(0 127.5 0)", (0, 0.5, 0, 1)),            # modern syntax, fractions allowed
    ("rgb(100% 127.5 0% / 0.5)", (1, 0.5, 0, 0.5)),  # numbers and percentages mixed
    ("rgb(none 255 none)", (0, 1, 0, 1)),           # none is zero
    ("rgba(255 0 0 / -1)", (1, 0, 0, 0)),           # alpha clamped to [0, 1]
    ("rgb(0 0 0 / 150%)", (0, 0, 0, 1)),
    ("hsl(120 200% 25%)", (0, 0.5, 0, 1)),          # saturation clamped
    ("RGB(255, 0, 0)", (1, 0, 0, 1)),
    ("CanvasText", (0, 0, 0, 1)),                   # system colours
    ("Canvas", (1, 1, 1, 1)),
])
def test_css4_colour_syntax(text, expected):
    assert parse_color(text) == pytest.approx(expected, abs=1e-9)


def test_deprecated_system_colours_map_as_css_color_4_says():
    # §6.3: each CSS 2 system colour computes to the named CSS 4 one
    for old, new in (("WindowText", "CanvasText"), ("Window", "Canvas"), ("Menu", "Canvas"),
                     ("ThreeDFace", "ButtonFace"), ("InactiveCaptionText", "GrayText"),
                     ("ActiveBorder", "ButtonBorder")):
        assert parse_color(old) == parse_color(new)


@pytest.mark.parametrize("text", ["hwb(120, 30%, 20%)", "lab(50, 10, 10)", "rgb(1 2 3 4 5)",
                                  "rgb(1, 2 3)", "rgb(1 2 3 /)", "rgb(1, none, 3)",
                                  "color(foo 1 2 3)", "color(srgb 1 2)", "hsl(10% 50% 50%)",
                                  "lch(50 10 10%)", "notafunction(1 2 3)"])
def test_invalid_css4_colours(text):
    assert parse_color(text) is None


# Colours inside documents follow resvg's reading (svgtypes): 8-bit channels, rounded half away
# from zero and saturated; the first rgb() channel decides whether the others are percentages.
@pytest.mark.parametrize("text, expected", [
    ("rgb(0, 127, 0)", (0, 127, 0, 255)),
    ("rgb(0 127 0)", (0, 127, 0, 255)),
    ("rgb(0 127 0 0.5)", (0, 127, 0, 128)),          # an alpha after spaces
    ("rgb(0.5, 127.5, 254.49)", (1, 128, 254, 255)),
    ("rgb(-10%, 50%, 120%)", (0, 128, 255, 255)),
    ("rgb(50%, 0.2, 0)", (128, 51, 0, 255)),          # after a percentage: 0.2 of 255
    ("rgba(0, 127, 0, -1)", (0, 127, 0, 0)),
    ("rgba(0, 127, 0, 2)", (0, 127, 0, 255)),
    ("rgb(1e2, 0, 0)", (100, 0, 0, 255)),
    ("rgb(1e999, -1e999, 0)", (255, 0, 0, 255)),   # infinities saturate as any number
    ("hsl(120, 100%, 25%)", (0, 128, 0, 255)),        # 127.5 rounds up
    ("hsl(-120, 100%, 50%)", (0, 0, 255, 255)),
    ("hsl(480, 100%, 50%)", (0, 255, 0, 255)),
    ("hsla(120, 200%, 25%, 0.5)", (0, 128, 0, 128)),  # saturation clamped
    ("#0f08", (0, 255, 0, 136)), (" Red ", (255, 0, 0, 255)), ("transparent", (0, 0, 0, 0)),
])
def test_document_colours_read_as_resvg(text, expected):
    got = parse_svg_color(text)
    assert tuple(round(c * 255, 6) for c in got) == expected


@pytest.mark.parametrize("text", [
    "rgb(127, 50%, 0)",           # a percentage after a number
    "rgba(0, 127, 0, 50%)", "rgb(0 127 0 / 0.5)", "hsla(120, 100%, 25%, 50%)",
    "hsl(120deg, 100%, 25%)", "hwb(120 0% 50%)", "lab(50 20 30)", "Canvas", "CurrentColor",
    "rgb (0, 0, 0)", "red icc-color(x, 1)", "#12", "", "rgb(0, 0)",
])
def test_document_colours_resvg_rejects(text):
    assert parse_svg_color(text) is None


# -- units and transforms -----------------------------------------------------------------------
def test_lengths():
    assert split_length(" 12.5mm ") == (12.5, "mm")
    assert to_px(1, "in") == 96
    assert to_px(25.4, "mm") == pytest.approx(96)
    assert to_px(12, "pt") == pytest.approx(16)
    assert to_px(1, "pc") == 16
    assert to_px(2, "em", font_size=10) == 20
    assert to_px(2, "ex", font_size=10) == 10
    assert to_px(50, "%", reference=300) == 150
    assert split_length("12 px") is None or split_length("12 px") == (12.0, "px")
    assert split_length("abc") is None


def test_transform_list_applies_right_to_left():
    # translate(10, 0) scale(2): the point (1, 1) → (2, 2) → (12, 2)
    m = parse_transform("translate(10) scale(2)")
    a, b, c, d, e, f = m
    assert (a * 1 + c * 1 + e, b * 1 + d * 1 + f) == pytest.approx((12, 2))


@pytest.mark.parametrize("css, svg", [
    # CSS Transforms: units on angles and lengths, the single-axis functions, skew(x, y)
    ("rotate(45deg)", "rotate(45)"), ("rotate(0.125turn)", "rotate(45)"),
    ("rotate(50grad)", "rotate(45)"), (f"rotate({math.pi / 4}rad)", "rotate(45)"),
    ("translate(10px, 2in)", "translate(10 192)"), ("translateX(5px)", "translate(5 0)"),
    ("translateY(1pc)", "translate(0 16)"), ("scaleX(2)", "scale(2 1)"),
    ("scaleY(50%)", "scale(1 0.5)"), ("skew(30deg)", "skewX(30)"),
    ("skew(10deg, 20deg)", "matrix(1 0.36397023 0.17632698 1 0 0)"),
    ("translate(10-5)", "translate(10, -5)"),   # SVG: no separator needed before a sign
])
def test_css_transform_syntax(css, svg):
    assert parse_transform(css) == pytest.approx(parse_transform(svg), abs=1e-7)


@pytest.mark.parametrize("text", ["rotate(45) invalid", "rotate(10 5)", "translate(10%)",
                                  "translate(1 2 3)", "scale(2px)", "skewX(1 2)", "foo(1)",
                                  "matrix(1 0 0 1 0)", "rotate(45em)"])
def test_malformed_transforms(text):
    assert parse_transform(text) is None


@pytest.mark.parametrize("prop, value, attr", [
    ("transform", "translate(-10-10)", "translate(-10 -10)"),
    ("transform", "matrix(1 0 0 1 5-5)", "matrix(1 0 0 1 5 -5)"),
    ("stroke-dasharray", "5-5", "5 -5"),
])
def test_declaration_values_keep_the_tokens_as_written(prop, value, attr):
    # a value in a declaration reads as the same text in a presentation attribute: tokens
    # that run together (`-10-10`: two numbers) stay two, not joined by an empty comment
    from vecmsaa.svg.document import load_document
    d = load_document(f'<svg xmlns="http://www.w3.org/2000/svg"><style>#a {{ {prop}: {value} }}'
                      f'</style><rect id="a"/><rect id="b" style="{prop}:{value}"/></svg>'
                      .encode())
    assert d.lookup("#a").specified[prop] == attr
    assert d.lookup("#b").specified[prop] == attr


def test_rotate_about_a_point():
    m = parse_transform("rotate(90, 10, 10)")
    a, b, c, d, e, f = m
    # (20, 10) rotates a quarter turn clockwise (y down) about (10, 10) to (10, 20)
    assert (a * 20 + c * 10 + e, b * 20 + d * 10 + f) == pytest.approx((10, 20))


def test_skew_and_matrix():
    a, b, c, d, e, f = parse_transform("skewX(45)")
    assert (a, b, c, d) == pytest.approx((1, 0, 1, 1))
    assert parse_transform("matrix(1 2 3 4 5 6)") == (1, 2, 3, 4, 5, 6)
    assert parse_transform("scale(2") is None
    assert parse_transform("bogus(1)") is None


@pytest.mark.parametrize("text, numbers", [
    ("1 2 3", [1, 2, 3]), ("1,2, 3 ,4", [1, 2, 3, 4]), ("  1e1\n-.5 ", [10, -0.5]),
    ("10-5", [10, -5]), ("1,", [1]), ("", []),
    # anything but numbers separated by whitespace and one comma: no list
    ("5px", None), ("5,,3", None), ("x5", None), ("0.5;", None), (",1", None), ("1 e", None)])
def test_number_lists_follow_the_comma_wsp_grammar(text, numbers):
    from vecmsaa.svg.units import parse_number_list
    assert parse_number_list(text) == numbers


@pytest.mark.parametrize("text, box", [
    ("0 0 100 50", (0, 0, 100, 50)), ("0,0,100,50", (0, 0, 100, 50)),
    ("0 0 100px 50", None), ("0 0 100,,50", None), ("x0 0 100 50", None),
    ("0 0 100 50 5", None)])
def test_viewbox_is_four_numbers(text, box):
    from vecmsaa.svg.units import parse_viewbox
    assert parse_viewbox(text) == box


def test_viewbox_meet_and_slice():
    # 200 x 100 viewBox into a 100 x 100 viewport
    assert viewbox_transform((0, 0, 200, 100), ("xMidYMid", False), 100, 100) == \
        pytest.approx((0.5, 0, 0, 0.5, 0, 25))
    assert viewbox_transform((0, 0, 200, 100), ("xMinYMin", True), 100, 100) == \
        pytest.approx((1, 0, 0, 1, 0, 0))
    assert viewbox_transform((0, 0, 200, 100), ("xMaxYMax", True), 100, 100) == \
        pytest.approx((1, 0, 0, 1, -100, 0))
    assert viewbox_transform((10, 10, 200, 100), ("none", False), 100, 100) == \
        pytest.approx((0.5, 0, 0, 1, -5, -10))


# -- cascade ----------------------------------------------------------------------------------
def test_css_specificity_and_order():
    d = doc("""<style>
        rect { fill: red }
        .a { fill: blue }
        #r { fill: green }
        rect.a { stroke: yellow }
        rect { stroke: black }
    </style><rect id="r" class="a" fill="purple"/>""")
    r = d.ids["r"]
    assert r.specified["fill"] == "green"
    assert r.specified["stroke"] == "yellow"   # higher specificity wins over a later rule


def test_style_attribute_beats_css_and_important_beats_style_attribute():
    d = doc("""<style>#r { fill: red } #r { stroke: red !important }</style>
        <rect id="r" style="fill: green; stroke: blue" stroke="black"/>""")
    r = d.ids["r"]
    assert r.specified["fill"] == "green"
    assert r.specified["stroke"] == "red"


@pytest.mark.parametrize("attrs, prop, want", [
    # SVG 2 parses presentation attributes as CSS values: CSS Syntax 3 drops comments while
    # tokenizing, except inside strings and url() (Mozilla's comments-in-pres-attrs reftest)
    ('fill="/* comment */lime/* also comment */"', "fill", "lime"),
    ('stroke-width=" 2/**/"', "stroke-width", "2"),
    ('stroke-dasharray="5/**/6"', "stroke-dasharray", "5 6"),
    ('stroke-dasharray="5,/* a, b */6"', "stroke-dasharray", "5,6"),
    ('font-family="\'a/*b*/c\', serif"', "font-family", "'a/*b*/c', serif"),
    ('fill="url(#a/*b*/c) /*d*/ red"', "fill", "url(#a/*b*/c) red"),
    ('opacity="/*.5*/"', "opacity", ""),
])
def test_comments_in_presentation_attributes(attrs, prop, want):
    d = doc(f'<rect id="r" {attrs}/>')
    got = d.ids["r"].specified[prop]
    assert " ".join(got.replace('"', "'").split()) == want     # white space as CSS reads it


@pytest.mark.parametrize("root, rect, fill", [
    # Selectors 4 :lang(): the element's language, inherited from its nearest ancestor that
    # sets one; SVG 2 takes HTML's lang attribute on SVG elements, xml:lang first when both
    # are set; "" is an unknown language; ranges match by prefix up to a hyphen
    ('lang="foo"', '', "green"),
    ('xml:lang="foo"', '', "green"),
    ('', 'lang="FOO"', "green"),
    ('lang="foo-BAR"', '', "green"),
    ('lang="foobar"', '', "red"),
    ('lang="it"', '', "red"),
    ('lang="foo"', 'lang="it"', "red"),
    ('xml:lang="it"', 'lang="foo"', "green"),
    ('', 'xml:lang="it" lang="foo"', "red"),
    ('', 'xml:lang="foo" lang="it"', "green"),
    ('lang="foo"', 'lang=""', "red"),
    ('', '', "red"),
])
def test_css_lang_pseudo_class_reads_lang_and_xml_lang(root, rect, fill):
    d = load_document(f'<svg xmlns="http://www.w3.org/2000/svg" {root}><style>'
                      f'rect {{ fill: red }} rect:lang(foo) {{ fill: green }}</style>'
                      f'<g><rect id="r" {rect}/></g></svg>'.encode())
    assert d.ids["r"].specified["fill"] == fill


@pytest.mark.parametrize("css, fill", [
    # CSS Namespaces 3 §2: a prefix declared by @namespace qualifies type and attribute
    # selectors; declared for another URL it matches nothing
    ("@namespace svg url(http://www.w3.org/2000/svg); svg|rect { fill: green }", "green"),
    ('@namespace svg "http://www.w3.org/2000/svg"; svg|* { fill: green }', "green"),
    ('@import url(x.css); @namespace s url("http://www.w3.org/2000/svg"); s|rect { fill: green }',
     "green"),
    ("@namespace svg url(http://example.org); rect { fill: green } svg|rect { fill: red }", "green"),
    # a default namespace qualifies unprefixed type selectors, not attribute selectors
    ("@namespace url(http://example.org); rect { fill: red } [id=r] { fill: green }", "green"),
    ("@namespace url(http://www.w3.org/2000/svg); rect { fill: green }", "green"),
    ("@namespace url(http://example.org); *|rect { fill: green }", "green"),
    ("@namespace xl url(http://www.w3.org/1999/xlink); [xl|href] { fill: green }", "green"),
    # an undeclared prefix invalidates the rule; @namespace after a rule is ignored (§2);
    # a declaration holds for its own style sheet only
    ("rect { fill: green } svg|rect { fill: red }", "green"),
    ("rect { fill: green } @namespace svg url(http://www.w3.org/2000/svg); svg|rect { fill: red }",
     "green"),
    ("@namespace svg url(http://example.org) junk; rect { fill: green } svg|rect { fill: red }",
     "green"),
    ("@namespace svg url(http://www.w3.org/2000/svg);</style><style>rect { fill: green }"
     " svg|rect { fill: red }", "green"),
])
def test_css_namespace_prefixes(css, fill):
    d = doc(f'<style>{css}</style><rect id="r" xmlns:xlink="http://www.w3.org/1999/xlink" '
            f'xlink:href="#r"/>')
    assert d.ids["r"].specified.get("fill") == fill


@pytest.mark.parametrize("group, own, rgba", [
    # CSS Cascade 4 §7.3: unset inherits an inherited property...
    ('fill="green"', 'style="fill: unset"', (0, 128, 0, 255)),
    ('fill="green"', 'fill="UNSET"', (0, 128, 0, 255)),
    ('fill="green"', 'style="fill: red; fill: unset"', (0, 128, 0, 255)),
    ('color="green"', 'fill="currentColor" style="color: unset"', (0, 128, 0, 255)),
    ('fill-opacity="0.5"', 'fill="#00f" style="fill-opacity: unset"', (0, 0, 255, 128)),
    # ... and is the initial value of one that is not (a group's opacity still applies once)
    ('opacity="0.5"', 'fill="#00f" style="opacity: unset"', (0, 0, 255, 128)),
    # §7.1: initial is the property's initial value, not the parent's
    ('fill="red"', 'style="fill: initial"', (0, 0, 0, 255)),
    ('fill-opacity="0.5"', 'fill="#00f" style="fill-opacity: initial"', (0, 0, 255, 255)),
])
def test_css_wide_keywords_unset_and_initial(group, own, rgba):
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg {SVG} width="10" height="10"><g {group}><rect width="10" '
                           f'height="10" {own}/></g></svg>'.encode(), width=10)
    assert tuple(int(v) for v in img[5, 5]) == pytest.approx(rgba, abs=1)


@pytest.mark.parametrize("own, width", [
    ('style="stroke-width: unset"', 8), ('style="stroke-width: initial"', 1)])
def test_css_wide_keywords_on_a_stroke_width(own, width):
    # a vertical stroke: the coverage summed across a row is its width
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg {SVG} width="100" height="10"><g stroke="#000" stroke-width="8">'
                           f'<path d="M50 0V10" {own}/></g></svg>'.encode(), width=100)
    assert img[5, :, 3].sum() / 255 == pytest.approx(width, abs=0.05)


def test_presentation_attributes_are_the_weakest():
    d = doc('<style>rect { fill: green }</style><rect id="r" fill="red"/>')
    assert d.ids["r"].specified["fill"] == "green"


def test_an_empty_declaration_is_dropped_and_what_it_would_override_applies():
    # CSS Syntax: "fill:" has no value, which no property accepts: the declaration is
    # invalid and dropped (the declarations after it still apply)
    d = doc('<style>rect { stroke: blue } #r { stroke: /* none */ ; }</style>'
            '<rect id="r" fill="green" style="fill: ; opacity: 0.5"/>')
    r = d.ids["r"]
    assert r.specified["fill"] == "green" and r.specified["opacity"] == "0.5"
    assert r.specified["stroke"] == "blue"


def test_geometry_in_css_is_an_svg_2_property():
    """SVG 2 makes height a property (its attribute the presentation attribute): the rule
    sets it; in a document that says it is SVG 1.1 it is an attribute only, and the rule
    names no property (the resvg suite's non-presentational-attribute). Neither leaves it
    among the specified properties."""
    body = '<style>#r { height: 160px }</style><rect id="r" width="10"/>'
    d = doc(body, 'width="100" height="100" version="1.1"')
    assert "height" not in d.ids["r"].specified and "height" not in d.ids["r"].attrs
    d = doc(body)
    assert "height" not in d.ids["r"].specified and d.ids["r"].attrs["height"] == "160px"


def test_css_only_properties_are_not_attributes():
    d = doc('<rect id="r" mix-blend-mode="multiply" style="isolation: isolate"/>')
    assert "mix-blend-mode" not in d.ids["r"].specified
    assert d.ids["r"].specified["isolation"] == "isolate"


def test_inheritance_and_inherit_keyword():
    d = doc('<g id="g" fill="green" opacity="0.5"><rect id="r" stroke="inherit"/>'
            '<circle id="c" opacity="inherit"/></g>')
    g_style = d.document_style(d.ids["g"])
    r_style = d.document_style(d.ids["r"])
    assert r_style.get("fill") == "green"          # inherited property
    assert r_style.get("opacity") == "1"           # not inherited: initial value
    assert d.document_style(d.ids["c"]).get("opacity") == "0.5"
    assert r_style.get("stroke") == g_style.get("stroke") == "none"


def test_font_size_em_and_percent():
    d = doc('<g id="g" font-size="20"><text id="t" font-size="1.5em"/>'
            '<text id="u" font-size="50%"/></g>')
    assert d.document_style(d.ids["t"]).font_size() == 30
    assert d.document_style(d.ids["u"]).font_size() == 10


def test_font_size_initial_and_named_sizes_follow_resvg():
    # resvg: initial 12 px; a named size is the parent's times 1.2 per step from medium.
    d = doc('<text id="root"/><text id="em" font-size="3em"/><text id="ex" font-size="5ex"/>'
            '<g font-size="20"><text id="m" font-size="medium"/><text id="l" font-size="large"/>'
            '<text id="xxs" font-size="xx-small"/><text id="s" font-size="smaller"/></g>'
            '<text id="xxl" font-size="xx-large"/>')
    size = lambda i: d.document_style(d.ids[i]).font_size()  # noqa: E731
    assert size("root") == 12
    assert size("em") == 36 and size("ex") == 30
    assert size("m") == 20
    assert size("l") == pytest.approx(24)
    assert size("xxs") == pytest.approx(20 / 1.728)
    assert size("s") == pytest.approx(20 / 1.2)
    assert size("xxl") == pytest.approx(12 * 1.728)


def test_invalid_fill_colour_falls_back_to_black():
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg {SVG} width="10" height="10"><rect width="10" height="10" '
                           'fill="rgba(0, 127, 0, 50%)"/></svg>')
    assert img[5, 5].tolist() == [0, 0, 0, 255]


def test_css_import_is_not_followed():
    # resvg ignores @import; the rules around it still apply
    fetched = []
    d = load_document(f'<svg {SVG}><style>@import "green.css"; #r {{ stroke: blue }}</style>'
                      '<rect id="r" fill="red"/></svg>'.encode(),
                      load_text=lambda url: fetched.append(url) or "#r { fill: green }")
    style = d.document_style(d.ids["r"])
    assert style.get("fill") == "red" and style.get("stroke") == "blue" and not fetched


def test_font_kerning_is_css_only():
    d = doc('<text id="a" font-kerning="none"/><text id="b" style="font-kerning: none"/>')
    assert d.document_style(d.ids["a"]).get("font-kerning") in (None, "auto")
    assert d.document_style(d.ids["b"]).get("font-kerning") == "none"


def test_foreign_elements_are_skipped():
    d = doc('<foo xmlns="http://example.org/x"><rect id="hidden"/></foo><rect id="r"/>')
    assert "r" in d.ids and "hidden" not in d.ids


def test_svg_namespace_elements_in_a_document_without_a_namespace():
    # a root without xmlns is read as SVG (as resvg 0.45.1+ reads it), and then an element
    # that is in the SVG namespace by a prefix is an SVG element too (XML Namespaces: its
    # name is (SVG namespace, rect)); one in another namespace is still foreign
    d = load_document(b'<svg xmlns:s="http://www.w3.org/2000/svg" xmlns:f="urn:f">'
                      b'<s:rect id="a"/><rect id="b"/><f:rect id="c"/>'
                      b'<s:style>#a { fill: green }</s:style></svg>')
    assert "a" in d.ids and "b" in d.ids and "c" not in d.ids
    assert d.ids["a"].tag == "rect" and d.ids["a"].specified.get("fill") == "green"


def test_use_instantiates_an_svg_element_inside_a_foreign_one():
    # the rect inside <f:foo> is an SVG element of the document, not rendered where it stands
    # (its foreign parent is not), but a <use> instantiates any element (SVG 2 §5.6; resvg
    # 0.8+ and browsers draw it); paint servers are looked up among rendered content only
    # (resvg and browsers do not find a gradient there), so the gradient paints nothing
    from vecmsaa.api import render_svg_array
    from vecmsaa.diagnostics import RenderWarning
    with pytest.warns(RenderWarning, match="unresolved"):
        img = render_svg_array(
            f'<svg {SVG} width="100" height="100"><f:foo xmlns:f="urn:f">'
            '<rect id="r" width="20" height="20" fill="#00ff00"/><linearGradient id="g">'
            '<stop stop-color="red"/></linearGradient></f:foo>'
            '<use href="#r" x="50" y="30"/><rect x="0" y="70" width="100" height="30" '
            'fill="url(#g)"/></svg>'.encode())
    assert (img[30:50, 50:70] == (0, 255, 0, 255)).all()
    assert img[:, :, 3].sum() == 255 * 400      # nothing else: not the rect itself, no red
    d = load_document(f'<svg {SVG}><f:foo xmlns:f="urn:f"><rect id="r"/></f:foo></svg>'.encode())
    assert "r" not in d.ids and d.lookup("#r") is None
    assert d.lookup("#r", detached=True).tag == "rect"


def test_an_unknown_element_is_treated_as_a_foreign_one():
    # <random> is no SVG element: nothing in it is drawn, a <use> still instantiates an
    # element inside it, but a paint server there is not found (resvg keeps no unknown
    # element in its tree; browsers lay out nothing under one), so the fallback colour paints
    from vecmsaa.api import render_svg_array
    img = render_svg_array(
        f'<svg {SVG} width="100" height="100"><random><rect id="r" width="20" height="20" '
        'fill="#0000ff"/><linearGradient id="g"><stop stop-color="red"/></linearGradient>'
        '</random><use href="#r" x="50" y="30"/><rect x="0" y="70" width="100" height="30" '
        'fill="url(#g) #00ff00"/></svg>'.encode())
    assert (img[30:50, 50:70] == (0, 0, 255, 255)).all()
    assert (img[70:100] == (0, 255, 0, 255)).all()
    assert img[:, :, 3].sum() == 255 * (400 + 3000)
    d = load_document(f'<svg {SVG}><random><g id="g"/></random><animate id="a"/></svg>'.encode())
    assert "g" not in d.ids and d.lookup("#g", detached=True).tag == "g" and "a" in d.ids


def test_xlink_href_and_href():
    d = load_document(f'<svg {SVG} xmlns:xlink="http://www.w3.org/1999/xlink">'
                      '<use id="u" xlink:href="#a"/><use id="v" href="#b"/></svg>'.encode())
    assert d.ids["u"].href() == "a" and d.ids["v"].href() == "b"


def test_the_tree_is_elementtrees_less_foreign_elements():
    # Elements come straight from expat's events; the truth here is the standard library's
    # ElementTree with the rules applied by hand: foreign subtrees dropped with their tails,
    # comments and processing instructions invisible, xlink:href as href, xml:* kept.
    import xml.etree.ElementTree as ET
    xlink = "http://www.w3.org/1999/xlink"
    data = (f'<svg {SVG} xmlns:xlink="{xlink}" xmlns:f="urn:f"><text id="t" xml:space="preserve">'
            'a<!-- c -->b<?pi x?>c<tspan>d</tspan> e <![CDATA[<&>]]><f:x>in<tspan/></f:x>gone'
            '<tspan id="s"/>f</text><f:y/><use xlink:href="#t" href="#s" fill=" red "/>'
            '<g><rect/><f:z/><rect/></g></svg>').encode()

    def expected(node, index):
        ns, _, tag = node.tag[1:].partition("}")
        attrs = {}
        for k, v in node.attrib.items():
            if k == f"{{{xlink}}}href":
                attrs.setdefault("href", v)
            elif k.startswith("{http://www.w3.org/XML/1998/namespace}"):
                attrs["xml:" + k.partition("}")[2]] = v
            else:
                attrs[k] = v
        kids = [c for c in node if c.tag.startswith("{http://www.w3.org/2000/svg}")]
        return (tag, index, attrs, node.text or "", [expected(c, i) for i, c in enumerate(kids)])

    def got(el):
        return (el.tag, el.index, el.attrs, el.text, [got(c) for c in el.children])

    d = load_document(data)
    assert got(d.root) == expected(ET.fromstring(data), 0)
    text = d.ids["t"]
    # the text after the foreign element is still the <text>'s (XML character data of the
    # parent): it joins the tail of the SVG element before it
    assert [c.tail for c in text.children] == [" e <&>gone", "f"]
    assert d.root.children[1].specified == {"fill": "red"}
    # the <tspan/> inside <f:x> is made too, detached (a <use> may reference it): 9 elements
    assert d.paths == [] and d.size == 9 and d.has_use
    assert [e.tag for e in d.detached] == ["tspan"] and d.detached[0].parent is text


# -- XML safety ---------------------------------------------------------------------------------
def test_malformed_xml():
    with pytest.raises(SvgError) as err:
        load_document(b"<svg xmlns='http://www.w3.org/2000/svg'><rect></svg>")
    assert "\n" not in str(err.value)


def test_root_must_be_svg():
    with pytest.raises(SvgError):
        load_document(b"<html/>")


def test_billion_laughs_is_rejected():
    # ten levels of ten: 10**10 "lol"s, past the expansion cap long before any is made
    decls = '<!ENTITY l0 "lol">' + "".join(
        f'<!ENTITY l{i} "{("&l%d;" % (i - 1)) * 10}">' for i in range(1, 11))
    bomb = (f'<?xml version="1.0"?><!DOCTYPE svg [{decls}]>'
            f'<svg xmlns="http://www.w3.org/2000/svg"><text>&l10;</text></svg>').encode()
    with pytest.raises(SvgError, match="too large"):
        load_document(bomb)


def test_external_entities_are_never_read(tmp_path):
    # XML 1.0 §4.4.3: a non-validating processor need not include an external parsed entity;
    # vecmsaa leaves it out (as Chromium does) and reads nothing from outside
    secret = tmp_path / "secret.txt"
    secret.write_text("secret")
    xxe = (f'<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x SYSTEM "file://{secret}">]>'
           f'<svg xmlns="http://www.w3.org/2000/svg"><text id="t">a&x;b</text></svg>').encode()
    assert load_document(xxe).ids["t"].text == "ab"


def test_entity_declarations_reaching_the_parser_are_forbidden():
    # the entity pass before parsing takes simple ones out; the parser itself refuses any
    from vecmsaa.svg.document import Document, _TreeReader
    for decl in ('<!ENTITY a "b">', '<!ENTITY a SYSTEM "file:///etc/passwd">',
                 '<!ENTITY a SYSTEM "x" NDATA n>'):
        with pytest.raises(SvgError, match="forbidden XML construct: EntitiesForbidden"):
            _TreeReader(Document(None, {}), mirror=False).read(
                f'<!DOCTYPE svg [{decl}]><svg {SVG}/>'.encode())


def test_simple_internal_entities_are_expanded_once():
    d = load_document(b'<!DOCTYPE svg [<!ENTITY c "green">]>'
                      b'<svg xmlns="http://www.w3.org/2000/svg"><rect id="r" fill="&c;"/></svg>')
    assert d.ids["r"].specified["fill"] == "green"


def test_non_utf8_encoding():
    data = ('<?xml version="1.0" encoding="windows-1251"?>'
            f'<svg {SVG}><text id="t">Привет</text></svg>').encode("windows-1251")
    assert load_document(data).ids["t"].text == "Привет"


def test_hsl_rounding_is_consistent():
    r, g, b, a = parse_color("hsl(0, 100%, 50%)")
    assert (r, g, b, a) == (1, 0, 0, 1)
    assert math.isclose(parse_color("hsl(360, 100%, 50%)")[0], 1)


def test_quadratic_entity_blowup_is_rejected():
    big = b"x" * 100_000
    data = (b'<!DOCTYPE svg [<!ENTITY a "' + big + b'">]><svg xmlns="http://www.w3.org/2000/svg">'
            + b"<text>" + b"&a;" * 200 + b"</text></svg>")
    with pytest.raises(SvgError, match="too large"):
        load_document(data)


def test_properties_parsed_but_not_applied_warn_once_unless_initial():
    import warnings

    from vecmsaa.diagnostics import RenderWarning, as_python_warnings

    with pytest.warns(RenderWarning) as caught, as_python_warnings():      # once per render
        doc('<text style="inline-size: 50px">a b</text><text style="inline-size: 50px">c</text>'
            '<text style="text-overflow: ellipsis">1</text>')
    messages = sorted(str(w.message) for w in caught)
    assert messages == ["inline-size: 50px is not supported: ignored",
                        "text-overflow: ellipsis is not supported: ignored"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")           # initial values draw what they ask for
        doc('<text style="inline-size: auto; white-space: normal; text-overflow: inherit">a'
            '</text>')


def test_pattern_cycles_are_broken_where_usvg_breaks_them():
    # usvg (svgtree fix_recursive_patterns): for pattern P in document order and a paint
    # url(#Q) inside it, the first element inside Q painting url(#P) loses that paint; a paint
    # of P inside P goes. resvg 0.44 draws the suite's recursive-on-child test so.
    doc = load_document(b"""<svg xmlns="http://www.w3.org/2000/svg">
      <pattern id="a" width="4" height="4"><rect id="ra" width="4" height="4" fill="url(#b)"
        stroke="url(#a)"/></pattern>
      <pattern id="b" width="4" height="4"><rect id="rb" width="4" height="4" fill="url(#a)"
        stroke="green"/></pattern>
      <rect width="8" height="8" fill="url(#a)"/></svg>""")
    ra, rb = doc.ids["ra"].specified, doc.ids["rb"].specified
    assert ra["fill"] == "url(#b)" and ra["stroke"] == "none"
    assert rb["fill"] == "none" and rb["stroke"] == "green"


def test_overflowing_colour_channels_clamp_instead_of_raising():
    # 1e999 reads as infinity; CSS Color 4 clamps out-of-range channels (the fuzzer found
    # an OverflowError here)
    assert parse_svg_color("rgb(1e999, 0, -1e999)") == (1.0, 0.0, 0.0, 1.0)
    assert parse_svg_color("rgb(0%, 1e999%, 0%)") == (0.0, 1.0, 0.0, 1.0)
    assert parse_svg_color("hsla(0, 0%, 0%, -1e999)")[3] == 0.0


def test_the_id_map_holds_the_first_element_in_document_order_with_each_id():
    # made from the tree when first asked for; an element of another namespace is skipped
    # with its subtree, so an id inside it names nothing
    d = load_document(b'<svg xmlns="http://www.w3.org/2000/svg" xmlns:x="urn:x">'
                      b'<g id="a"><rect id="b" width="1"/><x:y id="c"><rect id="d"/></x:y>'
                      b'</g><circle id="b"/><rect id="c" height="2"/><path id="a"/></svg>')
    assert d.ids["a"].tag == "g"
    assert d.ids["b"].tag == "rect" and d.ids["b"].get("width") == "1"
    assert d.ids["c"].tag == "rect" and d.ids["c"].get("height") == "2"
    assert "d" not in d.ids
    assert d.lookup("url(#b)") is d.ids["b"] and d.lookup("#zz") is None


def test_svg_colour_answers_kept_by_text_stay_right():
    # parse_svg_color keeps its answers by text (at most 4096): every answer after the store
    # fills and is cleared is still the colour its own text says
    from vecmsaa.svg.color import parse_svg_color
    for round_ in range(2):
        for i in range(5000):
            r, g, b = i % 256, (i // 256) % 256, (7 * i) % 256
            text = f"#{r:02x}{g:02x}{b:02x}" if i % 2 else f"rgb({r}, {g}, {b})"
            assert parse_svg_color(text) == (r / 255, g / 255, b / 255, 1.0)
    assert parse_svg_color(" currentColor ") == "currentColor"
    assert parse_svg_color("#12345") is None and parse_svg_color("#12345") is None


#: shapes under groups that specify only compositing or placement (Style.child shares their
#: styles past those groups), with what could tell the difference: inherited values from above
#: the groups, em lengths, currentColor, markers, CSS, <use>, and the inherit keyword (which
#: must read the group itself)
_SHARED_STYLE_DOCS = [
    '<g fill="#0a0" stroke="#00c" stroke-width="3" font-size="8" color="#c0c">'
    '<g clip-path="url(#a)"><rect x="2" y="2" width="30" height="20" stroke-width="0.5em"/>'
    '<path d="M2 2L40 30" stroke="currentColor"/></g>'
    '<g clip-path="url(#b)" opacity="0.7"><rect x="22" y="12" width="30" height="20"/>'
    '<circle cx="30" cy="30" r="9" stroke-dasharray="2 1"/></g>'
    '<g transform="translate(5 3)"><g><path d="M10 40L50 44" marker-mid="url(#m)" '
    'marker-end="url(#m)" fill="none"/></g></g></g>'
    '<defs><clipPath id="a"><circle cx="20" cy="15" r="14"/></clipPath>'
    '<clipPath id="b"><rect x="20" y="10" width="25" height="30"/></clipPath>'
    '<marker id="m" markerWidth="4" markerHeight="4" refX="2" refY="2">'
    '<circle cx="2" cy="2" r="2" fill="context-stroke"/></marker></defs>',
    # the inherit keyword on a shape reads the group it is in: opacity, clip and mask twice
    '<g opacity="0.5"><rect width="30" height="30" fill="#f00" opacity="inherit"/></g>'
    '<g clip-path="url(#c)"><rect x="20" y="20" width="30" height="30" '
    'clip-path="inherit"/></g>'
    '<g mask="url(#k)"><circle cx="15" cy="45" r="12" mask="inherit"/></g>'
    '<g fill="#00f"><g opacity="0.6"><rect x="30" width="20" height="20" fill="inherit"/>'
    '</g></g>'
    '<defs><clipPath id="c"><circle cx="35" cy="35" r="15"/></clipPath>'
    '<mask id="k"><rect width="60" height="60" fill="#888"/></mask></defs>',
    # CSS rules and <use> of shapes under groups with their own filter or transform
    '<style>.s { stroke: #a50; stroke-width: 4 } g.o { opacity: 0.5 }</style>'
    '<g class="o"><path class="s" d="M5 5L55 20"/><use href="#u" x="5"/></g>'
    '<g style="transform: translate(3px, 30px)"><use href="#u"/></g>'
    '<defs><polygon id="u" points="5 30 30 50 50 35" fill="#08f" stroke="#000"/></defs>',
]


@pytest.mark.parametrize("body", _SHARED_STYLE_DOCS)
def test_shapes_share_styles_past_layer_only_groups_without_changing_a_pixel(body, monkeypatch):
    # brute force: the same bytes with the sharing (Style.child) and without it
    from vecmsaa.api import render_svg_array
    from vecmsaa.svg import document
    source = f'<svg {SVG} width="60" height="60">{body}</svg>'.encode()
    shared = render_svg_array(source, width=120)
    monkeypatch.setattr(document, "LAYER_PROPERTIES", frozenset())
    assert np.array_equal(render_svg_array(source, width=120), shared)


def test_a_shape_saying_inherit_reads_its_own_group():
    # SVG / CSS: opacity="inherit" takes the parent's 0.5 (the group's opacity then applies
    # on top: 0.25 in all); fill="inherit" through a group with only opacity takes the fill
    # of the group above it
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg {SVG} width="10" height="10"><g fill="#00f"><g opacity="0.5">'
                           '<rect width="10" height="10" opacity="inherit" fill="inherit"/>'
                           '</g></g></svg>'.encode(), width=10)
    assert tuple(int(v) for v in img[5, 5]) == pytest.approx((0, 0, 255, 64), abs=1)


@pytest.mark.parametrize("attrs", ['stroke="none" fill="#00f" opacity="INHERIT"',
                                   'fill="#00f" style="stroke: none; opacity: Inherit"',
                                   'fill="#00f" stroke="none" opacity="inherit"'])
def test_a_shape_saying_inherit_in_any_value_and_case_reads_its_own_group(attrs):
    # opacity inherit (CSS-wide keywords are ASCII case-insensitive) after other values: the
    # group's 0.5 twice, 0.25 in all
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg {SVG} width="10" height="10"><g opacity="0.5">'
                           f'<rect width="10" height="10" {attrs}/></g></svg>'.encode(),
                           width=10)
    assert tuple(int(v) for v in img[5, 5]) == pytest.approx((0, 0, 255, 64), abs=1)


def test_shapes_under_groups_differing_only_by_clip_share_one_style():
    d = doc('<g id="a" clip-path="url(#x)"><path id="p" stroke="#000"/></g>'
            '<g id="b" clip-path="url(#y)"><path id="q" stroke="#000"/></g>'
            '<g id="c" fill="red"><path id="r" stroke="#000"/></g>')
    from vecmsaa.svg.document import Style
    root = Style(d.root.specified)
    style = root.child(d.ids["a"]).child(d.ids["p"])
    assert root.child(d.ids["b"]).child(d.ids["q"]) is style
    assert root.child(d.ids["c"]).child(d.ids["r"]) is not style     # fill is inherited
    assert style.get("stroke") == "#000" and style.get("fill") == "black"


def _cycles_broken_one_hit_a_walk(doc):
    """The reference: the rule as written before session 20, walking Q again from its start for
    each element that loses its reference (quadratic in Q's size)."""
    from vecmsaa.svg.document import _LINKS, _URL_ID, _descendants

    def link(el, name):
        value = el.specified.get(name) if el.specified else None
        m = _URL_ID.match(value) if value else None
        return m.group(1) if m else None

    for tag, name in _LINKS:
        for container in doc.link_containers:
            if container.tag != tag:
                continue
            cid = container.attrs.get("id")
            if cid is None or doc.ids.get(cid) is not container:
                continue
            for node in _descendants(container):
                while (target := link(node, name)) is not None:
                    if target == cid:
                        node.specified[name] = "none"
                        continue
                    linked = doc.ids.get(target)
                    hit = None if linked is None else next(
                        (n for n in _descendants(linked) if link(n, name) == cid), None)
                    if hit is None:
                        break
                    hit.specified[name] = "none"


def test_reference_cycles_are_broken_as_one_hit_a_walk_breaks_them():
    # random documents of patterns, clip paths and masks nested in and referencing each other
    # (several back-references in one container, a container inside another, an element both
    # in P and in Q): one walk over Q breaks exactly what walking Q again for each hit broke
    import random
    from vecmsaa.svg import document
    rng = random.Random(20)
    kinds = [("pattern", "fill"), ("pattern", "stroke"), ("clipPath", "clip-path"),
             ("mask", "mask")]

    def element(depth, ids):
        tag, prop = rng.choice(kinds) if depth < 2 and rng.random() < 0.4 else ("rect", None)
        attrs = [f'{p}="url(#{rng.choice(ids)})"' for _, p in kinds if rng.random() < 0.35]
        if tag == "rect":
            return f'<rect width="4" height="4" {" ".join(attrs)}/>'
        inner = "".join(element(depth + 1, ids) for _ in range(rng.randrange(1, 4)))
        return f'<{tag} id="{rng.choice(ids)}" {" ".join(attrs)}>{inner}</{tag}>'

    for _ in range(300):
        ids = [f"i{k}" for k in range(rng.randrange(1, 5))]
        body = "".join(element(0, ids) for _ in range(rng.randrange(2, 6)))
        src = f'<svg xmlns="http://www.w3.org/2000/svg">{body}</svg>'.encode()
        original = document._break_reference_cycles
        try:
            document._break_reference_cycles = _cycles_broken_one_hit_a_walk
            want = load_document(src)
        finally:
            document._break_reference_cycles = original
        got = load_document(src)
        w = [dict(e.specified or {}) for e in document._descendants(want.root)]
        g = [dict(e.specified or {}) for e in document._descendants(got.root)]
        assert g == w, src


def _nested_texts(rng, depth):
    """Groups nested ``depth`` deep, each declaring (or not) font-weight, font-variant and a
    longhand, font-family, text-transform, dominant-baseline, font-feature-settings,
    xml:space, text-decoration and kerning, valid, invalid or CSS-wide, a text at each level."""
    values = {
        "font-weight": ["bold", "bolder", "lighter", "650", "1500", "inherit", "initial", "x"],
        "font-variant": ["small-caps", "normal", "none", "inherit", "bogus"],
        "font-variant-numeric": ["oldstyle-nums", "normal", "initial", "lining-nums x"],
        "font-family": ["Noto Serif", "'Noto Sans', serif", "Mplus 1p", "inherit", "unset"],
        "text-transform": ["uppercase", "none", "capitalize", "inherit", "bogus"],
        "dominant-baseline": ["middle", "hanging", "no-change", "inherit", "x"],
        "font-feature-settings": ["'smcp'", "normal", "initial", "'liga' off", "bad"],
        "xml:space": ["preserve", "default", "bogus"],
        "text-decoration": ["underline", "overline line-through", "none"],
        "kerning": ["0", "auto", "1"]}
    parts = ['<svg xmlns="http://www.w3.org/2000/svg">']
    for level in range(depth):
        attrs = " ".join(f'{name}="{rng.choice(options)}"' for name, options in values.items()
                         if rng.random() < 0.3)
        parts.append(f'<g {attrs}><text x="1" y="{level}">t{level}</text>')
    parts.append("</g>" * depth + "</svg>")
    return "".join(parts).encode()


def _text_values(doc, el, only=None):
    """The inherited values a text needs (``only``: the one of that index alone)."""
    from vecmsaa.svg.text import content, draw, font_match, layout
    style = doc.document_style(el)
    values = (lambda: font_match._weight(style), lambda: font_match.variant_features(style),
              lambda: font_match._family_list(style),
              lambda: font_match._settings(style, "font-feature-settings"),
              lambda: content.text_transform(style), lambda: layout._dominant_baseline(style),
              lambda: el.computed("xml:space", content._space_preserved, False),
              lambda: el.computed("decorations", draw._declared_decorations, ()),
              lambda: font_match.kerning_attribute(el))
    return tuple(v() for v in values) if only is None else values[only]()


def _texts(doc):
    out, todo = [], [doc.root]
    while todo:
        el = todo.pop()
        todo.extend(el.children)
        if el.tag == "text":
            out.append(el)
    return out


@pytest.mark.filterwarnings("ignore")
def test_values_computed_down_the_tree_are_those_computed_afresh():
    """Inherited values cached on the styles and elements passed (Style.get_valid,
    Style.computed, Element.computed), asked for texts in a random order, equal each value
    asked alone for one text of a fresh document, whose caches are empty (the walk to the
    root, each time)."""
    import random
    rng = random.Random(21)
    for _ in range(8):
        data = _nested_texts(rng, rng.randrange(1, 25))
        doc = load_document(data)
        texts = _texts(doc)
        order = list(range(len(texts)))
        rng.shuffle(order)
        cached = {i: _text_values(doc, texts[i]) for i in order}
        for i in range(len(texts)):
            for k in range(len(cached[i])):
                fresh = load_document(data)
                assert _text_values(fresh, _texts(fresh)[i], k) == cached[i][k], (data, i, k)


@pytest.mark.filterwarnings("ignore")
def test_texts_nested_deep_compute_each_ancestor_once(monkeypatch):
    """600 texts at depths 1 to 600 compute each inherited value once an element (Style.computed,
    Style.get_valid, Element.computed cache what they pass): the walk to the root for every
    text was 180,000 steps, and a fuzzed document of 198,000 texts 300 deep took 54 s to
    reach the text limit."""
    import random
    from vecmsaa.svg.text import content, font_match
    doc = load_document(_nested_texts(random.Random(5), 600))
    calls = []

    def counted(fn):
        def wrapper(*args):
            calls.append(fn.__name__)
            return fn(*args)
        return wrapper
    monkeypatch.setattr(font_match, "_own_weight", counted(font_match._own_weight))
    monkeypatch.setattr(font_match, "_valid_family_names",
                        counted(font_match._valid_family_names))
    monkeypatch.setattr(content, "_space_preserved", counted(content._space_preserved))
    for el in _texts(doc):
        style = doc.document_style(el)
        font_match._weight(style)
        font_match._family_list(style)
        el.computed("xml:space", content._space_preserved, False)
    elements = 2 * 600 + 1
    for name in ("_own_weight", "_valid_family_names", "_space_preserved"):
        assert 0 < calls.count(name) <= elements, (name, calls.count(name))


def test_nested_patterns_are_looked_through_once_for_reference_cycles(monkeypatch):
    """_break_reference_cycles reads each element's references a bounded number of times
    however deep patterns nest (a fuzzed document of 255,000 patterns nested 300 deep walked
    every pattern's content again for each pattern around it: 110 s); a reference cycle at the
    bottom is still broken."""
    from vecmsaa.svg import document
    depth = 400
    pattern = ('<pattern id="p{k}" width="20" height="20"><rect width="10" height="10"/>'
               '<rect x="10" width="10" height="10" fill="green"/>')
    data = ('<svg xmlns="http://www.w3.org/2000/svg">'
            + "".join(pattern.format(k=k) for k in range(depth))
            + '<rect id="r" width="5" height="5" fill="url(#p399)"/>'
            + "</pattern>" * depth + "</svg>").encode()

    class Counting:
        calls = 0

        def match(self, value):
            Counting.calls += 1
            return real.match(value)
    real = document._URL_ID
    monkeypatch.setattr(document, "_URL_ID", Counting())
    doc = load_document(data)
    elements = 3 * depth + 2
    assert Counting.calls <= 8 * elements, Counting.calls
    # the rect in p399 (and in every pattern around it) filled with p399 itself: the fill goes
    assert doc.lookup("#r").specified["fill"] == "none"


@pytest.mark.parametrize("text, matrix", [
    ("rotate(90)", (0, 1, -1, 0, 0, 0)), ("rotate(180)", (-1, 0, 0, -1, 0, 0)),
    ("rotate(-90)", (0, -1, 1, 0, 0, 0)), ("rotate(270)", (0, -1, 1, 0, 0, 0)),
    ("rotate(450)", (0, 1, -1, 0, 0, 0)), ("rotate(180 100 100)", (-1, 0, 0, -1, 200, 200)),
    ("rotate(0.5turn)", (-1, 0, 0, -1, 0, 0)),
])
def test_quarter_turns_are_exact(text, matrix):
    # the rotation matrix [cos a, sin a, -sin a, cos a] at whole quarter turns holds 0 and +-1
    # exactly (not sin(radians(180)) = 1.2e-16), so a turned point on the grid stays on it
    assert parse_transform(text) == matrix


@pytest.mark.parametrize("rotate, matrix", [
    ("90deg", (0, 1, -1, 0, 0, 0)), ("0.5turn", (-1, 0, 0, -1, 0, 0)),
    ("z 180deg", (-1, 0, 0, -1, 0, 0)), ("-100grad", (0, -1, 1, 0, 0, 0)),
])
def test_the_rotate_property_s_quarter_turns_are_exact(rotate, matrix):
    from vecmsaa.svg.units import individual_transform
    assert individual_transform(None, rotate, None, (10, 10)) == matrix


@pytest.mark.parametrize("degrees, matrix", [
    (90, (0, 1, -1, 0, 10, -10)), (180, (-1, 0, 0, -1, 20, 0)), (-90, (0, -1, 1, 0, 10, 10)),
    (450, (0, 1, -1, 0, 10, -10)),
])
def test_rotate_at_is_exact_at_quarter_turns(degrees, matrix):
    # the rotation a glyph's rotate list, a textPath glyph and a marker's angle are turned by
    # (scene.transform.rotate_at), about (10, 0): exact, as the transform attribute's
    from vecmsaa.scene.transform import rotate_at
    assert rotate_at(degrees, 10, 0) == matrix


def test_a_rect_turned_half_a_turn_covers_whole_pixels():
    # edges on pixel boundaries cover each pixel wholly or not at all (exact geometry): the
    # 16-sample pattern has samples on the boundary (offset -8/16), which the float noise of
    # a turn computed in radians put inside the rect, one row and column of 1/16 beyond it
    from vecmsaa.api import render_svg_array
    a = render_svg_array(b'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">'
                         b'<g transform="rotate(180 100 100)"><rect x="20" y="20" width="160"'
                         b' height="150" transform="rotate(90 100 100) rotate(-90 100 100)"/>'
                         b'</g></svg>', width=200, height=200, samples=16)[..., 3]
    expected = np.zeros((200, 200), np.uint8)
    expected[30:180, 20:180] = 255
    assert np.array_equal(a, expected)
