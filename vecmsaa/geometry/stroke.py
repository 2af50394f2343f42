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

Offsets of curves are cubic Béziers fitted to the true offset (exact end points and tangents, the
midpoint matched), subdivided until within ``tolerance`` at the quarter points; where the offset
folds (bends tighter than half the width) or will not fit, pieces are split until flat within
half the tolerance and stroked as chords with round joins. Errors add up there: a chord off the
curve by f moves its whole stroke by up to f, so the joins and caps at a chord's ends are drawn
within the rest of the tolerance (tolerance − f, at least half of it).

Paths of straight lines only (map data), dashes and all, are stroked by the compiled kernels in
:mod:`vecmsaa.stroke_kernels`; so are the join, cap and dot shapes of the curve stroker here, and
the line-only subpaths and dashes of paths with curves.

Conventions: for a direction d, the left normal is n = (-d.y, d.x); "left" offsets are P + w/2·n.
"""
from __future__ import annotations

import math

import numpy as np

from . import stroke_kernels as kernels
from .arclength import as_cubic, cubic_exact_param_at, cubic_length
from .arclength import cubic_derivative as _cubic_deriv
from ..scene.path import CLOSE, CUBIC, LINE, MOVE, VERB_POINTS, Path

JOINS = ("miter", "miter-clip", "round", "bevel", "arcs")
CAPS = ("butt", "round", "square")

_MAX_DEPTH = 12          # curve subdivision depth: 4096 pieces at most per segment
_SMOOTH_COS = kernels.SMOOTH_COS           # tangents this close need no join


# -- small vector helpers on (x, y) tuples (pure Python: faster than numpy for 2-vectors) ----

def _unit(dx, dy):
    n = math.hypot(dx, dy)
    if n == 0.0 or not math.isfinite(n):
        return None
    return dx / n, dy / n


def _cubic_point(c, t):
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = c
    u = 1.0 - t
    a, b, cc, d = u * u * u, 3 * u * u * t, 3 * u * t * t, t * t * t
    return a * x0 + b * x1 + cc * x2 + d * x3, a * y0 + b * y1 + cc * y2 + d * y3


def _cubic_deriv2(c, t):
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = c
    u = 1.0 - t
    return (6 * (u * (x2 - 2 * x1 + x0) + t * (x3 - 2 * x2 + x1)),
            6 * (u * (y2 - 2 * y1 + y0) + t * (y3 - 2 * y2 + y1)))


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


# -- output ---------------------------------------------------------------------------------

class _Out:
    """The outline being built: contours from Python items, and arrays from the kernels."""

    def __init__(self):
        self.verbs: list[int] = []
        self.pts: list[tuple[float, float]] = []
        self.chunks: list[tuple[np.ndarray, np.ndarray]] = []

    def contour(self, items):
        """items: a start point, then (verb, points...) tuples, the contour being closed.
        Callers build every contour (or pair of loops) as a sum of positive pieces."""
        self.verbs.append(MOVE)
        self.pts.append(items[0])
        for s in items[1:]:
            self.verbs.append(s[0])
            self.pts.extend(s[1:])
        self.verbs.append(CLOSE)

    def arrays(self, verbs, pts):
        """Contours made by a kernel."""
        self._flush()
        self.chunks.append((verbs, pts))

    def _flush(self):
        if self.verbs:
            self.chunks.append((np.asarray(self.verbs, dtype=np.uint8),
                                np.asarray(self.pts, dtype=np.float64).reshape(-1, 2)))
            self.verbs, self.pts = [], []

    def path(self) -> Path:
        self._flush()
        if not self.chunks:
            return Path.from_arrays(np.empty(0, np.uint8), np.empty((0, 2)))
        if len(self.chunks) == 1:
            return Path.from_arrays(*self.chunks[0])
        return Path.from_arrays(np.concatenate([v for v, _ in self.chunks]),
                                np.concatenate([p for _, p in self.chunks]))


def _reverse_contour(start, segs):
    """The same closed contour traversed backwards."""
    ends = [start] + [s[-1] for s in segs]
    out = []
    for i in range(len(segs) - 1, -1, -1):
        s = segs[i]
        ctrl = list(reversed(s[1:-1]))
        out.append((s[0], *ctrl, ends[i]))
    return ends[-1], out


# -- geometry of one segment ----------------------------------------------------------------

class _Piece:
    """A piece of a segment: source control points (2 for lines, 4 for cubics), unit tangents
    at both ends, the control points of its right and left offsets, and err: how far the
    source may be from the true segment (a chord's flatness; 0 where it is exact)."""
    __slots__ = ("src", "t0", "t1", "right", "left", "err")

    def __init__(self, src, t0, t1, right, left, err=0.0):
        self.src, self.t0, self.t1 = src, t0, t1
        self.right, self.left = right, left
        self.err = err


def _line_piece(p0, p1, d, hw, err=0.0):
    nx, ny = -d[1] * hw, d[0] * hw
    return _Piece((p0, p1), d, d,
                  ((p0[0] - nx, p0[1] - ny), (p1[0] - nx, p1[1] - ny)),
                  ((p0[0] + nx, p0[1] + ny), (p1[0] + nx, p1[1] + ny)), err)


def _shape_tol(tol, *pieces):
    """Tolerance left for a join or cap at the ends of pieces: a chord's own error f moves the
    stroke around it by up to f, so the shape gets tol − f (at least tol / 2, chords being
    flat within that unless subdivision ran out of depth)."""
    return tol - min(max(p.err for p in pieces), tol / 2)


def _curvature(c, t):
    dx, dy = _cubic_deriv(c, t)
    sp2 = dx * dx + dy * dy
    if sp2 < 1e-24:
        return math.inf
    ex, ey = _cubic_deriv2(c, t)
    return (dx * ey - dy * ex) / (sp2 * math.sqrt(sp2))


def _offset_point(c, t, off):
    """Point of the true offset at parameter t (off = signed distance along the left normal)."""
    d = _unit(*_cubic_deriv(c, t))
    if d is None:
        return None
    x, y = _cubic_point(c, t)
    return x - d[1] * off, y + d[0] * off


def _fit_offset(c, t0, t1, off):
    """Cubic approximating the offset of cubic c by off (signed, along the left normal):
    end points and tangents exact, handle lengths chosen so the midpoints agree."""
    p0, p1, p2, p3 = c
    q0 = (p0[0] - t0[1] * off, p0[1] + t0[0] * off)
    q3 = (p3[0] - t1[1] * off, p3[1] + t1[0] * off)
    m = _offset_point(c, 0.5, off)
    a = b = None
    det = t1[0] * t0[1] - t0[0] * t1[1]     # det of [t0, -t1]
    if m is not None and abs(det) > 1e-9:
        # solve a·t0 − b·t1 = 8/3·(m − (q0 + q3)/2)
        rx = 8.0 / 3.0 * (m[0] - (q0[0] + q3[0]) / 2)
        ry = 8.0 / 3.0 * (m[1] - (q0[1] + q3[1]) / 2)
        a = (rx * (-t1[1]) - ry * (-t1[0])) / det
        b = (t0[0] * ry - t0[1] * rx) / det
        if a < 0 or b < 0:
            a = b = None
    if a is None:
        # parallel end tangents: scale the source handles by the offset's speed ratio
        k0 = _curvature(c, 0.0)
        k1 = _curvature(c, 1.0)
        a = math.hypot(p1[0] - p0[0], p1[1] - p0[1]) * max(0.0, 1 - off * k0) \
            if math.isfinite(k0) else 0.0
        b = math.hypot(p3[0] - p2[0], p3[1] - p2[1]) * max(0.0, 1 - off * k1) \
            if math.isfinite(k1) else 0.0
    return (q0, (q0[0] + a * t0[0], q0[1] + a * t0[1]),
            (q3[0] - b * t1[0], q3[1] - b * t1[1]), q3)


def _offset_error(c, fit, off):
    err = 0.0
    for t in (0.25, 0.75):
        true = _offset_point(c, t, off)
        if true is None:
            return math.inf
        x, y = _cubic_point(fit, t)
        err = max(err, math.hypot(x - true[0], y - true[1]))
    return err


def _cubic_pieces(c, hw, tol, out_pieces, depth=0):
    """Pieces of cubic c: offset cubics where they fit within tol, else halves, down to pieces
    flat within tol / 2, which become their chords. Stroked with round joins between them (the
    stroker's rule inside a curve), chords are within tol / 2 of the curve's stroke: the round-
    joined stroke of a polyline is its Minkowski sum with the pen disc. That is also how
    bends tighter than the half width are handled, where the offset folds back on itself.
    The joins' and caps' arcs may lie inside the disc by their own tolerance, which adds to
    the chord's: they get what the chord leaves (see _shape_tol)."""
    tans = segment_tangents(c)
    if tans is None:
        return
    t0, t1 = tans
    # a piece turning by more than 90° is split so the midpoint fit stays well posed
    ok = t0[0] * t1[0] + t0[1] * t1[1] >= 0.0
    if ok:
        # a bend tighter than hw on a side makes that side's offset fold back
        for t in (0.0, 0.5, 1.0):
            k = _curvature(c, t)
            if not math.isfinite(k) or hw * abs(k) >= 1.0:
                ok = False
                break
    if ok:
        fits = []
        for side in (-1.0, 1.0):
            fit = _fit_offset(c, t0, t1, side * hw)
            if _offset_error(c, fit, side * hw) > tol:
                ok = False
                break
            fits.append(fit)
    if ok:
        out_pieces.append(_Piece(c, t0, t1, fits[0], fits[1]))
        return
    flat = _flatness(c)
    if depth < _MAX_DEPTH and flat > tol / 2:
        a, b = _split_cubic(c, 0.5)
        _cubic_pieces(a, hw, tol, out_pieces, depth + 1)
        _cubic_pieces(b, hw, tol, out_pieces, depth + 1)
        return
    d = _unit(c[3][0] - c[0][0], c[3][1] - c[0][1])
    if d:
        out_pieces.append(_line_piece(c[0], c[3], d, hw, flat))
    else:
        # a closed loop too small to matter (or depth exhausted): two chords via its midpoint
        pm = _cubic_point(c, 0.5)
        for q0, q1 in ((c[0], pm), (pm, c[3])):
            d = _unit(q1[0] - q0[0], q1[1] - q0[1])
            if d:
                out_pieces.append(_line_piece(q0, q1, d, hw, flat))


def _flatness(c):
    """An upper bound of the cubic's distance from its chord: the control points' distance
    from the chord segment (not its line: a curve can overshoot along the chord)."""
    (x0, y0), _, _, (x3, y3) = c
    dx, dy = x3 - x0, y3 - y0
    l2 = dx * dx + dy * dy
    worst = 0.0
    for x, y in c[1:3]:
        t = ((x - x0) * dx + (y - y0) * dy) / l2 if l2 > 0 else 0.0
        t = min(1.0, max(0.0, t))
        worst = max(worst, math.hypot(x - x0 - t * dx, y - y0 - t * dy))
    return worst


def _segment_pieces(seg, hw, tol):
    """Pieces of one segment (control points tuple), or [] for a zero-length segment."""
    if len(seg) == 2:
        d = _unit(seg[1][0] - seg[0][0], seg[1][1] - seg[0][1])
        return [_line_piece(seg[0], seg[1], d, hw)] if d else []
    if len(seg) == 3:       # quadratic → the identical cubic
        p0, p1, p2 = seg
        seg = (p0, (p0[0] + 2 / 3 * (p1[0] - p0[0]), p0[1] + 2 / 3 * (p1[1] - p0[1])),
               (p2[0] + 2 / 3 * (p1[0] - p2[0]), p2[1] + 2 / 3 * (p1[1] - p2[1])), p2)
    pieces: list[_Piece] = []
    _cubic_pieces(seg, hw, tol, pieces)
    return pieces


# -- contours -------------------------------------------------------------------------------

def _side_items(pieces, attr):
    """The path along one side of a run of pieces (their offsets, joined by straight lines
    where consecutive offsets do not quite meet): a start point, then items."""
    items = [getattr(pieces[0], attr)[0]]
    for p in pieces:
        ctrl = getattr(p, attr)
        if len(items) > 1 and items[-1][-1] != ctrl[0]:
            items.append((LINE, ctrl[0]))
        items.append((LINE, ctrl[1]) if len(ctrl) == 2 else (CUBIC, *ctrl[1:]))
    return items


def _kernel_items(kernel, *args):
    """Items (verb, points...) written by a join or cap kernel."""
    verbs = np.empty(8, np.uint8)
    pts = np.empty((16, 2))
    cnt = np.zeros(2, np.int64)
    kernel(verbs, pts, cnt, *args)
    pts = list(map(tuple, pts[:cnt[1]].tolist()))
    items, i = [], 0
    for v in verbs[:cnt[0]].tolist():
        n = VERB_POINTS[v]
        items.append((v, *pts[i:i + n]))
        i += n
    return items


def _cap_items(p, d, hw, cap, tol):
    """Items from the right offset to the left offset at an end p with outward direction d."""
    return _kernel_items(kernels.cap_items, float(p[0]), float(p[1]), float(d[0]), float(d[1]),
                         float(hw), kernels.CAP_CODES.get(cap, 0), float(tol))


def _outer_join_items(p, d0, d1, side, hw, join, miterlimit, dot, tol):
    """Items along the outer side (side: +1 left, -1 right) of a turn at p from direction d0
    to d1 (see kernels.outer_join_items)."""
    return _kernel_items(kernels.outer_join_items, float(p[0]), float(p[1]), float(d0[0]),
                         float(d0[1]), float(d1[0]), float(d1[1]), float(side), float(hw),
                         kernels.JOIN_CODES.get(join, 0), float(miterlimit), float(dot),
                         float(tol))


def _emit_dot(out, p, hw, cap, tol, d=(1.0, 0.0)):
    """A zero-length subpath: a disc for round caps, a square (along d) for square caps."""
    verbs = np.empty(8, np.uint8)
    pts = np.empty((16, 2))
    cnt = np.zeros(2, np.int64)
    kernels.dot_contour(verbs, pts, cnt, float(p[0]), float(p[1]), float(d[0]), float(d[1]),
                        float(hw), kernels.CAP_CODES.get(cap, 0), float(tol))
    if cnt[0]:
        out.arrays(verbs[:cnt[0]], pts[:cnt[1]])


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


def _stroke_subpath(out, segs, closed, hw, tol, join, cap, miterlimit):
    """segs: control point tuples of one subpath (closing line included when closed)."""
    if all(len(seg) == 2 for seg in segs):
        pts = [seg[0] for seg in segs] + [segs[-1][1]]
        verbs = [MOVE] + [LINE] * (len(pts) - 1) + ([CLOSE] if closed else [])
        out.arrays(*_line_outline(verbs, pts, hw, tol, join, cap, miterlimit))
        return
    _stroke_pieces(out, segs, closed, hw, tol, join, cap, miterlimit)


def _stroke_pieces(out, segs, closed, hw, tol, join, cap, miterlimit):
    """The general stroker: segments become pieces (lines, offset cubics, chords) grouped
    into runs with continuous tangents, joined inline."""
    # runs: consecutive pieces with continuous tangents; a join between runs
    runs: list[list[_Piece]] = []
    run_joins: list[str] = []    # join kind before each run (intra-curve kinks are round)
    for seg in segs:
        pieces = _segment_pieces(seg, hw, tol)
        first_of_seg = True
        for pc in pieces:
            if runs and not first_of_seg:
                prev = runs[-1][-1]
                if prev.t1[0] * pc.t0[0] + prev.t1[1] * pc.t0[1] > _SMOOTH_COS:
                    runs[-1].append(pc)
                    continue
            runs.append([pc])
            run_joins.append(join if first_of_seg else "round")
            first_of_seg = False
    if not runs:
        if segs:
            _emit_dot(out, segs[0][0], hw, cap, tol)
        return
    # One chain along both sides, joins and caps inline: as chains this equals the sum of the
    # separate positive pieces (a contour per run closed by butt lines, a wedge per join), as
    # explained in the kernels' _stroke_polyline, so the nonzero fill is their union.
    right = _side_items(runs[0], "right")
    left = _side_items(runs[0], "left")
    for i in range(1, len(runs) + (1 if closed else 0)):
        run = runs[i % len(runs)]
        prev = runs[i - 1][-1]
        run_right = _side_items(run, "right")
        run_left = _side_items(run, "left")
        _join_items(right, left, run[0].src[0], prev.t1, run[0].t0, hw,
                    run_joins[i] if i < len(runs) else join, miterlimit,
                    _shape_tol(tol, prev, run[0]), run_right[0], run_left[0])
        if i < len(runs):
            right += run_right[1:]
            left += run_left[1:]
    if closed:
        # the lists start where the first run starts; the closing join ended there too
        out.contour([right[-1][-1]] + right[1:])
        out.contour(_reversed_items([left[-1][-1]] + left[1:]))
        return
    first, last = runs[0][0], runs[-1][-1]
    items = right + _cap_items(last.src[-1], last.t1, hw, cap, _shape_tol(tol, last)) + \
        _reversed_items(left)[1:]
    items += _cap_items(first.src[0], (-first.t0[0], -first.t0[1]), hw, cap,
                        _shape_tol(tol, first))
    out.contour(items)


def _join_items(right, left, p, d0, d1, hw, join, miterlimit, tol, r1, l1):
    """Extend both sides across the turn at p from direction d0 to d1; r1, l1 are the next
    offsets' starts. The outer side takes the join shape, the inner side goes through p."""
    cross = d0[0] * d1[1] - d0[1] * d1[0]
    dot = d0[0] * d1[0] + d0[1] * d1[1]
    if dot > _SMOOTH_COS:
        right.append((LINE, r1))
        left.append((LINE, l1))
        return
    if cross > 0:       # turning left: left side inner
        outer, side, inner, o1, c1 = right, -1.0, left, r1, l1
    else:
        outer, side, inner, o1, c1 = left, 1.0, right, l1, r1
    items = _outer_join_items(p, d0, d1, side, hw, join, miterlimit, dot, tol)
    if items[0][-1] == outer[-1][-1]:
        items = items[1:]               # the run already ends at the offset's end
    outer.extend(items)
    if outer[-1][-1] != o1:
        outer.append((LINE, o1))
    inner.extend(((LINE, p), (LINE, c1)))


def _reversed_items(items):
    start, segs = _reverse_contour(items[0], items[1:])
    return [start] + segs


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
            segs.append(ctrl)
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
    out = _Out()
    hw = width / 2.0
    if not (hw > 0 and math.isfinite(hw)):
        return out.path()
    miterlimit = max(1.0, miterlimit)
    pattern = dash_pattern(dashes)
    verbs = path.verbs
    # lines only (a test on the verb bytes: numpy calls cost more on the short paths of maps)
    if not verbs.tobytes().translate(None, _LINE_VERBS):
        return Path.from_arrays(*_line_outline(verbs, path.points, hw, tolerance, join, cap,
                                               miterlimit, pattern, dash_offset))
    for segs, closed in _subpaths(path):
        if pattern is None:
            _stroke_subpath(out, segs, closed, hw, tolerance, join, cap, miterlimit)
            continue
        for dash in _dash_subpath(segs, closed, pattern, dash_offset, tolerance):
            if isinstance(dash, tuple):      # a zero-length dash: (point, direction)
                _emit_dot(out, dash[0], hw, cap, tolerance, dash[1])
            else:
                _stroke_subpath(out, dash, False, hw, tolerance, join, cap, miterlimit)
    return out.path()


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
    """A segment measured by geometry/arclength.py: where it is after an arc length."""

    def __init__(self, seg, tol):
        if len(seg) == 3:            # quadratic: raised exactly
            seg = tuple((float(x), float(y)) for x, y in as_cubic(seg[0], seg[1:]))
        self.seg = seg
        if len(seg) == 2:
            self.length = math.hypot(seg[1][0] - seg[0][0], seg[1][1] - seg[0][1])
        else:
            self.length = cubic_length(seg)
            self.accuracy = tol * DASH_ACCURACY

    def t_at(self, s):
        """Parameter at arc length s."""
        if len(self.seg) == 2:
            return s / self.length if self.length > 0 else 0.0
        if self.length <= 0:
            return 0.0
        return cubic_exact_param_at(self.seg, self.length, s, self.accuracy)

    def part(self, s0, s1):
        t0, t1 = self.t_at(s0), self.t_at(s1)
        seg = self.seg
        if len(seg) == 2:
            (x0, y0), (x1, y1) = seg
            return ((x0 + (x1 - x0) * t0, y0 + (y1 - y0) * t0),
                    (x0 + (x1 - x0) * t1, y0 + (y1 - y0) * t1))
        return _sub_cubic(seg, t0, t1)

    def direction(self, s):
        seg = self.seg
        if len(seg) == 2:
            return _unit(seg[1][0] - seg[0][0], seg[1][1] - seg[0][1]) or (1.0, 0.0)
        return _unit(*_cubic_deriv(seg, self.t_at(s))) or (segment_tangents(seg) or ((1.0, 0.0),))[0]


def _dash_subpath(segs, closed, pattern, offset, tol):
    """Dashes of one subpath: lists of segments, or (point, direction) for zero-length dashes.
    On a closed subpath a dash running through the start point is one dash (as in Skia, and so
    in browsers and resvg), joined there rather than capped twice."""
    measured = [_Measured(s, tol) for s in segs]
    total = sum(m.length for m in measured)
    period = sum(pattern)
    # position within the pattern at the subpath's start
    phase = offset % period
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
                s = min(max(a - seg_start, 0.0), m.length)
                seg = m.part(s, s)
                dashes.append((seg[0], m.direction(s)))
            else:
                j, js = seg_i, seg_start
                while j < len(measured) and js < b:
                    m = measured[j]
                    lo, hi = max(a - js, 0.0), min(b - js, m.length)
                    if hi > lo:
                        dash.append(m.part(lo, hi))
                    js += m.length
                    j += 1
                if dash:
                    dashes.append(dash)
                    if a == 0.0:
                        first_at_start = True
                    last_at_end = b >= total
        pos += length
        k = (k + 1) % len(pattern)
    if closed and first_at_start and last_at_end and len(dashes) > 1 and \
            isinstance(dashes[-1], list):
        dashes[0] = dashes.pop() + dashes[0]
    return dashes


# -- markers --------------------------------------------------------------------------------


