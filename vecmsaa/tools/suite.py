"""The resvg test suite runner: render each test at its reference PNG's size with the suite's
fonts (``fonts/``, generic families mapped as resvg does), compare with the project's criterion
(:mod:`vecmsaa.tools.compare`), count per category and feature. The command is ``vecmsaa suite``.

The suite is the ``crates/resvg/tests`` folder of the resvg repository (tests/, fonts/,
resources/). Where ``exact-refs/<test>.png`` exists beside ``tests/`` it holds the conflation-free
truth of a test whose reference keeps resvg's antialiasing fringe (a red shape "should be covered"
by an identical one: resvg's own render with the covered element removed). Two more tests
whose references carry that fringe have an exact reference computed from their geometry
(:mod:`vecmsaa.tools.suite_truth`), and
tests whose references carry resvg's per-pixel compositing artifacts one rendered by resvg at 8x
resolution and box-filtered (``vecmsaa/data/exact-refs``). A test with an exact reference passes when it matches its reference *or* its exact reference, and both
counts are reported."""
from __future__ import annotations

import os
from typing import NamedTuple

#: how resvg's test harness maps the generic font families
SUITE_FONTS = {"serif_family": "Noto Serif", "sans_serif_family": "Noto Sans",
               "cursive_family": "Yellowtail", "fantasy_family": "Sedgwick Ave Display",
               "monospace_family": "Noto Mono", "font_family": "Noto Serif"}
#: CPU seconds one test may take. Processor time rather than wall-clock time, so that a loaded
#: machine does not time out a first run that compiles the numba kernels: an interrupted compile
#: is not cached, and every later test would start it over.
TEST_TIMEOUT = 180
#: names the suite folder for ``vecmsaa suite`` without an argument and for the test suite
SUITE_ENV = "VECMSAA_RESVG_SUITE"
EXACT_REFS = "exact-refs"
#: resvg's renders at 8x resolution, box-filtered, of tests whose references carry its per-pixel
#: compositing artifacts (written by tools/make_exact_refs.py, which says how they are chosen)
SUPERSAMPLED_REFS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                 "data", "exact-refs")


def suite_from_environment(default=None):
    """The suite folder named by $VECMSAA_RESVG_SUITE, else ``default``."""
    return os.environ.get(SUITE_ENV) or default


def tests_root(folder):
    folder = os.path.abspath(folder)
    if os.path.isdir(os.path.join(folder, "tests")):
        return folder, os.path.join(folder, "tests")
    return os.path.dirname(folder), folder


def collect(tests_dir, categories=(), only=()):
    """Names like 'shapes/rect/simple-case' of all SVG tests with a reference PNG."""
    out = []
    for base, dirs, files in os.walk(tests_dir):
        dirs.sort()
        for f in sorted(files):
            if not f.endswith(".svg"):
                continue
            rel = os.path.relpath(os.path.join(base, f[:-4]), tests_dir).replace(os.sep, "/")
            if categories and rel.split("/")[0] not in categories:
                continue
            if only and not any(o in rel for o in only):
                continue
            if os.path.exists(os.path.join(base, f[:-4] + ".png")):
                out.append(rel)
    return out


class Result(NamedTuple):
    """One test's outcome: ``plain`` = matches resvg's reference; ``exact`` = matches the exact
    reference (False when there is none); ``own_truth``: that exact reference is one of
    vecmsaa's (computed from geometry or a supersampled resvg render), not the suite's
    ``exact-refs/``, so the summary can count the suite's criterion apart."""
    plain: bool
    exact: bool
    detail: str
    own_truth: bool = False

    @property
    def passed(self) -> bool:
        return self.plain or self.exact


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


def suite_options(suite_dir, coverage=None) -> dict:
    """Render options of every test: the suite's fonts and resources, and the coverage options
    given (``mode``, ``samples``, ``pattern``, ``filter``, ``color_samples``; None: the
    renderer's default)."""
    kwargs = dict(SUITE_FONTS, use_fonts_dir=os.path.join(suite_dir, "fonts"),
                  skip_system_fonts=True, resources_dir=os.path.join(suite_dir, "resources"))
    kwargs.update({k: v for k, v in (coverage or {}).items() if v is not None})
    return kwargs


def render_test(svg, width, height, **kwargs):
    """One test at its reference's size: by width (the aspect ratio kept), and by both sides
    when that misses the height."""
    from vecmsaa.api import render_svg_array

    actual = render_svg_array(svg, width=width, **kwargs)
    if actual.shape[:2] != (height, width):
        actual = render_svg_array(svg, width=width, height=height, **kwargs)
    return actual


def _read_rgba(path):
    import numpy as np
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


def _reference(suite_dir, name):
    return _read_rgba(os.path.join(suite_dir, "tests", name + ".png"))


def run_one(job):
    """Render and compare one test → (name, Result). Runs in worker processes. The render's
    warnings (many tests exercise missing files and bad values on purpose) are not printed;
    a failure's detail ends with them, where they may say why."""
    import signal

    from vecmsaa import diagnostics

    name, suite_dir, out_dir, coverage = job
    svg = os.path.join(suite_dir, "tests", name + ".svg")
    ref = _reference(suite_dir, name)
    h, w = ref.shape[:2]
    old = signal.signal(signal.SIGPROF, _alarm) if hasattr(signal, "SIGPROF") else None
    if old is not None:
        signal.setitimer(signal.ITIMER_PROF, TEST_TIMEOUT)
    found = []
    try:
        with diagnostics.collecting(found):
            actual = render_test(svg, w, h, **suite_options(suite_dir, coverage))
    except _Timeout:
        return name, Result(False, False, "timeout")
    except Exception as exc:   # any failure of one test is a result, not a crash of the run
        actual = exc
    finally:
        if old is not None:
            signal.setitimer(signal.ITIMER_PROF, 0)
            signal.signal(signal.SIGPROF, old)
    name, result = judge(name, actual, ref, out_dir, suite_dir)
    if found and not result.passed:
        result = result._replace(detail=f"{result.detail}; warnings: {'; '.join(found[:3])}")
    return name, result


def judge(name, actual, ref, out_dir, suite_dir):
    """(name, Result) for a render (an array, or the exception rendering raised): against the
    reference, then against the exact reference where there is one."""
    from vecmsaa.tools.compare import compare_images

    if isinstance(actual, BaseException):
        msg = str(actual).splitlines()[0] if str(actual) else ""
        return name, Result(False, False, f"error: {type(actual).__name__}: {msg}"[:200])
    cmp = compare_images(actual, ref)
    if cmp.passed():
        return name, Result(True, False, cmp.describe())
    exact, own = exact_reference(suite_dir, name, ref.shape[1], ref.shape[0])
    if exact is None:
        if out_dir:
            _write_diff(actual, ref, "reference", os.path.join(out_dir, name + ".png"))
        return name, Result(False, False, cmp.describe())
    exact_cmp = compare_images(actual, exact)
    if exact_cmp.passed():
        return name, Result(False, True, f"passes against its exact reference "
                                         f"({exact_cmp.describe()}); reference: {cmp.describe()}",
                            own)
    if out_dir:
        _write_diff(actual, exact, "exact reference", os.path.join(out_dir, name + ".png"))
    return name, Result(False, False, f"exact reference: {exact_cmp.describe()}; "
                                      f"reference: {cmp.describe()}")


def exact_reference(suite_dir, name, width, height):
    """(image, own) for the exact reference of a test: ``exact-refs/<name>.png`` beside the
    suite's tests (own False), else the one computed from the test's geometry
    (:mod:`vecmsaa.tools.suite_truth`), else the supersampled resvg render in
    SUPERSAMPLED_REFS (own True); (None, False) when there is none."""
    path = os.path.join(suite_dir, EXACT_REFS, name + ".png")
    if os.path.exists(path):
        return _read_rgba(path), False
    from .suite_truth import exact_reference as computed

    exact = computed(name, width, height)
    if exact is None:
        path = os.path.join(SUPERSAMPLED_REFS, name + ".png")
        if os.path.exists(path):
            exact = _read_rgba(path)
    return exact, exact is not None


LABEL_HEIGHT = 16


def _write_diff(actual, ref, ref_label, path):
    """The project's triptych (reference | difference | render) under a row of labels."""
    import numpy as np
    from PIL import Image, ImageDraw

    from vecmsaa.files import write_bytes_atomic
    from vecmsaa.output.png import encode_png
    from vecmsaa.tools.compare import PANEL_GAP, triptych

    body = triptych(ref, actual)
    panel = (body.shape[1] - 2 * PANEL_GAP) // 3
    head = Image.new("RGBA", (body.shape[1], LABEL_HEIGHT), (255, 255, 255, 255))
    draw = ImageDraw.Draw(head)
    for i, label in enumerate((ref_label, "difference", "render")):
        draw.text((i * (panel + PANEL_GAP) + 3, 2), label, fill=(0, 0, 0, 255))
    image = np.concatenate([np.asarray(head), body], axis=0)
    write_bytes_atomic(encode_png(image), path, make_folders=True)


def run_suite(suite_dir, names, jobs=1, out_dir=None, coverage=None, progress=None,
              scheduler=None):
    """Run tests by name; returns {name: Result}. ``coverage``: render options as
    :func:`suite_options` takes them. With ``scheduler`` the renders run on that Dask cluster
    (vecmsaa.tools.cluster; no per-test timeout there), the comparisons here."""
    jobs_list = [(n, suite_dir, out_dir, coverage) for n in names]
    results = {}
    if scheduler:
        from PIL import Image

        from .cluster import Cluster

        def item(name):
            with Image.open(os.path.join(suite_dir, "tests", name + ".png")) as im:
                w, h = im.size
            return (os.path.join(suite_dir, "tests", name + ".svg"),
                    dict(suite_options(suite_dir, coverage), width=w, height=h))

        with Cluster(scheduler) as cluster:
            renders = cluster.render_arrays((item(n) for n in names), render_test)
            for name, actual in zip(names, renders):
                _, result = judge(name, actual, _reference(suite_dir, name), out_dir, suite_dir)
                results[name] = result
                if progress:
                    progress(len(results), len(names))
        return results
    if jobs <= 1 or len(names) <= 1:
        for j in jobs_list:
            name, result = run_one(j)
            results[name] = result
            if progress:
                progress(len(results), len(names))
        return results
    import multiprocessing as mp

    # the workers take the cores: one thread a render (the image does not depend on it)
    coverage = dict(coverage or {}, threads=1)
    jobs_list = [(n, suite_dir, out_dir, coverage) for n in names]
    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else mp.get_context()
    if ctx.get_start_method() == "fork":
        warm_up(suite_dir, coverage)
    with ctx.Pool(jobs, maxtasksperchild=200) as pool:
        for name, result in pool.imap_unordered(run_one, jobs_list, chunksize=2):
            results[name] = result
            if progress:
                progress(len(results), len(names))
    return results


#: a text in the suite's default family: rendering it loads the renderer, its kernels, the
#: suite's font folder and a face
WARM_UP_SVG = (b'<svg xmlns="http://www.w3.org/2000/svg" width="24" height="16"><path d="M1 1 '
               b'Q20 1 20 12Z" fill="red" stroke="blue"/><text x="1" y="12">Ag</text></svg>')


def warm_up(suite_dir, coverage=None) -> None:
    """Before the workers are forked: import and load in this process what every test needs,
    so that each worker (a new one every 200 tests) inherits it instead of loading it again
    (0.75 s of CPU each: imports, compiled kernels, the font folder, a face)."""
    import importlib

    from vecmsaa import diagnostics
    from vecmsaa.api import render_svg_array

    for module in ("vecmsaa.tools.compare", "PIL.Image", "PIL.PngImagePlugin"):  # judge's
        importlib.import_module(module)
    try:
        with diagnostics.collecting([]):
            render_svg_array(WARM_UP_SVG, **dict(suite_options(suite_dir, coverage), threads=1))
    except Exception:   # a broken option or font folder: every test reports it
        pass


def summarize(results, features=False):
    """Pass counts per category (and feature): against the references alone; counting a match
    with the suite's own ``exact-refs/`` as a pass (the suite's criterion); and counting a
    match with vecmsaa's exact references too (computed truths, supersampled renders)."""
    from collections import defaultdict

    counts = defaultdict(lambda: [0, 0, 0, 0])  # plain, suite exact refs, all exact refs, tests
    for name, r in results.items():
        parts = name.split("/")
        for key in ("", parts[0], "/".join(parts[:2]) if features else None):
            if key is not None:
                c = counts[key]
                c[0] += r.plain
                c[1] += r.passed and not r.own_truth
                c[2] += r.passed
                c[3] += 1

    def row(label, key):
        *passes, n = counts[key]
        return f"{label:<32}" + "".join(f" {p:4d}/{n:<4d} {100 * p / n:6.1f}%  " for p in passes)

    lines = [f"{'':<32} {'plain':>16}   {'+ exact-refs/':>16}   {'+ own truths':>16}"]
    for cat in sorted(k for k in counts if k and "/" not in k):
        lines.append(row(cat, cat))
        for f in sorted(k for k in counts if k.split("/")[0] == cat and "/" in k):
            lines.append(row("  " + f.split("/", 1)[1], f))
    if results:
        lines.append(row("total", ""))
    return "\n".join(lines)
