"""Arc length along paths: where a path is after a given length, and how long it is.

Every segment is measured as a cubic (a line becomes a cubic with its inner control points at
0.33 and 0.66, a quadratic is raised exactly), its length by 24-point Gauss–Legendre
quadrature, and the parameter at an arc length found with kurbo's ITP root finder stopped at a
fixed accuracy, as resvg does for text on a path. Stroke dashing keeps its own per-segment
tables (geometry/stroke.py), which follow tiny-skia's dash placement instead.
"""
from __future__ import annotations

import math

import numpy as np

from ..scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path


# Gauss–Legendre nodes and weights on [-1, 1] for arc lengths of cubic segments.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)


class PathWalker:
    """Points and tangents of a path at arc lengths, located the way resvg does.

    resvg turns every segment into a cubic (a line becomes a cubic with its inner control
    points at 0.33 and 0.66) and finds the parameter for an arc length with kurbo's ITP root
    finder stopped at a fixed accuracy (0.5 user units over the text's scale). That tolerance
    moves glyphs by up to a third of a pixel, visibly, so the same search is done here.
    """

    def __init__(self, path: Path, scale: float = 1.0):
        self.accuracy = 0.5 / max(scale, 1.0)
        self.cubics = []
        v, p = path.verbs, path.points
        i = 0
        cur = start = None
        for verb in v:
            k = VERB_POINTS[verb]
            q = p[i:i + k]
            i += k
            if verb == MOVE:
                cur = start = q[0]
                continue
            if verb == LINE or (verb == CLOSE and start is not None):
                end = q[0] if verb == LINE else start
                c = np.array([cur, cur + (end - cur) * 0.33, cur + (end - cur) * 0.66, end])
            elif verb == QUAD:
                c = np.array([cur, cur + 2 / 3 * (q[0] - cur), q[1] + 2 / 3 * (q[0] - q[1]),
                              q[1]])
            elif verb == CUBIC:
                c = np.array([cur, q[0], q[1], q[2]])
            else:
                continue
            self.cubics.append(c)
            cur = c[3]
        self.lengths = [self._arclen(c, 1.0) for c in self.cubics]
        self.length = float(sum(self.lengths))

    @staticmethod
    def _deriv(c, t):
        t = np.asarray(t)[..., None]
        return 3 * ((1 - t) ** 2 * (c[1] - c[0]) + 2 * t * (1 - t) * (c[2] - c[1])
                    + t ** 2 * (c[3] - c[2]))

    def _arclen(self, c, t1):
        u = (_GL_X + 1) / 2 * t1
        return float(np.sum(_GL_W * np.hypot(*self._deriv(c, u).T)) * t1 / 2)

    def _inv_arclen(self, c, total, arc):
        """kurbo's ParamCurveArclen::inv_arclen: ITP search to ``accuracy``."""
        if arc <= 0:
            return 0.0
        if arc >= total:
            return 1.0
        eps = self.accuracy / total
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
            y = self._arclen(c, x) - arc
            if y > 0:
                b, yb = x, y
            elif y < 0:
                a, ya = x, y
            else:
                return x
            scaled *= 0.5
        return 0.5 * (a + b)

    def at(self, s):
        """(x, y, tangent angle in degrees) at arc length s, or None off the path."""
        if s < 0:
            return None
        length = 0.0
        for c, L in zip(self.cubics, self.lengths):
            if length <= s <= length + L:
                t = min(max(self._inv_arclen(c, L, s - length), 0.0), 1.0)
                u = 1 - t
                pt = u ** 3 * c[0] + 3 * u * u * t * c[1] + 3 * u * t * t * c[2] + t ** 3 * c[3]
                d = self._deriv(c, t)
                return float(pt[0]), float(pt[1]), math.degrees(math.atan2(d[1], d[0]))
            length += L
        return None


def path_length(path: Path) -> float:
    """Total length of a path's segments (closepaths included; the gaps between subpaths are
    not part of it)."""
    return PathWalker(path).length
