"""The compiled part of :mod:`vecmsaa.geometry.hairline`: hairline outlines of paths of lines
(map data strokes thousands of them; numpy's per-call costs were ten times the stroke's)."""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from ..scene.path import CLOSE, LINE, MOVE
from .stroke_kernels import _grow, _grow_points


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_row(verbs, pts, cnt, x0, y0, x1, y1, stair_slope, max_steps):
    """Appends the hairline polygon of the device segment (x0, y0)-(x1, y1) (see the module
    hairline): per step of the major axis u a rectangle one pixel thick across it, centred on
    the segment's v at the step's centre, as long as the segment's part of the step; one
    parallelogram for a segment of |slope| below ``stair_slope``, or of more steps than
    ``max_steps`` (per segment: cnt[2] counts a path's steps against max_steps[1]). Returns
    (verbs, pts), grown as needed; cnt: [verbs used, points used, steps counted]."""
    dx, dy = x1 - x0, y1 - y0
    if (dx == 0.0 and dy == 0.0) or not (math.isfinite(x0) and math.isfinite(y0)
                                         and math.isfinite(x1) and math.isfinite(y1)):
        return verbs, pts
    ymaj = abs(dx) <= abs(dy)
    if ymaj:
        u0, v0, u1, v1 = y0, x0, y1, x1
    else:
        u0, v0, u1, v1 = x0, y0, x1, y1
    if u0 > u1:
        u0, u1, v0, v1 = u1, u0, v1, v0
    slope = (v1 - v0) / (u1 - u0)
    first = math.floor(u0)
    steps = math.ceil(u1) - first
    stair = abs(slope) >= stair_slope and steps <= max_steps[0]
    if stair:
        cnt[2] += int(steps)
        stair = cnt[2] <= max_steps[1]
    n = int(steps) if stair else 1
    verbs = _grow(verbs, cnt[0] + 4 * n + 1)
    pts = _grow_points(pts, cnt[1] + 4 * n)
    base = cnt[1]
    for k in range(n):
        if stair:
            col = first + k
            lo, hi = max(u0, col), min(u1, col + 1.0)
            v_lo = v_hi = v0 + slope * (col + 0.5 - u0)
        else:
            lo, hi, v_lo, v_hi = u0, u1, v0, v1
        # the step's top left to right (points 2k, 2k + 1), its bottom in the second half,
        # right to left; y-major polygons mirrored (reversed) to keep one orientation
        for j in range(4):
            if j == 0:
                p, u, v = 2 * k, lo, v_lo - 0.5
            elif j == 1:
                p, u, v = 2 * k + 1, hi, v_hi - 0.5
            elif j == 2:
                p, u, v = 2 * n + 2 * (n - 1 - k), hi, v_hi + 0.5
            else:
                p, u, v = 2 * n + 2 * (n - 1 - k) + 1, lo, v_lo + 0.5
            if ymaj:
                p = 4 * n - 1 - p
                pts[base + p, 0], pts[base + p, 1] = v, u
            else:
                pts[base + p, 0], pts[base + p, 1] = u, v
    verbs[cnt[0]] = MOVE
    for k in range(1, 4 * n):
        verbs[cnt[0] + k] = LINE
    verbs[cnt[0] + 4 * n] = CLOSE
    cnt[0] += 4 * n + 1
    cnt[1] += 4 * n
    return verbs, pts


@njit(cache=True)
def hairline_lines_batch(verbs, points, vstart, pstart, which, m, outset, stair_slope,
                         max_steps):
    """Hairline outlines (hairline.hairline_outline of hairline.hairline_segments) of the
    paths ``which`` of a batch of paths of lines (path i: verbs vstart[i]:vstart[i + 1],
    points pstart[i]:pstart[i + 1]) under the transform m (a, b, c, d, e, f), round and
    square caps lengthening open subpaths' ends by ``outset``. Returns (verbs, points,
    verb offsets, point offsets) of the outlines, one per path of ``which``."""
    a, b, c, d, e, f = m[0], m[1], m[2], m[3], m[4], m[5]
    ov = np.empty(64, np.uint8)
    op = np.empty((64, 2))
    vo = np.empty(len(which) + 1, np.int64)
    po = np.empty(len(which) + 1, np.int64)
    cnt = np.zeros(3, np.int64)
    seg = np.empty((16, 4))
    for w in range(len(which)):
        vo[w], po[w] = cnt[0], cnt[1]
        cnt[2] = 0
        i = which[w]
        ip = pstart[i]
        ns = 0
        have_start = False
        sx = sy = cx = cy = 0.0
        for iv in range(vstart[i], vstart[i + 1] + 1):
            # a subpath ends at a move, a close or the path's end: its segments are drawn
            v = verbs[iv] if iv < vstart[i + 1] else MOVE
            if v == MOVE or v == CLOSE:
                if v == CLOSE and have_start:
                    seg = _grow_points(seg, ns + 1)
                    seg[ns, 0], seg[ns, 1], seg[ns, 2], seg[ns, 3] = cx, cy, sx, sy
                    ns += 1
                    cx, cy = sx, sy
                elif v == MOVE and ns > 0 and outset > 0.0:
                    for end in range(2):    # open: the caps lengthen both ends
                        r = 0 if end == 0 else ns - 1
                        ddx, ddy = seg[r, 2] - seg[r, 0], seg[r, 3] - seg[r, 1]
                        ln = math.sqrt(ddx * ddx + ddy * ddy)
                        sign = -1.0 if end == 0 else 1.0
                        if ln == 0.0:
                            ux, uy = -sign, 0.0
                        else:
                            ux, uy = ddx / ln, ddy / ln
                        k = 0 if end == 0 else 2
                        seg[r, k] += sign * ux * outset
                        seg[r, k + 1] += sign * uy * outset
                for r in range(ns):
                    ov, op = _emit_row(ov, op, cnt, seg[r, 0], seg[r, 1], seg[r, 2],
                                       seg[r, 3], stair_slope, max_steps)
                ns = 0
                if v == MOVE and iv < vstart[i + 1]:
                    x, y = points[ip, 0], points[ip, 1]
                    sx = cx = a * x + c * y + e
                    sy = cy = b * x + d * y + f
                    ip += 1
                    have_start = True
            else:                           # a line
                x, y = points[ip, 0], points[ip, 1]
                nx, ny = a * x + c * y + e, b * x + d * y + f
                ip += 1
                seg = _grow_points(seg, ns + 1)
                seg[ns, 0], seg[ns, 1], seg[ns, 2], seg[ns, 3] = cx, cy, nx, ny
                ns += 1
                cx, cy = nx, ny
    vo[len(which)], po[len(which)] = cnt[0], cnt[1]
    return ov[:cnt[0]], op[:cnt[1]], vo, po


@njit(cache=True)
def hairline_rows(rows, stair_slope, max_steps):
    """The hairline outline (verbs, points) of the device segments ``rows`` (N, 4)."""
    verbs = np.empty(64, np.uint8)
    pts = np.empty((64, 2))
    cnt = np.zeros(3, np.int64)
    for r in range(rows.shape[0]):
        verbs, pts = _emit_row(verbs, pts, cnt, rows[r, 0], rows[r, 1], rows[r, 2], rows[r, 3],
                               stair_slope, max_steps)
    return verbs[:cnt[0]], pts[:cnt[1]]
