"""Colour glyphs: COLR v0 layers become fills with CPAL palette colours; COLR v1 paint graphs
become fills, gradients and layers (vecmsaa.fonts.colrv1); sbix and CBDT bitmap glyphs become
image fills. A glyph with several representations is drawn from its bitmap, else from COLR.

A COLR v0 glyph is a stack of ordinary outline glyphs, each filled with a palette entry (or with
the text's own paint for entry 0xFFFF). Glyphs without colour layers are gathered into one fill
with the text paint, as in :func:`vecmsaa.fonts.layout.glyphs_path`.
"""
from __future__ import annotations

import numpy as np

from ..diagnostics import warn
from ..scene.transform import IDENTITY
from ..scene.nodes import Fill, Solid
from .colrv1 import colr_v1_glyphs, colr_v1_nodes

FOREGROUND = 0xFFFF


def colr_layers(face) -> dict:
    """gid → [(layer gid, palette index)] for COLR v0 glyphs (of a version 0 table, or the
    version 0 records of a version 1 table); cached on the face."""
    layers = getattr(face, "_colr_layers", None)
    if layers is None:
        layers = {}
        t = face.ttfont
        if "COLR" in t and "CPAL" in t:
            try:
                colr = t["COLR"]
                ids = face.glyph_ids
                if getattr(colr, "version", 0) >= 1:
                    # a version 1 table keeps its version 0 records raw (fontTools only
                    # builds ColorLayers for version 0)
                    table = colr.table
                    recs = table.LayerRecordArray.LayerRecord if table.LayerRecordArray else []
                    for base in (table.BaseGlyphRecordArray.BaseGlyphRecord
                                 if table.BaseGlyphRecordArray else []):
                        if base.BaseGlyph in ids:
                            layers[ids[base.BaseGlyph]] = [
                                (ids.get(r.LayerGlyph, 0), r.PaletteIndex) for r in
                                recs[base.FirstLayerIndex:base.FirstLayerIndex + base.NumLayers]]
                for name, recs in (getattr(colr, "ColorLayers", None) or {}).items():
                    if name in ids:
                        layers[ids[name]] = [(ids.get(r.name, 0), r.colorID) for r in recs]
            except Exception:
                layers = {}
        face._colr_layers = layers
    return layers


def undrawn_color_formats(face) -> tuple:
    """The colour glyph formats of a face that are not drawn in colour: SVG documents, when
    the face has no COLR or bitmap glyphs to draw instead."""
    kinds = getattr(face, "_undrawn_color", None)
    if kinds is None:
        t = face.ttfont
        drawn = "COLR" in t or has_bitmaps(face)
        kinds = face._undrawn_color = ("SVG",) if "SVG " in t and not drawn else ()
    return kinds


def palette_color(face, index: int):
    """Straight RGBA in [0, 1] of an entry of palette 0."""
    cpal = face.ttfont["CPAL"]
    c = cpal.palettes[0][index]
    return (c.red / 255.0, c.green / 255.0, c.blue / 255.0, c.alpha / 255.0)


def has_color_glyphs(face) -> bool:
    """Whether any glyph of the face draws its own colours; cached on the face (asked per
    glyph of every text, where most faces have none)."""
    found = getattr(face, "_has_color", None)
    if found is None:
        found = face._has_color = bool(colr_layers(face) or colr_v1_glyphs(face)
                                       or has_bitmaps(face))
    return found


def is_color_glyph(face, gid) -> bool:
    """Whether a glyph draws its own colours (COLR layers or paints, an sbix/CBDT bitmap)."""
    if not has_color_glyphs(face):
        return False
    gid = int(gid)
    return (gid in colr_layers(face) or gid in colr_v1_glyphs(face)
            or (has_bitmaps(face) and bitmap_glyph(face, gid) is not None))


def color_glyph_fills(face, location, gid, matrix, paint, to_device=IDENTITY) -> list:
    """Scene nodes (fills, and layers for COLR v1 clips and composites) of one colour glyph
    placed by ``matrix`` (font units → user space; ``to_device`` then maps user space to
    device pixels)."""
    from ..scene.transform import compose
    from .layout import glyphs_path

    a, b, c, d = matrix[:4]
    scale = abs(a * d - b * c) ** 0.5
    if has_bitmaps(face) and scale > 0:
        # user units at the glyph origin (y down) → user space
        origin = compose(tuple(matrix), (1 / scale, 0.0, 0.0, -1 / scale, 0.0, 0.0))
        fill = bitmap_fill(face, int(gid), origin, scale * face.units_per_em, to_device)
        if fill is not None:
            return [fill]
    if int(gid) in colr_v1_glyphs(face):
        return colr_v1_nodes(face, location, gid, matrix, paint, to_device)
    fills = []
    for layer_gid, color_index in colr_layers(face).get(int(gid), []):
        path = glyphs_path(face, location, [layer_gid], [matrix])
        if path.is_empty():
            continue
        layer_paint = paint if color_index == FOREGROUND else Solid(
            palette_color(face, color_index))
        fills.append(Fill(path.transformed(to_device), layer_paint))
    return fills


def color_fills(face, location, gids, matrices, paint) -> list:
    """Fills for glyphs placed by ``matrices`` (see :func:`layout.placement`): plain glyphs
    share one fill with ``paint``, colour glyphs add their own."""
    from .layout import glyphs_path

    for kind in undrawn_color_formats(face):
        warn(f"font '{face.family}': {kind} colour glyphs are drawn as plain outlines")
    gids = np.asarray(gids)
    matrices = np.asarray(matrices, dtype=np.float64).reshape(-1, 6)
    if not colr_layers(face) and not colr_v1_glyphs(face) and not has_bitmaps(face):
        path = glyphs_path(face, location, gids, matrices)
        return [] if path.is_empty() else [Fill(path, paint)]
    colored = np.array([is_color_glyph(face, g) for g in gids], dtype=bool)
    fills = []
    if (~colored).any():
        path = glyphs_path(face, location, gids[~colored], matrices[~colored])
        if not path.is_empty():
            fills.append(Fill(path, paint))
    for i in np.nonzero(colored)[0]:
        fills.extend(color_glyph_fills(face, location, gids[i], matrices[i], paint))
    return fills


def bitmap_glyph(face, gid):
    """Bitmap of a glyph from its biggest sbix or CBDT strike: (premultiplied float RGBA
    (H, W, 4), x, y, ppem) with (x, y) the image's bottom-left corner in strike pixels from the
    glyph origin (y up), or None."""
    cache = getattr(face, "_bitmaps", None)
    if cache is None:
        cache = face._bitmaps = {}
    if gid in cache:
        return cache[gid]
    cache[gid] = found = _read_bitmap(face, gid)
    return found


def has_bitmaps(face) -> bool:
    return "sbix" in face.ttfont or "CBDT" in face.ttfont


def _read_bitmap(face, gid):
    t = face.ttfont
    if not 0 <= gid < face.num_glyphs:
        return None
    name = face.glyph_order[gid]
    data = None
    try:
        if "sbix" in t:
            for strike in sorted(t["sbix"].strikes.values(), key=lambda s: -s.ppem):
                g = strike.glyphs.get(name)
                if g is not None and g.graphicType in ("png ", "jpg ", "tiff") and g.imageData:
                    data, x, y, ppem = g.imageData, g.originOffsetX, g.originOffsetY, strike.ppem
                    break
        elif "CBDT" in t and "CBLC" in t:
            strikes = t["CBLC"].strikes
            order = sorted(range(len(strikes)), key=lambda i: -strikes[i].bitmapSizeTable.ppemX)
            for i in order:
                g = t["CBDT"].strikeData[i].get(name)
                if g is None or not getattr(g, "imageData", None):
                    continue
                m = g.metrics
                data, x, y = g.imageData, m.BearingX, m.BearingY - m.height
                ppem = strikes[i].bitmapSizeTable.ppemX
                break
    except Exception:
        return None
    if data is None:
        return None
    import io

    from PIL import Image
    try:
        with Image.open(io.BytesIO(data)) as im:
            rgba = np.asarray(im.convert("RGBA"), dtype=np.float32) / 255.0
    except Exception:
        return None
    rgba[..., :3] *= rgba[..., 3:4]
    return rgba, float(x), float(y), float(ppem)


def bitmap_fill(face, gid, origin_matrix, size, to_device):
    """An image fill of a bitmap glyph, or None. ``origin_matrix`` maps user units at the
    glyph origin (y down) to user space; ``to_device`` maps user space to device pixels.

    The image is scaled by size/ppem with its bottom-left corner at the strike offset. An
    sbix glyph that also has an outline sits on that outline's lowest point, as resvg (0.48)
    draws it (measured on the suite's CFF-and-SBIX font)."""
    from ..scene.transform import compose, invert
    from ..scene.path import rect_path
    from ..scene.nodes import ImagePaint

    found = bitmap_glyph(face, gid)
    if found is None:
        return None
    rgba, x, y, ppem = found
    h, w = rgba.shape[:2]
    k = size / ppem
    bottom = -y * k
    if "sbix" in face.ttfont:
        _, pts = face.outline(gid)
        if len(pts):
            bottom -= float(pts[:, 1].min()) * size / face.units_per_em
    m = compose(to_device, compose(origin_matrix, (k, 0.0, 0.0, k, x * k, bottom - h * k)))
    try:
        inverse = invert(m)
    except ValueError:
        return None
    return Fill(rect_path(0.0, 0.0, float(w), float(h)).transformed(m),
                ImagePaint(rgba, to_paint=inverse, smooth=True))

