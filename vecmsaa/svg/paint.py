"""Paint servers: linearGradient, radialGradient and pattern → scene paints.

Gradients become :class:`~vecmsaa.scene.nodes.LinearGradient` / ``RadialGradient`` with the matrix
from device pixels into gradient space; a pattern becomes a
:class:`~vecmsaa.scene.nodes.PatternPaint`: its content laid out in a tile of whole device pixels,
which the raster renders and repeats.
"""
from __future__ import annotations

import itertools
import math
import re
from dataclasses import replace

import numpy as np

from ..scene.transform import IDENTITY, apply, compose, invert, translate
from ..scene.nodes import Fill, Group, LinearGradient, PatternPaint, RadialGradient, Solid
from ..scene.path import rect_path
from .color import parse_svg_color as parse_color
from .document import href_chain, inherited_attr
from .units import (NUMBER_RE, box_coord, concat_f32, f32_chain, f32_matrix, row_scale,
                    row_scale_f32, parse_aspect, parse_opacity,
                    parse_transform, parse_viewbox, split_length, viewbox_transform,
                    zero_size_viewbox)

GRADIENT_TAGS = ("linearGradient", "radialGradient")
#: what a paint server with a singular transform (element, gradientTransform, patternTransform)
#: paints: nothing, and not its fallback either: it is a valid paint server (SVG 2 uses the
#: fallback for references that are not one), and CSS Transforms draws nothing through a
#: non-invertible matrix; resvg does the same
NO_PAINT = "no paint"
_OFFSET = re.compile(rf"({NUMBER_RE})(%?)")
MAX_TILE_PIXELS = 2048 * 2048
MAX_TILE_SIDE = 8192


def gradient_stops(builder, chain):
    """(K, 5) array of (offset, r, g, b, a) from the first element in the chain with stops."""
    for el in chain:
        stops = [c for c in el.children if c.tag == "stop"]
        if stops:
            break
    else:
        return np.zeros((0, 5))
    out = []
    last = 0.0
    for stop in stops:
        style = builder.doc.document_style(stop)
        # <number> | <percentage>; anything else ("50 %", "0.2px") is invalid: offset 0
        m = _OFFSET.fullmatch((stop.get("offset") or "0").strip())
        off = float(m.group(1)) / (100 if m.group(2) else 1) if m else 0.0
        off = min(1.0, max(0.0, off)) if math.isfinite(off) else 0.0
        off = max(off, last)
        last = off
        color = parse_color(style.get("stop-color") or "black")
        if color is None:
            color = (0.0, 0.0, 0.0, 1.0)
        elif color == "currentColor":
            color = builder.current_color(style)
        alpha = color[3] * parse_opacity(style.get("stop-opacity"))
        out.append([off, color[0], color[1], color[2], alpha])
    return np.asarray(separate_equal_offsets(out), dtype=np.float64)


def separate_equal_offsets(stops, eps=1e-6):
    """Of three or more stops at one offset keep the first and the last, and move the first
    of an equal pair slightly left (right at 0), so that the colour before a hard stop is the
    earlier stop's (what resvg and browsers show, e.g. in the pad area)."""
    kept = []
    for i, s in enumerate(stops):
        if (0 < i < len(stops) - 1 and stops[i - 1][0] == s[0] == stops[i + 1][0]):
            continue
        kept.append(list(s))
    for i in range(1, len(kept)):
        if abs(kept[i][0] - kept[i - 1][0]) < eps:
            if kept[i - 1][0] <= eps:
                kept[i][0] = kept[i - 1][0] + eps
            else:
                kept[i - 1][0] = kept[i][0] - eps
    return kept


#: tiny-skia's tolerance for equal gradient circles (centres and radii, user units)
DEGENERATE = 1 / (1 << 15)
#: tiny-skia's "nearly zero" for a transform's scale (f32::EPSILON)
ZERO_SCALE = 2.0 ** -23


def _units_transform(builder, chain, attr, el_style, ctx):
    """gradientTransform/patternTransform (or the CSS transform property, _own_transform) with
    transform-origin. The attribute comes through
    href like the others (SVG 2 "Using paint servers as templates": both are among the
    attributes copied from the template; resvg reads only the element's own), and a present
    one stops that even when empty or malformed. A malformed list is ignored;
    so is, as in resvg (usvg reads such a value as the identity), a matrix with a zero scale
    along an axis (a row norm under f32's epsilon: scale(0), scale(1 0)). Other singular
    matrices (matrix(1 2 2 4 0 0)) are None: the paint then paints nothing (NO_PAINT). That is
    decided on this matrix, not on its product with the element's: under a skew or rotation
    the product's determinant is rounding noise, not zero, and would paint a smear."""
    text, attribute = next((t for t in (_own_transform(e, attr) for e in chain) if t),
                           (None, True))
    m = parse_transform(text, attribute=attribute) if text and text != "none" else IDENTITY
    if m is None or min(row_scale(m)) <= ZERO_SCALE:
        m = IDENTITY
    if singular_linear(*m[:4]):
        return None
    origin = chain[0].get("transform-origin")
    if origin and m != IDENTITY:
        # resolved as anywhere else (percentages of the viewport, CSS transform-box'
        # view-box), also in objectBoundingBox units, where the point is then one in the
        # unit box (as in resvg: "center" is (100, 100) boxes in a 200-unit viewport)
        ox, oy = builder.transform_origin(origin, el_style, ctx.viewport)
        m = compose(compose(translate(ox, oy), m), translate(-ox, -oy))
    return m


def singular_linear(a, b, c, d, rtol=1e-12):
    """Whether the linear part [[a, c], [b, d]] is singular: its determinant ad - bc is zero
    up to the rounding of its two products (within ``rtol`` of |ad| + |bc|), so a matrix whose
    rows are parallel in exact arithmetic (matrix(1 2 2 4), matrix(0.5 0.866 1 1.732)) is,
    and one far from singular is not however its entries' sizes differ: skewX(90) is
    [[1, 1.6e16], [0, 1]] with determinant 1 (its entries, scaled by the largest, gave a
    determinant of 4e-33, which the test before read as singular; Chromium and resvg paint
    such a gradient, and SVG makes a paint server's transform invalid only when it has no
    inverse). Scaled by the largest entry first: 1e200 squared is inf in floats."""
    big = max(abs(a), abs(b), abs(c), abs(d))
    if not big > 0:
        return True
    ad, bc = a / big * (d / big), b / big * (c / big)
    return abs(ad - bc) <= rtol * (abs(ad) + abs(bc))


def _own_transform(el, attr):
    """(text, whether it is the attribute's) of the element's transform: the CSS `transform`
    property where a style attribute or sheet sets it, else the ``attr`` attribute; None when
    neither is given. SVG 2 makes gradientTransform and patternTransform those elements'
    presentation attributes for `transform`, so CSS overrides them (Chromium 150; resvg
    0.48.1 reads the attribute only); a `transform` attribute is none there (all three ignore
    it), and a CSS value equal to it is taken for it."""
    css = el.specified.get("transform")
    if css is not None and css != el.attrs.get("transform"):
        return css, False
    return (el.attrs[attr], True) if attr in el.attrs else None


def paint_server(builder, el, ctx, bbox, user_style, sampled_in_box=True):
    """A paint for a paint-server element, Solid for degenerate gradients, None where the
    fallback applies (no stops, an empty box), NO_PAINT where nothing is painted.
    ``sampled_in_box``: the paint is drawn only on the element ``bbox`` and ``user_style``
    belong to (inside the box, widened by its stroke); not so for a context paint, which a
    marker's shapes draw away from the context element."""
    if el.tag in GRADIENT_TAGS:
        return gradient(builder, el, ctx, bbox)
    if el.tag == "pattern":
        return pattern(builder, el, ctx, bbox, user_style if sampled_in_box else None)
    return None


def gradient(builder, el, ctx, bbox):
    chain = href_chain(builder.doc, el, GRADIENT_TAGS)
    stops = gradient_stops(builder, chain)
    if len(stops) == 0:
        return None
    if len(stops) == 1:
        return Solid(tuple(stops[0, 1:]))
    # enumerated attributes match their keywords exactly (no CSS whitespace trimming: they
    # are no properties; browsers and resvg take " userSpaceOnUse" as invalid, the default)
    obb = inherited_attr(chain, "gradientUnits", "objectBoundingBox") != "userSpaceOnUse"
    style = builder.doc.document_style(el)
    vp = ctx.viewport
    # coordinates inherit only from gradients of the same kind, up to the first of another
    # kind (usvg stops there)
    same = list(itertools.takewhile(lambda e: e.tag == el.tag, chain))

    def attr(name, axis, default):
        return box_coord(builder, inherited_attr(same, name), axis, obb, style, vp, default)

    # The single-colour gradients need neither the box nor the transform: SVG paints the area
    # with the last stop, as resvg does also on an empty box (a radius of zero) and through a
    # singular gradientTransform (both kinds).
    if el.tag == "radialGradient":
        r = attr("r", "xy", "50%")
        if r <= 0:
            # SVG: "a value of zero will cause the area to be painted as a single color using
            # the color and opacity of the last gradient stop"
            return Solid(tuple(stops[-1, 1:]))
    m = ctx.transform
    if obb:
        if bbox is None or bbox[2] - bbox[0] <= 0 or bbox[3] - bbox[1] <= 0:
            return None
        from .builder import bbox_matrix
        m = compose(m, bbox_matrix(bbox))
    if el.tag == "linearGradient":
        x1, y1 = attr("x1", "x", "0%"), attr("y1", "y", "0%")
        x2, y2 = attr("x2", "x", "100%"), attr("y2", "y", "0%")
        if x1 == x2 and y1 == y2:
            return Solid(tuple(stops[-1, 1:]))
    gradient_m = _units_transform(builder, chain, "gradientTransform", style, ctx)
    if gradient_m is None:
        return NO_PAINT
    m = compose(m, gradient_m)
    try:
        to_paint = invert(m)
    except ValueError:
        return NO_PAINT
    spread = inherited_attr(chain, "spreadMethod", "pad")
    if spread not in ("pad", "reflect", "repeat"):
        spread = "pad"
    if el.tag == "linearGradient":
        return LinearGradient(x1, y1, x2, y2, stops, spread, to_paint)
    cx, cy = attr("cx", "x", "50%"), attr("cy", "y", "50%")
    # fx/fy not given, or not a length (an invalid value is as if not given), coincide with
    # cx/cy (SVG 2's lacuna)
    fx = cx if split_length(inherited_attr(same, "fx")) is None else attr("fx", "x", "50%")
    fy = cy if split_length(inherited_attr(same, "fy")) is None else attr("fy", "y", "50%")
    fr = max(attr("fr", "xy", "0%"), 0.0)    # a negative radius is an error: the default
    if (math.hypot(cx - fx, cy - fy) <= DEGENERATE and abs(r - fr) <= DEGENERATE):
        # Equal circles: canvas paints nothing. tiny-skia (so resvg) paints, with pad, the
        # limit of a ring growing thin: the first stop's colour inside, the last one outside;
        # with reflect or repeat nothing.
        if spread != "pad":
            return NO_PAINT    # a valid paint server that paints nothing: not the fallback
        first, last = list(stops[0, 1:]), list(stops[-1, 1:])
        ring = separate_equal_offsets([[0.0, *first], [1.0, *first], [1.0, *last]])
        return RadialGradient(cx, cy, r, cx, cy, np.asarray(ring, dtype=np.float64), 0.0,
                              spread, to_paint)
    # Any focal circle, also one as large as or larger than the end circle (fr >= r) or lying
    # outside it, is the two-point conical gradient of SVG 2 / canvas: the shader takes the
    # largest t whose interpolated circle passes through the pixel and has a radius >= 0.
    return RadialGradient(cx, cy, r, fx, fy, stops, fr, spread, to_paint)


def pattern(builder, el, ctx, bbox, user_style=None):
    """``user_style``: the painted element's style, when the paint is drawn on that element
    alone (see paint_server); a tile too large to render whole is then laid out only where
    the element can sample it (_sampled_window)."""
    from .builder import Ctx

    if any(p is el for p in builder.paint_stack):
        return None
    chain = href_chain(builder.doc, el, ("pattern",))
    style = builder.doc.document_style(el)
    obb = inherited_attr(chain, "patternUnits", "objectBoundingBox") != "userSpaceOnUse"
    content_obb = (inherited_attr(chain, "patternContentUnits", "userSpaceOnUse")
                   == "objectBoundingBox")
    vb_text = inherited_attr(chain, "viewBox")
    vb = parse_viewbox(vb_text)
    if vb is None and zero_size_viewbox(vb_text):
        # SVG 2: a viewBox of zero width or height disables rendering (a negative one is an
        # error that only voids the attribute); the paint's fallback then applies, as in
        # Chromium 150 and Firefox (resvg 0.48.1 draws the content without the viewBox)
        return None
    vp = ctx.viewport

    def attr(name, axis):
        return box_coord(builder, inherited_attr(chain, name), axis, obb, style, vp, "0")
    x, y, w, h = attr("x", "x"), attr("y", "y"), attr("width", "x"), attr("height", "y")
    if w <= 0 or h <= 0:
        # a tile without area is no valid pattern (resvg skips it, so the fallback), whether
        # or not its content would need the box
        return None
    if obb or (content_obb and vb is None):
        if bbox is None or bbox[2] - bbox[0] <= 0 or bbox[3] - bbox[1] <= 0:
            # as in resvg: the fallback for a tile in box units, nothing for content alone
            return None if obb else NO_PAINT
    if obb:
        bx, by = bbox[0], bbox[1]
        bw, bh = bbox[2] - bbox[0], bbox[3] - bbox[1]
        x, y, w, h = bx + x * bw, by + y * bh, w * bw, h * bh
    if w <= 0 or h <= 0:
        return None
    pattern_m = _units_transform(builder, chain, "patternTransform", style, ctx)
    if pattern_m is None:
        return NO_PAINT
    full = compose(ctx.transform, pattern_m)
    # The tile's resolution as resvg picks it (row norms, in f32), so a skewed pattern's
    # content is laid out at the same scale as in resvg, and its size in whole pixels is too.
    element32 = f32_chain(ctx.chain, ctx.transform)
    pattern32 = f32_matrix(pattern_m)
    sx, sy = row_scale_f32(concat_f32(element32, pattern32))
    sx32, sy32 = np.float32(sx), np.float32(sy)
    if sx <= 0 or sy <= 0:
        return None
    tw, th = _tile_pixels(w, sx), _tile_pixels(h, sy)
    if tw is None or th is None:
        return None
    window = None
    if tw > MAX_TILE_SIDE or th > MAX_TILE_SIDE or tw * th > MAX_TILE_PIXELS:
        window = _sampled_window(builder, ctx, bbox, user_style, full, x, y, sx, sy, tw, th)
    if window is None:
        # each side is bounded too: a tile far longer than the output is wide (a fuzzed
        # height of 1e12) would otherwise become a 1-pixel sliver of millions of rows
        if tw > MAX_TILE_SIDE:
            sx *= MAX_TILE_SIDE / tw
        if th > MAX_TILE_SIDE:
            sy *= MAX_TILE_SIDE / th
        tw, th = _tile_pixels(w, sx), _tile_pixels(h, sy)
        if tw * th > MAX_TILE_PIXELS:
            f = math.sqrt(MAX_TILE_PIXELS / (tw * th))
            sx, sy = sx * f, sy * f
            tw, th = _tile_pixels(w, sx), _tile_pixels(h, sy)
        # Like resvg, the tile is a whole number of pixels at the device scale, so the period
        # drifts by under half a pixel per tile. Tiles under two pixels, where that error
        # would dominate, get their scale adjusted instead so the period stays exact.
        if w * sx < 2:
            sx = tw / w
        if h * sy < 2:
            sy = th / h
        window = (0, 0, tw, th)
    u0, v0, width, height = window
    if vb is not None:
        content = viewbox_transform(vb, parse_aspect(inherited_attr(chain, "preserveAspectRatio")),
                                    w, h)
    elif content_obb:
        content = (bbox[2] - bbox[0], 0.0, 0.0, bbox[3] - bbox[1], 0.0, 0.0)
    else:
        content = IDENTITY
    # A pattern establishes no viewport (SVG 2 §8.2 lists those that do): percentages in its
    # content are of the referencing element's, also under a viewBox (browsers, resvg).
    source = next((e for e in chain if any(_is_child(c) for c in e.children)), el)
    tile_scale = (sx, 0.0, 0.0, sy, 0.0, 0.0)
    # the content once for each copy of the tile the window overlaps (the whole tile: one; a
    # window, at most two along each axis, as it is no larger than the tile), shifted to the
    # window's corner and, when there are several, clipped to its copy
    copies = [(i * tw - u0, j * th - v0)
              for i in range(u0 // tw, (u0 + width - 1) // tw + 1)
              for j in range(v0 // th, (v0 + height - 1) // th + 1)]
    groups = []
    for ox, oy in copies:
        shifted = (translate(ox, oy),) if ox or oy else ()
        transform = compose(tile_scale, content)
        tile_ctx = Ctx(transform=compose(shifted[0], transform) if shifted else transform,
                       chain=(*shifted, tile_scale, content), viewport=vp,
                       use_stack=ctx.use_stack, context_fill=ctx.context_fill,
                       context_stroke=ctx.context_stroke)
        # Shapes sharing a pattern at the same scale share its tile (it does not depend on
        # where the shape is): they get the same content group, which the raster renders
        # once. The key holds everything the tile's content can depend on (the context
        # paints themselves, not their ids: the key keeps them alive, so no later one takes
        # an id).
        key = (id(el), tw, th, tile_ctx.transform, vp, ctx.context_fill,
               ctx.context_stroke, ctx.use_stack, tuple(map(id, builder.paint_stack)),
               tuple(map(id, builder.ref_stack)), window)
        if key not in builder.tile_cache:
            builder.tile_cache[key] = _tile_content(builder, el, source, tile_ctx)
        group = builder.tile_cache[key]
        if group is None or group is NO_PAINT:
            return group
        if len(copies) > 1:
            group = Group(children=[group],
                          clip=Group(children=[Fill(rect_path(ox, oy, tw, th))]))
        groups.append(group)
    try:
        to_paint = invert(_tile_to_device(full, x, y, sx, sy))
    except ValueError:
        return NO_PAINT
    if u0 or v0:
        to_paint = compose(translate(-u0, -v0), to_paint)
    # The tile is rendered at device resolution and sampled as tiny-skia samples resvg's:
    # nearest only where the shader's matrix (the element's, then the pattern's transform,
    # x/y and the tile's 1/scale, concatenated in f32) is exactly a translation, filtered
    # otherwise: rotated and skewed tiles, but also rotations that cancel with an f32 skew
    # left (an element's rotate(-30) and the pattern's rotate(30) at 1.5 px per unit; not
    # at 1) and scales that miss 1 by an ulp (300/131 px per unit).
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        f = np.float32
        ts2 = concat_f32(concat_f32(pattern32, (1.0, 0.0, 0.0, 1.0, float(f(x)), float(f(y)))),
                        (float(f(1) / sx32), 0.0, 0.0, float(f(1) / sy32), 0.0, 0.0))
        total = concat_f32(element32, ts2)
    crisp = total[0] == 1.0 and total[3] == 1.0 and total[1] == 0.0 and total[2] == 0.0
    return PatternPaint(groups[0] if len(groups) == 1 else Group(children=groups), width,
                        height, to_paint, smooth=not crisp)


#: the elements usvg's tree keeps (style, desc, title, metadata and unknown elements are not):
#: a pattern with none of them as children takes its href's children
_TREE_ELEMENTS = frozenset(
    "a circle clipPath defs ellipse filter g image line linearGradient marker mask path "
    "pattern polygon polyline radialGradient rect stop svg switch symbol text textPath tref "
    "tspan use".split())


def _is_child(el):
    return el.tag in _TREE_ELEMENTS or (el.tag or "").startswith("fe")


def _tile_pixels(length, scale):
    """A tile side in whole pixels as resvg computes it: length × scale in f32, rounded
    (halves away from zero). A 12.5-unit tile is 13 px under rotate(-46) (norm 1 in f32) and
    12 under rotate(45) (0.99999994). None past f32's range (matrix(1e308 ...)): such a
    tile has no pixel size in resvg, and is not drawn."""
    with np.errstate(over="ignore"):
        v = float(np.float32(length) * np.float32(scale))
    return max(1, math.floor(v + 0.5)) if math.isfinite(v) else None


#: containers that count as pattern content even when empty (usvg keeps them)
_CONTAINERS = ("g", "a")


def _tile_content(builder, el, source, tile_ctx):
    """The pattern's content in tile pixels as a Group; when it draws nothing, None (the
    fallback applies) if it has no content at all, NO_PAINT if its content is there but
    invisible. As in resvg, where a pattern with nothing to convert is no paint server: no
    children, or only non-rendering ones (desc, gradients, unknown elements), display: none,
    shapes without geometry; while a hidden, unpainted or transparent shape, an empty group
    are content that paints nothing."""
    builder.paint_stack.append(el)
    try:
        style = builder.doc.document_style(source)
        nodes = builder.children(source, tile_ctx, style)
        if nodes:
            return Group(children=nodes)
        if any(c.tag in _CONTAINERS and
               builder.doc.document_style(c).get("display").strip() != "none"
               for c in source.children):
            return NO_PAINT
        return NO_PAINT if builder.children(source, replace(tile_ctx, geometry=True),
                                            style) else None
    finally:
        builder.paint_stack.pop()


#: device pixels of slack around the sampled region of a windowed tile (bilinear reads one
#: texel beyond a sample; partly covered edge pixels have their centres outside the box)
WINDOW_SLACK = 3


def _tile_to_device(full, x, y, sx, sy):
    """Tile pixels to device pixels: ``full`` (pattern space to device) after the tile's
    origin (x, y) and its sx by sy pixels per unit."""
    return compose(compose(full, translate(x, y)), (1 / sx, 0.0, 0.0, 1 / sy, 0.0, 0.0))


def _sampled_window(builder, ctx, bbox, user_style, full, x, y, sx, sy, tw, th):
    """(u0, v0, width, height) in tile pixels: the part of a tw x th tile that the element can
    sample, when that part is small enough to render whole at full scale; None otherwise.
    ``full`` maps pattern space to device pixels; the tile lies at (x, y) with sx by sy
    pixels per unit. A tile over the caps would else be laid out at a reduced scale and its
    content's edges blurred (an objectBoundingBox pattern of width 20 on a 160-unit rect is
    a 3200 px tile in a 200 px render). The element draws the paint inside its box widened
    by its stroke's reach (Builder.outline_reach); a quarter of the box's larger side more
    covers what a text's box may leave out (decorations past the glyphs); a stroke that does
    not scale with the element has no such bound here. The window is that box's device
    bounds mapped into unwrapped tile pixels, so it may reach into the neighbouring copies of
    the tile (pattern draws those too)."""
    if user_style is None or bbox is None:
        return None
    if (user_style.get("vector-effect") or "").strip() == "non-scaling-stroke":
        return None
    x0, y0, x1, y1 = bbox
    stroke = builder.stroke_params(user_style, ctx)
    margin = builder.outline_reach(stroke) if stroke else 0.0
    margin += max(x1 - x0, y1 - y0) / 4
    corners = np.array([(x0 - margin, y0 - margin), (x1 + margin, y0 - margin),
                        (x0 - margin, y1 + margin), (x1 + margin, y1 + margin)])
    try:
        device_to_tile = invert(_tile_to_device(full, x, y, sx, sy))
    except ValueError:
        return None
    to_tile = compose(device_to_tile, ctx.transform)
    with np.errstate(all="ignore"):
        uv = apply(to_tile, corners)
    if not np.isfinite(uv).all():
        return None
    # the slack in tile pixels: device pixels through the tile's scale (its largest stretch)
    a, b, c, d = device_to_tile[:4]
    slack = WINDOW_SLACK * max(1.0, math.hypot(a, b), math.hypot(c, d))
    u0 = math.floor(uv[:, 0].min() - slack)
    v0 = math.floor(uv[:, 1].min() - slack)
    u1 = math.ceil(uv[:, 0].max() + slack)
    v1 = math.ceil(uv[:, 1].max() + slack)
    width, height = u1 - u0, v1 - v0
    if (width > MAX_TILE_SIDE or height > MAX_TILE_SIDE or width * height > MAX_TILE_PIXELS
            or width > tw or height > th):
        return None
    return u0, v0, width, height
