"""Strokes at most a device pixel wide, as Skia (and so resvg's tiny-skia and Chromium) draws
them: antialiased hairlines.

With antialiasing on, Skia draws a stroke whose width vectors (w, 0) and (0, w), mapped by the
transform, both have a "fast length" (max(|x|, |y|) + min / 2) of at most 1 as a hairline, its
paint faded by the two lengths' mean (SkDrawTreatAAStrokeAsHairline). The antialiased hairline
(SkScan_Antihair) walks each line segment one step of its major axis at a time (a column for a
mostly horizontal line, a row for a mostly vertical one): the line's minor coordinate at the
step's centre, c, splits one pixel of ink between the two nearest pixels across the step, as a
band one pixel thick centred on c covers them; a step the segment covers only in part gets
that fraction of the ink. So a 45° line puts one full pixel of ink in each column, where the
exact area of a band one pixel wide gives three partly covered pixels.

Here that coverage is geometry: per step an axis-aligned rectangle one pixel thick across the
major axis, centred on c, as long as the segment's part of the step (a staircase polygon per
segment), whose exact-area coverage is the hairline's. Round and square caps lengthen the
subpath's ends by π/8 and ½ pixel (the area of the half disc or half square of a unit-wide
cap); curves are flattened into chords as Skia subdivides them. Segments nearly along an axis
take one parallelogram one pixel thick across the major axis instead of a staircase: its
coverage differs from the steps' by at most a quarter of the slope per pixel, and it is 4
points where the staircase is 4 per step. Where segments of one path overlap (joins), this
draws their union where Skia blends each segment on its own.
"""
from __future__ import annotations

import math

import numpy as np

from . import stroke_kernels as kernels
from ..scene.path import CLOSE, LINE, MOVE, Path

#: how far a cap lengthens a hairline's end (device px): the area of a square or round cap on
#: a line one pixel wide (Skia's extend_pts)
CAP_OUTSET = {"butt": 0.0, "square": 0.5, "round": math.pi / 8.0}

#: segments with |slope| (minor over major) below this are one parallelogram, not a staircase
STAIR_SLOPE = 0.5
#: a staircase's steps per segment and per path at most; past them, parallelograms (bounded
#: memory for absurd coordinates: the steps are per device pixel)
MAX_STEPS_SEGMENT = 1 << 13
MAX_STEPS_PATH = 1 << 19


def hairline_coverage(width, m, antialias):
    """The opacity factor of a stroke of ``width`` under the transform ``m`` drawn as an
    antialiased hairline, or None when it is stroked as an outline (Skia's
    SkDrawTreatAAStrokeAsHairline, with the coverage quantised as tiny-skia pre-scales the
    paint's alpha by it)."""
    if not antialias or not (width > 0 and math.isfinite(width)):
        return None
    a, b, c, d = m[:4]

    def fast_len(x, y):
        x, y = abs(x), abs(y)
        return max(x, y) + min(x, y) / 2.0

    l0 = fast_len(a * width, b * width)
    l1 = fast_len(c * width, d * width)
    if not (l0 <= 1.0 and l1 <= 1.0):
        return None
    coverage = (l0 + l1) / 2.0
    if coverage >= 1.0:
        return 1.0
    return ((255 * int(coverage * 256.0)) >> 8) / 255.0


def _curve_chords(kind, s):
    """Points along one curve segment (device coordinates, row of path_segments' segs), as
    many chords as Skia's hairline subdivides it into (a power of two: chord error about an
    eighth of a pixel)."""
    p = s[:8].reshape(4, 2)
    if kind == 3:       # quadratic: Skia's compute_quad_level (4x closer per halving)
        dx, dy = np.abs((p[0] + p[2]) / 2.0 - p[1])
        dist = max(dx, dy) + min(dx, dy) / 2.0
        level = 0 if dist <= 0 else min(5, max(0, math.ceil(math.log(max(dist, 1.0), 4))))
        n = 1 << level
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        return (1 - t) ** 2 * p[0] + 2 * (1 - t) * t * p[1] + t ** 2 * p[2]
    if kind == 5:       # conic (b0, b1, midpoint, b2): its weight from the midpoint
        b0, b1, mid, b2 = p
        chord_mid = (b0 + b2) / 2.0
        den = np.dot(b1 - mid, b1 - mid)
        # mid = (b0 + 2 w b1 + b2) / (2 + 2w): w / (1 + w) = |mid - chord_mid| / |b1 - chord_mid|
        ratio = (math.sqrt(np.dot(mid - chord_mid, mid - chord_mid))
                 / max(math.sqrt(np.dot(b1 - chord_mid, b1 - chord_mid)), 1e-300))
        w = ratio / max(1.0 - ratio, 1e-12) if den > 0 else 1.0
        dist = float(np.max(np.abs(chord_mid - mid))) * 2.0
        level = 0 if dist <= 0 else min(9, max(0, math.ceil(math.log(max(dist * 8, 1.0), 4))))
        n = 1 << level
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        wt = (1 - t) ** 2 + 2 * w * (1 - t) * t + t ** 2
        return ((1 - t) ** 2 * b0 + 2 * w * (1 - t) * t * b1 + t ** 2 * b2) / wt
    # cubic: Skia's compute_cubic_segments
    p13 = p[3] / 3.0 + p[0] * (2.0 / 3.0)
    p23 = p[0] / 3.0 + p[3] * (2.0 / 3.0)
    diff = float(max(np.max(np.abs(p[1] - p13)), np.max(np.abs(p[2] - p23))))
    n, tol = 1 << 9, 1.0 / 8.0
    for i in range(9):
        if diff < tol:
            n = 1 << i
            break
        tol *= 4.0
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    mt = 1 - t
    return mt ** 3 * p[0] + 3 * mt ** 2 * t * p[1] + 3 * mt * t ** 2 * p[2] + t ** 3 * p[3]


def hairline_segments(path: Path, m, cap: str = "butt", dashes=None, offset: float = 0.0,
                      resolution: float = 1.0):
    """The line segments (N, 4: x0, y0, x1, y1, device px) Skia's hairline draws for ``path``
    (user space) under the transform ``m``: dashed first in user space (``dashes`` an
    effective pattern, see stroke.dash_pattern), curves cut into chords, round and square
    caps lengthening the ends of open subpaths."""
    from .stroke import _chord_tolerance, _path_segments, dash_curves
    if dashes:
        segments = kernels.dash_segments(*_path_segments(dash_curves(path, 0.0)),
                                         np.asarray(dashes, np.float64), float(offset),
                                         _chord_tolerance(resolution))
    else:
        segments = _path_segments(path)
    kinds, segs, subs, flags = segments
    if len(flags) == 0:
        return np.empty((0, 4))
    a, b, c, d, e, f = (float(v) for v in m)
    xs, ys = segs[:, 0::2], segs[:, 1::2]
    dev = np.empty_like(segs)
    dev[:, 0::2] = a * xs + c * ys + e
    dev[:, 1::2] = b * xs + d * ys + f
    outset = CAP_OUTSET.get(cap, 0.0)
    if (kinds == 2).all() and not (flags == kernels.SUB_DOT).any():
        rows = dev[:, :4].copy()
        if outset:
            open_ = flags == kernels.SUB_OPEN
            _extend(rows, subs[:-1][open_], subs[1:][open_] - 1, outset)
        return rows
    parts = []
    for k in range(len(flags)):
        lo, hi = subs[k], subs[k + 1]
        if flags[k] == kernels.SUB_DOT:
            if outset:      # a zero-length dash: Skia's cap outset along x, both ways
                x, y = dev[lo, 0], dev[lo, 1]
                parts.append(np.array([[x + outset, y, x - outset, y]]))
            continue
        sub = []
        for s in range(lo, hi):
            if kinds[s] == 2:
                sub.append(dev[s:s + 1, :4])
            else:
                pts = _curve_chords(int(kinds[s]), dev[s])
                sub.append(np.column_stack((pts[:-1], pts[1:])))
        rows = np.concatenate(sub)
        if outset and flags[k] == kernels.SUB_OPEN:
            _extend(rows, np.array([0]), np.array([len(rows) - 1]), outset)
        parts.append(rows)
    return np.concatenate(parts) if parts else np.empty((0, 4))


def _extend(rows, first, last, outset):
    """Lengthens rows[first]'s starts and rows[last]'s ends by ``outset`` along their
    directions, in place; a zero-length row along x (start forwards, end backwards, as Skia)."""
    for idx, sign, i0, i1 in ((first, -1.0, 0, 2), (last, 1.0, 2, 0)):
        dx = rows[idx, 2] - rows[idx, 0]
        dy = rows[idx, 3] - rows[idx, 1]
        ln = np.hypot(dx, dy)
        zero = ln == 0
        ux = np.where(zero, -sign, dx / np.where(zero, 1.0, ln))
        uy = np.where(zero, 0.0, dy / np.where(zero, 1.0, ln))
        rows[idx, i0] += sign * ux * outset
        rows[idx, i0 + 1] += sign * uy * outset


def hairline_outline(rows) -> Path:
    """A path (nonzero) whose exact-area coverage is the antialiased hairline of the line
    segments ``rows`` (see the module's docstring)."""
    rows = np.asarray(rows, np.float64).reshape(-1, 4)
    dx = rows[:, 2] - rows[:, 0]
    dy = rows[:, 3] - rows[:, 1]
    keep = ((dx != 0) | (dy != 0)) & np.isfinite(rows).all(axis=1)
    rows, dx, dy = rows[keep], dx[keep], dy[keep]
    if len(rows) == 0:
        return Path.from_arrays(np.empty(0, np.uint8), np.empty((0, 2)))
    # in the major axis' frame: u along it, v across; y-major rows have x and y swapped
    ymaj = np.abs(dx) <= np.abs(dy)
    u0 = np.where(ymaj, rows[:, 1], rows[:, 0])
    v0 = np.where(ymaj, rows[:, 0], rows[:, 1])
    u1 = np.where(ymaj, rows[:, 3], rows[:, 2])
    v1 = np.where(ymaj, rows[:, 2], rows[:, 3])
    back = u0 > u1
    u0, u1 = np.where(back, u1, u0), np.where(back, u0, u1)
    v0, v1 = np.where(back, v1, v0), np.where(back, v0, v1)
    slope = (v1 - v0) / (u1 - u0)
    first = np.floor(u0)
    steps = (np.ceil(u1) - first).astype(np.int64)
    stair = (np.abs(slope) >= STAIR_SLOPE) & (steps <= MAX_STEPS_SEGMENT)
    if stair.any():
        over = np.cumsum(np.where(stair, steps, 0)) > MAX_STEPS_PATH
        stair &= ~over
    n = np.where(stair, steps, 1)                   # "columns" per row
    start = np.concatenate(([0], np.cumsum(n)[:-1]))
    total = int(n.sum())
    row = np.repeat(np.arange(len(rows)), n)
    k = np.arange(total) - start[row]               # the step within its row
    col = first[row] + k
    st = stair[row]
    lo = np.where(st, np.maximum(u0[row], col), u0[row])
    hi = np.where(st, np.minimum(u1[row], col + 1.0), u1[row])
    centre = v0[row] + slope[row] * (col + 0.5 - u0[row])
    v_lo = np.where(st, centre, v0[row])
    v_hi = np.where(st, centre, v1[row])
    # per row: the step tops left to right, then the bottoms right to left (4 points a step)
    nr = n[row]
    pos = np.empty((total, 4), np.int64)
    pos[:, 0] = 2 * k
    pos[:, 1] = 2 * k + 1
    pos[:, 2] = 2 * nr + 2 * (nr - 1 - k)
    pos[:, 3] = pos[:, 2] + 1
    # swapping x and y mirrors the polygon: y-major rows go round the other way, so that
    # every polygon has the same orientation and nonzero unites them
    flip = ymaj[row][:, None]
    pos = np.where(flip, 4 * nr[:, None] - 1 - pos, pos) + 4 * start[row][:, None]
    u = np.stack((lo, hi, hi, lo), axis=1)
    v = np.stack((v_lo - 0.5, v_hi - 0.5, v_hi + 0.5, v_lo + 0.5), axis=1)
    pts = np.empty((4 * total, 2))
    ym = flip[:, 0]
    pts[pos.ravel(), 0] = np.where(ym[:, None], v, u).ravel()
    pts[pos.ravel(), 1] = np.where(ym[:, None], u, v).ravel()
    verbs = np.full(4 * total + len(rows), LINE, np.uint8)
    vstart = 4 * start + np.arange(len(rows))
    verbs[vstart] = MOVE
    verbs[vstart + 4 * n] = CLOSE
    return Path.from_arrays(verbs, pts)
