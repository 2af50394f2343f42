"""sRGB → linearRGB for scene paints (masks with ``color-interpolation: linearRGB``): the
front end converts solid colours and gradient stops, the raster a pattern's rendered tile."""
from __future__ import annotations

import numpy as np


def srgb_to_linear(c):
    """The sRGB transfer function inverted (IEC 61966-2-1), element-wise, in float64."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_rgb_image(rgba: np.ndarray) -> np.ndarray:
    """A premultiplied float32 RGBA image with its colours in linearRGB (a new array)."""
    rgba = rgba.astype(np.float32).copy()
    alpha = rgba[..., 3:4]
    straight = np.divide(rgba[..., :3], alpha, out=np.zeros_like(rgba[..., :3]),
                         where=alpha > 0)
    rgba[..., :3] = srgb_to_linear(straight).astype(np.float32) * alpha
    return rgba
