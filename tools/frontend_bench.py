"""Front-end timings in process: load_svg (file -> Scene) and prepare_items (Scene -> the
raster's batches) of each SVG, CPU time (time.process_time), the minimum of --repeat runs
after one warm-up, the garbage collector paused as load_svg pauses it.

    python tools/frontend_bench.py ../shared/corpus -w 2048 --repeat 9

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
    args = ap.parse_args(argv)
    from vecmsaa.api import load_svg
    from vecmsaa.raster.render import RenderOptions, prepare_items

    files = []
    for item in args.inputs:
        if os.path.isdir(item):
            files += sorted(os.path.join(item, f) for f in os.listdir(item) if f.endswith(".svg"))
        else:
            files.append(item)
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


if __name__ == "__main__":
    sys.exit(main())
