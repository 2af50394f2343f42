"""Image comparison with the project's pass criterion (../shared/README.md), and the one
picture of a difference that golden checks, the suite runner and the font reference write.

Both images are compared in premultiplied RGBA, 8 bits per channel; a pixel is *off* when any
channel differs by more than ``threshold`` (48); images *match* when at most ``max_fraction``
(0.2%) of pixels are off and the sizes agree. :func:`triptych` shows expected | difference |
actual side by side.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..files import write_bytes_atomic
from ..output.png import encode_png

THRESHOLD = 48
MAX_FRACTION = 0.002
#: golden checks: a pixel away from edges (its 3x3 neighbourhood varies by at most FLAT_SPREAD
#: in both images) is off when a channel differs by more than FLAT_THRESHOLD. Measured on the
#: corpus and suite drawings (docs/golden.md), 4 or 8 samples and analytic coverage against 16
#: samples differ there by at most 1; a one-colour change of 16 levels on a shape exceeds it.
FLAT_SPREAD = 4
FLAT_THRESHOLD = 8


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
    if a.dtype == np.uint8:
        # (c * alpha + 127) // 255 is c * alpha / 255 rounded to the nearest (it is never a
        # half), which (t + (t >> 8)) >> 8 gives for t = c * alpha + 128 in 16 bits: 7 times
        # as fast as the division in int32 (the suite judged a 200 px test in 11 ms, 2.5 times
        # its render); tests/test_batch_overhead.py checks every (c, alpha)
        t = a.astype(np.uint16)
        t *= t[..., 3:4].copy()
        t += 128
        t += t >> 8
        t >>= 8
        out = t.view(np.int16)
        out[..., 3] = a[..., 3]
        return out
    a = a.astype(np.int32)
    alpha = a[..., 3:4]
    rgb = (a[..., :3] * alpha + 127) // 255
    return np.concatenate([rgb, alpha], axis=-1).astype(np.int16)


def largest_channel(d: np.ndarray) -> np.ndarray:
    """(H, W) the largest of the 4 channels of (H, W, 4) ``d``: ``d.max(axis=-1)``, as three
    element-wise maxima (numpy's reduction over 4 values a pixel took 20 times as long)."""
    return np.maximum(np.maximum(d[..., 0], d[..., 1]), np.maximum(d[..., 2], d[..., 3]))


def channel_difference(actual, expected):
    """(H, W) largest premultiplied channel difference per pixel, or None when sizes differ."""
    a = premultiplied_u8(actual)
    e = premultiplied_u8(expected)
    if a.shape != e.shape:
        return None
    return largest_channel(np.abs(a - e))


def flat_areas(premultiplied: np.ndarray, spread: int) -> np.ndarray:
    """(H, W) bool: pixels whose 3x3 neighbourhood (clamped at the border) varies by at most
    ``spread`` in every channel, i.e. pixels no edge passes near."""
    padded = np.pad(premultiplied, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = premultiplied.shape[:2]
    views = [padded[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)]
    low, high = views[0].copy(), views[0].copy()
    for view in views[1:]:
        np.minimum(low, view, out=low)
        np.maximum(high, view, out=high)
    return ((high - low) <= spread).all(axis=-1)


def compare_images(actual, expected, threshold: int = THRESHOLD,
                   flat_threshold: int | None = None) -> Comparison:
    """Compare two straight-alpha RGBA images (PIL images or uint8 arrays).

    With ``flat_threshold``, a pixel in a flat area of both images (:func:`flat_areas` with
    FLAT_SPREAD) is off already when a channel differs by more than
    ``flat_threshold``: antialiasing noise lives on edges, so away from them the comparison can
    be strict and still pass it, while a colour change shows inside every shape."""
    a, e = premultiplied_u8(actual), premultiplied_u8(expected)
    if a.shape != e.shape:
        h, w = np.asarray(expected).shape[:2]
        return Comparison(False, h * w, h * w, 255, None)
    diff = largest_channel(np.abs(a - e))
    off = diff > threshold
    if flat_threshold is not None and flat_threshold < threshold:
        flat = flat_areas(a, FLAT_SPREAD) & flat_areas(e, FLAT_SPREAD)
        off |= flat & (diff > flat_threshold)
    return Comparison(True, int(off.sum()), int(off.size), int(diff.max(initial=0)), off)


PANEL_GAP = 4                          # px of neutral background between panels
GAP_COLOR = (64, 64, 64, 255)
CHECKER = (204, 255)                   # grey levels of the transparency checkerboard
CHECKER_CELL = 8                       # checkerboard square, in output pixels
MIN_PANEL = 128                        # small images are enlarged (nearest) up to this size
MAX_ZOOM = 16
OFF_COLOR = (230, 0, 0)                # pixels off
NEAR_COLOR = (0, 90, 255)              # pixels that differ but are not off
#: the signed map (``signed=True``): where the actual image has more ink (is darker over
#: white) than the expected one, and where it has less
MORE_INK_COLOR = (230, 0, 0)
LESS_INK_COLOR = (0, 60, 255)


def _zoom_for(*images) -> int:
    largest = max(max(im.shape[:2]) for im in images if im is not None)
    return int(min(MAX_ZOOM, max(1, math.ceil(MIN_PANEL / max(largest, 1)))))


def _over_checkerboard(rgba: np.ndarray, zoom: int) -> np.ndarray:
    """Straight RGBA → opaque RGB over a checkerboard (so transparency is visible in any
    viewer), enlarged ``zoom`` times with nearest neighbour."""
    premul = premultiplied_u8(rgba).astype(np.int32)
    premul = premul.repeat(zoom, axis=0).repeat(zoom, axis=1)
    h, w = premul.shape[:2]
    yy, xx = np.indices((h, w))
    checker = np.where(((yy // CHECKER_CELL) + (xx // CHECKER_CELL)) % 2 == 0,
                       CHECKER[0], CHECKER[1])[..., None]
    rgb = premul[..., :3] + ((255 - premul[..., 3:4]) * checker + 127) // 255
    return rgb.astype(np.uint8)


def _luma_over_white(rgba) -> np.ndarray:
    """(H, W) luma (0-255) of a straight RGBA image composited over white."""
    p = premultiplied_u8(rgba).astype(np.int32)
    return ((p[..., :3] + (255 - p[..., 3:4])) @ np.array([77, 150, 29])) >> 8


def heat_map(expected: np.ndarray, actual: np.ndarray, threshold: int,
             flat_threshold: int | None = None, signed: bool = False) -> np.ndarray:
    """Opaque RGB (H, W, 3): the expected image faded to light grey for orientation; pixels
    that differ but are not off in blue, stronger as they differ more; off pixels (beyond the
    threshold, or away from edges beyond ``flat_threshold``: those the criterion counts) in
    red. ``signed`` colours by the direction instead (coverage errors, as the font reference
    shows them): MORE_INK_COLOR where the actual image is darker over white, LESS_INK_COLOR
    where it is lighter, stronger as they differ more and full for off pixels."""
    luma = _luma_over_white(expected)
    out = np.repeat((191 + luma // 4)[..., None], 3, axis=-1)   # squeezed into 191..255
    diff = channel_difference(actual, expected).astype(np.int32)
    off = compare_images(actual, expected, threshold, flat_threshold).off_map
    near = (diff > 0) & (diff <= threshold)
    strength = np.zeros_like(diff)
    strength[near] = 64 + 191 * diff[near] // max(threshold, 1)
    strength[off] = 255
    if signed:
        more = _luma_over_white(actual) < luma
        target = np.where(more[..., None], np.array(MORE_INK_COLOR), np.array(LESS_INK_COLOR))
        out = (out * (255 - strength[..., None]) + target * strength[..., None]) // 255
        return out.astype(np.uint8)
    out[near] = (out[near] * (255 - strength[near][:, None])
                 + np.array(NEAR_COLOR) * strength[near][:, None]) // 255
    out[off] = OFF_COLOR
    return out.astype(np.uint8)


def triptych(expected: np.ndarray | None, actual: np.ndarray | None,
             threshold: int = THRESHOLD, flat_threshold: int | None = None,
             signed: bool = False) -> np.ndarray:
    """expected | difference heat map | actual, side by side, as straight RGBA uint8.

    A missing image (no golden, failed render) leaves its panel empty; the heat map (signed:
    more and less ink, see :func:`heat_map`) needs both images at the same size and is empty
    otherwise. Small images are enlarged so single pixels stay visible."""
    zoom = _zoom_for(expected, actual)
    panels = [None, None, None]
    if expected is not None:
        panels[0] = _over_checkerboard(expected, zoom)
    if actual is not None:
        panels[2] = _over_checkerboard(actual, zoom)
    if expected is not None and actual is not None and expected.shape == actual.shape:
        panels[1] = heat_map(expected, actual, threshold, flat_threshold,
                             signed).repeat(zoom, 0).repeat(zoom, 1)
    shown = [p for p in panels if p is not None]
    height = max(p.shape[0] for p in shown)
    width = max(p.shape[1] for p in shown)
    out = np.empty((height, 3 * width + 2 * PANEL_GAP, 4), np.uint8)
    out[:] = GAP_COLOR
    for i, panel in enumerate(panels):
        x = i * (width + PANEL_GAP)
        if panel is None:
            out[:, x:x + width, :3] = 128      # empty panel: flat mid grey
        else:
            out[:panel.shape[0], x:x + panel.shape[1], :3] = panel
    return out


def write_triptych(path, expected, actual, threshold: int = THRESHOLD,
                   flat_threshold: int | None = None, signed: bool = False) -> None:
    write_bytes_atomic(encode_png(triptych(expected, actual, threshold, flat_threshold, signed)),
                       path, make_folders=True)
