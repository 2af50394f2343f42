"""Benchmark: run time against error for every coverage mode, sample count and sample pattern.

A corpus of scenes (built-in synthetic ones plus any SVG files) is rendered

- at the *timing size* (``size``, the longer side in pixels): wall time per render, the median
  of ``repeat`` runs after one warm-up run (so JIT compilation is not in it);
- at the *error size* (small, so the ``reference`` mode — 256 stratified samples per pixel,
  composited per sample — is affordable): mean absolute error over all pixels, mean error over
  edge pixels (:func:`vecmsaa.tools.accuracy.edge_mask`) and the largest error, all in premultiplied
  RGBA in [0, 1] against that reference.

JIT compilation is measured apart, in fresh subprocesses: once with an empty numba cache (cold
compile) and once with the cache filled (what every later process pays to load it). resvg and
CairoSVG, when installed, are timed on the SVG inputs as whole processes / calls and compared
against the same reference. Special rows show that work the scene does not need is skipped
(a full-canvas rectangle against numpy filling the same buffer, scenes without curves, without
overlaps) and what memory a large output takes.

Results: ``results.csv`` and ``results.json`` (every row), ``table.md`` (summaries) and
``pareto.png`` (time against edge error per mode, drawn with Pillow) in the output folder.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from ..raster.modes import MSAA_MODES, PATTERN_NAMES

SAMPLE_COUNTS = (1, 2, 4, 8, 16)
QUICK_SAMPLES = (1, 4, 16)
#: longer side of the images the errors are measured on (the reference costs 256 spp)
ERROR_SIZE = 128
QUICK_ERROR_SIZE = 48
MODE_COLOURS = {"none": (120, 120, 120), "alpha": (214, 39, 40), "a2c": (255, 127, 14),
                "persample": (31, 119, 180), "approx": (44, 160, 44),
                "analytic": (148, 103, 189), "resvg": (23, 190, 207),
                "cairosvg": (140, 86, 75)}


# -- synthetic scenes ---------------------------------------------------------------------------
def _rgba(rng, alpha_range=(0.5, 1.0)):
    return tuple(float(c) for c in rng.uniform(0.05, 0.95, 3)) + (
        float(rng.uniform(*alpha_range)),)


def blobs_scene(size, count=200, seed=7):
    """Curve-heavy: many overlapping random cubic blobs, some translucent, some even-odd."""
    from .accuracy import _blob
    from ..scene.nodes import Fill, Group, Scene, Solid

    rng = np.random.default_rng(seed)
    fills = []
    for _ in range(count):
        path = _blob(rng, rng.uniform(0, size), rng.uniform(0, size),
                     rng.uniform(0.03, 0.15) * size, lobes=int(rng.integers(5, 12)))
        fills.append(Fill(path, Solid(_rgba(rng)),
                          rule="evenodd" if rng.random() < 0.2 else "nonzero"))
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def full_rect_scene(size):
    """One opaque rectangle covering the whole canvas: no edge inside, no curve."""
    from ..scene.path import rect_path
    from ..scene.nodes import Fill, Group, Scene, Solid

    return Scene(size, size, Group([Fill(rect_path(0, 0, size, size),
                                         Solid((0.2, 0.4, 0.8, 1.0)))]))


def _segment_polygon(x0, y0, x1, y1, width):
    from ..scene.path import Path

    dx, dy = x1 - x0, y1 - y0
    ln = math.hypot(dx, dy) or 1.0
    nx, ny = -dy / ln * width / 2, dx / ln * width / 2
    path = Path()
    path.moveTo((x0 + nx, y0 + ny))
    path.lineTo((x1 + nx, y1 + ny))
    path.lineTo((x1 - nx, y1 - ny))
    path.lineTo((x0 - nx, y0 - ny))
    path.closePath()
    return path


def thin_lines_scene(size, count=600, seed=3):
    """Many thin straight strokes (already outlined, 0.3 to 2 px wide) in random directions:
    map-like, every pixel of them is an edge pixel."""
    from ..scene.nodes import Fill, Group, Scene, Solid

    rng = np.random.default_rng(seed)
    fills = []
    for _ in range(count):
        x0, y0 = rng.uniform(0, size, 2)
        ang = rng.uniform(0, 2 * math.pi)
        ln = rng.uniform(0.05, 0.5) * size
        fills.append(Fill(_segment_polygon(x0, y0, x0 + ln * math.cos(ang),
                                           y0 + ln * math.sin(ang),
                                           rng.uniform(0.3, 2.0) * size / 512),
                          Solid(_rgba(rng, (1.0, 1.0)))))
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def _glyph_o(path, cx, cy, r):
    """A ring of two quadratic circles, even-odd: an 'o'."""
    for rad, sign in ((r, 1), (0.6 * r, -1)):
        pts = []
        for i in range(8):
            a = sign * i * math.pi / 4
            pts.append((cx + rad * math.cos(a), cy + rad * math.sin(a)))
        ctrl = [(cx + rad / math.cos(math.pi / 8) * math.cos(sign * (i + 0.5) * math.pi / 4),
                 cy + rad / math.cos(math.pi / 8) * math.sin(sign * (i + 0.5) * math.pi / 4))
                for i in range(8)]
        path.moveTo(pts[0])
        for i in range(8):
            path.qCurveTo(ctrl[i], pts[(i + 1) % 8])
        path.closePath()


def _glyph_s(path, x, y, h):
    """An 's'-like closed stroke of cubics."""
    w = 0.6 * h
    path.moveTo((x + w, y + 0.15 * h))
    path.curveTo((x + 0.6 * w, y - 0.05 * h), (x - 0.1 * w, y + 0.1 * h), (x + 0.1 * w, y + 0.35 * h))
    path.curveTo((x + 0.3 * w, y + 0.55 * h), (x + 1.05 * w, y + 0.5 * h), (x + 0.9 * w, y + 0.8 * h))
    path.curveTo((x + 0.75 * w, y + 1.05 * h), (x + 0.2 * w, y + 1.0 * h), (x, y + 0.85 * h))
    path.lineTo((x + 0.05 * w, y + 0.75 * h))
    path.curveTo((x + 0.25 * w, y + 0.9 * h), (x + 0.7 * w, y + 0.92 * h), (x + 0.75 * w, y + 0.75 * h))
    path.curveTo((x + 0.8 * w, y + 0.6 * h), (x + 0.1 * w, y + 0.6 * h), (x - 0.02 * w, y + 0.35 * h))
    path.curveTo((x - 0.1 * w, y + 0.05 * h), (x + 0.6 * w, y - 0.1 * h), (x + 0.95 * w, y + 0.07 * h))
    path.closePath()


def text_scene(size, em=None):
    """Text-like: lines of small glyph-shaped outlines (quadratic 'o's, cubic 's's), one fill
    per line of text as a font front end makes them."""
    from ..scene.path import Path
    from ..scene.nodes import Fill, Group, Scene, Solid

    em = em or max(6.0, size / 40)
    fills = []
    y = em
    line = 0
    while y + em < size:
        path = Path()
        x = em * 0.5
        i = line
        while x + em < size:
            if i % 3 == 2:
                x += 0.4 * em          # a space
            elif i % 2:
                _glyph_o(path, x + 0.3 * em, y + 0.5 * em, 0.28 * em)
            else:
                _glyph_s(path, x + 0.03 * em, y + 0.15 * em, 0.7 * em)
            x += 0.62 * em
            i += 1
        fills.append(Fill(path, Solid((0.05, 0.05, 0.1, 1.0))))
        y += 1.3 * em
        line += 1
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def tiles_scene(size, cells=16):
    """Non-overlapping axis-aligned rectangles: no curves, no overlaps (the cheap path)."""
    from ..scene.path import rect_path
    from ..scene.nodes import Fill, Group, Scene, Solid

    rng = np.random.default_rng(11)
    step = size / cells
    fills = [Fill(rect_path(i * step + 0.3 * step, j * step + 0.27 * step, 0.55 * step,
                            0.51 * step), Solid(_rgba(rng, (1.0, 1.0))))
             for j in range(cells) for i in range(cells)]
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def figure1(size):
    from .accuracy import figure1_scene
    return figure1_scene(size)


SYNTHETIC = {"blobs": blobs_scene, "full-rect": full_rect_scene, "thin-lines": thin_lines_scene,
             "text": text_scene, "tiles": tiles_scene, "figure1": figure1}


class Case:
    """One scene of the corpus: ``make(size)`` gives the Scene with longer side ``size``."""

    def __init__(self, name, make, svg_path=None):
        self.name = name
        self.make = make
        self.svg_path = svg_path


def svg_case(path):
    from ..api import load_svg

    landscape = []

    def make(size):
        if not landscape:
            probe = load_svg(path)
            landscape.append(probe.width >= probe.height)
        if landscape[0]:
            return load_svg(path, width=size)
        return load_svg(path, height=size)
    name = os.path.splitext(os.path.basename(path))[0]
    return Case(name, make, path)


def corpus(paths=(), synthetic=True):
    cases = [Case(n, f) for n, f in SYNTHETIC.items()] if synthetic else []
    for p in paths:
        if os.path.isdir(p):
            for name in sorted(os.listdir(p)):
                if name.lower().endswith((".svg", ".svgz")):
                    cases.append(svg_case(os.path.join(p, name)))
        else:
            cases.append(svg_case(p))
    return cases


# -- measurements -----------------------------------------------------------------------------
def timed(fn, repeat):
    """Median wall time of ``repeat`` calls after one warm-up call; returns (median, result)."""
    result = fn()
    times = []
    for _ in range(max(1, repeat)):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), result


def errors(img, truth, mask):
    diff = np.abs(img.astype(np.float64) - truth)
    edge = float(diff[mask].mean()) if mask.any() else 0.0
    return float(diff.mean()), edge, float(diff.max())


def configs(quick):
    samples = QUICK_SAMPLES if quick else SAMPLE_COUNTS
    out = [("none", 1, "d3d")]
    for mode in MSAA_MODES[1:]:
        # the Direct3D patterns and the ordered grid; every pattern: vecmsaa bench --patterns
        for pattern in PATTERN_NAMES[:2]:
            for n in samples:
                out.append((mode, n, pattern))
    out.append(("analytic", 1, "-"))
    return out


def bench_case(case, size, error_size, repeat, quick, log=print):
    from .accuracy import edge_mask
    from ..raster.render import render_scene

    rows = []
    scene = case.make(size)
    small = case.make(error_size)
    t_ref = time.perf_counter()
    truth = render_scene(small, mode="reference").astype(np.float64)
    t_ref = time.perf_counter() - t_ref
    mask = edge_mask(truth)
    for mode, n, pattern in configs(quick):
        pat = "d3d" if pattern == "-" else pattern
        t, _ = timed(lambda: render_scene(scene, mode=mode, samples=n, pattern=pat), repeat)
        img = render_scene(small, mode=mode, samples=n, pattern=pat)
        mean_e, edge_e, max_e = errors(img, truth, mask)
        rows.append(dict(scene=case.name, renderer="vecmsaa", mode=mode, samples=n,
                         pattern=pattern, width=scene.width, height=scene.height,
                         time_s=t, mean_error=mean_e, edge_error=edge_e, max_error=max_e,
                         error_width=small.width, error_height=small.height))
    rows.append(dict(scene=case.name, renderer="vecmsaa", mode="reference", samples=256,
                     pattern="stratified", width=small.width, height=small.height,
                     time_s=t_ref, mean_error=0.0, edge_error=0.0, max_error=0.0,
                     error_width=small.width, error_height=small.height))
    if case.svg_path:
        rows += external_rows(case, scene, small, truth, mask, repeat, log)
    return rows


# -- other renderers --------------------------------------------------------------------------
def resvg_binary():
    return shutil.which("resvg")


def cairosvg_available():
    import importlib.util
    try:
        return importlib.util.find_spec("cairosvg") is not None
    except (ImportError, ValueError):
        return False


def _read_png_premultiplied(path, w, h):
    from PIL import Image

    with Image.open(path) as im:
        im = im.convert("RGBA")
        if im.size != (w, h):
            im = im.resize((w, h), Image.BILINEAR)
        a = np.asarray(im, dtype=np.float64) / 255.0
    a[..., :3] *= a[..., 3:4]
    return a


def _run(cmd, repeat):
    def once():
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t, _ = timed(once, repeat)
    return t


def external_rows(case, scene, small, truth, mask, repeat, log):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "o.png")
        size_args = ["-w", str(scene.width)] if scene.width >= scene.height else [
            "-h", str(scene.height)]
        small_args = ["-w", str(small.width)] if small.width >= small.height else [
            "-h", str(small.height)]
        # the whole vecmsaa process, as a user runs it (default mode, warm JIT caches)
        try:
            t = _run([sys.executable, "-m", "vecmsaa.cli", "render", case.svg_path, "-o", out]
                     + size_args, repeat)
            rows.append(dict(scene=case.name, renderer="vecmsaa-process", mode="approx",
                             samples=8, pattern="d3d", width=scene.width,
                             height=scene.height, time_s=t))
        except (subprocess.CalledProcessError, OSError) as exc:
            log(f"  vecmsaa process failed on {case.name}: {exc}")
        resvg = resvg_binary()
        if resvg:
            try:
                t = _run([resvg] + size_args + [case.svg_path, out], repeat)
                subprocess.run([resvg] + small_args + [case.svg_path, out], check=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                img = _read_png_premultiplied(out, small.width, small.height)
                mean_e, edge_e, max_e = errors(img, truth, mask)
                rows.append(dict(scene=case.name, renderer="resvg", mode="resvg", samples=0,
                                 pattern="-", width=scene.width, height=scene.height,
                                 time_s=t, mean_error=mean_e, edge_error=edge_e,
                                 max_error=max_e, error_width=small.width,
                                 error_height=small.height))
            except (subprocess.CalledProcessError, OSError) as exc:
                log(f"  resvg failed on {case.name}: {exc}")
        if cairosvg_available():
            try:
                import cairosvg

                def render_cairo(w, h):
                    cairosvg.svg2png(url=case.svg_path, write_to=out, output_width=w,
                                     output_height=h)
                t, _ = timed(lambda: render_cairo(scene.width, scene.height), repeat)
                render_cairo(small.width, small.height)
                img = _read_png_premultiplied(out, small.width, small.height)
                mean_e, edge_e, max_e = errors(img, truth, mask)
                rows.append(dict(scene=case.name, renderer="cairosvg", mode="cairosvg",
                                 samples=0, pattern="-", width=scene.width,
                                 height=scene.height, time_s=t, mean_error=mean_e,
                                 edge_error=edge_e, max_error=max_e,
                                 error_width=small.width, error_height=small.height))
            except Exception as exc:   # an optional peer must never break the bench
                log(f"  cairosvg failed on {case.name}: {type(exc).__name__}: {exc}")
    return rows


# -- start-up, JIT, special rows, memory ------------------------------------------------------
_JIT_SNIPPET = r"""
import time, json
t0 = time.perf_counter()
from vecmsaa.raster.render import render_scene
from vecmsaa.tools.accuracy import figure1_scene
t1 = time.perf_counter()
scene = figure1_scene(32)
out = {"import_s": t1 - t0}
for mode in %r:
    t = time.perf_counter()
    render_scene(scene, mode=mode, samples=8)
    out[mode] = time.perf_counter() - t
print(json.dumps(out))
"""


def jit_times(cold, modes=("approx", "analytic", "reference")):
    """First-call time per mode in a fresh process: with empty caches (``cold``: the first run,
    which builds the compiled kernels, or compiles with numba's JIT under VECMSAA_JIT=1) or
    with the project's normal ones (loading compiled code)."""
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        if cold:
            env["NUMBA_CACHE_DIR"] = tmp
        t = time.perf_counter()
        res = subprocess.run([sys.executable, "-c", _JIT_SNIPPET % (tuple(modes),)],
                             capture_output=True, text=True, env=env)
        total = time.perf_counter() - t
    if res.returncode:
        return {"error": res.stderr.strip().splitlines()[-1:]}
    out = json.loads(res.stdout.strip().splitlines()[-1])
    out["process_s"] = total
    return out


_STARTUP_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64">'
                '<circle cx="32" cy="32" r="20" fill="teal"/></svg>')


def startup_time(repeat):
    """Whole process for a tiny SVG with warm JIT caches: python -m vecmsaa.cli render."""
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "small.svg")
        with open(src, "w") as f:
            f.write(_STARTUP_SVG)
        return _run([sys.executable, "-m", "vecmsaa.cli", "render", src, "-o",
                     os.path.join(tmp, "small.png")], repeat)


def special_rows(size, repeat, quick):
    """Skip-what-is-not-needed rows: each scene against the cheapest thing it could cost."""
    from ..raster.render import render_scene

    rows = []
    big = size if quick else 4096
    # full-canvas rectangle against numpy filling the same float32 RGBA buffer
    scene = full_rect_scene(big)
    t_fill, _ = timed(lambda: np.full((big, big, 4), 0.5, dtype=np.float32), repeat)
    for mode, n in (("approx", 8), ("approx", 16), ("persample", 16)):
        t, _ = timed(lambda: render_scene(scene, mode=mode, samples=n), repeat)
        rows.append(dict(row="full-canvas rectangle", size=big, mode=mode, samples=n,
                         time_s=t, baseline="numpy fill of the RGBA float32 buffer",
                         baseline_s=t_fill, ratio=t / t_fill))
    # curve-heavy: approx against alpha at 16 samples, and growth with the sample count
    scene = blobs_scene(big)
    times = {}
    for mode in ("alpha", "approx", "persample"):
        for n in ((1, 16) if quick else (1, 4, 16)):
            times[mode, n], _ = timed(lambda: render_scene(scene, mode=mode, samples=n), repeat)
    rows.append(dict(row="curve-heavy approx / alpha at 16 samples", size=big, mode="approx",
                     samples=16, time_s=times["approx", 16], baseline="alpha, 16 samples",
                     baseline_s=times["alpha", 16],
                     ratio=times["approx", 16] / times["alpha", 16]))
    for mode in ("alpha", "approx", "persample"):
        rows.append(dict(row=f"curve-heavy {mode}: 16 samples / 1 sample", size=big, mode=mode,
                         samples=16, time_s=times[mode, 16],
                         baseline=f"{mode}, 1 sample", baseline_s=times[mode, 1],
                         ratio=times[mode, 16] / times[mode, 1]))
    # no curves / no overlaps: against the curve-heavy scene's cost per pixel
    for name, make in (("tiles (no curves, no overlaps)", tiles_scene),
                       ("thin lines (no curves)", thin_lines_scene)):
        sc = make(big)
        t, _ = timed(lambda: render_scene(sc, mode="approx", samples=16), repeat)
        rows.append(dict(row=name, size=big, mode="approx", samples=16, time_s=t,
                         baseline="curve-heavy blobs, approx 16", baseline_s=times["approx", 16],
                         ratio=t / times["approx", 16]))
    return rows


_MEMORY_SNIPPET = r"""
import resource, time, json
from vecmsaa.tools.bench import blobs_scene
from vecmsaa.raster.render import render_scene_rgba8
scene = blobs_scene(%d, count=300)
t = time.perf_counter()
img = render_scene_rgba8(scene, mode=%r, samples=%d)
print(json.dumps({"time_s": time.perf_counter() - t,
                  "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def memory_rows(sizes, mode="approx", samples=16):
    rows = []
    for size in sizes:
        res = subprocess.run([sys.executable, "-c", _MEMORY_SNIPPET % (size, mode, samples)],
                             capture_output=True, text=True)
        if res.returncode:
            rows.append(dict(size=size, mode=mode, samples=samples,
                             error=(res.stderr.strip().splitlines() or ["?"])[-1]))
            continue
        out = json.loads(res.stdout.strip().splitlines()[-1])
        rows.append(dict(size=size, mode=mode, samples=samples, time_s=out["time_s"],
                         peak_rss_mb=out["peak_rss_mb"],
                         rgba8_mb=size * size * 4 / 2 ** 20,
                         float_target_mb=size * size * 16 / 2 ** 20))
    return rows


# -- against resvg on real files (issue 11's goals) -------------------------------------------
def user_env() -> dict:
    """The environment for timed processes: this one's, but Python may write and read its
    bytecode caches, as it does after ``pip install`` (which compiles them). With
    PYTHONDONTWRITEBYTECODE set (some shells and CI images set it) an editable or source
    checkout compiles vecmsaa's modules from source in every process: ≈ 0.1 s of a 0.2 s
    start on a 2-core machine, which a user's installed command never pays."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def _child(cmd):
    """Run a process to the end → (wall s, peak RSS MB) from its own resource usage."""
    t = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env=user_env())
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    return wall, usage.ru_maxrss / 1024


def _best_child(cmd, repeat):
    """(min wall, max peak RSS) of ``repeat`` runs after one untimed run (file caches, and
    the bytecode caches user_env lets the first run write)."""
    _child(cmd)
    runs = [_child(cmd) for _ in range(repeat)]
    return min(w for w, _ in runs), max(m for _, m in runs)


_WARM_SNIPPET = r"""
import json, sys, time
from vecmsaa.api import render_svg_png
path, width, repeat = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
render_svg_png(path, width=width)
best = 1e9
for _ in range(repeat):
    t = time.perf_counter()
    render_svg_png(path, width=width)
    best = min(best, time.perf_counter() - t)
print(json.dumps({"warm_s": best}))
"""


def versus_rows(paths, repeat=3, large=8192, small=2048, batch_size=800, log=print):
    """Rows for each SVG file: whole process at ``large`` and ``small`` px (wall time, min of
    ``repeat``, and peak RSS) for ``vecmsaa render`` and resvg, alternating; vecmsaa warm in
    one process (file → PNG bytes at ``small``, min of ``repeat`` after a warm-up) against
    resvg's whole process; and the files as one batch at ``batch_size`` with ``--jobs 1`` and
    ``--jobs 2``. Default mode (approx, 8 samples), warm JIT caches."""
    resvg = resvg_binary()
    vec = [sys.executable, "-m", "vecmsaa.cli", "render"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "o.png")
        for path in paths:
            name = os.path.splitext(os.path.basename(path))[0]
            row = dict(scene=name)
            for size in (large, small):
                try:
                    row[f"vecmsaa_{size}_s"], row[f"vecmsaa_{size}_mb"] = _best_child(
                        vec + [path, "-o", out, "-w", str(size)], repeat)
                    if resvg:
                        row[f"resvg_{size}_s"], row[f"resvg_{size}_mb"] = _best_child(
                            [resvg, "-w", str(size), path, out], repeat)
                except (subprocess.CalledProcessError, OSError) as exc:
                    log(f"  {name} at {size} px failed: {exc}")
            res = subprocess.run([sys.executable, "-c", _WARM_SNIPPET, path, str(small),
                                  str(repeat)], capture_output=True, text=True, env=user_env())
            if res.returncode == 0:
                row[f"warm_{small}_s"] = json.loads(res.stdout.strip().splitlines()[-1])["warm_s"]
            for key, base in ((f"vecmsaa_{large}_s", f"resvg_{large}_s"),
                              (f"vecmsaa_{large}_mb", f"resvg_{large}_mb"),
                              (f"vecmsaa_{small}_s", f"resvg_{small}_s"),
                              (f"warm_{small}_s", f"resvg_{small}_s")):
                if row.get(key) and row.get(base):
                    row[key.replace("_s", "").replace("_mb", "_mem") + "_ratio"] = \
                        row[key] / row[base]
            rows.append(row)
            log(f"{name}: " + ", ".join(f"{k} {v:.3g}" for k, v in row.items()
                                        if isinstance(v, float)))
        batch = {}
        for jobs in (1, 2):
            out_dir = os.path.join(tmp, f"jobs{jobs}")
            try:
                batch[jobs] = _best_child(vec + list(paths) + ["--out-dir", out_dir, "-w",
                                                               str(batch_size), "--jobs",
                                                               str(jobs)], repeat)[0]
            except (subprocess.CalledProcessError, OSError) as exc:
                log(f"  batch with --jobs {jobs} failed: {exc}")
    return dict(rows=rows, large=large, small=small, repeat=repeat, batch_size=batch_size,
                batch_jobs1_s=batch.get(1), batch_jobs2_s=batch.get(2), resvg=bool(resvg))


def write_versus(out_dir, result):
    """versus.md and versus.json in ``out_dir``."""
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "versus.json"), "w") as f:
        json.dump(result, f, indent=1)
    big, small = result["large"], result["small"]
    rows = list(result["rows"])
    total = {"scene": "**total**"}
    for key in (f"vecmsaa_{small}_s", f"resvg_{small}_s", f"warm_{small}_s",
                f"vecmsaa_{big}_s", f"resvg_{big}_s"):
        vals = [r.get(key) for r in rows]
        if all(v is not None for v in vals):
            total[key] = sum(vals)
    if total.get(f"resvg_{small}_s"):
        total[f"warm_{small}_ratio"] = total[f"warm_{small}_s"] / total[f"resvg_{small}_s"]
    rows.append(total)
    lines = ["# vecmsaa against resvg", "",
             f"{machine()}; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. Whole "
             f"process: `vecmsaa render FILE -o out.png -w N` and `resvg -w N FILE out.png`, "
             f"min wall time of {result['repeat']}, peak RSS (MB) of the process; warm: "
             f"file → PNG bytes in one process (`render_svg_png`), min of "
             f"{result['repeat']} after a warm-up. Approx, 8 samples, warm JIT caches; "
             f"every command run once untimed first, vecmsaa's with Python's bytecode caches "
             f"(PYTHONDONTWRITEBYTECODE unset, as after `pip install`).", "",
             md_table(rows, [("file", "scene"),
                             (f"vecmsaa {big} (s)", f"vecmsaa_{big}_s"),
                             (f"resvg {big} (s)", f"resvg_{big}_s"),
                             ("ratio", f"vecmsaa_{big}_ratio"),
                             (f"vecmsaa {big} (MB)", f"vecmsaa_{big}_mb"),
                             (f"resvg {big} (MB)", f"resvg_{big}_mb"),
                             ("ratio", f"vecmsaa_{big}_mem_ratio"),
                             (f"vecmsaa {small} (s)", f"vecmsaa_{small}_s"),
                             (f"resvg {small} (s)", f"resvg_{small}_s"),
                             ("ratio", f"vecmsaa_{small}_ratio"),
                             (f"warm {small} (s)", f"warm_{small}_s"),
                             ("warm / resvg", f"warm_{small}_ratio")]), ""]
    if result.get("batch_jobs1_s") and result.get("batch_jobs2_s"):
        lines += [f"Batch of the {len(result['rows'])} files at {result['batch_size']} px: "
                  f"`--jobs 1` {result['batch_jobs1_s']:.2f} s, `--jobs 2` "
                  f"{result['batch_jobs2_s']:.2f} s "
                  f"(ratio {result['batch_jobs2_s'] / result['batch_jobs1_s']:.2f}).", ""]
    with open(os.path.join(out_dir, "versus.md"), "w") as f:
        f.write("\n".join(lines))


# -- reports ----------------------------------------------------------------------------------
def summary(rows):
    """Per (renderer, mode, samples, pattern): total time over scenes and mean errors."""
    groups = {}
    for r in rows:
        if r["renderer"] not in ("vecmsaa", "resvg", "cairosvg") or r["mode"] == "reference":
            continue
        key = (r["renderer"], r["mode"], r["samples"], r["pattern"])
        groups.setdefault(key, []).append(r)
    out = []
    for key, rs in groups.items():
        out.append(dict(renderer=key[0], mode=key[1], samples=key[2], pattern=key[3],
                        scenes=len(rs), time_s=sum(r["time_s"] for r in rs),
                        mean_error=statistics.fmean(r["mean_error"] for r in rs),
                        edge_error=statistics.fmean(r["edge_error"] for r in rs),
                        max_error=max(r["max_error"] for r in rs)))
    order = {m: i for i, m in enumerate(MSAA_MODES + ("analytic", "resvg", "cairosvg"))}
    out.sort(key=lambda s: (order.get(s["mode"], 99), s["pattern"], s["samples"]))
    return out


def pareto(points):
    """Points (time, error, ...) not beaten in both time and error by another, by time."""
    front = []
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    return front


def plot(summ, path, title):
    """Total time (log x) against mean edge error (log y); one Pareto curve per mode."""
    from PIL import Image, ImageDraw, ImageFont

    W, H = 1000, 680
    left, right, top, bottom = 90, 180, 50, 70
    img = Image.new("RGB", (W, H), "white")
    d = ImageDraw.Draw(img)
    try:
        font = ImageFont.load_default(size=14)
    except TypeError:
        font = ImageFont.load_default()
    pts = [s for s in summ if s["time_s"] > 0 and s["edge_error"] > 0]
    if not pts:
        img.save(path)
        return
    tx = [math.log10(s["time_s"]) for s in pts]
    ey = [math.log10(s["edge_error"]) for s in pts]
    x0, x1 = math.floor(min(tx) * 4) / 4, math.ceil(max(tx) * 4) / 4
    y0, y1 = math.floor(min(ey) * 4) / 4, math.ceil(max(ey) * 4) / 4
    x1 = max(x1, x0 + 0.25)
    y1 = max(y1, y0 + 0.25)

    def X(v):
        return left + (v - x0) / (x1 - x0) * (W - left - right)

    def Y(v):
        return H - bottom - (v - y0) / (y1 - y0) * (H - top - bottom)
    # decades and half-decades
    for k in range(int(math.floor(x0 * 2)), int(math.ceil(x1 * 2)) + 1):
        v = k / 2
        if x0 <= v <= x1:
            d.line([(X(v), top), (X(v), H - bottom)], fill=(225, 225, 225))
            d.text((X(v) - 15, H - bottom + 6), f"{10 ** v:.3g}", fill="black", font=font)
    for k in range(int(math.floor(y0 * 2)), int(math.ceil(y1 * 2)) + 1):
        v = k / 2
        if y0 <= v <= y1:
            d.line([(left, Y(v)), (W - right, Y(v))], fill=(225, 225, 225))
            d.text((8, Y(v) - 7), f"{10 ** v:.2g}", fill="black", font=font)
    d.rectangle([left, top, W - right, H - bottom], outline="black")
    d.text((left + (W - left - right) / 2 - 120, H - bottom + 30),
           "total render time over the corpus (s, log)", fill="black", font=font)
    d.text((8, top - 20), "mean edge-pixel error vs reference (log)", fill="black", font=font)
    d.text((left, 4), title, fill="black", font=font)
    modes = []
    for s in pts:
        if s["mode"] not in modes:
            modes.append(s["mode"])
    for i, mode in enumerate(modes):
        col = MODE_COLOURS.get(mode, (0, 0, 0))
        mine = [(math.log10(s["time_s"]), math.log10(s["edge_error"]), s) for s in pts
                if s["mode"] == mode]
        for px, py, s in mine:
            cx, cy = X(px), Y(py)
            if s["pattern"] == "grid":
                d.rectangle([cx - 3, cy - 3, cx + 3, cy + 3], outline=col)
            else:
                d.ellipse([cx - 3, cy - 3, cx + 3, cy + 3], fill=col)
        front = pareto(mine)
        if len(front) > 1:
            d.line([(X(p[0]), Y(p[1])) for p in front], fill=col, width=2)
        for px, py, s in front:
            if s["samples"]:
                d.text((X(px) + 5, Y(py) - 14), str(s["samples"]), fill=col, font=font)
        ly = top + 10 + 22 * i
        d.line([(W - right + 15, ly + 7), (W - right + 40, ly + 7)], fill=col, width=3)
        d.text((W - right + 46, ly), mode, fill="black", font=font)
    ly = top + 10 + 22 * len(modes) + 10
    d.text((W - right + 15, ly), "dot: d3d pattern", fill="black", font=font)
    d.text((W - right + 15, ly + 18), "square: grid", fill="black", font=font)
    d.text((W - right + 15, ly + 36), "label: samples", fill="black", font=font)
    img.save(path)


def _fmt(v, digits=4):
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def md_table(rows, cols):
    out = ["| " + " | ".join(c for c, _ in cols) + " |",
           "|" + "|".join("---" for _ in cols) + "|"]
    for r in rows:
        out.append("| " + " | ".join(_fmt(r.get(k, "")) if k else "" for _, k in cols) + " |")
    return "\n".join(out)


def write_reports(out_dir, result):
    import csv

    os.makedirs(out_dir, exist_ok=True)
    rows = result["rows"]
    keys = ["scene", "renderer", "mode", "samples", "pattern", "width", "height", "time_s",
            "mean_error", "edge_error", "max_error", "error_width", "error_height"]
    with open(os.path.join(out_dir, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)
    with open(os.path.join(out_dir, "results.json"), "w") as f:
        json.dump(result, f, indent=1)
    summ = summary(rows)
    plot(summ, os.path.join(out_dir, "pareto.png"),
         f"vecmsaa bench: {len(result['scenes'])} scenes at {result['size']} px "
         f"(errors at {result['error_size']} px)")
    lines = ["# vecmsaa bench", "",
             f"{result['machine']}; {result['when']}; scenes: {', '.join(result['scenes'])}; "
             f"timing size {result['size']} px (longer side), median of {result['repeat']} "
             f"after a warm-up; errors at {result['error_size']} px against the reference "
             f"mode (256 stratified samples per pixel, per-sample compositing), premultiplied "
             f"RGBA in [0, 1].", "",
             "## Time against error, summed over the corpus", "",
             md_table(summ, [("renderer", "renderer"), ("mode", "mode"), ("samples", "samples"),
                             ("pattern", "pattern"), ("total time (s)", "time_s"),
                             ("mean error", "mean_error"), ("edge error", "edge_error"),
                             ("max error", "max_error")]), ""]
    proc = [r for r in rows if r["renderer"] in ("vecmsaa-process",)]
    if proc:
        peers = {(r["scene"], r["renderer"]): r["time_s"] for r in rows
                 if r["renderer"] in ("resvg", "cairosvg")}
        table = []
        for r in proc:
            t_resvg = peers.get((r["scene"], "resvg"))
            table.append(dict(scene=r["scene"], size=f"{r['width']}x{r['height']}",
                              vecmsaa=r["time_s"], resvg=t_resvg if t_resvg else "",
                              ratio=r["time_s"] / t_resvg if t_resvg else ""))
        lines += ["## Whole process against resvg (SVG inputs)", "",
                  "`python -m vecmsaa.cli render FILE -o out.png -w SIZE` (approx, 8 samples, "
                  "warm JIT caches) against `resvg -w SIZE FILE out.png`, median wall time.", "",
                  md_table(table, [("scene", "scene"), ("size", "size"),
                                   ("vecmsaa (s)", "vecmsaa"), ("resvg (s)", "resvg"),
                                   ("ratio", "ratio")]), ""]
    if result.get("special"):
        lines += ["## Work the scene does not need is skipped", "",
                  md_table(result["special"], [("row", "row"), ("size", "size"),
                                               ("mode", "mode"), ("samples", "samples"),
                                               ("time (s)", "time_s"),
                                               ("against", "baseline"),
                                               ("its time (s)", "baseline_s"),
                                               ("ratio", "ratio")]), ""]
    if result.get("memory"):
        lines += ["## Memory (curve-heavy blobs, fresh process, peak RSS)", "",
                  md_table(result["memory"], [("size", "size"), ("mode", "mode"),
                                              ("samples", "samples"), ("time (s)", "time_s"),
                                              ("peak RSS (MB)", "peak_rss_mb"),
                                              ("RGBA8 image (MB)", "rgba8_mb"),
                                              ("float32 target (MB)", "float_target_mb"),
                                              ("error", "error")]), ""]
    jit = result.get("jit") or {}
    if jit:
        lines += ["## JIT (fresh process, Figure 1 at 32 px)", ""]
        for label, key in (("cold: empty caches (first run: compiling)", "cold"),
                           ("warm: caches filled (loading compiled code)", "warm")):
            if key in jit:
                parts = ", ".join(f"{k} {v:.2f} s" for k, v in jit[key].items()
                                  if isinstance(v, float))
                lines.append(f"- {label}: {parts}")
        if "startup_s" in jit:
            lines.append(f"- whole `vecmsaa render` process, 64 px SVG, warm caches: "
                         f"{jit['startup_s']:.2f} s")
        lines.append("")
    with open(os.path.join(out_dir, "table.md"), "w") as f:
        f.write("\n".join(lines))
    return summ


def machine():
    import platform
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"numpy {np.__version__}")


def run_bench(paths=(), out_dir="bench", quick=False, size=None, repeat=None, log=print,
              synthetic=True, jit=True, special=True, memory=None):
    size = size or (256 if quick else 1024)
    repeat = repeat or (1 if quick else 3)
    error_size = QUICK_ERROR_SIZE if quick else ERROR_SIZE
    cases = corpus(paths, synthetic)
    rows = []
    t_start = time.perf_counter()
    for case in cases:
        t = time.perf_counter()
        try:
            rows += bench_case(case, size, error_size, repeat, quick, log)
        except (ValueError, OSError) as exc:
            log(f"{case.name}: skipped ({exc})")
            continue
        log(f"{case.name}: {time.perf_counter() - t:.1f} s")
    result = dict(machine=machine(), when=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                  size=size, error_size=error_size, repeat=repeat, quick=quick,
                  scenes=[c.name for c in cases], rows=rows)
    if special:
        result["special"] = special_rows(size, repeat, quick)
        log("special rows done")
    if memory is None:
        memory = () if quick else (2048, 4096, 8192)
    if memory:
        result["memory"] = memory_rows(memory)
        log("memory rows done")
    if jit:
        result["jit"] = {"warm": jit_times(cold=False)}
        if not quick:
            result["jit"]["cold"] = jit_times(cold=True)
        result["jit"]["startup_s"] = startup_time(repeat)
        log("jit rows done")
    result["bench_s"] = time.perf_counter() - t_start
    write_reports(out_dir, result)
    return result
