"""Accuracy at icon sizes: real SVG icons rendered at 16/24/32 px against ground truth.

Ground truth is the ``reference`` mode with 1024 samples per pixel (conflation-free); the
``analytic`` mode (exact area per path) is the other yardstick. An icon *passes* under the
suite's criterion (tools/compare.py: no more than 0.2% of the pixels off by more than 48/255,
which at 16 x 16 means not one pixel). The edge-pixel error is tools/accuracy.py's (× 255).

Icons are not part of the repository: point the command at folders of SVG files (e.g. a
desktop theme's symbolic icons)::

    python -m vecmsaa.tools.icons ~/icons/adwaita --sizes 16 24 32
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from ..api import load_svg, render_svg_array
from ..output.rgba8 import to_rgba8
from ..raster.render import RenderOptions, render_float
from .accuracy import GROUND_TRUTH_SAMPLES, edge_error, edge_mask
from .compare import compare_images, premultiplied_u8

#: (label, mode, samples); None is the renderer's default (16 samples up to 512 x 512 px)
CONFIGS = (("default", None, None), ("approx 8", "approx", 8), ("persample 8", "persample", 8),
           ("approx 16", "approx", 16), ("persample 16", "persample", 16),
           ("analytic", "analytic", 1))


def _render(path, size, mode, samples):
    """The straight RGBA8 image of one icon."""
    if mode is None:
        return render_svg_array(str(path), width=size, height=size)
    scene = load_svg(str(path), width=size, height=size)
    opts = RenderOptions(mode, samples)
    return to_rgba8(render_float(scene, opts))


def measure(paths, sizes=(16, 24, 32), configs=CONFIGS, log=None):
    """{(label, size): {"pass": fraction passing vs ground truth, "pass_analytic": vs
    analytic, "edge": mean edge-pixel error × 255, "bad": mean off pixels of failing icons,
    "seconds": render time}} over the icons that render."""
    stats = {}
    for size in sizes:
        for path in paths:
            try:
                truth8 = _render(path, size, "reference", GROUND_TRUTH_SAMPLES)
                exact8 = _render(path, size, "analytic", 1)
            except Exception as exc:  # an icon the renderer rejects is left out, and said
                if log:
                    log(f"skip {path.name} at {size}: {exc}")
                continue
            truth = premultiplied_u8(truth8) / 255.0
            mask = edge_mask(truth)
            for label, mode, samples in configs:
                t0 = time.perf_counter()
                img8 = exact8 if mode == "analytic" else _render(path, size, mode, samples)
                dt = time.perf_counter() - t0
                cmp = compare_images(img8, truth8)
                s = stats.setdefault((label, size), {"n": 0, "pass": 0, "pass_analytic": 0,
                                                     "edge": 0.0, "bad": 0, "seconds": 0.0})
                s["n"] += 1
                s["pass"] += cmp.passed()
                s["pass_analytic"] += compare_images(img8, exact8).passed()
                if not cmp.passed():
                    s["bad"] += cmp.off_pixels
                s["edge"] += 255.0 * edge_error(premultiplied_u8(img8) / 255.0, truth, mask)
                s["seconds"] += dt
    out = {}
    for key, s in stats.items():
        n = s["n"]
        fails = n - s["pass"]
        out[key] = {"icons": n, "pass": s["pass"] / n, "pass_analytic": s["pass_analytic"] / n,
                    "edge": s["edge"] / n, "bad": s["bad"] / fails if fails else 0.0,
                    "seconds": s["seconds"]}
    return out


def table(result, sizes) -> str:
    """Markdown: one row per configuration, per size the pass rate against ground truth
    (against analytic) and the edge-pixel error."""
    labels = list(dict.fromkeys(label for label, _ in result))
    head = "| mode | " + " | ".join(f"{s} px: pass (vs analytic) | edge err" for s in sizes) + " |"
    lines = [head, "|---|" + "---|---|" * len(sizes)]
    for label in labels:
        cells = []
        for size in sizes:
            r = result.get((label, size))
            if r is None:
                cells += ["—", "—"]
                continue
            cells += [f"{100 * r['pass']:.1f}% ({100 * r['pass_analytic']:.1f}%)",
                      f"{r['edge']:.2f}"]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def report(result, sizes) -> str:
    """How many icons, then the table."""
    n = max(r["icons"] for r in result.values()) if result else 0
    return f"{n} icons\n\n{table(result, sizes)}"


def write_study(out_dir, paths, sizes=(16, 24, 32), configs=CONFIGS, log=None) -> dict:
    """measure() the icons and write icons.md (the table) and icons.json into ``out_dir``."""
    result = measure(paths, sizes, configs, log=log)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "icons.md").write_text(report(result, sizes) + "\n")
    (out / "icons.json").write_text(json.dumps(
        [{"config": label, "size": size, **r} for (label, size), r in result.items()], indent=1))
    return result


def icon_paths(folders):
    paths = []
    for folder in folders:
        p = Path(folder)
        paths += sorted(p.rglob("*.svg")) if p.is_dir() else [p]
    return paths


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m vecmsaa.tools.icons",
                                description="Icon accuracy of the coverage modes at small sizes")
    p.add_argument("folders", nargs="+", help="folders of SVG icons (or SVG files)")
    p.add_argument("--sizes", type=int, nargs="+", default=[16, 24, 32])
    p.add_argument("--limit", type=int, default=0, help="only the first N icons")
    p.add_argument("--configs", nargs="+", metavar="LABEL", choices=[c[0] for c in CONFIGS],
                   help="only these configurations (default: all of "
                        + ", ".join(repr(c[0]) for c in CONFIGS) + ")")
    args = p.parse_args(argv)
    paths = icon_paths(args.folders)
    if args.limit:
        paths = paths[:args.limit]
    if not paths:
        print("no SVG files found", file=sys.stderr)
        return 1
    configs = [c for c in CONFIGS if not args.configs or c[0] in args.configs]
    result = measure(paths, tuple(args.sizes), configs, log=lambda m: print(m, file=sys.stderr))
    print(report(result, args.sizes))
    return 0


if __name__ == "__main__":
    sys.exit(main())
