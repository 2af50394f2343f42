"""Resolve filters, and the resolve of samples that a pixel does not own alone.

A filter is a separable weight w(dx) w(dy) of a sample at (dx, dy) pixels from the pixel's
centre; a pixel is the w-weighted mean of every sample in the filter's support. ``box`` and
``tent`` weigh the pixel's own samples, and those on its edges that a pattern shares with its
neighbours (quincunx, FLIPQUAD: the support is then the closed pixel); ``tent1``, ``gaussian``
and ``mitchell`` reach into the neighbouring pixels.

With a pattern whose samples are the pixel's own (SamplePattern.per_pixel) and a filter within
the pixel, the kernels resolve each pixel from its samples (scan.render_msaa); a tile of such
patterns (interleaved) with such a filter is one such render per class of the tile, each
pixel taken from its class's render. Otherwise a pixel needs its neighbours' samples: the band
is rendered once per stored sample (and per class of the pattern's tile), each render with
that one sample per pixel, into *sample images* with a margin of ``apron`` pixels on every
side; the pixel is then the weighted sum of the sample images around it (:func:`accumulate`).
A sample image's pixels do not depend on where the band begins, so neither does the result.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import njit

#: support radius (pixels) of each filter of modes.FILTERS
RADIUS = {"box": 0.5, "tent": 0.5, "tent1": 1.0, "gaussian": 1.5, "mitchell": 2.0}
#: the Gaussian's standard deviation (pixels), cut at RADIUS and lowered to reach 0 there
GAUSS_SIGMA = 0.5


def _mitchell(x, b=1 / 3, c=1 / 3):
    """Mitchell–Netravali cubic (B = C = 1/3) on [-2, 2]."""
    x = np.abs(x)
    near = ((12 - 9 * b - 6 * c) * x ** 3 + (-18 + 12 * b + 6 * c) * x ** 2 + (6 - 2 * b)) / 6
    far = ((-b - 6 * c) * x ** 3 + (6 * b + 30 * c) * x ** 2 + (-12 * b - 48 * c) * x
           + (8 * b + 24 * c)) / 6
    return np.where(x < 1, near, np.where(x < 2, far, 0.0))


def filter_weight_1d(name: str, x) -> np.ndarray:
    """The filter's 1-D weight at x pixels from the pixel centre (0 outside its support)."""
    x = np.abs(np.asarray(x, dtype=np.float64))
    r = RADIUS[name]
    if name == "box":
        return (x <= r).astype(np.float64)
    if name in ("tent", "tent1"):
        return np.where(x <= r, 1.0 - x, 0.0)
    if name == "gaussian":
        g = np.exp(-x * x / (2 * GAUSS_SIGMA ** 2)) - math.exp(-r * r / (2 * GAUSS_SIGMA ** 2))
        return np.where(x <= r, g, 0.0)
    if name == "mitchell":
        return _mitchell(x)
    raise ValueError(f"unknown filter {name!r}")


def filter_weight(name: str, dx, dy) -> np.ndarray:
    return filter_weight_1d(name, dx) * filter_weight_1d(name, dy)


def apron(name: str) -> int:
    """Pixels of neighbours on each side whose samples (at most half a pixel from their
    centres) can fall in the filter's support."""
    return int(math.floor(RADIUS[name] + 0.5))


def resolve_weights(pattern, name: str) -> np.ndarray:
    """(classes, 2R+1, 2R+1, n) float64: the weight, in the pixel of each class of the
    pattern's tile, of sample s of the pixel (dx, dy) away ([.., R + dy, R + dx, s]),
    normalised to sum to 1 per class."""
    tw, th = pattern.tile
    # a filter within the pixel weighs its own samples, and those it shares on its edges
    R = apron(name) if pattern.shared or RADIUS[name] > 0.5 else 0
    n = pattern.samples
    out = np.zeros((tw * th, 2 * R + 1, 2 * R + 1, n))
    for cy in range(th):
        for cx in range(tw):
            w = out[cy * tw + cx]
            for dy in range(-R, R + 1):
                for dx in range(-R, R + 1):
                    k = ((cy + dy) % th) * tw + (cx + dx) % tw
                    o = pattern.offsets[k]
                    w[R + dy, R + dx] = filter_weight(name, dx + o[:, 0], dy + o[:, 1])
            total = w.sum()
            if not total > 0:
                raise ValueError(f"filter {name!r} weighs no sample of pattern {pattern.name!r}")
            w /= total
    return out


def sample_classes(tile, y0: int, x0: int, rows: int, cols: int) -> np.ndarray:
    """(rows, cols) tile class of the pixels from device row y0 and column x0."""
    tw, th = tile
    return (np.arange(y0, y0 + rows) % th)[:, None] * tw + (np.arange(x0, x0 + cols) % tw)[None, :]


def accumulate(acc: np.ndarray, y0: int, weights: np.ndarray, tile, s: int, image) -> None:
    """Add sample image ``s`` ((rows + 2R, W + 2R, 4) float32, device rows y0 - R.. and columns
    -R..) into ``acc`` ((rows, W, 4) float32, device rows y0..) with the resolve weights."""
    rows, W = acc.shape[:2]
    R = (weights.shape[1] - 1) // 2
    term = np.empty((image.shape[0], W, 4), np.float32)     # products land here, not in temporaries
    if len(weights) == 1:
        w = weights[0, :, :, s]
        a, b = w.sum(axis=1), w.sum(axis=0)
        if R > 0 and a.sum() > 0 and np.allclose(np.outer(a, b) / a.sum(), w, rtol=0, atol=1e-12):
            # one class and a separable filter: a pass along x, then one along y (2(2R + 1)
            # products, not (2R + 1)²)
            add_separable(acc, np.ascontiguousarray(image), (b / a.sum()).astype(np.float32),
                          a.astype(np.float32), term)
            return
        for dy, dx in zip(*np.nonzero(w)):
            np.multiply(image[dy:dy + rows, dx:dx + W], np.float32(w[dy, dx]), out=term[:rows])
            acc += term[:rows]
        return
    cls = sample_classes(tile, y0, 0, rows, W).astype(np.int64)
    taps = weights[:, :, :, s].astype(np.float32)
    used = taps.any(axis=0).astype(np.bool_)
    add_by_class(acc, np.ascontiguousarray(image), taps, used, cls)


@njit(cache=True, nogil=True)   # bands resolve on threads
def add_separable(acc, image, bx, ay, along_x):
    """acc[y, x] += Σ_dy ay[dy] · (Σ_dx bx[dx] · image[y + dy, x + dx]): a pass along x into
    ``along_x`` (the image's rows, acc's width), then one along y, each over the non-zero taps
    in order and rounded to float32 at every step as numpy's multiply-and-add passes were, in
    one sweep instead of two numpy passes (and a temporary) per tap. Rows are walked as flat
    runs of floats, which vectorise (indexing [y, x, c] does not)."""
    rows, n = acc.shape[0], 4 * acc.shape[1]
    for y in range(image.shape[0]):
        src = image[y].reshape(-1)
        out = along_x[y].reshape(-1)
        out[:] = 0.0
        for dx in range(bx.shape[0]):
            w = bx[dx]
            if w == 0.0:
                continue
            o = 4 * dx
            for i in range(n):
                out[i] += src[o + i] * w
    for y in range(rows):
        out = acc[y].reshape(-1)
        for dy in range(ay.shape[0]):
            w = ay[dy]
            if w == 0.0:
                continue
            src = along_x[y + dy].reshape(-1)
            for i in range(n):
                out[i] += src[i] * w


@njit(cache=True, nogil=True)   # bands resolve on threads
def add_by_class(acc, image, taps, used, cls):
    """acc[y, x] += Σ taps[cls[y, x], dy, dx] · image[y + dy, x + dx] over the taps some class
    uses (``used``), in (dy, dx) order, float32 at every step as the numpy passes per tap were:
    the weights of the pixel's own tile class, without a per-tap array of them."""
    rows, W = acc.shape[0], acc.shape[1]
    for y in range(rows):
        for x in range(W):
            k = cls[y, x]
            for dy in range(taps.shape[1]):
                for dx in range(taps.shape[2]):
                    if used[dy, dx]:
                        w = taps[k, dy, dx]
                        for c in range(4):
                            acc[y, x, c] += image[y + dy, x + dx, c] * w


def finish(acc: np.ndarray, out: np.ndarray) -> None:
    """``out`` = ``acc`` clamped to a premultiplied colour (Mitchell's negative lobes can leave
    [0, 1])."""
    np.clip(acc[..., 3], 0.0, 1.0, out=acc[..., 3])
    np.clip(acc[..., :3], 0.0, acc[..., 3:4], out=acc[..., :3])
    out[:] = acc
