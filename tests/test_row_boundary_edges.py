"""Horizontal edges on a row boundary (an integer y) are left out of the scan converters' edges
(primitives._no_edge): such an edge adds no winding, and every sample of the pixel row below it
lies below it, so it splits no pixel's samples. A hairline's staircase (geometry/hairline.py)
is nearly a third such edges. Checked here against the renders with those edges put back, in
every coverage mode, bit for bit, and against the sides worked out from the points."""
from __future__ import annotations

import math

import numpy as np
import pytest

from vecmsaa.geometry.hairline import hairline_outline
from vecmsaa.geometry.primitives import NO_CULL, batch_arrays, build_batch
from vecmsaa.raster import render as render_module
from vecmsaa.raster.modes import MODES
from vecmsaa.raster.render import render_scene
from vecmsaa.scene.nodes import Fill, Group, LinearGradient, Scene, Solid
from vecmsaa.scene.path import CLOSE, LINE, MOVE, Path, rect_path

SIZE = 40


def polygon_sides(verbs, pts):
    """The sides (x0, y0, x1, y1) of a path of moves, lines and closes, in build_batch's
    order: each line, then each subpath's closing side (by CLOSE, the next move or the end)."""
    sides, start, cur, k, open_ = [], None, None, 0, False
    for v in verbs.tolist():
        if v == MOVE:
            if open_:
                sides.append((*cur, *start))
            start = cur = tuple(pts[k])
            k += 1
            open_ = True
        elif v == LINE:
            sides.append((*cur, *pts[k]))
            cur = tuple(pts[k])
            k += 1
        elif v == CLOSE:
            if open_:
                sides.append((*cur, *start))
            cur, open_ = start, False
    if open_:
        sides.append((*cur, *start))
    return [s for s in sides if (s[0], s[1]) != (s[2], s[3])]


def on_row_boundary(side):
    return side[1] == side[3] and math.floor(side[1]) == side[1]


def staircase_paths(rng, count):
    """Antialiased hairlines of random polylines (mostly steep and mostly flat ones: both
    staircases, and the near-axis parallelograms) as hairline_outline's paths, some placed at
    whole pixels (their steps' edges fall on integer coordinates) and at half pixels."""
    paths = []
    for i in range(count):
        n = int(rng.integers(2, 6))
        pts = rng.uniform(-4, SIZE + 4, (n, 2))
        if i % 3 == 0:
            pts = np.round(pts * 2) / 2
        rows = np.concatenate([pts[:-1], pts[1:]], axis=1)
        paths += hairline_outline(rows, alpha=float(rng.choice([1.0, 0.6])))
    return paths


def random_scene(seed, rule="nonzero"):
    """Staircases and rectangles with sides on row boundaries (and off them), in opaque and
    translucent solid paints and a gradient, over one another (runs of opaque fills too)."""
    rng = np.random.default_rng(seed)
    stops = np.array([[0, 1, 0.2, 0.1, 1], [1, 0.1, 0.3, 0.9, 0.7]], dtype=float)
    ramp = LinearGradient(0.0, 0.0, SIZE, SIZE * 0.7, stops)
    fills = []
    for i, path in enumerate(staircase_paths(rng, 12)):
        paint = ramp if i % 7 == 3 else Solid((*rng.uniform(0, 1, 3), [1.0, 0.6][i % 2]))
        fills.append(Fill(path, paint, rule=rule))
    for i in range(8):
        x, y = rng.uniform(-3, SIZE - 5, 2)
        w, h = rng.uniform(0.5, 12, 2)
        if i % 2 == 0:
            y, h = float(np.floor(y)), float(np.ceil(h))
        fills.append(Fill(rect_path(x, y, w, h), Solid((*rng.uniform(0, 1, 3), 1.0)), rule=rule))
    # a polygon of many sides on row boundaries, crossing itself
    zig = Path()
    zig.moveTo((2.5, 3.0))
    for k in range(1, 12):
        zig.lineTo((2.5 + 3 * k, 3.0 + (k % 2) * 7.0))
        zig.lineTo((4.0 + 3 * k, 3.0 + (k % 2) * 7.0))
    zig.lineTo((5.0, 30.0))
    zig.closePath()
    fills.append(Fill(zig, Solid((0.2, 0.7, 0.3, 0.8)), rule=rule))
    return Scene(SIZE, SIZE, Group(fills[:len(fills) // 2] + [
        Group(fills[len(fills) // 2:], opacity=0.8)]), background=(1, 1, 1, 1))


def put_back(keep, added):
    """A build_in_parts that adds back to each path's edges its sides for which ``keep`` is
    true and that build_batch left out (worked out from the points, after its own); counted
    in ``added[0]``."""
    build = render_module.build_in_parts

    def build_in_parts(verbs, pts, voff, poff, *args, **kw):
        built = build(verbs, pts, voff, poff, *args, **kw)

        def joined():
            edges, edge_off, prims, prim_off = built()
            rows, offs = [], [0]
            for p in range(len(voff) - 1):
                rows += edges[edge_off[p]:edge_off[p + 1]].tolist()
                extra = [s for s in polygon_sides(verbs[voff[p]:voff[p + 1]],
                                                  pts[poff[p]:poff[p + 1]]) if keep(s)]
                present = set(map(tuple, edges[edge_off[p]:edge_off[p + 1]].tolist()))
                extra = [s for s in extra if s not in present]
                added[0] += len(extra)
                rows += extra
                offs.append(len(rows))
            return (np.array(rows, np.float64).reshape(-1, 4), np.array(offs, np.int64),
                    prims, prim_off)
        return joined
    return build_in_parts


CASES = [(mode, {}) for mode in MODES] + [
    ("approx", {"color_samples": 2}), ("alpha", {"samples": 16, "color_samples": 4}),
    ("approx", {"samples": 16}), ("persample", {"samples": 4, "pattern": "rooks"})]


@pytest.mark.parametrize("mode, extra", CASES)
def test_edges_on_row_boundaries_change_no_pixel(mode, extra, monkeypatch):
    """The renders with the horizontal edges at integer y put back are those without them,
    bit for bit (float32), in every coverage mode, CSAA included, for nonzero and even-odd
    fills of staircases, rectangles and a self-crossing polygon."""
    opts = dict(extra)
    opts.setdefault("samples", 8)
    for seed, rule in ((1, "nonzero"), (2, "evenodd")):
        scene = random_scene(seed, rule)
        without = render_scene(scene, mode=mode, **opts)
        added = [0]
        with monkeypatch.context() as m:
            m.setattr(render_module, "build_in_parts", put_back(on_row_boundary, added))
            put = render_scene(scene, mode=mode, **opts)
        assert added[0] > 100
        assert np.array_equal(without, put)


def test_the_comparison_sees_a_horizontal_edge_off_the_row_boundaries(monkeypatch):
    """The check above can fail: scenes built with the horizontal edges off row boundaries
    left out (and put back: the renders differ)."""
    scene = random_scene(1)
    with monkeypatch.context() as m:
        m.setattr(render_module, "build_in_parts", put_back(on_row_boundary, [0]))
        base = render_scene(scene, mode="approx")
    build = render_module.build_in_parts

    def dropping(verbs, pts, voff, poff, *args, **kw):
        built = build(verbs, pts, voff, poff, *args, **kw)

        def without_horizontals():
            edges, edge_off, prims, prim_off = built()
            rows, offs = [], [0]
            for p in range(len(edge_off) - 1):
                rows += [e for e in edges[edge_off[p]:edge_off[p + 1]].tolist()
                         if e[1] != e[3]]
                offs.append(len(rows))
            return (np.array(rows, np.float64).reshape(-1, 4), np.array(offs, np.int64),
                    prims, prim_off)
        return without_horizontals
    with monkeypatch.context() as m:
        m.setattr(render_module, "build_in_parts", dropping)
        dropped = render_scene(scene, mode="approx")
    assert not np.array_equal(base, dropped)


@pytest.mark.parametrize("tol", [0.0, 0.25])
def test_build_batch_leaves_out_the_horizontal_sides_on_row_boundaries(tol):
    """build_batch's edges of hairline staircases and rectangles are their sides (worked out
    from the points) less those horizontal at an integer y, in order; a staircase has many
    (the drop happens), and no edge left is one of them."""
    rng = np.random.default_rng(3)
    paths = staircase_paths(rng, 10) + [rect_path(1.0, 2.0, 5.5, 7.0), rect_path(1, 2.5, 3, 4)]
    edges, edge_off, _, _ = build_batch(*batch_arrays(paths), tol, 1.0, NO_CULL)
    dropped = 0
    for p, path in enumerate(paths):
        sides = polygon_sides(path.verbs, path.points.astype(np.float64))
        want = [s for s in sides if not on_row_boundary(s)]
        dropped += len(sides) - len(want)
        assert edges[edge_off[p]:edge_off[p + 1]].tolist() == [list(s) for s in want]
    assert not any(on_row_boundary(e) for e in edges.tolist())
    assert dropped > len(edges) // 5


def marking_polygons(rng):
    """Edges (x0, y0, x1, y1) of closed polygons, as fills' ranges: hairline staircases, and
    polygons with corners at whole and half pixels (rectangles among them), and at random."""
    paths = staircase_paths(rng, 8)
    for i in range(12):
        k = int(rng.integers(3, 7))
        pts = rng.uniform(-3, 27, (k, 2))
        if i % 3 == 0:
            pts = np.round(pts)
        elif i % 3 == 1:
            pts = np.round(pts * 2) / 2
        paths.append(Path.from_arrays(np.array([MOVE] + [LINE] * (k - 1) + [CLOSE], np.uint8),
                                      pts))
    paths.append(rect_path(2.0, 3.0, 9.0, 5.0))
    edges, edge_off, _, _ = build_batch(*batch_arrays(paths), 0.0, 1.0, NO_CULL)
    return edges, edge_off


def sample_winding(edges, W, H, sx, sy):
    """The winding number at every sample of a W x H image by the raster's rule (docs/modes.md):
    an edge from y_top to y_bottom counts for the sample rows y_top <= y < y_bottom, +1 going
    down, -1 up, where the sample's x is at or beyond its crossing (worked out as the scan
    works it out: x_top + (y - y_top) * dx/dy, less the sample's offset, rounded up)."""
    X = np.arange(W)[None, :, None] + 0 * sx[None, None, :]
    Y = np.arange(H)[:, None, None] + sy[None, None, :]
    want = np.zeros((H, W, len(sx)))
    for x0, y0, x1, y1 in edges:
        if y0 == y1:
            continue
        (xt, yt, xb, yb), d = ((x0, y0, x1, y1), 1) if y0 < y1 else ((x1, y1, x0, y0), -1)
        v = xt + (Y - yt) * ((xb - xt) / (yb - yt)) - sx[None, None, :]
        want += np.where((Y >= yt) & (Y < yb) & (np.ceil(v) <= X), d, 0)
    return want


@pytest.mark.parametrize("samples", [1, 4, 8, 16])
def test_scan_edges_marks_every_pixel_whose_samples_differ(samples):
    """scan_edges' deltas sum to each sample's exact winding (crossings of the outline left
    of it), land only on dirty pixels, and a pixel left clean has one winding at all its
    samples (the sweep draws it as part of a span): for staircases and polygons whose
    corners lie on pixel corners and sides, in strips of a few rows."""
    from vecmsaa.raster.sample_patterns import standard_pattern
    from vecmsaa.raster.scan import msaa_scratch, scan_edges
    offsets = standard_pattern(samples) if samples > 1 else np.zeros((1, 2))
    sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
    n, W, H, rows = len(sx), SIZE, SIZE, 5
    edges, edge_off = marking_polygons(np.random.default_rng(samples))
    for p in range(len(edge_off) - 1):
        e = edges[edge_off[p]:edge_off[p + 1]]
        want = sample_winding(e, W, H, sx, sy)
        for sy0 in range(0, H, rows):
            delta, _, dirty, dlist, dcount = msaa_scratch(rows, W, n)[:5]
            scan_edges(edges, np.empty((0, 2)), edge_off[p], edge_off[p + 1], sy0, rows, W, sx,
                       sy, delta, dirty, dlist, dcount, np.zeros(rows, dtype=np.bool_),
                       np.zeros(n, dtype=np.int64))
            got = np.cumsum(delta[:, :W], axis=1)
            assert np.array_equal(got, want[sy0:sy0 + rows]), (p, sy0)
            marked = dirty[:, :W] != 0
            assert not np.any(delta[:, :W][~marked]), (p, sy0)
            clean = got[~marked]
            assert np.all(clean == clean[:, :1]), (p, sy0)


def test_a_rectangle_on_pixel_corners_marks_only_its_side_columns():
    """A rectangle with its corners on pixel corners changes the winding only in the columns
    of its left and right sides (all of a row's samples cross each side in that column; its
    top and bottom split no pixel): those are all the dirty pixels, two a row."""
    from vecmsaa.raster.scan import msaa_scratch, scan_edges
    edges, edge_off, _, _ = build_batch(*batch_arrays([rect_path(3.0, 2.0, 7.0, 4.0)]), 0.0,
                                        1.0, NO_CULL)
    assert len(edges) == 2
    offsets = np.array([[-0.375, -0.125], [0.125, -0.375], [-0.125, 0.375], [0.375, 0.125]])
    sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
    rows, W = 8, 16
    delta, _, dirty, dlist, dcount = msaa_scratch(rows, W, 4)[:5]
    scan_edges(edges, np.empty((0, 2)), 0, len(edges), 0, rows, W, sx, sy, delta, dirty, dlist,
               dcount, np.zeros(rows, dtype=np.bool_), np.zeros(4, dtype=np.int64))
    assert [sorted(dlist[r, :dcount[r]].tolist()) for r in range(rows)] == \
        [[]] * 2 + [[3, 10]] * 4 + [[]] * 2
