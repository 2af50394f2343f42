"""``vecmsaa demo``: Figure 1 of Schwarz & Stamminger rendered in every coverage mode, side by
side, with a magnified inset of the shared boundary and each mode's error image against the
conflation-free ground truth.

Two errors are printed under each mode, both mean |render − truth| over premultiplied RGBA
(× 255): on the **shared boundary** (pixels that the red and the green region both touch and the
blue one does not — where conflation shows as a dark seam) and on the **whole picture**. The
shared-boundary mask comes from rendering each region alone at the ground truth's sampling, not
from any mode under test.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..output.rgba8 import to_rgba8
from ..raster.modes import MODES
from ..raster.render import render_scene
from .accuracy import GROUND_TRUTH_SAMPLES, figure1_scene, ground_truth

#: every mode but the reference, which is the ground truth the errors are measured against;
#: alpha-sat beside alpha, whose seam it removes
DEMO_MODES = tuple(sorted((m for m in MODES if m != "reference"),
                          key=lambda m: MODES.index("alpha") + 0.5 if m == "alpha-sat"
                          else MODES.index(m)))
#: shared-boundary pixels: touched by both regions (coverage above this), by the third not at all
TOUCHED = 0.02
INSET_PIXELS = 10


def shared_boundary_mask(scene) -> np.ndarray:
    """Pixels covered in part by both halves of the canvas (its first two fills) and not by the
    region over them (the third), each rendered alone at the ground truth's sampling."""
    top, bottom, over = scene.root.children[:3]

    def coverage(fill):
        alone = replace(scene, root=replace(scene.root, children=[fill]), background=(0, 0, 0, 0))
        return render_scene(alone, mode="reference", samples=GROUND_TRUTH_SAMPLES)[..., 3]
    return (coverage(top) > TOUCHED) & (coverage(bottom) > TOUCHED) & (coverage(over) == 0)


def mode_errors(img: np.ndarray, truth: np.ndarray, boundary: np.ndarray) -> tuple[float, float]:
    """(shared-boundary error, whole-picture error), mean absolute difference × 255."""
    diff = np.abs(img.astype(np.float64) - truth).max(axis=-1) * 255.0
    return float(diff[boundary].mean()) if boundary.any() else 0.0, float(diff.mean())


def inset_window(boundary: np.ndarray, size: int = INSET_PIXELS) -> tuple[int, int]:
    """Top-left corner of a size × size window centred on the shared boundary's median pixel."""
    ys, xs = np.nonzero(boundary)
    h, w = boundary.shape
    if len(ys) == 0:
        return max(0, (h - size) // 2), max(0, (w - size) // 2)
    k = np.argsort(xs)[len(xs) // 2]
    y0 = int(np.clip(ys[k] - size // 2, 0, max(0, h - size)))
    x0 = int(np.clip(xs[k] - size // 2, 0, max(0, w - size)))
    return y0, x0


def _font(size: int):
    from PIL import ImageFont
    try:
        return ImageFont.load_default(size=size)   # Pillow's bundled scalable font (FreeType)
    except (TypeError, OSError):
        return ImageFont.load_default()


def demo_image(size: int = 36, zoom: int = 3, samples: int = 8) -> np.ndarray:
    """An RGBA uint8 sheet, one column per mode: the render, the shared-boundary inset
    (magnified, outlined in the render), and |error| × 4 as a heat map, with both errors."""
    from PIL import Image, ImageDraw

    scene = figure1_scene(size)
    truth = ground_truth(scene)
    boundary = shared_boundary_mask(scene)
    y0, x0 = inset_window(boundary)
    n = min(INSET_PIXELS, size)
    tile = size * zoom
    inset_zoom = max(1, tile // n)
    columns = [("reference", f"{GROUND_TRUTH_SAMPLES} spp", truth)]
    for mode in DEMO_MODES:
        detail = "" if mode in ("none", "analytic") else f"{samples} samples"
        columns.append((mode, detail, render_scene(scene, mode=mode, samples=samples)))
    # labels sized for a sheet of about 900 px shown at README width: 18 and 14 px at least
    big_px, small_px = max(18, tile // 6), max(14, tile // 8)
    big, small = _font(big_px), _font(small_px)
    pad, head, line = 8, big_px + small_px + 10, small_px + 4
    col = max(tile, n * inset_zoom)
    height = head + tile + pad + n * inset_zoom + pad + tile + 4 + 3 * line + 2 * pad
    sheet = Image.new("RGBA", (len(columns) * (col + pad) + pad, height), (255, 255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    grey = (80, 80, 80, 255)
    for i, (label, detail, img) in enumerate(columns):
        x = pad + i * (col + pad)
        draw.text((x, 4), label, fill=(0, 0, 0, 255), font=big)
        draw.text((x, 4 + big_px + 4), detail, fill=grey, font=small)
        rgba = Image.fromarray(to_rgba8(img))
        y = head
        sheet.paste(rgba.resize((tile, tile), Image.NEAREST), (x, y))
        draw.rectangle((x + x0 * zoom, y + y0 * zoom, x + (x0 + n) * zoom - 1,
                        y + (y0 + n) * zoom - 1), outline=(255, 255, 255, 255))
        y += tile + pad
        crop = rgba.crop((x0, y0, x0 + n, y0 + n)).resize((n * inset_zoom, n * inset_zoom),
                                                         Image.NEAREST)
        sheet.paste(crop, (x, y))
        y += n * inset_zoom + pad
        diff = np.abs(img.astype(np.float64) - truth).max(axis=-1)
        heat = np.clip(diff * 4.0, 0, 1)
        rgb = np.stack([np.ones_like(heat), 1 - heat, 1 - heat], axis=-1) * 255  # white = exact
        sheet.paste(Image.fromarray(rgb.astype(np.uint8)).resize((tile, tile), Image.NEAREST),
                    (x, y))
        draw.rectangle((x - 1, y - 1, x + tile, y + tile), outline=(200, 200, 200, 255))
        y += tile + 4
        if img is truth:
            draw.text((x, y), "ground truth", fill=grey, font=small)
            continue
        seam, whole = mode_errors(img, truth, boundary)
        draw.text((x, y), f"boundary {seam:.1f}", fill=(0, 0, 0, 255), font=small)
        draw.text((x, y + line), f"whole {whole:.2f}", fill=grey, font=small)
    draw.text((pad, height - line - pad // 2), "top: render; middle: shared boundary magnified; "
              "bottom: |error| x 4 (white = exact); mean |difference| x 255", fill=grey,
              font=small)
    return np.asarray(sheet)
