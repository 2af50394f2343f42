"""SVG-in-OpenType colour glyphs (the ``SVG `` table, OpenType 1.8): a glyph's SVG document
is drawn by vecmsaa's own SVG builder.

As the OpenType specification sets it up, the element with id ``glyph<gid>`` (the document's
root or any element in it) is drawn in the glyph's coordinate system: font units, origin at
the glyph origin, y down, in an em-square viewport. A document may hold many glyphs; each is
parsed once per face. A document that cannot be read leaves the glyph to its outline.
"""
from __future__ import annotations

from ...diagnostics import warn
from ...scene.transform import compose
from ..builder import Ctx, Options
from ..resources import Resources
from ..sizing import open_svg

#: a glyph document bigger than this (bytes, after decompression) is not drawn
MAX_DOCUMENT = 1 << 22


def _documents(face):
    """gid → index into the SVG table's documents; cached on the face."""
    found = getattr(face, "_svg_glyphs", None)
    if found is None:
        found = {}
        t = face.ttfont
        try:
            if "SVG " in t:
                for i, doc in enumerate(t["SVG "].docList):
                    for gid in range(doc.startGlyphID, doc.endGlyphID + 1):
                        found.setdefault(gid, i)
        except Exception:
            found = {}
        face._svg_glyphs = found
        face._svg_parsed = {}
    return found


def has_svg_glyph(face, gid) -> bool:
    return int(gid) in _documents(face)


def has_svg_glyphs(face) -> bool:
    """Whether the face has any glyph drawn by an SVG document."""
    return bool(_documents(face))


def _parsed(face, index):
    cache = face._svg_parsed
    if index not in cache:
        cache[index] = None
        try:
            data = face.ttfont["SVG "].docList[index].data
            data = data.encode("utf-8") if isinstance(data, str) else bytes(data)
            if len(data) <= MAX_DOCUMENT:
                # like an SVG image: data: URLs only, no files
                cache[index] = open_svg(data, None, Resources(), Options(image_nesting=1),
                                         whole_pixels=False)
        except Exception:     # a broken document: the glyph keeps its outline
            cache[index] = None
        if cache[index] is None:
            warn(f"font '{face.family}': SVG glyph document {index} cannot be read: "
                 "drawn as outlines")
    return cache[index]


def svg_glyph_nodes(face, gid, matrix, to_device):
    """Scene nodes of glyph ``gid``'s SVG description placed by ``matrix`` (font units, y up →
    user space) and ``to_device``, or None when the glyph has none that can be drawn."""
    index = _documents(face).get(int(gid))
    if index is None:
        return None
    sized = _parsed(face, index)
    if sized is None:
        return None
    builder = sized.builder
    el = builder.doc.ids.get(f"glyph{int(gid)}")
    if el is None:
        return None
    transform = compose(tuple(to_device), compose(tuple(matrix), (1.0, 0.0, 0.0, -1.0, 0.0, 0.0)))
    upem = float(face.units_per_em)
    try:
        if el is builder.doc.root:
            return builder.build_root(transform, (upem, upem))
        return builder.element(el, Ctx(transform=transform, viewport=(upem, upem)),
                               builder.doc.document_style(el.parent))
    except Exception:          # SvgError (a document too big or too deep): the outline
        return None
