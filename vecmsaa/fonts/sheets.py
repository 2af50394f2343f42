"""Scenes for the ``vecmsaa font`` command: one line, a waterfall, a glyph grid, a specimen.

Each builder returns a :class:`vecmsaa.scene.nodes.Scene` sized to its content. Text is collected in
a :class:`GlyphBatch` so that a whole sheet -- thousands of glyphs and their labels -- becomes a
few fills (one per face and paint) and is rasterised in one pass.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..scene.path import CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path, rect_path
from ..scene.nodes import Fill, Group, Scene, Solid
from .color import color_fills
from .face import FontError
from .layout import LineLayout, layout_line, placement, run_placements

LABEL_GRAY = (0.45, 0.45, 0.45, 1.0)
RULE_GRAY = (0.82, 0.82, 0.82, 1.0)


@dataclass
class GlyphBatch:
    """Glyphs gathered from many lines, drawn as one fill per (face, location, paint)."""
    groups: dict = field(default_factory=dict)

    def add_glyphs(self, face, location, gids, matrices, color):
        key = (id(face), location, tuple(color))
        entry = self.groups.setdefault(key, (face, location, color, [], []))
        entry[3].append(np.asarray(gids, dtype=np.int64).reshape(-1))
        entry[4].append(np.asarray(matrices, dtype=np.float64).reshape(-1, 6))

    def add_line(self, line: LineLayout, origin, color):
        for run, matrices in run_placements(line, origin):
            self.add_glyphs(run.face, run.location, run.gids, matrices, color)

    def fills(self) -> list:
        out = []
        for face, location, color, gids, mats in self.groups.values():
            out.extend(color_fills(face, location, np.concatenate(gids), np.concatenate(mats),
                                   Solid(tuple(color))))
        return out


def _rules(rects, color) -> list:
    """Thin guide rectangles (x, y, w, h) as one fill."""
    if not rects:
        return []
    path = Path()
    for r in rects:
        path.extend(rect_path(*r))
    return [Fill(path, Solid(tuple(color)))]


#: the largest sheet: as for SVG output, 32768 px per side and 2^28 pixels in all
MAX_SIDE = 32768
MAX_PIXELS = 1 << 28


def _scene(width, height, fills, background) -> Scene:
    w, h = max(1, int(math.ceil(width))), max(1, int(math.ceil(height)))
    if w > MAX_SIDE or h > MAX_SIDE or w * h > MAX_PIXELS:
        raise FontError(f"the image would be {w}x{h} px, over the limit of {MAX_SIDE} px per "
                        f"side and {MAX_PIXELS} pixels (less text, fewer sizes or a smaller "
                        "size or margin)")
    return Scene(w, h, Group(list(fills)), tuple(background))


def default_margin(size: float) -> float:
    return max(2.0, round(size * 0.125))


def line_scene(face, text, size, *, foreground=(0, 0, 0, 1), background=(1, 1, 1, 1),
               margin=None, **shaping) -> Scene:
    """Exactly one line: the image is the line's ascender/descender box plus a margin."""
    margin = default_margin(size) if margin is None else float(margin)
    line = layout_line(face, text, size, **shaping)
    batch = GlyphBatch()
    if line.vertical:
        column = line.ascent + line.descent
        # Vertical text: the pen moves down from the top; the box is one em column wide.
        origin = (margin + column / 2, margin)
        batch.add_line(line, origin, foreground)
        return _scene(column + 2 * margin, line.advance + 2 * margin, batch.fills(), background)
    batch.add_line(line, (margin, margin + line.ascent), foreground)
    return _scene(line.advance + 2 * margin, line.ascent + line.descent + 2 * margin,
                  batch.fills(), background)


def waterfall_scene(face, text, sizes, label_face, *, foreground=(0, 0, 0, 1),
                    background=(1, 1, 1, 1), label_size=11.0, **shaping) -> Scene:
    """The same text at several sizes, one row each, labelled with the size in px."""
    batch = GlyphBatch()
    margin = 8.0
    labels = [layout_line(label_face, f"{_fmt(s)} px", label_size) for s in sizes]
    label_width = max((lb.advance for lb in labels), default=0.0) + 12.0
    y = margin
    width = 0.0
    for size, label in zip(sizes, labels):
        line = layout_line(face, text, size, **shaping)
        baseline = y + line.ascent
        batch.add_line(line, (margin + label_width, baseline), foreground)
        batch.add_line(label, (margin, baseline), LABEL_GRAY)
        width = max(width, label_width + line.advance)
        y = baseline + line.descent + max(4.0, size * 0.15)
    return _scene(width + 2 * margin, y + margin - 4.0, batch.fills(), background)


def glyph_pages(num_glyphs: int, per_page: int) -> int:
    return max(1, -(-num_glyphs // per_page))


def glyph_grid_scene(face, label_face, *, page=1, columns=16, per_page=256, glyph_size=40.0,
                     location=(), foreground=(0, 0, 0, 1), background=(1, 1, 1, 1)) -> Scene:
    """Every glyph of the face in a grid, labelled with glyph name and code point; ``page`` is
    1-based and holds ``per_page`` glyphs."""
    location = face.clamp_location(location)
    pages = glyph_pages(face.num_glyphs, per_page)
    if not 1 <= page <= pages:
        raise ValueError(f"page {page} out of range: the font has {pages} page(s) of "
                         f"{per_page} glyphs")
    first = (page - 1) * per_page
    gids = np.arange(first, min(first + per_page, face.num_glyphs))
    label_size = max(7.0, glyph_size * 0.2)
    m = face.metrics
    scale = glyph_size / face.units_per_em
    ascent, descent = m.ascender * scale, -m.descender * scale
    cell_w = glyph_size * 1.9
    cell_h = ascent + descent + 2.6 * label_size + 10.0
    margin = 8.0
    rows = -(-len(gids) // columns)
    batch = GlyphBatch()
    col = gids - first
    cx = margin + (col % columns) * cell_w
    cy = margin + (col // columns) * cell_h
    advances = np.array([face.advance(int(g), location) for g in gids]) * scale
    origins = np.stack([cx + (cell_w - advances) / 2, cy + 4.0 + ascent], axis=1)
    batch.add_glyphs(face, location, gids, placement(origins, scale), foreground)
    rev = face.reverse_cmap
    max_label = cell_w - 4.0
    for i, gid in enumerate(gids):
        name = face.glyph_order[int(gid)]
        cp = rev.get(int(gid))
        y0 = cy[i] + 4.0 + ascent + descent + 1.1 * label_size
        for k, text in enumerate((name, f"U+{cp:04X}" if cp is not None else "")):
            if not text:
                continue
            line = layout_line(label_face, text, label_size)
            while line.advance > max_label and len(text) > 2:
                text = text[:max(1, int(len(text) * max_label / line.advance)) - 1] + "…"
                line = layout_line(label_face, text, label_size)
            batch.add_line(line, (cx[i] + (cell_w - line.advance) / 2,
                                  y0 + k * 1.2 * label_size), LABEL_GRAY)
    grid_w = columns * cell_w if len(gids) >= columns else len(gids) * cell_w
    # the rules cross, and exact_area_sheet unites them
    n_cols = int(round(grid_w / cell_w))
    rules = [(margin + c * cell_w, margin, 0.5, rows * cell_h + 0.5) for c in range(n_cols + 1)]
    rules += [(margin, margin + r * cell_h, grid_w + 0.5, 0.5) for r in range(rows + 1)]
    fills = _rules(rules, RULE_GRAY) + batch.fills()
    return _scene(grid_w + 2 * margin + 0.5, rows * cell_h + 2 * margin + 0.5, fills,
                  background)


SPECIMEN_LINES = ("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz",
                  "0123456789 .,:;!?&@#%()[]", "The quick brown fox jumps over the lazy dog.")


def sample_text(face, length=40) -> str:
    """Characters the face has: the pangram when it covers it, else its first code points."""
    pangram = SPECIMEN_LINES[3]
    if all(face.has_char(c) for c in pangram if c != " "):
        return pangram
    cps = [cp for cp in sorted(face.cmap) if cp > 0x20 and chr(cp).isprintable()]
    return "".join(chr(c) for c in cps[:length]) or pangram


def specimen_scene(face, label_face, *, location=(), foreground=(0, 0, 0, 1),
                   background=(1, 1, 1, 1), **shaping) -> Scene:
    """Family, style and metrics of the face, a metrics diagram, and samples at many sizes."""
    location = face.clamp_location(location)
    m = face.metrics
    batch = GlyphBatch()
    margin = 16.0
    y = margin
    width = 0.0
    rules = []

    def label(text, size, color=LABEL_GRAY, fc=label_face, x=margin):
        nonlocal y, width
        line = layout_line(fc, text, size, location=location if fc is face else ())
        y += line.ascent
        batch.add_line(line, (x, y), color)
        width = max(width, x + line.advance)
        y += line.descent + size * 0.3

    title_face = face if all(face.has_char(c) for c in face.family if c != " ") else label_face
    label(face.family, 36, foreground, title_face)
    axes = [f"{t} {lo:g}–{hi:g} (default {d:g})" for t, (lo, d, hi) in face.axes.items()]
    label(f"{face.subfamily} · weight {face.weight} · {face.style} · stretch {face.stretch:g}% · "
          f"{face.num_glyphs} glyphs · {_outline_kind(face)}", 13)
    label(f"units per em {m.units_per_em} · ascender {m.ascender:g} · descender "
          f"{m.descender:g} · line gap {m.line_gap:g} · x-height {m.x_height:g} · "
          f"cap height {m.cap_height:g}", 13)
    for k in range(0, len(axes), 5):
        label(("axes: " if k == 0 else "") + ", ".join(axes[k:k + 5]), 13)
    if location:
        label("location: " + ", ".join(f"{t}={v:g}" for t, v in location), 13)
    y += 10
    # Metrics diagram: sample glyphs with guide lines at the vertical metrics.
    size = 120.0
    scale = size / m.units_per_em
    diagram = "Hxgé" if all(face.has_char(c) for c in "Hxgé") else sample_text(face, 4)[:4]
    line = layout_line(face, diagram, size, location=location, **shaping)
    baseline = y + m.ascender * scale
    x0 = margin + 90.0
    batch.add_line(line, (x0, baseline), foreground)
    guide_w = line.advance + 20.0
    for name, value in (("ascender", m.ascender), ("cap height", m.cap_height),
                        ("x-height", m.x_height), ("baseline", 0.0),
                        ("descender", m.descender)):
        gy = baseline - value * scale
        rules.append((x0 - 10.0, gy - 0.25, guide_w, 0.5))
        lab = layout_line(label_face, name, 10)
        batch.add_line(lab, (x0 - 14.0 - lab.advance, gy + 3.5), LABEL_GRAY)
    width = max(width, x0 + guide_w)
    y = baseline - m.descender * scale + 16.0
    sample = sample_text(face)
    lines = [s for s in SPECIMEN_LINES[:3] if all(face.has_char(c) for c in s if c != " ")]
    for s in lines:
        label(s, 24, foreground, face)
    for px in (10, 12, 14, 18, 24, 36, 48):
        line = layout_line(face, sample, px, location=location, **shaping)
        lab = layout_line(label_face, f"{px}", 10)
        y += line.ascent
        batch.add_line(lab, (margin, y), LABEL_GRAY)
        batch.add_line(line, (margin + 30.0, y), foreground)
        width = max(width, margin + 30.0 + line.advance)
        y += line.descent + 6.0
    fills = _rules(rules, RULE_GRAY) + batch.fills()
    return _scene(width + margin, y + margin, fills, background)


def _outline_kind(face) -> str:
    t = face.ttfont
    kind = "CFF2" if "CFF2" in t else "CFF" if "CFF " in t else "TrueType" if "glyf" in t \
        else "bitmap"
    if face.axes:
        kind += " variable"
    if "COLR" in t:
        kind += ", COLR"
    return kind


def _fmt(size) -> str:
    return f"{size:g}"


# --- the default coverage mode of a sheet ------------------------------------------------------

#: tables of colour glyphs (layers, paints, bitmaps, SVG documents)
COLOR_TABLES = ("COLR", "sbix", "CBDT", "SVG ")


def exact_area_sheet(scene: Scene, face) -> Scene | None:
    """The sheet redrawn so that exact-area coverage per path (the ``analytic`` mode, what
    FreeType computes: 0.1-0.4% worst per-glyph ink at 10-16 px against 7-28% with 8 samples,
    docs/fonts.md) is exact for it, or None where it cannot be.

    Exact area per path is exact only where no point is covered twice. Within a fill (joined
    scripts, stacked marks, composite glyphs, overlapping contours of variable fonts)
    signed-area accumulation counts the pixels both edges cross twice, so each fill's outline
    is replaced by its union (skia-pathops, the overlap removal fontTools uses). Between
    fills (a specimen's guide lines under its glyphs) per-pixel compositing is exact except
    where a line's edge and a glyph's edge cross one pixel: 8/255 at worst on specimens,
    against 71/255 for 8 samples. Colour glyphs (layers that abut), translucent, gradient
    and aliased fills: None, and the MSAA modes are exact per sample."""
    fills = scene.fills()
    if any(tag in face.ttfont for tag in COLOR_TABLES) or any(
            not isinstance(f.paint, Solid) or f.opacity != 1.0 or not f.antialias
            for f in fills):
        return None
    united = [_union(f.path, f.rule) for f in fills]
    if any(p is None for p in united):
        return None
    return Scene(scene.width, scene.height,
                 Group([Fill(p, f.paint) for f, p in zip(fills, united)]), scene.background)


#: contours stacked on one box (to 1/16 px), and contours in one cluster, beyond which a fill
#: is not united (the sheet keeps approx): Skia's simplify takes 2.4 s for 32 coincident
#: copies of one curved contour and 80 s for 64 (stacked combining marks, composite fan-out)
MAX_STACKED_CONTOURS = 4
MAX_CLUSTER_CONTOURS = 2048


def _union(path: Path, rule: str) -> Path | None:
    """The outline covering what ``path`` covers under ``rule``, with no point covered twice;
    None where Skia's path ops give up (degenerate input) or would take too long (contours
    stacked on one another, MAX_STACKED_CONTOURS). Contours are united in clusters whose
    boxes meet: Skia's simplify grows faster than linearly with a path's size (a whole
    256-glyph grid in one call takes 20 s, glyph by glyph 0.4 s)."""
    import pathops      # here, not at the top: 50 ms of import only font sheets need

    v, p = path.verbs, path.points
    if not len(v):
        return path
    count = np.asarray(VERB_POINTS)[v]
    first_point = np.append(np.cumsum(count) - count, len(p))
    starts = np.append(np.flatnonzero(v == MOVE), len(v))
    fill_type = pathops.FillType.WINDING if rule == "nonzero" else pathops.FillType.EVEN_ODD
    groups = _clusters(p, first_point[starts])
    if groups is None or max(map(len, groups)) > MAX_CLUSTER_CONTOURS:
        return None
    out = Path()
    for group in groups:
        sk = pathops.Path(fillType=fill_type)
        for c in group:
            _add_contour(sk, v[starts[c]:starts[c + 1]].tolist(),
                         p[first_point[starts[c]]:first_point[starts[c + 1]]].tolist())
        try:
            sk.simplify(fix_winding=True, keep_starting_points=False)
        except pathops.PathOpsError:
            return None
        sk.draw(out)
    return out


def _add_contour(sk, verbs, pts):
    """One contour into a skia-pathops Path, by its own calls (a pen costs 3x as much)."""
    i = 0
    for verb in verbs:
        if verb == MOVE or verb == LINE:
            (sk.moveTo if verb == MOVE else sk.lineTo)(*pts[i])
            i += 1
        elif verb == QUAD:
            sk.quadTo(*pts[i], *pts[i + 1])
            i += 2
        elif verb == CUBIC:
            sk.cubicTo(*pts[i], *pts[i + 1], *pts[i + 2])
            i += 3
        else:
            sk.close()


def _clusters(points, bounds) -> list | None:
    """Contours (points[bounds[k]:bounds[k + 1]]) in groups whose bounding boxes meet,
    directly or through others: candidate pairs from a sort in x, then union-find. None
    where more than MAX_STACKED_CONTOURS share one box."""
    lo = np.minimum.reduceat(points[:bounds[-1]], bounds[:-1])
    hi = np.maximum.reduceat(points[:bounds[-1]], bounds[:-1])
    boxes = np.round(np.concatenate([lo, hi], axis=1) * 16)
    if np.unique(boxes, axis=0, return_counts=True)[1].max() > MAX_STACKED_CONTOURS:
        return None
    order = np.argsort(lo[:, 0], kind="stable")
    lo, hi = lo[order], hi[order]
    # contour i meets those after it in x order up to the first that starts right of it
    reach = np.searchsorted(lo[:, 0], hi[:, 0], side="right")
    n = np.maximum(reach - np.arange(len(lo)) - 1, 0)
    i = np.repeat(np.arange(len(lo)), n)
    j = i + 1 + np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    meet = (lo[j, 1] <= hi[i, 1]) & (lo[i, 1] <= hi[j, 1]) & (lo[j, 0] <= hi[i, 0])
    parent = list(range(len(lo)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    for a, b in zip(i[meet].tolist(), j[meet].tolist()):
        parent[root(a)] = root(b)
    groups = {}
    for k in range(len(lo)):
        groups.setdefault(root(k), []).append(int(order[k]))
    return list(groups.values())
