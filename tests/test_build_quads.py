"""build_batch's quadratics in the sample modes: a glyph's outline (quadratics between a few
lines) is built in the loop that assigns no array, each quadratic that lies in the culling
rect cut into its pieces there where the rooms hold them (session 36); a quadratic that finds
no room, or reaches beyond the rect, is left to the general code (_emit_quad), which grows
the rooms and culls. Checked against the pieces worked out from the control points in Python
(k pieces, the fewest whose bulge is at most max_sagitta; chords between the curve's points
at i / k, lenses whose control points are the parts' and whose implicit function vanishes on
the curve), lines as test_build_lines works them out, for paths of quadratics and lines
where the rooms run out in the middle of a path and where they do not; the in-place pieces
and _emit_quad's of the same quadratic are the same bytes."""
from __future__ import annotations

import math

import numpy as np
import pytest

from vecmsaa.geometry.primitives import (CULL_MARGIN, LINE_EPS, NO_CULL, P_CTRL, P_KIND,
                                         P_NCTRL, KIND_QUAD, _eval_implicit,
                                         build_batch, build_run, path_runs)
from vecmsaa.scene.path import CLOSE, LINE, MOVE, QUAD

from test_build_lines import batch, side_kept

NPTS = {MOVE: 1, LINE: 1, QUAD: 2, CLOSE: 0}


def pieces(p0, p1, p2, sagitta):
    """The fewest pieces k whose bulge (a quadratic's is |p0 - 2 p1 + p2| / 4, a k-th of it
    in parameter has a k²-th) is at most ``sagitta``; 0 where the curve is straight (its bulge
    below LINE_EPS: its chord alone)."""
    dev = 0.25 * math.hypot(p0[0] - 2 * p1[0] + p2[0], p0[1] - 2 * p1[1] + p2[1])
    if dev < LINE_EPS:
        return 0
    k = 1
    while dev > sagitta * k * k:
        k += 1
    return k


def point(p0, p1, p2, t):
    return tuple((1 - t) ** 2 * p0[j] + 2 * (1 - t) * t * p1[j] + t * t * p2[j] for j in (0, 1))


def part(p0, p1, p2, ta, tb):
    """The control points of the quadratic's part ta..tb: its ends, and where the tangents
    there meet (the blossom at (ta, tb))."""
    mid = tuple((1 - ta) * (1 - tb) * p0[j] + ((1 - ta) * tb + ta * (1 - tb)) * p1[j] +
                ta * tb * p2[j] for j in (0, 1))
    return point(p0, p1, p2, ta), mid, point(p0, p1, p2, tb)


def flat(a, m, b):
    """Whether the control triangle a, m, b has no area (its sides' cross product, in units
    of the longest side from a, below 1e-12): the piece is its chord, with no lens."""
    s = max(math.hypot(m[0] - a[0], m[1] - a[1]), math.hypot(b[0] - a[0], b[1] - a[1]))
    return s == 0 or abs((m[0] - a[0]) * (b[1] - a[1]) - (b[0] - a[0]) * (m[1] - a[1])) \
        < 1e-12 * s * s


def lenses(p0, p1, p2, k):
    """The lenses of the quadratic's k pieces: one a piece but the flat ones."""
    return sum(not flat(*part(p0, p1, p2, i / k, (i + 1) / k)) for i in range(k))


def close(a, b, tol=1e-9):
    return all(abs(x - y) <= tol * (1 + abs(y)) for x, y in zip(a, b))


def check_quad(edges, prims, p0, p1, p2, sagitta):
    """The edges and lenses of one quadratic lying in the canvas: its pieces' chords, from
    the curve's own ends, and a lens per piece with the part's control points."""
    k = pieces(p0, p1, p2, sagitta)
    if k == 0:
        want = [] if (p0[1] == p2[1] and (p0[0] == p2[0] or math.floor(p0[1]) == p0[1])) \
            else [(*p0, *p2)]
        assert [tuple(e) for e in edges] == want
        assert len(prims) == 0
        return
    assert len(edges) == k and len(prims) == lenses(p0, p1, p2, k)
    assert tuple(edges[0][:2]) == tuple(p0) and tuple(edges[-1][2:]) == tuple(p2)
    j = 0
    for i in range(k):
        a, m, b = part(p0, p1, p2, i / k, (i + 1) / k)
        if i == 0:
            a = p0
        if i == k - 1:
            b = p2
        assert close(edges[i], (*a, *b)), (i, k)
        if flat(a, m, b):
            continue
        lens = prims[j]
        j += 1
        assert lens[P_KIND] == KIND_QUAD and lens[P_NCTRL] == 3
        assert close(lens[P_CTRL:P_CTRL + 6], (*a, *m, *b))
        # the implicit function is zero on the curve (at the piece's middle) and at its ends
        s = max(math.hypot(m[0] - a[0], m[1] - a[1]), math.hypot(b[0] - a[0], b[1] - a[1]))
        for t in (i / k, (i + 0.5) / k):
            x, y = point(p0, p1, p2, t)
            f = _eval_implicit(lens, x, y)[0]
            assert abs(f) <= 1e-6 * max(1.0, s), (f, i, k)


def glyph_path(rng, size, big=False):
    """Subpaths of quadratics between a few lines (a TrueType outline's), some quadratics
    straight or with the control point on an end, all in the square 0..size; ``big``: a few
    quadratics large enough to be cut into dozens of pieces, more than the rooms reserved."""
    verbs, pts = [], []
    for _ in range(int(rng.integers(1, 4))):
        p = rng.uniform(0, size, 2)
        verbs.append(MOVE)
        pts.append(p)
        for _ in range(int(rng.integers(1, 30))):
            r = rng.random()
            if r < 0.3:
                p = np.round(rng.uniform(0, size, 2) * 2) / 2
                verbs.append(LINE)
                pts.append(p)
            else:
                c = rng.uniform(0, size, 2)
                e = rng.uniform(0, size, 2)
                if r < 0.35:
                    c = p + (e - p) * rng.random()      # straight
                elif r < 0.4:
                    c = p.copy()                         # control point on the start
                elif big and r > 0.9:
                    c = rng.uniform(-5 * size, 6 * size, 2)
                verbs.append(QUAD)
                pts += [c, e]
                p = e
        if rng.random() < 0.7:
            verbs.append(CLOSE)
    return np.array(verbs, np.uint8), np.array(pts, np.float64)


def walk(verbs, points, sagitta, canvas):
    """Each verb of a path (with the closing side at the end, as a CLOSE): (verb, the y of
    its points and the current point's, its edges' rows (first, last + 1), its lenses'),
    the rows as worked out from the points: a line's edge where side_kept keeps it, a
    quadratic's pieces (``pieces``), or its chord."""
    e = p = k = 0
    start = cur = (0.0, 0.0)
    open_ = False
    out = []
    for v in verbs.tolist() + [CLOSE]:
        pts = [tuple(q) for q in points[k:k + NPTS[v]].tolist()]
        ne = n = 0
        if v in (MOVE, CLOSE):
            ne = int(open_ and side_kept((*cur, *start), canvas))
            if v == MOVE:
                start = pts[0]
            cur, open_ = start, v == MOVE
        elif v == LINE:
            ne = int(side_kept((*cur, *pts[0]), canvas))
            cur = pts[0]
        else:
            npc = pieces(cur, pts[0], pts[1], sagitta)
            ne = npc if npc else int(side_kept((*cur, *pts[1]), NO_CULL))
            n = lenses(cur, pts[0], pts[1], npc)
            ys = (cur[1], pts[0][1], pts[1][1])
            cur = pts[1]
        out.append((v, ys if v == QUAD else (), (e, e + ne), (p, p + n)))
        e, p = e + ne, p + n
        k += NPTS[v]
    return out


def check_path(verbs, points, edges, prims, sagitta, canvas):
    """A path's edges and lenses, walked verb by verb: each line's edge as side_kept keeps
    it, each quadratic's as check_quad finds them."""
    k = 0
    start = cur = (0.0, 0.0)
    rows = walk(verbs, points, sagitta, canvas)
    for v, _, (e0, e1), (p0, p1) in rows:
        pts = [tuple(q) for q in points[k:k + NPTS[v]].tolist()]
        if v == QUAD:
            check_quad(edges[e0:e1].tolist(), prims[p0:p1], cur, pts[0], pts[1], sagitta)
            cur = pts[1]
        else:
            side = (cur, pts[0]) if v == LINE else (cur, start)
            if e1 > e0:
                assert tuple(edges[e0]) == (*side[0], *side[1]), e0
            if v == MOVE:
                start = pts[0]
            cur = pts[0] if v == LINE else start
        k += NPTS[v]
    assert rows[-1][2][1] == len(edges) and rows[-1][3][1] == len(prims)


@pytest.mark.parametrize("canvas", [NO_CULL, np.array([0.0, 0.0, 40.0, 30.0])])
@pytest.mark.parametrize("sagitta", [1.0, 0.05])
def test_glyph_outlines(canvas, sagitta):
    """Batches of glyph-like paths (all within the canvas): each path's edges and lenses
    are the pieces worked out from its points."""
    rng = np.random.default_rng(36)
    for trial in range(30):
        paths = [glyph_path(rng, 30) for _ in range(int(rng.integers(1, 8)))]
        edges, edge_off, prims, prim_off = build_batch(*batch(paths), 0.0, sagitta, canvas)
        for i, (v, p) in enumerate(paths):
            check_path(v, p, edges[edge_off[i]:edge_off[i + 1]],
                       prims[prim_off[i]:prim_off[i + 1]], sagitta, canvas)


def rooms(n, first):
    """The sizes a room reserved for ``first`` rows takes until it holds n (build_batch's
    growth: twice plus 16)."""
    sizes = [first]
    while sizes[-1] < n:
        sizes.append(2 * sizes[-1] + 16)
    return sizes


def test_rooms_run_out_among_the_quadratics():
    """Paths whose big quadratics outgrow the rooms reserved (two edges a point, five lenses
    a curve), small ones after them: the edges and lenses are still the pieces worked out
    from the points, and for many of the paths a room ran out in the middle of their
    quadratics (the next growth of the edges' or the lenses' room falls between the counts
    before and after a quadratic built in place, which found no room and went to _emit_quad)."""
    rng = np.random.default_rng(3636)
    crossed = 0
    for trial in range(60):
        v, p = glyph_path(rng, 30, big=True)
        edges, _, prims, _ = build_batch(*batch([(v, p)]), 0.0, 0.05, NO_CULL)
        check_path(v, p, edges, prims, 0.05, NO_CULL)
        n_curves = int(np.count_nonzero(v == QUAD))
        e_sizes = rooms(len(edges), max(16, 2 * len(p)))
        p_sizes = rooms(len(prims), max(16, 5 * n_curves))
        crossed += len(e_sizes) > 2 or len(p_sizes) > 2
    assert crossed >= 10


def test_in_place_pieces_are_emit_quads():
    """A quadratic whose control point lies just beyond the culling rect goes to _emit_quad
    (it culls), with none of its pieces culled (each piece's hull meets the rect): its edges
    and lenses are the same bytes as those of the same quadratic built in place (no rect)."""
    rng = np.random.default_rng(9)
    canvas = np.array([0.0, 0.0, 100.0, 100.0])
    for trial in range(50):
        a = rng.uniform(10, 90, 2)
        b = rng.uniform(10, 90, 2)
        c = np.array([rng.uniform(10, 90), -CULL_MARGIN - rng.uniform(0.01, 1)])
        v = np.array([MOVE, QUAD, LINE, QUAD], np.uint8)
        pts = np.array([a, c, b, a + 1, c, b], np.float64)
        placed = build_batch(*batch([(v, pts)]), 0.0, 0.1, NO_CULL)
        culled = build_batch(*batch([(v, pts)]), 0.0, 0.1, canvas)
        for x, y in zip(placed, culled):
            assert x.tobytes() == y.tobytes(), trial
        assert len(placed[2]) >= 2


def test_build_run_leaves_out_the_quadratics_beyond_its_rows():
    """build_run with rows ylo..yhi, in runs of a few verbs: the quadratics whose points all
    lie above or below the rows (CULL_MARGIN beyond) have no edges or lenses, the lines
    and the other quadratics build_batch's."""
    rng = np.random.default_rng(11)
    for trial in range(20):
        v, p = glyph_path(rng, 30)
        ylo, yhi = sorted(rng.uniform(0, 30, 2))
        lo, hi = ylo - CULL_MARGIN, yhi + CULL_MARGIN
        edges, _, prims, _ = build_batch(*batch([(v, p)]), 0.0, 0.5, NO_CULL)
        check_path(v, p, edges, prims, 0.5, NO_CULL)
        ints, flts = path_runs(v, p, 5)
        got_e, got_p = [], []
        for r in range(len(ints)):
            v1 = ints[r + 1, 0] if r + 1 < len(ints) else len(v)
            run = np.array([ints[r, 0], v1, ints[r, 1]], np.int64)
            state = np.array([*flts[r, :4], float(ints[r, 2])])
            e, q = build_run(v, p, run, state, r + 1 == len(ints), 0.5, NO_CULL, ylo, yhi)
            got_e += e.tolist()
            got_p.append(q)
        # build_batch's rows less those of the quadratics beyond the rows (check_path's
        # walk gives each verb's rows)
        want_e, want_p = [], []
        for verb, ys, (e0, e1), (p0, p1) in walk(v, p, 0.5, NO_CULL):
            if verb == QUAD and (all(y < lo for y in ys) or all(y > hi for y in ys)):
                continue
            want_e += edges[e0:e1].tolist()
            want_p.append(prims[p0:p1])
        assert got_e == want_e, trial
        assert np.concatenate(got_p).tobytes() == np.concatenate(want_p).tobytes(), trial
