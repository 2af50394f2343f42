"""Placing shaped glyphs in device space and turning them into scene fills.

All glyphs that share a paint become ONE :class:`~vecmsaa.scene.path.Path`: the cached font-unit
outlines are concatenated and transformed with numpy in one go (a glyph costs a dict lookup,
not a Python loop over its points), so a page of thousands of glyphs is one fill and one
raster pass.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene.path import Path
from ..scene.transform import apply_each
from ..scene.nodes import Solid
from .shape import ShapedRun, shape_text


def placement(origins, scale: float, skew: float = 0.0) -> np.ndarray:
    """(N, 6) matrices mapping font units (y up) to device pixels (y down) at each origin.

    ``skew`` is tan(angle) of a synthetic oblique (positive leans right).
    """
    origins = np.asarray(origins, dtype=np.float64).reshape(-1, 2)
    m = np.zeros((len(origins), 6))
    m[:, 0] = scale
    m[:, 2] = -skew * scale
    m[:, 3] = -scale
    m[:, 4:] = origins
    return m


def glyphs_arrays(face, location, gids, matrices):
    """Concatenated (verbs, points) of many glyphs, glyph i transformed by matrices[i]."""
    outlines = glyph_outlines(face, location, gids)
    if outlines is None:
        return np.zeros(0, np.uint8), np.zeros((0, 2))
    verbs, points, counts = outlines
    return verbs, _placed(points, counts, matrices)


def glyph_outlines(face, location, gids):
    """The font-unit outlines of glyphs ``gids`` one after the other: (verbs, points, each
    glyph's point count), or None when all are empty (a caller placing one line's glyphs
    many times keeps them: svg.text.line)."""
    outline = face.outline
    outlines = [outline(int(gid), location) for gid in gids]
    counts = [len(p) for _, p in outlines]
    if not sum(counts):
        return None
    return (np.concatenate([v for v, _ in outlines]), np.concatenate([p for _, p in outlines]),
            np.array(counts, dtype=np.int64))


def placed_outlines(outlines, matrices):
    """(verbs, points) of glyph_outlines' ``outlines``, glyph i mapped by matrices[i] (new
    arrays: the verbs are copied)."""
    if outlines is None:
        return np.zeros(0, np.uint8), np.zeros((0, 2))
    verbs, points, counts = outlines
    return verbs.copy(), _placed(points, counts, matrices)


def _placed(points, counts, matrices):
    return apply_each(np.asarray(matrices, dtype=np.float64).reshape(-1, 6), counts, points)


def glyphs_path(face, location, gids, matrices) -> Path:
    """One Path holding every glyph, glyph i placed by matrices[i] (see :func:`placement`)."""
    return Path.from_arrays(*glyphs_arrays(face, location, gids, matrices))


@dataclass
class GlyphRunLayout:
    """Shaped glyphs of one face with their pen positions in device pixels."""
    face: object
    location: tuple
    gids: np.ndarray
    origins: np.ndarray      # (N, 2) device px, relative to the line origin (baseline, left)
    clusters: np.ndarray
    scale: float             # device px per font unit


@dataclass
class LineLayout:
    """A shaped line: glyph runs and the box of the line relative to its baseline origin."""
    runs: list
    advance: float           # total advance in px (x for horizontal, y for vertical)
    ascent: float            # px above the baseline (positive)
    descent: float           # px below the baseline (positive)
    size: float
    vertical: bool = False


def place_runs(runs: list[ShapedRun], size: float, letter_spacing: float = 0.0):
    """Pen positions for shaped runs laid end to end from (0, 0); returns (layouts, advance)."""
    out = []
    pen = np.zeros(2)
    for run in runs:
        scale = size / run.face.units_per_em
        adv = run.advances * scale
        off = run.offsets * scale
        if letter_spacing:
            adv = adv.copy()
            adv[:, 0] += np.where(run.advances[:, 0] != 0, letter_spacing, 0.0)
        # HarfBuzz is y up; device is y down.
        adv[:, 1] *= -1
        off[:, 1] *= -1
        starts = pen + np.concatenate([np.zeros((1, 2)), np.cumsum(adv, axis=0)[:-1]]) \
            if len(adv) else np.zeros((0, 2))
        out.append(GlyphRunLayout(run.face, run.location, run.gids, starts + off,
                                  run.clusters, scale))
        if len(adv):
            pen = pen + adv.sum(axis=0)
    return out, pen


def layout_line(face, text: str, size: float, *, location=(), features=None, direction=None,
                script=None, language=None, letter_spacing: float = 0.0) -> LineLayout:
    """Shape and place one line of text in one face at ``size`` px per em."""
    location = face.clamp_location(location)
    runs = shape_text(face, text, location=location, features=features, direction=direction,
                      script=script, language=language)
    layouts, pen = place_runs(runs, size, letter_spacing)
    m = face.metrics
    scale = size / face.units_per_em
    vertical = direction in ("ttb", "btt")
    return LineLayout(layouts, float(abs(pen[1]) if vertical else pen[0]),
                      m.ascender * scale, -m.descender * scale, size, vertical)


def run_placements(line: LineLayout, origin=(0.0, 0.0), skew: float = 0.0):
    """(run, (N, 6) glyph matrices) of a laid-out line with its baseline origin at ``origin``.
    """
    origin = np.asarray(origin, dtype=np.float64)
    for run in line.runs:
        yield run, placement(run.origins + origin, run.scale, skew)


def line_fills(line: LineLayout, origin=(0.0, 0.0), paint=None, skew: float = 0.0) -> list:
    """Scene fills drawing a laid-out line with its baseline origin at ``origin``.

    Plain glyphs of a face share one Fill; colour glyphs add their own (fonts.color).
    """
    from .color import color_fills

    paint = paint if paint is not None else Solid()
    fills = []
    for run, matrices in run_placements(line, origin, skew):
        fills.extend(color_fills(run.face, run.location, run.gids, matrices, paint))
    return fills
