"""Text drawing: glyph outlines in runs of one element, filled and stroked through the builder
(``ctx.draw``), colour glyphs drawn in their own colours, and text decorations as rectangles
under/over the glyphs, those that cannot reach the image left out (ctx.sampled); the object
bounding box of text as resvg computes it."""
from __future__ import annotations

import math

import numpy as np

from ...fonts.color import color_glyph_fills, has_color_glyphs, is_color_glyph
from ...fonts.layout import glyphs_arrays
from ...scene.nodes import Fill, ImagePaint, Solid
from ...scene.path import Path, rect_path
from ...scene.transform import apply
from .svg_glyphs import has_svg_glyph, has_svg_glyphs, svg_glyph_nodes

def text_bbox(clusters):
    """Object bounding box of text as resvg computes it: the union of the clusters' em boxes
    (ascent to descent over the advance), not of the glyph outlines. A cluster of vertical
    text under text-orientation: upright has its em box on the line (its vertical advance
    along the column, the em height across), not turned back with its glyphs."""
    xs, ys = [], []                 # (plain floats: a text has a few clusters)
    for c in clusters:
        if not c.visible:
            continue
        adv = c.advance if c.advance > 0 else 1.0
        a, b, cc, d, e, f = c.frame if c.upright else c.placed
        # the corners (0, top), (adv, top), (0, bottom), (adv, bottom), mapped written out
        top, bottom = -c.ascent, -c.descent
        xs += (a * 0.0 + cc * top + e, a * adv + cc * top + e,
               a * 0.0 + cc * bottom + e, a * adv + cc * bottom + e)
        ys += (b * 0.0 + d * top + f, b * adv + d * top + f,
               b * 0.0 + d * bottom + f, b * adv + d * bottom + f)
    if not xs:
        return None
    if any(map(math.isnan, xs)) or any(map(math.isnan, ys)):
        return (math.nan,) * 4      # (a NaN wins, as in numpy's min and max)
    return (float(min(xs)), float(min(ys)), float(max(xs)), float(max(ys)))


def draw_clusters(text_el, chars, clusters, ctx, styles, vertical):
    visible = [c for c in clusters if c.visible]
    if not visible:
        return []
    # Glyphs are painted in the logical order of their characters, whatever the bidi
    # reordering (SVG 1.1 §10.4, SVG 2 text rendering order), as runs of consecutive
    # characters of one element: an element's text after a child's is painted over it.
    runs = []
    for c in sorted(visible, key=lambda c: c.char):
        el = chars[c.char].el
        if not runs or runs[-1][0] is not el:
            runs.append((el, []))
        runs[-1][1].extend(c.glyphs)
    bbox = text_bbox(visible)
    if bbox is None:
        return []
    decorations = text_decorations(text_el, chars, clusters, styles, vertical)
    for kind in decorations:
        for _, path, _, _ in decorations[kind]:
            b = path.bounds()
            if b is not None:
                bbox = (min(bbox[0], b[0]), min(bbox[1], b[1]), max(bbox[2], b[2]),
                        max(bbox[3], b[3]))
    if ctx.geometry_only:
        # The object bounding box of text is resvg's: the clusters' em boxes, not the ink.
        x0, y0, x1, y1 = bbox
        return ctx.draw(rect_path(x0, y0, x1 - x0, y1 - y0), ctx.style, bbox)
    if ctx.sampled is not None and not _within(bbox, ctx.transform, ctx.sampled):
        # what cannot reach the image is left out once the bounding box (of all) is known
        # (a text inside it is not looked at: culling is a saving, never needed)
        reach = _Reach(ctx, styles)
        runs = _reaching_runs(runs, reach, ctx)
        decorations = {kind: [(st, _reaching_rects(path, rects, reach(decl), ctx), rects, decl)
                              for st, path, rects, decl in entries]
                       for kind, entries in decorations.items()}
    out = []
    for kind in ("underline", "overline"):
        for deco_style, path, _, _ in decorations.get(kind, []):
            if not path.is_empty():
                out.extend(ctx.draw(path, deco_style, bbox))
    # Like resvg, opacity, clip-path, mask and filter on tspan-level elements are not
    # applied (only on <text> itself, by the builder).
    for el, glyphs in runs:
        style = styles[id(el)]
        if not glyphs or style.get("visibility").strip() in ("hidden", "collapse"):
            continue
        out.extend(_color_or_plain(glyphs, _glyph_path(glyphs), style, ctx, bbox))
    for deco_style, path, _, _ in decorations.get("line-through", []):
        if not path.is_empty():
            out.extend(ctx.draw(path, deco_style, bbox))
    return finish_text(out, ctx)


def finish_text(out, ctx):
    """A text's nodes ``out`` with its antialiasing set and its fills noted (ctx)."""
    # Antialiasing of text, decorations included, is the <text> element's text-rendering
    # (optimizeSpeed draws aliased, as crispEdges); shape-rendering and text-rendering on a
    # tspan do not apply (as resvg)
    antialias = (ctx.style.get("text-rendering") or "auto").strip().lower() != "optimizespeed"
    fills = _fills_of(out)
    for fill in fills:
        fill.antialias = antialias
    ctx.note_text_fills(fills)
    return out


class _Reach:
    """Device px each element's stroke reaches beyond its glyphs (None: unknown), once per
    style."""

    def __init__(self, ctx, styles):
        self.ctx, self.styles, self.known = ctx, styles, {}

    def __call__(self, el):
        style = self.styles[id(el)]
        try:
            return self.known[id(style)]
        except KeyError:
            r = self.known[id(style)] = self.ctx.stroke_reach(style)
            return r


def _within(box, m, rect):
    """Whether a user-space box mapped by m lies inside the device rect."""
    x0, y0, x1, y1 = box
    a, b, c, d, e, f = m
    xs = (a * x0 + c * y0 + e, a * x1 + c * y0 + e, a * x0 + c * y1 + e, a * x1 + c * y1 + e)
    ys = (b * x0 + d * y0 + f, b * x1 + d * y0 + f, b * x0 + d * y1 + f, b * x1 + d * y1 + f)
    return rect[0] <= min(xs) and max(xs) <= rect[2] and rect[1] <= min(ys) and max(ys) <= rect[3]


def _misses(boxes, reach, rect):
    """Which of the device boxes (N, 4: x0, y0, x1, y1), each grown by ``reach`` px, miss
    ``rect``; NaN misses nothing."""
    x0, y0, x1, y1 = rect
    return ((boxes[:, 2] + reach < x0) | (boxes[:, 0] - reach > x1)
            | (boxes[:, 3] + reach < y0) | (boxes[:, 1] - reach > y1))


def _reaching_runs(runs, reach, ctx):
    """The runs without the glyphs whose drawing cannot touch ``ctx.sampled``: a plain
    outline glyph lies in its points' box, placed by its matrix and the device transform
    (the box's corners mapped: the centre, and the half sides' images' absolute values
    summed), and its stroke within ``reach(element)`` px of it. Colour and SVG glyphs, with
    extents of their own, are all kept, and so is everything under a stroke of unknown reach
    (dashed). Leaving a glyph out leaves the winding of every sample in the rect, so its
    pixels, as they were: a glyph is closed contours, stroked each on its own."""
    where, boxes, mats, radii = [], [], [], []
    special = {}
    for k, (el, glyphs) in enumerate(runs):
        r = reach(el)
        if r is None:
            continue
        for i, g in enumerate(glyphs):
            key = (id(g.face), g.gid)
            own = special.get(key)
            if own is None:
                own = special[key] = (is_color_glyph(g.face, g.gid)
                                      or has_svg_glyph(g.face, g.gid))
            if own:
                continue
            box = g.face.outline_box(g.gid, g.location)
            if box is None:
                continue            # (an empty outline: kept, it draws nothing)
            where.append((k, i))
            boxes.append(box)
            mats.append(g.matrix)
            radii.append(r)
    if not where:
        return runs
    b = np.array(boxes)
    m = np.array(mats, dtype=np.float64)
    ta, tb, tc, td, te, tf = ctx.transform
    a = ta * m[:, 0] + tc * m[:, 1]
    bb = tb * m[:, 0] + td * m[:, 1]
    c = ta * m[:, 2] + tc * m[:, 3]
    d = tb * m[:, 2] + td * m[:, 3]
    e = ta * m[:, 4] + tc * m[:, 5] + te
    f = tb * m[:, 4] + td * m[:, 5] + tf
    cx, cy = (b[:, 0] + b[:, 2]) / 2, (b[:, 1] + b[:, 3]) / 2
    hx, hy = (b[:, 2] - b[:, 0]) / 2, (b[:, 3] - b[:, 1]) / 2
    x, y = a * cx + c * cy + e, bb * cx + d * cy + f
    wx, wy = np.abs(a) * hx + np.abs(c) * hy, np.abs(bb) * hx + np.abs(d) * hy
    missed = _misses(np.stack((x - wx, y - wy, x + wx, y + wy), axis=1), np.array(radii),
                     ctx.sampled)
    drop = {}
    for n in np.flatnonzero(missed).tolist():
        k, i = where[n]
        drop.setdefault(k, set()).add(i)
    return [(el, [g for i, g in enumerate(glyphs) if i not in drop[k]]) if k in drop
            else (el, glyphs) for k, (el, glyphs) in enumerate(runs)]


def _reaching_rects(path, rects, reach, ctx):
    """``path``, the decoration rectangles ``rects`` (user space) joined, without those
    that cannot touch ctx.sampled (their device corners' box grown by ``reach``)."""
    if reach is None:
        return path
    corners = apply(ctx.transform, np.concatenate([r.points for r in rects]))
    corners = corners.reshape(len(rects), 4, 2)
    missed = _misses(np.concatenate((corners.min(axis=1), corners.max(axis=1)), axis=1),
                     reach, ctx.sampled)
    if not missed.any():
        return path
    kept = [r for r, out in zip(rects, missed.tolist()) if not out]
    return _joined(kept) if kept else Path()


def _glyph_path(glyphs):
    """One user-space path for glyphs, each placed by its matrix (fonts.layout)."""
    verbs, points = [], []
    by_face = {}
    for g in glyphs:
        entry = by_face.setdefault((id(g.face), g.location), (g.face, g.location, [], []))
        entry[2].append(g.gid)
        entry[3].append(g.matrix)
    for face, loc, gids, mats in by_face.values():
        v, p = glyphs_arrays(face, loc, gids, mats)
        verbs.append(v)
        points.append(p)
    if len(verbs) == 1:             # (one face, as most texts: its arrays, not copies)
        return Path.from_arrays(verbs[0], points[0])
    return Path.from_arrays(np.concatenate(verbs), np.concatenate(points))


def _color_or_plain(glyphs, path, style, ctx, bbox):
    """Colour glyphs (COLR, sbix/CBDT bitmaps, else SVG documents) draw their own colours;
    everything else is the outline path filled and stroked through ctx.draw. Glyphs are
    painted in their order (SVG 2, text rendering order: each glyph over the ones before
    it; an sbix bitmap's opaque background hides an outline glyph drawn before it, and one
    drawn after it goes over the bitmap), a run of outline glyphs as one path."""
    # (faces without colour or SVG glyphs, most, asked once a run, not once a glyph)
    faces = {id(g.face): g.face for g in glyphs}.values()
    special = [g for g in glyphs if is_color_glyph(g.face, g.gid)
               or has_svg_glyph(g.face, g.gid)] \
        if any(has_color_glyphs(f) or has_svg_glyphs(f) for f in faces) else []
    if not special:
        return _nonzero(ctx.draw(path, style, bbox)) if not path.is_empty() else []
    ref = ctx.resolve_paint(style, "fill", bbox)
    paint = ref.paint if ref is not None else Solid()
    out, plain = [], []

    def flush():
        plain_path = _glyph_path(plain) if plain else None
        if plain_path is not None and not plain_path.is_empty():
            out.extend(_nonzero(ctx.draw(plain_path, style, bbox)))
        plain.clear()

    for g in glyphs:
        if is_color_glyph(g.face, g.gid):
            nodes = color_glyph_fills(g.face, g.location, g.gid, g.matrix, paint, ctx.transform)
        elif has_svg_glyph(g.face, g.gid):
            nodes = svg_glyph_nodes(g.face, g.gid, g.matrix, ctx.transform)
        else:
            nodes = None
        if nodes is None:                  # an outline glyph, or an unreadable SVG glyph
            plain.append(g)
            continue
        if ctx.in_clip:
            # in a clip path a colour glyph counts by its shape: every fill, opaque; a bitmap
            # glyph (sbix, CBDT) is an image, which has no geometry to clip with (as in
            # resvg, also where the font has an outline for it)
            nodes = [Fill(f.path, Solid((0.0, 0.0, 0.0, 1.0))) for f in _fills_of(nodes)
                     if not isinstance(f.paint, ImagePaint)]
        flush()
        out.extend(nodes)
    flush()
    return out


def _nonzero(nodes):
    """Glyph outlines fill by the nonzero rule whatever fill-rule (and, in a clip path,
    clip-rule) says: SVG 2 text rendering order, "the fill-rule property does not apply to
    SVG text elements" (as resvg), so the overlapping contours of joined Arabic glyphs and
    of overlapping spans leave no holes."""
    for n in nodes:
        if isinstance(n, Fill):
            n.rule = "nonzero"
    return nodes


def _fills_of(nodes):
    stack, out = list(reversed(nodes)), []
    while stack:
        n = stack.pop()
        if isinstance(n, Fill):
            out.append(n)
        else:
            stack.extend(reversed(n.children))
    return out


def _own_decorations(el):
    """The decoration kinds ``el``'s text-decoration declares."""
    value = (el.specified.get("text-decoration") or "").split()
    return [kind for kind in ("underline", "overline", "line-through") if kind in value]


def _declared_decorations(el, above):
    """The decoration kinds ``el`` or an ancestor declares (``above``: its ancestors')."""
    own = tuple(kind for kind in _own_decorations(el) if kind not in above)
    return above + own if own else above


def _span_decorations(span, above):
    """{kind: the element declaring it} for a span's characters: the innermost of the span
    and its ancestors that declares each kind (``above``: its parent's; at <text>, the text
    for the kinds declared outside it), shared by the spans below that declare none."""
    own = _own_decorations(span.el)
    return {**above, **{kind: span.el for kind in own}} if own else above


def _outer_decorations(text_el):
    """{kind: text_el} for the kinds declared outside <text> (on its ancestors)."""
    declared = () if text_el.parent is None else \
        text_el.parent.computed("decorations", _declared_decorations, ())
    return {kind: text_el for kind in declared}


def decorated(text_el, span):
    """Whether the characters of ``span`` (of <text> ``text_el``) have a decoration."""
    return bool(span.computed("decorations", _span_decorations, _outer_decorations(text_el)))


def text_decorated(text_el):
    """decorated() of the characters of a <text> without child elements (its own span, whose
    value is the kinds declared outside it and those it declares): whether it or an
    ancestor declares a decoration."""
    return bool(_own_decorations(text_el)) or bool(_outer_decorations(text_el))


def text_decorations(text_el, chars, clusters, styles, vertical):
    """{kind: [(style of the declaring element, user-space path, its rectangles, the
    declaring element)]}.

    As in resvg: a text span (characters of one innermost element) is decorated by every
    kind declared on it or an ancestor, painted with the declaring element's fill and stroke
    (the text's own style when declared outside <text>), sized by the span's own font (a
    rectangle centred on the underline, ascender or strike-out line, underline thickness);
    the line runs over consecutive clusters and restarts at each cluster moved by
    dx/dy/rotate, placed on a path or starting a chunk.
    """
    out = {}
    outer = _outer_decorations(text_el)
    span_kinds = {}
    for c in clusters:
        span = chars[c.char].span
        if id(span.el) not in span_kinds:
            span_kinds[id(span.el)] = span.computed("decorations", _span_decorations, outer)
    if not any(span_kinds.values()):
        return out                  # (most texts: no line to run over the clusters)
    # a hidden span's characters are not painted, and neither is a decoration under them
    # (a decoration is drawn with the text it decorates; a visible span inside a hidden
    # decorating one keeps its line)
    hidden = {key for key in span_kinds
              if styles[key].get("visibility").strip() in ("hidden", "collapse")}
    for kind in ("underline", "overline", "line-through"):
        by_decl = {}
        runs = []
        run = None
        prev_el = None
        for c in clusters:
            el = chars[c.char].el
            decl = span_kinds[id(el)].get(kind)
            if decl is None or not c.visible or id(el) in hidden:
                run = None
            elif run is None or c.shifted or el is not prev_el:
                run = [c, c.advance, decl]
                runs.append(run)
            else:
                run[1] += c.advance
            prev_el = el
        for c0, width, decl in runs:
            if width <= 0:
                # spacing pulled the run back past its start (word-spacing="-10000"): its
                # line would be a rectangle of negative width, which is empty (CSS leaves
                # it open; resvg draws none, rather than a line through where no glyph is)
                continue
            # the span's own font (its family list's best match), even where a character
            # fell back to another face, as resvg measures decorations
            face = chars[c0.char].primary_face or c0.face
            m = face.metrics
            scale = c0.size / face.units_per_em
            if vertical and not c0.sideways:
                half = (m.ascender - m.descender) * scale / 2
                dy = {"underline": half, "overline": -half}.get(kind, 0.0)
            elif kind == "underline":
                dy = -m.underline_position * scale
            elif kind == "overline":
                dy = -m.ascender * scale
            else:
                dy = -m.strikeout_position * scale
            thick = m.underline_thickness * scale
            rect = rect_path(0.0, dy - thick / 2, width, thick).transformed(c0.frame)
            by_decl.setdefault(id(decl), (styles[id(decl)], [], decl))[1].append(rect)
        out[kind] = [(style, _joined(rects), rects, decl)
                     for style, rects, decl in by_decl.values()]
    return out


def _joined(paths):
    """One path of the subpaths of ``paths`` in their order."""
    return Path.from_arrays(np.concatenate([p.verbs for p in paths]),
                            np.concatenate([p.points for p in paths]))
