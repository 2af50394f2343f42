"""Render a resolved :class:`~vecmsaa.scene.nodes.Scene`: batches of fills through the raster kernels,
groups that need it through layers (opacity, clip, mask, blend mode).

Coverage modes (see docs/modes.md):

- ``none``: one sample at the pixel centre, aliased.
- ``alpha``: Loop–Blinn distance alpha, α = clamp(½ − d), blended on the lens samples.
- ``a2c``: the same α as a sample mask of round(α·n) samples (alpha-to-coverage).
- ``alpha-sat``: ``alpha``'s α, each batch of fills drawn front to back with the saturating
  blend i = min(A_f, 1 − A_fb) (seed 002's anti-correlated blend), then composited over.
- ``persample``: the implicit function at every sample.
- ``approx``: the implicit function at every sample, as ``persample`` (default; until
  session 13 one evaluation per pixel and a half-plane coverage-mask look-up).
- ``analytic``: exact area per path, composited per pixel (tiny-skia style).
- ``reference``: 256 stratified samples per pixel on finely flattened outlines, composited per
  sample: conflation-free ground truth.
"""
from __future__ import annotations

import contextlib
import copy
import functools
import math
import os
import sys
import threading
import time
from itertools import repeat
from operator import attrgetter, eq, lt
from types import SimpleNamespace

import numpy as np

from .blend import blend_premultiplied, over_rects, over_scaled
from ..output.png import PngStream
from ..output.rgba8 import NO_REFILL, unpremultiply_to_rgba8
from .csaa import csaa_scratch, render_csaa
from ..jit import bind_tail
from .modes import EXACT_MODES, FILTERS, MODES, MSAA_MODES, SATURATE_MODES
from ..geometry.primitives import (CULL_MARGIN, NO_CULL, PRIM_FIELDS, QUAD_FALLBACK_TOL,
                                   RUN_VERBS, batch_arrays, batch_extents, build_batch,
                                   build_run, path_runs)
from ..scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD
from .resolve import RADIUS, accumulate, filter_weight, finish, resolve_weights
from .sample_patterns import (SamplePattern, a2c_order, sample_pattern,
                              stratified_pattern)
from .scan import (MODE_IDS, MODE_PERSAMPLE, RULE_EVENODD, RULE_NONZERO, analytic_scratch,
                   msaa_scratch, render_analytic, render_msaa, scan_run, sweep_fill)
from ..scene import bounds
from ..scene.color import linear_rgb_image
from ..scene.nodes import (Fill, FillRuns, Group, ImagePaint, PatternPaint, Scene, Solid,
                           translated, translated_filters)
from .shaders import PaintTable, solid_arrays, solid_row, style_arrays

#: flattening tolerance of the exact modes (pixels)
EXACT_TOLERANCE = 1.0 / 256.0
#: a curve piece bulges at most this far from its chord (pixels); keeps lenses thin
MAX_SAGITTA = 1.0
#: elements (rows x width x samples) of one strip's per-sample buffers (16 rows at 8192 px, 8
#: samples). 4 M elements (64 rows) held 32 MB of winding deltas per thread more and was no
#: faster: at 8192 px the peak RSS of alexandria-port 313 -> 242 MB, city-3 391 -> 314 MB
STRIP_BUDGET = 1 << 20
#: rows of a multisampled strip at most (fewer than STRIP_BUDGET gives below 8192 px): a fill's
#: winding deltas, lens samples and occlusion stamps then stay in the caches from its scan to
#: its sweep. 16 rows instead of 64 at 2048 px: the tiger 0.85-0.9 of the time, ASU, NASA and
#: the maps 0.9-0.95 (docs/bench.md, session 10, raster (2)). Not the analytic mode: its cost
#: per strip is per edge (16 rows made the tiger's 2048 px render 5x slower)
MSAA_STRIP_ROWS = 16
#: bytes of one band's float32 RGBA buffer (each layer, clip and mask adds one more); the top
#: level is rendered band by band so the whole image never exists in float
BAND_BUDGET = 1 << 24
#: bands a thread at least when bands are drawn on threads (see render_bands): a thread that
#: draws the last heavy band leaves the other idle for its length (the tiger at 2048 px on two
#: threads: bands of 512 rows took 26, 66, 41 and 18 ms, so one thread drew 84 ms and the
#: other 67; of 256 rows, at most 29 ms each)
BANDS_PER_THREAD = 4
#: seconds an item (a fill batch or a layer, nested ones counted) takes to draw on average,
#: at least, for band threads beyond the first to pay (BandPace). Below it a band is mostly
#: short kernel calls with Python between them, and threads handing the GIL back and forth at
#: every call cost more than the second core gives. The draw in process on 2 threads against
#: 1 (wall, both cores free; docs/bench.md, session 21): 1.14-1.69 times as long at 34-39 µs
#: an item (1000-4000 small clipped or masked groups), 0.79 at 60 µs (1000 faded groups),
#: 0.98 at 82 µs, 0.51-0.58 with few items (the corpus at 2048 px)
PARALLEL_ITEM_SECONDS = 50e-6
#: items a band at most, on average, for the band threads to start at once; with more, one
#: thread draws until BandPace has seen whether they are slow enough to share
ITEMS_PER_BAND_AT_ONCE = 8
#: pixels of an image, at most, whose band threads beyond the first wait for its first band
#: that draws something however few its items are (BandPace): they join only when the rows
#: left would take MIN_SHARED_SECONDS on one thread. A 200 px icon or suite test is a
#: millisecond of drawing, and its render made an executor and a thread, split its 200 rows
#: into 7 bands and handed the GIL back and forth: 1.3 times the CPU of one thread, and more
#: wall time on a busy machine (docs/bench.md, session 36). Larger images keep starting their
#: threads at once when their items are few (a band alone first would cost them up to an
#: eighth of the draw)
PACED_PIXELS = 1 << 20
#: CPU seconds the rows left after the first band that draws something would take on one
#: thread (that band's time per row), at least, for band threads beyond the first to join in
#: an image of at most PACED_PIXELS: sharing saves at most half of it, against a thread's
#: start, the GIL's hand-offs and the bands' split
MIN_SHARED_SECONDS = 4e-3
#: bytes the buffers of nested layers, clips and masks may hold together: each nesting level
#: keeps a buffer of the band's rows (layer_buffer), so 1,000 nested groups with opacity would
#: hold 16 GB in bands of BAND_BUDGET; deeper nesting draws in thinner bands instead
#: (layer_rows). Documents nested up to 8 levels keep their bands
LAYERS_BUDGET = 1 << 27
#: pixels of a filtered layer's buffers (a filter needs its whole region at once); a layer whose
#: filter region (within the image) is larger is not drawn
MAX_FILTER_PIXELS = 1 << 24


class RenderOptions:
    """Everything the raster stage needs besides the scene. ``filter`` None: the pattern's own
    (``tent`` for quincunx, else ``box``)."""

    def __init__(self, mode: str = "approx", samples: int = 8, filter: str | None = None,
                 pattern: str = "d3d", color_samples: int | None = None):
        if mode not in MODES:
            raise ValueError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}")
        self.mode = mode
        if mode == "none":
            samples = 1
        if mode == "reference":
            # 256 samples unless more are asked for (a square number: 1024 = 32 x 32)
            side = max(16, int(round(np.sqrt(samples)))) if samples > 16 else 16
            pat = SamplePattern("stratified", stratified_pattern(side))
        elif mode in ("analytic", "none"):
            pat = SamplePattern("centre", np.zeros((1, 2)))
        else:
            pat = sample_pattern(pattern, samples)
        filter = pat.filter if filter is None else filter
        if filter not in FILTERS:
            raise ValueError(f"unknown filter {filter!r}; choose from {', '.join(FILTERS)}")
        self.filter = filter
        self.pattern = pat.name
        self.kernel_mode = MODE_IDS.get(mode, MODE_PERSAMPLE)
        #: alpha-sat: alpha's coverage, each batch drawn front to back with the saturating
        #: blend into a transparent buffer that is then composited over the target
        self.saturate = mode in SATURATE_MODES
        #: CSAA: colours stored per pixel, fewer than the coverage samples (None: one each)
        if color_samples is not None:
            if mode in EXACT_MODES:
                raise ValueError(f"color samples need a multisample mode, not {mode}")
            if not 1 <= color_samples <= pat.samples:
                raise ValueError(f"color samples must be 1..{pat.samples} (the coverage "
                                 f"samples): {color_samples}")
        self.color_samples = pat.samples if color_samples is None else color_samples
        if self.saturate:
            self.kernel_mode = MODE_IDS["alpha"]
        #: runs of opaque fills drawn front to back (scan.render_msaa); the pixels do not
        #: change, so off only to test that
        self.occlude = True
        #: curve pixels evaluated per sample over a render (scan.scan_lenses)
        self.lens_stats = np.zeros(1, dtype=np.int64)
        self.flatten_tol = EXACT_TOLERANCE if mode in EXACT_MODES else 0.0
        #: rendered pattern tiles, by content group: see pattern_tile
        self.tiles = {}
        #: paint tables of one solid fill by (paint id, opacity): see FillBatch._one_fill
        self.solid_tables = {}
        #: the options small tiles render with, made when first needed (tile_options)
        self.tile_opts = None
        #: the options pattern tiles render with (a sample render's are its parent's)
        self.parent = self
        #: where the kernels cannot resolve a pixel alone (raster/resolve.py): the weights
        #: of resolve_band and the one-sample options of every (sample, tile class), else None
        self.resolve = None
        if pat.per_pixel and RADIUS[filter] <= 0.5:
            offsets = pat.offsets[0]
            self._use_offsets(offsets, filter_weight(filter, offsets[:, 0], offsets[:, 1]))
            return
        self.samples = pat.samples
        self.tile = pat.tile
        if not pat.shared and RADIUS[filter] <= 0.5:
            # a tile of patterns of the pixel's own samples (interleaved): one render per tile
            # class, resolved by the kernels as for any pattern, and each pixel taken from its
            # class's image (one "sample image" per class, of weight 1)
            self.resolve = np.ones((len(pat.offsets), 1, 1, 1))
            self.sample_opts = [[self._with_offsets(o, filter_weight(filter, o[:, 0], o[:, 1]))
                                 for o in pat.offsets]]
            return
        if mode == "analytic":
            raise ValueError(f"the analytic mode has no samples for the {filter} filter")
        if mode == "a2c" and pat.samples > 1:
            # its dither mask couples a pixel's samples: it has no one-sample images
            raise ValueError(f"a2c takes a pattern of a pixel's own samples and the box or "
                             f"tent filter, not {pat.name} with {filter}")
        if self.color_samples < pat.samples:
            raise ValueError(f"color samples need a pixel's own samples and the box or tent "
                             f"filter, not {pat.name} with {filter}")
        self.resolve = resolve_weights(pat, filter)
        self.sample_opts = [[self._one_sample(pat.offsets[c, s]) for c in range(len(pat.offsets))]
                            for s in range(pat.samples)]

    def _use_offsets(self, offsets: np.ndarray, weights: np.ndarray) -> None:
        """The kernels' sample positions (0..1 in the pixel), resolve weights and
        alpha-to-coverage masks for these offsets from the pixel centre."""
        n = len(offsets)
        self.samples = n
        self.sx = np.ascontiguousarray(offsets[:, 0] + 0.5)
        self.sy = np.ascontiguousarray(offsets[:, 1] + 0.5)
        self.weights = (weights / weights.sum()).astype(np.float32)
        if self.mode == "a2c":
            order = a2c_order(offsets)
            bits = np.zeros(n + 1, dtype=np.uint64)
            for k in range(1, n + 1):
                bits[k] = bits[k - 1] | (np.uint64(1) << np.uint64(order[k - 1]))
            self.a2c_bits = bits
        else:
            self.a2c_bits = np.zeros(2, dtype=np.uint64)

    def _one_sample(self, offset) -> "RenderOptions":
        """These options with the one sample at ``offset`` per pixel: a sample image's."""
        one = self._with_offsets(np.asarray(offset, dtype=np.float64).reshape(1, 2), np.ones(1))
        one.color_samples = 1
        return one

    def _with_offsets(self, offsets: np.ndarray, weights: np.ndarray) -> "RenderOptions":
        """These options with these samples per pixel, resolved by the kernels."""
        one = copy.copy(self)
        one.resolve = None
        one._use_offsets(offsets, weights)
        return one


def premultiplied(color) -> np.ndarray:
    r, g, b, a = color
    return np.array([r * a, g * a, b * a, a], dtype=np.float32)


def render_scene(scene: Scene, mode: str = "approx", samples: int = 8,
                 filter: str | None = None, pattern: str = "d3d",
                 band_budget: int = BAND_BUDGET, threads: int = 1,
                 color_samples: int | None = None) -> np.ndarray:
    """Render to an (H, W, 4) float32 array of premultiplied RGBA in [0, 1].

    ``samples`` per pixel for the MSAA modes (1, 2, 4, 8, 16; ``none`` always uses 1, the
    ``reference`` mode 256 or a larger square), ``pattern`` their positions (modes.PATTERN_NAMES:
    docs/modes.md), ``filter`` the resolve filter (modes.FILTERS; None: the pattern's own).
    ``band_budget``: bytes of one band's buffers; ``threads``: bands rendered at once (None:
    every available core). The result depends on neither.
    ``color_samples``: CSAA, colours stored per pixel (fewer than ``samples``; docs/modes.md)."""
    return render_float(scene, RenderOptions(mode, samples, filter, pattern, color_samples),
                        band_budget, threads)


def render_float(scene: Scene, opts: RenderOptions, band_budget: int = BAND_BUDGET,
                 threads: int = 1) -> np.ndarray:
    target = np.empty((scene.height, scene.width, 4), dtype=np.float32)
    render_bands(scene, opts, lambda y0, band: None, band_budget, threads, target)
    return target


def render_scene_rgba8(scene: Scene, mode: str = "approx", samples: int = 8,
                       filter: str | None = None, pattern: str = "d3d",
                       band_budget: int = BAND_BUDGET, threads: int = 1,
                       progress=None, color_samples: int | None = None) -> np.ndarray:
    """Render to an (H, W, 4) uint8 array of straight RGBA: ``to_rgba8(render_scene(...))``
    exactly, without ever holding the whole image in float (band by band).
    ``progress(rows done, rows)`` after each band, from the thread that drew it."""
    opts = RenderOptions(mode, samples, filter, pattern, color_samples)
    out = np.empty((scene.height, scene.width, 4), dtype=np.uint8)

    def convert(y0, band, refill=NO_REFILL):
        unpremultiply_to_rgba8(band, out[y0:y0 + band.shape[0]], refill)
    render_bands(scene, opts, reporting(convert, progress, scene.height), band_budget, threads,
                 refills=True)
    return out


def render_scene_png(scene: Scene, mode: str = "approx", samples: int = 8,
                     filter: str | None = None, pattern: str = "d3d",
                     band_budget: int = BAND_BUDGET, threads: int = 1, progress=None,
                     color_samples: int | None = None) -> bytes:
    """PNG bytes of the image: ``encode_png(render_scene_rgba8(...))`` exactly, band by band,
    each band converted and its PNG rows deflated by the thread that rendered it, so neither
    the float nor the 8-bit image is ever whole (at 8192² that is 256 MB less).
    ``progress`` as for :func:`render_scene_rgba8`."""
    opts = RenderOptions(mode, samples, filter, pattern, color_samples)
    stream = PngStream(scene.width, scene.height)
    per_thread = threading.local()

    def encode(y0, band, refill=NO_REFILL):
        rgba8 = getattr(per_thread, "rgba8", None)
        if rgba8 is None or rgba8.shape[0] < band.shape[0]:
            rgba8 = per_thread.rgba8 = np.empty((band.shape[0], band.shape[1], 4), np.uint8)
        rgba8 = rgba8[:band.shape[0]]
        unpremultiply_to_rgba8(band, rgba8, refill)
        stream.write_rows(y0, rgba8)
    render_bands(scene, opts, reporting(encode, progress, scene.height), band_budget, threads,
                 refills=True)
    return stream.finish()


def reporting(consume, progress, rows: int):
    """``consume``, then ``progress(rows done so far, rows)`` after each band (or ``consume``
    itself without ``progress``)."""
    if progress is None:
        return consume
    lock, done = threading.Lock(), [0]

    def consume_and_report(y0, band, *refill):
        consume(y0, band, *refill)
        with lock:
            done[0] += band.shape[0]
            so_far = done[0]
        progress(so_far, rows)
    return consume_and_report


def available_cores() -> int:
    """Cores this process may run on (its affinity mask, not the machine's count)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def render_bands(scene: Scene, opts: RenderOptions, consume, band_budget: int = BAND_BUDGET,
                 threads: int | None = 1, target: np.ndarray | None = None,
                 refills: bool = False) -> None:
    """Render the scene band by band and call ``consume(y0, band)`` with each band, the
    premultiplied float32 rows y0 .. y0 + len(band) - 1, valid only during the call. Geometry
    is built once for all bands. With ``target`` the bands are its rows (the whole image).
    ``refills``: ``consume(y0, band, refill)`` leaves every pixel of the band set to the
    colour ``refill`` (the next band's background; unpremultiply_to_rgba8 does it as it reads).

    ``threads`` > 1 (None: every available core) renders that many bands at once, each thread
    with its own kernel buffers; ``consume`` is then called from those threads, in no
    particular order, and must only touch its own rows. A band's pixels do not depend on
    where the band begins or on the other bands, so the image is the same for any number of
    threads (the kernels release the GIL)."""
    if opts.resolve is not None:
        draw_sampled_bands(scene, opts, consume, band_budget, threads, target)
        return
    threads = available_cores() if threads is None else max(1, int(threads))
    with band_pool(threads) as pool:
        items = prepare_items(scene.root, opts, pool, canvas=(0, 0, scene.width, scene.height))
        _draw_prepared(scene, opts, consume, band_budget, threads, target, refills, items, pool)


def _draw_prepared(scene, opts, consume, band_budget, threads, target, refills, items, pool):
    """render_bands once the items are prepared (``pool``: the band threads' executor)."""
    H, W = scene.height, scene.width
    band_rows, strip_rows = band_layout(W, opts.samples, band_budget, opts.mode == "analytic")
    band_rows = solo_rows = max(1, min(band_rows, H))
    if threads > 1 and band_rows > strip_rows:
        # at least BANDS_PER_THREAD bands a thread, so that a thread with a light band is not
        # left idle
        share = -(-H // (BANDS_PER_THREAD * threads))
        band_rows = max(strip_rows, min(band_rows, -(-share // strip_rows) * strip_rows))
    if band_rows < H and held_filtered_pixels(items, W, H) > W * H:
        # band by band, each filtered layer is kept from the first band that needs it to its
        # last; when those would outweigh the whole image, one band holds one at a time
        band_rows = solo_rows = H
    most_rows = layer_rows(W, layer_depth(items))
    band_rows, solo_rows = min(band_rows, most_rows), min(solo_rows, most_rows)
    starts = range(0, H, band_rows)
    pace = BandPace(items, starts, band_rows, solo_rows, H if W * H <= PACED_PIXELS else None) \
        if threads > 1 and len(starts) > 1 else None
    if threads > 1 and len(starts) > threads and not (pace is not None and pace.wait):
        starts = heaviest_first(items, starts, band_rows)
    bands = [(y0, min(band_rows, H - y0)) for y0 in starts]
    background = premultiplied(scene.background)

    refill = np.asarray(background, dtype=np.float32) if refills and target is None else None

    # a band drawn alone after the pace's first may have solo_rows (BandPace.regroup)
    buffer_rows = solo_rows if pace is not None and pace.wait else band_rows
    drawn_rows = BandsDrawn(H)
    kit_key = (W, strip_rows, opts.samples, buffer_rows, target is None)

    def draw_bands(next_band):
        # filled: rows of the buffer that hold the background already (a kept buffer's last
        # band refilled them)
        raster, buffer, filled = _take_kit(kit_key, opts, H, background)
        raster.bands = drawn_rows
        for y0, rows in iter(next_band, None):
            raster.band_start = y0
            band = buffer[:rows] if target is None else target[y0:y0 + rows]
            if filled < rows:
                # one row from the colour, the others copied from it: broadcasting the 4
                # values over the whole band runs numpy's copy loop per pixel (a quarter of
                # the tiger's render time at 8192 px)
                band[0] = background
                band[1:] = band[0]
                filled = rows
            began, cpu, drawn = time.perf_counter(), time.thread_time(), raster.drawn
            draw_items(items, band, y0, raster)
            if pace is not None and pace.decide is not None:
                pace.band_drawn(time.perf_counter() - began, raster.drawn - drawn, rows,
                                time.thread_time() - cpu)
            drawn_rows.band_done(y0, rows)
            if refill is None:
                consume(y0, band)
                filled = 0
            else:
                consume(y0, band, refill)
        raster.bands = None
        # only a thread that finished its bands gives its buffers back: clean
        _keep_kit(kit_key, raster, buffer, filled, background)
    run_bands(draw_bands, bands, threads, pool, pace)


#: Raster.bands of draw_sampled_bands' rasters: each band is drawn with an apron of rows of
#: the bands beside it
APRON_BANDS = "apron"


class BandsDrawn:
    """The rows of a render's bands drawn so far: a filtered layer's pixels go once every band
    that can need them is drawn (filtered_part). Threads take bands top down where a layer is
    filtered, but the band holding its last row may be done with it while one above has yet
    to reach it; that one filtered it again (two threads, a blurred disc over 200 rectangles:
    one render in four)."""

    def __init__(self, height: int):
        self.done = np.zeros(height, dtype=bool)
        self.lock = threading.Lock()
        #: (layer, key, first row, band start) of filtered pixels kept for bands above
        self.waiting = []

    def let_go(self, layer, key, first: int, band_start: int) -> bool:
        """Whether the rows from ``first`` to the band at ``band_start`` are drawn, so that the
        layer's filtered pixels (its ``filtered[key]``, with ``layer.filtering`` held) may go
        now; if not, they go when those rows are (band_done)."""
        with self.lock:
            if self.done[max(first, 0):band_start].all():
                return True
            self.waiting.append((layer, key, first, band_start))
            return False

    def band_done(self, y0: int, rows: int) -> None:
        with self.lock:
            self.done[y0:y0 + rows] = True
            ready = [w for w in self.waiting if self.done[max(w[2], 0):w[3]].all()]
            if ready:
                self.waiting = [w for w in self.waiting if w not in ready]
        # (outside self.lock: filtered_part takes the layer's lock, then this one)
        for layer, key, _, _ in ready:
            with layer.filtering:
                _let_go(layer, key)


class BandPace:
    """Whether band threads beyond the first join in. At once when the items are few for the
    bands (ITEMS_PER_BAND_AT_ONCE) in an image of more than PACED_PIXELS; otherwise the
    first band one thread draws that draws any items decides (``band_drawn``): the others
    join, taking the bands left heaviest first (``share``), where the items are many at
    PARALLEL_ITEM_SECONDS an item or more and, in an image of ``height`` rows (at most
    PACED_PIXELS), where the rows left would take MIN_SHARED_SECONDS or more; otherwise the
    same thread draws them, in bands of up to ``solo_rows`` (``regroup``: a layer crossing a
    band's edge is drawn once in each band). The image depends neither on the threads nor on
    the bands."""

    def __init__(self, items, starts, band_rows: int, solo_rows: int,
                 height: int | None = None):
        self.items, self.starts, self.band_rows = items, starts, band_rows
        self.solo_rows = solo_rows
        self.many = item_count(items) > ITEMS_PER_BAND_AT_ONCE * len(starts)
        #: rows of a small image (PACED_PIXELS), None for a larger one
        self.height = height
        self.wait = self.many or height is not None
        #: rows drawn before the deciding band (by this thread alone)
        self.rows_before = 0
        #: (join, alone) from run_bands while undecided, then None
        self.decide = None

    def band_drawn(self, seconds: float, drawn: int, rows: int = 0,
                   cpu_seconds: float = 0.0) -> None:
        """A band of ``rows`` rows drew ``drawn`` items in ``seconds`` (wall) and
        ``cpu_seconds`` (its thread's CPU)."""
        if drawn == 0:
            self.rows_before += rows
            return          # a band with nothing in it tells nothing
        join, alone = self.decide
        self.decide = None
        share = not self.many or seconds >= PARALLEL_ITEM_SECONDS * drawn
        if share and self.height is not None and rows > 0:
            left = self.height - self.rows_before - rows
            share = cpu_seconds * left / rows >= MIN_SHARED_SECONDS
        (join if share else alone)()

    def share(self, bands: list) -> list:
        """The (y0, rows) bands heaviest first (heaviest_first), for threads taking turns."""
        rows = dict(bands)
        return [(y0, rows[y0]) for y0 in heaviest_first(self.items, self.starts,
                                                         self.band_rows) if y0 in rows]

    def regroup(self, bands: list) -> list:
        """The (y0, rows) bands top down, neighbours joined up to solo_rows rows."""
        out = []
        for y0, rows in sorted(bands):
            if out and out[-1][0] + out[-1][1] == y0 and out[-1][1] + rows <= self.solo_rows:
                out[-1] = (out[-1][0], out[-1][1] + rows)
            else:
                out.append((y0, rows))
        return out


def item_count(items) -> int:
    """Fill batches and layers among ``items``, those in layers, clips and masks too."""
    return sum(1 for _ in nested_items(items))


def nested_items(items):
    """``items`` and every item in their layers, the layers' clips and masks (as layers) and
    theirs, each once (without recursion)."""
    todo = [items]
    while todo:
        for item in todo.pop():
            yield item
            if not isinstance(item, FillBatch):
                todo.append(item.items)
                todo.append([part for part in (item.clip, item.mask) if part is not None])


#: heaviest_first's cost of a pixel of a fill's box, against 1 for an edge or lens: with the
#: edges alone the tiger's heaviest band at 2048 px came third, and scheduled as two threads
#: take them, the bands' measured times (threads=1 CPU) ended the threads 1.4 ms later than in
#: the order of those times, which this weight gives (and no other corpus file's order worse;
#: docs/bench.md, session 13)
AREA_COST = 1e-4


def heaviest_first(items, starts, band_rows: int):
    """The band starts in order of a guess at their cost, most first (ties top down): each
    fill's edges and lenses spread evenly over the bands its box reaches, plus AREA_COST for
    each pixel of its box in the band. So threads taking bands in turn do not end with one of
    them drawing a heavy band alone: the tiger's 256-row bands at 2048 px took 7, 9, 15, 25,
    24, 13, 9 and 5 ms top down, and two threads ended 8 ms apart. Top down where a filtered
    layer takes part (its filtered pixels are kept until the bands from its first row to its
    last are drawn: BandsDrawn; top down keeps that short)."""
    n = len(starts)
    # the fills' boxes and offsets gathered, then one computation for all: numpy's calls on
    # each batch's few rows took 80 ms of 2000 clipped groups' 250 ms draw (two threads were
    # slower than one there, session 21)
    boxes, edge_offs, prim_offs = [], [], []
    for item in nested_items(items):
        if isinstance(item, FillBatch):
            boxes.append(item.box)
            edge_offs.append(item.edge_off)
            prim_offs.append(item.prim_off)
        elif item.filters:
            return starts
    if not boxes:
        return starts
    box = np.concatenate(boxes)
    first = np.clip(np.floor(box[:, 1] / band_rows), 0, n).astype(np.int64)
    last = np.clip(np.floor(box[:, 3] / band_rows), -1, n - 1).astype(np.int64)
    keep = first <= last
    first, last = first[keep], last[keep]
    work = (_sizes(edge_offs) + _sizes(prim_offs))[keep]
    width = (np.maximum(box[:, 2], 0.0) - np.maximum(box[:, 0], 0.0))[keep]
    share = work / (last - first + 1) + AREA_COST * band_rows * width
    # + share on the bands first .. last: a difference array
    cost = np.bincount(first, share, minlength=n + 1) - np.bincount(last + 1, share,
                                                                    minlength=n + 1)
    return [starts[i] for i in np.argsort(-np.cumsum(cost[:-1]), kind="stable")]


def _sizes(offsets: list) -> np.ndarray:
    """The sizes of the runs each offset array of ``offsets`` marks, all in one array."""
    sizes = np.diff(np.concatenate(offsets))
    # (the differences across two arrays' junctions go)
    return np.delete(sizes, np.cumsum([len(o) for o in offsets])[:-1] - 1)


#: bytes of band buffers and kernel strip buffers kept from one render to the next (each
#: thread's, for the image width, strip, samples and band the last render had): a warm render
#: otherwise pays for their fresh pages again (at 2048 px, threads=1, CPU: the flag 46 -> 39
#: ms, NASA 88 -> 74 ms). One thread's set is ~42 MB at 2048 px and ~46 MB at 8192 px (the
#: split-pixel pool, 17 MB of it, is touched only where pixels split), so two threads' fit
KEEP_BYTES = 96 << 20
_kits: dict = {}
_kits_lock = threading.Lock()


def _draws_with_msaa(opts: RenderOptions) -> bool:
    """Whether the options' fills are drawn by render_msaa (not the analytic or CSAA kernel):
    only its buffers are kept from render to render (_take_kit) and narrowed
    (Raster.layer_buffer)."""
    return opts.mode != "analytic" and opts.color_samples == opts.samples


def _drop_other_kits(key) -> None:
    """Forget the kept buffers of every other key (with _kits_lock held)."""
    for other in [k for k in _kits if k != key]:
        del _kits[other]


def _take_kit(key, opts: RenderOptions, height: int, background: np.ndarray):
    """(Raster, band buffer or None, rows of it that hold ``background``) for one thread of
    render_bands: the buffers a previous render with the same key gave back (the kernels
    leave them clean; its last band refilled its rows with its background: the tiger's first
    two bands at 2048 px spent 2 ms filling 16 MB with the colour they already held), or new
    ones (see _draws_with_msaa)."""
    W, strip_rows, _, band_rows, own_buffer = key
    with _kits_lock:
        # another size's buffers go now, not after this render has allocated its own
        _drop_other_kits(key)
        kits = _kits.get(key) if _draws_with_msaa(opts) else None
        kit = kits.pop() if kits else None
    if kit is None:
        raster = Raster(opts, W, height, strip_rows)
        buffer = np.empty((band_rows, W, 4), dtype=np.float32) if own_buffer else None
        return raster, buffer, 0
    scratch, buffer, filled, colour = kit
    # scratch[9]: where scan_lenses counts, the options' own
    return (Raster(opts, W, height, strip_rows, scratch[:9] + (opts.lens_stats,) + scratch[10:]),
            buffer, filled if colour == background.tobytes() else 0)


def _keep_kit(key, raster: Raster, buffer, filled: int, colour: np.ndarray) -> None:
    """Give back a thread's buffers for the next render (see KEEP_BYTES), its band buffer's
    first ``filled`` rows holding ``colour``."""
    if not _draws_with_msaa(raster.opts):
        return
    size = sum(a.nbytes for a in raster.scratch) + (0 if buffer is None else buffer.nbytes)
    with _kits_lock:
        _drop_other_kits(key)
        kits = _kits.get(key, [])
        if (len(kits) + 1) * size <= KEEP_BYTES:
            _kits[key] = kits + [(raster.scratch, buffer, filled, colour.tobytes())]


@contextlib.contextmanager
def band_pool(threads: int):
    """An executor of ``threads`` threads for a render (None for one thread): the fill
    batches' geometry is built on it (FillBatch), then the bands are drawn on it. The
    process's executor of that many threads (made on its first ``submit``, kept from render
    to render: a batch or a service rendering file after file made and joined one a file),
    or, while another render holds that one (renders on several threads at once) or renders
    ask for different numbers of threads, one of the render's own. Either way every task
    submitted has ended when the render gives it back."""
    if threads <= 1:
        yield None
        return
    shared = _borrow_shared_pool(threads)
    if shared is None:
        pool = _LazyPool(threads)
        try:
            yield pool
        finally:
            pool.shutdown()
        return
    lent = _LentPool(shared)
    try:
        yield lent
    finally:
        lent.wait()
        _give_back_shared_pool()


class _LazyPool:
    """A ThreadPoolExecutor of ``threads`` threads made on the first ``submit``: a small image
    is one band with little geometry and submits nothing, and concurrent.futures takes 7 ms
    of CPU to import (with logging), a twentieth of a 16 px render."""

    def __init__(self, threads: int):
        self.threads = threads
        self._executor = None
        self._lock = threading.Lock()
        #: executors made (tests count them)
        self.made = 0

    def submit(self, fn, *args):
        with self._lock:
            if self._executor is None:
                from concurrent.futures import ThreadPoolExecutor
                self._executor = ThreadPoolExecutor(self.threads)
                self.made += 1
        return self._executor.submit(fn, *args)

    def shutdown(self) -> None:
        if self._executor is not None:
            self._executor.shutdown()


class _LentPool:
    """The process's pool as one render sees it: its tasks are counted, so that the render
    ends with all of them (band_pool). Counted, not kept: a kept future holds its result
    (a part of a batch's geometry) until the render ends (scatter@3000: 394 -> 603 MB)."""

    def __init__(self, pool: _LazyPool):
        self.pool, self.threads = pool, pool.threads
        self._running = 0
        self._idle = threading.Condition()

    def submit(self, fn, *args):
        with self._idle:
            self._running += 1
        try:
            return self.pool.submit(self._run, fn, args)
        except BaseException:
            self._done()
            raise

    def _run(self, fn, args):
        try:
            return fn(*args)
        finally:
            self._done()

    def _done(self) -> None:
        with self._idle:
            self._running -= 1
            if not self._running:
                self._idle.notify_all()

    def wait(self) -> None:
        with self._idle:
            while self._running:
                self._idle.wait()


#: the process's band pool (band_pool): (_LazyPool, lent to a render now)
_shared_pool: list = [None, False]
_shared_lock = threading.Lock()


def _borrow_shared_pool(threads: int):
    """The process's pool of ``threads`` threads, lent to the caller; None while it is lent
    to another render."""
    with _shared_lock:
        pool, lent = _shared_pool
        if lent:
            return None
        if pool is None or pool.threads != threads:
            if pool is not None:
                pool.shutdown()     # (idle: nothing is lent)
            pool = _shared_pool[0] = _LazyPool(threads)
        _shared_pool[1] = True
        return pool


def _give_back_shared_pool() -> None:
    with _shared_lock:
        _shared_pool[1] = False


def release_band_pool() -> None:
    """End the process's band pool's threads (they wait idle between renders): the command
    line's quick exit (cli.main.console) needs this thread alone. A render after it makes a
    new one."""
    with _shared_lock:
        pool, lent = _shared_pool
        if pool is None or lent:
            return
        _shared_pool[0] = None
    pool.shutdown()


def _forget_band_pool() -> None:
    """In a forked child: the parent's pool threads do not exist there."""
    global _shared_lock
    _shared_lock = threading.Lock()
    _shared_pool[:] = [None, False]


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_band_pool)


def run_bands(draw_bands, bands, threads: int, pool=None, pace: BandPace | None = None) -> None:
    """``draw_bands(next_band)`` on ``threads`` threads sharing ``bands`` (``next_band()``
    gives each once, then None), on ``pool``'s threads (a band_pool of at least as many) if
    given, this thread being one of them. With a ``pace`` that waits, the others start when it
    says so (BandPace.band_drawn), or this thread draws the bands left as it regroups them."""
    threads = min(threads, len(bands))
    if threads == 1:
        todo = iter(bands)
        draw_bands(lambda: next(todo, None))
        return
    if pool is None:
        with band_pool(threads) as pool:
            run_bands(draw_bands, bands, threads, pool, pace)
        return
    todo = list(reversed(bands))        # popped from the end
    lock = threading.Lock()

    def next_band():
        with lock:
            return todo.pop() if todo else None
    futures = []

    def join():
        futures.extend(pool.submit(draw_bands, next_band) for _ in range(threads - 1))

    def join_paced():
        with lock:
            todo[:] = reversed(pace.share(todo))
        join()

    def alone():
        with lock:
            todo[:] = reversed(pace.regroup(todo))
    if pace is not None and pace.wait:
        pace.decide = (join_paced, alone)
    else:
        join()
    draw_bands(next_band)
    # (join, if it was called, was called by this thread, inside draw_bands)
    for future in futures:
        future.result()


def draw_sampled_bands(scene: Scene, opts: RenderOptions, consume, band_budget: int,
                       threads: int | None, target: np.ndarray | None) -> None:
    """render_bands where a pixel needs its neighbours' samples (raster/resolve.py): per band,
    one render per stored sample and tile class, each with that one sample per pixel, over the
    band grown by the filter's apron on every side (the scene moved R pixels right, so columns
    -R.. are drawn too), then the weighted sum of those sample images."""
    H, W = scene.height, scene.width
    R = (opts.resolve.shape[1] - 1) // 2
    WR = W + 2 * R
    items = prepare_items(translated(scene.root, R, 0), opts, canvas=(0, -R, WR, H + R))
    threads = available_cores() if threads is None else max(1, int(threads))
    band_rows, strip_rows = band_layout(WR, opts.sample_opts[0][0].samples, band_budget)
    band_rows = max(1, min(band_rows, H))
    if threads > 1:
        band_rows = max(1, min(band_rows, -(-H // (2 * threads))))
    starts = range(0, H, band_rows)
    background = premultiplied(scene.background)
    tw, th = opts.tile

    def draw_bands(next_start):
        # one set of kernel buffers for all: the kernels leave them clean
        first = Raster(opts.sample_opts[0][0], WR, H, strip_rows)
        rasters = [[Raster(o, WR, H, strip_rows, first.scratch) for o in per_class]
                   for per_class in opts.sample_opts]
        for raster in (r for per_class in rasters for r in per_class):
            raster.bands = APRON_BANDS
        for y0 in iter(next_start, None):
            rows = min(band_rows, H - y0)
            band = np.empty((rows, W, 4), np.float32) if target is None else target[y0:y0 + rows]
            acc = np.zeros((rows, W, 4), np.float32)
            image = np.empty((rows + 2 * R, WR, 4), np.float32)
            part = np.empty_like(image) if len(rasters[0]) > 1 else image
            for s, per_class in enumerate(rasters):
                for c, raster in enumerate(per_class):
                    part[0] = background
                    part[1:] = part[0]
                    draw_items(items, part, y0 - R, raster)
                    if part is not image:
                        # the pixels of tile class c (resolve.sample_classes): every th-th row
                        # and tw-th column, from the band's first device row y0 - R and column -R
                        cy, cx = divmod(c, tw)
                        iy, ix = (cy - (y0 - R)) % th, (cx + R) % tw
                        image[iy::th, ix::tw] = part[iy::th, ix::tw]
                accumulate(acc, y0, opts.resolve, opts.tile, s, image)
            finish(acc, band)
            consume(y0, band)
    run_bands(draw_bands, starts, threads)


def held_filtered_pixels(items, W: int, H: int) -> int:
    """Pixels of filtered content inside the W×H image that drawing ``items`` band by band
    may hold at once (every filtered layer, in layers, clips and masks included)."""
    total = 0
    for item in items:
        if not isinstance(item, Layer):
            continue
        if item.filters:
            x0, y0, x1, y1 = filter_box(item)
            total += max(0, min(W, x1) - max(0, x0)) * max(0, min(H, y1) - max(0, y0))
        else:
            total += held_filtered_pixels(item.items, W, H)
        total += held_filtered_pixels([p for p in (item.clip, item.mask) if p], W, H)
    return total


def layer_depth(items) -> int:
    """How many layer buffers drawing ``items`` holds at once: the deepest nesting of layers
    and their clips and masks (a filtered layer's content is drawn apart, when it is
    filtered: filtered_part)."""
    return max((item.depth for item in items if isinstance(item, (Layer, LayerRun))),
               default=0)


def layer_rows(width: int, depth: int) -> int:
    """Rows of a band whose ``depth`` nested layer buffers fit in LAYERS_BUDGET (at least 1)."""
    return max(1, LAYERS_BUDGET // max(1, width * 16 * depth))


def band_layout(W: int, samples: int, band_budget: int,
                analytic: bool = False) -> tuple[int, int]:
    """(rows of a band, rows of a kernel strip) for an image W pixels wide (``analytic``: for
    the analytic mode's kernel). A band is a whole number of strips, so no strip is cut short
    in the middle of the image."""
    most = 256 if analytic else MSAA_STRIP_ROWS
    strip_rows = max(1, min(most, STRIP_BUDGET // max(1, W * samples)))
    band_rows = max(1, band_budget // max(1, W * 16))     # float32 RGBA: 16 bytes a pixel
    if band_rows <= strip_rows:
        return band_rows, band_rows
    return band_rows // strip_rows * strip_rows, strip_rows


#: widths of filtered layers' rasters whose strip buffers a render keeps (Raster.local), and
#: the bytes one may hold (about 60 px wide at 8 samples: small layers are the ones whose
#: allocation counts, and a kept set is held while the layer is filtered, where a 400 px
#: region's 1.5 MB was half a canvas more at the filter's peak)
LOCAL_KITS = 8
LOCAL_KIT_BYTES = 1 << 18


class _Kit:
    """A Raster's strip buffers and its fill kernel bound to them (Raster.local)."""
    __slots__ = ("scratch", "fill")

    def __init__(self, scratch, fill):
        self.scratch, self.fill = scratch, fill


class Raster:
    """The raster kernels and their strip buffers for one image width: allocated once, reused
    by every band and batch (the kernels leave them clean), so no band pays for fresh pages."""

    def __init__(self, opts: RenderOptions, width: int, height: int, strip_rows: int,
                 scratch=None, kits=None):
        self.opts = opts
        self.width, self.height = width, height
        #: items draw_items has drawn with it (BandPace)
        self.drawn = 0
        #: the render's BandsDrawn and the device row of the band being drawn, while
        #: render_bands draws with it; None: bands one after another that do not overlap;
        #: APRON_BANDS (filtered_part)
        self.bands, self.band_start = None, 0
        #: kept layer buffers by nesting depth (layer_buffer)
        self.layer_buffers = []
        self.depth = 0
        #: the strip buffers and bound kernels of filtered layers' rasters (Raster.local),
        #: shared with the rasters made from this one
        self.kits = {} if kits is None else kits
        #: (rows, msaa_scratch of that many) for streamed fills (Raster.fill_streamed)
        self.stream_kit = None
        if isinstance(scratch, _Kit):
            self.scratch, self._fill = scratch.scratch, scratch.fill
            return
        if scratch is not None:
            # another Raster's buffers (same width, strips and sample count), used in turn
            self.scratch = scratch
        elif opts.mode == "analytic":
            self.scratch = analytic_scratch(strip_rows, width)
        elif opts.color_samples < opts.samples:
            self.scratch = csaa_scratch(strip_rows, width, opts.samples, opts.color_samples,
                                        opts.lens_stats)
        else:
            self.scratch = msaa_scratch(strip_rows, width, opts.samples, opts.lens_stats)
        self._fill = None

    def local(self, width: int, height: int) -> "Raster":
        """A raster for a filtered layer's region of width x height pixels, with this one's
        options: its strip buffers and bound kernel are kept for the render, by width (a
        document's many filtered elements come in a few sizes; allocating them and binding
        the kernel took a sixth of a small blurred marker's time), up to LOCAL_KITS of them,
        each of at most LOCAL_KIT_BYTES. The kernels leave the buffers clean, and a nested
        filtered layer of the same width uses them only between its parent's kernel calls."""
        opts = self.opts
        strip_rows = band_layout(width, opts.samples, BAND_BUDGET, opts.mode == "analytic")[1]
        key = (width, strip_rows)
        kit = self.kits.get(key)
        if kit is not None:
            return Raster(opts, width, height, strip_rows, kit, self.kits)
        local = Raster(opts, width, height, strip_rows, kits=self.kits)
        if LOCAL_KITS > 0 and sum(a.nbytes for a in local.scratch) <= LOCAL_KIT_BYTES:
            while len(self.kits) >= LOCAL_KITS:
                del self.kits[next(iter(self.kits))]        # the oldest
            self.kits[key] = _Kit(local.scratch, local.fill_kernel())
        return local

    def layer_buffer(self, rows: int, c: int, d: int) -> np.ndarray:
        """The (rows, width, 4) buffer of the layer, clip or mask drawn at the current
        nesting depth, transparent in columns c..d - 1 (the only ones its content can draw
        in, and the only ones read back): kept from band to band, where np.zeros gave fresh
        pages of the whole width each time (NASA's two clipped layers at 8192 px: 655 MB of
        pages cleared a render for content 1300 px wide). With render_msaa, (rows, d, 4):
        what lies right of column d - 1 is never read."""
        while len(self.layer_buffers) <= self.depth:
            self.layer_buffers.append(np.empty((0, self.width, 4), dtype=np.float32))
        buf = self.layer_buffers[self.depth]
        if buf.shape[0] < rows:
            buf = self.layer_buffers[self.depth] = np.empty((rows, self.width, 4), np.float32)
        buf = buf[:rows]
        if d < self.width and NARROW_LAYERS and _draws_with_msaa(self.opts):
            # only columns 0..d - 1, one contiguous array: render_msaa draws a pixel the same
            # for any width of target beyond it (crossings and lenses right of its last
            # column are dropped, not moved onto it), and a clip or mask reaching far to the
            # right of the content it multiplies is then not drawn there
            buf = buf.reshape(-1)[:rows * d * 4].reshape(rows, d, 4)
        buf[:, c:d] = 0.0
        return buf

    def draw_into(self, items, buf: np.ndarray, y0: int, c: int, d: int,
                  copy: bool = True) -> np.ndarray:
        """draw_items onto ``buf`` one nesting depth down (nested layers take the next
        buffer), then a copy of its columns c..d - 1, so that ``buf`` is free again (without
        ``copy`` those columns themselves: the caller copies what it needs before the buffer
        is drawn in again)."""
        self.depth += 1
        try:
            draw_items(items, buf, y0, self)
        finally:
            self.depth -= 1
        return buf[:, c:d].copy() if copy else buf[:, c:d]

    def fill_kernel(self):
        """The kernel bound to the options' arguments and the scratch buffers, their part of
        the call key worked out once (jit.bind_tail): made on the first fill."""
        if self._fill is None:
            o = self.opts
            if o.mode == "analytic":
                tail = (self.scratch,)
            elif o.color_samples < o.samples:
                tail = (o.sx, o.sy, o.weights, o.kernel_mode, o.a2c_bits, o.saturate,
                        self.scratch)
            else:
                tail = (o.sx, o.sy, o.weights, o.kernel_mode, o.a2c_bits, o.occlude,
                        o.saturate, self.scratch)
            self._fill = bind_tail(
                render_analytic if o.mode == "analytic" else
                render_csaa if o.color_samples < o.samples else render_msaa, tail)
        return self._fill

    def fill(self, batch: "FillBatch", target: np.ndarray, y0: int) -> None:
        b, o = batch, self.opts
        if b.runs is not None:
            self.fill_streamed(b, target, y0)
            return
        if b.source is not None:
            self.fill_chunked(b, target, y0)
            return
        kernel = self._fill or self.fill_kernel()
        if o.mode == "analytic":
            kernel(target, y0, b.edges, b.edge_off, b.box, b.rules, b.aa, b.kinds,
                   b.params, b.lut, b.tex)
            return
        out = np.zeros_like(target) if o.saturate else target
        kernel(out, y0, b.edges, b.edge_off, b.prims, b.prim_off, b.box, b.rules, b.aa,
               b.kinds, b.params, b.lut, b.tex)
        if o.saturate:
            # (over the whole buffer: a layer buffer's columns beyond its content hold what
            # was drawn there before, which may be infinite, and are never read)
            with np.errstate(invalid="ignore", over="ignore"):
                composite(out, target)


    def fill_chunked(self, b: "FillBatch", target: np.ndarray, y0: int) -> None:
        """Draw a batch built region by region (FillBatch.source) onto ``target`` (device rows
        from y0): the band cut into regions of whole strips (their first rows where the band's
        own strips begin), each drawn by render_msaa with the geometry of the fills whose box
        meets it (region_fills) and no rows for the others, which no strip of the region
        visits (scan.strip_buckets); each strip then does exactly what it does with the whole
        geometry: the same fills, their same edges and lenses (a path's geometry depends only
        on the path), the same paints and opaque runs (render_msaa's run_end is of the
        paints). So the same bytes, with only a region's geometry held at once."""
        o = self.opts
        H, W = target.shape[0], target.shape[1]
        strip = self.scratch[0].shape[0]
        kernel = self._fill or self.fill_kernel()
        out = np.zeros_like(target) if o.saturate else target
        verbs, pts, voff, poff, canvas = b.source
        cost, box = b.cost, b.box
        # regions of at least 4 mean fill heights: a fill is built again in each it meets
        least = max(strip, math.ceil(4 * b.fill_rows / strip) * strip)
        # (NaN compares false: such a fill meets every region)
        y_lo, y_hi = np.floor(box[:, 1]), np.floor(box[:, 3])
        shown = ~(box[:, 0] >= W) & ~(box[:, 2] < 0.0)
        a = y0
        while a < y0 + H:
            n = min(y0 + H - a, max(least, CHUNK_REGION_ROWS // strip * strip))
            while True:
                meets = shown & ~(y_hi < a) & ~(y_lo >= a + n)
                if n <= least or cost[meets].sum() <= CHUNK_REGION_BYTES:
                    break
                n = max(least, n // 2 // strip * strip)
            if meets.any():
                edges, edge_off, prims, prim_off = region_fills(
                    verbs, pts, voff, poff, canvas, np.flatnonzero(meets))
                kernel(out[a - y0:a - y0 + n], a, edges, edge_off, prims, prim_off, box,
                       b.rules, b.aa, b.kinds, b.params, b.lut, b.tex)
                del edges, prims
            a += n
        if o.saturate:
            with np.errstate(invalid="ignore", over="ignore"):
                composite(out, target)

    def fill_streamed(self, b: "FillBatch", target: np.ndarray, y0: int) -> None:
        """Draw a streamed fill (FillBatch.runs) onto ``target`` (device rows from y0): in
        regions of rows (stream_rows), each region's runs built (build_run: only the curves
        meeting the region's rows) and scanned one at a time (scan_run), then the region swept
        (sweep_fill). The same bytes as render_msaa drawing the whole geometry: see scan_run."""
        o = self.opts
        H, W = target.shape[0], target.shape[1]
        x0, y_top, x1, y_bottom = b.box[0].tolist()
        if x0 >= W or x1 < 0.0:
            return
        first, last = max(y0, math.floor(y_top)), min(y0 + H - 1, math.floor(y_bottom))
        if first > last:
            return
        rows = stream_rows(self.width, o.samples)
        if self.stream_kit is None or self.stream_kit[0] < min(rows, last + 1 - first):
            kit_rows = min(rows, last + 1 - first)
            self.stream_kit = (kit_rows, msaa_scratch(kit_rows, self.width, o.samples,
                                                      o.lens_stats))
        kit_rows, scratch = self.stream_kit
        out = np.zeros_like(target) if o.saturate else target
        ints, flts = b.runs
        ymin, ymax = flts[:, 4], flts[:, 5]
        nruns = len(ints)
        ends = np.append(ints[1:, 0], len(b.verbs))
        for a in range(first, last + 1, kit_rows):
            n = min(kit_rows, last + 1 - a)
            # (a NaN compares false: the run is built)
            skip = (ymax < a - 2 * CULL_MARGIN) | (ymin > a + n + 2 * CULL_MARGIN)
            for i in np.flatnonzero(~skip).tolist():
                run = np.array((ints[i, 0], ends[i], ints[i, 1]), np.int64)
                state = np.array((*flts[i, :4], float(ints[i, 2])))
                edges, prims = build_run(b.verbs, b.points, run, state, i == nruns - 1,
                                         MAX_SAGITTA, b.canvas, float(a), float(a + n))
                scan_run(edges, prims, a, n, W, o.sx, o.sy, o.kernel_mode, o.a2c_bits, scratch)
                del edges, prims
            sweep_fill(out, y0, a, n, b.rules, b.aa, b.kinds, b.params, b.lut, b.tex,
                       o.weights, o.saturate, scratch)
        if o.saturate:
            with np.errstate(invalid="ignore", over="ignore"):
                composite(out, target)


#: elements (rows x width x samples) of the per-sample buffers a streamed fill's region holds
#: at most (Raster.fill_streamed): 128 rows at 2048 px, 16 samples; a region's runs are built
#: again for each region they meet
STREAM_BUDGET = 1 << 22
#: curve segments of a fill from which it is streamed (FillBatch.runs): its edges and lenses
#: (~310 bytes a lens, a few lenses a curve) are not all held at once
STREAM_CURVES = 1 << 14
#: rows of a streamed fill's region at least
STREAM_MIN_ROWS = MSAA_STRIP_ROWS


def stream_rows(width: int, samples: int) -> int:
    """Rows of a streamed fill's region (Raster.fill_streamed) at that width and samples."""
    return max(STREAM_MIN_ROWS, STREAM_BUDGET // max(1, width * samples))


_IS_CURVE = np.zeros(256, np.bool_)
_IS_CURVE[[QUAD, CUBIC, CONIC]] = True


def _streams(fills, verbs, opts: RenderOptions) -> bool:
    """Whether a batch is drawn as a streamed fill (FillBatch.runs): one fill of at least
    STREAM_CURVES curves, in a sample mode drawn by render_msaa."""
    return (len(fills) == 1 and len(verbs) >= STREAM_CURVES and opts.flatten_tol == 0
            and _draws_with_msaa(opts)
            and int(np.count_nonzero(_IS_CURVE[verbs])) >= STREAM_CURVES)


class FillBatch:
    """Consecutive fills as the kernels take them: geometry and paints, built once per render.
    ``rows``, ``cols``: the device y and x ranges of its fills' boxes.

    A single fill of many curves (_streams) holds no geometry: ``runs`` (path_runs) cut its
    path into runs that Raster.fill_streamed builds and draws one at a time, so that its
    edges and lenses (a text element of 100,000 glyphs: 118 MB and 840 MB) are never held
    at once. Otherwise ``runs`` is None."""
    runs = None
    #: a batch built region by region (_chunked): (verbs, points, verb offsets, point
    #: offsets, canvas) for Raster.fill_chunked, and no geometry held; else None
    source = None
    #: a chunked batch's estimated bytes of geometry per fill, and the mean height of its
    #: fills weighted by those (_chunked)
    cost = fill_rows = None

    def __init__(self, fills, verbs, pts, voff, poff, opts: RenderOptions, pool=None,
                 extremes=None, canvas=NO_CULL, boxes=None, styles=None):
        moved = _crisp_at_centres(fills, pts, poff, opts)
        if _streams(fills, verbs, opts):
            built = None
            self.verbs, self.points = verbs, np.ascontiguousarray(moved)
            self.canvas = np.asarray(canvas, np.float64)
            self.runs = path_runs(verbs, self.points, RUN_VERBS)
            curves = int(np.count_nonzero(_IS_CURVE[verbs]))
            # (heaviest_first's guess at the work: the sizes build_batch reserves)
            self.edge_off = np.array([0, 2 * len(pts)], np.int64)
            self.prim_off = np.array([0, 5 * curves], np.int64)
            self.edges = self.prims = None
        elif (chunks := _chunked(fills, verbs, moved, voff, poff, opts,
                                 boxes if moved is pts else None)) is not None:
            # a batch too big to hold whole: built region by region as it is drawn
            # (Raster.fill_chunked), unless it reaches beyond FAR_X (below)
            built = None
            self.source = (verbs, moved, voff, poff, np.asarray(canvas, np.float64))
            self.cost, self.fill_rows = chunks
        else:
            # the geometry is built on the pool's threads while this one does the rest
            built = build_in_parts(verbs, moved, voff, poff, opts.flatten_tol, pool, canvas)
        # per-fill bounds from the control points (a curve lies in its control hull, the
        # quadratics standing in for a hopeless cubic within QUAD_FALLBACK_TOL of it)
        if extremes is None or moved is not pts:
            extremes = _extremes(moved, poff) if len(fills) == 1 and len(pts) else None
        if extremes is not None:
            # a few small paths (a clip's, a marker's content): their boxes from their
            # points' ``extremes`` as _fill_batches found them, Python floats (the same
            # values), where the general case's numpy calls on arrays of a few rows cost
            # several times the paths' geometry
            tol = QUAD_FALLBACK_TOL
            box = np.array([(x0 - tol, y0 - tol, x1 + tol, y1 + tol)
                            for x0, y0, x1, y1 in extremes])
            lo = (min(e[0] for e in extremes) - tol, min(e[1] for e in extremes) - tol)
            hi = (0.0, 0.0, max(e[2] for e in extremes) + tol, max(e[3] for e in extremes) + tol)
            if len(fills) == 1:
                self._one_fill(fills[0], box, lo, hi, built, opts)
                return
        else:
            box = np.empty((len(fills), 4))
            if boxes is None or moved is not pts:
                starts = poff[:-1]
                boxes = np.empty((len(fills), 4))
                boxes[:, :2] = np.minimum.reduceat(moved, starts, axis=0)
                boxes[:, 2:] = np.maximum.reduceat(moved, starts, axis=0)
            # (``boxes``: batch_extents' of these points, _fill_batches'; the same extremes,
            # but for the sign of a zero, which the margin added takes away)
            box[:, :2] = boxes[:, :2] - QUAD_FALLBACK_TOL
            box[:, 2:] = boxes[:, 2:] + QUAD_FALLBACK_TOL
            # (the columns' extremes in two reductions: a batch of one small fill costs its
            # reductions more than its geometry)
            lo, hi = box.min(axis=0), box.max(axis=0)
        self.box = box
        self.rows = (lo[1], hi[3])
        self.cols = (lo[0], hi[2])
        if styles is not None:
            # (fills given as styles, _run_batches': each array made per style, then taken
            # for each fill)
            styles, kind = styles
            evenodd = np.array([f.rule == "evenodd" for f in styles], np.bool_)
            self.rules = np.where(evenodd, RULE_EVENODD, RULE_NONZERO).astype(np.int64)[kind]
            self.aa = np.array([bool(f.antialias) for f in styles], np.bool_)[kind]
            self.kinds, self.params, self.lut, self.tex = style_arrays(
                styles, kind, lambda paint: pattern_tile(paint, opts))
        else:
            # (by maps over the fills, not a Python expression each: 140,000 fills' took
            # 70 ms)
            evenodd = np.fromiter(map(eq, map(_RULE, fills), repeat("evenodd")), np.bool_,
                                  len(fills))
            self.rules = np.where(evenodd, RULE_EVENODD, RULE_NONZERO).astype(np.int64)
            self.aa = np.fromiter(map(_ANTIALIAS, fills), np.bool_, len(fills))
            if (extremes is not None or len(fills) <= SOLID_ROWS) \
                    and all(type(f.paint) is Solid for f in fills):
                # (PaintTable.arrays of solid paints, without its bookkeeping: a LayerRun's
                # batch of 64 small layers' fills spent more on the table than on its
                # geometry)
                self.kinds, self.params, self.lut, self.tex = solid_arrays(
                    [solid_row(f.paint, f.opacity) for f in fills])
            else:
                table = PaintTable()
                table.add_fills(fills, lambda paint: pattern_tile(paint, opts))
                self.kinds, self.params, self.lut, self.tex = table.arrays()
        if built is None:
            if self.source is not None and lo[0] >= -FAR_X and hi[2] <= FAR_X:
                # (heaviest_first's guess at the work: the sizes build_batch reserves)
                self.edge_off, self.prim_off = _reserved_offsets(verbs, voff, poff)
                self.edges = self.prims = None
                return
            # (a streamed fill is one fill with finite points: _one_fill's case; not reached)
            self.runs = self.source = None
            built = build_in_parts(verbs, moved, voff, poff, opts.flatten_tol, None, canvas)
        self.edges, self.edge_off, self.prims, self.prim_off = built()
        # edges lie in their fills' boxes: only a batch reaching past x = ±FAR_X (or with a
        # NaN) has any to move, and the test costs a pass over the fills, not the edges
        if len(box) and not (lo[0] >= -FAR_X and hi[2] <= FAR_X):
            self.edges, self.edge_off = clamp_far_edges(self.edges, self.edge_off)

    def _one_fill(self, fill, box, lo, hi, built, opts) -> None:
        """The rest of __init__ for a batch of one fill: its rule and antialiasing as arrays
        shared by such batches, and a solid paint's table made once per render (shared by
        the fills of that paint and opacity: a marker's every instance), as the kernels only
        read them."""
        self.box = box
        self.rows = (lo[1], hi[3])
        self.cols = (lo[0], hi[2])
        self.rules = _ONE_RULE[fill.rule == "evenodd"]
        self.aa = _ONE_AA[bool(fill.antialias)]
        paint = fill.paint
        if type(paint) is Solid:
            key = (id(paint), fill.opacity)
            hit = opts.solid_tables.get(key)
            if hit is None:
                # (the paint is kept with its table: its id stays unique while the entry lives)
                hit = opts.solid_tables[key] = (paint, *solid_arrays([solid_row(paint,
                                                                                fill.opacity)]))
            _, self.kinds, self.params, self.lut, self.tex = hit
        else:
            table = PaintTable()
            table.add_fills([fill], lambda paint: pattern_tile(paint, opts))
            self.kinds, self.params, self.lut, self.tex = table.arrays()
        if built is None:
            if lo[0] >= -FAR_X and hi[2] <= FAR_X:
                return
            # (edges beyond FAR_X are moved: clamp_far_edges, on the whole geometry)
            self.runs = None
            built = build_in_parts(self.verbs, self.points, np.array([0, len(self.verbs)]),
                                   np.array([0, len(self.points)]), opts.flatten_tol, None,
                                   self.canvas)
        self.edges, self.edge_off, self.prims, self.prim_off = built()
        if not (lo[0] >= -FAR_X and hi[2] <= FAR_X):
            self.edges, self.edge_off = clamp_far_edges(self.edges, self.edge_off)


#: fills of solid paints a batch makes its paint table of from their solid_rows, at most (the
#: same arrays as PaintTable's; beyond, the table's sharing of rows pays)
SOLID_ROWS = 256
#: a one-fill batch's rules (by whether even-odd) and antialiasing arrays (FillBatch._one_fill)
_ONE_RULE = {True: np.array([RULE_EVENODD], np.int64),
             False: np.array([RULE_NONZERO], np.int64)}
_ONE_AA = {True: np.array([True]), False: np.array([False])}


#: device x beyond which an edge is moved onto the line x = ±FAR_X (see clamp_far_edges)
FAR_X = float(2 ** 24)


def clamp_far_edges(edges, edge_off):
    """The edges with their parts beyond x = ±FAR_X replaced by vertical edges on those
    lines over the same rows, the same winding for every sample on the canvas: the scan
    kernels find an edge's crossings from its top point, and with that point at x = 1e20 the
    crossing near the canvas is lost to rounding (and then lands on any column, into
    another fill's deltas). An edge within the bounds, all of them in practice, is kept as
    it is (the same bytes)."""
    if len(edges) == 0:
        return edges, edge_off
    xs = edges[:, 0::2]
    far = ~(np.abs(xs) <= FAR_X).all(axis=1)
    if not far.any():
        return edges, edge_off
    pieces = [None] * len(edges)
    counts = np.ones(len(edges), np.int64)
    for i in np.flatnonzero(far):
        got = _edge_within(*(float(v) for v in edges[i]))
        pieces[i] = got
        counts[i] = len(got)
    out = []
    for i, e in enumerate(edges):
        if pieces[i] is None:
            out.append(e[None])
        elif pieces[i]:
            out.append(np.asarray(pieces[i], np.float64))
    cum = np.zeros(len(edges) + 1, np.int64)
    np.cumsum(counts, out=cum[1:])
    new = np.concatenate(out) if out else np.empty((0, 4))
    return np.ascontiguousarray(new), np.ascontiguousarray(cum[edge_off])


def _edge_within(x0, y0, x1, y1):
    """One edge as pieces that stay within x = ±FAR_X (see clamp_far_edges); none for an
    edge with a NaN coordinate or a non-finite y (no winding can be made of it)."""
    if not (math.isfinite(y0) and math.isfinite(y1)) or x0 != x0 or x1 != x1:
        return []
    # infinite x: the edge's crossings are at infinity but for its end points
    x0 = max(min(x0, 1e300), -1e300)
    x1 = max(min(x1, 1e300), -1e300)
    ts = [0.0, 1.0]
    dx = x1 - x0
    for bound in (FAR_X, -FAR_X):
        if dx != 0.0:
            t = (bound - x0) / dx
            if 0.0 < t < 1.0:
                ts.append(t)
    ts.sort()
    out = []
    for ta, tb in zip(ts, ts[1:]):
        if tb <= ta:
            continue
        ya = y0 + (y1 - y0) * ta if ta < 1.0 else y1
        yb = y0 + (y1 - y0) * tb if tb < 1.0 else y1
        xm = x0 + dx * ((ta + tb) / 2)
        if xm > FAR_X:
            out.append((FAR_X, ya, FAR_X, yb))
        elif xm < -FAR_X:
            out.append((-FAR_X, ya, -FAR_X, yb))
        else:
            xa = x0 if ta == 0.0 else x0 + dx * ta
            xb = x1 if tb == 1.0 else x0 + dx * tb
            out.append((min(max(xa, -FAR_X), FAR_X), ya, min(max(xb, -FAR_X), FAR_X), yb))
    return out


#: estimated bytes of a batch's geometry (_chunked) from which it is built and drawn region
#: by region (Raster.fill_chunked), not held whole: a page of 2,000 text lines' 200,000
#: glyphs made 3.4 M edges and 2.3 M lenses, 840 MB
CHUNK_BYTES = 512 << 20
#: estimated bytes of the geometry of a region's fills at most (while the region is more
#: than a strip), and rows of a region at most
CHUNK_REGION_BYTES = 32 << 20
CHUNK_REGION_ROWS = 1024
#: mean height (rows) of a batch's fills, weighted by their geometry, up to which it is
#: chunked (see _chunked)
CHUNK_FILL_ROWS = 64
#: estimated bytes per point (two edges of 32 bytes) and per curve (lenses of 312 bytes)
_POINT_BYTES = 64
_CURVE_BYTES = 2 * 8 * PRIM_FIELDS


def _curves_before(verbs, voff) -> np.ndarray:
    """The number of curve verbs before each offset of ``voff``. (By the curves' positions,
    not a running sum over the verbs: numpy's cumsum of 6 M flags took 0.15 to 0.4 s.)"""
    return np.searchsorted(np.flatnonzero(_IS_CURVE[verbs]), voff)


def _chunked(fills, verbs, pts, voff, poff, opts: RenderOptions, boxes=None):
    """(each path's estimated geometry in bytes (_POINT_BYTES a point, _CURVE_BYTES a curve),
    the paths' mean height in rows weighted by those) where the batch is built region by
    region (FillBatch.source): several fills drawn by render_msaa, their geometry estimated
    at CHUNK_BYTES or more, that mean height at most CHUNK_FILL_ROWS; else None. ``boxes``:
    the paths' point extremes where known (batch_extents'). A fill is built once for each
    region it meets, and regions are at least 4 such heights (fill_chunked), so the builds
    of all regions cost at most (1 + CHUNK_FILL_ROWS / rows of a band) the whole build's on
    average (a text line is built once or twice, where a batch of tall paths is not
    chunked: each would be built again in every region)."""
    if len(fills) < 2 or opts.flatten_tol != 0 or not _draws_with_msaa(opts):
        return None
    if len(pts) * _POINT_BYTES + len(verbs) * _CURVE_BYTES < CHUNK_BYTES:
        return None         # (a bound on the estimate, without its passes)
    cost = np.diff(poff) * _POINT_BYTES + np.diff(_curves_before(verbs, voff)) * _CURVE_BYTES
    total = int(cost.sum())
    if total < CHUNK_BYTES:
        return None
    if boxes is None:
        # (every path of a batch has a point: _fill_batches keeps only paths that draw)
        ys = np.ascontiguousarray(pts[:, 1])
        height = np.maximum.reduceat(ys, poff[:-1]) - np.minimum.reduceat(ys, poff[:-1])
    else:
        height = boxes[:, 3] - boxes[:, 1]
    with np.errstate(invalid="ignore", over="ignore"):
        rows = float((cost * height).sum()) / total
    # (NaN, an infinite height: not chunked)
    return (cost, rows) if rows <= CHUNK_FILL_ROWS and math.isfinite(rows) else None


def _reserved_offsets(verbs, voff, poff):
    """Edge and lens offsets of the sizes build_batch reserves for each path (two edges a
    point, five lenses a curve): heaviest_first's guess at a chunked batch's work."""
    curves = _curves_before(verbs, voff)
    return 2 * (poff - poff[0]), 5 * (curves - curves[0])


#: fills a region's build skips at most between two it builds: a gap that short is built
#: along (its fills' geometry is never read) rather than cut into another build_batch call
REGION_GAP = 16


def region_fills(verbs, pts, voff, poff, canvas, which):
    """build_batch's (edges, edge_off, prims, prim_off) of a batch, of its fills ``which``
    (ascending indices) only: the other fills have no rows (edge_off and prim_off equal at
    their ends), those listed the rows build_batch gives them. Fills between two listed
    ones fewer than REGION_GAP apart are built too, in one call."""
    P = len(voff) - 1
    cuts = np.flatnonzero(np.diff(which) > REGION_GAP)
    firsts = np.concatenate(([which[0]], which[cuts + 1]))
    lasts = np.concatenate((which[cuts], [which[-1]]))
    ecount = np.zeros(P, np.int64)
    pcount = np.zeros(P, np.int64)
    edges, prims = [], []
    for f, l in zip(firsts.tolist(), lasts.tolist()):
        e, eo, p, po = build_batch(verbs, pts, voff[f:l + 2], poff[f:l + 2], 0.0, MAX_SAGITTA,
                                   canvas)
        ecount[f:l + 1] = np.diff(eo)
        pcount[f:l + 1] = np.diff(po)
        edges.append(e)
        prims.append(p)
    edge_off = np.zeros(P + 1, np.int64)
    prim_off = np.zeros(P + 1, np.int64)
    np.cumsum(ecount, out=edge_off[1:])
    np.cumsum(pcount, out=prim_off[1:])
    if len(edges) == 1:
        return edges[0], edge_off, prims[0], prim_off
    return np.concatenate(edges), edge_off, np.concatenate(prims), prim_off


#: build_batch's work per verb, roughly (a cubic: classified, split, a lens per piece), to
#: split a batch into parts of about equal work
_VERB_COST = np.ones(256, np.int64)
_VERB_COST[[QUAD, CONIC]] = 8
_VERB_COST[CUBIC] = 16
#: verbs' cost below which a batch is built in one part (a part costs a task and a copy)
SPLIT_COST = 4096
#: parts of a batch a thread (see build_in_parts)
PARTS_PER_THREAD = 4
#: a batch is built in parts only where its curves' cost (beyond a verb's) is at least this
#: much its verbs': joining the parts copies their rows into fresh pages, and a line's edge
#: takes about as long to copy there as to build (scatter's staircases, session 35: 3.9 M
#: verbs, 2.3 M edges built in 0.16-0.2 s on one thread, joined in 0.1-0.19 s more), so parts
#: pay for the curves' lenses only (a text's glyphs; not a plot's or a map's lines)
CURVE_SHARE = 1.0


def build_in_parts(verbs, pts, voff, poff, flatten_tol: float, pool=None, canvas=NO_CULL):
    """A function giving build_batch of the batch. With a pool and enough work the batch is
    built on the pool's threads (the kernel releases the GIL) from this call on, while this
    thread goes on, in parts of consecutive paths that the function joins: a path's edges
    and primitives depend only on the path, so they are the same bytes in one part or
    several. PARTS_PER_THREAD parts a thread, taken in turn, since the cost per verb is only
    a guess (a cubic's pieces grow with its size). ``canvas``: build_batch's (a float64
    array, as prepare_items makes it once for all its batches)."""
    parts = 1 if pool is None else pool.threads * PARTS_PER_THREAD
    if len(verbs) * _VERB_COST[CUBIC] < SPLIT_COST:
        parts = 1       # (no verb costs more than a cubic: a small batch is not summed up)
    if parts > 1:
        cost = np.zeros(len(verbs) + 1, np.int64)
        np.cumsum(_VERB_COST[verbs], out=cost[1:])
        total = int(cost[-1])
        # (total - len(verbs): the curves' cost beyond a verb's, as every other verb costs 1)
        if total < SPLIT_COST or total - len(verbs) < CURVE_SHARE * len(verbs):
            parts = 1
    if parts <= 1:
        whole = build_batch(verbs, pts, voff, poff, flatten_tol, MAX_SAGITTA, canvas)
        return lambda: whole
    # path boundaries nearest each equal share of the cost
    cuts = np.searchsorted(cost[voff], np.arange(1, parts) * (total / parts))
    bounds = [0] + sorted(set(int(c) for c in cuts) - {0, len(voff) - 1}) + [len(voff) - 1]

    def part(a, b):
        return build_batch(verbs, pts, voff[a:b + 1], poff[a:b + 1], flatten_tol, MAX_SAGITTA,
                           canvas)
    futures = [pool.submit(part, a, b) for a, b in zip(bounds, bounds[1:])]
    return functools.partial(_joined, bounds, futures)


def _joined(bounds, futures):
    """The parts of build_in_parts (paths bounds[i] .. bounds[i + 1] - 1) as one batch. Each
    part is let go once copied: joined by np.concatenate, every part was held beside the
    whole (2000 text labels on two threads: 134 MB of lenses twice, the render's peak)."""
    built = [f.result() for f in futures]
    futures.clear()
    edge_off = np.empty(bounds[-1] + 1, np.int64)
    prim_off = np.empty(bounds[-1] + 1, np.int64)
    edge_off[0] = prim_off[0] = ne = nc = 0
    for (a, b), (edges, eoff, prims, poff_) in zip(zip(bounds, bounds[1:]), built):
        edge_off[a + 1:b + 1] = eoff[1:] + ne
        prim_off[a + 1:b + 1] = poff_[1:] + nc
        ne, nc = ne + len(edges), nc + len(prims)
    edges = np.empty((ne, built[0][0].shape[1]), built[0][0].dtype)
    prims = np.empty((nc, built[0][2].shape[1]), built[0][2].dtype)
    for i, (a, b) in enumerate(zip(bounds, bounds[1:])):
        part = built[i]
        built[i] = None
        edges[edge_off[a]:edge_off[b]] = part[0]
        prims[prim_off[a]:prim_off[b]] = part[2]
        del part
    return edges, edge_off, prims, prim_off


#: see _crisp_at_centres
CRISP_NUDGE = 1 / 256


def _crisp_at_centres(fills, pts, poff, opts: RenderOptions):
    """The points with each aliased fill (shape-rendering crispEdges) moved by the offset of
    the first sample from the pixel centre: the sample kernels take an aliased pixel's
    coverage from its first sample, and so decide it by whether its centre is inside, as
    SVG's aliased rendering and resvg do (the analytic mode decides by half the area; the
    patterns rendered once per sample, without ``sx``, share the batch between samples)."""
    if opts.mode == "analytic" or not hasattr(opts, "sx") or all(map(_ANTIALIAS, fills)):
        return pts
    # and a 1/256 px further, so that a centre on a left or top edge is out and one on a
    # right or bottom edge in, as tiny-skia rounds an aliased edge (lines at n + 1/2 px)
    shift = np.array([opts.sx[0] - 0.5, opts.sy[0] - 0.5]) + CRISP_NUDGE
    pts = pts.copy()
    for i, f in enumerate(fills):
        if not f.antialias:
            pts[poff[i]:poff[i + 1]] += shift
    return pts


#: pattern tiles of at most this many pixels are rendered in the reference mode (see
#: tile_options)
EXACT_TILE_PIXELS = 64 * 64
_tile_opts_lock = threading.Lock()


def tile_options(opts: RenderOptions, width: int, height: int) -> RenderOptions:
    """The options a pattern tile of width x height pixels renders with. A tile's coverage
    error repeats in every copy of it: one texel of a small tile's curve 1/8 off (the default
    8 samples) is a pixel that far off in each of hundreds of copies, 0.9% of the pixels of a
    200 px square filled with 7 x 15 px tiles of a circle. So small tiles of the multisample
    modes take the reference mode's 256 samples (still composited per sample, so without
    conflation). The share of pixels off is the tile's own: high where a small tile is mostly
    edge pixels, as low as any drawing's in a large one, which keeps the render's own options
    (a 64 x 64 tile of 200 translucent curves costs about 50 ms more), as does a render that
    chose another mode (aliased, alpha, exact)."""
    if opts.mode not in ("approx", "persample") or width * height > EXACT_TILE_PIXELS:
        return opts
    with _tile_opts_lock:
        if opts.tile_opts is None:
            opts.tile_opts = RenderOptions("reference", 256)
    return opts.tile_opts


def pattern_tile(paint: PatternPaint, opts: RenderOptions) -> ImagePaint:
    """A pattern as the repeating image of its tile, rendered once per content group (shapes
    sharing a pattern share its content) with tile_options."""
    opts = opts.parent      # a sample image's pattern tiles are the whole render's
    key = (id(paint.content), paint.width, paint.height, paint.linear_rgb)
    hit = opts.tiles.get(key)
    if hit is None:
        rgba = render_float(Scene(paint.width, paint.height, paint.content),
                            tile_options(opts, paint.width, paint.height))
        if paint.linear_rgb:
            rgba = linear_rgb_image(rgba)
        # the content is kept with its tile: its id stays unique while the entry lives
        hit = opts.tiles[key] = (paint.content, rgba)
    return ImagePaint(hit[1], paint.to_paint, repeat=True, smooth=paint.smooth)


class Layer:
    """A group drawn into a buffer of its own and composited, prepared once per render: its
    items, the clip (a layer whose alpha is a coverage) and the mask (a layer whose luminance
    or alpha is) that multiply it, opacity and blend mode. ``rows``: the device y range where
    it can be non-zero — inside its content (or its filter region), its clip and its mask — or
    None. A filtered layer is rendered and filtered whole, once, the first time a band needs it
    (``filtered``: (x0, y0, x1, y1) device rect and its pixels, by the options drawing it: the
    sample images of raster/resolve.py each have their own).

    ``bound``: the device y range outside which the layer is not drawn (its parent's clip and
    mask rows), or None: content outside it, and the whole content when its clip or mask draws
    nothing, is not prepared (draw_items would skip it)."""

    def __init__(self, group: Group, opts: RenderOptions, pool=None, bound=None,
                 canvas=NO_CULL):
        # a clip that is one rectangle is prepared only if it does not cover the content
        # (_clip_covers); its rows are those its batch would have
        rect = _rectangle_clip(group.clip, opts) if group.clip is not None else None
        self.clip = (Layer(group.clip, opts, pool, canvas=canvas)
                     if group.clip is not None and rect is None else None)
        self.mask = (Layer(group.mask.content, opts, pool, canvas=canvas)
                     if group.mask is not None else None)
        parts = [p.rows for p in (self.clip, self.mask) if p is not None]
        if rect is not None:
            parts.insert(0, (rect[1] - QUAD_FALLBACK_TOL, rect[3] + QUAD_FALLBACK_TOL))
        for rows in parts:
            bound = rows if bound is None else _intersection(bound, rows)
            if bound is None:
                break
        hidden = bound is None and bool(parts)
        # a filtered layer's content is prepared when it is filtered (moved to its region)
        self.group = group if group.filters else None
        self.items = ([] if group.filters or hidden
                      else prepare_items(group, opts, pool, bound, canvas))
        if rect is not None and (hidden or not _clip_covers(rect, self.items)):
            self.clip = Layer(group.clip, opts, pool, canvas=canvas)
        self.mask_kind = group.mask.kind if group.mask is not None else None
        self.opacity = group.opacity
        self.blend = group.blend
        self.filters = group.filters
        if self.filters:
            self.filtered = {}
            self.filtering = threading.Lock()   # bands on threads: one of them filters
            #: the device box of its filter regions (filter_box)
            self.box = box = _filter_regions(self.filters)
            rows = (box[1], box[3])
        else:
            rows = _union([item.rows for item in self.items])
        self.rows = None if hidden or bound is None and rows is None else \
            rows if bound is None else _intersection(rows, bound)
        #: the filtered layer that is all this layer holds, when draw_layer may take its
        #: filtered pixels as this layer's (see _sole_filtered), else None
        self.sole = _sole_filtered(self)
        #: layer buffers drawing it holds at once (layer_depth)
        self.depth = 1 + max([layer_depth(self.items)]
                             + [part.depth for part in (self.clip, self.mask) if part is not None])

    @functools.cached_property
    def items_box(self):
        """_items_box of its items, once: each layer around it asks (n nested layers under
        rectangle clips, as nested <svg>s are, walked n^2/2 layers)."""
        return _items_box(self.items)


def _rectangle_clip(clip: Group, opts: RenderOptions):
    """(x0, y0, x1, y1) of a clip that is one opaque, antialiased, axis-aligned rectangle,
    drawn by a multisample kernel: its coverage is exactly 1 at a pixel whose samples are
    all inside (the opaque colour itself), so _clip_covers can tell where drawing it
    changes nothing. None for any other clip, and in the exact modes (an area summed in
    floats) and CSAA."""
    if opts.mode not in MSAA_MODES or opts.color_samples != opts.samples \
            or clip.clip is not None or clip.mask is not None or clip.filters \
            or len(clip.children) != 1 or type(clip.children[0]) is not Fill:
        return None
    fill = clip.children[0]
    if type(fill.paint) is not Solid or fill.paint.color[3] != 1.0 or fill.opacity != 1.0 \
            or not fill.antialias:
        return None
    return _axis_rectangle(fill.path)


def _clip_covers(rect, items) -> bool:
    """Whether a rectangle clip (_rectangle_clip) has coverage 1 at every pixel the items
    can draw in (their boxes, with the pixels a kernel can write beyond them, and one to
    spare on every side): it multiplies the layer by exactly 1 wherever the layer is not
    transparent, so drawing it changes no pixel (a mask's region around its content, a
    marker's viewport around its drawing)."""
    box = _items_box(items)
    if box is None:
        return False
    x0, y0, x1, y1 = rect
    # a kernel writes in columns floor(box x0) .. floor(box x1) + 1 and rows floor(box y0) ..
    # floor(box y1); a pixel px has its samples inside when x0 < px and px + 1 < x1
    return (x0 + 1.0 < math.floor(box[0]) and math.floor(box[2]) + 3.0 < x1
            and y0 + 1.0 < math.floor(box[1]) and math.floor(box[3]) + 2.0 < y1)


_RECT_VERBS = (bytes((MOVE, LINE, LINE, LINE, CLOSE)), bytes((MOVE, LINE, LINE, LINE, LINE, CLOSE)))


def _axis_rectangle(path):
    """(x0, y0, x1, y1) of a path that is one axis-aligned rectangle of positive size (four
    sides, the last one closed or drawn), else None."""
    verbs, pts = path.verbs, path.points
    if verbs.tobytes() not in _RECT_VERBS:
        return None
    p = pts.reshape(-1, 2).tolist()
    if len(p) == 5 and p[4] != p[0]:
        return None
    (ax, ay), (bx, by), (cx, cy), (dx, dy) = p[:4]
    sides = ((ax == bx and by == cy and cx == dx and dy == ay)
             or (ay == by and bx == cx and cy == dy and dx == ax))
    x0, x1 = min(ax, cx), max(ax, cx)
    y0, y1 = min(ay, cy), max(ay, cy)
    if not sides or not (x0 < x1 and y0 < y1) or not all(map(math.isfinite, (x0, y0, x1, y1))):
        return None
    return x0, y0, x1, y1


def _items_box(items):
    """(x0, y0, x1, y1) of the boxes of prepared items' fills (nested layers' content, a
    filtered layer's filter box), None when there are none or one is not finite."""
    lo_x = lo_y = math.inf
    hi_x = hi_y = -math.inf
    for item in items:
        if isinstance(item, FillBatch):
            box = (item.cols[0], item.rows[0], item.cols[1], item.rows[1])
        elif item.filters:
            box = filter_box(item)
        else:
            box = item.items_box
            if box is None:
                return None
        lo_x, lo_y = min(lo_x, box[0]), min(lo_y, box[1])
        hi_x, hi_y = max(hi_x, box[2]), max(hi_y, box[3])
    box = (lo_x, lo_y, hi_x, hi_y)
    return box if all(map(math.isfinite, box)) else None


def _sole_filtered(layer: Layer):
    """The one item of a layer that holds nothing but a filtered layer of plain pixels
    (normal blend, opacity 1, no clip or mask of its own), the layer itself composited
    normally and its clip and mask free of filters: drawn onto a transparent buffer, that
    item's filtered pixels are the buffer's (0·(1 - a) + x is x), so draw_layer composites
    them as they are, with this layer's clip, mask and opacity, and no buffer (a marker's
    viewport clip around its filtered content, a clipped group around a filtered one). None
    otherwise. (Clips and masks with filters inside keep the general path: it draws them
    on every band, which lets go of their filtered pixels.)"""
    if layer.filters or layer.blend != "normal" or len(layer.items) != 1:
        return None
    inner = layer.items[0]
    if not (isinstance(inner, Layer) and inner.filters and inner.blend == "normal"
            and inner.opacity == 1.0 and inner.clip is None and inner.mask is None):
        return None
    if _holds_filters(layer.clip) or _holds_filters(layer.mask):
        return None
    return inner


def _holds_filters(layer) -> bool:
    """Whether a layer (or None), its nested layers, clips or masks have filters."""
    if layer is None:
        return False
    return bool(layer.filters) or any(_holds_filters(item) for item in layer.items
                                      if isinstance(item, Layer)) \
        or _holds_filters(layer.clip) or _holds_filters(layer.mask)


def filter_box(layer: "Layer") -> tuple:
    """(x0, y0, x1, y1): the device box of the union of a filtered layer's filter regions."""
    return layer.box


def _filter_regions(filters) -> tuple:
    """The box of the union of the filters' regions."""
    if len(filters) == 1:
        return tuple(filters[0].region)
    regions = [f.region for f in filters]
    return (min(r[0] for r in regions), min(r[1] for r in regions),
            max(r[2] for r in regions), max(r[3] for r in regions))


def _union(ranges):
    ranges = [r for r in ranges if r is not None]
    if not ranges:
        return None
    return min(r[0] for r in ranges), max(r[1] for r in ranges)


def _intersection(a, b):
    if a is None or b is None or max(a[0], b[0]) > min(a[1], b[1]):
        return None
    return max(a[0], b[0]), min(a[1], b[1])


def prepare_items(group: Group, opts: RenderOptions, pool=None, bound=None,
                  canvas=NO_CULL) -> list:
    """The group's content as FillBatch and Layer items in paint order: fills and layer
    groups in paint order, plain groups flattened away (walked with a stack of iterators, not
    generators: map data yields tens of thousands of fills through them). ``pool``: an
    executor whose threads help build the batches' geometry (band_pool). ``bound``: the
    device y range the items are drawn in (a clipped layer's), or None: batches of fills
    wholly outside it are left out (_fill_batches). ``canvas``: build_batch's, as a tuple or
    array."""
    # (one array for all the batches: converting it per batch cost a map's thousands of them)
    canvas = np.asarray(canvas, np.float64)
    items = []
    batch: list[Fill] = []
    # folded fills whose pixels no other of them touches, drawn as one batch (boxes: their
    # pixel boxes, _pixel_box); None while ``batch`` holds other fills
    boxes = None
    # layers of fills alone whose pixels no other of them touches, drawn as one LayerRun:
    # [(group, content fills, clip fills or None)] and their footprints
    run, run_boxes = [], []
    # [layers taken into runs, refused]: the test costs about 15 µs a layer (its fills'
    # boxes), so where it keeps failing (large clips about small shapes) it is given up
    tried = [0, 0]

    def end_batch(new_boxes):
        # the fills gathered so far as batches, then a new batch: of folded fills that share
        # no pixel (``new_boxes`` []) or of any fills (None)
        nonlocal batch, boxes
        if batch:
            items.extend(_fill_batches(batch, opts, pool, None, bound, canvas))
        batch, boxes = [], new_boxes

    def end_run():
        if len(run) == 1:
            items.append(Layer(run[0][0], opts, pool, bound, canvas))
        elif run:
            items.append(LayerRun(run, opts, pool, canvas))
        run.clear()
        run_boxes.clear()
    stack = [_children(group)]
    while stack:
        for node in stack[-1]:
            if isinstance(node, Group):
                if node.needs_layer():
                    fills = _opacity_fold(node)
                    # (only where nothing bounds the rows drawn: a clipped layer's content
                    # keeps Layer, which leaves out what its bound never shows)
                    simple = None
                    if fills is None and LAYER_RUNS and bound is None \
                            and tried[1] <= RUN_TRIES * (tried[0] + 1):
                        simple = _run_layer(node, opts)
                        tried[simple is None] += 1
                    if simple is not None:
                        box = simple[3]
                        if len(run) >= RUN_LAYERS or _meets(box, run_boxes):
                            end_run()
                        end_batch(None)
                        run.append(simple[:3])
                        run_boxes.append(box)
                        continue
                    if run:
                        end_run()
                    if fills is not None and opts.mode == "analytic":
                        # the analytic kernel composites each fill on its own per pixel
                        batch.extend(fills)
                        continue
                    if fills is not None:
                        # a batch of fills that share no pixel draws each pixel as the one
                        # fill touching it would alone; the multisample kernels keep a split
                        # pixel's samples apart from one fill of a batch to the next, where
                        # a layer composites the resolved pixel
                        box = _pixel_box(fills[0]) if len(fills) == 1 else _EVERYWHERE
                        if boxes is None or len(boxes) >= DISJOINT_RUN or _meets(box, boxes):
                            end_batch([])
                        batch.extend(fills)
                        boxes.append(box)
                        continue
                    end_batch(None)
                    items.append(Layer(node, opts, pool, bound, canvas))
                else:
                    stack.append(_children(node))
                    break
            elif type(node) is _Fills:
                # (fills alone: what the loop below does for each of them)
                if run:
                    end_run()
                if boxes is not None:
                    end_batch(None)
                batch.extend(node.fills)
            else:
                if run:
                    end_run()
                if boxes is not None:
                    end_batch(None)
                batch.append(node)
        else:
            stack.pop()
    end_run()
    end_batch(None)
    return items


class _Fills:
    """A group's children when none is a group (_children)."""
    __slots__ = ("fills",)

    def __init__(self, fills):
        self.fills = fills


def _children(group: Group):
    """An iterator over the group's children for prepare_items, or over one _Fills of them
    all when none is a group: a plain group of many fills (20,000 circles and their strokes)
    is then gathered into the batch at once, where each fill cost a turn of the loop."""
    children = group.children
    if len(children) > 1 and not any(issubclass(t, Group) for t in set(map(type, children))):
        return iter((_Fills(children),))
    return iter(children)


def _meets(box, boxes) -> bool:
    """Whether the (x0, y0, x1, y1) ``box`` meets any of ``boxes`` (edges included)."""
    return any(box[0] <= b[2] and b[0] <= box[2] and box[1] <= b[3] and b[1] <= box[3]
               for b in boxes)


def _opacity_fold(group: Group):
    """[the one fill a layer draws], with the layer's opacity taken into the fill's own, when
    opacity is all the layer does (normal blend, no clip, mask, filter or isolation; plain or
    opacity-only groups of one child down to the fill), else None. Drawn alone onto the target
    it gives what the layer's composite gives, in exact arithmetic: a kernel puts a fill of
    premultiplied colour c, alpha a at coverage f over T as T(1 - f·a) + f·c, and the layer,
    f·c on transparent composited with opacity o, as T(1 - o·f·a) + o·f·c, which is the fill
    with o·c, o·a; no layer buffer, copy or composite (3000 `<path opacity>`s)."""
    opacity = 1.0
    node = group
    while type(node) is Group:
        if len(node.children) != 1 or node.clip is not None or node.mask is not None \
                or node.blend != "normal" or node.isolate or node.filters:
            return None
        opacity *= node.opacity
        node = node.children[0]
    if type(node) is not Fill:
        return None
    return [Fill(node.path, node.paint, node.rule, node.opacity * opacity, node.antialias)]


#: folded fills drawn as one batch at most (prepare_items tests each against the others)
DISJOINT_RUN = 32
#: _pixel_box of a fill whose pixels are not known: it shares them with any other
_EVERYWHERE = (-math.inf, -math.inf, math.inf, math.inf)


def _pixel_box(fill: Fill):
    """(x0, y0, x1, y1): bounds of the pixels a kernel can write drawing ``fill`` alone
    (_EVERYWHERE if unknown): its points' extremes (a curve lies in its control hull) grown
    by a pixel each way for the one a kernel writes beyond its box, and one more for
    QUAD_FALLBACK_TOL and an aliased fill's move onto sample centres."""
    flat = (fill.path._arrays or fill.path._freeze())[1].ravel().tolist()
    if not 0 < len(flat) <= 2 * SMALL_POINTS or not all(map(math.isfinite, flat)):
        return _EVERYWHERE
    xs, ys = flat[0::2], flat[1::2]
    return (math.floor(min(xs)) - 2, math.floor(min(ys)) - 2, math.floor(max(xs)) + 2,
            math.floor(max(ys)) + 2)


_NOT_DRAWING_BYTES = bytes((MOVE, CLOSE))


#: layers one LayerRun draws at most (prepare_items tests each against the others)
RUN_LAYERS = 64
#: whether prepare_items draws disjoint layers of fills as LayerRuns (off only to test them)
LAYER_RUNS = True
#: whether layer buffers end at the last column read (Raster.layer_buffer; off only to test)
NARROW_LAYERS = True
#: layers refused a run for each one taken, at most, before prepare_items stops trying
RUN_TRIES = 8


def _run_layer(group: Group, opts: RenderOptions):
    """(group, its fills, its clip's fills or None, footprint) of a layer that a LayerRun
    can draw, else None: fills alone (no nested group) under opacity, normal blend and at most
    a clip of fills alone (not a rectangle: Layer may leave that out, _rectangle_clip), each
    fill short, finite, drawing something and visible, so that the batches made of them keep
    every one (_fill_batches). The footprint holds every pixel a kernel writes drawing them
    (_pixel_box) and every pixel draw_run reads for the layer (its rows and columns as Layer
    and layer_columns find them, from boxes grown by QUAD_FALLBACK_TOL: a pixel more)."""
    if group.blend != "normal" or group.filters or group.mask is not None \
            or not group.children or any(type(c) is not Fill for c in group.children):
        return None
    clip = group.clip
    if clip is not None:
        if clip.clip is not None or clip.mask is not None or clip.filters \
                or not clip.children or any(type(c) is not Fill for c in clip.children) \
                or _rectangle_clip(clip, opts) is not None:
            return None
    box = _fills_box(group.children)
    if box is None:
        return None
    if clip is not None:
        clip_box = _fills_box(clip.children)
        if clip_box is None:
            return None
        # a Layer draws its content and its clip in the rows they share; a run draws each
        # whole, so only where that is not much more: a clip around its content, or within
        # it, not a large circle about a small shape (2000 such clipped groups were slower
        # in runs, and no faster with the clips drawn on their own in their layers' rows:
        # one batch of many opaque fills sharing rows draws its spans slower, by the
        # occlusion stamps of render_msaa)
        shared = min(box[3], clip_box[3]) - max(box[1], clip_box[1])
        if shared <= 0:
            return None
        width, clip_width = box[2] - box[0], clip_box[2] - clip_box[0]
        more = ((box[3] - box[1] - shared) * width
                + (clip_box[3] - clip_box[1] - shared) * clip_width)
        if more > RUN_MORE * shared * (width + clip_width):
            return None
        box = (min(box[0], clip_box[0]), min(box[1], clip_box[1]),
               max(box[2], clip_box[2]), max(box[3], clip_box[3]))
    return (group, group.children, None if clip is None else clip.children,
            (box[0] - 1, box[1] - 1, box[2] + 1, box[3] + 1))


#: pixels a run may draw of a clipped layer beyond those a Layer draws, at most, as a part of
#: the latter (_run_layer)
RUN_MORE = 0.1


def _fills_box(fills):
    """The union of the fills' _pixel_box, or None if one of them is unknown, invisible or
    draws nothing (_run_layer)."""
    x0 = y0 = math.inf
    x1 = y1 = -math.inf
    for fill in fills:
        if not fill.opacity > 0:
            return None
        box = _pixel_box(fill)
        if box is _EVERYWHERE or not fill.path.verbs.tobytes().translate(None,
                                                                          _NOT_DRAWING_BYTES):
            return None
        x0, y0 = min(x0, box[0]), min(y0, box[1])
        x1, y1 = max(x1, box[2]), max(y1, box[3])
    return x0, y0, x1, y1


class LayerRun:
    """Consecutive layers of fills alone (_run_layer) whose footprints do not meet, prepared
    and drawn together: their fills as one batch, their clips' fills as another, each drawn
    by one kernel call onto a shared buffer, then each layer composited from its own
    rectangle of those buffers as draw_layer composites a Layer. A pixel of a layer's
    rectangle is drawn by its own fills alone, in their order (the kernels draw a pixel from
    the fills touching it; disjoint folded fills share batches the same way), so it holds
    the bytes the layer's own buffer would; what the layers share is the per-batch and
    per-call cost (2000 clipped groups made 4000 batches and 4000 kernel calls).
    ``layers``: (rows, columns of its content's boxes, opacity, clipped) of each layer that
    shows anywhere."""
    filters = ()
    mask = None

    def __init__(self, run, opts: RenderOptions, pool=None, canvas=NO_CULL):
        content = [f for _, fills, _ in run for f in fills]
        clips = [f for _, _, fills in run if fills is not None for f in fills]
        (self.content,) = _fill_batches(content, opts, pool, None, None, canvas)
        self.clip = _fill_batches(clips, opts, pool, None, None, canvas)[0] if clips else None
        #: (items, as a Layer's: what layer_columns, _items_box and nested_items read)
        self.items = [self.content]
        boxes = self.content.box.tolist()
        clip_boxes = self.clip.box.tolist() if clips else None
        self.layers = []
        i = j = 0
        for group, fills, clip in run:
            box = boxes[i:i + len(fills)]
            i += len(fills)
            # a Layer's rows: its batch's (the boxes' extremes), within its clip's
            rows = (min(b[1] for b in box), max(b[3] for b in box))
            cols = (min(b[0] for b in box), max(b[2] for b in box))
            if clip is not None:
                box = clip_boxes[j:j + len(clip)]
                j += len(clip)
                rows = _intersection(rows, (min(b[1] for b in box), max(b[3] for b in box)))
                if rows is None:
                    continue
            self.layers.append((rows, cols, group.opacity, clip is not None))
        self.rows = _union([layer[0] for layer in self.layers])
        #: layer buffers drawing it holds at once (layer_depth)
        self.depth = 2 if clips else 1

    @property
    def items_box(self):
        return _items_box(self.items)   # (its one batch)


def draw_run(run: LayerRun, target: np.ndarray, y0: int, raster: Raster) -> None:
    """Composite a LayerRun's layers onto ``target`` (device rows from y0), each in the rows
    and columns draw_layer would composite it in."""
    h, w = target.shape[:2]
    shown = []
    for rows, cols, opacity, clipped in run.layers:
        a, b = band_rows(rows, y0, h)
        c, d = drawn_columns(cols[0], cols[1], w)
        if a < b and c < d:
            shown.append((a, b, c, d, opacity, clipped))
    if not shown:
        return
    raster.drawn += len(shown) - 1
    top = min(s[0] for s in shown)
    rows = max(s[1] for s in shown) - top
    # each layer's rectangle transparent (the rest of the buffers is never read; the
    # buffers end where the last rectangle does: c = d clears nothing)
    right = max(s[3] for s in shown)
    img = raster.layer_buffer(rows, right, right)
    for a, b, c, d, _, _ in shown:
        img[a - top:b - top, c:d] = 0.0
    raster.depth += 1
    try:
        draw_items(run.items, img, y0 + top, raster)
        if run.clip is not None:
            cov = raster.layer_buffer(rows, right, right)
            for a, b, c, d, _, clipped in shown:
                if clipped:
                    cov[a - top:b - top, c:d] = 0.0
            draw_items([run.clip], cov, y0 + top, raster)
    finally:
        raster.depth -= 1
    over_rects(img, img if run.clip is None else cov, target, top,
               np.array([s[:4] + (s[5],) for s in shown], np.int64),
               np.array([s[4] for s in shown], np.float64))


def _fill_batches(fills, opts: RenderOptions, pool=None, shift=None, bound=None,
                  canvas=NO_CULL) -> list:
    """[FillBatch] of the fills that can draw something (non-empty, visible, finite), or [].
    Emptiness and finiteness are found on the batch's arrays, per path from running sums.
    ``shift``: (dx, dy), the fills moved by that many device pixels, as nodes.translated
    moves them (see _shifted_arrays). ``bound``: a device y range outside which the batch is
    not drawn (prepare_items), or None: a batch whose points all lie beyond it is left out."""
    if FillRuns in set(map(type, fills)):
        return _run_batches(fills, opts, pool, shift, bound, canvas)
    if not all(map(lt, repeat(0), map(_OPACITY, fills))):
        fills = [f for f in fills if f.opacity > 0]
    if not fills:
        return []
    arrays = _shifted_arrays(fills, shift)
    verbs, pts, voff, poff = arrays
    if len(fills) == 1 or len(fills) <= SMALL_BATCH and len(pts) <= SMALL_POINTS:
        # (one path, or a few short ones: the tests below without their running sums or
        # numpy passes: a verb besides MOVE and CLOSE found in each path's bytes, and the
        # points' extremes, finite, which FillBatch takes as the boxes)
        vb, vo = verbs.tobytes(), voff.tolist()
        drawing = all(vb[a:b].translate(None, _NOT_DRAWING_BYTES) for a, b in zip(vo, vo[1:]))
        extremes = _extremes(pts, poff) if drawing else None
        if extremes is not None:
            if bound is not None and _beyond(min(e[1] for e in extremes),
                                             max(e[3] for e in extremes), bound):
                return []
            return [FillBatch(fills, *arrays, opts, pool, extremes, canvas)]
        if len(fills) == 1:
            return []
    return _drawing_batch(fills, arrays, opts, pool, bound, canvas)


def _drawing_batch(fills, arrays, opts, pool, bound, canvas, styles=None) -> list:
    """[FillBatch] of those of ``fills`` (their batch ``arrays``, moved) that can draw
    something, or [] for none: paths that draw (a verb besides MOVE and CLOSE, finite points)
    and their points' boxes found in one kernel pass (FillBatch's boxes of a batch whose
    points it does not move), the others' rows left out; none where all points lie beyond
    ``bound``. ``styles``: FillBatch's (the fills' styles and each one's index there)."""
    verbs, pts, voff, poff = arrays
    if bound is not None and len(pts) and _beyond(pts[:, 1].min(), pts[:, 1].max(), bound):
        return []
    keep, boxes = batch_extents(verbs, pts, voff, poff)
    if not keep.all():
        fills = [f for f, k in zip(fills, keep.tolist()) if k]
        if not fills:
            return []
        arrays = _kept_arrays(arrays, keep)
        boxes = boxes[keep]
        if styles is not None:
            styles = (styles[0], styles[1][keep])
    return [FillBatch(fills, *arrays, opts, pool, None, canvas, boxes, styles)]


def _run_batches(nodes, opts: RenderOptions, pool=None, shift=None, bound=None,
                 canvas=NO_CULL) -> list:
    """_fill_batches of Fills and FillRuns: the FillRuns' arrays taken as they are, joined
    with those of the Fills about them (batch_arrays) in one concatenation, each run's
    fill its style's (a Fill without a path per style, shared by its runs) and the batch's
    paints, rules and antialiasing made per style (FillBatch's ``styles``, each Fill about
    them a style of its own): the same batch as of the Fills the FillRuns stand for
    (FillRuns.fills)."""
    fills, parts, plain, protos, kinds = [], [], [], [], []

    def end_plain():
        parts.append(batch_arrays(list(map(_PATH, plain))))
        kinds.append(np.arange(len(protos), len(protos) + len(plain), dtype=np.int64))
        protos.extend(plain)
        fills.extend(plain)
        plain.clear()
    for node in nodes:
        if type(node) is FillRuns:
            if plain:
                end_plain()
            parts.append((node.verbs, node.points, node.voff, node.poff))
            own = [Fill(None, *style) for style in node.styles]
            kinds.append(node.kind + len(protos) if protos else node.kind)
            protos += own
            fills += map(own.__getitem__, node.kind.tolist())
        else:
            plain.append(node)
    if plain:
        end_plain()
    arrays = _joined_arrays(parts)
    kind = kinds[0] if len(kinds) == 1 else np.concatenate(kinds)
    if not all(map(lt, repeat(0), map(_OPACITY, protos))):
        keep = np.array([f.opacity > 0 for f in protos], np.bool_)[kind]
        fills = [f for f, k in zip(fills, keep.tolist()) if k]
        arrays = _kept_arrays(arrays, keep)
        kind = kind[keep]
    if not fills:
        return []
    if shift is not None and shift != (0, 0):
        # (the points may be a FillRuns' own: moved in a copy)
        arrays = (arrays[0], arrays[1] + np.array(shift, dtype=np.float64), *arrays[2:])
    return _drawing_batch(fills, arrays, opts, pool, bound, canvas, (protos, kind))


def _joined_arrays(parts):
    """The batch arrays (verbs, points, verb offsets, point offsets) of several, one after
    another."""
    if len(parts) == 1:
        return parts[0]
    verbs = np.concatenate([p[0] for p in parts])
    pts = np.concatenate([p[1] for p in parts])
    voff = np.zeros(1 + sum(len(p[2]) - 1 for p in parts), np.int64)
    poff = np.zeros(len(voff), np.int64)
    i = v = q = 0
    for _, _, vo, po in parts:
        n = len(vo) - 1
        voff[i + 1:i + n + 1] = vo[1:] + v
        poff[i + 1:i + n + 1] = po[1:] + q
        i, v, q = i + n, v + int(vo[-1]), q + int(po[-1])
    return verbs, pts, voff, poff


def _kept_arrays(arrays, keep):
    """The batch arrays of the paths where ``keep`` (a bool per path) holds."""
    verbs, pts, voff, poff = arrays
    return (verbs[_kept_rows(voff, keep)], pts[_kept_rows(poff, keep)],
            _kept_offsets(voff, keep), _kept_offsets(poff, keep))


def _kept_offsets(off, keep):
    out = np.zeros(int(np.count_nonzero(keep)) + 1, np.int64)
    np.cumsum(np.diff(off)[keep], out=out[1:])
    return out


def _kept_rows(off, keep):
    """The indexes of the rows of the paths kept (path i: rows off[i] .. off[i + 1] - 1)."""
    lengths = np.diff(off)[keep]
    starts = off[:-1][keep]
    # row j of the kept ones: its path's start plus its place in that path
    ends = np.cumsum(lengths)
    return np.repeat(starts - (ends - lengths), lengths) + np.arange(int(ends[-1]) if len(ends)
                                                                     else 0)


_OPACITY = attrgetter("opacity")
_PATH = attrgetter("path")
_ANTIALIAS = attrgetter("antialias")
_RULE = attrgetter("rule")

#: batches of at most this many fills and points take _fill_batches' shortcut
SMALL_BATCH = 8
SMALL_POINTS = 64


def _extremes(pts, poff):
    """[(x0, y0, x1, y1)] of each path's points, Python floats, or None if one of them is
    not finite. A long path by two numpy reductions (NaN propagates through them), a few short
    ones in Python (at most SMALL_POINTS points: the reductions cost more)."""
    if len(pts) > SMALL_POINTS:
        (x0, y0), (x1, y1) = pts.min(axis=0).tolist(), pts.max(axis=0).tolist()
        out = [(x0, y0, x1, y1)]
        return out if all(map(math.isfinite, out[0])) else None
    flat = pts.ravel().tolist()
    if not all(map(math.isfinite, flat)):
        return None
    out, po = [], poff.tolist()
    for a, b in zip(po, po[1:]):
        xs, ys = flat[2 * a:2 * b:2], flat[2 * a + 1:2 * b:2]
        out.append((min(xs), min(ys), max(xs), max(ys)))
    return out


def _beyond(lo: float, hi: float, bound) -> bool:
    """Whether points with y in lo..hi make a batch that draw_items never draws in the rows
    of ``bound``: its box (the points grown by QUAD_FALLBACK_TOL, and under a pixel more
    where aliased fills are moved onto sample centres) misses the device rows
    floor(bound[0]) .. floor(bound[1]) a layer of those rows is drawn in, with a pixel to
    spare. (NaN compares false: kept.)"""
    margin = QUAD_FALLBACK_TOL + 2.0
    return hi + margin < bound[0] or lo - margin > bound[1]


def _shifted_arrays(fills, shift):
    """batch_arrays of the fills' paths, moved by ``shift`` (dx, dy) unless None: the points
    nodes.translated gives (Path.transformed by (1, 0, 0, 1, dx, dy): 1·x + 0·y + dx is x + dx,
    zeros' signs included, and no move at all for (0, 0))."""
    arrays = batch_arrays(list(map(_PATH, fills)))
    if shift is not None and shift != (0, 0):
        # (batch_arrays' points are its own: one path's a copy, several a concatenation)
        arrays[1][...] += np.array(shift, dtype=np.float64)
    return arrays


def draw_items(items, target: np.ndarray, y0: int, raster: Raster) -> None:
    """Draw items onto ``target``, the device rows y0 .. y0 + len(target) - 1. An item outside
    those rows is skipped: a fill there draws nothing, and a transparent layer composites to
    exactly the target it is composited on."""
    y1 = y0 + target.shape[0]
    for item in items:
        if item.rows is None or item.rows[1] < y0 or item.rows[0] >= y1:
            continue
        raster.drawn += 1
        if isinstance(item, FillBatch):
            raster.fill(item, target, y0)
        elif isinstance(item, LayerRun):
            draw_run(item, target, y0, raster)
        else:
            draw_layer(item, target, y0, raster)


def draw_layer(layer: Layer, target: np.ndarray, y0: int, raster: Raster) -> None:
    """Composite the layer onto ``target`` (device rows from y0). Only the box where the layer
    can be non-transparent is drawn and composited — the rows of its content (``rows``) and,
    for a filtered layer, the box its filtered pixels cover: outside it the layer is
    transparent, which composites (in every blend mode) to the target unchanged."""
    h, w = target.shape[:2]
    if layer.filters:
        part = filtered_part(layer, y0, h, w, raster)
        if part is None:
            return
        (a, b, c, d), img = part
    else:
        a, b = band_rows(layer.rows, y0, h)
        if a >= b:
            return
        if layer.sole is not None:
            # its filtered layer's pixels, as drawing it onto a buffer of rows a..b - 1 takes
            # them (filtered_part, which lets them go after the last band, is called alike)
            part = filtered_part(layer.sole, y0 + a, b - a, w, raster)
            if part is None:
                return
            (pa, pb, c, d), img = part
            a, b = a + pa, a + pb
        else:
            c, d = layer_columns(layer, w)
            if c >= d:
                return
            img = raster.draw_into(layer.items, raster.layer_buffer(b - a, c, d), y0 + a, c, d)
    factor = None
    for part in _clip_and_mask(layer, b - a, c, d, y0 + a, raster):
        factor = part if factor is None else factor * part
    if layer.blend == "normal":
        over_scaled(img, target, a, c, NO_FACTOR if factor is None else factor,
                    factor is not None, layer.opacity)
        return
    if factor is not None:
        img *= factor[..., None]
    if layer.opacity < 1.0:
        img *= np.float32(layer.opacity)
    composite(img, target[a:b, c:d], layer.blend)


#: over_scaled's factor when a layer has neither clip nor mask (one signature for both cases)
NO_FACTOR = np.ones((1, 1), dtype=np.float32)


def filtered_part(layer: Layer, y0: int, h: int, w: int, raster: Raster):
    """((a, b, c, d), pixels): a copy of the layer's filtered pixels in rows a..b - 1 and
    columns c..d - 1 of the band of ``h`` x ``w`` pixels from device row y0, or None where
    they miss it. The band holding the filtered box's last row lets go of it, so a document
    of many filtered elements holds one filtered buffer at a time, not all of them; with
    bands on threads, once the bands above it are drawn too (BandsDrawn)."""
    with layer.filtering:
        key = id(raster.opts)
        if key not in layer.filtered:
            layer.filtered[key] = render_filtered(layer, raster)
        (x0, fy0, x1, fy1), pixels = layer.filtered[key]
        if pixels is not None and y0 + h >= fy1:
            bands = raster.bands
            if bands is APRON_BANDS:
                del layer.filtered[key]     # the next band draws these rows again
            elif bands is None or bands.let_go(layer, key, fy0, raster.band_start):
                _let_go(layer, key)
    a, b = max(y0, fy0), min(y0 + h, fy1)
    c, d = max(x0, 0), min(x1, w)
    if pixels is None or a >= b or c >= d:
        return None
    part = pixels[a - fy0:b - fy0, c - x0:d - x0]
    if layer.blend == "normal" and part.flags.c_contiguous:
        return (a - y0, b - y0, c, d), part        # draw_layer only reads it then
    return (a - y0, b - y0, c, d), part.copy()


def _let_go(layer: Layer, key) -> None:
    """Drop the layer's filtered pixels (``layer.filtering`` held), keeping their box: the
    bands below it that its filter region reaches still ask for them (the region is cut to
    the content's reach when filtered), and without the box they filtered it again, each
    (a blurred square in a region twice its size, 200 bands: 24 times)."""
    box, _ = layer.filtered[key]
    layer.filtered[key] = box, None


_filter_effects = None


def _effects():
    """The filter_effects module, imported on first use: the effects and their scene classes
    cost start-up that a render without filters does not need."""
    global _filter_effects
    if _filter_effects is None:
        from . import filter_effects
        _filter_effects = filter_effects
    return _filter_effects


def render_filtered(layer: Layer, raster: Raster):
    """(rect, pixels): the layer's content rendered in the union of its filter regions and put
    through its filters in order, each taking the previous one's result. Like resvg, content
    up to two image sizes beyond the image's edges takes part (a blur pulls it in); a region
    too large for MAX_FILTER_PIXELS is cut to the image, and not drawn if still too large."""
    fe = _filter_effects or _effects()

    W, H = raster.width, raster.height
    box = filter_box(layer)
    # where the filters keep transparent pixels transparent, only the content's box grown by
    # their reach can come out non-transparent: compute there, not in the whole region (an
    # element with a full-canvas drop shadow costs its own size, not the canvas's)
    reaches = [fe.transparent_reach(f) for f in layer.filters]
    if None not in reaches:
        content = content_box(layer.group)
        if content is None:
            return (0, 0, 0, 0), None
        if all(math.isfinite(v) for v in content):
            grow = sum(reaches)
            box = (max(box[0], math.floor(content[0]) - 1 - grow),
                   max(box[1], math.floor(content[1]) - 1 - grow),
                   min(box[2], math.ceil(content[2]) + 1 + grow),
                   min(box[3], math.ceil(content[3]) + 1 + grow))
    for limit in ((-2 * W, -2 * H, 3 * W, 3 * H), (0, 0, W, H)):
        x0, y0 = max(box[0], limit[0]), max(box[1], limit[1])
        x1, y1 = min(box[2], limit[2]), min(box[3], limit[3])
        if x1 <= x0 or y1 <= y0:
            return (0, 0, 0, 0), None
        if (x1 - x0) * (y1 - y0) <= MAX_FILTER_PIXELS:
            break
    else:
        return (0, 0, 0, 0), None
    w, h = x1 - x0, y1 - y0
    # the content's own move to device pixels (Group.shift), then to the region's corner
    dx, dy = layer.group.shift[0] - x0, layer.group.shift[1] - y0
    if _flat_solid(layer.group) and not any(_placed(f) for f in layer.filters):
        # plain fills of flat colour under filters that place nothing by device position:
        # their points moved as they are batched, the filters read at the region's offset
        # (integer pixels: the same rectangles), not copied (a small filtered marker spent
        # a tenth of its time moving its fill and filter)
        fills, filters = layer.group.children, [(f, x0, y0) for f in layer.filters]
    else:
        fills = None
        filters = [(f, 0, 0) for f in translated_filters(layer.filters, -x0, -y0)]
        moved = [translated(c, dx, dy) for c in layer.group.children]

    def draw(group, top, rows):
        if group is None:
            items = _fill_batches(fills, raster.opts, None, (dx, dy), None,
                                  np.array((0.0, 0.0, w, h)))
        else:
            items = prepare_items(group, raster.opts, canvas=(0, 0, w, h))
        # the first filtered group inside is filtered before this buffer and the rasteriser's
        # strip buffers exist (filtered_part then finds it done): groups with filters nested N
        # deep held N of each at once, now about two
        inner = next((item for item in items if isinstance(item, Layer) and item.filters), None)
        if inner is not None:
            with inner.filtering:
                if id(raster.opts) not in inner.filtered:
                    inner.filtered[id(raster.opts)] = render_filtered(
                        inner, SimpleNamespace(opts=raster.opts, width=w, height=h,
                                               local=raster.local))
        img = np.zeros((rows, w, 4), dtype=np.float32)
        local = raster.local(w, h)
        # in bands when nested layers would hold more than LAYERS_BUDGET at the region's size
        # (the same pixels: a band's do not depend on where it begins)
        step = layer_rows(w, layer_depth(items))
        for r in range(0, rows, step):
            draw_items(items, img[r:r + step], top + r, local)
        return img
    if any(i < 0 for prim in filters[0][0].primitives for i in prim.inputs):
        pixels = draw(None if fills is not None else Group(children=moved), 0, h)
    else:
        # nothing reads the content (a turbulence or a flood alone): not drawn, no buffer
        pixels = np.broadcast_to(np.float32(0), (h, w, 4))
    for f, ox, oy in filters:
        rx0, ry0, rx1, ry1 = f.region
        fx0, fy0 = max(rx0 - ox, 0), max(ry0 - oy, 0)
        fx1, fy1 = min(rx1 - ox, w), min(ry1 - oy, h)
        if fx1 <= fx0 or fy1 <= fy0:
            pixels = np.zeros_like(pixels)
            continue
        part = pixels[fy0:fy1, fx0:fx1]
        if part.flags.writeable:
            part = np.ascontiguousarray(part)

        def draw_content(group, fx0=fx0, fy0=fy0, fx1=fx1, fy1=fy1):
            return draw(group, fy0, fy1 - fy0)[:, fx0:fx1]
        # the content is not read again: the filter may write into it (a blur in place)
        done = fe.apply_filter(part, f, (fx0 + ox, fy0 + oy), draw_content,
                               own_source=part.flags.writeable)
        part = None
        if (fx0, fy0, fx1, fy1) == (0, 0, w, h):
            pixels = done           # the region is the whole buffer: nothing to copy
        else:
            pixels = np.zeros_like(pixels)
            pixels[fy0:fy1, fx0:fx1] = done
        done = None
    # only the part inside the image is ever copied out: keep that (a blur's region reaches
    # far beyond the image)
    cx0, cy0, cx1, cy1 = max(x0, 0), max(y0, 0), min(x1, W), min(y1, H)
    if cx1 <= cx0 or cy1 <= cy0:
        return (0, 0, 0, 0), None
    if (cx0, cy0, cx1, cy1) != (x0, y0, x1, y1):
        held, pixels = [pixels], None       # _cropped holds the only reference
        pixels = _cropped(held, cy0 - y0, cy1 - y0, cx0 - x0, cx1 - x0)
    return (cx0, cy0, cx1, cy1), pixels


def _flat_solid(group: Group) -> bool:
    """Whether a group's children are all fills of a flat colour (no groups)."""
    return all(type(c) is Fill and type(c.paint) is Solid for c in group.children)


def _placed(flt) -> bool:
    """Whether a filter has a primitive drawing by device position (feImage's content,
    turbulence, a light): moving its content means moving it too (render_filtered)."""
    fe = _filter_effects or _effects()
    return any(isinstance(p.effect, (fe.Image, fe.Turbulence, fe.Lighting))
               for p in flt.primitives)


def _sole_reference_count() -> int:
    """What sys.getrefcount says of an array one local name holds, as ``base`` in _cropped:
    2 up to Python 3.13 (the name and the call's argument); interpreters that count the
    argument otherwise give their own figure, so the test below never takes a shared buffer
    for a sole one."""
    probe = np.empty(1)
    return sys.getrefcount(probe)


_SOLE_REFERENCE = _sole_reference_count()


def _cropped(held: list, a: int, b: int, c: int, d: int) -> np.ndarray:
    """pixels[a:b, c:d] on its own (``held``: [pixels], emptied): moved to the front of the
    buffer it is in, which is then shrunk to it (realloc), so the crop never holds a second
    buffer (a copy held the region and the image at once); a copy where anything else
    refers to that buffer."""
    pixels = held.pop()
    base = pixels if pixels.base is None else pixels.base
    shape = pixels.shape
    if not (pixels.flags.c_contiguous and base.flags.c_contiguous and base.flags.owndata
            and base.ctypes.data == pixels.ctypes.data and base.nbytes == pixels.nbytes):
        return pixels[a:b, c:d].copy()
    pixels = None
    if sys.getrefcount(base) > _SOLE_REFERENCE:
        return base.reshape(shape)[a:b, c:d].copy()
    h, row = b - a, (d - c) * 4
    flat = base.reshape(-1)
    src = flat.reshape(shape)
    for r in range(h):               # each row moves toward the front: never over one unread
        flat[r * row:(r + 1) * row] = src[a + r, c:d].reshape(-1)
    flat = src = None
    try:
        base.resize((h, d - c, 4))   # refused (ValueError) while anything else refers to it
    except ValueError:
        return base.reshape(-1)[:h * row].reshape(h, d - c, 4)
    return base


def content_box(group: Group):
    """(x0, y0, x1, y1) device coordinates outside which nothing of ``group``'s children draws
    (their fills' points, control points included), or None if they hold nothing. A nested
    filtered group counts as its filter regions where a filter can draw on transparent
    input; where its filters keep transparent pixels transparent, as its own content's box
    grown by their reach (and a pixel of slack) inside those regions, and as nothing when
    that content is empty (a chain of filtered groups around nothing draws nothing: 37,000
    of them nested 600 deep took 78 s and 9 GB to filter each empty group)."""
    box = None
    points = {}     # (grow, clip, shift): the fills' points seen through those filters
    stack = [(node, 0, None, group.shift) for node in group.children]
    while stack:
        node, grow, clip, shift = stack.pop()
        if isinstance(node, Fill):
            p = node.path.points
            if len(p):
                points.setdefault((grow, clip, shift), []).append(p)
        elif isinstance(node, FillRuns):
            if len(node.points):
                points.setdefault((grow, clip, shift), []).append(node.points)
        elif node.filters:
            region = _grown(_filter_regions(node.filters), grow, clip, shift)
            if region is None:
                continue
            reaches = [(_filter_effects or _effects()).transparent_reach(f)
                       for f in node.filters]
            if None in reaches:
                box = bounds.union(box, region)
            else:
                inner = grow + sum(reaches) + len(reaches)
                moved = (shift[0] + node.shift[0], shift[1] + node.shift[1])
                stack.extend((child, inner, region, moved) for child in node.children)
        else:
            stack.extend((child, grow, clip, shift) for child in node.children)
    for (grow, clip, shift), parts in points.items():
        # one reduction over all the points of a context: a group of 20,000 small paths
        # took 0.2 s of per-path min/max calls
        p = np.concatenate(parts) if len(parts) > 1 else parts[0]
        x0, y0 = p.min(axis=0).tolist()
        x1, y1 = p.max(axis=0).tolist()
        box = bounds.union(box, _grown((x0, y0, x1, y1), grow, clip, shift))
    return box


def _grown(box, grow, clip, shift):
    """``box`` moved by ``shift``, grown by ``grow`` pixels on every side and cut to ``clip``
    (None: uncut); None when nothing is left."""
    x0, y0 = box[0] + shift[0] - grow, box[1] + shift[1] - grow
    x1, y1 = box[2] + shift[0] + grow, box[3] + shift[1] + grow
    if clip is not None:
        x0, y0 = max(x0, clip[0]), max(y0, clip[1])
        x1, y1 = min(x1, clip[2]), min(y1, clip[3])
        if not (x0 < x1 and y0 < y1):
            return None
    return x0, y0, x1, y1


def layer_columns(layer: Layer, w: int) -> tuple[int, int]:
    """Columns c..d - 1 of a layer without filters outside which its content draws nothing
    (0..w when unknown): its fills' boxes (a kernel writes at most a pixel beyond one) and
    its nested layers' columns (a filtered one's filter box)."""
    cols = getattr(layer, "columns", None)
    if cols is None:
        lo, hi = math.inf, -math.inf
        for item in layer.items:
            if isinstance(item, FillBatch):
                lo, hi = min(lo, item.cols[0]), max(hi, item.cols[1])
            elif item.filters:
                x0, _, x1, _ = filter_box(item)
                lo, hi = min(lo, x0), max(hi, x1)
            else:
                c, d = layer_columns(item, w)
                if c < d:
                    lo, hi = min(lo, c), max(hi, d)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            cols = (0, w) if lo <= hi else (0, 0)
        else:
            cols = drawn_columns(lo, hi, w)
        layer.columns = cols
    return cols


def drawn_columns(lo: float, hi: float, w: int) -> tuple[int, int]:
    """Columns c..d - 1 (within 0..w) that fills whose boxes span columns lo..hi can draw in:
    a kernel writes at most a pixel beyond a box (layer_columns, draw_run)."""
    return max(0, min(w, math.floor(lo) - 2)), max(0, min(w, math.floor(hi) + 3))


def band_rows(rows, y0: int, h: int) -> tuple[int, int]:
    """Rows a..b - 1 of a band of ``h`` rows from device row y0 that content spanning device
    rows rows[0]..rows[1] can hold: floor(rows[0]) .. floor(rows[1]) (draw_items' test)."""
    return max(0, math.floor(rows[0]) - y0), min(h, math.floor(rows[1]) - y0 + 1)


def _clip_and_mask(layer: Layer, rows: int, c: int, d: int, y0: int, raster: Raster):
    """The clip coverage, then the mask values, that multiply a layer (as they exist), in
    its columns c..d - 1."""
    if layer.clip is not None:
        yield render_coverage(layer.clip, "clip", rows, c, d, y0, raster)
    if layer.mask is not None:
        yield render_coverage(layer.mask, layer.mask_kind, rows, c, d, y0, raster)


def render_coverage(layer: Layer, kind: str, rows: int, c: int, d: int, y0: int,
                    raster: Raster) -> np.ndarray:
    """A clip's coverage (``clip``: the alpha of its content drawn opaque) or a mask's values
    (``alpha`` or ``luminance``), each times the layer's own clip and mask, in columns
    c..d - 1 of the rows from device row y0."""
    img = raster.draw_into(layer.items, raster.layer_buffer(rows, c, d), y0, c, d, copy=False)
    # (the coverage is a new array, made before the layer's own clip and mask draw in the
    # buffer)
    if kind == "luminance":
        # luminance of the premultiplied colour = luminance × alpha (sRGB coefficients)
        cov = img[..., 0] * 0.2125 + img[..., 1] * 0.7154 + img[..., 2] * 0.0721
    else:
        cov = img[..., 3].copy()
    for factor in _clip_and_mask(layer, rows, c, d, y0, raster):
        cov *= factor
    return cov if kind == "clip" else np.clip(cov, 0.0, 1.0)


def composite(src: np.ndarray, dst: np.ndarray, blend: str = "normal") -> None:
    """src over dst in place (premultiplied), with a CSS blend mode."""
    sa = src[..., 3:4]
    if blend == "normal":
        dst *= (1.0 - sa)
        dst += src
        return
    dst[:] = blend_premultiplied(src, dst, blend)


