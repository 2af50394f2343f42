"""Arc length along paths (vecmsaa.geometry.arclength) against exact lengths and a brute-force
polyline."""
import math

import numpy as np
import pytest

from vecmsaa.geometry.arclength import PathWalker, path_length
from vecmsaa.svg.pathdata import parse_path_data


def polyline_length(f, n=200_000):
    pts = np.array([f(t) for t in np.linspace(0.0, 1.0, n + 1)])
    return float(np.hypot(*np.diff(pts, axis=0).T).sum())


def test_lines_and_closepath_exactly():
    assert path_length(parse_path_data("M0 0 L3 4 L3 10 Z")) == pytest.approx(
        5 + 6 + math.hypot(3, 10), rel=1e-12)


def test_subpath_gaps_do_not_count():
    assert path_length(parse_path_data("M0 0 L10 0 M50 50 L50 60")) == pytest.approx(20, rel=1e-12)


def test_quadratic_and_cubic_against_brute_force():
    quad = polyline_length(lambda t: ((1 - t) ** 2 * np.array([0, 0]) + 2 * t * (1 - t)
                                      * np.array([10, 30]) + t * t * np.array([20, 0])))
    assert path_length(parse_path_data("M0 0 Q10 30 20 0")) == pytest.approx(quad, rel=1e-6)
    c = np.array([[0, 0], [0, 40], [30, -20], [30, 20]], dtype=float)
    cubic = polyline_length(lambda t: ((1 - t) ** 3 * c[0] + 3 * t * (1 - t) ** 2 * c[1]
                                       + 3 * t * t * (1 - t) * c[2] + t ** 3 * c[3]))
    assert path_length(parse_path_data("M0 0 C0 40 30 -20 30 20")) == pytest.approx(cubic,
                                                                                  rel=1e-6)


def test_circle_of_arcs():
    # arcs arrive as cubics, which bulge off the circle by ~1e-4 of the radius
    circle = parse_path_data("M10 0 A10 10 0 0 1 -10 0 A10 10 0 0 1 10 0 Z")
    assert path_length(circle) == pytest.approx(20 * math.pi, rel=5e-4)


def test_point_and_tangent_at_an_arc_length():
    # a fine accuracy (a large scale) makes the search exact enough to check
    walker = PathWalker(parse_path_data("M0 0 L3 4 L3 10"), scale=1e4)
    x, y, angle = walker.at(2.5)
    assert (x, y) == pytest.approx((1.5, 2.0), abs=1e-4)
    assert angle == pytest.approx(math.degrees(math.atan2(4, 3)))
    x, y, angle = walker.at(8.0)
    assert (x, y) == pytest.approx((3.0, 7.0), abs=1e-4) and angle == pytest.approx(90.0)
    assert walker.at(-1) is None and walker.at(11.5) is None


def test_points_along_a_long_polyline_are_found_without_walking_it():
    # A staircase of 2,000 unit segments, then a zero-length one: the point at arc length s
    # is exact, and each position looks at its own segment, not at every one before it (the
    # walk made a long text on a long path quadratic: 8,000 characters on 8,000 segments
    # took 40 s). (Where segments meet, the lengths' last bits decide.)
    d = "M0 0 " + " ".join(f"L{(k + 1) // 2} {k // 2}" for k in range(1, 2001)) + " L1000 1000"
    walker = PathWalker(parse_path_data(d), scale=1e4)
    touched = []

    class Counted(list):
        def __getitem__(self, i):
            touched.append(i)
            return list.__getitem__(self, i)

        def __iter__(self):
            for i in range(len(self)):
                touched.append(i)
                yield list.__getitem__(self, i)

    walker.cubics = Counted(walker.cubics)
    for s in (0.0, 0.5, 1.25, 1.5, 999.25, 1000.5, 1998.5, 1999.75):
        k = int(s)                            # the segment that holds s
        f = s - k
        x, y = (k + 1) // 2, k // 2           # its start: horizontal from even k, else up
        exact = (x + f, y, 0.0) if k % 2 == 0 else (x, y + f, 90.0)
        assert walker.at(s) == pytest.approx(exact, abs=1e-4)
    assert walker.at(2000.5) is None and walker.at(-0.5) is None
    assert len(touched) <= 8


def bezier(c):
    return lambda t: ((1 - t) ** 3 * c[0] + 3 * t * (1 - t) ** 2 * c[1]
                      + 3 * t * t * (1 - t) * c[2] + t ** 3 * c[3])


def test_cubic_lengths_against_brute_force():
    from vecmsaa.geometry.arclength import cubic_lengths, cubic_rows, gl_nodes
    rng = np.random.default_rng(7)
    cubics = [rng.uniform(-50, 50, (4, 2)) for _ in range(5)]
    cubics.append(np.array([[0, 0], [0, 0], [0, 0], [0, 0]], float))    # degenerate: length 0
    lengths = cubic_lengths(cubic_rows(cubics), gl_nodes())
    for c, L in zip(cubics, lengths):
        assert L == pytest.approx(polyline_length(bezier(c), 20_000), rel=1e-6, abs=1e-9)


def test_text_on_a_curve_at_an_arc_length():
    c = np.array([[0, 0], [0, 40], [30, -20], [30, 20]], dtype=float)
    walker = PathWalker(parse_path_data("M0 0 C0 40 30 -20 30 20"), scale=1e4)
    pts = np.array([bezier(c)(t) for t in np.linspace(0, 1, 100_001)])
    run = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    for s in (1.0, 17.5, 31.0):
        x, y, _ = walker.at(s)
        assert (x, y) == pytest.approx((np.interp(s, run, pts[:, 0]), np.interp(s, run, pts[:, 1])),
                                       abs=1e-3)


@pytest.mark.parametrize("scale", [1e12, 1e300, math.inf])
def test_a_point_at_an_arc_length_under_a_huge_scale(scale):
    # the search's accuracy is 0.5 device units; under scale(1e300) that is 5e-301 user units,
    # below the floats' resolution of the length: the search stops at the finest parameter
    # step the floats hold instead of dividing by a zero difference (found by the fuzzer: a
    # textPath in a text with transform="scale(1e300)")
    c = np.array([[0, 0], [0, 40], [30, -20], [30, 20]], dtype=float)
    walker = PathWalker(parse_path_data("M0 0 C0 40 30 -20 30 20"), scale=scale)
    half = walker.length / 2
    x, y, _ = walker.at(half)
    ts = np.linspace(0.0, 1.0, 200_001)
    pts = np.array([bezier(c)(t) for t in ts])
    run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    assert (x, y) == pytest.approx(tuple(pts[np.searchsorted(run, half)]), abs=1e-3)
