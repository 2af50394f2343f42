"""Loop–Blinn geometry: cubic classification and implicit functions, against exact geometry."""
import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from numba import njit

from vecmsaa.geometry.primitives import (NO_CULL, P_KIND, _eval_implicit, build_batch,
                                         classify_cubic as _classify_cubic, KIND_CUBIC)
from vecmsaa.scene.path import Path



@njit
def classify_cubic(X):
    """(kind, klm, splits) of the kernel, which has no CPython wrapper (only the batch builder
    calls it) and writes klm and splits into arrays it is given."""
    klm = np.empty((4, 3))
    splits = np.empty(2)
    kind = _classify_cubic(X, klm, splits)
    return kind, klm, splits

SERPENTINE, LOOP, CUSP, CUSP_AT_INFINITY, QUADRATIC, LINE = range(6)


def bezier(c, t):
    t = np.asarray(t)[..., None]
    return ((1 - t) ** 3 * c[0] + 3 * (1 - t) ** 2 * t * c[1] + 3 * (1 - t) * t ** 2 * c[2]
            + t ** 3 * c[3])


def normalised(c):
    c = np.asarray(c, dtype=np.float64)
    s = np.abs(c - c[0]).max()
    return np.ascontiguousarray((c - c[0]) / s)


def test_serpentine_loop_cusp_quadratic_line():
    assert classify_cubic(normalised([(0, 0), (1, 3), (2, -2), (4, 0)]))[0] == SERPENTINE
    # symmetric S: one inflection, the other at infinity (d1 = 0)
    assert classify_cubic(normalised([(0, 0), (1, 2), (2, -2), (3, 0)]))[0] == CUSP_AT_INFINITY
    assert classify_cubic(normalised([(0, 0), (3, 3), (-1, 3), (2, 0)]))[0] == LOOP
    # a cusp: control polygon b1, b2 such that the derivative vanishes at t = 1/2
    # P'(t) ∝ (1-t)²(b1-b0) + 2t(1-t)(b2-b1) + t²(b3-b2) = 0 at t = ½ ⟺ b0 + b3 = b1 + b2 ... (+)
    assert classify_cubic(normalised([(0, 0), (2, 2), (0, 2), (2, 0)]))[0] == CUSP
    # degree-elevated quadratic (0,0),(1,2),(2,0)
    q = np.array([(0, 0), (1, 2), (2, 0)], dtype=float)
    elevated = [q[0], q[0] / 3 + 2 * q[1] / 3, 2 * q[1] / 3 + q[2] / 3, q[2]]
    assert classify_cubic(normalised(elevated))[0] == QUADRATIC
    assert classify_cubic(normalised([(0, 0), (1, 1), (2, 2), (3, 3)]))[0] == LINE


def test_loop_split_parameters_are_the_double_point():
    c = np.array([(0, 0), (3, 3), (-1, 3), (2, 0)], dtype=float)
    kind, klm, splits = classify_cubic(normalised(c))
    assert kind == LOOP
    p, q = bezier(c, splits[0]), bezier(c, splits[1])
    np.testing.assert_allclose(p, q, atol=1e-9)        # the curve passes the same point twice
    assert 0 < min(splits) < max(splits) < 1


def test_serpentine_split_parameters_are_inflections():
    for c in ([(0, 0), (1, 3), (2, -2), (4, 0)], [(0, 0), (1, 2), (2, -2), (3, 0)]):
        check_inflections(np.array(c, dtype=float))


def check_inflections(c):
    kind, klm, splits = classify_cubic(normalised(c))
    assert kind in (SERPENTINE, CUSP_AT_INFINITY)
    found = [t for t in splits if 0 <= t <= 1]
    assert found
    for t in found:
        # curvature changes sign: the cross product of P' and P'' vanishes at an inflection
        d1 = 3 * ((1 - t) ** 2 * (c[1] - c[0]) + 2 * t * (1 - t) * (c[2] - c[1]) + t ** 2 * (c[3] - c[2]))
        d2 = 6 * ((1 - t) * (c[2] - 2 * c[1] + c[0]) + t * (c[3] - 2 * c[2] + c[1]))
        assert abs(d1[0] * d2[1] - d1[1] * d2[0]) < 1e-9


def primitives(path):
    v, p = path.verbs, path.points
    return build_batch(v, p, np.array([0, len(v)]), np.array([0, len(p)]), 0.0, 1.0,
                       NO_CULL)


cubic_pts = st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=4, max_size=4)


@settings(max_examples=150, deadline=None)
@given(cubic_pts, st.sampled_from([1e-6, 1.0, 1e4]), st.sampled_from([0.0, 1e7]))
def test_implicit_vanishes_on_the_curve_and_changes_sign_across_it(pts, scale, offset):
    c = np.array(pts) * scale + offset
    path = Path()
    path.moveTo(tuple(c[0]))
    path.curveTo(tuple(c[1]), tuple(c[2]), tuple(c[3]))
    path.closePath()
    edges, eo, prims, po = primitives(path)
    assert np.isfinite(edges).all() and np.isfinite(prims).all()
    for prim in prims:
        if prim[P_KIND] != KIND_CUBIC:
            continue
        # the piece's own control points are stored with it; its curve must be the zero set
        ctrl = prim[30:38].reshape(4, 2)
        size = np.abs(ctrl - ctrl[0]).max()
        if size < 1e-3:
            continue
        for t in (0.1, 0.3, 0.5, 0.7, 0.9):
            x, y = bezier(ctrl, t)
            f, gx, gy = _eval_implicit(prim, x, y)
            g = math.hypot(gx, gy)
            if g > 0:
                # first-order distance to the implicit curve: tiny relative to the piece
                assert abs(f) / g < 1e-5 * max(size, 1e-9) + 1e-7 * abs(offset) * 1e-3


def test_huge_coordinates_keep_the_lens_exact():
    # the same quarter circle at the origin and at 1e7: same coverage once shifted back
    r = 10.0
    k = 4 / 3 * (math.sqrt(2) - 1) * r
    base = np.array([(r, 0), (r, k), (k, r), (0, r)])
    for off in (0.0, 1e7):
        c = base + off
        path = Path()
        path.moveTo(tuple(c[0]))
        path.curveTo(tuple(c[1]), tuple(c[2]), tuple(c[3]))
        path.lineTo((off, off))
        path.closePath()
        edges, eo, prims, po = primitives(path)
        assert len(prims) >= 1 and np.isfinite(prims).all()
        for prim in prims:
            for t in (0.25, 0.5, 0.75):
                x, y = bezier(prim[30:38].reshape(4, 2), t)
                f, gx, gy = _eval_implicit(prim, x, y)
                assert abs(f) / math.hypot(gx, gy) < 1e-6
