"""COLR version 1 colour glyphs: the paint graph of a base glyph becomes scene nodes.

The OpenType COLR v1 table (ISO/IEC 14496-22 5.7.11, OpenType 1.9) describes a colour glyph
as a directed acyclic graph of paints, read here through fontTools:

- PaintGlyph fills an outline glyph with its child paint; a child that is a solid colour or a
  gradient (under any chain of transforms) becomes the fill's paint, anything else is drawn
  into a layer clipped by the outline;
- PaintSolid, PaintLinear/Radial/SweepGradient are the paints (palette colours with an alpha
  factor; entry 0xFFFF is the text's own colour); a linear gradient's third point p2 turns the
  colour line perpendicular to p0-p2; colour-line offsets outside [0, 1] widen the geometry;
  a sweep gradient (a conic, angles counter-clockwise in font space) is evaluated per device
  pixel into an image paint;
- PaintTransform, Translate, Scale, Rotate, Skew (and their around-centre forms) compose;
- PaintColrLayers and PaintColrGlyph draw other paints (a cycle or a depth beyond
  MAX_DEPTH draws nothing);
- PaintComposite draws a source over a backdrop with a Porter-Duff operator (through the
  filter Composite primitive, in sRGB) or a separable/non-separable blend mode (a blended
  group);
- the ClipList box of a base glyph clips what it draws.

Variable paints (PaintVar*) are drawn at their default values; a warning says so when the
face is instanced away from its default location.
"""
from __future__ import annotations

import math

import numpy as np

from ..diagnostics import warn
from ..scene.nodes import (SOURCE_GRAPHIC, Composite, Fill, Filter, Group, Image, ImagePaint,
                           LinearGradient, Primitive, RadialGradient, Solid)
from ..scene.path import Path, rect_path
from ..scene.transform import compose, invert

FOREGROUND = 0xFFFF
#: PaintColrGlyph / PaintColrLayers nesting beyond this draws nothing (hostile fonts)
MAX_DEPTH = 64
#: paints visited for one glyph: a graph reusing its paints can expand exponentially (each
#: level drawing the one below twice); beyond this the rest is not drawn, with a warning
MAX_PAINTS = 20000
#: a sweep gradient's image is at most this many pixels (coarser beyond)
MAX_SWEEP_PIXELS = 1 << 22

_SPREAD = {0: "pad", 1: "repeat", 2: "reflect"}
#: PaintComposite's Porter-Duff modes as (filter Composite operator, source first?)
_PORTER_DUFF = {5: ("in", True), 6: ("in", False), 7: ("out", True), 8: ("out", False),
                9: ("atop", True), 10: ("atop", False), 11: ("xor", True),
                12: ("lighter", True)}
_BLEND = {13: "screen", 14: "overlay", 15: "darken", 16: "lighten", 17: "color-dodge",
          18: "color-burn", 19: "hard-light", 20: "soft-light", 21: "difference",
          22: "exclusion", 23: "multiply", 24: "hue", 25: "saturation", 26: "color",
          27: "luminosity"}


def colr_v1_glyphs(face) -> dict:
    """gid → root Paint of the face's COLR v1 base glyphs; cached on the face."""
    found = getattr(face, "_colr_v1", None)
    if found is None:
        found = {}
        t = face.ttfont
        try:
            colr = t["COLR"].table if "COLR" in t and "CPAL" in t else None
            if colr is not None and getattr(colr, "Version", 0) >= 1 and colr.BaseGlyphList:
                ids = face.glyph_ids
                for rec in colr.BaseGlyphList.BaseGlyphPaintRecord:
                    if rec.BaseGlyph in ids:
                        found[ids[rec.BaseGlyph]] = rec.Paint
        except Exception:
            found = {}
        face._colr_v1 = found
    return found


def colr_v1_nodes(face, location, gid, matrix, paint, to_device) -> list:
    """Scene nodes drawing COLR v1 glyph ``gid`` placed by ``matrix`` (font units → user
    space), then ``to_device`` (user space → device pixels); ``paint`` is the text's paint
    (its colour is palette entry 0xFFFF)."""
    root = colr_v1_glyphs(face).get(int(gid))
    if root is None:
        return []
    if location and getattr(face.ttfont["COLR"].table, "VarStore", None) is not None:
        warn(f"font '{face.family}': COLRv1 variations are drawn at the default location")
    foreground = paint.color if isinstance(paint, Solid) else (0.0, 0.0, 0.0, 1.0)
    painter = _Painter(face, location, foreground)
    m = compose(tuple(to_device), tuple(matrix))
    return painter.base_glyph(face.glyph_order[int(gid)], root, m, set())


class _Painter:
    def __init__(self, face, location, foreground):
        self.face, self.location, self.foreground = face, location, foreground
        self.colr = face.ttfont["COLR"].table
        self.palette = face.ttfont["CPAL"].palettes[0]
        clips = getattr(self.colr, "ClipList", None)
        self.clips = getattr(clips, "clips", None) or {}
        self.budget = MAX_PAINTS

    # -- graph -----------------------------------------------------------------------------
    def base_glyph(self, name, root, m, active) -> list:
        """A base glyph's paint at device matrix ``m``, clipped by its clip box."""
        if name in active or len(active) >= MAX_DEPTH:
            return []
        nodes = self.nodes(root, m, active | {name})
        box = self.clips.get(name)
        if box is None or not nodes:
            return nodes
        clip = rect_path(box.xMin, box.yMin, box.xMax - box.xMin,
                         box.yMax - box.yMin).transformed(m)
        return [Group(children=nodes, clip=Group(children=[Fill(clip, Solid())]))]

    def nodes(self, p, m, active) -> list:
        """Scene nodes of paint ``p`` with font units mapped to device pixels by ``m``."""
        self.budget -= 1
        if self.budget < 0:
            if self.budget == -1:
                warn(f"font '{self.face.family}': a COLRv1 glyph has more than {MAX_PAINTS} "
                     "paints: the rest is not drawn")
            return []
        fmt = p.Format
        if fmt == 1:                                   # PaintColrLayers
            if len(active) >= MAX_DEPTH or self.colr.LayerList is None:
                return []
            layers = self.colr.LayerList.Paint[p.FirstLayerIndex:p.FirstLayerIndex + p.NumLayers]
            out = []
            for layer in layers:
                out.extend(self.nodes(layer, m, active | {("layers", id(p))}))
            return out
        if fmt in (10, 33):                            # PaintGlyph
            return self.glyph(p, m, active)
        if fmt == 11:                                  # PaintColrGlyph
            ref = colr_v1_glyphs(self.face).get(self.face.glyph_ids.get(p.Glyph, -1))
            return [] if ref is None else self.base_glyph(p.Glyph, ref, m, active)
        if 12 <= fmt <= 31:
            return self.nodes(p.Paint, compose(m, paint_transform(p)), active)
        if fmt == 32:
            return self.composite(p, m, active)
        # a bare colour or gradient fills the base glyph's clip box (or the whole em square)
        box = self.em_box(m)
        made = self.paint(p, m, box.bounds())
        return [] if made is None else [Fill(box, made)]

    def glyph(self, p, m, active) -> list:
        from .layout import glyphs_path

        gid = self.face.glyph_ids.get(p.Glyph)
        if gid is None:
            return []
        path = glyphs_path(self.face, self.location, [gid], [m])
        if path.is_empty():
            return []
        child, cm = p.Paint, m
        while 12 <= child.Format <= 31:                # transforms of a plain paint
            cm = compose(cm, paint_transform(child))
            child = child.Paint
        if child.Format in range(2, 10):
            made = self.paint(child, cm, path.bounds())
            return [] if made is None else [Fill(path, made)]
        inner = self.nodes(p.Paint, m, active)
        if not inner:
            return []
        return [Group(children=inner, clip=Group(children=[Fill(path, Solid())]))]

    def composite(self, p, m, active) -> list:
        source = self.nodes(p.SourcePaint, m, active)
        backdrop = self.nodes(p.BackdropPaint, m, active)
        mode = int(p.CompositeMode)
        if mode == 0:                                  # clear
            return []
        if mode == 1:                                  # src
            return source
        if mode == 2:                                  # dest
            return backdrop
        if mode == 3:                                  # src over
            return backdrop + source
        if mode == 4:                                  # dest over
            return source + backdrop
        if mode in _BLEND:
            if not backdrop:
                return source
            return [Group(children=[Group(children=backdrop),
                                    Group(children=source, blend=_BLEND[mode])],
                          isolate=True)]
        if mode not in _PORTER_DUFF:
            warn(f"font '{self.face.family}': COLRv1 composite mode {mode} is not drawn")
            return backdrop + source
        operator, source_first = _PORTER_DUFF[mode]
        first, second = (source, backdrop) if source_first else (backdrop, source)
        region = _device_box(first + second)
        if region is None:
            return []
        if not second:
            # A op nothing: in/atop leave nothing (atop keeps the nothing), out/xor/lighter A
            return [] if operator in ("in", "atop") else first
        if not first:
            return second if operator in ("atop", "xor", "lighter") else []
        flt = Filter(region=region, primitives=[
            Primitive(Image(Group(children=second)), (), region, False),
            Primitive(Composite(operator), (SOURCE_GRAPHIC, 0), region, False)])
        return [Group(children=first, filters=[flt])]

    def em_box(self, m) -> Path:
        """Where a paint outside any PaintGlyph is drawn: the font's em square widened to its
        ascender/descender (the base glyph's clip box, applied by base_glyph, cuts it)."""
        upm = self.face.units_per_em
        met = self.face.metrics
        lo, hi = min(met.descender, 0.0) - upm, max(met.ascender, upm) + upm
        return rect_path(-upm, lo, 3 * upm, hi - lo).transformed(m)

    # -- paints ----------------------------------------------------------------------------
    def color(self, index, alpha) -> tuple:
        if index == FOREGROUND:
            r, g, b, a = self.foreground
        elif 0 <= index < len(self.palette):
            c = self.palette[index]
            r, g, b, a = c.red / 255.0, c.green / 255.0, c.blue / 255.0, c.alpha / 255.0
        else:
            r, g, b, a = 0.0, 0.0, 0.0, 1.0
        return (r, g, b, a * min(max(float(alpha), 0.0), 1.0))

    def stops(self, color_line):
        """(offsets, straight RGBA (K, 4), spread) of a colour line, sorted by offset."""
        recs = list(color_line.ColorStop)
        if not recs:
            return None
        offs = np.array([float(s.StopOffset) for s in recs])
        rgba = np.array([self.color(s.PaletteIndex, s.Alpha) for s in recs])
        order = np.argsort(offs, kind="stable")
        return offs[order], rgba[order], _SPREAD.get(int(color_line.Extend), "pad")

    def paint(self, p, m, bounds):
        """A scene paint for a solid or gradient paint with font units → device ``m``, or
        None when nothing is drawn. ``bounds``: device box the paint must cover."""
        fmt = p.Format
        if fmt in (2, 3):
            return Solid(self.color(p.PaletteIndex, p.Alpha))
        line = self.stops(p.ColorLine)
        if line is None:
            return None
        offs, rgba, spread = line
        try:
            to_paint = invert(m)
        except ValueError:
            return None
        if fmt in (8, 9):
            return sweep_image(p.centerX, p.centerY, p.startAngle, p.endAngle, offs, rgba,
                               spread, to_paint, bounds)
        lo, hi = float(offs[0]), float(offs[-1])
        if hi - lo < 1e-9:                             # one offset: a hard step there
            hi = lo + 1e-6
        stops = np.column_stack([(offs - lo) / (hi - lo), rgba])
        if fmt in (4, 5):
            x0, y0, x1, y1 = linear_axis(p.x0, p.y0, p.x1, p.y1, p.x2, p.y2)
            if (x1 - x0) ** 2 + (y1 - y0) ** 2 == 0:
                return None
            return LinearGradient(x0 + lo * (x1 - x0), y0 + lo * (y1 - y0),
                                  x0 + hi * (x1 - x0), y0 + hi * (y1 - y0), stops, spread,
                                  to_paint)
        if fmt in (6, 7):
            def at(t):
                return (p.x0 + t * (p.x1 - p.x0), p.y0 + t * (p.y1 - p.y0),
                        max(p.r0 + t * (p.r1 - p.r0), 0.0))
            fx, fy, fr = at(lo)
            cx, cy, r = at(hi)
            return RadialGradient(cx, cy, r, fx, fy, stops, fr, spread, to_paint)
        return None


def linear_axis(x0, y0, x1, y1, x2, y2):
    """COLR's linear gradient p0, p1, p2 as an SVG-style axis p0 → p3: the colour is constant
    along lines parallel to p0-p2, so p3 is p1 projected onto the normal of p0-p2 through p0
    (p1 itself when p0 = p2)."""
    dx, dy = x2 - x0, y2 - y0
    nn = dx * dx + dy * dy
    if nn == 0:
        return float(x0), float(y0), float(x1), float(y1)
    nx, ny = dy, -dx
    k = ((x1 - x0) * nx + (y1 - y0) * ny) / nn
    return float(x0), float(y0), float(x0 + k * nx), float(y0 + k * ny)


def paint_transform(p) -> tuple:
    """The affine matrix (SVG order) of a transform paint (formats 12-31), font units."""
    fmt = p.Format
    if fmt in (12, 13):
        t = p.Transform
        return (t.xx, t.yx, t.xy, t.yy, t.dx, t.dy)
    if fmt in (14, 15):
        return (1.0, 0.0, 0.0, 1.0, p.dx, p.dy)
    if 16 <= fmt <= 23:
        sx, sy = (p.scale, p.scale) if fmt >= 20 else (p.scaleX, p.scaleY)
        m = (sx, 0.0, 0.0, sy, 0.0, 0.0)
    elif 24 <= fmt <= 27:
        a = math.radians(p.angle)                     # counter-clockwise, y up
        c, s = math.cos(a), math.sin(a)
        m = (c, s, -s, c, 0.0, 0.0)
    else:                                             # 28-31 skew
        m = (1.0, math.tan(math.radians(p.ySkewAngle)), -math.tan(math.radians(p.xSkewAngle)),
             1.0, 0.0, 0.0)
    if fmt in (18, 19, 22, 23, 26, 27, 30, 31):       # ... around a centre
        cx, cy = p.centerX, p.centerY
        m = compose((1.0, 0.0, 0.0, 1.0, cx, cy), compose(m, (1.0, 0.0, 0.0, 1.0, -cx, -cy)))
    return tuple(float(v) for v in m)


def sweep_colors(angles, start, end, offs, rgba, spread) -> np.ndarray:
    """Premultiplied RGBA at ``angles`` (degrees in [0, 360)) of a sweep gradient whose
    colour line runs from ``start`` to ``end`` degrees; straight-colour interpolation."""
    if abs(end - start) < 1e-9:
        t = np.where(angles < start, -1.0, 2.0)
        span_lo, span_hi = 0.0, 1.0
        offs = np.clip(offs, 0.0, 1.0)
    else:
        t = (angles - start) / (end - start)
        span_lo, span_hi = float(offs[0]), float(offs[-1])
    if spread != "pad" and span_hi - span_lo > 1e-9:
        u = (t - span_lo) / (span_hi - span_lo)
        if spread == "repeat":
            u = u - np.floor(u)
        else:
            u = np.abs(u - 2.0 * np.floor(u / 2.0 + 0.5))
        t = span_lo + u * (span_hi - span_lo)
    out = np.empty(angles.shape + (4,))
    for ch in range(4):
        out[..., ch] = np.interp(t, offs, rgba[:, ch])
    out[..., :3] *= out[..., 3:4]
    return out


def sweep_image(cx, cy, start, end, offs, rgba, spread, to_paint, bounds):
    """A sweep gradient as an image paint over the device box ``bounds``, one sample at each
    pixel centre (coarser when the box holds more than MAX_SWEEP_PIXELS)."""
    if bounds is None:
        return None
    x0, y0 = math.floor(bounds[0]), math.floor(bounds[1])
    w, h = max(1, math.ceil(bounds[2]) - x0), max(1, math.ceil(bounds[3]) - y0)
    step = max(1.0, math.sqrt(w * h / MAX_SWEEP_PIXELS))
    iw, ih = max(1, math.ceil(w / step)), max(1, math.ceil(h / step))
    px = x0 + (np.arange(iw) + 0.5) * step
    py = y0 + (np.arange(ih) + 0.5) * step
    gx, gy = np.meshgrid(px, py)
    a, b, c, d, e, f = to_paint
    fx, fy = a * gx + c * gy + e, b * gx + d * gy + f
    angles = np.degrees(np.arctan2(fy - cy, fx - cx)) % 360.0
    img = sweep_colors(angles, float(start), float(end), offs, rgba, spread)
    # device pixel → image pixel
    to_image = (1.0 / step, 0.0, 0.0, 1.0 / step, -x0 / step, -y0 / step)
    return ImagePaint(img.astype(np.float32), to_paint=to_image, smooth=True)


def _device_box(nodes):
    """Integer device box (x0, y0, x1, y1) of the fills in ``nodes``, or None."""
    box = None
    stack = list(nodes)
    while stack:
        n = stack.pop()
        if isinstance(n, Fill):
            b = n.path.bounds()
            if b is not None:
                box = b if box is None else (min(box[0], b[0]), min(box[1], b[1]),
                                             max(box[2], b[2]), max(box[3], b[3]))
        else:
            stack.extend(n.children)
    if box is None:
        return None
    return (math.floor(box[0]), math.floor(box[1]), math.ceil(box[2]) + 1,
            math.ceil(box[3]) + 1)
