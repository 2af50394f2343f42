"""build_batch's (and build_run's) straight edges: a path's moves, lines and closes are written
in a loop of their own that assigns no array (numba copies an array variable assigned in a
loop, a reference count up and down, on every pass), leaving it to grow the room where an
edge finds none and for each curve. Checked against the edges worked out from the points in
Python (each side but points, horizontal sides on a row boundary and sides wholly above,
below or right of the culling rect), with each curve's edges and lenses those of the curve
built alone, in order, in the sample and the flattening modes, where the room runs out in the
middle of a path's lines and where it does not."""
from __future__ import annotations

import math

import numpy as np
import pytest

from vecmsaa.geometry.primitives import (CULL_MARGIN, NO_CULL, PRIM_FIELDS, build_batch,
                                         build_run, path_runs)
from vecmsaa.scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD

NPTS = {MOVE: 1, LINE: 1, QUAD: 2, CUBIC: 3, CONIC: 3, CLOSE: 0}


def side_kept(side, canvas):
    """Whether build_batch keeps the straight side (x0, y0, x1, y1): not a point, not
    horizontal on a row boundary, and not wholly above, below or right of the canvas
    (CULL_MARGIN beyond)."""
    x0, y0, x1, y1 = side
    if y0 == y1 and (x0 == x1 or math.floor(y0) == y0):
        return False
    top, bottom, right = canvas[1] - CULL_MARGIN, canvas[3] + CULL_MARGIN, \
        canvas[2] + CULL_MARGIN
    return not ((y0 < top and y1 < top) or (y0 > bottom and y1 > bottom) or
                (x0 > right and x1 > right))


def curve_alone(v, cur, pts, tol, canvas):
    """The edges and lenses build_batch makes of one curve from ``cur``: those of the path
    (move, curve), less its closing chord (kept where side_kept keeps it: always its last)."""
    verbs = np.array([MOVE, v], np.uint8)
    points = np.array([cur] + [tuple(p) for p in pts], np.float64)
    edges, _, prims, _ = build_batch(verbs, points, np.array([0, 2]),
                                     np.array([0, len(points)]), tol, 1.0, canvas)
    edges = edges.tolist()
    chord = (*points[-1], *points[0])
    if side_kept(chord, canvas):
        assert edges[-1] == list(chord)
        edges = edges[:-1]
    return edges, prims


def reference(verbs, points, tol, canvas):
    """One path's edges (list) and lenses ((C, PRIM_FIELDS)) in build_batch's order."""
    edges, prims = [], [np.zeros((0, PRIM_FIELDS))]
    start = cur = (0.0, 0.0)
    open_ = False
    k = 0
    for v in verbs.tolist():
        n = NPTS[v]
        pts = points[k:k + n]
        if v in (MOVE, CLOSE):
            if open_ and side_kept((*cur, *start), canvas):
                edges.append([*cur, *start])
            if v == MOVE:
                start = tuple(pts[0])
            cur, open_ = start, v == MOVE
        elif v == LINE:
            if side_kept((*cur, *pts[0]), canvas):
                edges.append([*cur, *pts[0]])
            cur = tuple(pts[0])
        else:
            e, p = curve_alone(v, cur, pts, tol, canvas)
            edges += e
            prims.append(p)
            cur = tuple(pts[-1])
        k += n
    if open_ and side_kept((*cur, *start), canvas):
        edges.append([*cur, *start])
    return edges, np.concatenate(prims)


def random_path(rng, size):
    """Subpaths of lines (staircase steps on whole and half pixels, and random ones), some
    left open, some crossing themselves, with curves of each kind among them and some sides
    beyond the canvas."""
    verbs, pts = [], []
    for _ in range(int(rng.integers(1, 5))):
        p = rng.uniform(-10, size + 10, 2)
        verbs.append(MOVE)
        pts.append(p)
        for _ in range(int(rng.integers(1, 40))):
            r = rng.random()
            if r < 0.5:
                # a staircase step: along x, then y, on whole or half pixels
                axis = int(rng.integers(0, 2))
                p = p.copy()
                p[axis] = np.round(p[axis] + rng.uniform(-3, 3))
                if rng.random() < 0.3:
                    p[axis] += 0.5
                verbs.append(LINE)
                pts.append(p)
            elif r < 0.8:
                p = rng.uniform(-10, size + 10, 2)
                verbs.append(LINE)
                pts.append(p)
            else:
                v = [QUAD, CUBIC, CONIC][int(rng.integers(0, 3))]
                verbs.append(v)
                for _ in range(NPTS[v]):
                    p = rng.uniform(-10, size + 10, 2)
                    pts.append(p)
        if rng.random() < 0.6:
            verbs.append(CLOSE)
    return np.array(verbs, np.uint8), np.array(pts, np.float64)


def batch(paths):
    verbs = np.concatenate([v for v, _ in paths])
    points = np.concatenate([p for _, p in paths])
    voff = np.cumsum([0] + [len(v) for v, _ in paths]).astype(np.int64)
    poff = np.cumsum([0] + [len(p) for _, p in paths]).astype(np.int64)
    return verbs, points, voff, poff


@pytest.mark.parametrize("tol", [0.0, 0.1])
@pytest.mark.parametrize("canvas", [NO_CULL, np.array([0.0, 0.0, 40.0, 30.0])])
def test_random_paths_edges_and_lenses(tol, canvas):
    """build_batch of random batches: each path's edges and lenses are the reference's."""
    rng = np.random.default_rng(35)
    for trial in range(20):
        paths = [random_path(rng, 40) for _ in range(int(rng.integers(1, 8)))]
        edges, edge_off, prims, prim_off = build_batch(*batch(paths), tol, 1.0, canvas)
        for i, (v, p) in enumerate(paths):
            want, want_prims = reference(v, p, tol, canvas)
            assert edges[edge_off[i]:edge_off[i + 1]].tolist() == want, (trial, i)
            got = prims[prim_off[i]:prim_off[i + 1]]
            assert got.shape == want_prims.shape and got.tobytes() == want_prims.tobytes()


def circle_then_lines(k, radius=1e5):
    """A circle of four cubics (many pieces: its edges outgrow the room reserved for the
    path's points) followed by a subpath of k lines, a staircase."""
    verbs = [MOVE] + [CUBIC] * 4 + [CLOSE, MOVE] + [LINE] * k + [CLOSE]
    cx, cy, r = 500.0, 500.0, radius
    kappa = 0.5522847498 * r
    pts = [(cx + r, cy),
           (cx + r, cy + kappa), (cx + kappa, cy + r), (cx, cy + r),
           (cx - kappa, cy + r), (cx - r, cy + kappa), (cx - r, cy),
           (cx - r, cy - kappa), (cx - kappa, cy - r), (cx, cy - r),
           (cx + kappa, cy - r), (cx + r, cy - kappa), (cx + r, cy)]
    x, y = 10.5, 10.0
    pts.append((x, y))
    for j in range(k):
        if j % 2 == 0:
            x += 1.0
        else:
            y += 1.0
        pts.append((x, y))
    return np.array(verbs, np.uint8), np.array(pts, np.float64)


@pytest.mark.parametrize("tol", [0.0, 0.05])
def test_room_runs_out_among_the_lines(tol):
    """Where a path's curves outgrow the room and its lines then fill the grown room, the
    edges are still the reference's; the room's sizes (build_batch's growth: twice plus 16)
    show that for some of the line counts the room ran out in the middle of the lines."""
    crossed = 0
    for k in range(1, 700, 4):
        v, p = circle_then_lines(k)
        edges, edge_off, prims, prim_off = build_batch(*batch([(v, p)]), tol, 1.0, NO_CULL)
        want, want_prims = reference(v, p, tol, NO_CULL)
        assert edges.tolist() == want, k
        assert prims.tobytes() == want_prims.tobytes()
        # the room's sizes as it grows, and the edges before the lines (the circle's)
        room, sizes = max(16, 2 * len(p)), []
        while room < len(want) + 1:
            sizes.append(room)
            room = 2 * room + 16
        circle = len(reference(v[:6], p[:13], tol, NO_CULL)[0])
        crossed += any(circle < s < len(want) for s in sizes)
    assert crossed >= 5


@pytest.mark.parametrize("tol", [0.0])
def test_build_run_is_build_batch(tol):
    """build_run's edges and lenses of a path cut into runs (path_runs) are build_batch's
    of the path, run after run (no rows left out)."""
    rng = np.random.default_rng(7)
    for trial in range(10):
        v, p = random_path(rng, 40)
        edges, _, prims, _ = build_batch(*batch([(v, p)]), tol, 1.0, NO_CULL)
        ints, flts = path_runs(v, p, 7)
        got_e, got_p = [], []
        for r in range(len(ints)):
            v1 = ints[r + 1, 0] if r + 1 < len(ints) else len(v)
            run = np.array([ints[r, 0], v1, ints[r, 1]], np.int64)
            state = np.array([*flts[r, :4], float(ints[r, 2])])
            e, q = build_run(v, p, run, state, r + 1 == len(ints), 1.0, NO_CULL,
                             -np.inf, np.inf)
            got_e += e.tolist()
            got_p.append(q)
        assert got_e == edges.tolist(), trial
        assert np.concatenate(got_p).tobytes() == prims.tobytes()


class CountingPool:
    """A band pool's interface for build_in_parts, running each task at once and counting."""
    threads = 2

    def __init__(self):
        self.tasks = 0

    def submit(self, fn, *args):
        from concurrent.futures import Future
        self.tasks += 1
        f = Future()
        f.set_result(fn(*args))
        return f


def test_a_batch_of_lines_is_built_whole_and_one_of_curves_in_parts():
    """build_in_parts splits a batch among a pool's threads only where its curves' work
    outweighs its lines' (joining the parts copies every row: a line's edge costs about as
    much to copy as to build): a batch of staircases and rectangles is built in one part, a
    batch of circles as cubics in several; both give build_batch's arrays."""
    from vecmsaa.raster import render as render_module
    rng = np.random.default_rng(5)
    lines = [random_path(rng, 400) for _ in range(200)]
    lines = [(v[(v != QUAD) & (v != CUBIC) & (v != CONIC)], None) for v, _ in lines]
    lines = [(v, rng.uniform(0, 400, (int(np.count_nonzero((v == MOVE) | (v == LINE))), 2)))
             for v, _ in lines]
    circles = [circle_then_lines(1, radius=float(r)) for r in rng.uniform(2, 20, 300)]
    for paths, split in ((lines, False), (circles, True)):
        arrays = batch(paths)
        assert len(arrays[0]) * 16 >= render_module.SPLIT_COST
        pool = CountingPool()
        got = render_module.build_in_parts(*arrays, 0.0, pool, NO_CULL)()
        want = build_batch(*arrays, 0.0, render_module.MAX_SAGITTA, NO_CULL)
        assert (pool.tasks > 1) == split, pool.tasks
        assert pool.tasks == (2 * render_module.PARTS_PER_THREAD if split else 0)
        for a, b in zip(got, want):
            assert a.dtype == b.dtype and np.array_equal(a, b)
