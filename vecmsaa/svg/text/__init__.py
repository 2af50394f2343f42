"""SVG ``<text>``: characters → fonts → HarfBuzz → positioned glyph outlines → scene fills.

The steps follow SVG 1.1 §10 as resvg (usvg) implements them, one module per job:

1. :mod:`.content` — *collect* the characters of ``<text>`` with their innermost element
   (``tspan``, ``tref``, ``textPath``, ``a``), collapsing white space unless
   ``xml:space="preserve"``; *position attributes* ``x``, ``y``, ``dx``, ``dy``, ``rotate``.
2. :mod:`.font_match` — per character, the CSS font properties and family list matched in the
   font database (:mod:`vecmsaa.fonts.db`), with fallback faces for missing characters.
3. :mod:`.layout` — the entry point :func:`build_text`: text chunks (the unit of
   ``text-anchor``), shaping by HarfBuzz (kerning, ligatures, marks, bidi runs) with the
   chunk's text as context, letter/word spacing, baselines, vertical writing, textLength and
   placement along the line.
4. :mod:`.on_path` — ``textPath``: glyph midpoints at arc lengths on the path, turned to its
   tangent.
5. :mod:`.draw` — glyph outlines grouped by element, filled and stroked through the builder
   (``ctx.draw``), colour glyphs, text decorations, the object bounding box.
6. :mod:`.line` — the plain line (one element's characters in one font, one chunk, left to
   right, none of the features above): steps 3 to 5 as arrays, one kernel placing every
   glyph (:mod:`vecmsaa.fonts.line_kernel`), the general route's floats. A ``<text>`` of
   characters alone (a label, a tick, a line of a page) is recognised there from the element
   before steps 1 and 2 make per-character lists (``simple_text``): white space, positions,
   font and face are decided on its string and its computed style. A ``<text>`` of lines of
   one element each (Inkscape's ``<tspan x=.. y=..>`` lines) takes steps 1's characters and
   white space, then is laid out line by line so (``span_lines``).
"""
from .layout import build_text

__all__ = ["build_text"]
