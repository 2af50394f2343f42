"""An edge with a NaN y makes no winding in scan_edges: clamp_far_edges drops edges by their x
only, so one from a path with a NaN y coordinate reaches the scan, where its rows came out as
row 0 of the strip at y 0 (its bottom row from a NaN floor, 0) and its samples' crossings as
column 0 (a NaN crossing is no column past the row's end): ±1 added at the left of row 0 for
every sample, a band of wrong winding across the image. The same deltas and dirty pixels as
the path's edges without those, for NaN at the top, the bottom or both ends."""
from __future__ import annotations

import numpy as np
import pytest

from vecmsaa.geometry.primitives import NO_CULL, build_batch
from vecmsaa.raster.sample_patterns import standard_pattern
from vecmsaa.raster.scan import msaa_scratch, scan_edges
from vecmsaa.scene.path import CLOSE, LINE, MOVE


def scan(edges, sy0, rows, W, sx, sy):
    n = len(sx)
    delta, _, dirty, dlist, dcount = msaa_scratch(rows, W, n)[:5]
    scan_edges(edges, np.empty((0, 2)), 0, len(edges), sy0, rows, W, sx, sy, delta, dirty,
               dlist, dcount, np.zeros(rows, dtype=np.bool_), np.zeros(n, dtype=np.int64))
    marks = [sorted(dlist[r, :dcount[r]].tolist()) for r in range(rows)]
    return delta.copy(), (dirty != 0).copy(), marks


@pytest.mark.parametrize("where", [0, 1, 2])
def test_an_edge_with_a_nan_y_adds_no_winding(where):
    """A polygon one of whose points has a NaN y (``where``: the first, a middle one, or
    both coordinates of one), its edges built by build_batch: the
    scan of all of them gives what the scan of its edges with no NaN gives, in every strip
    (row 0 of the strip at 0 included), for 1 and 8 samples."""
    pts = [(2.5, 1.5), (9.25, 3.0), (7.0, 11.5), (1.0, 8.75)]
    if where == 0:
        pts[0] = (2.5, np.nan)
    elif where == 1:
        pts[2] = (7.0, np.nan)
    else:
        pts[1] = (np.nan, np.nan)
    verbs = np.array([MOVE, LINE, LINE, LINE, CLOSE], np.uint8)
    points = np.array(pts, np.float64)
    edges, _, _, _ = build_batch(verbs, points, np.array([0, 5]), np.array([0, 4]), 0.0, 1.0,
                                 NO_CULL)
    nan_y = np.isnan(edges[:, 1]) | np.isnan(edges[:, 3])
    assert nan_y.any() and not nan_y.all()
    finite = np.ascontiguousarray(edges[~nan_y])
    W, H, rows = 16, 16, 4
    for samples in (1, 8):
        offsets = standard_pattern(samples) if samples > 1 else np.zeros((1, 2))
        sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
        for sy0 in range(0, H, rows):
            got = scan(edges, sy0, rows, W, sx, sy)
            want = scan(finite, sy0, rows, W, sx, sy)
            assert np.array_equal(got[0], want[0]), (samples, sy0)
            assert np.array_equal(got[1], want[1]) and got[2] == want[2], (samples, sy0)


def test_edges_of_nan_alone_make_nothing():
    """Edges whose y are all NaN (and x NaN, finite, infinite) leave the strip at 0 clean:
    no delta, no dirty pixel."""
    edges = np.array([[0.0, np.nan, 3.0, np.nan], [np.nan, np.nan, np.nan, np.nan],
                      [1.0, 0.5, 2.0, np.nan], [1.0, np.nan, 2.0, 0.5],
                      [np.inf, np.nan, -np.inf, 2.0]])
    sx = sy = np.array([0.5])
    delta, dirty, marks = scan(edges, 0, 4, 8, sx, sy)
    assert not delta.any() and not dirty.any() and marks == [[]] * 4
