"""Per-file cost of many small renders in one process (docs/bench.md, session 36): the resvg
suite's tests of the given categories, each at its reference width with the suite's options,
through vecmsaa.api.render_svg_png in a loop (a service's requests), after one warm pass.
Prints wall and CPU per file (medians of --reps passes), the executors made; with --profile,
one more pass under cProfile (CPU time) and its totals for each phase.

    python tools/small_files_bench.py [--suite DIR] [--category shapes --category structure]
        [--threads N] [--reps 3] [--profile]
    python tools/small_files_bench.py --resvg-py     # the same files through resvg_py

Run it with PYTHONPATH=OTHER_TREE to time another tree the same way.
"""
import argparse
import concurrent.futures
import cProfile
import glob
import os
import pstats
import statistics
import time
import warnings

#: cProfile's function names → the phase they stand for
PHASES = {"_read_source": "read the file", "open_svg": "parse", "build": "build",
          "load_svg": "load_svg (read + parse + build)", "prepare_items": "raster: prepare",
          "_draw_prepared": "raster: draw", "render_scene_png": "raster + encode",
          "write_rows": "encode", "database_from_options": "font database",
          "_background": "options", "samples_for": "options", "submit": "executor submits",
          "shutdown": "executor shutdowns"}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--suite", default=os.environ.get("VECMSAA_RESVG_SUITE",
                                                     "/work/shared/resvg-suite"))
    p.add_argument("--category", action="append", default=[])
    p.add_argument("--threads", type=int)
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--profile", action="store_true")
    p.add_argument("--resvg-py", action="store_true")
    args = p.parse_args()
    warnings.simplefilter("ignore")
    from PIL import Image

    files = []
    for category in args.category or ["shapes", "structure"]:
        files += sorted(glob.glob(f"{args.suite}/tests/{category}/**/*.svg", recursive=True))
    files = [f for f in files if os.path.exists(f[:-4] + ".png")]
    widths = {}
    for f in files:
        with Image.open(f[:-4] + ".png") as im:
            widths[f] = im.size[0]
    made = []
    original = concurrent.futures.ThreadPoolExecutor

    class Counted(original):
        def __init__(self, *a, **k):
            made.append(1)
            super().__init__(*a, **k)
    concurrent.futures.ThreadPoolExecutor = Counted
    if args.resvg_py:
        import resvg_py
        from vecmsaa.tools.suite import SUITE_FONTS
        options = dict(SUITE_FONTS, font_dirs=[f"{args.suite}/fonts"], skip_system_fonts=True,
                       resources_dir=f"{args.suite}/resources")
        options.pop("use_fonts_dir", None)

        def one(f):
            try:
                resvg_py.svg_to_bytes(svg_path=f, width=widths[f], **options)
            except Exception:
                pass
    else:
        from vecmsaa.api import render_svg_png
        from vecmsaa.tools.suite import suite_options
        options = suite_options(args.suite)
        if args.threads:
            options["threads"] = args.threads

        def one(f):
            try:
                render_svg_png(f, width=widths[f], **options)
            except Exception:
                pass
    for f in files:
        one(f)
    made.clear()
    passes = []
    for _ in range(args.reps):
        t0, c0 = time.perf_counter(), time.process_time()
        for f in files:
            one(f)
        passes.append((time.perf_counter() - t0, time.process_time() - c0))
    n = len(files)
    print(f"{n} files, {args.reps} passes: wall {1000 * statistics.median(w for w, _ in passes) / n:.2f}"
          f" ms a file, CPU {1000 * statistics.median(c for _, c in passes) / n:.2f} ms a file;"
          f" executors made {len(made)} for {args.reps * n} renders")
    if args.profile:
        prof = cProfile.Profile(time.process_time)
        prof.enable()
        for f in files:
            one(f)
        prof.disable()
        stats = pstats.Stats(prof)
        rows = []
        for (path, line, name), (_cc, calls, _tt, cum, _callers) in stats.stats.items():
            if name in PHASES:
                rows.append((cum, calls, f"{PHASES[name]} ({os.path.basename(path)}:{line} {name})"))
        print(f"profiled pass: {1000 * stats.total_tt / n:.2f} ms CPU a file")
        for cum, calls, label in sorted(rows, reverse=True):
            print(f"  {1000 * cum / n:8.3f} ms a file  {calls:6d} calls  {label}")


if __name__ == "__main__":
    main()
