"""Temporal stability (vecmsaa.tools.sequence): the moving edge's exact coverage, and what
sampling theory says about the modes and patterns, measured on short sequences."""
from __future__ import annotations

import numpy as np
import pytest

from vecmsaa.tools.sequence import (EDGE_SLOPE, crawl, edge_frames, exact_edge_columns,
                                    flicker, motion, moved, render_frames, scenes)


def test_exact_edge_columns_match_brute_force_area():
    size, count = 16, 4
    exact = exact_edge_columns(size, count)
    xs = (np.arange(4096) + 0.5) / 4096                 # 4096 x positions per column
    for k in range(count):
        y0 = size / 2 + k / count
        for col in range(size):
            height = y0 + EDGE_SLOPE * (col + xs)       # the line over the column
            assert exact[k, col] == pytest.approx(np.mean(size - height), abs=1e-9)
    assert len(edge_frames(size, count)) == count


def test_exact_area_does_not_crawl_and_one_sample_does():
    analytic = crawl("analytic", 8, size=32, count=8)
    none = crawl("none", 8, size=32, count=8)
    assert max(abs(v) for v in analytic) < 1e-3
    assert none[1] > 0.1                                # a one-sample staircase


def test_rooks_pattern_crawls_less_than_the_ordered_grid_on_a_near_horizontal_edge():
    # the D3D 16 pattern puts every sample on its own sixteenth of the pixel's height
    # (n-rooks): an edge moving down 1/16 px a frame crosses one sample row per frame, so its
    # position error stays within half a row; an ordered grid has 4 rows and jumps by 4
    # samples every fourth frame (RTR3 §5.6)
    rooks = crawl("persample", 16, "d3d", size=32, count=16)
    grid = crawl("persample", 16, "grid", size=32, count=16)
    assert rooks[1] < grid[1] / 2 and rooks[2] < grid[2] / 1.5
    # ...and the pattern is centred (its table's offsets average (-1/32, -1/32) px, moved
    # back): the image sits where the geometry is
    assert rooks[0] == pytest.approx(0, abs=1e-6)


def test_flicker_is_zero_for_a_still_sequence_and_falls_with_more_samples():
    size = 32
    scene = scenes(size)["figure1"]
    still = [moved(scene, motion("pan", 0.0, size)) for _ in range(3)]
    reference = render_frames(still, "reference", 256)
    assert flicker(render_frames(still, "approx", 8), reference) == (0.0, 0.0)
    frames = [moved(scene, motion("pan", k / 7, size)) for k in range(8)]
    reference = render_frames(frames, "reference", 256)
    one = flicker(render_frames(frames, "none", 1), reference)[0]
    sixteen = flicker(render_frames(frames, "persample", 16), reference)[0]
    assert sixteen < one / 2


def test_shared_samples_crawl_like_more_samples_than_they_store():
    """Quincunx and FLIPQUAD store 2 samples but resolve 5 and 4 on 3 and 4 distinct rows: a
    near-horizontal edge crawls less than with the 2-sample ordered grid (1 row), and they see
    the edge's continuation beyond the image (no offset from the border columns)."""
    grid = crawl("persample", 2, "grid", size=32, count=16)
    for pattern in ("quincunx", "flipquad"):
        shared = crawl("persample", 2, pattern, size=32, count=16)
        assert shared[1] < 0.6 * grid[1], (pattern, shared, grid)
        assert abs(shared[0]) < 0.02
