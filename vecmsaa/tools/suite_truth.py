"""Computed exact references for resvg suite tests whose reference carries one of resvg's own
artifacts that ``exact-refs/`` does not cover. Each is the test's drawing evaluated from its
geometry alone (nothing of vecmsaa's renderer): axis-aligned rectangles by exact pixel-area
coverage, dashed circle strokes by point sampling of the exact annulus sectors (16x16 points
per pixel; an edge's coverage is then off by at most 1/16, far inside the 48/255 criterion).

Two artifacts are covered:

- *dashing along a circle*: resvg places dashes by the length of a flattened Bézier
  approximation of the circle, so its dashes sit up to a pixel away from where the exact arc
  length puts them (SVG 2 §13.5: dash positions are distances along the path). With butt caps,
  a dash of a circle's stroke is exactly the annulus sector between the radii through its ends.
- *conflation fringe* of a red shape "should be covered" by an identical green one, for the
  tests not in ``exact-refs/``: the exact drawing shows no red.

A test's truth is a list of shapes in user units (viewBox 0 0 200 200), painted source-over in
order; :func:`exact_reference` rasterises it at the reference's size, or returns None.
"""
from __future__ import annotations

import math

import numpy as np

GREEN = (0, 128, 0)
BLACK = (0, 0, 0)
VIEW = 200.0
SUPERSAMPLE = 16

#: every suite test's frame: <rect x="1" y="1" width="198" height="198" stroke="black"/>
FRAME = ("frame", 1, 1, 198, 198, 1, BLACK)


def _dashed_ring(r, dashes, offset):
    return ("dashed-circle", 100, 100, r, 10, tuple(dashes), offset, GREEN)


#: test name → shapes. Each entry restates the test's SVG: the dashed circles are all
#: cx=cy=100, stroke-width 10, butt caps; offsets resolved per SVG 2 (em: font-size 20,
#: mm: 96/25.4 px, %: of the viewport diagonal / sqrt 2 = 200).
TRUTHS = {
    "painting/stroke-dasharray/on-a-circle": [_dashed_ring(60, (10, 20), 0), FRAME],
    "painting/stroke-dasharray/comma-ws-separator":
        [_dashed_ring(70, (30, 20, 10, 30, 20, 10), 0), FRAME],
    "painting/stroke-dashoffset/px-units": [_dashed_ring(70, (10, 20), 15), FRAME],
    "painting/stroke-dashoffset/em-units": [_dashed_ring(70, (10, 20), 1.5 * 20), FRAME],
    "painting/stroke-dashoffset/mm-units": [_dashed_ring(70, (10, 20), 1.5 * 96 / 25.4), FRAME],
    "painting/stroke-dashoffset/percent-units": [_dashed_ring(70, (10, 20), 0.2 * 200), FRAME],
    "structure/use/href-precedence-over-xlink": [("rect", 75, 75, 50, 50, GREEN), FRAME],
    "paint-servers/linearGradient/href-precedence-over-xlink":
        [("rect", 15, 60, 80, 80, GREEN), ("rect", 105, 60, 80, 80, GREEN), FRAME],
}


def rect_coverage(x0, y0, x1, y1, width, height):
    """(height, width) exact area of each pixel square covered by [x0, x1] x [y0, y1]
    (pixel units)."""
    def axis(a, b, n):
        edges = np.arange(n, dtype=np.float64)
        return np.clip(np.minimum(edges + 1, b) - np.maximum(edges, a), 0, 1)
    return np.outer(axis(y0, y1, height), axis(x0, x1, width))


def dashed_circle_coverage(cx, cy, r, stroke_width, dashes, offset, scale, width, height,
                           ss=SUPERSAMPLE):
    """(height, width) coverage of a dashed, butt-capped circle stroke: the circle starts at
    (cx + r, cy) and runs towards +y (SVG's circle path), a point is inked when it lies within
    stroke_width / 2 of the circle and the arc length of its radial projection, plus
    ``offset``, falls in a dash (the pattern repeats; the path ends at 2 pi r)."""
    if len(dashes) % 2:          # an odd list is repeated to make it even (SVG 2 §13.5)
        dashes = tuple(dashes) * 2
    period = float(sum(dashes))
    ys = (np.arange(height * ss) + 0.5) / (ss * scale)
    xs = (np.arange(width * ss) + 0.5) / (ss * scale)
    dx = xs[None, :] - cx
    dy = ys[:, None] - cy
    ring = np.abs(np.hypot(dx, dy) - r) <= stroke_width / 2
    arc = np.mod(np.arctan2(dy, dx), 2 * math.pi) * r
    phase = np.mod(arc + offset, period)
    on = np.zeros(ring.shape, bool)
    start = 0.0
    for i, d in enumerate(dashes):
        if i % 2 == 0:
            on |= (phase >= start) & (phase < start + d)
        start += d
    return (ring & on).reshape(height, ss, width, ss).mean(axis=(1, 3))


def _coverage(shape, scale, width, height):
    kind = shape[0]
    if kind == "rect":
        _, x, y, w, h, _color = shape
        return rect_coverage(x * scale, y * scale, (x + w) * scale, (y + h) * scale,
                             width, height)
    if kind == "frame":     # a stroked rectangle: outer minus inner square
        _, x, y, w, h, sw, _color = shape
        outer = rect_coverage((x - sw / 2) * scale, (y - sw / 2) * scale,
                              (x + w + sw / 2) * scale, (y + h + sw / 2) * scale, width, height)
        inner = rect_coverage((x + sw / 2) * scale, (y + sw / 2) * scale,
                              (x + w - sw / 2) * scale, (y + h - sw / 2) * scale, width, height)
        return outer - inner
    _, cx, cy, r, sw, dashes, offset, _color = shape
    return dashed_circle_coverage(cx, cy, r, sw, dashes, offset, scale, width, height)


def exact_reference(name, width, height):
    """The computed exact reference of suite test ``name`` at width x height as straight 8-bit
    RGBA, or None when the test has none."""
    shapes = TRUTHS.get(name)
    if shapes is None:
        return None
    scale = width / VIEW
    rgb = np.zeros((height, width, 3))          # premultiplied, 0..1
    alpha = np.zeros((height, width))
    for shape in shapes:
        a = _coverage(shape, scale, width, height)
        color = np.asarray(shape[-1], dtype=np.float64) / 255
        rgb = rgb * (1 - a[..., None]) + color * a[..., None]
        alpha = alpha * (1 - a) + a
    straight = np.where(alpha[..., None] > 0, rgb / np.maximum(alpha, 1e-12)[..., None], 0)
    out = np.concatenate([straight, alpha[..., None]], axis=-1)
    return np.round(np.clip(out, 0, 1) * 255).astype(np.uint8)
