"""Filter effects of the scene: :class:`Filter` (a region and its primitives),
:class:`Primitive` and one frozen dataclass per kind of effect (as usvg's filter::Kind).

Apart from :mod:`vecmsaa.scene.nodes` because a dataclass costs about a millisecond to create
at import time on this machine (its methods are compiled from generated source) and a
document without filters needs none of these: ``vecmsaa.scene.nodes`` hands out these names on
first use (its module ``__getattr__``), so ``from vecmsaa.scene.nodes import GaussianBlur``
imports this module then.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Union

if TYPE_CHECKING:
    from .nodes import Group


# lengths in device pixels
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
    own_subregion: bool = False  # x, y, width or height given: the result is confined to it


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


def translated_filter(f: Filter, dx: int, dy: int) -> Filter:
    """``f`` moved by (dx, dy) device pixels (nodes.translated of a filtered group)."""
    from .nodes import translated

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
        prims.append(Primitive(effect, p.inputs, _shift_rect(p.subregion, dx, dy), p.linear))
    return Filter(region=_shift_rect(f.region, dx, dy), primitives=prims)
