"""The resolved scene: what every front end (SVG, fonts) produces and the renderer consumes.

Everything here is already resolved, as in usvg: geometry is in device pixels (y down, origin at
the top-left corner of the output image), styles are plain values, paints carry the matrix that
maps device pixels into paint space. A renderer needs nothing but this module (and
:mod:`vecmsaa.scene.effects`, the filters, whose names this module hands out on first use) to
draw a scene.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Union

import numpy as np

from .transform import IDENTITY, apply, compose
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
    filters: list = field(default_factory=list)    # scene.effects.Filter
    #: (dx, dy) device pixels a filtered group's children are still to be moved by: translated
    #: moves a filtered group's filters, clip and mask but leaves its children to the filter,
    #: which moves them to its region's corner anyway; moved at every level, filtered groups
    #: nested N deep were copied N times over (37,000 of them nested 600 deep: 9 GB). Only
    #: filtered groups carry one.
    shift: tuple = (0, 0)

    def needs_layer(self) -> bool:
        return (self.opacity < 1.0 or self.clip is not None or self.mask is not None
                or self.blend != "normal" or self.isolate or bool(self.filters))


@dataclass(slots=True, eq=False)
class FillRuns:
    """Many fills as a batch's arrays, in paint order: run r is the path ``verbs[voff[r]:
    voff[r + 1]]``, ``points[poff[r]:poff[r + 1]]`` (uint8 verbs, (P, 2) float64 device
    points, int64 offsets of N + 1 entries), filled as ``styles[kind[r]]``, a (paint, rule,
    opacity, antialias) as Fill's fields. What the SVG front end makes of a long run of
    simple shapes and their strokes (a scatter plot's 20,000 circles and their 100,000
    hairline runs), which the raster batches as they are; ``fills()`` gives the same as
    Fills, for what walks a scene fill by fill. Every run draws something (a verb besides
    MOVE and CLOSE is not promised, but none is empty of verbs)."""
    verbs: np.ndarray
    points: np.ndarray
    voff: np.ndarray
    poff: np.ndarray
    styles: list
    kind: np.ndarray

    def __len__(self) -> int:
        return len(self.kind)

    def fills(self) -> list:
        """The runs as Fills, each path a view of the arrays."""
        verbs, points, styles = self.verbs, self.points, self.styles
        vo, po = self.voff.tolist(), self.poff.tolist()
        return [Fill(Path._of_arrays(verbs[v0:v1], points[p0:p1]), *styles[k])
                for v0, v1, p0, p1, k in zip(vo, vo[1:], po, po[1:], self.kind.tolist())]


Node = Union[Fill, FillRuns, Group]


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
            elif isinstance(node, FillRuns):
                out.extend(node.fills())
            else:
                stack.extend(reversed(node.children))
        return out


def translated(node: Node, dx: float, dy: float) -> Node:
    """A copy of ``node`` moved by (dx, dy) device pixels: paths, paint matrices, clips, masks
    and filters (regions, subregions and the device positions in primitive parameters); a
    filtered group's children are not copied but their move added to its ``shift``."""
    if isinstance(node, Fill):
        paint = _moved_paint(node.paint, dx, dy)
        # (copies made field by field, not by dataclasses.replace, which costs more than the
        # rest: each filtered layer is moved, and filtered markers come by the ten thousand;
        # test_svg_scene checks that every field is kept)
        return Fill(node.path.transformed((1.0, 0.0, 0.0, 1.0, dx, dy)), paint, node.rule,
                    node.opacity, node.antialias)
    if isinstance(node, FillRuns):
        m = (1.0, 0.0, 0.0, 1.0, dx, dy)
        styles = [(_moved_paint(paint, dx, dy), rule, opacity, antialias)
                  for paint, rule, opacity, antialias in node.styles]
        return FillRuns(node.verbs, apply(m, node.points) if len(node.points) else node.points,
                        node.voff, node.poff, styles, node.kind)
    if node.filters:
        children, shift = node.children, (node.shift[0] + dx, node.shift[1] + dy)
    else:
        children, shift = [translated(c, dx, dy) for c in node.children], node.shift
    return Group(
        children, node.opacity,
        None if node.clip is None else translated(node.clip, dx, dy),
        None if node.mask is None else Mask(translated(node.mask.content, dx, dy), node.mask.kind),
        node.blend, node.isolate, translated_filters(node.filters, dx, dy), shift)


def _moved_paint(paint, dx, dy):
    """The paint of a fill moved by (dx, dy) device pixels (translated)."""
    if isinstance(paint, Solid):
        return paint
    return replace(paint, to_paint=compose(paint.to_paint, (1.0, 0.0, 0.0, 1.0, -dx, -dy)))


def translated_filters(filters, dx, dy):
    """The filters moved by (dx, dy) device pixels (scene.effects.translated_filter)."""
    if not filters:
        return []
    from .effects import translated_filter
    return [translated_filter(f, dx, dy) for f in filters]


#: the names of scene.effects, handed out from here on first use (see that module)
_EFFECTS = frozenset((
    "Flood", "GaussianBlur", "Offset", "DropShadow", "Merge", "Composite", "Blend",
    "ColorMatrix", "ComponentTransfer", "Tile", "Image", "Morphology", "Turbulence",
    "DisplacementMap", "ConvolveMatrix", "Lighting", "Effect", "Primitive", "Filter",
    "SOURCE_GRAPHIC", "SOURCE_ALPHA", "shifted_light"))


def __getattr__(name):
    if name in _EFFECTS:
        from . import effects
        value = getattr(effects, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
