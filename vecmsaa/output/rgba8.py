"""The way out of premultiplied float colour: straight RGBA bytes, as PNG and every encoder want."""
from __future__ import annotations

import numpy as np
from ..jit import njit


@njit(cache=True, nogil=True)   # bands convert on threads
def unpremultiply_to_rgba8(img, out, refill):
    """Premultiplied float32 RGBA (clamped to [0, 1]) → straight uint8 RGBA in ``out`` (same
    height and width), rounded half up. Every step is rounded to float32, as numpy computed
    it before this kernel existed, so the bytes did not change; NaN counts as 0.

    ``refill``: 4 float32 (a premultiplied colour) written over each pixel of ``img`` once it
    is read — the next band's background, set while the band is in the cache rather than in a
    pass of its own over memory — or an empty array to leave ``img`` as it is.

    Branch-free (selects, no jumps: a band's pixels alternate between opaque, transparent and
    edge, and the jumps of one branch each were mispredicted: 1.6x slower). An opaque pixel
    needs no case of its own: its channels divided by an alpha of exactly 1 are themselves."""
    tiny, scale, half = np.float32(1e-12), np.float32(255.0), np.float32(0.5)
    zero, one, none = np.float32(0.0), np.float32(1.0), np.uint8(0)
    again = refill.shape[0] == 4
    for y in range(img.shape[0]):
        row, orow = img[y], out[y]
        for x in range(img.shape[1]):
            r, g, b, a = row[x, 0], row[x, 1], row[x, 2], row[x, 3]
            # clamped to [0, 1] in this order, so that NaN becomes 0
            r, g = (r if r > zero else zero), (g if g > zero else zero)
            b, a = (b if b > zero else zero), (a if a > zero else zero)
            r, g = (r if r < one else one), (g if g < one else one)
            b, a = (b if b < one else one), (a if a < one else one)
            d = a if a > tiny else tiny
            shown = a > zero
            vr = min(np.float32(np.float32(r / d) * scale) + half, scale)
            vg = min(np.float32(np.float32(g / d) * scale) + half, scale)
            vb = min(np.float32(np.float32(b / d) * scale) + half, scale)
            va = np.float32(a * scale) + half
            orow[x, 0] = np.uint8(np.int32(vr)) if shown else none
            orow[x, 1] = np.uint8(np.int32(vg)) if shown else none
            orow[x, 2] = np.uint8(np.int32(vb)) if shown else none
            orow[x, 3] = np.uint8(np.int32(va)) if shown else none
        if again:
            for x in range(img.shape[1]):
                row[x, 0], row[x, 1] = refill[0], refill[1]
                row[x, 2], row[x, 3] = refill[2], refill[3]


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
