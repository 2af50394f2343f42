"""The ``filter`` property → resolved :class:`~vecmsaa.scene.nodes.Filter` lists (usvg semantics).

``filter`` is a list of ``url(#id)`` references to ``<filter>`` elements and CSS filter
functions (``blur()``, ``drop-shadow()``, ``grayscale()``...), applied in order. Regions,
subregions, standard deviations and offsets are resolved here to device pixels: the filter region
is the device bounding box of its user-space rectangle, and lengths are scaled by the
transform's x and y scale (as resvg: a rotated or skewed element is filtered in device space).

A reference to nothing usable (a missing element, another kind of element, an empty or invalid
region, a filter without primitives) counts as invalid; when every entry is invalid the element
is not drawn. A value that does not parse is ignored (the element is drawn unfiltered).

Keyword attributes of the filter elements (``operator``, ``mode``, ``type``, ``edgeMode``,
``filterUnits``...) and ``in``/``result`` names are compared as written: they are no CSS
properties, whose values are trimmed, and usvg and Blink match them exactly, so
``operator=" in "`` is an unknown operator (the default). Presentation attributes
(``color-interpolation-filters``, ``flood-color``) are trimmed like any property.
"""
from __future__ import annotations

import math
from array import array as _array

import numpy as np
import re
from dataclasses import replace

from ..scene.nodes import (SOURCE_ALPHA, SOURCE_GRAPHIC, Blend, ColorMatrix, ComponentTransfer,
                           Composite, ConvolveMatrix, DisplacementMap, DropShadow, Filter, Flood,
                           GaussianBlur, Group, Image, Lighting, Merge, Morphology, Offset,
                           Primitive, Tile, Turbulence)
from .color import parse_svg_color as parse_color
from .document import Element, href_chain, inherited_attr
from .units import (ANGLE_DEG, box_coord, f32_chain, parse_number, parse_number_list,
                    parse_number_prefix, parse_opacity, row_scale_f32, split_length,
                    url_argument)

_FUNCTION = re.compile(r"\s*([a-zA-Z-]+)\(\s*((?:[^()]|\([^()]*\))*?)\s*\)\s*")
PRIMITIVE_TAGS = {
    "feBlend", "feColorMatrix", "feComponentTransfer", "feComposite", "feConvolveMatrix",
    "feDiffuseLighting", "feDisplacementMap", "feDropShadow", "feFlood", "feGaussianBlur",
    "feImage", "feMerge", "feMorphology", "feOffset", "feSpecularLighting", "feTile",
    "feTurbulence"}
MAX_OCTAVES = 12
TRANSPARENT = Flood((0.0, 0.0, 0.0, 0.0))
LUMA = (0.2126, 0.7152, 0.0722)


def element_filters(builder, el, style, ctx, bbox_fn):
    """[Filter] for the element's ``filter`` value, [] when there is none (or it does not
    parse), False when the element is not drawn."""
    value = (style.specified.get("filter") or "").strip()
    if not value or value == "none":
        return []
    # (parsed once per value; _draws_itself only where a <filter> it names has an feImage)
    hit = builder.filter_cache.get(value)
    if hit is None:
        entries = parse_filter_value(value)
        hit = builder.filter_cache[value] = (
            entries, entries is not None and _draws_itself(builder, None, entries, True))
    entries, has_image = hit
    if entries is None:
        return []
    if has_image and _draws_itself(builder, el, entries) and (
            not ctx.use_stack or any(r is el for r in builder.ref_stack)):
        # a filter whose feImage draws the element the filter is on: the reference is
        # circular, which Filter Effects 1 leaves open; usvg removes such an element's
        # `filter` when it parses the document, after copying `use` instances, so the element
        # is drawn unfiltered, and an instance of it keeps the filter, whose feImage draws the
        # element unfiltered
        return []
    out, invalid = [], False
    for name, args in entries:
        if name == "url":
            ref = url_argument(args)
            if ref is None or not ref.startswith("#"):
                # a bad url (url(# f)) is no filter value; a url to another document is not
                # followed, and Filter Effects 1 ignores a chain that references no filter
                # (as resvg does for these; a missing #id is not drawn, as resvg draws it)
                return []
            target = builder.doc.lookup(ref)
            flt = (filter_element(builder, target, el, ctx, bbox_fn)
                   if target is not None and target.tag == "filter" else None)
            if flt is None:
                invalid = True
            else:
                out.append(flt)
        else:
            flt = filter_function(builder, name, args, style, ctx, bbox_fn,
                                  out[-1].region if out else None)
            if flt is False:
                return []
            if flt is not None:
                out.append(flt)
    if not out and invalid:
        return False
    return out


def _draws_itself(builder, el, entries, any_image=False):
    """Whether a url of the filter list names a <filter> with an feImage child whose href is
    ``el`` (usvg's test: the feImage's own parent, not one reached through href); with
    ``any_image``, whether it names one with an feImage child at all."""
    for name, args in entries:
        ref = url_argument(args) if name == "url" else None
        target = builder.doc.lookup(ref) if ref and ref.startswith("#") else None
        if target is not None and target.tag == "filter" and any(
                c.tag == "feImage" and (any_image
                                        or builder.doc.lookup(c.get("href") or "") is el)
                for c in target.children):
            return True
    return False


def parse_filter_value(value):
    """[(function name, argument text)] or None when the value does not parse."""
    out, pos = [], 0
    while pos < len(value):
        m = _FUNCTION.match(value, pos)
        if not m:
            return None
        out.append((m.group(1).lower(), m.group(2)))
        pos = m.end()
    return out


# -- geometry ------------------------------------------------------------------------------
def device_rect(x, y, w, h, m):
    """Integer device bounding box (x0, y0, x1, y1) of a user rectangle, as resvg computes it:
    in f32 (tiny-skia's ``Rect`` keeps left, top, right, bottom and maps the corners), then
    ``to_int_rect`` (corner floored, size ceiled). The f32 rounding matters: a width that is
    whole over a fractional left edge comes out a hair wider, so one pixel wider.

    Each f32 operation is the f64 one rounded to f32 (exact for a product of two f32 values,
    and correctly rounded for a sum, since f64 has more than twice f32's precision), a batch
    at a time through ``array('f')``: numpy scalars cost three times more, and filtered
    markers and shapes come by the ten thousand. Past f32's range a value is infinite, as in
    numpy."""
    x, y, w, h, a, b, c, d, e, ff = _f32(x, y, w, h, *m)
    right, bottom = _f32(x + w, y + h)
    ax, ar, cy, cb, bx, br, dy, db = _f32(a * x, a * right, c * y, c * bottom,
                                          b * x, b * right, d * y, d * bottom)
    # corners (x, y), (right, y), (x, bottom), (right, bottom)
    s = _f32(ax + cy, ar + cy, ax + cb, ar + cb, bx + dy, br + dy, bx + db, br + db)
    corners = _f32(s[0] + e, s[1] + e, s[2] + e, s[3] + e,
                   s[4] + ff, s[5] + ff, s[6] + ff, s[7] + ff)
    if not math.isfinite(sum(corners)):     # (f32 values: a sum of 8 is finite in f64)
        return None
    xs, ys = corners[:4], corners[4:]
    left, top = min(xs), min(ys)
    x0, y0 = math.floor(left), math.floor(top)
    # the size too is f32 (tiny-skia's width() is right - left): 140 - (-30.0000019) is 170 in
    # f32, so 170 px from row -31, where the exact 170.0000019 would take 171
    width, height = _f32(max(xs) - left, max(ys) - top)
    if not (math.isfinite(width) and math.isfinite(height)):
        return None
    return (x0, y0, x0 + max(1, math.ceil(width)), y0 + max(1, math.ceil(height)))


def _f32(*values):
    """The values rounded to f32 (as floats; inf past its range)."""
    return _array("f", values).tolist()


def layer_matrix(m, region):
    """resvg filters a layer whose corner is the filter region's whole-pixel corner, mapping
    the region and subregions again with the matrix translated by minus that corner (its
    translation in f32): a subregion from 63.6 to 75.6 px is 0.6 to 12.6 there, 12 px wide
    (ceil of 12.0), where mapped in place its f32 width is 12.000004 and it is 13."""
    x0, y0 = region[:2]
    e, ff, fx0, fy0 = _f32(m[4], m[5], x0, y0)
    e, ff = _f32(e - fx0, ff - fy0)         # (f32 subtractions, as in device_rect)
    return (m[0], m[1], m[2], m[3], e, ff), x0, y0


def layer_rect(x, y, w, h, layer):
    """device_rect in the layer of :func:`layer_matrix`, moved back to the canvas."""
    m, x0, y0 = layer
    r = device_rect(x, y, w, h, m)
    return None if r is None else (r[0] + x0, r[1] + y0, r[2] + x0, r[3] + y0)


def bbox_fractions_f32(fx, fy, fw, fh, bx, by, bw, bh):
    """x, y, width, height of a rectangle given in fractions of a bounding box, in f32 as usvg
    maps it (``x * bbox.width + bbox.x``, ``width * bbox.width``): the default region's 1.2 is
    1.2000000477 in f32, so 120% of 100 is 120.0000076 and the region's right edge
    (-10 + 120.0000076) rounds past 110, one device pixel more than in exact arithmetic."""
    fx, fy, fw, fh, bx, by, bw, bh = _f32(fx, fy, fw, fh, bx, by, bw, bh)
    pw, ph, w, h = _f32(fx * bw, fy * bh, fw * bw, fh * bh)
    return (*_f32(pw + bx, ph + by), w, h)


# -- <filter> ------------------------------------------------------------------------------
# primitives whose effect depends on where the element is (its translation) or on the element
# itself: the effects of a <filter> holding one are resolved afresh for each use
_PER_USE = frozenset(("feImage", "feTurbulence", "feDiffuseLighting", "feSpecularLighting"))


def filter_element(builder, fel, el, ctx, bbox_fn):
    """The Filter of a ``<filter>`` element for ``el``, or None when unusable.

    A marker or a shape drawn ten thousand times with one filter differs from use to use in
    its position and bounding box only, so what does not depend on them is resolved once
    (builder.filter_cache): the <filter>'s units, its region's and subregions' lengths (per
    viewport), and the primitives' effects and inputs (per viewport, linear part of the
    matrices, which is all the device scale depends on, and bounding box size when
    primitiveUnits is objectBoundingBox), except where a primitive of _PER_USE makes them
    the use's own. Each use maps the rectangles."""
    cache = builder.filter_cache
    head = cache.get(fel)
    if head is None:
        head = cache[fel] = _filter_head(builder, fel)
    units_obb, prim_obb, holder, per_use = head
    bbox = bbox_fn() if (units_obb or prim_obb) else None
    if (units_obb or prim_obb) and (bbox is None or bbox[2] <= bbox[0] or bbox[3] <= bbox[1]):
        return None
    lengths = cache.get((fel, ctx.viewport))
    if lengths is None:
        lengths = cache[(fel, ctx.viewport)] = _filter_lengths(builder, fel, units_obb,
                                                               prim_obb, holder, ctx)
    region_spec, subs = lengths
    if units_obb:
        bx, by, bw, bh = bbox[0], bbox[1], bbox[2] - bbox[0], bbox[3] - bbox[1]
        x, y, w, h = bbox_fractions_f32(*region_spec, bx, by, bw, bh)
    else:
        x, y, w, h = region_spec
    if not (w > 0 and h > 0) or holder is None:
        return None
    region = device_rect(x, y, w, h, ctx.transform)
    if region is None:
        return None
    layer = layer_matrix(ctx.transform, region)
    whole = layer_rect(x, y, w, h, layer)
    region = whole or region
    obb_box = bbox if prim_obb else None
    if per_use:
        resolver = PrimitiveResolver(builder, el, ctx, (x, y, w, h), obb_box)
        resolver.layer = layer
        effects = resolver.effects(holder)      # each resolved once its subregion is known
    else:
        size = (bbox[2] - bbox[0], bbox[3] - bbox[1]) if prim_obb else None
        key = (fel, ctx.viewport, ctx.transform[:4], tuple(m[:4] for m in ctx.chain), size)
        resolved = cache.get(key)
        if resolved is None:
            resolved = cache[key] = list(
                PrimitiveResolver(builder, el, ctx, None, obb_box).effects(holder))
        effects = iter(resolved)
    primitives = []
    users = []                                      # each primitive's user-space subregion
    for tag, spec in subs:
        effect, inputs, linear = next(effects)
        default = _default_subregion(tag, inputs, users, (x, y, w, h))
        user = _user_subregion(tag, spec, (x, y, w, h), obb_box, default)
        if user is None:
            # Filter Effects 1: a zero or negative width or height disables the primitive,
            # its result transparent black, and the primitives after it still run (usvg
            # stops the chain there, and drops the filter when it is the first)
            users.append(None)
            primitives.append(Primitive(TRANSPARENT, (), (*region[:2], *region[:2]), linear))
            continue
        # (a primitive without x, y, width and height has the region's rectangle)
        sub = whole if user == (x, y, w, h) else layer_rect(*user, layer)
        if sub is None:
            break
        users.append(user)
        if tag == "feOffset" and not prim_obb and any(v is not None for v in spec):
            # Filter Effects 1: a given subregion restricts the primitive's result (resvg
            # takes an feOffset's region from its input whatever its own x, y, width, height).
            # Not in objectBoundingBox units, where subregions follow usvg's rule, not the
            # specification's (_user_subregion), and that rule's rectangle would cut it wrongly
            effect = replace(effect, own_subregion=True)
        primitives.append(Primitive(effect, inputs, sub, linear))
    if not primitives:
        return None
    return Filter(region=region, primitives=primitives)


def _filter_head(builder, fel):
    """(filterUnits is objectBoundingBox, primitiveUnits is, the element holding the
    primitives, whether a primitive's effect is the use's own: _PER_USE) of a <filter>."""
    chain = href_chain(builder.doc, fel, ("filter",))
    holder = next((e for e in chain if e.children), None)   # usvg: the first with children
    return ((inherited_attr(chain, "filterUnits") or "") != "userSpaceOnUse",
            (inherited_attr(chain, "primitiveUnits") or "") == "objectBoundingBox", holder,
            holder is not None and any(c.tag in _PER_USE for c in holder.children))


def _filter_lengths(builder, fel, units_obb, prim_obb, holder, ctx):
    """A <filter>'s lengths in a viewport: its region (fractions of the bounding box, or
    user-space x, y, width, height), and for each primitive its tag and subregion
    (_subregion_spec)."""
    chain = href_chain(builder.doc, fel, ("filter",))
    attr = lambda name: inherited_attr(chain, name)  # noqa: E731
    style = builder.doc.document_style(fel)
    if units_obb:
        region = tuple(box_coord(builder, attr(n), a, True, style, ctx.viewport, d)
                       for n, a, d in (("x", "x", "-10%"), ("y", "y", "-10%"),
                                       ("width", "x", "120%"), ("height", "y", "120%")))
    else:
        vw, vh = ctx.viewport

        def length(name, axis, default):
            v = builder.length(attr(name), axis, style, ctx.viewport)
            return default if v is None else v
        region = (length("x", "x", -0.1 * vw), length("y", "y", -0.1 * vh),
                  length("width", "x", 1.2 * vw), length("height", "y", 1.2 * vh))
    subs = [(fe.tag, _subregion_spec(builder, fe, prim_obb, ctx.viewport))
            for fe in (holder.children if holder is not None else ())
            if fe.tag in PRIMITIVE_TAGS]
    return region, subs


def _subregion_spec(builder, fe, prim_obb, viewport):
    """A primitive's x, y, width and height: fractions with primitiveUnits=objectBoundingBox,
    else user-space lengths, None where not given."""
    style = builder.doc.document_style(fe)
    names = ("x", "y", "width", "height")
    if prim_obb:
        return tuple(None if fe.get(n) is None
                     else box_coord(builder, fe.get(n), a, True, style, viewport, d)
                     for n, a, d in zip(names, "xyxy", ("0%", "0%", "100%", "100%")))
    return tuple(builder.length(fe.get(n), a, style, viewport) for n, a in zip(names, "xyxy"))


#: primitives whose subregion defaults to the filter region whatever their inputs
_REGION_DEFAULT = frozenset(("feTile", "feImage", "feFlood", "feTurbulence"))


def _default_subregion(tag, inputs, users, region):
    """The user-space rectangle a primitive's missing x, y, width, height come from. Filter
    Effects 1 (filter primitive subregion): the union of the subregions of the primitives it
    references; the filter region when it references none, a standard input (SourceGraphic,
    SourceAlpha...), or for feTile. A disabled primitive's empty subregion adds nothing.
    (usvg takes the filter region in every case.)"""
    if tag in _REGION_DEFAULT or not inputs or any(i < 0 or i >= len(users) for i in inputs):
        return region
    rects = [users[i] for i in inputs if users[i] is not None]
    if not rects:
        return region
    x0 = min(r[0] for r in rects)
    y0 = min(r[1] for r in rects)
    x1 = max(r[0] + r[2] for r in rects)
    y1 = max(r[1] + r[3] for r in rects)
    return x0, y0, x1 - x0, y1 - y0


def _user_subregion(tag, spec, region, obb_box, default=None):
    """(x, y, width, height) of a primitive subregion in user space from its _subregion_spec
    and the filter region's user-space rectangle, or None when empty. ``obb_box``: the
    bounding box with primitiveUnits=objectBoundingBox; ``default``: where a value not given
    comes from (_default_subregion; the region when None)."""
    given = spec
    if obb_box is not None:
        bx, by = obb_box[0], obb_box[1]
        bw, bh = obb_box[2] - bx, obb_box[3] - by
        fx, fy, fw, fh = [d if v is None else v for v, d in zip(spec, (0.0, 0.0, 1.0, 1.0))]
        if tag in ("feFlood", "feImage"):
            # usvg: fractions of the bounding box
            x, y, w, h = bbox_fractions_f32(fx, fy, fw, fh, bx, by, bw, bh)
        else:
            # usvg: the filter region scaled by the fractions (and x, y added as they are;
            # Filter Effects 1 has x = bbox.x + x * bbox.width, but the suite's references,
            # subregion-and-primitiveUnits=objectBoundingBox-2, are drawn by usvg's rule)
            rx, ry, rw, rh = region
            x, y, w, h = rx * fw + fx, ry * fh + fy, rw * fw, rh * fh
    else:
        x, y, w, h = [d if v is None else v for v, d in zip(spec, region)]
    if default is not None and default != region:
        x, y, w, h = [d if g is None else v for v, g, d in zip((x, y, w, h), given, default)]
    if not (w > 0 and h > 0):
        return None
    return x, y, w, h


class PrimitiveResolver:
    """Resolves the primitives of one ``<filter>`` for one element: subregions, inputs and
    results, and the lengths (scaled by the bounding box with primitiveUnits=objectBoundingBox,
    then by the transform's scale)."""

    def __init__(self, builder, el, ctx, region, obb_box):
        self.builder, self.el, self.ctx = builder, el, ctx
        self.region = region                  # user-space x, y, w, h
        self.obb_box = obb_box                # bbox when primitiveUnits is objectBoundingBox
        sx, sy = device_scale(ctx)
        if obb_box is not None:
            sx *= obb_box[2] - obb_box[0]
            sy *= obb_box[3] - obb_box[1]
        self.scale = (sx, sy)                 # primitive units → device pixels
        self.names = {}
        self.count = 0

    def effects(self, holder):
        """(effect, inputs, linear) of each primitive in turn, a generator: filter_element
        asks for the next one once that primitive's subregion holds (usvg stops at the first
        invalid one, and an feImage's effect reads its subregion)."""
        for child in holder.children:
            if child.tag not in PRIMITIVE_TAGS:
                continue
            style = self.builder.doc.document_style(child)
            effect, inputs = self.effect(child, style)
            cif = (style.get("color-interpolation-filters") or "").strip()
            name = child.get("result")
            if name:
                self.names[name] = self.count
            self.count += 1
            yield effect, tuple(inputs), cif != "sRGB"

    def subregion(self, fe):
        """Device rect of the primitive subregion (default: the filter region), or None."""
        user = self.user_subregion(fe)
        return None if user is None else layer_rect(*user, self.layer)

    def user_subregion(self, fe):
        """(x, y, width, height) of the primitive subregion in user space, or None."""
        spec = _subregion_spec(self.builder, fe, self.obb_box is not None, self.ctx.viewport)
        return _user_subregion(fe.tag, spec, self.region, self.obb_box)

    def input(self, fe, attr="in"):
        # the name as written: " SourceGraphic " and " a " name nothing (usvg, and Blink's
        # lookup of in/result names, compare the attribute's text), so the previous result
        value = fe.get(attr)
        previous = self.count - 1 if self.count else SOURCE_GRAPHIC
        if value is None:
            return previous
        if value == "SourceAlpha":
            return SOURCE_ALPHA
        if value in ("SourceGraphic", "BackgroundImage", "BackgroundAlpha", "FillPaint",
                     "StrokePaint"):
            return SOURCE_GRAPHIC
        return self.names.get(value, previous)

    def pair(self, fe, attr, default):
        """A one-or-two number attribute scaled to device pixels (x, y); None when invalid."""
        text = fe.get(attr)
        nums = parse_number_prefix(text) if text is not None else list(default)
        if len(nums) == 1:
            nums = nums * 2
        if len(nums) != 2:
            return None
        return nums[0] * self.scale[0], nums[1] * self.scale[1]

    def number(self, fe, attr, default):
        return parse_number(fe.get(attr), default)

    def flood_color(self, style):
        c = parse_color(style.get("flood-color") or "black")
        if c == "currentColor":
            c = self.builder.current_color(style)
        if c is None:
            c = (0.0, 0.0, 0.0, 1.0)
        opacity = parse_opacity(style.get("flood-opacity"))
        return (c[0], c[1], c[2], c[3] * opacity)

    def effect(self, fe, style):
        """(effect, inputs) of one primitive element."""
        tag = fe.tag
        inp = self.input(fe)
        if tag == "feFlood":
            return Flood(self.flood_color(style)), ()
        if tag == "feGaussianBlur":
            s = self.pair(fe, "stdDeviation", (0.0,))
            if s is None or s[0] < 0 or s[1] < 0:
                s = (0.0, 0.0)
            return GaussianBlur(s[0], s[1]), (inp,)
        if tag == "feOffset":
            sx, sy = self.scale
            return Offset(f32_product(self.number(fe, "dx", 0.0), sx),
                          f32_product(self.number(fe, "dy", 0.0), sy)), (inp,)
        if tag == "feDropShadow":
            s = self.pair(fe, "stdDeviation", (2.0,))
            if s is None or s[0] < 0 or s[1] < 0:
                s = (0.0, 0.0)
            sx, sy = self.scale
            return DropShadow(s[0], s[1], f32_product(self.number(fe, "dx", 2.0), sx),
                              f32_product(self.number(fe, "dy", 2.0), sy),
                              self.flood_color(style)), (inp,)
        if tag == "feMerge":
            inputs = [self.input(node) for node in fe.children if node.tag == "feMergeNode"]
            return Merge(), tuple(inputs)
        if tag == "feComposite":
            op = fe.get("operator") or "over"
            if op not in ("over", "in", "out", "atop", "xor", "lighter", "arithmetic"):
                op = "over"
            k = tuple(self.number(fe, n, 0.0) for n in ("k1", "k2", "k3", "k4"))
            return Composite(op, k), (inp, self.input(fe, "in2"))
        if tag == "feBlend":
            mode = fe.get("mode") or "normal"
            if mode not in BLEND_MODES:
                mode = "normal"
            return Blend(mode), (inp, self.input(fe, "in2"))
        if tag == "feColorMatrix":
            return ColorMatrix(tuple(color_matrix_of(fe))), (inp,)
        if tag == "feComponentTransfer":
            funcs = [("identity", ())] * 4
            for node in fe.children:
                ch = {"feFuncR": 0, "feFuncG": 1, "feFuncB": 2, "feFuncA": 3}.get(node.tag)
                if ch is not None:
                    func = transfer_function(node)
                    if func is not None:
                        funcs[ch] = func
            return ComponentTransfer(tuple(funcs)), (inp,)
        if tag == "feTile":
            return Tile(), (inp,)
        if tag == "feMorphology":
            return self.morphology(fe, inp)
        if tag == "feTurbulence":
            return self.turbulence(fe), ()
        if tag == "feDisplacementMap":
            scale = self.number(fe, "scale", 0.0)

            def channel(name):
                v = fe.get(name) or "A"
                return v if v in ("R", "G", "B") else "A"
            return (DisplacementMap(scale * self.scale[0], scale * self.scale[1],
                                    channel("xChannelSelector"), channel("yChannelSelector")),
                    (inp, self.input(fe, "in2")))
        if tag == "feConvolveMatrix":
            effect = convolve_effect(fe)
            return (effect, (inp,)) if effect is not None else (TRANSPARENT, ())
        if tag in ("feDiffuseLighting", "feSpecularLighting"):
            effect = self.lighting(fe, style, tag == "feSpecularLighting")
            return (effect, (inp,)) if effect is not None else (TRANSPARENT, ())
        if tag == "feImage":
            if self.builder.doc.lookup(fe.get("href") or "") is self.el and not self.ctx.use_stack:
                # a filter drawing its own element through a filter's href (which usvg's
                # test above misses): resvg shows the element unfiltered
                return Offset(0.0, 0.0), (SOURCE_GRAPHIC,)
            content = self.image(fe)
            if content is None:
                return TRANSPARENT, ()
            return Image(content), ()
        return TRANSPARENT, ()

    def morphology(self, fe, inp):
        op = "dilate" if (fe.get("operator") or "") == "dilate" else "erode"
        rx, ry = 1.0, 1.0
        text = fe.get("radius")
        if text is not None:
            nums = parse_number_list(text) or []
            rx, ry = (nums * 2)[:2] if len(nums) == 1 else nums if len(nums) == 2 else (0, 0)
            if rx == 0 and ry == 0:
                rx = ry = 1.0
            rx = 1.0 if rx == 0 else rx          # Chrome and Safari: one zero radius is 1
            ry = 1.0 if ry == 0 else ry
            if rx < 0 or ry < 0:
                rx, ry = 1.0, 1.0
        # a radius overflowing to infinity in device pixels (1.7e308 × 10) is as wide as any
        # huge one: past the image either way, and infinity has no whole number of pixels
        # resvg's window is 2·ceil(r) pixels, r = radius × scale in f32: an ulp over a whole
        # number is a pixel more on each side
        return Morphology(op, f32_product(rx, self.scale[0]),
                          f32_product(ry, self.scale[1])), (inp,)

    def lighting(self, fe, style, specular):
        """The Lighting effect, or None for a primitive usvg drops (no light source, specular
        exponent outside 1..128)."""
        src = next((c for c in fe.children
                    if c.tag in ("feDistantLight", "fePointLight", "feSpotLight")), None)
        if src is None:
            return None
        exponent = parse_number(fe.get("specularExponent"), 1.0)
        if specular and not 1.0 <= exponent <= 128.0:
            return None
        num = lambda el, name: parse_number(el.get(name), 0.0)  # noqa: E731
        m = self.ctx.transform
        if src.tag == "feDistantLight":
            light = ("distant", num(src, "azimuth"), num(src, "elevation"))
        else:
            z_scale = math.hypot(m[0], m[3]) / math.sqrt(2)
            pts = [(num(src, "x"), num(src, "y"), num(src, "z"))]
            if src.tag == "feSpotLight":
                pts.append((num(src, "pointsAtX"), num(src, "pointsAtY"), num(src, "pointsAtZ")))
            device = []
            for x, y, z in pts:   # user units even with objectBoundingBox units (resvg)
                device.append((m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5],
                               z * z_scale))
            if src.tag == "fePointLight":
                light = ("point",) + device[0]
            else:
                spot_exp = parse_number(src.get("specularExponent"), 1.0)
                cone = parse_number(src.get("limitingConeAngle"), None)
                light = (("spot",) + device[0] + device[1]
                         + (spot_exp if spot_exp > 0 else 1.0, cone))
        return Lighting(specular, parse_number(fe.get("surfaceScale"), 1.0),
                        parse_number(fe.get("specularConstant" if specular
                                            else "diffuseConstant"), 1.0),
                        exponent, self.lighting_color(style), light)

    def lighting_color(self, style):
        value = (style.get("lighting-color") or "white").strip()
        c = parse_color(value)
        if c == "currentColor":
            c = self.builder.current_color(style)
        return (1.0, 1.0, 1.0) if c is None else tuple(c[:3])

    def turbulence(self, fe):
        fx = fy = 0.0
        nums = parse_number_list(fe.get("baseFrequency") or "") or []
        if len(nums) in (1, 2) and min(nums) >= 0:
            fx, fy = (nums * 2)[:2]
        octaves = parse_number(fe.get("numOctaves"), 1.0)
        seed = parse_number(fe.get("seed"), 0.0)
        a, b, c, d, e, f = self.ctx.transform
        sx, sy = device_scale(self.ctx)
        # a fractional count rounds half away from zero, as usvg rounds it (0.5 is one octave;
        # Python's round() would make it none); octaves past MAX_OCTAVES add under 1/4096 of
        # the first one: not a visible level
        octaves = math.floor(min(max(octaves, 0.0), MAX_OCTAVES) + 0.5)
        return Turbulence(fx, fy, octaves, int(seed),
                          (fe.get("stitchTiles") or "") == "stitch",
                          (fe.get("type") or "") == "fractalNoise", (sx, sy, e, f))

    def image(self, fe):
        """feImage content as a scene Group in device pixels, or None. An element is drawn as
        resvg draws it: at the device scale of the filtered element's user space (the row
        norms: rotation and skew are dropped), from the device subregion's whole-pixel
        corner, without its own filter; a file or data URL is fitted into the subregion at that
        scale and corner too."""
        from .image import image_nodes

        b = self.builder
        href = (fe.get("href") or "").strip()
        if not href:
            return None
        style = b.doc.document_style(fe)
        user, sub = self.user_subregion(fe), self.subregion(fe)
        if user is None or sub is None:
            return None             # (filter_element stops at this primitive)
        x, y, w, h = user
        sx, sy = device_scale(self.ctx)
        if href.startswith("#"):
            target = b.doc.lookup(href)
            if target is None or any(r is target for r in b.ref_stack):
                return None
            ctx = replace(self.ctx, transform=(sx, 0.0, 0.0, sy, float(sub[0]), float(sub[1])))
            parent = target.parent if target.parent is not None else target
            b.enter_reference(target)
            try:
                nodes = b.element(target, ctx, b.doc.document_style(parent))
            finally:
                b.ref_stack.pop()
            return Group(children=nodes) if nodes else None
        attrs = {"x": str(x), "y": str(y), "width": str(w), "height": str(h), "href": href}
        if fe.get("preserveAspectRatio") is not None:
            attrs["preserveAspectRatio"] = fe.get("preserveAspectRatio")
        # the subregion's user-space corner at its device corner, as for an element
        ctx = replace(self.ctx, transform=(sx, 0.0, 0.0, sy, float(sub[0]) - sx * x,
                                           float(sub[1]) - sy * y))
        nodes = image_nodes(b, Element("image", attrs, fe.parent, 0), ctx, style)
        return Group(children=nodes) if nodes else None


BLEND_MODES = {"normal", "multiply", "screen", "overlay", "darken", "lighten", "color-dodge",
               "color-burn", "hard-light", "soft-light", "difference", "exclusion", "hue",
               "saturation", "color", "luminosity"}


def saturate_matrix(s):
    r, g, b = LUMA
    return [r + (1 - r) * s, g - g * s, b - b * s, 0, 0,
            r - r * s, g + (1 - g) * s, b - b * s, 0, 0,
            r - r * s, g - g * s, b + (1 - b) * s, 0, 0,
            0, 0, 0, 1, 0]


def hue_rotate_matrix(degrees):
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    return [0.213 + c * 0.787 - s * 0.213, 0.715 - c * 0.715 - s * 0.715,
            0.072 - c * 0.072 + s * 0.928, 0, 0,
            0.213 - c * 0.213 + s * 0.143, 0.715 + c * 0.285 + s * 0.140,
            0.072 - c * 0.072 - s * 0.283, 0, 0,
            0.213 - c * 0.213 - s * 0.787, 0.715 - c * 0.715 + s * 0.715,
            0.072 + c * 0.928 + s * 0.072, 0, 0,
            0, 0, 0, 1, 0]


LUMINANCE_TO_ALPHA = [0] * 15 + [0.2125, 0.7154, 0.0721, 0, 0]
IDENTITY_MATRIX = [1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0]


def color_matrix_of(fe):
    """The 4 x 5 matrix of an feColorMatrix (usvg: a bad or missing ``values`` is identity,
    except that saturate and hueRotate without values mean 1 and 0)."""
    kind = fe.get("type") or "matrix"
    text = fe.get("values")
    values = parse_number_list(text) if text is not None else None
    if values is None and text is not None:
        return IDENTITY_MATRIX        # values that are no number list: usvg's identity
    if kind == "saturate":
        if values is None:
            return IDENTITY_MATRIX
        return saturate_matrix(min(max(values[0], 0.0), 1.0) if values else 1.0)
    if kind == "hueRotate":
        if values is None:
            return IDENTITY_MATRIX
        return hue_rotate_matrix(values[0] if values else 0.0)
    if kind == "luminanceToAlpha":
        return LUMINANCE_TO_ALPHA
    if values is not None and len(values) == 20:
        return values
    return IDENTITY_MATRIX


def convolve_effect(fe):
    """The ConvolveMatrix effect of an feConvolveMatrix, or None when usvg drops the
    primitive (a kernel of the wrong size, a zero divisor, a target outside the kernel).
    kernelUnitLength is not read: kernels step one device pixel, as resvg's, and Filter Effects 1
    takes a negative or zero value (or one that does not parse) as the default."""
    cols = rows = 3
    order = parse_number_list(fe.get("order") or "") or []
    if order:
        x = int(order[0])
        y = int(order[1]) if len(order) > 1 else x
        if x > 0 and y > 0:
            cols, rows = x, y
    values = parse_number_list(fe.get("kernelMatrix") or "") or []
    if len(values) != cols * rows:
        return None
    total = round(sum(values), 6)
    divisor = parse_number(fe.get("divisor"), total if total != 0 else 1.0)
    if divisor == 0:
        return None
    target = []
    for name, n in (("targetX", cols), ("targetY", rows)):
        t = int(parse_number(fe.get(name), float(n // 2)))
        if not 0 <= t < n:
            return None
        target.append(t)
    edge = fe.get("edgeMode") or "duplicate"
    return ConvolveMatrix(tuple(values[r * cols:(r + 1) * cols] for r in range(rows)),
                          tuple(target), divisor, parse_number(fe.get("bias"), 0.0),
                          edge if edge in ("none", "wrap") else "duplicate",
                          (fe.get("preserveAlpha") or "") == "true")


def transfer_function(node):
    kind = node.get("type") or ""
    if kind in ("table", "discrete"):
        # a list that does not parse throughout is no list (the identity), as in resvg
        tokens = re.split(r"[\s,]+", (node.get("tableValues") or "").strip())
        values = tuple(parse_number(t) for t in tokens if t)
        return kind, () if None in values else values
    if kind == "linear":
        return kind, (parse_number(node.get("slope"), 1.0),
                      parse_number(node.get("intercept"), 0.0))
    if kind == "gamma":
        return kind, (parse_number(node.get("amplitude"), 1.0),
                      parse_number(node.get("exponent"), 1.0),
                      parse_number(node.get("offset"), 0.0))
    if kind == "identity":
        return kind, ()
    return None


# -- CSS filter functions ------------------------------------------------------------------
def _amount(args, default=1.0):
    """A number or percentage argument; None when invalid (negative or not a number)."""
    args = args.strip()
    if not args:
        return default
    parsed = split_length(args)
    if parsed is None or parsed[1] not in ("", "%") or parsed[0] < 0:
        return None
    return parsed[0] / 100 if parsed[1] == "%" else parsed[0]


F32_MAX = float(np.finfo(np.float32).max)


def f32_product(length, scale):
    """A length in device pixels where resvg shifts by whole ones (feOffset, drop shadows:
    truncated): the product in f32 as resvg takes it, so -10 x 1.3 is -13 (f32 rounds the
    product to 13.0), not f64's -12.9999995 that truncates to -12. A product past f32's range
    (dx="1e308") saturates at its largest finite value: a shift that far out leaves nothing
    either way, and infinity has no whole number of pixels."""
    with np.errstate(over="ignore"):
        v = float(np.float32(length) * np.float32(scale))
    return v if math.isfinite(v) else math.copysign(F32_MAX, v)


def device_scale(ctx):
    """The factors resvg scales filter lengths by (tiny-skia's get_scale: the row norms in
    f32) of the element's matrix as resvg composes it, each transform in f32 and concatenated
    in f32 (units.f32_chain), not of the f64 product rounded: under rotate(25) at 1.5 px per
    unit the first is 1.5000001, the second 1.5, and a morphology radius of 10 units,
    ceil(15.000001), reaches 16 pixels in resvg."""
    return row_scale_f32(f32_chain(ctx.chain, ctx.transform))


def filter_function(builder, name, args, style, ctx, bbox_fn, input_region=None):
    """Filter for one CSS filter function; None when the element has no bounding box (the
    function is skipped), False when it does not parse (the whole value is ignored).
    ``input_region``: the region of the filter before it in the list, whose result it reads."""
    sx, sy = device_scale(ctx)
    linear = False                      # filter functions work in sRGB
    if name == "blur":
        std = _css_length(builder, args or "0", style, ctx)
        if std is None or std < 0:
            return False
        effect = GaussianBlur(std * sx, std * sy)
    elif name == "drop-shadow":
        effect = _drop_shadow(builder, args, style, ctx, sx, sy)
        if effect is None:
            return False
    elif name in ("grayscale", "sepia", "saturate", "hue-rotate", "invert", "opacity",
                  "brightness", "contrast"):
        if name == "hue-rotate":
            deg = _angle(args)
            if deg is None:
                return False
            effect = ColorMatrix(tuple(hue_rotate_matrix(deg)))
        else:
            amount = _amount(args)
            if amount is None:
                return False
            effect = _amount_effect(name, amount)
    else:
        return False
    bbox = bbox_fn()
    if bbox is None or bbox[2] <= bbox[0] or bbox[3] <= bbox[1]:
        return None
    frac = (-0.5, -0.5, 2.0, 2.0) if name in ("blur", "drop-shadow") else (-0.1, -0.1, 1.2, 1.2)
    bw, bh = bbox[2] - bbox[0], bbox[3] - bbox[1]
    user = (bbox[0] + frac[0] * bw, bbox[1] + frac[1] * bh, frac[2] * bw, frac[3] * bh)
    region = device_rect(*user, ctx.transform)
    if region is None:
        return None
    region = layer_rect(*user, layer_matrix(ctx.transform, region)) or region
    if input_region is not None:
        # Filter Effects 1, "Filter region for shorthands": a function's region covers the
        # visual content it is given, so it does not cut what the filter before it drew (a
        # drop shadow before hue-rotate(); resvg and Chromium keep it whole)
        region = (min(region[0], input_region[0]), min(region[1], input_region[1]),
                  max(region[2], input_region[2]), max(region[3], input_region[3]))
    return Filter(region=region, primitives=[Primitive(effect, (SOURCE_GRAPHIC,), region, linear)])


def _amount_effect(name, amount):
    a = min(amount, 1.0)
    if name == "grayscale":
        return ColorMatrix(tuple(saturate_matrix(1 - a)))
    if name == "sepia":
        k = 1 - a
        return ColorMatrix((
            0.393 + 0.607 * k, 0.769 - 0.769 * k, 0.189 - 0.189 * k, 0, 0,
            0.349 - 0.349 * k, 0.686 + 0.314 * k, 0.168 - 0.168 * k, 0, 0,
            0.272 - 0.272 * k, 0.534 - 0.534 * k, 0.131 + 0.869 * k, 0, 0,
            0, 0, 0, 1, 0))
    if name == "saturate":
        return ColorMatrix(tuple(saturate_matrix(amount)))
    identity = ("identity", ())
    if name == "invert":
        t = ("table", (a, 1 - a))
        return ComponentTransfer((t, t, t, identity))
    if name == "opacity":
        return ComponentTransfer((identity,) * 3 + (("table", (0.0, a)),))
    if name == "brightness":
        t = ("linear", (amount, 0.0))
        return ComponentTransfer((t, t, t, identity))
    t = ("linear", (amount, 0.5 - 0.5 * amount))          # contrast
    return ComponentTransfer((t, t, t, identity))


def _angle(args):
    args = args.strip()
    if not args:
        return 0.0
    m = re.fullmatch(r"([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(deg|grad|rad|turn)?", args)
    if not m:
        return None
    v = float(m.group(1))
    unit = m.group(2) or ("deg" if v == 0 else None)
    if unit is None or not math.isfinite(v):   # 1e400deg overflows: not an angle
        return None
    return v * ANGLE_DEG[unit]


def _css_length(builder, text, style, ctx):
    text = text.strip()
    parsed = split_length(text)
    if parsed is None or parsed[1] == "%":
        return None
    return builder.length(text, "x", style, ctx.viewport)


def _drop_shadow(builder, args, style, ctx, sx, sy):
    """drop-shadow(color? dx dy std?) in any order of colour and lengths."""
    tokens = re.findall(r"[a-zA-Z]+\([^)]*\)|#[0-9a-fA-F]+|[^\s]+", args)
    color, lengths = None, []
    for tok in tokens:
        length = _css_length(builder, tok, style, ctx)
        if length is not None:
            lengths.append(length)
            continue
        c = parse_color(tok)
        if c is None or color is not None:
            return None
        color = c
    if len(lengths) not in (2, 3) or (len(lengths) == 3 and lengths[2] < 0):
        return None
    dx, dy, std = (lengths + [0.0, 0.0, 0.0])[:3]
    if color is None or color == "currentColor":
        color = builder.current_color(style)
    return DropShadow(std * sx, std * sy, f32_product(dx, sx), f32_product(dy, sy),
                      tuple(color))
