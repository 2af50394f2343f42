"""Documents of many small fills (a scatter plot's circles and their hairline strokes): the
per-batch work that stands in for per-fill work (batch_arrays joining the paths' arrays,
PaintTable's rows of solid paints, prepare_items taking a group of fills at once,
build_batch writing a line's edge in place) against what each fill alone gives."""
import numpy as np

from vecmsaa.geometry.primitives import (CULL_MARGIN, NO_CULL, QUAD_FALLBACK_TOL, batch_arrays,
                                         build_batch)
from vecmsaa.raster import render as render_module
from vecmsaa.raster.render import RenderOptions, render_scene
from vecmsaa.raster.shaders import KIND_SOLID, PaintTable, solid_row
from vecmsaa.scene.nodes import Fill, Group, LinearGradient, Scene, Solid
from vecmsaa.scene.path import CLOSE, LINE, MOVE, Path


def polygon_paths(rng, n, shared=None):
    """n closed polygons of 3 to 6 points (some with an implicitly closed second subpath),
    a few empty; with ``shared``, the points of every other one a slice of one array, as the
    builder stores a batch of shapes."""
    paths = []
    for i in range(n):
        k = int(rng.integers(3, 7))
        pts = rng.uniform(-20, 120, (k, 2))
        verbs = [MOVE] + [LINE] * (k - 1) + [CLOSE]
        if i % 5 == 3:
            extra = rng.uniform(-20, 120, (3, 2))
            pts = np.vstack([pts, extra])
            verbs += [MOVE, LINE, LINE]                 # open: closed by build_batch
        if i % 7 == 6:
            pts, verbs = np.zeros((0, 2)), []
        if shared is not None and i % 2 == 0 and len(pts):
            start = len(shared[0])
            shared[0].extend(pts.tolist())
            paths.append((np.array(verbs, np.uint8), start, start + len(pts)))
        else:
            paths.append(Path.from_arrays(np.array(verbs, np.uint8), pts.reshape(-1, 2)))
    if shared is not None:
        store = np.array(shared[0], np.float64).reshape(-1, 2)
        paths = [p if isinstance(p, Path) else Path._of_arrays(p[0], store[p[1]:p[2]])
                 for p in paths]
    return paths


def test_batch_arrays_are_the_paths_arrays_joined():
    """Many paths, some of whose points are slices of one shared array: the verbs and
    points are each path's in turn and the offsets their running lengths, as uint8 and
    float64 (N, 2) arrays that are contiguous, aligned and writable (the kernels' argument
    types, and _shifted_arrays moves the points in place). A path whose points are not in
    the stored form (float32, a strided view) gives the same."""
    rng = np.random.default_rng(31)
    for odd in (None, "float32", "strided"):
        paths = polygon_paths(rng, 40, shared=[[]])
        if odd == "float32":
            paths[5] = Path._of_arrays(paths[5].verbs, paths[5].points.astype(np.float32))
        elif odd == "strided":
            wide = np.repeat(paths[5].points, 2, axis=0)
            paths[5] = Path._of_arrays(paths[5].verbs, wide[::2])
        verbs, pts, voff, poff = batch_arrays(paths)
        assert verbs.dtype == np.uint8 and pts.dtype == np.float64 and pts.shape[1:] == (2,)
        for a in (verbs, pts, voff, poff):
            assert a.flags.c_contiguous and a.flags.aligned and a.flags.writeable
        assert voff.tolist() == [0] + np.cumsum([len(p.verbs) for p in paths]).tolist()
        assert poff.tolist() == [0] + np.cumsum([len(p.points) for p in paths]).tolist()
        for i, p in enumerate(paths):
            assert verbs[voff[i]:voff[i + 1]].tolist() == p.verbs.tolist()
            assert pts[poff[i]:poff[i + 1]].tolist() == p.points.astype(np.float64).tolist()
        before = [p.points.copy() for p in paths]
        pts += 1.0                      # (the paths' own arrays are not the joined ones)
        assert all(np.array_equal(p.points, b) for p, b in zip(paths, before))


def test_build_batch_edges_of_polygons_are_their_sides():
    """build_batch of polygons: each path's edges are its sides in order, the closing side
    of each subpath (closed by CLOSE, by the next MOVE or at the path's end) included and
    zero-length sides and horizontal ones at an integer y left out; with a canvas, the sides
    wholly above, below or right of it (CULL_MARGIN beyond) left out too. Worked out here
    from the points."""
    rng = np.random.default_rng(8)
    paths = polygon_paths(rng, 30)
    # a repeated point: a zero-length side
    paths.append(Path.from_arrays(np.array([MOVE, LINE, LINE, LINE, CLOSE], np.uint8),
                                  np.array([[1.0, 1.0], [5.0, 1.0], [5.0, 1.0], [1.0, 6.0]])))
    canvas = np.array([0.0, 0.0, 100.0, 90.0])
    for clip in (NO_CULL, canvas):
        top, bottom, right = clip[1] - CULL_MARGIN, clip[3] + CULL_MARGIN, clip[2] + CULL_MARGIN
        edges, edge_off, prims, prim_off = build_batch(*batch_arrays(paths), 0.0, 1.0, clip)
        assert len(prims) == 0 and prim_off.tolist() == [0] * (len(paths) + 1)
        for i, p in enumerate(paths):
            want, start, cur, k = [], None, None, 0

            def side(a, b):
                if a == b or (a[1] == b[1] and a[1] == int(a[1])):
                    # (a point, or horizontal on a row boundary: primitives._no_edge)
                    return
                if (a[1] < top and b[1] < top) or (a[1] > bottom and b[1] > bottom) \
                        or (a[0] > right and b[0] > right):
                    return
                want.append((*a, *b))
            for v in p.verbs.tolist():
                if v == MOVE:
                    if start is not None:
                        side(cur, start)
                    start = cur = tuple(p.points[k].tolist())
                    k += 1
                elif v == LINE:
                    nxt = tuple(p.points[k].tolist())
                    side(cur, nxt)
                    cur = nxt
                    k += 1
                elif v == CLOSE:
                    side(cur, start)
                    cur, start = start, None
            if start is not None:
                side(cur, start)
            got = [tuple(e) for e in edges[edge_off[i]:edge_off[i + 1]].tolist()]
            assert got == want, i


def test_paint_table_of_many_solid_fills():
    """A table of many fills of solid paints (the rows found by maps over the fills): each
    fill's row is solid_row of its paint and opacity, and fills sharing a paint object and
    opacity share a parameter row (one per distinct pair, in order of first use). A table
    with a gradient among the solids gives each fill the same rows."""
    rng = np.random.default_rng(5)
    solids = [Solid(tuple(rng.uniform(0, 1, 4))) for _ in range(4)]
    fills = [Fill(Path(), solids[int(rng.integers(4))], opacity=[1.0, 0.5, 0.25][i % 3])
             for i in range(300)]
    table = PaintTable()
    table.add_fills(fills, None)
    pairs = list(dict.fromkeys((id(f.paint), f.opacity) for f in fills))
    assert len(table.params) == len(pairs)
    assert table.rows == [pairs.index((id(f.paint), f.opacity)) for f in fills]
    kinds, params, lut, tex = table.arrays()
    assert kinds.tolist() == [KIND_SOLID] * len(fills)
    assert params.tolist() == [solid_row(f.paint, f.opacity) for f in fills]
    gradient = LinearGradient(0, 0, 10, 0, np.array([(0, 1, 0, 0, 1), (1, 0, 0, 1, 1)], float))
    mixed = fills[:50] + [Fill(Path(), gradient)] + fills[50:]
    table = PaintTable()
    table.add_fills(mixed, None)
    kinds, params, _, _ = table.arrays()
    assert kinds[50] != KIND_SOLID
    assert np.delete(params, 50, axis=0).tolist() == [solid_row(f.paint, f.opacity)
                                                       for f in fills]


def test_a_group_of_fills_is_one_batch_in_paint_order():
    """prepare_items takes a group whose children are all fills at once (no turn of its loop
    per fill): the root's fills and a nested plain group's make one batch, in paint order,
    and a layer between them still ends the batch before it. The image is the one of the
    same fills each in a plain group of its own, which the loop gathers fill by fill."""
    rng = np.random.default_rng(2)
    paths = polygon_paths(rng, 24)
    paths = [p for p in paths if len(p.verbs)]
    colours = [Solid(tuple(rng.uniform(0, 1, 3)) + (0.7,)) for _ in paths]
    fills = [Fill(p, c) for p, c in zip(paths, colours)]
    layer = Group([Fill(paths[0], colours[1]), Fill(paths[1], colours[0])], opacity=0.5)
    root = Group(fills[:8] + [Group(fills[8:16])] + [layer] + fills[16:])
    items = render_module.prepare_items(root, RenderOptions())
    assert [type(i).__name__ for i in items] == ["FillBatch", "Layer", "FillBatch"]
    first, _, last = items
    for batch, group in ((first, fills[:16]), (last, fills[16:])):
        assert len(batch.box) == len(group)
        for box, f in zip(batch.box.tolist(), group):
            # (the points' extremes grown by QUAD_FALLBACK_TOL: FillBatch.box)
            tol = QUAD_FALLBACK_TOL
            assert box == [*(f.path.points.min(axis=0) - tol), *(f.path.points.max(axis=0) + tol)]
    scene = Scene(100, 90, root)
    one_by_one = Scene(100, 90, Group([Group([f]) for f in fills[:16]] + [layer]
                                      + [Group([f]) for f in fills[16:]]))
    assert np.array_equal(render_scene(scene), render_scene(one_by_one))
