"""Document-level XML (XML 1.0, Namespaces in XML) and the root <svg>'s attributes, checked
against the specifications' rules (session 24's three-way round on documents)."""
import subprocess
import sys

import pytest

from vecmsaa.svg import SvgError
from vecmsaa.svg.document import load_document
from vecmsaa.svg.units import parse_aspect, viewbox_transform

SVG = 'xmlns="http://www.w3.org/2000/svg"'


def load(subset, body):
    return load_document(f'<!DOCTYPE svg [{subset}]><svg {SVG}>{body}</svg>'.encode())


def test_entities_referring_to_entities_are_expanded():
    # XML 1.0 §4.5: a general entity reference in an entity's literal is kept as written and
    # expanded where the entity is used, so "&a;een" with a = "gr" reads "green"
    d = load('<!ENTITY a "gr"> <!ENTITY b "&a;een">', '<rect id="r" fill="&b;"/>'
             '<text id="t">x &b; y</text>')
    assert d.ids["r"].get("fill") == "green"
    assert d.ids["t"].text == "x green y"


def test_entity_holding_markup_and_another_entity():
    # §4.4.2/§4.5: a replacement text that is markup is parsed as part of the document
    d = load('<!ENTITY w "70"> <!ENTITY shape \'<rect id="r" width="&w;" height="5"/>\'>',
             '<g id="g">&shape;</g>')
    assert [c.tag for c in d.ids["g"].children] == ["rect"]
    assert d.ids["r"].get("width") == "70"


def test_first_entity_declaration_binds():
    # §4.2: "If the same entity is declared more than once, the first declaration
    # encountered is binding"
    d = load('<!ENTITY c "green"> <!ENTITY c "red">', '<rect id="r" fill="&c;"/>')
    assert d.ids["r"].get("fill") == "green"


@pytest.mark.parametrize("subset", ['<!ENTITY a "&a;">', '<!ENTITY a "x&b;"> <!ENTITY b "&a;">'])
def test_recursive_entities_are_an_error(subset):
    # §4.1 WFC "No Recursion"
    with pytest.raises(SvgError, match="refers to itself"):
        load(subset, "<text>&a;</text>")


def test_parameter_entity_declarations_are_skipped():
    d = load('<!ENTITY % p "x"> <!ENTITY c "green">', '<rect id="r" fill="&c;"/>')
    assert d.ids["r"].get("fill") == "green"


def test_attribute_defaults_of_the_internal_subset_apply():
    # §5.1: a non-validating processor must "supply default attribute values" declared in
    # the internal subset; a specified attribute wins over its default (§3.3.2)
    d = load('<!ATTLIST rect fill CDATA "green"> <!ENTITY w "9">',
             '<rect id="a" width="&w;"/><rect id="b" fill="blue"/>')
    assert d.ids["a"].specified["fill"] == "green"
    assert d.ids["b"].specified["fill"] == "blue"


def test_preserve_aspect_ratio_with_trailing_garbage_is_ignored():
    # SVG 2 grammar `<align> [<meetOrSlice>]`: anything else makes the attribute invalid, so
    # its initial value, xMidYMid meet, applies. viewBox 100x100 into 200x120: scale
    # min(2, 1.2) = 1.2, centred horizontally by (200 - 120) / 2 = 40
    for bad in ("xMinYMax bogus", "xMinYMax meet slice", "xMaxYMin Slice"):
        assert parse_aspect(bad) == ("xMidYMid", False)
        m = viewbox_transform((0, 0, 100, 100), parse_aspect(bad), 200, 120)
        assert m == pytest.approx((1.2, 0, 0, 1.2, 40, 0))
    assert parse_aspect("xMinYMax slice") == ("xMinYMax", True)
    assert parse_aspect("none meet") == ("none", False)


def test_malformed_entities_fail_the_cli_in_one_line(tmp_path):
    bad = tmp_path / "bad.svg"
    bad.write_text(f'<!DOCTYPE svg [<!ENTITY a "&b;"> <!ENTITY b "&a;">]><svg {SVG}>&a;</svg>')
    run = subprocess.run([sys.executable, "-m", "vecmsaa.cli.main", "render", str(bad), "-o",
                          str(tmp_path / "out.png")], capture_output=True, text=True)
    assert run.returncode != 0
    assert run.stderr.strip().count("\n") == 0 and "refers to itself" in run.stderr
    assert not (tmp_path / "out.png").exists()


def test_character_references_in_entity_values_expand_at_declaration():
    # XML 1.0 Appendix D's example: the character references are expanded when the
    # declaration is read, the entity references when the entity is used
    d = load('<!ENTITY example "<text id=\'t\'>An ampersand (&#38;#38;) may be escaped '
             'numerically (&#38;#38;#38;) or with a general entity (&amp;amp;).</text>">',
             "&example;")
    assert d.ids["t"].text == ("An ampersand (&) may be escaped numerically (&#38;) or with "
                               "a general entity (&amp;).")


def test_no_entity_is_recognised_in_cdata_comments_or_pis():
    # §2.7: in a CDATA section "&" is a character; §2.5/§2.6 comments and PIs are no content
    d = load('<!ENTITY c "green">', '<text id="t"><![CDATA[&c;]]><!-- &c; -->&c;</text>')
    assert d.ids["t"].text == "&c;green"


def test_unbalanced_entity_markup_is_an_error():
    # §4.3.2 WFC: an element begun in an entity's replacement text ends there
    with pytest.raises(SvgError, match="entity o is not well-formed"):
        load('<!ENTITY o "<g fill=\'green\'>">', "&o;<rect/></g>")


def test_root_viewbox_of_zero_size_disables_rendering():
    # SVG 2 (viewBox): "A negative value for <width> or <height> is an error and invalidates
    # the viewBox attribute. A value of zero disables rendering of the element."
    from vecmsaa.api import render_svg_array

    def draw(viewbox):
        return render_svg_array(
            f'<svg width="40" height="40" viewBox="{viewbox}" {SVG} style="background-color:'
            f'blue"><rect x="10" y="10" width="20" height="20" fill="green"/></svg>'.encode())
    for zero in ("0 0 0 40", "0 0 40 0", "0,0,0,0"):
        img = draw(zero)
        assert img.shape[:2] == (40, 40) and not img[..., 3].any()
    img = draw("0 0 -40 40")          # invalid: as if there were none, user units are pixels
    assert tuple(img[20, 20]) == (0, 128, 0, 255) and tuple(img[5, 5]) == (0, 0, 255, 255)


def test_entity_nesting_is_bounded():
    # a chain of entities each naming the next: refused cleanly past MAX_ENTITY_DEPTH,
    # whatever the chain's length (no RecursionError), accepted within it
    from vecmsaa.svg.document import MAX_ENTITY_DEPTH

    def chain(n):
        return '<!ENTITY e0 "x">' + "".join(f'<!ENTITY e{i} "&e{i - 1};">' for i in range(1, n))
    assert load(chain(MAX_ENTITY_DEPTH), f'<text id="t">&e{MAX_ENTITY_DEPTH - 1};</text>'
                ).ids["t"].text == "x"
    for n in (MAX_ENTITY_DEPTH + 1, 5000):
        with pytest.raises(SvgError, match="nest deeper"):
            load(chain(n), f"<text>&e{n - 1};</text>")


def test_unterminated_sections_after_entities_fail_as_malformed_xml():
    # the substitution pass skips CDATA, comments and PIs; one left open ends it, and expat
    # reports the document (many openers: each is looked at once)
    for opener in ("<!--", "<![CDATA[", "<?"):
        with pytest.raises(SvgError, match="malformed XML"):
            load('<!ENTITY a "x">', "&a;" + opener * 10_000)


def test_an_entity_reference_cannot_stand_for_the_root_element():
    # XML 1.0 §2.1: document ::= prolog element Misc*; a reference is content, which only an
    # element holds (resvg and Chromium refuse the document)
    root = f'<svg {SVG}><rect/></svg>'
    with pytest.raises(SvgError):
        load_document(f"<!DOCTYPE svg [<!ENTITY doc '{root}'>]><!-- c -->&doc;".encode())
    assert load_document(f"<!DOCTYPE svg [<!ENTITY r '<rect/>'>]><!-- &r; --> <?p &r;?>"
                         f"<svg {SVG}>&r;</svg>".encode()).root.children[0].tag == "rect"


def test_entity_expansion_is_capped_over_all_levels_together():
    # every entity's expansion is kept for its next use, so the cap counts the bytes
    # substituted at every level together: a 2 KB chain of distinct entities, each a copy of
    # the one before an 8 MB value, would otherwise hold 8 MB once per level
    from vecmsaa.svg.document import MAX_ENTITY_EXPANSION
    half = MAX_ENTITY_EXPANSION // 2
    doubling = ['<!ENTITY a0 "' + "x" * 1024 + '">']
    level = 0
    while 1024 << level < half:
        level += 1
        doubling.append(f'<!ENTITY a{level} "&a{level - 1};&a{level - 1};">')
    copies = "".join(f'<!ENTITY b{i} "&{"a%d" % level if i == 0 else "b%d" % (i - 1)};">'
                     for i in range(20))
    with pytest.raises(SvgError, match="too large after entity expansion"):
        load("".join(doubling) + copies, "<desc>&b19;</desc>")
    # one value used many times within the cap is fine: 1000 uses of 1 KB
    d = load('<!ENTITY k "' + "y" * 1024 + '">', '<desc id="d">' + "&k;" * 1000 + "</desc>")
    assert d.ids["d"].text == "y" * 1024 * 1000
