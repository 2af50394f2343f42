"""Exact conics (issue 15): arcs, circles, ellipses and rounded corners as rational quadratics.

Truth here is the ellipse itself: its equation for every sample (point in ellipse) and the
exact area of ellipse ∩ pixel (tests/truth.py, closed form), never the renderer's output.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from truth import ellipse_pixel_coverage, segments, winding_at
from vecmsaa.raster.render import EXACT_TOLERANCE, render_scene
from vecmsaa.raster.sample_patterns import pattern_offsets
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.geometry.stroke import arc_cubics
from vecmsaa.scene.path import CONIC, CUBIC, MOVE, Path, conic_weight
from vecmsaa.svg.pathdata import parse_path_data
from vecmsaa.svg.shapes import ellipse_path, rounded_rect_path


def _on_ellipse(p, cx, cy, rx, ry):
    return ((p[:, 0] - cx) / rx) ** 2 + ((p[:, 1] - cy) / ry) ** 2


def _conic_points(path, t):
    """Points at parameter t of every conic of path, evaluated as rational quadratics."""
    v, p = path.verbs, path.points
    out = []
    k = 0
    cur = None
    for verb in v:
        n = (1, 1, 2, 3, 0, 3)[verb]
        if verb == CONIC:
            b0, b1, mid, b2 = cur, p[k], p[k + 1], p[k + 2]
            w = conic_weight(b0[None], b1[None], mid[None], b2[None])[0]
            a, b, c = (1 - t) ** 2, 2 * w * t * (1 - t), t * t
            out.append((a * b0 + b * b1 + c * b2) / (a + b + c))
        if n:
            cur = p[k + n - 1]
        k += n
    return np.array(out)


def test_circle_is_four_exact_quarter_conics():
    path = ellipse_path(3.0, -2.0, 5.0, 5.0)
    assert list(path.verbs).count(CONIC) == 4
    for t in np.linspace(0, 1, 11):
        assert _on_ellipse(_conic_points(path, t), 3.0, -2.0, 5.0, 5.0) == \
            pytest.approx(1.0, abs=1e-14)


def test_a_conic_stays_the_ellipse_under_an_affine_map():
    # rotate by 30°, scale (2, 0.5), shear: the image of the unit circle is the ellipse
    # {q : |A⁻¹ (q − t)| = 1}, and the stored conics must trace exactly it
    a = np.array([[2.0, 0.7], [0.3, 0.5]]) @ np.array([[math.cos(0.5), -math.sin(0.5)],
                                                       [math.sin(0.5), math.cos(0.5)]])
    m = (a[0, 0], a[1, 0], a[0, 1], a[1, 1], 4.0, -1.0)
    path = ellipse_path(0.0, 0.0, 1.0, 1.0).transformed(m)
    inv = np.linalg.inv(a)
    for t in np.linspace(0, 1, 11):
        q = (_conic_points(path, t) - [4.0, -1.0]) @ inv.T
        assert np.hypot(q[:, 0], q[:, 1]) == pytest.approx(1.0, abs=1e-13)


def test_arcs_are_conics_on_the_ellipse():
    # a rotated elliptical arc of 270° (SVG F.6.5: centre (50, 50) by construction)
    rx, ry, phi = 40.0, 20.0, math.radians(30)
    def on(t):
        x, y = rx * math.cos(t), ry * math.sin(t)
        return (50 + x * math.cos(phi) - y * math.sin(phi), 50 + x * math.sin(phi) + y * math.cos(phi))
    (x1, y1), (x2, y2) = on(0.0), on(1.5 * math.pi)
    path = parse_path_data(f"M{x1!r} {y1!r} A40 20 30 1 1 {x2!r} {y2!r}")
    assert list(path.verbs).count(CONIC) == 3
    for t in np.linspace(0, 1, 9):
        p = _conic_points(path, t) - 50.0
        x = p[:, 0] * math.cos(phi) + p[:, 1] * math.sin(phi)
        y = -p[:, 0] * math.sin(phi) + p[:, 1] * math.cos(phi)
        assert (x / rx) ** 2 + (y / ry) ** 2 == pytest.approx(1.0, abs=1e-12)


def test_consumers_of_beziers_get_the_cubic_that_the_arc_used_to_be():
    cubic = ellipse_path(0.0, 0.0, 1.0, 1.0).without_conics()
    assert CONIC not in cubic.verbs and list(cubic.verbs).count(CUBIC) == 4
    # the classic quarter-circle handle 4/3 (√2 − 1)
    assert cubic.points[1] == pytest.approx((1.0, 4 / 3 * (math.sqrt(2) - 1)), abs=1e-15)
    rr = rounded_rect_path(0, 0, 10, 6, 2, 1).without_conics()
    assert CONIC not in rr.verbs


@settings(max_examples=300, deadline=None)
@given(st.floats(-3.0, 5.0), st.floats(0.05, 1.0), st.floats(0.0, 2 * math.pi),
       st.floats(0.1, math.pi / 2), st.floats(-1.0, 1.0), st.integers(0, 3))
def test_arc_cubics_cut_each_arc_as_kurbo_and_stay_on_the_ellipse(log_r, aspect, start, sweep,
                                                                   shear, keep_mask):
    """Arcs of affine images of a circle (radii 1e-3 .. 1e5 units, sweeps up to 90°), as
    stroke.arc_cubics cuts them: n = ⌈max((1.1163·R/0.1)^(1/6), 3.999999)·θ/2π⌉ cubics for an
    arc of θ on an ellipse of larger radius R (kurbo's Arc::append_iter at usvg's tolerance,
    R from the affine map's singular values here), every piece's ends on the ellipse and its
    handles along the circle's tangents at 4/3·tan(θ/4n) (in the circle's frame); conics
    ``keep`` marks stay as they are, and one cubic is Path.without_conics's."""
    r = 10.0 ** log_r
    a = np.array([[r, shear * r], [0.0, aspect * r]]) @ np.array(
        [[math.cos(0.3), -math.sin(0.3)], [math.sin(0.3), math.cos(0.3)]])
    big = np.linalg.svd(a, compute_uv=False)[0]
    phis = [start, start + sweep, start + 2 * sweep]         # two arcs, one after the other
    unit = [np.array((math.cos(f), math.sin(f))) for f in phis]
    path = Path()
    path.moveTo(tuple(a @ unit[0] + (7.0, -3.0)))
    for f0, f1 in zip(phis, phis[1:]):
        mid = 0.5 * (f0 + f1)
        w = math.cos(0.5 * (f1 - f0))
        corner = np.array((math.cos(mid), math.sin(mid))) / w
        path.conicTo(tuple(a @ corner + (7.0, -3.0)), tuple(a @ np.array((math.cos(f1),
                     math.sin(f1))) + (7.0, -3.0)), w)
    keep = np.array([keep_mask & 1, keep_mask & 2], bool)
    got = arc_cubics(path, keep=keep)
    n = max(1, math.ceil(max((1.1163 * big / 0.1) ** (1 / 6), 3.999999) * sweep / (2 * math.pi)))
    verbs = [MOVE] + sum(([CONIC] if k else [CUBIC] * n for k in keep), [])
    assert got.verbs.tolist() == verbs
    inv = np.linalg.inv(a)
    pts, cur = got.points, 1
    for arc, (f0, f1) in enumerate(zip(phis, phis[1:])):
        if keep[arc]:
            np.testing.assert_array_equal(pts[cur:cur + 3], path.points[1 + 3 * arc:4 + 3 * arc])
            cur += 3
            continue
        step = (f1 - f0) / n
        for j in range(n):
            c = (pts[cur:cur + 3] - (7.0, -3.0)) @ inv.T          # in the unit circle's frame
            start_pt = (pts[cur - 1] - (7.0, -3.0)) @ inv.T
            e = np.array((math.cos(f0 + (j + 1) * step), math.sin(f0 + (j + 1) * step)))
            assert np.hypot(*(c[2] - e)) < 1e-9
            arm = 4 / 3 * math.tan(step / 4)
            t0 = np.array((-math.sin(f0 + j * step), math.cos(f0 + j * step)))
            t1 = np.array((-math.sin(f0 + (j + 1) * step), math.cos(f0 + (j + 1) * step)))
            assert np.hypot(*(c[0] - start_pt - arm * t0)) < 1e-9
            assert np.hypot(*(c[1] - e + arm * t1)) < 1e-9
            cur += 3
    if n == 1 and not keep.any():
        np.testing.assert_array_equal(got.points, path.without_conics().points)


def _render(path, w, h, mode, samples=16):
    img = render_scene(Scene(w, h, Group([Fill(path, Solid((0, 0, 0, 1)))])), mode=mode,
                       samples=samples)
    return img[..., 3].astype(np.float64)


def _sampled_truth(cx, cy, rx, ry, w, h, samples):
    """Fraction of each pixel's samples inside the ellipse (the point-in-ellipse test)."""
    off = pattern_offsets("d3d", samples)
    ys, xs = np.mgrid[0:h, 0:w]
    inside = np.zeros((h, w))
    for ox, oy in off:
        inside += (((xs + 0.5 + ox - cx) / rx) ** 2 + ((ys + 0.5 + oy - cy) / ry) ** 2) < 1.0
    return inside / len(off)


# sizes from a few pixels to a big circle whose edge crosses the window where a cubic quarter
# strays most (±22.5° from its ends: 2.7e-4 of the radius, 0.5 px here)
BIG = (16.0 - 2000.0 * math.cos(math.pi / 8), 12.0 + 2000.0 * math.sin(math.pi / 8), 2000.0,
       2000.0, 32, 24)
CASES = [(10.3, 9.7, 3.2, 3.2, 20, 20), (16.25, 15.6, 11.0, 6.5, 32, 32), BIG]


@pytest.mark.parametrize("mode", ["persample", "approx"])
@pytest.mark.parametrize("case", CASES)
def test_msaa_modes_hit_exactly_the_samples_inside_the_ellipse(mode, case):
    cx, cy, rx, ry, w, h = case
    truth = _sampled_truth(cx, cy, rx, ry, w, h, 16)
    conic = _render(ellipse_path(cx, cy, rx, ry), w, h, mode)
    assert truth.sum() > 0
    # float32 output: a sample is 1/16; allow only the rounding of the resolve
    assert np.abs(conic - truth).max() < 1e-5
    if rx > 1000:
        cubic = _render(ellipse_path(cx, cy, rx, ry).without_conics(), w, h, mode)
        assert np.abs(cubic - truth).max() > 0.05      # today's cubics miss samples


def test_exact_ellipse_coverage_agrees_with_a_brute_force_count():
    cx, cy, rx, ry = 5.3, 4.6, 4.1, 2.7
    cov = ellipse_pixel_coverage(cx, cy, rx, ry, 11, 9)
    assert cov.sum() == pytest.approx(math.pi * rx * ry, rel=1e-12)
    n = 200     # a 200 x 200 grid of points per pixel: error ≲ perimeter / n per pixel
    f = (np.arange(n) + 0.5) / n
    for py, px in [(4, 1), (1, 5), (7, 8), (4, 5), (2, 2)]:
        x, y = np.meshgrid(px + f, py + f)
        count = ((((x - cx) / rx) ** 2 + ((y - cy) / ry) ** 2) <= 1).mean()
        assert cov[py, px] == pytest.approx(count, abs=3e-3)


@pytest.mark.parametrize("case", CASES[:2])
@pytest.mark.parametrize("mode", ["analytic", "reference"])
def test_exact_area_modes_match_the_exact_area_of_ellipse_and_pixel(case, mode):
    cx, cy, rx, ry, w, h = case
    truth = ellipse_pixel_coverage(cx, cy, rx, ry, w, h)
    assert truth.sum() == pytest.approx(math.pi * rx * ry, rel=1e-12)
    got = _render(ellipse_path(cx, cy, rx, ry), w, h, mode)
    # analytic: chords within EXACT_TOLERANCE of the curve, at most √2 long in a pixel;
    # reference: 256 samples per pixel
    tol = EXACT_TOLERANCE * math.sqrt(2) + 1e-6 if mode == "analytic" else 0.02
    assert np.abs(got - truth).max() < tol


def test_conic_area_error_is_below_the_cubics_on_a_large_circle():
    cx, cy, rx, _, _, _ = BIG
    truth = ellipse_pixel_coverage(cx, cy, rx, rx, 32, 24)
    conic = _render(ellipse_path(cx, cy, rx, rx), 32, 24, "analytic")
    cubic = _render(ellipse_path(cx, cy, rx, rx).without_conics(), 32, 24, "analytic")
    e_conic, e_cubic = np.abs(conic - truth).max(), np.abs(cubic - truth).max()
    assert e_conic < EXACT_TOLERANCE * math.sqrt(2) < 0.1 < e_cubic


def test_rounded_rect_corners_wind_like_the_exact_rounded_rect():
    path = rounded_rect_path(1.0, 2.0, 20.0, 12.0, 6.0, 4.0)
    segs = segments(path)
    rng = np.random.default_rng(3)
    for x, y in rng.uniform([0, 1], [22, 15], size=(300, 2)):
        # exact rounded rectangle: inside the rect and inside the corner ellipse when in a corner
        qx = min(max(x, 7.0), 15.0)
        qy = min(max(y, 6.0), 10.0)
        inside = 1 <= x <= 21 and 2 <= y <= 14 and ((x - qx) / 6) ** 2 + ((y - qy) / 4) ** 2 <= 1
        assert abs(winding_at(segs, x, y)) == int(inside)


@pytest.mark.parametrize("mode", ["alpha", "a2c", "none", "persample", "approx"])
def test_every_mode_is_closer_to_a_large_ellipse_with_conics(mode):
    cx, cy, rx, ry, w, h = BIG
    ry = rx / 2
    cy = 12.0 + ry * math.sin(math.pi / 8)
    truth = ellipse_pixel_coverage(cx, cy, rx, ry, w, h)
    edge = (truth > 0) & (truth < 1)
    conic = ellipse_path(cx, cy, rx, ry)
    e_conic = np.abs(_render(conic, w, h, mode) - truth)[edge].mean()
    e_cubic = np.abs(_render(conic.without_conics(), w, h, mode) - truth)[edge].mean()
    assert e_conic < 0.6 * e_cubic
