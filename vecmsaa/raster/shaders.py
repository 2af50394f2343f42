"""Paint evaluation, once per pixel (MSAA semantics): solid colours, gradients, images.

Paints of a batch are packed into flat tables so the raster kernels can shade any fill:
``paint_kind`` (one int per fill), ``paint_f`` (float64 parameters per fill), ``lut`` (gradient
colour ramps, premultiplied, LUT_SIZE entries each) and ``texels`` (all images, flattened).
"""
from __future__ import annotations

import math
from operator import attrgetter

import numpy as np
from ..jit import njit

from ..scene.nodes import ImagePaint, LinearGradient, PatternPaint, RadialGradient, Solid

KIND_SOLID, KIND_LINEAR, KIND_RADIAL, KIND_IMAGE = 0, 1, 2, 3
SPREADS = {"pad": 0, "reflect": 1, "repeat": 2}
LUT_SIZE = 1024

# paint_f layout
F_COLOR = 0        # premultiplied solid colour (4), already times opacity
F_MAT = 4          # device → paint space (a, b, c, d, e, f)
F_GEOM = 10        # linear: x1 y1 x2 y2 | radial: cx cy r fx fy fr | image: offset h w repeat smooth
F_SPREAD = 16
F_LUT = 17
F_OPACITY = 18
PAINT_FIELDS = 20
#: Texel units a nearest-texel sample point may lie below a texel boundary and still be read
#: as on it (the f64 rounding of device → texel maps is ~1e-15 per texel; no drawing puts a
#: pixel centre this close to a boundary on purpose)
NEAREST_SLACK = 1e-9


def gradient_lut(stops: np.ndarray, opacity: float) -> np.ndarray:
    """Premultiplied colour ramp sampled at LUT_SIZE points, followed by the exact first and
    last stop colours (what pad spread shows before the first and after the last offset, even
    when several stops share that offset). Colours interpolate in straight (non-premultiplied)
    sRGB between stops, as SVG specifies."""
    stops = np.asarray(stops, dtype=np.float64).reshape(-1, 5)
    t = np.concatenate([(np.arange(LUT_SIZE) + 0.5) / LUT_SIZE, [-1.0, 2.0]])
    offs = np.maximum.accumulate(np.clip(stops[:, 0], 0.0, 1.0))
    rgba = np.empty((LUT_SIZE + 2, 4))
    for ch in range(4):
        rgba[:, ch] = np.interp(t, offs, stops[:, 1 + ch]) if len(offs) > 1 else stops[0, 1 + ch]
    # np.interp takes the right-hand value at a repeated offset: a hard stop stays hard
    rgba[:, 3] *= opacity
    rgba[:, :3] *= rgba[:, 3:4]
    return rgba.astype(np.float32)


class PaintTable:
    """Packs the paints of a batch of fills into flat arrays for the kernels.

    Fills sharing a solid paint object and opacity share one parameter row (map data paints
    thousands of fills with the one Solid of their style): each fill's row is an index into
    the distinct rows, expanded once in :meth:`arrays`."""

    def __init__(self):
        self.row_kinds: list[int] = []         # the kind of each distinct row
        self.params: list[np.ndarray] = []     # the distinct parameter rows
        self.rows: list[int] = []              # each fill's row in params
        self._solid_rows: dict = {}            # (id(paint), opacity) -> row
        self._solids: list = []                # those paints (alive while their ids are keys)
        self.luts: list[np.ndarray] = []
        self.lut_size = 0
        # (stops' bytes, opacity) -> the offset of their ramp in the LUT: fills painted by one
        # gradient share it (each fill had its own 32 KB: 40,000 rects of one gradient 1.4 GB)
        self._lut_offsets: dict = {}
        self.images: list[np.ndarray] = []
        self.image_size = 0
        # id(rgba) -> its offset in the texture, the arrays kept alive in images: an image
        # drawn many times (one <image> used 30 times, a pattern tile on many fills) is in
        # the texture once, not once per fill (30 uses of a 2048² PNG took 2 GB)
        self._image_offsets: dict = {}
        self._image_sources: list = []

    def add_fills(self, fills, pattern_tile) -> None:
        """add() the paint and opacity of each fill; ``pattern_tile`` turns a PatternPaint
        into the ImagePaint of its tile."""
        if not self.params and len(fills) > 1:
            paints = list(map(_PAINT, fills))
            if set(map(type, paints)) == _SOLID:
                self._add_solids(paints, list(map(_OPACITY, fills)))
                return
        rows, solid_rows = self.rows, self._solid_rows
        last = last_opacity = row = None      # (neighbours mostly share their paint)
        for f in fills:
            paint = f.paint
            if type(paint) is Solid:
                if paint is last and f.opacity == last_opacity:
                    rows.append(row)
                    continue
                row = solid_rows.get((id(paint), f.opacity))
                if row is None:
                    self.add(paint, f.opacity)
                    row = rows[-1]
                else:
                    rows.append(row)
                last, last_opacity = paint, f.opacity
                continue
            elif isinstance(paint, PatternPaint):
                paint = pattern_tile(paint)
            self.add(paint, f.opacity)

    def _add_solids(self, paints, opacities) -> None:
        """add_fills of solid paints into an empty table: the rows add_fills makes (one per
        distinct paint object and opacity, in order of first use), found by maps over the
        fills, where a Python turn per fill cost 140,000 circles and strokes 0.15 s."""
        n = len(paints)
        ids = list(map(id, paints))
        # (paint, opacity) keys; the paint's id alone where all share one opacity
        keys = ids if opacities.count(opacities[0]) == n else list(zip(ids, opacities))
        # each key's first fill (the reversed pairs: the first one's index is set last),
        # those in order of first use, and each fill's row: the rank of its key there
        firsts = sorted(dict(zip(reversed(keys), range(n - 1, -1, -1))).values())
        rank = {keys[i]: row for row, i in enumerate(firsts)}
        self.rows.extend(map(rank.__getitem__, keys))
        for i in firsts:
            paint, opacity = paints[i], opacities[i]
            self._solid_rows[(id(paint), opacity)] = len(self.params)
            self._solids.append(paint)
            self.row_kinds.append(KIND_SOLID)
            self.params.append(np.array(solid_row(paint, opacity)))

    def add(self, paint, opacity: float = 1.0) -> None:
        if isinstance(paint, Solid):
            kind = KIND_SOLID
            f = np.array(solid_row(paint, opacity))
            self._solid_rows[(id(paint), opacity)] = len(self.params)
            self._solids.append(paint)
        else:
            f = np.zeros(PAINT_FIELDS)
            f[F_OPACITY] = opacity
            try:
                f[F_MAT:F_MAT + 6] = paint.to_paint
            except (TypeError, ValueError):
                f[F_MAT:F_MAT + 6] = (1, 0, 0, 1, 0, 0)
            if isinstance(paint, (LinearGradient, RadialGradient)):
                f[F_SPREAD] = SPREADS.get(paint.spread, 0)
                key = (np.asarray(paint.stops, dtype=np.float64).tobytes(), opacity)
                offset = self._lut_offsets.get(key)
                if offset is None:
                    offset = self._lut_offsets[key] = self.lut_size
                    lut = gradient_lut(paint.stops, opacity)
                    self.luts.append(lut)
                    self.lut_size += len(lut)
                f[F_LUT] = offset
                if isinstance(paint, LinearGradient):
                    kind = KIND_LINEAR
                    f[F_GEOM:F_GEOM + 4] = (paint.x1, paint.y1, paint.x2, paint.y2)
                else:
                    kind = KIND_RADIAL
                    f[F_GEOM:F_GEOM + 6] = (paint.cx, paint.cy, paint.r, paint.fx, paint.fy,
                                            paint.fr)
            elif isinstance(paint, ImagePaint):
                kind = KIND_IMAGE
                h, w = paint.rgba.shape[:2]
                offset = self._image_offsets.get(id(paint.rgba))
                if offset is None:
                    img = np.ascontiguousarray(paint.rgba, dtype=np.float32)
                    offset = self._image_offsets[id(paint.rgba)] = self.image_size
                    self._image_sources.append(paint.rgba)
                    self.images.append(img.reshape(-1))
                    self.image_size += img.size
                f[F_GEOM:F_GEOM + 5] = (offset, h, w, float(paint.repeat), float(paint.smooth))
            else:
                raise TypeError(f"unknown paint {paint!r}")
        self.rows.append(len(self.params))
        self.row_kinds.append(kind)
        self.params.append(f)

    def arrays(self):
        kinds = np.array(self.row_kinds, dtype=np.int64)
        if len(self.params) == 1:
            # (one row, as a layer's clip or a filtered marker's content has: its own array
            # as a row, where stacking a list of one cost as much as the rest of the table)
            params = self.params[0].reshape(1, PAINT_FIELDS)
        else:
            params = np.asarray(self.params, dtype=np.float64).reshape(-1, PAINT_FIELDS)
        if len(params) != len(self.rows):     # rows shared: expand them to one per fill
            rows = np.asarray(self.rows, dtype=np.int64)
            kinds, params = kinds[rows], params[rows]
        lut = np.concatenate(self.luts) if self.luts else _NO_LUT
        tex = np.concatenate(self.images) if self.images else _NO_TEX
        return kinds, params, lut, tex


def style_arrays(styles, kind, pattern_tile):
    """PaintTable.arrays of fills given as a style each (Fills whose paint and opacity are
    read: one per distinct style, FillRuns.styles') and each fill's index among them
    (``kind``, an int64 array): a row made per style, not per fill, then taken for each
    fill; the same arrays as add_fills of the fills gives. The gradients' ramps and the
    images are laid out in the order the fills first use them, as add_fills lays them."""
    if all(type(f.paint) is Solid for f in styles):
        # (a row of a style no fill uses costs nothing: no ramp or image to lay out)
        params = np.array([solid_row(f.paint, f.opacity) for f in styles],
                          np.float64).reshape(-1, PAINT_FIELDS)
        return np.full(len(kind), KIND_SOLID, np.int64), params[kind], _NO_LUT, _NO_TEX
    used, first = np.unique(kind, return_index=True)
    order = used[np.argsort(first, kind="stable")]
    rank = np.zeros(len(styles), np.int64)
    rank[order] = np.arange(len(order))
    table = PaintTable()
    for i in order.tolist():
        table.add_fills([styles[i]], pattern_tile)
    kinds, params, lut, tex = table.arrays()
    rows = rank[kind]
    return kinds[rows], params[rows], lut, tex


_PAINT = attrgetter("paint")
_OPACITY = attrgetter("opacity")
_SOLID = {Solid}


#: the tables of a batch without gradients or images: the kernels index neither then, and
#: never write them, so every such batch shares these
_NO_LUT = np.zeros((1, 4), np.float32)
_NO_TEX = np.zeros(4, np.float32)


def solid_row(paint: Solid, opacity: float) -> list:
    """A solid paint's parameter row as Python floats: its colour premultiplied by its alpha
    times ``opacity``, and the opacity."""
    r, g, b, a = paint.color
    a = a * opacity
    row = [0.0] * PAINT_FIELDS
    row[F_COLOR:F_COLOR + 4] = r * a, g * a, b * a, a
    row[F_OPACITY] = opacity
    return row


def solid_arrays(rows: list):
    """PaintTable.arrays of fills of solid paints, from their solid_rows, without a table
    (a small layer's batch: the table's bookkeeping cost more than its arrays)."""
    return np.full(len(rows), KIND_SOLID, np.int64), np.array(rows, np.float64), _NO_LUT, _NO_TEX


@njit(cache=True, inline="always")
def _spread(t, mode):
    if mode == 0:
        return t  # pad: _lut_index picks the end colours outside [0, 1]
    if mode == 2:
        return t - math.floor(t)
    t = abs(t) % 2.0
    return 2.0 - t if t > 1.0 else t


@njit(cache=True, inline="always")
def _lut_index(t):
    """Row of a gradient's colour table for t (after the spread): the end colours' rows
    LUT_SIZE and LUT_SIZE + 1 beyond [0, 1]. Scalars only, so inlining costs nothing."""
    if t <= 0.0:
        return LUT_SIZE if t < 0.0 else 0
    if t >= 1.0:
        return LUT_SIZE + 1 if t > 1.0 else LUT_SIZE - 1
    return min(LUT_SIZE - 1, int(t * LUT_SIZE))


@njit(cache=True, inline="always")
def _focal_on_circle(cx, cy, r, fx, fy, fr):
    """Whether a radial gradient's focal circle touches its end circle from inside (a = 0 in
    _gradient_t: one root), decided within a relative 1/4096 (tiny-skia's and Skia's "focal on
    circle" test, |dr| / |c - f| near 1): just past it the largest root runs off to 2b/a,
    thousands of periods, and reflect or repeat would draw moire where the on-circle limit is
    smooth. Constant per gradient: computed once per span, not per pixel."""
    cdx, cdy, dr = cx - fx, cy - fy, r - fr
    a = cdx * cdx + cdy * cdy - dr * dr
    cd = math.sqrt(cdx * cdx + cdy * cdy)
    return abs(a) < 1e-12 * max(1.0, r * r) or (cd > 0.0 and abs(cd - abs(dr)) < cd / 4096.0)


@njit(cache=True, inline="always")
def _gradient_t(kind, m0, m1, m2, m3, m4, m5, a0, a1, a2, a3, a4, a5, one_root, x, y):
    """(t, paints) of a gradient at device (x, y): m the device → gradient matrix (f[4:10]),
    a the gradient's geometry (f[10:16]: linear x1 y1 x2 y2, radial cx cy r fx fy fr),
    one_root whether a radial gradient's focal circle touches its end circle (_focal_on_circle);
    paints False where a radial gradient draws nothing. Scalars only."""
    gx = m0 * x + m2 * y + m4
    gy = m1 * x + m3 * y + m5
    if kind == 1:
        dx, dy = a2 - a0, a3 - a1
        den = dx * dx + dy * dy
        return (0.0 if den == 0.0 else ((gx - a0) * dx + (gy - a1) * dy) / den), True
    cx, cy, r, fx, fy, fr = a0, a1, a2, a3, a4, a5
    cdx, cdy, dr = cx - fx, cy - fy, r - fr
    pdx, pdy = gx - fx, gy - fy
    a = cdx * cdx + cdy * cdy - dr * dr
    b = pdx * cdx + pdy * cdy + fr * dr
    c = pdx * pdx + pdy * pdy - fr * fr
    if one_root:
        if b == 0.0:
            return 0.0, False
        t = c / (2.0 * b)
        # only circles of radius >= 0 paint
        return t, not (fr + t * dr < 0.0)
    disc = b * b - a * c
    if disc < 0.0:
        return 0.0, False
    sq = math.sqrt(disc)
    t1 = (b + sq) / a
    t2 = (b - sq) / a
    t = max(t1, t2)
    if fr + t * dr < 0.0:
        t = min(t1, t2)
        if fr + t * dr < 0.0:
            return 0.0, False
    return t, True


@njit(cache=True, inline="always")
def _texel_offset(base, h, w, ix, iy, repeat):
    """Index in the flat texture of texel (ix, iy) of an image of h × w texels from ``base``:
    wrapped when the image repeats, else clamped to its edge. Scalars only."""
    if repeat:
        ix = ix % w
        iy = iy % h
    else:
        ix = min(w - 1, max(0, ix))
        iy = min(h - 1, max(0, iy))
    return base + (iy * w + ix) * 4


@njit(cache=True, inline="always")
def _bilinear(c00, c10, c01, c11, fu, fv, op):
    """One channel of the bilinear blend of four texels, times the image's opacity."""
    w00, w10, w01, w11 = (1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv
    return (c00 * w00 + c10 * w10 + c01 * w01 + c11 * w11) * op


@njit(cache=True)
def shade_span(kind, f, lut, tex, x0, x1, y, out):
    """The colours of paint (kind, f) at the centres x + 0.5 of pixels x0 .. x1 - 1 of a row
    (device y) into out[0 .. x1 - x0), premultiplied: one call for a span instead of one per
    pixel, and its loops pass no array to a helper (a call costs its arrays' reference counts:
    most of a gradient's time on large spans). The one shader: the kernels call it for spans,
    rows and single pixels alike."""
    if kind == 0:
        for x in range(x0, x1):
            out[x - x0, 0], out[x - x0, 1], out[x - x0, 2], out[x - x0, 3] = f[0], f[1], f[2], f[3]
        return
    if kind == 1 or kind == 2:
        base, spread = int(f[17]), int(f[16])
        m0, m1, m2, m3, m4, m5 = f[4], f[5], f[6], f[7], f[8], f[9]
        a0, a1, a2, a3, a4, a5 = f[10], f[11], f[12], f[13], f[14], f[15]
        one_root = kind == 2 and _focal_on_circle(a0, a1, a2, a3, a4, a5)
        for x in range(x0, x1):
            t, paints = _gradient_t(kind, m0, m1, m2, m3, m4, m5, a0, a1, a2, a3, a4, a5,
                                    one_root, x + 0.5, y)
            if not paints:
                out[x - x0, 0] = out[x - x0, 1] = out[x - x0, 2] = out[x - x0, 3] = 0.0
                continue
            i = base + _lut_index(_spread(t, spread))
            out[x - x0, 0], out[x - x0, 1] = lut[i, 0], lut[i, 1]
            out[x - x0, 2], out[x - x0, 3] = lut[i, 2], lut[i, 3]
        return
    # an image: nearest texel, or bilinear between four (the image's own fill bounds it; a pixel
    # centre just outside, a partly covered edge pixel, takes the edge texel, as resvg does)
    m0, m1, m2, m3, m4, m5 = f[4], f[5], f[6], f[7], f[8], f[9]
    base, h, w = int(f[10]), int(f[11]), int(f[12])
    repeat = f[13] != 0.0
    smooth = f[14] != 0.0
    op = f[18]
    for x in range(x0, x1):
        gx = m0 * (x + 0.5) + m2 * y + m4
        gy = m1 * (x + 0.5) + m3 * y + m5
        j = x - x0
        if not smooth:
            # a centre exactly on a texel boundary belongs to the texel after it ([k, k + 1)),
            # but the inverse transform's rounding can put it a hair below (7.5 px texels from
            # 10: 122.5 maps to 14.999999999999998, not 15): read those as on the boundary
            o = _texel_offset(base, h, w, int(math.floor(gx + NEAREST_SLACK)),
                              int(math.floor(gy + NEAREST_SLACK)), repeat)
            out[j, 0], out[j, 1] = tex[o] * op, tex[o + 1] * op
            out[j, 2], out[j, 3] = tex[o + 2] * op, tex[o + 3] * op
            continue
        u, v = gx - 0.5, gy - 0.5
        ix, iy = int(math.floor(u)), int(math.floor(v))
        fu, fv = u - ix, v - iy
        o00 = _texel_offset(base, h, w, ix, iy, repeat)
        o10 = _texel_offset(base, h, w, ix + 1, iy, repeat)
        o01 = _texel_offset(base, h, w, ix, iy + 1, repeat)
        o11 = _texel_offset(base, h, w, ix + 1, iy + 1, repeat)
        for c in range(4):
            out[j, c] = _bilinear(tex[o00 + c], tex[o10 + c], tex[o01 + c], tex[o11 + c], fu, fv,
                                  op)
