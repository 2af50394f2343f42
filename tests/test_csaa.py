"""CSAA (``color_samples``): n coverage samples, at most K stored colours per pixel. Truth: plain
n-sample MSAA where no pixel needs more than K colours, and a brute-force per-sample model of
the documented table (raster.csaa) on the failure case, from exact point-in-triangle tests at
the pattern's samples; and the storage a split pixel is given, from the buffers' sizes."""
from __future__ import annotations

import numpy as np
import pytest

from vecmsaa.raster.render import Raster, RenderOptions, render_scene
from vecmsaa.tools.accuracy import figure1_scene
from vecmsaa.tools.csaa import fan_scene


def test_at_most_k_colours_a_pixel_is_n_sample_msaa_exactly():
    # Figure 1: red, green and blue cover the canvas, so a pixel holds at most 3 colours
    scene = figure1_scene(40)
    for mode in ("persample", "approx", "a2c"):
        plain = render_scene(scene, mode=mode, samples=16)
        assert np.array_equal(render_scene(scene, mode=mode, samples=16, color_samples=4), plain)
        assert np.array_equal(render_scene(scene, mode=mode, samples=16, color_samples=3), plain)


def _inside(x, y, tri):
    """Point in triangle, by the signs of the three edge functions (samples on an edge are
    reported, to be left out)."""
    (ax, ay), (bx, by), (cx, cy) = tri
    d = [(bx - ax) * (y - ay) - (by - ay) * (x - ax),
         (cx - bx) * (y - by) - (cy - by) * (x - bx),
         (ax - cx) * (y - cy) - (ay - cy) * (x - cx)]
    near = min(abs(v) for v in d) < 1e-7
    return (all(v > 0 for v in d) or all(v < 0 for v in d)), near


def _limit(colours, k):
    """The documented table, written independently: while more than k distinct colours, the one
    on the fewest samples (first appearing) joins its nearest (first appearing)."""
    colours = [tuple(c) for c in colours]
    while True:
        order = list(dict.fromkeys(colours))
        if len(order) <= k:
            return colours
        count = {c: colours.count(c) for c in order}
        u = min(order, key=lambda c: (count[c], order.index(c)))
        v = min((c for c in order if c != u),
                key=lambda c: (sum((np.float32(a) - np.float32(b)) ** 2 for a, b in zip(c, u)),
                               order.index(c)))
        colours = [v if c == u else c for c in colours]


@pytest.mark.parametrize("k", [1, 2, 4])
def test_more_colours_than_slots_follow_the_documented_table(k):
    scene = fan_scene(24, wedges=8, fans=2)
    opts = RenderOptions("persample", 16)
    img = render_scene(scene, mode="persample", samples=16, color_samples=k)
    plain = render_scene(scene, mode="persample", samples=16)
    tris = [((f.path.points[0]), (f.path.points[1]), (f.path.points[2]))
            for f in scene.root.children]
    paints = [np.float32(f.paint.color) for f in scene.root.children]
    checked = 0
    for py in range(scene.height):
        for px in range(scene.width):
            colours = [np.float32(scene.background)] * 16
            ambiguous = False
            for tri, paint in zip(tris, paints):
                covered = []
                for s in range(16):
                    inside, near = _inside(px + opts.sx[s], py + opts.sy[s], tri)
                    ambiguous |= near
                    if inside:
                        covered.append(s)
                if not covered:
                    continue
                for s in covered:
                    colours[s] = paint
                if len(covered) < 16:
                    colours = [np.float32(c) for c in _limit(colours, k)]
            if ambiguous:
                continue
            checked += 1
            want = np.mean(np.array(colours, dtype=np.float64), axis=0)
            assert np.abs(img[py, px] - want).max() < 1e-5, (px, py)
    assert checked > 0.8 * scene.width * scene.height
    # the failure case does fail: the fan centres (8 colours) differ from 16-sample MSAA
    assert np.abs(img - plain).max() > (0.1 if k <= 2 else 0.01)


def test_color_samples_must_fit_the_coverage_samples():
    with pytest.raises(ValueError):
        RenderOptions("approx", 4, color_samples=8)
    with pytest.raises(ValueError):
        RenderOptions("analytic", 8, color_samples=4)


def test_same_pixels_for_any_band_size_and_thread_count():
    """The colour table is per pixel, so bands and threads cannot change it."""
    scene = fan_scene(24, wedges=8, fans=2)
    whole = render_scene(scene, mode="approx", samples=16, color_samples=2)
    for rows in (1, 5):
        budget = rows * scene.width * 16
        assert np.array_equal(render_scene(scene, mode="approx", samples=16, color_samples=2,
                                           band_budget=budget, threads=2), whole)


@pytest.mark.parametrize("n, k", [(16, 1), (16, 2), (16, 4), (16, 8), (8, 2), (4, 3)])
def test_a_split_pixel_stores_k_colours_and_n_indices(n, k):
    """The raster's per-pixel sample storage, the arrays with a slot for every pixel of a strip
    (the pool of split pixels): n float32 RGBA colours a pixel for plain MSAA, K colours and an
    index byte per coverage sample for CSAA."""
    rows, width = 3, 10

    def pool_bytes(opts):
        return sum(a.nbytes for a in Raster(opts, width, 50, rows).scratch
                   if a.ndim > 1 and a.shape[0] == rows * width)
    assert pool_bytes(RenderOptions("approx", n)) == rows * width * 16 * n
    assert pool_bytes(RenderOptions("approx", n, color_samples=k)) == rows * width * (16 * k + n)
