"""Convenience API: SVG in, pixels out.

>>> from vecmsaa.api import render_svg
>>> render_svg("drawing.svg", width=512).save("drawing.png")   # doctest: +SKIP

``source`` may be a path, bytes, a str holding the XML, or a binary/text file object (read up
to 64 MiB). Sizes as resvg computes them: with only ``width`` or only ``height`` the aspect
ratio is kept; with both the drawing is stretched to exactly that size (or fitted inside with
``keep_aspect=True``); ``zoom`` scales the intrinsic size and is ignored with a width or
height. Problems that do not stop a render are :class:`vecmsaa.RenderWarning` warnings; all
errors are :class:`vecmsaa.svg.SvgError` (a ValueError) with a one-line message.
"""
from __future__ import annotations

import contextlib
import gc
import math
import os
from typing import TYPE_CHECKING, BinaryIO, Sequence, Union

import numpy as np

from . import diagnostics
from .raster.modes import DEFAULT_MODE, coverage, samples_for
from .scene.bounds import path_bounds, union
from .scene.nodes import Group, Scene
from .scene.transform import IDENTITY
from .svg import SvgError

if TYPE_CHECKING:
    from PIL import Image

#: an SVG: a path, the bytes, a str holding the XML, or a binary file object
Source = Union[str, os.PathLike, bytes, bytearray, memoryview, BinaryIO]
#: a CSS colour, an RGB(A) tuple (0–1, or 0–255 when any value is above 1) or None
Background = Union[str, Sequence[float], None]

MAX_PIXELS = 1 << 28
MAX_SIDE = 32768
FONT_OPTIONS = ("use_font_file", "use_fonts_dir", "font_family", "serif_family", "sans_serif_family",
                "cursive_family", "fantasy_family", "monospace_family", "skip_system_fonts")


def read_bounded(f, name: str) -> bytes:
    """At most MAX_DOCUMENT_BYTES from a binary file object (``/dev/zero`` and endless pipes
    stop there with an error instead of filling the memory)."""
    from .svg.document import MAX_DOCUMENT_BYTES

    data = f.read(MAX_DOCUMENT_BYTES + 1)
    if isinstance(data, str):
        data = data.encode("utf-8")
    if len(data) > MAX_DOCUMENT_BYTES:
        raise SvgError(f"{name} is larger than the {MAX_DOCUMENT_BYTES >> 20} MiB input limit")
    return data


def _read_source(source):
    """→ (bytes, folder of the document or None)."""
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source), None
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return source.encode("utf-8"), None
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        if os.path.isdir(path):
            raise SvgError(f"cannot read {path}: it is a folder")
        try:
            with open(path, "rb") as f:
                data = read_bounded(f, path)
        except OSError as exc:
            raise SvgError(f"cannot read {path}: {exc.strerror or exc}") from None
        return data, os.path.dirname(os.path.abspath(path))
    if hasattr(source, "read"):
        name = getattr(source, "name", None)
        data = read_bounded(source, name if isinstance(name, str) else "the input")
        folder = (os.path.dirname(os.path.abspath(name))
                  if isinstance(name, str) and os.path.exists(name) else None)
        return data, folder
    raise SvgError(f"unsupported SVG source type {type(source).__name__}")


def _round_half_up(v: float) -> int:
    return int(math.floor(v + 0.5))


def output_size(doc_w, doc_h, width=None, height=None, zoom=None, keep_aspect=False,
                size_limit=True):
    """The pixel size for a document of intrinsic size doc_w × doc_h, computed as resvg does:
    the intrinsic size is rounded to whole pixels first; ``width`` alone keeps the aspect ratio
    (the other side rounded up), as does ``height`` alone; both stretch to exactly that size,
    or with ``keep_aspect`` fit inside it (rsvg-convert's ``-a``, resvg's default); ``zoom``
    scales the rounded size and is ignored when a width or height is given. Sizes beyond
    MAX_SIDE per side or MAX_PIXELS in all are refused unless ``size_limit`` is False."""
    for name, v in (("width", width), ("height", height), ("zoom", zoom)):
        if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise SvgError(f"{name} must be a positive number, got {v!r}")
    if not (math.isfinite(doc_w) and math.isfinite(doc_h)):
        raise SvgError("the document's size is not a finite number")
    iw = max(1, _round_half_up(doc_w))
    ih = max(1, _round_half_up(doc_h))
    ceil = lambda v: max(1, math.ceil(v - 1e-9))   # noqa: E731
    if width is not None and height is not None:
        w, h = ceil(width), ceil(height)
        if keep_aspect:
            fit_w = ceil(h * iw / ih)
            w, h = (fit_w, h) if fit_w <= w else (w, ceil(w * ih / iw))
    elif width is not None:
        w = ceil(width)
        h = ceil(w * ih / iw)
    elif height is not None:
        h = ceil(height)
        w = ceil(h * iw / ih)
    elif zoom is not None:
        w, h = max(1, _round_half_up(iw * zoom)), max(1, _round_half_up(ih * zoom))
    else:
        w, h = iw, ih
    if size_limit and (w > MAX_SIDE or h > MAX_SIDE or w * h > MAX_PIXELS):
        raise SvgError(f"output size {w:.6g}x{h:.6g} is too large (limit {MAX_SIDE} px per side and "
                       f"{MAX_PIXELS} pixels in all; --no-size-limit lifts it)")
    return w, h


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


#: document options: how the SVG is read, independent of size and rendering
DOCUMENT_OPTIONS = ("stylesheet", "languages", "font_size", "shape_rendering", "text_rendering",
                    "image_rendering")


def load_svg(source: Source, width: float | None = None, height: float | None = None,
             zoom: float | None = None, dpi: float = 96, background: Background = None,
             resources_dir: str | os.PathLike | None = None, *, keep_aspect: bool = False,
             size_limit: bool = True, export_id: str | None = None, cull: bool = True,
             **options) -> Scene:
    """Parse an SVG document and resolve it into a Scene at the requested output size.

    ``options`` are the document options (DOCUMENT_OPTIONS) and the font options
    (FONT_OPTIONS); see :func:`render_svg` for all of them. ``cull``: leave out text glyphs
    that cannot reach the image (no pixel changes, but the scene's bounds no longer hold
    them: off where they are measured, as for ``export_area_drawing``)."""
    with collector_paused(), diagnostics.as_python_warnings():
        loaded = _Loaded(source, dpi, resources_dir, options)
        try:
            scene = loaded.scene(width, height, zoom, background, keep_aspect, size_limit,
                                 export_id, cull)
        finally:
            loaded.builder.doc.release()    # (see collector_paused)
        del loaded
    return scene


@contextlib.contextmanager
def collector_paused():
    """Python's cyclic garbage collector paused (and restored as it was): a document's build
    allocates hundreds of thousands of objects that all stay alive until its render ends, and
    the collections they trigger (a quarter of the front end's time on map data; during the
    render, full passes over the live scene) would find nothing to free. The pass when it
    resumes walks whatever tracked objects are still alive or in reference cycles, so a render
    drops its scene before (the scene holds no cycles) and load_svg the element tree's
    cycles (Document.release)."""
    collecting = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if collecting:
            gc.enable()


class _Loaded:
    """A parsed document and its builder, ready to be built at any size."""

    def __init__(self, source, dpi, resources_dir, options):
        from .svg.builder import Options
        from .svg.resources import Resources
        from .svg.sizing import open_svg

        unknown = set(options) - set(FONT_OPTIONS) - set(DOCUMENT_OPTIONS)
        if unknown:
            raise TypeError(f"unknown options: {', '.join(sorted(unknown))}")
        font_options = {k: options[k] for k in FONT_OPTIONS if options.get(k) is not None}
        data, folder = _read_source(source)
        try:
            document = open_svg(data, folder, Resources(folder, resources_dir),
                                Options(dpi=float(dpi), font_options=font_options),
                                stylesheet=options.get("stylesheet"),
                                root_defaults=_root_defaults(options),
                                languages=tuple(options.get("languages") or ("en",)))
        except RecursionError:
            raise SvgError("document nesting is too deep") from None
        self.document, self.builder = document, document.builder

    def intrinsic_size(self):
        return self.document.width, self.document.height

    def build(self, to_device, root_scale=1.0, nodes_by_id=None, image=None) -> list:
        """The root's nodes under ``to_device`` (intrinsic px → device), [] when the root
        transform is singular; ``image``: (width, height) of the image they are drawn in,
        to cull text with (Builder.build_root)."""
        self.builder.nodes_by_id = nodes_by_id
        try:
            return self.document.build(to_device, root_scale, image)
        except RecursionError:
            raise SvgError("document nesting is too deep") from None
        finally:
            self.builder.nodes_by_id = None

    def bounds_by_id(self) -> dict:
        """{id: (x0, y0, x1, y1)} in intrinsic px for each rendered element with an id that
        draws something, in document order."""
        found = {}
        self.build(IDENTITY, nodes_by_id=found)
        out = {}
        for ident, nodes in found.items():
            box = nodes_bounds(nodes)
            if box is not None:
                out[ident] = box
        return out

    def scene(self, width, height, zoom, background, keep_aspect, size_limit,
              export_id=None, cull=False) -> Scene:
        doc_w, doc_h = self.intrinsic_size()
        bg = _background(background)
        if not (doc_w > 0 and doc_h > 0):
            # SVG: a zero or negative size disables rendering; an explicit output size still
            # gives an (empty) image of that size
            if width is None and height is None:
                raise SvgError("the document has a zero or negative size")
            w, h = output_size(1.0, 1.0, width, height, zoom, keep_aspect, size_limit)
            return Scene(w, h, Group(), bg)
        x0 = y0 = 0.0
        if export_id is not None:
            box = self.bounds_by_id().get(export_id)
            if box is None:
                raise SvgError(f"no element with id {export_id!r} that draws something")
            x0, y0, x1, y1 = box
            doc_w, doc_h = x1 - x0, y1 - y0
        w, h = output_size(doc_w, doc_h, width, height, zoom, keep_aspect, size_limit)
        sx, sy = w / doc_w, h / doc_h
        to_device = (sx, 0.0, 0.0, sy, -x0 * sx, -y0 * sy)
        found = {} if export_id is not None else None
        # the geometric mean as a product of roots: sx * sy underflows to 0 for a content
        # box of 1e302 units drawn 100 px wide, and the text-on-path tolerance divides by it
        nodes = self.build(to_device, math.sqrt(sx) * math.sqrt(sy), found,
                           (w, h) if cull and export_id is None else None)
        if export_id is not None:
            nodes = found.get(export_id, [])
        return Scene(w, h, Group(children=nodes), bg)


def _root_defaults(options) -> dict:
    out = {}
    if options.get("font_size") is not None:
        size = options["font_size"]
        if not (isinstance(size, (int, float)) and math.isfinite(size) and size > 0):
            raise SvgError(f"font_size must be a positive number, got {size!r}")
        out["font-size"] = f"{float(size):g}"
    for name in ("shape_rendering", "text_rendering", "image_rendering"):
        if options.get(name):
            out[name.replace("_", "-")] = str(options[name])
    return out


def nodes_bounds(nodes):
    """(x0, y0, x1, y1) of the fills among ``nodes`` (strokes are fills by then), or None."""
    box = None
    for f in Scene(1, 1, Group(children=nodes)).fills():
        box = union(box, path_bounds(f.path))
    if box is None or box[2] <= box[0] and box[3] <= box[1]:
        return None
    return box


def query_bounds(source, dpi=96, resources_dir=None, **options) -> list:
    """``[(id, (x, y, width, height))]`` for each rendered element with an id, in px of the
    document's intrinsic size (resvg's ``--query-all``). Size and rendering options are
    accepted and ignored, so the same options as for :func:`render_svg` can be passed."""
    for name in ("width", "height", "zoom", "background", "mode", "samples", "keep_aspect",
                 "size_limit", "export_id", "export_area_drawing"):
        options.pop(name, None)
    with diagnostics.as_python_warnings():
        loaded = _Loaded(source, dpi, resources_dir, options)
        return [(ident, (x0, y0, x1 - x0, y1 - y0))
                for ident, (x0, y0, x1, y1) in loaded.bounds_by_id().items()]


def render_svg_array(source: Source, width: float | None = None, height: float | None = None,
                     zoom: float | None = None, dpi: float = 96, background: Background = None,
                     mode: str = DEFAULT_MODE, samples: int | None = None,
                     resources_dir: str | os.PathLike | None = None, *,
                     keep_aspect: bool = False, size_limit: bool = True,
                     export_id: str | None = None, export_area_drawing: bool = False,
                     threads: int | None = None, progress=None,
                     pattern: str = "d3d", filter: str | None = None,
                     color_samples: int | None = None, **options) -> np.ndarray:
    """Render to an (H, W, 4) uint8 array of straight RGBA; see :func:`render_svg`.
    ``threads``: bands rendered at once (None: every available core; the image does not
    depend on it). ``progress(rows done, rows)``: called after each band is drawn."""
    from .raster.render import render_scene_rgba8

    with collector_paused():
        scene = load_svg(source, width=width, height=height, zoom=zoom, dpi=dpi,
                         background=background, resources_dir=resources_dir,
                         keep_aspect=keep_aspect, size_limit=size_limit, export_id=export_id,
                         cull=not export_area_drawing, **options)
        rgba = render_scene_rgba8(scene, mode=mode, threads=threads, progress=progress,
                                  samples=samples_for(samples, scene.width, scene.height),
                                  pattern=pattern, filter=filter, color_samples=color_samples)
        if export_area_drawing and export_id is None:
            rgba = crop_to_drawing(rgba, scene)
        del scene                           # (see collector_paused)
    return rgba


def render_svg_png(source: Source, width: float | None = None, height: float | None = None,
                   zoom: float | None = None, dpi: float = 96, background: Background = None,
                   mode: str = DEFAULT_MODE, samples: int | None = None,
                   resources_dir: str | os.PathLike | None = None, *,
                   keep_aspect: bool = False, size_limit: bool = True,
                   export_id: str | None = None, export_area_drawing: bool = False,
                   threads: int | None = None, progress=None,
                   pattern: str = "d3d", filter: str | None = None,
                   color_samples: int | None = None, **options) -> bytes:
    """Render to PNG bytes, the same as ``encode_png(render_svg_array(...))``, without holding
    the whole image: bands are encoded as they are rendered (``progress`` as there)."""
    if export_area_drawing and export_id is None:
        from .output.png import encode_png
        return encode_png(render_svg_array(
            source, width, height, zoom, dpi, background, mode, samples, resources_dir,
            keep_aspect=keep_aspect, size_limit=size_limit, export_area_drawing=True,
            threads=threads, progress=progress, pattern=pattern, filter=filter,
            color_samples=color_samples, **options))
    from .raster.render import render_scene_png

    with collector_paused():
        scene = load_svg(source, width=width, height=height, zoom=zoom, dpi=dpi,
                         background=background, resources_dir=resources_dir,
                         keep_aspect=keep_aspect, size_limit=size_limit, export_id=export_id,
                         **options)
        png = render_scene_png(scene, mode=mode, threads=threads, progress=progress,
                               samples=samples_for(samples, scene.width, scene.height),
                               pattern=pattern, filter=filter, color_samples=color_samples)
        del scene                           # (see collector_paused)
    return png


def crop_to_drawing(rgba: np.ndarray, scene: Scene) -> np.ndarray:
    """The pixels covering the drawing's bounds (resvg's ``--export-area-drawing``)."""
    box = nodes_bounds([scene.root])
    if box is None:
        return rgba
    h, w = rgba.shape[:2]
    x0, y0 = max(0, math.floor(box[0])), max(0, math.floor(box[1]))
    x1, y1 = min(w, math.ceil(box[2])), min(h, math.ceil(box[3]))
    if x1 <= x0 or y1 <= y0:
        return rgba
    return rgba[y0:y1, x0:x1]


def render_svg(source: Source, width: float | None = None, height: float | None = None,
               zoom: float | None = None, dpi: float = 96, background: Background = None,
               mode: str = DEFAULT_MODE, samples: int | None = None,
               resources_dir: str | os.PathLike | None = None, **options) -> Image.Image:
    """Render an SVG document to a PIL RGBA image.

    ``source``: a path, bytes, a str holding the XML, or a binary file object.
    Size: ``width``/``height`` in px (one keeps the aspect ratio; both stretch, or fit inside
    with ``keep_aspect=True``), ``zoom`` (ignored with a width or height), ``dpi`` for
    physical units; ``size_limit=False`` lifts the 32768 px / 2^28 pixel cap.
    ``background``: a CSS colour or an RGB(A) tuple. ``mode``/``samples``: coverage (see
    docs/modes.md; without ``samples``, 16 for outputs of at most 512 x 512 pixels, else 8).
    ``pattern`` (``d3d``, ``grid``, ``rgss``, ``rooks``, ``jittered``, ``poisson``,
    ``quincunx``, ``flipquad``, ``interleaved``) and ``filter`` (``box``, ``tent``, ``tent1``,
    ``gaussian``, ``mitchell``; None: the pattern's own): where a pixel's samples lie and how
    they are weighed (docs/modes.md). ``color_samples``: CSAA, at most that many colours
    stored per pixel over the ``samples`` coverage samples. ``resources_dir``: an extra folder
    images and CSS may come from.
    ``export_id``: only that element, cropped to its bounds; ``export_area_drawing=True``:
    the image cropped to the drawing's bounds.
    Document options: ``stylesheet`` (CSS text), ``languages`` (for systemLanguage, default
    ``("en",)``), ``font_size`` (default 12), ``shape_rendering``, ``text_rendering``,
    ``image_rendering`` (defaults for those properties).
    Fonts: ``use_font_file`` and ``use_fonts_dir`` (a path or a list), ``font_family``,
    ``serif_family``, ``sans_serif_family``, ``cursive_family``, ``fantasy_family``,
    ``monospace_family``, ``skip_system_fonts``.
    Problems that do not stop the render (a missing font or image, an unresolved reference)
    are reported through :mod:`warnings` as :class:`vecmsaa.RenderWarning`; errors raise
    :class:`vecmsaa.SvgError` (a ValueError) with a one-line message."""
    from PIL import Image

    arr = render_svg_array(source, width=width, height=height, zoom=zoom, dpi=dpi,
                           background=background, mode=mode, samples=samples,
                           resources_dir=resources_dir, **options)
    return Image.fromarray(np.ascontiguousarray(arr), "RGBA")


def render_sheet(scene, face, mode: str | None = None, samples: int | None = None,
                 pattern: str | None = None, filter: str | None = None) -> np.ndarray:
    """A font sheet's (H, W, 4) straight RGBA8 pixels. Without ``mode`` (nor ``pattern`` or
    ``filter``, which ask for samples): exact-area coverage of its outlines with their overlaps
    united where that is exact (:func:`vecmsaa.fonts.sheets.exact_area_sheet`), the MSAA default
    elsewhere; ``samples``, ``pattern``, ``filter`` as for ``vecmsaa render``."""
    from .fonts.sheets import exact_area_sheet
    from .raster.render import render_scene_rgba8

    sampled = mode is not None or pattern is not None or filter is not None
    exact = exact_area_sheet(scene, face) if not sampled else None
    return render_scene_rgba8(scene if exact is None else exact, pattern=pattern or "d3d",
                              filter=filter, **coverage(mode, samples, scene.width, scene.height,
                                                        analytic_exact=exact is not None))
