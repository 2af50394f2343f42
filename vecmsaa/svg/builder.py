"""Scene construction: Element tree + computed styles → resolved :class:`~vecmsaa.scene.nodes.Scene`.

All geometry leaves this module in device pixels. Each element is visited with a :class:`Ctx`
holding the user → device matrix, the viewport used for percentages, and the state that ``<use>``
and markers carry (``context-fill``/``context-stroke``, the instantiation stack). Structural
effects (opacity, clip-path, mask, mix-blend-mode, isolation, filter) become
:class:`~vecmsaa.scene.nodes.Group` layers; anything else is flattened into its parent.
"""
from __future__ import annotations

import functools
import itertools
import math
from operator import attrgetter, itemgetter
import re
from dataclasses import dataclass, field

import numpy as np

from ..diagnostics import warn
from ..scene.transform import IDENTITY, apply, apply_each, compose, point_mapper, translate
from ..scene.path import _RECT_VERBS, CLOSE, LINE, MOVE, Path, rect_corners, rect_path
from ..scene.nodes import Fill, FillRuns, Group, Scene, Solid
from ..geometry import stroke_kernels
from ..geometry.primitives import batch_arrays, gather_runs
from ..geometry.hairline import (CAP_OUTSET, blend_alpha, hairline_batch, hairline_coverage,
                                 hairline_each, hairline_outline, hairline_path,
                                 hairline_segments, use_alpha)
from ..geometry.stroke import (dash_coverage, dash_length, dash_pattern, dash_resolution,
                               stroke_batch, stroke_path)
from . import SvgError
from .color import parse_svg_color as parse_color
from . import document
from .document import (INHERITED, LAYER_PROPERTIES, SVG_ELEMENT_NAMES, Document, Element,
                       Style)
from ..scene.bounds import path_bounds, union
from .markers import draw_markers
from .pathdata import PathBatch, parse_path_data
from .resources import Resources
from .shapes import (CIRCLE_LENGTHS, ELLIPSE_VERBS, RECT_LENGTHS, _ellipse_params,
                     author_path_length, ellipse_points, rect_params, rounded_rect_path,
                     shape_box, shape_path)
from .units import (NUMBER_RE, eval_calc, individual_transform, mean_scale, parse_aspect,
                    parse_length_list, parse_number, parse_number_prefix, parse_opacity,
                    parse_transform, parse_viewbox, split_length, to_px, UNIT_PX, url_argument,
                    viewbox_transform, viewbox_transform_f32, zero_size_viewbox)

SHAPES = {"rect", "circle", "ellipse", "line", "polyline", "polygon", "path"}
#: SVG 2 draws markers on every basic shape
MARKABLE = SHAPES
CONTAINERS = {"g", "a", "switch"}
#: elements drawn where they appear in the tree
RENDERED = SHAPES | CONTAINERS | {"svg", "use", "image", "text"}
#: elements that draw nothing where they stand but are still a <switch>'s choice when they come
#: first (SVG 2 §5.8.2: the first direct child whose conditions hold is rendered, the others
#: bypassed); resvg and Chromium both choose them (a <switch> whose first child is a gradient
#: draws nothing), and a filter's content too (every SVG element named fe...); descriptive,
#: animation and unknown elements are passed over as in resvg
SWITCH_CHOICES_DRAWING_NOTHING = {
    "defs", "clipPath", "mask", "marker", "pattern", "linearGradient", "radialGradient", "stop",
    "filter", "symbol"} | {name for name in SVG_ELEMENT_NAMES if name.startswith("fe")}
#: elements that would draw something but are not drawn (warned about, as resvg does)
UNSUPPORTED = {"foreignObject", "animate", "animateMotion", "animateTransform", "set",
               "video", "audio", "iframe", "canvas"}
#: elements whose ``overflow`` defaults to hidden (UA style sheet)
CLIPPING_BY_DEFAULT = {"svg", "symbol", "marker", "pattern", "image"}

MAX_USE_DEPTH = 32
MAX_NODES = 1_000_000
#: Characters of all <text> elements of a document (as built: a text drawn twice, by <use> or
#: for a bounding box, counts twice); layout is linear, about 30 µs per character.
MAX_TEXT_CHARS = 200_000
MAX_IMAGE_NESTING = 4
#: Clip paths, masks, markers and feImage targets built inside another one: fan-out multiplies
#: (a mask whose content uses two masks, 14 deep, is 2^14 layers), so these count per document.
#: Their chain (a mask's mask's mask...) nests layers as elements do, so its length is held to
#: the elements' (svg.document.MAX_DEPTH): the drawing recurses a few frames per level.
MAX_NESTED_REFERENCES = 4096

#: the verbs of a path of lines only, and the dash pattern of a solid stroke, as
#: geometry.stroke.stroke_path has them
_LINE_VERBS = bytes((MOVE, LINE, CLOSE))
_SOLID = np.empty(0)
_CLOSE_BYTE = bytes((CLOSE,))


def _zero_length_closes(path):
    """A path of moveto-closepath pairs only, each as a moveto and a zero-length lineto (the
    stroker's dot) followed by the close."""
    verbs, pts = [], []
    pi = 0
    for v in path.verbs.tolist():
        if v == MOVE:
            verbs.append(MOVE)
            pts.append(path.points[pi])
            pi += 1
        elif v == CLOSE and verbs and verbs[-1] == MOVE:
            verbs += [LINE, CLOSE]
            pts.append(pts[-1])
    return Path.from_arrays(np.array(verbs, np.uint8), np.array(pts, np.float64).reshape(-1, 2))


#: shapes whose object bounding box shape_box knows from their attributes
_BOXED_SHAPES = frozenset(("rect", "circle", "ellipse"))

#: the verbs that draw nothing (Path.is_empty)
_NOT_DRAWING = bytes((MOVE, CLOSE))

#: url(...) and what follows it: the argument, a quoted string or text up to the first
#: ')', is read by url_argument. "url" is ASCII case-insensitive (CSS Syntax 3 §4.3.4), in
#: presentation attributes as in style sheets
_URL = re.compile(r"^\s*[uU][rR][lL]\(\s*('[^']*'|\"[^\"]*\"|[^)]*?)\s*\)\s*(.*)$", re.S)


@dataclass
class Options:
    font_options: dict = field(default_factory=dict)
    image_nesting: int = 0
    dpi: float = 96.0            # what 1in is in px: scales pt, pc, mm, cm, in


@dataclass(frozen=True)
class Ctx:
    """Traversal state for one element (see module doc)."""
    transform: tuple = IDENTITY           # user space → device pixels
    viewport: tuple = (100.0, 100.0)      # width, height that percentages refer to
    use_stack: tuple = ()                 # ids of elements being instantiated (cycle guard)
    context_fill: object = None           # ContextPaint of the context element, or None
    context_stroke: object = None
    clip: bool = False                    # inside a clipPath: plain black fills, no strokes
    geometry: bool = False                # only object geometry (bounding boxes)
    chain: tuple = ()                     # the matrices composed into transform, outermost
                                          # first (the root's, elements'; units.f32_chain)
    # the device rect outside which nothing drawn here can show (the image grown by
    # SAMPLED_MARGIN), or None where content may be moved or drawn elsewhere (a filter's
    # region and offsets, a pattern's tile, a bounds pass): text culls its glyphs with it
    sampled: tuple | None = field(default=None, compare=False)


#: device px Ctx.sampled reaches beyond the image: the resolve filters' apron (raster.resolve,
#: at most 2 px) plus the raster's own culling margin (geometry.primitives.CULL_MARGIN), with
#: room to spare
SAMPLED_MARGIN = 8.0


def _has_filter(style) -> bool:
    """Whether an element's style names a filter (valid or not: as wrap reads it)."""
    f = style.specified.get("filter")
    return bool(f) and f.strip() != "none"


def ctx_with(ctx: Ctx, **changes) -> Ctx:
    """dataclasses.replace(ctx, **changes) without its per-call walk over the fields and
    the frozen class's __init__ (a fifth of the time: markers make one per instance)."""
    new = object.__new__(Ctx)
    d = new.__dict__
    d.update(ctx.__dict__)
    d.update(changes)
    return new


class ContextPaint:
    """The fill or stroke of a context element (``<use>``, a shape with markers). (Plain
    classes here and in PaintRef: a dataclass costs a millisecond of start-up to create.)"""
    __slots__ = ("bbox_fn", "ctx", "style", "value")

    def __init__(self, value: str, style, ctx, bbox_fn):
        self.value, self.style, self.ctx, self.bbox_fn = value, style, ctx, bbox_fn


class PaintRef:
    """A resolved paint for one shape: the paint and its opacity."""
    __slots__ = ("opacity", "paint")

    def __init__(self, paint, opacity: float):
        self.paint, self.opacity = paint, opacity

    def __repr__(self):
        return f"PaintRef({self.paint!r}, {self.opacity!r})"


def parse_url(value):
    """``url(#id) fallback`` → (ref, fallback text) or None."""
    m = _URL.match(value or "")
    ref = url_argument(m.group(1)) if m else None
    return None if ref is None else (ref, m.group(2).strip())


def bbox_matrix(bbox):
    x0, y0, x1, y1 = bbox
    return (x1 - x0, 0.0, 0.0, y1 - y0, x0, y0)


class LazyBounds:
    """A path's bounding box, computed on first use (only paint servers need it)."""
    __slots__ = ("path", "_box")

    def __init__(self, path):
        self.path = path
        self._box = False

    def get(self):
        if self._box is False:
            self._box = path_bounds(self.path)
        return self._box


def resolve_bbox(bbox):
    return bbox.get() if isinstance(bbox, LazyBounds) else bbox



def _hairline_fills(path, m, cap, dashes, offset, resolution, ref, opacity, antialias):
    """A stroke at most a device pixel wide, as Skia draws it (geometry.hairline); solid, in
    one kernel call from the path's arrays to the outline's (hairline_path)."""
    paint = ref.paint
    alpha = blend_alpha(paint, opacity)
    dashes = dash_pattern(dashes) if dashes else None
    if dashes:
        return [Fill(run, paint, "nonzero", opacity, antialias) for run in hairline_outline(
            *hairline_segments(path, m, cap, dashes, offset, resolution), alpha)]
    ov, op, rv, rp, _ = hairline_path(path, m, cap, alpha)
    return _run_fills(ov, op, rv, rp, paint, opacity, antialias)[0]


def _run_fills(ov, op, vo, po, paint, opacity, antialias, rule="nonzero"):
    """The Fills of an outline's runs (hairline_batch's, stroke_lines_batch's: run r is
    ov[vo[r]:vo[r + 1]], op[po[r]:po[r + 1]]), a run without verbs left out, and the
    indexes of the runs kept (None: all)."""
    fills = []
    append = fills.append
    # Path._of_arrays written out: its call costs more than the Path (map data and scatter
    # plots make tens of thousands here)
    new_path = Path.__new__
    rv, rp = vo.tolist(), po.tolist()
    for v0, v1, p0, p1 in zip(rv, rv[1:], rp, rp[1:]):
        if v1 > v0:
            path = new_path(Path)
            path._arrays = ov[v0:v1], op[p0:p1]
            append(Fill(path, paint, rule, opacity, antialias))
    if len(fills) == len(rv) - 1:
        return fills, None
    return fills, np.flatnonzero(vo[1:] > vo[:-1])


def _outline_arrays(verbs, points, vstart, pstart, which, plan, transform, ref, curves=False):
    """The stroke outlines (_stroke_plan's plan: a hairline, or a solid stroke) of the paths
    ``which`` of a batch (path i: verbs[vstart[i]:vstart[i + 1]], points[pstart[i]:pstart[i
    + 1]]; int64 arrays), stroked in one kernel call (hairlines made in the device, other
    outlines mapped there in one more call): (ov, op, vo, po, owner) as hairline_batch gives
    them (owner None: one run per path). ``curves``: paths with curves, stroked by the curve
    stroker (geometry.stroke.stroke_batch: stroke_path's outline of each), else lines only.
    ref: the stroke's PaintRef."""
    if plan[0] == "hairline":       # (runs: a path's may be several, or none; see hairline)
        return hairline_batch(verbs, points, vstart, pstart, which, transform, plan[1],
                              blend_alpha(ref.paint, _stroke_opacity(plan, ref)))
    (join, cap, limit, offset), width, tolerance = plan
    if curves:
        ov, op, vo, po = stroke_batch(verbs, points, vstart, pstart, which, width / 2.0,
                                      tolerance, join, cap, limit)
    else:
        ov, op, vo, po = stroke_kernels.stroke_lines_batch(
            verbs, points, vstart, pstart, which, width / 2.0, tolerance, join, cap, limit,
            _SOLID, offset)
    if transform != IDENTITY and len(op):
        op = apply(transform, op)
    return ov, op, vo, po, None


def _outline_fills(verbs, points, vstart, pstart, which, plan, transform, ref, antialias,
                   curves=False):
    """The Fills of the stroke outlines (_outline_arrays') of the paths ``which`` of a batch,
    and where each path's are: (fills, bounds), path which[j]'s fills[bounds[j]:bounds[j +
    1]]; bounds None where each path has exactly one, fills[j]."""
    paint, opacity = ref.paint, _stroke_opacity(plan, ref)
    ov, op, vo, po, owner = _outline_arrays(verbs, points, vstart, pstart, which, plan,
                                            transform, ref, curves)
    fills, kept = _run_fills(ov, op, vo, po, paint, opacity, antialias)
    if kept is not None:
        owner = kept if owner is None else owner[kept]
    n = len(which)
    if owner is None or (len(owner) == n and not (owner != np.arange(n)).any()):
        return fills, None
    return fills, np.searchsorted(owner, np.arange(n + 1)).tolist()


def _outline_runs(verbs, points, vstart, pstart, which, plan, transform, ref, antialias,
                  curves=False, chunk=None):
    """_outline_fills' outlines as a _Runs of each path (which[j]'s the j-th), not yet
    Fills: _joined_runs makes them FillRuns, or Fills where few. ``chunk``: the paths
    stroked that many at a time, a kernel call and a _RunSource each (the kernels stroke
    each path on its own: the same outlines); None: all in one call."""
    style = (ref.paint, "nonzero", _stroke_opacity(plan, ref), antialias)
    out = []
    chunk = chunk or max(len(which), 1)
    for c0 in range(0, len(which), chunk):
        part = which[c0:c0 + chunk]
        ov, op, vo, po, owner = _outline_arrays(verbs, points, vstart, pstart, part, plan,
                                                transform, ref, curves)
        source = _RunSource(ov, op, vo, po)
        n = len(part)
        if owner is None:
            out.extend([_Runs(source, j, j + 1, style) for j in range(n)])
            continue
        bounds = np.searchsorted(owner, np.arange(n + 1)).tolist()
        out.extend([_Runs(source, b0, b1, style) for b0, b1 in zip(bounds, bounds[1:])])
    return out


#: hairlines of several styles queued together (_shape_run) stroked this many paths a kernel
#: call, at most: a call's arrays grow with its outlines (a hairline's are hundreds of points)
#: and past a few hundred paths growing them and writing fresh memory cost more per path
#: than the calls (8,000 class-styled paths at 1000 px: 14 us a path in one call, 6 to 7 in
#: calls of 16 to 128, 8 of 512). One style's stay one call, as before (a D3 scatter's
#: 20,000 circles: no faster in chunks, and 40 MB more at the peak, the chunks' freed room
#: kept in the heap); the curve stroker hardly cares (7 us a path in one call, 6 in chunks)
HAIRLINE_CHUNK = 128


class _RunSource:
    """Paths in a batch's arrays (an outline kernel's, _outline_arrays'; a _ShapeBlock's; the
    document's path batch): run r is ov[vo[r]:vo[r + 1]], op[po[r]:po[r + 1]] (vo, po int64
    arrays), mapped by ``transform`` (None: already on the device) as apply() maps them."""
    __slots__ = ("ov", "op", "vo", "po", "transform")

    def __init__(self, ov, op, vo, po, transform=None):
        self.ov, self.op, self.vo, self.po = ov, op, vo, po
        self.transform = transform


class _Runs:
    """Runs b0 .. b1 - 1 of a _RunSource (a path's outline runs, a shape's path) filled as
    ``style`` (paint, rule, opacity, antialias: Fill's fields), held in its place among
    nodes."""
    __slots__ = ("source", "b0", "b1", "style")

    def __init__(self, source, b0, b1, style):
        self.source, self.b0, self.b1, self.style = source, b0, b1, style

    def fills(self) -> list:
        """The Fills _run_fills makes of these runs."""
        s = self.source
        b0, b1 = self.b0, self.b1
        paint, rule, opacity, antialias = self.style
        op, po = s.op, s.po[b0:b1 + 1]
        if s.transform is not None and b1 > b0:
            op = apply(s.transform, op[po[0]:po[-1]])
            po = po - po[0]
        return _run_fills(s.ov, op, s.vo[b0:b1 + 1], po, paint, opacity, antialias, rule)[0]


#: runs (fills) in a stretch of nodes that _joined_runs makes one FillRuns of, at least
#: (fewer are made Fills, as before FillRuns: a small document's scene keeps its Fills)
MIN_JOINED_RUNS = 512


def _joined_runs(nodes) -> list:
    """nodes (Fills, Groups, _Runs, lists of Fills) with each stretch of Fills and _Runs of
    at least MIN_JOINED_RUNS runs made one FillRuns, the other _Runs made Fills and the
    lists replaced by their items: the same fills in the same order, where a long one
    costs no object per fill (see FillRuns)."""
    out = []
    stretch = []
    count = 0
    for node in _flat(nodes):
        cls = node.__class__
        if cls is Fill:
            stretch.append(node)
            count += 1
        elif cls is _Runs:
            stretch.append(node)
            count += node.b1 - node.b0
        else:
            _end_stretch(out, stretch, count)
            stretch, count = [], 0
            out.append(node)
    _end_stretch(out, stretch, count)
    return out


def _end_stretch(out, stretch, count) -> None:
    """Append a stretch of Fills and _Runs to out as _joined_runs does."""
    if count >= MIN_JOINED_RUNS:
        out.append(_fill_runs(stretch))
        return
    for node in stretch:
        if node.__class__ is Fill:
            out.append(node)
        else:
            out.extend(node.fills())


def _fill_runs(stretch):
    """The FillRuns of a stretch of Fills and _Runs, the runs without verbs left out (a
    Fill's path kept as it is): the stretch read as (source, first run, end, style) pieces
    by maps over it, the Fills' paths made one source first, then every run's rows copied
    from its source to the FillRuns' arrays (_gathered_runs)."""
    loose = None
    if Fill in set(map(type, stretch)):
        stretch = list(stretch)
        paths, styles_of = [], {}
        loose = _RunSource(None, None, None, None)      # (its arrays set below)
        for j, node in enumerate(stretch):
            if node.__class__ is Fill:
                key = (id(node.paint), node.rule, node.opacity, node.antialias)
                style = styles_of.get(key)
                if style is None:
                    style = styles_of[key] = (node.paint, node.rule, node.opacity,
                                              node.antialias)
                stretch[j] = _Runs(loose, len(paths), len(paths) + 1, style)
                paths.append(node.path)
        loose.ov, loose.op, loose.vo, loose.po = batch_arrays(paths)
    sources, seg_src = _first_uses(list(map(_SOURCE, stretch)))
    styles, seg_kind = _first_uses(list(map(_STYLE, stretch)))
    n = len(stretch)
    verbs, points, voff, poff, kind = _gathered_runs(
        sources, np.array(seg_src, np.int64), np.fromiter(map(_B0, stretch), np.int64, n),
        np.fromiter(map(_B1, stretch), np.int64, n), np.array(seg_kind, np.int64),
        next((i for i, source in enumerate(sources) if source is loose), None))
    return FillRuns(verbs, points, voff, poff, styles, kind)


def _map_unmapped(unmapped) -> None:
    """The points of the Fills Builder._instance left to its caller (``unmapped``: (Path,
    (verbs, mapper, points), matrix) each), mapped in one kernel call (apply_each maps each
    group as apply() maps it) and set."""
    if not unmapped:
        return
    fills = list(map(itemgetter(1), unmapped))
    points = list(map(itemgetter(2), fills))
    mapped = apply_each(np.array(list(map(itemgetter(2), unmapped)), np.float64),
                        np.fromiter(map(len, points), np.int64, len(points)),
                        np.concatenate(points))
    at = 0
    for (device, fill, _), pts in zip(unmapped, points):
        n = len(pts)
        device._arrays = fill[0], mapped[at:at + n]
        at += n


def _compose_rows(rows, m):
    """compose(row, m) for each row of an (N, 6) array of transforms, by the operations
    compose() does, on columns (the same bytes as each row composed alone); m's entries
    numbers or arrays of N."""
    a1, b1, c1, d1, e1, f1 = rows.T
    a2, b2, c2, d2, e2, f2 = m
    out = np.empty_like(rows)
    with np.errstate(all="ignore"):     # (inf - inf is NaN here as in compose(), silently)
        out[:, 0] = a1 * a2 + c1 * b2
        out[:, 1] = b1 * a2 + d1 * b2
        out[:, 2] = a1 * c2 + c1 * d2
        out[:, 3] = b1 * c2 + d1 * d2
        out[:, 4] = a1 * e2 + c1 * f2 + e1
        out[:, 5] = b1 * e2 + d1 * f2 + f1
    return out


def _gather_mapped(sources, source_at, ts):
    """For Builder._use_arrays: runs r of sources[source_at[r]] ((verbs, points), user space)
    copied into one batch's arrays (gather_runs) and mapped by ts[r] (one apply_each call;
    a run under the identity keeps its source's points, as _instance gives them): (verbs,
    points, run verb offsets, run point offsets)."""
    total = len(source_at)
    voff, poff = np.zeros(total + 1, np.int64), np.zeros(total + 1, np.int64)
    if not total:
        return np.empty(0, np.uint8), np.empty((0, 2), np.float64), voff, poff
    vl = np.array([len(v) for v, _ in sources], np.int64)
    pl = np.array([len(p) for _, p in sources], np.int64)
    vo, po = np.zeros(len(sources) + 1, np.int64), np.zeros(len(sources) + 1, np.int64)
    np.cumsum(vl, out=vo[1:])
    np.cumsum(pl, out=po[1:])
    lp = pl[source_at]
    np.cumsum(vl[source_at], out=voff[1:])
    np.cumsum(lp, out=poff[1:])
    verbs = np.empty(int(voff[-1]), np.uint8)
    points = np.empty((int(poff[-1]), 2), np.float64)
    gather_runs(np.concatenate([v for v, _ in sources]).astype(np.uint8, copy=False),
                _points64(np.concatenate([p for _, p in sources])), vo, po, source_at,
                np.arange(total), verbs, points, voff, poff)
    mapped = apply_each(ts, lp, points)
    # (a run under the identity is its source's points, as _instance gives them)
    same = (ts == IDENTITY).all(axis=1)
    if same.any():
        rows = np.repeat(same, lp)
        mapped[rows] = points[rows]
    return verbs, mapped, voff, poff


def _use_hairlines(sources, source_at, ts, kind, hairs):
    """For Builder._use_arrays, where some of a stretch's runs are hairlines (source_at[r] =
    -1 - h: the Path of hairs[h], cap outset, alpha; _use_plan): the other
    runs as _gather_mapped makes them, and each hairline's runs (none or several) made a
    kernel call for HAIRLINE_CHUNK of them (hairline_each: under ts[r], the same floats as
    stroke() makes per instance, hairline_path's), in their place: (verbs, points, run verb
    offsets, run point offsets, each run's style index, the runs each row became)."""
    normal = source_at >= 0
    hw = np.flatnonzero(~normal)
    nv, nm, nvoff, npoff = _gather_mapped(sources, np.ascontiguousarray(source_at[normal]),
                                          ts[normal])
    h = -1 - source_at[hw]
    hv, hp, hvs, hps = batch_arrays([path for path, _, _ in hairs])
    outsets = np.array([o for _, o, _ in hairs], np.float64)[h]
    alphas = np.array([a for _, _, a in hairs], np.float64)[h]
    ms = ts[hw]
    # (HAIRLINE_CHUNK paths a call: one call's arrays grown for 5,000 markers cost half as
    # much again as the calls)
    ovs, ops, rvs, rps, owners = [nv], [nm], [nvoff], [npoff], []
    for c in range(0, len(h), HAIRLINE_CHUNK):
        e = c + HAIRLINE_CHUNK
        ov, op, rv, rp, owner = hairline_each(hv, hp, hvs, hps, h[c:e], ms[c:e], outsets[c:e],
                                              alphas[c:e])
        rvs.append(rv[1:] + rvs[-1][-1])
        rps.append(rp[1:] + rps[-1][-1])
        ovs.append(ov)
        ops.append(op)
        owners.append(owner + c)
    # the pool of both: the other runs' (nn), then the hairlines'
    nn = len(nvoff) - 1
    vo, po = np.concatenate(rvs), np.concatenate(rps)
    owner = np.concatenate(owners)
    # (a run without verbs left out, as _run_fills leaves it)
    kept = np.flatnonzero(vo[nn + 1:] > vo[nn:-1])
    owner = owner[kept]
    counts = np.ones(len(source_at), np.int64)
    counts[hw] = np.bincount(owner, minlength=len(hw))
    starts = np.cumsum(counts) - counts
    total = int(starts[-1] + counts[-1]) if len(counts) else 0
    # each run's place in the pool
    src = np.empty(total, np.int64)
    src[starts[normal]] = np.arange(nn)
    src[starts[hw][owner] + np.arange(len(owner)) - np.searchsorted(owner, owner)] = nn + kept
    voff, poff = np.zeros(total + 1, np.int64), np.zeros(total + 1, np.int64)
    np.cumsum((vo[1:] - vo[:-1])[src], out=voff[1:])
    np.cumsum((po[1:] - po[:-1])[src], out=poff[1:])
    verbs = np.empty(int(voff[-1]), np.uint8)
    points = np.empty((int(poff[-1]), 2), np.float64)
    gather_runs(np.concatenate(ovs), np.concatenate(ops), vo, po, src, np.arange(total),
                verbs, points, voff, poff)
    return verbs, points, voff, poff, np.repeat(kind, counts), counts


def _composed(top, matrices):
    """``top`` composed with each of ``matrices`` in turn (an instance's chain: the
    transforms from the used element down to one of its shapes)."""
    for m in matrices:
        top = compose(top, m)
    return top


def _first_uses(objects):
    """The distinct objects (by identity) in order of first use, and each one's index
    there, by maps (a Python turn per object cost a scatter plot's 40,000 pieces more)."""
    ids = list(map(id, objects))
    at = dict.fromkeys(ids)
    for i, key in enumerate(at):
        at[key] = i
    by_id = dict(zip(ids, objects))
    return [by_id[key] for key in at], list(map(at.__getitem__, ids))


_SOURCE = attrgetter("source")
_STYLE = attrgetter("style")
_B0 = attrgetter("b0")
_B1 = attrgetter("b1")


def _gathered_runs(sources, seg_src, seg_b0, seg_b1, seg_kind, loose=None):
    """(verbs, points, verb offsets, point offsets, kind) of the runs seg_b0[i] ..
    seg_b1[i] - 1 of sources[seg_src[i]] filled as seg_kind[i], in that order, the runs
    without verbs left out but those of sources[loose] (the Fills' paths, kept as they are):
    each run's rows copied once, from its source to their place (gather_runs, a call per
    source; a source with a transform gathered and mapped first)."""
    lengths = seg_b1 - seg_b0
    ends = np.cumsum(lengths)
    n = int(ends[-1]) if len(ends) else 0
    src = np.repeat(seg_src, lengths)
    index = np.repeat(seg_b0 - (ends - lengths), lengths) + np.arange(n)
    kind = np.repeat(seg_kind, lengths)
    one = len(sources) == 1
    where = [slice(None) if one else np.flatnonzero(src == i) for i in range(len(sources))]
    vl, pl = np.empty(n, np.int64), np.empty(n, np.int64)
    for source, rows in zip(sources, where):
        at = index[rows]
        vl[rows] = source.vo[at + 1] - source.vo[at]
        pl[rows] = source.po[at + 1] - source.po[at]
    keep = vl > 0
    if loose is not None:
        keep |= src == loose
    if not keep.all():
        src, index, kind, vl, pl = (a[keep] for a in (src, index, kind, vl, pl))
        where = [slice(None) if one else np.flatnonzero(src == i)
                 for i in range(len(sources))]
    voff = np.zeros(len(kind) + 1, np.int64)
    poff = np.zeros(len(kind) + 1, np.int64)
    np.cumsum(vl, out=voff[1:])
    np.cumsum(pl, out=poff[1:])
    verbs = np.empty(int(voff[-1]), np.uint8)
    points = np.empty((int(poff[-1]), 2), np.float64)
    dest = np.arange(len(kind))
    for source, rows in zip(sources, where):
        ov, op, vo, po = source.ov, source.op, source.vo, source.po
        runs = index[rows]
        if source.transform is not None:
            # (the runs gathered, in order, then mapped in one apply(): the bytes apply()
            # gives each, a point mapped alone)
            m = len(runs)
            vo, po = np.zeros(m + 1, np.int64), np.zeros(m + 1, np.int64)
            np.cumsum(vl[rows], out=vo[1:])
            np.cumsum(pl[rows], out=po[1:])
            ov, op = np.empty(int(vo[-1]), np.uint8), np.empty((int(po[-1]), 2), np.float64)
            gather_runs(source.ov.astype(np.uint8, copy=False), _points64(source.op),
                        source.vo, source.po, runs, dest[:m], ov, op, vo, po)
            op = apply(source.transform, op)
            runs = dest[:m]
        gather_runs(ov.astype(np.uint8, copy=False), _points64(op), vo, po, runs, dest[rows],
                    verbs, points, voff, poff)
    return verbs, points, voff, poff, kind


def _points64(points):
    """(P, 2) C-contiguous float64 points (as gather_runs takes them)."""
    return np.ascontiguousarray(points, np.float64).reshape(-1, 2)


def _stroke_opacity(plan, ref):
    """The opacity of the Fills of a stroke (ref: its PaintRef) of a plan of _stroke_plan's
    but (None,): a hairline's takes its coverage."""
    return ref.opacity * (plan[2] if plan[0] == "hairline" else 1)


def _batch_of(parts):
    """Paths (verbs, points) in one batch as _outline_fills takes them: (verbs, points,
    verb offsets, point offsets)."""
    vstart = np.zeros(len(parts) + 1, np.int64)
    pstart = np.zeros(len(parts) + 1, np.int64)
    np.cumsum([len(v) for v, _ in parts], out=vstart[1:])
    np.cumsum([len(p) for _, p in parts], out=pstart[1:])
    return (np.concatenate([v for v, _ in parts]), np.concatenate([p for _, p in parts]),
            vstart, pstart)


def _plain_lengths(texts, default):
    """Builder.length of each of texts (attribute values, None where absent: default) when
    each is absent or a plain number, which length reads with float() whatever the axis,
    style or viewport (digits, signs and points: exporters write lengths so); None when
    one is something else (then each goes through length())."""
    if None in texts:
        given = [t for t in texts if t is not None]
        if not given:
            return [default] * len(texts)
        values = _plain_lengths(given, default)
        if values is None:
            return None
        values.reverse()
        pop = values.pop
        return [default if t is None else pop() for t in texts]
    # (every character a plain number's: then the joined texts strip to nothing)
    if "".join(texts).strip(_PLAIN_NUMBER_CHARS) or "" in texts:
        return None
    try:
        return list(map(float, texts))
    except ValueError:                  # ("1.2.3", "+"): length() reads these otherwise
        return None


def _put_fills(nodes, ats, fills, bounds) -> bool:
    """Each path's outline Fills (_outline_fills' fills and bounds) in its place in nodes
    (path j's at ats[j]): fills[j] where bounds is None, else the list of its Fills (for
    _flat); True when lists were put."""
    if bounds is None:
        for at, fill in zip(ats, fills):
            nodes[at] = fill
        return False
    for at, b0, b1 in zip(ats, bounds, bounds[1:]):
        nodes[at] = fills[b0:b1]
    return True


def _flat(nodes) -> list:
    """nodes with each list among them (_put_fills') replaced by its items."""
    out = []
    append, extend = out.append, out.extend
    for node in nodes:
        if node.__class__ is list:
            extend(node)
        else:
            append(node)
    return out


def _passes_on(style) -> bool:
    """Whether the elements below an element of ``style`` that take nothing from it but by
    inheritance (see Builder._inherits_within) get exactly the values they would get under its
    parent's: it specifies only LAYER_PROPERTIES (not inherited) and inherited properties
    with the value the parent passes on, as written (matplotlib's ``*{stroke-linejoin:
    round}`` on every element); not font-size, whose relative values compound."""
    got = style.cache.get("passes-on")
    if got is None:
        parent = style.parent
        got = style.cache["passes-on"] = parent is not None and all(
            k in LAYER_PROPERTIES or (k in INHERITED and k != "font-size" and parent.get(k) == v)
            for k, v in style.specified.items())
    return got


def _stroke_fills(outline, transform, ref, opacity, antialias):
    """The fill of a stroke outline in user space, mapped to the device, or none."""
    if outline is None or outline.is_empty():
        return []
    return [Fill(outline.transformed(transform), ref.paint, opacity=opacity,
                 antialias=antialias)]

_ORIGIN_X = {"left": "0%", "center": "50%", "right": "100%"}
_ORIGIN_Y = {"top": "0%", "center": "50%", "bottom": "100%"}


def _origin_values(text):
    """The x and y of a ``transform-origin`` value as length or percentage texts, or None when
    it is not CSS Transforms 1's grammar: one keyword or length-percentage; two, horizontal
    then vertical, where keywords alone may come in either order (``top left``); a third, a
    length (z, which a 2-D drawing does not use)."""
    parts = text.strip().split()
    if not 1 <= len(parts) <= 3:
        return None
    if len(parts) == 3:
        z = split_length(parts.pop())
        if z is None or z[1] == "%":
            return None

    def length(p):
        return p if split_length(p) is not None else None
    words = [p.lower() for p in parts]
    if len(words) == 1:
        w = words[0]
        if w in ("top", "bottom"):
            return "50%", _ORIGIN_Y[w]
        x = _ORIGIN_X.get(w) or length(parts[0])
        return None if x is None else (x, "50%")
    a, b = words
    if (a in _ORIGIN_Y and a != "center" and b in _ORIGIN_X) or (
            a == "center" and b in ("left", "right")):
        a, b = b, a                                  # 'top left', 'bottom center', 'center right'
    x = _ORIGIN_X.get(a) or (None if a in _ORIGIN_Y else length(parts[0]))
    y = _ORIGIN_Y.get(b) or (None if b in _ORIGIN_X else length(parts[1]))
    if x is None or y is None:
        return None
    return x, y


#: the targets of <use> whose content may be prepared once for all instances (see
#: Builder._prepare_instance)
_INSTANCEABLE = SHAPES | {"symbol", "g", "a"}

#: the properties that give an element a transform of its own (Builder.element_transform
#: is IDENTITY for a style that specifies none of them)
_TRANSFORMING = frozenset(("transform", "translate", "rotate", "scale"))

#: what Builder.length reads as a plain number without split_length (see there)
_PLAIN_NUMBER_CHARS = "0123456789.+-"
assert UNIT_PX[""] == 1.0       # (so split_length's value times it is the value)

#: units a calc() may hold (those split_length reads)
_LENGTH_UNITS = frozenset(UNIT_PX).difference({""}).union({"%", "em", "ex"})


#: containers whose children children() may walk as its own (see Builder._flat_group)
_FLAT_GROUPS = frozenset(("g", "a"))

#: below this many shapes of a kind, _ShapeBlock makes their points row by row
_FEW_SHAPES = 16
#: below this many strokes of one queue (_queue_key) and kind, _shape_run strokes each
#: through stroke()
_FEW_STROKES = 4


#: a points list's items one after another (units._LIST_ITEM, whose matches at each place
#: _points_path's finditer finds while they are contiguous)
_POINTS_ITEM = re.compile(rf"[ \t\n\r]*({NUMBER_RE})[ \t\n\r]*,?")
#: (a polyline's or polygon's points, whether closed) -> its verbs, for up to _FEW_POINTS
_POINTS_VERBS = {}
_FEW_POINTS = 64


def _points_path(tag, el):
    """shape_path's Path of a <polyline> or <polygon> (its moveTo, lineTos and closePath
    recorded; None for fewer than two points) made as arrays: the list read by one
    finditer where its items follow one another to its end and all are finite (the
    numbers parse_number_prefix reads: the same float() of the same text), else by
    parse_number_prefix; the verbs of each length made once."""
    text = el.get("points", "") or ""
    groups, end = [], 0
    for m in _POINTS_ITEM.finditer(text):
        if m.start() != end:
            break
        groups.append(m.group(1))
        end = m.end()
    nums = list(map(float, groups))
    if end != len(text) or not all(map(math.isfinite, nums)):
        nums = parse_number_prefix(text)
    k = len(nums) // 2
    if k < 2:
        return None
    closed = tag == "polygon"
    verbs = _POINTS_VERBS.get((k, closed))
    if verbs is None:
        verbs = np.array([MOVE] + [LINE] * (k - 1) + [CLOSE] * closed, np.uint8)
        if k <= _FEW_POINTS:
            _POINTS_VERBS[k, closed] = verbs
    return Path._of_arrays(verbs, np.array(nums[:2 * k], np.float64).reshape(k, 2))


class _ShapeBlock:
    """_shape_run's shapes of one kind (one list of verbs): their parameters, then the points
    of all of them made at once, in user space and on the device (finish)."""
    __slots__ = ("verbs", "params", "points", "device", "source")

    def __init__(self, verbs):
        self.verbs = verbs
        self.params = []
        self.points = self.device = self.source = None

    def add(self, params) -> int:
        self.params.append(params)
        return len(self.params) - 1

    def finish(self, make, transform):
        """The points, (shapes, points per shape, 2), from make (shapes.ellipse_points or
        scene.path.rect_corners): on each row's numbers for a few shapes, else on the
        parameters' columns (_bulk_points)."""
        if self.params:
            if len(self.params) < _FEW_SHAPES:
                pts = self.points = np.array([make(*row) for row in self.params],
                                             np.float64)
            else:
                pts = self.points = _bulk_points(make, self.params)
            self.device = pts if transform == IDENTITY else \
                apply(transform, pts.reshape(-1, 2)).reshape(pts.shape)

    def fill_source(self):
        """The shapes on the device as a _RunSource, shape i run i (made once)."""
        if self.source is None:
            n, k = self.device.shape[:2]
            nv = len(self.verbs)
            self.source = _RunSource(np.tile(self.verbs, n), self.device.reshape(-1, 2),
                                     np.arange(0, n * nv + 1, nv, dtype=np.int64),
                                     np.arange(0, n * k + 1, k, dtype=np.int64))
        return self.source

    def batch(self):
        """The shapes in user space as _outline_fills takes a batch of paths: (verbs, points,
        verb offsets, point offsets), shape i the i-th path."""
        n, k = self.points.shape[:2]
        nv = len(self.verbs)
        return (np.tile(self.verbs, n), self.points.reshape(-1, 2),
                np.arange(0, n * nv + 1, nv, dtype=np.int64),
                np.arange(0, n * k + 1, k, dtype=np.int64))


def _bulk_points(make, rows):
    """The points make (shapes.ellipse_points, scene.path.rect_corners) gives each of rows
    (each its parameters), (rows, points, 2), from one call on the parameters' columns."""
    pairs = make(*np.array(rows, np.float64).T)        # ((x column, y column), ...)
    return np.ascontiguousarray(np.array(pairs, np.float64).transpose(2, 0, 1))


class Builder:
    """Builds one document into scene nodes. Holds the document, resources and options."""

    #: whether children() builds runs of sibling shapes with their styles' decisions made
    #: once (_path_run, _shape_run); off, each element goes through element() (tests
    #: compare the two)
    shape_runs = True

    def __init__(self, doc: Document, resources: Resources, options: Options):
        self.doc = doc
        self.resources = resources
        self.options = options
        self.nodes_made = 0
        self.text_chars = 0            # characters laid out so far (MAX_TEXT_CHARS)
        # the fills that draw text by their ids, when a dict (sizing.py's drawing_extent sizes
        # a document by text's object bounding box rather than its ink, as resvg does)
        self.text_fills = None
        self.text_cache = {}           # the text modules' memo for this document (font_match)
        self.root_scale = 1.0
        self.paint_stack = []          # patterns being built (recursion guard)
        self.ref_stack = []            # clip paths / masks / markers being built
        self.nested_references = 0     # of them built inside another (MAX_NESTED_REFERENCES)
        self.tile_cache = {}           # pattern tile contents, see paint.pattern
        self.filter_cache = {}         # <filter> elements resolved, see filters.filter_element
        self.marker_cache = {}         # <marker> layouts, see markers.one_marker
        self._links_back_memo = {}     # see links_back()
        self._use_targets = {}         # see use_target()
        self.nodes_by_id = None        # a dict: the nodes of each element with an id go there
        self._path_index = None        # <path> element → its index in self._path_batch
        self._path_batch = None
        self._path_curved = None       # per path of the batch: a verb besides M, L and Z
        self._path_odd = None          # per path of the batch: see _odd_in_run
        # Object bounding boxes and the geometry-pass nodes of elements other than shapes,
        # each computed once per element and context (see object_bbox; emptied around each
        # build_root)
        self._bbox_memo = {}
        self._geometry_memo = {}
        self._hidden_memo = {}         # see _filter_hides
        self._reference_boxes = {}     # see reference_box
        self._shape_memo = {}          # see _shape_path
        self._instanced = {}           # see use() and _Instanced
        self._instance_strokes = {}    # see _instance_stroke
        self._inherits_memo = {}       # see _inherits_within

    def enter_reference(self, el):
        """Push a clip path, mask, marker or feImage target being built (pop ref_stack when
        done); one built inside another counts against MAX_NESTED_REFERENCES."""
        if self.ref_stack:
            self.nested_references += 1
            if self.nested_references > MAX_NESTED_REFERENCES:
                raise SvgError(f"more than {MAX_NESTED_REFERENCES} clip paths, masks and "
                               f"markers inside others (reference fan-out)")
            if len(self.ref_stack) >= document.MAX_DEPTH:
                raise SvgError(f"clip paths, masks and markers nest deeper than "
                               f"{document.MAX_DEPTH} levels")
        self.ref_stack.append(el)

    # -- entry point -----------------------------------------------------------------------
    def build_root(self, transform, viewport, root_scale=1.0, canvas=None,
                   geometry=False, image=None) -> list:
        """Nodes of the root <svg>'s content under ``transform`` (user → device).
        ``canvas``: user → device without the root's own ``transform`` (which the canvas
        background does not take), when it has one. ``geometry``: the object geometry
        alone (see Ctx.geometry), unpainted shapes included. ``image``: (width, height) of
        the device image the nodes are drawn in, when they are drawn nowhere else: text
        then leaves out glyphs that cannot reach it (Ctx.sampled)."""
        self.root_scale = root_scale
        self._clear_memos()
        try:
            return self._build_root(transform, viewport, canvas, geometry, image)
        finally:
            self._clear_memos()     # the scene, drawn next, needs none of their geometry

    def _clear_memos(self):
        self._bbox_memo.clear()
        self._geometry_memo.clear()
        self._hidden_memo.clear()
        self._reference_boxes.clear()
        self._shape_memo.clear()
        self._instanced.clear()

    def _build_root(self, transform, viewport, canvas, geometry, image) -> list:
        root = self.doc.root
        if expanded_size(self.doc, self._use_targets, self._links_back_memo) > MAX_NODES:
            raise SvgError("document expands to too many elements (<use> nesting)")
        style = self.doc.document_style(root)
        if (style.get("display").strip() == "none" or not conditions_pass(root)
                or zero_size_viewbox(root.get("viewBox"))):
            # a root viewBox of zero width or height disables rendering (SVG 2 viewBox; as
            # Chromium; resvg draws the content as if there were no viewBox): the document
            # keeps the size it would have without the viewBox, and is empty
            return []
        sampled = None
        if image is not None and not geometry and not _has_filter(style):
            sampled = (-SAMPLED_MARGIN, -SAMPLED_MARGIN, image[0] + SAMPLED_MARGIN,
                       image[1] + SAMPLED_MARGIN)
        ctx = Ctx(transform=transform, viewport=viewport, chain=(transform,), geometry=geometry,
                  sampled=sampled)
        nodes = self.wrap(root, style, ctx, self.children(root, ctx, style))
        if geometry:
            return nodes
        background = parse_color(root.specified.get("background-color") or "transparent")
        if background not in (None, "currentColor") and background[3] > 0:
            # the canvas background (CSS Backgrounds 3 §2.11.2: the root's background covers
            # the canvas, under the root's transform, opacity and effects), over the viewBox
            # as resvg paints it (its svg/background-color-with-viewbox test)
            vb = parse_viewbox(root.get("viewBox"))
            box = rect_path(*(vb if vb is not None else (0, 0, *viewport)))
            nodes.insert(0, Fill(box.transformed(canvas or transform),
                                 Solid(tuple(float(c) for c in background))))
        return nodes

    def root_transform(self, width, height):
        """The root <svg>'s own transform in its viewport's px (None when singular)."""
        root = self.doc.root
        return self.element_transform(root, self.doc.document_style(root),
                                      Ctx(viewport=(width, height)))

    # -- lengths ---------------------------------------------------------------------------
    def length(self, value, axis, style, viewport, default=None):
        """A length attribute value → user units (axis: x, y or xy for the diagonal)."""
        if value is not None and value and not value.strip(_PLAIN_NUMBER_CHARS):
            # digits, signs and points only: a number in user units when float() reads it,
            # which it does exactly when split_length does (no exponent, no white space)
            try:
                return float(value)
            except ValueError:
                pass
        parsed = split_length(value) if value is not None else None
        if parsed is None:
            # calc() (CSS Values 4 §10): SVG 2's lengths are CSS lengths
            if value is None or "calc(" not in value.lower():
                return default
            got = eval_calc(value, lambda v, unit: self.length_px(v, unit, axis, style, viewport)
                            if unit in _LENGTH_UNITS else None)
            return default if got is None else got
        return self.length_px(*parsed, axis, style, viewport)

    def length_px(self, v, unit, axis, style, viewport):
        if unit == "%":
            w, h = viewport
            ref = w if axis == "x" else h if axis == "y" else math.sqrt((w * w + h * h) / 2)
            return v * ref / 100
        return to_px(v, unit, style.font_size(), dpi=self.options.dpi)

    def length_getter(self, el, style, ctx):
        def get(name, axis, default=None):
            return self.length(el.get(name), axis, style, ctx.viewport, default)
        return get

    # -- traversal -------------------------------------------------------------------------
    def children(self, el, ctx, style) -> list:
        out = []
        if ctx.geometry or ctx.clip or self.nodes_by_id is not None or not self.shape_runs:
            for child in el.children:
                out.extend(self.element(child, ctx, style))
            return out
        # consecutive children built together: plain <path>s (_path_run), other shapes of a
        # plain shape plan (_shape_run), <use>s (_use_run); ``kind`` the one pending
        pending, kind = [], None
        # (shapes not in content built again for each instance (a marker's on every vertex, a
        # <use>'s, a pattern's, mask's or clip path's): there element() keeps each shape's
        # path for the next instance (_shape_path); nor uses)
        shape_runs = not (self.ref_stack or ctx.use_stack)
        # the children of plain groups (_flat_group: what element() makes of one is its
        # children's nodes as they are) are walked here as if they were el's, so that a run
        # of shapes goes on across groups (Graphviz: a <g> per node and per edge); ``stack``
        # the levels walked into, ``it`` and ``parent`` the one being walked. Other elements
        # met while shapes are pending are built at once and their nodes kept in the run as
        # a break (an item (None, nodes, False): _shape_run puts them in their place)
        stack = []
        it, parent = iter(el.children), style
        while True:
            child = next(it, None)
            if child is None:
                if not stack:
                    break
                if pending and kind != "shape":     # (a path or use run shares its parent)
                    self._built_together(kind, pending, ctx, parent, out)
                    pending, kind = [], None
                it, parent = stack.pop()
                continue
            # (no conditional processing attribute: conditions_pass holds without looking;
            # no pathLength, which only shape() applies; tested here, not in a function: a
            # call per path costs more than the test)
            tag = child.tag
            item = None
            if tag == "use":
                if shape_runs:
                    item, what = child, "use"
            elif (tag in SHAPES and "systemLanguage" not in child.attrs
                    and "requiredExtensions" not in child.attrs
                    and "pathLength" not in child.attrs):
                if tag == "path" and not child.specified:
                    item, what = child, "path"
                elif shape_runs:
                    child_style = parent.child(child)
                    cache = child_style.cache
                    plan = cache.get("shape-plan", cache)
                    if plan is cache:
                        plan = cache["shape-plan"] = self._shape_plan(child_style, ctx)
                    if plan is not None:
                        item, what = (child, child_style, plan), "shape"
            elif (tag in _FLAT_GROUPS and shape_runs
                    and LAYER_PROPERTIES.isdisjoint(child.specified)):
                # (a group with a transform or layer of its own, D3's every tick, is built by
                # element(): its Style is not made twice)
                group_style = parent.child(child)
                if self._flat_group(group_style) and conditions_pass(child):
                    self.nodes_made += 1                # (as element() counts it)
                    if self.nodes_made > MAX_NODES:
                        raise SvgError("document expands to too many elements")
                    if pending and kind != "shape":
                        self._built_together(kind, pending, ctx, parent, out)
                        pending, kind = [], None
                    stack.append((it, parent))
                    it, parent = iter(child.children), group_style
                    continue
            if item is not None and what == kind:
                pending.append(item)
                continue
            if item is None and kind == "shape":
                nodes = self.element(child, ctx, parent)
                if nodes:
                    pending.append((None, nodes, False))
                continue
            if pending:
                self._built_together(kind, pending, ctx, parent, out)
            if item is None:
                pending, kind = [], None
                out.extend(self.element(child, ctx, parent))
            else:
                pending, kind = [item], what
        if pending:
            self._built_together(kind, pending, ctx, parent, out)
        return out

    def _flat_group(self, style) -> bool:
        """Whether children() may walk the children of a <g> or <a> of this style as its own
        (kept with the style as "flat-group"): displayed, and no transform, clip path, mask,
        filter, opacity, blending or isolation of its own (_shape_plan's LAYER_PROPERTIES;
        opacity 1 and the rest as _plain_wrap reads them), so that element() gives its
        children's nodes as they are, built in the same context."""
        cache = style.cache
        flat = cache.get("flat-group")
        if flat is None:
            flat = cache["flat-group"] = (LAYER_PROPERTIES.isdisjoint(style.specified)
                                          and style.get("display").strip() != "none"
                                          and self._plain_wrap(style))
        return flat

    def _built_together(self, kind, items, ctx, style, out) -> None:
        """children()'s pending run of ``kind``'s items, built and appended to ``out``."""
        if kind == "path":
            self._path_run(items, ctx, style, out)
        elif kind == "shape":
            self._shape_run(items, ctx, out)
        else:
            self._use_run(items, ctx, style, out)

    def _use_run(self, uses, ctx, parent_style, out) -> None:
        """Append the nodes of sibling <use> elements (cairo's and pdftocairo's glyphs,
        matplotlib's markers and glyphs: thousands in a page or a plot): what element() makes
        of each whose style is plain (displayed; no filter, clip path, mask, opacity, blending
        or isolation, so wrap() gives its nodes as they are) and whose target has prepared
        content (use()'s _Instanced) that clips to no viewport, its transform composed as
        _element and use_translated compose it; those of a stretch of such uses are made
        together (_use_instances). Any other <use> goes through element()."""
        doc, targets, links = self.doc, self._use_targets, self._links_back_memo
        # Style -> None where a use of it goes through element(), else whether it may
        # have a transform of its own (element_transform is IDENTITY without one)
        plain = {}
        # (target, Style, width, height) -> the prepared content (None: element()'s way)
        contents = {}
        # the stretch of uses made together: each one's prepared content, x and y texts and
        # Style, and for a use with a transform of its own, (its index, that transform
        # composed with the context's, its own)
        gots, xs, ys, styles, owns = [], [], [], [], []
        for el in uses:
            style = parent_style.child(el)
            moves = plain.get(style, plain)
            if moves is plain:
                moves = plain[style] = (
                    (not _TRANSFORMING.isdisjoint(style.specified))
                    if style.get("display").strip() != "none" and self._instance_plain(style)
                    else None)
            m = None
            attrs = el.attrs
            if moves is not None and ("systemLanguage" not in attrs and
                                      "requiredExtensions" not in attrs
                                      or conditions_pass(el)):
                target = targets.get(el, targets)
                if target is targets:
                    target = use_target(el, doc, targets, links)
                if target is not None and target.tag in _INSTANCEABLE:
                    key = (target, style, attrs.get("width"), attrs.get("height"))
                    got = contents.get(key, contents)
                    if got is contents:
                        got = contents[key] = self._use_content(el, target, style, ctx)
                    if got is not None:
                        m = self.element_transform(el, style, ctx) if moves else IDENTITY
            if m is None:
                if gots:
                    self._use_instances(gots, xs, ys, styles, owns, ctx, out)
                    gots, xs, ys, styles, owns = [], [], [], [], []
                out.extend(self.element(el, ctx, parent_style))
                continue
            self.nodes_made += 1 + got.count
            if self.nodes_made > MAX_NODES:
                raise SvgError("document expands to too many elements")
            if m is not IDENTITY:
                owns.append((len(gots), compose(ctx.transform, m), m))
            gots.append(got)
            xs.append(attrs.get("x"))
            ys.append(attrs.get("y"))
            styles.append(style)
        if gots:
            self._use_instances(gots, xs, ys, styles, owns, ctx, out)

    def _use_content(self, el, target, style, ctx):
        """For _use_run: the prepared content (an _Instanced that clips to no viewport) a
        <use> of ``style`` and ``target`` (one of _INSTANCEABLE) draws, kept in
        self._instanced, or None where the use goes through element(). Content that
        inherits nothing from the use's own values is prepared under the style it inherits
        from (matplotlib's glyphs: a use each with a translation of its own, one prepared
        content per glyph)."""
        owner = style
        if not self._inherits_within(target):
            while owner.parent is not None and _passes_on(owner):
                owner = owner.parent
        attrs = el.attrs
        key = (target, owner, ctx.viewport, attrs.get("width"), attrs.get("height"))
        instanced = self._instanced
        got = instanced.get(key, instanced)
        if got is instanced:
            got = instanced[key] = self._prepare_instance(el, target, owner, ctx)
        return got if got is not None and got.clip_rect is None else None

    def _use_instances(self, gots, xs, ys, styles, owns, ctx, out) -> None:
        """Append the nodes of a stretch of _use_run's uses: use i instantiates gots[i]
        under the transform compose(base, translate(xs[i], ys[i])) (base where both are 0),
        base being ctx's transform, or for a use in ``owns`` (i, base, its own transform)
        that composed with ctx's. Where the stretch has too few fills for a FillRuns
        (MIN_JOINED_RUNS) or is not drawn as built (_joins_runs), each instance is
        _instance's and every fill's points are mapped in one kernel call for the stretch
        (apply_each maps each group as apply() maps it); else _use_arrays makes them. xs
        and ys are the uses' attribute texts (None where absent), read as Builder.length
        reads them under their ``styles``."""
        xs = self._use_lengths(xs, "x", styles, ctx.viewport)
        ys = self._use_lengths(ys, "y", styles, ctx.viewport)
        if (sum(len(got.items) for got in gots) >= MIN_JOINED_RUNS
                and self._joins_runs(ctx)):
            self._use_arrays(gots, xs, ys, owns, ctx, out)
            return
        own = {i: (base, m) for i, base, m in owns}
        unmapped = []
        for i, (got, x, y) in enumerate(zip(gots, xs, ys)):
            c = ctx
            if i in own:
                base, m = own[i]
                c = ctx_with(ctx, transform=base, chain=ctx.chain + (m,))
            top = c.transform if x == 0.0 and y == 0.0 else \
                compose(c.transform, translate(x, y))
            out.extend(self._instance(got, c, top, unmapped, counted=True))
        _map_unmapped(unmapped)

    def _use_lengths(self, texts, axis, styles, viewport) -> list:
        """Builder.length of each of texts (0 where absent) under its Style: in one go
        where each is a plain number or absent (_plain_lengths), else one by one."""
        values = _plain_lengths(texts, 0.0)
        if values is None:
            length = self.length
            values = [length(text, axis, style, viewport, 0.0)
                      for text, style in zip(texts, styles)]
        return values

    def _use_arrays(self, gots, xs, ys, owns, ctx, out) -> None:
        """_use_instances' stretch made as arrays, with Python work per prepared content
        and per transform's linear part (_use_plan) rather than per instance: every fill of
        every instance (a prepared fill, or a stroke outline _instance_outline makes once
        per linear part) is a run of one source's verbs and points, its transform composed
        for all the instances at once (_compose_rows: the operations compose() does, on
        columns), its points gathered and mapped by one apply_each call, and the runs
        appended as one FillRuns (the same fills, in the same order, as _instance's).
        Hairline strokes, which follow each instance's whole transform, are each instance's
        runs, made for the stretch in a few kernel calls (_use_hairlines). An instance whose
        strokes are made per instance otherwise (dashes, non-scaling) is _instance's,
        between the runs of the others; runs between two such that are too few for a
        FillRuns become Fills."""
        n = len(gots)
        x, y = np.array(xs, np.float64), np.array(ys, np.float64)
        moved = ~((x == 0.0) & (y == 0.0))
        # each instance's plan, by (content, the linear part of its base: None for ctx's),
        # made once for each in order of first use (x and y change no linear part: the top
        # compose() makes of a translation has the base's, zeros' signs aside, which no
        # key tells apart)
        lins = [None] * n
        for i, base, _ in owns:
            lins[i] = base[:4]
        keys = list(zip(gots, lins))
        # (each key's first instance: the dict keeps the smallest index, set last)
        firsts = sorted(dict(zip(reversed(keys), range(n - 1, -1, -1))).items(),
                        key=itemgetter(1))
        own = {i: (base, m) for i, base, m in owns}
        chains, chain_of = [], {}
        sources, source_of = [], {}
        styles, style_of = [], {}
        hairs, hair_of = [], {}
        plans, index = [], {}
        for key, i in firsts:
            index[key] = len(plans)
            got, lin = key
            base = ctx.transform if lin is None else own[i][0]
            top = compose(base, translate(xs[i], ys[i])) if moved[i] else base
            plans.append(self._use_plan(got, top, ctx, chains, chain_of, sources, source_of,
                                        styles, style_of, hairs, hair_of))
        at = np.fromiter(map(index.__getitem__, keys), np.int64, n)
        # the runs: each instance's plan's, in order
        sizes = np.array([0 if plan is False else len(plan) for plan in plans], np.int64)
        per = sizes[at]
        table = np.array([e for plan in plans if plan is not False for e in plan] or
                         np.empty((0, 3)), np.int64).reshape(-1, 3)
        first = np.cumsum(sizes) - sizes
        ends = np.cumsum(per)
        total = int(ends[-1]) if n else 0
        rows = np.repeat(first[at] - (ends - per), per) + np.arange(total)
        chain_at, source_at, kind = (np.ascontiguousarray(table[rows, k]) for k in range(3))
        if not total:
            self._use_pieces(gots, xs, ys, own, moved, ctx, at, plans, ends, 0, out)
            return
        # each instance's top transform, then each run's: its content's chain composed
        tops = np.empty((n, 6), np.float64)
        tops[:] = ctx.transform
        if owns:
            tops[[i for i, _, _ in owns]] = [base for _, base, _ in owns]
        if moved.any():
            tops[moved] = _compose_rows(tops[moved], (1.0, 0.0, 0.0, 1.0, x[moved], y[moved]))
        ts = tops[np.repeat(np.arange(n), per)]
        lengths = np.array([len(chain) for chain in chains], np.int64)
        if lengths.any():
            longest = int(lengths.max())
            mats = np.zeros((len(chains), longest, 6), np.float64)
            for c, chain in enumerate(chains):
                if chain:
                    mats[c, :len(chain)] = chain
            run_lengths = lengths[chain_at]
            for size in np.unique(lengths[lengths > 0]).tolist():
                take = run_lengths == size
                every = take.all()
                t = ts if every else ts[take]
                chain_mats = mats[chain_at if every else chain_at[take]]
                for k in range(size):
                    t = _compose_rows(t, chain_mats[:, k].T)
                if every:
                    ts = t
                else:
                    ts[take] = t
        if hairs:
            verbs, mapped, voff, poff, kind, counts = _use_hairlines(
                sources, source_at, ts, kind, hairs)
            # (run ends moved past each hairline's runs: an instance's end is the runs of
            # its rows so far)
            cum = np.zeros(total + 1, np.int64)
            np.cumsum(counts, out=cum[1:])
            ends, total, source_at = cum[ends], int(cum[-1]), None
        else:
            verbs, mapped, voff, poff = _gather_mapped(sources, source_at, ts)
        self._use_pieces(gots, xs, ys, own, moved, ctx, at, plans, ends, total, out,
                         (verbs, mapped, voff, poff, styles, kind, source_at, sources))

    def _use_pieces(self, gots, xs, ys, own, moved, ctx, at, plans, ends, total, out,
                    runs=None) -> None:
        """For _use_arrays: the stretch appended to ``out`` in order: its runs (``runs``:
        the device verbs, points, run verb and point offsets, styles and style index of
        each of ``total`` runs, and the source of each or None, with ``sources``; instance
        i's runs end at ends[i]) as FillRuns, or Fills where too few between two instances
        whose strokes are made per instance (plans[at[i]] False: _instance's nodes)."""
        pieces = []
        r0 = 0
        general = [j for j, plan in enumerate(plans) if plan is False]
        unmapped = []
        if general:
            for i in np.flatnonzero(np.isin(at, general)).tolist():
                c = ctx
                if i in own:
                    base, m = own[i]
                    c = ctx_with(ctx, transform=base, chain=ctx.chain + (m,))
                top = compose(c.transform, translate(xs[i], ys[i])) if moved[i] else \
                    c.transform
                nodes = self._instance(gots[i], c, top, unmapped, counted=True)
                if nodes:
                    r1 = int(ends[i])
                    if r1 > r0:
                        pieces.append((r0, r1))
                        r0 = r1
                    pieces.append(nodes)
        _map_unmapped(unmapped)
        if total > r0:
            pieces.append((r0, total))
        if not total:
            for piece in pieces:
                out.extend(piece)
            return
        verbs, mapped, voff, poff, styles, kind, source_at, sources = runs
        for piece in pieces:
            if piece.__class__ is list:
                out.extend(piece)
                continue
            b0, b1 = piece
            if b1 - b0 >= MIN_JOINED_RUNS:
                v0, v1, p0, p1 = voff[b0], voff[b1], poff[b0], poff[b1]
                out.append(FillRuns(verbs[v0:v1], mapped[p0:p1], voff[b0:b1 + 1] - v0,
                                    poff[b0:b1 + 1] - p0, styles, kind[b0:b1]))
                continue
            new_path = Path.__new__
            bounds = poff[b0:b1 + 1].tolist()
            if source_at is None:
                vb = voff[b0:b1 + 1].tolist()
                run_verbs = [verbs[v0:v1] for v0, v1 in zip(vb, vb[1:])]
            else:
                run_verbs = [sources[s][0] for s in source_at[b0:b1].tolist()]
            for rv, k, q0, q1 in zip(run_verbs, kind[b0:b1].tolist(), bounds, bounds[1:]):
                path = new_path(Path)
                path._arrays = rv, mapped[q0:q1]
                out.append(Fill(path, *styles[k]))

    def _use_plan(self, got, top, ctx, chains, chain_of, sources, source_of, styles,
                  style_of, hairs, hair_of):
        """For _use_arrays: the runs an instance of prepared content ``got`` under a top
        transform of ``top``'s linear part makes, as (chain, source, style) indexes into
        the lists ``chains`` (each the matrices a run's transform composes with the top, in
        order), ``sources`` ((verbs, points) of a fill or stroke outline in user space) and
        ``styles`` ((paint, rule, opacity, antialias)), each kept once (``*_of``: its index
        by key); a hairline's source is -1 - h, ``hairs[h]`` (the Path in user space, its
        cap's outset, the alpha it blends with: _instance_hairline), its
        runs made per instance (_use_hairlines); False when another stroke is made per
        instance (dashed, non-scaling: _instance_outline's False)."""
        symbol = () if got.symbol_m is None else (got.symbol_m,)
        t0 = top if got.symbol_m is None else compose(top, got.symbol_m)
        plan = []
        last, t = (), t0
        for matrices, fill, path, a, b, c, d in got.items:
            if matrices is not last:
                t, last = _composed(t0, matrices), matrices
            if fill is not None:
                arrays, style = fill, (a, b, c, d)
            else:
                outline = self._instance_outline(path, a, ctx, t, c, b)
                if outline is False:
                    # a hairline: its runs made per instance (_use_hairlines), from the
                    # path's own arrays, as source -1 - h of ``hairs``
                    hair = self._instance_hairline(a, ctx, t, c, b)
                    if hair is None:
                        return False
                    style, outset, alpha = hair
                    hkey = (id(path), outset, alpha)
                    hi = hair_of.get(hkey)
                    if hi is None:
                        hi = hair_of[hkey] = len(hairs)
                        hairs.append((path, outset, alpha))
                    arrays = None
                elif not outline:
                    continue
                else:
                    _, ref, opacity, arrays = outline
                    style = (ref.paint, "nonzero", opacity, b)
            key = (id(got), id(matrices))
            ci = chain_of.get(key)
            if ci is None:
                ci = chain_of[key] = len(chains)
                chains.append(symbol + matrices)
            if arrays is None:
                si = -1 - hi
            else:
                si = source_of.get(id(arrays))
                if si is None:
                    si = source_of[id(arrays)] = len(sources)
                    sources.append((arrays[0], arrays[2]))
            skey = (id(style[0]),) + style[1:]
            ki = style_of.get(skey)
            if ki is None:
                ki = style_of[skey] = len(styles)
                styles.append(style)
            plan.append((ci, si, ki))
        return plan

    def _path_run(self, run, ctx, parent_style, out) -> None:
        """Append the nodes of sibling <path> elements that specify no style (no presentation
        attribute, style or CSS rule: so no transform, clip, mask, filter or opacity of their
        own) and no condition: what element() makes of each, with what depends on their one
        shared style decided once. Map data is runs of thousands of these. Paints that depend
        on the element (paint servers, context paints) and markers go through element()."""
        style = parent_style.child(run[0])      # the same Style for all: their key is ()
        first = len(out)                        # (where the run's nodes begin)
        try:
            plan = style.cache["run-plan"]
        except KeyError:                        # (nothing in it depends on ctx)
            plan = style.cache["run-plan"] = self._run_plan(style, ctx)
        if plan is None:
            for el in run:
                out.extend(self.element(el, ctx, parent_style))
            return
        self.nodes_made += len(run)
        if self.nodes_made > MAX_NODES:
            raise SvgError("document expands to too many elements")
        if plan is False:                       # display: none or invisible
            return
        antialias, order, rule, fill_ref, stroke_ref = plan
        transform = ctx.transform
        path_data = self.path_data
        # a solid, scaling stroke of lines is stroked here (as stroke() would) and the outlines
        # mapped to the device together, after the run: _apply maps each point alone, so one
        # call on all of them gives each outline the points a call of its own would
        lines_plan = None
        if stroke_ref is not None:
            plan = self._cached_stroke_plan(style, ctx, antialias)
            if plan is not None and plan[0] is not None:
                lines_plan = plan
        # the run's strokes for _outline_fills: their places in out, their paths' indexes in
        # the batch; those of curved paths (solid, wider than a hairline) apart (curves=True)
        ats, which = [], []
        curve_ats, curve_which = [], []
        # the paths' verbs and points straight from the document's path batch (the Paths
        # path_data would make are needed only for strokes that are not lines)
        path_data(run[0])                       # (reads the path data, the first time)
        batch, index = self._path_batch, self._path_index
        vstart, pstart, status = batch.vstart, batch.pstart, batch.status
        all_verbs, shared, drawing = batch.verbs, batch.points, batch.drawing()
        identity = transform == IDENTITY
        # the run's fills transformed together (a lookup by matrix per path costs more)
        moved = None if identity or "fill" not in order else \
            shared.all_transformed(transform, len(run))
        # which of the batch's paths are lines only, from the batch's verbs at once (a stroked
        # path needs no verb slice of its own then); a hairline's kernel takes curves too
        curved = self._batch_curved() if lines_plan is not None and \
            lines_plan[0] != "hairline" else None

        def one(el):
            """The nodes of one path of the run, each decided on its own."""
            i = index.get(el)
            if i is None or status[i]:
                path = path_data(el)
                verbs, points = path._freeze()
                empty = not verbs.tobytes().translate(None, _NOT_DRAWING)
            else:
                path = verbs = None             # the verbs sliced where they are needed
                empty = not drawing[i]
            if empty:
                if verbs is None:
                    verbs = all_verbs[vstart[i]:vstart[i + 1]]
                if _CLOSE_BYTE in verbs.tobytes():   # "M x y Z": shape() may stroke a dot
                    out.extend(self.shape(el, ctx, style))
                return                          # empty: shape() draws nothing
            if path is None:
                p0, p1 = pstart[i], pstart[i + 1]
            for item in order:
                if item == "fill":
                    if verbs is None:
                        verbs = all_verbs[vstart[i]:vstart[i + 1]]
                    if not (len(verbs) == 2 and verbs[1] == LINE):
                        if path is not None:
                            device = path.transformed(transform)
                        elif identity:          # (what Path.transformed returns)
                            device = Path._of_shared(verbs, shared, p0, p1)
                        elif moved is not None:
                            device = Path._of_arrays(verbs, moved[p0:p1])
                        else:
                            device = Path._of_arrays(verbs, shared.transformed(transform, p0,
                                                                                p1))
                        out.append(Fill(device, fill_ref.paint, rule, fill_ref.opacity,
                                        antialias))
                elif lines_plan is not None and path is None:
                    # stroked after the loop, all together
                    if curved is None or not curved[i]:
                        ats.append(len(out))
                        which.append(i)
                    else:
                        curve_ats.append(len(out))
                        curve_which.append(i)
                    out.append(None)
                else:
                    if path is None:
                        if verbs is None:
                            verbs = all_verbs[vstart[i]:vstart[i + 1]]
                        path = Path._of_shared(verbs, shared, p0, p1)
                    out.extend(self.stroke(path, style, ctx, None, antialias))

        # A run whose paths are consecutive in the batch (map data): the paths that one()
        # would fill from the batch's points and queue for the lines stroke kernel, a
        # stretch at a time without its tests per path; the others go through one()
        n = len(run)
        i0 = index.get(run[0])
        filled, stroked = "fill" in order, "stroke" in order
        if (i0 is not None and (not filled or identity or moved is not None)
                and (not stroked or lines_plan is not None)
                and self.doc.paths[i0:i0 + n] == run):
            fill_paint = fill_ref.paint if filled else None
            fill_opacity = fill_ref.opacity if filled else None
            new_path = Path.__new__             # (Path._of_arrays written out: see below)
            at = 0
            # (curved paths are odd for the lines stroke kernel, not for a hairline's: one()
            # queues them for the curve stroker's)
            for odd in self._odd_in_run(i0, n, filled, stroked and curved is not None) + [n]:
                ia, ib = i0 + at, i0 + odd
                if order == ("stroke",):
                    base = len(out)
                    out.extend(itertools.repeat(None, ib - ia))
                    ats.extend(range(base, base + ib - ia))
                    which.extend(range(ia, ib))
                else:
                    for i, v0, v1, p0, p1 in zip(range(ia, ib), vstart[ia:ib],
                                                 vstart[ia + 1:ib + 1], pstart[ia:ib],
                                                 pstart[ia + 1:ib + 1]):
                        for item in order:
                            if item == "fill":
                                device = new_path(Path)
                                if identity:        # (Path._of_shared)
                                    device._arrays = all_verbs[v0:v1], shared.points[p0:p1]
                                    device._shared = shared, p0, p1
                                else:
                                    device._arrays = all_verbs[v0:v1], moved[p0:p1]
                                out.append(Fill(device, fill_paint, rule, fill_opacity,
                                                antialias))
                            else:
                                ats.append(len(out))
                                which.append(i)
                                out.append(None)
                if odd < n:
                    one(run[odd])
                at = odd + 1
        else:
            for el in run:
                one(el)
        # the strokes of lines, then of curves (each kind one kernel call), as FillRuns where
        # many (with the fills about them), else Fills
        joins = bool(ats or curve_ats) and self._joins_runs(ctx)
        lists = False                           # whether out holds lists of Fills
        for got_ats, got_which, curves in ((ats, which, False), (curve_ats, curve_which, True)):
            if not got_ats:
                continue
            arrays = (batch.verbs, batch.points.points, *batch.offsets,
                      np.array(got_which, np.int64), lines_plan, transform, stroke_ref,
                      antialias)
            if joins:
                for at, runs in zip(got_ats, _outline_runs(*arrays, curves)):
                    out[at] = runs
            else:
                fills, bounds = _outline_fills(*arrays, curves)
                lists |= _put_fills(out, got_ats, fills, bounds)
        if joins:
            out[first:] = _joined_runs(out[first:])
        elif lists:
            start = min(ats[:1] + curve_ats[:1])
            out[start:] = _flat(out[start:])

    def _joins_runs(self, ctx) -> bool:
        """Whether _path_run and _shape_run give FillRuns (_joined_runs) here: in what is
        drawn as it is built, not in the content of clip paths, masks, markers, <use>s or
        patterns (built again per instance, and read fill by fill) nor in geometry built for
        a bounding box."""
        return not (self.ref_stack or ctx.use_stack or ctx.geometry)

    def _run_plan(self, style, ctx):
        """For _path_run: False when nothing is drawn, None when the elements must go through
        element() one by one, else (antialias, paint order, fill rule, fill PaintRef or
        None)."""
        if style.get("display").strip() == "none":
            return False
        if style.get("visibility").strip() in ("hidden", "collapse"):
            return False
        for which in ("fill", "stroke"):
            value = self.paint_value(style, which)
            if value in ("context-fill", "context-stroke") or parse_url(value) is not None:
                return None                     # depends on the element
        antialias, order, rule, marked = self._draw_plan(style)
        if marked:
            return None
        if not self._plain_wrap(style):
            return None
        fill_ref = self.resolve_paint(style, "fill", ctx, None)
        stroke_ref = self.resolve_paint(style, "stroke", ctx, None)
        order = tuple(item for item in order if (item == "fill" and fill_ref is not None)
                      or (item == "stroke" and stroke_ref is not None))
        return (antialias, order, "evenodd" if rule == "evenodd" else "nonzero", fill_ref,
                stroke_ref)

    def _shape_plan(self, style, ctx):
        """For _shape_run (kept with the style as "shape-plan"): _run_plan's, or None for the
        general route when the style specifies one of LAYER_PROPERTIES (a transform, clip
        path, mask, filter, opacity, blending or isolation of the element's own: those are
        not inherited, so a style without them has none)."""
        if not LAYER_PROPERTIES.isdisjoint(style.specified):
            return None
        return self._run_plan(style, ctx)

    def _shape_run(self, items, ctx, out) -> None:
        """Append the nodes of consecutive sibling shapes (basic shapes, and paths that
        specify a style) whose styles need nothing of element() (_shape_plan: no transform,
        clip, mask, filter or opacity of their own, no paint that depends on the element, no
        markers) and that have no condition or pathLength: what element() makes of each.
        items: (element, its Style, the style's plan). The styles may differ from one
        element to the next (class-styled exports); each style's plan is decided once. The
        circles' and rectangles' lengths are read for all of them at once (_shape_lengths),
        the geometry of circles, ellipses and rectangles made for all of them at once
        (_ShapeBlock, the points of shapes.py's paths), the fills mapped to the device in
        one call, and hairlines and strokes of lines (solid, scaling) stroked per stroke
        (_queue_key: styles alike in their strokes together) and kind of geometry in one
        kernel call (_outline_fills; several styles' hairlines in chunks, HAIRLINE_CHUNK);
        other strokes go through stroke() path by path. Items (None, nodes, False) are
        breaks (children(): other elements' nodes), put in their place."""
        breaks = 0
        transform = ctx.transform
        identity = transform == IDENTITY
        ellipses = _ShapeBlock(ELLIPSE_VERBS)
        rects = _ShapeBlock(_RECT_VERBS)
        circle_rows, rect_rows = self._shape_rows(items, ctx.viewport)
        # per element: (element, style, plan, where its geometry is) with where one of
        # (block, row), (None, batch index) for a path of the document's path batch, or
        # (False, Path) for a path of its own
        todo = []
        batch = None
        for el, style, plan in items:
            if plan is False:                   # display: none, or invisible
                if el is None:                  # a break: other elements' nodes (children())
                    todo.append((None, style, None, None, None))
                    breaks += 1
                continue
            tag = el.tag
            if tag == "circle":
                row = next(circle_rows)
                if row is not None:
                    todo.append((el, style, plan, ellipses, ellipses.add(row)))
            elif tag == "path":
                if batch is None:
                    if self._path_index is None:
                        self.path_data(el)      # (reads the path data, the first time)
                    batch = self._path_batch
                i = self._path_index.get(el)
                if i is None or batch.status[i]:
                    todo.append((el, style, plan, False, self.path_data(el)))
                else:
                    todo.append((el, style, plan, None, i))
            elif tag == "rect":
                r = next(rect_rows)
                if r is None:
                    continue
                if r[4] <= 0:                   # (rounded_rect_path: rect_path)
                    todo.append((el, style, plan, rects, rects.add(r[:4])))
                else:
                    todo.append((el, style, plan, False, rounded_rect_path(*r)))
            elif tag == "ellipse":
                e = _ellipse_params(tag, self.length_getter(el, style, ctx))
                if e is not None:
                    todo.append((el, style, plan, ellipses, ellipses.add(e)))
            else:
                path = _points_path(tag, el) if tag == "polygon" or tag == "polyline" else \
                    shape_path(el, self.length_getter(el, style, ctx))
                if path is not None:
                    todo.append((el, style, plan, False, path))
        # (the elements counted as element() counts them; a break's were)
        self.nodes_made += len(items) - breaks
        if self.nodes_made > MAX_NODES:
            raise SvgError("document expands to too many elements")
        if not todo:
            return
        ellipses.finish(ellipse_points, transform)
        rects.finish(rect_corners, transform)
        if batch is not None:
            vstart, pstart, drawing = batch.vstart, batch.pstart, batch.drawing()
            all_verbs, shared = batch.verbs, batch.points
        curved_paths = None
        nodes = []
        # strokes for _outline_fills (curves=True: curves, solid, wider than a hairline), per
        # stroke (_queue_key), where their geometry is (the document's path batch: None; a
        # _ShapeBlock; paths of their own: False, in own_paths) and whether curves: [stroke
        # plan, stroke PaintRef, antialias, each one's style, where, their places in nodes,
        # their indexes in the batch, block or own_paths, whether curves]
        queued = {}
        own_paths = []                          # (verbs, points) of paths of their own queued
        stroke_plans = {}                       # style -> its (stroke plan, queue key) here
        new_path = Path.__new__                 # (Path._of_arrays written out)
        joins = self._joins_runs(ctx)
        fill_styles = {}                        # id(plan) -> its fills' style (joins)
        batch_source = None                     # the document's path batch as a _RunSource
        for el, style, plan, block, at in todo:
            if el is None:                      # a break: its nodes (style) in their place
                nodes.extend(style)
                continue
            antialias, order, rule, fill_ref, stroke_ref = plan
            user = None
            if block is None:                   # the document's path batch
                i = at
                if not drawing[i]:
                    if _CLOSE_BYTE in all_verbs[vstart[i]:vstart[i + 1]].tobytes():
                        nodes.extend(self.shape(el, ctx, style))    # (a dot, maybe)
                    continue
                verbs = all_verbs[vstart[i]:vstart[i + 1]]
                p0, p1 = pstart[i], pstart[i + 1]
            elif block is False:                # a Path of its own
                user = at
                verbs = user._freeze()[0]
                if not verbs.tobytes().translate(None, _NOT_DRAWING):
                    if _CLOSE_BYTE in verbs.tobytes():
                        nodes.extend(self.shape(el, ctx, style))
                    continue
            else:
                verbs = block.verbs
            for item in order:
                if item == "fill":
                    if len(verbs) == 2 and verbs[1] == LINE:
                        continue                # a lone line segment encloses nothing
                    if joins and block is not False:
                        # (a run of a source, not a Path and a Fill: _fill_runs copies its
                        # arrays straight into the FillRuns')
                        fill_style = fill_styles.get(id(plan))
                        if fill_style is None:
                            fill_style = fill_styles[id(plan)] = (
                                fill_ref.paint, rule, fill_ref.opacity, antialias)
                        if block is None:
                            if batch_source is None:
                                batch_source = _RunSource(
                                    all_verbs, shared.points, *self._path_batch.offsets,
                                    None if identity else transform)
                            nodes.append(_Runs(batch_source, i, i + 1, fill_style))
                        else:
                            nodes.append(_Runs(block.fill_source(), at, at + 1, fill_style))
                        continue
                    if block is None:
                        device = new_path(Path)
                        if identity:            # (Path._of_shared)
                            device._arrays = verbs, shared.points[p0:p1]
                            device._shared = shared, p0, p1
                        else:
                            device._arrays = verbs, shared.transformed(transform, p0, p1)
                    elif block is False:
                        device = user.transformed(transform)
                    else:
                        device = new_path(Path)
                        device._arrays = verbs, block.device[at]
                    nodes.append(Fill(device, fill_ref.paint, rule, fill_ref.opacity,
                                      antialias))
                    continue
                # the stroke
                got = stroke_plans.get(style)
                if got is None:
                    got = stroke_plans[style] = self._queue_key(style, ctx, antialias,
                                                                stroke_ref)
                stroke_plan, stroke_key = got
                if stroke_plan is None:
                    continue
                if block is None:
                    if curved_paths is None:
                        curved_paths = self._batch_curved()
                    curved = curved_paths[i]
                elif block is False:
                    curved = bool(verbs.tobytes().translate(None, _LINE_VERBS))
                else:
                    curved = block.verbs is ELLIPSE_VERBS
                kind = stroke_plan[0]
                # (hairline_batch takes curves, conics included; the lines stroke kernel
                # lines only: a curved outline stroke goes to the curve stroker's batch)
                if kind is not None:
                    curves = curved and kind != "hairline"
                    got = queued.get((stroke_key, block, curves))
                    if got is None:
                        got = queued[stroke_key, block, curves] = (
                            stroke_plan, stroke_ref, antialias, [], block, [], [], curves)
                    got[3].append(style)
                    got[5].append(len(nodes))
                    nodes.append(None)
                    if block is False:
                        got[6].append(len(own_paths))
                        own_paths.append(user._freeze())
                    else:
                        got[6].append(at)
                    continue
                if user is None:
                    if block is None:
                        user = Path._of_shared(verbs, shared, p0, p1)
                    else:
                        user = new_path(Path)
                        user._arrays = verbs, block.points[at]
                nodes.extend(self.stroke(user, style, ctx, None, antialias))
        if not queued:
            out.extend(_joined_runs(nodes) if joins else nodes)
            return
        lists = False                           # whether nodes holds lists of Fills
        local = None
        block_batches = {}                      # _ShapeBlock -> its batch(), made once
        for stroke_plan, stroke_ref, antialias, styles, block, ats, indexes, curves in \
                queued.values():
            if len(ats) < _FEW_STROKES:
                # (a kernel call for a few paths costs more than stroke()'s for each)
                for at, index, style in zip(ats, indexes, styles):
                    if block is None:
                        user = Path._of_shared(all_verbs[vstart[index]:vstart[index + 1]],
                                               shared, pstart[index], pstart[index + 1])
                    elif block is False:
                        user = Path._of_arrays(*own_paths[index])
                    else:
                        user = Path._of_arrays(block.verbs, block.points[index])
                    nodes[at] = self.stroke(user, style, ctx, None, antialias)
                lists = True
                continue
            if block is None:
                arrays = (all_verbs, shared.points, *self._path_batch.offsets)
            elif block is False:
                if local is None:
                    local = _batch_of(own_paths)
                arrays = local
            else:
                arrays = block_batches.get(block)
                if arrays is None:
                    arrays = block_batches[block] = block.batch()
            if joins:
                # (several styles' hairlines, once calls of their own, a few calls: see
                # HAIRLINE_CHUNK)
                chunk = HAIRLINE_CHUNK if stroke_plan[0] == "hairline" and any(
                    style is not styles[0] for style in styles) else None
                for at, runs in zip(ats, _outline_runs(*arrays, np.array(indexes, np.int64),
                                                       stroke_plan, transform, stroke_ref,
                                                       antialias, curves, chunk)):
                    nodes[at] = runs
                continue
            fills, bounds = _outline_fills(*arrays, np.array(indexes, np.int64), stroke_plan,
                                           transform, stroke_ref, antialias, curves)
            lists |= _put_fills(nodes, ats, fills, bounds)
        out.extend(_joined_runs(nodes) if joins else _flat(nodes) if lists else nodes)

    def _queue_key(self, style, ctx, antialias, stroke_ref):
        """For _shape_run: the stroke plan of a style (_cached_stroke_plan's) and the key its
        strokes are queued by for one kernel call: the plan with the paint and opacity and
        antialias the outlines' Fills take, so that strokes of styles that differ only
        elsewhere (class-styled exports: a fill colour each, one stroke) are one call; the
        outlines are the same, each path stroked on its own in the kernels. A solid paint
        is keyed by its colour, another by identity."""
        plan = self._cached_stroke_plan(style, ctx, antialias)
        if plan is None or plan[0] is None:
            return plan, None
        paint = stroke_ref.paint
        paint_key = paint.color if paint.__class__ is Solid else id(paint)
        return plan, (plan, paint.__class__, paint_key, stroke_ref.opacity, antialias)

    def _shape_rows(self, items, viewport):
        """For _shape_run: iterators over the parameters of the circles (_ellipse_params')
        and of the rectangles (_rect_params') among items, those not of a plan False, in
        order (None for one that draws nothing): their lengths read for all at once
        (_shape_lengths)."""
        circles = ([], [])
        rects = ([], [])
        for el, style, plan in items:
            if plan is False:                   # (a break among them too: see children())
                continue
            tag = el.tag
            if tag == "circle" or tag == "rect":
                got = circles if tag == "circle" else rects
                got[0].append(el)
                got[1].append(style)
        circle_rows = rect_rows = ()
        if circles[0]:
            cx, cy, r = self._shape_lengths(*circles, CIRCLE_LENGTHS, viewport)
            circle_rows = [None if s <= 0 else (x, y, s, s) for x, y, s in zip(cx, cy, r)]
        if rects[0]:
            rect_rows = itertools.starmap(rect_params, zip(*self._shape_lengths(
                *rects, RECT_LENGTHS, viewport)))
        return iter(circle_rows), iter(rect_rows)

    def _shape_lengths(self, elements, styles, lengths, viewport) -> list:
        """The lengths (name, axis, default) of lengths of each element, Builder.length's, as
        columns: all of one at once where each element's value is a plain number or absent
        (_plain_lengths), else each through length()."""
        columns = []
        for name, axis, default in lengths:
            texts = [el.attrs.get(name) for el in elements]
            values = _plain_lengths(texts, default)
            if values is None:
                length = self.length
                values = [length(text, axis, style, viewport, default)
                          for text, style in zip(texts, styles)]
            columns.append(values)
        return columns

    def element(self, el: Element, ctx: Ctx, parent_style: Style) -> list:
        if ctx.geometry and ctx.transform is IDENTITY and el.tag not in SHAPES:
            # built once per context (see object_bbox), at the identity, where a box's walk
            # starts (under a transform from there a key would miss, and hashing costs); a
            # copy, as callers own their lists
            key = (el, parent_style, ctx, tuple(self.ref_stack))
            try:
                return list(self._geometry_memo[key])
            except KeyError:
                nodes = self._geometry_memo[key] = self._element(el, ctx, parent_style)
                return list(nodes)
        return self._element(el, ctx, parent_style)

    def _element(self, el: Element, ctx: Ctx, parent_style: Style) -> list:
        if el.tag not in RENDERED:
            if el.tag in UNSUPPORTED:
                warn(f"<{el.tag}> is not supported: skipped")
            return []
        if not conditions_pass(el):
            return []
        self.nodes_made += 1
        if self.nodes_made > MAX_NODES:
            raise SvgError("document expands to too many elements")
        style = parent_style.child(el)
        if style.get("display").strip() == "none":
            return []
        m = self.element_transform(el, style, ctx)
        if m is None:
            return []
        c = ctx if m is IDENTITY else ctx_with(ctx, transform=compose(ctx.transform, m),
                                               chain=ctx.chain + (m,))
        if c.sampled is not None and _has_filter(style):
            c = ctx_with(c, sampled=None)   # (a filter's region and offsets reach anywhere)
        tag = el.tag
        disabled = False
        if tag in SHAPES:
            nodes = self.shape(el, c, style)
            # SVG 2: a zero width or height (rect), radius (circle, ellipse) "disables
            # rendering of the element", so its filter draws nothing either (as in Gecko)
            disabled = not nodes and tag in _BOXED_SHAPES and \
                shape_box(el, self.length_getter(el, style, c)) is None
        elif tag == "switch":
            nodes = self.switch(el, c, style)
        elif tag in CONTAINERS:
            nodes = self.children(el, c, style)
        elif tag == "svg":
            nodes = self.nested_svg(el, c, style, effects=True)
            if self.nodes_by_id is not None and el.id is not None:
                self.nodes_by_id.setdefault(el.id, nodes)
            return nodes
        elif tag == "use":
            # x and y are a translation appended to the use element's transform (SVG 2
            # §5.6.2): its clip-path, mask and filter are in the translated user space
            c = self.use_translated(el, style, c)
            nodes = self.use(el, c, style, translated=True)
        elif tag == "image":
            nodes = self.image(el, c, style)
        elif tag == "text":
            nodes = self.text(el, c, style)
        else:
            nodes = []
        nodes = [] if disabled else self.wrap(el, style, c, nodes)
        if self.nodes_by_id is not None and el.id is not None:
            self.nodes_by_id.setdefault(el.id, nodes)
        return nodes

    def switch(self, el, ctx, style):
        """The nodes of a <switch>: those of its first child whose conditions hold, of the
        elements it may choose (no nodes when that child draws nothing)."""
        for child in el.children:
            if (child.tag in RENDERED or child.tag in SWITCH_CHOICES_DRAWING_NOTHING) \
                    and conditions_pass(child):
                return self.element(child, ctx, style)
        return []

    def element_transform(self, el, style, ctx):
        """The element's own transform (with transform-origin), None when it is singular.
        (Read from its style: under a <use>, var() there takes the use's custom properties.)"""
        spec = style.specified
        text = spec.get("transform")
        if text == "none":
            text = None
        individual = None
        if "translate" in spec or "rotate" in spec or "scale" in spec:
            individual = [spec.get(name) for name in ("translate", "rotate", "scale")]
            individual = [None if v is None or v.strip() == "none" else v for v in individual]
            if not any(individual):
                individual = None
        if not text and individual is None:
            return IDENTITY
        origin = spec.get("transform-origin")
        # the reference box (CSS Transforms 1 transform-box) is wanted for percentages and
        # for an origin; with fill-box or stroke-box also for the initial origin, 0 0 of the
        # box (SVG 2's UA style sheet), which is then the box's corner
        box = None
        if (origin or "%" in (text or "") or (individual and "%" in (individual[0] or ""))
                or self.transform_box(el) != "view-box"):
            box = self.reference_box(el, style, ctx)
        size = ctx.viewport if box is None else box[2:]
        # the attribute has SVG's grammar, the CSS property CSS's (CSS Transforms 1 §7.1;
        # resvg 0.48.1 and Chromium 150 read units in the attribute as malformed)
        attribute = text == el.attrs.get("transform")
        m = parse_transform(text, size, style.font_size(), attribute) if text else IDENTITY
        if m is None:
            m = IDENTITY
        if individual is not None:
            # CSS Transforms 2: translate, rotate and scale come before transform
            m = compose(individual_transform(*individual, size, style.font_size()), m)
        if m == IDENTITY:
            return IDENTITY
        if box is not None:
            ox, oy = self.transform_origin(origin or "0 0", style, box)
            if ox or oy:
                m = compose(compose(translate(ox, oy), m), translate(-ox, -oy))
        a, b, c, d, _, _ = m
        if abs(a * d - b * c) < 1e-12 or not all(math.isfinite(v) for v in m):
            return None
        return m

    def transform_origin(self, text, style, box):
        """transform-origin → (x, y) in user units; ``box`` is the reference box, (x, y,
        width, height), or a viewport's (width, height) (the view-box at 0, 0)."""
        bx, by, bw, bh = box if len(box) == 4 else (0.0, 0.0, *box)
        vals = _origin_values(text)
        if vals is None:
            # invalid: the initial value, which for SVG elements is 0 0 (SVG 2's UA style sheet)
            vals = ("0", "0")

        def resolve(v, size):
            parsed = split_length(v)
            if parsed is None:
                return 0.0
            n, unit = parsed
            if unit == "%":
                return n * size / 100
            return to_px(n, unit, style.font_size(), dpi=self.options.dpi)
        return bx + resolve(vals[0], bw), by + resolve(vals[1], bh)

    @staticmethod
    def transform_box(el):
        """An element's used transform-box: view-box, fill-box or stroke-box. CSS Transforms 1:
        content-box is fill-box and border-box stroke-box for SVG elements without a CSS layout
        box; the initial value (and that of an invalid one) is view-box. The root <svg> has a
        CSS box in a browser: it keeps the view-box here."""
        value = el.specified.get("transform-box")
        # (lower-cased by the cascade: transform-box is among document.KEYWORD_PROPERTIES)
        while value is not None and value.strip() == "inherit" and el.parent is not None:
            el = el.parent
            value = el.specified.get("transform-box")
        if value is None or el.parent is None:
            return "view-box"
        value = value.strip()
        if value in ("fill-box", "content-box"):
            return "fill-box"
        if value in ("stroke-box", "border-box"):
            return "stroke-box"
        return "view-box"

    def reference_box(self, el, style, ctx):
        """The reference box of the element's transform and transform-origin (CSS Transforms 1
        transform-box) as (x, y, width, height) in its user space: the object bounding box
        (fill-box), the stroke bounding box (stroke-box), or the nearest viewport's viewBox
        placed at the origin (view-box). An element without a box has an empty one at 0, 0."""
        kind = self.transform_box(el)
        if kind == "view-box":
            return (0.0, 0.0, *ctx.viewport)
        # once per element, style and viewport, like object_bbox's memo (whose key, with the
        # whole context, misses here): the box is computed by building the element (in
        # geometry mode), and building it again computes its descendants' boxes, so nested
        # fill-box groups would cost 2^depth builds
        key = (el, style, ctx.viewport, kind)
        got = self._reference_boxes.get(key)
        if got is not None:
            return got
        bbox = self.object_bbox(el, ctx, style)
        if kind == "stroke-box":
            bbox = self.stroke_bbox(el, ctx, style, bbox)
        if bbox is not None and el.tag in ("use", "svg"):
            bbox = self._own_space_box(el, style, ctx, bbox)
        box = ((0.0, 0.0, 0.0, 0.0) if bbox is None
               else (bbox[0], bbox[1], bbox[2] - bbox[0], bbox[3] - bbox[1]))
        self._reference_boxes[key] = box
        return box

    def _own_space_box(self, el, style, ctx, bbox):
        """A <use>'s or nested <svg>'s object bounding box (object_bbox gives it where their
        clip-path, mask and filter apply: after a use's x/y, inside an svg's viewport) in the
        space their transform applies in: moved by x/y, and for an svg mapped by its viewBox."""
        get = self.length_getter(el, style, ctx)
        m = translate(get("x", "x", 0.0), get("y", "y", 0.0))
        if el.tag == "svg":
            vb = parse_viewbox(el.get("viewBox"))
            w = get("width", "x", ctx.viewport[0])
            h = get("height", "y", ctx.viewport[1])
            if vb is not None and w > 0 and h > 0:
                m = compose(m, viewbox_transform_f32(
                    vb, parse_aspect(el.get("preserveAspectRatio")), w, h))
        a, _, _, d, e, f = m                     # a translation and a scale: no rotation
        x0, x1 = a * bbox[0] + e, a * bbox[2] + e
        y0, y1 = d * bbox[1] + f, d * bbox[3] + f
        return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)

    def stroke_bbox(self, el, ctx, style, bbox):
        """SVG 2's stroke bounding box of a shape: its object bounding box ``bbox`` with the
        stroke shape (when the stroke is not none), markers left out. For other elements the
        object bounding box."""
        if el.tag not in SHAPES or style.get("stroke").strip() == "none":
            return bbox
        path = (self.path_data(el) if el.tag == "path"
                else shape_path(el, self.length_getter(el, style, ctx)))
        params = self.stroke_params(style, ctx)
        if path is None or params is None:
            return bbox
        width, join, cap, limit, dashes, offset = params
        outline = stroke_path(path, width, join=join, cap=cap, miterlimit=limit, dashes=dashes,
                              dash_offset=offset)
        return union(bbox, path_bounds(outline)) if not outline.is_empty() else bbox

    # -- structural wrapping ---------------------------------------------------------------
    def wrap(self, el, style, ctx, nodes) -> list:
        """Apply filter, opacity, clip-path, mask, mix-blend-mode and isolation of an element."""
        if ctx.geometry:
            # an element its filter keeps from being drawn (a url to no filter, or to filters
            # that cannot apply to it) adds nothing to a bounding box either: SVG 2's
            # algorithm skips children that are not rendered, and usvg drops the element
            if nodes and _has_filter(style) and self._filter_hides(el, ctx, style):
                return []
            return nodes
        if ctx.clip:
            clip_ref = style.specified.get("clip-path")
            if clip_ref and clip_ref != "none" and nodes:
                clip = self.clip_path(clip_ref, ctx, lambda: self.object_bbox(el, ctx, style))
                if clip is False:
                    return []
                if clip is not None:
                    return [Group(children=nodes, clip=clip)]
            return nodes
        if style.cache.get("plain-wrap"):
            return nodes
        opacity = parse_opacity(style.get("opacity"))
        blend = (style.get("mix-blend-mode") or "normal").strip()
        isolate = style.get("isolation").strip() == "isolate"
        clip_ref = style.specified.get("clip-path")
        mask_ref = style.specified.get("mask")
        has_clip = clip_ref and clip_ref.strip() != "none"
        has_mask = mask_ref and mask_ref.strip() != "none"
        has_filter = _has_filter(style)
        if opacity <= 0 and not has_mask:
            return []
        if not (has_clip or has_mask or has_filter or opacity < 1 or blend != "normal"
                or isolate):
            # This follows from the style alone (clip-path, mask and filter are not inherited,
            # so they are among the element's own values that styles are shared by): kept
            # with it, since map data asks thousands of times.
            style.cache["plain-wrap"] = True
            return nodes
        bbox_cache = []

        def bbox():
            if not bbox_cache:
                bbox_cache.append(self.object_bbox(el, ctx, style))
            return bbox_cache[0]
        if has_filter:      # (imported here: filters and their scene classes cost start-up)
            from .filters import element_filters
            filters = element_filters(self, el, style, ctx, bbox)
        else:
            filters = []
        if filters is False or not (nodes or filters):
            return []
        group = Group(children=nodes, filters=filters)
        if has_clip:
            clip = self.clip_path(clip_ref, ctx, bbox)
            if clip is False:
                return []
            group.clip = clip
        if has_mask:
            masks = self.masks(mask_ref, ctx, bbox, style.specified.get("mask-mode"))
            if masks is False:
                return []
            if masks:
                group.mask = masks[0]
                for extra in masks[1:]:     # the mask's own mask multiplies in
                    group = Group(children=[group], mask=extra)
        # opacity and blending apply to the result, so they go on the outermost layer
        group.opacity = min(opacity, 1.0)
        group.blend = blend
        group.isolate = isolate
        return [group]

    def _filter_hides(self, el, ctx, style):
        """Whether the element's filter keeps it from being drawn, for the geometry pass:
        decided once per element and context, as its box (which the decision needs) is, in
        its own user space (transform-free: only an overflowing device rectangle, which the
        drawing pass refuses, would decide otherwise). The chain of matrices is left out,
        of the key and of the filter resolved to decide (hashing it, and device_scale's f32
        product, cost its length, and a walk under a transform on every level asks n^2/2
        times): it scales primitives' lengths, never decides whether a filter applies."""
        key = (el, style, ctx.viewport, ctx.use_stack, ctx.context_fill, ctx.context_stroke,
               tuple(self.ref_stack))
        try:
            return self._hidden_memo[key]
        except KeyError:
            from .filters import element_filters
            g = ctx_with(ctx, transform=IDENTITY, chain=(), geometry=True, clip=False)
            hidden = self._hidden_memo[key] = element_filters(
                self, el, style, g, lambda: self.object_bbox(el, ctx, style)) is False
            return hidden

    def _plain_wrap(self, style):
        """Whether wrap() leaves the nodes of an element of this style as they are, for an
        element without clip-path, mask or filter of its own (_path_run's): opacity 1, normal
        blending, no isolation."""
        if style.cache.get("plain-wrap"):
            return True
        if (parse_opacity(style.get("opacity")) < 1
                or (style.get("mix-blend-mode") or "normal").strip() != "normal"
                or style.get("isolation").strip() == "isolate"):
            return False
        style.cache["plain-wrap"] = True        # what wrap() itself would conclude
        return True

    def object_bbox(self, el, ctx, style):
        """Object bounding box of an element in its own user space (after its transform).

        Memoized per element and all the box can depend on: its computed style (Styles are
        shared: the same object, the same values), the context but for its transform (the
        box is in the element's own space; viewport, use stack, context paints and the chain
        of matrices stay in the key) and the clip paths, masks and markers being built.
        element()'s geometry pass is memoized the same way with the transform in the key (a
        box maps each shape's box through the product of the transforms from the element
        down, which memoized subtrees could only reproduce to an ulp). Without them a box
        walked its whole subtree at every filtered or clipped level of a nesting (n^2/2
        builds), and deciding in the geometry pass whether each level's filter draws, which
        needs its box, built each subtree twice (2^n)."""
        g = ctx_with(ctx, transform=IDENTITY, geometry=True, clip=False)
        key = (el, style, g, tuple(self.ref_stack))
        try:
            return self._bbox_memo[key]
        except KeyError:
            pass
        tag = el.tag
        if tag in SHAPES:
            nodes = self.shape(el, g, style)
        elif tag == "switch":
            # the child it renders, not the others
            nodes = self.switch(el, g, style)
        elif tag in CONTAINERS:
            nodes = self.children(el, g, style)
        elif tag == "svg":
            # in the inner coordinate system its clip-path, mask and filter are applied in
            nodes = self.children(el, ctx_with(g, viewport=self._svg_viewport(el, style, ctx)),
                                  style)
        elif tag == "use":
            nodes = self.use(el, g, style, translated=True)   # x, y are part of its transform
        elif tag == "image":
            nodes = self.image(el, g, style)
        elif tag == "text":
            nodes = self.text(el, g, style)
        else:
            nodes = []
        box = None
        for f in Scene(1, 1, Group(children=nodes)).fills():
            box = union(box, path_bounds(f.path))
        self._bbox_memo[key] = box
        return box

    # -- containers ------------------------------------------------------------------------
    def viewport_clip(self, x, y, w, h, ctx) -> Group:
        return Group(children=[Fill(rect_path(x, y, w, h).transformed(ctx.transform))])

    def overflow_hidden(self, el, style, parent=None):
        """``parent``: the element ``inherit`` takes the value of when it is not the document
        parent (the <use> of a symbol or svg: the parent in the rendering tree)."""
        # (lower-cased by the cascade: overflow is among document.KEYWORD_PROPERTIES)
        v = (el.specified.get("overflow") or "").strip()
        if v in ("visible", "auto", "initial", "unset"):   # SVG: auto is visible
            return False
        if v in ("hidden", "scroll", "clip"):
            return True
        parent = el.parent if parent is None else parent
        if v == "inherit" and parent is not None:
            return self.overflow_hidden(parent, style)
        # none or an invalid value (CSS drops the declaration): the UA style sheet's
        # `svg:not(:root), symbol, image, marker, pattern { overflow: hidden }`
        return el.tag in CLIPPING_BY_DEFAULT and el.parent is not None

    def nested_svg(self, el, ctx, style, size_override=None, effects=False, parent=None):
        """The content of a nested <svg> under its viewport transform (x/y, viewBox) and
        viewport clip. ``effects``: with its clip-path, mask, filter and opacity applied in
        that inner coordinate system, where the root <svg> has them too (and browsers and
        resvg put them on a nested one)."""
        if zero_size_viewbox(el.get("viewBox")):
            return []           # SVG 2: a zero viewBox width or height disables rendering
        get = self.length_getter(el, style, ctx)
        x, y = get("x", "x", 0.0), get("y", "y", 0.0)
        w = get("width", "x", ctx.viewport[0])
        h = get("height", "y", ctx.viewport[1])
        if size_override is not None:
            ow, oh = size_override
            w = w if ow is None else ow
            h = h if oh is None else oh
        empty = w <= 0 or h <= 0
        if empty and self.overflow_hidden(el, style, parent):
            return []           # clipped to an empty viewport
        # an empty viewport disables nothing (SVG 2 dropped SVG 1.1's rule): with overflow
        # visible, resvg and Chromium draw the content at x/y, the viewBox left out as
        # its scale would be zero
        vb = None if empty else parse_viewbox(el.get("viewBox"))
        m = translate(x, y)
        if vb is not None:
            # in f32 as usvg maps it: whole-pixel edges (filter regions, pattern tiles) then
            # fall where resvg's do
            m = compose(m, viewbox_transform_f32(vb, parse_aspect(el.get("preserveAspectRatio")),
                                                 w, h))
            viewport = (vb[2], vb[3])
        else:
            viewport = (w, h)
        inner = ctx_with(ctx, transform=compose(ctx.transform, m), viewport=viewport,
                         chain=ctx.chain + (m,))
        nodes = self.children(el, inner, style)
        if effects:
            nodes = self.wrap(el, style, inner, nodes)
        if nodes and not (ctx.geometry or ctx.clip) and self.overflow_hidden(el, style, parent):
            # the viewport clips the filtered result too (a filter region may reach past it)
            clipped = Group(children=nodes, clip=self.viewport_clip(x, y, w, h, ctx))
            if (effects and len(nodes) == 1 and isinstance(nodes[0], Group)
                    and (style.get("mix-blend-mode") or "normal").strip() != "normal"):
                # the element's blend mixes its clipped result with what is below: inside
                # the clip's layer it would mix with nothing (resvg 0.48.1 draws it so)
                clipped.blend, nodes[0].blend = nodes[0].blend, "normal"
            nodes = [clipped]
        return nodes

    def _svg_viewport(self, el, style, ctx):
        """The viewport a nested <svg> gives its content: its viewBox size, else its own."""
        vb = parse_viewbox(el.get("viewBox"))
        if vb is not None:
            return (vb[2], vb[3])
        get = self.length_getter(el, style, ctx)
        return (get("width", "x", ctx.viewport[0]), get("height", "y", ctx.viewport[1]))

    def use_translated(self, el, style, ctx):
        """ctx with the <use> element's x/y translation appended to its transform."""
        attrs = el.attrs
        x = self.length(attrs.get("x"), "x", style, ctx.viewport, 0.0)
        y = self.length(attrs.get("y"), "y", style, ctx.viewport, 0.0)
        if x == 0.0 and y == 0.0:
            return ctx
        return ctx_with(ctx, transform=compose(ctx.transform, translate(x, y)))

    def use(self, el, ctx, style, translated=False):
        """The instantiated content of a <use>; ``translated``: ctx already holds its x/y."""
        target = use_target(el, self.doc, self._use_targets, self._links_back_memo)
        if target is None or id(target) in ctx.use_stack or len(ctx.use_stack) >= MAX_USE_DEPTH:
            return []
        if not translated:
            ctx = self.use_translated(el, style, ctx)
        if (target.tag in _INSTANCEABLE and not (ctx.geometry or ctx.clip)
                and self.nodes_by_id is None):
            # content that draws the same in every instance but for its placement is
            # prepared once (see _Instanced)
            key = (target, style, ctx.viewport, el.attrs.get("width"), el.attrs.get("height"))
            got = self._instanced.get(key, self._instanced)
            if got is self._instanced:
                got = self._instanced[key] = self._prepare_instance(el, target, style, ctx)
            if got is not None:
                return self._instance(got, ctx)
        get = self.length_getter(el, style, ctx)
        c = ctx_with(ctx, use_stack=ctx.use_stack + (id(target),))
        if not ctx.geometry:
            def bbox_fn():
                return self.object_bbox(el, ctx, style)
            c = ctx_with(c, context_fill=self.context_paint(style, "fill", ctx, bbox_fn),
                         context_stroke=self.context_paint(style, "stroke", ctx, bbox_fn))
        if ctx.clip and target.tag not in SHAPES | {"text"}:
            return []   # in a clipPath, <use> may only point at shapes and text
        if target.tag == "symbol":
            return self.symbol(target, el, c, style)
        if target.tag == "svg":
            w = get("width", "x", None)
            h = get("height", "y", None)
            if not conditions_pass(target):
                return []
            tstyle = style.child(target)
            if tstyle.get("display").strip() == "none":
                return []
            # its own transform (SVG 2: the svg element takes one) applies in the use's
            # space, as where it stands (resvg 0.48 draws it so)
            m = self.element_transform(target, tstyle, c)
            if m is None:
                return []
            if m is not IDENTITY:
                c = ctx_with(c, transform=compose(c.transform, m), chain=c.chain + (m,))
            return self.nested_svg(target, c, tstyle, size_override=(w, h), effects=True,
                                   parent=el)
        return self.element(target, c, style)

    def symbol(self, sym, use_el, ctx, use_style):
        # 'display' does not apply to <symbol>: it is drawn through <use> regardless
        if zero_size_viewbox(sym.get("viewBox")):
            return []           # SVG 2: a zero viewBox width or height disables rendering
        style = use_style.child(sym)
        frame = self._symbol_frame(sym, style, use_el, use_style, ctx)
        if frame is None:
            return []
        m, viewport, (sx, sy, w, h) = frame
        # a transform on <symbol> is SVG 2 only; like resvg we follow SVG 1.1 and ignore it
        inner = ctx_with(ctx, transform=compose(ctx.transform, m), viewport=viewport)
        if inner.sampled is not None and _has_filter(style):
            inner = ctx_with(inner, sampled=None)   # (wrapped in the symbol's filter below)
        nodes = self.children(sym, inner, style)
        if (not nodes or ctx.geometry or ctx.clip
                or not self.overflow_hidden(sym, style, use_el)):
            return self.wrap(sym, style, ctx, nodes)
        nodes = [Group(children=nodes, clip=self.viewport_clip(sx, sy, w, h, ctx))]
        return self.wrap(sym, style, ctx, nodes)

    def _symbol_frame(self, sym, style, use_el, use_style, ctx):
        """Where a <use> puts a <symbol> (``style``: the symbol's): (its x/y and viewBox
        transform, the viewport its content sees, the rectangle (x, y, w, h) its overflow
        clips to); None where a viewBox meets a viewport of no size (nothing is drawn).
        Width and height are the use's, else the symbol's, else the viewport's."""
        get = self.length_getter(use_el, use_style, ctx)
        w, h = get("width", "x", None), get("height", "y", None)
        sget = self.length_getter(sym, style, ctx)
        if w is None:
            w = sget("width", "x", ctx.viewport[0])
        if h is None:
            h = sget("height", "y", ctx.viewport[1])
        sx, sy = sget("x", "x", 0.0), sget("y", "y", 0.0)
        vb = parse_viewbox(sym.get("viewBox"))
        m = translate(sx, sy)
        viewport = (w, h)
        if vb is not None:
            if w <= 0 or h <= 0:
                return None
            m = compose(m, viewbox_transform(vb, parse_aspect(sym.get("preserveAspectRatio")),
                                             w, h))
            viewport = (vb[2], vb[3])
        return m, viewport, (sx, sy, w, h)

    def _prepare_instance(self, use_el, target, use_style, ctx):
        """What a <use> of ``target`` draws, as an _Instanced, when every instance with the
        key use() files it under draws it alike but for its transform; None when it may not
        (then each instance is built as it stands). The key holds all the content's build
        reads besides the transform: the target, the use's computed style (the content's
        styles are its descendants: Styles are shared by their values, so one Style object
        is one set of inherited values, CSS having matched the original tree already), the
        viewport, and the use's width and height (a symbol's viewport). The content may then
        be shapes with colours (no paint server, context paint or marker) in groups without
        effects; text, images, nested <use> and <svg>, switch and unsupported elements (each
        instance warns) go the general way."""
        prepared = _Instanced()
        vctx = Ctx(viewport=ctx.viewport, use_stack=(id(target),))
        tag = target.tag
        if tag == "symbol":
            if zero_size_viewbox(target.get("viewBox")):
                return None
            style = use_style.child(target)
            if (not self._instance_plain(style)
                    or (target.specified.get("overflow") or "").strip() == "inherit"):
                return None
            frame = self._symbol_frame(target, style, use_el, use_style, vctx)
            if frame is None:
                return None
            m, viewport, (sx, sy, w, h) = frame
            prepared.symbol_m = m
            if self.overflow_hidden(target, style, use_el):
                prepared.clip_rect = (sx, sy, w, h)
            inner = ctx_with(vctx, viewport=viewport)
            for child in target.children:
                if not self._prepare_element(child, style, inner, (), prepared):
                    return None
        elif tag in SHAPES or tag in ("g", "a"):
            if not self._prepare_element(target, use_style, vctx, (), prepared):
                return None
        else:
            return None
        return prepared

    def _instance_plain(self, style):
        """Whether wrap() gives an element of this style its nodes as they are (and
        _element() puts it in no other space): no filter, clip path or mask, opacity 1,
        normal blending, no isolation."""
        if _has_filter(style):
            return False
        for name in ("clip-path", "mask"):
            value = style.specified.get(name)
            if value and value.strip() != "none":
                return False
        return self._plain_wrap(style)

    def _prepare_element(self, el, parent_style, ctx, matrices, prepared):
        """_prepare_instance for one element of the content and what is below it, as
        _element() would build it (``matrices``: the element transforms between the
        content's top and ``el``); False when the content must be built per instance."""
        tag = el.tag
        if tag not in RENDERED:
            return tag not in UNSUPPORTED
        if not conditions_pass(el):
            return True
        prepared.count += 1
        style = parent_style.child(el)
        if style.get("display").strip() == "none":
            return True
        if (tag not in SHAPES and tag not in ("g", "a")) or not self._instance_plain(style):
            return False
        if self.transform_box(el) != "view-box":
            return False        # (the transform's reference box is the element's own box)
        m = self.element_transform(el, style, ctx)
        if m is None:
            return True
        if m is not IDENTITY:
            matrices = matrices + (m,)
        if tag not in SHAPES:
            for child in el.children:
                if not self._prepare_element(child, style, ctx, matrices, prepared):
                    return False
            return True
        if "pathLength" in el.attrs:
            return False
        path = (self.path_data(el) if tag == "path"
                else shape_path(el, self.length_getter(el, style, ctx)))
        if path is None:
            return True
        if path.is_empty():
            return False        # (a dot, markers: see shape())
        if style.get("visibility").strip() in ("hidden", "collapse"):
            return True
        antialias, order, rule, marked = self._draw_plan(style)
        if marked:
            return False
        verbs = path.verbs
        fillable = not (len(verbs) == 2 and verbs[1] == LINE)
        for item in order:
            if item == "markers" or (item == "fill" and not fillable):
                continue
            value = self.paint_value(style, item)
            if value in ("context-fill", "context-stroke") or parse_url(value) is not None:
                return False
            ref = self.resolve_paint(style, item, ctx, None)
            if ref is None:
                continue
            if item == "fill":
                # mapped by a point_mapper of its own, not through the document batch's
                # SharedPoints (which would keep a count for every instance's matrix)
                verbs, points = path._freeze()
                points = np.ascontiguousarray(points, dtype=np.float64)
                prepared.items.append((matrices, (verbs, point_mapper(points), points),
                                       path, ref.paint,
                                       "evenodd" if rule == "evenodd" else "nonzero",
                                       ref.opacity, antialias))
            else:
                prepared.items.append((matrices, None, path, style, antialias, ctx.viewport,
                                       None))
        return True

    def _instance(self, prepared, ctx, top=None, unmapped=None, counted=False):
        """The nodes of one instance of prepared content (_Instanced) under the <use>'s
        context: the transforms composed as the build composes them, element by element,
        so every point is where building the instance would put it. ``top``: the use's
        transform where ``ctx`` does not hold it (_use_run's: then the content clips to no
        viewport); ``unmapped``: a list to which each fill's (Path, points, matrix) is
        appended for the caller to map, the Path's points left unset (_use_run);
        ``counted``: the caller has counted the content's elements (MAX_NODES)."""
        if not counted:
            self.nodes_made += prepared.count
            if self.nodes_made > MAX_NODES:
                raise SvgError("document expands to too many elements")
        if top is None:
            top = ctx.transform
        if prepared.symbol_m is not None:
            top = compose(top, prepared.symbol_m)
        out = []
        last, t = (), top
        new_path = Path.__new__             # (Path._of_arrays written out, as _path_run)
        for matrices, fill, path, a, b, c, d in prepared.items:
            if matrices is not last:
                t, last = _composed(top, matrices), matrices
            if fill is not None:
                if t == IDENTITY:                   # (path.transformed(t))
                    device = path
                elif unmapped is None:
                    device = new_path(Path)
                    device._arrays = fill[0], fill[1](t)
                else:
                    device = new_path(Path)
                    unmapped.append((device, fill, t))
                out.append(Fill(device, a, b, c, d))
            else:
                out.extend(self._instance_stroke(path, a, ctx, t, c, b, unmapped))
        if out and prepared.clip_rect is not None:
            out = [Group(children=out, clip=self.viewport_clip(*prepared.clip_rect, ctx))]
        return out

    def _inherits_within(self, target) -> bool:
        """Whether an element of ``target``'s subtree may take a value from the element
        above it other than by inheritance: a value "inherit" (of a property that is not
        inherited, such as opacity, it takes the parent's own), or a var() (resolved later).
        Without either, the subtree's values are the same under a <use> that specifies only
        LAYER_PROPERTIES as under the style the use inherits from (see Style.child)."""
        got = self._inherits_memo.get(target)
        if got is None:
            var_raw = self.doc.var_raw
            stack, got = [target], False
            while stack and not got:
                el = stack.pop()
                got = (var_raw and id(el) in var_raw) or \
                    "inherit" in "\n".join(el.specified.values()).lower()
                stack.extend(el.children)
            self._inherits_memo[target] = got = bool(got)
        return got

    def _instance_stroke(self, path, style, ctx, t, viewport, antialias, unmapped=None):
        """stroke() of a path of prepared content under an instance's transform ``t``: a
        solid scaling stroke's outline (_instance_outline's, made once for each linear part)
        mapped by ``t`` as stroke() maps it (a plot's thousands of markers), or left to the
        caller to map with ``unmapped`` (see _instance). Other strokes (hairlines, dashed,
        non-scaling) are stroke()'s for each instance."""
        got = self._instance_outline(path, style, ctx, t, viewport, antialias)
        if got is False:
            return self.stroke(path, style, ctx_with(ctx, transform=t, viewport=viewport),
                               LazyBounds(path), antialias)
        if not got:
            return []
        outline, ref, opacity, arrays = got
        if unmapped is None or t == IDENTITY:
            return _stroke_fills(outline, t, ref, opacity, antialias)
        device = Path.__new__(Path)
        unmapped.append((device, arrays, t))
        return [Fill(device, ref.paint, opacity=opacity, antialias=antialias)]

    def _instance_outline(self, path, style, ctx, t, viewport, antialias):
        """The stroke of a path of prepared content under an instance's transform ``t``,
        where it depends on ``t`` only through its linear part (its plan: _stroke_plan): a
        solid scaling stroke's outline in user space, (outline Path, PaintRef, opacity,
        (verbs, None, C-contiguous float64 points)), kept per (path, style, linear part,
        viewport, antialias); () for no stroke (or an outline that draws nothing, which
        _stroke_fills leaves out); False for a stroke that stroke() makes per instance
        (hairlines, dashed, non-scaling)."""
        key = (id(path), style, t[:4], viewport, antialias)
        got = self._instance_strokes.get(key)
        if got is None:
            c = ctx_with(ctx, transform=t, viewport=viewport)
            ref = self.resolve_paint(style, "stroke", c, LazyBounds(path))
            plan = None if ref is None else self._stroke_plan(style, c, antialias)
            if plan is None:
                got = ()                    # no stroke
            elif plan[0] is None or plan[0] == "hairline":
                got = False
            else:
                outline = self._scaling_outline(path, style, c, plan)
                # (_stroke_fills' test: an outline that draws nothing makes no fill)
                if outline is None or outline.is_empty():
                    got = ()
                else:
                    v, p = outline._freeze()
                    got = (outline, ref, _stroke_opacity(plan, ref),
                           (v, None, np.ascontiguousarray(p, dtype=np.float64)))
            self._instance_strokes[key] = got
        return got

    def _instance_hairline(self, style, ctx, t, viewport, antialias):
        """For a stroke _instance_outline leaves to stroke() per instance: where stroke()
        draws it as a hairline under ``t`` (which its linear part decides: _stroke_plan),
        (the Fills' style (paint, rule, opacity, antialias), the cap's outset and the alpha
        the hairline kernel blends with, as _hairline_fills gives hairline_path them), kept
        per (style, linear part, viewport, antialias); else None (dashed, non-scaling)."""
        key = ("hairline", style, t[:4], viewport, antialias)
        strokes = self._instance_strokes
        got = strokes.get(key, strokes)
        if got is strokes:
            got = None
            c = ctx_with(ctx, transform=t, viewport=viewport)
            ref = self.resolve_paint(style, "stroke", c, None)
            plan = None if ref is None else self._stroke_plan(style, c, antialias)
            if plan is not None and plan[0] == "hairline":
                opacity = _stroke_opacity(plan, ref)
                got = ((ref.paint, "nonzero", opacity, antialias),
                       float(CAP_OUTSET.get(plan[1], 0.0)),
                       float(use_alpha(blend_alpha(ref.paint, opacity))))
            strokes[key] = got
        return got

    # -- shapes and painting -----------------------------------------------------------------
    def path_data(self, el) -> Path:
        """The Path of a <path> element. The document's path data is read in one go when
        the first one is asked for."""
        if self._path_index is None:
            elements = self.doc.paths
            self._path_index = dict(zip(elements, range(len(elements))))
            self._path_batch = PathBatch([e.attrs.get("d") or "" for e in elements])
        i = self._path_index.get(el)
        if i is None:
            return parse_path_data(el.get("d") or "")
        return self._path_batch.path(i)

    def _batch_curved(self) -> list:
        """Per path of the document's path batch whether it has a verb besides MOVE, LINE and
        CLOSE (a curve or an arc's cubics), from all its verbs at once: _path_run strokes the
        others in one kernel call per run."""
        if self._path_curved is None:
            verbs = self._path_batch.verbs
            counts = np.zeros(len(verbs) + 1, np.int64)
            np.cumsum((verbs != MOVE) & (verbs != LINE) & (verbs != CLOSE), out=counts[1:])
            at = self._path_batch.offsets[0]
            self._path_curved = (counts[at[1:]] > counts[at[:-1]]).tolist()
        return self._path_curved

    def _odd_in_run(self, i0, n, filled, stroked) -> list:
        """The positions in a run of the batch's paths i0 .. i0 + n - 1 of those _path_run
        must hand to its one(): read with Python's float (status), drawing nothing, and when
        filled "M L" (no fill), when stroked curved (not for the lines stroke kernel)."""
        if self._path_odd is None:
            batch = self._path_batch
            verbs = batch.verbs
            at = batch.offsets[0]
            two = at[1:] - at[:-1] == 2
            two[two] = verbs[at[:-1][two] + 1] == LINE
            self._path_odd = (np.array(batch.status, np.bool_)
                              | ~np.array(batch.drawing(), np.bool_), two,
                              np.array(self._batch_curved(), np.bool_))
        odd, lone_line, curved = (flags[i0:i0 + n] for flags in self._path_odd)
        if filled:
            odd = odd | lone_line
        if stroked:
            odd = odd | curved
        return np.flatnonzero(odd).tolist()

    def shape(self, el, ctx, style):
        if ctx.geometry and el.tag in _BOXED_SHAPES:
            # a bounding box from the shape's parameters, without its outline
            box = shape_box(el, self.length_getter(el, style, ctx))
            return [] if box is None else self.draw_path(None, style, ctx, bbox=box)
        if el.tag == "path":
            path = self.path_data(el)
        else:
            path = self._shape_path(el, style, ctx)
        if path is None:
            return []
        if path.is_empty():
            # "M x y Z" is a zero-length subpath, not a lone moveto: SVG 2 strokes it as a dot
            # with round and square caps (as tiny-skia does), and its vertices take markers
            # (a start and an end marker; resvg too)
            if _CLOSE_BYTE not in path.verbs.tobytes():
                return []
            if style.get("visibility").strip() in ("hidden", "collapse") and not ctx.geometry:
                return []
            dot = (style.get("stroke-linecap").strip() in ("round", "square")
                   and style.get("stroke").strip() != "none")
            out = self.draw_path(_zero_length_closes(path), style, ctx) if dot else []
            if el.tag in MARKABLE and not (ctx.geometry or ctx.clip):
                marks = self.markers(path, style, ctx)
                order = paint_order(style.get("paint-order"))
                out = marks + out if order.index("markers") < order.index("stroke") \
                    else out + marks
            return out
        if style.get("visibility").strip() in ("hidden", "collapse") and not ctx.geometry:
            return []
        dash_scale = None
        if "pathLength" in el.attrs and not (ctx.geometry or ctx.clip):
            dash_scale = self._path_length_scale(el, path, style, ctx)
        return self.draw_path(path, style, ctx, markers=el.tag in MARKABLE,
                              dash_scale=dash_scale)

    def _shape_path(self, el, style, ctx):
        """shape_path of a basic shape, kept where the same element is likely built again:
        in a bounding box's geometry pass (the drawing pass follows), inside a <use> and a
        clip path, mask, marker or pattern (each instance builds it anew: a marker on ten
        thousand vertices). Keyed by all the path depends on: the element, its computed style
        (font size) and the viewport (percentages). Paths are not drawn into once made."""
        key = (el, style, ctx.viewport)
        memo = self._shape_memo
        path = memo.get(key, memo)
        if path is memo:
            path = shape_path(el, self.length_getter(el, style, ctx))
            if ctx.geometry or ctx.use_stack or self.ref_stack:
                memo[key] = path
        return path

    def _path_length_scale(self, el, path, style, ctx):
        """The factor a shape's ``pathLength`` scales its dash array and offset by (SVG 2
        painting, the stroke shape: dash positions are in the author's length), or None for
        none: no pathLength, an erroneous one, or no dashes. A pathLength of 0 scales by
        infinity (SVG 2 paths: zero stays zero, a positive length becomes +∞): a factor that
        makes every nonzero dash and offset longer than the path stands for it."""
        author = author_path_length(el)
        params = self.stroke_params(style, ctx) if author is not None else None
        if params is None or params[4] is None:
            return None
        length = dash_length(path, dash_resolution(ctx.transform))
        if not length > 0:
            return None                 # no distance along the path to scale
        if author > 0:
            return length / author
        nonzero = [abs(v) for v in (*params[4], params[5]) if v]
        return 2.0 * (length + 1.0) / min(nonzero)

    def draw_path(self, path: Path, style: Style, ctx: Ctx, markers=False, bbox=None,
                  dash_scale=None) -> list:
        """Fill, stroke and markers of a user-space path with a computed style.

        In a clip path only the fill outline is produced (black, clip-rule); when collecting
        geometry for bounding boxes only the plain outline. ``dash_scale`` multiplies the dash
        array and offset (an element's pathLength).
        """
        if ctx.geometry:
            # Bounding boxes of groups are unions of their children's boxes mapped through
            # the transforms (as browsers and resvg compute them), not of the mapped outlines.
            box = bbox.get() if isinstance(bbox, LazyBounds) else bbox or path_bounds(path)
            if box is None:
                return []
            x0, y0, x1, y1 = box
            return [Fill(rect_path(x0, y0, x1 - x0, y1 - y0).transformed(ctx.transform))]
        # a lone line segment encloses nothing
        verbs = path.verbs
        fillable = not (len(verbs) == 2 and verbs[1] == LINE)
        antialias, order, rule, marked = self._draw_plan(style)
        if ctx.clip:
            # an invalid value is dropped, so the parent's applies (CSS Syntax 3 §8)
            rule = style.get_valid("clip-rule", _clip_rule, "nonzero")
            return [Fill(path.transformed(ctx.transform), Solid((0, 0, 0, 1)), rule=rule,
                         antialias=antialias)]
        if bbox is None:
            bbox = LazyBounds(path)
        out = []
        for item in order:
            if item == "fill" and fillable:
                ref = self.resolve_paint(style, "fill", ctx, bbox)
                if ref is not None:
                    out.append(Fill(path.transformed(ctx.transform), ref.paint,
                                    "evenodd" if rule == "evenodd" else "nonzero",
                                    ref.opacity, antialias))
            elif item == "stroke":
                out.extend(self.stroke(path, style, ctx, bbox, antialias, dash_scale))
            elif item == "markers" and markers and marked:
                out.extend(self.markers(path, style, ctx))
        return out

    @staticmethod
    def _draw_plan(style):
        """What draw_path reads of a style on every shape: (antialias, paint order, fill-rule,
        whether it names markers); kept with the (shared) style. The properties are all
        inherited, so a style specifying none of them has its parent's plan (the tiger's
        styles differ in paint and stroke width only); found without recursion, as deep
        nesting must not reach Python's recursion limit."""
        plan = style.cache.get("draw-plan")
        if plan is not None:
            return plan
        passed = []
        while style.parent is not None and _DRAW_PLAN_PROPERTIES.isdisjoint(style.specified):
            passed.append(style)
            style = style.parent
            plan = style.cache.get("draw-plan")
            if plan is not None:
                break
        else:
            plan = style.cache["draw-plan"] = Builder._own_draw_plan(style)
        for s in passed:
            s.cache["draw-plan"] = plan
        return plan

    @staticmethod
    def _own_draw_plan(style):
        return (style.get("shape-rendering").strip() not in ("crispEdges", "optimizeSpeed"),
                paint_order(style.get("paint-order")), style.get("fill-rule").strip(),
                any(style.get(f"marker-{kind}") != "none" for kind in ("start", "mid", "end")))

    def stroke_params(self, style, ctx):
        """(width, join, cap, miterlimit, dashes, offset) in user units, None for no stroke.
        Kept with the (shared) style: they depend on nothing else but the viewport."""
        key = ("stroke-params", ctx.viewport, self.options.dpi)
        try:
            return style.cache[key]
        except KeyError:
            params = style.cache[key] = self._stroke_params(style, ctx.viewport)
            return params

    def _stroke_params(self, style, viewport):
        width = self.length(style.get("stroke-width"), "xy", style, viewport, 1.0)
        if width is None or width <= 0:
            return None
        join = style.get("stroke-linejoin").strip()
        if join not in ("miter", "round", "bevel", "miter-clip", "arcs"):
            join = "miter"
        cap = style.get("stroke-linecap").strip()
        if cap not in ("butt", "round", "square"):
            cap = "butt"
        # a number below 1 is an error in SVG; resvg (so its references) clamps it to 1
        limit = max(1.0, parse_number(style.get("stroke-miterlimit"), 4.0))
        # the lengths up to the first that does not parse, as in resvg; a negative one or a
        # zero sum draws a solid stroke (geometry.stroke.dash_pattern)
        dashes = dash_pattern([self.length_px(v, unit, "xy", style, viewport)
                               for v, unit in parse_length_list(style.get("stroke-dasharray"))])
        offset = self.length(style.get("stroke-dashoffset"), "xy", style, viewport, 0.0)
        return width, join, cap, limit, dashes, offset or 0.0

    def stroke(self, path, style, ctx, bbox, antialias, dash_scale=None):
        ref = self.resolve_paint(style, "stroke", ctx, bbox)
        if ref is None:
            return []
        plan = self._cached_stroke_plan(style, ctx, antialias)
        if plan is None:
            return []
        if plan[0] is None:
            return self._general_stroke(path, style, ctx, ref, antialias, dash_scale)
        # a solid, scaling stroke: everything but the path follows from style and transform
        opacity = _stroke_opacity(plan, ref)
        if plan[0] == "hairline":
            return _hairline_fills(path, ctx.transform, plan[1], None, 0.0, 1.0, ref, opacity,
                                   antialias)
        return _stroke_fills(self._scaling_outline(path, style, ctx, plan), ctx.transform, ref,
                             opacity, antialias)

    def _scaling_outline(self, path, style, ctx, plan):
        """The outline, in user space, of a solid scaling stroke of ``path`` (stroke()'s
        plan: everything but the path follows from the style and the transform's linear
        part)."""
        v, p = path._freeze()
        codes, stroke_width, tolerance = plan
        if not v.tobytes().translate(None, _LINE_VERBS):
            # lines only: stroke_path's own dispatch, without its per-call conversions
            join, cap, limit, offset = codes
            ov, op = stroke_kernels.stroke_lines(v, p, stroke_width / 2.0, tolerance, join,
                                                 cap, limit, _SOLID, offset)
            return Path._of_arrays(ov, op)
        _, join, cap, limit, dashes, offset = self.stroke_params(style, ctx)
        return stroke_path(path, stroke_width, join=join, cap=cap, miterlimit=limit,
                           dashes=dashes, dash_offset=offset, tolerance=tolerance)

    @staticmethod
    def outline_reach(params):
        """User units beyond its path within which a stroke (stroke_params) draws: half its
        width, but at a miter join the miter limit times that (square caps and clipped or
        arc joins stay inside it too, a square cap's corner at the square root of 2)."""
        return params[0] / 2 * max(params[3], math.sqrt(2.0))

    def stroke_reach(self, style, ctx):
        """Device px beyond which a path's stroke draws nothing (0 for no stroke), None when
        that depends on the path (dashes): the outline's reach (outline_reach) under the
        transform times its largest stretch (at most the root of the sum of its four
        squares); a hairline within a pixel."""
        params = self.stroke_params(style, ctx)
        if params is None:
            return 0.0
        if params[4]:
            return None                 # (dash_coverage and the phase follow the whole path)
        reach = self.outline_reach(params)
        if style.get("vector-effect").strip() == "non-scaling-stroke":
            return reach * self.root_scale + 1.0
        a, b, c, d, _, _ = ctx.transform
        return reach * math.sqrt(a * a + b * b + c * c + d * d) + 1.0

    def _cached_stroke_plan(self, style, ctx, antialias):
        key = ("stroke-plan", ctx.transform, ctx.viewport, self.options.dpi, antialias)
        try:
            return style.cache[key]
        except KeyError:
            plan = style.cache[key] = self._stroke_plan(style, ctx, antialias)
            return plan

    def _stroke_plan(self, style, ctx, antialias):
        """What stroke() needs of a style under one transform: None for no stroke; (None,)
        for strokes that depend on the path (non-scaling, dashed); ("hairline", cap, opacity
        factor) for a stroke drawn as a hairline (geometry.hairline); else ((join code, cap
        code, miterlimit, dash offset), stroke width, tolerance)."""
        params = self.stroke_params(style, ctx)
        if params is None:
            return None
        width, join, cap, limit, dashes, offset = params
        if style.get("vector-effect").strip() == "non-scaling-stroke" or dashes:
            return (None,)
        coverage = hairline_coverage(width, ctx.transform, antialias)
        if coverage is not None:
            return ("hairline", cap, coverage)
        scale = mean_scale(ctx.transform)
        stroke_width = width
        tolerance = 0.25 / max(scale, 1e-9)
        hw = stroke_width / 2.0
        if not (hw > 0 and math.isfinite(hw)):
            return None       # stroke_path draws nothing
        codes = (stroke_kernels.JOIN_CODES.get(join, 0), stroke_kernels.CAP_CODES.get(cap, 0),
                 float(max(1.0, limit)), float(offset))
        return codes, stroke_width, tolerance

    def _general_stroke(self, path, style, ctx, ref, antialias, dash_scale=None):
        width, join, cap, limit, dashes, offset = self.stroke_params(style, ctx)
        if dashes and dash_scale is not None:
            # (a pattern scaled past floats, or to nothing, is solid, as such a pattern given)
            dashes = dash_pattern([d * dash_scale for d in dashes])
            offset = offset * dash_scale if dashes and math.isfinite(offset * dash_scale) else 0.0
        non_scaling = style.get("vector-effect").strip() == "non-scaling-stroke"
        opacity = ref.opacity
        if non_scaling:
            # Stroke in device space: the width is in the outer viewport's px.
            device_path = path.transformed(ctx.transform)
            dev_width = width * self.root_scale
            if dashes:
                dashes = [d * self.root_scale for d in dashes]
                offset *= self.root_scale
                coverage = dash_coverage(dashes, device_path, dev_width, cap, 1.0)
                if coverage is not None:
                    opacity, dashes = opacity * coverage, None
            hair = hairline_coverage(dev_width, IDENTITY, antialias)
            if hair is not None:
                return _hairline_fills(device_path, IDENTITY, cap, dashes, offset, 1.0, ref,
                                       opacity * hair, antialias)
            outline = stroke_path(device_path, dev_width, join=join, cap=cap, miterlimit=limit,
                                  dashes=dashes, dash_offset=offset, tolerance=0.25)
            return [Fill(outline, ref.paint, opacity=opacity, antialias=antialias)]
        scale = mean_scale(ctx.transform)
        if dashes:
            coverage = dash_coverage(dashes, path, width, cap, scale)
            if coverage is not None:
                opacity, dashes = opacity * coverage, None
        hair = hairline_coverage(width, ctx.transform, antialias)
        if hair is not None:
            return _hairline_fills(path, ctx.transform, cap, dashes, offset,
                                   dash_resolution(ctx.transform), ref, opacity * hair, antialias)
        tolerance = 0.25 / max(scale, 1e-9)
        outline = stroke_path(path, width, join=join, cap=cap, miterlimit=limit,
                              dashes=dashes, dash_offset=offset, tolerance=tolerance,
                              resolution=dash_resolution(ctx.transform))
        return _stroke_fills(outline, ctx.transform, ref, opacity, antialias)

    # -- paints ----------------------------------------------------------------------------
    def paint_value(self, style, name):
        """The specified paint, resolved up the ancestors without recursion and cached on each
        style passed. An invalid value paints as resvg paints it: a fill black, a stroke none."""
        key = ("paint", name)
        passed = []
        while True:
            value = style.cache.get(key)
            if value is not None:
                break
            passed.append(style)
            v = style.specified.get(name)
            if v is not None and v != "inherit":
                value = v.strip() if valid_paint(v) else "black" if name == "fill" else "none"
                break
            if style.parent is None:
                from .document import INITIAL
                value = INITIAL[name]
                break
            style = style.parent
        for style in passed:
            style.cache[key] = value
        return value

    def resolve_paint(self, style, which, ctx, bbox):
        """fill/stroke of a style → PaintRef, or None when nothing is drawn. A colour depends
        on the style alone and is kept with it; paint servers and context paints are not."""
        key = ("paint-ref", which)
        try:
            return style.cache[key]
        except KeyError:
            pass
        value = self.paint_value(style, which)
        opacity = parse_opacity(style.get(f"{which}-opacity"))
        ref = self.paint_from_value(value, style, ctx, bbox, opacity)
        if value not in ("context-fill", "context-stroke") and parse_url(value) is None:
            style.cache[key] = ref
        return ref

    def paint_from_value(self, value, style, ctx, bbox, opacity, sampled_in_box=True):
        """``sampled_in_box``: drawn on the element of ``style`` and ``bbox`` (see
        paint.paint_server); a context paint is not."""
        if value == "none":
            return None
        if value in ("context-fill", "context-stroke"):
            got = ctx.context_fill if value == "context-fill" else ctx.context_stroke
            if got is None:
                return None
            # the context element's paint only: opacity is the element's own fill-opacity
            # or stroke-opacity (SVG 2 "Specifying paint", as resvg)
            return self.paint_from_value(got.value, got.style, got.ctx, got.bbox_fn(), opacity,
                                         False)
        url = parse_url(value)
        if url is not None:
            ref, fallback = url
            target = self.doc.lookup(ref) if ref.startswith("#") else None
            if target is None:
                warn(f"unresolved url({ref}): "
                     + (f"using the fallback {fallback}" if fallback else "not painted"))
            if target is None or target.tag not in ("linearGradient", "radialGradient",
                                                    "pattern"):
                if fallback and target is None:
                    return self.paint_from_value(fallback, style, ctx, bbox, opacity,
                                                 sampled_in_box)
                return None
            from .paint import NO_PAINT, paint_server
            paint = paint_server(self, target, ctx, resolve_bbox(bbox), style, sampled_in_box)
            if paint is NO_PAINT:
                return None
            if paint is None:
                # no stops, or objectBoundingBox units on an empty box: the fallback applies
                if fallback:
                    return self.paint_from_value(fallback, style, ctx, bbox, opacity,
                                                 sampled_in_box)
                return None
            return PaintRef(paint, opacity)
        color = parse_color(value)
        if color is None:
            return None
        if color == "currentColor":
            color = self.current_color(style)
        return PaintRef(Solid(tuple(float(c) for c in color)), opacity)

    def current_color(self, style):
        s = style
        while s is not None:
            v = s.specified.get("color")
            if v is not None and v != "inherit":
                c = parse_color(v)      # invalid: black, as in resvg
                return c if isinstance(c, tuple) else (0.0, 0.0, 0.0, 1.0)
            s = s.parent
        return (0.0, 0.0, 0.0, 1.0)

    def context_paint(self, style, which, ctx, bbox_fn):
        """What a ``<use>`` or a marked shape passes on to ``context-fill``/``context-stroke``:
        its paint, resolved lazily in its own user space and bounding box."""
        value = self.paint_value(style, which)
        if value in ("context-fill", "context-stroke"):
            return ctx.context_fill if value == "context-fill" else ctx.context_stroke
        return ContextPaint(value, style, ctx, bbox_fn)

    # -- markers ---------------------------------------------------------------------------
    def markers(self, path, style, ctx):
        return draw_markers(self, path, style, ctx)

    # -- clip paths and masks --------------------------------------------------------------
    def clip_path(self, value, ctx, bbox_fn):
        """clip-path value → clip Group, None (no clipping) or False (draw nothing)."""
        from .masking import clip_path
        return clip_path(self, value, ctx, bbox_fn)

    def masks(self, value, ctx, bbox_fn, mode=None):
        from .masking import masks
        return masks(self, value, ctx, bbox_fn, mode)

    # -- images and text -------------------------------------------------------------------
    def image(self, el, ctx, style):
        from .image import image_nodes
        return image_nodes(self, el, ctx, style)

    def text(self, el, ctx, style):
        # imported at the first <text>: text brings in HarfBuzz and the font database (~0.25 s)
        from .text import build_text
        return list(build_text(el, TextContext(self, ctx, style)))


class _Instanced:
    """What one <use> key draws (Builder._prepare_instance): ``count`` elements (for
    MAX_NODES), the symbol's viewport transform (``symbol_m``, None for another target) and
    viewport clip rectangle (``clip_rect``, None when it does not clip), and ``items`` in
    drawing order: (matrices, (verbs, point_mapper of the points, the points), user-space
    path, paint,
    fill rule, opacity, antialias) for a fill, (matrices, None, path, style, antialias,
    viewport, None) for a stroke (stroked per instance: its plan follows the transform),
    matrices being the element transforms below the top, composed in order."""
    __slots__ = ("count", "symbol_m", "clip_rect", "items")

    def __init__(self):
        self.count = 0
        self.symbol_m = None
        self.clip_rect = None
        self.items = []


class TextContext:
    """What ``vecmsaa.svg.text.build_text(element, ctx)`` gets besides the ``<text>`` element.

    ``element`` is a :class:`vecmsaa.svg.document.Element`: ``.tag``, ``.attrs`` / ``.get(name)``
    (attributes with local names; ``xlink:href`` is ``href``), ``.children`` (elements: tspan,
    textPath, tref, a), ``.text`` (characters before the first child) and ``.tail`` (characters
    after the element, inside its parent), ``.source`` (the Document; ``.lookup('#id')`` resolves
    references, e.g. for textPath and tref).

    The context offers:

    - ``style``: the computed :class:`~vecmsaa.svg.document.Style` of the ``<text>`` element;
      ``style.get('font-family')`` returns specified/inherited values as strings,
      ``style.font_size()`` the computed font size in user units.
      ``style_of(child, parent_style)`` computes a child's style (tspan) from its parent's.
    - ``transform``: user space → device pixels (already includes the element's transform);
      ``viewport``: (w, h) in user units for percentages; ``root_scale``: the scale from the
      SVG's own units to output pixels (the output size over the document size).
    - ``length(value, axis, style, default)`` converts a length (axis 'x', 'y' or 'xy').
    - ``draw(path, style, bbox=None)``: fill + stroke a glyph run path given in *user* units with
      the style's paints (gradients use ``bbox``, the text's object bounding box in user units;
      pass the same bbox for all runs of one text element); returns scene nodes in device
      space. It honours paint-order, and in clip paths and bounding-box passes it returns the
      plain outline, so text works in ``clipPath`` without special cases.
    - ``resolve_paint(style, 'fill'|'stroke', bbox)``: a :class:`PaintRef` (``.paint``,
      ``.opacity``) or None, for decorations drawn by hand.
    - ``path_of(element)``: the user-space :class:`~vecmsaa.scene.path.Path` of a shape element
      (for textPath), or None.
    - ``font_options``: dict of the font flags given to the API/CLI (``use_fonts_dir``,
      ``font_family``, ``serif_family``, ``sans_serif_family``, ``cursive_family``,
      ``fantasy_family``, ``monospace_family``, ``skip_system_fonts``).
    - ``in_clip`` / ``geometry_only``: booleans, in case the text module wants to skip work.
    - ``sampled``: the device rect outside which nothing drawn shows, or None (anywhere);
      ``stroke_reach(style)``: device px the style's stroke reaches beyond a path, or None.
    - ``cache``: a dict kept for the whole document (the font database, loaded faces).
    - ``count_characters(n)``: charge n characters to the document's MAX_TEXT_CHARS budget.
    - ``wrap(element, style, nodes)``: apply opacity/clip-path/mask/blend of a tspan-level
      element if needed.
    """

    def __init__(self, builder: Builder, ctx: Ctx, style: Style):
        self._builder = builder
        self._ctx = ctx
        self.style = style
        self.transform = ctx.transform
        self.viewport = ctx.viewport
        self.root_scale = builder.root_scale
        self.font_options = dict(builder.options.font_options)
        #: a dict the text modules keep what they found for the whole document in
        self.cache = builder.text_cache
        self.in_clip = ctx.clip
        self.geometry_only = ctx.geometry
        #: device rect (x0, y0, x1, y1) outside which nothing drawn can show, or None
        self.sampled = ctx.sampled

    def style_of(self, element, parent_style=None):
        return (parent_style or self.style).child(element)

    def count_characters(self, n):
        """Charge ``n`` characters to the document's MAX_TEXT_CHARS budget (SvgError past it)."""
        self._builder.text_chars += n
        if self._builder.text_chars > MAX_TEXT_CHARS:
            raise SvgError(f"the document's text is longer than {MAX_TEXT_CHARS} characters")

    def length(self, value, axis="x", style=None, default=None):
        return self._builder.length(value, axis, style or self.style, self.viewport, default)

    def draw(self, path, style=None, bbox=None):
        return self._builder.draw_path(path, style or self.style, self._ctx, bbox=bbox)

    def resolve_paint(self, style, which, bbox=None):
        return self._builder.resolve_paint(style or self.style, which, self._ctx, bbox)

    def stroke_reach(self, style):
        """Device px a style's stroke reaches beyond its path, None when unknown (dashes)."""
        return self._builder.stroke_reach(style, self._ctx)

    def note_text_fills(self, fills):
        """Record the fills that draw a text, when the builder collects them (kept with their
        ids: a fill the scene replaces is freed, and a later fill may take its id)."""
        if self._builder.text_fills is not None:
            self._builder.text_fills.update((id(f), f) for f in fills)

    def path_of(self, element):
        """A shape's outline in the referencing text's user space: its own ``transform`` is
        "a supplemental transformation" there (SVG 2 textPath); a singular one is ignored, as
        usvg reads it (the identity)."""
        style = self._builder.doc.document_style(element)
        if element.tag == "path":
            p = self._builder.path_data(element)
        else:
            p = shape_path(element, self._builder.length_getter(element, style, self._ctx))
        if p is None:
            return None
        m = self._builder.element_transform(element, style, self._ctx)
        return p.transformed(m) if m not in (None, IDENTITY) else p

    def wrap(self, element, style, nodes):
        return self._builder.wrap(element, style, self._ctx, nodes)


# -- helpers --------------------------------------------------------------------------------
def expanded_size(doc, targets=None, links=None) -> int:
    """How many elements the document has once every <use> is instantiated as the build
    instantiates it (capped just above MAX_NODES), computed without instantiating anything:
    the tree's elements, and for each <use> its target's once more with the <use> elements
    in it followed in turn, cut where the build cuts them: a <use> drawing nothing whatever
    its context (use_target), one whose target is being instantiated already (a cycle), and
    below MAX_USE_DEPTH <use> levels. (Conditions and display only leave more out.)
    ``targets`` and ``links``: the memos of use_target, when the caller keeps them."""
    if not doc.has_use:
        return min(doc.size, MAX_NODES + 1)
    counter = _UseCount(doc, {} if targets is None else targets,
                        {} if links is None else links)
    return counter.expand(doc.root, ())


class _UseCount:
    """expanded_size's walk: ``expand(el, stack)`` is what building ``el`` with ``stack``
    (the ids of the targets being instantiated, as Ctx.use_stack) makes, past MAX_NODES
    at most a step (it stops there). An element's own elements and the <use> elements among
    them are found once (``subtrees``); each instance then costs a step per <use> in it,
    and the steps are at most the elements counted, so at most MAX_NODES + 1."""

    def __init__(self, doc, targets, links):
        self.doc, self.targets, self.links = doc, targets, links
        self.subtrees = {}          # id(element) -> (elements, the <use> elements) below it
        self.total = 0

    def subtree(self, el):
        key = id(el)
        got = self.subtrees.get(key)
        if got is None:
            size, uses = 0, []
            stack = [el]
            while stack:
                node = stack.pop()
                size += 1
                if node.tag == "use":
                    uses.append(node)
                if node.children:
                    stack.extend(node.children)
            got = self.subtrees[key] = (size, uses)
        return got

    def expand(self, el, stack):
        size, uses = self.subtree(el)
        self.total += size
        if self.total > MAX_NODES or len(stack) >= MAX_USE_DEPTH:
            return min(self.total, MAX_NODES + 1)
        subtrees = self.subtrees
        for use in uses:
            target = use_target(use, self.doc, self.targets, self.links)
            if target is not None and id(target) not in stack:
                got = subtrees.get(id(target))
                if got is not None and not got[1]:
                    self.total += got[0]        # (expand() for a target without <use>)
                else:
                    self.expand(target, stack + (id(target),))
                if self.total > MAX_NODES:
                    break
        return min(self.total, MAX_NODES + 1)


def use_target(el, doc, memo, links):
    """The element the <use> ``el`` instantiates, or None when it draws nothing whatever its
    context: no or an unknown reference, itself or an ancestor (what contains() finds), or
    an element whose content links back to it (see links_back; ``links`` is its memo).
    Kept in ``memo`` by element: it depends on the tree alone."""
    got = memo.get(el, memo)
    if got is memo:
        ref = el.attrs.get("href")
        got = None
        if ref is not None and ref.strip().startswith("#"):
            got = doc.lookup(ref, detached=True)
            if got is not None and (contains(got, el) or links_back(el, got, doc, links)):
                got = None
        memo[el] = got
    return got


def links_back(el, target, doc, memo) -> bool:
    """Whether a <use> inside ``target`` (at any depth, through no other reference)
    references ``el`` or ``target`` itself: then instantiating ``el`` would recurse, and the
    <use> ``el`` draws nothing, as resvg skips it. SVG 2 makes a <use> whose target is its
    ancestor an error but leaves the <use> that instantiates such a cycle open (w3c/svgwg
    issue 770); the SVG 1.1 suite's struct-use-12-f renders none of them. ``memo`` keeps,
    per target for the document, the ids of the elements the <use> elements inside it
    reference (a glyph symbol is used thousands of times, by as many <use> elements)."""
    key = id(target)
    linked = memo.get(key)
    if linked is None:
        linked = set()
        stack = list(target.children)
        while stack:
            node = stack.pop()
            if node.tag == "use":
                found = doc.lookup(node.get("href") or "", detached=True)
                if found is not None:
                    linked.add(id(found))
            stack.extend(node.children)
        memo[key] = linked
    return key in linked or id(el) in linked


def contains(ancestor, el):
    """Whether ``el`` is ``ancestor`` or inside it."""
    node = el
    while node is not None:
        if node is ancestor:
            return True
        node = node.parent
    return False


def conditions_pass(el):
    """Conditional processing: systemLanguage (a listed language is one of the user's, or
    starts with one and a hyphen: en-US for en), requiredExtensions."""
    lang = el.attrs.get("systemLanguage")
    if lang is not None:
        user = getattr(el.source, "languages", ("en",))
        langs = [x.strip().lower() for x in lang.split(",") if x.strip()]
        if not any(x in user or x.split("-")[0] in user for x in langs):
            return False
    ext = el.attrs.get("requiredExtensions")
    if ext is not None:
        return False
    return True


def _clip_rule(value):
    return value if value in ("nonzero", "evenodd") else None    # lower-cased by the cascade


#: what Builder._draw_plan reads of a style (``marker`` in case a shorthand is kept as given)
_DRAW_PLAN_PROPERTIES = frozenset({"shape-rendering", "paint-order", "fill-rule", "marker",
                                   "marker-start", "marker-mid", "marker-end"})


@functools.lru_cache(maxsize=64)
def paint_order(value):
    """The painting steps of a paint-order value, in order (a tuple: the result is shared)."""
    default = ("fill", "stroke", "markers")
    words = (value or "normal").split()
    if (not words or words == ["normal"] or any(w not in default for w in words)
            or len(set(words)) != len(words)):
        return default   # invalid (unknown keyword, duplicates): the initial value
    order = []
    for w in words:
        if w not in order:
            order.append(w)
    order.extend(w for w in default if w not in order)
    return tuple(order)


def valid_paint(value):
    v = value.strip()
    if v in ("none", "context-fill", "context-stroke"):
        return True
    url = parse_url(v)
    if url is not None:
        # <url> [none | <color>]?: a second url or a context paint is no fallback
        fallback = url[1]
        return not fallback or fallback == "none" or parse_color(fallback) is not None
    return parse_color(v) is not None

