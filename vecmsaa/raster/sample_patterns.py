"""Sample patterns.

Patterns are sample offsets from the pixel centre in pixels (RTR3 §5.6 and docs/modes.md):
the Direct3D 10.1 standard patterns (offsets in 1/16 pixel, Fig. 2 of Schwarz & Stamminger),
an ordered grid, the rotated grid, N-rooks, jittered and Poisson-disk patterns (fixed seeds:
the same image every run), and three that a pixel does not own alone: quincunx and FLIPQUAD
(samples on the pixel's corners or edges, shared with the neighbours) and interleaved sampling
(a tile of pixels, each with its own pattern). The scan converter takes any positions in the
pixel; samples that share a row (the grid) just share a scanline.
"""
from __future__ import annotations

import math

import numpy as np

from .modes import PATTERN_NAMES

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


def standard_pattern(samples: int) -> np.ndarray:
    """(n, 2) float64 offsets from the pixel centre for a D3D 10.1 standard pattern, moved so
    that its samples' mean is the pixel centre. Only the 16-sample pattern moves: its offsets
    run from -8 to 7 sixteenths, mean (-1/32, -1/32), which drew every edge 1/32 px right and
    down (a rectangle's or a glyph's centroid +0.03 px against exact areas); moved by
    (+1/32, +1/32), its error against 256-sample coverage is 21% lower on the resvg suite's
    shapes and text tests and 26% lower on Adwaita's icons at 16 and 24 px (docs/modes.md),
    and no sample lies on the pixel's edge or on an edge through its centre."""
    if samples not in D3D_PATTERNS:
        raise ValueError(f"samples must be one of {sorted(D3D_PATTERNS)}, not {samples}")
    offsets = np.asarray(D3D_PATTERNS[samples], dtype=np.float64) / 16.0
    return offsets - offsets.mean(axis=0)


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
    cols, rows = _grid_shape(samples)
    xs = (np.arange(cols) + 0.5) / cols - 0.5
    ys = (np.arange(rows) + 0.5) / rows - 0.5
    return np.array([(x, y) for y in ys for x in xs], dtype=np.float64)


def _grid_shape(samples: int) -> tuple[int, int]:
    """(columns, rows) of the most nearly square grid of ``samples`` cells, wider than tall."""
    cols = int(round(np.sqrt(samples)))
    while samples % cols:
        cols -= 1
    rows = samples // cols
    return (rows, cols) if cols < rows else (cols, rows)


def rotated_grid_pattern(samples: int = 4) -> np.ndarray:
    """RGSS: the 2 x 2 ordered grid turned by atan(1/2), so the four samples have four
    distinct x and four distinct y (near-horizontal and near-vertical edges see 4 levels, the
    ordered grid's 2)."""
    t = math.atan(0.5)
    c, s = math.cos(t), math.sin(t)
    g = grid_pattern(4)
    return np.stack([g[:, 0] * c - g[:, 1] * s, g[:, 0] * s + g[:, 1] * c], axis=1)


def rooks_pattern(samples: int, seed: int = 1) -> np.ndarray:
    """N-rooks (Latin hypercube): one sample in every column and every row of an n x n grid
    of cells, jittered inside its cell; a fixed seed's permutation."""
    rng = np.random.default_rng(seed)
    perm = rng.permutation(samples)
    x = (np.arange(samples) + rng.random(samples)) / samples
    y = (perm + rng.random(samples)) / samples
    return np.stack([x, y], axis=1) - 0.5


def jittered_pattern(samples: int, seed: int = 1) -> np.ndarray:
    """Jittered (stratified): the ordered grid's cells, one uniformly placed sample in each;
    a fixed seed."""
    rng = np.random.default_rng(seed)
    cols, rows = _grid_shape(samples)
    cells = np.array([(c, r) for r in range(rows) for c in range(cols)], dtype=np.float64)
    pts = (cells + rng.random((samples, 2))) / np.array([cols, rows])
    return pts - 0.5


def poisson_pattern(samples: int, seed: int = 1) -> np.ndarray:
    """Poisson disk by Mitchell's best candidate: each new sample is the one of 10 x (samples
    placed) uniform points (a fixed seed) farthest from those placed, distances measured on
    the torus so the spacing holds across the borders of pixels that repeat the pattern. (More
    candidates approach the densest packing, a lattice, whose aligned rows cover edges worse.)"""
    rng = np.random.default_rng(seed)
    pts = [rng.random(2)]
    for placed in range(1, samples):
        cand = rng.random((10 * placed, 2))
        d = np.abs(cand[:, None, :] - np.asarray(pts)[None, :, :])
        d = np.minimum(d, 1.0 - d)
        nearest = np.hypot(d[..., 0], d[..., 1]).min(axis=1)
        pts.append(cand[int(np.argmax(nearest))])
    return np.asarray(pts) - 0.5


def quincunx_pattern(samples: int = 2) -> np.ndarray:
    """Quincunx: the centre and the top-left corner, which the pixel stores; its other three
    corners are its neighbours' top-left ones. Resolved with the tent (centre 1/2, each corner
    1/8): five samples per pixel for the cost of two."""
    return np.array([(0.0, 0.0), (-0.5, -0.5)])


def flipquad_pattern(samples: int = 2) -> np.ndarray:
    """FLIPQUAD: four samples on the pixel's edges at 1/3 and 2/3 (distinct x and y), the
    pattern mirrored in x on odd columns and in y on odd rows so that each edge sample is the
    neighbour's too. A pixel stores its top and left ones: (4 classes of a 2 x 2 tile, 2, 2)."""
    base = np.array([(1 / 3, 0.0), (1.0, 1 / 3), (2 / 3, 1.0), (0.0, 2 / 3)])
    out = np.empty((4, 2, 2))
    for cy in range(2):
        for cx in range(2):
            p = base.copy()
            if cx:
                p[:, 0] = 1.0 - p[:, 0]
            if cy:
                p[:, 1] = 1.0 - p[:, 1]
            top = p[np.argmin(p[:, 1])]
            left = p[np.argmin(p[:, 0])]
            out[cy * 2 + cx] = np.array([top, left]) - 0.5
    return out


#: pixels per side of the interleaved sampling tile
INTERLEAVE_SIDE = 4


def interleaved_pattern(samples: int) -> np.ndarray:
    """Interleaved sampling (Keller & Heidrich): a 4 x 4 tile of pixels, each with its own
    N-rooks pattern (seeds 1..16), repeated over the image: the aliasing of a regular
    pattern becomes fine noise. (16 classes, n, 2)."""
    return np.stack([rooks_pattern(samples, seed=1 + k)
                     for k in range(INTERLEAVE_SIDE * INTERLEAVE_SIDE)])


class SamplePattern:
    """A pattern as the raster uses it. ``offsets``: (classes, n, 2) positions from the pixel
    centre, in [-0.5, 0.5) (so every sample belongs to one pixel's row and column: an offset
    of -0.5 lies on the pixel's top or left edge); pixel (x, y) uses class
    (y mod th) * tw + (x mod tw) of a ``tile`` of (tw, th) pixels. ``per_pixel``: one class
    and every sample strictly inside its pixel, so a pixel's samples are its own and the
    kernels resolve them; a tile of such classes (interleaved) is rendered once per class,
    each resolved by the kernels, when the filter stays in the pixel; otherwise samples are
    shared with or differ between neighbours and raster/resolve.py resolves them. ``shared``: samples on the pixel's edges or corners are
    also the neighbours' (quincunx, FLIPQUAD); elsewhere an offset of -0.5 is this pixel's
    alone. ``filter``: the resolve filter the pattern is defined with."""

    def __init__(self, name, offsets, tile=(1, 1), filter="box", shared=False):
        offsets = np.asarray(offsets, dtype=np.float64)
        if offsets.ndim == 2:
            offsets = offsets[None]
        assert offsets.shape[0] == tile[0] * tile[1]
        assert offsets.min() >= -0.5 and offsets.max() < 0.5, name
        self.name, self.offsets, self.tile, self.filter = name, offsets, tile, filter
        self.shared = shared
        self.samples = offsets.shape[1]
        self.per_pixel = offsets.shape[0] == 1 and not shared


#: the counts a pattern is defined for (the others take any of D3D_PATTERNS), and the count
#: of those that have just one: that one is used whatever the sample count asked for
FIXED_SAMPLES = {"rgss": 4, "quincunx": 2, "flipquad": 2}
_TILES = {"flipquad": (2, 2), "interleaved": (INTERLEAVE_SIDE, INTERLEAVE_SIDE)}
_FILTERS = {"quincunx": "tent"}
# by modes.PATTERN_NAMES, in its order (the names are spelled once, there)
_BUILDERS = (standard_pattern, grid_pattern, rotated_grid_pattern, rooks_pattern,
             jittered_pattern, poisson_pattern, quincunx_pattern, flipquad_pattern,
             interleaved_pattern)
PATTERNS = dict(zip(PATTERN_NAMES, _BUILDERS))
assert len(PATTERNS) == len(_BUILDERS)


def sample_pattern(name: str, samples: int) -> SamplePattern:
    """The :class:`SamplePattern` ``name`` with ``samples`` per pixel (those of
    FIXED_SAMPLES have their own count)."""
    if name not in PATTERNS:
        raise ValueError(f"unknown sample pattern {name!r}; choose from {', '.join(PATTERNS)}")
    samples = FIXED_SAMPLES.get(name, samples)
    if samples not in D3D_PATTERNS:
        raise ValueError(f"samples must be one of {sorted(D3D_PATTERNS)}, not {samples}")
    return SamplePattern(name, PATTERNS[name](samples), _TILES.get(name, (1, 1)),
                         _FILTERS.get(name, "box"), shared=name in ("quincunx", "flipquad"))


def pattern_offsets(name: str, samples: int) -> np.ndarray:
    """(n, 2) offsets of a pattern that is the same in every pixel."""
    offsets = sample_pattern(name, samples).offsets
    if offsets.shape[0] != 1:
        raise ValueError(f"pattern {name!r} differs between pixels")
    return offsets[0]


def a2c_order(offs: np.ndarray) -> np.ndarray:
    """Fixed order in which alpha-to-coverage turns samples on: farthest-point order, so any
    prefix is spread over the pixel (as hardware dither patterns are)."""
    samples = len(offs)
    order = [int(np.argmin(np.hypot(offs[:, 0], offs[:, 1])))]
    while len(order) < samples:
        d = np.min(np.hypot(offs[:, None, 0] - offs[None, order, 0],
                            offs[:, None, 1] - offs[None, order, 1]), axis=1)
        d[order] = -1
        order.append(int(np.argmax(d)))
    return np.asarray(order, dtype=np.int64)
