"""Dashes along curves placed where resvg (tiny-skia) and Chromium (Skia) place them.

Both measure a path with a contour measure rather than by exact arc length: a curve is halved
until its control points are within half a device pixel (in x and in y) of the chord's thirds
(a quadratic's control point: half its distance from the chord's midpoint), the length is the
sum of the chords, and a length inside a chord maps to the parameter linearly between the
chord's end parameters. usvg turns every circle, ellipse, rounded corner and path arc into
cubics first (kurbo's Arc::append_iter at a tolerance of 0.1 user units).

Truth here: that algorithm written again below from its description (recursive, on points
and parameters in [0, 1]), with kurbo's cubics made from the arcs' centres, radii and angles;
resvg 0.48.1's closing threshold of a dashed circle measured on its images; and the
renderer's own image of a solid circle. Never numbers copied from the dasher.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.geometry import stroke
from vecmsaa.geometry.stroke import arc_cubics, dash_length, dash_resolution
from vecmsaa.scene.path import CUBIC, MOVE
from vecmsaa.svg.pathdata import parse_path_data
from vecmsaa.svg.shapes import ellipse_path, rounded_rect_path


# -- the independent measure ----------------------------------------------------------------

def kurbo_arc(cx, cy, rx, ry, start, sweep, tolerance=0.1):
    """The cubics (4 control points each) kurbo makes of an axis-aligned elliptical arc."""
    n_err = max((1.1163 * max(rx, ry) / tolerance) ** (1 / 6), 3.999999)
    n = math.ceil(n_err * abs(sweep) / (2 * math.pi))
    step = sweep / n
    arm = 4 / 3 * math.tan(step / 4)

    def at(a):
        return np.array([cx + rx * math.cos(a), cy + ry * math.sin(a)])

    def tangent(a):
        return np.array([-rx * math.sin(a), ry * math.cos(a)])

    out = []
    for k in range(n):
        a0, a1 = start + k * step, start + (k + 1) * step
        out.append(np.array([at(a0), at(a0) + arm * tangent(a0), at(a1) - arm * tangent(a1),
                             at(a1)]))
    return out


def bezier_at(ctrl, t):
    pts = np.asarray(ctrl, float)
    while len(pts) > 1:
        pts = pts[:-1] + (pts[1:] - pts[:-1]) * t
    return pts[0]


def halves(ctrl):
    """de Casteljau at ½: the left and right halves' control points."""
    rows = [np.asarray(ctrl, float)]
    while len(rows[-1]) > 1:
        rows.append(0.5 * (rows[-1][:-1] + rows[-1][1:]))
    return [r[0] for r in rows], [r[-1] for r in reversed(rows)]


def too_curvy(ctrl, tol):
    p = np.asarray(ctrl, float)
    if len(p) == 3:
        off = p[1] / 2 - (p[0] + p[2]) / 4
        return np.abs(off).max() > tol
    return any(np.abs(p[0] + (p[3] - p[0]) * k / 3 - p[k]).max() > tol for k in (1, 2))


def chords(ctrl, tol, t0=0, t1=1 << 30, depth=0):
    """(chord length, parameter at its end) of a curve halved while too curvy (at most 20
    times, the measures' parameter resolution: spans of 2^30 units halved while ≥ 1024)."""
    if len(ctrl) == 2:
        return [(float(np.hypot(*(ctrl[1] - ctrl[0]))), 1.0)]
    if depth < 20 and too_curvy(ctrl, tol):
        left, right = halves(ctrl)
        mid = (t0 + t1) // 2
        return chords(left, tol, t0, mid, depth + 1) + chords(right, tol, mid, t1, depth + 1)
    return [(float(np.hypot(*(ctrl[-1] - ctrl[0]))), t1 / (1 << 30))]


class Measure:
    """A subpath of segments (control point arrays) measured by chords."""

    def __init__(self, segments, tol):
        self.rows = []                  # (distance at chord end, segment, t at end, t before)
        d = 0.0
        for i, seg in enumerate(segments):
            t_prev = 0.0
            for length, t in chords(seg, tol):
                if length > 0:
                    d += length
                    self.rows.append((d, i, t, t_prev))
                    t_prev = t
        self.segments = segments
        self.length = d

    def point(self, s):
        d0 = 0.0
        for d, i, t, t_prev in self.rows:
            if d >= s:
                return bezier_at(self.segments[i], t_prev + (t - t_prev) * (s - d0) / (d - d0))
            d0 = d
        return self.segments[-1][-1]

    def dash_ends(self, pattern, offset):
        """(start, end) points of the dashes of the subpath taken as open."""
        pattern = list(pattern) * (2 if len(pattern) % 2 else 1)
        period = sum(pattern)
        s, k = -(offset % period), 0
        out = []
        while s < self.length:
            a, b = max(s, 0.0), min(s + pattern[k], self.length)
            if k % 2 == 0 and b > a:
                out.append((self.point(a), self.point(b)))
            s += pattern[k]
            k = (k + 1) % len(pattern)
        return out


def dasher_ends(path, pattern, offset, resolution):
    """(start, end) points of the dasher's dashes, every subpath taken as open."""
    kinds, rows, subs, flags = stroke._path_segments(stroke.dash_curves(path, 0.0))
    kinds, rows, subs, flags = stroke.kernels.dash_segments(
        kinds, rows, subs, flags * 0, np.array(pattern, float), float(offset),
        0.5 / resolution)
    out = []
    for a, b in zip(subs[:-1], subs[1:]):
        last = 6 if kinds[b - 1] == 5 else 2 * kinds[b - 1] - 2     # (a conic: b0 b1 mid b2)
        out.append((rows[a, :2], rows[b - 1, last:last + 2]))
    return out


def circle_cubics(cx, cy, r):
    """usvg's circle: four arcs of +90° from angle 0 (y down), each kurbo's cubics."""
    return [c for k in range(4) for c in kurbo_arc(cx, cy, r, r, k * math.pi / 2, math.pi / 2)]


# -- tests ----------------------------------------------------------------------------------

@pytest.mark.parametrize("r, resolution", [(60, 1.0), (30, 2.0), (90, 0.5), (3, 1.0),
                                           (500, 1.0), (60, 7.3)])
def test_circle_length_is_the_chord_measure(r, resolution):
    closing = [circle_cubics(100, 100, r)[-1][-1], np.array([100.0 + r, 100.0])]
    truth = Measure(circle_cubics(100, 100, r) + [np.array(closing)], 0.5 / resolution)
    assert dash_length(ellipse_path(100, 100, r, r), resolution) == pytest.approx(
        truth.length, rel=1e-12)


@pytest.mark.parametrize("svg_r, transform, resvg_closes_at", [
    (60, "", 376.438), (30, "scale(2)", 188.218), (90, "scale(0.5)", 564.656)])
def test_circle_closes_where_resvg_closes_it(svg_r, transform, resvg_closes_at):
    """resvg 0.48.1 draws a circle with stroke-dasharray="X 10000" whole from these X on
    (found by bisection on its images, the gap turned to lie across its exact x coverage,
    to ±0.001): vecmsaa's measure of the circle under the same transform."""
    m = parse_transform_matrix(transform)
    got = dash_length(ellipse_path(100, 100, svg_r, svg_r), dash_resolution(m))
    assert got == pytest.approx(resvg_closes_at, abs=0.002)


def parse_transform_matrix(text):
    if not text:
        return (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    s = float(text[text.index("(") + 1:text.index(")")])
    return (s, 0.0, 0.0, s, 0.0, 0.0)


def test_dash_resolution_is_tiny_skias():
    # tiny-skia: the longer of the lengths of (sx, kx) and (ky, sy) of its transform, whose
    # x' = sx·x + kx·y + tx: SVG's (a, c) and (b, d)
    c, s = math.cos(0.5), math.sin(0.5)
    m = (2 * c, 2 * s, -0.5 * s, 0.5 * c, 10.0, 20.0)      # rotate(0.5 rad) scale(2, 0.5)
    assert dash_resolution(m) == pytest.approx(max(math.hypot(2 * c, 0.5 * s),
                                                   math.hypot(2 * s, 0.5 * c)))
    assert dash_resolution((0.0, 0.0, 0.0, 0.0, 0.0, 0.0)) == 1.0


#: name: (the path, its subpaths as usvg's curves, the circle its arcs lie on or None); the
#: dasher cuts circular arcs on the exact circle at the angles of usvg's curve's points
PATHS = {
    "circle": (lambda: ellipse_path(100, 100, 60, 60),
               lambda: [circle_cubics(100, 100, 60)], (100, 100, 60)),
    "big circle": (lambda: ellipse_path(0, 0, 500, 500), lambda: [circle_cubics(0, 0, 500)],
                   (0, 0, 500)),
    "ellipse": (lambda: ellipse_path(100, 100, 80, 30),
                lambda: [[c for k in range(4)
                          for c in kurbo_arc(100, 100, 80, 30, k * math.pi / 2, math.pi / 2)]],
                None),
    "rounded rect": (lambda: rounded_rect_path(10, 20, 150, 100, 30, 20), lambda: [
        [np.array([(40.0, 20.0), (130.0, 20.0)])]
        + kurbo_arc(130, 40, 30, 20, -math.pi / 2, math.pi / 2)
        + [np.array([(160.0, 40.0), (160.0, 100.0)])]
        + kurbo_arc(130, 100, 30, 20, 0, math.pi / 2)
        + [np.array([(130.0, 120.0), (40.0, 120.0)])]
        + kurbo_arc(40, 100, 30, 20, math.pi / 2, math.pi / 2)
        + [np.array([(10.0, 100.0), (10.0, 40.0)])]
        + kurbo_arc(40, 40, 30, 20, math.pi, math.pi / 2)], None),
    "quad and cubic": (lambda: parse_path_data("M 10 80 Q 50 -40 90 80 C 60 60 40 100 10 80"),
                       lambda: [[np.array([(10.0, 80.0), (50.0, -40.0), (90.0, 80.0)]),
                                 np.array([(90.0, 80.0), (60.0, 60.0), (40.0, 100.0),
                                           (10.0, 80.0)])]], None),
    "half-circle arcs": (lambda: parse_path_data("M 160 100 A 60 60 0 0 1 40 100 "
                                                 "A 60 60 0 0 1 160 100"),
                         lambda: [kurbo_arc(100, 100, 60, 60, 0, math.pi)
                                  + kurbo_arc(100, 100, 60, 60, math.pi, math.pi)],
                         (100, 100, 60)),
    "two subpaths": (lambda: parse_path_data("M 0 0 C 30 60 60 -60 90 0 M 0 50 Q 45 0 90 50"),
                     lambda: [[np.array([(0.0, 0.0), (30.0, 60.0), (60.0, -60.0), (90.0, 0.0)])],
                              [np.array([(0.0, 50.0), (45.0, 0.0), (90.0, 50.0)])]], None),
}


@pytest.mark.parametrize("name", sorted(PATHS))
@pytest.mark.parametrize("pattern, offset, resolution", [
    ([9.0, 4.5, 2.5, 4.5], 3.0, 1.0), ([20.0, 7.0], -12.5, 1.0), ([5.0, 3.0, 11.0], -40.0, 2.0),
    ([13.0, 6.0], 100.0, 0.37), ([7.0], 0.0, 3.0)])
def test_dash_ends_are_where_the_chord_measure_puts_them(name, pattern, offset, resolution):
    make_path, make_truth, circle = PATHS[name]
    tol = 0.5 / resolution
    expected = [e for sub in make_truth()
                for e in Measure(sub, tol).dash_ends(pattern, offset)]
    if circle:
        centre, r = np.array(circle[:2], float), circle[2]
        expected = [[centre + (p - centre) * r / np.hypot(*(p - centre)) for p in e]
                    for e in expected]
    got = dasher_ends(make_path(), stroke.dash_pattern(pattern), offset, resolution)
    assert len(got) == len(expected)
    err = max(np.abs(np.array(g) - np.array(e)).max() for g, e in zip(got, expected))
    assert err < 1e-12 * 500


def test_arc_cubics_are_kurbos():
    # a radius of 500 (tolerance 0.1): kurbo cuts each quarter in two
    cubic = arc_cubics(ellipse_path(0, 0, 500, 500))
    assert cubic.verbs.tolist() == [MOVE] + [CUBIC] * 8 + [cubic.verbs[-1]]
    truth = np.concatenate([c[1:] for c in circle_cubics(0, 0, 500)])
    assert np.abs(cubic.points[1:len(truth) + 1] - truth).max() < 1e-9
    # under ~367 units one cubic per quarter: Path.without_conics's own
    small = ellipse_path(0, 0, 300, 100)
    np.testing.assert_array_equal(arc_cubics(small).points, small.without_conics().points)


def test_dashed_circle_closes_at_its_measured_length():
    """A circle drawn with stroke-dasharray="X 10000": from X = the chord measure's length on,
    it is the solid circle's image; a little short of it, a gap shows."""
    truth = Measure(circle_cubics(100, 100, 60) + [np.array(
        [circle_cubics(100, 100, 60)[-1][-1], (160.0, 100.0)])], 0.5).length

    def draw(dasharray):
        dash = f' stroke-dasharray="{dasharray}"' if dasharray else ""
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">'
               f'<circle cx="100" cy="100" r="60" fill="none" stroke="black" '
               f'stroke-width="10" transform="rotate(90 100 100)"{dash}/></svg>')
        return render_svg_array(svg.encode())[..., 3].astype(int)

    solid = draw(None)
    assert np.abs(draw(f"{truth + 0.01} 10000") - solid).max() <= 2
    assert np.abs(draw(f"{truth - 0.4} 10000") - solid).max() > 60


def test_dots_on_a_circle_sit_where_the_chord_measure_puts_them():
    """Zero-length dashes with square caps are squares centred on the circle at the chord
    measure's lengths k·period (projected on the exact circle), turned along its tangent."""
    r, hw, cx, cy, period = 30.0, 1.0, 50.0, 50.0, 7.0
    circle = parse_path_data(f"M {cx + r} {cy} A {r} {r} 0 0 1 {cx - r} {cy} "
                             f"A {r} {r} 0 0 1 {cx + r} {cy} Z")
    out = stroke.stroke_path(circle, 2 * hw, cap="square", dashes=[0, period])
    truth = Measure(kurbo_arc(cx, cy, r, r, 0, math.pi) + kurbo_arc(cx, cy, r, r, math.pi, math.pi),
                    0.5)
    squares = out.points.reshape(-1, 4, 2)           # MOVE + 3 LINEs + CLOSE each
    assert len(squares) == int(truth.length // period) + 1
    for k, sq in enumerate(squares):
        p = truth.point(k * period)
        a = math.atan2(p[1] - cy, p[0] - cx)
        centre = sq.mean(0)
        assert centre == pytest.approx((cx + r * math.cos(a), cy + r * math.sin(a)), abs=1e-9)
        side = sq[1] - sq[0]
        assert abs(side[0] * math.cos(a) + side[1] * math.sin(a)) < 1e-9     # along it


@pytest.mark.parametrize("rx, ry", [(1e150, 1e150), (1e150, 3e149)])
def test_huge_arcs_are_cut_into_a_bounded_number_of_cubics(rx, ry):
    # kurbo's count grows as the radius^(1/6) without bound (3.5e25 cubics a turn here)
    path = ellipse_path(0, 0, rx, ry)
    assert len(arc_cubics(path).verbs) <= 2 + 4 * stroke.kernels.MAX_ARC_CUBICS
    out = stroke.stroke_path(path, 1e148, dashes=[1e149, 1e149], resolution=1e-140)
    assert not out.is_empty()
