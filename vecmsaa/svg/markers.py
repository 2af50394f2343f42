"""Markers (marker-start, marker-mid, marker-end) placed on path vertices."""
from __future__ import annotations

import math
import re

from ..geometry.stroke import segment_tangents
from ..scene.path import CLOSE, CUBIC, MOVE, VERB_POINTS, Path
from ..scene.transform import compose, rotate_at, translate
from ..scene.nodes import Fill, Group
from .units import (ANGLE_DEG, NUMBER_RE, parse_aspect, parse_viewbox,
                    viewbox_transform, zero_size_viewbox)


_ANGLE = re.compile(rf"({NUMBER_RE})(deg|grad|rad|turn)?", re.I)


def auto_angle(angle_in, angle_out):
    """orient="auto" at a mid vertex (degrees): the bisector of the incoming and outgoing
    directions, halfway the short way round (SVG 1.1 §11.6.2). At a U-turn both halves are
    equally short and SVG 2 leaves the side open (svgwg issue 333); the result here is the
    incoming direction turned by +90° unless rounding tips it. resvg (in f32) and Chrome
    pick the side by rounding too, each its own way (session 23: of 24 random U-turns,
    resvg and Chrome agreed on 12, this on 3 of those)."""
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
    width = builder.length(style.get("stroke-width"), "xy", style, ctx.viewport, 1.0)
    from ..scene.bounds import path_bounds
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
        if url is None or url[1]:
            continue                    # not a url, or more after it: invalid
        el = doc.lookup(url[0]) if url[0].startswith("#") else None   # url(k): another file
        if el is not None and el.tag == "marker":
            targets[kind] = el
    return targets


def one_marker(builder, marker, x, y, angle_in, angle_out, kind, stroke_width, ctx,
               context_fill, context_stroke):
    from .builder import ctx_with

    if any(m is marker for m in builder.ref_stack):
        return []
    # (what does not depend on the vertex is worked out once per marker, stroke width and
    # viewport: a polyline may place tens of thousands)
    key = (marker, stroke_width, ctx.viewport)
    layout = builder.marker_cache.get(key)
    if layout is None:
        layout = builder.marker_cache[key] = marker_layout(builder, marker, stroke_width, ctx)
    if layout is False:
        return []
    style, orient, fixed_angle, scaling, ref, clip_rect, viewport = layout
    if orient == "auto":
        angle = angle_out if kind == "start" else angle_in if kind == "end" else \
            auto_angle(angle_in, angle_out)
    elif orient == "auto-start-reverse":
        if kind == "start":
            angle = angle_out + 180
        else:
            angle = angle_in if kind == "end" else auto_angle(angle_in, angle_out)
    else:
        angle = fixed_angle
    m = translate(x, y)
    if angle:
        m = compose(m, rotate_at(angle, 0.0, 0.0))
    m = compose(m, scaling)
    m = compose(m, ref)
    # Marker content is a fresh instantiation: the <use> cycle guard restarts (recursion
    # through markers is cut by ref_stack instead).
    inner = ctx_with(ctx, transform=compose(ctx.transform, m), viewport=viewport, use_stack=(),
                     context_fill=context_fill, context_stroke=context_stroke)
    builder.enter_reference(marker)
    try:
        nodes = builder.children(marker, inner, style)
    finally:
        builder.ref_stack.pop()
    if not nodes:
        return []
    if clip_rect is not None:
        clip = builder.viewport_clip(*clip_rect, ctx_with(ctx, transform=inner.transform))
        if not keeps_every_sample(clip.children[0].path.points, nodes):
            nodes = [Group(children=nodes, clip=clip)]
    return nodes


def keeps_every_sample(corners, nodes) -> bool:
    """Whether the clip rectangle with device ``corners`` (4 x 2, in order round it) covers
    every sample of every pixel that ``nodes`` can draw in, so that it clips nothing and the
    nodes may draw in their parent's pass instead of a layer (SVG 2 §11.6.2: the clip is there
    to cut content crossing the viewport; a layer costs about 0.2 ms of raster a marker).

    A layer is resolved, then multiplied by its clip's resolved coverage: at a pixel the
    clip's edge crosses, content drawn inside the clip would still be scaled by the covered
    fraction. So the test is on whole pixels, not on geometry alone. A pixel's samples lie in
    [i, i + 1) × [j, j + 1) (the per-pixel patterns; the scan converter counts a sample on an
    edge's crossing as right of it, so a rectangle [x0, x1) × [y0, y1) covers exactly the
    samples in it). What the nodes can draw in: their fills' points (curves and stroke
    outlines lie in their control points' hull) and filtered groups' regions (the filter
    result is cut to them). Patterns sharing samples with the neighbours (quincunx,
    FLIPQUAD) and resolve filters reaching into them (tent1, gaussian, mitchell) still see
    the clip's edge in pixels near it; there drawing without the clip is the per-sample
    product itself (content times clip is the content), which the layer approximated.
    A group blending with what is below it (mix-blend-mode) keeps the clip: the layer is its
    transparent backdrop."""
    xy, boxes = [], []              # the fills' points as x, y, x, y...; filter regions
    while nodes:
        inner = []
        for node in nodes:
            if type(node) is Fill:
                # (Python floats: numpy's reductions over a marker's few points cost more
                # than the rest of the test)
                xy += node.path.points.ravel().tolist()
            elif node.blend != "normal":
                return False
            elif node.filters:
                boxes += [f.region for f in node.filters]
            else:
                inner += node.children      # (its own clip and mask only take away)
        nodes = inner
    if xy:
        if not math.isfinite(sum(xy)):      # (NaN would slip through min and max)
            return False
        x0, x1 = min(xy[0::2]), max(xy[0::2])
        y0, y1 = min(xy[1::2]), max(xy[1::2])
    elif not boxes:
        return True                         # nothing drawn
    ax, ay, bx, by, cx, cy, dx, dy = corners.ravel().tolist()
    if (ax == bx and cx == dx and ay == dy and by == cy) or \
            (ay == by and cy == dy and ax == dx and bx == cx):
        # axis-aligned: the pixels the content reaches inside [left, right) × [top, bottom)
        # (a hair of slack where a point sits on a pixel's edge)
        left, right = min(ax, cx), max(ax, cx)
        top, bottom = min(ay, cy), max(ay, cy)
        if xy:
            boxes.append((math.floor(x0 - _slack(x0)), math.floor(y0 - _slack(y0)),
                          math.floor(x1 + _slack(x1)) + 1, math.floor(y1 + _slack(y1)) + 1))
        for b in boxes:
            if not (left <= math.floor(b[0]) and top <= math.floor(b[1])
                    and math.ceil(b[2]) <= right and math.ceil(b[3]) <= bottom):
                return False
        return True
    # rotated or skewed (a parallelogram): along the inward unit normal n of an edge, every
    # sample s must have n·s between the edge's n·p and the opposite edge's n·o; a pixel
    # holding a point q has its samples within |nx| + |ny| of n·q, a filter region's within it
    turn = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
    if not (turn != 0 and math.isfinite(turn)):
        return False
    sign = 1.0 if turn > 0 else -1.0
    slack = _slack(max(abs(ax), abs(ay), abs(bx), abs(by), abs(cx), abs(cy), abs(dx), abs(dy)))
    it = iter(xy)
    pairs = list(zip(it, it))
    for px, py, qx, qy, ox, oy in ((ax, ay, bx, by, cx, cy), (bx, by, cx, cy, dx, dy)):
        ex, ey = qx - px, qy - py
        length = math.hypot(ex, ey)
        nx, ny = -ey * sign / length, ex * sign / length
        low, high = nx * px + ny * py, nx * ox + ny * oy
        if pairs:
            along = [nx * x + ny * y for x, y in pairs]
            reach = abs(nx) + abs(ny) + slack
            if not (min(along) - low >= reach and high - max(along) >= reach):
                return False
        for b in boxes:
            along = [nx * x + ny * y for x in (b[0], b[2]) for y in (b[1], b[3])]
            if not (min(along) - low >= slack and high - max(along) >= slack):
                return False
    return True


def _slack(v):
    """Far more than the rounding of a device coordinate of magnitude |v| in float64 (or once
    in float32), far less than a sample's spacing."""
    return 2.0 ** -20 * max(1.0, abs(v))


def marker_layout(builder, marker, stroke_width, ctx):
    """(style, orient, its angle when fixed, scaling matrix, refX/refY translation, clip
    rectangle or None, viewport of the content) of a marker drawn on a stroke of
    ``stroke_width``, or False when it is not drawn."""
    # 'display' does not apply to <marker>: it is drawn even under display="none"
    style = builder.doc.document_style(marker)
    get = builder.length_getter(marker, style, ctx)
    mw = get("markerWidth", "x", 3.0)
    mh = get("markerHeight", "y", 3.0)
    if mw <= 0 or mh <= 0:
        return False
    # the keywords of orient and markerUnits match exactly, as the other enumerated
    # attributes do (paint.py): resvg 0.48.1 and Chromium 150 both take " auto" or
    # " userSpaceOnUse" as invalid (0° and strokeWidth); an angle's whitespace is trimmed
    orient = marker.get("orient") or "0"
    angle = None
    if orient not in ("auto", "auto-start-reverse"):
        # an <angle> is a number with its unit right after it ('45 deg' is invalid: 0)
        m = _ANGLE.fullmatch(orient.strip())
        angle = float(m[1]) * ANGLE_DEG[(m[2] or "").lower()] if m else 0.0
        if not math.isfinite(angle):
            angle = 0.0
    scale = stroke_width if marker.get("markerUnits") != "userSpaceOnUse" else 1.0
    if not scale > 0:
        # a viewport of markerWidth·strokeWidth ≤ 0 disables rendering, as a zero marker
        # size does (a negative stroke-width, which draws no stroke, gave mirrored markers)
        return False
    if zero_size_viewbox(marker.get("viewBox")):
        return False        # SVG 2: a zero viewBox width or height disables rendering
    vb = parse_viewbox(marker.get("viewBox"))
    if vb is not None:
        width, height = mw * scale, mh * scale
        sx, _, _, sy, tx, ty = viewbox_transform(
            vb, parse_aspect(marker.get("preserveAspectRatio")), width, height)
        # (the alignment's translation drops out: refX/refY, in the content's coordinates,
        # go to the vertex)
        scaling = (sx, 0.0, 0.0, sy, 0.0, 0.0)
        # the clip is the viewport, markerWidth x markerHeight, in the content's coordinates:
        # wider or taller than the viewBox under 'meet', narrower or shorter under 'slice'
        # (SVG 2's "Details on how markers are rendered": the clip is "at the bounds of the
        # viewport", in its example 0.5 units past each side of a viewBox that xMidYMid meet
        # centres; resvg 0.48.1 clips to the viewBox itself, Chromium 150 to the viewport)
        clip_rect = (-tx / sx, -ty / sy, width / sx, height / sy)
    else:
        scaling = (scale, 0.0, 0.0, scale, 0.0, 0.0)
        clip_rect = (0.0, 0.0, mw, mh)
    # percentages in the marker (refX/refY, its content's lengths, a pattern's x/y/width/
    # height there) are of the viewport the marker is used in, not of its viewBox: SVG's
    # list of elements that establish a new viewport (svg, symbol, image, foreignObject)
    # has no marker, and resvg 0.48.1 and Chromium 150 both take it so
    viewport = ctx.viewport
    ref_x = get("refX", "x", 0.0)
    ref_y = get("refY", "y", 0.0)
    if not builder.overflow_hidden(marker, style):
        clip_rect = None
    return style, orient, angle, scaling, translate(-ref_x, -ref_y), clip_rect, viewport


def marker_vertices(path: Path, commands=None):
    """Marker positions with directions: [(x, y, angle_in, angle_out, kind)], angles in degrees,
    kind "start" (first vertex of the path), "end" (last) or "mid".

    ``commands`` (from parse_path_data_with_commands) groups verbs that came from one path
    command (an arc's cubic pieces) into one segment. For orient="auto" use
    :func:`auto_angle` at mid vertices. Zero-length segments take their
    direction from the neighbouring segments; a closed subpath's first vertex takes its
    incoming direction from the closing segment and its last vertex its outgoing direction
    from the first segment.
    """
    path = path.without_conics()    # (one cubic per conic: commands still line up)
    verbs = path.verbs.tolist()
    pts = path.points.tolist()
    # group into segments: (start, ctrl..., end) with zero-length check
    subpaths = []          # [(vertices [(x,y)], segs [(dir_start, dir_end) or None], closed)]
    cur = start = None
    verts, dirs, closed = None, None, False
    i = 0
    prev_cmd = None
    for vi, v in enumerate(verbs):
        n = VERB_POINTS[v]
        cmd = commands[vi] if commands is not None else vi
        if v == MOVE:
            if verts is not None and len(verts) > 1:
                # (a lone moveto is no segment and so no vertex, wherever it stands)
                subpaths.append((verts, dirs, closed))
            start = cur = tuple(pts[i])
            verts, dirs, closed = [start], [], False
        elif verts is None:
            pass
        else:
            if v == CLOSE:
                ctrl = (cur, start)
            else:
                ctrl = (cur,) + tuple(tuple(q) for q in pts[i:i + n])
            tans = segment_tangents(ctrl)
            if v != CLOSE and prev_cmd == cmd and dirs and v == CUBIC:
                # another piece of the same arc: extend the segment
                d0 = dirs[-1][0] if dirs[-1] else (tans[0] if tans else None)
                d1 = tans[1] if tans else (dirs[-1][1] if dirs[-1] else None)
                dirs[-1] = (d0, d1) if d0 and d1 else dirs[-1]
                verts[-1] = ctrl[-1]
            else:
                dirs.append(tans)
                verts.append(ctrl[-1])
            cur = ctrl[-1]
            if v == CLOSE:
                closed = True
                subpaths.append((verts, dirs, closed))
                verts, dirs, closed = [start], [], False
                verts = None
                cur = start
        prev_cmd = cmd
        i += n
    if verts is not None and len(verts) > 1:
        subpaths.append((verts, dirs, closed))
    # A path ending in a lone moveto ends at that vertex (SVG 2 paths: a marker is drawn on
    # every vertex "even if moveto commands follow each other"): the subpath before it ends
    # on a mid vertex, as in resvg and Chrome, and the end marker goes on the moveto.
    trailing = tuple(verts[0]) if verts is not None and len(verts) == 1 and subpaths else None

    out = []
    ang = []
    for k, (verts, dirs, closed) in enumerate(subpaths):
        if closed and (k < len(subpaths) - 1 or trailing):
            # the vertex a closepath returns to gets no mid marker (resvg skips ClosePath
            # segments); only the path's very last one is kept, as the end marker
            verts = verts[:-1]
        # fill zero-length segments' directions from neighbours
        filled = list(dirs)
        last = None
        for j, d in enumerate(filled):
            if d is None and last is not None:
                filled[j] = (last, last)
            elif d is not None:
                last = d[1]
        nxt = None
        for j in range(len(filled) - 1, -1, -1):
            if filled[j] is None and nxt is not None:
                filled[j] = (nxt, nxt)
            elif filled[j] is not None:
                nxt = filled[j][0]
        filled = [d or ((1.0, 0.0), (1.0, 0.0)) for d in filled]
        ang = [(math.degrees(math.atan2(a[1], a[0])), math.degrees(math.atan2(b[1], b[0])))
               for a, b in filled]
        for j, (x, y) in enumerate(verts):
            if not ang:
                a_in = a_out = 0.0
            elif j == 0:
                a_out = ang[0][0]
                a_in = ang[-1][1] if closed else a_out
            elif j == len(verts) - 1 and j == len(ang):
                a_in = ang[-1][1]
                a_out = ang[0][0] if closed else a_in
            else:
                a_in, a_out = ang[j - 1][1], ang[j][0]
            out.append([x, y, a_in, a_out, "mid"])
    if trailing and ang:
        # a moveto is no segment: the path's direction there is the one at the end of the
        # last segment (SVG 2 path directionality)
        out.append([*trailing, ang[-1][1], ang[-1][1], "mid"])
    if out:
        out[0][4] = "start"
        out[-1][4] = "end"
    return [tuple(v) for v in out]

