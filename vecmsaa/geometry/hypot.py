"""CPython's math.hypot in a kernel, bit for bit: libm's hypot, which numba calls for
math.hypot, differs in the last bit now and then (and from one platform's libm to another's),
and the curve stroker's offset fits and flatness tests magnify that. Its own module, below
the kernels that measure with it."""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit

_DBL_MIN = 2.2250738585072014e-308      # the smallest normal double


@njit(cache=True, inline="always")
def _square(x):
    """x·x exactly, as (hi, lo) (Dekker's product of Veltkamp halves)."""
    t = x * 134217729.0
    hi = t - (t - x)
    lo = x - hi
    p = hi * hi
    q = hi * lo + lo * hi
    z = p + q
    return z, p - z + q + lo * lo


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _hypot(x, y):
    """math.hypot as CPython computes it (the square root of an exactly summed sum of squares,
    corrected by one step): libm's hypot, which numba calls, differs in the last bit now and
    then, and the offsets' fits and flatness tests magnify that; so the curve stroker keeps
    the outlines it drew in Python, bit for bit (subnormal lengths aside)."""
    x, y = abs(x), abs(y)
    m = 0.0
    if x > m:
        m = x
    if y > m:
        m = y
    if math.isinf(m):
        return m
    if math.isnan(x) or math.isnan(y):
        return math.nan
    if m == 0.0:
        return m
    factor = 1.0
    # frexp's exponent and 2**-e from m's bits where both are normal numbers (m in
    # [2**-1022, 2**1022)): frexp and ldexp are calls into libm, this is its most frequent case
    biased = (np.float64(m).view(np.int64) >> 52) & 0x7FF
    if 0 < biased < 2045:
        scale = np.int64((2045 - biased) << 52).view(np.float64)
    else:
        e = math.frexp(m)[1]
        if e < -1023:           # subnormal: scaled up first
            x, y, m, factor = x / _DBL_MIN, y / _DBL_MIN, m / _DBL_MIN, _DBL_MIN
            e = math.frexp(m)[1]
        scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for v in (x * scale, y * scale):
        hi, lo = _square(v)
        s = csum + hi
        frac2 += (csum - s) + hi
        csum = s
        frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _square(h)
    s = csum - hi
    frac2 += (csum - s) - hi
    csum = s
    frac1 -= lo
    v = csum - 1.0 + (frac1 + frac2)
    h += v / (2.0 * h)
    return factor * (h / scale)
