"""Sample patterns and resolve filters measured (``vecmsaa bench --patterns``).

Patterns are compared at equal sample cost — the samples a pixel stores, which is what the
scan converter and the framebuffer pay for: quincunx and FLIPQUAD store 2 (and resolve 5 and
4), so they sit with the 2-sample patterns. Errors are the edge-pixel error × 255 against the
1024-sample reference (tools/accuracy.py) on Figure 1 and random scenes, and on two scenes
whose edges are all near-horizontal or all near-vertical (1° to 10° off the axis), where
patterns differ most: a pattern with n distinct rows sees n coverage levels on a
near-horizontal edge, an ordered grid √n.

Filters are compared with the approx mode's D3D patterns against the reference filtered the
same way (the reference mode's 256 samples through the same filter), so the error is the
sampling's, not the filter's blur. Times are the best of ``repeat`` renders at ``size`` px.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..raster.modes import FILTERS, PATTERN_NAMES
from ..raster.render import render_scene
from ..raster.sample_patterns import FIXED_SAMPLES
from ..scene.nodes import Fill, Group, Scene, Solid
from ..scene.path import Path
from .accuracy import edge_error, edge_mask, figure1_scene, ground_truth, random_scene


def slanted_bands(size: int, vertical: bool = False) -> Scene:
    """Bands 5 px apart whose long edges run 1° to 10° off the horizontal (or vertical), their
    ends beyond the image, on white."""
    fills = []
    count = max(1, size // 10)
    for k in range(count):
        angle = math.radians(1 + 9 * k / max(1, count - 1))
        y0 = (k + 0.3) * size / count + 0.123
        slope = math.tan(angle)
        pts = [(-2.0, y0), (size + 2.0, y0 + (size + 4) * slope),
               (size + 2.0, y0 + (size + 4) * slope + 4.7), (-2.0, y0 + 4.7)]
        if vertical:
            pts = [(y, x) for x, y in pts]
        p = Path()
        p.moveTo(pts[0])
        for q in pts[1:]:
            p.lineTo(q)
        p.closePath()
        fills.append(Fill(p, Solid((0.1, 0.1, 0.1, 1.0))))
    return Scene(size, size, Group(fills), background=(1, 1, 1, 1))


def scenes(size: int, quick: bool) -> list[tuple[str, list[Scene]]]:
    return [("Figure 1", [figure1_scene(size)]),
            ("random scenes", [random_scene(1000 + i, size) for i in range(1 if quick else 3)]),
            ("near-horizontal edges", [slanted_bands(size)]),
            ("near-vertical edges", [slanted_bands(size, vertical=True)])]


def _best_time(fn, repeat: int) -> float:
    fn()        # compile, warm caches
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def pattern_configs(counts) -> list[tuple[int, str]]:
    """(stored samples, pattern) for each count: every pattern defined at that count."""
    return [(n, name) for n in counts for name in PATTERN_NAMES
            if FIXED_SAMPLES.get(name, n) == n]


def pattern_rows(size: int = 64, time_size: int = 256, repeat: int = 3, quick: bool = False,
                 mode: str = "approx", log=None) -> list[dict]:
    counts = (2, 4) if quick else (2, 4, 8, 16)
    cases = scenes(size, quick)
    truths = [[ground_truth(s) for s in group] for _, group in cases]
    timed_scene = figure1_scene(time_size)
    out = []
    for n, name in pattern_configs(counts):
        if log:
            log(f"patterns: {name} {n}")
        row = dict(samples=n, pattern=name, mode=mode)
        for (case, group), group_truth in zip(cases, truths):
            row[case] = 255 * float(np.mean([
                edge_error(render_scene(s, mode=mode, samples=n, pattern=name), t)
                for s, t in zip(group, group_truth)]))
        row["ms"] = 1000 * _best_time(lambda: render_scene(timed_scene, mode=mode, samples=n,
                                                           pattern=name), repeat)
        out.append(row)
    return out


def filter_rows(size: int = 64, time_size: int = 256, repeat: int = 3, quick: bool = False,
                mode: str = "approx", log=None) -> list[dict]:
    counts = (8,) if quick else (8, 16)
    cases = scenes(size, quick)[:2]
    timed_scene = figure1_scene(time_size)
    out = []
    for filt in FILTERS:
        if log:
            log(f"patterns: filter {filt}")
        refs = [[render_scene(s, mode="reference", filter=filt) for s in group]
                for _, group in cases]
        for n in counts:
            row = dict(filter=filt, samples=n, mode=mode)
            for (case, group), group_refs in zip(cases, refs):
                row[case] = 255 * float(np.mean([
                    edge_error(render_scene(s, mode=mode, samples=n, filter=filt), r,
                               edge_mask(r)) for s, r in zip(group, group_refs)]))
            row["ms"] = 1000 * _best_time(lambda: render_scene(timed_scene, mode=mode, samples=n,
                                                               filter=filt), repeat)
            out.append(row)
    return out


def _table(rows, first, cases) -> str:
    head = "| " + " | ".join(first) + " | " + " | ".join(cases) + " | time (ms) |"
    lines = [head, "|" + "---|" * (len(first) + len(cases) + 1)]
    for r in rows:
        cells = [str(r[k]) for k in first] + [f"{r[c]:.2f}" for c in cases]
        lines.append("| " + " | ".join(cells) + f" | {r['ms']:.1f} |")
    return "\n".join(lines)


def write_study(out_dir: str, quick: bool = False, repeat: int | None = None,
                size: int | None = None, log=None) -> str:
    """``vecmsaa bench --patterns``: patterns.md (both tables) and patterns.json in out_dir."""
    import json
    import os

    os.makedirs(out_dir, exist_ok=True)
    repeat = repeat or (1 if quick else 3)
    time_size = size or (128 if quick else 256)
    err_size = 48 if quick else 64
    prow = pattern_rows(err_size, time_size, repeat, quick, log=log)
    frow = filter_rows(err_size, time_size, repeat, quick, log=log)
    cases = [c for c, _ in scenes(err_size, quick)]
    text = (f"Sample patterns at equal stored samples (approx mode): edge error ×255 against "
            f"the 1024-sample reference at {err_size} px; time of Figure 1 at {time_size} px\n\n"
            + _table(prow, ("samples", "pattern"), cases)
            + f"\n\nResolve filters (approx, D3D patterns): edge error ×255 against the reference "
            f"filtered the same way at {err_size} px; time of Figure 1 at {time_size} px\n\n"
            + _table(frow, ("filter", "samples"), cases[:2]))
    with open(os.path.join(out_dir, "patterns.md"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out_dir, "patterns.json"), "w") as f:
        json.dump(dict(patterns=prow, filters=frow), f, indent=1)
    return text
