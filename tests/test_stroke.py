"""Stroking, dashing and marker vertices, checked against geometry computed independently:
exact areas, distances to the source curve, the SVG miter/cap/dash rules."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from numba import njit

from vecmsaa.scene.path import (CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path,
                               conic_weight)
from vecmsaa.svg.markers import auto_angle, marker_vertices
from vecmsaa.geometry import hypot
from vecmsaa.geometry.stroke import dash_pattern, stroke_path
from vecmsaa.svg.pathdata import parse_path_data, parse_path_data_with_commands


# -- independent geometry: flattening, winding numbers, distances ---------------------------

def _bezier(ctrl, ts):
    ctrl = np.asarray(ctrl, dtype=np.float64)
    pts = np.repeat(ctrl[None], len(ts), axis=0)
    t = ts[:, None, None]
    while pts.shape[1] > 1:
        pts = pts[:, :-1] + (pts[:, 1:] - pts[:, :-1]) * t
    return pts[:, 0]


def _conic(b0, b1, mid, b2, ts):
    """Points of the rational quadratic (b0, b1, b2) whose point at t = ½ is mid (the weight
    on b1 as scene.path stores it)."""
    w = float(conic_weight(b0[None], b1[None], mid[None], b2[None])[0])
    t = ts[:, None]
    a, b, c = (1 - t) ** 2, 2 * w * t * (1 - t), t ** 2
    return (a * b0 + b * b1 + c * b2) / (a + b + c)


def contours(path, per_curve=64):
    """Closed polylines of a path (every subpath closed, as filling does)."""
    return [c for c, _ in _polylines(path, per_curve)]


def source_polylines(path, per_curve):
    """Polylines of a path as stroked: a closed subpath includes its closing segment."""
    return [np.vstack([c, c[:1]]) if closed else c for c, closed in _polylines(path, per_curve)]


def _polylines(path, per_curve):
    out, cur = [], None
    i = 0
    ts = np.linspace(0, 1, per_curve + 1)[1:]
    for v in path.verbs:
        n = VERB_POINTS[v]
        p = path.points[i:i + n]
        i += n
        if v == MOVE:
            cur = [p[0]]
            out.append([cur, False])
        elif v == LINE:
            cur.append(p[0])
        elif v in (QUAD, CUBIC):
            cur.extend(_bezier(np.vstack([cur[-1][None], p]), ts))
        elif v == CONIC:
            cur.extend(_conic(np.asarray(cur[-1]), p[0], p[1], p[2], ts))
        elif v == CLOSE:
            out[-1][1] = True
    return [(np.asarray(c), closed) for c, closed in out if len(c) > 1]


def winding(path, q):
    """Nonzero winding number of the (flattened) path at points q (M, 2)."""
    q = np.asarray(q, dtype=np.float64)
    w = np.zeros(len(q), dtype=np.int64)
    cs = contours(path)
    if not cs:
        return w
    a = np.vstack(cs)
    b = np.vstack([np.roll(c, -1, axis=0) for c in cs])
    qx, qy = q[:, 0:1], q[:, 1:2]
    for lo in range(0, len(a), 256):
        ax, ay = a[lo:lo + 256, 0][None], a[lo:lo + 256, 1][None]
        bx, by = b[lo:lo + 256, 0][None], b[lo:lo + 256, 1][None]
        side = (bx - ax) * (qy - ay) - (qx - ax) * (by - ay)
        up = (ay <= qy) & (by > qy) & (side > 0)
        down = (ay > qy) & (by <= qy) & (side < 0)
        w += up.sum(axis=1) - down.sum(axis=1)
    return w


def inside(path, q):
    return winding(path, q) != 0


def distance_to_polylines(q, polys):
    """Exact distance from points q to a set of polylines."""
    q = np.asarray(q, dtype=np.float64)
    best = np.full(len(q), np.inf)
    for poly in polys:
        a, b = poly[:-1], poly[1:]
        ab = b - a
        l2 = (ab ** 2).sum(-1)
        l2 = np.where(l2 > 0, l2, 1)
        for lo in range(0, len(q), 256):
            qq = q[lo:lo + 256, None]
            t = np.clip(((qq - a) * ab).sum(-1) / l2, 0, 1)
            d2 = ((qq - (a + ab * t[..., None])) ** 2).sum(-1).min(axis=1)
            best[lo:lo + 256] = np.minimum(best[lo:lo + 256], np.sqrt(d2))
    return best


def grid_area(path, box, step):
    x0, y0, x1, y1 = box
    xs = np.arange(x0 + step / 2, x1, step)
    ys = np.arange(y0 + step / 2, y1, step)
    gx, gy = np.meshgrid(xs, ys)
    q = np.column_stack([gx.ravel(), gy.ravel()])
    return inside(path, q).sum() * step * step


def line(*pts, close=False):
    p = Path()
    p.moveTo(pts[0])
    for q in pts[1:]:
        p.lineTo(q)
    if close:
        p.closePath()
    else:
        p.endPath()
    return p


def polygon_area(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


# -- basic shapes ----------------------------------------------------------------------------

def test_straight_line_is_exact_rectangle():
    length, w = math.hypot(30, 40), 3.0
    out = stroke_path(line((10, 20), (40, 60)), w)
    cs = contours(out)
    assert len(cs) == 1
    assert polygon_area(cs[0]) == pytest.approx(length * w, rel=1e-12)


def test_polyline_miter_areas_exact():
    # open L shape: union of [0, 11]x[-1, 1] and [9, 11]x[-1, 10]
    out = stroke_path(line((0, 0), (10, 0), (10, 10)), 2, join="miter")
    assert sum(polygon_area(c) for c in contours(out)) == pytest.approx(40.0, rel=1e-12)
    # closed square: the square ring between side 12 and side 8. Its edges lie on integer
    # lines, so counting cell centres of a 0.25 grid measures its area exactly.
    out = stroke_path(line((0, 0), (10, 0), (10, 10), (0, 10), close=True), 2, join="miter")
    assert grid_area(out, (-2, -2, 12, 12), 0.25) == 144.0 - 64.0
    assert not inside(out, [(5, 5)])[0] and inside(out, [(5, 0.5), (10.9, 10.9)]).all()


@pytest.mark.parametrize("join", ["miter", "round", "bevel"])
def test_winding_never_negative(join):
    # the outline is a sum of positive pieces: a negative winding anywhere would mean a piece
    # turned the wrong way (harmless for nonzero only by luck)
    out = stroke_path(parse_path_data("M0 0 C 50 100 100 -50 150 50 L 160 0 Q 100 30 90 90 Z "
                                      "M 10 10 L 12 11 L 11 13 L 40 5 L 10 10"), 8,
                      join=join, cap="round")
    gx, gy = np.meshgrid(np.arange(-10, 170, 0.7), np.arange(-30, 110, 0.7))
    w = winding(out, np.column_stack([gx.ravel(), gy.ravel()]))
    assert w.min() >= 0 and w.max() >= 1


def test_circle_stroke_is_annulus():
    r, w = 40.0, 10.0
    circle = parse_path_data(f"M {50 + r} 50 A {r} {r} 0 0 1 {50 - r} 50 A {r} {r} 0 0 1 {50 + r} 50 Z")
    out = stroke_path(circle, w, tolerance=0.01)
    area = grid_area(out, (0, 0, 100, 100), 0.2)
    expected = math.pi * ((r + w / 2) ** 2 - (r - w / 2) ** 2)
    assert area == pytest.approx(expected, rel=0.005)
    assert not inside(out, [(50, 50)])[0]


def test_tight_circle_has_no_hole():
    # radius smaller than the half width: the stroke is a full disc of radius r + w/2
    r, w = 3.0, 10.0
    circle = parse_path_data(f"M {50 + r} 50 A {r} {r} 0 0 1 {50 - r} 50 A {r} {r} 0 0 1 {50 + r} 50 Z")
    out = stroke_path(circle, w, tolerance=0.01)
    area = grid_area(out, (40, 40, 60, 60), 0.1)
    assert area == pytest.approx(math.pi * (r + w / 2) ** 2, rel=0.01)


# -- every point of the stroke within w/2 of the source, every such point covered ------------

def check_distance_property(src_path, w, tol, rng, n=3000, join="round"):
    """With round joins and caps the stroke is exactly the set of points within w/2 of the
    source (the Minkowski sum with a disc), so it is checked point by point (any join where
    the source's tangents are continuous)."""
    out = stroke_path(src_path, w, join=join, cap="round", tolerance=tol)
    polys = source_polylines(src_path, per_curve=800)
    poly = np.vstack(polys)
    lo = poly.min(axis=0) - w
    hi = poly.max(axis=0) + w
    q = lo + rng.random((n, 2)) * (hi - lo)
    # also points concentrated near the boundary
    idx = rng.integers(0, len(poly), n)
    ang = rng.random(n) * 2 * math.pi
    rad = w / 2 + (rng.random(n) - 0.5) * 4 * tol
    q = np.vstack([q, poly[idx] + np.column_stack([np.cos(ang), np.sin(ang)]) * rad[:, None]])
    d = distance_to_polylines(q, polys)
    ins = inside(out, q)
    margin = tol * 1.01 + 1e-6
    assert np.all(ins[d < w / 2 - margin]), "point within the stroke not covered"
    assert not np.any(ins[d > w / 2 + margin]), "point outside the stroke covered"
    return out


def test_distance_property_curves():
    rng = np.random.default_rng(1)
    for d in ["M 10 10 C 90 10 10 90 90 90", "M 10 50 Q 50 -30 90 50 T 170 50",
              "M 0 0 C 100 100 0 100 100 0",            # a loop
              "M 0 0 C 100 100 0 100 100 0 L 10 5 Z",
              "M 0 0 C 60 60 40 60 100 0",             # tight bend vs a wide stroke
              "M 10 10 L 60 10 L 15 14 L 70 40"]:       # sharp turns, short segments
        src = parse_path_data(d)
        for w in (2.0, 12.0, 40.0):
            check_distance_property(src, w, 0.05, rng)


def test_cusp_cubic():
    rng = np.random.default_rng(2)
    # control polygon crossing itself symmetrically: a true cusp (zero derivative) at t = 0.5
    check_distance_property(parse_path_data("M 0 0 C 100 100 0 100 100 0"), 10, 0.05, rng)
    check_distance_property(parse_path_data("M 0 0 C 100 60 0 60 100 0"), 10, 0.05, rng)


@pytest.mark.parametrize("join", ["miter", "miter-clip", "bevel", "arcs"])
def test_smooth_junctions_of_tight_bends_take_no_join(join):
    # segments meeting with continuous tangents, each bending tighter than the half width
    # there, so the stroker draws their ends as chords that turn: the path's join does not
    # apply (no tangent discontinuity), the stroke is the pen disc swept along the path
    from vecmsaa.svg.shapes import ellipse_path, rounded_rect_path
    rng = np.random.default_rng(4)
    for src, w in ((rounded_rect_path(59, 21, 0.5, 60, 0.25, 30), 11.34),   # rx clamped
                   (ellipse_path(52, 52, 0.5, 0.5), 40.0),                  # circle r < w/2
                   (ellipse_path(50, 50, 0.3, 20), 8.0),
                   (parse_path_data("M 0 0 L 50 0 C 60 0 60 1 50 1 L 0 1"), 10.0)):
        check_distance_property(src, w, 0.05, rng, join=join)


@pytest.mark.parametrize("join", ["bevel", "miter", "round"])
@pytest.mark.parametrize("d, w", [
    ("M 83 73 Q 128 83 168 148 C 168 148 93 51 164 78 L 85 89", 60.0),   # a control at a start
    ("M 0 0 C 0 0 100 0 100 100", 60.0),
    ("M 0 0 C 100 0 100 100 100 100 L 0 120", 40.0),                      # ... at an end
    ("M 20 20 C 20 20 60 0 40 -10 C 30 -15 30 -15 0 0", 30.0)])
def test_normals_at_segment_ends_are_covered(d, w, join):
    # SVG 2's stroke shape holds the normal segment (length w, centred on the path) at every
    # point, the segments' ends included, whatever the join and caps. Curves bending tighter
    # than the half width at an end are drawn as chords there, whose direction is off the end
    # tangent: the join or cap offset along the chord left part of the normal uncovered
    # (0.5 units at 30 from the vertex, the first case, width 60)
    # (square caps: at an open end a butt cap's edge is that normal, where the shape ends.
    # The outline is within tol of the true one, and a normal point may lie on the true
    # boundary (a bevel's edge), so each must have a covered point within tol of it.)
    tol = 0.05
    src = parse_path_data(d)
    out = stroke_path(src, w, join=join, cap="square", tolerance=tol)
    s = np.linspace(-(w / 2 - 2 * tol), w / 2 - 2 * tol, 201)[:, None]
    near = tol * np.array([(0.0, 0.0)] + [(math.cos(a), math.sin(a))
                                          for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)])
    for p, t0, q, t1 in re_segments(src):
        for pt, t in ((p, t0), (q, t1)):
            n = np.array([-t[1], t[0]])
            pts = np.asarray(pt) + s * n
            covered = np.zeros(len(pts), bool)
            for e in near:
                covered |= inside(out, pts + e)
            assert covered.all(), (pt, t, s[~covered, 0])


def _chord_stroke_inside(q, p0, p1, hw, cap):
    """(inside, margin) of points q for the stroke of the segment p0 → p1 (exact geometry)."""
    q = np.asarray(q, float)
    d = np.subtract(p1, p0) / math.dist(p0, p1)
    rel = q - p0
    s = rel @ d
    lat = rel @ np.array([-d[1], d[0]])
    length = math.dist(p0, p1)
    if cap == "round":
        dist = np.hypot(np.clip(s, 0, length) - s, lat)
        return dist <= hw, np.abs(dist - hw)
    ext = hw if cap == "square" else 0.0
    margin = np.minimum(np.minimum(s + ext, length + ext - s), hw - np.abs(lat))
    return margin >= 0, np.abs(margin)


@pytest.mark.parametrize("cap", ["butt", "square", "round"])
@pytest.mark.parametrize("d, w", [
    ("M 20 160 C 20.1 160 160 20 160.1 20", 20.0),        # the suite's stroke/line-as-curve-2
    ("M 20 160 C 20.0001 160 160 20 160.0001 20", 25.0),  # ... -1
    ("M 60 40 C 60.01 40 67 33 67.07 32.93", 20.0),       # short: the control 0.01 off
    ("M 10 10 Q 10.05 10 90 50", 12.0)])                  # a quadratic
def test_a_curve_in_line_is_stroked_as_its_chord(d, w, cap):
    # a curve whose control points lie within m·√1e-5 of the segment joining its two
    # farthest points (m their larger coordinate difference) is a line to Skia's and
    # tiny-skia's strokers (SkStroke: cubic_in_line, quad_in_line): resvg and Chromium draw
    # the chord's stroke, caps square to the chord. Drawn exactly, the tangent at a control
    # point 0.1 from the start is horizontal, so the cap turned 45° and a fan stuck out
    # (the suite's line-as-curve-2 with square caps, dashes or width 25: 0.26-0.46% of
    # pixels off resvg, which Chromium matched)
    src = parse_path_data(d)
    tol = 0.05
    out = stroke_path(src, w, cap=cap, tolerance=tol)
    p0, p1 = tuple(src.points[0]), tuple(src.points[-1])
    lo = np.minimum(p0, p1) - w
    hi = np.maximum(p0, p1) + w
    g = np.random.default_rng(5).random((6000, 2)) * (hi - lo) + lo
    truth, margin = _chord_stroke_inside(g, p0, p1, w / 2, cap)
    keep = margin > 4 * tol
    assert np.array_equal(inside(out, g)[keep], truth[keep])


def test_a_curve_just_out_of_line_keeps_its_end_tangent():
    # the control point 0.1 off a 10-unit curve is beyond Skia's line slop (0.022 here): the
    # curve is stroked as such, the fan its normal sweeps at the start (from straight down
    # to the chord's normal) inside the stroke, where the chord's stroke ends short of it
    q = [(60.5, 49.0), (60.3, 45.0), (61.0, 47.0), (62.0, 48.0)]
    out = stroke_path(parse_path_data("M 60 40 C 60.1 40 67 33 67.07 32.93"), 20.0,
                      tolerance=0.01)
    assert inside(out, q).all()
    assert not _chord_stroke_inside(q, (60, 40), (67.07, 32.93), 10.0, "butt")[0].any()


def re_segments(path):
    """(start, start tangent, end, end tangent) of each line, quadratic and cubic segment of
    non-zero length (unit tangents: toward the first control point apart from the start)."""
    from vecmsaa.geometry.stroke import segment_tangents
    out, i, cur = [], 0, None
    for v in path.verbs:
        k = VERB_POINTS[v]
        ctrl = [tuple(x) for x in path.points[i:i + k]]
        i += k
        if v == MOVE:
            cur = ctrl[0]
        elif v in (LINE, QUAD, CUBIC):
            tt = segment_tangents([cur] + ctrl)
            if tt:
                out.append((cur, tt[0], ctrl[-1], tt[1]))
            cur = ctrl[-1]
    return out


@pytest.mark.parametrize("scale", [1e-3, 1e6])
def test_distance_property_curves_tiny_and_huge(scale):
    # the compiled curve stroker's tests (flatness, offset error, curvature against the half
    # width) are all relative to the tolerance, so a scaled drawing strokes the same
    rng = np.random.default_rng(3)
    d = "M 10 10 C 90 10 10 90 90 90 L 95 20 Q 50 -30 20 40 Z M 0 0 C 100 100 0 100 100 0"
    src = parse_path_data(d).transformed((scale, 0, 0, scale, 0, 0))
    for w in (2.0, 30.0):
        check_distance_property(src, w * scale, 0.05 * scale, rng, n=1500)


# (the kernel has no CPython wrapper: only other kernels call it)
_hypot = njit(lambda x, y: hypot._hypot(x, y))


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e300, 1e300), st.floats(-1e300, 1e300),
       st.sampled_from([1.0, 1e-9, 1e9, 1e-160, 1e150]))
def test_kernel_hypot_is_cpythons(x, y, scale):
    # the curve kernels measure with CPython's correctly rounded hypot (libm's is off by
    # an ulp at times, which the offset fits magnify)
    assert _hypot(x, y * scale) == math.hypot(x, y * scale)
    assert _hypot(x * 1e-12, y) == math.hypot(x * 1e-12, y)


@pytest.mark.parametrize("m", [2.0 ** -1022, math.nextafter(2.0 ** -1022, 0), 2.0 ** -1021,
                               2.0 ** 1021, math.nextafter(2.0 ** 1022, 0), 2.0 ** 1022,
                               2.0 ** 1023, 1.7976931348623157e308, 0.5, 1.0, 3.0, 5e-324])
def test_kernel_hypot_at_the_exponent_limits(m):
    # the kernel takes frexp's exponent from m's bits for normal m below 2**1022 and calls
    # frexp and ldexp elsewhere: both sides of either limit agree with CPython
    for other in (0.0, m, m * 0.75, m * 1e-8, math.nextafter(m, 0)):
        assert _hypot(m, other) == math.hypot(m, other)
        assert _hypot(-other, -m) == math.hypot(other, m)


coordinate = st.floats(-100, 100, allow_nan=False).map(lambda v: round(v, 2))


@pytest.mark.parametrize("a", [4.0, 5.0, 6.0])
@pytest.mark.parametrize("h", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("w", [1.0, 2.0])
def test_s_cubic_parallel_ends_within_tolerance_in_the_middle(a, h, w):
    # An S whose end tangents are parallel (0,0) (a,0) (0,h) (a+2,h): no offset cubic with
    # those tangents can take the true offset's midpoint, so a fit that tried is judged there
    # too, not only at its quarter points. Probes along the exact curve's normals, 1.05 tol
    # inside and outside the half width, against their brute-force distance to the curve.
    tol = 0.1
    ctrl = [(0.0, 0.0), (a, 0.0), (0.0, h), (a + 2.0, h)]
    p = Path()
    p.moveTo(ctrl[0])
    p.curveTo(*ctrl[1:])
    p.endPath()
    out = stroke_path(p, w, join="round", cap="round", tolerance=tol)
    ts = np.linspace(0, 1, 801)
    c = np.asarray(ctrl)
    pt = _bezier(c, ts)
    vel = _bezier(3 * (c[1:] - c[:-1]), ts)
    nrm = np.column_stack([-vel[:, 1], vel[:, 0]]) / np.hypot(vel[:, 0], vel[:, 1])[:, None]
    q = np.vstack([pt + nrm * s * (w / 2 + e * 1.05 * tol) for s in (1, -1) for e in (1, -1)])
    d = distance_to_polylines(q, [_bezier(c, np.linspace(0, 1, 20001))])
    ins = inside(out, q)
    margin = tol * 1.01
    assert np.all(ins[d < w / 2 - margin]), "point within the stroke not covered"
    assert not np.any(ins[d > w / 2 + margin]), "point outside the stroke covered"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(coordinate, coordinate), min_size=4, max_size=4),
       st.sampled_from([1.0, 6.0, 30.0]), st.integers(0, 2 ** 31))
@example(ctrl=[(0, 0), (0, 0), (2, 0), (0, 0)], w=1.0, seed=0)   # overshoots its chord
@example(ctrl=[(0.0, 0.0), (0.0, 2.0), (4.0, 2.0), (0.0, 1.0)], w=30.0, seed=0)  # errors add
@example(ctrl=[(0.0, 0.0), (5.0, 0.0), (0.0, 1.0), (7.0, 1.0)], w=1.0, seed=0)  # an S: its middle
def test_random_cubic_distance_property(ctrl, w, seed):
    p = Path()
    p.moveTo(ctrl[0])
    p.curveTo(*ctrl[1:])
    p.endPath()
    check_distance_property(p, w, 0.1, np.random.default_rng(seed), n=800)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(0, 40), st.integers(0, 40)), min_size=2, max_size=12),
       st.sampled_from([0.5, 3.0, 12.0]), st.booleans(), st.integers(0, 2 ** 31))
@example(pts=[(0, 0), (0, 11), (10, 5)], w=3.0, closed=True, seed=0)   # shortcuts all round
@example(pts=[(0, 1), (0, 0), (0, 1)], w=0.5, closed=False, seed=0)     # a U-turn
def test_random_polyline_distance_property(pts, w, closed, seed):
    # short segments, sharp turns and U-turns relative to the width: where the polyline
    # stroker's inline joins stop being exact it must fall back to separate pieces
    p = line(*[(x / 4, y / 4) for x, y in pts], close=closed)
    check_distance_property(p, w, 0.05, np.random.default_rng(seed), n=800)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(coordinate, coordinate), min_size=4, max_size=10),
       st.sampled_from(["miter", "miter-clip", "round", "bevel", "arcs"]),
       st.sampled_from(["butt", "round", "square"]),
       st.floats(0.01, 50), st.booleans())
def test_random_curves_finite_and_bounded(pts, join, cap, w, closed):
    p = Path()
    p.moveTo(pts[0])
    rest = pts[1:]
    while len(rest) >= 3:
        p.curveTo(*rest[:3])
        rest = rest[3:]
    for q in rest:
        p.lineTo(q)
    p.closePath() if closed else p.endPath()
    tol = 0.1
    out = stroke_path(p, w, join=join, cap=cap, miterlimit=4.0, tolerance=tol)
    assert np.all(np.isfinite(out.points))
    if len(out.points):
        # the outline's points (not its control points), which the source's control box
        # bounds: a miter reaches miterlimit · w/2 along the bisector, a clipped one w/2
        # sideways too, and offsets may be off by the tolerance
        pts_out = np.vstack(contours(out, per_curve=16))
        src = np.asarray(pts)
        reach = w / 2 * math.sqrt(4.0 ** 2 + 1) + tol + 1e-6
        assert np.all(pts_out >= src.min(axis=0) - reach)
        assert np.all(pts_out <= src.max(axis=0) + reach)


# -- joins -----------------------------------------------------------------------------------

def _corner(angle_deg):
    """Two segments of length 50 meeting at (50, 50) with the given interior angle."""
    a = math.radians(angle_deg)
    return line((0, 50), (50, 50), (50 - 50 * math.cos(a), 50 - 50 * math.sin(a)))


def _outer_bisector(angle_deg):
    a = math.radians(angle_deg)
    d0 = np.array([1.0, 0.0])
    d1 = np.array([-math.cos(a), -math.sin(a)])
    b = d0 - d1
    return b / np.linalg.norm(b)


@pytest.mark.parametrize("angle", [30, 60, 90, 120, 150])
def test_miter_tip_length(angle):
    w = 4.0
    ratio = 1 / math.sin(math.radians(angle) / 2)     # SVG: miter length / stroke width
    tip = ratio * w / 2
    b = _outer_bisector(angle)
    probe = lambda out, dist: inside(out, [np.array([50, 50]) + b * dist])[0]
    out = stroke_path(_corner(angle), w, join="miter", miterlimit=ratio + 0.01)
    assert probe(out, tip * 0.98) and not probe(out, tip * 1.02)
    # over the limit: bevel, whose edge is at w/2 · sin(θ/2) from the vertex
    out = stroke_path(_corner(angle), w, join="miter", miterlimit=ratio - 0.01)
    bevel = w / 2 * math.sin(math.radians(angle) / 2)
    assert probe(out, bevel * 0.98) and not probe(out, bevel * 1.02 + 1e-3)
    # miter-clip: cut at miterlimit · w/2 from the vertex
    limit = max(1.0, ratio / 2)
    out = stroke_path(_corner(angle), w, join="miter-clip", miterlimit=limit)
    clip = max(limit * w / 2, bevel)
    assert probe(out, clip * 0.98) and not probe(out, clip * 1.02 + 1e-3)


@pytest.mark.parametrize("ratio", [4.03, 3.97])
@pytest.mark.parametrize("bend", [1, -1])
def test_miter_limit_judges_a_curve_by_its_tangent(ratio, bend):
    # A cubic whose first control point is its start (an `S` after an arc) leaves along the
    # direction to its second (SVG 2 path directionality) and bends tighter than the half width
    # there; the miter limit (4) judges that tangent, whichever way the curve then bends.
    w = 10.0
    p, vertex, _ = _tight_curve_corner(ratio, bend)
    out = stroke_path(p, w, join="miter", miterlimit=4.0)
    mid_miter = vertex + _outer_bisector(_interior_angle(ratio)) * ratio * w / 2 * 0.6
    assert inside(out, [mid_miter])[0] == (ratio <= 4.0)


@pytest.mark.parametrize("ratio", [2.0, 3.5, 8.0])
@pytest.mark.parametrize("bend", [1, -1])
def test_miter_at_a_tight_curve_end_is_shaped_by_its_tangent(ratio, bend):
    # The same corner within the limit: the miter is the tangents' (SVG 2: the join's
    # directions are the segments' at the vertex), its tip ratio · w/2 out along their
    # bisector, and the whole wedge between the tangents' offset lines is covered, though
    # the curve's first piece is a chord (it bends tighter than w/2 there).
    w = 10.0
    theta = _interior_angle(ratio)
    p, vertex, d1 = _tight_curve_corner(ratio, bend)
    out = stroke_path(p, w, join="miter", miterlimit=10.0, tolerance=0.01)
    b = _outer_bisector(theta)
    tip = vertex + b * ratio * w / 2
    assert inside(out, [vertex + b * ratio * w / 2 * 0.99])[0]
    assert not inside(out, [vertex + b * ratio * w / 2 * 1.01])[0]
    # the wedge: vertex, the incoming offset corner, the tip, the outgoing (tangent) one
    n0 = np.array([0.0, math.copysign(1.0, b[1])])
    n1 = np.array([-d1[1], d1[0]])
    n1 = n1 if np.dot(n1, b) > 0 else -n1
    u, v = np.meshgrid(np.linspace(0.02, 0.96, 12), np.linspace(0.02, 0.96, 12))
    keep = (u + v) <= 0.97
    for q0, q1 in ((vertex + n0 * w / 2, tip), (tip, vertex + n1 * w / 2)):
        pts = vertex + u[keep, None] * (q0 - vertex) + v[keep, None] * (q1 - vertex)
        assert inside(out, pts).all()


def _tight_curve_corner(ratio, bend):
    """A line to (50, 50), then a cubic whose first control point is that vertex (an `S` after
    an arc): it leaves along the direction to its second control point, at the interior angle
    of a miter ``ratio``, and bends (1 left, -1 right) tighter than a 10-wide stroke's half
    width there. → (path, vertex, the cubic's direction at the vertex)."""
    a = math.radians(_interior_angle(ratio))
    d1 = np.array([-math.cos(a), -math.sin(a)])
    vertex, c2 = np.array([50.0, 50.0]), np.array([50.0, 50.0]) + 30 * d1
    p3 = c2 + 30 * bend * np.array([-d1[1], d1[0]])
    p = Path()
    p.moveTo((0, 50))
    p.lineTo(tuple(vertex))
    p.curveTo(tuple(vertex), tuple(c2), tuple(p3))
    p.endPath()
    return p, vertex, d1


def _interior_angle(ratio):
    """The interior angle (degrees) of a corner whose miter ratio is ratio: 1 / sin(θ/2)."""
    return math.degrees(2 * math.asin(1 / ratio))


@pytest.mark.parametrize("angle", [20, 90, 160])
def test_round_join_radius(angle):
    w = 6.0
    b = _outer_bisector(angle)
    out = stroke_path(_corner(angle), w, join="round", tolerance=0.001)
    assert inside(out, [np.array([50, 50]) + b * w / 2 * 0.99])[0]
    assert not inside(out, [np.array([50, 50]) + b * w / 2 * 1.01])[0]


def test_u_turn_has_no_spike():
    out = stroke_path(line((0, 0), (50, 0), (0, 0)), 4, join="miter")
    assert np.all(np.isfinite(out.points))
    assert out.points[:, 0].max() <= 52 + 1e-9
    out = stroke_path(line((0, 0), (50, 0), (0, 0)), 4, join="round")
    assert inside(out, [(51.9, 0)])[0] and not inside(out, [(52.1, 0)])[0]


@pytest.mark.parametrize("limit", [1.0, 4.0, 10.0])
def test_u_turn_miter_clip_reaches_half_the_limit(limit):
    # SVG 2 stroke-linejoin miter-clip: a miter over the limit is clipped at miterlimit · w/2
    # from the vertex along the bisector. At a reversal the miter is infinite and the
    # bisector runs on along the incoming segment (as it does at 179.9°): a box past the turn.
    w = 4.0
    reach = 50 + limit * w / 2
    for pts in (((0, 0), (50, 0), (0, 0)), ((0, 0), (50, 0), (50, 0), (10, 0))):
        out = stroke_path(line(*pts), w, join="miter-clip", miterlimit=limit)
        assert inside(out, [(reach - 0.05, 1.9), (reach - 0.05, -1.9)]).all()
        assert not inside(out, [(reach + 0.05, 0), (reach - 0.05, 2.1)]).any()
    # continuous with a turn just short of the reversal
    near = stroke_path(line((0, 0), (50, 0), (0, 1e-6)), w, join="miter-clip", miterlimit=limit)
    assert inside(near, [(reach - 0.05, 0)])[0] and not inside(near, [(reach + 0.05, 0)])[0]


# -- caps ------------------------------------------------------------------------------------

@pytest.mark.parametrize("cap, beyond", [("butt", 0.0), ("square", 3.0), ("round", 3.0)])
def test_cap_extent(cap, beyond):
    out = stroke_path(line((10, 10), (50, 10)), 6, cap=cap)
    for x_end, sign in ((50, 1), (10, -1)):
        assert inside(out, [(x_end + sign * (beyond - 0.05), 10)])[0] or beyond == 0
        assert not inside(out, [(x_end + sign * (beyond + 0.05), 10)])[0]
    if cap == "round":   # the corner of a square cap is outside a round one
        assert not inside(out, [(50 + 2.5, 12.5)])[0]
    if cap == "square":
        assert inside(out, [(50 + 2.9, 12.9)])[0]


def test_closed_subpath_has_no_caps():
    out = stroke_path(line((10, 10), (50, 10), (50, 50), close=True), 4, cap="square",
                      join="bevel")
    # a square cap at (10, 10) would cover the point just before the start along -x
    assert not inside(out, [(7.5, 10)])[0]


@pytest.mark.parametrize("cap, area", [("round", math.pi * 9), ("square", 36.0), ("butt", 0.0)])
def test_zero_length_subpath_dot(cap, area):
    for d in ("M 20 20 Z", "M 20 20 L 20 20", "M 20 20 l 0 0 0 0"):
        out = stroke_path(parse_path_data(d), 6, cap=cap)
        assert grid_area(out, (10, 10, 30, 30), 0.1) == pytest.approx(area, rel=0.02, abs=0.01)


def test_lone_moveto_not_stroked():
    assert stroke_path(parse_path_data("M 20 20"), 6, cap="round").is_empty()


def _pieces_stroke(path, w, join, cap, miterlimit, dashes, offset, tol):
    """The same stroke through the general (curve) stroker: every line a separate piece,
    dashes walked by the curve dasher (kernels.dash_segments)."""
    from vecmsaa.geometry import stroke

    pattern = dash_pattern(dashes)
    segments = stroke._path_segments(path)
    if pattern is not None:
        segments = stroke.kernels.dash_segments(*segments, np.asarray(pattern, np.float64),
                                                float(offset), 0.5)
    return Path.from_arrays(*stroke._segments_outline(
        segments, w / 2, tol, join, cap, max(1.0, miterlimit), general=True))


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.lists(st.tuples(st.integers(0, 24), st.integers(0, 24)), min_size=1,
                         max_size=8), min_size=1, max_size=3),
       st.lists(st.booleans(), min_size=3, max_size=3),
       st.sampled_from(["miter", "miter-clip", "round", "bevel", "arcs"]),
       st.sampled_from(["butt", "round", "square"]), st.sampled_from([0.4, 2.0, 7.0]),
       st.sampled_from([1.0, 1.5, 4.0]),
       st.one_of(st.none(), st.lists(st.sampled_from([0.0, 0.5, 1.5, 4.0]), min_size=1,
                                     max_size=3)),
       st.floats(-10, 10), st.integers(0, 2 ** 31))
@example(subpaths=[[(0, 0), (8, 0), (8, 8), (0, 8)]], closed=[True, False, False], join="miter",
         cap="butt", w=2.0, miterlimit=4.0, dashes=[8.0, 4.0], offset=2.0, seed=0)
@example(subpaths=[[(17, 15), (21, 3), (20, 6)]], closed=[False, False, False], join="miter",
         cap="butt", w=0.4, miterlimit=1.0, dashes=None, offset=0.0, seed=0)   # a U-turn
@example(subpaths=[[(0, 0), (6, 4)]], closed=[True, False, False], join="miter", cap="round",
         w=2.0, miterlimit=4.0, dashes=[0.0, 0.0, 0.5], offset=0.0, seed=0)   # a dot at the start
@example(subpaths=[[(21, 16), (21, 11), (21, 0), (20, 24), (0, 24), (15, 12)],
                   [(0, 24), (20, 0), (0, 0), (0, 24), (0, 0)]], closed=[True, True, False],
         join="miter", cap="round", w=7.0, miterlimit=1.0, dashes=[0.5, 0.0, 0.0],
         offset=-4.658218353121597e-19, seed=96)    # offset % period rounds to the period
@example(subpaths=[[(0, 0)], [(0, 0), (0, 1), (1, 2)]], closed=[False, True, False],
         join="miter", cap="butt", w=0.4, miterlimit=1.0, dashes=[0.0, 0.0, 0.5], offset=0.0,
         seed=0)   # a dot at the start, then the dash the last one runs on into
def test_compiled_polylines_fill_as_the_general_stroker(subpaths, closed, join, cap, w,
                                                        miterlimit, dashes, offset, seed):
    # the compiled polyline stroker (inline joins, shortcuts at inner corners, dashes walked
    # in the kernel) against the curve stroker's separate pieces: the same filled set
    p = Path()
    for pts, cl in zip(subpaths, closed):
        p.moveTo((pts[0][0] / 2, pts[0][1] / 2))
        for x, y in pts[1:]:
            p.lineTo((x / 2, y / 2))
        p.closePath() if cl else p.endPath()
    tol = 0.05
    fast = stroke_path(p, w, join=join, cap=cap, miterlimit=miterlimit, dashes=dashes,
                       dash_offset=offset, tolerance=tol)
    ref = _pieces_stroke(p, w, join, cap, miterlimit, dashes, offset, tol)
    assert np.all(np.isfinite(fast.points))
    rng = np.random.default_rng(seed)
    reach = w / 2 * (max(miterlimit, math.sqrt(2)) + 1)
    q = -reach + rng.random((2000, 2)) * (12 + 2 * reach)
    ref_pts = np.vstack(contours(ref)) if len(ref.points) else np.empty((0, 2))
    if len(ref_pts):
        # also points right next to the reference outline
        idx = rng.integers(0, len(ref_pts), 1000)
        q = np.vstack([q, ref_pts[idx] + rng.normal(0, w / 20, (1000, 2))])
    got, want = inside(fast, q), inside(ref, q)
    assert np.all(winding(fast, q) >= 0)
    differ = got != want
    if differ.any():
        # only within rounding distance of an outline (collinear pieces meet slightly
        # differently in the two strokers: within w·(1 − cos 0.5°))
        polys = contours(fast) + contours(ref)
        polys = [np.vstack([c, c[:1]]) for c in polys]
        d = distance_to_polylines(q[differ], polys)
        assert np.all(d < 1e-4 * w + 1e-9), q[differ][d >= 1e-4 * w + 1e-9][:5]


# -- dashes ----------------------------------------------------------------------------------

def test_dash_pattern_rules():
    assert dash_pattern(None) is None
    assert dash_pattern([5]) == [5, 5]
    assert dash_pattern([1, 2, 3]) == [1, 2, 3, 1, 2, 3]
    assert dash_pattern([1, -2]) is None
    assert dash_pattern([0, 0]) is None
    assert dash_pattern([]) is None


def _dash_on(s, pattern, offset):
    pattern = dash_pattern(pattern)
    pos = (s + offset) % sum(pattern)
    for k, v in enumerate(pattern):
        if pos < v:
            return k % 2 == 0
        pos -= v
    return False


@pytest.mark.parametrize("pattern, offset", [([10, 5], 0), ([10, 5], 3), ([10, 5], -4),
                                             ([7], 0), ([3, 2, 6], 1.5), ([4, 1], 123)])
def test_dashes_on_line(pattern, offset):
    out = stroke_path(line((0, 0), (100, 0)), 2, dashes=pattern, dash_offset=offset)
    s = np.arange(0.25, 100, 0.5)
    on = np.array([_dash_on(v, pattern, offset) for v in s])
    # skip samples within 0.05 of a dash boundary
    near = np.array([_dash_on(v - 0.05, pattern, offset) != _dash_on(v + 0.05, pattern, offset)
                     for v in s])
    got = inside(out, np.column_stack([s, np.zeros_like(s)]))
    assert np.array_equal(got[~near], on[~near])


def test_dashes_follow_curves():
    # (at a fine resolution the dasher's chords are within 0.005 of the curve: its lengths
    # are the arc lengths to ~1e-4, see tests/test_dash_measure.py)
    r = 30.0
    circle = parse_path_data(f"M {50 + r} 50 A {r} {r} 0 0 1 {50 - r} 50 A {r} {r} 0 0 1 {50 + r} 50 Z")
    pattern, offset = [12, 7], 2.0
    out = stroke_path(circle, 2, dashes=pattern, dash_offset=offset, tolerance=0.01,
                      resolution=100.0)
    s = np.arange(0.1, 2 * math.pi * r, 0.37)
    on = np.array([_dash_on(v, pattern, offset) for v in s])
    near = np.array([_dash_on(v - 0.2, pattern, offset) != _dash_on(v + 0.2, pattern, offset)
                     for v in s])
    # the arc starts at angle 0 and runs with increasing angle (sweep flag 1, y down)
    q = np.column_stack([50 + r * np.cos(s / r), 50 + r * np.sin(s / r)])
    got = inside(out, q)
    assert np.array_equal(got[~near], on[~near])


def test_dash_through_start_of_closed_subpath_is_joined():
    # perimeter 40, dashes [0, 10], [15, 25], [30, 40]: the last and the first are one dash
    # turning the corner at (0, 0), so that corner gets the miter, not two butt ends
    square = line((0, 0), (10, 0), (10, 10), (0, 10), close=True)
    out = stroke_path(square, 2, join="miter", dashes=[10, 5])
    assert inside(out, [(-0.9, -0.9)])[0]
    assert not inside(out, [(12.5, 0)])[0]          # a gap: 12.5 lies in (10, 15)
    # the same outline left open is not joined: its ends get (butt) caps
    out = stroke_path(line((0, 0), (10, 0), (10, 10), (0, 10), (0, 0)), 2, join="miter",
                      dashes=[10, 5])
    assert not inside(out, [(-0.9, -0.9)])[0]


@pytest.mark.parametrize("on, off, curve", [
    ("960/254", "1920/254", False),         # 1mm 2mm: 42 periods and a dash make 127 mm
    ("960/254", "1920/254", True), ("0.4", "0.7", False), ("0.5", "0.2", True),
    ("1.2", "3.0", False)])
def test_a_dash_ending_exactly_at_a_closed_subpaths_end_joins_the_first(on, off, curve):
    # a 120-unit square (perimeter 480): in exact arithmetic the last dash ends at the start
    # point, where the first begins: one dash through the corner at (40, 40), mitred there as
    # the solid square is. Summed in floats, the pattern's intervals fall 1e-13 to 1e-11
    # short of the end, and the corner got two butt ends and a hole
    from fractions import Fraction
    n = (480 - Fraction(on)) / (Fraction(on) + Fraction(off))
    assert n.denominator == 1                       # exactly: n periods and a dash
    d = ("M 40 40 C 60 40 120 40 160 40 L 160 160 L 40 160 Z" if curve
         else "M 40 40 L 160 40 L 160 160 L 40 160 Z")
    dashes = [float(Fraction(on)), float(Fraction(off))]
    out = stroke_path(parse_path_data(d), 20, join="miter", dashes=dashes)
    assert inside(out, [(32, 32), (35, 38), (38, 35)]).all()
    # and nothing beyond the solid square's outline there
    solid = stroke_path(parse_path_data(d), 20, join="miter")
    q = [(x, y) for x in np.linspace(28, 52, 13) for y in np.linspace(28, 52, 13)]
    assert not (inside(out, q) & ~inside(solid, q)).any()


def test_dashes_of_curves_join_through_the_start_and_make_dots():
    # the square above with its first side a cubic (straight, so its arc lengths are known):
    # the compiled curve dasher joins the dash through (0, 0) as the polyline dasher does
    square = parse_path_data("M0 0 C 2 0 8 0 10 0 L10 10 L0 10 Z")
    out = stroke_path(square, 2, join="miter", dashes=[10, 5])
    assert inside(out, [(-0.9, -0.9)])[0]
    assert not inside(out, [(10, 12.5 - 10), (30 - 27, 10)]).any()  # gaps (10, 15), (25, 30)
    assert inside(out, [(10, 18 - 10), (30 - 22, 10)]).all()        # the dash (15, 25)
    # zero-length dashes on a curve are dots with round caps, at 0, 10, 20 ... of its length
    curve = parse_path_data("M0 0 C 10 0 20 0 30 0")
    dots = stroke_path(curve, 2, cap="round", dashes=[0, 10])
    assert inside(dots, [(0.5, 0), (10, 0.9), (20, -0.9)]).all()
    assert not inside(dots, [(5, 0), (15, 0), (25, 0)]).any()


@pytest.mark.parametrize("dashes", [None, [3.0, 1.0, 0.0, 2.0]])
@pytest.mark.parametrize("join, cap", [("round", "round"), ("miter", "butt")])
def test_every_subpath_strokes_as_it_would_alone(dashes, join, cap):
    # the curve stroker keeps its scratch (piece table, stack, side buffers and their
    # counts, run tables) from one subpath to the next and grows it for a longer one: each
    # subpath's outline must be the one it gets alone, whatever came before it (a long tight
    # curve of many pieces, then short ones; lines only; closed; a lone point; dashes, dots;
    # a line's end directions, which the miter limit judges, where a curve's were before)
    from vecmsaa.geometry import stroke, stroke_kernels
    ds = ["M 0 0 C 300 0 -200 90 100 100 S 0 300 90 260", "M 5 5 L 20 5 L 20 30",
          "M 40 40 Q 60 10 80 40 Z", "M 10 90 C 12 91 14 91 16 90", "M 50 50 Z",
          "M 0 120 L 40 120 L 40 160 C 60 160 60 120 80 120 L 80 80 Z",
          "M 0 400 C 10 400 20 400 30 400 L 0 403"]
    segments = stroke._path_segments(parse_path_data(" ".join(ds)))
    if dashes:
        segments = stroke_kernels.dash_segments(*segments, np.array(dashes), 0.5, 0.5)
    kinds, segs, subs, flags = segments
    assert len(flags) >= len(ds)
    verbs, pts = stroke._segments_outline(segments, 1.5, 0.05, join, cap, 4.0)
    alone_verbs, alone_pts = [], []
    for k in range(len(flags)):
        lo, hi = subs[k], subs[k + 1]
        v, p = stroke._segments_outline((kinds[lo:hi].copy(), segs[lo:hi].copy(),
                                         np.array([0, hi - lo]), flags[k:k + 1].copy()),
                                        1.5, 0.05, join, cap, 4.0)
        alone_verbs.append(v)
        alone_pts.append(p)
    assert bytes(verbs) == b"".join(map(bytes, alone_verbs))
    assert np.array_equal(pts, np.vstack(alone_pts))
    if join == "miter":
        # the U-turn at (30, 400) is over the miter limit: beveled, its corners 0.15 beyond
        # x = 30 (a clipped miter would reach 31.4 or more)
        assert pts[pts[:, 1] > 350, 0].max() < 30.2


def test_dashes_invalid_or_zero_draw_solid():
    solid = stroke_path(line((0, 0), (100, 0)), 2)
    for pattern in ([5, -1], [0, 0], []):
        out = stroke_path(line((0, 0), (100, 0)), 2, dashes=pattern)
        np.testing.assert_array_equal(out.points, solid.points)


def test_zero_length_dashes_with_round_caps_are_dots():
    out = stroke_path(line((0, 0), (100, 0)), 2, cap="round", dashes=[0, 10])
    assert inside(out, [(50, 0), (50, 0.9), (0.5, 0)]).all()
    assert not inside(out, [(55, 0)])[0]
    assert stroke_path(line((0, 0), (100, 0)), 2, cap="butt", dashes=[0, 10]).is_empty()


# -- markers ---------------------------------------------------------------------------------

def test_marker_vertices_open_path():
    v = marker_vertices(parse_path_data("M 0 0 L 10 0 L 10 10"))
    assert [k for *_, k in v] == ["start", "mid", "end"]
    assert [(x, y) for x, y, *_ in v] == [(0, 0), (10, 0), (10, 10)]
    assert v[0][2:4] == (0.0, 0.0)
    assert v[1][2:4] == (0.0, 90.0)
    assert auto_angle(*v[1][2:4]) == pytest.approx(45.0)
    assert v[2][2:4] == (90.0, 90.0)


@pytest.mark.parametrize("angle_in, angle_out, expected", [
    (0, 90, 45), (90, 0, 45), (350, 10, 0), (10, 350, 0), (-90, 180, 225),
    # U-turns: both bisectors are as short (SVG 2 leaves the side open); +90° from the incoming
    (0, 180, 90), (180, 0, 90), (90, -90, 180), (45, 225, 135),
])
def test_auto_orient_is_the_short_bisector(angle_in, angle_out, expected):
    assert auto_angle(angle_in, angle_out) % 360 == pytest.approx(expected % 360)


def test_auto_orient_at_a_u_turn_vertex_is_perpendicular():
    v = marker_vertices(parse_path_data("M 10 50 L 90 50 L 10 50"))
    assert v[1][2:4] == (0.0, 180.0)
    assert auto_angle(*v[1][2:4]) == pytest.approx(90.0)


def test_a_trailing_lone_moveto_is_the_end_vertex():
    # SVG 2: the moveto is the last vertex of the path data, so the subpath before it ends on
    # a mid vertex (oriented along its last segment: the end of an open subpath), and the
    # end marker's direction is the path's at its end, the last segment's (a moveto is no
    # segment). resvg 0.48.1 and Chrome 150 both put marker-mid on (160, 60).
    v = marker_vertices(parse_path_data("M 40 60 L 100 40 L 160 60 M 100 160"))
    assert [(x, y, kind) for x, y, _i, _o, kind in v] == [
        (40, 60, "start"), (100, 40, "mid"), (160, 60, "mid"), (100, 160, "end")]
    down_right = math.degrees(math.atan2(20, 60))
    assert v[2][2:4] == pytest.approx((down_right, down_right))
    assert v[3][2:4] == pytest.approx((down_right, down_right))


def test_marker_vertices_closed_path_uses_closing_segment():
    v = marker_vertices(parse_path_data("M 0 0 L 10 0 L 10 10 Z"))
    assert [(x, y) for x, y, *_ in v] == [(0, 0), (10, 0), (10, 10), (0, 0)]
    assert v[0][2] == pytest.approx(-135.0) and v[0][3] == 0.0
    assert v[-1][2] == pytest.approx(-135.0) and v[-1][3] == 0.0


def test_marker_vertices_arc_is_one_segment():
    path, cmds = parse_path_data_with_commands("M 0 0 A 10 10 0 0 1 20 0 L 20 10")
    v = marker_vertices(path, cmds)
    assert [(round(x, 9), round(y, 9)) for x, y, *_ in v] == [(0, 0), (20, 0), (20, 10)]
    # the half circle from (0,0) to (20,0) with sweep 1 leaves going up (-y) and ends going down
    assert v[0][3] == pytest.approx(-90.0)
    assert v[1][2] == pytest.approx(90.0)


def test_marker_zero_length_segment_takes_neighbour_direction():
    v = marker_vertices(parse_path_data("M 0 0 L 0 0 L 10 0"))
    assert v[0][3] == 0.0 and v[1][2] == 0.0


def test_closepath_vertex_gets_no_mid_marker_but_the_next_moveto_does():
    from vecmsaa.svg.markers import marker_vertices
    path = Path()
    path.moveTo((0, 0))
    path.lineTo((10, 0))
    path.lineTo((10, 10))
    path.closePath()
    path.moveTo((20, 0))
    path.lineTo((30, 0))
    got = [(round(x), round(y), kind) for x, y, _i, _o, kind in marker_vertices(path)]
    # resvg: mid markers on every vertex but those reached by ClosePath
    assert got == [(0, 0, "start"), (10, 0, "mid"), (10, 10, "mid"), (20, 0, "mid"),
                   (30, 0, "end")]


@pytest.mark.parametrize("x,w", [(49.9, 77.3), (0.1, 0.7), (1e3 + 0.3, 33.3)])
def test_rect_with_half_width_corners_has_no_u_turn(x, w):
    # rx = w/2 (a clamped rx) leaves the top and bottom sides zero-length (SVG 2 rect's path);
    # computed as x + w − rx they could reverse by a last bit, and a miter-clip U-turn there
    # would add a box of limit·w/2 along the side. The stroke stays within hw of the ellipse.
    from vecmsaa.svg.shapes import rounded_rect_path
    y, h, sw = 38.0, 0.5 * w, 0.15 * w
    rx, ry = w / 2, h / 2
    out = stroke_path(rounded_rect_path(x, y, w, h, rx, ry), sw, join="miter-clip",
                      miterlimit=4)
    cx, cy = x + rx, y + ry
    t = np.linspace(0, 2 * math.pi, 721)
    # points 0.1 sw outside the stroke band along the ellipse's outward normals
    ex, ey = cx + rx * np.cos(t), cy + ry * np.sin(t)
    nx, ny = np.cos(t) / rx, np.sin(t) / ry
    nl = np.hypot(nx, ny)
    q = np.stack([ex + nx / nl * 0.6 * sw, ey + ny / nl * 0.6 * sw], 1)
    assert not inside(out, q).any()
