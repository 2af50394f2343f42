"""Convenience API: SVG in, pixels out.

>>> from vecmsaa.api import render_svg
>>> render_svg("drawing.svg", width=512).save("drawing.png")   # doctest: +SKIP

``source`` may be a path, bytes, a str holding the XML, or a binary/text file object. Sizes:
with only ``width`` or only ``height`` the aspect ratio is kept; with both the drawing is
stretched to exactly that size; ``zoom`` scales the intrinsic size. All errors are
:class:`vecmsaa.svg.SvgError` (a ValueError) with a one-line message.
"""
from __future__ import annotations

import gc
import math
import os

import numpy as np

from .scene.transform import compose
from .scene.nodes import Group, Scene
from .svg import SvgError

MAX_PIXELS = 1 << 28
MAX_SIDE = 32768
FONT_OPTIONS = ("use_fonts_dir", "font_family", "serif_family", "sans_serif_family",
                "cursive_family", "fantasy_family", "monospace_family", "skip_system_fonts")


def _read_source(source):
    """→ (bytes, folder of the document or None)."""
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source), None
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return source.encode("utf-8"), None
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        try:
            with open(path, "rb") as f:
                data = f.read()
        except OSError as exc:
            raise SvgError(f"cannot read {path}: {exc.strerror or exc}") from None
        return data, os.path.dirname(os.path.abspath(path))
    if hasattr(source, "read"):
        data = source.read()
        if isinstance(data, str):
            data = data.encode("utf-8")
        name = getattr(source, "name", None)
        folder = (os.path.dirname(os.path.abspath(name))
                  if isinstance(name, str) and os.path.exists(name) else None)
        return data, folder
    raise SvgError(f"unsupported SVG source type {type(source).__name__}")


def output_size(doc_w, doc_h, width=None, height=None, zoom=None):
    """The pixel size for a document of intrinsic size doc_w × doc_h."""
    for name, v in (("width", width), ("height", height), ("zoom", zoom)):
        if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise SvgError(f"{name} must be a positive number, got {v!r}")
    if width is not None and height is not None:
        w, h = float(width), float(height)
    elif width is not None:
        w, h = float(width), width * doc_h / doc_w
    elif height is not None:
        w, h = height * doc_w / doc_h, float(height)
    else:
        z = zoom if zoom is not None else 1.0
        w, h = doc_w * z, doc_h * z
    if width is not None or height is not None:
        if zoom is not None:
            w, h = w * zoom, h * zoom
    if w > MAX_SIDE or h > MAX_SIDE or w * h > MAX_PIXELS:
        raise SvgError(f"output size {w:.6g}x{h:.6g} is too large (limit {MAX_SIDE} px per "
                       f"side and {MAX_PIXELS} pixels)")
    iw, ih = max(1, math.ceil(w - 1e-6)), max(1, math.ceil(h - 1e-6))
    return iw, ih


def _background(background):
    if background is None:
        return (0.0, 0.0, 0.0, 0.0)
    if isinstance(background, str):
        from .svg.color import parse_color
        c = parse_color(background)
        if c is None or c == "currentColor":
            raise SvgError(f"not a colour: {background!r}")
        return tuple(float(x) for x in c)
    vals = tuple(float(x) for x in background)
    if len(vals) == 3:
        vals = vals + (1.0,)
    if len(vals) != 4:
        raise SvgError("background must be a colour string or an RGB(A) tuple")
    if max(vals) > 1.0:
        vals = tuple(v / 255 for v in vals)
    return vals


def load_svg(source, width=None, height=None, zoom=None, dpi=96, background=None,
             resources_dir=None, **font_options) -> Scene:
    """Parse an SVG document and resolve it into a Scene at the requested output size."""
    # The cyclic garbage collector is paused meanwhile: the build allocates hundreds of
    # thousands of objects that all stay alive, and the collections they trigger (a quarter
    # of the time on map data) would find nothing to free.
    collecting = gc.isenabled()
    gc.disable()
    try:
        return _load_svg(source, width, height, zoom, dpi, background, resources_dir,
                         font_options)
    finally:
        if collecting:
            gc.enable()


def _load_svg(source, width, height, zoom, dpi, background, resources_dir, font_options) -> Scene:
    from .svg.builder import Options
    from .svg.resources import Resources
    from .svg.sizing import open_svg

    unknown = set(font_options) - set(FONT_OPTIONS)
    if unknown:
        raise TypeError(f"unknown options: {', '.join(sorted(unknown))}")
    data, folder = _read_source(source)
    options = Options(dpi=float(dpi),
                      font_options={k: v for k, v in font_options.items() if v is not None})
    try:
        document = open_svg(data, folder, Resources(folder, resources_dir), options)
    except RecursionError:
        raise SvgError("document nesting is too deep") from None
    builder, doc_w, doc_h = document.builder, document.width, document.height
    root_m, viewport = document.root_matrix, document.viewport
    if not (doc_w > 0 and doc_h > 0):
        # SVG: a zero or negative size disables rendering; an explicit output size still
        # gives an (empty) image of that size
        if width is None and height is None:
            raise SvgError("the document has a zero or negative size")
        w, h = output_size(1.0, 1.0, width, height, zoom)
        return Scene(w, h, Group(), _background(background))
    w, h = output_size(doc_w, doc_h, width, height, zoom)
    # SVG 2: a transform on the root <svg> applies to its viewport, outside the viewBox
    root_transform = builder.root_transform(doc_w, doc_h)
    if root_transform is None:
        return Scene(w, h, Group(), _background(background))
    to_device = compose(compose((w / doc_w, 0.0, 0.0, h / doc_h, 0.0, 0.0), root_transform),
                        root_m)
    try:
        nodes = builder.build_root(to_device, viewport, root_scale=math.sqrt(
            (w / doc_w) * (h / doc_h)))
    except RecursionError:
        raise SvgError("document nesting is too deep") from None
    return Scene(w, h, Group(children=nodes), _background(background))


def render_svg_array(source, width=None, height=None, zoom=None, dpi=96, background=None,
                     mode="approx", samples=8, resources_dir=None, threads=None,
                     **font_options) -> np.ndarray:
    """Render to an (H, W, 4) uint8 array of straight RGBA. ``threads``: bands rendered at
    once (None: every available core; the image does not depend on it)."""
    from .raster.render import render_scene_rgba8

    scene = load_svg(source, width=width, height=height, zoom=zoom, dpi=dpi,
                     background=background, resources_dir=resources_dir, **font_options)
    return render_scene_rgba8(scene, mode=mode, samples=samples, threads=threads)


def render_svg_png(source, width=None, height=None, zoom=None, dpi=96, background=None,
                   mode="approx", samples=8, resources_dir=None, threads=None,
                   **font_options) -> bytes:
    """Render to PNG bytes: ``encode_png(render_svg_array(...))``, without holding the whole
    image (bands are encoded as they are rendered)."""
    from .raster.render import render_scene_png

    scene = load_svg(source, width=width, height=height, zoom=zoom, dpi=dpi,
                     background=background, resources_dir=resources_dir, **font_options)
    return render_scene_png(scene, mode=mode, samples=samples, threads=threads)


def render_svg(source, width=None, height=None, zoom=None, dpi=96, background=None,
               mode="approx", samples=8, resources_dir=None, **font_options):
    """Render to a PIL RGBA image."""
    from PIL import Image

    arr = render_svg_array(source, width=width, height=height, zoom=zoom, dpi=dpi,
                           background=background, mode=mode, samples=samples,
                           resources_dir=resources_dir, **font_options)
    return Image.fromarray(np.ascontiguousarray(arr), "RGBA")
