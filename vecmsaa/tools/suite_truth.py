"""Computed exact references for resvg suite tests whose reference carries one of resvg's own
artifacts that ``exact-refs/`` does not cover. Each is the test's drawing evaluated from its
geometry alone (nothing of vecmsaa's renderer): axis-aligned rectangles by exact pixel-area
coverage.

The artifact covered is the *conflation fringe* of a red shape "should be covered" by an
identical green one, for the tests not in ``exact-refs/``: the exact drawing shows no red.
(Session 25 dropped the dashed circles' truths: vecmsaa now places dashes where resvg and
Chromium do, and those tests pass against their references.)

A test's truth is a list of shapes in user units (viewBox 0 0 200 200), painted source-over in
order; :func:`exact_reference` rasterises it at the reference's size, or returns None.
"""
from __future__ import annotations

import numpy as np

GREEN = (0, 128, 0)
BLACK = (0, 0, 0)
VIEW = 200.0

#: every suite test's frame: <rect x="1" y="1" width="198" height="198" stroke="black"/>
FRAME = ("frame", 1, 1, 198, 198, 1, BLACK)


#: test name → shapes. Each entry restates the test's SVG.
TRUTHS = {
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
    raise ValueError(f"unknown truth shape {kind!r}")


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
