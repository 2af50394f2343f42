"""Front-end timings in process: load_svg (file -> Scene) and prepare_items (Scene -> the
raster's batches) of each SVG, CPU time (time.process_time), the minimum of --repeat runs
after one warm-up, the garbage collector paused as load_svg pauses it.

    python tools/frontend_bench.py ../shared/corpus -w 2048 --repeat 9

``--collector``: instead, the CPU time Python's cyclic garbage collector spends in
``load_svg`` and in ``render_svg_png`` (``gc.callbacks``; the collector on, as a user has it),
the median of --repeat calls, each after a full collection.

``--phases``: instead, load_svg in its parts, the medians of --repeat runs after two warm-ups
(CPU, the collector paused): the XML read (the document parsed into its element tree), the
build (tree -> Scene), prepare_items, and freeing the tree and the scene.

Run it with PYTHONPATH=<another checkout> to time that tree the same way."""
from __future__ import annotations

import argparse
import gc
import os
import sys
import time


def best(fn, repeat):
    times = []
    for _ in range(repeat + 1):
        gc.disable()
        t = time.process_time()
        fn()
        times.append(time.process_time() - t)
        gc.enable()
    return min(times[1:])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inputs", nargs="+", help="SVG files or folders")
    ap.add_argument("-w", "--width", type=int, default=2048)
    ap.add_argument("--repeat", type=int, default=9)
    ap.add_argument("--collector", action="store_true",
                    help="the garbage collector's time in load_svg and render_svg_png")
    ap.add_argument("--phases", action="store_true",
                    help="load_svg's parts: XML read, build, prepare_items, freeing")
    args = ap.parse_args(argv)
    from vecmsaa.api import load_svg
    from vecmsaa.raster.render import RenderOptions, prepare_items

    files = []
    for item in args.inputs:
        if os.path.isdir(item):
            files += sorted(os.path.join(item, f) for f in os.listdir(item) if f.endswith(".svg"))
        else:
            files.append(item)
    if args.collector:
        return collector_times(files, args.width, args.repeat)
    if args.phases:
        return phase_times(files, args.width, args.repeat)
    print(f"| file | load_svg ms | prepare_items ms | sum ms |  ({args.width} px, CPU, "
          f"min of {args.repeat})")
    print("|---|---|---|---|")
    total = [0.0, 0.0]
    for path in files:
        scene = load_svg(path, width=args.width)
        load = best(lambda: load_svg(path, width=args.width), args.repeat)
        prep = best(lambda: prepare_items(scene.root, RenderOptions("approx", 8)), args.repeat)
        total[0] += load
        total[1] += prep
        print(f"| {os.path.basename(path)} | {load * 1e3:.1f} | {prep * 1e3:.1f} | "
              f"{(load + prep) * 1e3:.1f} |")
    print(f"| total | {total[0] * 1e3:.1f} | {total[1] * 1e3:.1f} | {sum(total) * 1e3:.1f} |")
    return 0


def phase_times(files, width, repeat):
    import statistics

    from vecmsaa.api import _Loaded
    from vecmsaa.raster.render import RenderOptions, prepare_items
    print(f"| file | XML read ms | build ms | prepare_items ms | freeing ms | sum ms |  ({width} "
          f"px, CPU, median of {repeat})")
    print("|---|---|---|---|---|---|")
    for path in files:
        rows = []
        for _ in range(repeat + 2):
            gc.disable()
            t0 = time.process_time()
            loaded = _Loaded(path, 96, None, {})
            t1 = time.process_time()
            scene = loaded.scene(width, None, None, None, False, True)
            t2 = time.process_time()
            loaded.builder.doc.release()
            del loaded
            t3 = time.process_time()
            prepare_items(scene.root, RenderOptions("approx", 8))
            t4 = time.process_time()
            del scene
            t5 = time.process_time()
            gc.enable()
            rows.append((t1 - t0, t2 - t1, t4 - t3, t3 - t2 + t5 - t4, t5 - t0))
        cols = [statistics.median(c) * 1e3 for c in zip(*rows[2:])]
        print(f"| {os.path.basename(path)} | " + " | ".join(f"{c:.1f}" for c in cols) + " |")
    return 0


def collector_times(files, width, repeat):
    import statistics

    from vecmsaa.api import load_svg, render_svg_png

    spent, start = [0.0], [0.0]

    def timer(phase, info):
        if phase == "start":
            start[0] = time.process_time()
        else:
            spent[0] += time.process_time() - start[0]
    print(f"| file | collector in load_svg ms | in render_svg_png ms |  ({width} px, CPU, "
          f"median of {repeat})")
    print("|---|---|---|")
    gc.callbacks.append(timer)
    try:
        for path in files:
            row = []
            for call in (load_svg, render_svg_png):
                call(path, width=width)
                times = []
                for _ in range(repeat):
                    gc.collect()
                    spent[0] = 0.0
                    call(path, width=width)
                    # (the pass a render leaves due runs at the next allocations)
                    _ = [[] for _ in range(1000)]
                    times.append(spent[0])
                row.append(statistics.median(times))
            print(f"| {os.path.basename(path)} | {row[0] * 1e3:.1f} | {row[1] * 1e3:.1f} |")
    finally:
        gc.callbacks.remove(timer)
    return 0


if __name__ == "__main__":
    sys.exit(main())
