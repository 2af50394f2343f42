"""Sample patterns and the half-plane coverage-mask table of the ``approx`` mode.

Patterns are sample offsets from the pixel centre in pixels. The multisample ones are the
Direct3D 10.1 standard patterns (offsets in 1/16 pixel, Fig. 2 of Schwarz & Stamminger); every
one of them has a distinct y per sample (n-rooks), which the scan converter relies on: each
sample sits on its own scanline inside the pixel.

The coverage-mask table answers "which samples lie in the half-plane <x, n> + d < 0" for a
quantised (angle, distance) pair — the Hough parametrisation of the paper's look-up texture.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

# Direct3D 10.1 standard multisample patterns, offsets in 1/16 pixel from the pixel centre.
D3D_PATTERNS = {
    1: [(0, 0)],
    2: [(4, 4), (-4, -4)],
    4: [(-2, -6), (6, -2), (-6, 2), (2, 6)],
    8: [(1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7)],
    16: [(1, 1), (-1, -3), (-3, 2), (4, -1), (-5, -2), (2, 5), (5, 3), (3, -5),
         (-2, 6), (0, -7), (-4, -6), (-6, 4), (-8, 0), (7, -4), (6, 7), (-7, -8)],
}

#: samples per pixel of the conflation-free ``reference`` mode (a 16 x 16 stratified grid)
REFERENCE_SIDE = 16

#: table resolution: pseudo-angle bins over the full circle, distance bins over [-DMAX, DMAX]
ANGLE_BINS = 512
DIST_BINS = 128
#: the largest distance of a pattern sample from the centre is below sqrt(2)/2
DMAX = 0.75


def standard_pattern(samples: int) -> np.ndarray:
    """(n, 2) float64 offsets from the pixel centre for a D3D 10.1 standard pattern."""
    if samples not in D3D_PATTERNS:
        raise ValueError(f"samples must be one of {sorted(D3D_PATTERNS)}, not {samples}")
    return np.asarray(D3D_PATTERNS[samples], dtype=np.float64) / 16.0


def stratified_pattern(side: int = REFERENCE_SIDE, seed: int = 1) -> np.ndarray:
    """side x side jittered grid: one sample per stratum, every y distinct (n-rooks in y too).

    The y jitter is a permutation inside each row of strata (Latin hypercube style), so no two
    samples share a scanline and the scan converter's one-sample-per-row layout still holds.
    """
    rng = np.random.default_rng(seed)
    n = side * side
    # x: stratified by column, jittered; y: n distinct levels, each row of strata gets `side` of them
    ys = (np.arange(n) + rng.random(n)) / n
    pts = np.empty((n, 2))
    k = 0
    for row in range(side):
        levels = ys[row * side:(row + 1) * side]
        perm = rng.permutation(side)
        for col in range(side):
            pts[k, 0] = (col + rng.random()) / side
            pts[k, 1] = levels[perm[col]]
            k += 1
    return pts - 0.5


def grid_pattern(samples: int) -> np.ndarray:
    """Ordered grid (√n x √n, or 2 x 1 / 4 x 2 for non-squares): a baseline to compare the
    D3D patterns against. Samples share rows here, which the scan converter handles too."""
    cols = int(round(np.sqrt(samples)))
    while samples % cols:
        cols -= 1
    rows = samples // cols
    if cols < rows:
        cols, rows = rows, cols
    xs = (np.arange(cols) + 0.5) / cols - 0.5
    ys = (np.arange(rows) + 0.5) / rows - 0.5
    return np.array([(x, y) for y in ys for x in xs], dtype=np.float64)


PATTERNS = {"d3d": standard_pattern, "grid": grid_pattern}     # by modes.PATTERN_NAMES


def pattern_offsets(name: str, samples: int) -> np.ndarray:
    if name not in PATTERNS:
        raise ValueError(f"unknown sample pattern {name!r}; choose from {', '.join(PATTERNS)}")
    if samples not in D3D_PATTERNS:
        raise ValueError(f"samples must be one of {sorted(D3D_PATTERNS)}, not {samples}")
    return PATTERNS[name](samples)


def _diamond_to_vector(a):
    """Direction of a table bin: inverse of the pseudo-angle used by scan.mask_lookup
    (a cheap monotone stand-in for atan2 on [0, 4))."""
    if a < 1:
        return np.array([1.0 - a, a])
    if a < 2:
        return np.array([1.0 - a, 2.0 - a])
    if a < 3:
        return np.array([a - 3.0, 2.0 - a])
    return np.array([a - 3.0, a - 4.0])


@lru_cache(maxsize=None)
def mask_table(samples: int, pattern: str = "d3d") -> np.ndarray:
    """(ANGLE_BINS, DIST_BINS) uint64: bit s set when sample s is inside <x, n> + d < 0 for the
    bin's centre direction n and centre distance d. One table per sample pattern."""
    offs = pattern_offsets(pattern, samples)
    table = np.zeros((ANGLE_BINS, DIST_BINS), dtype=np.uint64)
    dists = (np.arange(DIST_BINS) + 0.5) / DIST_BINS * 2 * DMAX - DMAX
    for ai in range(ANGLE_BINS):
        n = _diamond_to_vector((ai + 0.5) / ANGLE_BINS * 4.0)
        n = n / np.hypot(*n)
        proj = offs @ n                                   # <x_s, n>
        inside = proj[None, :] + dists[:, None] < 0       # (DIST_BINS, n)
        weights = (np.uint64(1) << np.arange(samples, dtype=np.uint64))
        table[ai] = (inside.astype(np.uint64) * weights[None, :]).sum(axis=1).astype(np.uint64)
    return table


def a2c_order(samples: int, pattern: str = "d3d") -> np.ndarray:
    """Fixed order in which alpha-to-coverage turns samples on: farthest-point order, so any
    prefix is spread over the pixel (as hardware dither patterns are)."""
    offs = pattern_offsets(pattern, samples)
    order = [int(np.argmin(np.hypot(offs[:, 0], offs[:, 1])))]
    while len(order) < samples:
        d = np.min(np.hypot(offs[:, None, 0] - offs[None, order, 0],
                            offs[:, None, 1] - offs[None, order, 1]), axis=1)
        d[order] = -1
        order.append(int(np.argmax(d)))
    return np.asarray(order, dtype=np.int64)
