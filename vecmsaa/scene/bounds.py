"""Exact bounding boxes of paths (curves included, not just their control points)."""
from __future__ import annotations

import numpy as np

from .path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS
from .transform import apply


def _cubic_extrema(p0, p1, p2, p3):
    """Points at the interior extrema (per axis) of cubic segments; inputs (N, 2) arrays."""
    a = -p0 + 3 * p1 - 3 * p2 + p3
    b = 2 * (p0 - 2 * p1 + p2)
    c = p1 - p0
    # derivative/3 = a t^2 + b t + c
    ts = []
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = b * b - 4 * a * c
        sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
        for t in ((-b + sq) / (2 * a), (-b - sq) / (2 * a)):
            ts.append(t)
        lin = np.where(np.abs(a) < 1e-12, -c / b, np.nan)
        ts.append(lin)
    out = []
    for t in ts:
        for axis in (0, 1):
            tt = t[:, axis]
            ok = np.isfinite(tt) & (tt > 0) & (tt < 1)
            if not ok.any():
                continue
            tt = tt[ok][:, None]
            q0, q1, q2, q3 = p0[ok], p1[ok], p2[ok], p3[ok]
            mt = 1 - tt
            out.append(mt ** 3 * q0 + 3 * mt * mt * tt * q1 + 3 * mt * tt * tt * q2 + tt ** 3 * q3)
    return out


def path_bounds(path, matrix=None):
    """Tight bounds (x0, y0, x1, y1) of a path, optionally after a transform; None if empty."""
    verbs, pts = path.without_conics()._freeze()    # (a conic's cubic: within 3e-4 of it)
    if len(pts) == 0:
        return None
    if matrix is not None:
        pts = apply(matrix, pts)
    anchors = []
    cubics = []
    i = 0
    cur = None
    start = None
    for v in verbs:
        n = VERB_POINTS[v]
        if v == MOVE:
            cur = start = pts[i]
            anchors.append(cur)
        elif v == LINE:
            anchors.append(pts[i])
            cur = pts[i]
        elif v == QUAD:
            c1 = cur + 2 / 3 * (pts[i] - cur)
            c2 = pts[i + 1] + 2 / 3 * (pts[i] - pts[i + 1])
            cubics.append((cur, c1, c2, pts[i + 1]))
            anchors.append(pts[i + 1])
            cur = pts[i + 1]
        elif v == CUBIC:
            cubics.append((cur, pts[i], pts[i + 1], pts[i + 2]))
            anchors.append(pts[i + 2])
            cur = pts[i + 2]
        elif v == CLOSE:
            cur = start
        i += n
    if len(anchors) == 0:
        return None
    allp = [np.asarray(anchors)]
    if cubics:
        arr = np.asarray(cubics)
        allp.extend(_cubic_extrema(arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3]))
    allp = np.concatenate([a.reshape(-1, 2) for a in allp])
    return (float(allp[:, 0].min()), float(allp[:, 1].min()),
            float(allp[:, 0].max()), float(allp[:, 1].max()))


def union(a, b):
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))
