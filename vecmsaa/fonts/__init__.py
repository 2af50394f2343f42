"""Fonts: faces and cached glyph outlines (fontTools), shaping (HarfBuzz), layout into scenes.

``load_face(path, index)`` gives a :class:`Face`; ``layout_line`` shapes and places one line;
``line_fills`` turns it into scene fills. The font database for CSS font matching lives in
:mod:`vecmsaa.fonts.db`.
"""
from __future__ import annotations

from .face import Face, FontError, FontWarning, Metrics, load_face, face_count, parse_variations
from .layout import (LineLayout, glyphs_arrays, glyphs_path, layout_line, line_fills, place_runs,
                     placement)
from .shape import ShapedRun, parse_features, shape_text

__all__ = ["Face", "FontError", "FontWarning", "Metrics", "load_face", "face_count", "parse_variations",
           "LineLayout", "glyphs_arrays", "glyphs_path", "layout_line", "line_fills",
           "place_runs", "placement", "ShapedRun", "parse_features", "shape_text"]
