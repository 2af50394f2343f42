"""Image comparison with the project's pass criterion (../shared/README.md).

Both images are compared in premultiplied RGBA, 8 bits per channel; a pixel is *off* when any
channel differs by more than ``threshold`` (48); images *match* when at most ``max_fraction``
(0.2%) of pixels are off and the sizes agree.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

THRESHOLD = 48
MAX_FRACTION = 0.002


@dataclass
class Comparison:
    same_size: bool
    off_pixels: int
    total_pixels: int
    max_diff: int
    off_map: np.ndarray | None   # (H, W) bool, None when sizes differ

    @property
    def off_fraction(self) -> float:
        return self.off_pixels / self.total_pixels if self.total_pixels else 1.0

    def passed(self, max_fraction: float = MAX_FRACTION) -> bool:
        return self.same_size and self.off_fraction <= max_fraction

    def describe(self) -> str:
        if not self.same_size:
            return "size differs"
        return (f"{self.off_pixels} of {self.total_pixels} pixels off "
                f"({100 * self.off_fraction:.3f}%), max channel difference {self.max_diff}")


def premultiplied_u8(rgba) -> np.ndarray:
    """Straight 8-bit RGBA (array or PIL image) → premultiplied 8-bit RGBA as int16."""
    a = np.asarray(rgba)
    if a.ndim == 2:
        a = np.stack([a, a, a, np.full_like(a, 255)], axis=-1)
    elif a.shape[2] == 3:
        a = np.concatenate([a, np.full(a.shape[:2] + (1,), 255, a.dtype)], axis=-1)
    a = a.astype(np.int32)
    alpha = a[..., 3:4]
    rgb = (a[..., :3] * alpha + 127) // 255
    return np.concatenate([rgb, alpha], axis=-1).astype(np.int16)


def channel_difference(actual, expected):
    """(H, W) largest premultiplied channel difference per pixel, or None when sizes differ."""
    a = premultiplied_u8(actual)
    e = premultiplied_u8(expected)
    if a.shape != e.shape:
        return None
    return np.abs(a - e).max(axis=-1)


def compare_images(actual, expected, threshold: int = THRESHOLD) -> Comparison:
    """Compare two straight-alpha RGBA images (PIL images or uint8 arrays)."""
    diff = channel_difference(actual, expected)
    if diff is None:
        h, w = np.asarray(expected).shape[:2]
        return Comparison(False, h * w, h * w, 255, None)
    off = diff > threshold
    return Comparison(True, int(off.sum()), int(off.size), int(diff.max(initial=0)), off)
