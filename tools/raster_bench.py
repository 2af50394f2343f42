"""Raster timings in process: each SVG loaded once, then file's scene -> PNG bytes
(render_scene_png, threads=1) after one warm-up, CPU time (time.process_time: on a machine
shared with other work it moves less than wall time), the minimum and median of --repeat.

    python tools/raster_bench.py ../shared/corpus/*.svg -w 8192 --repeat 3

``--strip-rows N`` sets render.MSAA_STRIP_ROWS (256: the rule before session 10's 16).
``--threads 1,2`` times each count of band threads in turn, in wall time (CPU time adds up
the threads'), and prints the later counts' medians over the first's: run it where that
many cores are free.
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
    ap.add_argument("--threads", default="1",
                    help="comma-separated band thread counts, timed in turn in wall time")
    args = ap.parse_args()
    if args.tree:
        sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f).lower()]
        sys.path.insert(0, os.path.abspath(args.tree))
    from vecmsaa.api import collector_paused, load_svg
    from vecmsaa.raster import render
    from vecmsaa.raster.render import render_scene_png

    if args.strip_rows:
        render.MSAA_STRIP_ROWS = args.strip_rows

    counts = [int(n) for n in args.threads.split(",")]
    clock = time.process_time if counts == [1] else time.perf_counter
    for path in args.files:
        with collector_paused():
            scene = load_svg(path, width=args.width)
            times = {n: [] for n in counts}
            for n in counts:
                render_scene_png(scene, threads=n)
            for _ in range(args.repeat):
                for n in counts:
                    t = clock()
                    render_scene_png(scene, threads=n)
                    times[n].append(clock() - t)
        for n in counts:
            line = (f"{os.path.basename(path):28s} threads {n}  min {min(times[n]):.3f} s  "
                    f"median {statistics.median(times[n]):.3f} s")
            if n != counts[0]:
                line += (f"  ({statistics.median(times[n]) / statistics.median(times[counts[0]]):.2f}"
                         f" of {counts[0]})")
            print(line, flush=True)


if __name__ == "__main__":
    main()
