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
centre; their dashes are cut at exact arc lengths (r·angle). Elliptical arcs, and arcs no
wider than the stroke's half width (whose inner offset folds), are stroked as the cubics of
Path.without_conics, like every other curve:

Offsets of curves are cubic Béziers fitted to the true offset (exact end points and tangents, the
midpoint matched), subdivided until within ``tolerance`` at the quarter points; where the offset
folds (bends tighter than half the width) or will not fit, pieces are split until flat within
half the tolerance and stroked as chords with round joins. Errors add up there: a chord off the
curve by f moves its whole stroke by up to f, so the joins and caps at a chord's ends are drawn
within the rest of the tolerance (tolerance − f, at least half of it).

Strokes are drawn by the compiled kernels in :mod:`vecmsaa.geometry.stroke_kernels`: paths of
straight lines only (map data), dashes and all, by stroke_lines; paths with curves, and the
dashes of curves (measured and cut here), by stroke_segments.

Conventions: for a direction d, the left normal is n = (-d.y, d.x); "left" offsets are P + w/2·n.
"""
from __future__ import annotations

import math

import numpy as np

from . import stroke_kernels as kernels
from .arclength import as_cubic, cubic_exact_params, cubic_lengths, cubic_rows, gl_nodes
from .arclength import cubic_derivative as _cubic_deriv
from ..scene.path import CLOSE, CONIC, LINE, MOVE, VERB_POINTS, Path, conic_weight

JOINS = ("miter", "miter-clip", "round", "bevel", "arcs")
CAPS = ("butt", "round", "square")


# -- small vector helpers on (x, y) tuples (pure Python: faster than numpy for 2-vectors) ----

def _unit(dx, dy):
    n = math.hypot(dx, dy)
    if n == 0.0 or not math.isfinite(n):
        return None
    return dx / n, dy / n


def _split_cubic(c, t):
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = c
    ax, ay = x0 + (x1 - x0) * t, y0 + (y1 - y0) * t
    bx, by = x1 + (x2 - x1) * t, y1 + (y2 - y1) * t
    cx, cy = x2 + (x3 - x2) * t, y2 + (y3 - y2) * t
    dx, dy = ax + (bx - ax) * t, ay + (by - ay) * t
    ex, ey = bx + (cx - bx) * t, by + (cy - by) * t
    fx, fy = dx + (ex - dx) * t, dy + (ey - dy) * t
    return ((x0, y0), (ax, ay), (dx, dy), (fx, fy)), ((fx, fy), (ex, ey), (cx, cy), (x3, y3))


def _sub_cubic(c, t0, t1):
    """The part of cubic c between parameters t0 < t1."""
    if t1 < 1.0:
        c = _split_cubic(c, t1)[0]
        t0 = t0 / t1 if t1 > 0 else 0.0
    if t0 > 0.0:
        c = _split_cubic(c, t0)[1]
    return c


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


def _segment_arrays(parts):
    """The curve stroker's input (see kernels.stroke_segments) for parts: (segments as
    control point tuples, closed) subpaths, or (point, direction) for zero-length dashes."""
    kinds, rows, subs, flags = [], [], [], []
    for first, second in parts:
        subs.append(len(kinds))
        if isinstance(first, list):
            flags.append(kernels.SUB_CLOSED if second else kernels.SUB_OPEN)
            for seg in first:
                kinds.append(5 if isinstance(seg, _Conic) else len(seg))
                row = [c for p in seg for c in p]
                rows.append(row + [0.0] * (8 - len(row)))
        else:
            flags.append(kernels.SUB_DOT)
            kinds.append(0)
            rows.append([*first, *second, 0.0, 0.0, 0.0, 0.0])
    subs.append(len(kinds))
    return (np.array(kinds, np.int64), np.array(rows, np.float64).reshape(-1, 8),
            np.array(subs, np.int64), np.array(flags, np.int64))


def _segments_outline(segments, hw, tol, join, cap, miterlimit, general=False):
    """Outline arrays of kernels.path_segments-style subpaths, from the compiled stroker
    (general: lines too go through the curve stroker, as the tests compare them)."""
    return kernels.stroke_segments(*segments, float(hw), float(tol),
                                   kernels.JOIN_CODES.get(join, 0),
                                   kernels.CAP_CODES.get(cap, 0), float(miterlimit), general)


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


def exact_conics(path: Path, hw: float) -> Path:
    """``path`` with the conics that are circular arcs of radius above hw kept (their offsets
    by ±hw are conics again) and every other conic replaced by Path.without_conics's cubic."""
    v, p = path._freeze()
    if CONIC not in v.tobytes():
        return path
    ends = np.cumsum(np.asarray(VERB_POINTS)[v])
    conics = np.flatnonzero(v == CONIC)
    at = ends[conics] - 3           # index of b1 of every conic
    ok, _, radius = circular_conics(p[at - 1], p[at], p[at + 1], p[at + 2])
    keep = ok & (radius > hw)
    if keep.all():
        return path
    cubic = path.without_conics()
    if not keep.any():
        return cubic
    cv, q = cubic.verbs.copy(), cubic.points.copy()
    cv[conics[keep]] = CONIC
    for k in (0, 1):
        q[at[keep] + k] = p[at[keep] + k]
    return Path._of_arrays(cv, q)


class _Conic(tuple):
    """A conic segment as the dasher takes it: (b0, b1, point at t = ½, b2), a circular arc."""
    __slots__ = ()


# -- subpaths of a Path ----------------------------------------------------------------------

def _subpaths(path):
    """[(segments as control point tuples, closed)] with the closing line made explicit.
    Subpaths with a moveto alone are dropped (they are not stroked); others are kept even if
    all their segments have zero length (they get dots with round or square caps)."""
    verbs = path.verbs
    pts = list(map(tuple, path.points.tolist()))
    out = []
    segs: list = []
    start = cur = None
    drawn = False
    i = 0
    for v in verbs.tolist():
        n = VERB_POINTS[v]
        if v == MOVE:
            if drawn:
                out.append((segs, False))
            segs, drawn = [], False
            start = cur = pts[i]
        elif v == CLOSE:
            if start is not None:
                segs.append((cur, start))
                out.append((segs, True))
                cur = start
            segs, drawn = [], False
        else:
            ctrl = (cur, *pts[i:i + n])
            segs.append(_Conic(ctrl) if v == CONIC else ctrl)
            drawn = True
            cur = ctrl[-1]
        i += n
    if drawn:
        out.append((segs, False))
    return out


def stroke_path(path: Path, width: float, join: str = "miter", cap: str = "butt",
                miterlimit: float = 4.0, dashes=None, dash_offset: float = 0.0,
                tolerance: float = 0.25) -> Path:
    """The outline of ``path`` stroked with ``width``, to be filled with the nonzero rule.

    ``tolerance`` bounds the distance between the approximated and the true offset curves, in
    the path's units (callers pass 0.25 device pixels divided by the device scale).
    ``join`` is one of JOINS ("arcs" falls back to "miter"), ``cap`` one of CAPS.
    ``dashes`` is the stroke-dasharray (odd counts repeat, negative values disable dashing,
    all zeros draw solid); ``dash_offset`` shifts the pattern's start (negative allowed).
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
        segments = kernels.path_segments(np.ascontiguousarray(verbs, dtype=np.uint8),
                                         np.ascontiguousarray(path.points, dtype=np.float64))
    else:
        # (the kernels keep circular arcs exact and stroke other conics as their cubics)
        exact = exact_conics(path, hw)
        if CONIC not in exact.verbs.tobytes():
            segments = kernels.dash_segments(
                *kernels.path_segments(np.ascontiguousarray(exact.verbs, dtype=np.uint8),
                                       np.ascontiguousarray(exact.points, dtype=np.float64)),
                np.asarray(pattern, np.float64), float(dash_offset),
                float(tolerance * DASH_ACCURACY), gl_nodes())
        else:
            # (circular arcs are measured here, exactly)
            segments = _segment_arrays(
                dash if isinstance(dash, tuple) else (dash, False)
                for segs, closed in _subpaths(exact)
                for dash in _dash_subpath(segs, closed, pattern, dash_offset, tolerance))
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


#: how exactly a dash end is placed along a curve, as a fraction of the flattening tolerance
DASH_ACCURACY = 1 / 4096


class _Measured:
    """A straight or cubic segment (a quadratic is raised exactly) measured by
    geometry/arclength.py's kernels; ``row`` is its row among the cubics of :func:`_measure`."""

    def __init__(self, seg):
        if len(seg) == 3:            # quadratic: raised exactly
            seg = tuple((float(x), float(y)) for x, y in as_cubic(seg[0], seg[1:]))
        self.seg = seg
        self.row = -1
        if len(seg) == 2:
            self.length = math.hypot(seg[1][0] - seg[0][0], seg[1][1] - seg[0][1])

    def line_t(self, s):
        """Parameter at arc length s of a straight segment."""
        return s / self.length if self.length > 0 else 0.0

    def part(self, t0, t1):
        """The segment between parameters t0 and t1."""
        seg = self.seg
        if len(seg) == 2:
            (x0, y0), (x1, y1) = seg
            return ((x0 + (x1 - x0) * t0, y0 + (y1 - y0) * t0),
                    (x0 + (x1 - x0) * t1, y0 + (y1 - y0) * t1))
        return _sub_cubic(seg, t0, t1)

    def direction(self, t):
        seg = self.seg
        if len(seg) == 2:
            return _unit(seg[1][0] - seg[0][0], seg[1][1] - seg[0][1]) or (1.0, 0.0)
        return _unit(*_cubic_deriv(seg, t)) or (segment_tangents(seg) or ((1.0, 0.0),))[0]


def _measure(segs, tol):
    """The segments measured, and a function giving the parameters at arc lengths of many
    (segment index, arc length) requests at once (one kernel call for all of a subpath's
    curves: per request in Python, Newton's search cost ~75 µs)."""
    measured = [_MeasuredArc(s) if isinstance(s, _Conic) else _Measured(s) for s in segs]
    curves = [m for m in measured if isinstance(m, _Measured) and len(m.seg) == 4]
    if curves:
        rows = cubic_rows([m.seg for m in curves])
        lengths = cubic_lengths(rows, gl_nodes())
        for i, m in enumerate(curves):
            m.row, m.length = i, float(lengths[i])

    def params(requests):
        """Parameters for (index, arc length) requests on straight and cubic segments."""
        which = [measured[j].row for j, _ in requests]
        out = [measured[j].line_t(s) if w < 0 else 0.0 for (j, s), w in zip(requests, which)]
        on_curves = [k for k, w in enumerate(which) if w >= 0]
        if on_curves:
            ts = cubic_exact_params(rows, lengths, np.array([which[k] for k in on_curves], np.int64),
                                    np.array([requests[k][1] for k in on_curves], np.float64),
                                    float(tol * DASH_ACCURACY), gl_nodes())
            for k, t in zip(on_curves, ts.tolist()):
                out[k] = t
        return out
    return measured, params


class _MeasuredArc:
    """A circular conic measured exactly: its length is r·θ (θ the angle it spans) and the
    part between two arc lengths is the conic of that sub-arc (from the centre, the radius and
    the angles; the original end points where a part reaches an end)."""

    def __init__(self, seg):
        self.seg = seg
        b0, b1, mid, b2 = (np.array([q], np.float64) for q in seg)
        _, centre, radius = circular_conics(b0, b1, mid, b2)
        self.cx, self.cy = float(centre[0, 0]), float(centre[0, 1])
        self.r = float(radius[0])
        (x0, y0), (x1, y1), _, (x2, y2) = seg
        # the half angle φ: between the chord and the tangent at b0
        half = math.hypot(0.5 * (x2 - x0), 0.5 * (y2 - y0))
        rise = math.hypot(0.5 * (x0 + x2) - x1, 0.5 * (y0 + y2) - y1)
        self.angle = 2.0 * math.atan2(rise, half)
        self.length = self.r * self.angle
        self.a0 = math.atan2(y0 - self.cy, x0 - self.cx)
        # turning towards increasing angles (y down: the centre on the tangent's left) or not
        self.sense = 1.0 if (x1 - x0) * (y0 - self.cy) - (y1 - y0) * (x0 - self.cx) < 0 else -1.0

    def _at(self, a):
        b = self.a0 + self.sense * a
        return self.cx + self.r * math.cos(b), self.cy + self.r * math.sin(b)

    def part(self, s0, s1):
        a0 = min(max(s0 / self.r, 0.0), self.angle)
        a1 = min(max(s1 / self.r, 0.0), self.angle)
        p0 = self.seg[0] if a0 <= 0.0 else self._at(a0)
        p1 = self.seg[3] if a1 >= self.angle else self._at(a1)
        if a0 <= 0.0 and a1 >= self.angle:
            return self.seg
        half = 0.5 * (a1 - a0)
        if self.r * (1.0 - math.cos(half)) <= 1e-9 * self.r:    # flat to rounding: a line
            return (p0, p1)
        mid = self._at(a0 + half)
        k = 1.0 / math.cos(half)
        b1 = (self.cx + k * (mid[0] - self.cx), self.cy + k * (mid[1] - self.cy))
        return _Conic((p0, b1, mid, p1))

    def direction(self, s):
        b = self.a0 + self.sense * min(max(s / self.r, 0.0), self.angle)
        return (-self.sense * math.sin(b), self.sense * math.cos(b))


def dash_length(path: Path) -> float:
    """The total length of ``path`` as the dasher measures it (circular arcs exactly, r·θ;
    closing lines included, the gaps between subpaths not): the user agent's path length that
    a ``pathLength`` attribute calibrates dashes against, so that a pattern dividing the
    author's length divides this one exactly."""
    return sum(m.length for segs, _ in _subpaths(exact_conics(path, 0.0))
               for m in _measure(segs, 0.25)[0])


def _dash_subpath(segs, closed, pattern, offset, tol):
    """Dashes of one subpath: lists of segments, or (point, direction) for zero-length dashes.
    On a closed subpath a dash running through the start point is one dash (as in Skia, and so
    in browsers and resvg), joined there rather than capped twice."""
    measured, params = _measure(segs, tol)
    total = sum(m.length for m in measured)
    period = sum(pattern)
    # position within the pattern at the subpath's start
    phase = offset % period
    if phase >= period:     # (a tiny negative offset rounds to the period: as the kernels do)
        phase -= period
    k = 0
    # intervals are half open, except that a zero-length dash right at the phase is drawn
    while phase > pattern[k] or (phase == pattern[k] and pattern[k] > 0):
        phase -= pattern[k]
        k = (k + 1) % len(pattern)
    dashes = []
    # walk the pattern intervals along the subpath
    pos = -phase                     # subpath arc length where the current interval starts
    seg_i, seg_start = 0, 0.0        # current segment and the arc length where it starts
    guard = 0
    first_at_start = last_at_end = False
    while pos < total and guard < 1_000_000:
        guard += 1
        length = pattern[k]
        on = k % 2 == 0
        a, b = max(pos, 0.0), min(pos + length, total)
        if on and b >= a and (b > a or pos >= 0):
            dash = []
            # find segments overlapping [a, b]
            while seg_i < len(measured) - 1 and seg_start + measured[seg_i].length < a:
                seg_start += measured[seg_i].length
                seg_i += 1
            if b == a:
                m = measured[seg_i]
                dashes.append((seg_i, min(max(a - seg_start, 0.0), m.length)))
            else:
                j, js = seg_i, seg_start
                while j < len(measured) and js < b:
                    m = measured[j]
                    lo, hi = max(a - js, 0.0), min(b - js, m.length)
                    if hi > lo:
                        dash.append((j, lo, hi))
                    js += m.length
                    j += 1
                if dash:
                    dashes.append(dash)
                    if a == 0.0:
                        first_at_start = True
                    last_at_end = b >= total
        pos += length
        k = (k + 1) % len(pattern)
    dashes = _cut(dashes, measured, params)
    if closed and first_at_start and last_at_end and isinstance(dashes[-1], list):
        # the last dash runs on into the first one of segments (a zero-length dash, a dot,
        # may come before it at the start: the compiled dasher merges past it too)
        first = next(i for i, d in enumerate(dashes) if isinstance(d, list))
        if first < len(dashes) - 1:
            dashes[first] = dashes.pop() + dashes[first]
    return dashes


def _cut(plan, measured, params):
    """The dashes of a plan (lists of (segment, from, to) arc lengths; (segment, at) for a
    zero-length dash) as segments, and (point, direction) for zero-length dashes, with every
    parameter on the subpath's curves found in one call."""
    requests = []
    for d in plan:
        for piece in (d if isinstance(d, list) else (d,)):
            if not isinstance(measured[piece[0]], _MeasuredArc):
                requests.extend((piece[0], s) for s in piece[1:])
    ts = iter(params(requests))
    out = []
    for d in plan:
        if isinstance(d, list):
            out.append([measured[j].part(lo, hi) if isinstance(measured[j], _MeasuredArc)
                        else measured[j].part(next(ts), next(ts)) for j, lo, hi in d])
            continue
        j, at = d
        m = measured[j]
        if isinstance(m, _MeasuredArc):
            out.append((m.part(at, at)[0], m.direction(at)))
        else:
            t = next(ts)
            out.append((m.part(t, t)[0], m.direction(t)))
    return out


# -- markers --------------------------------------------------------------------------------


