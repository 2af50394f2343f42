"""Arc length along paths: where a path is after a given length, and how long it is.

Every segment is measured as a cubic (a line becomes a cubic with its inner control points at
0.33 and 0.66, a quadratic is raised exactly), its length by 24-point Gauss–Legendre
quadrature; the parameter at an arc length is found with kurbo's ITP root finder stopped at
resvg's coarse accuracy (:func:`cubic_param_at`, since the references show where that puts
glyphs). (Stroke dashes are measured otherwise, by chords as tiny-skia measures them: see
geometry/stroke_kernels' dasher.)

The searches are compiled kernels over cubics stored as rows (x0 y0 x1 y1 x2 y2 x3 y3): in
Python, each length is 24 hypotenuses, and a curve cut into thousands of dashes or glyphs
took a second or more.
"""
from __future__ import annotations

import functools
import itertools
import math
from bisect import bisect_left

import numpy as np

from ..jit import njit
from ..scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path


@functools.cache
def gl_nodes() -> np.ndarray:
    """Gauss–Legendre nodes and weights for arc lengths of cubic segments, mapped to [0, 1]
    (24 rows: node, weight), made on first use: numpy.polynomial and the eigenvalues cost
    start-up a render without dashes or text on a path does not need."""
    x, w = np.polynomial.legendre.leggauss(24)
    return np.ascontiguousarray(np.stack([(x + 1) / 2, w / 2], axis=1))


def as_cubic(p0, pts) -> np.ndarray:
    """The segment from ``p0`` through ``pts`` (1 point: a line, 2: a quadratic, 3: a cubic)
    as a cubic's (4, 2) control points, as resvg measures it: a line gets its inner control
    points at 0.33 and 0.66, a quadratic is raised exactly."""
    p0 = np.asarray(p0, dtype=np.float64)
    q = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
    if len(q) == 1:
        return np.array([p0, p0 + (q[0] - p0) * 0.33, p0 + (q[0] - p0) * 0.66, q[0]])
    if len(q) == 2:
        return np.array([p0, p0 + 2 / 3 * (q[0] - p0), q[1] + 2 / 3 * (q[0] - q[1]), q[1]])
    return np.array([p0, q[0], q[1], q[2]])


def cubic_derivative(c, t: float) -> tuple:
    """B'(t) of the cubic ``c``, as (dx, dy)."""
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = c
    v = 1 - t
    p, q, r = 3 * v * v, 6 * t * v, 3 * t * t
    return (p * (x1 - x0) + q * (x2 - x1) + r * (x3 - x2),
            p * (y1 - y0) + q * (y2 - y1) + r * (y3 - y2))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _length_to(c, i, t1, nodes):
    """Arc length of cubic ``i`` of ``c`` (rows x0 y0 x1 y1 x2 y2 x3 y3) from t = 0 to ``t1``,
    by the Gauss–Legendre ``nodes`` (rows: node on [0, 1], weight)."""
    ax, ay = 3 * (c[i, 2] - c[i, 0]), 3 * (c[i, 3] - c[i, 1])
    bx, by = 3 * (c[i, 4] - c[i, 2]), 3 * (c[i, 5] - c[i, 3])
    cx, cy = 3 * (c[i, 6] - c[i, 4]), 3 * (c[i, 7] - c[i, 5])
    total = 0.0
    for j in range(nodes.shape[0]):
        u = nodes[j, 0] * t1
        v = 1 - u
        p, q, r = v * v, 2 * u * v, u * u
        total += nodes[j, 1] * math.hypot(p * ax + q * bx + r * cx, p * ay + q * by + r * cy)
    return total * t1


@njit(cache=True)
def cubic_lengths(c, nodes):
    """Arc lengths of the cubics ``c`` (n x 8: x0 y0 x1 y1 x2 y2 x3 y3)."""
    out = np.empty(c.shape[0])
    for i in range(c.shape[0]):
        out[i] = _length_to(c, i, 1.0, nodes)
    return out


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_velocity(c, t):
    """B'(t) of the cubic row c (x0, y0, ..., x3, y3), as (dx, dy)."""
    v = 1.0 - t
    p, q, r = 3.0 * v * v, 6.0 * t * v, 3.0 * t * t
    return (p * (c[2] - c[0]) + q * (c[4] - c[2]) + r * (c[6] - c[4]),
            p * (c[3] - c[1]) + q * (c[5] - c[3]) + r * (c[7] - c[5]))


#: the finest parameter step cubic_param_at searches to
_FINEST_PARAMETER = 2.0 ** -40


@njit(cache=True)
def cubic_param_at(c, i, total, arc, accuracy, nodes):
    """The parameter where cubic ``i`` of ``c`` (of length ``total``) has run ``arc``, found by
    kurbo's ParamCurveArclen::inv_arclen: an ITP search stopped at ``accuracy`` (in length)."""
    if arc <= 0:
        return 0.0
    if arc >= total:
        return 1.0
    eps = accuracy / total
    if not eps >= _FINEST_PARAMETER:
        # past ~2^-40 the parameter is below the floats' resolution of the length (a text
        # under scale(1e300) asks for 1e-303): the search would never narrow to it
        eps = _FINEST_PARAMETER
    a, b = 0.0, 1.0
    ya, yb = -arc, total - arc
    n_half = max(math.ceil(math.log2((b - a) / eps)) - 1, 0)
    scaled = eps * float(1 << (1 + n_half))
    k1 = 0.2
    while b - a > 2 * eps:
        mid = 0.5 * (a + b)
        r = scaled - 0.5 * (b - a)
        xf = (yb * a - ya * b) / (yb - ya) if yb != ya else mid
        sigma = mid - xf
        delta = k1 * (b - a) ** 2
        xt = xf + math.copysign(delta, sigma) if delta <= abs(mid - xf) else mid
        x = xt if abs(xt - mid) <= r else mid - math.copysign(r, sigma)
        y = _length_to(c, i, x, nodes) - arc
        if y > 0:
            b, yb = x, y
        elif y < 0:
            a, ya = x, y
        else:
            return x
        scaled *= 0.5
    return 0.5 * (a + b)


def cubic_rows(cubics) -> np.ndarray:
    """Cubics' (4, 2) control points as the kernels' rows (n x 8)."""
    return np.ascontiguousarray(np.asarray(cubics, dtype=np.float64).reshape(-1, 8))


class PathWalker:
    """Points and tangents of a path at arc lengths, located the way resvg does.

    resvg turns every segment into a cubic (:func:`as_cubic`) and finds the parameter for an
    arc length with kurbo's ITP root finder stopped at a fixed accuracy (0.5 user units over
    the text's scale). That tolerance moves glyphs by up to a third of a pixel, visibly, so
    the same search is done here.
    """

    def __init__(self, path: Path, scale: float = 1.0):
        self.accuracy = 0.5 / max(scale, 1.0)
        self.cubics = []
        v, p = path.without_conics()._freeze()
        i = 0
        cur = start = None
        for verb in v:
            k = VERB_POINTS[verb]
            q = p[i:i + k]
            i += k
            if verb == MOVE:
                cur = start = q[0]
                continue
            if verb in (LINE, QUAD, CUBIC):
                c = as_cubic(cur, q)
            elif verb == CLOSE and start is not None:
                c = as_cubic(cur, [start])
            else:
                continue
            self.cubics.append(c)
            cur = c[3]
        self.rows = cubic_rows(self.cubics)
        self.lengths = cubic_lengths(self.rows, gl_nodes()).tolist()
        self.length = float(sum(self.lengths))
        # where each segment ends along the path, summed in order (a search per position
        # instead of a walk from the start: a long text on a long path was quadratic)
        self.ends = list(itertools.accumulate(self.lengths))

    def at(self, s):
        """(x, y, tangent angle in degrees) at arc length s, or None off the path: on the
        first segment that holds it (a position where segments meet is on the earlier)."""
        if s < 0:
            return None
        i = bisect_left(self.ends, s)
        start = self.ends[i - 1] if i else 0.0
        if i == len(self.ends) or not start <= s <= self.ends[i]:
            return None
        c, L = self.cubics[i], self.lengths[i]
        t = cubic_param_at(self.rows, i, L, float(s - start), self.accuracy, gl_nodes())
        t = min(max(t, 0.0), 1.0)
        u = 1 - t
        pt = u ** 3 * c[0] + 3 * u * u * t * c[1] + 3 * u * t * t * c[2] + t ** 3 * c[3]
        d = cubic_derivative(c, t)
        return float(pt[0]), float(pt[1]), math.degrees(math.atan2(d[1], d[0]))


def path_length(path: Path) -> float:
    """Total length of a path's segments (closepaths included; the gaps between subpaths are
    not part of it)."""
    return PathWalker(path).length
