"""Strokes as fillable outlines, dashing, and marker vertices.

:func:`stroke_path` returns the stroke's outline as a Path to be filled with the nonzero rule:
per subpath one contour (right side forward, end cap, left side backward, start cap), or two
loops for a closed one, with the joins inline.

Why that is exact under nonzero even with segments shorter than the stroke is wide (map data):
as a chain, the contour is exactly the sum of separate positively oriented pieces (a contour
per smooth run of segment pieces closed by butt lines, a wedge per join on the outer side of the
turn, the caps). On the outer side a wedge and the butt lines collapse into the join shape; on
the inner side into the detour offset corner → vertex → next offset corner. Winding numbers add
over chains, every piece winds +1 over itself, so the fill is their union.

Circular arcs (conics whose control triangle is isosceles with the weight of a circle: SVG
arcs, circles, rounded corners under a similarity) are offset exactly: the offset of an arc
of radius r by ±w/2 is the concentric arc of radius r ± w/2, the same conic scaled about the
centre; their dashes are cut on the exact arc too. Elliptical arcs, and arcs no wider than
the stroke's half width (whose inner offset folds), are stroked as cubics, like every other
curve:

Offsets of curves are cubic Béziers fitted to the true offset (exact end points and tangents, the
midpoint matched), subdivided until within ``tolerance`` at the quarter points; where the offset
folds (bends tighter than half the width) or will not fit, pieces are split until flat within
half the tolerance and stroked as chords with round joins. Errors add up there: a chord off the
curve by f moves its whole stroke by up to f, so the joins and caps at a chord's ends are drawn
within the rest of the tolerance (tolerance − f, at least half of it). A quadratic or cubic
in line (its control points within √1e-5, a quadratic's √5e-6, of its extent of the line
through its farthest points) is stroked as the lines through its points of extreme speed instead, as Skia's and
tiny-skia's strokers do (stroke_kernels._in_line).

Strokes are drawn by the compiled kernels in :mod:`vecmsaa.geometry.stroke_kernels`: paths of
straight lines only (map data), dashes and all, by stroke_lines; paths with curves by
stroke_segments, their dashes first cut by dash_segments where resvg and Chromium cut them:
along lengths measured by chords (tiny-skia's and Skia's contour measure), with arcs first
turned into usvg's cubics (:func:`arc_cubics`).

Conventions: for a direction d, the left normal is n = (-d.y, d.x); "left" offsets are P + w/2·n.
"""
from __future__ import annotations

import math

import numpy as np

from . import stroke_kernels as kernels
from ..scene.conics import conics_as_cubics
from ..scene.path import _KEEP_NONE, CLOSE, CONIC, LINE, MOVE, VERB_POINTS, Path, conic_weight

JOINS = ("miter", "miter-clip", "round", "bevel", "arcs")
CAPS = ("butt", "round", "square")


# -- small vector helpers on (x, y) tuples (pure Python: faster than numpy for 2-vectors) ----

def _unit(dx, dy):
    n = math.hypot(dx, dy)
    if n == 0.0 or not math.isfinite(n):
        return None
    return dx / n, dy / n


def segment_tangents(seg):
    """Unit directions at the start and end of a segment (control points tuple), or None
    for a segment of zero length."""
    p0 = seg[0]
    start = end = None
    for q in seg[1:]:
        start = _unit(q[0] - p0[0], q[1] - p0[1])
        if start:
            break
    p3 = seg[-1]
    for q in reversed(seg[:-1]):
        end = _unit(p3[0] - q[0], p3[1] - q[1])
        if end:
            break
    if start is None or end is None:
        return None
    return start, end


# -- the compiled strokers -------------------------------------------------------------------

_SOLID = np.empty(0)
_LINE_VERBS = bytes((MOVE, LINE, CLOSE))


def _line_outline(verbs, pts, hw, tol, join, cap, miterlimit, pattern=None, offset=0.0):
    """Outline arrays (verbs, points) of a path of lines only, from the compiled stroker."""
    return kernels.stroke_lines(np.ascontiguousarray(verbs, dtype=np.uint8),
                                np.ascontiguousarray(pts, dtype=np.float64).reshape(-1, 2),
                                float(hw), float(tol), kernels.JOIN_CODES.get(join, 0),
                                kernels.CAP_CODES.get(cap, 0), float(miterlimit),
                                _SOLID if pattern is None else np.asarray(pattern, np.float64),
                                float(offset))


def _path_segments(path):
    """The curve stroker's input (see kernels.path_segments) for a path."""
    return kernels.path_segments(np.ascontiguousarray(path.verbs, dtype=np.uint8),
                                 np.ascontiguousarray(path.points, dtype=np.float64))


def _segments_outline(segments, hw, tol, join, cap, miterlimit, general=False):
    """Outline arrays of kernels.path_segments-style subpaths (as one path's), from the
    compiled stroker (general: lines too go through the curve stroker, as the tests compare
    them)."""
    return kernels.stroke_segments(*segments, np.array([0, len(segments[3])], np.int64),
                                   float(hw), float(tol), kernels.JOIN_CODES.get(join, 0),
                                   kernels.CAP_CODES.get(cap, 0), float(miterlimit),
                                   general)[:2]


def stroke_batch(verbs, points, vstart, pstart, which, hw, tol, join, cap, miterlimit):
    """The solid stroke outlines of the paths ``which`` of a batch of paths, curves and all
    (path i: verbs[vstart[i]:vstart[i + 1]], points[pstart[i]:pstart[i + 1]]; int64
    offsets), in the kernels' arrays: (verbs, points, verb offsets, point offsets), path
    which[k]'s outline verbs[vo[k]:vo[k + 1]], points[po[k]:po[k + 1]], empty where it draws
    nothing. What stroke_path makes of each path alone, undashed (join and cap as codes,
    miterlimit at least 1), from two kernel calls for them all: the subpaths of all, then
    their outlines (the stroker's scratch made once for all)."""
    return kernels.stroke_segments(
        *kernels.path_segments_batch(verbs, points, vstart, pstart, which), float(hw),
        float(tol), join, cap, float(miterlimit), False)


# -- circular arcs --------------------------------------------------------------------------

CIRCLE_RTOL = kernels.CIRCLE_RTOL     # (how exactly a conic must be a circular arc)


def circular_conics(b0, b1, mid, b2):
    """For conics (b0, b1, b2) with their points at t = ½ ((n, 2) arrays each): which are
    circular arcs, with their centres (n, 2) and radii. A conic is a circular arc when its
    control triangle is isosceles (|b0 b1| = |b1 b2|) and its weight is cos φ, φ the angle
    between the chord and either tangent (the half angle of the arc)."""
    d0, d1 = b1 - b0, b2 - b1
    l0, l1 = np.hypot(*d0.T), np.hypot(*d1.T)
    e = 0.5 * (b0 + b2) - b1                    # from b1 to the chord's midpoint
    e2 = (e * e).sum(-1)
    half = np.hypot(*(0.5 * (b2 - b0)).T)       # half the chord
    scale = np.maximum(l0, l1)
    with np.errstate(divide="ignore", invalid="ignore"):
        centre = b1 + e * (l0 * l1 / e2)[:, None]
        radius = 0.5 * (np.hypot(*(b0 - centre).T) + np.hypot(*(b2 - centre).T))
        cos_phi = half / l0
        ok = (l0 > 0) & (l1 > 0) & (e2 > 0) & (np.abs(l0 - l1) <= CIRCLE_RTOL * scale) & \
            (np.abs(conic_weight(b0, b1, mid, b2) - cos_phi) <= CIRCLE_RTOL) & \
            np.isfinite(radius)
    return ok, centre, radius


def stroke_path(path: Path, width: float, join: str = "miter", cap: str = "butt",
                miterlimit: float = 4.0, dashes=None, dash_offset: float = 0.0,
                tolerance: float = 0.25, resolution: float = 1.0) -> Path:
    """The outline of ``path`` stroked with ``width``, to be filled with the nonzero rule.

    ``tolerance`` bounds the distance between the approximated and the true offset curves, in
    the path's units (callers pass 0.25 device pixels divided by the device scale).
    ``join`` is one of JOINS ("arcs" falls back to "miter"), ``cap`` one of CAPS.
    ``dashes`` is the stroke-dasharray (odd counts repeat, negative values disable dashing,
    all zeros draw solid); ``dash_offset`` shifts the pattern's start (negative allowed).
    ``resolution`` is the device pixels a path unit spans (:func:`dash_resolution`): the
    dashes' lengths are measured with chords within half a device pixel, as resvg does.
    """
    hw = width / 2.0
    if not (hw > 0 and math.isfinite(hw)):
        return Path.from_arrays(np.empty(0, np.uint8), np.empty((0, 2)))
    miterlimit = max(1.0, miterlimit)
    pattern = dash_pattern(dashes)
    verbs = path.verbs
    # lines only (a test on the verb bytes: numpy calls cost more on the short paths of maps)
    if not verbs.tobytes().translate(None, _LINE_VERBS):
        # (the kernels' arrays are in Path's stored form: no conversions)
        return Path._of_arrays(*_line_outline(verbs, path.points, hw, tolerance, join, cap,
                                              miterlimit, pattern, dash_offset))
    if pattern is None:
        segments = _path_segments(path)
    else:
        # (circular arcs stay exact conics: the dasher measures them by usvg's cubics and
        # cuts them at the angles of the cubics' points; other conics become those cubics)
        segments = kernels.dash_segments(*_path_segments(dash_curves(path, hw)),
                                         np.asarray(pattern, np.float64), float(dash_offset),
                                         _chord_tolerance(resolution))
    return Path._of_arrays(*_segments_outline(segments, hw, tolerance, join, cap, miterlimit))


# -- dashes ---------------------------------------------------------------------------------

def dash_pattern(dashes):
    """The effective dash array, or None for a solid stroke (SVG rules: odd counts repeat,
    any negative value or an all-zero sum makes the stroke solid)."""
    if dashes is None:
        return None
    values = [float(v) for v in dashes]
    if not values or any(v < 0 or not math.isfinite(v) for v in values) or sum(values) <= 0:
        return None
    if len(values) % 2:
        values = values * 2
    return values


#: Dash patterns repeating faster than this (device px), or cutting one path into more than
#: MAX_DASHES dashes, are drawn as a solid stroke faded by the pattern's coverage (see
#: dash_coverage): below a pixel the dashes are a coverage, not millions of segments.
MIN_DASH_PERIOD = 1.0
MAX_DASHES = 100_000


def dash_coverage(pattern, path: Path, width: float, cap: str, device_scale: float):
    """None when the dashes are drawn as dashes; else the fraction of the solid stroke they
    cover (per period: the dashes plus their caps, at most 1), for a dash pattern too fine for
    the device (MIN_DASH_PERIOD) or too long a path (MAX_DASHES)."""
    period = sum(pattern)
    if period * device_scale >= MIN_DASH_PERIOD:
        pts = path.points        # the control polygon is at least as long as the path
        if len(pts) < 2 or np.abs(np.diff(pts, axis=0)).sum() <= MAX_DASHES * period:
            return None
    caps = {"butt": 0.0, "square": width, "round": width * math.pi / 4}.get(cap, 0.0)
    covered = sum(pattern[0::2]) + caps * (len(pattern) // 2)
    return min(1.0, covered / period)


def dash_resolution(m) -> float:
    """The device pixels a unit spans under the transform ``m`` (a, b, c, d, e, f), as
    tiny-skia reckons it for dashing and stroking (PathStroker::compute_resolution_scale: the
    longer of the lengths of (a, c) and (b, d); 1 when that is 0 or not finite)."""
    a, b, c, d = m[:4]
    scale = max(math.hypot(a, c), math.hypot(b, d))
    return scale if scale > 0 and math.isfinite(scale) else 1.0


def _chord_tolerance(resolution: float) -> float:
    """How far the dasher's contour measure lets a curve's control points be off its chord
    (tiny-skia's and Skia's CHEAP_DIST_LIMIT, half a device pixel), in path units."""
    return 0.5 / resolution if resolution > 0 and math.isfinite(resolution) else 0.5


def dash_length(path: Path, resolution: float = 1.0) -> float:
    """The total length of ``path`` as the dasher measures it (chords within half a device
    pixel, see stroke_path; closing lines included, the gaps between subpaths not): the user
    agent's path length that a ``pathLength`` attribute calibrates dashes against, so that a
    pattern dividing the author's length divides this one exactly."""
    kinds, segs, _, _ = _path_segments(dash_curves(path, 0.0))
    return float(kernels.dash_length(kinds, segs, _chord_tolerance(resolution)))


def dash_curves(path: Path, hw: float) -> Path:
    """``path`` as the dasher takes it: conics that are circular arcs of radius above hw
    kept (exact: their offsets by ±hw are conics again), every other conic replaced by the
    cubics usvg makes of that arc (:func:`arc_cubics`)."""
    v, p = path._freeze()
    if CONIC not in v.tobytes():
        return path
    at = np.cumsum(np.asarray(VERB_POINTS)[v])[v == CONIC] - 3    # index of every conic's b1
    ok, _, radius = circular_conics(p[at - 1], p[at], p[at + 1], p[at + 2])
    return arc_cubics(path, keep=ok & (radius > hw))


def arc_cubics(path: Path, keep=None) -> Path:
    """``path`` with every conic (but those ``keep`` marks, in the order of the path's
    conics) replaced by the cubics usvg draws that arc as: kurbo's Arc::append_iter at
    usvg's tolerance, which cuts an arc of the ellipse with radii rx, ry into
    n = ⌈max(4, (1.1163·max(rx, ry)/0.1)^(1/6))·sweep/2π⌉ (less a hair) equal angles, each a
    cubic with its handles 4/3·tan(angle/4) along the tangents. Circles, rounded corners and
    path arcs reach usvg as such arcs, a conic here each (svg/shapes.py, svg/pathdata._arc
    cut them as usvg does), so for radii under ~367 units a conic is one cubic,
    Path.without_conics's own. (At most kernels.MAX_ARC_CUBICS an arc: kurbo's count grows
    without bound.)"""
    v, p = path._freeze()
    if CONIC not in v.tobytes():
        return path
    keep = _KEEP_NONE if keep is None else np.asarray(keep, np.bool_)
    if len(keep) and keep.all():
        return path
    return Path._of_arrays(*conics_as_cubics(v, p, keep, kernels.ARC_TOLERANCE,
                                             kernels.MAX_ARC_CUBICS))


# -- markers --------------------------------------------------------------------------------


