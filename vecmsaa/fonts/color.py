"""Colour glyphs: COLR v0 layers become fills with CPAL palette colours.

A COLR v0 glyph is a stack of ordinary outline glyphs, each filled with a palette entry (or with
the text's own paint for entry 0xFFFF). Glyphs without colour layers are gathered into one fill
with the text paint, as in :func:`vecmsaa.fonts.layout.glyphs_path`.
"""
from __future__ import annotations

import numpy as np

from ..scene import Fill, Solid

FOREGROUND = 0xFFFF


def colr_layers(face) -> dict:
    """gid → [(layer gid, palette index)] for COLR v0 glyphs; cached on the face."""
    layers = getattr(face, "_colr_layers", None)
    if layers is None:
        layers = {}
        t = face.ttfont
        if "COLR" in t and "CPAL" in t:
            try:
                colr = t["COLR"]
                ids = face.glyph_ids
                for name, recs in (getattr(colr, "ColorLayers", None) or {}).items():
                    if name in ids:
                        layers[ids[name]] = [(ids.get(r.name, 0), r.colorID) for r in recs]
            except Exception:
                layers = {}
        face._colr_layers = layers
    return layers


def palette_color(face, index: int):
    """Straight RGBA in [0, 1] of an entry of palette 0."""
    cpal = face.ttfont["CPAL"]
    c = cpal.palettes[0][index]
    return (c.red / 255.0, c.green / 255.0, c.blue / 255.0, c.alpha / 255.0)


def color_fills(face, location, gids, matrices, paint) -> list:
    """Fills for glyphs placed by ``matrices`` (see :func:`layout.placement`)."""
    from .layout import glyphs_path

    gids = np.asarray(gids)
    matrices = np.asarray(matrices, dtype=np.float64).reshape(-1, 6)
    layers = colr_layers(face)
    if not layers:
        path = glyphs_path(face, location, gids, matrices)
        return [] if path.is_empty() else [Fill(path, paint)]
    colored = np.array([int(g) in layers for g in gids], dtype=bool)
    fills = []
    if (~colored).any():
        path = glyphs_path(face, location, gids[~colored], matrices[~colored])
        if not path.is_empty():
            fills.append(Fill(path, paint))
    for i in np.nonzero(colored)[0]:
        for layer_gid, color_index in layers[int(gids[i])]:
            path = glyphs_path(face, location, [layer_gid], matrices[i:i + 1])
            if path.is_empty():
                continue
            layer_paint = paint if color_index == FOREGROUND else Solid(
                palette_color(face, color_index))
            fills.append(Fill(path, layer_paint))
    return fills


__all__ = ["color_fills", "colr_layers", "palette_color"]
