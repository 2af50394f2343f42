"""Markers (marker-start, marker-mid, marker-end) placed on path vertices."""
from __future__ import annotations

import math
from dataclasses import replace

from ..path import compose
from ..scene import Group
from .units import (matrix_scale, parse_aspect, parse_number, parse_viewbox, translate,
                    viewbox_transform)


def bisector(angle_in, angle_out):
    """orient="auto" at a vertex: halfway from the incoming to the outgoing direction, turning
    the short way; a U-turn gives the perpendicular (as resvg and Chrome draw it)."""
    a_in = math.radians(angle_in) % (2 * math.pi)
    a_out = math.radians(angle_out) % (2 * math.pi)
    d = (a_out - a_in) / 2
    angle = a_in + d
    if abs(d) > math.pi / 2:
        angle -= math.pi
    return math.degrees(angle % (2 * math.pi))


def draw_markers(builder, path, style, ctx):
    """Marker nodes of a path. Every verb is a segment, the cubic pieces of an arc included:
    resvg places mid markers between them too."""
    targets = style.cache.get(("marker-targets",))
    if targets is None:
        targets = style.cache[("marker-targets",)] = marker_targets(builder.doc, style)
    if not targets:
        return []
    from ..stroke import marker_vertices
    width = builder.length(style.get("stroke-width"), "xy", style, ctx.viewport, 1.0)
    from .geometry import path_bounds
    bbox = path_bounds(path)
    context_fill = builder.context_paint(style, "fill", ctx, lambda: bbox)
    context_stroke = builder.context_paint(style, "stroke", ctx, lambda: bbox)
    out = []
    for x, y, angle_in, angle_out, kind in marker_vertices(path):
        marker = targets.get(kind)
        if marker is None:
            continue
        out.extend(one_marker(builder, marker, x, y, angle_in, angle_out, kind, width, ctx,
                              context_fill, context_stroke))
    return out


def marker_targets(doc, style):
    """The <marker> elements a style names, by kind (start, mid, end)."""
    from .builder import parse_url

    targets = {}
    for kind in ("start", "mid", "end"):
        value = style.get(f"marker-{kind}")
        if value == "none":
            continue
        url = parse_url(value or "none")
        if url is None:
            continue
        el = doc.lookup(url[0])
        if el is not None and el.tag == "marker":
            targets[kind] = el
    return targets


def one_marker(builder, marker, x, y, angle_in, angle_out, kind, stroke_width, ctx,
               context_fill, context_stroke):
    if any(m is marker for m in builder.ref_stack):
        return []
    # 'display' does not apply to <marker>: it is drawn even under display="none"
    style = builder.doc.document_style(marker)
    get = builder.length_getter(marker, style, ctx)
    mw = get("markerWidth", "x", 3.0)
    mh = get("markerHeight", "y", 3.0)
    if mw <= 0 or mh <= 0:
        return []
    orient = (marker.get("orient") or "0").strip()
    if orient == "auto":
        angle = angle_out if kind == "start" else angle_in if kind == "end" else \
            bisector(angle_in, angle_out)
    elif orient == "auto-start-reverse":
        if kind == "start":
            angle = angle_out + 180
        else:
            angle = angle_in if kind == "end" else bisector(angle_in, angle_out)
    else:
        o = orient.lower()
        factor = 1.0
        for unit, f in (("deg", 1.0), ("grad", 0.9), ("rad", 180 / math.pi), ("turn", 360.0)):
            if o.endswith(unit):
                o = o[:-len(unit)]
                factor = f
                break
        angle = (parse_number(o, 0.0) or 0.0) * factor
    units = (marker.get("markerUnits") or "strokeWidth").strip()
    scale = stroke_width if units != "userSpaceOnUse" else 1.0
    m = translate(x, y)
    if angle:
        r = math.radians(angle)
        m = compose(m, (math.cos(r), math.sin(r), -math.sin(r), math.cos(r), 0.0, 0.0))
    vb = parse_viewbox(marker.get("viewBox"))
    if vb is not None:
        vb_m = viewbox_transform(vb, parse_aspect(marker.get("preserveAspectRatio")),
                                 mw * scale, mh * scale)
        sx, sy = matrix_scale(vb_m)
        m = compose(m, (sx, 0.0, 0.0, sy, 0.0, 0.0))
        clip_rect = vb
        viewport = (vb[2], vb[3])
    else:
        m = compose(m, (scale, 0.0, 0.0, scale, 0.0, 0.0))
        clip_rect = (0.0, 0.0, mw, mh)
        viewport = ctx.viewport
    ref_x = builder.length(marker.get("refX"), "x", style, viewport, 0.0)
    ref_y = builder.length(marker.get("refY"), "y", style, viewport, 0.0)
    m = compose(m, translate(-ref_x, -ref_y))
    # Marker content is a fresh instantiation: the <use> cycle guard restarts (recursion
    # through markers is cut by ref_stack instead).
    inner = replace(ctx, transform=compose(ctx.transform, m), viewport=viewport, use_stack=(),
                    context_fill=context_fill, context_stroke=context_stroke)
    builder.ref_stack.append(marker)
    try:
        nodes = builder.children(marker, inner, style)
    finally:
        builder.ref_stack.pop()
    if not nodes:
        return []
    if builder.overflow_hidden(marker, style):
        clip = builder.viewport_clip(*clip_rect, replace(ctx, transform=inner.transform))
        nodes = [Group(children=nodes, clip=clip)]
    return nodes
