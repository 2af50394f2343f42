"""CairoSVG-style conversions (``svg2png`` and its siblings) and font previews (``render_text``).

``svg2png(bytestring=None, *, url=None, file_obj=None, write_to=None, ...)`` takes the same
arguments as CairoSVG's function of that name and returns the PNG bytes when ``write_to`` is
None; ``svg2webp``, ``svg2jpeg`` and ``svg2tiff`` do the same in those formats. Differences:
``url`` is a file path or ``file://`` URL (no network access, as everywhere in vecmsaa);
``unsafe``, ``parent_width`` and ``parent_height`` are accepted and have no effect (resources
always stay within the document's folder and ``resources_dir``; a percentage size on the root
resolves against its viewBox, as in resvg).
"""
from __future__ import annotations

import os
import urllib.parse
from typing import BinaryIO, Union

import numpy as np

from .raster.modes import DEFAULT_MODE
from .svg import SvgError

PathOrFile = Union[str, os.PathLike, BinaryIO]


def _source(bytestring, url, file_obj):
    given = [v is not None for v in (bytestring, url, file_obj)]
    if sum(given) != 1:
        raise TypeError("give exactly one of bytestring, url and file_obj")
    if bytestring is not None:
        return bytestring.encode("utf-8") if isinstance(bytestring, str) else bytes(bytestring)
    if file_obj is not None:
        return file_obj
    parsed = urllib.parse.urlsplit(os.fspath(url))
    if parsed.scheme.lower() == "file":
        return urllib.parse.unquote(parsed.path)
    if len(parsed.scheme) > 1:
        raise SvgError(f"only local files can be read, not {parsed.scheme}: URLs")
    return os.fspath(url)


def _write(data: bytes, write_to):
    if write_to is None:
        return data
    if hasattr(write_to, "write"):
        write_to.write(data)
        return None
    from .files import write_bytes_atomic
    write_bytes_atomic(data, write_to)
    return None


def svg2image(fmt: str, bytestring: bytes | str | None = None, *, url=None, file_obj=None,
              write_to: PathOrFile | None = None, dpi: float = 96, parent_width=None,
              parent_height=None, scale: float = 1, unsafe: bool = False,
              background_color: str | None = None, negate_colors: bool = False,
              invert_images: bool = False, output_width: float | None = None,
              output_height: float | None = None, mode: str = DEFAULT_MODE,
              samples: int | None = None, **options) -> bytes | None:
    """Render an SVG to the bytes of ``fmt`` (png, webp, jpeg, tiff); see the module doc.
    ``options`` are those of :func:`vecmsaa.render_svg` (fonts, languages, stylesheet...)."""
    from .api import render_svg_array
    from .output.formats import encode

    del unsafe, parent_width, parent_height   # accepted for CairoSVG's callers; see above
    source = _source(bytestring, url, file_obj)
    width, height, zoom = output_width, output_height, None
    if width is None and height is None:
        zoom = scale if scale != 1 else None
    elif scale != 1:
        width = width * scale if width is not None else None
        height = height * scale if height is not None else None
    negate = negate_colors or invert_images
    rgba = render_svg_array(source, width=width, height=height, zoom=zoom, dpi=dpi,
                            background=None if negate else background_color,
                            mode=mode, samples=samples, **options)
    if negate:
        # CairoSVG negates the drawing's colours (images too with invert_images), not the
        # background: 255 - c on the straight colours, alpha kept, then the background
        rgba = rgba.copy()
        rgba[..., :3] = 255 - rgba[..., :3]
        if background_color is not None:
            rgba = _over_background(rgba, background_color)
    return _write(encode(rgba, fmt), write_to)


def _over_background(rgba: np.ndarray, color: str) -> np.ndarray:
    """Straight RGBA over a CSS colour (after negate_colors, as CairoSVG paints it)."""
    from .api import _background

    r, g, b, a = _background(color)
    bg = np.array([r * a, g * a, b * a, a], dtype=np.float64) * 255
    src = rgba.astype(np.float64)
    alpha = src[..., 3:4] / 255
    premul = np.concatenate([src[..., :3] * alpha, src[..., 3:4]], axis=-1)
    out = premul + bg * (1 - alpha)
    out_a = out[..., 3:4]
    rgb = np.where(out_a > 0, out[..., :3] * 255 / np.maximum(out_a, 1e-9), 0)
    return np.clip(np.concatenate([rgb, out_a], axis=-1) + 0.5, 0, 255).astype(np.uint8)


def svg2png(bytestring=None, **kwargs) -> bytes | None:
    """CairoSVG's ``svg2png``: PNG bytes, or None after writing them to ``write_to``."""
    return svg2image("png", bytestring, **kwargs)


def svg2webp(bytestring=None, **kwargs) -> bytes | None:
    """As :func:`svg2png`, lossless WebP."""
    return svg2image("webp", bytestring, **kwargs)


def svg2jpeg(bytestring=None, **kwargs) -> bytes | None:
    """As :func:`svg2png`, JPEG (transparency flattened onto white)."""
    return svg2image("jpeg", bytestring, **kwargs)


def svg2tiff(bytestring=None, **kwargs) -> bytes | None:
    """As :func:`svg2png`, TIFF."""
    return svg2image("tiff", bytestring, **kwargs)


def render_text(font: str | os.PathLike, text: str, size: float = 48.0, *,
                foreground: str = "black", background: str = "white",
                margin: float | None = None, face_index: int = 0,
                variations: str | dict | None = None, features: str | dict | None = None,
                language: str | None = None, script: str | None = None,
                direction: str | None = None, mode: str | None = None,
                samples: int | None = None):
    """One line of ``text`` in ``font`` at ``size`` px per em, as a PIL RGBA image tight
    around the line box plus ``margin`` (what ``vecmsaa font FONT --text`` draws).

    ``variations`` (``"wght=700"`` or a dict) and ``features`` (``"liga=0,ss01"`` or a dict)
    as in :mod:`vecmsaa.fonts`; ``direction`` one of ltr, rtl, ttb, btt (default: from the
    text). ``mode``/``samples`` as for ``vecmsaa font`` (default: exact-area coverage of the
    outline with its overlaps united, approx for colour fonts; docs/fonts.md). Colours are CSS colours; ``background="transparent"`` is allowed. Raises
    :class:`vecmsaa.fonts.FontError` for an unusable font, ValueError for a bad option."""
    from PIL import Image

    from .fonts import load_face, parse_features, parse_variations
    from .fonts.sheets import line_scene
    from .svg.color import parse_color

    def color(value, what):
        c = parse_color(value)
        if not isinstance(c, tuple):
            raise ValueError(f"bad {what} colour {value!r}")
        return tuple(float(v) for v in c)

    if not 0 < size <= 2000:
        raise ValueError("size must be in (0, 2000]")
    location = variations if isinstance(variations, dict) else parse_variations(variations)
    feats = features if isinstance(features, dict) else parse_features(features)
    face = load_face(font, face_index)
    scene = line_scene(face, text, size, margin=margin, location=location, features=feats,
                       direction=direction, script=script, language=language,
                       foreground=color(foreground, "foreground"),
                       background=color(background, "background"))
    from .api import render_sheet

    rgba = render_sheet(scene, face, mode, samples)
    return Image.fromarray(np.ascontiguousarray(rgba), "RGBA")

