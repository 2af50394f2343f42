"""clipPath and mask → the ``clip`` / ``mask`` of a scene Group.

References to missing elements and recursive references are ignored (as in resvg and
browsers). A clip-path referencing an element of another kind clips nothing (CSS Masking 1
§5.1: "no clipping is applied"; Chromium too; usvg's conversion fails and resvg does not draw
the element); a mask referencing one is a transparent black layer (§7.1), so the element is
not drawn. With objectBoundingBox units an element without a usable bounding box is not drawn
at all.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..diagnostics import warn
from ..scene.transform import compose
from ..scene.path import rect_path
from ..scene.color import linear_rgb_image, srgb_to_linear
from ..scene.nodes import (Fill, Group, ImagePaint, LinearGradient, Mask, PatternPaint,
                           RadialGradient, Solid)
from .units import box_coord

CLIP_CHILDREN = {"rect", "circle", "ellipse", "line", "polyline", "polygon", "path", "text",
                 "use"}


def _target(builder, value, tag):
    """The referenced ``tag`` element; None for no usable reference, False for an element of
    another kind (the referencing element is not drawn)."""
    from .builder import parse_url

    url = parse_url(value or "")
    if url is None or url[1]:
        return None                     # not a url, or more after it (url(#c);): invalid
    el = builder.doc.lookup(url[0]) if url[0].startswith("#") else None
    if el is None:
        warn(f"unresolved url({url[0]}) in {tag.replace('P', '-p')}")
    if el is None:
        return None
    if el.tag != tag:
        return False
    if any(r is el for r in builder.ref_stack):
        return None   # recursion: the inner reference is dropped
    return el


def _usable(bbox):
    return bbox is not None and bbox[2] - bbox[0] > 0 and bbox[3] - bbox[1] > 0


def clip_path(builder, value, ctx, bbox_fn):
    """clip-path value → clip Group, None (no clipping), or False (the element is not drawn)."""
    from .builder import bbox_matrix

    el = _target(builder, value, "clipPath")
    if not el:
        return None                     # nothing, or another kind of element: no clipping
    style = builder.doc.document_style(el)
    m = builder.element_transform(el, style, ctx)
    if m is None:
        return False
    transform = compose(ctx.transform, m)
    # units match their keyword exactly, as in paint.gradient
    if el.get("clipPathUnits") == "objectBoundingBox":
        bbox = bbox_fn()
        if not _usable(bbox):
            return False
        transform = compose(transform, bbox_matrix(bbox))
    inner = replace(ctx, transform=transform, clip=True, geometry=False)
    builder.enter_reference(el)
    try:
        nodes = []
        for child in el.children:
            if child.tag not in CLIP_CHILDREN:
                continue
            nodes.extend(builder.element(child, inner, style))
        group = Group(children=nodes)
        own = el.specified.get("clip-path")
        if own and own.strip() != "none":
            outer = clip_path(builder, own, ctx, bbox_fn)
            if outer is False:
                return False
            if outer is not None:
                group.clip = outer
    finally:
        builder.ref_stack.pop()
    return group


def masks(builder, value, ctx, bbox_fn, mode=None):
    """mask value → list of Mask (the element's, then its mask's mask...), [] for none, or
    False when the element is not drawn. ``mode``: the masked element's ``mask-mode``."""
    from .builder import bbox_matrix

    el = _target(builder, value, "mask")
    if not el:
        return [] if el is None else False
    style = builder.doc.document_style(el)
    units_obb = el.get("maskUnits") != "userSpaceOnUse"
    content_obb = el.get("maskContentUnits") == "objectBoundingBox"
    bbox = bbox_fn() if (units_obb or content_obb) else None
    if (units_obb or content_obb) and not _usable(bbox):
        return False
    if units_obb:
        def frac(name, axis, default):
            return box_coord(builder, el.get(name), axis, True, style, ctx.viewport, default)
        bx, by, bw, bh = bbox[0], bbox[1], bbox[2] - bbox[0], bbox[3] - bbox[1]
        x = bx + frac("x", "x", "-10%") * bw
        y = by + frac("y", "y", "-10%") * bh
        w = frac("width", "x", "120%") * bw
        h = frac("height", "y", "120%") * bh
    else:
        get = builder.length_getter(el, style, ctx)
        x, y = get("x", "x", None), get("y", "y", None)
        w, h = get("width", "x", None), get("height", "y", None)
        vw, vh = ctx.viewport
        x = -0.1 * vw if x is None else x
        y = -0.1 * vh if y is None else y
        w = 1.2 * vw if w is None else w
        h = 1.2 * vh if h is None else h
    if w <= 0 or h <= 0:
        return False
    transform = ctx.transform
    if content_obb:
        transform = compose(transform, bbox_matrix(bbox))
    inner = replace(ctx, transform=transform, clip=False, geometry=False)
    builder.enter_reference(el)
    try:
        nodes = builder.children(el, inner, style)
        region = Group(children=[Fill(rect_path(x, y, w, h).transformed(ctx.transform))])
        content = Group(children=nodes, clip=region)
        # CSS Masking 1: the masked element's mask-mode (its first layer's) decides, and
        # match-source (the initial value) leaves it to the mask element's mask-type
        # (both keywords come lower-cased from the cascade: document.KEYWORD_PROPERTIES)
        kind = (mode or "").split(",")[0].strip()
        if kind not in ("alpha", "luminance"):
            kind = "alpha" if (style.get("mask-type") or "").strip() == "alpha" else "luminance"
        if (kind == "luminance"
                and (style.get("color-interpolation") or "").strip().lower() == "linearrgb"):
            to_linear_rgb(content)
        out = [Mask(content=content, kind=kind)]
        own = el.specified.get("mask")
        if own and own.strip() != "none":
            more = masks(builder, own, ctx, bbox_fn, el.specified.get("mask-mode"))
            if more is False:
                return False
            out.extend(more)
    finally:
        builder.ref_stack.pop()
    return out


def to_linear_rgb(group):
    """Convert the paints of mask content to linear RGB in place. SVG 1.1 §14.4 takes the
    luminance of linearRGB values when the mask's color-interpolation is linearRGB, and the
    property also sets the space its content is composited in (children inherit it): so
    each paint's colours are converted before compositing, as Chromium 150 draws it (two
    translucent shapes mix as linear values). A gradient interpolates in sRGB (vecmsaa
    applies no color-interpolation to gradients) and its colours are converted after."""
    stack = [group]
    while stack:
        node = stack.pop()
        if isinstance(node, Group):
            stack.extend(node.children)
            continue
        paint = node.paint
        if isinstance(paint, Solid):
            r, g, b, a = paint.color
            node.paint = Solid((*(float(v) for v in srgb_to_linear((r, g, b))), a))
        elif isinstance(paint, (LinearGradient, RadialGradient)):
            node.paint = replace(paint, stops=_linear_stops(paint.stops))
        elif isinstance(paint, ImagePaint):
            node.paint = replace(paint, rgba=linear_rgb_image(paint.rgba))
        elif isinstance(paint, PatternPaint):
            node.paint = replace(paint, linear_rgb=True)    # the raster converts the tile


#: pieces each stop interval is cut into: the chords of the sRGB → linear curve (second
#: derivative at most 3.1) are then within 3.1 / 8 / 32² ≈ 0.1/255 of it
LINEAR_STOP_PIECES = 32


def _linear_stops(stops):
    """Stops whose straight interpolation follows the gradient's own (straight, in sRGB)
    with the colours converted to linearRGB afterwards: each interval cut into
    LINEAR_STOP_PIECES (converting the stops alone would interpolate in linearRGB)."""
    offsets = np.maximum.accumulate(np.clip(stops[:, 0], 0.0, 1.0))
    rows = [stops[:1].copy()]
    rows[0][0, 0] = offsets[0]
    for i in range(1, len(stops)):
        n = LINEAR_STOP_PIECES if offsets[i] > offsets[i - 1] else 1   # a hard stop stays
        t = (np.arange(1, n + 1) / n)[:, None]
        piece = stops[i - 1] + (stops[i] - stops[i - 1]) * t
        piece[:, 0] = offsets[i - 1] + (offsets[i] - offsets[i - 1]) * t[:, 0]
        rows.append(piece)
    out = np.concatenate(rows)
    out[:, 1:4] = srgb_to_linear(out[:, 1:4])
    return out
