"""Text on a path: clusters placed at arc lengths along a ``textPath``'s path, as resvg does."""
from __future__ import annotations

import math

from ...geometry.arclength import PathWalker
from ...scene.transform import compose, rotate_at, translate
from ..shapes import author_path_length
from .content import href_target


def path_walker(text_path, ctx):
    """The walker along a textPath's path, or None when the textPath is in error: its href
    names no path or basic shape, or an empty one, or one with infinite coordinates (or a
    length that overflows)."""
    target = href_target(text_path)
    path = ctx.path_of(target) if target is not None else None
    if path is None or path.is_empty():
        return None
    a, b, cc, d = ctx.transform[:4]
    # resvg's tolerance follows the text's transform in the SVG's own units, before the
    # output is scaled to its pixel size: divide that scaling out.
    walker = PathWalker(path, math.sqrt(math.hypot(a, b)) * math.sqrt(math.hypot(cc, d)) / ctx.root_scale)
    return walker if math.isfinite(walker.length) else None


def start_offset(text_path, walker, ctx, style):
    """startOffset as an arc length along the walker's path. A percentage is of the whole
    path. The path's ``pathLength`` calibrates distances along it (SVG 2 paths, "pathLength":
    the user agent scales them by its own length over the author's; 0 is an infinite scale
    under which 0 stays 0 and any other distance leaves the path), so a length is in the
    author's units and a percentage is of ``pathLength`` before that scaling."""
    target = href_target(text_path)
    author = author_path_length(target) if target is not None else None
    offset = 0.0
    raw = text_path.get("startOffset")
    if raw is not None:
        raw = raw.strip()
        if raw.endswith("%"):
            try:
                offset = float(raw[:-1]) / 100 * (walker.length if author is None else author)
            except ValueError:
                offset = 0.0
            if not math.isfinite(offset):
                offset = 0.0
        else:
            offset = ctx.length(raw, "x", style, 0.0) or 0.0
    if author is None or offset == 0.0:
        return offset
    if author == 0.0:
        return math.copysign(math.inf, offset)
    return offset * walker.length / author


def position_on_path(clusters, chars, text_path, walker, start, ctx, styles, shifts):
    """Clusters along a textPath (``walker`` along its path) from arc length ``start`` (the
    chunk's x moved by its text-anchor) plus startOffset: each cluster's midpoint on the path,
    turned to its tangent, then moved off the path by dy and baseline shifts; returns the pen
    at the end."""
    style = styles.get(id(text_path), ctx.style)
    offset = start_offset(text_path, walker, ctx, style)
    advance = start + offset
    dy = 0.0
    last = (0.0, 0.0)
    for c in clusters:
        ch = chars[c.char]
        advance += ch.dx * c.sx      # (squeezed with its cluster by spacingAndGlyphs)
        # placed and turned at the middle of its widest glyph (as resvg, whose cluster width
        # is that glyph's; the pen moves by the whole advance)
        hw = c.widest / 2
        at = walker.at(advance + hw)
        advance += c.advance + c.carry[0] * c.sx
        dy += ch.dy
        if at is None:
            c.visible = False
            dy += c.carry[1]
            continue
        px, py, ang = at
        frame = compose(translate(px - hw, py), rotate_at(ang, hw, 0.0))
        frame = compose(frame, translate(0.0, dy + shifts[c.char]))
        if ch.rotate:
            frame = compose(frame, rotate_at(ch.rotate, 0.0, 0.0))
        c.frame = compose(frame, compose(c.pre, (c.sx, 0.0, 0.0, 1.0, 0.0, 0.0)))
        c.shifted = True
        dy += c.carry[1]
        last = (px + c.advance, py)
    return last
