"""Coverage-sample antialiasing (CSAA) measured: n coverage samples with K stored colours per
pixel against plain K- and n-sample MSAA, on Figure 1, random scenes and the failure case the
seed names (a pixel needing more distinct colours than slots), with error, time and the storage
a split pixel needs.

Storage per split pixel (the framebuffer's compressed form keeps one colour for the others),
read from the sizes of the raster's buffers: plain n-sample MSAA stores n colours (16 bytes each,
float32 RGBA); CSAA (raster/csaa.py) stores K colours plus a one-byte table index per coverage
sample.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..raster.render import Raster, RenderOptions, render_scene
from ..scene.nodes import Fill, Group, Scene, Solid
from ..scene.path import Path
from .accuracy import edge_error, edge_mask, figure1_scene, ground_truth, random_scene

#: (coverage samples, colour slots): plain 4x and 16x MSAA, and CSAA 16 / 4 and 16 / 2
CONFIGS = ((4, None), (16, None), (16, 8), (16, 4), (16, 2))


def fan_scene(size: int = 48, wedges: int = 8, fans: int = 3) -> Scene:
    """The failure case: fans × fans pinwheels of ``wedges`` opaque triangles in distinct hues
    meeting at one point inside a pixel, so that pixel holds ``wedges`` colours (more than K
    slots) and its neighbours several (wedges must not be a multiple of 3). Centres sit off the
    sample rows and columns."""
    fills = []
    step = size / fans
    radius = 0.42 * step
    for i in range(fans):
        for j in range(fans):
            cx = (i + 0.5) * step + 0.1234
            cy = (j + 0.5) * step + 0.0617
            for w in range(wedges):
                a0 = 2 * math.pi * (w + 0.37 * i + 0.21 * j) / wedges
                a1 = a0 + 2 * math.pi / wedges
                p = Path()
                p.moveTo((cx, cy))
                p.lineTo((cx + radius * math.cos(a0), cy + radius * math.sin(a0)))
                p.lineTo((cx + radius * math.cos(a1), cy + radius * math.sin(a1)))
                p.closePath()
                # neighbouring wedges far apart in hue: a dropped colour's nearest is far
                h = (3 * w % wedges) / wedges
                # and of differing brightness, so no two colours are equally near a third
                # (the table's choice then does not hang on rounding)
                rgb = tuple((0.45 + 0.45 * math.cos(2 * math.pi * (h + k / 3))) * (1 - 0.07 * w)
                            + 0.05 for k in range(3))
                fills.append(Fill(p, Solid(rgb + (1.0,))))
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def storage_bytes(samples: int, slots: int | None) -> int:
    """Bytes the raster allocates for one split pixel's samples: the arrays of its buffers with a
    slot per pixel (n colours, or K colours and n table indices), for a strip of 1 × 2 pixels."""
    opts = RenderOptions("approx", samples, color_samples=slots)
    return sum(a.nbytes for a in Raster(opts, 2, 1, 1).scratch
               if a.ndim > 1 and a.shape[0] == 2) // 2


def _timed(scene, mode, samples, slots, repeat):
    render_scene(scene, mode=mode, samples=samples, color_samples=slots)   # compile, warm
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        img = render_scene(scene, mode=mode, samples=samples, color_samples=slots)
        best = min(best, time.perf_counter() - t0)
    return img, best


def rows(mode: str = "approx", size: int = 128, repeat: int = 3, quick: bool = False,
         log=None) -> list[dict]:
    """One row per (scene, configuration): edge-pixel error × 255 against the 1024-sample
    reference, the largest pixel error × 255, best-of-``repeat`` render time, storage."""
    scenes = [(f"Figure 1 ({size} px)", [figure1_scene(size)]),
              (f"random scenes 1000-100{1 if quick else 3} ({size} px)",
               [random_scene(1000 + i, size) for i in range(2 if quick else 4)]),
              (f"fans of 8 colours ({size} px)", [fan_scene(size, 8, max(1, size // 16))])]
    out = []
    for name, group in scenes:
        if log:
            log(f"csaa: {name}")
        truths = [ground_truth(s) for s in group]
        masks = [edge_mask(t) for t in truths]
        plain = {}
        for samples, slots in CONFIGS:
            err = worst = damage = seconds = 0.0
            for i, (scene, truth, mask) in enumerate(zip(group, truths, masks)):
                img, t = _timed(scene, mode, samples, slots, repeat)
                if slots is None:
                    plain[samples, i] = img
                err += edge_error(img, truth, mask) * 255 / len(group)
                worst = max(worst, float(np.abs(img - truth).max()) * 255)
                # what the colour table alone costs: the largest change from n-sample MSAA
                damage = max(damage, float(np.abs(img - plain[samples, i]).max()) * 255)
                seconds += t
            out.append(dict(scene=name, mode=mode, samples=samples, slots=slots or samples,
                            bytes=storage_bytes(samples, slots), error=err, worst=worst,
                            versus_msaa=damage, ms=seconds * 1000))
    return out


def write_study(out_dir: str, quick: bool = False, repeat: int | None = None, log=None) -> str:
    """``vecmsaa bench --csaa``: csaa.md (the table) and csaa.json in out_dir."""
    import json
    import os

    os.makedirs(out_dir, exist_ok=True)
    found = rows(size=64 if quick else 256, repeat=repeat or (1 if quick else 5), quick=quick,
                 log=log)
    text = table(found)
    with open(os.path.join(out_dir, "csaa.md"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out_dir, "csaa.json"), "w") as f:
        json.dump(found, f, indent=1)
    return text


def table(rows_: list[dict]) -> str:
    lines = ["| scene | coverage samples | colours | bytes per split pixel | edge error ×255 "
             "| worst pixel ×255 | worst change from n-sample MSAA ×255 | time (ms) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows_:
        kind = "MSAA" if r["slots"] == r["samples"] else "CSAA"
        lines.append(f"| {r['scene']} | {r['samples']} ({kind}) | {r['slots']} | {r['bytes']} "
                     f"| {r['error']:.3f} | {r['worst']:.1f} | {r['versus_msaa']:.1f} "
                     f"| {r['ms']:.1f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(table(rows(log=print)))
