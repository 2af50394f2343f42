"""Exact bounding boxes of paths (curves included, not just their control points)."""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from .path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD


def path_bounds(path, matrix=None):
    """Tight bounds (x0, y0, x1, y1) of a path, optionally after a transform; None if empty.

    A conic counts as the cubic Path.without_conics makes of it (within 3e-4 of it)."""
    verbs, pts = path._freeze()
    if len(pts) == 0:
        return None
    if matrix is None:
        return _bounds(verbs, pts, False, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    a, b, c, d, e, f = matrix
    return _bounds(verbs, pts, True, float(a), float(b), float(c), float(d), float(e),
                   float(f))


# One kernel call per path: bounds are asked for one small path at a time (an object bounding
# box per filtered, clipped or masked element, thousands of them), where numpy's per-call
# overhead on arrays of a few points cost 80 µs a path. The arithmetic is that of the numpy
# version this replaced, operation for operation (Path.without_conics' handles, transform.apply,
# the cubic's derivative roots and its value there with pow), so the boxes are the same bits.
@njit(cache=True)
def _bounds(verbs, pts, mapped, a, b, c, d, e, f):
    inf = math.inf
    box = np.array([inf, inf, -inf, -inf])
    cur = np.zeros(2)
    start = np.zeros(2)
    q = np.zeros((4, 2))        # a segment's cubic (mapped)
    i = 0
    for v in verbs:
        if v == MOVE:
            _map(q, 0, pts[i, 0], pts[i, 1], mapped, a, b, c, d, e, f)
            cur[0], cur[1] = q[0, 0], q[0, 1]
            start[0], start[1] = cur[0], cur[1]
            _take(box, cur[0], cur[1])
            i += 1
        elif v == LINE:
            _map(q, 0, pts[i, 0], pts[i, 1], mapped, a, b, c, d, e, f)
            cur[0], cur[1] = q[0, 0], q[0, 1]
            _take(box, cur[0], cur[1])
            i += 1
        elif v == QUAD:
            _map(q, 1, pts[i, 0], pts[i, 1], mapped, a, b, c, d, e, f)
            _map(q, 3, pts[i + 1, 0], pts[i + 1, 1], mapped, a, b, c, d, e, f)
            q[0, 0], q[0, 1] = cur[0], cur[1]
            m1x, m1y = q[1, 0], q[1, 1]
            q[1, 0] = cur[0] + 2 / 3 * (m1x - cur[0])
            q[1, 1] = cur[1] + 2 / 3 * (m1y - cur[1])
            q[2, 0] = q[3, 0] + 2 / 3 * (m1x - q[3, 0])
            q[2, 1] = q[3, 1] + 2 / 3 * (m1y - q[3, 1])
            _cubic_extrema(box, q)
            cur[0], cur[1] = q[3, 0], q[3, 1]
            _take(box, cur[0], cur[1])
            i += 2
        elif v == CUBIC or v == CONIC:
            if v == CUBIC:
                h1x, h1y = pts[i, 0], pts[i, 1]
                h2x, h2y = pts[i + 1, 0], pts[i + 1, 1]
            else:
                # Path.without_conics: from the point before it in the array (b0), b1 at i,
                # the midpoint, b2
                x0, y0 = pts[i - 1, 0], pts[i - 1, 1]
                x1, y1 = pts[i, 0], pts[i, 1]
                x2, y2 = pts[i + 2, 0], pts[i + 2, 1]
                w = _conic_weight(x0, y0, x1, y1, pts[i + 1, 0], pts[i + 1, 1], x2, y2)
                k = 4.0 * w / (3.0 * (1.0 + w))
                h1x, h1y = x0 + k * (x1 - x0), y0 + k * (y1 - y0)
                h2x, h2y = x2 + k * (x1 - x2), y2 + k * (y1 - y2)
            q[0, 0], q[0, 1] = cur[0], cur[1]
            _map(q, 1, h1x, h1y, mapped, a, b, c, d, e, f)
            _map(q, 2, h2x, h2y, mapped, a, b, c, d, e, f)
            _map(q, 3, pts[i + 2, 0], pts[i + 2, 1], mapped, a, b, c, d, e, f)
            _cubic_extrema(box, q)
            cur[0], cur[1] = q[3, 0], q[3, 1]
            _take(box, cur[0], cur[1])
            i += 3
        elif v == CLOSE:
            cur[0], cur[1] = start[0], start[1]
    return (box[0], box[1], box[2], box[3])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _map(q, j, x, y, mapped, a, b, c, d, e, f):
    if mapped:      # transform.apply's arithmetic
        q[j, 0] = a * x + c * y + e
        q[j, 1] = b * x + d * y + f
    else:
        q[j, 0] = x
        q[j, 1] = y


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _take(box, x, y):
    """Widen box by a point; a NaN coordinate makes its side NaN (as numpy's min and max)."""
    if x < box[0] or x != x:
        box[0] = x if box[0] == box[0] else box[0]
    if y < box[1] or y != y:
        box[1] = y if box[1] == box[1] else box[1]
    if x > box[2] or x != x:
        box[2] = x if box[2] == box[2] else box[2]
    if y > box[3] or y != y:
        box[3] = y if box[3] == box[3] else box[3]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _conic_weight(x0, y0, x1, y1, mx, my, x2, y2):
    """scene.path.conic_weight for one conic (its point at t = ½ is (mx, my))."""
    cx, cy = 0.5 * (x0 + x2), 0.5 * (y0 + y2)
    dx, dy = x1 - cx, y1 - cy
    dd = dx * dx + dy * dy
    lam = ((mx - cx) * dx + (my - cy) * dy) / dd if dd > 0 else 0.0
    lam = min(max(lam, 1e-12), 0.5)
    return lam / (1.0 - lam)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_extrema(box, q):
    """Widen box by the cubic q's points at the interior zeros of its derivative, per axis:
    derivative/3 = A t² + B t + C, roots (−B ± √(B² − 4AC)) / 2A, and −C/B where |A| < 1e-12.

    Where |4AC| is tiny beside B² (a cubic that is nearly a quadratic: a raised one is, to
    rounding), the root whose −B and ±√ nearly cancel has lost most of its digits (t = 0.499
    for 0.5, and an extremum 3e-6 of the size short); it is taken as 2C / (−B ∓ √(B² − 4AC))
    instead (the product of the roots is C/A), which is exact to rounding. Below 1e-8 only: a
    root losing fewer digits is still exact to 1e-8 in t, and an extremum's value to its
    square, so other boxes keep the bits they had."""
    for axis in range(2):
        p0, p1, p2, p3 = q[0, axis], q[1, axis], q[2, axis], q[3, axis]
        aa = -p0 + 3 * p1 - 3 * p2 + p3
        bb = 2 * (p0 - 2 * p1 + p2)
        cc = p1 - p0
        disc = bb * bb - 4 * aa * cc
        if disc >= 0 and aa != 0:       # (a zero A: ±inf or NaN, which no t is)
            sq = math.sqrt(disc)
            t1 = (-bb + sq) / (2 * aa)
            t2 = (-bb - sq) / (2 * aa)
            if abs(4 * aa * cc) < 1e-8 * (bb * bb):
                if bb > 0:
                    t1 = 2 * cc / (-bb - sq)
                else:
                    t2 = 2 * cc / (-bb + sq)
            _extremum(box, q, t1)
            _extremum(box, q, t2)
        if abs(aa) < 1e-12 and bb != 0:
            _extremum(box, q, -cc / bb)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _extremum(box, q, t):
    if not (math.isfinite(t) and t > 0 and t < 1):
        return
    mt = 1 - t
    m3 = math.pow(mt, 3.0)
    t3 = math.pow(t, 3.0)
    _take(box, m3 * q[0, 0] + 3 * mt * mt * t * q[1, 0] + 3 * mt * t * t * q[2, 0] + t3 * q[3, 0],
          m3 * q[0, 1] + 3 * mt * mt * t * q[1, 1] + 3 * mt * t * t * q[2, 1] + t3 * q[3, 1])


def union(a, b):
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))
