"""One text line's glyph matrices and em box in one pass (``svg.text.line``: a ``<text>`` of one
font, one element and one chunk, left to right, without per-character positions after the first).

The arithmetic is the general route's (``svg.text.layout``: ``_shape_clusters``,
``anchor_shift``, ``position_linear``, the glyph matrices of ``build_text``, ``draw.text_bbox``)
operation for operation, with its constants (a scale of 1.0, spacing of 0.0) kept, so the
results are the same floats: tests compare the two routes bit for bit. Its own module, with
no imports from the package but the kernel decorator: a kernel file's stamp covers every
module it imports (jitcache), and the text modules change more often than this.
"""
from __future__ import annotations

import numpy as np

from ..jit import njit

#: text-anchor as line_glyphs takes it
ANCHORS = {"start": 0, "middle": 1, "end": 2}


@njit(cache=True)
def _compose(a1, b1, c1, d1, e1, f1, a2, b2, c2, d2, e2, f2):
    # scene.transform.compose, the same products and sums
    return (a1 * a2 + c1 * b2, b1 * a2 + d1 * b2,
            a1 * c2 + c1 * d2, b1 * c2 + d1 * d2,
            a1 * e2 + c1 * f2 + e1, b1 * e2 + d1 * f2 + f1)


@njit(cache=True)
def line_glyphs(advances, offsets, clusters, scale, ascent, descent, dx0, dy0, anchor,
                sa, sb, sc, sd, se, sf):
    """HarfBuzz's glyphs of a line (``advances`` and ``offsets`` (N, 2) in font units, y up;
    ``clusters`` (N,) their characters) at ``scale`` user units per font unit, its first
    character moved by (dx0, dy0), anchored by ``anchor`` (ANCHORS) and placed by the span
    matrix (sa..sf: the chunk's start and baseline shift) → (matrices (N, 6) mapping each
    glyph's outline, em box (x0, y0, x1, y1) of its clusters, ok). Not ok (the caller takes
    the general route) where a cluster comes back after another (no plain left-to-right
    run), the first glyph is not the first character's, or a position is not finite."""
    n = clusters.shape[0]
    mats = np.empty((n, 6))
    box = np.empty(4)
    if n == 0 or clusters[0] != 0:
        return mats, box, False
    # clusters: consecutive glyphs of one character; the pen from each cluster's start
    of = np.empty(n, np.int64)          # each glyph's cluster
    gdx = np.empty(n)                   # each glyph's x in its cluster
    cadv = np.empty(n)                  # each cluster's advance
    nc = 0
    pen = 0.0
    for i in range(n):
        if i == 0 or clusters[i] != clusters[i - 1]:
            if i > 0 and clusters[i] < clusters[i - 1]:
                return mats, box, False
            nc += 1
            pen = 0.0
        k = nc - 1
        of[i] = k
        dx = offsets[i, 0] * scale
        gdx[i] = pen + dx
        width = advances[i, 0] * scale
        pen += width
        cadv[k] = pen
    # text-anchor (layout.anchor_shift: spacing, gaps and carries 0.0, lengthAdjust's 1.0)
    x = 0.0
    if anchor != 0:
        pos = 0.0
        lo = np.inf
        hi = -np.inf
        for k in range(nc):
            pos += (dx0 if k == 0 else 0.0) * 1.0
            advance = cadv[k] * 1.0
            end = pos + advance - 0.0 * 1.0
            m = lo                      # min(lo, pos, end), the first of equals kept
            if pos < m:
                m = pos
            if end < m:
                m = end
            lo = m
            m = hi
            if pos > m:
                m = pos
            if end > m:
                m = end
            hi = m
            pos += advance + 0.0 * 1.0
        first = dx0 * 1.0
        x = first - (hi if anchor == 2 else (lo + hi) / 2)
    # cluster frames (layout.position_linear) composed with the span and the identity
    placed = np.empty((nc, 6))
    y = 0.0
    for k in range(nc):
        x += (dx0 if k == 0 else 0.0) * 1.0
        y += dy0 if k == 0 else 0.0
        if not (np.isfinite(x) and np.isfinite(y)):
            return mats, box, False
        a, b, c, d, e, f = _compose(sa, sb, sc, sd, se, sf, 1.0, 0.0, 0.0, 1.0, x + 0.0, y + 0.0)
        a, b, c, d, e, f = _compose(a, b, c, d, e, f, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
        placed[k, 0] = a
        placed[k, 1] = b
        placed[k, 2] = c
        placed[k, 3] = d
        placed[k, 4] = e
        placed[k, 5] = f
        x += cadv[k] * 1.0
    for i in range(n):
        # the glyph's frame (scale, y flipped, its offset) in its cluster's
        k = of[i]
        (mats[i, 0], mats[i, 1], mats[i, 2], mats[i, 3], mats[i, 4], mats[i, 5]) = _compose(
            placed[k, 0], placed[k, 1], placed[k, 2], placed[k, 3], placed[k, 4],
            placed[k, 5], scale, 0.0, 0.0, -scale, gdx[i], -offsets[i, 1] * scale)
    # the em boxes' union (draw.text_bbox: four corners a cluster, min and max keeping the
    # first of equals; a NaN anywhere makes all four NaN)
    top = -ascent
    bottom = -descent
    nan = False
    x0 = y0 = x1 = y1 = 0.0
    for k in range(nc):
        adv = cadv[k] if cadv[k] > 0 else 1.0
        a = placed[k, 0]
        b = placed[k, 1]
        c = placed[k, 2]
        d = placed[k, 3]
        e = placed[k, 4]
        f = placed[k, 5]
        xs = (a * 0.0 + c * top + e, a * adv + c * top + e,
              a * 0.0 + c * bottom + e, a * adv + c * bottom + e)
        ys = (b * 0.0 + d * top + f, b * adv + d * top + f,
              b * 0.0 + d * bottom + f, b * adv + d * bottom + f)
        for j in range(4):
            u = xs[j]
            v = ys[j]
            if np.isnan(u) or np.isnan(v):
                nan = True
            if k == 0 and j == 0:
                x0 = x1 = u
                y0 = y1 = v
                continue
            if u < x0:
                x0 = u
            if u > x1:
                x1 = u
            if v < y0:
                y0 = v
            if v > y1:
                y1 = v
    if nan:
        x0 = y0 = x1 = y1 = np.nan
    box[0] = x0
    box[1] = y0
    box[2] = x1
    box[3] = y1
    return mats, box, True
