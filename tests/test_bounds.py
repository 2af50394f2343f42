"""scene.bounds.path_bounds against exact geometry: the extrema of the curves themselves (the
roots of their derivatives, found here by numpy's polynomial roots), and dense sampling."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vecmsaa.scene.bounds import path_bounds
from vecmsaa.scene.path import Path

coord = st.floats(-100, 100, allow_nan=False)
point = st.tuples(coord, coord)
# coordinates in the tens of thousands: a quadratic raised to a cubic has A = 0 only to
# rounding there, ~1e-11, and its quadratic formula then cancels (the x extremum of the first
# example came out at -22645 for -24551)
far = st.tuples(st.floats(-1e5, 1e5), st.floats(-1e5, 1e5))


def bezier(ctrl, t):
    """Points of a Bézier of any degree at parameters t, by de Casteljau."""
    pts = [np.outer(np.ones_like(t), c) for c in np.asarray(ctrl, float)]
    while len(pts) > 1:
        pts = [(1 - t)[:, None] * a + t[:, None] * b for a, b in zip(pts, pts[1:])]
    return pts[0]


def exact_box(ctrl):
    """The box of a Bézier: its ends and its points where a coordinate's derivative is zero
    (real roots in (0, 1) of the derivative's power-basis polynomial)."""
    ctrl = np.asarray(ctrl, float)
    n = len(ctrl) - 1
    ts = [0.0, 1.0]
    for axis in range(2):
        # the derivative's Bernstein coefficients, turned into a power-basis polynomial
        d = n * np.diff(ctrl[:, axis])
        poly = np.zeros(n)
        for i, c in enumerate(d):
            k = n - 1
            for j in range(i, k + 1):
                poly[j] += c * math.comb(k, i) * math.comb(k - i, j - i) * (-1) ** (j - i)
        poly = np.trim_zeros(poly[::-1], "f")       # highest power first
        if len(poly) > 1:
            for r in np.roots(poly):
                if abs(r.imag) < 1e-9 and 0 < r.real < 1:
                    ts.append(r.real)
    p = bezier(ctrl, np.array(ts))
    return (*p.min(axis=0), *p.max(axis=0))


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


@settings(max_examples=300, deadline=None)
@given(point, point, point, point)
def test_cubic_bounds_are_the_curves_extrema(p0, p1, p2, p3):
    path = Path()
    path.moveTo(p0)
    path.curveTo(p1, p2, p3)
    box = path_bounds(path)
    assert close(box, exact_box([p0, p1, p2, p3]), 1e-6)
    # no sampled point lies outside, and every side is reached by a sample (to the distance
    # a sample step can miss an extremum by: |B''| ≤ 6 · 400, step² / 8)
    s = bezier([p0, p1, p2, p3], np.linspace(0, 1, 4001))
    assert (s.min(axis=0) >= np.array(box[:2]) - 1e-9).all()
    assert (s.max(axis=0) <= np.array(box[2:]) + 1e-9).all()
    assert close(box, (*s.min(axis=0), *s.max(axis=0)), 2400 / 4000 ** 2 / 8 + 1e-9)


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.tuples(point, point, point), st.tuples(far, far, far)))
def test_quadratic_bounds_are_the_curves_extrema(ctrl):
    path = Path()
    path.moveTo(ctrl[0])
    path.qCurveTo(*ctrl[1:])
    scale = max(1.0, *(abs(v) for p in ctrl for v in p))
    assert close(path_bounds(path), exact_box(ctrl), 1e-8 * scale)


def test_quadratic_far_from_the_origin():
    ctrl = [(0.7057173803747319, -9677.641462626469), (-48704.06507368092, -2.0),
            (-790.7406211201842, 0.927825246302275)]
    path = Path()
    path.moveTo(ctrl[0])
    path.qCurveTo(*ctrl[1:])
    # x(t) = (1 - t)² x0 + 2t(1 - t) x1 + t² x2 is least where x'(t) = 0
    (x0, _), (x1, _), (x2, _) = ctrl
    t = (x0 - x1) / (x0 - 2 * x1 + x2)
    want = (1 - t) ** 2 * x0 + 2 * t * (1 - t) * x1 + t * t * x2
    assert path_bounds(path)[0] == pytest.approx(want, rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("LQC"), point, point, point), min_size=1, max_size=6),
       point, st.tuples(*[st.floats(-3, 3)] * 4 + [coord, coord]))
def test_path_bounds_under_a_matrix_are_those_of_the_mapped_curves(segs, start, m):
    a, b, c, d, e, f = m
    mapped = lambda p: (a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f)   # noqa: E731
    path, boxes, cur = Path(), [], start
    path.moveTo(start)
    boxes.append((*mapped(start), *mapped(start)))
    for kind, p1, p2, p3 in segs:
        ctrl = {"L": [cur, p1], "Q": [cur, p1, p2], "C": [cur, p1, p2, p3]}[kind]
        {"L": path.lineTo, "Q": path.qCurveTo, "C": path.curveTo}[kind](*ctrl[1:])
        boxes.append(exact_box([mapped(p) for p in ctrl]))   # an affine map of a Bézier is
        cur = ctrl[-1]                                         # the Bézier of mapped points
    want = (min(bx[0] for bx in boxes), min(bx[1] for bx in boxes),
            max(bx[2] for bx in boxes), max(bx[3] for bx in boxes))
    assert close(path_bounds(path, m), want, 1e-6)


@pytest.mark.parametrize("start_deg", [0.0, 30.0, 77.0])
def test_circle_of_conics_has_the_circles_box(start_deg):
    # four quarter arcs as conics (weight cos 45°) starting anywhere on a circle of radius 50
    # about (10, -20): the box is the circle's, to the 3e-4 of the radius by which a conic's
    # cubic (what bounds count) may stray from the arc
    cx, cy, r = 10.0, -20.0, 50.0
    at = lambda deg: (cx + r * math.cos(math.radians(deg)), cy + r * math.sin(math.radians(deg)))
    path = Path()
    path.moveTo(at(start_deg))
    for q in range(4):
        a0 = start_deg + 90 * q
        corner = (cx + r * math.sqrt(2) * math.cos(math.radians(a0 + 45)),
                  cy + r * math.sqrt(2) * math.sin(math.radians(a0 + 45)))
        path.conicTo(corner, at(a0 + 90), math.cos(math.radians(45)))
    path.closePath()
    box = path_bounds(path)
    assert close(box, (cx - r, cy - r, cx + r, cy + r), 3e-4 * r)
    # and under a matrix: scaled by 2 and 3 and moved, an ellipse's box
    sbox = path_bounds(path, (2.0, 0.0, 0.0, 3.0, 5.0, 7.0))
    assert close(sbox, (2 * (cx - r) + 5, 3 * (cy - r) + 7, 2 * (cx + r) + 5, 3 * (cy + r) + 7),
                 3 * 3e-4 * r)


def test_empty_and_degenerate_paths():
    assert path_bounds(Path()) is None
    p = Path()
    p.moveTo((3.0, 4.0))
    assert path_bounds(p) == (3.0, 4.0, 3.0, 4.0)
    p.lineTo((-1.0, 9.0))
    p.closePath()
    assert path_bounds(p) == (-1.0, 4.0, 3.0, 9.0)


class _El:
    def __init__(self, tag, **attrs):
        self.tag, self.attrs = tag, {k: str(v) for k, v in attrs.items()}


def _length(el):
    def get(name, axis, default=None):
        v = el.attrs.get(name)
        return default if v is None else float(v)
    return get


@pytest.mark.parametrize("el, want", [
    (_El("rect", x=-791.6, y=276.8, width=36.8, height=973.9, rx=5.4e-5, ry=0.019),
     (-791.6, 276.8, -791.6 + 36.8, 276.8 + 973.9)),
    (_El("rect", x=10, y=20, width=30, height=40, rx=100), (10.0, 20.0, 40.0, 60.0)),
    (_El("rect", x=10, y=20, width=30, height=0), None),
    (_El("circle", cx=-552.8, cy=3.5, r=138.8), (-552.8 - 138.8, 3.5 - 138.8,
                                                 -552.8 + 138.8, 3.5 + 138.8)),
    (_El("circle", cx=1, cy=1, r=0), None),
    (_El("ellipse", cx=5, cy=6, rx=2), (3.0, 4.0, 7.0, 8.0)),        # ry auto: rx
    (_El("ellipse", cx=5, cy=6, rx=-1, ry=3), (2.0, 3.0, 8.0, 9.0)),  # rx auto: ry
    (_El("ellipse", cx=5, cy=6), None),
])
def test_shape_box_is_the_shapes_geometry(el, want):
    # SVG 2 §8.2 (rect), §9.2-9.3 (circle, ellipse): the box of the rectangle or ellipse the
    # attributes describe, rounded corners or not; None where the shape renders nothing
    from vecmsaa.svg.shapes import shape_box, shape_path
    assert shape_box(el, _length(el)) == want
    path = shape_path(el, _length(el))
    if want is None:
        assert path is None
    else:       # the outline's box (its conics counted as cubics) agrees to rounding
        assert close(path_bounds(path), want, 1e-12 * max(abs(v) for v in want))
