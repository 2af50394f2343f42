"""Text on a path: clusters placed at arc lengths along a ``textPath``'s path, as resvg does."""
from __future__ import annotations

import math

import numpy as np

from ...scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path
from ...scene.transform import compose, rotate_at, translate
from .content import href_target

def position_on_path(clusters, chars, text_path, start, ctx, styles, shifts):
    """Clusters along a textPath from arc length ``start`` (the chunk's x moved by its
    text-anchor) plus startOffset: each cluster's midpoint on the path, turned to its tangent,
    then moved off the path by dy and baseline shifts; returns the pen at the end."""
    target = href_target(text_path)
    path = ctx.path_of(target) if target is not None else None
    walker = None
    if path is not None and not path.is_empty():
        a, b, cc, d = ctx.transform[:4]
        # resvg's tolerance follows the text's transform in the SVG's own units, before the
        # output is scaled to its pixel size: divide that scaling out.
        walker = PathWalker(path, math.sqrt(math.hypot(a, b) * math.hypot(cc, d))
                            / ctx.root_scale)
    # a path with infinite coordinates (or a length that overflows) is not drawn, and has no
    # length to lay text along
    if walker is None or not math.isfinite(walker.length):
        for c in clusters:
            c.visible = False
        return 0.0, 0.0
    style = styles.get(id(text_path), ctx.style)
    offset = 0.0
    start_offset = text_path.get("startOffset")
    if start_offset is not None:
        start_offset = start_offset.strip()
        if start_offset.endswith("%"):
            try:
                offset = float(start_offset[:-1]) / 100 * walker.length
            except ValueError:
                offset = 0.0
        else:
            offset = ctx.length(start_offset, "x", style, 0.0) or 0.0
    advance = start + offset
    dy = 0.0
    last = (0.0, 0.0)
    for c in clusters:
        ch = chars[c.char]
        advance += ch.dx
        hw = c.width / 2
        at = walker.at(advance + hw)
        advance += c.advance
        dy += ch.dy
        if at is None:
            c.visible = False
            continue
        px, py, ang = at
        frame = compose(translate(px - hw, py), rotate_at(ang, hw, 0.0))
        frame = compose(frame, translate(0.0, dy + shifts[c.char]))
        if ch.rotate:
            frame = compose(frame, rotate_at(ch.rotate, 0.0, 0.0))
        c.frame = compose(frame, compose(c.pre, (c.sx, 0.0, 0.0, 1.0, 0.0, 0.0)))
        c.shifted = True
        last = (px + c.advance, py)
    return last



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
