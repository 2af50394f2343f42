"""The resvg test suite runner: render each test at its reference PNG's size with the suite's
fonts (``fonts/``, generic families mapped as resvg does), compare with the project's criterion
(:mod:`vecmsaa.tools.compare`), count per category and feature. The command is ``vecmsaa suite``."""
from __future__ import annotations

import os

#: how resvg's test harness maps the generic font families
SUITE_FONTS = {"serif_family": "Noto Serif", "sans_serif_family": "Noto Sans",
               "cursive_family": "Yellowtail", "fantasy_family": "Sedgwick Ave Display",
               "monospace_family": "Noto Mono", "font_family": "Noto Serif"}
TEST_TIMEOUT = 120


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


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


def suite_options(suite_dir, mode=None, samples=None) -> dict:
    """Render options of every test: the suite's fonts and resources, and the coverage."""
    kwargs = dict(SUITE_FONTS, use_fonts_dir=os.path.join(suite_dir, "fonts"),
                  skip_system_fonts=True, resources_dir=os.path.join(suite_dir, "resources"))
    if mode:
        kwargs["mode"] = mode
    if samples:
        kwargs["samples"] = samples
    return kwargs


def render_test(svg, width, height, **kwargs):
    """One test at its reference's size: by width (the aspect ratio kept), and by both sides
    when that misses the height."""
    from vecmsaa.api import render_svg_array

    actual = render_svg_array(svg, width=width, **kwargs)
    if actual.shape[:2] != (height, width):
        actual = render_svg_array(svg, width=width, height=height, **kwargs)
    return actual


def _reference(suite_dir, name):
    import numpy as np
    from PIL import Image

    with Image.open(os.path.join(suite_dir, "tests", name + ".png")) as im:
        return np.asarray(im.convert("RGBA"))


def run_one(job):
    """Render and compare one test → (name, passed, detail). Runs in worker processes."""
    import signal

    name, suite_dir, out_dir, mode, samples = job
    svg = os.path.join(suite_dir, "tests", name + ".svg")
    ref = _reference(suite_dir, name)
    h, w = ref.shape[:2]
    old = signal.signal(signal.SIGALRM, _alarm) if hasattr(signal, "SIGALRM") else None
    if old is not None:
        signal.alarm(TEST_TIMEOUT)
    try:
        actual = render_test(svg, w, h, **suite_options(suite_dir, mode, samples))
    except _Timeout:
        return name, False, "timeout"
    except Exception as exc:   # any failure of one test is a result, not a crash of the run
        actual = exc
    finally:
        if old is not None:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, old)
    return judge(name, actual, ref, out_dir)


def judge(name, actual, ref, out_dir):
    """(name, passed, detail) for a render (an array, or the exception rendering raised)."""
    from vecmsaa.tools.compare import compare_images, write_triptych

    if isinstance(actual, BaseException):
        msg = str(actual).splitlines()[0] if str(actual) else ""
        return name, False, f"error: {type(actual).__name__}: {msg}"[:200]
    cmp = compare_images(actual, ref)
    ok = cmp.passed()
    if not ok and out_dir:
        write_triptych(os.path.join(out_dir, name + ".png"), ref, actual)
    return name, ok, cmp.describe()


def run_suite(suite_dir, names, jobs=1, out_dir=None, mode=None, samples=None, progress=None,
              scheduler=None):
    """Run tests by name; returns {name: (passed, detail)}. With ``scheduler`` the renders run
    on that Dask cluster (vecmsaa.tools.cluster; no per-test timeout there), the comparisons
    here."""
    jobs_list = [(n, suite_dir, out_dir, mode, samples) for n in names]
    results = {}
    if scheduler:
        from PIL import Image

        from .cluster import Cluster

        def item(name):
            with Image.open(os.path.join(suite_dir, "tests", name + ".png")) as im:
                w, h = im.size
            return (os.path.join(suite_dir, "tests", name + ".svg"),
                    dict(suite_options(suite_dir, mode, samples), width=w, height=h))

        with Cluster(scheduler) as cluster:
            renders = cluster.render_arrays((item(n) for n in names), render_test)
            for name, actual in zip(names, renders):
                _, ok, detail = judge(name, actual, _reference(suite_dir, name), out_dir)
                results[name] = (ok, detail)
                if progress:
                    progress(len(results), len(names))
        return results
    if jobs <= 1 or len(names) <= 1:
        for j in jobs_list:
            name, ok, detail = run_one(j)
            results[name] = (ok, detail)
            if progress:
                progress(len(results), len(names))
        return results
    import multiprocessing as mp

    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else mp.get_context()
    with ctx.Pool(jobs, maxtasksperchild=200) as pool:
        for name, ok, detail in pool.imap_unordered(run_one, jobs_list, chunksize=2):
            results[name] = (ok, detail)
            if progress:
                progress(len(results), len(names))
    return results


def summarize(results, features=False):
    from collections import defaultdict

    cats = defaultdict(lambda: [0, 0])
    feats = defaultdict(lambda: [0, 0])
    for name, (ok, _) in results.items():
        parts = name.split("/")
        cats[parts[0]][0] += ok
        cats[parts[0]][1] += 1
        feats["/".join(parts[:2])][0] += ok
        feats["/".join(parts[:2])][1] += 1
    lines = []
    total = [0, 0]
    for c in sorted(cats):
        p, n = cats[c]
        total[0] += p
        total[1] += n
        lines.append(f"{c:<16} {p:4d}/{n:<4d} {100 * p / n:6.1f}%")
        if features:
            for f in sorted(k for k in feats if k.split("/")[0] == c):
                fp, fn = feats[f]
                lines.append(f"  {f.split('/', 1)[-1]:<30} {fp:4d}/{fn:<4d} {100 * fp / fn:6.1f}%")
    if total[1]:
        lines.append(f"{'total':<16} {total[0]:4d}/{total[1]:<4d} "
                     f"{100 * total[0] / total[1]:6.1f}%")
    return "\n".join(lines)
