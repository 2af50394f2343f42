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

from . import hairline_kernels, stroke_kernels as kernels
from ..scene.path import Path

#: how far a cap lengthens a hairline's end (device px): the area of a square or round cap on
#: a line one pixel wide (Skia's extend_pts)
CAP_OUTSET = {"butt": 0.0, "square": 0.5, "round": math.pi / 8.0}

#: segments with |slope| (minor over major) below this are one parallelogram, not a staircase
STAIR_SLOPE = 0.25
#: a staircase's steps per segment and per path at most; past them, parallelograms (bounded
#: memory for absurd coordinates: the steps are per device pixel)
MAX_STEPS = np.array([1 << 13, 1 << 19], np.int64)      # (per segment, per path)


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
    """Points along one curve segment (device coordinates, a row of path_segments' segs) at
    as many even steps of t as Skia's hairline cuts it into chords: a quadratic 2^level, the
    level from the whole pixels between its control point and its chord's midpoint (4x closer
    a halving, at most 32 chords); a cubic the least 2^i whose control points lie within
    4^i / 8 px of the chord's thirds (at most 512)."""
    p = s[:8].reshape(4, 2)
    if kind == 3:
        dx, dy = (int(min(math.ceil(v), 1 << 30)) for v in np.abs((p[0] + p[2]) / 2.0 - p[1]))
        dist = max(dx, dy) + (min(dx, dy) >> 1)
        n = 1 << min(5, (dist.bit_length() + 1) >> 1)
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        return (1 - t) ** 2 * p[0] + 2 * (1 - t) * t * p[1] + t ** 2 * p[2]
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
    pts = mt ** 3 * p[0] + 3 * mt ** 2 * t * p[1] + 3 * mt * t ** 2 * p[2] + t ** 3 * p[3]
    return pts if np.isfinite(pts).all() else pts[:0]


def hairline_segments(path: Path, m, cap: str = "butt", dashes=None, offset: float = 0.0,
                      resolution: float = 1.0):
    """The line segments (N, 4: x0, y0, x1, y1, device px) Skia's hairline draws for ``path``
    (user space) under the transform ``m``: dashed first in user space (``dashes`` an
    effective pattern, see stroke.dash_pattern), curves cut into chords, round and square
    caps lengthening the ends of open subpaths."""
    from .stroke import _chord_tolerance, _path_segments, arc_cubics
    path = arc_cubics(path)         # conics as the cubics usvg makes of arcs
    if dashes:
        segments = kernels.dash_segments(*_path_segments(path),
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
                if len(pts):
                    sub.append(np.column_stack((pts[:-1], pts[1:])))
        if not sub:
            continue
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
    segments ``rows`` (N, 4: x0, y0, x1, y1, device px; see the module's docstring)."""
    rows = np.ascontiguousarray(rows, np.float64).reshape(-1, 4)
    return Path._of_arrays(*hairline_kernels.hairline_rows(rows, STAIR_SLOPE, MAX_STEPS))


def hairline_batch(verbs, points, vstart, pstart, which, m, cap):
    """hairline_outline(hairline_segments(path, m, cap)) for the paths ``which`` of a batch of
    paths of lines, at once: (verbs, points, verb offsets, point offsets)."""
    return hairline_kernels.hairline_lines_batch(
        verbs, points, vstart, pstart, which, np.asarray(m, np.float64),
        CAP_OUTSET.get(cap, 0.0), STAIR_SLOPE, MAX_STEPS)
