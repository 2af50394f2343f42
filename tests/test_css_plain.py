"""Reading without tinycss2 what tinycss2 would write back as written (plain style sheets and
declaration lists: document._plain_sheet, _plain_declarations), against tinycss2's own
reading; and attributes read by what their list of names makes of an element
(_attribute_shape), against the attributes and specified values SVG 2 gives them."""
import random

import pytest
import tinycss2

from vecmsaa.svg import document
from vecmsaa.svg.document import load_document

SVG = "http://www.w3.org/2000/svg"

#: pieces of declaration lists: plain ones, and ones tinycss2 reads otherwise than as written
#: (escapes, exponents, a unit ``e``, comments, strings, functions, !important, CR and FF,
#: tokens that would run together, custom properties, non-ASCII)
NAMES = ("fill", "FILL", "stroke-width", "-x-y", "_a", "--v", "é", "a\\62", "1a", "")
WORDS = ("red", "Red", "#000", "#94118e", "#-a", "#-", "#1", "10", "1.5", ".5", "+.5", "-1",
         "1.", "10px", "10PX", "5%", "1e", "1E", "1e3", "1e-2", "1em", "1ex", "0e1px", "e",
         "-e", "-", "--x", "U+1F", "u+a", "url(x)", "f(1)", "'s'", '"s"', "\\61", "/**/",
         "/* c */", "!important", "! IMPORTANT", "é", "a-1", "1-2", "x--", "a_b")
SEPARATORS = (" ", "  ", ",", " , ", "\t", "\n", "\r\n", "\r", "\f", "")


def random_declarations(rng, words=WORDS, separators=SEPARATORS):
    parts = []
    for _ in range(rng.randint(0, 4)):
        value = rng.choice(words)
        for _ in range(rng.choice((0, 0, 1, 2))):
            value += rng.choice(separators) + rng.choice(words)
        colon = rng.choice((":", " : ", ":\n", ": ", ""))
        parts.append(rng.choice(SEPARATORS[:3]) + rng.choice(NAMES[:5] if rng.random() < 0.8
                                                             else NAMES) + colon + value)
    return rng.choice((";", "; ", ";;")).join(parts) + rng.choice(("", ";", " ; "))


def tinycss2_declarations(text):
    """(lower name, value as tinycss2 writes it, important) of each declaration with a value."""
    out = []
    for d in tinycss2.parse_declaration_list(text, skip_whitespace=True, skip_comments=True):
        if d.type == "declaration":
            value = tinycss2.serialize(d.value).strip()
            if value:
                out.append((d.lower_name, value, d.important))
    return out


def test_plain_declarations_are_what_tinycss2_reads():
    rng = random.Random(5)
    plain = 0
    for _ in range(4000):
        text = random_declarations(rng)
        got = document._plain_declarations(text)
        if got is None:
            continue
        plain += 1
        assert got == tinycss2_declarations(text), text
    assert plain > 800          # the plain reading is taken for a good part of them


@pytest.mark.parametrize("text, plain", [
    ("fill:#94118e;stroke:#000;stroke-miterlimit:10;", True),
    (" fill : red , blue 10px ;; opacity:", True),
    ("a:1e3", False), ("a:1e", False), ("a:b!important", False), ("--x:1", False),
    ("a: url(#x)", False), ("a:1-2", False), ("a:b/**/c", False), ("a:'s'", False),
    ("fill:red;;junk", False), ("fill\r\n:\fred", True)])
def test_plain_declarations_where_tinycss2_writes_the_text_back(text, plain):
    assert (document._plain_declarations(text) is not None) == plain
    assert document._declarations(text) == [
        (n, v.replace("/**/", " "), i) for n, v, i in tinycss2_declarations(text)]


SELECTORS = (".a", ".st0", "#x", "#-y", "rect", "RECT", "*", ".a.b", "rect.a", "g > .a",
             "#1x", ".1a", "a b", "[x]", ":first-child", "*|*", ". a", "# x", "svg|rect",
             "::before", "")


def random_sheet(rng):
    rules = []
    for _ in range(rng.randint(0, 6)):
        sels = rng.choice((",", ", ", " ,")).join(rng.choice(SELECTORS[:7] if rng.random() < 0.8
                                                             else SELECTORS)
                                                  for _ in range(rng.choice((1, 1, 2, 3))))
        block = random_declarations(rng, WORDS[:9], SEPARATORS[:6]) if rng.random() < 0.8 \
            else random_declarations(rng)
        rules.append(sels + rng.choice(("", " ", "\n")) + "{" + block + "}")
    head = rng.choice(("", "", "", "", "", "", "@charset 'x';", "/* c */", "<!--", "@import 'u';",
                       "@namespace url(%s);" % SVG))
    return head + rng.choice(("", " ", "\n")).join(rules) + rng.choice(("", " ", "}"))


def indexed(sheets):
    return (sheets.count, sheets.complex, sheets.matcher.order, sheets.by_class, sheets.by_id,
            sheets.by_tag, sheets.universal)


def test_plain_sheets_index_as_tinycss2_and_cssselect2_read_them(monkeypatch):
    """Stylesheets read a plain sheet without tinycss2 into the same index, in the same order,
    as tinycss2 and cssselect2 read it (the declarations are the same lists)."""
    rng = random.Random(11)
    texts = [random_sheet(rng) for _ in range(2000)]
    plain = sum(document._plain_sheet(t) is not None for t in texts)
    assert plain > 100
    fast = []
    for text in texts:
        sheets = document.Stylesheets()
        sheets.add(text)
        fast.append(indexed(sheets))
    monkeypatch.setattr(document, "_plain_sheet", lambda text: None)
    monkeypatch.setattr(document, "_plain_declarations", lambda text: None)
    for text, got in zip(texts, fast):
        sheets = document.Stylesheets()
        sheets.add(text)
        assert got == indexed(sheets), text


def test_a_plain_sheet_is_not_tokenized(monkeypatch):
    """An Illustrator sheet of 200 class rules and its 8,000 paths: tinycss2 reads nothing."""
    calls = []
    for name in ("parse_stylesheet", "parse_declaration_list", "parse_component_value_list"):
        real = getattr(tinycss2, name)
        monkeypatch.setattr(tinycss2, name,
                            lambda *a, _real=real, **k: calls.append(1) or _real(*a, **k))
    css = "".join(f".st{i}{{fill:#{i:06x};stroke:#000;stroke-miterlimit:10;}}" for i in range(200))
    paths = "".join(f'<path class="st{i % 200}" d="M0 0h{i}"/>' for i in range(8000))
    doc = load_document(f'<svg xmlns="{SVG}"><style>{css}</style>{paths}</svg>'.encode())
    assert calls == []
    assert doc.root.children[5].specified == {"fill": "#000004", "stroke": "#000",
                                              "stroke-miterlimit": "10"}


XLINK = "http://www.w3.org/1999/xlink"
#: (attribute as written, its name in Element.attrs or None (not kept), value)
ATTRS = (("cx", "cx"), ("fill", "fill"), ("stroke", "stroke"), ("style", "style"),
         ("href", "href"), ("xlink:href", "href"), ("xml:space", "xml:space"),
         ("o:fill", None), ("id", "id"), ("opacity", "opacity"), ("font", "font"))
VALUES = (" red", "#abc ", "1", "url(#a)", "fill: blue", "opacity: .5; stroke: lime")


def expected(written):
    """Element.attrs and the specified presentation values of an element with attributes
    ``written`` ((name as written, value)...), as SVG 2 gives them: xlink:href is href unless
    a plain href is there too, xml:* keep their prefix, other namespaces go; presentation
    attributes are specified stripped, under the style attribute's declarations."""
    attrs = {}
    for name, value in written:
        if name == "xlink:href":
            attrs.setdefault("href", value)
        elif name == "o:fill":
            continue
        else:
            attrs[name] = value
    spec = {k: v.strip() for k, v in attrs.items()
            if k in ("fill", "stroke", "opacity")}
    if "style" in attrs:
        for d in tinycss2.parse_declaration_list(attrs["style"], True, True):
            if d.type == "declaration" and d.lower_name in ("fill", "stroke", "opacity"):
                spec[d.lower_name] = tinycss2.serialize(d.value).strip()
    return attrs, spec


def test_attributes_read_by_their_list_of_names(monkeypatch):
    """Elements of random attribute lists (repeating, in several orders): the attributes and
    specified values SVG 2 gives them, each distinct list of names worked out once."""
    rng = random.Random(3)
    shapes = []
    real = document._attribute_shape
    monkeypatch.setattr(document, "_attribute_shape",
                        lambda names: shapes.append(names) or real(names))
    lists = [rng.sample(ATTRS, rng.randint(0, 5)) for _ in range(30)]
    elements = []
    for _ in range(600):
        names = rng.choice(lists)
        elements.append([(a, rng.choice(VALUES)) for a, _ in names])
    body = "".join("<circle %s/>" % " ".join(f'{n}="{v}"' for n, v in written)
                   for written in elements)
    doc = load_document(f'<svg xmlns="{SVG}" xmlns:xlink="{XLINK}" xmlns:o="u">{body}</svg>'
                        .encode())
    for el, written in zip(doc.root.children, elements):
        attrs, spec = expected(written)
        assert el.attrs == attrs and list(el.attrs) == list(attrs)
        assert {k: v for k, v in el.specified.items() if k in ("fill", "stroke", "opacity")} \
            == spec
    assert len(shapes) == len(set(shapes)) <= len(lists) + 1
