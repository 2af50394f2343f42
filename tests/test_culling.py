"""Geometry outside the canvas costs (almost) nothing: build_batch draws a curve piece whose
control points' hull misses the canvas as its chord, and leaves out edges above, below or
right of it. Checked by counting what the batch builder makes (not by timing), and by the
pixels: the exact samples inside huge ellipses, and the same bytes as the unculled geometry."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_raster import polygon_path

from vecmsaa.geometry.primitives import NO_CULL, batch_arrays, build_batch
from vecmsaa.raster import render as render_module
from vecmsaa.raster.render import EXACT_TOLERANCE, MAX_SAGITTA, render_scene
from vecmsaa.raster.sample_patterns import pattern_offsets
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.svg.pathdata import parse_path_data
from vecmsaa.svg.shapes import ellipse_path

CANVAS = np.array([0.0, 0.0, 200.0, 200.0])


def built(path, canvas, exact=False):
    """(edges, lenses) build_batch makes of one path, in the sample modes or the exact ones."""
    edges, _, prims, _ = build_batch(*batch_arrays([path]), EXACT_TOLERANCE if exact else 0.0,
                                     MAX_SAGITTA, canvas)
    return len(edges), len(prims)


HUGE = {
    # around the canvas: every piece's hull misses it
    "circle": ellipse_path(100.0, 100.0, 1e6, 1e6),
    "arc": parse_path_data("M-1e6 100 A 1e6 2e6 0 1 1 -1e6 101 Z"),
    "cubic": parse_path_data("M-1e6 -1e6 C 3e6 -1e6 3e6 3e6 -1e6 3e6 Z"),
    "quad": parse_path_data("M-1e6 -1e6 Q 3e6 100 -1e6 1e6 Z"),
    # crossing it: only the pieces near the canvas are split
    "circle crossing": ellipse_path(100.0, 1e6 + 50.0, 1e6, 1e6),
    "arc crossing": parse_path_data("M0 100 a 1e6 5e5 10 1 0 1 1Z"),
    "cubic crossing": parse_path_data("M0 0 C 1e6 1e6 -1e6 1e6 0 200 Z"),
    "quad crossing": parse_path_data("M0 0 Q 1e6 1e6 0 200 Z"),
}


@pytest.mark.parametrize("exact", [False, True])
@pytest.mark.parametrize("name", HUGE)
def test_a_huge_curve_costs_what_the_canvas_shows_of_it(name, exact):
    """A million-pixel circle, arc, cubic or quadratic around or across a 200 px canvas is a
    few dozen edges and lenses, where unculled it is over a thousand (halved or cut until each
    piece bulges less than a pixel, up to 4096 pieces a curve, or 65536 segments flattened)."""
    edges, lenses = built(HUGE[name], CANVAS, exact)
    assert edges + lenses <= 64
    if "crossing" not in name:
        assert lenses == 0
    all_edges, all_lenses = built(HUGE[name], NO_CULL, exact)
    assert all_edges + all_lenses >= 1000


def test_edges_above_below_and_right_of_the_canvas_are_left_out():
    """Lines wholly above, below or right of the canvas add no winding to any sample in it and
    are dropped; those left of it count (a sample's winding is its row's crossings to its
    left) and are kept."""
    assert built(polygon_path([(10, -50), (190, -60), (100, -5)]), CANVAS)[0] == 0   # above
    assert built(polygon_path([(10, 250), (190, 260), (100, 205)]), CANVAS)[0] == 0   # below
    assert built(polygon_path([(210, 10), (260, 190), (300, 100)]), CANVAS)[0] == 0   # right
    assert built(polygon_path([(-10, 10), (-60, 190), (-30, 100)]), CANVAS)[0] == 3   # left
    # a triangle over the canvas's right edge: its edge right of it goes (its top is off
    # the row boundaries: a horizontal edge at an integer y goes anyway, primitives._no_edge)
    assert built(polygon_path([(150, 10.5), (300, 10.5), (300, 150)]), CANVAS)[0] == 2


def _render(path, w, h, mode="approx", samples=16):
    img = render_scene(Scene(w, h, Group([Fill(path, Solid((0, 0, 0, 1)))])), mode=mode,
                       samples=samples)
    return img[..., 3].astype(np.float64)


W, H = 24, 18


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 7.0), st.floats(0.05, 1.0), st.floats(0.0, 2 * math.pi),
       st.floats(-0.3, 0.3))
def test_huge_ellipses_cover_exactly_their_samples(log_r, aspect, angle, depth):
    """An axis-aligned ellipse of radii up to 1e7 px placed so that its edge runs through the
    canvas (a point of it at angle ``angle`` moved ``depth`` x the canvas inwards) covers
    exactly the samples inside it (16 a pixel, the approx mode): the culled pieces change no
    sample's winding. Pixels with a sample within 1e-6 px of the edge are not judged."""
    rx = 10 ** log_r + 2.0
    ry = rx * aspect
    cx = W / 2 - (rx + depth * W) * math.cos(angle)
    cy = H / 2 - (ry + depth * H) * math.sin(angle)
    got = _render(ellipse_path(cx, cy, rx, ry), W, H)
    off = pattern_offsets("d3d", 16)
    ys, xs = np.mgrid[0:H, 0:W]
    inside = np.zeros((H, W))
    near = np.zeros((H, W), bool)
    for ox, oy in off:
        u, v = (xs + 0.5 + ox - cx) / rx, (ys + 0.5 + oy - cy) / ry
        f = np.hypot(u, v)
        inside += f < 1.0
        # distance to the edge, to first order: |f − 1| over the gradient's length
        g = np.hypot(u / rx, v / ry) / np.maximum(f, 1e-300)
        near |= np.abs(f - 1.0) < 1e-6 * g
    truth = inside / len(off)
    assert np.abs(got - truth)[~near].max() < 1e-5


def _curves(draw_scale, rng):
    d = [f"M{rng.normal(0, draw_scale):.9g} {rng.normal(0, draw_scale):.9g}"]
    for _ in range(rng.integers(1, 4)):
        kind = rng.integers(0, 4)
        pts = " ".join(f"{rng.normal(10, draw_scale):.9g}" for _ in range((6, 4, 2, 0)[kind]))
        if kind == 0:
            d.append("C" + pts)
        elif kind == 1:
            d.append("Q" + pts)
        elif kind == 2:
            d.append("L" + pts)
        else:
            d.append(f"A{abs(rng.normal(0, draw_scale)):.9g} {abs(rng.normal(0, draw_scale)):.9g} "
                     f"{rng.uniform(0, 180):.6g} {rng.integers(0, 2)} {rng.integers(0, 2)} "
                     f"{rng.normal(10, draw_scale):.9g} {rng.normal(10, draw_scale):.9g}")
    return parse_path_data(" ".join(d) + "Z")


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.floats(0.0, 5.0),
       st.sampled_from(["approx", "alpha", "analytic"]))
def test_culled_geometry_draws_the_bytes_of_the_whole_geometry(seed, log_scale, mode):
    """Random paths of cubics, quadratics, lines and elliptical arcs from 1 to 1e5 px across,
    around a small canvas, draw byte for byte what they draw unculled (the culled pieces'
    lenses and the dropped edges are where no sample is). (Larger curves meet the unculled
    limits on their pieces, MAX_DEPTH and the like, where culled ones are split further.)"""
    rng = np.random.default_rng(seed)
    scene = Scene(W, H, Group([Fill(_curves(10 ** log_scale, rng), Solid((0.2, 0.4, 0.6, 0.9)),
                                    rule=rule) for rule in ("nonzero", "evenodd")]))
    culled = render_scene(scene, mode=mode)
    build = render_module.build_batch
    try:
        render_module.build_batch = lambda *a: build(*a[:-1], NO_CULL)
        whole = render_scene(scene, mode=mode)
    finally:
        render_module.build_batch = build
    if mode == "analytic":
        # exact area sums a row's cover from the edges left of the canvas: one chord for a
        # run of segments there rounds otherwise than their sum (1e-16 of a pixel)
        assert np.abs(culled - whole).max() < 1e-6
    else:
        assert np.array_equal(culled, whole)


def _disc_coverage(cx, cy, r, w, h, n=4000):
    """Area of disc and pixel for each pixel, integrated over n columns a pixel (midpoint
    rule: error below 1e-3 for these edges): the disc's extent at x is cy ± √((r − dx)(r + dx)),
    dx = x − cx, without the cancellation of the closed form's r² terms (tests/truth.py's
    ellipse_pixel_coverage is 1e-4 off at r = 1e6 and meaningless at 1e8)."""
    x = (np.arange(w * n) + 0.5) / n
    dx = x - cx
    s = np.sqrt(np.maximum((r - dx) * (r + dx), 0.0))
    lo, hi = cy - s, cy + s
    rows = np.arange(h)[:, None]
    inside = np.clip(np.minimum(hi, rows + 1.0) - np.maximum(lo, rows), 0.0, 1.0)
    return inside.reshape(h, w, n).mean(axis=2)


@pytest.mark.parametrize("r", [1e4, 1e6, 1e8])
@pytest.mark.parametrize("mode", ["analytic", "reference"])
def test_huge_circles_have_the_exact_area_where_they_cross_the_image(r, mode):
    """A circle of radius up to 1e8 px whose edge crosses the image at 30° is drawn with the
    area of circle and pixel: where it crosses, its pieces are halved to the exact modes'
    flatness (past the 2¹² pieces a whole curve may have: at r = 1e6 those were 0.015 px off
    the circle, 0.15 px at 1e8), and the rest of it is a few chords."""
    w, h = 20, 14
    a = math.radians(30)
    cx, cy = w / 2 - r * math.cos(a), h / 2 - r * math.sin(a)
    truth = _disc_coverage(cx, cy, r, w, h)
    assert 0 < truth.sum() < w * h
    got = _render(ellipse_path(cx, cy, r, r), w, h, mode)
    # chords within EXACT_TOLERANCE of the curve, at most √2 long in a pixel (as
    # tests/test_conics), plus the integration's error; 256 samples per pixel
    tol = EXACT_TOLERANCE * math.sqrt(2) + 1e-3 if mode == "analytic" else 0.02
    assert np.abs(got - truth).max() < tol
    assert sum(built(ellipse_path(cx, cy, r, r), np.array([0.0, 0.0, w, h]), True)) <= 100
