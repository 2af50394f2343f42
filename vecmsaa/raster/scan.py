"""Scan conversion: per-sample winding numbers, curve coverage by mode, MSAA compositing.

One kernel call renders a whole batch of fills into a float32 premultiplied target, strip by
strip (bounded memory). Per fill and strip:

1. Straight edges (including curve chords) add ±1 at the first pixel right of their crossing
   with each *sample row* (every pattern sample has its own y inside the pixel). A pixel box that
   no edge touches has the same winding at all its samples, so it is *clean*; touched pixels are
   *dirty* and listed per row.
2. Curve primitives add their lens contribution to the samples of the pixels they touch, with
   the coverage mode deciding which samples: the implicit function at every sample
   (``persample`` and ``approx``), a fractional alpha
   (``alpha``) or an alpha-to-coverage mask (``a2c``).
3. A sweep over the dirty pixels of each row turns windings into coverage (fill rule) and
   composites the paint — evaluated once per pixel — into the covered samples. Runs of clean
   pixels between dirty ones are spans with one coverage: no per-sample work.

The framebuffer is compressed like MSAA hardware: a pixel holds one colour until a partial
coverage splits it into per-sample colours, and an opaque full cover merges it back.
"""
from __future__ import annotations

import math

import numpy as np
from ..jit import njit

from ..geometry.primitives import (KIND_QUAD, P_BBOX, P_CHORD, P_CTRL, P_INVS, P_K, P_KIND, P_L,
                                   P_M, P_NCTRL, P_OX, P_OY, P_RIGHT, P_SIGMA, P_T1, P_T2,
                                   P_WSIGN, _eval_implicit)
from .shaders import shade_span

# The per-fill kernels use numpy's error model: a float division by zero gives inf or NaN
# (which the scan arithmetic treats as off the image) instead of raising. With no raise
# paths numba's reference-count pruning removes the atomic incref/decref of every array
# argument on every call (once per fill and strip: 5% of a city map's render).

MODE_NONE, MODE_ALPHA, MODE_A2C, MODE_PERSAMPLE, MODE_APPROX = 0, 1, 2, 3, 4
MODE_IDS = {"none": MODE_NONE, "alpha": MODE_ALPHA, "a2c": MODE_A2C,
            "persample": MODE_PERSAMPLE, "approx": MODE_APPROX}
RULE_NONZERO, RULE_EVENODD = 0, 1
#: the dirty flag of a pixel a lens touched (its samples may hold lens windings in ``local``);
#: an edge alone sets 1. The sweeps read and clear ``local`` only where this is set: elsewhere
#: it is all zero, and the read was half of a dirty pixel's memory traffic
DIRTY_LENS = 2
BIG = 1 << 40
#: run numbers stamp int32 (2·run + 1): past this the stamps are cleared and numbering restarts
RUN_LIMIT = (1 << 30) - 1


@njit(cache=True, inline="always")
def coverage_of(w, rule):
    """Fill rule on a (possibly fractional, alpha-mode) winding number."""
    a = abs(w)
    if rule == RULE_NONZERO:
        return a if a < 1.0 else 1.0
    a = a % 2.0
    return a if a <= 1.0 else 2.0 - a


@njit(cache=True, inline="always")
def crossing_x(xt, yt, dxdy, ys):
    """x where an edge (top point, slope dx/dy) crosses the scanline y = ys. The chord test of
    a curve primitive uses this same arithmetic, so both always agree on a sample's side."""
    return xt + (ys - yt) * dxdy


@njit(cache=True, inline="always")
def _floor_int(v):
    """floor(v) as an int, clamped to ±BIG first (0 for NaN): converting a float beyond the
    int64 range is undefined (a coordinate of 1e307 once became a row past the strip)."""
    if not (v == v):
        return 0
    # clamp before floor: numba's math.floor already returns an int64
    return math.floor(max(min(v, float(BIG)), -float(BIG)))


@njit(cache=True, inline="always")
def _ceil_int(v):
    """ceil(v) as an int, clamped to ±BIG first (0 for NaN), as _floor_int. A bound beyond
    the int64 range came out as -2**63 (x86's answer for a conversion it cannot make): a lens
    whose end tangent was off horizontal by 2e-20 put the tangent's crossing of a row 1e19 px
    to the right, and that bound became the far left, dropping the lens's samples."""
    if not (v == v):
        return 0
    return math.ceil(max(min(v, float(BIG)), -float(BIG)))


@njit(cache=True, inline="always")
def _pixel_index(v, W):
    """floor(v) clamped to the columns 0..W-1, and 0 for NaN (compiled min/max pass NaN
    through, and int(NaN) is undefined: an index far outside the row)."""
    if v >= W - 1.0:
        return W - 1
    if v >= 0.0:
        return int(math.floor(v))
    return 0


@njit(cache=True, inline="always")
def _band_x_range(prim, y_lo, y_hi):
    """x extent of the primitive's control polygon inside the band y_lo ≤ y ≤ y_hi."""
    n = int(prim[P_NCTRL])
    xmin, xmax = np.inf, -np.inf
    for i in range(n):
        j = i + 1 if i + 1 < n else 0     # not (i + 1) % n: an integer division per edge
        ax, ay = prim[P_CTRL + 2 * i], prim[P_CTRL + 2 * i + 1]
        bx, by = prim[P_CTRL + 2 * j], prim[P_CTRL + 2 * j + 1]
        if ay > by:
            ax, ay, bx, by = bx, by, ax, ay
        if by < y_lo or ay > y_hi:
            continue
        if by == ay:
            xmin = min(xmin, ax, bx)
            xmax = max(xmax, ax, bx)
            continue
        t0 = max(0.0, (y_lo - ay) / (by - ay))
        t1 = min(1.0, (y_hi - ay) / (by - ay))
        xa = ax + (bx - ax) * t0
        xb = ax + (bx - ax) * t1
        xmin = min(xmin, xa, xb)
        xmax = max(xmax, xa, xb)
    return xmin, xmax


@njit(cache=True, inline="always")
def saturated(sa, da):
    """The share of a source of alpha ``sa`` that the saturating (anti-correlated) blend adds
    over a destination of alpha ``da``: i = min(A_f, 1 - A_fb), as a factor of the source
    (seed 002). Abutting fills drawn front to back then fill a pixel exactly once."""
    if sa <= 0.0:
        return 0.0
    return max(0.0, min(1.0, (1.0 - da) / sa))


@njit(cache=True, inline="always")
def _blend_span(fb, cplx, pool, r, q0, q1, py, kind, f, lut, tex, c, sat, span, s0, s1):
    """Source-over of the paint × coverage c onto every sample of pixels q0..q1-1 of a row
    (``sat``: the saturating blend, fills drawn front to back, instead). A paint that is not
    solid is read from ``span``, which holds the row's pixels s0..s1-1 shaded (sweep_rows),
    or is shaded into it for the span when the span lies outside them."""
    cr, cg, cb, ca = f[0], f[1], f[2], f[3]
    sr, sg, sb, sa = cr * c, cg * c, cb * c, ca * c
    k = 1.0 - sa
    if kind == 0 and sa >= 1.0 and not sat:
        # opaque solid span: every sample becomes the colour (the common case of big areas)
        for px in range(q0, q1):
            cplx[r, px] = -1
            fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = sr, sg, sb, sa
        return
    if kind != 0 and not (s0 <= q0 and q1 <= s1):
        shade_span(kind, f, lut, tex, q0, q1, py + 0.5, span)
        s0 = q0
    for px in range(q0, q1):
        if kind != 0:
            j = px - s0
            cr, cg, cb, ca = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
            sr, sg, sb, sa = cr * c, cg * c, cb * c, ca * c
            k = 1.0 - sa
        slot = cplx[r, px]
        if slot < 0:
            if sat:
                t = saturated(sa, fb[r, px, 3])
                fb[r, px, 0] += sr * t
                fb[r, px, 1] += sg * t
                fb[r, px, 2] += sb * t
                fb[r, px, 3] += sa * t
                continue
            fb[r, px, 0] = sr + fb[r, px, 0] * k
            fb[r, px, 1] = sg + fb[r, px, 1] * k
            fb[r, px, 2] = sb + fb[r, px, 2] * k
            fb[r, px, 3] = sa + fb[r, px, 3] * k
        elif sa >= 1.0 and not sat:
            # opaque full cover: the pixel is one colour again
            cplx[r, px] = -1
            fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = sr, sg, sb, sa
        else:
            for s in range(pool.shape[1]):
                if sat:
                    t = saturated(sa, pool[slot, s, 3])
                    pool[slot, s, 0] += sr * t
                    pool[slot, s, 1] += sg * t
                    pool[slot, s, 2] += sb * t
                    pool[slot, s, 3] += sa * t
                    continue
                pool[slot, s, 0] = sr + pool[slot, s, 0] * k
                pool[slot, s, 1] = sg + pool[slot, s, 1] * k
                pool[slot, s, 2] = sb + pool[slot, s, 2] * k
                pool[slot, s, 3] = sa + pool[slot, s, 3] * k


#: consecutive edges (of the batch's array) that share one y extent in band_chunks
EDGE_CHUNK = 16
#: edges a batch has at least for render_msaa to work out its band_chunks: below it, reading
#: the few edges of a fill that miss a strip costs less than the pass (a one-fill batch of a
#: rectangle is drawn once per band)
CHUNKED_EDGES = 256


@njit(cache=True, error_model="numpy")
def band_chunks(edges, edge_off, path_box, y0, H, strip_rows):
    """(C, 2) lowest and highest y of each EDGE_CHUNK consecutive edges of the batch (-inf,
    inf where one is NaN), for render_msaa's band of H rows from y0: scan_edges skips a chunk
    that lies wholly above or below the strip. A fill's edges follow its outline, so a strip
    of 16 rows meets few of its chunks, where it read every edge of every fill whose box meets
    it (a city map's large polygons: each of their 128 strips at 2048 px). Only the chunks of
    the fills whose box meets the band are worked out (the rest stay -inf, inf: never
    skipped, never read): one pass over the band's edges, not the batch's, per band. A chunk
    may hold the ends of two fills: its extent covers both, which only makes it skipped less
    often. None (empty) where the band is one strip or the batch has under CHUNKED_EDGES
    edges."""
    E = edges.shape[0]
    if E < CHUNKED_EDGES or H <= strip_rows:
        return np.empty((0, 2))
    out = np.empty(((E + EDGE_CHUNK - 1) // EDGE_CHUNK, 2))
    out[:, 0] = -np.inf
    out[:, 1] = np.inf
    done = -1
    for k in range(edge_off.shape[0] - 1):
        if path_box[k, 3] < y0 or path_box[k, 1] >= y0 + H:
            continue
        for ch in range(max(done + 1, edge_off[k] // EDGE_CHUNK),
                        (edge_off[k + 1] + EDGE_CHUNK - 1) // EDGE_CHUNK):
            lo, hi = np.inf, -np.inf
            nan = False
            for e in range(ch * EDGE_CHUNK, min(E, (ch + 1) * EDGE_CHUNK)):
                ya, yb = edges[e, 1], edges[e, 3]
                nan |= not (ya == ya and yb == yb)
                lo = min(lo, ya, yb)
                hi = max(hi, ya, yb)
            if not nan:
                out[ch, 0], out[ch, 1] = lo, hi
            done = ch
    return out


@njit(cache=True, error_model="numpy")
def strip_buckets(path_box, y0, H, W, strip_rows, left):
    """The fills of a batch by the strips of the band (device rows y0 .. y0 + H - 1, strips of
    ``strip_rows``) their boxes meet, for the kernels' strip loops, which tested every fill's
    box on every strip (a third of render_msaa's own time at 120,000 small fills): (start,
    order, last), the fills whose first strip is s being order[start[s]:start[s + 1]], in
    batch order (a counting sort), and last[k] the last strip fill k meets (-1: none).
    strip_fills turns them into each strip's list. A fill meets strip s exactly where the
    kernels' test draws it there: not box y1 < s's first row, not box y0 >= its end (a NaN
    meets every strip), and not box x0 >= W (nor, with ``left``, box x1 < 0). Since the rows
    are integers, box y0 < end exactly where floor(y0) < end, and so on: each fill's strips
    are one range, worked out from its floored box."""
    S = max(0, (H + strip_rows - 1) // strip_rows)
    P = path_box.shape[0] if S > 0 else 0       # (no rows: no fill meets one)
    last = np.full(path_box.shape[0], -1, np.int32)
    first = np.empty(P, np.int32)
    start = np.zeros(S + 1, np.int64)
    for k in range(P):
        if path_box[k, 0] >= W or (left and path_box[k, 2] < 0.0):
            continue
        fy0 = np.floor(path_box[k, 1])
        fy1 = np.floor(path_box[k, 3])
        # (NaN compares false: the first strip, or the last)
        if fy1 < y0 or fy0 >= y0 + H:
            continue
        a = int(fy0 - y0) // strip_rows if fy0 >= y0 else 0
        b = int(fy1 - y0) // strip_rows if fy1 < y0 + H else S - 1
        if a > b:
            continue
        first[k], last[k] = a, b
        start[a + 1] += 1
    for s in range(S):
        start[s + 1] += start[s]
    order = np.empty(start[S], np.int32)
    put = start[:S].copy()
    for k in range(P):
        if last[k] >= 0:
            order[put[first[k]]] = k
            put[first[k]] += 1
    return start, order, last


@njit(cache=True, error_model="numpy")
def strip_fills(prev, nprev, order, a, b, last, s, out):
    """The fills meeting strip s, in batch order, into ``out``; returns their count. ``prev``
    [:nprev]: those of strip s - 1 (those of them that reach strip s stay), merged with the
    fills that start at s (order[a:b], strip_buckets'); both are in batch order."""
    i, j, n = 0, a, 0
    while i < nprev or j < b:
        if j >= b or (i < nprev and prev[i] < order[j]):
            k = prev[i]
            i += 1
            if last[k] < s:
                continue
        else:
            k = order[j]
            j += 1
        out[n] = k
        n += 1
    return n


@njit(cache=True, error_model="numpy")
def scan_edges(edges, chunk_y, e0, e1, sy0, rows, W, sx, sy, delta, dirty, dlist, dcount,
               hidden, col):
    """Winding deltas of the straight edges e0..e1 (one fill) on the sample rows of strip
    [sy0, sy0 + rows), except the rows where ``hidden`` is set (nothing of the fill shows).
    Written out in one loop nest: an array handed to a helper costs a reference count per
    call, here per edge and per marked pixel. ``col``: n int64, where each sample's crossing
    of a row lands. ``chunk_y``: band_chunks of ``edges``, or empty (no chunk skipped)."""
    n = sx.shape[0]
    chunked = chunk_y.shape[0] > 0
    ch_first = e0 // EDGE_CHUNK if chunked else 0
    ch_last = (e1 - 1) // EDGE_CHUNK if chunked else 0
    for ch in range(ch_first, ch_last + 1):
        if chunked:
            # a chunk whose every edge the test below would reject: skipped whole (a NaN
            # made its extent infinite)
            if chunk_y[ch, 1] < sy0 or chunk_y[ch, 0] >= sy0 + rows:
                continue
            ea, ez = max(e0, ch * EDGE_CHUNK), min(e1, (ch + 1) * EDGE_CHUNK)
        else:
            ea, ez = e0, e1
        for e in range(ea, ez):
            x0, y0, x1, y1 = edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3]
            # most of a fill's edges lie above or below the strip: rejected before the row
            # arithmetic (the rows they would give are empty; a NaN goes on to it, as before)
            if (y0 < sy0 and y1 < sy0) or (y0 >= sy0 + rows and y1 >= sy0 + rows):
                continue
            if min(x0, x1) >= W:
                continue
            if y0 == y1:
                # no crossing, but samples above and below it differ: the pixels whose
                # inside it crosses are dirty (not one whose left side it ends on: the edge
                # going on from that end marks it, see below)
                r = _floor_int(y0) - sy0
                if 0 <= r < rows and not hidden[r]:
                    lo_i = _pixel_index(min(x0, x1), W)
                    hi_i = _pixel_index(_ceil_int(max(x0, x1)) - 1, W)
                    for px in range(lo_i, hi_i + 1):
                        if dirty[r, px] == 0:
                            dirty[r, px] = 1
                            dlist[r, dcount[r]] = px
                            dcount[r] += 1
                continue
            # d in float32, as delta: the same sums (±1 on small integers is exact either
            # way) without a conversion to double and back per sample
            if y0 < y1:
                xt, yt, xb, yb, d = x0, y0, x1, y1, np.float32(1.0)
            elif y1 < y0:
                xt, yt, xb, yb, d = x1, y1, x0, y0, np.float32(-1.0)
            else:
                # a NaN y (clamp_far_edges drops edges by their x only): no winding is made
                # of it, where its rows came out as row 0 and its crossings as column 0
                continue
            r_lo = max(_floor_int(yt) - sy0, 0)
            # an edge ending on a row boundary counts for no sample of the row below it
            # (all at y >= yb) nor splits one there: not that row (a hairline staircase's
            # side one row tall marked two rows)
            r_hi = min(_ceil_int(yb) - 1 - sy0, rows - 1)
            if r_lo > r_hi:
                continue
            dxdy = (xb - xt) / (yb - yt)
            for r in range(r_lo, r_hi + 1):
                if hidden[r]:
                    continue
                py = sy0 + r
                # each sample's pixel first, W for none (arithmetic alone: it vectorises),
                # then the deltas (a scatter: it does not)
                for s in range(n):
                    ys = py + sy[s]
                    # the sample's pixel is ceil(v); compared as a float first (ceil(v) >= W
                    # exactly when v > W - 1): an edge reaching 1e19 px converts to no int64
                    v = crossing_x(xt, yt, dxdy, ys) - sx[s]
                    c = _ceil_int(v) if v > 0.0 else 0
                    col[s] = W if (ys < yt) | (ys >= yb) | (v > W - 1.0) else c
                for s in range(n):
                    if col[s] < W:
                        delta[r, col[s], s] += d
                # every pixel box this edge touches in the row becomes dirty, and the one to
                # the right, where crossings of samples left of the edge land: up to column
                # ceil(x) for the rightmost x, since a sample's crossing (monotone in its y
                # between ya and yb_) minus its sx >= 0 is at most x. An edge at an integer
                # x (a hairline staircase's riser) lands all its samples in column x, whose
                # right neighbour it marked for nothing
                ya = max(yt, py)
                yb_ = min(yb, py + 1.0)
                xa = crossing_x(xt, yt, dxdy, ya)
                xz = crossing_x(xt, yt, dxdy, yb_)
                lo = _floor_int(min(xa, xz))
                hi = _ceil_int(max(xa, xz))
                lo_i = _pixel_index(lo, W)
                hi_i = _pixel_index(hi, W)
                for px in range(lo_i, hi_i + 1):
                    if dirty[r, px] == 0:
                        dirty[r, px] = 1
                        dlist[r, dcount[r]] = px
                        dcount[r] += 1


@njit(cache=True, inline="always")
def _lens_alpha(dist, bx0, by0, bx1, by1, px, py):
    """A lens's coverage of pixel (px, py) from its signed distance to the pixel centre, at
    most the overlap of the lens's box with the pixel: the one-evaluation distance of a
    degenerate curve (a cubic a thousandth of a pixel across) can say 0.26 for a lens of
    area 1e-7."""
    ox = max(0.0, min(bx1, px + 1.0) - max(bx0, float(px)))
    oy = max(0.0, min(by1, py + 1.0) - max(by0, float(py)))
    return min(1.0, max(0.0, 0.5 - dist), ox * oy)


@njit(cache=True, error_model="numpy")
def prim_rows(prims):
    """(N, 2) y0, y1 of each primitive's box, contiguous: scan_lenses's strip test."""
    out = np.empty((prims.shape[0], 2))
    for c in range(prims.shape[0]):
        out[c, 0], out[c, 1] = prims[c, P_BBOX + 1], prims[c, P_BBOX + 3]
    return out


@njit(cache=True, error_model="numpy")
def scan_lenses(prims, prim_y, c0, c1, sy0, rows, W, sx, sy, mode, a2c_bits, local, dirty,
                dlist, dcount, lo, hi, terms, lens_stats, hidden, stamp, full_id):
    """Lens contributions of the curve primitives c0..c1 (one fill) on the strip, by coverage
    mode, except in the rows where ``hidden`` is set and at the pixels stamped ``full_id``
    (covered whole by the fills in front of this one in its occlusion run: a lens's winding
    stays in its pixel, so nothing of it can show there; -1 for a fill drawn on its own).
    Written out in one loop nest: an array handed to a helper costs a reference count per
    call, here per primitive and per touched pixel.

    The sample modes (approx, persample, none) evaluate the implicit function at each sample
    on the lens side of the chord and tangents. That is what approx's half-plane table decided
    until session 13 (docs/modes.md: its bounded error sent every sample it could not decide
    surely to this same test), and cheaper than the one evaluation, gradient, table look-ups
    and undecided samples it took per pixel (the tiger at 2048 px: 45% of its curve pixels
    left samples undecided; docs/bench.md, session 13). alpha and a2c evaluate the distance at
    the pixel centre. ``lens_stats[0]`` counts the curve pixels the sample modes evaluate.
    ``lo``, ``hi``: n int64 and ``terms``: (3, n) float64 of the caller's, to work in: the
    kernel allocates nothing and calls no kernel (either makes numba keep the reference
    counts of every array argument, at each of the batch's fills and strips)."""
    n = sx.shape[0]
    by_sample = mode == MODE_APPROX or mode == MODE_PERSAMPLE or mode == MODE_NONE
    evaluated = 0
    for c in range(c0, c1):
        if prim_y[c, 1] < sy0 or prim_y[c, 0] >= sy0 + rows:
            continue
        prim = prims[c]
        bx0, by0, bx1, by1 = prim[P_BBOX], prim[P_BBOX + 1], prim[P_BBOX + 2], prim[P_BBOX + 3]
        if bx0 >= W or bx1 < -1.0:
            continue
        r_lo = max(_floor_int(by0) - sy0, 0)
        r_hi = min(_floor_int(by1) - sy0, rows - 1)
        if r_lo > r_hi:
            continue
        xt, yt, xb, yb = prim[P_CHORD], prim[P_CHORD + 1], prim[P_CHORD + 2], prim[P_CHORD + 3]
        right = prim[P_RIGHT] != 0.0
        horizontal = yt == yb
        dxdy = 0.0 if horizontal else (xb - xt) / (yb - yt)
        sigma = prim[P_SIGMA]
        wsign = prim[P_WSIGN]
        # end tangents bound cubic and conic lenses (plain quads have none: (0, 0, 1))
        t1a, t1b, t1c = prim[P_T1], prim[P_T1 + 1], prim[P_T1 + 2]
        t2a, t2b, t2c = prim[P_T2], prim[P_T2 + 1], prim[P_T2 + 2]
        tangents = t1a != 0.0 or t1b != 0.0 or t2a != 0.0 or t2b != 0.0
        # _eval_implicit's terms, the same arithmetic
        ox, oy, inv = prim[P_OX], prim[P_OY], prim[P_INVS]
        ka, kb, kc = prim[P_K], prim[P_K + 1], prim[P_K + 2]
        la, lb, lc = prim[P_L], prim[P_L + 1], prim[P_L + 2]
        ma, mb, mc = prim[P_M], prim[P_M + 1], prim[P_M + 2]
        cubic = prim[P_KIND] != KIND_QUAD
        w32 = np.float32(wsign)
        full = np.uint64(0xFFFFFFFFFFFFFFFF) if n >= 64 else np.uint64((1 << n) - 1)
        for r in range(r_lo, r_hi + 1):
            if hidden[r]:
                continue
            py = sy0 + r
            xa, xz = _band_x_range(prim, py, py + 1.0)
            if not (xa <= xz):
                continue
            pxa = max(0, _floor_int(xa))
            pxz = min(W - 1, _floor_int(xz))
            if pxa > pxz:
                continue
            # per sample: the pixel range where it is on the lens side of chord and tangents,
            # each bound in a loop of its own with the tests on the primitive outside it, so
            # that the loops vectorise (the tangents' divisions and roundings four or eight
            # samples at once; one loop with the tests inside was 40% of this kernel's time
            # at 16 samples). Each sample's arithmetic is the same as one at a time.
            if horizontal:
                for s in range(n):
                    inside = (py + sy[s] >= yt) == right
                    lo[s] = -BIG if inside else BIG
                    hi[s] = BIG
            else:
                # a nearly horizontal chord crosses far rows beyond the int64 range: clamped
                # before the conversion (_ceil_int)
                for s in range(n):
                    t = _ceil_int(crossing_x(xt, yt, dxdy, py + sy[s]) - sx[s])
                    lo[s] = t if right else -BIG
                    hi[s] = BIG if right else t - 1
            for tangent in range(2 if tangents else 0):
                # narrowed to a·x + b·y + c ≥ 0: x ≥ v / a (a > 0) or x ≤ v / a (a < 0),
                # v = -(c + b·y), clamped before the conversion to int (_ceil_int): a nearly
                # horizontal tangent (tiny a) crosses the row far beyond the int64 range;
                # for a = 0 (or NaN) the whole row or none, and nothing for a = b = 0
                if tangent == 0:
                    a, b, c_ = t1a, t1b, t1c
                else:
                    a, b, c_ = t2a, t2b, t2c
                if a > 0.0:
                    for s in range(n):
                        v = -(c_ + b * (py + sy[s]))
                        lo[s] = max(lo[s], _ceil_int(v / a - sx[s]))
                elif a < 0.0:
                    for s in range(n):
                        v = -(c_ + b * (py + sy[s]))
                        hi[s] = min(hi[s], _floor_int(v / a - sx[s]))
                elif not (a == 0.0 and b == 0.0):
                    for s in range(n):
                        if -(c_ + b * (py + sy[s])) > 0.0:
                            lo[s] = BIG
            max_lo, min_hi = -BIG, BIG
            min_lo, max_hi = BIG, -BIG
            for s in range(n):
                max_lo = max(max_lo, lo[s])
                min_hi = min(min_hi, hi[s])
                min_lo = min(min_lo, lo[s])
                max_hi = max(max_hi, hi[s])
            # only the pixels where some sample is on the lens side
            pxa = max(pxa, min_lo)
            pxz = min(pxz, max_hi)
            # per sample, the row's terms of k, l and m (see _eval_implicit)
            for s in range(n):
                Y = (py + sy[s] - oy) * inv
                terms[0, s] = kb * Y
                terms[1, s] = lb * Y
                terms[2, s] = mb * Y
            for px in range(pxa, pxz + 1):
                if stamp[r, px] == full_id:
                    continue
                # the samples that gain the lens's winding (alpha adds fractions instead)
                bits = np.uint64(0)
                per_sample = by_sample
                if not by_sample:
                    if px >= max_lo and px <= min_hi:
                        region = full
                    else:
                        region = np.uint64(0)
                        for s in range(n):
                            if lo[s] <= px and px <= hi[s]:
                                region |= np.uint64(1) << np.uint64(s)
                        if region == 0:
                            continue
                    f, gx, gy = _eval_implicit(prim, px + 0.5, py + 0.5)
                    # |∇f| by sqrt where the squares can neither overflow nor underflow
                    # (glibc's hypot, exact-rounded at every scale, was 2% of a render)
                    g = math.sqrt(gx * gx + gy * gy)
                    if not (1e-150 < g < 1e150):
                        g = math.hypot(gx, gy)
                    if not (g > 0.0 and math.isfinite(f)):
                        per_sample = True   # a singular point (cusp, double point)
                    else:
                        alpha = _lens_alpha(sigma * f / g, bx0, by0, bx1, by1, px, py)
                        if mode == MODE_ALPHA:
                            if not (alpha > 0.0):
                                continue
                            for s in range(n):
                                if (region >> np.uint64(s)) & np.uint64(1):
                                    local[r, px, s] += wsign * alpha
                        else:  # MODE_A2C
                            bits = a2c_bits[int(alpha * n + 0.5)] & region
                            if bits == 0:
                                continue
                if per_sample:
                    # the samples inside the lens, in registers first: only a pixel with some
                    # is read and written (the strip's lens buffer is not in the caches)
                    evaluated += 1
                    for s in range(n):
                        X = (px + sx[s] - ox) * inv
                        k = ka * X + terms[0, s] + kc
                        l = la * X + terms[1, s] + lc
                        m = ma * X + terms[2, s] + mc
                        kk = k * k
                        f = (kk * k if cubic else kk) - l * m
                        inside = (sigma * f < 0.0) & (lo[s] <= px) & (px <= hi[s])
                        bits |= np.uint64(inside) << np.uint64(s)
                    if bits == 0:
                        continue
                if bits != 0:
                    for s in range(n):
                        if (bits >> np.uint64(s)) & np.uint64(1):
                            local[r, px, s] += w32
                touched = dirty[r, px]
                if touched < DIRTY_LENS:
                    if touched == 0:
                        dlist[r, dcount[r]] = px
                        dcount[r] += 1
                    dirty[r, px] = touched | DIRTY_LENS
    lens_stats[0] += evaluated


@njit(cache=True, error_model="numpy", inline="always")
def _sort_row(a, r, cnt):
    """Sort a[r, :cnt] in place, by hand: numba's sort is a further 2.5 s of first-run compile
    (its quicksort kernels) and allocates its partition stack. A row's dirty list is short (a
    few edge crossings): insertion sort; long lists (horizontal edges) get a heapsort. Inlined
    in numba's IR into the sweeps: a call to a kernel makes numba keep the reference counts
    of all the caller's array arguments (sweep_rows_behind's, at each fill and strip; in
    sweep_rows they stay, its size alone defeats numba's pruning of them)."""
    if cnt <= 64:
        for i in range(1, cnt):
            v = a[r, i]
            j = i - 1
            while j >= 0 and a[r, j] > v:
                a[r, j + 1] = a[r, j]
                j -= 1
            a[r, j + 1] = v
        return
    # heapsort: sift each of a[r, :cnt] into a max-heap, then move the root to the end
    end = cnt
    start = cnt // 2
    while end > 1:
        if start > 0:
            start -= 1
            root = start
        else:
            end -= 1
            a[r, 0], a[r, end] = a[r, end], a[r, 0]
            root = 0
        v = a[r, root]
        while True:
            child = 2 * root + 1
            if child >= end:
                break
            if child + 1 < end and a[r, child + 1] > a[r, child]:
                child += 1
            if a[r, child] <= v:
                break
            a[r, root] = a[r, child]
            root = child
        a[r, root] = v


@njit(cache=True, error_model="numpy")
def sweep_rows(r0, r1, sy0, W, rule, aa, kind, f, lut, tex, delta, local, dirty, dlist,
               dcount, fb, cplx, slot_of, slot_pixel, pool, npool, wrun, cov, sat, span):
    """Per row r0..r1 of the strip: turn the winding deltas into coverage and composite the
    fill's paint (one call per fill). The per-pixel work is written out in this loop nest:
    every array handed to a helper, even an inlined one, costs an atomic reference count
    increment and decrement per call, which per dirty pixel was a third of the kernel time.
    Spans (fewer) still go through _blend_span. ``sat``: the saturating blend (fills drawn
    front to back) instead of source-over."""
    n = wrun.shape[0]
    solid = kind == 0
    for r in range(r0, r1 + 1):
        cnt = dcount[r]
        if cnt == 0:
            continue
        py = sy0 + r
        _sort_row(dlist, r, cnt)
        wrun[:] = 0.0
        cr, cg, cb, ca = f[0], f[1], f[2], f[3]
        # a paint that is not solid: the row shaded once from its first dirty pixel to its
        # last, for the dirty pixels and the spans between them (one call, not one a pixel)
        s0, s1 = dlist[r, 0], dlist[r, cnt - 1] + 1
        if not solid:
            shade_span(kind, f, lut, tex, s0, s1, py + 0.5, span)
        prev = -1
        for i in range(cnt + 1):
            px = dlist[r, i] if i < cnt else W
            if px > prev + 1:
                c = coverage_of(wrun[0], rule)
                if c > 0.0:
                    _blend_span(fb, cplx, pool, r, prev + 1, px, py, kind, f, lut, tex, c, sat,
                                span, s0, s1)
            if i == cnt:
                break
            lens = dirty[r, px] & DIRTY_LENS
            dirty[r, px] = 0
            if lens:
                for s in range(n):
                    wrun[s] += delta[r, px, s]
                    delta[r, px, s] = 0.0
                    cov[s] = coverage_of(wrun[s] + local[r, px, s], rule)
                    local[r, px, s] = 0.0
            else:
                for s in range(n):
                    wrun[s] += delta[r, px, s]
                    delta[r, px, s] = 0.0
                    cov[s] = coverage_of(wrun[s], rule)
            uniform = True
            c0 = cov[0]
            for s in range(1, n):
                if cov[s] != c0:
                    uniform = False
            if not aa:
                # crispEdges: one sample decides for the whole pixel
                uniform = True
            prev = px
            if uniform and cov[0] <= 0.0:
                continue
            if uniform:
                # _blend_span of the one pixel, coverage cov[0]
                cu = cov[0]
                if kind != 0:
                    j = px - s0
                    pr, pg, pb, pa = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
                else:
                    pr, pg, pb, pa = f[0], f[1], f[2], f[3]
                sr, sg, sb, sa = pr * cu, pg * cu, pb * cu, pa * cu
                k = 1.0 - sa
                if kind == 0 and sa >= 1.0 and not sat:
                    cplx[r, px] = -1
                    fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = sr, sg, sb, sa
                    continue
                slot = cplx[r, px]
                if sat:
                    if slot < 0:
                        t = saturated(sa, fb[r, px, 3])
                        fb[r, px, 0] += sr * t
                        fb[r, px, 1] += sg * t
                        fb[r, px, 2] += sb * t
                        fb[r, px, 3] += sa * t
                    else:
                        for s in range(n):
                            t = saturated(sa, pool[slot, s, 3])
                            pool[slot, s, 0] += sr * t
                            pool[slot, s, 1] += sg * t
                            pool[slot, s, 2] += sb * t
                            pool[slot, s, 3] += sa * t
                    continue
                if slot < 0:
                    fb[r, px, 0] = sr + fb[r, px, 0] * k
                    fb[r, px, 1] = sg + fb[r, px, 1] * k
                    fb[r, px, 2] = sb + fb[r, px, 2] * k
                    fb[r, px, 3] = sa + fb[r, px, 3] * k
                elif sa >= 1.0:
                    # opaque full cover: the pixel is one colour again
                    cplx[r, px] = -1
                    fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = sr, sg, sb, sa
                else:
                    for s in range(n):
                        pool[slot, s, 0] = sr + pool[slot, s, 0] * k
                        pool[slot, s, 1] = sg + pool[slot, s, 1] * k
                        pool[slot, s, 2] = sb + pool[slot, s, 2] * k
                        pool[slot, s, 3] = sa + pool[slot, s, 3] * k
                continue
            if not solid:
                j = px - s0
                cr, cg, cb, ca = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
            # per-sample coverage: a one-colour pixel splits into samples
            if cplx[r, px] < 0:
                # split (written out: as a call, its five arrays cost ten reference counts per
                # split pixel): the pixel's colour at every sample of its pool slot; a pixel keeps
                # its slot once it has one (slot_pixel records whose it is)
                slot = slot_of[r, px]
                if slot < 0:
                    slot = npool
                    npool += 1
                    slot_of[r, px] = slot
                    slot_pixel[slot] = r * W + px
                for s in range(n):
                    pool[slot, s, 0], pool[slot, s, 1] = fb[r, px, 0], fb[r, px, 1]
                    pool[slot, s, 2], pool[slot, s, 3] = fb[r, px, 2], fb[r, px, 3]
                cplx[r, px] = slot
            slot = cplx[r, px]
            for s in range(n):
                cs = cov[s]
                if cs <= 0.0:
                    continue
                if sat:
                    t = cs * saturated(ca * cs, pool[slot, s, 3])
                    pool[slot, s, 0] += cr * t
                    pool[slot, s, 1] += cg * t
                    pool[slot, s, 2] += cb * t
                    pool[slot, s, 3] += ca * t
                    continue
                k = 1.0 - ca * cs
                pool[slot, s, 0] = cr * cs + pool[slot, s, 0] * k
                pool[slot, s, 1] = cg * cs + pool[slot, s, 1] * k
                pool[slot, s, 2] = cb * cs + pool[slot, s, 2] * k
                pool[slot, s, 3] = ca * cs + pool[slot, s, 3] * k
        dcount[r] = 0
    return npool


@njit(cache=True, error_model="numpy")
def sweep_rows_behind(r0, r1, W, rule, aa, f, delta, local, dirty, dlist, dcount, fb, cplx,
                      slot_of, slot_pixel, pool, npool, wrun, occ, stamp, nxt, run, extent):
    """sweep_rows for an opaque solid fill of a run drawn front to back (render_msaa): it
    paints only the samples that no fill in front of it covers and records the ones it
    paints. An opaque sample takes the paint's colour whatever was under it, so each sample
    ends as the back-to-front sweep_rows leaves it, bit for bit.

    What the run has covered is stamped with its number ``run``, so nothing is reset when a
    run ends: stamp[r, x] == 2·run + 1 means the pixel is full — nxt[r, x] then links to a
    later pixel, a union-find of the next pixel not full, so spans jump over covered ones —
    and stamp[r, x] == 2·run means its samples in the mask occ[r, x] are painted; any other
    stamp means nothing of the run is there yet.

    ``extent[r]`` = (run, lo, hi): the pixels lo..hi of row r hold all that run ``run`` has
    stamped there (another number: nothing yet). A span's stretch outside them is painted by
    plain loops (no stamp to test, one link for all: LLVM vectorises them), inside them by
    the walk that skips full pixels; a fill's spans are mostly outside what the fills in front
    of it cover (the flag's red field around its cross: 2.5x less time in this kernel)."""
    n = wrun.shape[0]
    full = np.uint64(0xFFFFFFFFFFFFFFFF) if n >= 64 else np.uint64((1 << n) - 1)
    full_id = 2 * run + 1
    part_id = 2 * run
    cr, cg, cb, ca = f[0], f[1], f[2], f[3]
    one = np.uint64(1)
    for r in range(r0, r1 + 1):
        cnt = dcount[r]
        if cnt == 0:
            continue
        _sort_row(dlist, r, cnt)
        wrun[:] = 0.0
        if extent[r, 0] != run:
            extent[r, 0], extent[r, 1], extent[r, 2] = run, W + 1, -1
        # lo..hi: what the fills before this one stamped in the row; the tests below use
        # that alone, since all this fill stamps is left of the cursor x (dirty pixels and
        # spans go left to right). Its own stamps grow elo..ehi, the row's next extent:
        # grown at once, a dirty pixel at the row's left end put the span from it up to
        # the fills in front inside the extent, walked pixel by pixel (the flag: 28% of
        # its pixels, the red field between its left edge and the cross)
        lo, hi = extent[r, 1], extent[r, 2]
        elo, ehi = lo, hi
        prev = -1
        for i in range(cnt + 1):
            px = dlist[r, i] if i < cnt else W
            x = prev + 1
            while px > x and coverage_of(wrun[0], rule) > 0.0:
                if x < lo or x > hi:
                    # pixels x..e-1 hold nothing of the run: all painted, all full, all
                    # linked to the first pixel from e on that is not full
                    e = min(px, lo) if x < lo else px
                    root = e
                    while stamp[r, root] == full_id:
                        root = nxt[r, root]
                    # unsigned columns: no negative-index wraparound, so LLVM stores
                    # vectors instead of scattering (3x faster on the flag's field)
                    for t in range(np.uint64(x), np.uint64(e)):
                        fb[r, t, 0], fb[r, t, 1], fb[r, t, 2], fb[r, t, 3] = cr, cg, cb, ca
                    for t in range(np.uint64(x), np.uint64(e)):
                        cplx[r, t] = -1
                        stamp[r, t] = full_id
                        nxt[r, t] = root
                    elo, ehi = min(elo, x), max(ehi, e - 1)
                    x = e
                    continue
                # inside what the run has stamped: the first pixel from x on that is not
                # full (path halving; column W is never full) ...
                while stamp[r, x] == full_id:
                    y = nxt[r, x]
                    if stamp[r, y] == full_id:
                        y = nxt[r, y]
                        nxt[r, x] = y
                    x = y
                if x >= px:
                    break
                if x > hi:
                    continue
                # ... and the pixels from there up to the next full one (or the span's end,
                # or the end of what the run has stamped)
                end = min(px, hi + 1)
                start = x
                while x < end and stamp[r, x] != full_id:
                    if stamp[r, x] == part_id:
                        # partly covered: a split pixel; its other samples take the paint
                        m = occ[r, x]
                        slot = cplx[r, x]
                        for s in range(n):
                            if not ((m >> np.uint64(s)) & one):
                                pool[slot, s, 0], pool[slot, s, 1] = cr, cg
                                pool[slot, s, 2], pool[slot, s, 3] = cb, ca
                    else:
                        cplx[r, x] = -1
                        fb[r, x, 0], fb[r, x, 1], fb[r, x, 2], fb[r, x, 3] = cr, cg, cb, ca
                    stamp[r, x] = full_id
                    x += 1
                # ... and link them all to the first pixel beyond that is not full: a later
                # fill crossing them jumps there at once (linked one to the next, each
                # walk would step through them again)
                root = x
                while stamp[r, root] == full_id:
                    root = nxt[r, root]
                for t in range(start, x):
                    nxt[r, t] = root
            if i == cnt:
                break
            lens = dirty[r, px] & DIRTY_LENS
            dirty[r, px] = 0
            bits = np.uint64(0)
            if lens:
                for s in range(n):
                    wrun[s] += delta[r, px, s]
                    delta[r, px, s] = 0.0
                    if coverage_of(wrun[s] + local[r, px, s], rule) > 0.0:
                        bits |= one << np.uint64(s)
                    local[r, px, s] = 0.0
            else:
                for s in range(n):
                    wrun[s] += delta[r, px, s]
                    delta[r, px, s] = 0.0
                    if coverage_of(wrun[s], rule) > 0.0:
                        bits |= one << np.uint64(s)
            if not aa:
                # crispEdges: one sample decides for the whole pixel
                bits = full if bits & one else np.uint64(0)
            prev = px
            st = stamp[r, px]
            if st == full_id:
                continue
            m = occ[r, px] if st == part_id else np.uint64(0)
            new = bits & ~m
            if new == 0:
                continue
            if new == full:
                cplx[r, px] = -1
                fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = cr, cg, cb, ca
            else:
                if cplx[r, px] < 0:
                    # split (written out: as a call, its five arrays cost ten reference counts per
                    # split pixel): the pixel's colour at every sample of its pool slot; a pixel keeps
                    # its slot once it has one (slot_pixel records whose it is)
                    slot = slot_of[r, px]
                    if slot < 0:
                        slot = npool
                        npool += 1
                        slot_of[r, px] = slot
                        slot_pixel[slot] = r * W + px
                    for s in range(n):
                        pool[slot, s, 0], pool[slot, s, 1] = fb[r, px, 0], fb[r, px, 1]
                        pool[slot, s, 2], pool[slot, s, 3] = fb[r, px, 2], fb[r, px, 3]
                    cplx[r, px] = slot
                slot = cplx[r, px]
                for s in range(n):
                    if (new >> np.uint64(s)) & one:
                        pool[slot, s, 0], pool[slot, s, 1] = cr, cg
                        pool[slot, s, 2], pool[slot, s, 3] = cb, ca
            m |= new
            if m == full:
                stamp[r, px] = full_id
                nxt[r, px] = px + 1
            else:
                occ[r, px] = m
                stamp[r, px] = part_id
            elo, ehi = min(elo, px), max(ehi, px)
        extent[r, 1], extent[r, 2] = elo, ehi
        dcount[r] = 0
    return npool


#: bytes of a cache line: the per-sample buffers start on one, so that a pixel's samples (64
#: bytes of winding deltas at 16 samples) fill whole lines instead of straddling two
CACHE_LINE = 64


def line_aligned(shape, dtype, fill=None):
    """An array of ``shape`` whose first element begins a cache line (numpy's large
    allocations begin 16 bytes into one), zeroed or set to ``fill``."""
    dtype = np.dtype(dtype)
    size = int(np.prod(shape)) * dtype.itemsize
    raw = np.zeros(size + CACHE_LINE, dtype=np.uint8)
    skip = -raw.ctypes.data % CACHE_LINE
    out = raw[skip:skip + size].view(dtype).reshape(shape)
    if fill is not None:
        out[...] = fill
    return out


def msaa_scratch(strip_rows, W, n, lens_stats=None):
    """render_msaa's per-strip buffers, allocated once per image and reused by every call:
    the kernel leaves them as it found them (zero deltas, nothing dirty, no split pixels),
    but for the occlusion stamps, which hold the numbers of past runs (no later run's).
    ``lens_stats``: where scan_lenses counts (1 int64), e.g. shared by a whole render."""
    return (line_aligned((strip_rows, W + 1, n), np.float32),       # delta
            line_aligned((strip_rows, W + 1, n), np.float32),       # local
            np.zeros((strip_rows, W + 1), dtype=np.uint8),          # dirty
            np.empty((strip_rows, W + 1), dtype=np.int64),          # dlist
            np.zeros(strip_rows, dtype=np.int64),                   # dcount
            # one-colour pixels live in the target itself; only split pixels have pool
            # slots, and only those are reset and resolved (untouched and fully covered
            # pixels cost nothing)
            np.full((strip_rows, W), -1, dtype=np.int32),           # cplx
            np.full((strip_rows, W), -1, dtype=np.int32),           # slot_of
            np.empty(strip_rows * W, dtype=np.int64),               # slot_pixel
            line_aligned((strip_rows * W, n, 4), np.float32),       # pool
            np.zeros(1, dtype=np.int64) if lens_stats is None else lens_stats,
            # runs of opaque fills (sweep_rows_behind): samples painted so far, whose they
            # are (the run's number), the next pixel not full, and the last run's number
            np.zeros((strip_rows, W), dtype=np.uint64),             # occ
            np.zeros((strip_rows, W + 1), dtype=np.int32),          # stamp
            np.zeros((strip_rows, W + 1), dtype=np.int32),          # nxt
            np.zeros(1, dtype=np.int64),                            # runs
            np.empty((W + 1, 4), dtype=np.float64))                 # span: a span's paint


@njit(cache=True)
def resolve_pool(fb, cplx, slot_of, slot_pixel, pool, npool, weights):
    """A strip's resolve: the pixels split into samples (pool slots 0 .. npool - 1) average
    them with the resolve filter's weights into ``fb``; one-colour pixels are already there.
    Every slot is let go (cplx and slot_of back to -1). Once a strip: its arrays' reference
    counts cost nothing beside the loop."""
    W = fb.shape[1]
    n = weights.shape[0]
    for slot in range(npool):
        r = slot_pixel[slot] // W
        px = slot_pixel[slot] - r * W
        if cplx[r, px] == slot:
            # the four channels side by side, each summed in sample order: one pass over
            # the slot's samples (a channel at a time strode through them four times)
            a0 = a1 = a2 = a3 = 0.0
            for s in range(n):
                w = weights[s]
                a0 += pool[slot, s, 0] * w
                a1 += pool[slot, s, 1] * w
                a2 += pool[slot, s, 2] * w
                a3 += pool[slot, s, 3] * w
            fb[r, px, 0], fb[r, px, 1], fb[r, px, 2], fb[r, px, 3] = a0, a1, a2, a3
        cplx[r, px] = -1
        slot_of[r, px] = -1


@njit(cache=True, nogil=True)   # bands render on threads
def render_msaa(target, y0, edges, edge_off, prims, prim_off, path_box, rules, aa, paint_kind,
                paint_f, lut, tex, sx, sy, weights, mode, a2c_bits, occlude, saturate, scratch):
    """Render a batch of fills onto ``target`` ((H, W, 4) float32 premultiplied, holding the
    device rows y0 .. y0 + H - 1) in place, strip by strip with the ``msaa_scratch`` buffers.

    sx, sy: sample positions inside the pixel (0..1); weights: resolve filter weight per
    sample (sums to 1). path_box: (P, 4) float bounds (x0, y0, x1, y1) per fill.

    ``occlude``: runs of consecutive opaque solid fills are drawn front to back
    (sweep_rows_behind), each painting only the samples the fills in front of it left
    uncovered, and the rows of a fill's box that they cover whole are not scanned; the
    pixels are the same as drawn back to front (sample masks need a coverage that is 0 or 1:
    not the alpha mode, and at most 64 samples).

    ``saturate``: the fills are drawn front to back (last fill first) with the saturating blend
    i = min(A_f, 1 - A_fb) instead of source-over (the ``alpha-sat`` mode): ``target`` must
    start transparent, and the caller composites it over what lies behind.
    CSAA (fewer stored colours than samples) is raster/csaa.py's render_csaa.
    """
    H, W = target.shape[0], target.shape[1]
    n = sx.shape[0]
    P = edge_off.shape[0] - 1
    (delta, local, dirty, dlist, dcount, cplx, slot_of, slot_pixel, pool, lens_stats, occ,
     stamp, nxt, runs, span) = scratch
    strip_rows = delta.shape[0]
    wrun = np.zeros(n, dtype=np.float32)
    cov = np.zeros(n, dtype=np.float32)
    lo = np.zeros(n, dtype=np.int64)
    hi = np.zeros(n, dtype=np.int64)
    terms = np.zeros((3, n))
    col = np.zeros(n, dtype=np.int64)
    hidden = np.zeros(strip_rows, dtype=np.bool_)
    # what each run has stamped in each row (sweep_rows_behind); run numbers start at 1
    extent = np.zeros((strip_rows, 3), dtype=np.int64)
    prim_y = prim_rows(prims)
    occlude = occlude and mode != MODE_ALPHA and n <= 64 and not saturate
    chunk_y = band_chunks(edges, edge_off, path_box, y0, H, strip_rows)
    # where the run of opaque solid fills from each fill on ends (the fill itself where it is
    # not one): worked out once, where each strip tested every fill's paint again (two more
    # arrays through the caches per strip: a third of this kernel's own time on a city map)
    run_end = np.empty(P + 1, dtype=np.int64)
    run_end[P] = P
    for q in range(P - 1, -1, -1):
        run_end[q] = run_end[q + 1] if paint_kind[q] == 0 and paint_f[q, 3] >= 1.0 else q
    # each strip visits only the fills whose box meets it (strip_buckets), in batch order
    start, order, last = strip_buckets(path_box, y0, H, W, strip_rows, True)
    now = np.empty(order.shape[0], dtype=np.int32)
    then = np.empty(order.shape[0], dtype=np.int32)
    nnow = 0
    for si in range((H + strip_rows - 1) // strip_rows):
        sy0 = y0 + si * strip_rows
        rows = min(strip_rows, y0 + H - sy0)
        fb = target[sy0 - y0:sy0 - y0 + rows]
        now, then = then, now
        nnow = strip_fills(then, nnow, order, start[si], start[si + 1], last, si, now)
        # np.int64, not the literal 0: a Literal[int](0) argument compiles sweep_rows and
        # sweep_rows_behind a second time (~7 s of first-run compile)
        npool = np.int64(0)
        i = 0
        while i < nnow:
            # a run of opaque solid fills (run_end: its fills meeting the strip, drawn front
            # to back), or one fill drawn as usual; saturate: the fills last to first
            j = i + 1
            k0 = now[nnow - 1 - i] if saturate else now[i]
            # (a fill in a run of two or more: run_end beyond the next fill, or the fill
            # before it opaque too)
            run = occlude and (run_end[k0] > k0 + 1 or
                               (run_end[k0] > k0 and k0 > 0 and run_end[k0 - 1] > k0 - 1))
            if run:
                while j < nnow and now[j] < run_end[k0]:
                    j += 1
                # the run's number stamps what it covers (sweep_rows_behind): a new number
                # starts it with nothing covered, no buffer to reset
                if runs[0] >= RUN_LIMIT:
                    stamp[:] = 0
                    runs[0] = 0
                runs[0] += 1
            run_id = runs[0]
            full_id = 2 * run_id + 1
            for t in range(j - i):
                if saturate:
                    k = k0
                else:
                    k = now[j - 1 - t] if run else now[i + t]
                # rows outside the fill's box have no deltas and nothing dirty
                r_first = max(0, _floor_int(path_box[k, 1]) - sy0)
                r_last = min(rows - 1, _floor_int(path_box[k, 3]) - sy0)
                if run:
                    x_first = max(0, _floor_int(path_box[k, 0]))
                    x_last = min(W - 1, _floor_int(path_box[k, 2]))
                    # rows where the fills in front cover the whole box are not scanned
                    shown = 0
                    for r in range(r_first, r_last + 1):
                        x = x_first
                        while stamp[r, x] == full_id and x <= x_last:
                            x = nxt[r, x]
                        hidden[r] = x > x_last
                        shown += x <= x_last
                    if shown == 0:
                        hidden[r_first:r_last + 1] = False
                        continue
                scan_edges(edges, chunk_y, edge_off[k], edge_off[k + 1], sy0, rows, W, sx, sy,
                           delta, dirty, dlist, dcount, hidden, col)
                if prim_off[k + 1] > prim_off[k]:
                    scan_lenses(prims, prim_y, prim_off[k], prim_off[k + 1], sy0, rows, W, sx,
                                sy, mode, a2c_bits, local, dirty, dlist, dcount, lo, hi,
                                terms, lens_stats, hidden, stamp, full_id if run else -1)
                if run:
                    npool = sweep_rows_behind(r_first, r_last, W, rules[k], aa[k], paint_f[k],
                                              delta, local, dirty, dlist, dcount, fb, cplx,
                                              slot_of, slot_pixel, pool, npool, wrun, occ,
                                              stamp, nxt, run_id, extent)
                    hidden[r_first:r_last + 1] = False
                else:
                    npool = sweep_rows(r_first, r_last, sy0, W, rules[k], aa[k], paint_kind[k],
                                       paint_f[k], lut, tex, delta, local, dirty, dlist, dcount,
                                       fb, cplx, slot_of, slot_pixel, pool, npool, wrun, cov,
                                       saturate, span)
            i = j
        resolve_pool(fb, cplx, slot_of, slot_pixel, pool, npool, weights)


# -- one fill drawn from runs of its geometry (render.StreamedFill) ---------------------------
@njit(cache=True, nogil=True, error_model="numpy")
def scan_run(edges, prims, sy0, rows, W, sx, sy, mode, a2c_bits, scratch):
    """The winding deltas and lens samples of a run of one fill's edges and primitives on the
    rows sy0 .. sy0 + rows - 1, added to what ``scratch`` (msaa_scratch of at least ``rows``
    rows) holds: render_msaa's scan of a fill, by the same kernels, in pieces. Edges add ±1
    and the sample modes' lenses ±1 to float32 sums of small integers (exact in any order);
    alpha's fractions are added in the order of the primitives, runs taken in order; the
    dirty lists are sorted by the sweep. So sweep_fill after every run of a fill gives what
    render_msaa gives with all of them at once."""
    (delta, local, dirty, dlist, dcount, cplx, slot_of, slot_pixel, pool, lens_stats, occ,
     stamp, nxt, runs, span) = scratch
    n = sx.shape[0]
    lo = np.zeros(n, dtype=np.int64)
    hi = np.zeros(n, dtype=np.int64)
    terms = np.zeros((3, n))
    col = np.zeros(n, dtype=np.int64)
    hidden = np.zeros(delta.shape[0], dtype=np.bool_)
    # (np.int64, not literals: a literal argument compiles the scan kernels once more)
    first, none = np.int64(0), np.int64(-1)
    scan_edges(edges, np.empty((0, 2)), first, np.int64(edges.shape[0]), sy0, rows, W, sx, sy,
               delta, dirty, dlist, dcount, hidden, col)
    if prims.shape[0] > 0:
        scan_lenses(prims, prim_rows(prims), first, np.int64(prims.shape[0]), sy0, rows, W, sx,
                    sy, mode, a2c_bits, local, dirty, dlist, dcount, lo, hi, terms, lens_stats,
                    hidden, stamp, none)


@njit(cache=True, nogil=True, error_model="numpy")
def sweep_fill(target, y0, sy0, rows, rules, aa, paint_kind, paint_f, lut, tex, weights,
               saturate, scratch):
    """render_msaa's sweep and resolve of one fill (row 0 of its arrays of rules, paints)
    on the target rows sy0 .. sy0 + rows - 1 (``target`` holds the device rows from y0),
    from what scan_run has added to ``scratch``, which it leaves clean."""
    (delta, local, dirty, dlist, dcount, cplx, slot_of, slot_pixel, pool, lens_stats, occ,
     stamp, nxt, runs, span) = scratch
    W = target.shape[1]
    n = weights.shape[0]
    wrun = np.zeros(n, dtype=np.float32)
    cov = np.zeros(n, dtype=np.float32)
    fb = target[sy0 - y0:sy0 - y0 + rows]
    npool = sweep_rows(np.int64(0), rows - 1, sy0, W, rules[0], aa[0], paint_kind[0],
                       paint_f[0], lut, tex, delta, local, dirty, dlist, dcount, fb, cplx,
                       slot_of, slot_pixel, pool, np.int64(0), wrun, cov, saturate, span)
    resolve_pool(fb, cplx, slot_of, slot_pixel, pool, npool, weights)


# -- analytic coverage (tiny-skia style exact area) -------------------------------------------
@njit(cache=True)
def _accumulate(acc, sy0, rows, W, x0, y0, x1, y1, xmin_row, xmax_row):
    """Signed-area accumulation of one line (font-rs style) into rows of the strip;
    x is already inside [0, W]."""
    if y0 == y1:
        return
    if y0 < y1:
        d = 1.0
    else:
        d = -1.0
        x0, y0, x1, y1 = x1, y1, x0, y0
    ytop = max(y0, float(sy0))
    ybot = min(y1, float(sy0 + rows))
    if ytop >= ybot:
        return
    dxdy = (x1 - x0) / (y1 - y0)
    x_lo, x_hi = min(x0, x1), max(x0, x1)
    r0 = int(math.floor(ytop)) - sy0
    r1 = min(rows - 1, int(math.ceil(ybot)) - 1 - sy0)
    for r in range(r0, r1 + 1):
        yrow = sy0 + r
        ya = max(float(yrow), ytop)
        yz = min(yrow + 1.0, ybot)
        dy = yz - ya
        if dy <= 0.0:
            continue
        # x where the line enters and leaves the row, from the line alone (not summed from
        # the strip's top), so a pixel's value does not depend on where strips begin; kept
        # inside the line's x range, which rounding could leave by an ulp (column -1)
        x = min(max(x0 + (ya - y0) * dxdy, x_lo), x_hi)
        xnext = x1 if yz == y1 else min(max(x0 + (yz - y0) * dxdy, x_lo), x_hi)
        dd = dy * d
        xa, xb = (x, xnext) if x < xnext else (xnext, x)
        xa_f = math.floor(xa)
        xai = int(xa_f)
        xb_c = math.ceil(xb)
        xbi = int(xb_c)
        xmin_row[r] = min(xmin_row[r], xai)
        xmax_row[r] = max(xmax_row[r], xbi + 1)
        if xbi <= xai + 1:
            xmf = 0.5 * (x + xnext) - xa_f
            acc[r, xai] += dd - dd * xmf
            acc[r, xai + 1] += dd * xmf
        else:
            s = 1.0 / (xb - xa)
            x0f = xa - xa_f
            a0 = 0.5 * s * (1.0 - x0f) * (1.0 - x0f)
            x1f = xb - xb_c + 1.0
            am = 0.5 * s * x1f * x1f
            acc[r, xai] += dd * a0
            if xbi == xai + 2:
                acc[r, xai + 1] += dd * (1.0 - a0 - am)
            else:
                a1 = s * (1.5 - x0f)
                acc[r, xai + 1] += dd * (a1 - a0)
                for xi in range(xai + 2, xbi - 1):
                    acc[r, xi] += dd * s
                a2 = a1 + (xbi - xai - 3) * s
                acc[r, xbi - 1] += dd * (1.0 - a2 - am)
            acc[r, xbi] += dd * am


@njit(cache=True)
def _accumulate_clipped(acc, sy0, rows, W, x0, y0, x1, y1, xmin_row, xmax_row):
    """Split a line at x = 0 and x = W; parts outside become vertical lines on the border,
    which keeps the accumulated cover of the visible pixels exact."""
    ts = np.empty(4)
    nt = 0
    ts[nt] = 0.0
    nt += 1
    if x0 != x1:
        for xb in (0.0, float(W)):
            t = (xb - x0) / (x1 - x0)
            if 0.0 < t < 1.0:
                ts[nt] = t
                nt += 1
    ts[nt] = 1.0
    nt += 1
    # 0 and 1 are in place; only two crossings (one per border) can be out of order. By hand:
    # np.sort compiles numba's quicksort kernels, ~1 s more of first-run compile
    if nt == 4 and ts[2] < ts[1]:
        ts[1], ts[2] = ts[2], ts[1]
    for i in range(nt - 1):
        ta, tb = ts[i], ts[i + 1]
        ax, ay = x0 + (x1 - x0) * ta, y0 + (y1 - y0) * ta
        bx, by = x0 + (x1 - x0) * tb, y0 + (y1 - y0) * tb
        if tb == 1.0:
            bx, by = x1, y1
        ax = min(max(ax, 0.0), float(W))
        bx = min(max(bx, 0.0), float(W))
        _accumulate(acc, sy0, rows, W, ax, ay, bx, by, xmin_row, xmax_row)


def analytic_scratch(strip_rows, W):
    """render_analytic's per-strip buffers, allocated once per image and reused by every call
    (the kernel leaves the accumulator zero)."""
    return (np.zeros((strip_rows, W + 3), dtype=np.float64),       # acc
            np.empty(strip_rows, dtype=np.int64),                   # xmin_row
            np.empty(strip_rows, dtype=np.int64),                   # xmax_row
            np.empty((W + 3, 4), dtype=np.float64))                 # span: a row's paint


@njit(cache=True, nogil=True)   # bands render on threads
def render_analytic(target, y0, edges, edge_off, path_box, rules, aa, paint_kind, paint_f, lut,
                    tex, scratch):
    """Exact-area coverage per fill, composited source-over per pixel (conflation included);
    ``target`` holds the device rows y0 .. y0 + H - 1."""
    H, W = target.shape[0], target.shape[1]
    acc, xmin_row, xmax_row, span = scratch
    tail = span[W + 2:]
    strip_rows = acc.shape[0]
    # each strip visits only the fills whose box meets it, in batch order (strip_buckets)
    start, order, last = strip_buckets(path_box, y0, H, W, strip_rows, False)
    now = np.empty(order.shape[0], dtype=np.int32)
    then = np.empty(order.shape[0], dtype=np.int32)
    nnow = 0
    for si in range((H + strip_rows - 1) // strip_rows):
        sy0 = y0 + si * strip_rows
        rows = min(strip_rows, y0 + H - sy0)
        now, then = then, now
        nnow = strip_fills(then, nnow, order, start[si], start[si + 1], last, si, now)
        for i in range(nnow):
            p = now[i]
            xmin_row[:] = W + 2
            xmax_row[:] = -1
            for e in range(edge_off[p], edge_off[p + 1]):
                _accumulate_clipped(acc, sy0, rows, W, edges[e, 0], edges[e, 1], edges[e, 2],
                                    edges[e, 3], xmin_row, xmax_row)
            kind = paint_kind[p]
            f = paint_f[p]
            # a solid paint is its colour: no shade call (and its reference counts) per pixel
            fr, fg, fb_, fa = f[0], f[1], f[2], f[3]
            for r in range(rows):
                if xmax_row[r] < 0:
                    continue
                a = 0.0
                x_end = min(W + 2, xmax_row[r])
                # a paint that is not solid: the columns of the row's edges shaded at once
                s0, s1 = xmin_row[r], min(W, x_end)
                if kind != 0 and s1 > s0:
                    shade_span(kind, f, lut, tex, s0, s1, sy0 + r + 0.5, span)
                # a path running off the right border keeps its cover up to the last column
                for x in range(xmin_row[r], W + 3):
                    a += acc[r, x]
                    acc[r, x] = 0.0
                    if x >= x_end and abs(a) < 1e-9:
                        break
                    if x >= W:
                        continue
                    c = coverage_of(a, rules[p])
                    if not aa[p]:
                        # crispEdges: a pixel is in when at least half of it is
                        c = 1.0 if c >= 0.5 else 0.0
                    if c <= 1e-7:
                        continue
                    if kind == 0:
                        cr, cg, cb, ca = fr, fg, fb_, fa
                    elif x < s1:
                        j = x - s0
                        cr, cg, cb, ca = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
                    else:
                        # past the shaded columns (a path running off the right border): the
                        # row's last slot of the buffer, one pixel
                        shade_span(kind, f, lut, tex, x, x + 1, sy0 + r + 0.5, tail)
                        cr, cg, cb, ca = tail[0, 0], tail[0, 1], tail[0, 2], tail[0, 3]
                    k = 1.0 - ca * c
                    ty = sy0 - y0 + r
                    target[ty, x, 0] = cr * c + target[ty, x, 0] * k
                    target[ty, x, 1] = cg * c + target[ty, x, 1] * k
                    target[ty, x, 2] = cb * c + target[ty, x, 2] * k
                    target[ty, x, 3] = ca * c + target[ty, x, 3] * k
