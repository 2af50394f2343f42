"""The way out of premultiplied float colour: straight RGBA bytes, as PNG and every encoder want."""
from __future__ import annotations

import numpy as np
from ..jit import njit


@njit(cache=True, inline="always")
def _unit(v):
    """v clamped to [0, 1] as float32, NaN → 0."""
    if v > 1.0:
        return np.float32(1.0)
    if v > 0.0:
        return np.float32(v)
    return np.float32(0.0)


@njit(cache=True, nogil=True)   # bands convert on threads
def unpremultiply_to_rgba8(img, out, refill):
    """Premultiplied float32 RGBA (clamped to [0, 1]) → straight uint8 RGBA in ``out`` (same
    height and width), rounded half up. Every step is rounded to float32, as numpy computed
    it before this kernel existed, so the bytes did not change; NaN counts as 0.

    ``refill``: 4 float32 (a premultiplied colour) written over each pixel of ``img`` once it
    is read — the next band's background, set while the band is in the cache rather than in a
    pass of its own over memory — or an empty array to leave ``img`` as it is."""
    tiny, scale, half = np.float32(1e-12), np.float32(255.0), np.float32(0.5)
    again = refill.shape[0] == 4
    for y in range(img.shape[0]):
        for x in range(img.shape[1]):
            r, g, b, a = _unit(img[y, x, 0]), _unit(img[y, x, 1]), _unit(img[y, x, 2]), \
                _unit(img[y, x, 3])
            if again:
                img[y, x, 0], img[y, x, 1] = refill[0], refill[1]
                img[y, x, 2], img[y, x, 3] = refill[2], refill[3]
            if a >= 1.0:
                # opaque (most pixels): dividing by 1 changes nothing
                out[y, x, 0] = np.uint8(min(np.float32(np.float32(r * scale) + half), scale))
                out[y, x, 1] = np.uint8(min(np.float32(np.float32(g * scale) + half), scale))
                out[y, x, 2] = np.uint8(min(np.float32(np.float32(b * scale) + half), scale))
                out[y, x, 3] = 255
            elif a > 0.0:
                d = max(a, tiny)
                out[y, x, 0] = np.uint8(min(np.float32(np.float32(np.float32(r / d) * scale)
                                                      + half), scale))
                out[y, x, 1] = np.uint8(min(np.float32(np.float32(np.float32(g / d) * scale)
                                                      + half), scale))
                out[y, x, 2] = np.uint8(min(np.float32(np.float32(np.float32(b / d) * scale)
                                                      + half), scale))
                out[y, x, 3] = np.uint8(np.float32(a * scale) + half)
            else:
                out[y, x, 0] = out[y, x, 1] = out[y, x, 2] = out[y, x, 3] = 0


#: the ``refill`` of unpremultiply_to_rgba8 that leaves its image alone
NO_REFILL = np.empty(0, dtype=np.float32)


def to_rgba8(img: np.ndarray) -> np.ndarray:
    """Premultiplied float RGBA → straight uint8 RGBA (float32 arithmetic)."""
    img = np.ascontiguousarray(img, dtype=np.float32)
    out = np.empty(img.shape[:2] + (4,), dtype=np.uint8)
    unpremultiply_to_rgba8(img, out, NO_REFILL)
    return out


def to_pil(img: np.ndarray):
    from PIL import Image
    return Image.fromarray(to_rgba8(img), "RGBA")
