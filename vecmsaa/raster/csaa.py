"""Coverage-sample antialiasing (CSAA, seed 001): n coverage samples, at most K stored colours.

A split pixel holds a table of K float32 RGBA colours and, per coverage sample, a uint8 index
into it (``csaa_scratch``: ``colours`` (pixels, K, 4), ``index`` (pixels, n)), so its storage is
16·K + n bytes against plain n-sample MSAA's 16·n. The table's entries are in order of first
appearance in sample order and every entry is used, so its length is the largest index + 1.

Per fill the kernels are the MSAA ones (``scan.scan_edges``, ``scan.scan_lenses``: windings and
lens samples); only the sweep differs. A uniform cover blends each table colour once (not each
sample); a partial cover blends each sample's colour from its entry and rebuilds the table: the
distinct colours in sample order, and while there are more than K, the colour held by the
fewest samples (of those, the first) is dropped and its samples take the nearest remaining
colour (RGBA distance; ties: the first) -- docs/modes.md. A pixel with at most K colours is
exactly n-sample MSAA. Fills are drawn in order (no occlusion runs): which colour a full table
drops depends on the order.
"""
from __future__ import annotations

import numpy as np

from ..jit import njit
from .scan import (_floor_int, _sort_row, band_chunks, coverage_of, prim_rows, saturated,
                   scan_edges, scan_lenses, strip_buckets, strip_fills)
from .shaders import shade_span


def csaa_scratch(strip_rows: int, W: int, n: int, slots: int, lens_stats=None) -> tuple:
    """render_csaa's per-strip buffers (reused by every call, left clean): scan.msaa_scratch's
    winding and dirty-pixel buffers, and the colour tables of the split pixels."""
    pixels = strip_rows * W
    return (np.zeros((strip_rows, W + 1, n), dtype=np.float32),     # delta
            np.zeros((strip_rows, W + 1, n), dtype=np.float32),     # local
            np.zeros((strip_rows, W + 1), dtype=np.uint8),          # dirty
            np.empty((strip_rows, W + 1), dtype=np.int64),          # dlist
            np.zeros(strip_rows, dtype=np.int64),                   # dcount
            np.full((strip_rows, W), -1, dtype=np.int32),           # cplx: the pixel's table
            np.full((strip_rows, W), -1, dtype=np.int32),           # slot_of
            np.empty(pixels, dtype=np.int64),                       # slot_pixel
            np.empty((pixels, slots, 4), dtype=np.float32),         # colours: K per table
            np.empty((pixels, n), dtype=np.uint8),                  # index: a sample's entry
            np.zeros(1, dtype=np.int64) if lens_stats is None else lens_stats,
            np.empty((W + 1, 4), dtype=np.float64))                 # span: a span's paint


@njit(cache=True, error_model="numpy")
def _partial(colours, index, slot, cov, cr, cg, cb, ca, sat, fresh, uniq, counts, key_entry):
    """A partial cover of a split pixel: every sample's colour blended from its table entry at
    its own coverage, then the table rebuilt from them (distinct colours in sample order; while
    more than K, the one on fewest samples joins its nearest). Where every coverage is 0 or 1
    (all but the alpha modes) samples of one entry and coverage share one colour, which is
    blended and looked up once (``key_entry``: its new entry, by 2 · entry + covered)."""
    n = index.shape[1]
    K = colours.shape[1]
    binary = True
    for s in range(n):
        if cov[s] != 0.0 and cov[s] != 1.0:
            binary = False
    if binary:
        key_entry[:] = -1
    m = 0
    for s in range(n):
        j = index[slot, s]
        cs = cov[s]
        key = 2 * j + (1 if cs > 0.0 else 0)
        if binary and key_entry[key] >= 0:
            u = key_entry[key]
        else:
            r, g, b, a = colours[slot, j, 0], colours[slot, j, 1], colours[slot, j, 2], colours[slot, j, 3]
            if cs > 0.0:
                if sat:
                    t = cs * saturated(ca * cs, a)
                    r, g, b, a = r + cr * t, g + cg * t, b + cb * t, a + ca * t
                else:
                    k = 1.0 - ca * cs
                    r, g, b, a = cr * cs + r * k, cg * cs + g * k, cb * cs + b * k, ca * cs + a * k
            # float32 here, as a stored sample: equal colours are found by exact comparison
            fresh[s, 0], fresh[s, 1], fresh[s, 2], fresh[s, 3] = r, g, b, a
            u = 0
            while u < m and not (uniq[u, 0] == fresh[s, 0] and uniq[u, 1] == fresh[s, 1]
                                 and uniq[u, 2] == fresh[s, 2] and uniq[u, 3] == fresh[s, 3]):
                u += 1
            if u == m:
                for ch in range(4):
                    uniq[m, ch] = fresh[s, ch]
                counts[m] = 0
                m += 1
            if binary:
                key_entry[key] = u
        counts[u] += 1
        index[slot, s] = u
    while m > K:
        u = 0
        for j in range(1, m):
            if counts[j] < counts[u]:
                u = j
        v, best = -1, np.inf
        for j in range(m):
            if j != u:
                d = 0.0
                for ch in range(4):
                    d += (uniq[j, ch] - uniq[u, ch]) ** 2
                if d < best:
                    v, best = j, d
        counts[v] += counts[u]
        # entry u goes: its samples join v, the later entries move up one (the table stays in
        # order of first appearance, which the ties above rely on)
        for s in range(n):
            j = index[slot, s]
            if j == u:
                j = v
            index[slot, s] = j - 1 if j > u else j
        for j in range(u, m - 1):
            counts[j] = counts[j + 1]
            for ch in range(4):
                uniq[j, ch] = uniq[j + 1, ch]
        m -= 1
    for j in range(m):
        for ch in range(4):
            colours[slot, j, ch] = uniq[j, ch]


@njit(cache=True, error_model="numpy")
def sweep_csaa(r0, r1, sy0, W, rule, aa, kind, f, lut, tex, delta, local, dirty, dlist, dcount,
               fb, cplx, slot_of, slot_pixel, colours, index, npool, wrun, cov, sat, fresh,
               uniq, counts, key_entry, span):
    """scan.sweep_rows with colour tables: per row r0..r1, windings to coverage, the fill's
    paint composited onto the one-colour pixels in the target and the tables of split ones
    (scan._blend_span's arithmetic). Written out in one loop nest, as sweep_rows is: an array
    handed to a helper costs a reference count per call, here per pixel."""
    n = wrun.shape[0]
    for r in range(r0, r1 + 1):
        cnt = dcount[r]
        if cnt == 0:
            continue
        py = sy0 + r
        _sort_row(dlist, r, cnt)
        wrun[:] = 0.0
        # a paint that is not solid: shaded once from the row's first dirty pixel to its last
        s0, s1 = dlist[r, 0], dlist[r, cnt - 1] + 1
        if kind != 0:
            shade_span(kind, f, lut, tex, s0, s1, py + 0.5, span)
        prev = -1
        for i in range(cnt + 1):
            px = dlist[r, i] if i < cnt else W
            # part 0: the clean pixels before px, one coverage; part 1: px, if its samples
            # have one coverage
            q0, q1 = prev + 1, px
            c = coverage_of(wrun[0], rule) if q1 > q0 else 0.0
            uniform = True
            for part in range(2):
                if part == 1:
                    if i == cnt:
                        break
                    dirty[r, px] = 0
                    for s in range(n):
                        wrun[s] += delta[r, px, s]
                        delta[r, px, s] = 0.0
                        cov[s] = coverage_of(wrun[s] + local[r, px, s], rule)
                        local[r, px, s] = 0.0
                        if cov[s] != cov[0]:
                            uniform = False
                    # crispEdges: one sample decides for the whole pixel
                    uniform = uniform or not aa
                    prev = px
                    if not uniform:
                        break
                    q0, q1, c = px, px + 1, cov[0]
                if c <= 0.0:
                    continue
                if kind != 0 and not (s0 <= q0 and q1 <= s1):
                    # past the shaded pixels (the row's last span: nothing is read after it)
                    shade_span(kind, f, lut, tex, q0, q1, py + 0.5, span)
                    s0, s1 = q0, q1
                for x in range(q0, q1):
                    if kind != 0:
                        j = x - s0
                        cr, cg, cb, ca = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
                    else:
                        cr, cg, cb, ca = f[0], f[1], f[2], f[3]
                    sr, sg, sb, sa = cr * c, cg * c, cb * c, ca * c
                    k = 1.0 - sa
                    slot = cplx[r, x]
                    if sa >= 1.0 and not sat:
                        # opaque full cover: the pixel is one colour again
                        cplx[r, x] = -1
                        fb[r, x, 0], fb[r, x, 1], fb[r, x, 2], fb[r, x, 3] = sr, sg, sb, sa
                    elif slot >= 0:
                        # every entry of the table (in order of first use: the last index + 1)
                        m = 0
                        for s in range(n):
                            m = max(m, index[slot, s] + 1)
                        for j in range(m):
                            if sat:
                                t = saturated(sa, colours[slot, j, 3])
                                colours[slot, j, 0] += sr * t
                                colours[slot, j, 1] += sg * t
                                colours[slot, j, 2] += sb * t
                                colours[slot, j, 3] += sa * t
                            else:
                                colours[slot, j, 0] = sr + colours[slot, j, 0] * k
                                colours[slot, j, 1] = sg + colours[slot, j, 1] * k
                                colours[slot, j, 2] = sb + colours[slot, j, 2] * k
                                colours[slot, j, 3] = sa + colours[slot, j, 3] * k
                    elif sat:
                        t = saturated(sa, fb[r, x, 3])
                        fb[r, x, 0] += sr * t
                        fb[r, x, 1] += sg * t
                        fb[r, x, 2] += sb * t
                        fb[r, x, 3] += sa * t
                    else:
                        fb[r, x, 0] = sr + fb[r, x, 0] * k
                        fb[r, x, 1] = sg + fb[r, x, 1] * k
                        fb[r, x, 2] = sb + fb[r, x, 2] * k
                        fb[r, x, 3] = sa + fb[r, x, 3] * k
            if i == cnt:
                break
            if uniform:
                continue
            # per-sample coverage: a one-colour pixel becomes a table of one entry; a pixel
            # keeps its slot once it has one (slot_pixel records whose it is)
            if cplx[r, px] < 0:
                slot = slot_of[r, px]
                if slot < 0:
                    slot = npool
                    npool += 1
                    slot_of[r, px] = slot
                    slot_pixel[slot] = r * W + px
                for ch in range(4):
                    colours[slot, 0, ch] = fb[r, px, ch]
                index[slot, :] = 0
                cplx[r, px] = slot
            if kind != 0:
                j = px - s0
                cr, cg, cb, ca = span[j, 0], span[j, 1], span[j, 2], span[j, 3]
            else:
                cr, cg, cb, ca = f[0], f[1], f[2], f[3]
            _partial(colours, index, cplx[r, px], cov, cr, cg, cb, ca, sat, fresh, uniq, counts,
                     key_entry)
        dcount[r] = 0
    return npool


@njit(cache=True, nogil=True)   # bands render on threads
def render_csaa(target, y0, edges, edge_off, prims, prim_off, path_box, rules, aa, paint_kind,
                paint_f, lut, tex, sx, sy, weights, mode, a2c_bits, saturate, scratch):
    """scan.render_msaa with K colours per split pixel (the ``colours`` of ``csaa_scratch``):
    the fills of a batch in order (``saturate``: last first, the saturating blend, onto a
    transparent ``target``), then every split pixel resolved from its table."""
    H, W = target.shape[0], target.shape[1]
    n = sx.shape[0]
    (delta, local, dirty, dlist, dcount, cplx, slot_of, slot_pixel, colours, index, lens_stats,
     span) = scratch
    strip_rows = delta.shape[0]
    wrun = np.zeros(n, dtype=np.float32)
    cov = np.zeros(n, dtype=np.float32)
    lo = np.zeros(n, dtype=np.int64)
    hi = np.zeros(n, dtype=np.int64)
    terms = np.zeros((3, n))
    hidden = np.zeros(strip_rows, dtype=np.bool_)
    prim_y = prim_rows(prims)
    # no occlusion runs here: no pixel carries the stamp -1 that scan_lenses skips (passed as
    # an int64, as render_msaa passes its run's id: a literal -1 compiled scan_lenses again)
    stamp = np.zeros((strip_rows, W + 1), dtype=np.int32)
    fresh = np.zeros((n, 4), dtype=np.float32)
    uniq = np.zeros((n, 4), dtype=np.float32)
    counts = np.zeros(n, dtype=np.int64)
    key_entry = np.zeros(2 * colours.shape[1], dtype=np.int64)
    chunk_y = band_chunks(edges, edge_off, path_box, y0, H, strip_rows)
    # each strip visits only the fills whose box meets it, in batch order (strip_buckets)
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
        npool = np.int64(0)
        for i in range(nnow):
            k = now[nnow - 1 - i] if saturate else now[i]
            r_first = max(0, _floor_int(path_box[k, 1]) - sy0)
            r_last = min(rows - 1, _floor_int(path_box[k, 3]) - sy0)
            scan_edges(edges, chunk_y, edge_off[k], edge_off[k + 1], sy0, rows, W, sx, sy, delta,
                       dirty, dlist, dcount, hidden, lo)
            if prim_off[k + 1] > prim_off[k]:
                scan_lenses(prims, prim_y, prim_off[k], prim_off[k + 1], sy0, rows, W, sx, sy,
                            mode, a2c_bits, local, dirty, dlist, dcount, lo, hi, terms,
                            lens_stats, hidden, stamp, np.int64(-1))
            npool = sweep_csaa(r_first, r_last, sy0, W, rules[k], aa[k], paint_kind[k],
                               paint_f[k], lut, tex, delta, local, dirty, dlist, dcount, fb, cplx,
                               slot_of, slot_pixel, colours, index, npool, wrun, cov, saturate,
                               fresh, uniq, counts, key_entry, span)
        for slot in range(npool):
            r = slot_pixel[slot] // W
            px = slot_pixel[slot] - r * W
            if cplx[r, px] == slot:
                for ch in range(4):
                    acc = 0.0
                    for s in range(n):
                        acc += colours[slot, index[slot, s], ch] * weights[s]
                    fb[r, px, ch] = acc
            cplx[r, px] = -1
            slot_of[r, px] = -1
