"""Render a resolved :class:`~vecmsaa.scene.Scene`: batches of fills through the raster kernels,
groups that need it through layers (opacity, clip, mask, blend mode).

Coverage modes (see docs/modes.md):

- ``none``: one sample at the pixel centre, aliased.
- ``alpha``: Loop–Blinn distance alpha, α = clamp(½ − d), blended on the lens samples.
- ``a2c``: the same α as a sample mask of round(α·n) samples (alpha-to-coverage).
- ``persample``: the implicit function at every sample.
- ``approx``: one evaluation per pixel and a half-plane coverage-mask look-up (default).
- ``analytic``: exact area per path, composited per pixel (tiny-skia style).
- ``reference``: 256 stratified samples per pixel on finely flattened outlines, composited per
  sample: conflation-free ground truth.
"""
from __future__ import annotations

import numpy as np

from .geometry import batch_arrays, build_batch
from .patterns import PATTERNS, a2c_order, mask_table, pattern_offsets, stratified_pattern
from .scan import MODE_IDS, MODE_PERSAMPLE, RULE_EVENODD, RULE_NONZERO, render_analytic, render_msaa
from .scene import Fill, Group, Scene
from .shaders import PaintTable

MSAA_MODES = ("none", "alpha", "a2c", "persample", "approx")
EXACT_MODES = ("analytic", "reference")
ALL_MODES = MSAA_MODES + EXACT_MODES
#: flattening tolerance of the exact modes (pixels)
EXACT_TOLERANCE = 1.0 / 256.0
#: a curve piece bulges at most this far from its chord (pixels); keeps lenses thin
MAX_SAGITTA = 1.0
#: elements (rows x width x samples) of one strip's per-sample buffers
STRIP_BUDGET = 1 << 22
FILTERS = ("box", "tent")
PATTERN_NAMES = tuple(PATTERNS)


class RenderOptions:
    """Everything the raster stage needs besides the scene."""

    def __init__(self, mode: str = "approx", samples: int = 8, filter: str = "box",
                 pattern: str = "d3d"):
        if mode not in ALL_MODES:
            raise ValueError(f"unknown mode {mode!r}; choose from {', '.join(ALL_MODES)}")
        if filter not in FILTERS:
            raise ValueError(f"unknown filter {filter!r}; choose from {', '.join(FILTERS)}")
        self.mode = mode
        self.filter = filter
        if mode == "none":
            samples = 1
        if mode == "reference":
            # 256 samples unless more are asked for (a square number: 1024 = 32 x 32)
            side = max(16, int(round(np.sqrt(samples)))) if samples > 16 else 16
            offsets = stratified_pattern(side)
        elif mode == "analytic":
            offsets = np.zeros((1, 2))
        else:
            offsets = pattern_offsets(pattern, samples)
        self.samples = len(offsets)
        self.sx = np.ascontiguousarray(offsets[:, 0] + 0.5)
        self.sy = np.ascontiguousarray(offsets[:, 1] + 0.5)
        if filter == "tent":
            w = (1.0 - np.abs(offsets[:, 0])) * (1.0 - np.abs(offsets[:, 1]))
        else:
            w = np.ones(len(offsets))
        self.weights = (w / w.sum()).astype(np.float32)
        if mode in ("approx", "a2c", "alpha", "persample"):
            self.table = mask_table(samples, pattern)
            order = a2c_order(samples, pattern)
            bits = np.zeros(samples + 1, dtype=np.uint64)
            for k in range(1, samples + 1):
                bits[k] = bits[k - 1] | (np.uint64(1) << np.uint64(order[k - 1]))
            self.a2c_bits = bits
        else:
            self.table = np.zeros((1, 1), dtype=np.uint64)
            self.a2c_bits = np.zeros(2, dtype=np.uint64)
        self.kernel_mode = MODE_IDS.get(mode, MODE_PERSAMPLE)
        self.flatten_tol = EXACT_TOLERANCE if mode in EXACT_MODES else 0.0


def premultiplied(color) -> np.ndarray:
    r, g, b, a = color
    return np.array([r * a, g * a, b * a, a], dtype=np.float32)


def render_scene(scene: Scene, mode: str = "approx", samples: int = 8,
                 filter: str = "box", pattern: str = "d3d") -> np.ndarray:
    """Render to an (H, W, 4) float32 array of premultiplied RGBA in [0, 1].

    ``samples`` per pixel for the MSAA modes (1, 2, 4, 8, 16; ``none`` always uses 1, the
    ``reference`` mode 256 or a larger square), ``pattern`` their positions (``d3d``: the
    Direct3D 10.1 standard patterns, ``grid``: an ordered grid), ``filter`` the resolve filter
    (``box`` or ``tent``)."""
    opts = RenderOptions(mode, samples, filter, pattern)
    target = np.zeros((scene.height, scene.width, 4), dtype=np.float32)
    if scene.background[3] > 0:
        target[:] = premultiplied(scene.background)
    draw_group_children(scene.root, target, opts)
    return target


def draw_group_children(group: Group, target: np.ndarray, opts: RenderOptions) -> None:
    batch: list[Fill] = []
    for node in _walk(group):
        if isinstance(node, Fill):
            batch.append(node)
            continue
        draw_fills(batch, target, opts)
        batch = []
        draw_layer(node, target, opts)
    draw_fills(batch, target, opts)


def _walk(group: Group):
    """Fills and layer groups in paint order; plain groups are flattened away."""
    for node in group.children:
        if isinstance(node, Group):
            if node.needs_layer():
                yield node
            else:
                yield from _walk(node)
        else:
            yield node


def draw_fills(fills, target: np.ndarray, opts: RenderOptions) -> None:
    fills = [f for f in fills if not f.path.is_empty() and f.opacity > 0]
    if not fills:
        return
    verbs, pts, voff, poff = batch_arrays([f.path for f in fills])
    if not np.isfinite(pts).all():
        keep = [i for i, f in enumerate(fills) if np.isfinite(f.path.points).all()]
        fills = [fills[i] for i in keep]
        if not fills:
            return
        verbs, pts, voff, poff = batch_arrays([f.path for f in fills])
    edges, edge_off, prims, prim_off = build_batch(verbs, pts, voff, poff, opts.flatten_tol,
                                                   MAX_SAGITTA)
    # per-fill bounds from the control points (a curve lies in its control hull)
    starts = poff[:-1]
    box = np.empty((len(fills), 4))
    box[:, 0] = np.minimum.reduceat(pts[:, 0], starts)
    box[:, 1] = np.minimum.reduceat(pts[:, 1], starts)
    box[:, 2] = np.maximum.reduceat(pts[:, 0], starts)
    box[:, 3] = np.maximum.reduceat(pts[:, 1], starts)
    rules = np.array([RULE_EVENODD if f.rule == "evenodd" else RULE_NONZERO for f in fills],
                     dtype=np.int64)
    aa = np.array([f.antialias for f in fills], dtype=np.bool_)
    table = PaintTable()
    for f in fills:
        table.add(f.paint, f.opacity)
    kinds, params, lut, tex = table.arrays()
    H, W = target.shape[:2]
    if opts.mode == "analytic":
        rows = max(1, min(256, STRIP_BUDGET // max(1, W)))
        render_analytic(target, edges, edge_off, box, rules, aa, kinds, params, lut, tex, rows)
        return
    rows = max(1, min(256, STRIP_BUDGET // max(1, W * opts.samples)))
    render_msaa(target, edges, edge_off, prims, prim_off, box, rules, aa, kinds, params, lut,
                tex, opts.sx, opts.sy, opts.weights, opts.kernel_mode, opts.table,
                opts.a2c_bits, rows)


def draw_layer(group: Group, target: np.ndarray, opts: RenderOptions) -> None:
    layer = np.zeros_like(target)
    draw_group_children(group, layer, opts)
    if group.clip is not None:
        layer *= render_coverage(group.clip, target.shape, opts)[..., None]
    if group.mask is not None:
        layer *= render_mask(group.mask, target.shape, opts)[..., None]
    if group.opacity < 1.0:
        layer *= np.float32(group.opacity)
    composite(layer, target, group.blend)


def render_coverage(clip: Group, shape, opts: RenderOptions) -> np.ndarray:
    """A clip group's coverage: the alpha of its content drawn opaque, clipped by its own clip."""
    img = np.zeros(shape, dtype=np.float32)
    draw_group_children(clip, img, opts)
    cov = img[..., 3].copy()
    if clip.clip is not None:
        cov *= render_coverage(clip.clip, shape, opts)
    if clip.mask is not None:
        cov *= render_mask(clip.mask, shape, opts)
    return cov


def render_mask(mask, shape, opts: RenderOptions) -> np.ndarray:
    img = np.zeros(shape, dtype=np.float32)
    draw_group_children(mask.content, img, opts)
    if mask.kind == "alpha":
        cov = img[..., 3].copy()
    else:
        # luminance of the premultiplied colour = luminance × alpha (sRGB coefficients)
        cov = img[..., 0] * 0.2125 + img[..., 1] * 0.7154 + img[..., 2] * 0.0721
    content = mask.content
    if content.clip is not None:
        cov *= render_coverage(content.clip, shape, opts)
    if content.mask is not None:
        cov *= render_mask(content.mask, shape, opts)
    return np.clip(cov, 0.0, 1.0)


def composite(src: np.ndarray, dst: np.ndarray, blend: str = "normal") -> None:
    """src over dst in place (premultiplied), with a CSS blend mode."""
    sa = src[..., 3:4]
    if blend == "normal":
        dst *= (1.0 - sa)
        dst += src
        return
    from .blend import blend_premultiplied
    dst[:] = blend_premultiplied(src, dst, blend)


def to_rgba8(img: np.ndarray) -> np.ndarray:
    """Premultiplied float RGBA → straight uint8 RGBA."""
    img = np.clip(img, 0.0, 1.0)
    a = img[..., 3:4]
    with np.errstate(divide="ignore", invalid="ignore"):
        rgb = np.where(a > 0, img[..., :3] / np.maximum(a, 1e-12), 0.0)
    out = np.empty(img.shape[:2] + (4,), dtype=np.uint8)
    out[..., :3] = np.clip(rgb * 255.0 + 0.5, 0, 255).astype(np.uint8)
    out[..., 3] = np.clip(a[..., 0] * 255.0 + 0.5, 0, 255).astype(np.uint8)
    return out


def to_pil(img: np.ndarray):
    from PIL import Image
    return Image.fromarray(to_rgba8(img), "RGBA")
