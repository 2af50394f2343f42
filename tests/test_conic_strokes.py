"""Exact strokes of circular arcs (issue 15): the offset of an arc of radius r by ±w/2 is the
concentric arc of radius r ± w/2, so a stroked circle is two exact circles. (Its dashes are
placed as resvg places them: tests/test_dash_measure.py.)

Truth here is the geometry: the two circles' equations, the exact area of a ring ∩ pixel (two
discs' closed-form areas, tests/truth.py), the samples inside the ring; never the renderer's output.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from truth import ellipse_pixel_coverage
from vecmsaa.geometry.stroke import stroke_path
from vecmsaa.raster.render import EXACT_TOLERANCE, render_scene
from vecmsaa.raster.sample_patterns import pattern_offsets
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import CLOSE, CONIC, LINE, MOVE, VERB_POINTS, conic_weight
from vecmsaa.svg.shapes import ellipse_path, rounded_rect_path


def _pieces(path, t):
    """(conic points at parameters t, each as rational quadratic; lines as (start, end));
    per subpath."""
    subs, cur, k = [], None, 0
    for verb in path.verbs:
        n = VERB_POINTS[verb]
        p = path.points[k:k + n]
        if verb == MOVE:
            subs.append(([], []))
        elif verb == CONIC:
            b0, b1, mid, b2 = cur, p[0], p[1], p[2]
            w = conic_weight(b0[None], b1[None], mid[None], b2[None])[0]
            a, b, c = (1 - t) ** 2, 2 * w * t * (1 - t), t * t
            subs[-1][0].append((a[:, None] * b0 + b[:, None] * b1 + c[:, None] * b2)
                               / (a + b + c)[:, None])
        elif verb == LINE:
            subs[-1][1].append((cur, p[0]))
        if n:
            cur = p[n - 1]
        k += n
    return subs


def _render(path, w, h, mode, samples=16):
    img = render_scene(Scene(w, h, Group([Fill(path, Solid((0, 0, 0, 1)))])), mode=mode,
                       samples=samples)
    return img[..., 3].astype(np.float64)


@pytest.mark.parametrize("r, width", [(40.0, 6.0), (3.5, 1.0), (1000.0, 0.5), (10.0, 19.0)])
def test_a_stroked_circle_is_two_exact_circles(r, width):
    cx, cy, hw = 50.3, 49.8, width / 2
    out = stroke_path(ellipse_path(cx, cy, r, r), width)
    assert set(out.verbs.tolist()) <= {MOVE, CONIC, LINE, CLOSE}
    subs = _pieces(out, np.linspace(0, 1, 33))
    assert len(subs) == 2
    radii = []
    for conics, lines in subs:
        pts = np.vstack(conics)
        d = np.hypot(pts[:, 0] - cx, pts[:, 1] - cy)
        radii.append(d.mean())
        assert np.abs(d - d.mean()).max() < 1e-9 * r
        for a, b in lines:          # only where two offsets meet to rounding
            assert math.hypot(*(b - a)) < 1e-9 * r
    assert sorted(radii) == pytest.approx([r - hw, r + hw], rel=1e-12)


def test_rounded_corners_stroke_as_exact_arcs():
    x, y, w, h, rr, hw = 10.0, 12.0, 60.0, 40.0, 8.0, 1.5
    out = stroke_path(rounded_rect_path(x, y, w, h, rr, rr), 2 * hw)
    corners = np.array([(x + rr, y + rr), (x + w - rr, y + rr), (x + w - rr, y + h - rr),
                        (x + rr, y + h - rr)])
    n = 0
    for conics, _ in _pieces(out, np.linspace(0, 1, 17)):
        for pts in conics:
            c = corners[np.argmin(np.hypot(*(corners - pts.mean(0)).T))]
            d = np.hypot(*(pts - c).T)
            assert np.abs(d - d[0]).max() < 1e-9
            assert d[0] == pytest.approx(rr - hw, rel=1e-12) or \
                d[0] == pytest.approx(rr + hw, rel=1e-12)
            n += 1
    assert n == 8


def test_ellipses_and_arcs_narrower_than_the_stroke_stay_cubic():
    assert CONIC not in stroke_path(ellipse_path(50, 50, 30, 20), 4).verbs
    # r ≤ w/2: the inner offset would fold; the cubic stroker covers the whole disc
    out = stroke_path(ellipse_path(50, 50, 4, 4), 10, tolerance=0.02)
    assert CONIC not in out.verbs
    cov = _render(out, 100, 100, "analytic")
    truth = ellipse_pixel_coverage(50, 50, 9, 9, 100, 100)
    assert np.abs(cov - truth).max() < 0.05     # within the stroker's tolerance


def _ring_samples(cx, cy, r0, r1, w, h, samples):
    off = pattern_offsets("d3d", samples)
    ys, xs = np.mgrid[0:h, 0:w]
    inside = np.zeros((h, w))
    for ox, oy in off:
        d2 = (xs + 0.5 + ox - cx) ** 2 + (ys + 0.5 + oy - cy) ** 2
        inside += (d2 < r1 * r1) & ~(d2 < r0 * r0)
    return inside / len(off)


# a small ring whole; a big one in a window where its edge runs at 22.5° (a cubic quarter's
# worst place)
BIG_R = 2000.0
RING_CASES = [(16.3, 15.8, 9.0, 4.0, 32, 32),
              (16.0 - BIG_R * math.cos(math.pi / 8), 12.0 + BIG_R * math.sin(math.pi / 8), BIG_R,
               6.0, 32, 24)]


@pytest.mark.parametrize("mode", ["persample", "approx"])
@pytest.mark.parametrize("case", RING_CASES)
def test_msaa_modes_hit_exactly_the_samples_inside_the_ring(mode, case):
    cx, cy, r, width, w, h = case
    hw = width / 2
    truth = _ring_samples(cx, cy, r - hw, r + hw, w, h, 16)
    circle = ellipse_path(cx, cy, r, r)
    got = _render(stroke_path(circle, width), w, h, mode)
    assert truth.sum() > 0
    assert np.abs(got - truth).max() < 1e-5
    if r > 1000:
        cubic = _render(stroke_path(circle.without_conics(), width), w, h, mode)
        assert np.abs(cubic - truth).max() > 0.05       # the cubics miss samples


@pytest.mark.parametrize("case", RING_CASES)
def test_exact_area_mode_matches_the_ring_area_in_every_pixel(case):
    cx, cy, r, width, w, h = case
    hw = width / 2
    truth = ellipse_pixel_coverage(cx, cy, r + hw, r + hw, w, h) - \
        ellipse_pixel_coverage(cx, cy, r - hw, r - hw, w, h)
    circle = ellipse_path(cx, cy, r, r)
    got = _render(stroke_path(circle, width), w, h, "analytic")
    # chords within EXACT_TOLERANCE of each circle, at most √2 long in a pixel: twice
    tol = 2 * EXACT_TOLERANCE * math.sqrt(2) + 1e-6
    assert np.abs(got - truth).max() < tol
    if r > 1000:
        cubic = _render(stroke_path(circle.without_conics(), width), w, h, "analytic")
        assert np.abs(cubic - truth).max() > 2 * tol
