"""Accuracy of the coverage modes against ground truth, on the paper's Figure 1 situation and on
random scenes of the same kind (regions sharing curved boundaries, overlapped by others).

- *ground truth*: the ``reference`` mode with 1024 stratified samples per pixel, composited per
  sample (no conflation).
- *ideal MSAA*: exact point-in-region at the same pattern samples as a mode uses (finely
  flattened outlines, per-sample compositing) — the best any n-sample MSAA can do.
- *edge-pixel error*: mean absolute difference of premultiplied RGBA over pixels whose ground
  truth neighbourhood is not flat.
"""
from __future__ import annotations

import math

import numpy as np

from ..scene.path import Path
from ..raster.modes import MODES
from ..raster.render import EXACT_TOLERANCE, RenderOptions, render_float, render_scene
from ..scene.nodes import Fill, Group, Scene, Solid

GROUND_TRUTH_SAMPLES = 1024


def ground_truth(scene: Scene) -> np.ndarray:
    return render_scene(scene, mode="reference", samples=GROUND_TRUTH_SAMPLES)


def ideal_msaa(scene: Scene, samples: int) -> np.ndarray:
    """Exact coverage at the standard pattern's samples: outlines flattened to 1/256 px and
    tested per sample, no Loop–Blinn approximation anywhere."""
    opts = RenderOptions("persample", samples)
    opts.flatten_tol = EXACT_TOLERANCE
    return render_float(scene, opts)


def edge_mask(truth: np.ndarray) -> np.ndarray:
    """Pixels whose 3 x 3 ground-truth neighbourhood is not flat."""
    t = truth.astype(np.float64)
    pad = np.pad(t, ((1, 1), (1, 1), (0, 0)), mode="edge")
    lo = hi = t
    H, W = t.shape[:2]
    for dy in range(3):
        for dx in range(3):
            nb = pad[dy:dy + H, dx:dx + W]
            lo = np.minimum(lo, nb)
            hi = np.maximum(hi, nb)
    return (hi - lo).max(axis=-1) > 1.0 / 255.0


def edge_error(img: np.ndarray, truth: np.ndarray, mask=None) -> float:
    if mask is None:
        mask = edge_mask(truth)
    if not mask.any():
        return 0.0
    return float(np.abs(img.astype(np.float64) - truth)[mask].mean())


def _blob(rng, cx, cy, r, lobes=7) -> Path:
    """A smooth closed blob: cubic Béziers through points at random radii (Catmull-Rom)."""
    n = lobes
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    rad = r * rng.uniform(0.55, 1.0, n)
    pts = np.stack([cx + rad * np.cos(ang), cy + rad * np.sin(ang)], axis=1)
    path = Path()
    path.moveTo(tuple(pts[0]))
    for i in range(n):
        p0, p1, p2, p3 = pts[i - 1], pts[i], pts[(i + 1) % n], pts[(i + 2) % n]
        path.curveTo(tuple(p1 + (p2 - p0) / 6), tuple(p2 - (p3 - p1) / 6), tuple(p2))
    path.closePath()
    return path


def _split_canvas(size, curve) -> tuple[Path, Path]:
    """Two regions above and below one cubic from the left border to the right border: they
    share the curved boundary exactly (same control points, opposite direction)."""
    (x0, y0), c1, c2, (x3, y3) = curve
    top = Path()
    top.moveTo((x0, y0))
    top.curveTo(c1, c2, (x3, y3))
    top.lineTo((size, -1))
    top.lineTo((0, -1))
    top.closePath()
    bottom = Path()
    bottom.moveTo((x3, y3))
    bottom.curveTo(c2, c1, (x0, y0))
    bottom.lineTo((0, size + 1))
    bottom.lineTo((size, size + 1))
    bottom.closePath()
    return top, bottom


def figure1_scene(size: int = 64) -> Scene:
    """Figure 1 of Schwarz & Stamminger: red and green share one curved boundary, a blue
    region overlaps both."""
    s = size / 64.0
    top, bottom = _split_canvas(size, ((0, 22 * s), (20 * s, 62 * s), (44 * s, -6 * s),
                                       (size, 40 * s)))
    blue = Path()
    blue.moveTo((40 * s, 18 * s))
    blue.qCurveTo((64 * s, 30 * s), (44 * s, 58 * s))
    blue.qCurveTo((26 * s, 40 * s), (40 * s, 18 * s))
    blue.closePath()
    return Scene(size, size, Group([
        Fill(top, Solid((0.85, 0.1, 0.1, 1))),
        Fill(bottom, Solid((0.1, 0.7, 0.2, 1))),
        Fill(blue, Solid((0.15, 0.25, 0.9, 1))),
    ]), background=(0, 0, 0, 1))


def random_scene(seed: int, size: int = 64) -> Scene:
    """An unseen test scene: a canvas split by a random cubic (shared boundary) and random
    blobs, some opaque, some translucent, overlapping the split."""
    rng = np.random.default_rng(seed)
    curve = ((0.0, rng.uniform(0.2, 0.8) * size),
             (rng.uniform(0.1, 0.5) * size, rng.uniform(-0.3, 1.3) * size),
             (rng.uniform(0.5, 0.9) * size, rng.uniform(-0.3, 1.3) * size),
             (float(size), rng.uniform(0.2, 0.8) * size))
    top, bottom = _split_canvas(size, curve)
    fills = [Fill(top, Solid(tuple(rng.uniform(0, 1, 3)) + (1.0,))),
             Fill(bottom, Solid(tuple(rng.uniform(0, 1, 3)) + (1.0,)))]
    for _ in range(int(rng.integers(2, 5))):
        blob = _blob(rng, rng.uniform(0.2, 0.8) * size, rng.uniform(0.2, 0.8) * size,
                     rng.uniform(0.15, 0.35) * size)
        alpha = 1.0 if rng.random() < 0.6 else float(rng.uniform(0.4, 0.9))
        fills.append(Fill(blob, Solid(tuple(rng.uniform(0, 1, 3)) + (alpha,)),
                          rule="evenodd" if rng.random() < 0.3 else "nonzero"))
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def measure(scenes, samples: int = 8, modes=tuple(m for m in MODES if m != "reference")):
    """Mean edge-pixel error per mode (and of ideal MSAA) over scenes, against ground truth."""
    totals = {m: 0.0 for m in modes}
    totals["ideal"] = 0.0
    for scene in scenes:
        truth = ground_truth(scene)
        mask = edge_mask(truth)
        totals["ideal"] += edge_error(ideal_msaa(scene, samples), truth, mask)
        for m in modes:
            totals[m] += edge_error(render_scene(scene, mode=m, samples=samples), truth, mask)
    return {k: v / len(scenes) for k, v in totals.items()}
