"""Affine transforms in SVG order (a, b, c, d, e, f): composition, inversion, applying to points."""
from __future__ import annotations

import math

import numpy as np
from ..jit import njit

IDENTITY = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)


def compose(m1, m2):
    """Affine matrices in SVG order (a, b, c, d, e, f): the result applies m2 first, then m1."""
    a1, b1, c1, d1, e1, f1 = m1
    a2, b2, c2, d2, e2, f2 = m2
    return (a1 * a2 + c1 * b2, b1 * a2 + d1 * b2,
            a1 * c2 + c1 * d2, b1 * c2 + d1 * d2,
            a1 * e2 + c1 * f2 + e1, b1 * e2 + d1 * f2 + f1)


def translate(x, y):
    return (1.0, 0.0, 0.0, 1.0, float(x), float(y))


def cos_sin_degrees(degrees):
    """cos and sin of an angle in degrees, exact at whole quarter turns. math.radians(180) is
    not pi, so its sine is 1.2e-16: a shape turned by 180 or 90 degrees would have its edges
    at 180 +- 3e-14 instead of on the pixel boundary they were on."""
    quarter, rest = divmod(degrees, 90.0)
    if rest == 0.0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4]
    a = math.radians(degrees)
    return math.cos(a), math.sin(a)


def rotate_at(degrees, cx, cy):
    """Rotation by ``degrees`` (clockwise on screen, y down) about (cx, cy)."""
    c, s = cos_sin_degrees(degrees)
    return (c, s, -s, c, cx - c * cx + s * cy, cy - s * cx - c * cy)


def invert(m):
    """Inverse of an affine matrix; raises ValueError when it is singular."""
    a, b, c, d, e, f = m
    det = a * d - b * c
    if det == 0 or not np.isfinite(det):
        raise ValueError("singular transform")
    ia, ib, ic, id_ = d / det, -b / det, -c / det, a / det
    return (ia, ib, ic, id_, -(ia * e + ic * f), -(ib * e + id_ * f))


def apply(m, pts):
    """Transform an (N, 2) array of points."""
    a, b, c, d, e, f = m
    # one specialisation: C-contiguous float64 points, float coefficients
    return _apply(np.ascontiguousarray(pts, dtype=np.float64), float(a), float(b), float(c),
                  float(d), float(e), float(f))


def apply_each(matrices, counts, pts):
    """Points ``pts`` taken in groups, counts[i] of them mapped by matrices[i] (an (N, 6)
    array): x' = a x + c y + e, y' = b x + d y + f, as apply() maps each group."""
    return _apply_each(np.ascontiguousarray(matrices, dtype=np.float64),
                       np.ascontiguousarray(counts, dtype=np.int64),
                       np.ascontiguousarray(pts, dtype=np.float64))


def point_mapper(pts):
    """A function m -> apply(m, pts) for one (N, 2) array that many matrices map (a glyph
    placed by thousands of <use>): the compiled kernel's entry for the array's types is
    found once, where apply() finds it on every call (≈ 4.5 of a 40-point path's 7 µs)."""
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    entries = getattr(_apply, "entries", None)
    entry = None
    if entries:
        from ..jit import arg_key
        entry = entries.get((arg_key(pts),) + (arg_key(0.0),) * 6)
    if entry is None:               # (numba's JIT, or a kernel not loaded yet)
        return lambda m: apply(m, pts)

    def mapped(m):
        a, b, c, d, e, f = m
        return entry(pts, float(a), float(b), float(c), float(d), float(e), float(f))
    return mapped


# Compiled because most paths are short: numpy's per-call overhead was most of the cost.
# Lazily (no signature in the decorator): an explicit signature loads the kernel, and with it
# numba's typing and lowering registries (≈ 0.7 s), when this module is imported.
@njit(cache=True)
def _apply(pts, a, b, c, d, e, f):
    # empty_like: np.empty with a shape tuple costs numba an unpickled constant per call,
    # 1.5 of its 3.4 µs on a short path
    out = np.empty_like(pts)
    for i in range(pts.shape[0]):
        x = pts[i, 0]
        y = pts[i, 1]
        out[i, 0] = a * x + c * y + e
        out[i, 1] = b * x + d * y + f
    return out


# (a text's glyphs, each by its own matrix: numpy repeating each glyph's matrix onto its
# points was most of a short label's placement)
@njit(cache=True)
def _apply_each(matrices, counts, pts):
    out = np.empty_like(pts)
    i = 0
    for g in range(counts.shape[0]):
        a = matrices[g, 0]
        b = matrices[g, 1]
        c = matrices[g, 2]
        d = matrices[g, 3]
        e = matrices[g, 4]
        f = matrices[g, 5]
        for _ in range(counts[g]):
            x = pts[i, 0]
            y = pts[i, 1]
            out[i, 0] = a * x + c * y + e
            out[i, 1] = b * x + d * y + f
            i += 1
    return out
