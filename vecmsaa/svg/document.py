"""Safe XML parsing, the CSS cascade and computed styles.

The XML is parsed by expat with defusedxml's guards: no entity declarations, no external
entities, no network. Documents that declare general entities in their DTD subset
(``<!ENTITY name "value">``, common in files exported by old editors) are accepted through one
bounded substitution pass before parsing: an entity's value may hold markup and other
entities, each expanded once (a cycle is an error), and the expansion is capped, so there is no
"billion laughs" amplification; external entities are never read (a reference to one is left
out, with a warning). The rest of the subset stays for expat, which applies its attribute
defaults (XML 1.0 §5.1).

expat's events become :class:`Element` objects carrying the *specified* style of each
element (presentation attributes < CSS rules by specificity and order < ``style=""`` <
``!important``). :class:`Style` resolves inheritance and ``inherit`` on top of that.
"""
from __future__ import annotations

import functools
import operator
import re

from ..diagnostics import warn
from . import SvgError
from .units import split_length, to_px

SVG_NS = "http://www.w3.org/2000/svg"
XLINK_NS = "http://www.w3.org/1999/xlink"
#: xlink:href as expat names it (namespace, "}", local name)
_XLINK_HREF = XLINK_NS + "}href"
XML_NS = "http://www.w3.org/XML/1998/namespace"
_XML_LANG = "{%s}lang" % XML_NS

MAX_DOCUMENT_BYTES = 64 * 1024 * 1024
MAX_ENTITY_EXPANSION = 8 * 1024 * 1024
#: Entities expanded inside one another at most (libxml2 stops at 40); each level is a frame
MAX_ENTITY_DEPTH = 40
MAX_ELEMENTS = 1_000_000
#: Deepest element nesting accepted; building and drawing recurse per level, and vecmsaa's
#: recursion limit (vecmsaa/__init__.py) leaves room for this many levels of filtered groups.
MAX_DEPTH = 1024
#: Steps of CSS selector matching per document (a selector tested on an element, an
#: ancestor or sibling visited, an element wrapped): descendant combinators backtrack
#: (``a b b b b b b rect`` over deep nesting is exponential), ``~`` and ``:*-of-type``
#: scan every earlier sibling, and rules with an unkeyed subject (``... *``) are tested on
#: every element. Past it the document is refused. Indexed selectors (a class, id, type or
#: ``*`` alone, or a compound of them: Stylesheets) are charged their candidates (and the
#: compound ones tested) once per distinct (tag, id, class) and their declarations once per
#: distinct cascade.
MAX_SELECTOR_STEPS = 50_000_000

#: properties that CSS (and presentation attributes) may set
PROPERTIES = {
    "alignment-baseline", "baseline-shift", "clip", "clip-path", "clip-rule", "color",
    "color-interpolation", "color-interpolation-filters", "color-rendering", "direction",
    "display", "dominant-baseline", "fill", "fill-opacity", "fill-rule", "filter",
    "flood-color", "flood-opacity", "font", "font-family", "font-feature-settings",
    "font-kerning", "font-size", "font-size-adjust", "font-stretch", "font-style",
    "font-variant", "font-variant-caps", "font-variant-east-asian", "font-variant-ligatures",
    "font-variant-numeric", "font-variant-position", "font-variation-settings", "font-weight",
    "font-optical-sizing", "glyph-orientation-horizontal", "glyph-orientation-vertical",
    "image-rendering",
    "isolation", "letter-spacing", "lighting-color", "marker", "marker-end", "marker-mid",
    "marker-start", "mask", "mask-mode", "mask-type", "mix-blend-mode", "opacity", "overflow",
    "paint-order", "pointer-events", "shape-rendering", "stop-color", "stop-opacity", "stroke",
    "stroke-dasharray", "stroke-dashoffset", "stroke-linecap", "stroke-linejoin",
    "stroke-miterlimit", "stroke-opacity", "stroke-width", "text-anchor", "text-decoration",
    "text-overflow", "text-rendering", "transform", "transform-box", "transform-origin",
    "translate", "rotate", "scale",
    "unicode-bidi",
    "vector-effect", "visibility", "white-space", "white-space-collapse", "word-spacing",
    "writing-mode", "inline-size", "text-orientation", "font-synthesis", "line-height",
    "background-color", "text-transform", "text-decoration-line",
}

#: properties settable from CSS only, not as presentation attributes
CSS_ONLY = {"mix-blend-mode", "isolation", "marker", "background-color", "font", "mask-mode",
            "inline-size", "text-orientation", "font-synthesis", "line-height", "white-space",
            "white-space-collapse",   # CSS Text 4 (text.content reads white-space's attribute)
            "text-transform",   # CSS Text 3; not among SVG 2's presentation attributes
            "text-decoration-line",     # CSS Text Decoration 3's longhand (expanded below)
            "font-kerning",   # resvg: font-kerning is not a presentation attribute
            # CSS Fonts 4's feature properties, none of SVG 2's presentation attributes
            # (Chromium 150 ignores them as attributes too; resvg ignores them all)
            "font-feature-settings", "font-variant-caps", "font-variant-east-asian",
            "font-variant-ligatures", "font-variant-numeric", "font-variant-position",
            "transform-box",  # not in SVG 2's list of presentation attributes
            # CSS Transforms 2's individual transforms (a rotate attribute is text's glyph
            # rotation)
            "translate", "rotate", "scale"}

#: properties that may be given as presentation attributes
PRESENTATION = PROPERTIES - CSS_ONLY

#: SVG 2's geometry properties (§"Geometry Properties"; ``d``: §9.3.1) by the elements they
#: apply to. Their attributes are their presentation attributes, so a rule or a ``style``
#: declaration overrides the attribute (CSS Cascade 4 §6.4: presentation hints come before
#: all author rules). Read at load: apply_geometry_properties writes the cascaded value over
#: the element's attribute, where every reader of the shape takes it. The outermost ``svg``
#: is left out (its size is the document's intrinsic size, which CSS sizes in an embedding
#: context), as are nested ``svg``, ``symbol``, ``foreignObject`` and a ``use``'s width and
#: height, which Chromium 150 does not apply either (see docs/svg.md, session 36).
GEOMETRY_APPLIES = {
    "rect": frozenset(("x", "y", "width", "height", "rx", "ry")),
    "circle": frozenset(("cx", "cy", "r")),
    "ellipse": frozenset(("cx", "cy", "rx", "ry")),
    "path": frozenset(("d",)),
    "image": frozenset(("x", "y", "width", "height")),
    "use": frozenset(("x", "y")),
}
GEOMETRY_PROPERTIES = frozenset().union(*GEOMETRY_APPLIES.values())
#: the key under which _specified leaves an element's geometry declarations, in cascade
#: order (not a property name: CSS names have no space); apply_geometry_properties takes it
GEOMETRY_KEY = " geometry"
#: the initial values (SVG 2): for ``inherit`` on a parent that computes none of its own
GEOMETRY_INITIAL = {"x": "0", "y": "0", "cx": "0", "cy": "0", "r": "0", "width": "auto",
                    "height": "auto", "rx": "auto", "ry": "auto", "d": "none"}

#: properties parsed but not applied, with the values that need no warning (their initial
#: values: the drawing is then what the property asks for)
UNSUPPORTED_PROPERTIES = {
    "inline-size": {"0", "auto"},                       # SVG 2 text wrapping
    "text-overflow": {"clip"},
}
_NO_WARNING = {"inherit", "initial", "unset", "revert"}

#: properties whose value passes from parent to child when not specified
INHERITED = {
    "clip-rule", "color", "color-interpolation", "color-interpolation-filters",
    "color-rendering", "direction", "dominant-baseline", "fill", "fill-opacity", "fill-rule",
    "font-family", "font-feature-settings", "font-kerning", "font-size", "font-size-adjust",
    "font-stretch", "font-style", "font-variant", "font-variant-caps",
    "font-variant-east-asian", "font-variant-ligatures", "font-variant-numeric",
    "font-variant-position", "font-variation-settings", "font-weight", "font-optical-sizing",
    "glyph-orientation-horizontal", "glyph-orientation-vertical", "image-rendering",
    "letter-spacing", "marker-end", "marker-mid", "marker-start", "paint-order",
    "pointer-events", "shape-rendering", "stroke", "stroke-dasharray", "stroke-dashoffset",
    "stroke-linecap", "stroke-linejoin", "stroke-miterlimit", "stroke-opacity",
    "stroke-width", "text-anchor", "text-rendering", "visibility", "white-space-collapse",
    "word-spacing", "writing-mode", "text-orientation", "font-synthesis", "line-height",
    "text-transform",
}

#: initial values of the properties the front end reads
INITIAL = {
    "fill": "black", "fill-opacity": "1", "fill-rule": "nonzero", "stroke": "none",
    "stroke-width": "1", "stroke-opacity": "1", "stroke-linecap": "butt",
    "stroke-linejoin": "miter", "stroke-miterlimit": "4", "stroke-dasharray": "none",
    "stroke-dashoffset": "0", "opacity": "1", "color": "black", "display": "inline",
    "visibility": "visible", "clip-rule": "nonzero", "stop-color": "black", "stop-opacity": "1",
    "overflow": "visible", "mix-blend-mode": "normal", "isolation": "auto",
    "paint-order": "normal", "shape-rendering": "auto", "image-rendering": "auto",
    "mask-type": "luminance", "font-size": "12", "font-family": "serif",
    "vector-effect": "none", "marker-start": "none", "marker-mid": "none", "marker-end": "none",
}

#: resvg's initial font size (its default ``Options::font_size``)
INITIAL_FONT_SIZE = 12.0

#: named font sizes as steps of 1.2 (CSS 2's suggested ratio). resvg applies the step to the
#: *parent's* size, so ``medium`` keeps it and ``large`` is 1.2 times it; we follow resvg.
_FONT_SIZE_STEPS = {"xx-small": -3, "x-small": -2, "small": -1, "medium": 0, "large": 1,
                    "x-large": 2, "xx-large": 3, "smaller": -1, "larger": 1}


class Element:
    """One SVG element: local tag name, attributes (local names; ``xlink:href`` → ``href``),
    specified style properties, children, and the text around it (for ``<text>``)."""

    __slots__ = ("tag", "attrs", "specified", "children", "parent", "text", "tail", "index",
                 "source", "memo")

    def __init__(self, tag, attrs, parent, index, source=None, specified=None):
        self.tag = tag
        self.attrs = attrs
        self.specified = {} if specified is None else specified
        self.children = ()         # a list from the first child on (most have none)
        self.parent = parent
        self.text = ""
        self.tail = ""
        self.index = index
        self.source = source   # the Document this element belongs to
        self.memo = None       # values computed down the document tree (computed)

    def get(self, name, default=None):
        return self.attrs.get(name, default)

    @property
    def id(self):
        return self.attrs.get("id")

    def href(self):
        """The fragment id of ``href``/``xlink:href`` (``#id`` only), or None."""
        value = (self.attrs.get("href") or "").strip()
        # the fragment as written: '# r' names ' r', which no element is
        return value[1:] if value.startswith("#") and value[1:2].strip() else None

    def computed(self, key, own, root=None):
        """computed_down the document tree: what a text needs from all its ancestors
        (xml:space, the decorations they declare, kerning) costs each element once, not once
        per text below it."""
        return computed_down(self, key, own, root)

    def ancestors(self):
        node = self.parent
        while node is not None:
            yield node
            node = node.parent

    def __repr__(self):
        return f"<{self.tag} id={self.id!r}>"


#: inherited properties whose computed value is an absolute length: ``em`` and ``ex`` are
#: resolved with the font size of the element that specifies them, and its children inherit
#: that length (CSS Values 4 §6.1.1; ``<g stroke-width="1em" font-size="10">`` strokes a child
#: of font-size 40 10 wide). Percentages stay percentages (of the viewport where used).
FONT_RELATIVE_INHERITED = {"stroke-width", "stroke-dasharray", "stroke-dashoffset",
                           "letter-spacing", "word-spacing"}
_EM_LENGTH = re.compile(r"(?<![\w.])([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(em|ex)(?![\w%])",
                        re.I)


def href_chain(doc, el, tags):
    """The element followed by what its href leads to (same kind of element only, ``tags``:
    gradients, patterns, filters), no cycles."""
    chain = [el]
    seen = {id(el)}
    node = el
    while True:
        ref = node.href()
        nxt = doc.lookup(ref) if ref else None
        if nxt is None or id(nxt) in seen or nxt.tag not in tags:
            break
        chain.append(nxt)
        seen.add(id(nxt))
        node = nxt
    return chain


def inherited_attr(chain, name, default=None):
    """The attribute of the first element of ``chain`` (an element and those its href leads
    to: gradients, patterns, filters) that has it, else ``default``."""
    for el in chain:
        if name in el.attrs:
            return el.attrs[name]
    return default


def _absolute_em(value: str, font_size: float) -> str:
    """``value`` with its em and ex lengths written in px for ``font_size``."""
    return _EM_LENGTH.sub(
        lambda m: f"{to_px(float(m.group(1)), m.group(2).lower(), font_size)!r}px", value)


def computed_down(node, key, own, root=None):
    """``own(node, its parent's value)`` computed down the ``parent`` links from the nearest
    node whose ``memo`` has ``key`` (``root`` above the topmost), and memoised on every node
    passed (a node's ``memo`` None: none yet). Elements and styles alike: each node is
    computed once, however many nodes below it ask."""
    passed = []
    while node is not None and (node.memo is None or key not in node.memo):
        passed.append(node)
        node = node.parent
    value = root if node is None else node.memo[key]
    for node in reversed(passed):
        if node.memo is None:
            node.memo = {}
        value = node.memo[key] = own(node, value)
    return value


class Style:
    """Computed style: the element's specified values over its parent's computed style.

    ``get(name)`` returns the value as a stripped string (``inherit`` resolved, initial values
    filled in). The parent is the *rendering* parent: for content instantiated by ``<use>`` it
    is the ``<use>`` element, as the SVG specification requires.
    """

    __slots__ = ("specified", "parent", "_font_size", "cache", "_children", "_layer")

    def __init__(self, specified, parent=None):
        self.specified = specified
        self.parent = parent
        self._font_size = None
        self.cache = {}   # computed values by name (styles are read many times, never changed)
        self._children = {}
        self._layer = None      # whether it passes its parent's values on (see child)

    def get(self, name, default=None):
        try:
            value = self.cache[name]
        except KeyError:
            value = self._inherit(name)
        return default if value is None else value

    def _inherit(self, name):
        """Resolve ``name`` up the ancestors without recursion (deep nesting must not reach
        Python's recursion limit) and cache it on every style passed on the way."""
        passed = []
        style = self
        inherited = name in INHERITED
        while True:
            if name in style.cache:
                value = style.cache[name]
                break
            v = style.specified.get(name)
            if v is not None and v != "inherit":
                value = v
                if name in FONT_RELATIVE_INHERITED and _EM_LENGTH.search(v):
                    value = _absolute_em(v, style.font_size())
                passed.append(style)
                break
            if style.parent is None or not (v == "inherit" or inherited):
                value = INITIAL.get(name)
                passed.append(style)
                break
            passed.append(style)
            style = style.parent
        for style in passed:
            style.cache[name] = value
        return value

    def get_valid(self, name, parse, initial):
        """The computed value of an inherited property whose declarations are validated by
        ``parse`` (the parsed value, or None for an invalid one): an invalid declaration is
        ignored as a whole, so the nearest ancestor's valid one applies (CSS Syntax 3 §8);
        ``inherit`` and ``unset`` (an inherited property's, CSS Cascade 4 §7.3) take the
        parent's; ``initial``, or no declaration up to the root, gives ``initial``. Computed
        down the styles (computed_down; a property has one ``parse`` and ``initial``), so
        texts nested a thousand deep do not each walk to the root."""
        assert name in INHERITED, name

        def own(style, above):
            v = style.specified.get(name)
            if v is None:
                return above
            v = v.strip()
            if v == "initial":
                return initial
            if v in ("inherit", "unset"):
                return above
            parsed = parse(v)
            return above if parsed is None else parsed
        return computed_down(self, ("valid", name), own, initial)

    def custom(self, name):
        """The computed value of the custom property ``name`` (None: none, or the
        guaranteed-invalid value); custom properties are always inherited."""
        value = computed_down(self, name, lambda style, above: style.specified.get(name, above))
        return None if value is None or value == "\0" else value   # variables.INVALID

    def computed(self, key, own):
        """computed_down the styles (the root's parent's value None): a property whose
        computed value needs its parent's (font-weight's ``bolder``)."""
        return computed_down(self, key, own)

    @property
    def memo(self):
        """The computed values (computed_down's name for them)."""
        return self.cache

    def font_size(self) -> float:
        """Computed font size in user units (em and % relative to the parent's)."""
        if self._font_size is None:
            unresolved = []   # up to the nearest resolved ancestor, without recursion
            style = self
            while style is not None and style._font_size is None:
                unresolved.append(style)
                style = style.parent
            size = style._font_size if style is not None else INITIAL_FONT_SIZE
            for style in reversed(unresolved):
                size = style._font_size = style._own_font_size(size)
        return self._font_size

    def _own_font_size(self, parent: float) -> float:
        v = self.specified.get("font-size")
        size = parent
        if v and v != "inherit":
            v = v.strip().lower()
            if v in _FONT_SIZE_STEPS:
                size = parent * 1.2 ** _FONT_SIZE_STEPS[v]
            else:
                parsed = split_length(v)
                if parsed is not None:
                    value, unit = parsed
                    if unit == "%":
                        size = value * parent / 100
                    elif unit in ("em", "ex"):
                        size = to_px(value, unit, parent)
                    else:
                        size = to_px(value, unit)
        return size

    def child(self, element: Element) -> "Style":
        """The style of ``element`` under this one. Siblings specifying the same values share
        one Style, and with it every value computed from it (map data repeats one style over
        thousands of elements). The shared Style keeps a copy of the values, as the text
        module expands ``font`` in an element's own dict.

        A basic shape (no children, no text) takes its style under the nearest ancestor
        style that specifies more than LAYER_PROPERTIES: those are not inherited, so such a
        style passes on exactly its parent's values, and a shape that says ``inherit`` for
        none of its values never reads them. Shapes under groups that differ only by their
        clip path, mask, opacity, filter or transform (each group of a sheet of symbols
        with its own clip) then share one Style, and the stroke parameters, paints and
        plans computed from it, instead of one each. So does a ``<text>`` without child
        elements (a label: D3 puts each axis tick's in a translated group of its own), whose
        style no other element's derives from either: its font settings, shaping and paints
        are then the document's few, not one per tick."""
        spec = element.specified
        doc = element.source
        if doc is not None and doc.var_raw:
            pending = doc.var_raw.get(id(element))
            if pending is not None:     # it uses custom properties: ours may differ
                spec = pending.specified_under(element, self)
        key = tuple(spec.items())
        owner = self
        layer = self._layer
        if layer is None:
            layer = self._layer = (self.parent is not None
                                   and LAYER_PROPERTIES.issuperset(self.specified))
        # (the values joined: one lower() and search instead of one per value; "inherit"
        # cannot span the line break between two)
        if layer and (element.tag in _SHAPE_TAGS or (element.tag == "text"
                                                     and not element.children)) and \
                "inherit" not in "\n".join(spec.values()).lower():
            owner = self.parent
            while owner.parent is not None and LAYER_PROPERTIES.issuperset(owner.specified):
                owner = owner.parent
        style = owner._children.get(key)
        if style is None:
            style = owner._children[key] = Style(dict(key), owner)
        return style


#: properties that are not inherited and that nothing reads up a shape's ancestors (see
#: Style.child): a group's compositing and placement
LAYER_PROPERTIES = frozenset((
    "clip-path", "mask", "opacity", "filter", "mix-blend-mode", "isolation", "transform",
    "transform-origin", "transform-box", "translate", "rotate", "scale"))
#: elements whose style no other element's derives from (see Style.child)
_SHAPE_TAGS = frozenset(("rect", "circle", "ellipse", "line", "polyline", "polygon", "path"))


# -- XML ------------------------------------------------------------------------------------------
_DOCTYPE_SUBSET = re.compile(rb"<!DOCTYPE[^\[>]*\[(.*?)\]\s*>", re.S)
#: an entity declaration: (%), name, then a quoted value or an external id
_ANY_ENTITY_DECL = re.compile(
    rb"<!ENTITY\s+(%\s+)?([A-Za-z_:][\w.:-]*)\s+(?:\"([^\"]*)\"|'([^']*)'|"
    rb"(?:SYSTEM|PUBLIC)\s[^>]*)\s*>")
#: an entity reference, or the start of a section where none is recognised (CDATA, comment,
#: PI), whose end is then found with bytes.find: a regular expression matching the whole
#: section would rescan the rest of the document from every unterminated opener
_ENTITY_REF = re.compile(rb"(<!\[CDATA\[|<!--|<\?)|&([A-Za-z_:][\w.:-]*);")
#: what may come between the DOCTYPE and the root element: white space, comments, PIs
_PROLOG_MISC = re.compile(rb"(?:\s|<!--.*?-->|<\?.*?\?>)*", re.S)
_SECTION_END = {b"<![CDATA[": b"]]>", b"<!--": b"-->", b"<?": b"?>"}


def _entity_references(text: bytes):
    """(start, end, name) of each entity reference outside CDATA sections, comments and
    PIs, in one pass over ``text``; an unterminated section ends the search (expat then
    reports the document malformed)."""
    pos = 0
    while True:
        m = _ENTITY_REF.search(text, pos)
        if m is None:
            return
        if m.group(1):
            end = text.find(_SECTION_END[m.group(1)], m.end())
            if end < 0:
                return
            pos = end + len(_SECTION_END[m.group(1)])
        else:
            yield m.start(), m.end(), m.group(2)
            pos = m.end()


_CHAR_REF = re.compile(rb"&#(?:([0-9]+)|x([0-9A-Fa-f]+));")


def _char_ref_bytes(m) -> bytes:
    """A character reference as the UTF-8 character it names (XML 1.0 §4.1 Char)."""
    code = int(m.group(1)) if m.group(1) else int(m.group(2), 16)
    if not (code in (0x9, 0xA, 0xD) or 0x20 <= code <= 0xD7FF or 0xE000 <= code <= 0xFFFD
            or 0x10000 <= code <= 0x10FFFF):
        raise SvgError(f"reference to invalid character number {code} in an entity value")
    return chr(code).encode("utf-8")


def _well_formed(name: bytes, value: bytes) -> bytes:
    """``value``, the replacement text of entity ``name``, if it is balanced markup (XML 1.0
    §4.3.2 WFC "Parsed Entity": an element starting in it ends in it)."""
    if b"<" in value:
        from xml.parsers import expat
        try:
            expat.ParserCreate().Parse(b"<e>" + value + b"</e>", True)
        except expat.error as exc:
            if exc.code != 11:       # XML_ERROR_UNDEFINED_ENTITY: reported in the document
                raise SvgError(f"entity {name.decode('ascii', 'replace')} is not well-formed "
                               f"markup: {expat.errors.messages[exc.code]}") from None
    return value
_ENCODING_DECL = re.compile(rb"^(<\?xml[^>]*?)\s+encoding\s*=\s*[\"'][^\"']*[\"']", re.S)


def _expand_internal_entities(data: bytes) -> bytes:
    """Substitute the internal subset's general entities in the document body (see module
    doc) and take every entity declaration out of the subset; the rest of it (attribute
    defaults, element declarations) stays for expat, which applies the defaults as XML 1.0
    §5.1 asks of any processor. An entity's value may hold markup and other entities, expanded
    once each and capped in size; a cycle is an error. External entities are never read: their
    declarations go, and a reference to one is skipped (XML 1.0 §4.4.3, "included if
    validating": a non-validating processor may leave it out), as are parameter entities."""
    start = data.find(b"<!DOCTYPE")     # the first only: one attempt, not one per opener
    m = _DOCTYPE_SUBSET.match(data, start) if start >= 0 else None
    if not m:
        return data
    subset = m.group(1)
    declared = {}       # name -> value as written (bytes), None for an external entity
    for em in _ANY_ENTITY_DECL.finditer(subset):
        if em.group(1):
            continue                                   # a parameter entity: not used here
        name, value = em.group(2), em.group(3) if em.group(3) is not None else em.group(4)
        if value is not None and b"%" in value:
            raise SvgError("parameter entity references in an entity value are not allowed")
        if value is not None:
            value = _CHAR_REF.sub(_char_ref_bytes, value)   # §4.5: at declaration already
        declared.setdefault(name, value)               # the first declaration binds (§4.2)
    rest = _ANY_ENTITY_DECL.sub(b"", subset)
    expanded = {}
    busy = set()
    skipped = set()
    # bytes substituted so far, at every level together: each entity's expansion is kept
    # (expanded), so a cap per expansion would let a chain of distinct entities, each a copy
    # of the one before, hold the cap once per level (40 x 8 MB from a 2 KB file)
    produced = [0]

    def expand(text: bytes) -> bytes:
        out = []
        pos = 0
        for start, end, name in _entity_references(text):
            if name not in declared:
                continue                                # predefined or undefined: expat's
            value = declared[name]
            if value is None:
                skipped.add(name.decode("ascii", "replace"))
                value = b""
            elif name in expanded:
                value = expanded[name]
            else:
                if name in busy:
                    raise SvgError(f"entity {name.decode('ascii', 'replace')} refers to itself")
                if len(busy) >= MAX_ENTITY_DEPTH:
                    raise SvgError(f"entities nest deeper than {MAX_ENTITY_DEPTH} levels")
                busy.add(name)
                value = expanded[name] = _well_formed(name, expand(value))
                busy.discard(name)
            out.append(text[pos:start])
            out.append(value)
            produced[0] += len(value)
            if produced[0] > MAX_ENTITY_EXPANSION:
                raise SvgError("document too large after entity expansion")
            pos = end
        out.append(text[pos:])
        return b"".join(out)

    body = data[m.end():]
    if body[_PROLOG_MISC.match(body).end():][:1] == b"<":
        body = expand(body)
    # else a reference stands where the root element must (XML 1.0 §2.1: document ::=
    # prolog element Misc*; a reference is content): left for expat to refuse
    for name in sorted(skipped):
        warn(f"external entity {name} is not read: left out")
    subset_left = rest if rest.strip(b" \t\r\n") else b""
    doctype = data[m.start():m.start(1)] + subset_left + data[m.end(1):m.end()]
    return data[:m.start()] + doctype + body


def _decode_to_utf8(data: bytes) -> bytes:
    """Re-encode a document as UTF-8 and drop its encoding declaration (needed before text-level
    entity substitution)."""
    m = re.match(rb"^\s*<\?xml[^>]*encoding\s*=\s*[\"']([^\"']+)[\"']", data)
    enc = m.group(1).decode("ascii", "replace") if m else "utf-8"
    try:
        text = data.decode(enc)
    except (LookupError, UnicodeDecodeError) as exc:
        raise SvgError(f"cannot decode document as {enc}") from exc
    return _ENCODING_DECL.sub(rb"\1", text.encode("utf-8"), count=1)


def _prepare(data: bytes) -> bytes:
    """The document's bytes ready for expat: bounded, gunzipped, internal entities expanded."""
    if len(data) > MAX_DOCUMENT_BYTES:
        raise SvgError("document too large")
    if data[:2] == b"\x1f\x8b":
        import zlib
        try:
            d = zlib.decompressobj(16 + zlib.MAX_WBITS)
            data = d.decompress(data, MAX_DOCUMENT_BYTES + 1)
        except (OSError, zlib.error, EOFError) as exc:
            raise SvgError(f"bad svgz data: {exc}") from exc
        if len(data) > MAX_DOCUMENT_BYTES:
            raise SvgError("document too large")
    if b"<!ENTITY" in data:
        data = _expand_internal_entities(_decode_to_utf8(data))
    return data


def _et_name(name):
    """An expat name ("uri}local") as ElementTree spells it ("{uri}local")."""
    return "{" + name if "}" in name else name


def _attribute_shape(names):
    """What start_plain makes of an element whose attributes (expat's dict) have ``names``,
    in this order: False when start() reads it (a namespaced attribute other than
    xlink:href, or xlink:href and href both), else (the names with xlink:href as ``href``, or
    None where none is; the presentation attributes' names; an operator.itemgetter of their
    values, None for none; whether it has a style attribute). The getter gives a tuple for
    one name too (the name twice: _given_dict pairs the names with as many values)."""
    rename = None
    if _XLINK_HREF in names:
        if "href" in names:
            return False
        rename = tuple("href" if k == _XLINK_HREF else k for k in names)
    if "}" in "".join(rename or names):
        return False
    pnames = tuple(k for k in names if k in PRESENTATION)
    getter = None if not pnames else operator.itemgetter(*pnames) if len(pnames) > 1 else \
        operator.itemgetter(pnames[0], pnames[0])
    return rename, pnames, getter, "style" in names


def _pairs_given(pairs):
    """Presentation attributes [(name, value as written)...] as _attribute_shape's readers
    give them: (names, values), None for none."""
    if not pairs:
        return None
    return tuple(k for k, _ in pairs), tuple(v for _, v in pairs)


def _given_dict(given):
    """{name: value stripped} of presentation attributes ``given`` ((names, values) or None)."""
    return {} if given is None else {k: v.strip() for k, v in zip(*given)}


#: a <style> element (any prefix): the document needs the CSS cascade's element tree
_STYLE_ELEMENT = re.compile(rb"<(?:[^\s<>/!?:]+:)?style[\s/>]")


#: the elements SVG 1.1 and SVG 2 define; another name in the SVG namespace is an unknown
#: element, treated as one of another namespace
SVG_ELEMENT_NAMES = frozenset("""
a altGlyph altGlyphDef altGlyphItem animate animateColor animateMotion animateTransform circle
clipPath color-profile cursor defs desc discard ellipse feBlend feColorMatrix
feComponentTransfer feComposite feConvolveMatrix feDiffuseLighting feDisplacementMap
feDistantLight feDropShadow feFlood feFuncA feFuncB feFuncG feFuncR feGaussianBlur feImage
feMerge feMergeNode feMorphology feOffset fePointLight feSpecularLighting feSpotLight feTile
feTurbulence filter font font-face font-face-format font-face-name font-face-src
font-face-uri foreignObject g glyph glyphRef hkern image line linearGradient marker mask
metadata missing-glyph mpath path pattern polygon polyline radialGradient rect script set
stop style svg switch symbol text textPath title tref tspan use view vkern""".split())


class _Foreign:
    """On the reader's stack: an element of another namespace, and the SVG element around
    it (which the SVG elements inside inherit from)."""
    __slots__ = ("parent",)

    def __init__(self, parent):
        self.parent = parent


class _TreeReader:
    """expat events straight into the :class:`Element` tree (no ElementTree in between: on
    map data building it and converting it cost three times expat's own parse).

    The tree is what ElementTree's tree converted element by element would be: elements
    outside the root's namespace are skipped with their subtree (the text after one stays
    its parent's character data), comments and processing instructions leave no trace in
    the text around them. The guards are defusedxml's (no entity declarations, no external
    entities), with its exceptions. With ``mirror`` the ElementTree tree is built as well,
    for CSS selector matching, and each element's specified style is left to
    :func:`_cascade`; with ``deferred`` too, without the ElementTree tree (the document's
    selectors are all indexed ones, :class:`Stylesheets`), and its ``<style>`` elements are
    listed in ``styles``."""

    def __init__(self, doc, mirror: bool, custom: bool = False, deferred: bool = False):
        self.doc = doc
        self.custom = custom       # the document has var() (_specified)
        self.mirror = None
        # (Element, its ElementTree twin or None, its presentation attributes as written
        # ((name, value)...), its style attribute) of each element, for _cascade
        self.pending = []
        self.styles = []           # the <style> Elements in document order (deferred)
        self.deferred = mirror or deferred
        self.warnings = []         # unsupported values, warned about once the tree is read
        self.geometry = False      # an element's style has geometry declarations (GEOMETRY_KEY)
        self.error = None          # the first limit exceeded, in document order
        self.bad_root = False
        self.root = None
        self._mirror = mirror

    def read(self, data: bytes) -> Element | None:
        """The root Element (None when the root is not <svg> or a limit was exceeded: see
        ``bad_root`` and ``error``). Raises SvgError for malformed or forbidden XML."""
        from xml.parsers import expat

        from defusedxml import DefusedXmlException
        from defusedxml.common import EntitiesForbidden, ExternalReferenceForbidden

        parser = expat.ParserCreate(None, "}")
        parser.buffer_text = True
        parser.ordered_attributes = False   # a dict in document order, built by expat
        doc = self.doc
        paths = doc.paths
        stack = []                 # open elements, None for skipped ones
        chunks = []                # character data since the last tag
        last = [None, False]       # where it goes: the element, and whether as its tail
        default_ns = None
        count = 0                  # elements visited (the foreign ones included)
        unmade = 0                 # of those, the ones skipped (made: count - unmade)
        error = None
        names = {}                 # expat name -> (namespace, local name)
        own = {}                   # expat name -> local name, of the root's namespace
        shapes = {}                # attribute names (expat's) -> _attribute_shape of them
        warnings = self.warnings
        custom = self.custom
        deferred = self.deferred and not self._mirror     # start_plain defers
        pending = self.pending
        styles = self.styles
        # the specified style by (presentation attributes as written, style attribute), with
        # the warnings it gave (map data and charts repeat a few over thousands of elements):
        # the first element's dict stands for the others, as nothing changes it while the
        # document is read; each element gets a copy of its own
        made = {}

        def specify(given, style_attr):
            """The specified style of an element without CSS rules: its presentation
            attributes ``given`` (_given: (names, values as written) or None) under its style
            attribute; made once for each such pair (in a document with var(), each time),
            its warnings given again for each element."""
            if custom:
                spec = _specified(_given_dict(given), None, style_attr, warnings, True)
                if GEOMETRY_KEY in spec:
                    self.geometry = True
                return spec
            got = made.get((given, style_attr))
            if got is not None:
                warnings.extend(got[1])
                return dict(got[0])
            before = len(warnings)
            spec = _specified(_given_dict(given), None, style_attr, warnings)
            made[given, style_attr] = spec, warnings[before:]
            if GEOMETRY_KEY in spec:
                self.geometry = True
            return spec
        tb = None
        if self._mirror:
            import xml.etree.ElementTree as ET
            tb = ET.TreeBuilder()

        def flush():
            text = chunks[0] if len(chunks) == 1 else "".join(chunks)
            chunks.clear()
            el = last[0]
            if el is not None:
                if last[1]:
                    el.tail += text    # += : a foreign element may have split it
                else:
                    el.text += text

        def start_plain(name, attr):
            """start() without the mirror, for the common case in one go: an element of the
            root's namespace inside it, none of whose attributes has a namespace, within the
            limits (map data: tens of thousands of <path d="...">; flush() written out, one
            Python call less per element)."""
            nonlocal count
            if chunks:
                text = chunks[0] if len(chunks) == 1 else "".join(chunks)
                chunks.clear()
                el = last[0]
                if el is not None:
                    if last[1]:
                        el.tail += text
                    else:
                        el.text += text
            tag = own.get(name)
            if (tag is None or not stack or error is not None or count >= MAX_ELEMENTS
                    or len(stack) > MAX_DEPTH):
                return start(name, attr, False)
            parent = stack[-1]
            if parent.__class__ is not Element:      # skipped, or inside a foreign element
                return start(name, attr, False)
            # what an element's attribute names (in document order) make of it, worked out
            # once per distinct list of names (scatter plots repeat cx cy r fill...)
            names = tuple(attr)
            shape = shapes.get(names)
            if shape is None:
                shape = shapes[names] = _attribute_shape(names)
            if shape is False:
                return start(name, attr, False)
            rename, pnames, getter, has_style = shape
            if rename is not None:
                # xlink:href (a <use> of pdftocairo's glyphs) read as start() reads it: as
                # href, at its place (with a plain href too, start() reads the element)
                attr = dict(zip(rename, attr.values()))
            if getter is None and not has_style:
                spec = {}
                given = None
                style_attr = None
            else:
                style_attr = attr.get("style") if has_style else None
                given = None if getter is None else (pnames, getter(attr))
                if deferred or not (given or style_attr):
                    spec = {}
                else:
                    got = None if custom else made.get((given, style_attr))
                    if got is None:
                        spec = specify(given, style_attr)
                    else:
                        spec = dict(got[0])
                        if got[1]:
                            warnings.extend(got[1])
            count += 1
            siblings = parent.children
            el = Element(tag, attr, parent, len(siblings), doc, spec)
            if deferred:
                pending.append((el, None, given, style_attr))
                if tag == "style":
                    styles.append(el)
            if tag == "path":
                paths.append(el)
            elif tag == "use":
                doc.has_use = True
            elif tag in _LINK_CONTAINERS:
                doc.link_containers.append(el)
            if siblings:
                siblings.append(el)
            else:
                parent.children = [el]
            stack.append(el)
            last[0] = el
            last[1] = False

        def start(name, attr, pending_text=True):
            nonlocal default_ns, count, unmade, error
            if pending_text and chunks:
                flush()
            if tb is not None:
                node = tb.start(_et_name(name), {_et_name(k): v for k, v in attr.items()})
            if stack and stack[-1] is None or error is not None:
                stack.append(None)
                last[0] = None
                return
            try:
                ns, tag = names[name]
            except KeyError:
                ns, sep, tag = name.partition("}")
                if not sep:
                    ns, tag = "", name
                names[name] = ns, tag
            if not stack:
                if tag != "svg" or ns not in (SVG_NS, ""):
                    self.bad_root = True
                    stack.append(None)
                    last[0] = None
                    return
                default_ns = ns
            count += 1
            if count > MAX_ELEMENTS:
                error = "too many elements"
            elif len(stack) > MAX_DEPTH:
                error = f"elements nest deeper than {MAX_DEPTH} levels"
            # a document whose root has no namespace (read as SVG, as resvg reads it) takes
            # elements of the SVG namespace too (`<s:rect>` with xmlns:s for SVG): they are
            # SVG elements whatever the root is
            if error is not None or tag not in SVG_ELEMENT_NAMES or (
                    ns != default_ns and not (ns == SVG_NS and default_ns == "")):
                unmade += 1
                if error is not None:
                    stack.append(None)
                else:
                    # foreign or unknown element: not drawn, nor anything in it; the SVG
                    # elements inside are made, detached (<use> may reference them, as in
                    # resvg), inheriting from the SVG element around. Paint servers, clips,
                    # masks, markers, filters and paths there are not found (as in resvg, and
                    # in browsers, which lay out nothing under an unknown element)
                    top = stack[-1]
                    stack.append(_Foreign(top.parent if top.__class__ is _Foreign else top))
                last[0] = None
                return
            own[name] = tag
            # presentation attributes (none is a shorthand: marker is CSS only)
            if "}" not in "".join(attr):
                # no namespaced attribute (map data: d and id): expat's dict as it is
                attrs = attr
                style_attr = attr.get("style")
                given = None if PRESENTATION.isdisjoint(attr) else \
                    _pairs_given([(k, v) for k, v in attr.items() if k in PRESENTATION])
            else:
                attrs = {}
                style_attr = None
                given = []
                for key, value in attr.items():
                    if "}" in key:
                        ans, _, aname = key.partition("}")
                        if ans == XLINK_NS and aname == "href":
                            attrs.setdefault("href", value)
                        elif ans == XML_NS:
                            attrs["xml:" + aname] = value
                        continue
                    attrs[key] = value      # a plain href overrides xlink:href
                    if key == "style":
                        style_attr = value
                    elif key in PRESENTATION:
                        given.append((key, value))
                given = _pairs_given(given)
            parent = stack[-1] if stack else None
            if parent.__class__ is _Foreign:
                el = Element(tag, attrs, parent.parent, 0, doc)
                doc.detached.append(el)
                parent = None
            else:
                el = Element(tag, attrs, parent, len(parent.children) if parent else 0, doc)
            if tag == "path":
                paths.append(el)
            elif tag == "use":
                doc.has_use = True
            elif tag in _LINK_CONTAINERS:
                doc.link_containers.append(el)
            if self.deferred:
                pending.append((el, node if tb is not None else None, given, style_attr))
                if tag == "style":
                    styles.append(el)
            elif given or style_attr:
                el.specified = specify(given, style_attr)
            if parent is not None:
                if parent.children:
                    parent.children.append(el)
                else:
                    parent.children = [el]
            elif self.root is None:
                self.root = el
            stack.append(el)
            last[0] = el
            last[1] = False

        def end(name):
            if chunks:
                flush()
            el = stack.pop()
            if el.__class__ is not Element and stack and stack[-1].__class__ is Element:
                # the characters after a skipped (foreign) element are still its parent's:
                # a <text>'s words after an element of another namespace are drawn
                parent = stack[-1]
                if parent.children:
                    last[0], last[1] = parent.children[-1], True
                else:
                    last[0], last[1] = parent, False
                return
            if el.__class__ is not Element:
                last[0] = None
                return
            last[0] = el
            last[1] = True

        def end_mirrored(name):
            tb.end(_et_name(name))
            end(name)

        def characters_mirrored(text):
            chunks.append(text)
            tb.data(text)

        def default(text):
            if text[:1] == "&":   # an entity no DTD declares (ElementTree's message)
                err = expat.error(f"undefined entity {text}: line {parser.ErrorLineNumber}, "
                                  f"column {parser.ErrorColumnNumber}")
                err.code = 11       # XML_ERROR_UNDEFINED_ENTITY
                raise err

        def no_entities(name, *args):     # declared or unparsed: (..., base, ids, notation)
            raise EntitiesForbidden(name, None, *args[-4:])

        def no_external(context, base, sysid, pubid):
            raise ExternalReferenceForbidden(context, base, sysid, pubid)

        parser.StartElementHandler = start if tb is not None else start_plain
        # without the mirror, no Python frame per end tag test and per text run
        parser.EndElementHandler = end if tb is None else end_mirrored
        parser.CharacterDataHandler = chunks.append if tb is None else characters_mirrored
        parser.DefaultHandlerExpand = default
        parser.EntityDeclHandler = no_entities
        parser.UnparsedEntityDeclHandler = no_entities
        parser.ExternalEntityRefHandler = no_external
        try:
            parser.Parse(data, True)
        except expat.error as exc:
            raise SvgError(f"malformed XML: {exc}") from None
        except DefusedXmlException as exc:
            raise SvgError(f"forbidden XML construct: {type(exc).__name__}") from None
        except (ValueError, UnicodeError, LookupError) as exc:   # LookupError: unknown encoding
            raise SvgError(f"malformed XML: {exc}") from None
        finally:
            # the handlers' closures hold the parser (default() reads its position): without
            # them the reader and its state go when unused, not at the collector's next pass
            parser.StartElementHandler = parser.EndElementHandler = None
            parser.CharacterDataHandler = parser.DefaultHandlerExpand = None
        self.error = error
        doc.size = count - unmade
        if tb is not None:
            self.mirror = tb.close()
        return self.root

# -- CSS ------------------------------------------------------------------------------------------
#: CSS's white space as tinycss2 tokenizes it (\r and \f are read as \n)
_CSS_WS = "[ \t\n]"
_IDENT = "-?[A-Za-z_][A-Za-z0-9_-]*"
#: one token of a plain value (_plain_declarations): an identifier, a hash, a number with an
#: optional percent sign or ASCII unit (not ``e`` alone, which tinycss2 writes escaped)
_PLAIN_WORD = (_IDENT + "|#[A-Za-z0-9_-]+|[+-]?(?:[0-9]+(?:\\.[0-9]+)?|\\.[0-9]+)"
               "(?:%|(?![eE](?![A-Za-z]))[A-Za-z]+)?")
_PLAIN_DECLARATION = re.compile(
    "%s*(%s)%s*:%s*((?:%s)(?:(?:%s*,%s*|%s+)(?:%s))*)?%s*" % (
        _CSS_WS, _IDENT, _CSS_WS, _CSS_WS, _PLAIN_WORD, _CSS_WS, _CSS_WS, _CSS_WS, _PLAIN_WORD,
        _CSS_WS), re.ASCII)
_CSS_NEWLINES = re.compile("\r\n|[\r\f]")


def _plain_declarations(text):
    """_declarations(text) for a plain declaration list, without tinycss2: ``name: value``
    separated by semicolons, the name an ASCII identifier (not a custom property), the value
    identifiers, hashes and numbers (with a unit or %) separated by white space or commas,
    nothing else (no comments, strings, functions, escapes, ``!important``): tinycss2 would
    write such a value back as written, so the text is the value. None for any other text
    (_declarations reads it with tinycss2)."""
    if "\r" in text or "\f" in text:
        text = _CSS_NEWLINES.sub("\n", text)
    out = []
    match = _PLAIN_DECLARATION.fullmatch
    for part in text.split(";"):
        m = match(part)
        if m is None:
            if part.strip(" \t\n"):
                return None
            continue
        value = m.group(2)
        if value:
            out.append((m.group(1).lower(), value, False))
    return out


def _declarations(tokens_or_text):
    import tinycss2

    if isinstance(tokens_or_text, str):
        plain = _plain_declarations(tokens_or_text)
        if plain is not None:
            return plain
    if isinstance(tokens_or_text, str):
        decls = tinycss2.parse_declaration_list(tokens_or_text, skip_whitespace=True,
                                                skip_comments=True)
    else:
        decls = tinycss2.parse_declaration_list(tokens_or_text, skip_whitespace=True,
                                                skip_comments=True)
    out = []
    for d in decls:
        if d.type != "declaration":
            continue
        value = _value_text(d.value)
        name = d.lower_name
        if name[:2] == "--":
            # a custom property: its name is case-sensitive, its value may be empty
            # (CSS Variables 1 §2)
            out.append((d.name, value, bool(d.important)))
        elif value:
            # no property takes an empty value: CSS drops the declaration, and what it would
            # have overridden (a presentation attribute, an earlier rule) applies
            out.append((name, value, bool(d.important)))
    return out


def _value_text(tokens):
    import tinycss2

    value = tinycss2.serialize(tokens).strip()
    if "/**/" in value and '"' not in value and "'" not in value:
        # tinycss2 writes an empty comment between tokens that would run together
        # (`translate(-10-10)` → `-10/**/-10`); the SVG number grammars the values are
        # read with take a space there
        value = value.replace("/**/", " ")
    return value


def _without_comments(value):
    """A presentation attribute's value without its CSS comments: SVG 2 parses presentation
    attributes as CSS values (styling, "Presentation attributes"), and CSS Syntax 3 drops
    comments as it tokenizes (not inside strings or url()); the tokens they separate stay
    apart."""
    import tinycss2

    return _value_text(tinycss2.parse_component_value_list(value, skip_comments=True))


@functools.lru_cache(maxsize=4096)
def _style_attribute(text):
    """The declarations of a ``style`` attribute; documents repeat the same few strings over
    thousands of elements, so each is parsed once."""
    return tuple(_declarations(text))


_MARKER_LONGHANDS = ("marker-start", "marker-mid", "marker-end")


def _longhands(name):
    """The properties the shorthand ``name`` sets (_expand_shorthand), None for any other
    property."""
    if name == "marker":
        return _MARKER_LONGHANDS
    if name == "font":
        from .text.font_match import FONT_RESETS
        return (*FONT_RESETS, "font-size", "font-family")
    if name in ("white-space", "white-space-collapse"):
        return ("white-space-collapse",)
    if name == "text-decoration-line":
        return ("text-decoration",)
    return None


def _expand_shorthand(name, value):
    """``marker`` sets all three marker properties; ``text-decoration-line`` the lines
    text-decoration sets; ``font`` sets the font longhands and
    ``white-space`` white-space-collapse (text-wrap-mode wraps nothing here), in the
    cascade as CSS expands any shorthand: over presentation attributes and earlier
    declarations, under later ones, and inherited from a group like the longhands (CSS Fonts 4
    §2.9); an invalid ``font``, ``white-space`` or ``white-space-collapse`` is dropped, so an
    earlier declaration stays (CSS Syntax 3 §8). A value holding var() is expanded once it is
    substituted (variables.resolve)."""
    if value.__class__ is not str:      # variables.Unresolved
        longhands = _longhands(name)
        if longhands is None:
            return [(name, value)]
        from .variables import shorthand_pending
        return shorthand_pending(name, value, longhands)
    if name == "marker":
        return [(n, value) for n in _MARKER_LONGHANDS]
    if name == "text-decoration-line":
        # text-decoration is its shorthand (SVG 2 §11.11, CSS Text Decoration 3 §2.4): both
        # set the lines, the only part SVG draws (the decoration's paint is the declaring
        # element's fill and stroke, not text-decoration-color), so the later one wins
        return [("text-decoration", value)]
    if name == "font":
        from .text.font_match import parse_font_shorthand
        if value.strip().lower() == "inherit":
            return [(n, "inherit") for n in _longhands(name)]
        return list((parse_font_shorthand(value) or {}).items())
    if name in ("white-space", "white-space-collapse"):
        from .text.content import white_space_collapse
        collapse = white_space_collapse(value, name == "white-space")
        return [("white-space-collapse", collapse)] if collapse else []
    return [(name, value)]


def _namespace_rule(rule, namespaces):
    """Record an ``@namespace [prefix] <string or url>;`` rule in ``namespaces`` (prefix, or
    None for the default namespace -> URL); anything else in the prelude, or a block, makes
    the rule invalid and it is ignored (CSS Namespaces 3 §2)."""
    if rule.content is not None:
        return
    parts = [t for t in rule.prelude if t.type not in ("whitespace", "comment")]
    prefix = None
    if len(parts) == 2 and parts[0].type == "ident":
        prefix = parts.pop(0).value
    if len(parts) != 1:
        return
    tok = parts[0]
    if tok.type == "function" and tok.lower_name == "url":     # url("...")
        args = [a for a in tok.arguments if a.type != "whitespace"]
        if len(args) == 1 and args[0].type == "string":
            namespaces[prefix] = args[0].value
    elif tok.type in ("string", "url"):
        namespaces[prefix] = tok.value


#: a private @namespace prefix for xlink (_hyperlinks): CSS prefixes cannot hold a space
_XLINK_PREFIX = "vecmsaa xlink"


def _hyperlinks(prelude):
    """A rule's selector tokens with ``:link`` and ``:any-link`` as SVG defines them, for
    cssselect2 (which matches HTML's a, area and link only): Selectors 4 §9.2 leaves the
    hyperlinks to the document language, and SVG 2 §16.2 makes an ``a`` with an ``href``
    (or ``xlink:href``, which ``href`` overrides) one; an empty one is none, as Chromium 150
    takes it. Each becomes ``:where(*|a):is([href], [xlink|href])`` with those conditions in
    more :where(), of the same specificity as one pseudo-class (:where counts nothing).
    ``:visited`` matches nothing (cssselect2's: a renderer has no history; Selectors 4 lets
    all links be unvisited). The prelude itself when it names neither."""
    import tinycss2

    def rewrite(tokens):
        out = []
        changed = False
        for i, tok in enumerate(tokens):
            if (tok.type == "ident" and tok.lower_value in ("link", "any-link") and i and
                    tokens[i - 1].type == "literal" and tokens[i - 1].value == ":"
                    and not (i > 1 and tokens[i - 2].type == "literal"
                             and tokens[i - 2].value == ":")):
                out.extend(_HYPERLINK_TOKENS)
                changed = True
                continue
            if tok.type == "function":
                args, sub = rewrite(tok.arguments)
                if sub:
                    tok = tinycss2.ast.FunctionBlock(tok.source_line, tok.source_column,
                                                     tok.name, args)
                    changed = True
            out.append(tok)
        return out, changed

    global _HYPERLINK_TOKENS
    if _HYPERLINK_TOKENS is None:
        # the ":" before the pseudo-class stays in the rule's tokens: these replace its name
        _HYPERLINK_TOKENS = tuple(tinycss2.parse_component_value_list(
            'where(*|a):is([href], [X|href]):where(:not([href=""])):where([href], '
            ':not([X|href=""]))'.replace("X", _XLINK_PREFIX.replace(" ", "\\ "))))
    got, changed = rewrite(prelude)
    return got if changed else prelude


_HYPERLINK_TOKENS = None


#: cssselect2 compiles a selector into one Python expression nesting three parentheses per
#: combinator, which Python's parser refuses past 200 (67 combinators); its parser also takes
#: time quadratic in a selector's length (20,000 combinators: minutes). A rule with a longer
#: selector is dropped before it is parsed: it could never match anyway.
MAX_COMBINATORS = 100


def _most_combinators(prelude) -> int:
    """The most combinators (between compound selectors) in one selector of a list."""
    most = count = 0
    started = pending = False
    for tok in prelude:
        if tok.type == "literal" and tok.value == ",":
            count, started, pending = 0, False, False
        elif tok.type in ("whitespace", "comment") or (tok.type == "literal"
                                                       and tok.value in (">", "+", "~")):
            pending = started
        else:
            if pending:
                count += 1
                most = max(most, count)
            started, pending = True, False
    return most


def _split_selectors(prelude):
    """The top-level comma-separated parts of a selector list's tokens, each without the
    white space at its ends (a comma inside a function, ``:is(a, b)``, is not top-level)."""
    parts = [[]]
    for tok in prelude:
        if tok.type == "literal" and tok.value == ",":
            parts.append([])
        else:
            parts[-1].append(tok)
    for part in parts:
        while part and part[0].type == "whitespace":
            del part[0]
        while part and part[-1].type == "whitespace":
            del part[-1]
    return parts


#: the specificity of each kind of simple selector (Selectors 4 §17)
_SIMPLE_SPECIFICITY = {"id": (1, 0, 0), "class": (0, 1, 0), "tag": (0, 0, 1), "*": (0, 0, 0)}


def _selector_key(tag, star, ids, classes):
    """What Stylesheets indexes a compound selector of a type selector ``tag`` (or None),
    the universal selector (``star``), ids and classes (lists, as written) under: ("class",
    "a"), ("id", "a"), ("tag", "rect") or ("*", None) for one of them alone (``*`` with
    one id or class is that one alone), ("compound", (tag or None, id or None, classes))
    for more (``rect.a``, ``.a.b``, ``#x.a``: Selectors 4 §4, all of them tested on the
    element); None for two ids (left to cssselect2) or nothing."""
    if len(ids) > 1 or (tag is not None and star):
        return None
    parts = (tag is not None) + len(ids) + len(classes)
    if parts == 0:
        return ("*", None) if star else None
    if parts == 1:
        return ("tag", tag) if tag is not None else ("id", ids[0]) if ids else \
            ("class", classes[0])
    return "compound", (tag, ids[0] if ids else None, tuple(classes))


def _key_specificity(kind, name):
    """The specificity of an indexed selector (Selectors 4 §17)."""
    if kind == "compound":
        tag, ident, classes = name
        return (ident is not None, len(classes), tag is not None)
    return _SIMPLE_SPECIFICITY[kind]


def _simple_tokens(tokens):
    """_selector_key of a selector's tokens (white space at the ends taken off) that are one
    compound selector of a type or universal selector, ids (``#a``) and classes (``.a``);
    None for any other."""
    n = len(tokens)
    if n == 0:
        return None
    tag = None
    star = False
    ids = []
    classes = []
    i = 0
    first = tokens[0]
    if first.type == "ident":
        tag = first.value
        i = 1
    elif first.type == "literal" and first.value == "*":
        star = True
        i = 1
    while i < n:
        tok = tokens[i]
        if tok.type == "hash" and tok.is_identifier:
            ids.append(tok.value)
            i += 1
        elif tok.type == "literal" and tok.value == "." and i + 1 < n and \
                tokens[i + 1].type == "ident":
            classes.append(tokens[i + 1].value)
            i += 2
        else:
            return None
    return _selector_key(tag, star, ids, classes)


def _simple_selector(tokens, compiled):
    """_simple_tokens(tokens), where it agrees with ``compiled``, cssselect2's compilation
    of the same selector: with what it indexes and with its specificity (a type or universal
    selector under a default @namespace tests the namespace too, and is not simple)."""
    if compiled.pseudo_element is not None or compiled.never_matches:
        return None
    got = _simple_tokens(tokens)
    if got is None:
        return None
    kind, name = got
    if tuple(compiled.specificity) != tuple(_key_specificity(kind, name)) or \
            compiled.namespace is not None or compiled.requires_lang_attr:
        return None
    if kind == "compound":
        # cssselect2 keeps the last id and class and the type of a compound selector
        tag, ident, classes = name
        expect = (ident, classes[-1] if classes else None, tag)
    else:
        expect = (name if kind == "id" else None, name if kind == "class" else None,
                  name if kind == "tag" else None)
    if (compiled.id, compiled.class_name, compiled.local_name) != expect:
        return None
    return kind, name


#: a class attribute's names (cssselect2's and Selectors 4's white space)
_CLASS_NAMES = re.compile("[^ \t\r\n\f]+").findall


_PLAIN_SIMPLE = "(?:%s|\\*)?(?:\\.%s|#%s)+|%s|\\*" % (_IDENT, _IDENT, _IDENT, _IDENT)
_PLAIN_PART = re.compile("([.#]?)(%s|\\*)" % _IDENT, re.ASCII)
#: a rule of a plain sheet (_plain_sheet): simple selectors separated by commas, then a block
#: without braces (_plain_declarations reads it)
_PLAIN_RULE = re.compile("%s*((?:%s)(?:%s*,%s*(?:%s))*)%s*\\{([^{}]*)\\}%s*" % (
    _CSS_WS, _PLAIN_SIMPLE, _CSS_WS, _CSS_WS, _PLAIN_SIMPLE, _CSS_WS, _CSS_WS), re.ASCII)
_PLAIN_SELECTOR = re.compile(_PLAIN_SIMPLE, re.ASCII)


def _plain_sheet(css_text):
    """[(its selectors as _simple_tokens gives them, its declarations)...] of each rule of a
    plain style sheet, without tinycss2: every rule a list of simple selectors (a class, an
    id, a type or ``*``) with a plain declaration block (_plain_declarations), nothing else
    (exporters' sheets: ``.st0{fill:#94118e;stroke:#000;stroke-miterlimit:10;}``). None for
    any other sheet (Stylesheets.add reads it with tinycss2)."""
    if "\r" in css_text or "\f" in css_text:
        css_text = _CSS_NEWLINES.sub("\n", css_text)
    rules = []
    pos = 0
    end = len(css_text)
    match = _PLAIN_RULE.match
    while pos < end:
        m = match(css_text, pos)
        if m is None:
            return None if css_text[pos:].strip(" \t\n") else rules
        decls = _plain_declarations(m.group(2))
        if decls is None:
            return None
        selectors = []
        for sel in _PLAIN_SELECTOR.findall(m.group(1)):
            tag = None
            star = False
            ids = []
            classes = []
            for mark, name in _PLAIN_PART.findall(sel):
                if mark == ".":
                    classes.append(name)
                elif mark == "#":
                    ids.append(name)
                elif name == "*":
                    star = True
                else:
                    tag = name
            key = _selector_key(tag, star, ids, classes)
            if key is None:
                return None
            selectors.append(key)
        rules.append((selectors, decls))
        pos = m.end()
    return rules


class Stylesheets:
    """All CSS rules of a document. Selectors that are a single class, id, type or the
    universal selector (exporters' style sheets are all ``.st0{...}``), or a compound of a
    type, one id and classes (``rect.a``, ``.a.b``: _selector_key), are indexed here and
    looked up per element (:meth:`simple_matches`); the others are matched with cssselect2
    (``matcher``). Both number their selectors in one sequence, cssselect2's ``order``, so
    the cascade sorts the matches of both by specificity and order together."""

    def __init__(self):
        import cssselect2

        self.matcher = cssselect2.Matcher()
        self.count = 0
        self.complex = 0            # selectors in ``matcher``
        self.by_class = {}          # name -> [(specificity, order, None, payload)]
        self.by_id = {}
        self.by_tag = {}
        self.universal = []
        # compound selectors (rect.a, .a.b, #x.a): (tag or None, classes, entry) by their id,
        # or by one of their classes where they have no id
        self.compound_by_id = {}
        self.compound_by_class = {}
        self.key_tags = set()       # the types and ids a selector names (simple_matches' key)
        self.key_ids = set()
        self._simple = {}           # (tag, id, class attribute) -> matches (simple_matches)

    def add(self, css_text):
        plain = _plain_sheet(css_text)
        if plain is not None:
            for simple, decls in plain:
                self._add_rule([None] * len(simple), simple, decls)
            self._simple.clear()
            return
        import cssselect2
        import tinycss2

        rules = tinycss2.parse_stylesheet(css_text, skip_whitespace=True, skip_comments=True)
        namespaces = {}     # this sheet's @namespace prefixes (CSS Namespaces 3 §2)
        head = True         # @namespace is valid only before any rule but @charset/@import
        for rule in rules:
            # other at-rules, @import included, are skipped: resvg does not follow @import
            if rule.type == "at-rule" and rule.lower_at_keyword in ("charset", "import"):
                continue
            if rule.type == "at-rule" and rule.lower_at_keyword == "namespace":
                if head:
                    _namespace_rule(rule, namespaces)
                continue
            head = False
            if rule.type != "qualified-rule":
                continue
            if _most_combinators(rule.prelude) > MAX_COMBINATORS:
                continue
            parts = _split_selectors(rule.prelude)
            # a list of simple selectors only (without a default namespace, which a type
            # selector tests too) is valid as it is: cssselect2 need not compile it
            simple = None if None in namespaces else [_simple_tokens(p) for p in parts]
            if simple is None or None in simple:
                prelude, names = rule.prelude, namespaces
                if "link" in tinycss2.serialize(prelude).lower():
                    prelude = _hyperlinks(prelude)
                    if prelude is not rule.prelude:
                        names = {**namespaces, _XLINK_PREFIX: XLINK_NS}
                try:
                    selectors = cssselect2.compile_selector_list(prelude, names)
                except Exception:   # cssselect2 raises its own SelectorError and others
                    continue
                if len(parts) != len(selectors):
                    parts = [()] * len(selectors)
                simple = [_simple_selector(tokens, sel) for sel, tokens in zip(selectors, parts)]
            else:
                selectors = [None] * len(simple)
            self._add_rule(selectors, simple, _declarations(rule.content))
        self._simple.clear()

    def _add_rule(self, selectors, simple, decls):
        """A rule's selectors (cssselect2's compiled ones, None where not compiled), what
        _simple_selector makes of them, and its declarations."""
        for sel, kind_name in zip(selectors, simple):
            if sel is not None and sel.pseudo_element:
                continue
            payload = (self.count, decls)
            self.count += 1
            if kind_name is None:
                self.matcher.add_selector(sel, payload)
                self.complex += 1
                continue
            self.matcher.order += 1     # as add_selector numbers it
            kind, name = kind_name
            entry = (_key_specificity(kind, name), self.matcher.order, None, payload)
            if kind == "*":
                self.universal.append(entry)
            elif kind == "compound":
                tag, ident, classes = name
                if tag is not None:
                    self.key_tags.add(tag)
                if ident is not None:
                    self.key_ids.add(ident)
                    self.compound_by_id.setdefault(ident, []).append(
                        (tag, frozenset(classes), entry))
                else:
                    self.compound_by_class.setdefault(classes[0], []).append(
                        (tag, frozenset(classes[1:]), entry))
            else:
                if kind == "tag":
                    self.key_tags.add(name)
                elif kind == "id":
                    self.key_ids.add(name)
                index = self.by_class if kind == "class" else \
                    self.by_id if kind == "id" else self.by_tag
                index.setdefault(name, []).append(entry)

    def simple_matches(self, tag, attrs, charge):
        """The indexed selectors' matches for an element of local name ``tag`` and
        attributes ``attrs`` (id and class without a namespace), as cssselect2's
        Matcher.match gives them (specificity, order, pseudo-element, payload), unsorted
        (_in_cascade_order sorts); an empty tuple for none. Elements alike in tag, id and class share one answer;
        ``charge(n)`` is told of the n selectors gathered for each new one."""
        ident = attrs.get("id")
        if ident is not None and ident not in self.key_ids:
            ident = None
        classes = attrs.get("class")
        if tag not in self.key_tags:
            tag = None
        key = (tag, ident, classes)
        found = self._simple.get(key)
        if found is None:
            found = list(self.universal)
            tested = 0      # compound selectors tested
            names = set(_CLASS_NAMES(classes)) if classes else ()
            if tag is not None:
                found += self.by_tag.get(tag, ())
            if ident is not None:
                found += self.by_id.get(ident, ())
                for ctag, cclasses, entry in self.compound_by_id.get(ident, ()):
                    tested += 1
                    if (ctag is None or ctag == tag) and cclasses.issubset(names):
                        found.append(entry)
            if names:
                by_class = self.by_class
                compound = self.compound_by_class
                for name in names:
                    got = by_class.get(name)
                    if got is not None:
                        found += got
                    got = compound.get(name)
                    if got is not None:
                        for ctag, cclasses, entry in got:
                            tested += 1
                            if (ctag is None or ctag == tag) and cclasses.issubset(names):
                                found.append(entry)
            charge(len(found) + tested + 1)
            found = self._simple[key] = tuple(found)
        return found


class Document:
    """A parsed SVG document: the Element tree, an id map and the base folder for resources."""

    def __init__(self, root: Element, ids: dict | None, base_dir=None):
        self.root = root
        self._ids = ids             # None: made from the tree when first asked for
        self.base_dir = base_dir
        self.languages = ("en",)   # the user's, for systemLanguage
        self._doc_styles = {}
        self.paths = []             # the <path> elements in document order
        self.size = 0               # how many elements the tree has
        self.has_use = False        # whether any <use> instantiates content
        self.link_containers = []   # pattern, clipPath and mask elements in document order
        self.detached = []          # SVG elements inside foreign ones: referable, not drawn
        self._detached_ids = None
        self.var_raw = {}           # id(element) -> variables.Pending, where var() is used
        self.var_budget = None      # variables.Budget, in a document with var()

    @property
    def ids(self) -> dict:
        """{id: the first element in document order with it}, made when first asked for:
        map data gives every path an id, and most documents look up none of them."""
        if self._ids is None:
            ids = self._ids = {}
            for el in _descendants(self.root) if self.root is not None else ():
                ident = el.attrs.get("id")
                if ident is not None:
                    ids.setdefault(ident, el)
        return self._ids

    def lookup(self, ref, detached=False):
        """Element for an id, ``#id``, ``url(#id)`` or None. ``detached``: an SVG element
        inside a foreign one may be the answer too (for <use>, which instantiates any element
        of the document, as resvg's and browsers' do; paint servers, clips, masks, markers
        and filters there are not drawn, so not found, as in resvg and browsers)."""
        found = self._lookup(ref)
        if found is None and detached and self.detached and ref is not None:
            if self._detached_ids is None:
                self._detached_ids = {}
                for top in self.detached:
                    for el in _descendants(top):
                        ident = el.attrs.get("id")
                        if ident is not None:
                            self._detached_ids.setdefault(ident, el)
            ref = ref.strip()
            return self._detached_ids.get(ref[1:] if ref.startswith("#") else ref)
        return found

    def _lookup(self, ref):
        if ref is None:
            return None
        ref = ref.strip()
        if ref.startswith("url("):
            ref = ref[4:].rstrip(")").strip().strip("'\"")
        if ref.startswith("#"):
            ref = ref[1:]
        return self.ids.get(ref)

    def release(self):
        """Drop the reference cycles of the element tree (parent and children, elements and
        this document) and of its computed styles, for a document that is done with: its
        memory then goes when the last reference to it does, and the collector's next pass
        (at the end of a render) does not walk tens of thousands of elements. The elements
        keep their attributes and parents; the tree is no longer walkable from here."""
        stack = [self.root] if self.root is not None else []
        while stack:
            el = stack.pop()
            if el.children:
                stack.extend(el.children)
                el.children = ()
        styles = list(self._doc_styles.values())
        while styles:
            style = styles.pop()
            styles.extend(style._children.values())
            style._children = {}
        self.root, self._ids, self.paths, self._doc_styles = None, {}, [], {}
        self.var_raw = {}
        self.detached, self._detached_ids = [], None
        self.link_containers = []

    def document_style(self, el: Element) -> Style:
        """Computed style from the element's document ancestors (for paint servers, clip paths,
        masks, markers and patterns, whose content inherits from where it is defined)."""
        key = id(el)
        style = self._doc_styles.get(key)
        if style is None:
            parent = self.document_style(el.parent) if el.parent is not None else None
            style = Style(el.specified, parent)
            self._doc_styles[key] = style
        return style


#: properties whose values are keywords, numbers and lengths only: CSS reads keywords
#: (and units) ASCII case-insensitively (CSS Values 4 §2.1), so their values are lower-cased
#: here, once for attributes and declarations alike (``font-style="ITALIC"``,
#: ``text-anchor="Middle"``; resvg 0.44 and 0.48.1 take such values as invalid)
KEYWORD_PROPERTIES = {
    "alignment-baseline", "baseline-shift", "direction", "dominant-baseline", "font-kerning",
    "font-optical-sizing", "font-size", "font-size-adjust", "font-stretch", "font-style",
    "font-synthesis",
    "font-variant", "font-variant-caps", "font-variant-east-asian", "font-variant-ligatures",
    "font-variant-numeric", "font-variant-position", "font-weight",
    "glyph-orientation-horizontal", "glyph-orientation-vertical", "letter-spacing",
    "text-anchor", "text-decoration", "text-orientation", "text-rendering", "text-transform",
    "unicode-bidi", "white-space-collapse", "word-spacing", "writing-mode",
    # painting, compositing and display properties of lower-case keywords only
    # (``visibility="HIDDEN"``, ``display: None``, ``fill-rule="EvenOdd"``: Chromium 150 reads
    # them as CSS does, resvg 0.48.1 as invalid). The camel-case keywords of the rendering
    # hints and colour spaces (crispEdges, linearRGB) stay as written: their readers compare
    # them exactly, as resvg does.
    "clip-rule", "display", "fill-rule", "isolation", "mask-mode", "mask-type", "mix-blend-mode",
    "overflow", "paint-order", "stroke-linecap", "stroke-linejoin", "transform-box",
    "vector-effect", "visibility",
}
_CSS_WIDE_INITIALS = frozenset("iIuUrR")   # of inherit, initial, unset, revert: any property
#: properties whose ``initial`` is replaced by their initial value in the cascade (text
#: properties read ``initial`` themselves: the font family's is the reader's option)
_PAINT_INITIAL = frozenset(INITIAL) - {"font-size", "font-family"}
_ASCII_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")


def _ascii_lower(value):
    return value.lower() if value.isascii() else value.translate(_ASCII_LOWER)


def _specified(spec, found, style_attr, warnings, custom=False):
    """An element's specified style: its presentation attributes ``spec`` (updated in place)
    under the CSS rules that match it (``found``: cssselect2 matches), its ``style``
    attribute, then the ``!important`` declarations. Unsupported values go to ``warnings``.
    ``custom``: the document has var(); custom properties are then declarations too, and
    values holding var() stay variables.Unresolved, for variables.substitute_document."""
    if custom:
        return _specified_with_variables(spec, found, style_attr, warnings)
    geometry = None
    if found or style_attr:
        important = {}
        for name, value, imp in _in_cascade_order(found, style_attr):
            if name not in PROPERTIES:
                if name in GEOMETRY_PROPERTIES:
                    geometry = (geometry or []) + [(name, value, imp)]
                continue
            for pname, pval in _expand_shorthand(name, value):
                (important if imp else spec)[pname] = pval
        spec.update(important)
    for name, value in spec.items():
        if "/*" in value and name != "transform":   # the transform attribute has SVG's grammar
            spec[name] = value = _without_comments(value)
        if name in KEYWORD_PROPERTIES or value[:1] in _CSS_WIDE_INITIALS:
            low = _ascii_lower(value)
            if name in KEYWORD_PROPERTIES or low in _NO_WARNING:
                spec[name] = value = low
            if value == "unset":     # CSS Cascade 4 §7.3: inherit if inherited, else initial
                spec[name] = value = "inherit" if name in INHERITED else "initial"
            if value == "initial" and name in _PAINT_INITIAL:   # §7.1
                spec[name] = value = INITIAL[name]
        if name == "color" and value.strip() == "currentColor":
            # CSS Color 4 §4.4: currentColor as the color property's own value is inherit
            # (resvg 0.48.1 takes it as invalid: black)
            spec[name] = value = "inherit"
        if name in UNSUPPORTED_PROPERTIES:
            value = value.strip().lower()
            if value not in UNSUPPORTED_PROPERTIES[name] and value not in _NO_WARNING:
                warnings.append(f"{name}: {value[:40]} is not supported: ignored")
    if geometry:
        _keep_geometry(spec, geometry)
    return spec


def _keep_geometry(spec, declared):
    """Leave the geometry declarations ``declared`` ((name, value, important)... in cascade
    order) in ``spec`` for apply_geometry_properties: the normal ones, then the important
    ones (CSS Cascade 4 §6.1), each to override the one before where it is valid."""
    spec[GEOMETRY_KEY] = tuple((n, v) for n, v, imp in declared if not imp) + tuple(
        (n, v) for n, v, imp in declared if imp)


def _in_cascade_order(found, style_attr):
    """The declarations (name, value, important) of the CSS rules that match an element
    (``found``: cssselect2 matches), by specificity and order, then of its ``style``
    attribute."""
    if not found:
        return _style_attribute(style_attr) if style_attr else ()
    declared = [d for m in sorted(found, key=lambda m: (m[0], m[1])) for d in m[3][1]]
    if style_attr:
        declared += _style_attribute(style_attr)
    return declared


def _specified_with_variables(spec, found, style_attr, warnings):
    """_specified for a document with var(): custom properties (``--*``) take part in the
    cascade like the others (CSS Variables 1 §2), and values holding var() (presentation
    attributes' too: SVG 2 parses them as the property's CSS value, and Chromium 150
    substitutes them) are set aside, unchecked, as variables.Unresolved; a malformed var()
    makes its declaration invalid, and it is ignored (§3)."""
    from .variables import VAR, unresolved

    for name, value in list(spec.items()):
        if VAR.search(value):
            value = unresolved(name, value)
            if value is None:
                del spec[name]
            else:
                spec[name] = value
    important = {}
    geometry = None
    for name, value, imp in _in_cascade_order(found, style_attr):
        if name[:2] == "--":
            if VAR.search(value) and unresolved(name, value) is None:
                continue
            (important if imp else spec)[name] = value
            continue
        if name not in PROPERTIES:
            if name in GEOMETRY_PROPERTIES and not VAR.search(value):
                # (var() in a geometry property is not substituted: dropped, as invalid)
                geometry = (geometry or []) + [(name, value, imp)]
            continue
        if VAR.search(value):
            value = unresolved(name, value)
            if value is None:
                continue
        for pname, pval in _expand_shorthand(name, value):
            (important if imp else spec)[pname] = pval
    spec.update(important)
    pending = {name: value for name, value in spec.items()
               if name[:2] == "--" or value.__class__ is not str}
    if pending:
        for name in pending:
            del spec[name]
    spec = _specified(spec, None, None, warnings)
    spec.update(pending)
    if geometry:
        _keep_geometry(spec, geometry)
    return spec


def load_document(data: bytes, base_dir=None, load_text=None, stylesheet=None,
                  root_defaults=None, languages=("en",)) -> Document:
    """Parse SVG bytes into a Document.

    ``stylesheet`` is CSS applied before the document's own ``<style>`` sheets (resvg's
    ``--stylesheet``); ``root_defaults`` are property values the root element gets where it
    specifies none (``--font-size``, ``--shape-rendering``...: inherited, so they act as new
    initial values); ``languages`` are the user's languages for ``systemLanguage``.
    ``load_text`` is accepted for existing callers and unused: CSS ``@import`` is not followed,
    as in resvg."""
    data = _prepare(data)
    doc = Document(None, None, base_dir)
    doc.languages = tuple(x.strip().lower() for x in languages)
    # Only a document with CSS needs the ElementTree tree (cssselect2 matches on it).
    # (the substring test first: a regular expression search of a map costs milliseconds)
    has_css = b"style" in data and _STYLE_ELEMENT.search(data) is not None
    # custom properties matter only where var() uses them (b"ar(" first: see has_css)
    custom = (b"ar(" in data and _VAR_FUNCTION.search(data) is not None) or (
        bool(stylesheet) and "ar(" in stylesheet)
    css = bool(stylesheet) or has_css
    # A document with CSS is read first without the mirror, its elements' styles deferred:
    # when all its selectors are indexed ones (exporters' sheets) the cascade needs no more.
    reader = _TreeReader(doc, mirror=False, custom=custom, deferred=css)
    doc.root = reader.read(data)
    if reader.bad_root:
        raise SvgError("the root element is not <svg>")
    if css:
        sheets = _tree_stylesheets(reader.styles, stylesheet) if reader.error is None else None
        if sheets is None or sheets.complex:
            # cssselect2 matches on ElementTree's tree: the document is read again, with it
            # (past a limit, the sheets are read from it as before: the error is raised next);
            # the first tree's reference cycles are broken, so it goes now, not at the
            # collector's next pass (paused while rendering)
            doc.release()
            doc = Document(None, None, base_dir)
            doc.languages = tuple(x.strip().lower() for x in languages)
            reader = _TreeReader(doc, mirror=True, custom=custom)
            doc.root = reader.read(data)
            if sheets is None:
                sheets = _mirror_stylesheets(reader.mirror, stylesheet)
        _cascade(reader, sheets)
    if reader.geometry and doc.root is not None:
        apply_geometry_properties(doc)
    if custom and doc.root is not None and reader.error is None:
        from .variables import substitute_document
        substitute_document(doc, reader.warnings)
    for message in reader.warnings:
        warn(message)
    if reader.error is not None:
        raise SvgError(reader.error)
    for name, value in (root_defaults or {}).items():
        doc.root.specified.setdefault(name, value)
    _break_reference_cycles(doc)
    return doc


_VAR_FUNCTION = re.compile(rb"(?i)var\(")


def apply_geometry_properties(doc):
    """SVG 2's geometry properties given in CSS (GEOMETRY_APPLIES): the last valid one of
    each element's declarations (_specified's GEOMETRY_KEY, which this takes out of every
    element's specified style) replaces the attribute. A document that says it is SVG 1.1
    (``version="1.1"`` on its root) keeps SVG 1.1's rule, where these are attributes only
    and such a declaration names no property: ignored. An invalid value (not a length or
    percentage, a negative size or radius, ``auto`` where the property has none, var()) is
    dropped, so the declaration before it or the attribute stays (CSS Syntax 3 §8)."""
    svg2 = (doc.root.attrs.get("version") or "").strip() != "1.1"
    computed = {}       # id(element) -> {name: its value from CSS}, for children's inherit
    for top in (doc.root, *doc.detached):
        for el in _descendants(top):
            spec = el.specified
            declared = spec.pop(GEOMETRY_KEY, None) if spec else None
            if declared is None or not svg2:
                continue
            own = {}
            for name, value in declared:
                value = _geometry_value(name, value, el, computed)
                if value is not None:
                    own[name] = value
            computed[id(el)] = own
            applies = GEOMETRY_APPLIES.get(el.tag)
            if applies is not None:
                for name, value in own.items():
                    if name in applies:
                        el.attrs[name] = value


def _geometry_value(name, value, el, computed):
    """A geometry declaration's value as its attribute would say it, None when invalid."""
    value = _without_comments(value).strip() if "/*" in value else value.strip()
    low = _ascii_lower(value)
    if low in ("initial", "unset", "revert", "revert-layer"):
        return GEOMETRY_INITIAL[name]          # none of them inherits
    if low == "inherit":
        parent = el.parent
        if parent is None:
            return GEOMETRY_INITIAL[name]
        got = computed.get(id(parent), {}).get(name)
        if got is None:
            applies = GEOMETRY_APPLIES.get(parent.tag)
            got = parent.attrs.get(name) if applies is not None and name in applies else None
        return GEOMETRY_INITIAL[name] if got is None else got
    if name == "d":
        if low == "none":
            return ""
        m = _PATH_FUNCTION.match(value)
        return m.group(2) if m else None
    if low == "auto":
        return "auto" if name in ("width", "height", "rx", "ry") else None
    if low.startswith("calc("):
        return value
    parsed = split_length(value)
    if parsed is None:
        return None
    if parsed[0] < 0 and name in ("width", "height", "r", "rx", "ry"):
        return None         # negative sizes and radii are invalid (SVG 2 §"Geometry Properties")
    return value


#: CSS's path() with its string (CSS Shapes 1; SVG 2's ``d`` property takes it or none)
_PATH_FUNCTION = re.compile(r"""(?is)path\(\s*(["'])(.*?)\1\s*\)$""")
_URL_ID = re.compile(r"""^\s*url\(\s*["']?#([^"')\s]+)["']?\s*\)""")


def _descendants(el):
    """``el`` and every element below it, in document order (without recursion)."""
    stack = [el]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(reversed(node.children))


#: elements whose content may reference them back, with the properties that can: usvg's
#: fix_recursive_links (svgtree) breaks the cycles these make, before anything is drawn
_LINKS = (("pattern", "fill"), ("pattern", "stroke"), ("clipPath", "clip-path"), ("mask", "mask"))
_LINK_CONTAINERS = frozenset(tag for tag, _ in _LINKS)


def _break_reference_cycles(doc):
    """A fill, stroke, clip-path or mask that would make a pattern, clip path or mask contain
    itself becomes ``none``, chosen as usvg chooses it (SVG leaves a circular reference an
    error without saying what is drawn): for each such element P in document order, each
    element E in P (P itself too) whose property references Q: if Q is P, E's reference goes;
    otherwise every element in Q (Q too) referencing P loses that reference. So of
    two clip paths referencing each other, the earlier one in the document keeps its clip.
    Fills first, then strokes. Only elements references reach (the first with their id)
    are looked at, and the id map is made only once a reference is found. The build's own
    guards (paint.pattern, masking._target) still stop any cycle this leaves, e.g. through
    ``use`` or inherited paints."""
    if not doc.link_containers:
        return

    def link(el, name):
        value = el.specified.get(name) if el.specified else None
        m = _URL_ID.match(value) if value else None
        return m.group(1) if m else None

    linking = _linking_elements(doc.link_containers, link)
    for tag, name in _LINKS:
        for container in doc.link_containers:
            if container.tag != tag:
                continue
            cid = container.attrs.get("id")
            reached = None
            for node in linking[id(container)]:
                target = link(node, name)
                if target is None:
                    continue
                if reached is None:
                    reached = cid is not None and doc.ids.get(cid) is container
                if not reached:
                    break
                if target == cid:
                    node.specified[name] = "none"
                    continue
                # every element in Q referencing P loses the reference (``node`` is not one:
                # its reference is Q's), in one walk over Q; taking the first and walking Q
                # again for the next was quadratic (15,000 such rects: 100 s)
                linked = doc.ids.get(target)
                if linked is not None:
                    inside = linking.get(id(linked))
                    for n in _descendants(linked) if inside is None else inside:
                        if link(n, name) == cid:
                            n.specified[name] = "none"


def _linking_elements(containers, link):
    """{id(container): the elements in it (it too), in document order, that reference
    something by fill, stroke, clip-path or mask}: walked innermost container first, each
    taking a nested one's list instead of walking its content again, so each element is
    visited once. (Walking every container whole was quadratic in their nesting: 255,000
    patterns nested 300 deep, none referencing anything, took 110 s.) References only go:
    the lists hold every element that may still have one."""
    names = [name for _, name in _LINKS]
    linking = {}
    for container in reversed(containers):
        out = []
        stack = [container]
        while stack:
            node = stack.pop()
            nested = linking.get(id(node)) if node is not container else None
            if nested is not None:
                out.extend(nested)
                continue
            if node.specified and any(link(node, name) for name in names):
                out.append(node)
            stack.extend(reversed(node.children))
        linking[id(container)] = out
    return linking


def _media_matches(media):
    """Whether a ``<style>`` element's ``media`` attribute (a media query list, SVG 2 §6.3)
    may match a drawing on the screen: absent or empty, or any of its queries is more than
    a bare media type (features, ``not``: kept, as before) or the type all or screen. A list
    of other bare media types alone (``print``, ``only speech``) matches nothing (Media
    Queries 4 §2.3), as Chromium 150 has it."""
    if media is None or not media.strip():
        return True
    for query in media.lower().split(","):
        words = query.split()
        if words[:1] == ["only"]:
            words = words[1:]
        if len(words) != 1 or not words[0].isalpha() or words[0] in ("all", "screen"):
            return True
    return False


def _style_text(kind, text, sheets, media=None):
    """Add a ``<style>`` element's sheet, of type attribute ``kind``, to ``sheets``. The type
    is a media type, whose type and subtype are case-insensitive (RFC 2045 §5.1; HTML: an
    ASCII case-insensitive match for text/css): ``TEXT/CSS`` is CSS too. A sheet whose
    ``media`` is only other media types (``print``) does not apply (_media_matches)."""
    kind = (kind or "text/css").strip().lower()
    if kind in ("", "text/css") and _media_matches(media):
        sheets.add(text)


def _mirror_stylesheets(xml_root, stylesheet):
    """The Stylesheets of a document read with the ElementTree mirror: ``stylesheet`` (the
    user's), then its ``<style>`` elements'."""
    default_ns = xml_root.tag[1:].partition("}")[0] if xml_root.tag[0] == "{" else ""
    sheets = Stylesheets()
    if stylesheet:
        sheets.add(stylesheet)
    # <style> elements anywhere apply to the whole document (even those after their use).
    for node in xml_root.iter():
        nns, _, ntag = node.tag[1:].partition("}") if node.tag[0] == "{" else ("", "", node.tag)
        if ntag == "style" and (nns == default_ns or nns == SVG_NS):
            # its child text content (HTML/CSSOM), not its descendants' text: elements nested
            # in <style> are not CSS, and thousands of nested <style>s would otherwise read
            # the same text over and over (quadratic in memory)
            _style_text(node.get("type"), (node.text or "") + "".join(c.tail or "" for c in node),
                        sheets, node.get("media"))
    return sheets


def _tree_stylesheets(styles, stylesheet):
    """The same from the Element tree of a document read without the mirror (and within
    its limits): ``styles``, its <style> Elements in document order (those the reader
    made, detached ones too, are the mirror's <style> elements of the root's namespace or
    SVG's), each with its character data as the mirror's (the text after an element of
    another namespace in it is in its text or its last child's tail)."""
    sheets = Stylesheets()
    if stylesheet:
        sheets.add(stylesheet)
    for el in styles:
        _style_text(el.attrs.get("type"), el.text + "".join(c.tail for c in el.children),
                    sheets, el.attrs.get("media"))
    return sheets


def _cascade(reader, sheets):
    """The specified styles of a document with CSS (``sheets``): the indexed selectors
    looked up per element, the others matched by cssselect2 on the ElementTree mirror of the
    tree (``reader.mirror``, there when ``sheets.complex``)."""
    xml_root = reader.mirror
    matches = {}
    wrapper, matcher, charge = _counted_matching(sheets.matcher)
    if sheets.complex:
        # cssselect2 walks the ElementTree mirror for the selectors not indexed
        wrapper = wrapper.from_xml_root(xml_root)
        for w in wrapper.iter_subtree():
            found = matcher.match(w)
            if found:
                matches[id(w.etree_element)] = found
    simple = sheets.simple_matches if sheets.count > sheets.complex else None
    warnings = reader.warnings
    custom = reader.custom
    if simple is not None and not sheets.complex and not custom:
        if _indexed_cascade(reader.pending, sheets, warnings, charge):
            reader.geometry = True
        return
    # the specified style of elements alike in their matches, presentation attributes and
    # style attribute: made once, copied for each (an element's dict is its own: the
    # cascade's later steps and the text module change it), with its warnings repeated
    made = {}
    for el, node, given, style_attr in reader.pending:
        found = simple(el.tag, el.attrs, charge) if simple is not None else ()
        more = matches.get(id(node)) if matches else None
        if more:
            found = (*found, *more)
        if custom or more:
            if found:
                charge(len(found))
            el.specified = _specified(_given_dict(given), found, style_attr, warnings, custom)
            if GEOMETRY_KEY in el.specified:
                reader.geometry = True
            continue
        key = (id(found), given, style_attr)
        got = made.get(key)
        if got is None:
            if found:
                charge(len(found))      # the declarations are read once per key
            before = len(warnings)
            # the first element's dict stands for the others: nothing changes it in this loop
            el.specified = _specified(_given_dict(given), found, style_attr, warnings)
            made[key] = (el.specified, warnings[before:])
            if GEOMETRY_KEY in el.specified:
                reader.geometry = True
        else:
            el.specified = dict(got[0])
            warnings.extend(got[1])


def _indexed_cascade(pending, sheets, warnings, charge):
    """_cascade's loop where all selectors are indexed ones and there is no var(): the
    specified style made once per distinct (tag and id where the index has them, class
    attribute, presentation attributes, style attribute) and copied for each element alike
    (with its warnings repeated), the index asked only for a new one. The matches (and
    with them the steps charged) are those simple_matches gives per (tag, id, class).
    True when a style has geometry declarations (GEOMETRY_KEY)."""
    geometry = False
    by_tag, by_id = sheets.key_tags, sheets.key_ids
    simple = sheets.simple_matches
    made = {}
    for el, _, given, style_attr in pending:
        attrs = el.attrs
        tag = el.tag
        ident = attrs.get("id")
        key = (tag if tag in by_tag else None, ident if ident in by_id else None,
               attrs.get("class"), given, style_attr)
        got = made.get(key)
        if got is not None:
            el.specified = dict(got[0])
            if got[1]:
                warnings.extend(got[1])
            continue
        found = simple(tag, attrs, charge)
        if found:
            charge(len(found))      # the declarations are read once per key
        before = len(warnings)
        # the first element's dict stands for the others: nothing changes it in this loop
        el.specified = _specified(_given_dict(given), found, style_attr, warnings)
        made[key] = (el.specified, warnings[before:])
        if GEOMETRY_KEY in el.specified:
            geometry = True
    return geometry


def _counted_matching(matcher):
    """An ElementWrapper class, a Matcher (sharing ``matcher``'s rules) and a function
    ``charge(steps)`` that count the work of matching against MAX_SELECTOR_STEPS and raise
    SvgError past it. cssselect2 walks
    ancestors and earlier siblings through these attributes; its tuples of earlier siblings
    (one per element, of all its earlier siblings: quadratic memory for a long list of
    siblings) become walks along the previous-sibling links, and its tuples of ancestors one
    per parent. Counting charges whole tuples and lists at once (a walk may stop early): a
    call per step cost half again the matching's time."""
    import cssselect2

    left = [MAX_SELECTOR_STEPS]

    def charge(n):
        left[0] -= n
        if left[0] < 0:
            raise SvgError(f"CSS selectors take more than {MAX_SELECTOR_STEPS} steps to match "
                           f"(vecmsaa.svg.document.MAX_SELECTOR_STEPS)")

    class Siblings(list):
        # `:first-of-type` and its kind scan slices of the siblings
        def __getitem__(self, key):
            got = list.__getitem__(self, key)
            if isinstance(key, slice):
                charge(len(got))
            return got

    def below(el):
        got = el._below
        if got is None:
            got = el._below = (() if el.parent is None else below(el.parent)) + (el,)
            charge(len(got))
        return got

    class Wrapper(cssselect2.ElementWrapper):
        _below = None       # this element's ancestors and itself: its children's ancestors

        @property
        def ancestors(self):
            # one tuple per parent (cssselect2 makes one per element: depth times the
            # elements), its length charged when made and at each walk (`any` over it)
            parent = self.parent
            if parent is None:
                return ()
            got = parent._below
            if got is None:
                got = below(parent)
            left[0] -= len(got)     # charge(), inline: this runs once per selector test
            if left[0] < 0:
                charge(0)
            return got

        @property
        def previous_siblings(self):
            el = self.previous
            while el is not None:
                charge(1)
                yield el
                el = el.previous

        @functools.cached_property
        def etree_children(self):
            return Siblings(cssselect2.ElementWrapper.etree_children.func(self))

        @functools.cached_property
        def lang(self):
            # `:lang()`: SVG 2 takes HTML's `lang` attribute on every element, `xml:lang`
            # first where both are set (HTML, "the lang and xml:lang attributes"); cssselect2
            # reads `lang` on HTML elements only
            el = self.etree_element
            value = el.get(_XML_LANG)
            if value is None:
                value = el.get("lang")
            if value is not None:
                return value.strip().lower()
            return "" if self.parent is None else self.parent.lang

        def iter_children(self):
            charge(len(self.etree_children))
            return super().iter_children()

    class Matcher(cssselect2.Matcher):
        @staticmethod
        def add_relevant_selectors(element, selectors, relevant_selectors):
            charge(len(selectors))
            cssselect2.Matcher.add_relevant_selectors(element, selectors, relevant_selectors)

    counted = Matcher()
    counted.__dict__.update(matcher.__dict__)
    return Wrapper, counted, charge
