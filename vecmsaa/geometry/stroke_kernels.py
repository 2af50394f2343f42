"""Compiled kernels of the stroker: polylines (the bulk of map data) with every join, cap and
dash, and the join and cap shapes that the curve stroker in :mod:`vecmsaa.geometry.stroke` shares.

Outlines are written into flat buffers: ``verbs`` (uint8, the path.py codes), ``pts`` (N x 2)
and ``cnt`` = [verbs written, points written]. A *side* buffer has the same layout without
MOVE/CLOSE: its point 0 is the side's start, then each verb's points. The geometry and why it
fills the exact stroke under nonzero is explained in :mod:`vecmsaa.geometry.stroke`.
"""
from __future__ import annotations

import math

import numpy as np
from ..jit import njit

from ..scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD
from .arclength import _cubic_velocity
from .hypot import _hypot
from .primitives import _conic_weight

JOIN_CODES = {"miter": 0, "arcs": 0, "miter-clip": 1, "round": 2, "bevel": 3}
CAP_CODES = {"butt": 0, "round": 1, "square": 2}
_MITER, _MITER_CLIP, _ROUND, _BEVEL = 0, 1, 2, 3
_BUTT, _ROUND_CAP, _SQUARE = 0, 1, 2

SMOOTH_COS = math.cos(math.radians(0.5))   # tangents this close need no join
#: how exactly a conic must be a circular arc to be stroked as one (relative to its size: the
#: curve is then within ~1e-9 of its radius of the circle)
CIRCLE_RTOL = 1e-9
_MAX_DASH_STEPS = 1_000_000                # pattern intervals walked per subpath at most
#: a dash interval starting or ending within this fraction of a subpath's length of its end
#: (or start) does so exactly: the pattern's lengths summed in floats drift from their exact
#: sum by ~1e-16 of the length a step (1mm 2mm on a 480-unit square: the last dash, exactly
#: at the end, 6e-13 short), and a closed subpath's last dash reaching its end joins the
#: first instead of leaving two butt ends and a hole at the corner
_DASH_END_RTOL = 1e-9

_MAX_ARC_CHORDS = 4     # an arc needing more chords within the tolerance is drawn as cubics
# bounds of what one vertex's side, a cap or a dot adds (a round U-turn: a line and two
# quarter cubics or _MAX_ARC_CHORDS lines; an inner corner: three lines)
_SIDE_PTS_PER_VERTEX = 7
_SIDE_VERBS_PER_VERTEX = 1 + _MAX_ARC_CHORDS
_CAP_PTS = 6
_CAP_VERBS = _MAX_ARC_CHORDS
_DOT_PTS = 13
_DOT_VERBS = 2 + _MAX_ARC_CHORDS


# (calls, not inline="always": an inlined copy is ~80 IR statements and ~15 ms of compile time
# at each of the ~55 call sites; LLVM inlines the calls anyway)
@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _point(pts, cnt, x, y):
    pts[cnt[1], 0] = x
    pts[cnt[1], 1] = y
    cnt[1] += 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _line(verbs, pts, cnt, x, y):
    verbs[cnt[0]] = LINE
    cnt[0] += 1
    pts[cnt[1], 0] = x
    pts[cnt[1], 1] = y
    cnt[1] += 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc(verbs, pts, cnt, cx, cy, r, a0, a1, tol):
    """The circular arc from angle a0 to a1 (radians): chords when a few lie within tol of it
    (thin strokes: lines are cheaper to raster than curves), else cubics of ≤ 90° each."""
    quarters = max(1, int(math.ceil(abs(a1 - a0) / (math.pi / 2) - 1e-9)))
    chord_angle = 2.0 * math.acos(max(-1.0, 1.0 - tol / r))   # widest chord within tol
    if chord_angle > 0.0:
        chords = max(quarters, int(math.ceil(abs(a1 - a0) / chord_angle - 1e-9)))
    else:   # tol below the rounding of r: only curves will do
        chords = _MAX_ARC_CHORDS + 1
    if chords <= _MAX_ARC_CHORDS:
        for i in range(1, chords + 1):
            b = a0 + (a1 - a0) * i / chords
            _line(verbs, pts, cnt, cx + r * math.cos(b), cy + r * math.sin(b))
        return
    n = quarters
    delta = (a1 - a0) / n
    k = 4.0 / 3.0 * math.tan(delta / 4.0) * r
    ca, sa = math.cos(a0), math.sin(a0)
    for i in range(n):
        b = a0 + (i + 1) * delta
        cb, sb = math.cos(b), math.sin(b)
        verbs[cnt[0]] = CUBIC
        cnt[0] += 1
        _point(pts, cnt, cx + r * ca - k * sa, cy + r * sa + k * ca)
        _point(pts, cnt, cx + r * cb + k * sb, cy + r * sb - k * cb)
        _point(pts, cnt, cx + r * cb, cy + r * sb)
        ca, sa = cb, sb


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def cap_items(verbs, pts, cnt, px, py, dx, dy, hw, cap, tol):
    """From the right offset to the left offset at an end p with outward direction d."""
    nx, ny = -dy * hw, dx * hw          # left normal of the outward direction
    if cap == _SQUARE:
        _line(verbs, pts, cnt, px - nx + dx * hw, py - ny + dy * hw)
        _line(verbs, pts, cnt, px + nx + dx * hw, py + ny + dy * hw)
        _line(verbs, pts, cnt, px + nx, py + ny)
    elif cap == _ROUND_CAP:
        a0 = math.atan2(-ny, -nx)
        _arc(verbs, pts, cnt, px, py, hw, a0, a0 + math.pi, tol)
    else:
        _line(verbs, pts, cnt, px + nx, py + ny)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def dot_contour(verbs, pts, cnt, px, py, dx, dy, hw, cap, tol):
    """A zero-length subpath or dash: a disc for round caps, a square along d for square caps,
    nothing for butt caps."""
    if cap == _ROUND_CAP:
        verbs[cnt[0]] = MOVE
        cnt[0] += 1
        _point(pts, cnt, px + hw, py)
        _arc(verbs, pts, cnt, px, py, hw, 0.0, 2 * math.pi, tol)
    elif cap == _SQUARE:
        nx, ny = -dy * hw, dx * hw
        ex, ey = dx * hw, dy * hw
        verbs[cnt[0]] = MOVE
        cnt[0] += 1
        _point(pts, cnt, px - ex - nx, py - ey - ny)
        _line(verbs, pts, cnt, px + ex - nx, py + ey - ny)
        _line(verbs, pts, cnt, px + ex + nx, py + ey + ny)
        _line(verbs, pts, cnt, px - ex + nx, py - ey + ny)
    else:
        return
    verbs[cnt[0]] = CLOSE
    cnt[0] += 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def outer_join_items(verbs, pts, cnt, px, py, d0x, d0y, d1x, d1y, side, hw, join, miterlimit,
                     dot, limit_dot, tol):
    """Items along the outer side (side: +1 left, -1 right) of a turn at p, after the incoming
    side's last point (on its offset line) and before the outgoing side's next point (on the
    outgoing offset line). The offset ends a and b are left out where they are collinear with
    their neighbours (a miter's tip, a clipped miter's corners). limit_dot: the cosine of the
    turn that the miter limit judges, the segments' own end tangents; dot (of the directions
    d0, d1 the sides were offset along) places the shapes."""
    n0x, n0y = -d0y * side, d0x * side
    n1x, n1y = -d1y * side, d1x * side
    ax, ay = px + n0x * hw, py + n0y * hw
    bx, by = px + n1x * hw, py + n1y * hw
    cos_half = math.sqrt(max(0.0, (1.0 + dot) / 2.0))   # cos of half the turning angle
    has_tip = cos_half > 0
    tx = ty = 0.0
    if has_tip:
        k = hw / (1.0 + dot)
        tx, ty = px + (n0x + n1x) * k, py + (n0y + n1y) * k
    if join == _ROUND:
        # thin strokes of dense polylines: a miter tip or a bevel within tolerance of the arc
        if has_tip and hw * (1.0 / cos_half - 1.0) <= tol:
            _line(verbs, pts, cnt, tx, ty)
            return
        if hw * (1.0 - cos_half) <= tol:
            _line(verbs, pts, cnt, ax, ay)
            _line(verbs, pts, cnt, bx, by)
            return
        a0 = math.atan2(n0y, n0x)
        turn = math.atan2(n0x * n1y - n0y * n1x, n0x * n1x + n0y * n1y)
        if abs(turn) > math.pi - 1e-9:
            turn = -side * math.pi      # a U-turn: round the far side (through p + hw·d0)
        _line(verbs, pts, cnt, ax, ay)
        _arc(verbs, pts, cnt, px, py, hw, a0, a0 + turn, tol)
        return
    cos_limit = math.sqrt(max(0.0, (1.0 + limit_dot) / 2.0))
    within = cos_limit > 0 and 1.0 / cos_limit <= miterlimit    # the tangents' miter
    lim = miterlimit * hw
    if join != _BEVEL and has_tip and 1.0 / cos_half <= miterlimit and (
            within or join == _MITER_CLIP):
        # miter (and "arcs", which falls back to it); a clip beyond the tip leaves it whole
        _line(verbs, pts, cnt, tx, ty)
        return
    if join != _BEVEL and join != _MITER_CLIP and within:
        # the tangents' miter is within the limit but the directions' (chords of a tight
        # bend) is not: clipped where the tangents' tip would be, no farther
        join = _MITER_CLIP
        lim = hw / cos_limit
    if join == _MITER_CLIP:
        ux, uy = n0x + n1x, n0y + n1y
        ul = math.hypot(ux, uy)
        if ul <= 1e-12:
            # a U-turn: the outer bisector is the limit of the near-reversal ones, straight on
            # along the incoming segment, so the clipped miter is a box of limit·w/2 past p
            ux, uy, ul = d0x, d0y, 1.0
        if ul > 0:
            ux, uy = ux / ul, uy / ul
            da = d0x * ux + d0y * uy
            pa = hw * (n0x * ux + n0y * uy)
            if da > 1e-12 and lim > pa:
                u = (lim - pa) / da
                _line(verbs, pts, cnt, ax + d0x * u, ay + d0y * u)
                _line(verbs, pts, cnt, bx - d1x * u, by - d1y * u)
                return
    _line(verbs, pts, cnt, ax, ay)      # bevel, and miters over the limit
    _line(verbs, pts, cnt, bx, by)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_side_forward(verbs, pts, cnt, sv, sp, scnt, first_point):
    """The side's verbs with their points, from point first_point on."""
    for i in range(scnt[0]):
        verbs[cnt[0]] = sv[i]
        cnt[0] += 1
    for i in range(first_point, scnt[1]):
        _point(pts, cnt, sp[i, 0], sp[i, 1])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_side_backward(verbs, pts, cnt, sv, sp, scnt, last_point):
    """The side traversed backwards, after its last point: reversed verbs, and the points
    reversed (a cubic's controls swap places) down to point last_point. A conic, stored as
    (b1, point at t = ½, b2), reversed is (b1, the same midpoint, b0): its first two points
    swap back."""
    v0, p0 = cnt[0], cnt[1]
    conics = False
    for i in range(scnt[0] - 1, -1, -1):
        verbs[cnt[0]] = sv[i]
        cnt[0] += 1
        conics = conics or sv[i] == CONIC
    for i in range(scnt[1] - 2, last_point - 1, -1):
        _point(pts, cnt, sp[i, 0], sp[i, 1])
    if conics:
        p = p0
        for i in range(v0, cnt[0]):
            if verbs[i] == LINE:
                p += 1
                continue
            if verbs[i] == CONIC:
                x, y = pts[p, 0], pts[p, 1]
                pts[p, 0], pts[p, 1] = pts[p + 1, 0], pts[p + 1, 1]
                pts[p + 1, 0], pts[p + 1, 1] = x, y
            p += 3


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_closed_sides(verbs, pts, cnt, rv, rp, rc, lv, lp, lc):
    """A closed subpath's stroke as two loops, each started at its side's last point (where
    the closing join ended): the right side forward, the left side backward."""
    verbs[cnt[0]] = MOVE
    cnt[0] += 1
    _point(pts, cnt, rp[rc[1] - 1, 0], rp[rc[1] - 1, 1])
    _emit_side_forward(verbs, pts, cnt, rv, rp, rc, np.int64(1))
    verbs[cnt[0]] = CLOSE
    cnt[0] += 1
    verbs[cnt[0]] = MOVE
    cnt[0] += 1
    _point(pts, cnt, lp[lc[1] - 1, 0], lp[lc[1] - 1, 1])
    _emit_side_backward(verbs, pts, cnt, lv, lp, lc, np.int64(1))
    _point(pts, cnt, lp[lc[1] - 1, 0], lp[lc[1] - 1, 1])
    verbs[cnt[0]] = CLOSE
    cnt[0] += 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _stroke_polyline(verbs, pts, cnt, src, lo, hi, closed, hw, tol, join, cap, miterlimit,
                     q, dirs, lens, rv, rp, lv, lp, rc, lc):
    """One subpath of straight lines, src[lo:hi] (a closed one without its closing point
    repeated): one contour when open, two loops when closed, joins and caps inline.
    q, dirs, lens and the side buffers rv/rp, lv/lp with their counts rc, lc are scratch
    space.

    As chains this outline is exactly the sum of separate positive pieces (a rectangle per
    segment, a wedge per join, the caps): on the outer side the wedge and the rectangles' butt
    ends collapse into the join shape, on the inner side into corner → vertex → corner. Where
    the inner offsets' crossing lies within both segments (and so does the other corner), the
    crossing replaces that detour: it removes a quadrilateral inside both rectangles, which
    leaves the union unchanged but avoids overlapping edges."""
    n = 0
    for i in range(lo, hi):
        if n == 0 or src[i, 0] != q[n - 1, 0] or src[i, 1] != q[n - 1, 1]:
            q[n, 0] = src[i, 0]
            q[n, 1] = src[i, 1]
            n += 1
    if closed and n > 1 and q[n - 1, 0] == q[0, 0] and q[n - 1, 1] == q[0, 1]:
        n -= 1
    if n < 2:
        dot_contour(verbs, pts, cnt, src[lo, 0], src[lo, 1], 1.0, 0.0, hw, cap, tol)
        return
    nseg = n if closed else n - 1
    for i in range(nseg):
        j = (i + 1) % n
        dx, dy = q[j, 0] - q[i, 0], q[j, 1] - q[i, 1]
        ln = math.hypot(dx, dy)
        dirs[i, 0] = dx / ln
        dirs[i, 1] = dy / ln
        lens[i] = ln
    rc[0] = rc[1] = lc[0] = lc[1] = 0
    px, py = q[0, 0], q[0, 1]
    _point(rp, rc, px + dirs[0, 1] * hw, py - dirs[0, 0] * hw)
    _point(lp, lc, px - dirs[0, 1] * hw, py + dirs[0, 0] * hw)
    for i in range(nseg if closed else nseg - 1):
        j = (i + 1) % nseg
        d0x, d0y, d1x, d1y = dirs[i, 0], dirs[i, 1], dirs[j, 0], dirs[j, 1]
        px, py = q[j, 0], q[j, 1]
        cross = d0x * d1y - d0y * d1x
        dot = d0x * d1x + d0y * d1y
        if dot > SMOOTH_COS:
            # (almost) straight on: both sides meet at their offsets' crossing
            k = hw / (1.0 + dot)
            cx, cy = (-d0y - d1y) * k, (d0x + d1x) * k     # (n0 + n1)·hw/(1 + dot)
            _line(lv, lp, lc, px + cx, py + cy)
            _line(rv, rp, rc, px - cx, py - cy)
            continue
        if cross > 0:       # turning left: left side inner
            outer_join_items(rv, rp, rc, px, py, d0x, d0y, d1x, d1y, -1.0, hw, join,
                             miterlimit, dot, dot, tol)
            sign = 1.0
        else:
            outer_join_items(lv, lp, lc, px, py, d0x, d0y, d1x, d1y, 1.0, hw, join,
                             miterlimit, dot, dot, tol)
            sign = -1.0
        # the crossing is hw·tan(φ/2) from the vertex along each segment, the other corner
        # hw·sin φ; both must lie within both segments. Each shortcut removes a region
        # covered by the two segments at its vertex; around a whole loop of shortcuts a point
        # could lose all its cover, so a closed loop keeps the detour at vertex 0.
        # tan(φ/2) as (1 − cos φ)/sin φ: near a U-turn sin φ/(1 + cos φ) is rounding noise
        # over rounding noise, and a shortcut there would cut the turn's inside open
        sin_turn = abs(cross)
        reach = hw * max((1.0 - dot) / sin_turn if sin_turn > 0.0 else math.inf, sin_turn)
        # (at dot = −1 with a rounding-noise cross, the offsets cross at infinity)
        if reach <= lens[i] and reach <= lens[j] and not (closed and j == 0) and dot > -1.0:
            k = sign * hw / (1.0 + dot)
            ix, iy = px + (-d0y - d1y) * k, py + (d0x + d1x) * k
            if cross > 0:
                _line(lv, lp, lc, ix, iy)
            else:
                _line(rv, rp, rc, ix, iy)
        else:
            # corner of the incoming offset, the vertex, corner of the outgoing offset
            if cross > 0:
                _line(lv, lp, lc, px - d0y * hw, py + d0x * hw)
                _line(lv, lp, lc, px, py)
                _line(lv, lp, lc, px - d1y * hw, py + d1x * hw)
            else:
                _line(rv, rp, rc, px + d0y * hw, py - d0x * hw)
                _line(rv, rp, rc, px, py)
                _line(rv, rp, rc, px + d1y * hw, py - d1x * hw)
    if closed:
        # the sides start at vertex 0's butt points, on the first segment's offsets: start
        # the loops at the closing join's last point instead
        _emit_closed_sides(verbs, pts, cnt, rv, rp, rc, lv, lp, lc)
        return
    dx, dy = dirs[nseg - 1, 0], dirs[nseg - 1, 1]
    px, py = q[n - 1, 0], q[n - 1, 1]
    _line(rv, rp, rc, px + dy * hw, py - dx * hw)
    _line(lv, lp, lc, px - dy * hw, py + dx * hw)
    verbs[cnt[0]] = MOVE
    cnt[0] += 1
    _emit_side_forward(verbs, pts, cnt, rv, rp, rc, np.int64(0))
    cap_items(verbs, pts, cnt, px, py, dx, dy, hw, cap, tol)
    _emit_side_backward(verbs, pts, cnt, lv, lp, lc, np.int64(0))
    cap_items(verbs, pts, cnt, q[0, 0], q[0, 1], -dirs[0, 0], -dirs[0, 1], hw, cap,
              tol)
    verbs[cnt[0]] = CLOSE
    cnt[0] += 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _line_subpaths(verbs, points):
    """Subpaths of a path of lines as polylines: (points, start offsets, closed flags). A
    closed subpath ends with its start point again (the closing line made explicit); a moveto
    alone is dropped, a moveto with a close kept (round and square caps draw it as a dot)."""
    out = np.empty((len(points) + len(verbs), 2))
    starts = np.empty(len(verbs) + 1, np.int64)
    closed = np.empty(len(verbs), np.bool_)
    ns = 0
    n = 0                   # points written
    sub = 0                 # where the current subpath starts in out
    drawn = False
    have_start = False
    sx = sy = 0.0
    ip = 0
    for v in verbs:
        if v == MOVE:
            if drawn:
                starts[ns] = sub
                closed[ns] = False
                ns += 1
            else:
                n = sub
            sx, sy = points[ip, 0], points[ip, 1]
            ip += 1
            sub = n
            out[n, 0], out[n, 1] = sx, sy
            n += 1
            drawn = False
            have_start = True
        elif v == CLOSE:
            if have_start:
                out[n, 0], out[n, 1] = sx, sy
                n += 1
                starts[ns] = sub
                closed[ns] = True
                ns += 1
                sub = n
                out[n, 0], out[n, 1] = sx, sy     # drawing on after a close starts here
                n += 1
            drawn = False
        else:
            out[n, 0], out[n, 1] = points[ip, 0], points[ip, 1]
            ip += 1
            n += 1
            drawn = True
    if drawn:
        starts[ns] = sub
        closed[ns] = False
        ns += 1
        sub = n
    starts[ns] = sub
    return out[:sub], starts[:ns + 1], closed[:ns]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _grow_points(a, need):
    """a with room for need rows (points, or the rows of any float table)."""
    if need <= a.shape[0]:
        return a
    b = np.empty((max(need, 2 * a.shape[0]), a.shape[1]))
    # one flat loop (LLVM makes it a memcpy): a slice assignment costs seconds of compile
    # time, a loop over rows and columns ~600 instructions in every kernel that grows
    src = a.reshape(a.size)
    dst = b.reshape(b.size)
    for k in range(a.size):
        dst[k] = src[k]
    return b


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _grow(a, need):
    """a (verbs, or any 1-D array) with room for need entries, of its own dtype."""
    if need <= a.shape[0]:
        return a
    b = np.empty(max(need, 2 * a.shape[0]), a.dtype)
    for i in range(a.shape[0]):
        b[i] = a[i]
    return b


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _pattern_at(pattern, period, phase):
    """(interval, how far into it) at a subpath's start, ``phase`` being the offset reduced
    to the period (a tiny negative offset can round to the period itself). Intervals are half
    open, except that a zero-length dash right at the phase is drawn."""
    if phase >= period:
        phase -= period
    k = 0
    while phase > pattern[k] or (phase == pattern[k] and pattern[k] > 0):
        phase -= pattern[k]
        k = (k + 1) % len(pattern)
    return k, phase


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _dash_polylines(src, starts, closed, pattern, offset):
    """Dashes of polylines: (dash points, dash start offsets, dots, dot directions). A dash
    is an open polyline; a zero-length dash is a dot with the direction it lies on. On a
    closed subpath a dash running through the start point is one dash (as in Skia, and so in
    browsers and resvg), joined there rather than capped twice."""
    period = 0.0
    for v in pattern:
        period += v
    npat = len(pattern)
    out = np.empty((2 * len(src) + 16, 2))
    ostarts = np.empty(len(src) + 16, np.int64)
    dots = np.empty((16, 2))
    no = 0
    nd = 0
    ndot = 0
    seglen = np.empty(len(src))
    for s in range(len(starts) - 1):
        lo, hi = starts[s], starts[s + 1]
        nseg = hi - lo - 1
        total = 0.0
        for i in range(nseg):
            seglen[i] = math.hypot(src[lo + i + 1, 0] - src[lo + i, 0],
                                   src[lo + i + 1, 1] - src[lo + i, 1])
            total += seglen[i]
        k, phase = _pattern_at(pattern, period, offset - math.floor(offset / period) * period)
        pos = -phase                 # subpath arc length where the current interval starts
        seg_i, seg_start = 0, 0.0    # current segment and the arc length where it starts
        first_dash = nd              # this subpath's first dash
        first_at_start = last_at_end = False
        last_is_dot = False
        steps = 0
        near = total * _DASH_END_RTOL
        while pos < total - near and steps < _MAX_DASH_STEPS:
            steps += 1
            length = pattern[k]
            a, b = max(pos, 0.0), min(pos + length, total)
            if k % 2 == 0 and b >= a and (b > a or pos >= 0):
                while seg_i < nseg - 1 and seg_start + seglen[seg_i] < a:
                    seg_start += seglen[seg_i]
                    seg_i += 1
                if b == a:
                    ln = seglen[seg_i]
                    t = min(max(a - seg_start, 0.0), ln) / ln if ln > 0 else 0.0
                    x0, y0 = src[lo + seg_i, 0], src[lo + seg_i, 1]
                    dx, dy = src[lo + seg_i + 1, 0] - x0, src[lo + seg_i + 1, 1] - y0
                    dots = _grow_points(dots, 2 * ndot + 2)
                    dots[2 * ndot, 0], dots[2 * ndot, 1] = x0 + dx * t, y0 + dy * t
                    if ln > 0:
                        dots[2 * ndot + 1, 0], dots[2 * ndot + 1, 1] = dx / ln, dy / ln
                    else:
                        dots[2 * ndot + 1, 0], dots[2 * ndot + 1, 1] = 1.0, 0.0
                    ndot += 1
                    last_is_dot = True
                else:
                    begin = no
                    j, js = seg_i, seg_start
                    ex = ey = 0.0
                    while j < nseg and js < b:
                        ln = seglen[j]
                        plo, phi = max(a - js, 0.0), min(b - js, ln)
                        if phi > plo:
                            x0, y0 = src[lo + j, 0], src[lo + j, 1]
                            dx, dy = src[lo + j + 1, 0] - x0, src[lo + j + 1, 1] - y0
                            out = _grow_points(out, no + 2)
                            t0, t1 = plo / ln, phi / ln
                            out[no, 0], out[no, 1] = x0 + dx * t0, y0 + dy * t0
                            no += 1
                            ex, ey = x0 + dx * t1, y0 + dy * t1
                        js += ln
                        j += 1
                    if no > begin:
                        out[no, 0], out[no, 1] = ex, ey
                        no += 1
                        ostarts = _grow(ostarts, nd + 2)
                        ostarts[nd] = begin
                        nd += 1
                        last_is_dot = False
                        if a <= near:
                            first_at_start = True
                        last_at_end = b >= total - near
            pos += length
            k = (k + 1) % npat
        if closed[s] and first_at_start and last_at_end and nd - first_dash > 1 and \
                not last_is_dot:
            # the last dash runs on into the first: the first dash's points go after the
            # last's (whose end point, the subpath's start, the first begins with again), and
            # the dashes after the first move down into its place
            f0, f1 = ostarts[first_dash], ostarts[first_dash + 1]
            m = f1 - f0
            # (loops: slice assignments cost seconds of compile time)
            first = np.empty((m, 2))
            for i in range(m):
                first[i, 0], first[i, 1] = out[f0 + i, 0], out[f0 + i, 1]
            no -= 1
            out = _grow_points(out, no + m)
            for i in range(m):
                out[no + i, 0], out[no + i, 1] = first[i, 0], first[i, 1]
            no += m
            for i in range(f0, no - m):     # down by m = f1 - f0, front to back
                out[i, 0], out[i, 1] = out[i + m, 0], out[i + m, 1]
            no -= m
            for d in range(first_dash + 1, nd):
                ostarts[d - 1] = ostarts[d] - m
            nd -= 1
    ostarts = _grow(ostarts, nd + 1)
    ostarts[nd] = no
    return out[:no], ostarts[:nd + 1], dots[:2 * ndot]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _stroke_polylines(src, starts, closed, dots, hw, tol, join, cap, miterlimit):
    """Outline (verbs, points) of polylines src[starts[i]:starts[i + 1]] and of dots
    (point, direction pairs). Empty polylines are skipped."""
    longest = 1
    total = 0
    for s in range(len(starts) - 1):
        m = starts[s + 1] - starts[s]
        longest = max(longest, m)
        total += max(m, 0)
    nsub = len(starts) - 1
    ndot = len(dots) // 2
    max_pts = 2 * (_SIDE_PTS_PER_VERTEX * total + 2 * nsub) + (2 * _CAP_PTS + 4) * nsub + \
        (_DOT_PTS + 1) * (ndot + nsub)
    max_verbs = 2 * (_SIDE_VERBS_PER_VERTEX * total + 2 * nsub) + (2 * _CAP_VERBS + 4) * nsub + \
        _DOT_VERBS * (ndot + nsub)
    verbs = np.empty(max_verbs, np.uint8)
    pts = np.empty((max_pts, 2))
    cnt = np.zeros(2, np.int64)
    q = np.empty((longest, 2))
    dirs = np.empty((longest, 2))
    lens = np.empty(longest)
    side_pts = _SIDE_PTS_PER_VERTEX * longest + 4
    rv = np.empty(_SIDE_VERBS_PER_VERTEX * longest + 4, np.uint8)
    lv = np.empty(_SIDE_VERBS_PER_VERTEX * longest + 4, np.uint8)
    rp = np.empty((side_pts, 2))
    lp = np.empty((side_pts, 2))
    rc = np.zeros(2, np.int64)
    lc = np.zeros(2, np.int64)
    for s in range(nsub):
        lo, hi = starts[s], starts[s + 1]
        if hi <= lo:
            continue
        _stroke_polyline(verbs, pts, cnt, src, lo, hi, closed[s], hw, tol, join, cap,
                         miterlimit, q, dirs, lens, rv, rp, lv, lp, rc, lc)
    for i in range(ndot):
        dot_contour(verbs, pts, cnt, dots[2 * i, 0], dots[2 * i, 1], dots[2 * i + 1, 0],
                    dots[2 * i + 1, 1], hw, cap, tol)
    return verbs[:cnt[0]], pts[:cnt[1]]


@njit(cache=True)
def stroke_lines_batch(verbs, points, vstart, pstart, which, hw, tol, join, cap, miterlimit,
                       pattern, offset):
    """The outlines of many paths of lines only, in one call (map data strokes thousands of
    short paths with one style: a call each cost more than the stroking). Path i is
    verbs[vstart[i]:vstart[i + 1]] with points[pstart[i]:pstart[i + 1]]; the paths stroked
    are which[0], which[1], ... Returns (verbs, points, verb offsets, point offsets): outline
    k is verbs[vo[k]:vo[k + 1]] with points[po[k]:po[k + 1]], and has no verbs when it draws
    nothing (only moves and closes)."""
    n = len(which)
    vo = np.empty(n + 1, np.int64)
    po = np.empty(n + 1, np.int64)
    vo[0] = po[0] = 0
    total = 16
    for k in range(n):
        total += pstart[which[k] + 1] - pstart[which[k]]
    out_v = np.empty(4 * total, np.uint8)
    out_p = np.empty((4 * total, 2))
    nv = npt = 0
    no_dots = np.empty((0, 2))
    for k in range(n):
        i = which[k]
        # (written out here, not in a helper: each call level compiles what it calls again)
        src, starts, closed = _line_subpaths(verbs[vstart[i]:vstart[i + 1]],
                                             points[pstart[i]:pstart[i + 1]])
        if len(pattern) == 0:
            v, p = _stroke_polylines(src, starts, closed, no_dots, hw, tol, join, cap,
                                     miterlimit)
        else:
            dash_pts, dash_starts, dots = _dash_polylines(src, starts, closed, pattern, offset)
            v, p = _stroke_polylines(dash_pts, dash_starts,
                                     np.zeros(len(dash_starts), np.bool_), dots, hw, tol, join,
                                     cap, miterlimit)
        drawn = False
        for j in range(len(v)):
            if v[j] != MOVE and v[j] != CLOSE:
                drawn = True
                break
        if drawn:
            out_v = _grow(out_v, nv + len(v))
            out_p = _grow_points(out_p, npt + len(p))
            for j in range(len(v)):
                out_v[nv + j] = v[j]
            for j in range(len(p)):
                out_p[npt + j, 0] = p[j, 0]
                out_p[npt + j, 1] = p[j, 1]
            nv += len(v)
            npt += len(p)
        vo[k + 1] = nv
        po[k + 1] = npt
    return out_v[:nv], out_p[:npt], vo, po


_ONE = np.zeros(1, np.int64)


def stroke_lines(verbs, points, hw, tol, join, cap, miterlimit, pattern, offset):
    """Outline (verbs, points) of one path of lines only (contiguous uint8 verbs, float64
    (N, 2) points); pattern is the effective dash array (empty for a solid stroke). Empty
    arrays when the outline draws nothing."""
    ov, op, _, _ = stroke_lines_batch(verbs, points, np.array([0, len(verbs)], np.int64),
                                      np.array([0, len(points)], np.int64), _ONE, hw, tol,
                                      join, cap, miterlimit, pattern, offset)
    return ov, op


# -- curves ---------------------------------------------------------------------------------
# Subpaths as the curve stroker takes them (stroke_segments): per segment its number of
# control points (2 a line, 3 a quadratic, 4 a cubic) and a row of 8 coordinates x0, y0, x1,
# y1, ...; per subpath the index of its first segment and a kind: open, closed (its closing
# line included), or a dot (a zero-length dash: its point and direction in its one row).
SUB_OPEN, SUB_CLOSED, SUB_DOT = 0, 1, 2

_MAX_DEPTH = 12          # curve subdivision depth: 4096 pieces at most per segment

# A piece of a segment is a row of the piece table: source end points, unit tangents at both
# ends, the control points of its right and left offsets (4 each, a line's 2) and err: how far
# the source may be from the true segment (a chord's flatness; 0 where it is exact).
_PS, _PE, _PT0, _PT1, _PR, _PL, _PERR = 0, 2, 4, 6, 8, 16, 24
_PIECE_COLS = 25
# what a join adds to either side at most: outer items (a line and two quarter cubics, or a
# line and _MAX_ARC_CHORDS chords), the line to the next offset; or the inner detour
_JOIN_SIDE_VERBS = 2 + _MAX_ARC_CHORDS
_JOIN_SIDE_PTS = 8


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _unit(dx, dy):
    """(ok, ux, uy): the direction of (dx, dy); not ok for a zero or non-finite length."""
    n = _hypot(dx, dy)
    if n == 0.0 or not math.isfinite(n):
        return False, 0.0, 0.0
    return True, dx / n, dy / n


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_at(c, t):
    """Point at t of the cubic c (a row x0, y0, ..., x3, y3)."""
    u = 1.0 - t
    a, b, cc, d = u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t
    return (a * c[0] + b * c[2] + cc * c[4] + d * c[6],
            a * c[1] + b * c[3] + cc * c[5] + d * c[7])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _curvature(c, t):
    """Signed curvature at t (inf where the speed vanishes)."""
    dx, dy = _cubic_velocity(c, t)
    sp2 = dx * dx + dy * dy
    if sp2 < 1e-24:
        return math.inf
    u = 1.0 - t
    ex = 6.0 * (u * (c[4] - 2.0 * c[2] + c[0]) + t * (c[6] - 2.0 * c[4] + c[2]))
    ey = 6.0 * (u * (c[5] - 2.0 * c[3] + c[1]) + t * (c[7] - 2.0 * c[5] + c[3]))
    return (dx * ey - dy * ex) / (sp2 * math.sqrt(sp2))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _offset_probes(c, probes):
    """Where the true offsets of c are compared with their fits, at t = ¼, ½, ¾: rows (ok,
    x, y, ux, uy), the point and the unit tangent (ok 0 where the speed vanishes); the offset
    by off is (x − uy·off, y + ux·off). Both sides' fits share them."""
    for i in range(3):
        t = 0.25 * (i + 1)
        ok, ux, uy = _unit(*_cubic_velocity(c, t))
        x, y = _cubic_at(c, t)
        probes[i, 0] = 1.0 if ok else 0.0
        probes[i, 1], probes[i, 2], probes[i, 3], probes[i, 4] = x, y, ux, uy


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _fit_offset(c, t0x, t0y, t1x, t1y, off, fit, probes):
    """Write into fit the cubic approximating the offset of c by off: end points and tangents
    exact, handle lengths chosen so the midpoints agree (the midpoint from _offset_probes'
    probes). Returns whether they do: where the end tangents are parallel or the handles
    would point backwards, the handles are the source's scaled instead, and the midpoint is
    wherever that puts it."""
    q0x, q0y = c[0] - t0y * off, c[1] + t0x * off
    q3x, q3y = c[6] - t1y * off, c[7] + t1x * off
    ok = probes[1, 0] != 0.0
    mx, my = probes[1, 1] - probes[1, 4] * off, probes[1, 2] + probes[1, 3] * off
    det = t1x * t0y - t0x * t1y             # det of [t0, -t1]
    a = b = 0.0
    solved = False
    if ok and abs(det) > 1e-9:
        # solve a·t0 − b·t1 = 8/3·(m − (q0 + q3)/2)
        rx = 8.0 / 3.0 * (mx - (q0x + q3x) / 2.0)
        ry = 8.0 / 3.0 * (my - (q0y + q3y) / 2.0)
        a = (rx * (-t1y) - ry * (-t1x)) / det
        b = (t0x * ry - t0y * rx) / det
        solved = not (a < 0.0 or b < 0.0)
    if not solved:
        # parallel end tangents: scale the source handles by the offset's speed ratio
        k0 = _curvature(c, 0.0)
        k1 = _curvature(c, 1.0)
        a = b = 0.0
        if math.isfinite(k0):
            s = 1.0 - off * k0
            a = _hypot(c[2] - c[0], c[3] - c[1]) * (s if s > 0.0 else 0.0)
        if math.isfinite(k1):
            s = 1.0 - off * k1
            b = _hypot(c[6] - c[4], c[7] - c[5]) * (s if s > 0.0 else 0.0)
    fit[0], fit[1] = q0x, q0y
    fit[2], fit[3] = q0x + a * t0x, q0y + a * t0y
    fit[4], fit[5] = q3x - b * t1x, q3y - b * t1y
    fit[6], fit[7] = q3x, q3y
    return solved


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _offset_error(fit, off, mid, probes):
    """Distance of the fitted offset from the true one (_offset_probes' probes) at the quarter
    points, and at the midpoint unless the fit matched it there (mid: it did not). The scaled
    handles of an S-shaped piece with parallel end tangents can be off most in the middle: for
    (0,0) (5,0) (0,1) (7,1) at half width 0.5 by 0.34 there (0.116 from the true offset's
    points) and 0.098 and 0.049 at the quarter points."""
    err = 0.0
    for i in range(3):
        if i == 1 and not mid:
            continue
        if probes[i, 0] == 0.0:
            return math.inf
        tx, ty = probes[i, 1] - probes[i, 4] * off, probes[i, 2] + probes[i, 3] * off
        x, y = _cubic_at(fit, 0.25 * (i + 1))
        e = _hypot(x - tx, y - ty)
        if e > err:
            err = e
    return err


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _cubic_tangents(c):
    """(ok, start direction, end direction) of the cubic c; not ok for zero length."""
    ok0 = ok1 = False
    sx = sy = ex = ey = 0.0
    for i in range(1, 4):
        ok0, sx, sy = _unit(c[2 * i] - c[0], c[2 * i + 1] - c[1])
        if ok0:
            break
    for i in range(2, -1, -1):
        ok1, ex, ey = _unit(c[6] - c[2 * i], c[7] - c[2 * i + 1])
        if ok1:
            break
    return ok0 and ok1, sx, sy, ex, ey


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _flatness(c):
    """An upper bound of the cubic's distance from its chord: the control points' distance
    from the chord segment (not its line: a curve can overshoot along the chord)."""
    x0, y0 = c[0], c[1]
    dx, dy = c[6] - x0, c[7] - y0
    l2 = dx * dx + dy * dy
    worst = 0.0
    for i in range(1, 3):
        x, y = c[2 * i], c[2 * i + 1]
        t = ((x - x0) * dx + (y - y0) * dy) / l2 if l2 > 0 else 0.0
        t = t if t > 0.0 else 0.0
        t = t if t < 1.0 else 1.0
        e = _hypot(x - x0 - t * dx, y - y0 - t * dy)
        if e > worst:
            worst = e
    return worst


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _line_piece(tab, kinds, n, x0, y0, x1, y1, dx, dy, hw, err):
    """Append the piece of the line p0 → p1 (direction d); returns the grown table."""
    tab = _grow_points(tab, n + 1)
    kinds = _grow(kinds, n + 1)
    nx, ny = -dy * hw, dx * hw
    r = tab[n]
    r[0], r[1], r[2], r[3] = x0, y0, x1, y1
    r[4], r[5], r[6], r[7] = dx, dy, dx, dy
    r[8], r[9], r[10], r[11] = x0 - nx, y0 - ny, x1 - nx, y1 - ny
    r[16], r[17], r[18], r[19] = x0 + nx, y0 + ny, x1 + nx, y1 + ny
    r[24] = err
    kinds[n] = 2
    return tab, kinds, n + 1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _circle_centre(x0, y0, x1, y1, x2, y2):
    """(centre x, y, radius) of the circular arc with the isosceles control triangle b0 b1 b2
    (its chord's midpoint m not at b1): the centre lies on the line from b1 through m, at
    |b1 b0|·|b1 b2| / |b1 m| over |b1 m| (right angles at b0 and b2); the radius is the mean
    of its distances from b0 and b2."""
    l0 = _hypot(x1 - x0, y1 - y0)
    l1 = _hypot(x2 - x1, y2 - y1)
    ex, ey = 0.5 * (x0 + x2) - x1, 0.5 * (y0 + y2) - y1
    k = l0 * l1 / (ex * ex + ey * ey)
    cx, cy = x1 + ex * k, y1 + ey * k
    return cx, cy, 0.5 * (_hypot(x0 - cx, y0 - cy) + _hypot(x2 - cx, y2 - cy))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _circle_piece(tab, kinds, n, seg, hw):
    """Append the piece of a conic segment (seg: b0, b1, its point at t = ½, b2) that is a
    circular arc of radius above hw: its offsets are the concentric arcs of radius r ± hw,
    conics with the segment's weight whose points are the segment's scaled about the centre
    (an affine map), so the stroke's outline is exact. Returns (tab, kinds, n, ok); nothing is
    appended (not ok) where the conic is no circular arc (stroke.circular_conics's test: an
    isosceles control triangle, weight cos φ for the half angle φ), is degenerate, or the inner
    offset would fold (r ≤ hw)."""
    x0, y0, x1, y1, xm, ym, x2, y2 = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6], \
        seg[7]
    l0 = _hypot(x1 - x0, y1 - y0)
    l1 = _hypot(x2 - x1, y2 - y1)
    if not (l0 > 0.0 and l1 > 0.0 and abs(l0 - l1) <= CIRCLE_RTOL * max(l0, l1)):
        return tab, kinds, n, False
    ok0, t0x, t0y = _unit(x1 - x0, y1 - y0)
    ok1, t1x, t1y = _unit(x2 - x1, y2 - y1)
    if not (ok0 and ok1):
        return tab, kinds, n, False
    if not abs(_conic_weight(x0, y0, x1, y1, xm, ym, x2, y2) -
               _hypot(0.5 * (x2 - x0), 0.5 * (y2 - y0)) / l0) <= CIRCLE_RTOL:
        return tab, kinds, n, False
    ex, ey = 0.5 * (x0 + x2) - x1, 0.5 * (y0 + y2) - y1
    if not ex * ex + ey * ey > 0.0:
        return tab, kinds, n, False
    cx, cy, r = _circle_centre(x0, y0, x1, y1, x2, y2)
    if not (math.isfinite(r) and r > hw):
        return tab, kinds, n, False
    # the centre on the left of the start direction: the left offset is the inner arc
    inner_left = (cx - x0) * -t0y + (cy - y0) * t0x > 0.0
    sl = (r - hw) / r if inner_left else (r + hw) / r
    sr = (r + hw) / r if inner_left else (r - hw) / r
    tab = _grow_points(tab, n + 1)
    kinds = _grow(kinds, n + 1)
    row = tab[n]
    row[0], row[1], row[2], row[3] = x0, y0, x2, y2
    row[4], row[5], row[6], row[7] = t0x, t0y, t1x, t1y
    # ends exactly as a line's offsets (they meet the joins), the controls scaled
    row[_PR] = x0 + t0y * hw
    row[_PR + 1] = y0 - t0x * hw
    row[_PR + 2] = cx + sr * (x1 - cx)
    row[_PR + 3] = cy + sr * (y1 - cy)
    row[_PR + 4] = cx + sr * (xm - cx)
    row[_PR + 5] = cy + sr * (ym - cy)
    row[_PR + 6] = x2 + t1y * hw
    row[_PR + 7] = y2 - t1x * hw
    row[_PL] = x0 - t0y * hw
    row[_PL + 1] = y0 + t0x * hw
    row[_PL + 2] = cx + sl * (x1 - cx)
    row[_PL + 3] = cy + sl * (y1 - cy)
    row[_PL + 4] = cx + sl * (xm - cx)
    row[_PL + 5] = cy + sl * (ym - cy)
    row[_PL + 6] = x2 - t1y * hw
    row[_PL + 7] = y2 + t1x * hw
    row[_PERR] = 0.0
    kinds[n] = 5
    return tab, kinds, n + 1, True


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _shape_tol(tab, a, b, tol):
    """Tolerance left for a join or cap at the ends of pieces a and b: a chord's own error f
    moves the stroke around it by up to f, so the shape gets tol − f (at least tol / 2,
    chords being flat within that unless subdivision ran out of depth)."""
    e = tab[a, _PERR]
    if tab[b, _PERR] > e:
        e = tab[b, _PERR]
    half = tol / 2.0
    return tol - (half if half < e else e)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _meet_straight(tab, a, b, hw, tol):
    """Whether piece b may follow piece a with their offsets joined by straight lines, no
    join: they turn by under SMOOTH_COS's angle, the outer side's gap (hw times the turn) is
    within tol, and the inner side's crossing (a lobe as long as hw, as wide as hw times the
    turn at its end, winding -1) lies within both pieces' own strokes, which cover it +1 each
    (not so for the short chords of a bend tighter than hw: a hole where nothing else covers)."""
    d0x, d0y, d1x, d1y = tab[a, _PT1], tab[a, _PT1 + 1], tab[b, _PT0], tab[b, _PT0 + 1]
    if not d0x * d1x + d0y * d1y > SMOOTH_COS:
        return False
    gap = hw * _hypot(d1x - d0x, d1y - d0y)
    return gap <= tol and gap <= _hypot(tab[a, 2] - tab[a, 0], tab[a, 3] - tab[a, 1]) and \
        gap <= _hypot(tab[b, 2] - tab[b, 0], tab[b, 3] - tab[b, 1])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _append_side(sv, sp, sc, tab, kinds, lo, hi, col):
    """The offsets (columns col...) of pieces lo..hi-1 along one side, joined by straight
    lines where consecutive offsets do not quite meet; the side is at the first one's start."""
    for j in range(lo, hi):
        r = tab[j]
        if j > lo and (sp[sc[1] - 1, 0] != r[col] or sp[sc[1] - 1, 1] != r[col + 1]):
            _line(sv, sp, sc, r[col], r[col + 1])
        if kinds[j] == 2:
            _line(sv, sp, sc, r[col + 2], r[col + 3])
        else:
            sv[sc[0]] = CUBIC if kinds[j] == 4 else CONIC   # (a conic: b1, midpoint, b2)
            sc[0] += 1
            _point(sp, sc, r[col + 2], r[col + 3])
            _point(sp, sc, r[col + 4], r[col + 5])
            _point(sp, sc, r[col + 6], r[col + 7])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _turn_sides(ov, op, oc, iv, ip, ic, tv, tp, tc, px, py, d0x, d0y, d1x, d1y, side, hw,
                join, miterlimit, dot, limit_dot, tol, o1x, o1y, i1x, i1y):
    """Extend the outer side (side: +1 left, −1 right) by the join shape to its next offset's
    start o1, the inner side through p to its next start i1. tv, tp, tc: scratch."""
    tc[0] = 0
    tc[1] = 0
    outer_join_items(tv, tp, tc, px, py, d0x, d0y, d1x, d1y, side, hw, join, miterlimit, dot,
                     limit_dot, tol)
    first_pts = 3 if tv[0] == CUBIC else 1
    e = first_pts - 1
    v0 = p0 = 0
    if tp[e, 0] == op[oc[1] - 1, 0] and tp[e, 1] == op[oc[1] - 1, 1]:
        v0, p0 = 1, first_pts       # the side already ends at the offset's end
    for i in range(v0, tc[0]):
        ov[oc[0]] = tv[i]
        oc[0] += 1
    for i in range(p0, tc[1]):
        _point(op, oc, tp[i, 0], tp[i, 1])
    if op[oc[1] - 1, 0] != o1x or op[oc[1] - 1, 1] != o1y:
        _line(ov, op, oc, o1x, o1y)
    _line(iv, ip, ic, px, py)
    _line(iv, ip, ic, i1x, i1y)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _in_line(c, npts):
    """Whether the first npts points of the row c (a quadratic's 3, a cubic's 4) lie on a
    line, as Skia's and tiny-skia's strokers judge it (SkStroke's cubic_in_line and
    quad_in_line): the two points farthest apart by their larger coordinate difference m
    are the line's ends, and every other point is within m·√1e-5 of that segment (a
    quadratic's control m·√5e-6), or of its first end where it projects outside it. Such a
    curve is stroked as the lines through its points of extreme speed: for a near-straight
    curve whose control point nearly meets an end the tangent there turns by up to 90° in a
    sliver of the curve, and the cap and joins would follow it (the resvg suite's
    stroke/line-as-curve: a line is drawn)."""
    best = -1.0
    o1 = o2 = 0
    for i in range(npts - 1):
        for j in range(i + 1, npts):
            m = max(abs(c[2 * j] - c[2 * i]), abs(c[2 * j + 1] - c[2 * i + 1]))
            if best < m:
                best, o1, o2 = m, i, j
    slop = best * best * (1e-5 if npts == 4 else 5e-6)
    ax, ay = c[2 * o1], c[2 * o1 + 1]
    dx, dy = c[2 * o2] - ax, c[2 * o2 + 1] - ay
    den = dx * dx + dy * dy
    for k in range(npts):
        if k == o1 or k == o2:
            continue
        ex, ey = c[2 * k] - ax, c[2 * k + 1] - ay
        t = (dx * ex + dy * ey) / den if den > 0.0 else -1.0
        if 0.0 <= t <= 1.0:
            ex, ey = ex - t * dx, ey - t * dy
        if ex * ex + ey * ey > slop:
            return False
    return True


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _speed_extrema(c, out):
    """The parameters in (0, 1) where the cubic c's speed is extreme (F'·F'' = 0, a cubic
    in t: Skia's points of maximum curvature for a curve in line), ascending, into out;
    their count."""
    ax = c[6] - 3.0 * c[4] + 3.0 * c[2] - c[0]
    ay = c[7] - 3.0 * c[5] + 3.0 * c[3] - c[1]
    bx, by = c[4] - 2.0 * c[2] + c[0], c[5] - 2.0 * c[3] + c[1]
    cx, cy = c[2] - c[0], c[3] - c[1]
    # (A t² + 2B t + C)·(A t + B)
    k3 = ax * ax + ay * ay
    k2 = 3.0 * (ax * bx + ay * by)
    k1 = 2.0 * (bx * bx + by * by) + ax * cx + ay * cy
    k0 = bx * cx + by * cy
    # split (0, 1) where the polynomial turns (roots of its derivative), then bisect each
    # piece whose ends differ in sign
    cuts = np.empty(4)
    cuts[0] = 0.0
    nc = 1
    qa, qb, qc = 3.0 * k3, 2.0 * k2, k1
    if qa != 0.0:
        disc = qb * qb - 4.0 * qa * qc
        if disc > 0.0:
            r = math.sqrt(disc)
            t0, t1 = (-qb - r) / (2.0 * qa), (-qb + r) / (2.0 * qa)
            if t0 > t1:
                t0, t1 = t1, t0
            if 0.0 < t0 < 1.0:
                cuts[nc] = t0
                nc += 1
            if 0.0 < t1 < 1.0:
                cuts[nc] = t1
                nc += 1
    elif qb != 0.0:
        t = -qc / qb
        if 0.0 < t < 1.0:
            cuts[nc] = t
            nc += 1
    cuts[nc] = 1.0
    nc += 1
    n = 0
    for i in range(nc - 1):
        lo, hi = cuts[i], cuts[i + 1]
        glo = ((k3 * lo + k2) * lo + k1) * lo + k0
        ghi = ((k3 * hi + k2) * hi + k1) * hi + k0
        if glo == 0.0:
            if 0.0 < lo < 1.0 and (n == 0 or out[n - 1] != lo):
                out[n] = lo
                n += 1
            continue
        if glo * ghi > 0.0 or ghi == 0.0:
            continue
        for _ in range(64):
            mid = 0.5 * (lo + hi)
            gm = ((k3 * mid + k2) * mid + k1) * mid + k0
            if (gm > 0.0) == (glo > 0.0):
                lo, glo = mid, gm
            else:
                hi = mid
        out[n] = 0.5 * (lo + hi)
        n += 1
    return n


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _as_cubic(stack, seg, kind):
    """Write into stack[0] the cubic of a segment row: a cubic itself (kind 4), a quadratic
    raised exactly (3), or a conic (5) as the cubic Path.without_conics makes of it (handles at
    4w / (3(1 + w)) of the way to b1, the same arithmetic: the same bits)."""
    if kind == 5:
        w = _conic_weight(seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6], seg[7])
        kk = 4.0 * w / (3.0 * (1.0 + w))
        stack[0, 0], stack[0, 1] = seg[0], seg[1]
        stack[0, 2] = seg[0] + kk * (seg[2] - seg[0])
        stack[0, 3] = seg[1] + kk * (seg[3] - seg[1])
        stack[0, 4] = seg[6] + kk * (seg[2] - seg[6])
        stack[0, 5] = seg[7] + kk * (seg[3] - seg[7])
        stack[0, 6], stack[0, 7] = seg[6], seg[7]
    elif kind == 3:
        stack[0, 0], stack[0, 1] = seg[0], seg[1]
        stack[0, 2] = seg[0] + 2.0 / 3.0 * (seg[2] - seg[0])
        stack[0, 3] = seg[1] + 2.0 / 3.0 * (seg[3] - seg[1])
        stack[0, 4] = seg[4] + 2.0 / 3.0 * (seg[2] - seg[4])
        stack[0, 5] = seg[5] + 2.0 / 3.0 * (seg[3] - seg[5])
        stack[0, 6], stack[0, 7] = seg[4], seg[5]
    else:
        for j in range(8):
            stack[0, j] = seg[j]


@njit(cache=True)
def path_segments_batch(verbs, points, vstart, pstart, which):
    """The subpaths of the paths ``which`` of a batch (path i: verbs[vstart[i]:vstart[i + 1]],
    points[pstart[i]:pstart[i + 1]]) as stroke_segments takes them: (kinds, segments, subpath
    starts, subpath kinds, path starts), path k's subpaths those from path starts[k] to path
    starts[k + 1], the closing lines made explicit. Subpaths with a moveto alone are dropped
    (they are not stroked); others are kept even if all their segments have zero length
    (round and square caps draw them as dots)."""
    total = 0
    for w in range(len(which)):
        total += vstart[which[w] + 1] - vstart[which[w]]
    kinds = np.empty(total, np.int64)
    segs = np.zeros((total, 8))
    subs = np.empty(total + 1, np.int64)
    flags = np.empty(total, np.int64)
    psubs = np.empty(len(which) + 1, np.int64)
    ns = nsub = 0
    for w in range(len(which)):
        psubs[w] = nsub
        i = which[w]
        ip = pstart[i]
        first = ns
        drawn = have_start = False
        sx = sy = cx = cy = 0.0
        for iv in range(vstart[i], vstart[i + 1]):
            v = verbs[iv]
            if v == MOVE:
                if drawn:
                    subs[nsub] = first
                    flags[nsub] = SUB_OPEN
                    nsub += 1
                first = ns
                sx, sy = points[ip, 0], points[ip, 1]
                cx, cy = sx, sy
                ip += 1
                drawn = False
                have_start = True
            elif v == CLOSE:
                if have_start:
                    kinds[ns] = 2
                    segs[ns, 0], segs[ns, 1], segs[ns, 2], segs[ns, 3] = cx, cy, sx, sy
                    ns += 1
                    subs[nsub] = first
                    flags[nsub] = SUB_CLOSED
                    nsub += 1
                    cx, cy = sx, sy
                ns = first = ns if have_start else first
                drawn = False
            else:
                k = 3 if v == CUBIC or v == CONIC else (2 if v == QUAD else 1)
                kinds[ns] = 5 if v == CONIC else k + 1     # (a conic: b0, b1, midpoint, b2)
                segs[ns, 0], segs[ns, 1] = cx, cy
                for j in range(k):
                    segs[ns, 2 + 2 * j] = points[ip + j, 0]
                    segs[ns, 3 + 2 * j] = points[ip + j, 1]
                cx, cy = points[ip + k - 1, 0], points[ip + k - 1, 1]
                ip += k
                ns += 1
                drawn = True
        if drawn:
            subs[nsub] = first
            flags[nsub] = SUB_OPEN
            nsub += 1
            first = ns
        ns = first          # (segments after the last subpath's end belong to none)
    psubs[len(which)] = nsub
    subs[nsub] = ns
    return kinds[:ns], segs[:ns], subs[:nsub + 1], flags[:nsub], psubs


def path_segments(verbs, points):
    """A path's subpaths as stroke_segments takes them (kinds, segments, subpath starts,
    subpath kinds): path_segments_batch's of the one path (contiguous uint8 verbs, float64
    (N, 2) points)."""
    return path_segments_batch(verbs, points, np.array([0, len(verbs)], np.int64),
                               np.array([0, len(points)], np.int64), _ONE)[:4]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _path_done(verbs, cnt, vo, po, w):
    """Ends path w's outline in stroke_segments' output (from vo[w], po[w] to the counts
    cnt): left out (cnt set back) when it draws nothing, only moves and closes, as
    Path.is_empty judges. Returns the next path's index."""
    drawn = False
    for j in range(vo[w], cnt[0]):
        if verbs[j] != MOVE and verbs[j] != CLOSE:
            drawn = True
            break
    if not drawn:
        cnt[0], cnt[1] = vo[w], po[w]
    vo[w + 1], po[w + 1] = cnt[0], cnt[1]
    return w + 1


@njit(cache=True)
def stroke_segments(kinds, segs, subs, flags, psubs, hw, tol, join, cap, miterlimit,
                    general):
    """Outline (verbs, points) of subpaths of segments (see path_segments). Subpaths of lines
    only go to _stroke_polyline unless general (tests compare the two strokers); the others to
    the general stroker, written out below rather than a kernel of its own: each call level
    is linked, optimised and compiled to machine code again in its caller.

    The general stroker takes the segments lo..hi-1 of one subpath: they become pieces (lines,
    offset cubics, chords) grouped into runs with continuous tangents, joined inline; one
    contour when open, two loops when closed, as in _stroke_polyline."""
    verbs = np.empty(64, np.uint8)
    pts = np.empty((64, 2))
    cnt = np.zeros(2, np.int64)
    # scratch for every subpath, grown as a longer one needs (dashes make thousands of short
    # subpaths, and twenty small allocations each took a third of the stroker's time)
    src = np.empty((16, 2))
    q = np.empty((16, 2))
    dirs = np.empty((16, 2))
    lens = np.empty(16)
    tab = np.empty((16, _PIECE_COLS))
    pk = np.empty(16, np.uint8)
    stack = np.empty((_MAX_DEPTH + 2, 9))
    roots = np.empty(3)
    cur = np.empty(8)
    right = np.empty(8)
    left = np.empty(8)
    probes = np.empty((3, 5))
    firsts = np.empty(16, np.int64)
    ends = np.empty((16, 4))
    piece_seg = np.empty(16, np.int64)
    run_lo = np.empty(16, np.int64)
    run_join = np.empty(16, np.int64)
    rv = np.empty(64, np.uint8)
    lv = np.empty(64, np.uint8)
    rp = np.empty((64, 2))
    lp = np.empty((64, 2))
    rc = np.zeros(2, np.int64)
    lc = np.zeros(2, np.int64)
    tv = np.empty(_SIDE_VERBS_PER_VERTEX, np.uint8)
    tp = np.empty((_SIDE_PTS_PER_VERTEX, 2))
    tc = np.zeros(2, np.int64)
    vo = np.zeros(len(psubs), np.int64)
    po = np.zeros(len(psubs), np.int64)
    w = 0                   # the path whose subpaths are stroked
    for k in range(len(flags)):
        while psubs[w + 1] <= k:
            w = _path_done(verbs, cnt, vo, po, w)
        lo, hi = subs[k], subs[k + 1]
        if flags[k] == SUB_DOT:
            verbs = _grow(verbs, cnt[0] + _DOT_VERBS)
            pts = _grow_points(pts, cnt[1] + _DOT_PTS)
            dot_contour(verbs, pts, cnt, segs[lo, 0], segs[lo, 1], segs[lo, 2], segs[lo, 3],
                        hw, cap, tol)
            continue
        closed = flags[k] == SUB_CLOSED
        lines = not general
        for s in range(lo, hi):
            lines = lines and kinds[s] == 2
        if lines:
            m = hi - lo + 1
            src = _grow_points(src, m)
            for s in range(lo, hi):
                src[s - lo, 0], src[s - lo, 1] = segs[s, 0], segs[s, 1]
            src[m - 1, 0], src[m - 1, 1] = segs[hi - 1, 2], segs[hi - 1, 3]
            verbs = _grow(verbs, cnt[0] + 2 * (_SIDE_VERBS_PER_VERTEX * m + 2) +
                                2 * _CAP_VERBS + 4 + _DOT_VERBS)
            pts = _grow_points(pts, cnt[1] + 2 * (_SIDE_PTS_PER_VERTEX * m + 2) + 2 * _CAP_PTS +
                               4 + _DOT_PTS + 1)
            side_verbs = _SIDE_VERBS_PER_VERTEX * m + 4
            side_pts = _SIDE_PTS_PER_VERTEX * m + 4
            q = _grow_points(q, m)
            dirs = _grow_points(dirs, m)
            lens = _grow(lens, m)
            rv = _grow(rv, side_verbs)
            lv = _grow(lv, side_verbs)
            rp = _grow_points(rp, side_pts)
            lp = _grow_points(lp, side_pts)
            _stroke_polyline(verbs, pts, cnt, src, np.int64(0), m, closed, hw, tol, join, cap,
                             miterlimit, q, dirs, lens, rv, rp, lv, lp, rc, lc)
            continue
        firsts = _grow(firsts, hi - lo + 1)     # each segment's first piece, then n
        # each segment's own end directions (start x, y, end x, y): where a bend tighter than
        # the half width makes a curve's end pieces chords, their directions are off its tangent,
        # and a join's miter limit must judge the tangents (SVG 2 path directionality)
        ends = _grow_points(ends, hi - lo)
        for s in range(hi - lo):
            for j in range(4):
                ends[s, j] = 0.0
        n = np.int64(0)         # (not a literal 0: that would compile the helpers twice)
        for s in range(lo, hi):
            firsts[s - lo] = n
            seg = segs[s]
            if kinds[s] == 2:
                ok, dx, dy = _unit(seg[2] - seg[0], seg[3] - seg[1])
                if ok:
                    tab, pk, n = _line_piece(tab, pk, n, seg[0], seg[1], seg[2], seg[3], dx, dy,
                                             hw, 0.0)
            else:
                if kinds[s] == 5:       # a circular arc: exact offsets
                    tab, pk, n, ok = _circle_piece(tab, pk, n, seg, hw)
                    if ok:
                        continue
                _as_cubic(stack, seg, kinds[s])
                if kinds[s] != 5 and _in_line(seg, kinds[s]):
                    # a curve in line: the lines through its points of extreme speed
                    # (_in_line), their directions its ends' (ends[] stays unset)
                    nr = _speed_extrema(stack[0], roots)
                    px, py = stack[0, 0], stack[0, 1]
                    for i in range(nr + 1):
                        qx, qy = stack[0, 6], stack[0, 7]
                        if i < nr:
                            qx, qy = _cubic_at(stack[0], roots[i])
                            if (qx == stack[0, 0] and qy == stack[0, 1]) or \
                                    (qx == stack[0, 6] and qy == stack[0, 7]):
                                continue
                        ok, dx, dy = _unit(qx - px, qy - py)
                        if ok:
                            tab, pk, n = _line_piece(tab, pk, n, px, py, qx, qy, dx, dy, hw,
                                                     0.0)
                            px, py = qx, qy
                    continue
                for j in range(8):
                    cur[j] = stack[0, j]
                ok, t0x, t0y, t1x, t1y = _cubic_tangents(cur)
                ends[s - lo, 0], ends[s - lo, 1], ends[s - lo, 2], ends[s - lo, 3] = \
                    t0x, t0y, t1x, t1y
                # The cubic in stack[0] becomes pieces (written out here, not a kernel of its
                # own: each call level is linked, optimised and compiled again in its caller):
                # offset cubics where they fit within tol, else halves (depth first, the first
                # half first), down to pieces flat within tol / 2, which become their chords.
                # Stroked with round joins between them (the stroker's rule inside a curve),
                # chords are within tol / 2 of the curve's stroke: the round-joined stroke of a
                # polyline is its Minkowski sum with the pen disc. That is also how bends
                # tighter than the half width are handled, where the offset folds back on
                # itself. The joins' and caps' arcs may lie inside the disc by their own
                # tolerance, which adds to the chord's: they get what the chord leaves (see
                # _shape_tol). stack rows: 8 coordinates and the depth; cur: one cubic.
                stack[0, 8] = 0.0
                sx0, sy0, sx3, sy3 = cur[0], cur[1], cur[6], cur[7]
                top = 1
                while top > 0:
                    top -= 1
                    for j in range(8):
                        cur[j] = stack[top, j]
                    depth = int(stack[top, 8])
                    if depth > 0:       # (the whole cubic's were found above)
                        ok, t0x, t0y, t1x, t1y = _cubic_tangents(cur)
                    if not ok:
                        continue
                    # a piece turning by more than 90° is split so the midpoint fit stays well
                    # posed
                    fits = t0x * t1x + t0y * t1y >= 0.0
                    if fits:
                        # a bend tighter than hw on a side makes that side's offset fold back
                        for t in (0.0, 0.5, 1.0):
                            kc = _curvature(cur, t)
                            if not math.isfinite(kc) or hw * abs(kc) >= 1.0:
                                fits = False
                                break
                    if fits:
                        _offset_probes(cur, probes)
                        mid = not _fit_offset(cur, t0x, t0y, t1x, t1y, -hw, right, probes)
                        fits = not _offset_error(right, -hw, mid, probes) > tol
                    if fits:
                        mid = not _fit_offset(cur, t0x, t0y, t1x, t1y, hw, left, probes)
                        fits = not _offset_error(left, hw, mid, probes) > tol
                    if fits:
                        tab = _grow_points(tab, n + 1)
                        pk = _grow(pk, n + 1)
                        row = tab[n]
                        row[0], row[1], row[2], row[3] = cur[0], cur[1], cur[6], cur[7]
                        row[4], row[5], row[6], row[7] = t0x, t0y, t1x, t1y
                        for j in range(8):
                            row[_PR + j] = right[j]
                            row[_PL + j] = left[j]
                        row[_PERR] = 0.0
                        pk[n] = 4
                        n += 1
                        continue
                    flat = _flatness(cur)
                    split = flat > tol / 2.0
                    if not split and depth < _MAX_DEPTH:
                        # a chord at the segment's end stands for it in the join or cap there,
                        # whose shape is offset along the chord: halved until the chord's
                        # offset end is within tol / 2 of the tangent's (a curve turning tighter
                        # than the half width, e.g. from a control point at its start, turns
                        # its first chord off the tangent by an angle that the flatness does
                        # not bound, and a wide stroke's offset by hw times it)
                        ok, dx, dy = _unit(cur[6] - cur[0], cur[7] - cur[1])
                        if ok and cur[0] == sx0 and cur[1] == sy0:
                            split = hw * _hypot(dx - ends[s - lo, 0],
                                                dy - ends[s - lo, 1]) > tol / 2.0
                        if ok and not split and cur[6] == sx3 and cur[7] == sy3:
                            split = hw * _hypot(dx - ends[s - lo, 2],
                                                dy - ends[s - lo, 3]) > tol / 2.0
                    if depth < _MAX_DEPTH and split:
                        # the second half below the first, which is popped next
                        sa, sb = stack[top + 1], stack[top]
                        x0, y0, x1, y1, x2, y2, x3, y3 = (cur[0], cur[1], cur[2], cur[3],
                                                          cur[4], cur[5], cur[6], cur[7])
                        ax, ay = x0 + (x1 - x0) * 0.5, y0 + (y1 - y0) * 0.5
                        bx, by = x1 + (x2 - x1) * 0.5, y1 + (y2 - y1) * 0.5
                        cx, cy = x2 + (x3 - x2) * 0.5, y2 + (y3 - y2) * 0.5
                        dx, dy = ax + (bx - ax) * 0.5, ay + (by - ay) * 0.5
                        ex, ey = bx + (cx - bx) * 0.5, by + (cy - by) * 0.5
                        fx, fy = dx + (ex - dx) * 0.5, dy + (ey - dy) * 0.5
                        sa[0], sa[1], sa[2], sa[3] = x0, y0, ax, ay
                        sa[4], sa[5], sa[6], sa[7] = dx, dy, fx, fy
                        sb[0], sb[1], sb[2], sb[3] = fx, fy, ex, ey
                        sb[4], sb[5], sb[6], sb[7] = cx, cy, x3, y3
                        sa[8] = sb[8] = depth + 1.0
                        top += 2
                        continue
                    ok, dx, dy = _unit(cur[6] - cur[0], cur[7] - cur[1])
                    if ok:
                        tab, pk, n = _line_piece(tab, pk, n, cur[0], cur[1], cur[6], cur[7], dx,
                                                 dy, hw, flat)
                        continue
                    # a closed loop too small to matter (or depth exhausted): two chords via its
                    # midpoint
                    mx, my = _cubic_at(cur, 0.5)
                    ok, dx, dy = _unit(mx - cur[0], my - cur[1])
                    if ok:
                        tab, pk, n = _line_piece(tab, pk, n, cur[0], cur[1], mx, my, dx, dy,
                                                 hw, flat)
                    ok, dx, dy = _unit(cur[6] - mx, cur[7] - my)
                    if ok:
                        tab, pk, n = _line_piece(tab, pk, n, mx, my, cur[6], cur[7], dx, dy,
                                                 hw, flat)
        firsts[hi - lo] = n
        piece_seg = _grow(piece_seg, n + 1)
        for s in range(hi - lo):
            if firsts[s + 1] > firsts[s] and ends[s, 0] == 0.0 and ends[s, 1] == 0.0:
                # a line or an exact arc: its pieces' own directions
                ends[s, 0], ends[s, 1] = tab[firsts[s], _PT0], tab[firsts[s], _PT0 + 1]
                ends[s, 2] = tab[firsts[s + 1] - 1, _PT1]
                ends[s, 3] = tab[firsts[s + 1] - 1, _PT1 + 1]
            for j in range(firsts[s], firsts[s + 1]):
                piece_seg[j] = s
        run_lo = _grow(run_lo, n + 1)
        run_join = _grow(run_join, n + 1)
        nruns = 0
        for s in range(hi - lo):
            first = firsts[s]
            for j in range(first, firsts[s + 1]):
                if j > first and _meet_straight(tab, j - 1, j, hw, tol / 2.0):
                    continue            # on with the run
                run_lo[nruns] = j
                run_join[nruns] = join if j == first else _ROUND
                nruns += 1
        run_lo[nruns] = n
        if nruns == 0:
            verbs = _grow(verbs, cnt[0] + _DOT_VERBS)
            pts = _grow_points(pts, cnt[1] + _DOT_PTS)
            dot_contour(verbs, pts, cnt, segs[lo, 0], segs[lo, 1], 1.0, 0.0, hw, cap, tol)
            continue
        # One chain along both sides, joins and caps inline: as chains this equals the sum of the
        # separate positive pieces (a contour per run closed by butt lines, a wedge per join), as
        # explained in _stroke_polyline, so the nonzero fill is their union.
        side_verbs = 2 * n + _JOIN_SIDE_VERBS * (nruns + 1) + 4
        side_pts = 4 * n + _JOIN_SIDE_PTS * (nruns + 1) + 4
        rv = _grow(rv, side_verbs)
        lv = _grow(lv, side_verbs)
        rp = _grow_points(rp, side_pts)
        lp = _grow_points(lp, side_pts)
        rc[0] = rc[1] = lc[0] = lc[1] = 0
        _point(rp, rc, tab[0, _PR], tab[0, _PR + 1])
        _point(lp, lc, tab[0, _PL], tab[0, _PL + 1])
        # (np.int64: an int literal argument would compile a specialisation of its own)
        _append_side(rv, rp, rc, tab, pk, np.int64(0), run_lo[1], np.int64(_PR))
        _append_side(lv, lp, lc, tab, pk, np.int64(0), run_lo[1], np.int64(_PL))
        for i in range(1, nruns + 1 if closed else nruns):
            a = run_lo[i % nruns]
            prev = run_lo[i] - 1
            d0x, d0y = tab[prev, _PT1], tab[prev, _PT1 + 1]
            d1x, d1y = tab[a, _PT0], tab[a, _PT0 + 1]
            px, py = tab[a, _PS], tab[a, _PS + 1]
            r1x, r1y = tab[a, _PR], tab[a, _PR + 1]
            l1x, l1y = tab[a, _PL], tab[a, _PL + 1]
            cross = d0x * d1y - d0y * d1x
            dot = d0x * d1x + d0y * d1y
            jtol = _shape_tol(tab, prev, a, tol)
            if _meet_straight(tab, prev, a, hw, jtol):
                _line(rv, rp, rc, r1x, r1y)
                _line(lv, lp, lc, l1x, l1y)
            else:
                jn = run_join[i] if i < nruns else join
                e0, e1 = ends[piece_seg[prev]], ends[piece_seg[a]]
                if e0[2] * e1[0] + e0[3] * e1[1] > SMOOTH_COS:
                    # segments meeting smoothly, where a chord standing in for a bend tighter
                    # than the half width turns: no join of the path's but the curve's own
                    # (the stroke is the pen disc swept along it), round as inside a curve
                    jn = _ROUND
                limit_dot = e0[2] * e1[0] + e0[3] * e1[1] if jn != _ROUND else dot
                t_cross = e0[2] * e1[1] - e0[3] * e1[0]
                if jn != _ROUND and limit_dot < dot and t_cross * cross > 0.0:
                    # a join of segments takes its shape from their own tangents too (SVG 2:
                    # the directions at the vertex) where they turn the same way as the
                    # pieces, and more: the chord standing in for a curve's end that bends
                    # tighter than the half width turns less, and would pull a miter's tip in
                    # (M 159 146 L 80 88 C 80 88 99 93 174 46, width 20: 14 units short). The
                    # chord's offset end then lies between the tip and the tangent's offset
                    # end, in the chord's own stroke, so the join still meets it.
                    d0x, d0y, d1x, d1y = e0[2], e0[3], e1[0], e1[1]
                    cross = t_cross
                    dot = limit_dot
                if cross > 0:       # turning left: left side inner
                    _turn_sides(rv, rp, rc, lv, lp, lc, tv, tp, tc, px, py, d0x, d0y, d1x, d1y,
                                -1.0, hw, jn, miterlimit, dot, limit_dot, jtol, r1x, r1y, l1x,
                                l1y)
                else:
                    _turn_sides(lv, lp, lc, rv, rp, rc, tv, tp, tc, px, py, d0x, d0y, d1x, d1y,
                                1.0, hw, jn, miterlimit, dot, limit_dot, jtol, l1x, l1y, r1x,
                                r1y)
            if i < nruns:
                _append_side(rv, rp, rc, tab, pk, a, run_lo[i + 1], np.int64(_PR))
                _append_side(lv, lp, lc, tab, pk, a, run_lo[i + 1], np.int64(_PL))
        verbs = _grow(verbs, cnt[0] + rc[0] + lc[0] + 2 * _CAP_VERBS + 4)
        pts = _grow_points(pts, cnt[1] + rc[1] + lc[1] + 2 * _CAP_PTS + 4)
        if closed:
            # the sides start where the first run starts; the closing join ended there too
            _emit_closed_sides(verbs, pts, cnt, rv, rp, rc, lv, lp, lc)
            continue
        last = n - 1
        verbs[cnt[0]] = MOVE
        cnt[0] += 1
        _emit_side_forward(verbs, pts, cnt, rv, rp, rc, np.int64(0))
        cap_items(verbs, pts, cnt, tab[last, _PE], tab[last, _PE + 1], tab[last, _PT1],
                  tab[last, _PT1 + 1], hw, cap, _shape_tol(tab, last, last, tol))
        _emit_side_backward(verbs, pts, cnt, lv, lp, lc, np.int64(0))
        cap_items(verbs, pts, cnt, tab[0, _PS], tab[0, _PS + 1], -tab[0, _PT0], -tab[0, _PT0 + 1],
                  hw, cap, _shape_tol(tab, np.int64(0), np.int64(0), tol))
        verbs[cnt[0]] = CLOSE
        cnt[0] += 1
    while w < len(psubs) - 1:
        w = _path_done(verbs, cnt, vo, po, w)
    return verbs[:cnt[0]], pts[:cnt[1]], vo, po


# -- dashes of curves -----------------------------------------------------------------------
# Dashes are placed where resvg (tiny-skia's ContourMeasure) and Chromium (Skia's
# SkContourMeasure) place them, not at exact arc lengths: a curve is halved until its control
# points are within a tolerance of the chord's thirds (a quadratic's of the chord's midpoint),
# its length is the sum of those chords, and a distance inside a chord maps to the parameter
# linearly between the chord's end parameters. The chords undershoot the curve: on a circle
# of 60 device px a dash ends ~0.5 px short of its exact arc length by the end of the turn,
# visibly so in a dash's cap. usvg draws every arc as kurbo's cubics (stroke.arc_cubics):
# circular arcs stay exact conics here (stroke.dash_curves), measured by those cubics and cut
# at the angles of the cubics' points (the same places along the arc to within ~3e-4 of its
# radius across it), so that dashed circles are the solid circle's pieces.

#: the measure's parameter resolution: a curve is halved while its parameter span in these
#: units is 1024 or more, 20 times at most, as in Skia (whose kMaxTValue is 2^30 - 1, so its
#: halves are labelled ~1e-9 off the parameters they are cut at; these are exact)
_MAX_T = 1 << 30
_MIN_SPAN = 1 << 10
#: at most this many cubics an arc (kurbo's count grows as the radius^(1/6) without bound:
#: 1024 is reached at radii of ~1e17 units)
MAX_ARC_CUBICS = 1024
#: usvg's tolerance for the cubics it makes of arcs (kurbo's Arc::to_cubic_beziers), in user
#: units (see stroke.arc_cubics)
ARC_TOLERANCE = 0.1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _too_curvy(kind, c, tol):
    """Whether a quadratic (kind 3: c = x0 y0 x1 y1 x2 y2) or cubic (4) is to be halved again:
    the control point off the midpoint of the chord and its ends' midpoint (half of its
    distance from the chord's midpoint), or either cubic control point off the chord's third,
    by more than tol in x or y (the measures' "cheap distance")."""
    if kind == 3:
        dx = 0.5 * c[2] - 0.25 * (c[0] + c[4])
        dy = 0.5 * c[3] - 0.25 * (c[1] + c[5])
        return max(abs(dx), abs(dy)) > tol
    for k in range(1, 3):
        f = k / 3.0
        dx = c[0] + (c[6] - c[0]) * f - c[2 * k]
        dy = c[1] + (c[7] - c[1]) * f - c[2 * k + 1]
        if max(abs(dx), abs(dy)) > tol:
            return True
    return False


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _halve(kind, c, left, right):
    """de Casteljau at ½ of a quadratic (kind 3) or cubic (4) row c into left and right."""
    if kind == 3:
        ax, ay = 0.5 * (c[0] + c[2]), 0.5 * (c[1] + c[3])
        bx, by = 0.5 * (c[2] + c[4]), 0.5 * (c[3] + c[5])
        mx, my = 0.5 * (ax + bx), 0.5 * (ay + by)
        left[0], left[1], left[2], left[3], left[4], left[5] = c[0], c[1], ax, ay, mx, my
        right[0], right[1], right[2], right[3], right[4], right[5] = mx, my, bx, by, c[4], c[5]
        return
    ax, ay = 0.5 * (c[0] + c[2]), 0.5 * (c[1] + c[3])
    bx, by = 0.5 * (c[2] + c[4]), 0.5 * (c[3] + c[5])
    cx, cy = 0.5 * (c[4] + c[6]), 0.5 * (c[5] + c[7])
    dx, dy = 0.5 * (ax + bx), 0.5 * (ay + by)
    ex, ey = 0.5 * (bx + cx), 0.5 * (by + cy)
    mx, my = 0.5 * (dx + ex), 0.5 * (dy + ey)
    left[0], left[1], left[2], left[3], left[4], left[5] = c[0], c[1], ax, ay, dx, dy
    left[6], left[7] = mx, my
    right[0], right[1], right[2], right[3], right[4], right[5] = mx, my, ex, ey, cx, cy
    right[6], right[7] = c[6], c[7]


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _curve_chords(kind, c, tol, chords, n, length, u0, du, min_span):
    """Appends the chords a quadratic (kind 3: c = x0 y0 x1 y1 x2 y2) or cubic (4) is
    measured by to ``chords`` (rows: length from the segment's start, which is ``length`` at
    the curve's start, to the chord's end; the segment's parameter there, u0 + du·t at the
    curve's t) from row n on: the curve halved while _too_curvy by tol and its span of
    _MAX_T is min_span or more; chords of zero length add no row. Returns (chords, possibly
    grown; new n; length at the curve's end)."""
    npts = 3 if kind == 3 else 4
    last = 2 * npts - 2
    stack = np.empty((24, 8))           # depth ≤ 20: span >> 10 ends the halving
    lo = np.empty(24, np.int64)
    hi = np.empty(24, np.int64)
    stack[0] = c
    lo[0], hi[0] = 0, _MAX_T
    top = 1
    while top > 0:
        top -= 1
        a, b = lo[top], hi[top]
        if b - a >= min_span and _too_curvy(kind, stack[top], tol):
            half = (a + b) >> 1
            # the right half goes below the left (in place: _halve reads c first), so the
            # left is measured first
            _halve(kind, stack[top], stack[top + 1], stack[top])
            lo[top], hi[top] = half, b
            lo[top + 1], hi[top + 1] = a, half
            top += 2
            continue
        q = stack[top]
        d = _hypot(q[last] - q[0], q[last + 1] - q[1])
        if length + d > length:
            length += d
            chords = _grow_points(chords, n + 1)
            chords[n, 0], chords[n, 1] = length, u0 + du * (b / _MAX_T)
            n += 1
    return chords, n, length


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _segment_chords(kind, c, arc, tol, chords, n):
    """Appends the chords a segment (path_segments' kind and row c: 2 a line, 3 a quadratic,
    4 a cubic, 5 a circular arc with its _arc_measure in ``arc``) is measured by (see
    _curve_chords); an arc by the cubics usvg makes of it (_arc_cubic), its parameter k + t
    over their number n on the k-th's t. Returns (chords, possibly grown; new n)."""
    if kind == 2:
        d = _hypot(c[2] - c[0], c[3] - c[1])
        if d > 0.0:
            chords = _grow_points(chords, n + 1)
            chords[n, 0], chords[n, 1] = d, 1.0
            n += 1
        return chords, n
    if kind != 5:
        chords, n, _ = _curve_chords(kind, c, tol, chords, n, 0.0, 0.0, 1.0, _MIN_SPAN)
        return chords, n
    pieces = _arc_cubic_count(arc)
    # (the arc's cubics together halved no finer than one curve: 2^20 chords at most)
    min_span = _MIN_SPAN
    while min_span < _MIN_SPAN * pieces:
        min_span *= 2
    cubic = np.empty(8)
    length = 0.0
    for k in range(pieces):
        _arc_cubic(arc, k, pieces, cubic)
        chords, n, length = _curve_chords(4, cubic, tol, chords, n, length, k / pieces,
                                          1.0 / pieces, min_span)
    return chords, n


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc_cubic_count(arc):
    """How many cubics kurbo cuts a circular arc (_arc_measure's ``arc``) into at usvg's
    tolerance (see stroke.arc_cubics)."""
    density = max((1.1163 * arc[2] / ARC_TOLERANCE) ** (1.0 / 6.0), 3.999999)
    return max(1, int(math.ceil(min(density * arc[3] / (2.0 * math.pi), MAX_ARC_CUBICS))))


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc_cubic(arc, k, pieces, out):
    """The k-th of the ``pieces`` cubics kurbo makes of a circular arc (_arc_measure's
    ``arc``): equal angles, handles 4/3·tan(angle/4)·r along the tangents, into out."""
    cx, cy, r, angle, start, sense = arc[0], arc[1], arc[2], arc[3], arc[4], arc[5]
    step = sense * angle / pieces
    arm = 4.0 / 3.0 * math.tan(0.25 * step) * r
    a0, a1 = start + k * step, start + (k + 1) * step
    c0, s0, c1, s1 = math.cos(a0), math.sin(a0), math.cos(a1), math.sin(a1)
    out[0], out[1] = cx + r * c0, cy + r * s0
    out[2], out[3] = out[0] - arm * s0, out[1] + arm * c0
    out[6], out[7] = cx + r * c1, cy + r * s1
    out[4], out[5] = out[6] + arm * s1, out[7] - arm * c1


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc_angle_at(arc, u):
    """The angle from a circular arc's start (_arc_measure's ``arc``), towards its end, of
    the point at parameter u of its cubics (see _segment_chords): where usvg's curve is
    there, projected on the exact arc."""
    if u <= 0.0:
        return 0.0
    if u >= 1.0:
        return arc[3]
    pieces = _arc_cubic_count(arc)
    k = min(int(u * pieces), pieces - 1)
    cubic = np.empty(8)
    _arc_cubic(arc, k, pieces, cubic)
    x, y = _cubic_at(cubic, u * pieces - k)
    turn = arc[5] * (math.atan2(y - arc[1], x - arc[0]) - arc[4])
    turn -= 2.0 * math.pi * math.floor((turn + math.pi) / (2.0 * math.pi))   # to [-π, π)
    return min(max(turn, 0.0), arc[3])


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc_measure(c, out):
    """A circular conic (b0, b1, point at t = ½, b2) measured exactly into out: centre x, y,
    radius, the angle it spans, its start angle, its sense (+1 towards increasing angles, y
    down); its length is radius × angle."""
    x0, y0, x1, y1, x2, y2 = c[0], c[1], c[2], c[3], c[6], c[7]
    cx, cy, r = _circle_centre(x0, y0, x1, y1, x2, y2)
    # the half angle φ: between the chord and the tangent at b0
    half = math.hypot(0.5 * (x2 - x0), 0.5 * (y2 - y0))
    rise = math.hypot(0.5 * (x0 + x2) - x1, 0.5 * (y0 + y2) - y1)
    out[0], out[1], out[2] = cx, cy, r
    out[3] = 2.0 * math.atan2(rise, half)
    out[4] = math.atan2(y0 - cy, x0 - cx)
    out[5] = 1.0 if (x1 - x0) * (y0 - cy) - (y1 - y0) * (x0 - cx) < 0 else -1.0


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc_piece(c, a, a0, a1, out):
    """The part of the measured arc (row c, measures a) between the angles a0 and a1 from its
    start into out: the arc itself where it spans it all (kind 5), a line where the part is
    flat to rounding (2), else the conic of the sub-arc (5), from the centre, radius and
    angles."""
    cx, cy, r, angle, start, sense = a[0], a[1], a[2], a[3], a[4], a[5]
    if a0 <= 0.0 and a1 >= angle:
        out[:] = c
        return 5
    out[:] = 0.0
    if a0 <= 0.0:
        out[0], out[1] = c[0], c[1]
    else:
        out[0], out[1] = cx + r * math.cos(start + sense * a0), cy + r * math.sin(start + sense * a0)
    if a1 >= angle:
        px, py = c[6], c[7]
    else:
        px, py = cx + r * math.cos(start + sense * a1), cy + r * math.sin(start + sense * a1)
    half = 0.5 * (a1 - a0)
    if r * (1.0 - math.cos(half)) <= 1e-9 * r:
        out[2], out[3] = px, py
        return 2
    b = start + sense * (a0 + half)
    mx, my = cx + r * math.cos(b), cy + r * math.sin(b)
    k = 1.0 / math.cos(half)
    out[2], out[3] = cx + k * (mx - cx), cy + k * (my - cy)
    out[4], out[5], out[6], out[7] = mx, my, px, py
    return 5


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _param_at(chords, lo, hi, s):
    """The parameter at length s along a segment measured by chords[lo:hi]: linear between
    the ends of the first chord reaching s (0 on a segment with no chords)."""
    if hi <= lo:
        return 0.0
    a, b = lo, hi - 1
    while a < b:
        mid = (a + b) >> 1
        if chords[mid, 0] < s:
            a = mid + 1
        else:
            b = mid
    d0 = chords[a - 1, 0] if a > lo else 0.0
    t0 = chords[a - 1, 1] if a > lo else 0.0
    t = t0 + (chords[a, 1] - t0) * (s - d0) / (chords[a, 0] - d0)
    return min(max(t, 0.0), 1.0)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _split_at(c, t, left):
    """de Casteljau at t of the cubic row c (8 values) in place: its left part, or its
    right."""
    x0, y0, x1, y1, x2, y2, x3, y3 = c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]
    ax, ay = x0 + (x1 - x0) * t, y0 + (y1 - y0) * t
    bx, by = x1 + (x2 - x1) * t, y1 + (y2 - y1) * t
    cx, cy = x2 + (x3 - x2) * t, y2 + (y3 - y2) * t
    dx, dy = ax + (bx - ax) * t, ay + (by - ay) * t
    ex, ey = bx + (cx - bx) * t, by + (cy - by) * t
    fx, fy = dx + (ex - dx) * t, dy + (ey - dy) * t
    if left:
        c[2], c[3], c[4], c[5], c[6], c[7] = ax, ay, dx, dy, fx, fy
    else:
        c[0], c[1], c[2], c[3], c[4], c[5] = fx, fy, ex, ey, cx, cy


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _dash_piece(mk, mrow, j, t0, t1, out):
    """The part of measured segment j between parameters t0 and t1 into out (8 values); its
    kind (2 a line, 4 a cubic)."""
    if mk[j] == 2:
        x0, y0, x1, y1 = mrow[j, 0], mrow[j, 1], mrow[j, 2], mrow[j, 3]
        out[:] = 0.0
        out[0], out[1] = x0 + (x1 - x0) * t0, y0 + (y1 - y0) * t0
        out[2], out[3] = x0 + (x1 - x0) * t1, y0 + (y1 - y0) * t1
        return 2
    out[:] = mrow[j]
    if t1 < 1.0:
        _split_at(out, t1, True)
        t0 = t0 / t1 if t1 > 0 else 0.0
    if t0 > 0.0:
        _split_at(out, t0, False)
    return 4


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _dot_direction(mk, mrow, j, t):
    """Direction of a zero-length dash at parameter t of segment j: the tangent there, else
    the segment's start tangent, else +x."""
    c = mrow[j]
    if mk[j] == 2:
        ok, ux, uy = _unit(c[2] - c[0], c[3] - c[1])
        return (ux, uy) if ok else (1.0, 0.0)
    ok, ux, uy = _unit(*_cubic_velocity(c, t))
    if ok:
        return ux, uy
    ok, sx, sy, _, _ = _cubic_tangents(c)
    return (sx, sy) if ok else (1.0, 0.0)


@njit(cache=True)
def dash_length(kinds, segs, tol):
    """The total length of path_segments' subpaths as the dasher measures it (its chords
    within tol: _segment_chords)."""
    chords = np.empty((64, 2))
    arc = np.zeros(6)
    total = 0.0
    for i in range(len(kinds)):
        if kinds[i] == 5:
            _arc_measure(segs[i], arc)
        chords, n = _segment_chords(kinds[i], segs[i], arc, tol, chords, 0)
        if n > 0:
            total += chords[n - 1, 0]
    return total


@njit(cache=True)
def dash_segments(kinds, segs, subs, flags, pattern, offset, tol):
    """The dashes of subpaths (path_segments' arrays, whose conics are circular arcs: see
    stroke.dash_curves), in the same arrays: a dash is an open subpath, a zero-length dash a dot (its point and
    direction). The pattern is walked along each subpath's length as the contour measure
    gives it (chords within ``tol``: _segment_chords), and a curve is cut at the parameters
    _param_at maps its dash ends to (quadratics raised to cubics). On a closed subpath a dash
    running through the start point is one dash (as in Skia, and so in browsers and resvg),
    joined there rather than capped twice."""
    period = 0.0
    for v in pattern:
        period += v
    npat = len(pattern)
    cap = len(kinds) * 4 + 16
    okind = np.empty(cap, np.int64)
    oseg = np.zeros((cap, 8))
    osub = np.empty(cap + 1, np.int64)
    oflag = np.empty(cap, np.int64)
    no = nsub = 0
    mk = np.empty(len(kinds), np.int64)
    mrow = np.zeros((len(kinds), 8))
    mlen = np.empty(len(kinds))
    chords = np.empty((64, 2))      # one segment's chords, measured again where it is cut
    arcs = np.zeros((len(kinds), 6))
    piece = np.empty(8)
    tmp_kind = np.empty(0, np.int64)
    tmp_seg = np.empty((0, 8))
    for sp in range(len(subs) - 1):
        lo, hi = subs[sp], subs[sp + 1]
        m = hi - lo
        closed = flags[sp] == SUB_CLOSED
        total = 0.0
        for j in range(m):
            kind = kinds[lo + j]
            if kind == 5:
                _arc_measure(segs[lo + j], arcs[j])
            chords, nch = _segment_chords(kind, segs[lo + j], arcs[j], tol, chords, 0)
            mlen[j] = chords[nch - 1, 0] if nch > 0 else 0.0
            if kind == 2 or kind == 5:
                mk[j] = kind
                mrow[j] = segs[lo + j]
            else:
                mk[j] = 4
                _as_cubic(mrow[j:j + 1], segs[lo + j], kind)
            total += mlen[j]
        measured = m - 1            # the segment whose chords are in chords[:nch]
        k, phase = _pattern_at(pattern, period, offset % period)
        pos = -phase
        seg_i, seg_start = 0, 0.0
        guard = 0
        first_sub = nsub             # this subpath's first dash
        first_at_start = last_at_end = False
        near = total * _DASH_END_RTOL
        while pos < total - near and guard < 1_000_000:
            guard += 1
            length = pattern[k]
            on = k % 2 == 0
            a, b = max(pos, 0.0), min(pos + length, total)
            if on and b >= a and (b > a or pos >= 0):
                while seg_i < m - 1 and seg_start + mlen[seg_i] < a:
                    seg_start += mlen[seg_i]
                    seg_i += 1
                if no + m + 1 > okind.shape[0] or nsub + 2 > oflag.shape[0]:
                    okind = _grow(okind, 2 * (no + m + 1))
                    oseg = _grow_points(oseg, 2 * (no + m + 1))
                    osub = _grow(osub, 2 * (nsub + 2) + 1)
                    oflag = _grow(oflag, 2 * (nsub + 2))
                if b == a:
                    s = min(max(a - seg_start, 0.0), mlen[seg_i])
                    if measured != seg_i:
                        measured = seg_i
                        chords, nch = _segment_chords(kinds[lo + seg_i], segs[lo + seg_i],
                                                      arcs[seg_i], tol, chords, 0)
                    t = _param_at(chords, 0, nch, s)
                    if mk[seg_i] == 5:
                        ac = arcs[seg_i]
                        turn = _arc_angle_at(ac, t)
                        _arc_piece(mrow[seg_i], ac, turn, turn, piece)
                        bb = ac[4] + ac[5] * turn
                        dx, dy = -ac[5] * math.sin(bb), ac[5] * math.cos(bb)
                    else:
                        _dash_piece(mk, mrow, seg_i, t, t, piece)
                        dx, dy = _dot_direction(mk, mrow, seg_i, t)
                    osub[nsub], oflag[nsub] = no, SUB_DOT
                    nsub += 1
                    okind[no] = 0
                    oseg[no] = 0.0
                    oseg[no, 0], oseg[no, 1], oseg[no, 2], oseg[no, 3] = piece[0], piece[1], dx, dy
                    no += 1
                else:
                    start = no
                    j, js = seg_i, seg_start
                    while j < m and js < b:
                        plo, phi = max(a - js, 0.0), min(b - js, mlen[j])
                        if phi > plo:
                            if measured != j:
                                measured = j
                                chords, nch = _segment_chords(kinds[lo + j], segs[lo + j],
                                                              arcs[j], tol, chords, 0)
                            t0 = _param_at(chords, 0, nch, plo)
                            t1 = _param_at(chords, 0, nch, phi)
                            if mk[j] == 5:
                                okind[no] = _arc_piece(mrow[j], arcs[j], _arc_angle_at(arcs[j], t0),
                                                       _arc_angle_at(arcs[j], t1), piece)
                            else:
                                okind[no] = _dash_piece(mk, mrow, j, t0, t1, piece)
                            oseg[no] = piece
                            no += 1
                        js += mlen[j]
                        j += 1
                    if no > start:
                        osub[nsub], oflag[nsub] = start, SUB_OPEN
                        nsub += 1
                        if a <= near:
                            first_at_start = True
                        last_at_end = b >= total - near
            pos += length
            k = (k + 1) % npat
        if closed and first_at_start and last_at_end and nsub > first_sub and \
                oflag[nsub - 1] == SUB_OPEN:
            first = first_sub
            while oflag[first] != SUB_OPEN:
                first += 1
            if first < nsub - 1:
                # the last dash runs on into the first one: its segments move in front of
                # the first's (a rotation of the rows from the first dash on)
                r0, last0 = osub[first], osub[nsub - 1]
                n_last = no - last0
                if tmp_kind.shape[0] < no - r0:
                    tmp_kind = np.empty(no - r0, np.int64)
                    tmp_seg = np.empty((no - r0, 8))
                for i in range(no - r0):
                    src = last0 + i if i < n_last else r0 + i - n_last
                    tmp_kind[i] = okind[src]
                    tmp_seg[i] = oseg[src]
                for i in range(no - r0):
                    okind[r0 + i] = tmp_kind[i]
                    oseg[r0 + i] = tmp_seg[i]
                nsub -= 1
                for d in range(first + 1, nsub):
                    osub[d] += n_last
    osub[nsub] = no
    return okind[:no], oseg[:no], osub[:nsub + 1], oflag[:nsub]
