"""``<image>``: raster images (PNG, JPEG, GIF, WebP via Pillow) and nested SVG documents."""
from __future__ import annotations

import io
from dataclasses import replace

import numpy as np

from ..scene.transform import compose, invert, translate
from ..scene.path import rect_path
from ..scene.nodes import Fill, Group, ImagePaint
from .units import parse_aspect, viewbox_transform

MAX_IMAGE_PIXELS = 1 << 26


def sniff(data: bytes, mime=None):
    """'raster', 'svg' or None from the first bytes (the MIME type is only a hint)."""
    head = data[:16]
    if (head.startswith(b"\x89PNG") or head.startswith(b"\xff\xd8") or head.startswith(b"GIF8")
            or (head.startswith(b"RIFF") and data[8:12] == b"WEBP")):
        return "raster"
    if head.startswith(b"\x1f\x8b"):
        return "svg"
    text = data[:2048].lstrip()
    if text.startswith(b"\xef\xbb\xbf"):
        text = text[3:]
    if text.startswith(b"<"):
        return "svg"
    if mime and "svg" in mime:
        return "svg"
    return None


def decode_raster(data: bytes) -> np.ndarray:
    """Image bytes → (H, W, 4) float32 premultiplied RGBA."""
    from PIL import Image

    with Image.open(io.BytesIO(data)) as im:
        if im.width * im.height > MAX_IMAGE_PIXELS:
            raise ValueError("image too large")
        im.seek(0)
        rgba = np.asarray(im.convert("RGBA"), dtype=np.float32) / 255.0
    rgba[..., :3] *= rgba[..., 3:4]
    return rgba


def image_nodes(builder, el, ctx, style):
    if style.get("visibility").strip() in ("hidden", "collapse") and not ctx.geometry:
        return []
    got = builder.resources.fetch(el.get("href") or "")
    if got is None:
        return []
    data, mime, _ = got
    kind = sniff(data, mime)
    get = builder.length_getter(el, style, ctx)
    x, y = get("x", "x", 0.0), get("y", "y", 0.0)
    w, h = get("width", "x", None), get("height", "y", None)
    aspect = parse_aspect(el.get("preserveAspectRatio"))
    if kind == "raster":
        try:
            rgba = decode_raster(data)
        except Exception:   # Pillow raises many kinds of errors on corrupt data
            return []
        iw, ih = rgba.shape[1], rgba.shape[0]
        sub = None
    elif kind == "svg":
        if builder.options.image_nesting >= 3:
            return []
        sub = _load_svg(builder, data)
        if sub is None:
            return []
        iw, ih = sub.width, sub.height
    else:
        return []
    if w is None and h is None:
        w, h = iw, ih
    elif w is None:
        w = h * iw / ih if ih else 0
    elif h is None:
        h = w * ih / iw if iw else 0
    if w <= 0 or h <= 0 or iw <= 0 or ih <= 0:
        return []
    view = viewbox_transform((0.0, 0.0, iw, ih), aspect, w, h)
    image_to_user = compose(translate(x, y), view)
    if ctx.geometry:
        return [Fill(rect_path(x, y, w, h).transformed(ctx.transform))]
    if kind == "raster":
        rendering = style.get("image-rendering").strip()
        smooth = rendering not in ("optimizeSpeed", "pixelated", "crisp-edges")
        to_device = compose(ctx.transform, image_to_user)
        try:
            to_paint = invert(to_device)
        except ValueError:
            return []
        if aspect[1] and aspect[0] != "none":
            outline = rect_path(x, y, w, h)          # slice: the viewport clips the image
        else:
            outline = rect_path(0, 0, iw, ih).transformed(image_to_user)
        # One texel of edge replication: filtering at the image border then repeats the edge
        # (clamp) instead of fading into transparency; the outline does the clipping.
        padded = np.pad(rgba, ((1, 1), (1, 1), (0, 0)), mode="edge")
        to_paint = compose(translate(1, 1), to_paint)
        return [Fill(outline.transformed(ctx.transform),
                     ImagePaint(padded, to_paint, False, smooth))]
    sub_ctx = replace(ctx, transform=compose(ctx.transform, compose(image_to_user,
                                                                     sub.root_matrix)),
                      viewport=sub.viewport, use_stack=(), context_fill=None, context_stroke=None)
    nodes = sub.builder.build_root(sub_ctx.transform, sub_ctx.viewport, builder.root_scale)
    if not nodes:
        return []
    clip = Group(children=[Fill(rect_path(x, y, w, h).transformed(ctx.transform))])
    return [Group(children=nodes, clip=clip)]


def _load_svg(builder, data):
    """A nested SVG image as a SizedDocument, or None when it cannot be read. As in resvg, it
    may embed data: URLs but load no files: that also rules out documents that show
    themselves."""
    from . import SvgError
    from .resources import Resources
    from .sizing import open_svg

    options = replace(builder.options, image_nesting=builder.options.image_nesting + 1)
    try:
        return open_svg(data, None, Resources(), options)
    except SvgError:
        return None
