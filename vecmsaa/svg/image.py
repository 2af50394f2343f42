"""``<image>``: raster images (PNG, JPEG, GIF, WebP via Pillow) and nested SVG documents."""
from __future__ import annotations

import io
import math
from dataclasses import replace

import numpy as np

from ..diagnostics import warn
from ..scene.transform import compose, invert, translate
from ..scene.bounds import path_bounds
from ..scene.path import rect_path
from ..scene.nodes import Fill, FillRuns, Group, ImagePaint
from .units import parse_aspect, viewbox_transform

#: Pixels of one raster image, and of all distinct raster images of a document (each decoded
#: once, however often it is referenced, SVG images inside it included); an image over either
#: limit is not drawn.
MAX_IMAGE_PIXELS = 1 << 26
MAX_DECODED_PIXELS = 1 << 28
#: Texels (16 bytes each: float32 RGBA) of all images of a document, SVG images inside it
#: included, one set per image and reduction (an image drawn at several scales has several);
#: an image past it is not drawn. One image of MAX_IMAGE_PIXELS drawn unreduced fits.
MAX_TEXEL_PIXELS = 1 << 26
#: Pixels converted to float32 at a time (image_texels, by whole rows): whole-image
#: temporaries were one and a half times the texels themselves.
_TEXEL_BAND = 1 << 16


def sniff(data: bytes, mime=None):
    """'raster', 'svg' or None from the first bytes. The MIME type is only a hint, but an XML
    type is taken as given (MIME Sniffing's rules for images: `image/svg+xml` over PNG bytes
    is an SVG document that does not parse, not a PNG) and SVG is read only under no type,
    `text/plain` or an SVG one."""
    if mime and (mime.endswith("+xml") or mime in ("text/xml", "application/xml")):
        return "svg"
    head = data[:16]
    if (head.startswith(b"\x89PNG") or head.startswith(b"\xff\xd8") or head.startswith(b"GIF8")
            or (head.startswith(b"RIFF") and data[8:12] == b"WEBP")):
        return "raster"
    if mime and mime != "text/plain" and "svg" not in mime:
        # MIME Sniffing matches image types only: SVG bytes under another given type
        # (`image/png`, `application/octet-stream`) are that type, and no image. Without a type
        # (a data: URL's default is text/plain) the document is read, as in resvg.
        return None
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


def decode_raster(data: bytes, resources=None):
    """The first frame of an image file as a Pillow image in its own mode (1-bit, grey and
    palette images stay one byte per pixel), decoded once per document (``resources`` holds
    the cache and the MAX_DECODED_PIXELS budget). Raises ValueError when over a limit."""
    from PIL import Image

    store = resources.images if resources is not None else None
    cache = store.decoded if store is not None else {}
    im = cache.get(data)
    if im is None:
        im = Image.open(io.BytesIO(data))
        pixels = im.width * im.height
        if pixels > MAX_IMAGE_PIXELS:
            raise ImageLimit(f"an image of {im.width}x{im.height} pixels was not drawn (limit "
                             f"{MAX_IMAGE_PIXELS} pixels)")
        if store is not None:
            if store.decoded_pixels + pixels > MAX_DECODED_PIXELS:
                raise ImageLimit(f"an image was not drawn: the document's images decode to "
                                 f"more than {MAX_DECODED_PIXELS} pixels")
            store.decoded_pixels += pixels
        im.seek(0)
        im.load()
        if im.mode in ("I", "I;16", "I;16B", "I;16L"):
            # 16-bit grey (PNG): Pillow's conversions clamp the samples to 0-255 where 65535
            # is white, so scale them here (to 8 bits, as resvg decodes every image)
            grey = np.asarray(im, dtype=np.float64)
            im = Image.fromarray(np.round(np.clip(grey, 0, 65535) / 257.0).astype(np.uint8), "L")
        cache[data] = im
    return im


class ImageLimit(ValueError):
    """An image over one of this module's limits (not drawn, with a warning)."""


def image_texels(im, fx: int = 1, fy: int = 1) -> np.ndarray:
    """A Pillow image → (H + 2, W + 2, 4) float32 premultiplied RGBA with one texel of edge
    replication (filtering at the border then repeats the edge instead of fading into
    transparency), box-reduced by (fx, fy) first when it is drawn that much smaller."""
    if fx > 1 or fy > 1:
        if im.mode in ("1", "L"):
            im = im.convert("L")
        elif im.mode != "RGB":
            im = im.convert("RGBA").convert("RGBa")    # average premultiplied colours
        im = im.reduce((fx, fy))
    h, w = im.height, im.width
    out = np.empty((h + 2, w + 2, 4), np.float32)
    inner = out[1:-1, 1:-1]
    # by bands of rows (the same per-pixel arithmetic): whole-image uint8 and float32
    # temporaries held two to three times the texels at once
    step = max(1, _TEXEL_BAND // max(w, 1))
    for r0 in range(0, h, step):
        r1 = min(h, r0 + step)
        band = im.crop((0, r0, w, r1))
        rows = inner[r0:r1]
        if im.mode in ("L", "RGB"):
            rows[..., :3] = np.asarray(band, dtype=np.float32).reshape(r1 - r0, w, -1) / 255.0
            rows[..., 3] = 1.0
        elif im.mode == "RGBa":
            rows[...] = np.asarray(band, dtype=np.float32) / 255.0
        else:
            rows[...] = np.asarray(band.convert("RGBA"), dtype=np.float32) / 255.0
            rows[..., :3] *= rows[..., 3:4]
    out[0, 1:-1], out[-1, 1:-1] = inner[0], inner[-1]
    out[:, 0], out[:, -1] = out[:, 1], out[:, -2]
    return out


def _reduction(to_device, iw, ih):
    """Integer box-reduction factors along the image's x and y that keep at least two texels
    per device pixel (bilinear sampling would skip the others); 1 below four texels."""
    a, b, c, d = to_device[:4]
    fx = int(1.0 / (2.0 * max(math.hypot(a, b), 1e-300)))
    fy = int(1.0 / (2.0 * max(math.hypot(c, d), 1e-300)))
    fx = min(fx, iw) if fx >= 2 else 1
    fy = min(fy, ih) if fy >= 2 else 1
    return fx, fy


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
            im = decode_raster(data, builder.resources)
        except ImageLimit as exc:
            warn(str(exc))
            return []
        except Exception:   # Pillow raises many kinds of errors on corrupt data
            return []
        iw, ih = im.width, im.height
        sub = None
    elif kind == "svg":
        if builder.options.image_nesting >= 3:
            return []
        href = el.get("href") or ""
        sub = _load_svg(builder, data, href.partition("#")[2] if "#" in href else None)
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
        to_device = compose(ctx.transform, image_to_user)
        # a texel per device pixel, only moved: the nearest texel (tiny-skia's pattern shader
        # drops its filter for a translation, as resvg draws it; the filter is the UA's choice)
        smooth = (rendering not in ("optimizeSpeed", "pixelated", "crisp-edges")
                  and tuple(np.float32(to_device[:4])) != (1.0, 0.0, 0.0, 1.0))
        try:
            to_paint = invert(to_device)
        except ValueError:
            return []
        if aspect[1] and aspect[0] != "none":
            outline = rect_path(x, y, w, h)          # slice: the viewport clips the image
        else:
            outline = rect_path(0, 0, iw, ih).transformed(image_to_user)
        fx, fy = _reduction(to_device, iw, ih)
        key = (data, fx, fy)
        store = builder.resources.images
        texels = store.texels.get(key)
        if texels is None:
            pixels = -(-iw // fx) * -(-ih // fy)      # Pillow's reduce rounds up
            if store.texel_pixels + pixels > MAX_TEXEL_PIXELS:
                warn(f"an image was not drawn: the document's images need more than "
                     f"{MAX_TEXEL_PIXELS} texels at the sizes they are drawn")
                return []
            try:
                texels = store.texels[key] = image_texels(im, fx, fy)
            except Exception:   # Pillow raises many kinds of errors on corrupt data
                return []
            store.texel_pixels += pixels
        # texels are reduced by (fx, fy) and padded by one (see image_texels); the outline
        # does the clipping
        to_paint = compose(compose(translate(1, 1), (1.0 / fx, 0, 0, 1.0 / fy, 0, 0)),
                           to_paint)
        return [Fill(outline.transformed(ctx.transform),
                     ImagePaint(texels, to_paint, False, smooth))]
    # the nested document's elements and characters count against this document's limits
    # (MAX_NODES, MAX_TEXT_CHARS): counted apart, an image used a thousand times, of a
    # document using an image of another a thousand times, built a billion elements
    sub.builder.nodes_made, sub.builder.text_chars = builder.nodes_made, builder.text_chars
    try:
        # the document as drawn on its own, its root's transform included
        nodes = sub.build(compose(ctx.transform, image_to_user), builder.root_scale)
    finally:
        builder.nodes_made = max(builder.nodes_made, sub.builder.nodes_made)
        builder.text_chars = max(builder.text_chars, sub.builder.text_chars)
    if not nodes:
        return []
    if _within(nodes, ctx.transform, (x, y, x + w, y + h)):
        # the viewport clips nothing; as a clip its edge, where the drawing's own edge often
        # lies (a background filling the viewBox), would multiply the two coverages there
        return nodes
    clip = Group(children=[Fill(rect_path(x, y, w, h).transformed(ctx.transform))])
    return [Group(children=nodes, clip=clip)]


def _within(nodes, to_device, box) -> bool:
    """Whether everything ``nodes`` draw lies inside ``box`` (x0, y0, x1, y1) of the user
    space ``to_device`` maps to device pixels (filters may reach outside: never)."""
    try:
        to_user = invert(to_device)
    except ValueError:
        return False
    x0, y0, x1, y1 = box
    eps = 1e-7 * max(1.0, abs(x0), abs(y0), abs(x1), abs(y1))
    stack = list(nodes)
    while stack:
        node = stack.pop()
        if isinstance(node, Fill):
            b = path_bounds(node.path, to_user)
            if b is not None and not (b[0] >= x0 - eps and b[1] >= y0 - eps
                                      and b[2] <= x1 + eps and b[3] <= y1 + eps):
                return False
        elif isinstance(node, FillRuns):
            stack.extend(node.fills())
        elif node.filters:
            return False
        else:
            stack.extend(node.children)
    return True


def _load_svg(builder, data, fragment=None):
    """A nested SVG image as a SizedDocument, or None when it cannot be read; ``fragment``,
    the URL's fragment, may name a <view> of it. As in resvg, it may embed data: URLs but
    load no files: that also rules out documents that show themselves."""
    from . import SvgError
    from .resources import Resources
    from .sizing import open_svg

    options = replace(builder.options, image_nesting=builder.options.image_nesting + 1)
    store = builder.resources.images
    key = (data, fragment, options.image_nesting)
    if key in store.documents:      # parsed once however often it is drawn
        return store.documents[key]
    try:
        # no folders; the document's images (and their budgets) are shared
        sub = open_svg(data, None, Resources(images=store), options, whole_pixels=False,
                       view=fragment)
    except SvgError:
        sub = None
    store.documents[key] = sub
    return sub
