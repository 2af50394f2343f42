"""The compiled part of :mod:`vecmsaa.geometry.hairline`: hairline outlines of paths, many at
once (map data strokes thousands of paths of lines, a scatter plot thousands of circles;
numpy's per-call costs were ten times the stroke's, and four kernel calls a path from Python
more than the kernels' own work)."""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from ..scene.conics import conics_as_cubics
from ..scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD
from .stroke_kernels import SUB_DOT, SUB_OPEN, _grow, _grow_points

#: pixels a step shared by several segments of a run may hold (a step's band covers two
#: pixels, and the segments sharing a step lie within a pixel of each other across it)
JOINT_PIXELS = 16


@njit(cache=True, inline="always")
def _emit_rect(verbs, pts, cnt, u_lo, u_hi, v_lo, v_hi, ymaj):
    """Appends the rectangle [u_lo, u_hi] x [v_lo, v_hi] of the (u, v) plane (u along x, or
    along y when ymaj), wound as _emit_rows' polygons (verbs and pts have room: _rows_room)."""
    base = cnt[1]
    for j in range(4):
        u = u_lo if j == 0 or j == 3 else u_hi
        v = v_lo if j < 2 else v_hi
        if ymaj:
            pts[base + 3 - j, 0], pts[base + 3 - j, 1] = v, u
        else:
            pts[base + j, 0], pts[base + j, 1] = u, v
    verbs[cnt[0]] = MOVE
    for k in range(1, 4):
        verbs[cnt[0] + k] = LINE
    verbs[cnt[0] + 4] = CLOSE
    cnt[0] += 5
    cnt[1] += 4


@njit(cache=True, inline="always")
def _flush_joint(verbs, pts, cnt, joint, jrows, alpha):
    """Appends the pixels of the step shared by several segments of a run (joint: [column,
    rows used, y-major]; jrows: [row, product of (1 - alpha * coverage)] per pixel): one
    rectangle a pixel, as wide as the coverage whose ink blended with ``alpha`` is Skia's
    segments blended one over the other, (1 - product) / alpha."""
    col, ymaj = float(joint[0]), joint[2] == 1
    for i in range(joint[1]):
        cov = min((1.0 - jrows[i, 1]) / alpha, 1.0)
        if cov > 0.0:
            _emit_rect(verbs, pts, cnt, col, col + cov, jrows[i, 0], jrows[i, 0] + 1.0, ymaj)
    joint[1] = 0


@njit(cache=True, inline="always")
def _new_run(runs, cnt, owner):
    """Starts a run (runs: rows verb offsets, point offsets, owners; cnt[3] runs so far;
    room for it: _rows_room)."""
    nr = cnt[3]
    runs[0, nr], runs[1, nr], runs[2, nr] = cnt[0], cnt[1], owner
    cnt[3] += 1


@njit(cache=True, inline="always")
def _emit_steps(verbs, pts, cnt, c0, c1, u0, u1, v0, v1, slope, ymaj, stair):
    """Appends one polygon: with ``stair``, the steps of columns c0 .. c1 - 1 of the segment
    from u0 to u1 whose v is v0 at u0 (slope: dv/du), each one pixel thick across the axis
    centred on the segment's v at the column's centre and as long as the segment's part of
    the column; else the parallelogram one pixel thick across the axis from (u0, v0) to
    (u1, v1)."""
    n = int(c1 - c0) if stair else 1
    base = cnt[1]
    for k in range(n):
        if stair:
            col = c0 + k
            lo, hi = max(u0, col), min(u1, col + 1.0)
            v_lo = v_hi = v0 + slope * (col + 0.5 - u0)
        else:
            lo, hi, v_lo, v_hi = u0, u1, v0, v1
        # the step's top left to right (points 2k, 2k + 1), its bottom in the second half,
        # right to left; y-major polygons mirrored (reversed) to keep one orientation
        for j in range(4):
            if j == 0:
                p, u, v = 2 * k, lo, v_lo - 0.5
            elif j == 1:
                p, u, v = 2 * k + 1, hi, v_hi - 0.5
            elif j == 2:
                p, u, v = 2 * n + 2 * (n - 1 - k), hi, v_hi + 0.5
            else:
                p, u, v = 2 * n + 2 * (n - 1 - k) + 1, lo, v_lo + 0.5
            if ymaj:
                p = 4 * n - 1 - p
                pts[base + p, 0], pts[base + p, 1] = v, u
            else:
                pts[base + p, 0], pts[base + p, 1] = u, v
    verbs[cnt[0]] = MOVE
    for k in range(1, 4 * n):
        verbs[cnt[0] + k] = LINE
    verbs[cnt[0] + 4 * n] = CLOSE
    cnt[0] += 4 * n + 1
    cnt[1] += 4 * n


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _extend_ends(seg, lo, hi, outset):
    """Lengthens seg[lo]'s start and seg[hi - 1]'s end by ``outset`` along their directions
    (Skia's extend_pts); a zero-length segment along x, its start forwards, its end back."""
    for end in range(2):
        r = lo if end == 0 else hi - 1
        ddx, ddy = seg[r, 2] - seg[r, 0], seg[r, 3] - seg[r, 1]
        ln = math.sqrt(ddx * ddx + ddy * ddy)
        sign = -1.0 if end == 0 else 1.0
        if ln == 0.0:
            ux, uy = -sign, 0.0
        else:
            ux, uy = ddx / ln, ddy / ln
        k = 0 if end == 0 else 2
        seg[r, k] += sign * ux * outset
        seg[r, k + 1] += sign * uy * outset


@njit(cache=True, inline="always")
def _chord_count(kind, x0, y0, x1, y1, x2, y2, x3, y3):
    """How many chords Skia's hairline cuts a curve into: a quadratic 2^level, the level
    from the whole pixels between its control point and its chord's midpoint (4x closer a
    halving, at most 32 chords); a cubic the least 2^i whose control points lie within
    4^i / 8 px of the chord's thirds (at most 512). The curve's points as scalars (x3, y3
    unused for a quadratic)."""
    if kind == 3:
        dx = min(math.ceil(abs((x0 + x2) / 2.0 - x1)), 1 << 30)
        dy = min(math.ceil(abs((y0 + y2) / 2.0 - y1)), 1 << 30)
        if not (dx >= 0 and dy >= 0):
            return 1
        idx, idy = int(dx), int(dy)
        dist = max(idx, idy) + (min(idx, idy) >> 1)
        bits = 0
        while dist > 0:
            bits += 1
            dist >>= 1
        return 1 << min(5, (bits + 1) >> 1)
    diff = 0.0
    for j in range(2):
        p0, p1, p2, p3 = (x0, x1, x2, x3) if j == 0 else (y0, y1, y2, y3)
        p13 = p3 / 3.0 + p0 * (2.0 / 3.0)
        p23 = p0 / 3.0 + p3 * (2.0 / 3.0)
        diff = max(diff, abs(p1 - p13), abs(p2 - p23))
    tol = 1.0 / 8.0
    for i in range(9):
        if diff < tol:
            return 1 << i
        tol *= 4.0
    return 1 << 9


@njit(cache=True, inline="always")
def _cubic_xy(x0, y0, x1, y1, x2, y2, x3, y3, t):
    """Point at t of the cubic (x0, y0) ... (x3, y3) (stroke_kernels._cubic_at on scalars,
    the same arithmetic)."""
    u = 1.0 - t
    a, b, cc, d = u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t
    return a * x0 + b * x1 + cc * x2 + d * x3, a * y0 + b * y1 + cc * y2 + d * y3


@njit(cache=True, inline="always")
def _chord_end(kind, i, n, x0, y0, x1, y1, x2, y2, x3, y3):
    """The end of chord i (1 .. n) of the n at even steps of t of a quadratic (kind 3: (x0,
    y0) .. (x2, y2)) or a cubic (kind 4); the last one ends on the curve's end exactly."""
    if i == n:
        return (x2, y2) if kind == 3 else (x3, y3)
    t = i / n
    mt = 1.0 - t
    if kind == 3:
        return (mt * mt * x0 + 2 * mt * t * x1 + t * t * x2,
                mt * mt * y0 + 2 * mt * t * y1 + t * t * y2)
    return _cubic_xy(x0, y0, x1, y1, x2, y2, x3, y3, t)


@njit(cache=True)
def hairline_chords(kinds, user, subs, flags, m, outset):
    """The line segments (rows (N, 4), subpath starts) of Skia's hairline of path_segments'
    arrays (``user``: conics already cubics, stroke.arc_cubics) taken to device coordinates
    by ``m`` (a, b, c, d, e, f): curves cut into _chord_count chords at even steps of t, the
    ends of open subpaths lengthened by ``outset``, a dot (SUB_DOT) a segment of 2 · outset
    along x (none for butt caps)."""
    # (the transform here, not in numpy: ten array calls on a circle's four rows cost more
    # than the rest of its hairline)
    segs = np.empty_like(user)
    a, b, c, d, e, f = m[0], m[1], m[2], m[3], m[4], m[5]
    for i in range(user.shape[0]):
        for j in range(0, user.shape[1], 2):
            x, y = user[i, j], user[i, j + 1]
            segs[i, j] = a * x + c * y + e
            segs[i, j + 1] = b * x + d * y + f
    # the rows' count first (one array of the right size, no segment's row views: each cost
    # the runtime's reference counts)
    total = 0
    for k in range(len(flags)):
        if flags[k] == SUB_DOT:
            total += 1
            continue
        for si in range(subs[k], subs[k + 1]):
            kind = kinds[si]
            if kind == 3 or kind == 4:
                total += _chord_count(kind, segs[si, 0], segs[si, 1], segs[si, 2], segs[si, 3],
                                      segs[si, 4], segs[si, 5], segs[si, 6], segs[si, 7])
            else:
                total += 1
    rows = np.empty((total, 4))
    rsubs = np.empty(len(flags) + 1, np.int64)
    nr = nsub = 0
    for k in range(len(flags)):
        lo, hi = subs[k], subs[k + 1]
        start = nr
        if flags[k] == SUB_DOT:
            if outset > 0.0:
                x, y = segs[lo, 0], segs[lo, 1]
                rows[nr, 0], rows[nr, 1], rows[nr, 2], rows[nr, 3] = x + outset, y, x - outset, y
                nr += 1
        else:
            for si in range(lo, hi):
                kind = kinds[si]
                x0, y0, x1, y1 = segs[si, 0], segs[si, 1], segs[si, 2], segs[si, 3]
                x2, y2, x3, y3 = segs[si, 4], segs[si, 5], segs[si, 6], segs[si, 7]
                if kind == 3 or kind == 4:
                    n = _chord_count(kind, x0, y0, x1, y1, x2, y2, x3, y3)
                    px, py = x0, y0
                    for i in range(1, n + 1):
                        qx, qy = _chord_end(kind, i, n, x0, y0, x1, y1, x2, y2, x3, y3)
                        rows[nr, 0], rows[nr, 1], rows[nr, 2], rows[nr, 3] = px, py, qx, qy
                        nr += 1
                        px, py = qx, qy
                else:           # a line (a conic here would be its chord)
                    rows[nr, 0], rows[nr, 1] = x0, y0
                    rows[nr, 2], rows[nr, 3] = (x1, y1) if kind == 2 else (x3, y3)
                    nr += 1
            if outset > 0.0 and flags[k] == SUB_OPEN and nr > start:
                _extend_ends(rows, start, nr, outset)
        if nr > start:
            rsubs[nsub] = start
            nsub += 1
    rsubs[nsub] = nr
    return rows[:nr].copy() if nr < total else rows, rsubs[:nsub + 1].copy()


@njit(cache=True, inline="always")
def _run_key(seg, r):
    """The run of segment r: its major axis and direction along it (0-3), -1 if a point."""
    dx, dy = seg[r, 2] - seg[r, 0], seg[r, 3] - seg[r, 1]
    if dx == 0.0 and dy == 0.0:
        return -1
    ymaj = abs(dx) <= abs(dy)
    return (2 if ymaj else 0) + (1 if (dy if ymaj else dx) > 0 else 0)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _rows_room(seg, ns, max_steps, run_rows, counted):
    """(polygon pieces, runs) the segments seg[:ns] of a subpath can make at most (_emit_rows):
    a segment of n steps along its major axis drawn as a staircase takes n pieces of 4 points
    and 5 verbs (a polygon of k steps: 4k points, 4k + 1 verbs), else one parallelogram, and
    4 more for the pixels of the joints at its ends (the joint takes at most two pixels an
    end, _flush_joint a rectangle a pixel); it starts at most a run for its direction and
    n // run_rows + 2 for the pieces of its staircase (a run for its direction even when it
    draws nothing: not finite). Staircases are of at most max_steps[0] steps, and the
    path's, ``counted`` steps so far, of max_steps[1] in all: the room for their steps is
    bounded by what is left of that (a hairline of a circle 10^9 px across took one piece
    for each of max_steps[0] steps of each of its thousands of chords: gigabytes reserved)."""
    quads = 0
    nruns = ns
    stair_steps = 0
    rr = max(run_rows, 1)
    for r in range(ns):
        x0, y0, x1, y1 = seg[r, 0], seg[r, 1], seg[r, 2], seg[r, 3]
        dx, dy = x1 - x0, y1 - y0
        if (dx == 0.0 and dy == 0.0) or not (math.isfinite(x0) and math.isfinite(y0)
                                             and math.isfinite(x1) and math.isfinite(y1)):
            continue
        lo, hi = (min(y0, y1), max(y0, y1)) if abs(dx) <= abs(dy) else \
            (min(x0, x1), max(x0, x1))
        # (past 2^63 the steps' count, as _emit_rows computes it, is the float-to-int
        # conversion's overflow value, and the segment one parallelogram)
        n = math.ceil(hi) - math.floor(lo)
        quads += 5
        nruns += 2
        if n <= max_steps[0]:
            stair_steps += max(0, int(n))
    stair_steps = min(stair_steps, max(0, max_steps[1] - counted))
    return quads + stair_steps, nruns + stair_steps // rr


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _grow_runs(runs, need):
    """runs (rows: verb offsets, point offsets, owners) with room for ``need`` runs."""
    if need <= runs.shape[1]:
        return runs
    b = np.empty((3, max(need, 2 * runs.shape[1])), np.int64)
    for j in range(3):
        for i in range(runs.shape[1]):
            b[j, i] = runs[j, i]
    return b


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _emit_rows(ov, op, cnt, seg, ns, runs, owner, stair_slope, max_steps, joint, jrows,
               alpha, run_rows):
    """Appends the polygons of the segments seg[:ns] of one subpath, starting a run (runs:
    [verb offsets, point offsets, owners], cnt[3] runs so far) at the subpath's start and
    wherever the major axis or the direction along it changes: within a run the segments'
    steps overlap only where one ends and the next begins within a step, and there the
    shared step's pixels are Skia's segment-by-segment blending (_flush_joint); where runs
    overlap (turns, crossings) the runs are drawn one over the other. Returns (ov, op, runs),
    grown once for the subpath (_rows_room: the helpers write without checks); cnt: [verbs
    used, points used, steps counted, runs]."""
    quads, nruns = _rows_room(seg, ns, max_steps, run_rows, cnt[2])
    ov = _grow(ov, cnt[0] + 5 * quads)
    op = _grow_points(op, cnt[1] + 4 * quads)
    runs = _grow_runs(runs, cnt[3] + nruns + 1)
    key = -1
    shared0 = False
    r = 0
    while r < ns:
        k = _run_key(seg, r)
        if k < 0:
            r += 1
            continue
        if k != key:
            if joint[1] > 0:
                _flush_joint(ov, op, cnt, joint, jrows, alpha)
            key = k
            shared0 = False
            _new_run(runs, cnt, owner)
        nxt = r + 1
        while nxt < ns and _run_key(seg, nxt) < 0:
            nxt += 1
        # the next segment of the run starts within the step this one ends in
        u_end = seg[r, 3] if k >= 2 else seg[r, 2]
        shared1 = nxt < ns and _run_key(seg, nxt) == k and u_end != math.floor(u_end)
        sh0, sh1 = shared0, shared1
        shared0 = shared1
        x0, y0, x1, y1 = seg[r, 0], seg[r, 1], seg[r, 2], seg[r, 3]
        r = nxt
        # the segment's polygon: per step of the major axis u a rectangle one pixel thick
        # across it, centred on the segment's v at the step's centre, as long as the
        # segment's part of the step; one parallelogram for a segment of |slope| below
        # ``stair_slope``, or of more steps than max_steps[0] (cnt[2] counts the path's steps
        # against max_steps[1]). The step at the start (sh0) or the end (sh1) that another
        # segment of the run shares goes to the pending joint instead.
        # (Written out here, its helpers inlined: a call passing a dozen arrays a segment
        # cost more in the runtime's reference counts than the segment's polygon.)
        dx, dy = x1 - x0, y1 - y0
        if (dx == 0.0 and dy == 0.0) or not (math.isfinite(x0) and math.isfinite(y0)
                                             and math.isfinite(x1) and math.isfinite(y1)):
            continue
        ymaj = abs(dx) <= abs(dy)
        if ymaj:
            u0, v0, u1, v1 = y0, x0, y1, x1
        else:
            u0, v0, u1, v1 = x0, y0, x1, y1
        back = u0 > u1
        if back:
            u0, u1, v0, v1 = u1, u0, v1, v0
            sh0, sh1 = sh1, sh0
        slope = (v1 - v0) / (u1 - u0)
        first = math.floor(u0)
        steps = math.ceil(u1) - first
        total = int(steps)
        stair = abs(slope) >= stair_slope and steps <= max_steps[0]
        # the steps shared with the run's previous and next segments, in the path's order
        # (the pending joint is the previous segment's), to the joint; the others kept:
        # kept0 to kept1 - 1
        kept0, kept1 = 0, total
        if sh0 or sh1:
            for i in range(2):
                end = 1 - i if back else i
                if (sh0 if end == 0 else sh1) and kept1 > kept0:
                    col = first if end == 0 else first + steps - 1.0
                    lo, hi = max(u0, col), min(u1, col + 1.0)
                    # the segment's part f of the step, its band centred on vc, to the
                    # pending shared step (flushed first if it is another column's), unless
                    # jrows has no room for two more pixels
                    if joint[1] > 0 and joint[0] != col:
                        _flush_joint(ov, op, cnt, joint, jrows, alpha)
                    ok = joint[1] + 2 <= jrows.shape[0]
                    if ok:
                        f, vc = hi - lo, v0 + slope * (col + 0.5 - u0)
                        joint[0], joint[2] = int(col), 1 if ymaj else 0
                        r0 = math.floor(vc - 0.5)
                        share = (r0 + 1.0) - (vc - 0.5)     # of row r0; the rest row r0 + 1
                        for j in range(2):
                            row, a = (r0, share) if j == 0 else (r0 + 1.0, 1.0 - share)
                            if a <= 0.0:
                                continue
                            q = 0
                            while q < joint[1] and jrows[q, 0] != row:
                                q += 1
                            if q == joint[1]:
                                jrows[q, 0], jrows[q, 1] = row, 1.0
                                joint[1] += 1
                            jrows[q, 1] *= 1.0 - alpha * f * a
                    if ok and end == 0:
                        kept0 += 1
                    elif ok:
                        kept1 -= 1
            if kept1 <= kept0:
                continue
        first_kept, steps = first + kept0, kept1 - kept0
        ua = u0 if kept0 == 0 else first_kept
        ub = u1 if kept1 == total else first + kept1
        if stair:
            cnt[2] += int(steps)
            stair = cnt[2] <= max_steps[1]
        if not stair:
            v_lo = v0 if ua == u0 else v0 + slope * (ua - u0)
            v_hi = v1 if ub == u1 else v0 + slope * (ub - u0)
            _emit_steps(ov, op, cnt, 0, 1, ua, ub, v_lo, v_hi, 0.0, ymaj, False)
            continue
        # a run is cut into pieces of at most `chunk` steps (of about run_rows rows across,
        # see hairline.RUN_ROWS), each a run of its own
        chunk = max(1, run_rows if ymaj else int(run_rows / max(abs(slope), 0.25)))
        n = int(steps)
        k0 = 0
        while k0 < n:
            room = chunk - (cnt[1] - runs[1, cnt[3] - 1]) // 4
            if room <= 0:
                _new_run(runs, cnt, owner)
                room = chunk
            k1 = min(n, k0 + room)
            _emit_steps(ov, op, cnt, first_kept + k0, first_kept + k1, u0, u1, v0, 0.0,
                        slope, ymaj, True)
            k0 = k1
    if joint[1] > 0:
        _flush_joint(ov, op, cnt, joint, jrows, alpha)
    return ov, op, runs


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _runs_out(ov, op, cnt, runs):
    nr = cnt[3]
    runs[0, nr], runs[1, nr] = cnt[0], cnt[1]
    return (ov[:cnt[0]], op[:cnt[1]], runs[0, :nr + 1].copy(), runs[1, :nr + 1].copy(),
            runs[2, :nr].copy())


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _path_outline(ov, op, cnt, seg, verbs, points, v_lo, v_hi, ip, m, outset, runs, w,
                  stair_slope, max_steps, joint, jrows, alpha, run_rows):
    """Appends the hairline outline (runs owned by ``w``) of the path verbs[v_lo:v_hi] (moves,
    lines, quadratics, cubics, closes: no conics), its points from points[ip] on, under the
    transform m (see hairline_paths_batch): what hairline_chords makes of path_segments'
    subpaths (the same chords, in the same order, with the same arithmetic), each
    subpath's chords drawn as they are made (_emit_rows). Returns (ov, op, seg, runs), grown
    as needed (seg: scratch rows of a subpath's chords)."""
    a, b, c, d, e, f = m[0], m[1], m[2], m[3], m[4], m[5]
    seg = _grow_points(seg, v_hi - v_lo)
    ns = 0
    have_start = False
    sx = sy = cx = cy = 0.0
    for iv in range(v_lo, v_hi + 1):
        # a subpath ends at a move, a close or the path's end: its segments are drawn
        v = verbs[iv] if iv < v_hi else MOVE
        if v == MOVE or v == CLOSE:
            if v == CLOSE and have_start:
                seg[ns, 0], seg[ns, 1], seg[ns, 2], seg[ns, 3] = cx, cy, sx, sy
                ns += 1
                cx, cy = sx, sy
            elif v == MOVE and ns > 0 and outset > 0.0:
                _extend_ends(seg, 0, ns, outset)    # open: the caps lengthen both ends
            ov, op, runs = _emit_rows(ov, op, cnt, seg, ns, runs, w, stair_slope, max_steps,
                                      joint, jrows, alpha, run_rows)
            ns = 0
            if v == MOVE and iv < v_hi:
                x, y = points[ip, 0], points[ip, 1]
                sx = cx = a * x + c * y + e
                sy = cy = b * x + d * y + f
                ip += 1
                have_start = True
        elif v == LINE:
            x, y = points[ip, 0], points[ip, 1]
            nx, ny = a * x + c * y + e, b * x + d * y + f
            ip += 1
            seg[ns, 0], seg[ns, 1], seg[ns, 2], seg[ns, 3] = cx, cy, nx, ny
            ns += 1
            cx, cy = nx, ny
        else:                           # a curve cut into chords (hairline_chords)
            kind = 3 if v == QUAD else 4
            x1, y1 = points[ip, 0], points[ip, 1]
            x2, y2 = points[ip + 1, 0], points[ip + 1, 1]
            x3 = y3 = 0.0
            if v == CUBIC:
                x3, y3 = points[ip + 2, 0], points[ip + 2, 1]
                x3, y3 = a * x3 + c * y3 + e, b * x3 + d * y3 + f
            x1, y1 = a * x1 + c * y1 + e, b * x1 + d * y1 + f
            x2, y2 = a * x2 + c * y2 + e, b * x2 + d * y2 + f
            ip += kind - 1
            n = _chord_count(kind, cx, cy, x1, y1, x2, y2, x3, y3)
            # (room for the rest of the path's verbs too: a row each)
            seg = _grow_points(seg, ns + n + v_hi - iv)
            px, py = cx, cy
            for i in range(1, n + 1):
                qx, qy = _chord_end(kind, i, n, cx, cy, x1, y1, x2, y2, x3, y3)
                seg[ns, 0], seg[ns, 1], seg[ns, 2], seg[ns, 3] = px, py, qx, qy
                ns += 1
                px, py = qx, qy
            cx, cy = px, py
    return ov, op, seg, runs


@njit(cache=True)
def hairline_paths_batch(verbs, points, vstart, pstart, which, m, outset, alpha, stair_slope,
                         max_steps, run_rows, arc_tolerance, max_arc):
    """Hairline outlines (hairline.hairline_outline of hairline.hairline_segments) of the
    paths ``which`` of a batch of paths (path i: verbs vstart[i]:vstart[i + 1], points
    pstart[i]:pstart[i + 1]) under the transform m (a, b, c, d, e, f), round and square caps
    lengthening open subpaths' ends by ``outset``. Returns (verbs, points, run verb offsets,
    run point offsets, the index in ``which`` of each run's path): each path's outline is
    its runs (_emit_rows), in order. A path is read here (_path_outline: what the kernels
    hairline_segments calls make of it, stroke_kernels.path_segments and hairline_chords,
    without their arrays), its conics first made the cubics usvg makes of arcs
    (conics_as_cubics at ``arc_tolerance``, at most ``max_arc`` cubics an arc:
    stroke.arc_cubics); a path's steps are counted against max_steps[1] together.
    (The parameters that are the module hairline's constants come last: jit.bind_tail.)"""
    ov = np.empty(64, np.uint8)
    op = np.empty((64, 2))
    runs = np.empty((3, 16), np.int64)
    cnt = np.zeros(4, np.int64)
    seg = np.empty((16, 4))
    joint, jrows = np.zeros(3, np.int64), np.empty((JOINT_PIXELS, 2))
    keep = np.zeros(0, np.bool_)
    for w in range(len(which)):
        ov, op, seg, runs = _batch_path(ov, op, cnt, seg, runs, verbs, points, vstart, pstart,
                                        which[w], w, m, outset, alpha, stair_slope, max_steps,
                                        run_rows, arc_tolerance, max_arc, joint, jrows, keep)
    return _runs_out(ov, op, cnt, runs)


@njit(cache=True)
def hairline_paths_each(verbs, points, vstart, pstart, which, ms, outsets, alphas,
                        stair_slope, max_steps, run_rows, arc_tolerance, max_arc):
    """hairline_paths_batch with a transform, cap outset and alpha of each path drawn: path
    which[w] under ms[w] ((W, 6): a, b, c, d, e, f), its open subpaths' ends lengthened by
    outsets[w], blended with alphas[w] (the runs of a stretch of <use> instances, each with
    a transform of its own, in one call; each path's outline the same floats as
    hairline_paths_batch's of it alone under its transform)."""
    ov = np.empty(64, np.uint8)
    op = np.empty((64, 2))
    runs = np.empty((3, 16), np.int64)
    cnt = np.zeros(4, np.int64)
    seg = np.empty((16, 4))
    joint, jrows = np.zeros(3, np.int64), np.empty((JOINT_PIXELS, 2))
    keep = np.zeros(0, np.bool_)
    for w in range(len(which)):
        ov, op, seg, runs = _batch_path(ov, op, cnt, seg, runs, verbs, points, vstart, pstart,
                                        which[w], w, ms[w], outsets[w], alphas[w],
                                        stair_slope, max_steps, run_rows, arc_tolerance,
                                        max_arc, joint, jrows, keep)
    return _runs_out(ov, op, cnt, runs)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _batch_path(ov, op, cnt, seg, runs, verbs, points, vstart, pstart, i, w, m, outset, alpha,
                stair_slope, max_steps, run_rows, arc_tolerance, max_arc, joint, jrows, keep):
    """Appends the hairline outline of path i of a batch (runs owned by ``w``) under the
    transform m: hairline_paths_batch's (and hairline_paths_each's) work for one path, its
    steps counted from 0. Returns (ov, op, seg, runs), grown as needed."""
    cnt[2] = 0
    v_lo, v_hi = vstart[i], vstart[i + 1]
    conic = False
    for iv in range(v_lo, v_hi):
        if verbs[iv] == CONIC:
            conic = True
    if not conic:
        return _path_outline(ov, op, cnt, seg, verbs, points, v_lo, v_hi, pstart[i], m,
                             outset, runs, w, stair_slope, max_steps, joint, jrows, alpha,
                             run_rows)
    pv, pp = conics_as_cubics(verbs[v_lo:v_hi], points[pstart[i]:pstart[i + 1]], keep,
                              arc_tolerance, max_arc)
    return _path_outline(ov, op, cnt, seg, pv, pp, 0, len(pv), 0, m, outset, runs, w,
                         stair_slope, max_steps, joint, jrows, alpha, run_rows)


@njit(cache=True)
def hairline_rows(rows, subs, stair_slope, max_steps, alpha, run_rows):
    """The hairline outline (verbs, points, run verb offsets, run point offsets) of the
    device segments ``rows`` (N, 4), subpath k being rows subs[k]:subs[k + 1]."""
    verbs = np.empty(64, np.uint8)
    pts = np.empty((64, 2))
    runs = np.empty((3, 16), np.int64)
    cnt = np.zeros(4, np.int64)
    joint, jrows = np.zeros(3, np.int64), np.empty((JOINT_PIXELS, 2))
    for k in range(len(subs) - 1):
        verbs, pts, runs = _emit_rows(verbs, pts, cnt, rows[subs[k]:subs[k + 1]],
                                      subs[k + 1] - subs[k], runs, 0, stair_slope, max_steps,
                                      joint, jrows, alpha, run_rows)
    out = _runs_out(verbs, pts, cnt, runs)
    return out[0], out[1], out[2], out[3]
