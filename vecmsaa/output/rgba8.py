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
def unpremultiply_to_rgba8(img, out):
    """Premultiplied float32 RGBA (clamped to [0, 1]) → straight uint8 RGBA in ``out`` (same
    height and width), rounded half up. Every step is rounded to float32, as numpy computed
    it before this kernel existed, so the bytes did not change; NaN counts as 0."""
    tiny, scale, half = np.float32(1e-12), np.float32(255.0), np.float32(0.5)
    for y in range(img.shape[0]):
        for x in range(img.shape[1]):
            a = _unit(img[y, x, 3])
            if a >= 1.0:
                # opaque (most pixels): dividing by 1 changes nothing
                out[y, x, 3] = 255
                for c in range(3):
                    v = _unit(img[y, x, c])
                    out[y, x, c] = np.uint8(min(np.float32(np.float32(v * scale) + half), scale))
                continue
            out[y, x, 3] = np.uint8(np.float32(a * scale) + half)
            if a > 0.0:
                d = max(a, tiny)
                for c in range(3):
                    v = np.float32(_unit(img[y, x, c]) / d)
                    out[y, x, c] = np.uint8(min(np.float32(np.float32(v * scale) + half), scale))
            else:
                out[y, x, 0] = out[y, x, 1] = out[y, x, 2] = 0


def to_rgba8(img: np.ndarray) -> np.ndarray:
    """Premultiplied float RGBA → straight uint8 RGBA (float32 arithmetic)."""
    img = np.ascontiguousarray(img, dtype=np.float32)
    out = np.empty(img.shape[:2] + (4,), dtype=np.uint8)
    unpremultiply_to_rgba8(img, out)
    return out


def to_pil(img: np.ndarray):
    from PIL import Image
    return Image.fromarray(to_rgba8(img), "RGBA")
