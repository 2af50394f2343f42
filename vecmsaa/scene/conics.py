"""Conics as cubics, in one pass over a path's arrays.

Strokes, dashes, hairlines, markers and pens take lines and Béziers only, so every path with
an arc passes through here (``Path.without_conics``, ``geometry.stroke.arc_cubics``): a
document of 20,000 stroked circles did so 20,000 times. Written with numpy's array calls
the conversion cost about 0.2 ms a path (some forty calls on arrays of four rows); this
kernel does the same arithmetic, operation for operation, on the path's own arrays.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from .bounds import _conic_weight
from .path import CONIC, CUBIC, VERB_POINTS


@njit(cache=True, inline="always", error_model="numpy")   # (w = 1 divides by zero)
def _arc_frame(b0x, b0y, mx, my, b2x, b2y, w):
    """The conic (b0, b1, b2) of weight w (its point at ½ is m) as the affine image
    C + u·cos φ + v·sin φ of a circular arc, φ in ±θ/2: the chord's midpoint c (C is
    c − w·u), u and v."""
    cx = 0.5 * (b0x + b2x)
    cy = 0.5 * (b0y + b2y)
    ux = (mx - cx) / (1.0 - w)
    uy = (my - cy) / (1.0 - w)
    s = 2.0 * math.sqrt(1.0 - w * w)
    return cx, cy, ux, uy, (b2x - b0x) / s, (b2y - b0y) / s


# (error_model="numpy": a degenerate conic divides by zero, as the numpy code it replaced did,
# and comes out as one cubic)
@njit(cache=True, error_model="numpy")
def conics_as_cubics(verbs, points, keep, tolerance, max_pieces):
    """(verbs, points) with every conic but those ``keep`` marks (a flag a conic, in the
    path's order; an empty array keeps none) replaced by cubics: with ``tolerance`` 0 one
    each, its handles at 4w / (3(1 + w)) of the way to b1 (Path.without_conics); with
    ``tolerance`` > 0 the arc of the ellipse with larger radius r is cut as kurbo's
    Arc::append_iter cuts it at that tolerance, n = ⌈max((1.1163·r/tolerance)^(1/6),
    3.999999)·θ/2π⌉ equal angles (at most ``max_pieces``), each a cubic with handles
    4/3·tan(angle/4) along the tangents, and an arc it leaves whole is the one cubic above
    (stroke.arc_cubics). A kept conic is copied as it is. b0 is the point before b1 in the
    array, as the path stores it."""
    nv = verbs.shape[0]
    # the output's size: a conic cut into n cubics takes 3n points for its 3
    counts = np.ones(nv, np.int64)
    thetas = np.zeros(nv)
    i = 0
    k = 0
    extra = 0
    for vi in range(nv):
        v = verbs[vi]
        i += VERB_POINTS[v]
        if v != CONIC:
            continue
        at = i - 3
        if not (k < keep.shape[0] and keep[k]) and tolerance > 0:
            b0x, b0y = points[at - 1, 0], points[at - 1, 1]
            b1x, b1y = points[at, 0], points[at, 1]
            mx, my = points[at + 1, 0], points[at + 1, 1]
            b2x, b2y = points[at + 2, 0], points[at + 2, 1]
            w = _conic_weight(b0x, b0y, b1x, b1y, mx, my, b2x, b2y)
            w = min(max(w, -1.0), 1.0) if w == w else w
            theta = 2.0 * math.acos(w) if w == w else w
            cx, cy, ux, uy, vx, vy = _arc_frame(b0x, b0y, mx, my, b2x, b2y, w)
            sq = (ux * ux + uy * uy) + (vx * vx + vy * vy)
            det = ux * vy - uy * vx
            disc = sq * sq - 4.0 * det * det
            if disc < 0.0:
                disc = 0.0
            radius = math.sqrt(0.5 * (sq + math.sqrt(disc)))
            density = (1.1163 * radius / tolerance) ** (1.0 / 6.0)
            if density < 3.999999:
                density = 3.999999
            n = np.ceil(density * theta / (2.0 * math.pi))
            if math.isfinite(n) and n > 1:
                counts[vi] = int(min(n, max_pieces))
                thetas[vi] = theta
                extra += 3 * (counts[vi] - 1)
        k += 1
    out_v = np.empty(nv + extra // 3, np.uint8)
    out_p = np.empty((points.shape[0] + extra, 2))
    i = 0       # next input point
    o = 0       # next output point
    ov = 0
    k = 0
    for vi in range(nv):
        v = verbs[vi]
        m = VERB_POINTS[v]
        if v != CONIC or (k < keep.shape[0] and keep[k]):
            out_v[ov] = v
            ov += 1
            for j in range(m):
                out_p[o + j, 0] = points[i + j, 0]
                out_p[o + j, 1] = points[i + j, 1]
            o += m
            i += m
            if v == CONIC:
                k += 1
            continue
        k += 1
        at = i
        b0x, b0y = points[at - 1, 0], points[at - 1, 1]
        b1x, b1y = points[at, 0], points[at, 1]
        mx, my = points[at + 1, 0], points[at + 1, 1]
        b2x, b2y = points[at + 2, 0], points[at + 2, 1]
        n = counts[vi]
        if n == 1:
            w = _conic_weight(b0x, b0y, b1x, b1y, mx, my, b2x, b2y)
            h = 4.0 * w / (3.0 * (1.0 + w))
            out_v[ov] = CUBIC
            ov += 1
            out_p[o, 0] = b0x + h * (b1x - b0x)
            out_p[o, 1] = b0y + h * (b1y - b0y)
            out_p[o + 1, 0] = b2x + h * (b1x - b2x)
            out_p[o + 1, 1] = b2y + h * (b1y - b2y)
            out_p[o + 2, 0] = b2x
            out_p[o + 2, 1] = b2y
            o += 3
            i += 3
            continue
        # the arc C + u·cos φ + v·sin φ, φ in ±θ/2, cut into n equal angles
        theta = thetas[vi]
        w = _conic_weight(b0x, b0y, b1x, b1y, mx, my, b2x, b2y)
        w = min(max(w, -1.0), 1.0)
        cx, cy, ux, uy, vx, vy = _arc_frame(b0x, b0y, mx, my, b2x, b2y, w)
        ox = cx - w * ux
        oy = cy - w * uy
        arm = 4.0 / 3.0 * math.tan(0.25 * theta / n)
        step = theta / n
        px, py = b0x, b0y
        tx = vx * math.cos(-0.5 * theta) - ux * math.sin(-0.5 * theta)
        ty = vy * math.cos(-0.5 * theta) - uy * math.sin(-0.5 * theta)
        for j in range(1, n + 1):
            phi = -0.5 * theta + step * j
            c = math.cos(phi)
            sn = math.sin(phi)
            if j == n:
                qx, qy = b2x, b2y
            else:
                qx = ox + ux * c + vx * sn
                qy = oy + uy * c + vy * sn
            sx = vx * c - ux * sn
            sy = vy * c - uy * sn
            out_v[ov] = CUBIC
            ov += 1
            out_p[o, 0] = px + arm * tx
            out_p[o, 1] = py + arm * ty
            out_p[o + 1, 0] = qx - arm * sx
            out_p[o + 1, 1] = qy - arm * sy
            out_p[o + 2, 0] = qx
            out_p[o + 2, 1] = qy
            o += 3
            px, py, tx, ty = qx, qy, sx, sy
        i += 3
    return out_v, out_p
