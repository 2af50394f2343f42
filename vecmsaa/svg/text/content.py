"""The characters of a ``<text>`` element (SVG 1.1 §10 steps 1–3, as resvg does them).

*Collect* the characters with their innermost text content element (``tspan``, ``tref``,
``textPath``, ``a``), collapse white space unless ``xml:space="preserve"``, and apply the
position attributes: ``x``, ``y``, ``dx``, ``dy``, ``rotate`` lists address characters in order
from the element that carries them, inner elements overriding outer ones. A character with an
absolute ``x`` or ``y`` (or the first of a ``textPath``) starts a text chunk (:mod:`.layout`).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..builder import conditions_pass
from ..units import parse_length_list, parse_number_list

TEXT_CONTENT = {"tspan", "tref", "textPath", "a"}
#: tref may take the characters of SVG elements only
SVG_ELEMENTS = {"svg", "g", "defs", "symbol", "use", "switch", "a", "rect", "circle", "ellipse",
                "line", "polyline", "polygon", "path", "text", "tspan", "tref", "textPath",
                "image", "title", "desc", "metadata", "style", "clipPath", "mask", "marker",
                "pattern", "linearGradient", "radialGradient", "stop", "filter", "view",
                "foreignObject"}




@dataclass
class Char:
    ch: str
    el: object                 # innermost text content element
    chain: tuple               # elements from <text> to ``el``
    preserve: bool
    x: float | None = None
    y: float | None = None
    dx: float = 0.0
    dy: float = 0.0
    rotate: float = 0.0
    text_path: object = None   # the enclosing <textPath> element
    new_chunk: bool = False
    primary_face: object = None   # its family list's best match, before any fallback


def _space_preserved(el, inherited):
    v = el.get("xml:space", el.get("space"))
    if v == "preserve":
        return True
    if v == "default":
        return False
    return inherited


def content_elements(text_el):
    """<text> and its text content elements, depth first."""
    stack = [text_el]
    while stack:
        el = stack.pop()
        yield el
        stack.extend(c for c in el.children if c.tag in TEXT_CONTENT)


def collect_chars(text_el, ctx, styles):
    """The text nodes of a <text> element, in document order, as
    [(characters, depth, preserve)]: depth 0 for <text>'s own text, +1 per nested element."""
    nodes = []

    def add(string, el, chain, depth, preserve, text_path):
        if string:
            nodes.append(([Char(ch, el, chain, preserve, text_path=text_path)
                           for ch in string], depth, preserve))

    def walk(el, chain, style, preserve, text_path, depth):
        styles[id(el)] = style
        add(el.text, el, chain, depth, preserve, text_path)
        for child in el.children:
            if child.tag in TEXT_CONTENT and conditions_pass(child):
                cstyle = style.child(child)
                if cstyle.get("display").strip() != "none":
                    cpres = _space_preserved(child, preserve)
                    tp = text_path
                    if child.tag == "textPath":
                        # textPath must be a direct child of <text> (as in resvg)
                        if text_path is None and el is text_el:
                            tp = child
                            walk(child, chain + (child,), cstyle, cpres, tp, depth + 1)
                    elif child.tag == "tref":
                        styles[id(child)] = cstyle
                        target = href_target(child, detached=True)
                        if target is not None and target.tag in SVG_ELEMENTS:
                            add(_all_text(target), child, chain + (child,), depth + 1, cpres,
                                tp)
                    else:
                        walk(child, chain + (child,), cstyle, cpres, tp, depth + 1)
            add(child.tail, el, chain, depth, preserve, text_path)

    preserve = False
    for el in [text_el] + list(text_el.ancestors()):
        if el.get("xml:space", el.get("space")) is not None:
            preserve = _space_preserved(el, False)
            break
    walk(text_el, (text_el,), ctx.style, preserve, None, 0)
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
    """x/y/dx/dy/rotate lists, outer elements first so inner ones override."""
    order = []

    def walk(el):
        order.append(el)
        for c in el.children:
            if c.tag in TEXT_CONTENT:
                walk(c)
    walk(text_el)
    by_el = {}
    for i, c in enumerate(chars):
        for e in c.chain:
            by_el.setdefault(id(e), []).append(i)
    for el in order:
        idx = by_el.get(id(el))
        if not idx:
            continue
        style = styles.get(id(el), ctx.style)
        if el.tag != "textPath":
            # a list's lengths before the first that does not parse, as resvg reads it
            for name, axis in (("x", "x"), ("y", "y"), ("dx", "x"), ("dy", "y")):
                for k, (v, unit) in zip(idx, parse_length_list(el.get(name))):
                    setattr(chars[k], name, ctx.length(f"{v!r}{unit}", axis, style))
        # a list with anything but numbers in it (``10,,20``, ``10 x``) is invalid, as in resvg
        rot = parse_number_list(el.get("rotate") or "") or ()
        if rot:
            for j, k in enumerate(idx):
                chars[k].rotate = rot[min(j, len(rot) - 1)]

