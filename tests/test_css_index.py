"""The cascade's index of simple selectors (a class, id, type or ``*`` alone, looked up per
element instead of matched by cssselect2) against the cascade done the plain way: every
selector of every rule tested with cssselect2 on every element, the matches sorted by
specificity then source order (Selectors 4 §17, CSS Cascade 4 §6.4), normal declarations
before ``!important`` ones, the ``style`` attribute after the rules in each, presentation
attributes under all (SVG 2 §6.6)."""
import random
import xml.etree.ElementTree as ET

import cssselect2
import pytest
import tinycss2

from vecmsaa.svg.document import load_document

SVG = "http://www.w3.org/2000/svg"
PROPS = ("fill", "stroke", "opacity", "stroke-width")
TAGS = ("rect", "circle", "g", "path")
CLASSES = ("a", "b", "c", "A", "st1")
IDS = ("x", "y", "z", " x")
SIMPLE = (".a", ".b", ".c", ".A", ".st1", "#x", "#y", "#z", "rect", "circle", "g", "path",
          "RECT", "*", ".zz", "#none")
COMPOUND = ("rect.a", ".a.b", "g > .a", "g .b", ":first-child", "rect:nth-child(2n)",
            "[fill]", ".a + rect", "circle ~ .c", "*:not(.a)", "#x.a", "g rect", "path:last-child",
            "circle:first-of-type", "svg|rect", "*|*", ".b::before", "[class~=st1]")
#: compound selectors of a type or ``*``, ids and classes (indexed too: each part tested)
INDEXED_COMPOUND = ("rect.a", ".a.b", "#x.a", "circle.b.c", ".A.a", "*.a", "g#x", "#y.b.c",
                    "rect#x.st1", ".a.a", "*#z", "path.st1.a", "RECT.a", ".b.a.c", "g.a.b",
                    "circle#y", "#x#x")


def brute_force(svg_text):
    """{document order: {property: value}}: each element's specified values, by the plain
    cascade described above (cssselect2 tests each selector on its own)."""
    root = ET.fromstring(svg_text)
    rules = []      # (selector test, specificity, source order, declarations)
    order = 0
    for node in root.iter("{%s}style" % SVG):
        sheet = tinycss2.parse_stylesheet(node.text or "", skip_whitespace=True,
                                          skip_comments=True)
        namespaces = {}
        for rule in sheet:
            if rule.type == "at-rule" and rule.lower_at_keyword == "namespace":
                *prefix, url = [t for t in rule.prelude if t.type != "whitespace"]
                namespaces[prefix[0].value if prefix else None] = url.value
                continue
            try:
                selectors = cssselect2.compile_selector_list(rule.prelude, namespaces)
            except cssselect2.SelectorError:
                continue
            decls = [(d.lower_name, tinycss2.serialize(d.value).strip(), d.important)
                     for d in tinycss2.parse_declaration_list(rule.content, True, True)
                     if d.type == "declaration"]
            for sel in selectors:
                if sel.pseudo_element is None and not sel.never_matches:
                    rules.append((sel.test, sel.specificity, order, decls))
                order += 1
    out = {}
    wrapper = cssselect2.ElementWrapper.from_xml_root(root)
    for n, w in enumerate(wrapper.iter_subtree()):
        matched = sorted((r for r in rules if r[0](w)), key=lambda r: (r[1], r[2]))
        el = w.etree_element
        declared = [d for r in matched for d in r[3]]
        if el.get("style"):
            declared += [(d.lower_name, tinycss2.serialize(d.value).strip(), d.important)
                         for d in tinycss2.parse_declaration_list(el.get("style"), True, True)
                         if d.type == "declaration"]
        spec = {p: el.get(p).strip() for p in PROPS if el.get(p) is not None}
        for important in (False, True):
            for name, value, imp in declared:
                if imp == important and name in PROPS and value:
                    spec[name] = value
        out[n] = spec
    return out


def random_document(rng, selectors, elements):
    rules = []
    for _ in range(rng.randint(1, 12)):
        sels = ", ".join(rng.choice(selectors) for _ in range(rng.choice((1, 1, 1, 2, 3))))
        decls = "; ".join(f"{p}: {rng.choice(('#%06x' % rng.getrandbits(24), '2', '.5'))}"
                          + (" !important" if rng.random() < 0.15 else "")
                          for p in rng.sample(PROPS, rng.randint(1, 3)))
        rules.append(f"{sels} {{{decls}}}")
    cut = rng.randint(0, len(rules))
    body = []
    depth = 0
    for _ in range(elements):
        tag = rng.choice(TAGS)
        attrs = []
        if rng.random() < 0.7:
            names = rng.choices(CLASSES, k=rng.choice((1, 1, 2, 3)))
            attrs.append('class="%s"' % rng.choice((" ", "&#9;", "&#10; ")).join(names))
        if rng.random() < 0.3:
            attrs.append(f'id="{rng.choice(IDS)}"')
        if rng.random() < 0.3:
            attrs.append(f'{rng.choice(PROPS)}="{rng.choice(("#123", " 3 ", ".25"))}"')
        if rng.random() < 0.2:
            attrs.append(f'style="{rng.choice(PROPS)}: #abc'
                         f'{rng.choice(("", " !important"))}"')
        if tag == "g" and depth < 4 and rng.random() < 0.6:
            body.append(f"<g {' '.join(attrs)}>")
            depth += 1
            continue
        body.append(f"<{tag} {' '.join(attrs)}/>")
        if depth and rng.random() < 0.3:
            body.append("</g>")
            depth -= 1
    body.append("</g>" * depth)
    first = "".join(rules[:cut])
    last = "".join(rules[cut:])
    namespace = rng.choice((f"@namespace svg url({SVG});", "", f"@namespace url({SVG});",
                            '@namespace "other";'))
    return (f'<svg xmlns="{SVG}"><style>{namespace} {first}</style>'
            f'{"".join(body)}<style>{last}</style></svg>')


def specified_by_load(svg_text):
    doc = load_document(svg_text.encode())
    stack, out = [doc.root], {}
    while stack:
        el = stack.pop()
        out[len(out)] = {p: el.specified[p] for p in PROPS if p in el.specified}
        stack.extend(reversed(el.children))
    return out


@pytest.mark.parametrize("seed", range(60))
@pytest.mark.parametrize("kinds", ["simple", "mixed", "compound"])
def test_indexed_selectors_cascade_as_cssselect2_matched_one_by_one(seed, kinds):
    rng = random.Random(seed * 2 + (kinds == "mixed") + 1000 * (kinds == "compound"))
    selectors = {"simple": SIMPLE, "mixed": SIMPLE + COMPOUND + INDEXED_COMPOUND,
                 "compound": SIMPLE + INDEXED_COMPOUND}[kinds]
    text = random_document(rng, selectors, rng.randint(1, 60))
    assert specified_by_load(text) == brute_force(text)


def test_compound_selectors_need_no_cssselect2_matching(monkeypatch):
    """A sheet of compound selectors of types, ids and classes (``rect.a``, ``.a.b``,
    ``#x.a``) is looked up per element as the simple ones are: the document is read once,
    without ElementTree's tree, and cssselect2 matches nothing."""
    from vecmsaa.svg import document
    reads = []
    real = document._TreeReader.read
    monkeypatch.setattr(document._TreeReader, "read",
                        lambda self, data: reads.append(self._mirror) or real(self, data))
    matched = []
    monkeypatch.setattr(cssselect2.Matcher, "match",
                        lambda self, el: matched.append(1) or [])
    rng = random.Random(17)
    for _ in range(20):
        text = random_document(rng, SIMPLE + INDEXED_COMPOUND[:-1], 200)
        if "@namespace url" in text or '@namespace "' in text:
            # a default namespace: the types (and the implied universal) test it too
            continue
        reads.clear()
        assert specified_by_load(text) == brute_force(text)
        assert reads == [False]
    assert matched == []


def test_simple_selectors_need_no_cssselect2_matching(monkeypatch):
    """A sheet of single class, id, type and universal selectors is looked up per element:
    cssselect2 matches nothing, the elements alike in tag, id and class share one lookup."""
    from vecmsaa.svg import document
    calls = {"match": 0, "lookups": 0}
    real = document.Stylesheets.simple_matches

    def count_lookups(self, tag, attrs, charge):
        before = len(self._simple)
        got = real(self, tag, attrs, charge)
        calls["lookups"] += len(self._simple) - before
        return got
    monkeypatch.setattr(document.Stylesheets, "simple_matches", count_lookups)
    monkeypatch.setattr(cssselect2.Matcher, "match",
                        lambda self, el: calls.__setitem__("match", calls["match"] + 1) or [])
    rng = random.Random(7)
    text = random_document(rng, SIMPLE, 300)
    assert specified_by_load(text) == brute_force(text)
    assert calls["match"] == 0
    # one lookup per distinct (tag if a rule names it, id if one does, class attribute)
    root = ET.fromstring(text)
    keys = {(el.tag.split("}")[1], el.get("id"), el.get("class")) for el in root.iter()}
    assert 0 < calls["lookups"] <= len(keys)


def test_many_elements_alike_read_their_rules_once(monkeypatch):
    """8,000 paths over 40 class rules (an Illustrator export): the declarations of each
    class are cascaded once, each path gets its own copy of the values."""
    from vecmsaa.svg import document
    made = []
    real = document._specified
    monkeypatch.setattr(document, "_specified", lambda *a, **k: made.append(1) or real(*a, **k))
    css = "".join(f".st{i}{{fill:#{i:06x};stroke:#000;stroke-miterlimit:10;}}" for i in range(40))
    paths = "".join(f'<path class="st{i % 40}" d="M0 0h{i}"/>' for i in range(8000))
    doc = load_document(f'<svg xmlns="{SVG}"><style>{css}</style>{paths}</svg>'.encode())
    assert len(made) <= 40 + 2          # the 40 classes, the svg and style elements
    els = doc.root.children[1:]
    assert [el.specified for el in els[:40]] == [
        {"fill": f"#{i:06x}", "stroke": "#000", "stroke-miterlimit": "10"} for i in range(40)]
    assert len({id(el.specified) for el in els}) == len(els)


def test_elements_alike_in_their_attributes_are_specified_once(monkeypatch):
    """20,000 circles of a chart, presentation attributes and style attributes repeating:
    each pair of (presentation attributes, style attribute) is cascaded once, and each circle
    has its own dict of the values SVG 2 §6.6 gives (the style attribute over the attributes,
    values without their surrounding white space)."""
    from vecmsaa.svg import document
    made = []
    real = document._specified
    monkeypatch.setattr(document, "_specified", lambda *a, **k: made.append(1) or real(*a, **k))
    kinds = [('fill="steelblue" stroke=" #333" stroke-width="0.5"',
              {"fill": "steelblue", "stroke": "#333", "stroke-width": "0.5"}),
             ('fill="red" style="fill: blue; opacity: .5"', {"fill": "blue", "opacity": ".5"}),
             ('style="stroke: lime"', {"stroke": "lime"}),
             ('fill="steelblue" stroke="#333"', {"fill": "steelblue", "stroke": "#333"})]
    circles = "".join(f'<circle cx="{i}" cy="{i % 7}" r="2" {kinds[i % 4][0]}/>'
                      for i in range(20000))
    doc = load_document(f'<svg xmlns="{SVG}">{circles}</svg>'.encode())
    assert len(made) == 4
    els = doc.root.children
    assert [el.specified for el in els] == [kinds[i % 4][1] for i in range(20000)]
    assert len({id(el.specified) for el in els}) == len(els)


@pytest.mark.parametrize("alike, refused", [(True, False), (False, True)])
def test_simple_selectors_count_their_work_against_the_limit(monkeypatch, alike, refused):
    """100 universal rules over 200 rects: rects alike read the rules once; rects each with a
    style of their own read them once each, 20,000 steps, past a limit of 10,000."""
    from vecmsaa.svg import SvgError, document
    monkeypatch.setattr(document, "MAX_SELECTOR_STEPS", 10_000)
    rects = "".join('<rect width="1" height="1" style="opacity: %s"/>' % (1 if alike else i)
                    for i in range(200))
    text = f'<svg xmlns="{SVG}"><style>{"* {fill: red} " * 100}</style>{rects}</svg>'
    if refused:
        with pytest.raises(SvgError, match="CSS selectors take more than 10000 steps"):
            load_document(text.encode())
    else:
        assert specified_by_load(text) == brute_force(text)


@pytest.mark.parametrize("root_ns, body, sheets", [
    # a <style> element's sheet is its child text content (HTML's and CSSOM's): the text of
    # elements in it is not CSS, comments and CDATA sections are no boundary
    (SVG, '<style>a{}<x:y xmlns:x="u">zz</x:y>b{}</style>', ["a{}b{}"]),
    (SVG, '<style>a<rect/>b<circle>no</circle>c</style>', ["abc"]),
    (SVG, "<style><![CDATA[.a{fill:red}]]></style>", [".a{fill:red}"]),
    (SVG, "<style>a<!-- c -->b</style>", ["ab"]),
    (SVG, "<style>outer<style>inner</style>tail</style>", ["outertail", "inner"]),
    # only CSS: type text/css, or none, or empty
    (SVG, '<style type="text/foo">x</style><style type=" text/css ">y</style>'
          '<style type="">z</style>', ["y", "z"]),
    # a media type's type and subtype are case-insensitive (RFC 2045 5.1; HTML's style
    # element: an ASCII case-insensitive match for text/css); a parameter is no match
    (SVG, '<style type="TEXT/CSS">a</style><style type="Text/Css">b</style>'
          '<style type="text/css; charset=utf-8">c</style><style type="TEXT/FOO">d</style>',
     ["a", "b"]),
    # a media attribute of other media types alone matches no screen (SVG 2 6.3, Media
    # Queries 4 2.3); all, screen, an empty list and queries with features apply
    (SVG, '<style media="print">a</style><style media="only print, speech">b</style>'
          '<style media="print, screen">c</style><style media="ALL">d</style>'
          '<style media="">e</style><style media="(min-width: 1px)">f</style>', ["c", "d", "e", "f"]),
    # a style element anywhere in the document, inside unknown and foreign elements too;
    # of SVG's namespace (or none, under a root of none), not of another
    (SVG, '<x:y xmlns:x="u"><style>s1</style></x:y><unknown><style>s2</style></unknown>'
          '<style xmlns="u">no</style>', ["s1", "s2"]),
    ("", '<style>s1</style><s:style xmlns:s="http://www.w3.org/2000/svg">s2</s:style>',
     ["s1", "s2"]),
])
def test_style_sheets_are_the_style_elements_child_text(monkeypatch, root_ns, body, sheets):
    from vecmsaa.svg import document
    added = []
    real = document.Stylesheets.add
    monkeypatch.setattr(document.Stylesheets, "add",
                        lambda self, text: added.append(text) or real(self, text))
    xmlns = f' xmlns="{root_ns}"' if root_ns else ""
    load_document(f"<svg{xmlns}>{body}</svg>".encode())
    assert added == sheets


@pytest.mark.parametrize("attrs, green", [
    ('type="TEXT/CSS"', True), ('type="Text/Css"', True), ('media="print"', False),
    ('media="only print, speech"', False), ('media="print, screen"', True), ('media="all"', True),
    ('type="text/css; charset=utf-8"', False)])
def test_style_element_type_and_media_when_drawn(attrs, green):
    """A <style> whose type is text/css in any case applies (media types are case-insensitive,
    RFC 2045 5.1); one whose media list names only other media types (print) does not (SVG 2
    6.3, Media Queries 4): the sheet's green over the attribute's red, or the red."""
    from vecmsaa import render_svg_array
    svg = (f'<svg xmlns="{SVG}" width="10" height="10"><style {attrs}>rect {{fill: #00ff00}}'
           '</style><rect width="10" height="10" fill="#ff0000"/></svg>')
    px = render_svg_array(svg.encode(), width=10, height=10)[5, 5]
    assert tuple(px) == ((0, 255, 0, 255) if green else (255, 0, 0, 255))


@pytest.mark.parametrize("css, reads", [(".a {fill: red} rect, #b {stroke: blue}", 1),
                                        (".a {fill: red} g > rect {stroke: blue}", 2)])
def test_the_elementtree_mirror_is_built_for_cssselect2_only(monkeypatch, css, reads):
    """A document whose selectors are all indexed ones is read once, without ElementTree's
    tree; one with another selector is read again with it, for cssselect2."""
    from vecmsaa.svg import document
    calls = []
    real = document._TreeReader.read
    monkeypatch.setattr(document._TreeReader, "read",
                        lambda self, data: calls.append(self._mirror) or real(self, data))
    text = (f'<svg xmlns="{SVG}"><style>{css}</style><g><rect class="a" width="1"/>'
            f'<circle id="b" r="1"/></g></svg>')
    assert specified_by_load(text) == brute_force(text)
    assert calls == [False, True][:reads]


def test_the_tree_read_before_the_mirror_goes_without_the_collector():
    """A document read again for cssselect2: its first tree (a clip path in it, which the
    document lists) is freed by reference counting, as the collector is paused while a
    document renders: the collector finds none of its elements."""
    import gc

    from vecmsaa.svg.document import Element
    text = (f'<svg xmlns="{SVG}"><style>g > rect {{fill: red}}</style><clipPath id="c">'
            f'<rect width="1"/></clipPath><g><rect width="1"/></g></svg>')
    gc.collect()
    gc.disable()
    gc.set_debug(gc.DEBUG_SAVEALL)
    try:
        doc = load_document(text.encode())
        gc.collect()
        left = [o for o in gc.garbage if isinstance(o, Element)]
    finally:
        gc.set_debug(0)
        gc.garbage.clear()
        gc.enable()
    assert left == []
    assert doc.root.children[2].children[0].specified == {"fill": "red"}
