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
points where the staircase is 4 per step. Skia blends each segment on its own, so where a path's
segments overlap a pixel takes 1 - (1 - αa)(1 - αb) (α the paint's alpha): the segments are
grouped in runs going one way along one axis, each run drawn on its own; within a run steps
overlap only where one segment ends and the next begins inside a step, and that step's pixels
are one rectangle each whose coverage drawn with α is the blend of the segments' (so the
outline depends on α: blend_alpha). A closed subpath has no caps (SVG; Chromium), where
tiny-skia lengthens its first and last lines as an open subpath's.
"""
from __future__ import annotations

import math

import numpy as np

from . import hairline_kernels, stroke_kernels as kernels
from ..jit import bind_tail
from ..scene.path import Path

#: how far a cap lengthens a hairline's end (device px): the area of a square or round cap on
#: a line one pixel wide (Skia's extend_pts)
CAP_OUTSET = {"butt": 0.0, "square": 0.5, "round": math.pi / 8.0}

#: segments with |slope| (minor over major) below this are one parallelogram, not a staircase
STAIR_SLOPE = 0.25
#: a staircase's steps per segment and per path at most; past them, parallelograms (bounded
#: memory for absurd coordinates: the steps are per device pixel)
MAX_STEPS = np.array([1 << 13, 1 << 19], np.int64)      # (per segment, per path)
#: a staircase is cut into runs (Fills) of about this many rows across: the raster reads every
#: edge of a fill for each strip of rows its box meets, so one long staircase of 4 edges a
#: step costs its length squared; the pieces are pixel-disjoint, so the image is the same
RUN_ROWS = 64


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


def hairline_segments(path: Path, m, cap: str = "butt", dashes=None, offset: float = 0.0,
                      resolution: float = 1.0):
    """(rows, subs): the line segments (N, 4: x0, y0, x1, y1, device px) Skia's hairline
    draws for ``path`` (user space) under the transform ``m``, subpath k being rows
    subs[k]:subs[k + 1]: dashed first in user space (``dashes`` an effective pattern, see
    stroke.dash_pattern), curves cut into chords, round and square caps lengthening the ends
    of open subpaths."""
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
        return np.empty((0, 4)), np.zeros(1, np.int64)
    return hairline_kernels.hairline_chords(kinds, segs, np.ascontiguousarray(subs, np.int64),
                                            np.ascontiguousarray(flags, np.int64),
                                            np.asarray(m, np.float64), CAP_OUTSET.get(cap, 0.0))


def hairline_outline(rows, subs=None, alpha: float = 1.0) -> list:
    """Paths (nonzero, to be drawn one over the other) whose exact-area coverage is the
    antialiased hairline of the line segments ``rows`` (N, 4: x0, y0, x1, y1, device px;
    subpath k rows subs[k]:subs[k + 1], default one subpath; see the module's docstring),
    when drawn with the opacity ``alpha`` (see blend_alpha)."""
    rows = np.ascontiguousarray(rows, np.float64).reshape(-1, 4)
    subs = np.array([0, len(rows)], np.int64) if subs is None else \
        np.ascontiguousarray(subs, np.int64)
    v, p, rv, rp = hairline_kernels.hairline_rows(rows, subs, STAIR_SLOPE, MAX_STEPS,
                                                  _alpha(alpha), RUN_ROWS)
    return runs_paths(v, p, rv, rp)


def blend_alpha(paint, opacity: float) -> float:
    """The alpha Skia blends each segment of a hairline with: the opacity (hairline_coverage
    included) times a flat colour's own alpha (a gradient's varies: its opacity alone)."""
    color = getattr(paint, "color", None)
    return opacity * (color[3] if color is not None else 1.0)


def _alpha(alpha):
    # where steps of several segments meet, the coverage that blends as Skia's segments one
    # over the other depends on it (hairline_kernels._flush_joint); 0 draws nothing anyway
    return float(alpha) if 0.0 < alpha <= 1.0 else 1.0


def runs_paths(v, p, rv, rp) -> list:
    """The Paths of the runs of a hairline kernel's outline."""
    rv, rp = rv.tolist(), rp.tolist()
    return [Path._of_arrays(v[v0:v1], p[p0:p1])
            for v0, v1, p0, p1 in zip(rv, rv[1:], rp, rp[1:]) if v1 > v0]


def hairline_batch(verbs, points, vstart, pstart, which, m, cap, alpha: float = 1.0):
    """hairline_outline(*hairline_segments(path, m, cap), alpha) for the paths ``which`` of a
    batch of paths, at once and array for array: path i is verbs[vstart[i]:vstart[i + 1]]
    (uint8: MOVE, LINE, QUAD, CUBIC, CLOSE, CONIC, as Path stores them) with its points
    points[pstart[i]:pstart[i + 1]] ((N, 2) float64, user space; a conic's three points as
    Path stores them); ``m`` the transform to the device (a, b, c, d, e, f), ``cap`` the
    SVG linecap, ``alpha`` the paint's (blend_alpha). No dashes (a dashed hairline goes
    through hairline_segments). vstart, pstart and which int64 arrays. Returns (verbs,
    points, run verb offsets, run point offsets, the index in ``which`` of each run's path):
    run r is verbs[rv[r]:rv[r + 1]], points[rp[r]:rp[r + 1]], a nonzero fill drawn over the
    runs before it; a path's runs are consecutive, in hairline_outline's order, and a path
    that draws nothing has none."""
    return _paths_kernel()(verbs, points, vstart, pstart, which, _matrix(m),
                           CAP_OUTSET.get(cap, 0.0), _alpha(alpha))


def hairline_each(verbs, points, vstart, pstart, which, ms, outsets, alphas):
    """hairline_batch with a transform, cap and alpha of each path drawn: path which[w]
    under the transform ms[w] ((W, 6) float64), its cap's CAP_OUTSET outsets[w] and the
    alpha alphas[w] (float64 arrays of W; blend_alpha's, as _alpha takes it), in one kernel
    call; each path's runs (owned by w) are those hairline_batch makes of it alone under its
    transform, the same floats (a stretch of <use> instances of one marker, each under a
    translation of its own)."""
    return _each_kernel()(verbs, points, vstart, pstart, which, ms, outsets, alphas)


def use_alpha(alpha: float) -> float:
    """The alpha hairline_batch and hairline_each blend with for a paint's ``alpha``."""
    return _alpha(alpha)


_ONE = np.zeros(1, np.int64)


def hairline_path(path: Path, m, cap: str = "butt", alpha: float = 1.0):
    """hairline_batch's arrays for one path (its whole outline: hairline_outline(
    *hairline_segments(path, m, cap), alpha)), in one kernel call."""
    v, p = path._freeze()
    return hairline_batch(v, p, np.array([0, len(v)], np.int64),
                          np.array([0, len(p)], np.int64), _ONE, m, cap, alpha)


#: the kernel with the module's constants bound (jit.bind_tail: their part of the call key
#: computed once), for the constants and kernel it was made of (tests change them)
_bound = {}


def _paths_kernel():
    return _bind(hairline_kernels.hairline_paths_batch)


def _each_kernel():
    return _bind(hairline_kernels.hairline_paths_each)


def _bind(kernel):
    """``kernel`` with the constants bound, kept until they change (one binding a kernel;
    the keys listed at once and dropped with pop: threads may bind at the same time)."""
    key = (kernel, STAIR_SLOPE, id(MAX_STEPS), RUN_ROWS)
    bound = _bound.get(key)
    if bound is None:
        for old in list(_bound):
            if old[0] is kernel:
                _bound.pop(old, None)
        bound = _bound[key] = bind_tail(kernel, (STAIR_SLOPE, MAX_STEPS, RUN_ROWS,
                                                 kernels.ARC_TOLERANCE, kernels.MAX_ARC_CUBICS))
    return bound


_last_matrix = [(None, None)]


def _matrix(m):
    """m as the kernels take it; a tuple's array kept for the next call with the same tuple
    (a document's paths share their context's: the conversion cost a tenth of a circle's
    hairline). The pair is read and replaced whole (threads)."""
    last = _last_matrix[0]
    if m is last[0]:
        return last[1]
    a = np.asarray(m, np.float64)
    if type(m) is tuple:
        _last_matrix[0] = m, a      # (held: the tuple's id cannot be reused)
    return a
