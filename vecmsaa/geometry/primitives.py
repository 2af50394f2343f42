"""Paths → Loop–Blinn primitives: the straight-edge part plus one curve primitive per curve piece.

Every curve segment is split into *pieces*. A piece contributes its chord (b0 → b_last) to the
straight-edge polygon, and a curve primitive describing the *lens* between the chord and the
curve. A sample's winding number is

    winding(polygon with chords) + Σ_lenses wsign · [sample inside the lens]

and a sample is inside a lens when it is on the lens side of the chord (tested with exactly the
arithmetic the scan converter uses for that chord, so the two never disagree), on the inner side
of the piece's end tangents (cubics and conics), and on the inner side of the curve according to the
Loop–Blinn implicit function: k² − l·m for quadratics and conics, k³ − l·m for cubics, with
(k, l, m) affine in pixel coordinates. A conic (rational quadratic with weight w, the exact form
of an elliptical arc) has k = τ1 / 2w, l = τ0, m = τ2 in the barycentric coordinates τ of its
control triangle: its points have τ ∝ ((1 − t)², 2w·t(1 − t), t²), so τ1² = 4w²·τ0·τ2 exactly
on the curve; w = 1 is the parabola (a plain quadratic: the same code, the same lens).

Cubics are classified as in Loop & Blinn (serpentine, loop, cusp, cusp at infinity, quadratic,
line), split at inflections and at the double point of a loop, and further until each piece
turns by at most 90° and bulges at most ``max_sagitta`` pixels from its chord (thin lenses keep
the per-sample work on edge pixels). Numerically hopeless pieces fall back to quadratics.

Everything here runs in numba over flat arrays for a whole batch of paths at once.
"""
from __future__ import annotations

import math
from itertools import accumulate
from operator import itemgetter

import numpy as np
from ..jit import njit

from ..scene.bounds import _conic_weight
from ..scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD

# -- curve primitive record layout (float64 row) ----------------------------------------------
P_KIND = 0          # 0 quadratic or conic (f = k² − l·m), 1 cubic (f = k³ − l·m)
P_SIGMA = 1         # inside the lens ⟺ sigma · f < 0
P_WSIGN = 2         # winding added to samples inside the lens
P_OX, P_OY, P_INVS = 3, 4, 5   # f is evaluated at X = (x − ox)·invs, Y = (y − oy)·invs
P_K, P_L, P_M = 6, 9, 12       # (a, b, c) of k, l, m = a·X + b·Y + c
P_CHORD = 15        # x_top, y_top, x_bot, y_bot (sorted by y, exactly as the edge is scanned)
P_RIGHT = 19        # 1: lens at x ≥ x_chord(y) (horizontal chord: at y ≥ y_chord); 0: other side
P_T1, P_T2 = 20, 23  # tangent half-planes a·x + b·y + c ≥ 0 (cubics, conics); (0, 0, 1) = none
P_BBOX = 26         # x0, y0, x1, y1
P_CTRL = 30         # up to 4 control points (x, y), for the per-row x-range of the lens
P_NCTRL = 38
PRIM_FIELDS = 39

KIND_QUAD = 0
KIND_CUBIC = 1

#: a curve that deviates less than this from its chord (pixels) is drawn as its chord
LINE_EPS = 1.0 / 1024.0
#: cubic → quadratic fallback tolerance (pixels)
QUAD_FALLBACK_TOL = 1.0 / 128.0
MAX_PIECES = 4096
#: halvings of a conic or cubic at most (2¹² pieces): a bigger bulge (absurd coordinates)
#: keeps a thicker lens, which is still exact, instead of exploding in count
MAX_DEPTH = 12
#: segments a curve is flattened into at most
MAX_SEGMENTS = 65536
#: the limits above for a curve reaching beyond the canvas, where only the pieces that meet
#: it are split (primitives._outside): a circle 1e8 px across is cut to the flatness asked
#: for where it crosses the image, in a few dozen pieces
CULLED_MAX_DEPTH = 30
CULLED_MAX_PIECES = 1 << 24


# -- growable output buffers --------------------------------------------------------------------
@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _grow(arr, n):
    if n < arr.shape[0]:
        return arr
    new = np.empty((arr.shape[0] * 2 + 16, arr.shape[1]), dtype=arr.dtype)
    # one flat loop (LLVM makes it a memcpy): a slice assignment compiles to far more code,
    # and a loop over rows and columns to ~700 instructions in every kernel that grows
    src = arr.reshape(arr.size)
    dst = new.reshape(new.size)
    for k in range(n * arr.shape[1]):
        dst[k] = src[k]
    return new


@njit(cache=True, inline="always")
def _no_edge(x0, y0, x1, y1):
    """Whether the line (x0, y0) - (x1, y1) is no edge for the scan converters: a point, or a
    horizontal line on a row boundary (an integer y). A horizontal edge adds no winding
    anywhere; it only splits the samples of the pixels it lies in, above it and below, and
    the sample rows of pixel row floor(y) all lie at or below y = floor(y): the row's samples
    are all on one side of it, so the scan marked its pixels dirty for nothing (a uniform
    dirty pixel is drawn with its span's arithmetic: scan.sweep_rows), and the exact-area
    kernel adds nothing for any horizontal line. A hairline's staircase is nearly a third
    such lines (scan converters: docs/bench.md, session 34). (inf is an integer here: a row
    no strip has.)"""
    return y0 == y1 and (x0 == x1 or np.floor(y0) == y0)


@njit(cache=True, inline="always")
def _append_edge(edges, ne, x0, y0, x1, y1):
    """Edge ne of ``edges`` (grown if need be), unless it is a point. (Inlined in numba's IR
    into _push_edge and _push_line: as a call, its array arguments' reference counts cost a
    map's batch a third more time.)"""
    if _no_edge(x0, y0, x1, y1):
        return edges, ne
    # horizontal edges cross no scanline but still split a pixel's samples: keep them (but
    # those on a row boundary: _no_edge)
    edges = _grow(edges, ne)
    edges[ne, 0] = x0
    edges[ne, 1] = y0
    edges[ne, 2] = x1
    edges[ne, 3] = y1
    return edges, ne + 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _push_edge(edges, ne, x0, y0, x1, y1):
    return _append_edge(edges, ne, x0, y0, x1, y1)


# -- culling: geometry outside the canvas ----------------------------------------------------
#: device pixels the culling rect (build_batch's ``clip``) reaches beyond the canvas it stands
#: for: more than a sample's distance from its pixel, and more than the rounding of a chord's
#: crossing with a sample row at any sane coordinate
CULL_MARGIN = 2.0
#: rows of build_batch's outputs copied out of a room at least twice their size (see there)
SMALL_COPY_ROWS = 256
#: no canvas: nothing is culled (build_batch's ``clip`` for callers that draw anywhere)
NO_CULL = np.array([-np.inf, -np.inf, np.inf, np.inf])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _outside(q, n, clip):
    """Whether the convex hull of the points q[:n] misses the rect ``clip`` (x0, y0, x1, y1,
    margin included): the rect's sides or a line through two of the points separate them
    (the hull's edges are among those lines: the separating axis test of two convex
    polygons). A curve piece lies in its control points' hull, and so does the lens between
    it and its chord: drawn as its chord alone, the piece changes the winding number only
    inside the hull, where no sample is. False for NaN and for NO_CULL."""
    cx0, cy0, cx1, cy1 = clip[0], clip[1], clip[2], clip[3]
    if not (cx0 > -np.inf):
        return False
    xmin = xmax = q[0, 0]
    ymin = ymax = q[0, 1]
    for k in range(1, n):
        xmin = min(xmin, q[k, 0])
        xmax = max(xmax, q[k, 0])
        ymin = min(ymin, q[k, 1])
        ymax = max(ymax, q[k, 1])
    if xmax < cx0 or xmin > cx1 or ymax < cy0 or ymin > cy1:
        return True
    if not (xmin <= xmax and ymin <= ymax):
        return False
    # rounding of the side values: relative to the largest coordinate in play (1e-12 of it,
    # a millionth of a pixel at a million pixels), on top of the margin
    big = max(max(abs(xmin), abs(xmax)), max(abs(ymin), abs(ymax)))
    big = max(big, max(max(abs(cx0), abs(cx1)), max(abs(cy0), abs(cy1))))
    for i in range(n):
        px, py = q[i, 0], q[i, 1]
        for j in range(i + 1, n):
            nx, ny = py - q[j, 1], q[j, 0] - px
            if nx == 0.0 and ny == 0.0:
                continue
            lo = hi = 0.0
            for k in range(n):
                s = nx * (q[k, 0] - px) + ny * (q[k, 1] - py)
                lo = min(lo, s)
                hi = max(hi, s)
            if lo < 0.0 and hi > 0.0:
                continue        # points on both sides: not an edge of the hull
            # the rect's extent along the normal, from p_i
            ax0, ax1 = nx * (cx0 - px), nx * (cx1 - px)
            ay0, ay1 = ny * (cy0 - py), ny * (cy1 - py)
            rmin = min(ax0, ax1) + min(ay0, ay1)
            rmax = max(ax0, ax1) + max(ay0, ay1)
            slack = 1e-12 * big * (abs(nx) + abs(ny))
            if (hi <= 0.0 and rmin > slack) or (lo >= 0.0 and rmax < -slack):
                return True
    return False


@njit(cache=True, inline="always")
def _adds_winding(x0, y0, x1, y1, top, bottom, right):
    """Whether the edge can add winding to a sample of the rect from ``top`` to ``bottom``
    left of ``right``: one wholly above, below or right of it adds none (the scan converters
    count crossings left of a sample in its own row); one left of it still counts. (Scalars
    only: an array argument costs a reference count per call, here per edge of a map.)"""
    return not ((y0 < top and y1 < top) or (y0 > bottom and y1 > bottom) or
                (x0 > right and x1 > right))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _push_line(edges, ne, x0, y0, x1, y1, top, bottom, right):
    """_push_edge of an edge that can add winding to a sample of the rect (_adds_winding)."""
    if not _adds_winding(x0, y0, x1, y1, top, bottom, right):
        return edges, ne
    return _append_edge(edges, ne, x0, y0, x1, y1)


@njit(cache=True, inline="always")
def _store_line(edges, ne, x0, y0, x1, y1, top, bottom, right):
    """_push_line, the edge written here where the room holds it (nearly always: build_batch
    reserves two edges a point). Inlined in numba's IR into the builders' loops over a path's
    lines: the call to _push_line costs the reference counts of the array it takes and
    returns, per edge (a third of the batch's build for 20,000 circles' hairline strokes)."""
    if _no_edge(x0, y0, x1, y1):
        return edges, ne
    if ne < edges.shape[0] and _adds_winding(x0, y0, x1, y1, top, bottom, right):
        edges[ne, 0] = x0
        edges[ne, 1] = y0
        edges[ne, 2] = x1
        edges[ne, 3] = y1
        return edges, ne + 1
    return _push_line(edges, ne, x0, y0, x1, y1, top, bottom, right)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _push_visible(edges, ne, x0, y0, x1, y1, clip):
    """_push_line with the rect ``clip``."""
    return _push_line(edges, ne, x0, y0, x1, y1, clip[1], clip[3], clip[2])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _block(i, n):
    """The largest power of two b with i a multiple of b and i + b <= n (i < n): the aligned
    runs of pieces i .. i + b - 1 that the uniform splitters below try to cull at once."""
    b = 1
    while i % (2 * b) == 0 and i + 2 * b <= n:
        b *= 2
    return b


# -- Bézier helpers -----------------------------------------------------------------------------
@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _quad_point(x0, y0, x1, y1, x2, y2, t):
    mt = 1.0 - t
    return (mt * mt * x0 + 2 * mt * t * x1 + t * t * x2,
            mt * mt * y0 + 2 * mt * t * y1 + t * t * y2)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_point(c, t):
    mt = 1.0 - t
    a, b, cc, d = mt * mt * mt, 3 * mt * mt * t, 3 * mt * t * t, t * t * t
    return (a * c[0, 0] + b * c[1, 0] + cc * c[2, 0] + d * c[3, 0],
            a * c[0, 1] + b * c[1, 1] + cc * c[2, 1] + d * c[3, 1])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_sub(out, c, ta, tb):
    """Control points of the cubic restricted to [ta, tb] (blossoming), into ``out`` (4 x 2,
    not ``c``): one buffer for all of a cubic's pieces, not an allocation per piece."""
    for k in range(2):
        p0, p1, p2, p3 = c[0, k], c[1, k], c[2, k], c[3, k]
        for r in range(4):
            # the polar form at (u, v, w) = (ta, ta, ta), (ta, ta, tb), (ta, tb, tb), (tb, tb, tb):
            # de Casteljau with three parameters
            u = ta if r < 3 else tb
            v = ta if r < 2 else tb
            w = ta if r < 1 else tb
            a0 = p0 + (p1 - p0) * u
            a1 = p1 + (p2 - p1) * u
            a2 = p2 + (p3 - p2) * u
            b0 = a0 + (a1 - a0) * v
            b1 = a1 + (a2 - a1) * v
            out[r, k] = b0 + (b1 - b0) * w
    # the ends must be bit-identical to the parent's so pieces join without cracks
    if ta == 0.0:
        out[0, 0], out[0, 1] = c[0, 0], c[0, 1]
    if tb == 1.0:
        out[3, 0], out[3, 1] = c[3, 0], c[3, 1]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _dist_to_line(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    ln = math.hypot(dx, dy)
    if ln == 0.0:
        return math.hypot(px - ax, py - ay)
    return abs((px - ax) * dy - (py - ay) * dx) / ln


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _bulge(c):
    """max(_dist_to_line(c[1], chord), _dist_to_line(c[2], chord)) for the chord c[0] → c[3],
    the same arithmetic with the chord's length taken once (hypot is a tenth of the batch
    builder's time)."""
    ax, ay = c[0, 0], c[0, 1]
    dx, dy = c[3, 0] - ax, c[3, 1] - ay
    ln = math.hypot(dx, dy)
    if ln == 0.0:
        return max(math.hypot(c[1, 0] - ax, c[1, 1] - ay), math.hypot(c[2, 0] - ax, c[2, 1] - ay))
    return max(abs((c[1, 0] - ax) * dy - (c[1, 1] - ay) * dx) / ln,
               abs((c[2, 0] - ax) * dy - (c[2, 1] - ay) * dx) / ln)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _within(q, n, clip):
    """Whether the points q[:n] lie in ``clip``: then no part of the curve can be culled and
    the splitters run as they do without a rect (most curves of a drawing)."""
    for k in range(n):
        if not (clip[0] <= q[k, 0] <= clip[2] and clip[1] <= q[k, 1] <= clip[3]):
            return False
    return True


@njit(cache=True, inline="always")
def _quad_part(x0, y0, x1, y1, x2, y2, ta, tb):
    """The control points of the quadratic's part ta..tb (ends as _quad_point gives them,
    the curve's own at t = 0 and 1; the middle one by blossoming), as six numbers."""
    ax, ay = _quad_point(x0, y0, x1, y1, x2, y2, ta)
    bx, by = _quad_point(x0, y0, x1, y1, x2, y2, tb)
    if ta == 0.0:
        ax, ay = x0, y0
    if tb == 1.0:
        bx, by = x2, y2
    mt_a, mt_b = 1.0 - ta, 1.0 - tb
    return (ax, ay, mt_a * mt_b * x0 + (mt_a * tb + ta * mt_b) * x1 + ta * tb * x2,
            mt_a * mt_b * y0 + (mt_a * tb + ta * mt_b) * y1 + ta * tb * y2, bx, by)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _quad_hull(q, x0, y0, x1, y1, x2, y2, ta, tb):
    """_quad_part into q (3, 2)."""
    q[0, 0], q[0, 1], q[1, 0], q[1, 1], q[2, 0], q[2, 1] = _quad_part(x0, y0, x1, y1, x2, y2,
                                                                      ta, tb)


@njit(cache=True, inline="always")
def _quad_run_outside(q, x0, y0, x1, y1, x2, y2, i, n, clip):
    """Of the quadratic cut into n uniform pieces, the longest aligned run from piece i
    (_block, then halves of it) whose part misses ``clip`` (_outside), that part's control
    points left in q; 0 when piece i's own part does not miss it. (Pieces i .. n - 1 end at
    (i + b) / n, exactly 1.0 for the last.) Inlined: called once a piece, and a call with
    array arguments costs their reference counts (a crossing curve's flattening took 15% more
    time with a plain call)."""
    b = _block(i, n)
    while b > 0:
        _quad_hull(q, x0, y0, x1, y1, x2, y2, i / n, (i + b) / n)
        if _outside(q, 3, clip):
            return b
        b //= 2
    return 0


@njit(cache=True, inline="always")
def _cubic_run_outside(q, c, i, n, clip):
    """_quad_run_outside of the cubic c (its part's four control points left in q)."""
    b = _block(i, n)
    while b > 0:
        _cubic_sub(q, c, i / n, (i + b) / n)
        if _outside(q, 4, clip):
            return b
        b //= 2
    return 0


# -- flattening (analytic / reference modes) ----------------------------------------------------
@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _flatten_quad(edges, ne, x0, y0, x1, y1, x2, y2, tol, clip, q):
    dd = math.hypot(x0 - 2 * x1 + x2, y0 - 2 * y1 + y2)
    n = int(math.ceil(math.sqrt(dd / (4.0 * tol)))) if dd > 0 else 1
    q[0, 0], q[0, 1], q[1, 0], q[1, 1], q[2, 0], q[2, 1] = x0, y0, x1, y1, x2, y2
    cull = not _within(q, 3, clip)
    n = max(1, min(n, CULLED_MAX_PIECES if cull else MAX_SEGMENTS))
    px, py = x0, y0
    i = 0
    while i < n:
        # a run of segments whose part of the curve misses the canvas: one edge (_outside)
        b = _quad_run_outside(q, x0, y0, x1, y1, x2, y2, i, n, clip) if cull else 0
        if b > 0:
            edges, ne = _push_visible(edges, ne, px, py, q[2, 0], q[2, 1], clip)
            px, py = q[2, 0], q[2, 1]
            i += b
            continue
        i += 1
        qx, qy = _quad_point(x0, y0, x1, y1, x2, y2, i / n)
        if i == n:
            qx, qy = x2, y2
        edges, ne = _push_edge(edges, ne, px, py, qx, qy)
        px, py = qx, qy
    return edges, ne


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _flatten_cubic(edges, ne, c, tol, clip, q):
    m = max(math.hypot(c[0, 0] - 2 * c[1, 0] + c[2, 0], c[0, 1] - 2 * c[1, 1] + c[2, 1]),
            math.hypot(c[1, 0] - 2 * c[2, 0] + c[3, 0], c[1, 1] - 2 * c[2, 1] + c[3, 1]))
    n = int(math.ceil(math.sqrt(3.0 * m / (4.0 * tol)))) if m > 0 else 1
    cull = not _within(c, 4, clip)
    n = max(1, min(n, CULLED_MAX_PIECES if cull else MAX_SEGMENTS))
    px, py = c[0, 0], c[0, 1]
    i = 0
    while i < n:
        # a run of segments whose part of the curve misses the canvas: one edge (_outside)
        b = _cubic_run_outside(q, c, i, n, clip) if cull else 0
        if b > 0:
            # (the part's end as the segments' own ends are computed: no crack between them)
            qx, qy = _cubic_point(c, (i + b) / n)
            if i + b == n:
                qx, qy = c[3, 0], c[3, 1]
            edges, ne = _push_visible(edges, ne, px, py, qx, qy, clip)
            px, py = qx, qy
            i += b
            continue
        i += 1
        qx, qy = _cubic_point(c, i / n)
        if i == n:
            qx, qy = c[3, 0], c[3, 1]
        edges, ne = _push_edge(edges, ne, px, py, qx, qy)
        px, py = qx, qy
    return edges, ne


# -- curve primitives -----------------------------------------------------------------------------
@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _set_lens(prims, nc, nctrl, sx, sy, t0x, t0y, t1x, t1y, n0=-1.0, n1=-1.0):
    """Everything of the lens primitive prims[nc] but its implicit function and its ``nctrl``
    control points (the caller has stored them: no array of them per piece; and the row
    indexed, not taken as a view, which would cost its reference counts): bounding
    box, winding sign, the chord (first to last control point) sorted by y (as the scan
    converter sees it) with the side the lens lies on, judged from the point (sx, sy) known to
    be inside the lens, and the tangent half-planes through the ends along t0 and t1 (left at
    (0, 0, 1), none, for a zero tangent). ``n0``, ``n1``: the tangents' lengths where the
    caller has taken them (a cubic piece's refinement does), else negative."""
    x0 = prims[nc, P_CTRL]
    y0 = prims[nc, P_CTRL + 1]
    bx0, by0, bx1, by1 = x0, y0, x0, y0
    for i in range(nctrl):
        bx0 = min(bx0, prims[nc, P_CTRL + 2 * i])
        by0 = min(by0, prims[nc, P_CTRL + 2 * i + 1])
        bx1 = max(bx1, prims[nc, P_CTRL + 2 * i])
        by1 = max(by1, prims[nc, P_CTRL + 2 * i + 1])
    prims[nc, P_NCTRL] = nctrl
    prims[nc, P_BBOX] = bx0
    prims[nc, P_BBOX + 1] = by0
    prims[nc, P_BBOX + 2] = bx1
    prims[nc, P_BBOX + 3] = by1
    # shoelace sign of the control polygon = orientation of the lens loop (curve, chord back);
    # with y down and +1 for downward edges left of a sample, a positive area winds −1.
    area = 0.0
    for i in range(nctrl):
        j = (i + 1) % nctrl
        area += prims[nc, P_CTRL + 2 * i] * prims[nc, P_CTRL + 2 * j + 1] - \
            prims[nc, P_CTRL + 2 * j] * prims[nc, P_CTRL + 2 * i + 1]
    prims[nc, P_WSIGN] = -1.0 if area > 0 else 1.0
    # the chord
    x1, y1 = prims[nc, P_CTRL + 2 * nctrl - 2], prims[nc, P_CTRL + 2 * nctrl - 1]
    if y0 < y1 or (y0 == y1 and x0 <= x1):
        xt, yt, xb, yb = x0, y0, x1, y1
    else:
        xt, yt, xb, yb = x1, y1, x0, y0
    prims[nc, P_CHORD] = xt
    prims[nc, P_CHORD + 1] = yt
    prims[nc, P_CHORD + 2] = xb
    prims[nc, P_CHORD + 3] = yb
    if yt == yb:
        prims[nc, P_RIGHT] = 1.0 if sy >= yt else 0.0
    else:
        dxdy = (xb - xt) / (yb - yt)
        prims[nc, P_RIGHT] = 1.0 if sx >= xt + (sy - yt) * dxdy else 0.0
    # the tangent half-planes a·x + b·y + c ≥ 0, oriented so (sx, sy) is inside
    for e in range(2):
        base = P_T1 if e == 0 else P_T2
        px, py, dx, dy, ln = (x0, y0, t0x, t0y, n0) if e == 0 else (x1, y1, t1x, t1y, n1)
        prims[nc, base] = 0.0
        prims[nc, base + 1] = 0.0
        prims[nc, base + 2] = 1.0
        if ln < 0.0:
            ln = math.hypot(dx, dy)
        if ln == 0.0:
            continue
        a, b = -dy / ln, dx / ln
        c = -(a * px + b * py)
        if a * sx + b * sy + c < 0:
            a, b, c = -a, -b, -c
        prims[nc, base] = a
        prims[nc, base + 1] = b
        prims[nc, base + 2] = c - 1e-9 * (abs(c) + 1.0)


@njit(cache=True, inline="always")
def _quad_split(x0, y0, x1, y1, x2, y2, max_sagitta):
    """The pieces a quadratic is cut into (at least 1; not yet capped), or 0 where it is its
    chord alone (straight within LINE_EPS, or not finite)."""
    dev = 0.25 * math.hypot(x0 - 2 * x1 + x2, y0 - 2 * y1 + y2)
    if dev < LINE_EPS or not (math.isfinite(dev)):
        return 0
    # splitting into k pieces divides the bulge by k²
    return int(math.ceil(math.sqrt(dev / max_sagitta)))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_quad(edges, ne, prims, nc, x0, y0, x1, y1, x2, y2, max_sagitta, clip, q):
    k = _quad_split(x0, y0, x1, y1, x2, y2, max_sagitta)
    if k == 0:
        edges, ne = _push_edge(edges, ne, x0, y0, x2, y2)
        return edges, ne, prims, nc
    q[0, 0], q[0, 1], q[1, 0], q[1, 1], q[2, 0], q[2, 1] = x0, y0, x1, y1, x2, y2
    cull = not _within(q, 3, clip)
    k = max(1, min(k, CULLED_MAX_PIECES if cull else MAX_PIECES))
    i = 0
    while i < k:
        # a run of pieces whose part of the curve misses the canvas: its chord (_outside)
        b = _quad_run_outside(q, x0, y0, x1, y1, x2, y2, i, k, clip) if cull else 0
        if b > 0:
            edges, ne = _push_visible(edges, ne, q[0, 0], q[0, 1], q[2, 0], q[2, 1], clip)
            i += b
            continue
        _quad_hull(q, x0, y0, x1, y1, x2, y2, i / k, (i + 1) / k)
        # a quadratic is the conic of weight 1
        edges, ne, prims, nc = _emit_conic_piece(edges, ne, prims, nc, q[0, 0], q[0, 1],
                                                 q[1, 0], q[1, 1], q[2, 0], q[2, 1], 1.0)
        i += 1
    return edges, ne, prims, nc


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_conic_piece(edges, ne, prims, nc, x0, y0, x1, y1, x2, y2, w):
    """Chord edge plus lens primitive for one conic piece (k² − l·m, lens where f < 0)."""
    edges = _grow(edges, ne)
    prims = _grow(prims, nc)
    ne, nc = _conic_piece_at(edges, ne, prims, nc, x0, y0, x1, y1, x2, y2, w)
    return edges, ne, prims, nc


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _conic_piece_at(edges, ne, prims, nc, x0, y0, x1, y1, x2, y2, w):
    """_emit_conic_piece where the rooms hold its edge and lens (ne and nc below their rows):
    the new (ne, nc), no array returned (build_batch's in-place quadratics)."""
    if not _no_edge(x0, y0, x2, y2):
        edges[ne, 0], edges[ne, 1], edges[ne, 2], edges[ne, 3] = x0, y0, x2, y2
        ne += 1
    s = max(math.hypot(x1 - x0, y1 - y0), math.hypot(x2 - x0, y2 - y0))
    if s == 0.0:
        return ne, nc
    inv = 1.0 / s
    X1, Y1 = (x1 - x0) * inv, (y1 - y0) * inv
    X2, Y2 = (x2 - x0) * inv, (y2 - y0) * inv
    det = X1 * Y2 - X2 * Y1
    if abs(det) < 1e-12:
        return ne, nc
    for j in range(PRIM_FIELDS):
        prims[nc, j] = 0.0
    prims[nc, P_KIND] = KIND_QUAD
    prims[nc, P_SIGMA] = 1.0
    prims[nc, P_OX], prims[nc, P_OY], prims[nc, P_INVS] = x0, y0, inv
    # barycentric coordinates in the frame (b0 at the origin): τ1 = (X·Y2 − Y·X2) / det,
    # τ2 = (X1·Y − Y1·X) / det, τ0 = 1 − τ1 − τ2; k = τ1 / 2w, l = τ0, m = τ2
    h = 0.5 / (w * det)
    prims[nc, P_K] = Y2 * h
    prims[nc, P_K + 1] = -X2 * h
    prims[nc, P_L] = (Y1 - Y2) / det
    prims[nc, P_L + 1] = (X2 - X1) / det
    prims[nc, P_L + 2] = 1.0
    prims[nc, P_M] = -Y1 / det
    prims[nc, P_M + 1] = X1 / det
    prims[nc, P_CTRL], prims[nc, P_CTRL + 1] = x0, y0
    prims[nc, P_CTRL + 2], prims[nc, P_CTRL + 3] = x1, y1
    prims[nc, P_CTRL + 4], prims[nc, P_CTRL + 5] = x2, y2
    # inside: half-way between the curve's midpoint and the chord's
    lam = 0.5 * w / (1.0 + w)
    cx, cy = 0.5 * (x0 + x2), 0.5 * (y0 + y2)
    qx, qy = cx + lam * (x1 - cx), cy + lam * (y1 - cy)
    # the end tangents (b0 → b1, b1 → b2) close the control triangle around the lens: the
    # one-evaluation modes (alpha, a2c) then give no coverage beyond the lens's ends, where the
    # whole ellipse's distance says "near the curve"
    _set_lens(prims, nc, 3, qx, qy, x1 - x0, y1 - y0, x2 - x1, y2 - y1)
    return ne, nc + 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _conic_pieces(edges, ne, prims, nc, x0, y0, x1, y1, x2, y2, w, tol, flatten, clip, q):
    """A conic halved until each piece bulges at most ``tol`` from its chord, then each piece
    as its chord (``flatten``: the exact-area modes) or as chord plus lens. A piece's bulge is
    exactly dist(b1, chord) · w / (1 + w), at t = ½; halving gives weight √((1 + w) / 2).
    At most MAX_DEPTH halvings (absurd coordinates keep thicker lenses, which are still
    exact). A piece whose control triangle misses ``clip`` is its chord, not halved further
    (_outside): a circle a million pixels across around the canvas is a few dozen pieces,
    and one crossing it is halved up to CULLED_MAX_DEPTH times where it does."""
    q[0, 0], q[0, 1], q[1, 0], q[1, 1], q[2, 0], q[2, 1] = x0, y0, x1, y1, x2, y2
    cull = not _within(q, 3, clip)
    most = CULLED_MAX_DEPTH if cull else MAX_DEPTH
    stack = np.empty((32, 7))
    top = 0
    st = stack[0]
    st[0], st[1], st[2], st[3], st[4], st[5], st[6] = x0, y0, x1, y1, x2, y2, w
    depth = np.zeros(32, np.int64)
    while top >= 0:
        st = stack[top]
        ax, ay, bx, by, ex, ey, wt = st[0], st[1], st[2], st[3], st[4], st[5], st[6]
        d = depth[top]
        top -= 1
        if cull:
            q[0, 0], q[0, 1], q[1, 0], q[1, 1], q[2, 0], q[2, 1] = ax, ay, bx, by, ex, ey
            if _outside(q, 3, clip):
                edges, ne = _push_visible(edges, ne, ax, ay, ex, ey, clip)
                continue
        bulge = _dist_to_line(bx, by, ax, ay, ex, ey) * wt / (1.0 + wt)
        if not math.isfinite(bulge):
            continue
        if bulge < LINE_EPS or (flatten and bulge <= tol):
            edges, ne = _push_edge(edges, ne, ax, ay, ex, ey)
            continue
        if bulge > tol and d < most:
            # de Casteljau on (b0, w·b1, b2) at ½, renormalised to end weights 1
            s = 1.0 / (1.0 + wt)
            qx, qy = (ax + wt * bx) * s, (ay + wt * by) * s
            rx, ry = (ex + wt * bx) * s, (ey + wt * by) * s
            mx, my = 0.5 * (qx + rx), 0.5 * (qy + ry)
            w2 = math.sqrt(0.5 * (1.0 + wt))
            top += 1
            st = stack[top]
            st[0], st[1], st[2], st[3], st[4], st[5], st[6] = mx, my, rx, ry, ex, ey, w2
            depth[top] = d + 1
            top += 1
            st = stack[top]
            st[0], st[1], st[2], st[3], st[4], st[5], st[6] = ax, ay, qx, qy, mx, my, w2
            depth[top] = d + 1
            continue
        if flatten:
            edges, ne = _push_edge(edges, ne, ax, ay, ex, ey)
        else:
            edges, ne, prims, nc = _emit_conic_piece(edges, ne, prims, nc, ax, ay, bx, by,
                                                     ex, ey, wt)
    return edges, ne, prims, nc


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_as_quads(edges, ne, prims, nc, c, max_sagitta, clip, q):
    """Fallback: approximate a cubic by quadratics within QUAD_FALLBACK_TOL (runs of them
    whose part of the cubic misses ``clip``: its chord)."""
    err = math.sqrt(3.0) / 36.0 * math.hypot(c[3, 0] - 3 * c[2, 0] + 3 * c[1, 0] - c[0, 0],
                                             c[3, 1] - 3 * c[2, 1] + 3 * c[1, 1] - c[0, 1])
    n = int(math.ceil((err / QUAD_FALLBACK_TOL) ** (1.0 / 3.0))) if err > 0 else 1
    n = max(1, min(n, MAX_PIECES))
    s = np.empty((4, 2))
    cull = not _within(c, 4, clip)
    i = 0
    while i < n:
        b = _cubic_run_outside(s, c, i, n, clip) if cull else 0
        if b > 0:
            edges, ne = _push_visible(edges, ne, s[0, 0], s[0, 1], s[3, 0], s[3, 1], clip)
            i += b
            continue
        _cubic_sub(s, c, i / n, (i + 1) / n)
        qx = (3.0 * (s[1, 0] + s[2, 0]) - s[0, 0] - s[3, 0]) * 0.25
        qy = (3.0 * (s[1, 1] + s[2, 1]) - s[0, 1] - s[3, 1]) * 0.25
        edges, ne, prims, nc = _emit_quad(edges, ne, prims, nc, s[0, 0], s[0, 1], qx, qy,
                                          s[3, 0], s[3, 1], max_sagitta, clip, q)
        i += 1
    return edges, ne, prims, nc


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _klm_serpentine(klm, ls, lt, ms, mt):
    """klm at the control points of a serpentine or cusp with roots ls/lt, ms/mt."""
    klm[0, 0], klm[0, 1], klm[0, 2] = ls * ms, ls * ls * ls, ms * ms * ms
    klm[1, 0] = (3.0 * ls * ms - ls * mt - lt * ms) / 3.0
    klm[1, 1] = ls * ls * (ls - lt)
    klm[1, 2] = ms * ms * (ms - mt)
    klm[2, 0] = (lt * (mt - 2.0 * ms) + ls * (3.0 * ms - 2.0 * mt)) / 3.0
    klm[2, 1] = (lt - ls) * (lt - ls) * ls
    klm[2, 2] = (mt - ms) * (mt - ms) * ms
    klm[3, 0] = (lt - ls) * (mt - ms)
    klm[3, 1] = -((lt - ls) * (lt - ls) * (lt - ls))
    klm[3, 2] = -((mt - ms) * (mt - ms) * (mt - ms))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _klm_loop(klm, ls, lt, ms, mt):
    """klm at the control points of a loop with double point parameters ls/lt, ms/mt."""
    klm[0, 0], klm[0, 1], klm[0, 2] = ls * ms, ls * ls * ms, ls * ms * ms
    klm[1, 0] = (-ls * mt - lt * ms + 3.0 * ls * ms) / 3.0
    klm[1, 1] = -ls * (ls * (mt - 3.0 * ms) + 2.0 * lt * ms) / 3.0
    klm[1, 2] = -ms * (ls * (2.0 * mt - 3.0 * ms) + lt * ms) / 3.0
    klm[2, 0] = (lt * (mt - 2.0 * ms) + ls * (3.0 * ms - 2.0 * mt)) / 3.0
    klm[2, 1] = (lt - ls) * (ls * (2.0 * mt - 3.0 * ms) + lt * ms) / 3.0
    klm[2, 2] = (mt - ms) * (ls * (mt - 3.0 * ms) + 2.0 * lt * ms) / 3.0
    klm[3, 0] = (lt - ls) * (mt - ms)
    klm[3, 1] = -((lt - ls) * (lt - ls)) * (mt - ms)
    klm[3, 2] = -(lt - ls) * ((mt - ms) * (mt - ms))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _klm_cusp_at_infinity(klm, ls, lt):
    klm[0, 0], klm[0, 1], klm[0, 2] = ls, ls * ls * ls, 1.0
    klm[1, 0], klm[1, 1], klm[1, 2] = ls - lt / 3.0, ls * ls * (ls - lt), 1.0
    klm[2, 0], klm[2, 1], klm[2, 2] = ls - 2.0 * lt / 3.0, (ls - lt) * (ls - lt) * ls, 1.0
    klm[3, 0], klm[3, 1], klm[3, 2] = ls - lt, (ls - lt) * (ls - lt) * (ls - lt), 1.0


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def classify_cubic(X, klm, splits):
    """Loop–Blinn classification of a cubic given in a normalised frame (4 x 2 array).

    Returns the kind, 0 serpentine, 1 loop, 2 cusp, 3 cusp at infinity, 4 quadratic, 5
    line/point, and sets ``klm`` (4, 3) at the control points and the 2 ``splits``
    parameters, inflections (serpentine, cusp) or the double point (loop), or -1.
    Powers are products: the same bits as numba's ``**`` (by squaring), without compiling it.
    (Scalars and small helpers: one long straight-line kernel compiles in superlinear time.)
    """
    x0, y0, x1, y1 = X[0, 0], X[0, 1], X[1, 0], X[1, 1]
    x2, y2, x3, y3 = X[2, 0], X[2, 1], X[3, 0], X[3, 1]
    # the determinants of Loop & Blinn with homogeneous coordinates (x, y, 1), the products
    # with 1 left out (exact)
    a1 = x0 * (y3 - y2) - y0 * (x3 - x2) + (x3 * y2 - y3 * x2)
    a2 = x1 * (y0 - y3) - y1 * (x0 - x3) + (x0 * y3 - y0 * x3)
    a3 = x2 * (y1 - y0) - y2 * (x1 - x0) + (x1 * y0 - y1 * x0)
    d1 = a1 - 2.0 * a2 + 3.0 * a3
    d2 = -a2 + 3.0 * a3
    d3 = 3.0 * a3
    dn = math.sqrt(d1 * d1 + d2 * d2 + d3 * d3)
    for i in range(4):
        klm[i, 0] = klm[i, 1] = klm[i, 2] = 0.0
    splits[0] = -1.0
    splits[1] = -1.0
    eps = 1e-9
    if dn < eps:
        return 5
    d1 /= dn
    d2 /= dn
    d3 /= dn
    disc = 3.0 * d2 * d2 - 4.0 * d1 * d3
    if abs(d1) > eps:
        if disc >= -1e-12:
            kind = 0 if disc > 1e-12 else 2
            sq = math.sqrt(max(0.0, 3.0 * disc))
            ls, lt = 3.0 * d2 - sq, 6.0 * d1
            ms, mt = 3.0 * d2 + sq, 6.0 * d1
            _klm_serpentine(klm, ls, lt, ms, mt)
        else:
            kind = 1
            sq = math.sqrt(-disc)
            ls, lt = d2 - sq, 2.0 * d1
            ms, mt = d2 + sq, 2.0 * d1
            _klm_loop(klm, ls, lt, ms, mt)
        splits[0] = ls / lt
        splits[1] = ms / mt
        return kind
    if abs(d2) > eps:
        ls, lt = d3, 3.0 * d2
        _klm_cusp_at_infinity(klm, ls, lt)
        splits[0] = ls / lt
        return 3
    if abs(d3) > eps:
        return 4
    return 5


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _end_tangents(c):
    """Directions of a cubic at its ends; a control point on its end point defers to the next."""
    t0x, t0y = c[1, 0] - c[0, 0], c[1, 1] - c[0, 1]
    if t0x == 0.0 and t0y == 0.0:
        t0x, t0y = c[2, 0] - c[0, 0], c[2, 1] - c[0, 1]
    t1x, t1y = c[3, 0] - c[2, 0], c[3, 1] - c[2, 1]
    if t1x == 0.0 and t1y == 0.0:
        t1x, t1y = c[3, 0] - c[1, 0], c[3, 1] - c[1, 1]
    return t0x, t0y, t1x, t1y


@njit(cache=True, inline="always")
def _eval_implicit(prim, x, y):
    """f and its gradient (in pixel units) at (x, y)."""
    inv = prim[P_INVS]
    X = (x - prim[P_OX]) * inv
    Y = (y - prim[P_OY]) * inv
    k = prim[P_K] * X + prim[P_K + 1] * Y + prim[P_K + 2]
    l = prim[P_L] * X + prim[P_L + 1] * Y + prim[P_L + 2]
    m = prim[P_M] * X + prim[P_M + 1] * Y + prim[P_M + 2]
    if prim[P_KIND] == KIND_QUAD:
        f = k * k - l * m
        gx = 2.0 * k * prim[P_K] - l * prim[P_M] - m * prim[P_L]
        gy = 2.0 * k * prim[P_K + 1] - l * prim[P_M + 1] - m * prim[P_L + 1]
    else:
        f = k * k * k - l * m
        gx = 3.0 * k * k * prim[P_K] - l * prim[P_M] - m * prim[P_L]
        gy = 3.0 * k * k * prim[P_K + 1] - l * prim[P_M + 1] - m * prim[P_L + 1]
    return f, gx * inv, gy * inv


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _implicit(prim, x, y):
    """f of _eval_implicit (the same arithmetic) for the batch builder, which needs no
    gradient: an inlined copy of _eval_implicit costs compile time, and here it runs once or
    twice per curve piece, not per sample."""
    inv = prim[P_INVS]
    X = (x - prim[P_OX]) * inv
    Y = (y - prim[P_OY]) * inv
    k = prim[P_K] * X + prim[P_K + 1] * Y + prim[P_K + 2]
    l = prim[P_L] * X + prim[P_L + 1] * Y + prim[P_L + 2]
    m = prim[P_M] * X + prim[P_M + 1] * Y + prim[P_M + 2]
    if prim[P_KIND] == KIND_QUAD:
        return k * k - l * m
    return k * k * k - l * m


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_cubic_piece(edges, ne, prims, nc, c, M, ox, oy, inv, t0x, t0y, t1x, t1y, n0, n1):
    """Chord plus lens for a convex cubic piece sharing the parent's implicit (k, l, m); its
    end tangents (_end_tangents) and their lengths as the refinement took them."""
    prims = _grow(prims, nc)
    prim = prims[nc]
    for j in range(PRIM_FIELDS):
        prim[j] = 0.0
    prim[P_KIND] = KIND_CUBIC
    prim[P_OX], prim[P_OY], prim[P_INVS] = ox, oy, inv
    for j in range(3):
        prim[P_K + j] = M[j, 0]
        prim[P_L + j] = M[j, 1]
        prim[P_M + j] = M[j, 2]
    mx, my = _cubic_point(c, 0.5)
    # q: half-way from the curve's midpoint to the chord's, inside the (convex) lens; its
    # mirror image through the curve point lies outside. The implicit function must change
    # sign between them, or the frame is numerically unusable (caller falls back to quads).
    qx = 0.5 * (mx + 0.5 * (c[0, 0] + c[3, 0]))
    qy = 0.5 * (my + 0.5 * (c[0, 1] + c[3, 1]))
    f = _implicit(prim, qx, qy)
    f_out = _implicit(prim, 2.0 * mx - qx, 2.0 * my - qy)
    if not (math.isfinite(f) and math.isfinite(f_out)) or f == 0.0 or (f < 0) == (f_out < 0):
        return edges, ne, prims, nc, False
    prim[P_SIGMA] = 1.0 if f < 0 else -1.0
    for i in range(4):
        prim[P_CTRL + 2 * i] = c[i, 0]
        prim[P_CTRL + 2 * i + 1] = c[i, 1]
    _set_lens(prims, nc, 4, qx, qy, t0x, t0y, t1x, t1y, n0, n1)
    edges, ne = _push_edge(edges, ne, c[0, 0], c[0, 1], c[3, 0], c[3, 1])
    return edges, ne, prims, nc + 1, True


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _affine_fit(X, V, M, tmp):
    """Least-squares M (3, 3, set here) with [x y 1] · M ≈ V for the 4 points X (4, 2) and
    values V (4, 3); ``tmp``: (4, 4) scratch.

    Centred columns and Gram–Schmidt on the two that remain: as stable as a QR solve, and no
    np.linalg, whose first use makes numba import scipy (~0.1 s of every start-up). Collinear
    points give NaN, which the caller's residual test rejects."""
    xm = 0.25 * (X[0, 0] + X[1, 0] + X[2, 0] + X[3, 0])
    ym = 0.25 * (X[0, 1] + X[1, 1] + X[2, 1] + X[3, 1])
    # scalar loops over the 4 rows, not array expressions: those cost seconds of compile time
    xc, yc, q1, y2 = tmp[0], tmp[1], tmp[2], tmp[3]
    n1 = 0.0
    for i in range(4):
        xc[i] = X[i, 0] - xm
        yc[i] = X[i, 1] - ym
        n1 += xc[i] * xc[i]
    for i in range(3):
        for j in range(3):
            M[i, j] = np.nan
    n1 = math.sqrt(n1)
    if n1 == 0.0:
        return
    beta = 0.0
    for i in range(4):
        q1[i] = xc[i] / n1
        beta += q1[i] * yc[i]
    n2 = 0.0
    for i in range(4):
        y2[i] = yc[i] - beta * q1[i]
        n2 += y2[i] * y2[i]
    n2 = math.sqrt(n2)
    if n2 == 0.0:
        return
    for j in range(3):
        vm = 0.25 * (V[0, j] + V[1, j] + V[2, j] + V[3, j])
        c1 = 0.0
        c2 = 0.0
        for i in range(4):
            c1 += q1[i] * V[i, j]
            c2 += (y2[i] / n2) * V[i, j]
        M[1, j] = c2 / n2
        M[0, j] = c1 / n1 - c2 * beta / (n1 * n2)
        M[2, j] = vm - M[0, j] * xm - M[1, j] * ym


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_cubic(edges, ne, prims, nc, c, max_sagitta, w1, w2, w3, w4, clip, q):
    """Chords and lenses of a cubic. w1..w4: scratch, allocated once by build_batch for all of a
    batch's cubics (eight small arrays allocated per cubic: 6.7 -> 5.8 ms of the tiger's batch
    at 2048 px; rows of 2-d arrays, not reshaped slices of one: a reshape is a call). Pieces
    whose control polygon misses ``clip`` are their chords, not split further (_outside);
    ``q``: (4, 2) scratch of the quadratics' tests."""
    # bulge of the control polygon over the chord; degenerate → chord or nothing
    dev = _bulge(c)
    if not math.isfinite(dev):
        return edges, ne, prims, nc
    cull = not _within(c, 4, clip)
    most = CULLED_MAX_DEPTH if cull else MAX_DEPTH
    if cull and _outside(c, 4, clip):
        edges, ne = _push_visible(edges, ne, c[0, 0], c[0, 1], c[3, 0], c[3, 1], clip)
        return edges, ne, prims, nc
    if dev < LINE_EPS:
        edges, ne = _push_edge(edges, ne, c[0, 0], c[0, 1], c[3, 0], c[3, 1])
        return edges, ne, prims, nc
    ox, oy = c[0, 0], c[0, 1]
    s = 0.0
    for i in range(1, 4):
        s = max(s, math.hypot(c[i, 0] - ox, c[i, 1] - oy))
    inv = 1.0 / s
    splits, ts = w1[0:2], w1[2:6]
    X, sub = w2[0:4], w2[4:8]
    klm, M, stack = w3[0:4], w3[4:7], w3[7:71]
    tmp = w4
    for i in range(4):
        X[i, 0] = (c[i, 0] - ox) * inv
        X[i, 1] = (c[i, 1] - oy) * inv
    kind = classify_cubic(X, klm, splits)
    if kind == 5:
        edges, ne = _push_edge(edges, ne, c[0, 0], c[0, 1], c[3, 0], c[3, 1])
        return edges, ne, prims, nc
    if kind == 4:
        qx = 0.25 * (3.0 * (c[1, 0] + c[2, 0]) - c[0, 0] - c[3, 0])
        qy = 0.25 * (3.0 * (c[1, 1] + c[2, 1]) - c[0, 1] - c[3, 1])
        return _emit_quad(edges, ne, prims, nc, c[0, 0], c[0, 1], qx, qy, c[3, 0], c[3, 1],
                          max_sagitta, clip, q)
    # k, l, m are affine in the frame: solve [X Y 1] · M = klm (4 equations, 3 unknowns each)
    _affine_fit(X, klm, M, tmp)
    resid = 0.0
    scale = 0.0
    for i in range(4):
        for j in range(3):
            r = X[i, 0] * M[0, j] + X[i, 1] * M[1, j] + M[2, j] - klm[i, j]
            resid = max(resid, abs(r))
            scale = max(scale, abs(klm[i, j]))
    if not (resid <= 1e-7 * max(scale, 1e-300)):
        return _cubic_as_quads(edges, ne, prims, nc, c, max_sagitta, clip, q)
    # parameter intervals: split at inflections / the double point inside (0, 1)
    nts = 0
    ts[nts] = 0.0
    nts += 1
    s0, s1 = splits[0], splits[1]
    if s1 < s0:     # (np.sort would put a NaN last; a NaN is never taken here either way)
        s0, s1 = s1, s0
    for t in (s0, s1):
        if 1e-6 < t < 1.0 - 1e-6 and t - ts[nts - 1] > 1e-6:
            ts[nts] = t
            nts += 1
    ts[nts] = 1.0
    nts += 1
    # refine each interval until it turns ≤ 90° and bulges ≤ max_sagitta (explicit stack)
    max_turn_cos = 0.0  # cos 90°
    for iv in range(nts - 1):
        top = 0
        stack[0, 0], stack[0, 1], stack[0, 2] = ts[iv], ts[iv + 1], 0
        while top >= 0:
            ta, tb, depth = stack[top, 0], stack[top, 1], stack[top, 2]
            top -= 1
            _cubic_sub(sub, c, ta, tb)
            if cull and _outside(sub, 4, clip):
                edges, ne = _push_visible(edges, ne, sub[0, 0], sub[0, 1], sub[3, 0], sub[3, 1],
                                          clip)
                continue
            bulge = _bulge(sub)
            split = 0.75 * bulge > max_sagitta
            # the end tangents and their lengths, once taken (_emit_cubic_piece's too)
            t0x = t0y = t1x = t1y = n1 = 0.0
            n0 = -1.0
            if not split:
                # does the piece turn by more than acos(max_turn_cos) between its end tangents?
                t0x, t0y, t1x, t1y = _end_tangents(sub)
                n0, n1 = math.hypot(t0x, t0y), math.hypot(t1x, t1y)
                # on a piece that turns by at most 90° the chord lies between the end
                # tangents; a loop turns by over 270° with its end tangents less than 90°
                # apart, and its chord (none, between the double point's parameters) does not
                chx, chy = sub[3, 0] - sub[0, 0], sub[3, 1] - sub[0, 1]
                split = n0 == 0.0 or n1 == 0.0 or \
                    (t0x * t1x + t0y * t1y) / (n0 * n1) < max_turn_cos or \
                    chx * t0x + chy * t0y <= 0.0 or chx * t1x + chy * t1y <= 0.0
            if bulge * 0.75 < LINE_EPS and math.hypot(sub[3, 0] - sub[0, 0], sub[3, 1] - sub[0, 1]) > 0:
                edges, ne = _push_edge(edges, ne, sub[0, 0], sub[0, 1], sub[3, 0], sub[3, 1])
                continue
            # at most MAX_DEPTH halvings (CULLED_MAX_DEPTH beyond the canvas); a bigger bulge
            # (absurd coordinates) keeps a thicker lens, which is still exact, instead of
            # exploding in count
            if split and depth < most and top < 60:
                tm = 0.5 * (ta + tb)
                top += 1
                stack[top, 0], stack[top, 1], stack[top, 2] = tm, tb, depth + 1
                top += 1
                stack[top, 0], stack[top, 1], stack[top, 2] = ta, tm, depth + 1
                continue
            if n0 < 0.0:
                t0x, t0y, t1x, t1y = _end_tangents(sub)
                n0, n1 = math.hypot(t0x, t0y), math.hypot(t1x, t1y)
            edges, ne, prims, nc, ok = _emit_cubic_piece(edges, ne, prims, nc, sub, M, ox, oy,
                                                         inv, t0x, t0y, t1x, t1y, n0, n1)
            if not ok:
                edges, ne, prims, nc = _cubic_as_quads(edges, ne, prims, nc, sub, max_sagitta,
                                                       clip, q)
    return edges, ne, prims, nc


@njit(cache=True, inline="always")
def _build_scratch(canvas):
    """The builders' work arrays for _build_verbs (a cubic's points, the splitter's and the
    lens maker's rooms, a hull) and the culling rect: ``canvas`` CULL_MARGIN wider all round."""
    clip = np.empty(4)
    for k in range(4):
        clip[k] = canvas[k] - CULL_MARGIN if k < 2 else canvas[k] + CULL_MARGIN
    return (np.empty((4, 2)), np.empty(6), np.empty((8, 2)), np.empty((71, 3)),
            np.empty((4, 4)), np.empty((4, 2)), clip)


@njit(cache=True, inline="always")
def _build_verbs(verbs, points, v0, v1, pi, sx, sy, cx, cy, open_, edges, ne, prims, nc,
                 flatten_tol, max_sagitta, clip, lo, hi, c, w1, w2, w3, w4, q):
    """build_batch's work on the verbs v0 .. v1 - 1 from point pi, in the state (subpath
    start sx, sy; current point cx, cy; whether a subpath is open) the verbs before left:
    edges and (flatten_tol 0) lenses appended, but for curves whose control points lie
    wholly below ``lo`` or above ``hi`` (build_run's rows; -inf, inf: none left out).
    Returns the arrays, their counts and the state after them (an open subpath left open).
    Inlined into both builders: their loops over many small paths would pay a call, and
    its arrays' reference counts, per path."""
    left, top, right, bottom = clip[0], clip[1], clip[2], clip[3]
    sample = not flatten_tol > 0
    vi = v0
    while vi < v1:
        # the moves, lines and closes, and the quadratics of the sample modes that lie in the
        # culling rect, in a loop that assigns no array: numba copies an array variable
        # assigned in a loop (a reference count up and down) on every pass, which cost a
        # staircase's batch more than its edges (docs/bench.md, session 35), and a glyph's
        # quadratics as much again as their lenses (session 36). What finds no room leaves
        # the loop to the code below, which grows the arrays; so do the other curves.
        room = edges.shape[0]
        proom = prims.shape[0]
        while vi < v1:
            v = verbs[vi]
            if v == LINE:
                x, y = points[pi, 0], points[pi, 1]
                if not _no_edge(cx, cy, x, y) and _adds_winding(cx, cy, x, y, top, bottom,
                                                                 right):
                    if ne >= room:
                        break
                    edges[ne, 0], edges[ne, 1], edges[ne, 2], edges[ne, 3] = cx, cy, x, y
                    ne += 1
                cx, cy = x, y
                pi += 1
            elif v == QUAD and sample:
                # _emit_quad's edges and lenses of a quadratic wholly in the rect (none of
                # its pieces is culled), written in place
                x1, y1 = points[pi, 0], points[pi, 1]
                x2, y2 = points[pi + 1, 0], points[pi + 1, 1]
                if not _misses_rows(cy, y1, y2, y2, lo, hi):
                    k = _quad_split(cx, cy, x1, y1, x2, y2, max_sagitta)
                    if k == 0:
                        if not _no_edge(cx, cy, x2, y2):
                            if ne >= room:
                                break
                            edges[ne, 0], edges[ne, 1] = cx, cy
                            edges[ne, 2], edges[ne, 3] = x2, y2
                            ne += 1
                    else:
                        if not (left <= cx <= right and top <= cy <= bottom and
                                left <= x1 <= right and top <= y1 <= bottom and
                                left <= x2 <= right and top <= y2 <= bottom):
                            break
                        k = max(1, min(k, MAX_PIECES))
                        if ne + k > room or nc + k > proom:
                            break
                        for i in range(k):
                            ax, ay, bx, by, ex, ey = _quad_part(cx, cy, x1, y1, x2, y2, i / k,
                                                                (i + 1) / k)
                            ne, nc = _conic_piece_at(edges, ne, prims, nc, ax, ay, bx, by,
                                                     ex, ey, 1.0)
                cx, cy = x2, y2
                pi += 2
            elif v == MOVE or v == CLOSE:
                # the open subpath closed (a move starts the next one)
                if open_ and not _no_edge(cx, cy, sx, sy) and \
                        _adds_winding(cx, cy, sx, sy, top, bottom, right):
                    if ne >= room:
                        break
                    edges[ne, 0], edges[ne, 1], edges[ne, 2], edges[ne, 3] = cx, cy, sx, sy
                    ne += 1
                if v == MOVE:
                    sx, sy = points[pi, 0], points[pi, 1]
                    pi += 1
                    open_ = True
                else:
                    open_ = False
                cx, cy = sx, sy
            elif v == QUAD or v == CUBIC or v == CONIC:
                break
            vi += 1
        if vi >= v1:
            break
        v = verbs[vi]
        if v == LINE or v == MOVE or v == CLOSE:
            edges = _grow(edges, ne)
            continue
        if v == QUAD:
            x1, y1 = points[pi, 0], points[pi, 1]
            x2, y2 = points[pi + 1, 0], points[pi + 1, 1]
            if flatten_tol > 0:
                edges, ne = _flatten_quad(edges, ne, cx, cy, x1, y1, x2, y2, flatten_tol,
                                          clip, q)
            elif not _misses_rows(cy, y1, y2, y2, lo, hi):
                edges, ne, prims, nc = _emit_quad(edges, ne, prims, nc, cx, cy, x1, y1,
                                                  x2, y2, max_sagitta, clip, q)
            cx, cy = x2, y2
            pi += 2
        elif v == CUBIC:
            c[0, 0], c[0, 1] = cx, cy
            for k in range(3):
                c[k + 1, 0] = points[pi + k, 0]
                c[k + 1, 1] = points[pi + k, 1]
            if flatten_tol > 0:
                edges, ne = _flatten_cubic(edges, ne, c, flatten_tol, clip, q)
            elif not _misses_rows(c[0, 1], c[1, 1], c[2, 1], c[3, 1], lo, hi):
                edges, ne, prims, nc = _emit_cubic(edges, ne, prims, nc, c, max_sagitta,
                                                   w1, w2, w3, w4, clip, q)
            cx, cy = c[3, 0], c[3, 1]
            pi += 3
        elif v == CONIC:
            x1, y1 = points[pi, 0], points[pi, 1]
            x2, y2 = points[pi + 2, 0], points[pi + 2, 1]
            flatten = flatten_tol > 0
            if flatten or not _misses_rows(cy, y1, y2, y2, lo, hi):
                w = _conic_weight(cx, cy, x1, y1, points[pi + 1, 0], points[pi + 1, 1], x2,
                                  y2)
                edges, ne, prims, nc = _conic_pieces(
                    edges, ne, prims, nc, cx, cy, x1, y1, x2, y2, w,
                    flatten_tol if flatten else max_sagitta, flatten, clip, q)
            cx, cy = x2, y2
            pi += 3
        vi += 1
    return edges, ne, prims, nc, sx, sy, cx, cy, open_


@njit(cache=True, nogil=True)   # a batch is built in parts on threads (render.build_in_parts)
def build_batch(verbs, points, verb_off, pt_off, flatten_tol, max_sagitta, canvas):
    """Straight edges and curve primitives for a batch of paths.

    verbs/points are the concatenated arrays of all paths; path i owns verbs
    verb_off[i]:verb_off[i+1] and points pt_off[i]:pt_off[i+1]. With flatten_tol > 0 curves
    are flattened into edges (analytic and reference modes) and no primitives are made.
    ``canvas``: (x0, y0, x1, y1), the device rect the edges are drawn in (the image, or a
    filter's region), or NO_CULL: geometry outside it (CULL_MARGIN beyond) costs next to
    nothing, whatever its size: curve pieces there are their chords, edges above, below or
    right of it are left out (see _outside, _push_visible); no sample inside sees a change.
    Returns (edges (E, 4), edge_off (P+1), prims (C, PRIM_FIELDS), prim_off (P+1)).
    """
    npaths = verb_off.shape[0] - 1
    # room for two edges a point and five lenses a curve, which a batch rarely outgrows at
    # 2048 px (the tiger: 19.8k edges, 15.6k lenses from 15.8k points and 3.8k curves): each
    # _grow copies everything so far into fresh pages, and pages never written cost no memory
    n = 0
    for p in range(npaths):
        n += pt_off[p + 1] - pt_off[p]
    curves = 0
    for vi in range(verb_off[0], verb_off[npaths]):
        v = verbs[vi]
        if v == CUBIC or v == QUAD or v == CONIC:
            curves += 1
    edges = np.empty((max(16, 2 * n), 4))
    prims = np.empty((max(16, 5 * curves), PRIM_FIELDS))
    edge_off = np.zeros(npaths + 1, dtype=np.int64)
    prim_off = np.zeros(npaths + 1, dtype=np.int64)
    # not the literal 0: numba would compile every helper called with it once more, for
    # Literal[int](0) (a second specialisation of the whole batch builder)
    ne = np.int64(0)
    nc = np.int64(0)
    c, w1, w2, w3, w4, q, clip = _build_scratch(canvas)
    top, bottom, right = clip[1], clip[3], clip[2]
    for p in range(npaths):
        edges, ne, prims, nc, sx, sy, cx, cy, open_ = _build_verbs(
            verbs, points, verb_off[p], verb_off[p + 1], pt_off[p], 0.0, 0.0, 0.0, 0.0, False,
            edges, ne, prims, nc, flatten_tol, max_sagitta, clip, -np.inf, np.inf,
            c, w1, w2, w3, w4, q)
        if open_:
            edges, ne = _push_line(edges, ne, cx, cy, sx, sy, top, bottom, right)
        edge_off[p + 1] = ne
        prim_off[p + 1] = nc
    # views, not copies: a copy is as many fresh pages again (the arrays live for one render;
    # a large array's room never written takes no memory). But a small copy where less than
    # half the room was taken (culled curves take next to none of the room their points
    # reserve): a small array's room is all memory, and 50,000 marker copies of a huge
    # circle held 7 KB each of unused lens rows
    if 2 * ne < edges.shape[0] and ne <= SMALL_COPY_ROWS:
        edges = edges[:ne].copy()
    if 2 * nc < prims.shape[0] and nc <= SMALL_COPY_ROWS:
        prims = prims[:nc].copy()
    return edges[:ne], edge_off, prims[:nc], prim_off


#: verbs of a path a run of path_runs holds, about (see build_run): a run's edges and lenses are
#: a few MB at most, built, drawn and let go one after another
RUN_VERBS = 4096


@njit(cache=True, nogil=True)
def path_runs(verbs, points, run_verbs):
    """Cut one path (all of verbs and points) into runs of about ``run_verbs`` verbs for
    build_run: (R, 3) int64 (first verb, first point, subpath open) and (R, 6) float64 (sx,
    sy, cx, cy: the subpath's start and the current point where the run begins, then the
    lowest and highest y of the run's points and of those two, NaN where one is NaN). The
    state is what build_batch's loop holds at that verb, so the runs' edges and lenses are
    its own, in its order."""
    nv = verbs.shape[0]
    nr = max(1, (nv + run_verbs - 1) // run_verbs)
    ints = np.zeros((nr, 3), np.int64)
    flts = np.zeros((nr, 6))
    sx = sy = cx = cy = 0.0
    open_ = False
    pi = 0
    r = -1
    for vi in range(nv):
        if vi % run_verbs == 0:
            r += 1
            ints[r, 0], ints[r, 1], ints[r, 2] = vi, pi, 1 if open_ else 0
            flts[r, 0], flts[r, 1], flts[r, 2], flts[r, 3] = sx, sy, cx, cy
            flts[r, 4] = min(sy, cy)
            flts[r, 5] = max(sy, cy)
            if not (sy == sy and cy == cy):
                flts[r, 4] = flts[r, 5] = np.nan
        v = verbs[vi]
        k = 1 if v == MOVE or v == LINE else 2 if v == QUAD else 3 if v == CUBIC or \
            v == CONIC else 0
        for j in range(k):
            y = points[pi + j, 1]
            if not (y == y):
                flts[r, 4] = flts[r, 5] = np.nan
            elif flts[r, 4] == flts[r, 4]:
                flts[r, 4] = min(flts[r, 4], y)
                flts[r, 5] = max(flts[r, 5], y)
        if v == MOVE:
            sx, sy = points[pi, 0], points[pi, 1]
            cx, cy = sx, sy
            open_ = True
        elif v == CLOSE:
            cx, cy = sx, sy
            open_ = False
        elif k > 0:
            cx, cy = points[pi + k - 1, 0], points[pi + k - 1, 1]
        pi += k
    if r < 0:
        ints[0, 0], ints[0, 1] = nv, pi
        flts[0, 4], flts[0, 5] = np.inf, -np.inf
    return ints, flts


@njit(cache=True, inline="always")
def _misses_rows(a, b, c, d, lo, hi):
    """Whether the y values a..d (a curve's control points') all lie below ``lo`` or all
    above ``hi`` (False for a NaN)."""
    return (a < lo and b < lo and c < lo and d < lo) or (a > hi and b > hi and c > hi and d > hi)


@njit(cache=True, nogil=True)
def build_run(verbs, points, run, state, last, max_sagitta, canvas, ylo, yhi):
    """build_batch's edges and curve primitives (sample modes) of the verbs run[0] .. run[1] - 1
    of one path, from point run[2], continuing from ``state`` (sx, sy, cx, cy, open: what
    path_runs gives): the same calls in the same order, so the same rows, but for the curves
    whose control points lie wholly above ``ylo`` or below ``yhi`` (CULL_MARGIN beyond),
    which are left out: their chords and lenses lie in their control points' hull (a
    hopeless cubic's quadratics within QUAD_FALLBACK_TOL of it), so they add no winding to a
    sample of the rows ylo .. yhi and mark none of their pixels. ``last``: the run ends the
    path (its open subpath is closed, as build_batch closes it). Returns (edges, prims)."""
    v0, v1, pi = run[0], run[1], run[2]
    n = 0
    curves = 0
    for vi in range(v0, v1):
        v = verbs[vi]
        if v == CUBIC or v == QUAD or v == CONIC:
            curves += 1
            n += 3
        else:
            n += 1
    edges = np.empty((max(16, 2 * n), 4))
    prims = np.empty((max(16, 5 * curves), PRIM_FIELDS))
    ne = np.int64(0)
    nc = np.int64(0)
    c, w1, w2, w3, w4, q, clip = _build_scratch(canvas)
    top, bottom, right = clip[1], clip[3], clip[2]
    lo, hi = ylo - CULL_MARGIN, yhi + CULL_MARGIN
    edges, ne, prims, nc, sx, sy, cx, cy, open_ = _build_verbs(
        verbs, points, v0, v1, pi, state[0], state[1], state[2], state[3], state[4] != 0.0,
        edges, ne, prims, nc, 0.0, max_sagitta, clip, lo, hi, c, w1, w2, w3, w4, q)
    if last and open_:
        edges, ne = _push_line(edges, ne, cx, cy, sx, sy, top, bottom, right)
    return edges[:ne], prims[:nc]


# (numpy's concatenate, not a join of the arrays' bytes, which was faster but has numpy keep
# a buffer record on each array it exports for as long as the array lives: 64 bytes a path's
# verbs or points, 15 MB held by the scene of 120,000 fills)
_FIRST, _SECOND = itemgetter(0), itemgetter(1)


def batch_arrays(paths):
    """Concatenate the verb/point arrays of several Paths for :func:`build_batch`: (verbs,
    points, verb offsets, point offsets). From each path's stored arrays, with no property
    call or copy per path (map data batches tens of thousands of paths)."""
    # (the stored arrays where a path has them: a _freeze call per path costs more)
    arrays = [p._arrays or p._freeze() for p in paths]
    n = len(arrays)
    if n == 1:
        # (one path, as a layer's clip or a marker's filtered content gives: the same arrays
        # in a third of the time the general case's dozen small numpy calls take)
        verbs, pts = arrays[0]
        return (verbs.astype(np.uint8), pts.reshape(-1, 2).astype(np.float64),
                np.array([0, len(verbs)], np.int64), np.array([0, len(pts)], np.int64))
    if n == 0:
        none = np.zeros(1, np.int64)
        return np.zeros(0, np.uint8), np.zeros((0, 2)), none, none.copy()
    verbs = list(map(_FIRST, arrays))
    pts = list(map(_SECOND, arrays))
    if n <= 16:
        # (a few paths, a small layer's: the offsets summed in Python, one numpy call each)
        verb_off = np.array(list(accumulate(map(len, verbs), initial=0)), np.int64)
        pt_off = np.array(list(accumulate(map(len, pts), initial=0)), np.int64)
    else:
        verb_off = np.zeros(n + 1, dtype=np.int64)
        pt_off = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(list(map(len, verbs)), out=verb_off[1:])
        np.cumsum(list(map(len, pts)), out=pt_off[1:])
    all_verbs = np.concatenate(verbs).astype(np.uint8, copy=False)
    all_pts = np.concatenate(pts).reshape(-1, 2).astype(np.float64, copy=False)
    return all_verbs, all_pts, verb_off, pt_off


@njit(cache=True, nogil=True)
def batch_extents(verbs, points, verb_off, point_off):
    """Per path of a batch (batch_arrays' arrays): whether it can draw something (a verb
    besides MOVE and CLOSE, and every point finite) and its points' box (x0, y0, x1, y1),
    in one pass over the arrays, where numpy took five over the whole batch (a running sum
    of drawing verbs, a finiteness test, two reductions per path, their columns: ~70 ms of
    120,000 small fills). Returns (keep: (P,) bool, box: (P, 4) float64)."""
    P = verb_off.shape[0] - 1
    keep = np.empty(P, np.bool_)
    box = np.empty((P, 4))
    for k in range(P):
        drawing = False
        for v in range(verb_off[k], verb_off[k + 1]):
            if verbs[v] != MOVE and verbs[v] != CLOSE:
                drawing = True
                break
        finite = True
        x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
        for i in range(point_off[k], point_off[k + 1]):
            x, y = points[i, 0], points[i, 1]
            # (NaN compares false: not finite)
            if not (abs(x) < np.inf and abs(y) < np.inf):
                finite = False
            x0, x1 = min(x0, x), max(x1, x)
            y0, y1 = min(y0, y), max(y1, y)
        keep[k] = drawing and finite
        box[k, 0], box[k, 1], box[k, 2], box[k, 3] = x0, y0, x1, y1
    return keep, box


@njit(cache=True, nogil=True)
def gather_runs(ov, op, vo, po, runs, at, verbs, points, voff, poff):
    """Copy the paths ``runs`` of a batch (run r: ov[vo[r]:vo[r + 1]], op[po[r]:po[r + 1]])
    into another's (path at[j] of verbs, points, voff, poff, which has room for run
    runs[j]): a row copy each, where numpy's gathers took index arrays of every row (a
    scatter plot's FillRuns: 4 million verbs and 3 million points, interleaved from the
    circles' and their strokes' batches)."""
    for j in range(runs.shape[0]):
        r, d = runs[j], at[j]
        v0, p0 = vo[r], po[r]
        dv, dp = voff[d], poff[d]
        for i in range(vo[r + 1] - v0):
            verbs[dv + i] = ov[v0 + i]
        for i in range(po[r + 1] - p0):
            points[dp + i, 0] = op[p0 + i, 0]
            points[dp + i, 1] = op[p0 + i, 1]
