"""Independent ground truth for raster tests: no code from vecmsaa's raster path is used here.

- :func:`winding_at` counts signed crossings of a horizontal ray with every segment, finding
  curve crossings as polynomial roots (numpy.roots), not with implicit functions.
- :func:`polygon_pixel_coverage` clips a polygon against each pixel square (Sutherland–Hodgman)
  and takes the exact area.
"""
from __future__ import annotations

import numpy as np

from vecmsaa.scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD, VERB_POINTS


def segments(path):
    """(kind, control points) of every segment, with implicit closing lines."""
    out = []
    start = cur = None
    i = 0
    pts = path.points
    for v in path.verbs:
        n = VERB_POINTS[v]
        p = pts[i:i + n]
        i += n
        if v == MOVE:
            if cur is not None and start is not None and not np.allclose(cur, start, 0, 0):
                out.append(("line", np.array([cur, start])))
            start = cur = p[0]
        elif v == LINE:
            out.append(("line", np.array([cur, p[0]])))
            cur = p[0]
        elif v == QUAD:
            out.append(("quad", np.array([cur, p[0], p[1]])))
            cur = p[1]
        elif v == CUBIC:
            out.append(("cubic", np.array([cur, p[0], p[1], p[2]])))
            cur = p[2]
        elif v == CONIC:
            # stored as (b1, point at t = ½, b2): that point is (1 − λ)·chord midpoint + λ·b1
            # with λ = w / (1 + w); rows b0, w·b1, b2 and the weights (1, w, 1) in column 2
            c = 0.5 * (cur + p[2])
            d = p[0] - c
            lam = float(np.dot(p[1] - c, d) / np.dot(d, d))
            w = lam / (1 - lam)
            out.append(("conic", np.array([[*cur, 1.0], [*(w * p[0]), w], [*p[2], 1.0]])))
            cur = p[2]
        elif v == CLOSE:
            out.append(("line", np.array([cur, start])))
            cur = start
            start = None
    if start is not None and cur is not None:
        out.append(("line", np.array([cur, start])))
    return out


def _power_coeffs(kind, c):
    """Polynomial coefficients (highest first) of x(t) and y(t); for conics of the
    homogeneous x(t)·d(t), y(t)·d(t) and d(t) (three columns)."""
    if kind == "line":
        return np.array([c[1] - c[0], c[0]])
    if kind in ("quad", "conic"):
        return np.array([c[0] - 2 * c[1] + c[2], 2 * (c[1] - c[0]), c[0]])
    return np.array([-c[0] + 3 * c[1] - 3 * c[2] + c[3], 3 * c[0] - 6 * c[1] + 3 * c[2],
                     3 * (c[1] - c[0]), c[0]])


def winding_at(segs, x, y):
    """Winding number at (x, y): crossings of the ray to the left, +1 for downward crossings."""
    w = 0
    for kind, c in segs:
        coef = _power_coeffs(kind, c)
        ox, oy = x, y
        if kind == "conic":     # crossings of y·d(t) = y(t)·d(t); d > 0, so signs carry over
            coef = coef[:, :2] - np.outer(coef[:, 2], [x, y])
            ox = oy = 0.0
        cy = coef[:, 1].copy()
        cy[-1] -= oy
        cy = np.trim_zeros(cy, "f")
        if len(cy) <= 1:
            continue
        roots = np.roots(cy)
        deriv = np.polyder(coef[:, 1])
        for r in roots:
            if abs(r.imag) > 1e-9:
                continue
            t = r.real
            if t < 0 or t >= 1:
                continue
            xt = np.polyval(coef[:, 0], t)
            if xt <= ox:
                dy = np.polyval(deriv, t)
                if dy != 0:
                    w += 1 if dy > 0 else -1
    return w


def distance_to_outline(segs, x, y, samples=400):
    """Distance from (x, y) to the outline: exact point-to-segment distance to a fine polyline
    through each segment (lines are exact; curves to within their flattening error)."""
    best = np.inf
    t = np.linspace(0, 1, samples)
    for kind, c in segs:
        coef = _power_coeffs(kind, c)
        tt = np.array([0.0, 1.0]) if kind == "line" else t
        px = np.polyval(coef[:, 0], tt)
        py = np.polyval(coef[:, 1], tt)
        if kind == "conic":
            d = np.polyval(coef[:, 2], tt)
            px, py = px / d, py / d
        ax, ay, bx, by = px[:-1], py[:-1], px[1:], py[1:]
        dx, dy = bx - ax, by - ay
        den = dx * dx + dy * dy
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.clip(np.where(den > 0, ((x - ax) * dx + (y - ay) * dy) / den, 0.0), 0, 1)
        best = min(best, float(np.min(np.hypot(ax + u * dx - x, ay + u * dy - y))))
    return best


def _clip(poly, inside, intersect):
    out = []
    for i in range(len(poly)):
        a, b = poly[i - 1], poly[i]
        if inside(b):
            if not inside(a):
                out.append(intersect(a, b))
            out.append(b)
        elif inside(a):
            out.append(intersect(a, b))
    return out


def _area(poly):
    if len(poly) < 3:
        return 0.0
    p = np.asarray(poly)
    return 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


def polygon_pixel_coverage(poly, width, height):
    """Exact coverage of each pixel by a simple polygon (absolute area in the pixel square)."""
    cov = np.zeros((height, width))
    poly = [tuple(p) for p in poly]
    for py in range(height):
        for px in range(width):
            p = poly
            for axis, bound, keep_above in ((0, px, True), (0, px + 1, False),
                                            (1, py, True), (1, py + 1, False)):
                def inside(q, axis=axis, bound=bound, keep_above=keep_above):
                    return q[axis] >= bound if keep_above else q[axis] <= bound

                def intersect(a, b, axis=axis, bound=bound):
                    t = (bound - a[axis]) / (b[axis] - a[axis])
                    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
                p = _clip(p, inside, intersect)
                if not p:
                    break
            cov[py, px] = abs(_area(p)) if p else 0.0
    return cov



def ellipse_pixel_coverage(cx, cy, rx, ry, width, height):
    """Exact coverage of each pixel by the axis-aligned ellipse (x−cx)²/rx² + (y−cy)²/ry² ≤ 1,
    in closed form (vecmsaa.tools.conics, which the bench measures with; outside the raster
    path, and checked against the ellipse's area and a brute-force count in test_conics)."""
    from vecmsaa.tools.conics import exact_coverage
    return exact_coverage(cx, cy, rx, ry, width, height)
