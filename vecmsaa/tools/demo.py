"""``vecmsaa demo``: Figure 1 of Schwarz & Stamminger rendered in every coverage mode, side by
side, with each mode's error image against the conflation-free ground truth."""
from __future__ import annotations

import numpy as np

from .accuracy import edge_error, edge_mask, figure1_scene, ground_truth
from ..raster.render import render_scene
from ..output.rgba8 import to_rgba8

DEMO_MODES = ("none", "alpha", "a2c", "persample", "approx", "analytic")


def demo_image(size: int = 48, zoom: int = 6, samples: int = 8) -> np.ndarray:
    """An RGBA uint8 sheet: top row the renders, bottom row |error| × 4 as a heat map."""
    from PIL import Image, ImageDraw

    scene = figure1_scene(size)
    truth = ground_truth(scene)
    mask = edge_mask(truth)
    tiles = [("reference (1024 spp)", truth, None)]
    for mode in DEMO_MODES:
        img = render_scene(scene, mode=mode, samples=samples)
        label = mode if mode in ("none", "analytic") else f"{mode} ({samples}x)"
        tiles.append((label, img, edge_error(img, truth, mask)))
    tile = size * zoom
    pad, head = 8, 34
    sheet = Image.new("RGBA", (len(tiles) * (tile + pad) + pad, 2 * (tile + head) + pad),
                      (255, 255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for i, (label, img, err) in enumerate(tiles):
        x = pad + i * (tile + pad)
        big = Image.fromarray(to_rgba8(img)).resize((tile, tile), Image.NEAREST)
        sheet.paste(big, (x, head))
        draw.text((x, 4), label, fill=(0, 0, 0, 255))
        if err is None:
            draw.text((x, 16), "ground truth", fill=(90, 90, 90, 255))
            continue
        draw.text((x, 16), f"edge error {err * 255:.2f}/255", fill=(90, 90, 90, 255))
        diff = np.abs(img.astype(np.float64) - truth).max(axis=-1)
        heat = np.clip(diff * 4.0, 0, 1)
        rgb = np.stack([np.ones_like(heat), 1 - heat, 1 - heat], axis=-1) * 255  # white = exact
        himg = Image.fromarray(rgb.astype(np.uint8)).resize((tile, tile), Image.NEAREST)
        y = 2 * head + tile - 16
        draw.text((x, y - 14), "|error| x 4", fill=(90, 90, 90, 255))
        sheet.paste(himg, (x, y))
    return np.asarray(sheet)
