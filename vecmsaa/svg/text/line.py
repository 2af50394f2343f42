"""The plain line: a ``<text>`` whose characters are one element's in one font, one chunk
(x and y on the first character at most), left to right, with no spacing, rotation,
textLength, decoration, colour glyph or per-character offset after the first — chart ticks,
map labels, lines of a page — laid out as arrays: HarfBuzz's glyph arrays go to one kernel
(:func:`vecmsaa.fonts.line_kernel.line_glyphs`) that places every glyph and measures the
line's em box, and the placed outlines become one path. No Cluster or Glyph objects.

Everything else, and anything the kernel declines (clusters out of order, non-finite
positions), takes the general route (:func:`.layout.build_text` from the shaping on); so does
a line that reaches past the image when glyphs are culled (``ctx.sampled``), which the
general route culls glyph by glyph. The kernel's arithmetic is the general route's, so both
give the same floats (tests compare them bit for bit).
"""
from __future__ import annotations

from ...fonts.color import has_color_glyphs
from ...fonts.layout import glyph_outlines, placed_outlines
from ...fonts.line_kernel import ANCHORS, line_glyphs
from ...scene.path import Path
from ...scene.transform import IDENTITY, compose, translate
from . import layout as _layout      # (layout imports this module: attributes at call time)
from .draw import _nonzero, _within, decorated, finish_text
from .font_match import face_location
from .svg_glyphs import has_svg_glyphs

#: whether build_text takes this route where it can (tests turn it off to compare)
ENABLED = True
#: the longest line whose shaping is kept for the document (as layout.MEMO_CHUNK)
MEMO_LINE = 16


def plain_line(element, chars, faces, specs, shifts, styles, ctx, text):
    """The scene nodes of a plain line, or None where the general route must draw it.
    ``chars`` are one chunk's, without textPath, in horizontal writing, with no textLength
    or spacing (build_text has checked those)."""
    first = chars[0]
    face, spec, span = faces[0], specs[0], first.span
    n = len(chars)
    if (face is None or ctx.geometry_only or faces.count(face) != n or specs.count(spec) != n
            or shifts.count(shifts[0]) != n
            or any(c.span is not span or c.rotate or c.dx or c.dy for c in chars[1:])
            or first.rotate or has_color_glyphs(face) or has_svg_glyphs(face)
            or decorated(element, span)
            # (bidi: no ASCII character can start a right-to-left run)
            or not text.isascii() and _layout.shaping_runs(text, 0, n, None) != [(0, n, "ltr")]):
        return None
    anchor = ANCHORS.get((styles[id(span.el)].get("text-anchor") or "start").strip(), 0)
    loc = face_location(face, spec)
    memo = ctx.cache.setdefault("plain lines", {}) if n <= MEMO_LINE else None
    key = (text, id(face), id(spec))
    got = memo.get(key) if memo is not None else None
    if got is None:
        run = _layout.shaped_run(face, spec, loc, text, 0, n, "ltr", (0, n))
        owner = _layout.cluster_owners(text, faces, 0, n, run)
        clusters = run.clusters
        if owner:
            clusters = clusters.copy()
            for i, c in enumerate(clusters.tolist()):
                clusters[i] = owner.get(c, c)
        # [.., the glyphs' outlines, joined once (when first drawn) for every line of these
        # characters]
        got = [run.advances, run.offsets, clusters, run.gids, None]
        if memo is not None:
            memo[key] = got
    advances, offsets, clusters, gids, outlines = got
    x = first.x if first.x is not None else 0.0
    y = first.y if first.y is not None else 0.0
    at = compose(IDENTITY, translate(x, y + shifts[0]))
    scale = spec.size / face.units_per_em
    m = face.metrics
    mats, box, ok = line_glyphs(advances, offsets, clusters, float(scale), m.ascender * scale,
                                m.descender * scale, float(first.dx), float(first.dy), anchor,
                                *map(float, at))
    if not ok:
        return None
    bbox = (float(box[0]), float(box[1]), float(box[2]), float(box[3]))
    if ctx.sampled is not None and not _within(bbox, ctx.transform, ctx.sampled):
        return None
    out = []
    style = styles[id(span.el)]
    if style.get("visibility").strip() not in ("hidden", "collapse"):
        if outlines is None:
            outlines = got[4] = glyph_outlines(face, loc, gids.tolist()) or ()
        path = Path.from_arrays(*placed_outlines(outlines or None, mats))
        if not path.is_empty():
            out = _nonzero(ctx.draw(path, style, bbox))
    return finish_text(out, ctx)
