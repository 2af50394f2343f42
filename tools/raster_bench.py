"""Raster timings in process: each SVG loaded once, then file's scene -> PNG bytes
(render_scene_png, threads=1) after one warm-up, CPU time (time.process_time: on a machine
shared with other work it moves less than wall time), the minimum and median of --repeat.

    python tools/raster_bench.py ../shared/corpus/*.svg -w 8192 --repeat 3

``--strip-rows N`` sets render.MSAA_STRIP_ROWS (256: the rule before session 10's 16).
``--tree DIR`` times another checkout the same way (an editable install's import hook would
win over PYTHONPATH). A/B: alternate the two trees, A B B A, and compare the minimums."""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("-w", "--width", type=int, default=8192)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tree", help="a checkout to import vecmsaa from")
    ap.add_argument("--strip-rows", type=int, help="rows of a multisampled strip at most")
    args = ap.parse_args()
    if args.tree:
        sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f).lower()]
        sys.path.insert(0, os.path.abspath(args.tree))
    from vecmsaa.api import collector_paused, load_svg
    from vecmsaa.raster import render
    from vecmsaa.raster.render import render_scene_png

    if args.strip_rows:
        render.MSAA_STRIP_ROWS = args.strip_rows

    for path in args.files:
        with collector_paused():
            scene = load_svg(path, width=args.width)
            render_scene_png(scene, threads=1)
            times = []
            for _ in range(args.repeat):
                t = time.process_time()
                render_scene_png(scene, threads=1)
                times.append(time.process_time() - t)
        print(f"{os.path.basename(path):28s} min {min(times):.3f} s  median "
              f"{statistics.median(times):.3f} s", flush=True)


if __name__ == "__main__":
    main()
