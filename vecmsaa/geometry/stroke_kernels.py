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
from numba import njit

from ..scene.path import CLOSE, CUBIC, LINE, MOVE

JOIN_CODES = {"miter": 0, "arcs": 0, "miter-clip": 1, "round": 2, "bevel": 3}
CAP_CODES = {"butt": 0, "round": 1, "square": 2}
_MITER, _MITER_CLIP, _ROUND, _BEVEL = 0, 1, 2, 3
_BUTT, _ROUND_CAP, _SQUARE = 0, 1, 2

SMOOTH_COS = math.cos(math.radians(0.5))   # tangents this close need no join
_MAX_DASH_STEPS = 1_000_000                # pattern intervals walked per subpath at most

_MAX_ARC_CHORDS = 4     # an arc needing more chords within the tolerance is drawn as cubics
# bounds of what one vertex's side, a cap or a dot adds (a round U-turn: a line and two
# quarter cubics or _MAX_ARC_CHORDS lines; an inner corner: three lines)
_SIDE_PTS_PER_VERTEX = 7
_SIDE_VERBS_PER_VERTEX = 1 + _MAX_ARC_CHORDS
_CAP_PTS = 6
_CAP_VERBS = _MAX_ARC_CHORDS
_DOT_PTS = 13
_DOT_VERBS = 2 + _MAX_ARC_CHORDS


@njit(cache=True, inline="always")
def _point(pts, cnt, x, y):
    pts[cnt[1], 0] = x
    pts[cnt[1], 1] = y
    cnt[1] += 1


@njit(cache=True, inline="always")
def _line(verbs, pts, cnt, x, y):
    verbs[cnt[0]] = LINE
    cnt[0] += 1
    _point(pts, cnt, x, y)


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def outer_join_items(verbs, pts, cnt, px, py, d0x, d0y, d1x, d1y, side, hw, join, miterlimit,
                     dot, tol):
    """Items along the outer side (side: +1 left, -1 right) of a turn at p, after the incoming
    side's last point (on its offset line) and before the outgoing side's next point (on the
    outgoing offset line). The offset ends a and b are left out where they are collinear with
    their neighbours (a miter's tip, a clipped miter's corners)."""
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
    if join != _BEVEL and has_tip and 1.0 / cos_half <= miterlimit:
        _line(verbs, pts, cnt, tx, ty)  # miter (and "arcs", which falls back to it)
        return
    if join == _MITER_CLIP:
        ux, uy = n0x + n1x, n0y + n1y
        ul = math.hypot(ux, uy)
        if ul > 1e-12:
            ux, uy = ux / ul, uy / ul
            lim = miterlimit * hw
            da = d0x * ux + d0y * uy
            pa = hw * (n0x * ux + n0y * uy)
            if da > 1e-12 and lim > pa:
                u = (lim - pa) / da
                _line(verbs, pts, cnt, ax + d0x * u, ay + d0y * u)
                _line(verbs, pts, cnt, bx - d1x * u, by - d1y * u)
                return
    _line(verbs, pts, cnt, ax, ay)      # bevel, and miters over the limit
    _line(verbs, pts, cnt, bx, by)


@njit(cache=True)
def _emit_side_forward(verbs, pts, cnt, sv, sp, scnt, first_point):
    """The side's verbs with their points, from point first_point on."""
    for i in range(scnt[0]):
        verbs[cnt[0]] = sv[i]
        cnt[0] += 1
    for i in range(first_point, scnt[1]):
        _point(pts, cnt, sp[i, 0], sp[i, 1])


@njit(cache=True)
def _emit_side_backward(verbs, pts, cnt, sv, sp, scnt, last_point):
    """The side traversed backwards, after its last point: reversed verbs, and the points
    reversed (a cubic's controls swap places) down to point last_point."""
    for i in range(scnt[0] - 1, -1, -1):
        verbs[cnt[0]] = sv[i]
        cnt[0] += 1
    for i in range(scnt[1] - 2, last_point - 1, -1):
        _point(pts, cnt, sp[i, 0], sp[i, 1])


@njit(cache=True)
def _stroke_polyline(verbs, pts, cnt, src, lo, hi, closed, hw, tol, join, cap, miterlimit,
                     q, dirs, lens, rv, rp, lv, lp):
    """One subpath of straight lines, src[lo:hi] (a closed one without its closing point
    repeated): one contour when open, two loops when closed, joins and caps inline.
    q, dirs, lens and the side buffers rv/rp, lv/lp are scratch space.

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
    rc = np.zeros(2, np.int64)
    lc = np.zeros(2, np.int64)
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
                             miterlimit, dot, tol)
            sign = 1.0
        else:
            outer_join_items(lv, lp, lc, px, py, d0x, d0y, d1x, d1y, 1.0, hw, join,
                             miterlimit, dot, tol)
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
        # the loops at the closing join's last point instead. Right forward, left backward.
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


@njit(cache=True)
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


@njit(cache=True)
def _grow_points(a, need):
    if need <= a.shape[0]:
        return a
    b = np.empty((max(need, 2 * a.shape[0]), 2))
    for i in range(a.shape[0]):     # (a loop: a slice assignment costs seconds of compile time)
        b[i, 0] = a[i, 0]
        b[i, 1] = a[i, 1]
    return b


@njit(cache=True)
def _grow_ints(a, need):
    if need <= a.shape[0]:
        return a
    b = np.empty(max(need, 2 * a.shape[0]), np.int64)
    for i in range(a.shape[0]):
        b[i] = a[i]
    return b


@njit(cache=True)
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
        # position within the pattern at the subpath's start; intervals are half open,
        # except that a zero-length dash right at the phase is drawn
        phase = offset - math.floor(offset / period) * period
        if phase >= period:
            phase -= period
        k = 0
        while phase > pattern[k] or (phase == pattern[k] and pattern[k] > 0):
            phase -= pattern[k]
            k = (k + 1) % npat
        pos = -phase                 # subpath arc length where the current interval starts
        seg_i, seg_start = 0, 0.0    # current segment and the arc length where it starts
        first_dash = nd              # this subpath's first dash
        first_at_start = last_at_end = False
        last_is_dot = False
        steps = 0
        while pos < total and steps < _MAX_DASH_STEPS:
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
                        ostarts = _grow_ints(ostarts, nd + 2)
                        ostarts[nd] = begin
                        nd += 1
                        last_is_dot = False
                        if a == 0.0:
                            first_at_start = True
                        last_at_end = b >= total
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
    ostarts = _grow_ints(ostarts, nd + 1)
    ostarts[nd] = no
    return out[:no], ostarts[:nd + 1], dots[:2 * ndot]


@njit(cache=True)
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
    for s in range(nsub):
        lo, hi = starts[s], starts[s + 1]
        if hi <= lo:
            continue
        _stroke_polyline(verbs, pts, cnt, src, lo, hi, closed[s], hw, tol, join, cap,
                         miterlimit, q, dirs, lens, rv, rp, lv, lp)
    for i in range(ndot):
        dot_contour(verbs, pts, cnt, dots[2 * i, 0], dots[2 * i, 1], dots[2 * i + 1, 0],
                    dots[2 * i + 1, 1], hw, cap, tol)
    return verbs[:cnt[0]], pts[:cnt[1]]


@njit(cache=True)
def stroke_lines(verbs, points, hw, tol, join, cap, miterlimit, pattern, offset):
    """Outline (verbs, points) of a path of lines only; pattern is the effective dash array
    (empty for a solid stroke)."""
    src, starts, closed = _line_subpaths(verbs, points)
    if len(pattern) == 0:
        return _stroke_polylines(src, starts, closed, np.empty((0, 2)), hw, tol, join, cap,
                                 miterlimit)
    dash_pts, dash_starts, dots = _dash_polylines(src, starts, closed, pattern, offset)
    return _stroke_polylines(dash_pts, dash_starts, np.zeros(len(dash_starts), np.bool_), dots,
                             hw, tol, join, cap, miterlimit)
