"""The characters of a ``<text>`` element (SVG 1.1 §10 steps 1–3, as resvg does them).

*Collect* the characters with their innermost text content element (``tspan``, ``tref``,
``textPath``, ``a``), collapse white space unless ``xml:space="preserve"`` or CSS
``white-space`` keeps it, and apply the position attributes: ``x``, ``y``, ``dx``, ``dy``,
``rotate`` lists address characters in order from the element that carries them, inner
elements overriding outer ones. A character with an absolute ``x`` or ``y`` (or the first of a
``textPath``) starts a text chunk (:mod:`.layout`).
"""
from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, replace

from ..builder import MAX_TEXT_CHARS, conditions_pass
from ..document import computed_down
from .. import SvgError
from ..units import parse_length_list, parse_number_list

TEXT_CONTENT = {"tspan", "tref", "textPath", "a"}
#: tref may take the characters of SVG elements only
SVG_ELEMENTS = {"svg", "g", "defs", "symbol", "use", "switch", "a", "rect", "circle", "ellipse",
                "line", "polyline", "polygon", "path", "text", "tspan", "tref", "textPath",
                "image", "title", "desc", "metadata", "style", "clipPath", "mask", "marker",
                "pattern", "linearGradient", "radialGradient", "stop", "filter", "view",
                "foreignObject"}


class Span:
    """A text content element (or ``<text>``) as its characters see it: the element, its
    computed style and the span it is in (None for ``<text>``). What an element takes from
    its ancestors up to ``<text>`` (the nearest rotate list, the elements with a textLength,
    the decorations they declare, baseline shifts, alignment-baseline) is computed down the
    spans, each span once (``computed``), and shared by every span below that adds nothing:
    each element keeping the tuple of elements from ``<text>`` to it, looked through by each
    step, made 150,000 one-letter spans under 800 nested ones 3 GB and a minute."""

    __slots__ = ("el", "style", "parent", "memo")

    def __init__(self, el, style, parent):
        self.el = el
        self.style = style
        self.parent = parent
        self.memo = None

    def computed(self, key, own, root=None):
        """``own(span, its parent's value)`` from ``<text>`` down to this span (``root`` above
        ``<text>``), memoised on each span (document.computed_down)."""
        return computed_down(self, key, own, root)


def span_values(chars, key, own):
    """Span.computed(key, own) of each character's span, asked once for each stretch of
    characters of one span (a span's characters follow each other)."""
    out = []
    span = value = None
    for c in chars:
        if c.span is not span:
            span = c.span
            value = span.computed(key, own)
        out.append(value)
    return out


@dataclass(slots=True)
class Char:
    ch: str
    span: Span                 # its innermost text content element
    preserve: bool
    x: float | None = None
    y: float | None = None
    dx: float = 0.0
    dy: float = 0.0
    rotate: float = 0.0
    text_path: object = None   # the enclosing <textPath> element
    new_chunk: bool = False
    primary_face: object = None   # its family list's best match, before any fallback

    @property
    def el(self):
        return self.span.el


#: white-space-collapse (CSS Text 4 §3.1) by whether its spaces are kept. Without line boxes
#: (SVG text has none unless inline-size, not supported) a segment break is a space for every
#: value, as SVG 1.1's xml:space="preserve" makes it and as Chromium 150 draws it: so
#: preserve-breaks (pre-line) collapses like collapse, and preserve-spaces (SVG 2's user agent
#: style sheet maps xml:space="preserve" to it; Chromium 150 has no such value) keeps them
WHITE_SPACE_COLLAPSE = {"collapse": False, "preserve-breaks": False, "preserve": True,
                        "preserve-spaces": True, "break-spaces": True}
#: white-space's keywords for both longhands (CSS Text 4 §3.3)
_WHITE_SPACE_KEYWORDS = {"normal": "collapse", "pre": "preserve", "pre-wrap": "preserve",
                         "pre-line": "preserve-breaks"}


def parse_white_space(value):
    """The white-space-collapse the ``white-space`` shorthand sets, or None when the value is
    invalid: ``normal | pre | pre-wrap | pre-line | <white-space-collapse> || <text-wrap-mode>``
    (CSS Text 4 §3.3, as Chromium 150 reads it: ``nowrap`` is collapse, ``preserve nowrap`` is
    pre; text-wrap-mode only matters for wrapped lines)."""
    words = value.strip().lower().split()
    if len(words) == 1 and words[0] in _WHITE_SPACE_KEYWORDS:
        return _WHITE_SPACE_KEYWORDS[words[0]]
    collapse = [w for w in words if w in WHITE_SPACE_COLLAPSE]
    wrap = [w for w in words if w in ("wrap", "nowrap")]
    if not words or len(collapse) > 1 or len(wrap) > 1 or len(collapse) + len(wrap) != len(words):
        return None
    return collapse[0] if collapse else "collapse"


def white_space_collapse(value, shorthand):
    """The white-space-collapse a ``white-space`` value (``shorthand``) or a
    ``white-space-collapse`` one sets: a keyword of WHITE_SPACE_COLLAPSE or a CSS-wide
    keyword, None when the value is invalid."""
    low = value.strip().lower()
    if low in _CSS_WIDE:
        return low
    if shorthand:
        return parse_white_space(low)
    return low if low in WHITE_SPACE_COLLAPSE else None


_CSS_WIDE = frozenset(("inherit", "initial", "unset", "revert"))


def _space_preserved(el, inherited):
    """Whether an element's white space is kept: its own white-space-collapse (the CSS
    property, or the white-space shorthand's), then its white-space presentation attribute
    (SVG 2 §6.6 lists it; Chromium 150 ignores it), then its own xml:space, then the
    inherited value (SVG 2 §11.7.3: the property set on an element makes xml:space ignored;
    the user agent style sheet's mapping of xml:space is under author declarations and over
    inheritance). ``inherit``/``unset`` take the parent's value, ``initial`` collapses, and
    ``revert`` or an invalid value leave the next source to decide."""
    attribute = el.get("white-space")
    for v in (el.specified.get("white-space-collapse"),
              None if attribute is None else white_space_collapse(attribute, True)):
        if v is None:
            continue
        v = v.strip()
        if v == "initial":
            return False
        if v in ("inherit", "unset"):
            return inherited
        if v in WHITE_SPACE_COLLAPSE:
            return WHITE_SPACE_COLLAPSE[v]
    # a value other than preserve is default, as resvg 0.48.1 and Chromium read it (session
    # 23's three-way audit: xml:space="-" in a preserving element collapses in both)
    v = el.get("xml:space", el.get("space"))
    return inherited if v is None else v == "preserve"


#: collapse_white_space's first step, on a node's string
_TO_SPACE = str.maketrans("\r\n\t", "   ")
_SPACES = re.compile(" {2,}")


def collect_chars(text_el, ctx, styles):
    """The text nodes of a <text> element, in document order, as
    [(characters, depth, preserve)]: depth 0 for <text>'s own text, +1 per nested element.
    Each node's own white space is collapsed (collapse_white_space's first step) before its
    characters are made: a pretty-printed document's indentation would be most of them (a
    fuzzed 14 MB text held 2.3 GB of them). SvgError as soon as the characters that collapsing
    cannot take (all but a node's end spaces) outnumber MAX_TEXT_CHARS."""
    nodes = []
    kept = 0

    def add(string, span, depth, preserve, text_path):
        nonlocal kept
        if string:
            string = string.translate(_TO_SPACE)
            if not preserve:
                string = _SPACES.sub(" ", string)
            # collapsing across nodes takes only spaces at a node's ends
            kept += len(string) - (string[0] == " ") - (len(string) > 1 and string[-1] == " ")
            if kept > MAX_TEXT_CHARS:
                raise SvgError(f"the document's text is longer than {MAX_TEXT_CHARS} characters")
            nodes.append(([Char(ch, span, preserve, text_path=text_path)
                           for ch in string], depth, preserve))

    def walk(span, preserve, text_path, depth):
        el, style = span.el, span.style
        styles[id(el)] = style
        add(el.text, span, depth, preserve, text_path)
        for child in el.children:
            if child.tag in TEXT_CONTENT:
                cstyle = style.child(child)
                if not conditions_pass(child) or cstyle.get("display").strip() == "none":
                    # a span that is not rendered keeps its place as a node without
                    # characters: the text's end spaces are the ends of its first and last
                    # nodes with text, not of the two nodes around it taken as the whole text
                    # (' a<tspan display="none">b</tspan>c ' is "ac", as in CSS and resvg).
                    # Before any text it is left out: standing first, it would keep the
                    # leading space of the text after it, which CSS removes
                    if nodes:
                        nodes.append(([], depth + 1, preserve))
                else:
                    cpres = _space_preserved(child, preserve)
                    tp = text_path
                    if child.tag == "textPath":
                        # textPath must be a direct child of <text> (as in resvg)
                        if text_path is None and el is text_el:
                            tp = child
                            walk(Span(child, cstyle, span), cpres, tp, depth + 1)
                    elif child.tag == "tref":
                        styles[id(child)] = cstyle
                        target = href_target(child, detached=True)
                        if target is not None and target.tag in SVG_ELEMENTS:
                            add(_all_text(target), Span(child, cstyle, span), depth + 1, cpres,
                                tp)
                    else:
                        walk(Span(child, cstyle, span), cpres, tp, depth + 1)
            add(child.tail, span, depth, preserve, text_path)

    preserve = text_el.computed("xml:space", _space_preserved, False)
    walk(Span(text_el, ctx.style, None), preserve, None, 0)
    return nodes


def href_target(el, detached=False):
    """The element an ``href="#id"`` (tref, textPath) points at, or None. ``detached``: an
    element inside a foreign or unknown one may be it too (a tref's characters, as a use's
    content; a textPath's path there is not found, as in resvg)."""
    ref = (el.get("href") or "").strip()
    if not ref.startswith("#") or el.source is None:
        return None
    return el.source.lookup(ref, detached=detached)


def _all_text(el):
    parts = [el.text]
    for c in el.children:
        parts.append(_all_text(c))
        parts.append(c.tail)
    return "".join(parts)


def collapse_white_space(nodes):
    """White space as resvg handles it (it mimics Chrome): in each text node newlines and tabs
    become spaces and, unless ``xml:space="preserve"``, runs of spaces collapse; then between
    neighbouring nodes a node entered one level deeper loses its leading space, and of two
    spaces meeting otherwise the first goes; the text's first leading and last trailing spaces
    go. Returns the characters."""
    texts = []
    for chars, depth, preserve in nodes:
        kept = []
        for c in chars:
            if c.ch in "\r\n\t":
                c.ch = " "
            if not preserve and c.ch == " " and kept and kept[-1].ch == " ":
                continue
            kept.append(c)
        texts.append([kept, depth, preserve])
    if len(texts) == 1:
        chars, _, preserve = texts[0]
        if not preserve:
            if chars and chars[0].ch == " ":
                chars.pop(0)
            if chars and chars[-1].ch == " ":
                chars.pop()
    last_non_empty = None
    n = len(texts) - 1
    for i in range(n):
        first = texts[i]
        second = texts[i + 1]
        depth1 = first[1]
        if not first[0] and last_non_empty is not None:
            # an emptied node stands in for the last node with text, at its own depth (as
            # resvg: '<tspan>a </tspan><tspan><tspan> b' keeps one space, not two)
            first = last_non_empty
        t1, _, pres1 = first
        t2, depth2, pres2 = second
        c1 = t1[0].ch if t1 else None
        c2 = t1[-1].ch if t1 else None
        c3 = t2[0].ch if t2 else None
        c4 = t2[-1].ch if t2 else None
        if depth1 < depth2:
            if c3 == " " and not pres2:
                t2.pop(0)
        elif c2 == " " and c3 == " ":
            if not pres1 and not pres2:
                t1.pop()
            elif pres1 and not pres2:
                t2.pop(0)
        if i == 0 and c1 == " " and not pres1 and t1:
            t1.pop(0)
        elif i == n - 1 and c4 == " " and t2 and not pres2:
            t2.pop()
        if i == n - 1 and c2 == " " and t1 and not t2 and t1[-1].ch == " ":
            t1.pop()
        if any(c.ch != " " for c in t1):
            last_non_empty = first
    return [c for chars, _, _ in texts for c in chars]


# -- position attributes -------------------------------------------------------------------
def apply_positions(text_el, chars, ctx, styles):
    """x/y/dx/dy/rotate lists, outer elements first so inner ones override. An element's
    characters are consecutive, so its x, y, dx and dy lists address them from its first
    one, and each character takes its rotate from the nearest element with a rotate list
    (which gives one to every character inside it): the work is the characters and the
    lists' values, however deep the spans (looking through the elements around each
    character made 800 nested spans with a list each cost each character inside 800 steps)."""
    order = []

    def walk(el):
        order.append(el)
        for c in el.children:
            if c.tag in TEXT_CONTENT:
                walk(c)
    walk(text_el)
    # each element's first and last character: a span's first is where it is first met
    # (with those of its ancestors met there); its last, the latest of its own and of its
    # descendants' (carried up with descendants before ancestors)
    first, last, met = {}, {}, []
    for i, c in enumerate(chars):
        span, new = c.span, []
        last[id(span.el)] = i
        while span is not None and id(span.el) not in first:
            first[id(span.el)] = i
            new.append(span)
            span = span.parent
        met.extend(reversed(new))
    for span in reversed(met):
        if span.parent is not None:
            up = id(span.parent.el)
            last[up] = max(last.get(up, -1), last[id(span.el)])
    for el in order:
        if id(el) not in first or el.tag == "textPath":
            continue
        idx = range(first[id(el)], last[id(el)] + 1)
        style = styles.get(id(el), ctx.style)
        # a list's lengths before the first that does not parse, as resvg reads it
        for name, axis in (("x", "x"), ("y", "y"), ("dx", "x"), ("dy", "y")):
            for k, (v, unit) in zip(idx, parse_length_list(el.get(name))):
                # a number in user units or px is itself (what the length of its text gives):
                # lists of thousands of them skip the text and its parsing
                setattr(chars[k], name, v if unit in _USER_UNITS
                        else ctx.length(f"{v!r}{unit}", axis, style))
    for i, (c, rotating) in enumerate(zip(chars, span_values(chars, "rotate", _rotate_list))):
        if rotating is not None:
            el, rot = rotating
            c.rotate = rot[min(i - first[id(el)], len(rot) - 1)]


#: units of a list's lengths that are user units as they stand (parse_length_list lowers none:
#: "PX" is not a unit there)
_USER_UNITS = frozenset(("", "px"))


def _rotate_list(span, above):
    """(element, its rotate values) of the nearest element at or above a span with a valid
    rotate list; a list with anything but numbers in it (``10,,20``, ``10 x``) is invalid,
    as in resvg."""
    rot = parse_number_list(span.el.get("rotate") or "")
    return (span.el, rot) if rot else above


# -- text-transform (CSS Text 3 §2.1) --------------------------------------------------------
_CASES = {"capitalize", "uppercase", "lowercase"}
#: UAX #29's MidLetter, MidNumLet and ExtendNumLet characters: inside a word
_IN_WORD = frozenset("'.:\u00b7\u2018\u2019\u2024\ufe52\uff07\uff0e\u2027\ufe13\ufe55"
                     "\uff1a_\u203f\u2040\u2054\ufe33\ufe34\ufe4d\ufe4e\ufe4f\uff3f")


def _parse_text_transform(value):
    """none | [capitalize | uppercase | lowercase] || full-width || full-size-kana, as a set
    of keywords (empty for none); None when invalid or a CSS-wide keyword."""
    words = value.split()
    if words == ["none"]:
        return frozenset()
    if not words or len(set(words)) != len(words):
        return None
    if any(w not in _CASES | {"full-width", "full-size-kana"} for w in words):
        return None
    if len(_CASES.intersection(words)) > 1:
        return None
    return frozenset(words)


def text_transform(style):
    """The computed text-transform of an element (inherited; an invalid declaration is
    ignored; the initial value is none)."""
    return style.get_valid("text-transform", _parse_text_transform, frozenset())


_FULL_WIDTH = None


def _full_width(ch):
    """The character's fullwidth form: the character whose compatibility decomposition is
    ``<wide>`` of it (U+FF01-FF5E, U+FFE0-FFE6; the space's is U+3000), else itself."""
    global _FULL_WIDTH
    if _FULL_WIDTH is None:
        table = {}
        for cp in [0x3000] + list(range(0xFF01, 0xFFEF)):
            d = unicodedata.decomposition(chr(cp))
            if d.startswith("<wide> "):
                table[chr(int(d.split()[1], 16))] = chr(cp)
        _FULL_WIDTH = table
    return _FULL_WIDTH.get(ch, ch)


def _full_size_kana(ch):
    """Small kana to their full-size forms (CSS Text 3 appendix: the small letters of the
    hiragana, katakana, halfwidth katakana and small kana extension blocks)."""
    name = unicodedata.name(ch, "")
    if " LETTER SMALL " in name and ("KATAKANA" in name or "HIRAGANA" in name):
        try:
            return unicodedata.lookup(name.replace(" SMALL ", " "))
        except KeyError:
            return ch
    return ch


def _cased(ch):
    return ch != ch.lower() or ch != ch.upper() or unicodedata.category(ch) == "Lt"


def apply_text_transform(chars, styles, default_style):
    """Case and width transforms of each character by its element's text-transform, after
    white space collapsing and after the position lists took their values: SVG 2 addresses
    characters before any text-transform, so a character that maps to several (``ß`` upper
    case is ``SS``) keeps its values on the first and the others follow it. Returns the new
    character list."""
    cache = {}
    for c in chars:
        if id(c.el) not in cache:
            cache[id(c.el)] = text_transform(styles.get(id(c.el), default_style))
    if not any(cache.values()):
        return chars
    out = []
    word_start = True
    for i, c in enumerate(chars):
        tt = cache[id(c.el)]
        ch = c.ch
        new = ch
        if "uppercase" in tt:
            new = ch.upper()
        elif "lowercase" in tt:
            new = ch.lower()
            if ch == "\u03a3":
                # Unicode's Final_Sigma context: after a cased letter, before none
                before = any(_cased(p.ch) for p in chars[max(0, i - 1):i])
                after = i + 1 < len(chars) and _cased(chars[i + 1].ch)
                if before and not after:
                    new = "\u03c2"
        elif "capitalize" in tt and word_start and unicodedata.category(ch)[0] == "L":
            new = ch.title()
        # words as UAX #29 bounds them (CSS Text 3 suggests it): letters, digits and marks,
        # joined by apostrophes, periods, colons and connectors; anything else ends one
        if ch not in _IN_WORD:
            word_start = unicodedata.category(ch)[0] not in "LMN"
        if "full-width" in tt:
            new = "".join(_full_width(x) for x in new)
        if "full-size-kana" in tt:
            new = "".join(_full_size_kana(x) for x in new)
        if new == ch:
            out.append(c)
            continue
        c.ch = new[0]
        out.append(c)
        for extra in new[1:]:
            out.append(replace(c, ch=extra, x=None, y=None, dx=0.0, dy=0.0, new_chunk=False))
    return out
