"""Front-end timings in process: load_svg (file -> Scene) and prepare_items (Scene -> the
raster's batches) of each SVG, CPU time (time.process_time), the minimum of --repeat runs
after one warm-up, the garbage collector paused as load_svg pauses it.

    python tools/frontend_bench.py ../shared/corpus -w 2048 --repeat 9

``--collector``: instead, the CPU time Python's cyclic garbage collector spends in
``load_svg`` and in ``render_svg_png`` (``gc.callbacks``; the collector on, as a user has it),
the median of --repeat calls, each after a full collection.

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
