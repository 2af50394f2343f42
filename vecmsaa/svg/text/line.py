"""The plain line: a ``<text>`` whose characters are one element's in one font, one chunk
(x and y on the first character at most), left to right, with no spacing, rotation,
textLength, decoration, colour glyph or per-character offset after the first — chart ticks,
map labels, lines of a page — laid out as arrays: HarfBuzz's glyph arrays go to one kernel
(:func:`vecmsaa.fonts.line_kernel.line_glyphs`) that places every glyph and measures the
line's em box, and the placed outlines become one path. No Cluster or Glyph objects.

A ``<text>`` holding characters alone (no child element: a label, a tick, a line of a page)
is recognised from the element before any per-character list is made (:func:`simple_text`):
its white space collapsed on the string, its position lists read for the first character,
its one font spec and face (the face of its family list that draws every character), its
baseline shift, then the same arrays. A ``<text>`` of lines of one element each (Inkscape's
``<tspan x=.. y=..>`` lines, a label in a tspan) is laid out line by line so once its
characters are collected and their white space collapsed (:func:`span_lines`).

Everything else, and anything the kernel declines (clusters out of order, non-finite
positions), takes the general route (:func:`.layout.build_text` from the shaping on); so does
a line that reaches past the image when glyphs are culled (``ctx.sampled``), which the
general route culls glyph by glyph. The kernel's arithmetic is the general route's, so both
give the same floats (tests compare them bit for bit).
"""
from __future__ import annotations

import math

from ...fonts.color import has_color_glyphs
from ...fonts.layout import glyph_outlines, placed_outlines
from ...fonts.line_kernel import ANCHORS, line_glyphs
from ...scene.path import Path
from ...scene.transform import IDENTITY, compose, translate
from . import layout as _layout      # (layout imports this module: attributes at call time)
from ..builder import MAX_TEXT_CHARS
from ..units import parse_length_list, parse_number_list
from .content import _SPACES, _TO_SPACE, _USER_UNITS, Span, _space_preserved, text_transform
from .draw import _nonzero, _within, decorated, finish_text, text_decorated
from .font_match import (_draws, _load, document_faces, face_location, font_database,
                         kerning_attribute, needs_no_face)
from .svg_glyphs import has_svg_glyphs

#: whether build_text takes this route where it can (tests turn it off to compare)
ENABLED = True
#: the longest line whose shaping is kept for the document (as layout.MEMO_CHUNK)
MEMO_LINE = 16


def plain_line(element, chars, faces, specs, shifts, styles, ctx, text):
    """The scene nodes of a plain line, or None where the general route must draw it.
    ``chars`` are one chunk's, without textPath, in horizontal writing, with no textLength
    or spacing (build_text has checked those)."""
    first = chars[0]
    face, spec, span = faces[0], specs[0], first.span
    n = len(chars)
    if (face is None or ctx.geometry_only or faces.count(face) != n or specs.count(spec) != n
            or shifts.count(shifts[0]) != n
            or any(c.span is not span or c.rotate or c.dx or c.dy for c in chars[1:])
            or first.rotate or not _plain_face(face) or decorated(element, span)
            or not _one_run(text)):
        return None
    placed = _place(face, spec, faces, text, first.x, first.y, first.dx, first.dy, shifts[0],
                    styles[id(span.el)], ctx)
    return None if placed is None else _draw(placed, styles[id(span.el)], ctx)


def simple_text(element, ctx):
    """The scene nodes of a ``<text>`` whose content is characters alone (no child element)
    that make a plain line, or None where build_text's per-character route must draw it
    (that route decides everything this declines, so nothing here has an effect before it
    is sure: no characters counted, no warning).

    The steps are the per-character route's on one element: white space (content.collect_chars
    and collapse_white_space on a single text node: newlines and tabs to spaces, runs of spaces
    collapsed and the ends' spaces dropped unless preserved), the position lists (the first
    value of x, y, dx and dy; a second value that applies makes another chunk or offset,
    which is not a plain line; rotate only where all the values that apply are zero),
    text-transform (none), the element's font spec and the face its family list finds
    (assign_faces: where that face draws every character that needs a face, it is every
    character's), the baseline shift (baseline_offset of the element): those that follow
    from the element's computed style once per style (_line_style)."""
    string = element.text
    if element.children or not string or len(string) > MAX_TEXT_CHARS:
        return None
    style = ctx.style
    if ctx.geometry_only:
        return None
    string = string.translate(_TO_SPACE)
    if not element.computed("xml:space", _space_preserved, False):
        string = _SPACES.sub(" ", string)
        if string[:1] == " ":
            string = string[1:]
        if string[-1:] == " ":
            string = string[:-1]
        if not string:
            return None
    n = len(string)
    get = element.get
    if get("textLength") is not None:
        return None
    firsts = _first_positions(element, style, ctx, n)
    if firsts is None or _rotates(element, n):
        return None
    firsts = [d if v is None else v for v, (_, _, d) in zip(firsts, _POSITIONS)]
    got = _line_style(element, style, ctx)
    if got is None:
        return None
    spec, face, shift = got
    if not _draws_all(face, string, ctx) or not _one_run(string) or text_decorated(element):
        return None
    x, y, dx, dy = firsts
    placed = _place(face, spec, None, string, x, y, dx, dy, shift, style, ctx)
    if placed is None:
        return None
    ctx.count_characters(n)
    return _draw(placed, style, ctx)


_VERTICAL = frozenset(("tb", "tb-rl", "vertical-rl", "vertical-lr"))
#: the position attributes simple_text reads: (name, axis, value when absent)
_POSITIONS = (("x", "x", None), ("y", "y", None), ("dx", "x", 0.0), ("dy", "y", 0.0))


def span_lines(element, chars, styles, ctx):
    """The scene nodes of a ``<text>`` with child elements whose characters are lines of one
    element each, or None where the general route must draw it: the first line where the
    text starts (the text's own characters or a ``<tspan>``'s), every other a ``<tspan>``
    child with an x and a y of its own, so a chunk of its own (Inkscape's lines,
    ``sodipodi:role="line"``; a label or a title in a tspan). ``chars`` are build_text's
    after white space (read, not changed: the general route goes on with them where this
    declines); ``styles`` collect_chars'. Each line is laid out as simple_text lays out a
    ``<text>`` of its characters in its element's style and position values (the tspan's
    first, else the text's for the first line), and the lines' fills, in order, share the
    object bounding box of them all, as draw_clusters draws the runs of one element each."""
    n = len(chars)
    if ctx.geometry_only or (ctx.style.get("writing-mode") or "lr").strip() in _VERTICAL \
            or element.get("textLength") is not None or _rotates(element, n) \
            or any(child.get("textLength") is not None for child in element.children):
        return None
    outer = _first_positions(element, ctx.style, ctx, n)
    if outer is None:
        return None
    # the lines: where each element's characters start (a span's follow each other)
    starts = [i for i, (a, b) in enumerate(zip(chars, chars[1:]), 1) if a.span is not b.span]
    lines = []                          # (decided before any is shaped)
    for a, b in zip([0] + starts, starts + [n]):
        span = chars[a].span
        el = span.el
        if chars[a].text_path is not None:
            return None
        style = styles[id(el)]
        text = "".join(c.ch for c in chars[a:b])
        if el is element:
            got = _line_style(el, style, ctx)
            if a:
                # the text's own characters after a line: only spaces in the line's font
                # (a pretty-printed document's line breaks), which the line takes: the
                # general route shapes and places them with its chunk, and their run draws
                # nothing (the spaces' glyphs must be blank: checked once placed)
                line = lines[-1]
                if text.strip(" ") or got is None or got[0] is not line[1] \
                        or got[1] is not line[0] or got[2] != line[4] \
                        or decorated(element, span):
                    return None
                line[2] += text
                continue
            firsts = outer
        else:
            if el.tag != "tspan" or span.parent.el is not element or _rotates(el, b - a):
                return None
            firsts = _first_positions(el, style, ctx, b - a)
            if firsts is None or (a and firsts[0] is None):
                return None
            if not a:                   # (the text's values where the tspan has none)
                firsts = [o if v is None else v for v, o in zip(firsts, outer)]
            got = _line_style(el, style, ctx, span)
        if got is None:
            return None
        spec, face, shift = got
        if (not _draws_all(face, text, ctx) or not _one_run(text)
                or decorated(element, span)):
            return None
        lines.append([face, spec, text, firsts, shift, style, b - a])
    placed_lines = []
    y_end = 0.0                         # (where the line before ends: a line of x alone)
    for face, spec, text, (x, y, dx, dy), shift, style, own in lines:
        dx = 0.0 if dx is None else dx
        dy = 0.0 if dy is None else dy
        # a chunk started by x alone continues at the y the one before ends at: its y plus
        # its first character's dy, as position_linear sums a horizontal chunk's dy
        y = y_end if y is None else y
        y_end = y + (0.0 + dy)
        placed = _place(face, spec, None, text, x, y, dx, dy, shift, style, ctx)
        if placed is None:
            return None
        if own < len(text):
            _, loc, gids, _, _, (_, _, clusters, _, _) = placed
            if any(face.outline_box(int(g), loc) is not None
                   for g, c in zip(gids.tolist(), clusters.tolist()) if c >= own):
                return None
        placed_lines.append((placed, style))
    boxes = [p[4] for p, _ in placed_lines]
    if any(math.isnan(v) for box in boxes for v in box):
        return None
    bbox = (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes),
            max(b[3] for b in boxes))
    out = []
    for placed, style in placed_lines:
        out.extend(_line_nodes(placed, style, bbox, ctx))
    return finish_text(out, ctx)


def _first_positions(element, style, ctx, n):
    """[x, y, dx, dy]: the first value of each of the element's position lists (user units;
    None where it has none), or None where a value after the first applies to another of
    its ``n`` characters (another chunk or offset: not a plain line) or a length does not
    resolve."""
    get = element.get
    firsts = []
    for name, axis, _ in _POSITIONS:
        value = get(name)
        if value is None:
            firsts.append(None)
            continue
        v = _plain_number(value)
        if v is not None:
            firsts.append(v)
            continue
        values = parse_length_list(value)
        if len(values) > 1 and n > 1:
            return None
        if values:
            v, unit = values[0]
            v = v if unit in _USER_UNITS else ctx.length(f"{v!r}{unit}", axis, style)
            if v is None:
                return None
        firsts.append(v)
    return firsts


def _rotates(element, n):
    """Whether the element's rotate list turns one of its ``n`` characters (the last value
    turns those after it; an invalid list turns none)."""
    rotate = element.get("rotate")
    return rotate is not None and any((parse_number_list(rotate) or ())[:n])


def _plain_number(value):
    """A list of one number written with digits, a point and a sign at most (``166.0``), as
    parse_length_list reads it (its NUMBER_RE and float agree on these characters), or None
    for anything else, which takes parse_length_list."""
    digits = value[1:] if value[:1] in ("+", "-") else value
    if digits.isascii() and digits.replace(".", "", 1).isdigit():
        v = float(value)
        if math.isfinite(v):
            return v
    return None


def _line_style(element, style, ctx, span=None):
    """(font spec, face, baseline shift) of a <text> of computed ``style`` whose characters
    may make a plain line, or None where its style says they do not (vertical writing,
    text-transform,
    letter- or word-spacing, a size that draws nothing, no family of its list, a face of
    colour or SVG glyphs); once per (style, kerning attribute, viewport) for the document,
    as its font spec (layout.element_spec): all of these follow from them, the baseline
    shift of a <text> (layout.baseline_offset of its span) from its style and face.
    ``span``: a tspan's (span_lines), whose baseline shift and alignment add to its text's:
    from its style too, whose parent is the text's (document.Style.child)."""
    known = ctx.cache.setdefault("plain styles", {})
    key = style, kerning_attribute(element), ctx.viewport, span is None
    got = known.get(key)
    if got is None:
        got = known[key] = _style_of_line(element, style, ctx, span) or ()
    return got or None


def _style_of_line(element, style, ctx, span):
    if text_transform(style) or (style.get("writing-mode") or "lr").strip() in _VERTICAL:
        return None
    spec = _layout.element_spec(element, style, ctx)
    if spec.letter_spacing or spec.word_spacing or not (math.isfinite(spec.size)
                                                          and spec.size > 0):
        return None
    face = _face(spec, ctx)
    if face is None or not _plain_face(face):
        return None
    return spec, face, _layout.baseline_offset(span or Span(element, style, None), face, spec,
                                               False)


def _plain_face(face):
    return not has_color_glyphs(face) and not has_svg_glyphs(face)


def _one_run(text):
    """Whether the text is one left-to-right bidi run (no ASCII character starts a
    right-to-left one)."""
    return text.isascii() or _layout.shaping_runs(text, 0, len(text), None) == [
        (0, len(text), "ltr")]


def _face(spec, ctx):
    """The loaded face of spec's family list (assign_faces' primary face), or None where the
    list finds no family (the per-character route warns of that) or the face does not load;
    once per spec for the document."""
    known = ctx.cache.setdefault("plain faces", {})
    got = known.get(id(spec))
    if got is None or got[0] is not spec:
        db = font_database(ctx)
        families = list(spec.families)
        face = None
        if db.query(families, spec.weight, spec.style, spec.stretch) is not None:
            info = db.query_or_default(families, spec.weight, spec.style, spec.stretch)
            loaded = document_faces(ctx)
            hit = loaded.get(id(info))
            if hit is None:
                hit = loaded[id(info)] = (info, _load(info))
            face = hit[1]
        got = known[id(spec)] = (spec, face)
    return got[1]


def _draws_all(face, text, ctx):
    """Whether ``face`` draws every character of ``text`` that needs a face (assign_faces
    then gives it every character: those that need none keep the primary face, and marks
    and selectors follow their base's). The characters found so are kept per face for the
    document."""
    known = ctx.cache.setdefault("plain characters", {})
    got = known.get(id(face))
    if got is None or got[0] is not face:
        got = known[id(face)] = (face, set())
    drawn = got[1]
    chars = set(text)
    if chars <= drawn:
        return True
    cmap = face.cmap
    if all(ord(ch) in cmap or needs_no_face(ch) or _draws(face, ch) for ch in chars - drawn):
        drawn |= chars
        return True
    return False


def _place(face, spec, faces, text, x, y, dx0, dy0, shift, style, ctx):
    """(face, location, glyph ids, their matrices, the em box, the memo entry) of a plain
    line of ``text`` (``faces``: each character's, None: all ``face``) whose first character
    is at (x, y) (None: 0) moved by (dx0, dy0), baseline shifted by ``shift``; or None
    where the kernel declines or the line reaches past the image while glyphs are culled."""
    n = len(text)
    anchor = ANCHORS.get((style.get("text-anchor") or "start").strip(), 0)
    loc = face_location(face, spec)
    memo = ctx.cache.setdefault("plain lines", {}) if n <= MEMO_LINE else None
    key = (text, id(face), id(spec))
    got = memo.get(key) if memo is not None else None
    if got is None:
        run = _layout.shaped_run(face, spec, loc, text, 0, n, "ltr", (0, n))
        owner = _layout.cluster_owners(text, faces or [face] * n, 0, n, run) \
            if not text.isascii() else None
        clusters = run.clusters
        if owner:
            clusters = clusters.copy()
            for i, c in enumerate(clusters.tolist()):
                clusters[i] = owner.get(c, c)
        # [.., the glyphs' outlines, joined once (when first drawn) for every line of these
        # characters]
        got = [run.advances, run.offsets, clusters, run.gids, None]
        if memo is not None:
            memo[key] = got
    advances, offsets, clusters, gids, outlines = got
    x = x if x is not None else 0.0
    y = y if y is not None else 0.0
    at = compose(IDENTITY, translate(x, y + shift))
    scale = spec.size / face.units_per_em
    m = face.metrics
    mats, box, ok = line_glyphs(advances, offsets, clusters, float(scale), m.ascender * scale,
                                m.descender * scale, float(dx0), float(dy0), anchor,
                                *map(float, at))
    if not ok:
        return None
    bbox = (float(box[0]), float(box[1]), float(box[2]), float(box[3]))
    if ctx.sampled is not None and not _within(bbox, ctx.transform, ctx.sampled):
        return None
    return face, loc, gids, mats, bbox, got


def _draw(placed, style, ctx):
    """The nodes of a placed plain line (_place) in ``style``."""
    return finish_text(_line_nodes(placed, style, placed[4], ctx), ctx)


def _line_nodes(placed, style, bbox, ctx):
    """The fill of a placed line's glyphs (none where hidden or empty), its object
    bounding box ``bbox`` (the text's), before finish_text."""
    face, loc, gids, mats, _, got = placed
    if style.get("visibility").strip() in ("hidden", "collapse"):
        return []
    outlines = got[4]
    if outlines is None:
        outlines = got[4] = glyph_outlines(face, loc, gids.tolist()) or ()
    path = Path.from_arrays(*placed_outlines(outlines or None, mats))
    return [] if path.is_empty() else _nonzero(ctx.draw(path, style, bbox))
