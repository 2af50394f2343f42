"""CSS custom properties and var() (CSS Custom Properties for Cascading Variables Module
Level 1): the specification's examples and rules, checked on the rendered colours of plain
20 x 20 squares. Each expected colour follows from the specification's text (section cited);
Chromium 150 draws the same (docs/svg.md, session 25, custom properties)."""
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.svg import SvgError
from vecmsaa.svg.document import load_document
from vecmsaa.svg.variables import (MAX_VAR_EXPANSION, MAX_VAR_LENGTH, Budget, custom_values,
                                   substitute)

SVG = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'
RED, LIME, BLUE = "#ff0000", "#00ff00", "#0000ff"


def cells(body, n, root=""):
    """The colours (#rrggbb, or None where nothing is drawn) at the centres of ``n`` cells
    20 px wide."""
    svg = f'<svg {SVG} width="{20 * n}" height="20" {root}>{body}</svg>'
    a = render_svg_array(svg.encode())
    out = []
    for i in range(n):
        r, g, b, alpha = (int(v) for v in a[10, 20 * i + 10])
        out.append(None if alpha == 0 else "#%02x%02x%02x" % (r, g, b))
    return out


def squares(*styles, attrs=None):
    """One square per style attribute value, each at its own x."""
    return "".join(f'<rect x="{20 * i}" width="20" height="20" style="{s}" '
                   f'{(attrs or {}).get(i, "")}/>' for i, s in enumerate(styles))


# -- declaring and using -------------------------------------------------------------------
def test_root_palette_and_style_sheet():
    # §1 example 1: the values declared once on the root, used by rules below
    body = ('<style>svg { --main-color: #0000ff; --accent-color: #00ff00 }'
            '.a { fill: var(--main-color) } .b { fill: var(--accent-color) }</style>'
            '<rect class="a" width="20" height="20"/>'
            '<rect class="b" x="20" width="20" height="20"/>')
    assert cells(body, 2) == [BLUE, LIME]


def test_names_are_case_sensitive():
    # §2: custom property names are case-sensitive (--foo and --FOO are two properties)
    assert cells(squares("--foo: #0000ff; --FOO: #ff0000; fill: var(--foo)",
                         "--foo: #0000ff; --FOO: #ff0000; fill: var(--FOO)",
                         "--foo: #0000ff; fill: var(--Foo, #00ff00)"), 3) == [BLUE, RED, LIME]


def test_cascade_specificity_importance_and_order():
    # §2: custom properties are ordinary properties in the cascade
    body = ('<style>#i { --c: #0000ff } .c { --c: #ff0000 } rect { fill: var(--c) }'
            '.imp { --c: #00ff00 !important }</style>'
            '<rect id="i" class="c" width="20" height="20"/>'
            '<rect class="c" x="20" width="20" height="20" style="--c: #0000ff"/>'
            '<rect class="c imp" x="40" width="20" height="20" style="--c: #0000ff"/>'
            '<rect x="60" width="20" height="20" style="--c: #ff0000; --c: #00ff00"/>')
    assert cells(body, 4) == [BLUE, BLUE, LIME, LIME]


def test_always_inherited():
    # §2: custom properties are inherited, whatever property uses them
    body = ('<g style="--c: #0000ff"><g><rect width="20" height="20" style="fill: var(--c)"/>'
            '</g></g><g style="--o: 0"><rect x="20" width="20" height="20" '
            'style="opacity: var(--o)"/></g>')
    assert cells(body, 2) == [BLUE, None]


def test_value_is_trimmed_and_may_be_empty():
    # §2: the value is the declaration's tokens, leading and trailing white space removed;
    # an empty value is valid, and substitutes nothing
    assert cells(squares("--c:    #0000ff   ; fill: var(--c)",
                         "--e:; fill: var(--e) #0000ff",
                         "--e: ; fill: var(--e)"), 3, root='fill="#00ff00"') \
        == [BLUE, BLUE, LIME]


def test_fallback():
    # §3: the fallback is used when the property has no value; it may hold commas and var()
    assert cells(squares("fill: var(--none, #0000ff)",
                         "fill: var(--none, rgb(0, 255, 0))",
                         "--b: #0000ff; fill: var(--none, var(--b))",
                         "--a: #ff0000; fill: var(--a, #0000ff)",
                         "fill: var(--none,)"), 5, root='fill="#00ff00"') \
        == [BLUE, LIME, BLUE, RED, LIME]


def test_substitution_inside_functions_and_lists():
    assert cells(squares("--r: 255; fill: rgb(var(--r), 0, 0)",
                         "--p: 0, 255; fill: rgb(var(--p), 0)",
                         "--col: 0 0 255; fill: rgb(var(--col))",
                         "--b: 255; fill: rgb(0 0 VAR( --b ))"), 4) == [RED, LIME, BLUE, BLUE]


def test_substituted_tokens_do_not_join():
    # §3: var() is replaced by tokens: `var(--n)0%` is the number 5 then the percentage
    # 0%, not 50% (an invalid fill-opacity, so the inherited 1); written 50% it is 0.5
    body = squares("--n: 5; fill-opacity: var(--n)0%", "--n: 50%; fill-opacity: var(--n)")
    svg = f'<svg {SVG} width="40" height="20">{body}</svg>'
    a = render_svg_array(svg.encode())
    assert int(a[10, 10, 3]) == 255 and abs(int(a[10, 30, 3]) - 128) <= 1


# -- invalid at computed-value time ---------------------------------------------------------
def test_invalid_at_computed_value_time_inherited_property():
    # §3.1 example: a var() giving an invalid value does not fall back to the cascade's
    # earlier declaration (the red): the property is unset, and fill inherits the lime
    body = ('<style>.p { fill: #ff0000 } .p { fill: var(--not-a-color) }</style>'
            '<g fill="#00ff00"><rect class="p" width="20" height="20" style="--not-a-color: 20px"/>'
            '<rect class="p" x="20" width="20" height="20"/>'
            '<rect x="40" width="20" height="20" fill="#ff0000" style="fill: var(--missing)"/>'
            '</g>')
    assert cells(body, 3) == [LIME, LIME, LIME]
    # the same for a stroke width: the group's 20 covers the square's centre, where the
    # initial 1 would leave it empty
    body = ('<g stroke-width="20" stroke="#0000ff" fill="none">'
            + squares("--w: red; stroke-width: var(--w)", "--w: 10 px; stroke-width: var(--w)",
                      "stroke-width: var(--w)0px", "--w: 1; stroke-width: var(--w)") + '</g>')
    assert cells(body, 4) == [BLUE, BLUE, BLUE, None]


def test_invalid_at_computed_value_time_other_property():
    # §3.1: a property that is not inherited takes its initial value (opacity 1), not the
    # presentation attribute it overrode
    assert cells(squares("fill: #0000ff; opacity: var(--bad)",
                         "fill: #0000ff; --bad: 20px; opacity: var(--bad)",
                         "fill: #0000ff; --z: 0; opacity: var(--z)"),
                 3, root="") == [BLUE, BLUE, None] and \
        cells('<rect width="20" height="20" fill="#0000ff" opacity="0" '
              'style="opacity: var(--bad)"/>', 1) == [BLUE]


def test_malformed_var_is_invalid_when_parsed():
    # §3: a var() whose first argument is no custom property name makes the declaration
    # invalid at parse time: it is dropped, and what it would override applies
    body = squares("fill: var(red)", "fill: var(--a red)", "fill: var()",
                   attrs={i: 'fill="#0000ff"' for i in range(3)})
    assert cells(body, 3) == [BLUE, BLUE, BLUE]


def test_initial_and_css_wide_keywords():
    # §2.2: initial is the guaranteed-invalid value; inherit and unset take the parent's
    body = ('<g style="--a: #ff0000">'
            + squares("--a: initial; fill: var(--a, #0000ff)",
                      "--a: inherit; fill: var(--a, #0000ff)",
                      "--a: unset; fill: var(--a, #0000ff)",
                      "--a: var(--missing); fill: var(--a, #00ff00)") + '</g>')
    assert cells(body, 4) == [BLUE, RED, RED, LIME]


def test_cycles_make_every_property_on_them_invalid():
    # §2.3 example: --one and --two depend on each other: both are invalid; a property
    # not on the cycle that uses one takes its fallback
    assert cells(squares("--one: var(--two); --two: var(--one); fill: var(--one, #0000ff)",
                         "--one: var(--two, #ff0000); --two: var(--one); "
                         "fill: var(--two, #0000ff)",
                         "--a: var(--a); fill: var(--a, #00ff00)",
                         "--a: var(--b); --b: var(--c); --c: #0000ff; fill: var(--a)"),
                 4) == [BLUE, BLUE, LIME, BLUE]


def test_fallback_not_taken_makes_no_cycle():
    # a fallback is substituted only when needed (as Chromium 150 does): --a takes --x,
    # and its fallback's reference to --b is never followed, so --b is --a's value too
    assert cells(squares("--a: var(--x, var(--b)); --b: var(--a); --x: #0000ff; "
                         "fill: var(--b, #ff0000)"), 1) == [BLUE]


def test_current_color_resolves_where_used():
    # a substituted currentColor is the using element's color
    body = ('<g style="color: #ff0000; --k: currentColor">'
            '<rect width="20" height="20" style="color: #0000ff; fill: var(--k)"/></g>')
    assert cells(body, 1) == [BLUE]


# -- where it applies --------------------------------------------------------------------------
def test_presentation_attributes():
    # SVG 2 parses a presentation attribute as a CSS value of its property (Chromium 150
    # substitutes var() there); a style sheet still overrides it
    body = ('<style>.s { fill: #00ff00 }</style>'
            '<rect width="20" height="20" fill="var(--c)"/>'
            '<rect class="s" x="20" width="20" height="20" fill="var(--c)"/>'
            '<rect x="40" width="20" height="20" fill="var(red)"/>')
    assert cells(body, 3, root='style="--c: #0000ff"') == [BLUE, LIME, "#000000"]


def test_shorthands():
    # §3: a shorthand holding var() is substituted, then expanded; a later longhand wins
    body = ('<defs><marker id="m" markerWidth="20" markerHeight="20" refX="10" refY="10" '
            'markerUnits="userSpaceOnUse"><rect width="20" height="20" fill="#0000ff"/>'
            '</marker></defs>'
            '<path d="M10 10h0.01" style="--m: url(#m); marker: var(--m)"/>'
            '<path d="M30 10h0.01" style="--m: url(#m); marker: var(--m); marker-start: none;'
            ' marker-end: none"/>'
            '<path d="M50 10h0.01" style="marker: var(--missing)"/>')
    assert cells(body, 3) == [BLUE, None, None]
    d = load_document(f'<svg {SVG}><text style="--f: bold 20px serif; font: var(--f); '
                      f'font-style: italic"/><text style="font: var(--f)"/></svg>'.encode())
    first, second = d.root.children
    assert first.specified["font-size"] == "20px" and first.specified["font-weight"] == "bold"
    assert first.specified["font-style"] == "italic"
    # no --f: every longhand unset, which for these inherited properties is inherit
    assert all(second.specified.get(n, "inherit") == "inherit"
               for n in ("font-size", "font-weight", "font-style", "font-family"))


def test_use_instances_inherit_from_the_use():
    # content instantiated by <use> inherits from the <use> (SVG 2 §5.6.3), custom
    # properties too; each instance its own
    body = ('<defs><symbol id="s" viewBox="0 0 20 20"><rect width="20" height="20" '
            'style="fill: var(--c, #000000)"/></symbol>'
            '<g id="g" style="--d: var(--c)"><rect width="20" height="20" '
            'fill="var(--d)"/></g></defs>'
            '<use xlink:href="#s" width="20" height="20" style="--c: #0000ff"/>'
            '<use xlink:href="#s" x="20" width="20" height="20" style="--c: #00ff00"/>'
            '<use xlink:href="#g" x="40" style="--c: #ff0000"/>'
            '<use xlink:href="#s" x="60" width="20" height="20"/>')
    assert cells(body, 4) == [BLUE, LIME, RED, "#000000"]


def test_paint_servers_inherit_where_defined():
    # a gradient's stops and a pattern's content inherit from their own ancestors, not
    # from the element they paint (as every inherited property)
    body = ('<defs><linearGradient id="lg" style="--s: #0000ff"><stop stop-color="var(--s)"/>'
            '</linearGradient><pattern id="p" width="20" height="20" '
            'patternUnits="userSpaceOnUse" style="--p: #00ff00"><rect width="20" height="20" '
            'fill="var(--p)"/></pattern></defs>'
            '<rect width="20" height="20" fill="url(#lg)" style="--s: #ff0000"/>'
            '<rect x="20" width="20" height="20" fill="url(#p)" style="--p: #ff0000"/>'
            '<rect x="40" width="20" height="20" style="--u: url(#lg); fill: var(--u)"/>')
    assert cells(body, 3) == [BLUE, LIME, BLUE]


def test_document_without_var_is_unchanged():
    # declaring custom properties without using them changes nothing, and a document
    # without var() is read by the same code as before (its specified values plain)
    d = load_document(f'<svg {SVG} style="--c: red"><rect style="--x: 1; fill: blue"/>'
                      f'</svg>'.encode())
    assert d.root.specified == {} and d.root.children[0].specified == {"fill": "blue"}
    assert d.var_raw == {}


# -- limits ----------------------------------------------------------------------------------
def chain(n, first="0"):
    return "; ".join([f"--v0: {first}"] + [f"--v{i}: var(--v{i - 1}) var(--v{i - 1})"
                                            for i in range(1, n + 1)])


def test_doubling_chain_is_capped():
    # the "billion laughs" of variables: --v40 would be 2^40 tokens; each value over
    # MAX_VAR_LENGTH is invalid (the fallback applies), the work stays small
    assert cells(squares(chain(40) + "; fill: var(--v40, #0000ff)"), 1) == [BLUE]
    customs = custom_values(dict(x.split(": ") for x in chain(25).split("; ")),
                            lambda name: None, Budget())
    valid = [i for i in range(26) if customs[f"--v{i}"] is not None]
    # --v{i} has 2^(i+1) - 1 characters
    assert valid == [i for i in range(26) if 2 ** (i + 1) - 1 <= MAX_VAR_LENGTH]


def test_total_substitution_is_bounded():
    # a capped value used by many elements: refused past MAX_VAR_EXPANSION characters
    # (each declaration its own: equal ones are substituted once)
    n = MAX_VAR_EXPANSION // MAX_VAR_LENGTH + 2
    uses = "".join(f'<rect style="fill: var(--v20, #{i:06x})"/>' for i in range(n))
    with pytest.raises(SvgError, match="MAX_VAR_EXPANSION"):
        load_document(f'<svg {SVG} style="{chain(20)}">{uses}</svg>'.encode())


def test_long_chains_need_no_recursion():
    # ten thousand custom properties each naming the next, on one element
    n = 10_000
    own = {f"--v{i}": f"var(--v{i + 1})" for i in range(n)}
    own[f"--v{n}"] = "#0000ff"
    assert custom_values(own, lambda name: None, Budget())["--v0"] == "#0000ff"
    own[f"--v{n}"] = "var(--v0)"        # now one cycle through all of them
    assert set(custom_values(own, lambda name: None, Budget()).values()) == {None}


def test_substitute():
    values = {"--a": "1px", "--b": "", "--n": "5"}
    budget = Budget()
    assert substitute("var(--a) var(--a)", values.get, budget) == "1px 1px"
    assert substitute("calc(var(--a) + var(--b)2px)", values.get, budget) == "calc(1px + 2px)"
    assert substitute("var(--n)px", values.get, budget) == "5 px"
    assert substitute("var(--none)", values.get, budget) is None
    assert substitute("var(--none, var(--none2, a, b))", values.get, budget) == "a, b"


def test_use_instances_substitute_their_own_layer_properties():
    # clip-path, mask, filter, transform and opacity of instantiated content take the
    # <use>'s custom properties too (each cell's centre: clipped, masked away, flooded red,
    # moved onto the centre, transparent; the last <use> sets nothing: no clip)
    body = ('<defs><clipPath id="c"><rect width="5" height="20"/></clipPath>'
            '<mask id="m"><rect width="5" height="20" fill="white"/></mask>'
            '<filter id="f"><feFlood flood-color="#ff0000"/></filter>'
            '<g id="g1"><rect width="20" height="20" fill="#0000ff" clip-path="var(--c)"/></g>'
            '<g id="g2"><rect width="20" height="20" fill="#0000ff" style="mask: var(--m)"/></g>'
            '<g id="g3"><rect width="20" height="20" fill="#0000ff" style="filter: var(--f)"/></g>'
            '<g id="g4"><rect width="10" height="20" fill="#0000ff" style="transform: var(--t)"/>'
            '</g><g id="g5"><rect width="20" height="20" fill="#0000ff" style="opacity: var(--o)"/>'
            '</g></defs>'
            '<use xlink:href="#g1" style="--c: url(#c)"/>'
            '<use xlink:href="#g2" x="20" style="--m: url(#m)"/>'
            '<use xlink:href="#g3" x="40" style="--f: url(#f)"/>'
            '<use xlink:href="#g4" x="60" style="--t: translateX(10px)"/>'
            '<use xlink:href="#g5" x="80" style="--o: 0"/>'
            '<use xlink:href="#g1" x="100"/>')
    assert cells(body, 6) == [None, None, RED, BLUE, None, BLUE]


def test_equal_declarations_under_other_values():
    # elements repeating one rule's declarations are substituted once per set of inherited
    # values they use: each still gets its own ancestors' values
    body = ('<style>.k { fill: var(--c) } .d { --d: var(--c); fill: var(--d) }</style>'
            '<g style="--c: #0000ff"><rect class="k" width="20" height="20"/>'
            '<rect class="d" x="20" width="20" height="20"/></g>'
            '<g style="--c: #00ff00"><rect class="k" x="40" width="20" height="20"/>'
            '<rect class="d" x="60" width="20" height="20"/>'
            '<rect class="k" x="80" width="20" height="20" style="--c: #ff0000"/></g>'
            '<g style="--c: #0000ff; --x: 1"><rect class="k" x="100" width="20" height="20"/>'
            '<rect class="k" x="120" width="20" height="20" fill-opacity="0"/></g>')
    assert cells(body, 7) == [BLUE, BLUE, LIME, LIME, RED, BLUE, None]
