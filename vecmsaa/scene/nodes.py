"""The resolved scene: what every front end (SVG, fonts) produces and the renderer consumes.

Everything here is already resolved, as in usvg: geometry is in device pixels (y down, origin at
the top-left corner of the output image), styles are plain values, paints carry the matrix that
maps device pixels into paint space. A renderer needs nothing but this module to draw a scene.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Union

import numpy as np

from .transform import IDENTITY, compose
from .path import Path


@dataclass
class Solid:
    """A flat colour: straight (not premultiplied) RGBA, each in [0, 1]."""
    color: tuple = (0.0, 0.0, 0.0, 1.0)


@dataclass
class LinearGradient:
    """Gradient along (x1, y1) → (x2, y2) in gradient space.

    ``stops`` is a (K, 5) float array of (offset, r, g, b, a), offsets non-decreasing in [0, 1],
    colours straight RGBA. ``to_paint`` maps device pixel coordinates into gradient space.
    """
    x1: float
    y1: float
    x2: float
    y2: float
    stops: np.ndarray
    spread: str = "pad"          # pad | reflect | repeat
    to_paint: tuple = IDENTITY


@dataclass
class RadialGradient:
    """Two-point conical gradient from the focal circle (fx, fy, fr) to the circle (cx, cy, r)."""
    cx: float
    cy: float
    r: float
    fx: float
    fy: float
    stops: np.ndarray
    fr: float = 0.0
    spread: str = "pad"
    to_paint: tuple = IDENTITY


@dataclass
class ImagePaint:
    """A raster image (<image>, colour glyph bitmaps, rendered pattern tiles): (H, W, 4)
    float32 premultiplied RGBA in [0, 1].

    ``to_paint`` maps device pixels into image pixel coordinates (0..W, 0..H); ``repeat`` tiles
    it (patterns), otherwise outside is transparent. ``smooth`` picks bilinear over nearest.
    """
    rgba: np.ndarray
    to_paint: tuple = IDENTITY
    repeat: bool = False
    smooth: bool = True


@dataclass
class PatternPaint:
    """An SVG ``<pattern>``: ``content`` drawn in tile pixels (0..width, 0..height), repeated.

    The raster renders the tile with the render's own options, once per render for each
    ``content`` group: shapes sharing a pattern at one scale share its content (the front end
    hands them the same group) and so the tile. ``to_paint`` maps device pixels into tile
    pixels; ``smooth`` picks bilinear over nearest; ``linear_rgb`` converts the rendered tile's
    colours to linearRGB (mask content with color-interpolation: linearRGB)."""
    content: "Group"
    width: int
    height: int
    to_paint: tuple = IDENTITY
    smooth: bool = True
    linear_rgb: bool = False


Paint = Union[Solid, LinearGradient, RadialGradient, ImagePaint, PatternPaint]


@dataclass(slots=True)
class Fill:
    """A path filled with a paint. Strokes and text arrive here already turned into outlines.
    (Slots: map data makes tens of thousands, each made faster and smaller without a dict.)"""
    path: Path
    paint: Paint = field(default_factory=Solid)
    rule: str = "nonzero"        # nonzero | evenodd
    opacity: float = 1.0
    antialias: bool = True       # shape-rendering: crispEdges turns it off


@dataclass
class Mask:
    """``content`` is rendered, turned into a coverage (luminance or alpha), and multiplies."""
    content: "Group"
    kind: str = "luminance"      # luminance | alpha


# -- filter primitives, one kind each (as usvg's filter::Kind); lengths in device pixels ------
@dataclass(frozen=True)
class Flood:
    color: tuple                 # straight sRGB RGBA


@dataclass(frozen=True)
class GaussianBlur:
    sx: float                    # standard deviations
    sy: float


@dataclass(frozen=True)
class Offset:
    dx: float                    # whole pixels (truncated, as resvg)
    dy: float


@dataclass(frozen=True)
class DropShadow:
    sx: float
    sy: float
    dx: float
    dy: float
    color: tuple


@dataclass(frozen=True)
class Merge:
    """Its inputs drawn over each other in order."""


@dataclass(frozen=True)
class Composite:
    operator: str                # over, in, out, atop, xor, lighter, arithmetic
    k: tuple = (0.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Blend:
    mode: str                    # any CSS blend mode; in over in2


@dataclass(frozen=True)
class ColorMatrix:
    matrix: tuple                # 4 x 5, row by row, on straight colour


@dataclass(frozen=True)
class ComponentTransfer:
    funcs: tuple                 # four (type, values) for R, G, B, A


@dataclass(frozen=True)
class Tile:
    """The region filled with the input's subregion, repeated."""


@dataclass(frozen=True)
class Image:
    content: "Group"             # device pixels, rendered into the region by the raster


@dataclass(frozen=True)
class Morphology:
    operator: str                # erode, dilate
    rx: float
    ry: float


@dataclass(frozen=True)
class Turbulence:
    fx: float                    # base frequency
    fy: float
    octaves: int
    seed: int
    stitch: bool
    fractal: bool
    to_device: tuple             # (sx, sy, e, f): primitive units → device pixels


@dataclass(frozen=True)
class DisplacementMap:
    sx: float                    # scale in device pixels
    sy: float
    x_channel: str               # R, G, B, A
    y_channel: str


@dataclass(frozen=True)
class ConvolveMatrix:
    kernel: tuple                # rows of columns
    target: tuple                # (x, y)
    divisor: float
    bias: float
    edge_mode: str               # duplicate, wrap, none
    preserve_alpha: bool


@dataclass(frozen=True)
class Lighting:
    """feDiffuseLighting, or feSpecularLighting when ``specular``. ``light``: ("distant",
    azimuth, elevation), ("point", x, y, z) or ("spot", x, y, z, at x, at y, at z, exponent,
    cone angle or None), positions in device pixels."""
    specular: bool
    surface_scale: float
    constant: float
    exponent: float
    color: tuple
    light: tuple


Effect = Union[Flood, GaussianBlur, Offset, DropShadow, Merge, Composite, Blend, ColorMatrix,
               ComponentTransfer, Tile, Image, Morphology, Turbulence, DisplacementMap,
               ConvolveMatrix, Lighting]


@dataclass
class Primitive:
    """One filter primitive, resolved to device pixels: ``effect`` is what it computes (one of
    the kinds above; vecmsaa/raster/filter_effects.py computes them). ``inputs``:
    SOURCE_GRAPHIC, SOURCE_ALPHA or the index of an earlier primitive; ``subregion``: (x0, y0,
    x1, y1) device pixels its result is confined to; ``linear``: computed in linearRGB
    (color-interpolation-filters) rather than sRGB."""
    effect: Effect
    inputs: tuple = ()
    subregion: tuple = (0, 0, 0, 0)
    linear: bool = True


SOURCE_GRAPHIC = -1
SOURCE_ALPHA = -2


@dataclass
class Filter:
    """A filter effect: its primitives applied in order inside ``region`` ((x0, y0, x1, y1)
    device pixels); the last primitive's result, cropped to the region, replaces the group."""
    region: tuple
    primitives: list = field(default_factory=list)


@dataclass
class Group:
    """Children drawn in order. A group with opacity < 1, a clip, a mask, a blend mode other
    than normal or filters is drawn into a layer of its own and composited; a plain group is
    flattened. Filters apply first (each to the previous one's result), then clip, mask and
    opacity."""
    children: list = field(default_factory=list)
    opacity: float = 1.0
    clip: "Group | None" = None  # its rendered alpha is the clip coverage
    mask: Mask | None = None
    blend: str = "normal"        # any CSS mix-blend-mode
    isolate: bool = False
    filters: list = field(default_factory=list)

    def needs_layer(self) -> bool:
        return (self.opacity < 1.0 or self.clip is not None or self.mask is not None
                or self.blend != "normal" or self.isolate or bool(self.filters))


Node = Union[Fill, Group]


@dataclass
class Scene:
    width: int
    height: int
    root: Group = field(default_factory=Group)
    background: tuple = (0.0, 0.0, 0.0, 0.0)   # straight RGBA under everything

    def fills(self):
        """All Fill nodes in paint order (ignoring layers); handy for tests and statistics."""
        stack = [self.root]
        out = []
        while stack:
            node = stack.pop()
            if isinstance(node, Fill):
                out.append(node)
            else:
                stack.extend(reversed(node.children))
        return out


def translated(node: Node, dx: float, dy: float) -> Node:
    """A copy of ``node`` moved by (dx, dy) device pixels: paths, paint matrices, clips, masks
    and filters (regions, subregions and the device positions in primitive parameters)."""
    if isinstance(node, Fill):
        paint = node.paint
        if not isinstance(paint, Solid):
            paint = replace(paint, to_paint=compose(paint.to_paint, (1.0, 0.0, 0.0, 1.0,
                                                                      -dx, -dy)))
        return replace(node, path=node.path.transformed((1.0, 0.0, 0.0, 1.0, dx, dy)),
                       paint=paint)
    return replace(
        node, children=[translated(c, dx, dy) for c in node.children],
        clip=None if node.clip is None else translated(node.clip, dx, dy),
        mask=None if node.mask is None else replace(node.mask,
                                                     content=translated(node.mask.content, dx, dy)),
        filters=[_translated_filter(f, dx, dy) for f in node.filters])


def shifted_light(light: tuple, dx: float, dy: float) -> tuple:
    """A lighting primitive's light source moved by (dx, dy) pixels: a point light's position,
    a spot light's position and target; a distant light has no position."""
    if light[0] == "distant":
        return light
    light = list(light)
    light[1] += dx
    light[2] += dy
    if light[0] == "spot":
        light[4] += dx
        light[5] += dy
    return tuple(light)


def _shift_rect(r, dx, dy):
    return (r[0] + dx, r[1] + dy, r[2] + dx, r[3] + dy)


def _translated_filter(f: Filter, dx: int, dy: int) -> Filter:
    prims = []
    for p in f.primitives:
        effect = p.effect
        if isinstance(effect, Image):
            effect = replace(effect, content=translated(effect.content, dx, dy))
        elif isinstance(effect, Turbulence):
            sx, sy, e, f_ = effect.to_device
            effect = replace(effect, to_device=(sx, sy, e + dx, f_ + dy))
        elif isinstance(effect, Lighting):
            effect = replace(effect, light=shifted_light(effect.light, dx, dy))
        prims.append(replace(p, effect=effect, subregion=_shift_rect(p.subregion, dx, dy)))
    return Filter(region=_shift_rect(f.region, dx, dy), primitives=prims)
