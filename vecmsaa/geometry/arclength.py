"""Arc length along paths: where a path is after a given length, and how long it is.

Every segment is measured as a cubic (a line becomes a cubic with its inner control points at
0.33 and 0.66, a quadratic is raised exactly), its length by 24-point Gauss–Legendre
quadrature. The parameter at an arc length is found two ways: for text on a path with kurbo's
ITP root finder stopped at resvg's coarse accuracy (:func:`cubic_param_at`, since the
references show where that puts glyphs), for stroke dashing (geometry/stroke.py) by Newton's
method to a fine accuracy (:func:`cubic_exact_param_at`): dashes sit at their exact arc
lengths.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from ..scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path


@functools.cache
def _gl_nodes():
    """Gauss–Legendre nodes and weights for arc lengths of cubic segments, mapped to [0, 1]
    (on first use: numpy.polynomial and the eigenvalues cost start-up a render without dashes
    or text on a path does not need)."""
    return tuple(((float(x) + 1) / 2, float(w) / 2)
                 for x, w in zip(*np.polynomial.legendre.leggauss(24)))


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


def cubic_length(c, t1: float = 1.0) -> float:
    """Arc length of the cubic ``c`` from t = 0 to ``t1`` (24-point Gauss–Legendre; plain
    floats, which for 24 nodes beat numpy's per-call cost)."""
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = c
    ax, ay = 3 * (x1 - x0), 3 * (y1 - y0)
    bx, by = 3 * (x2 - x1), 3 * (y2 - y1)
    cx, cy = 3 * (x3 - x2), 3 * (y3 - y2)
    total = 0.0
    for x, w in _gl_nodes():
        u = x * t1
        v = 1 - u
        p, q, r = v * v, 2 * u * v, u * u
        total += w * math.hypot(p * ax + q * bx + r * cx, p * ay + q * by + r * cy)
    return total * t1


def cubic_exact_param_at(c, total: float, arc: float, accuracy: float) -> float:
    """The parameter where the cubic ``c`` (of length ``total``) has run ``arc``, to within
    ``accuracy`` of length: Newton's method on the arc length, kept inside a shrinking bracket
    (bisection where a step would leave it), usually 2-4 length evaluations."""
    if arc <= 0:
        return 0.0
    if arc >= total:
        return 1.0
    a, b = 0.0, 1.0
    t = arc / total
    for _ in range(60):
        err = cubic_length(c, t) - arc
        if abs(err) <= accuracy:
            return t
        if err > 0:
            b = t
        else:
            a = t
        speed = math.hypot(*cubic_derivative(c, t))
        step = t - err / speed if speed > 0 else -1.0
        t = step if a < step < b else 0.5 * (a + b)
    return t


def cubic_param_at(c, total: float, arc: float, accuracy: float) -> float:
    """The parameter where the cubic ``c`` (of length ``total``) has run ``arc``, found by
    kurbo's ParamCurveArclen::inv_arclen: an ITP search stopped at ``accuracy`` (in length)."""
    if arc <= 0:
        return 0.0
    if arc >= total:
        return 1.0
    eps = accuracy / total
    a, b = 0.0, 1.0
    ya, yb = -arc, total - arc
    n_half = max(math.ceil(math.log2((b - a) / eps)) - 1, 0)
    scaled = eps * float(1 << (1 + n_half))
    k1 = 0.2
    while b - a > 2 * eps:
        mid = 0.5 * (a + b)
        r = scaled - 0.5 * (b - a)
        xf = (yb * a - ya * b) / (yb - ya)
        sigma = mid - xf
        delta = k1 * (b - a) ** 2
        xt = xf + math.copysign(delta, sigma) if delta <= abs(mid - xf) else mid
        x = xt if abs(xt - mid) <= r else mid - math.copysign(r, sigma)
        y = cubic_length(c, x) - arc
        if y > 0:
            b, yb = x, y
        elif y < 0:
            a, ya = x, y
        else:
            return x
        scaled *= 0.5
    return 0.5 * (a + b)


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
        self.lengths = [cubic_length(c) for c in self.cubics]
        self.length = float(sum(self.lengths))

    def at(self, s):
        """(x, y, tangent angle in degrees) at arc length s, or None off the path."""
        if s < 0:
            return None
        length = 0.0
        for c, L in zip(self.cubics, self.lengths):
            if length <= s <= length + L:
                t = min(max(cubic_param_at(c, L, s - length, self.accuracy), 0.0), 1.0)
                u = 1 - t
                pt = u ** 3 * c[0] + 3 * u * u * t * c[1] + 3 * u * t * t * c[2] + t ** 3 * c[3]
                d = cubic_derivative(c, t)
                return float(pt[0]), float(pt[1]), math.degrees(math.atan2(d[1], d[0]))
            length += L
        return None


def path_length(path: Path) -> float:
    """Total length of a path's segments (closepaths included; the gaps between subpaths are
    not part of it)."""
    return PathWalker(path).length
