#!/usr/bin/env python3
"""Find the resvg suite tests whose reference carries an artifact of resvg's per-pixel
rasterisation, and write their exact references (supersampled resvg renders).

    python tools/make_exact_refs.py [SUITE] [--resvg PATH] [--out vecmsaa/data/exact-refs]

resvg composites each shape's antialiased coverage per pixel and renders patterns at device
resolution, so a reference keeps a fringe where one shape covers an identical one (red "should be
covered" or "hovered"), along edges where shapes touch, and pixel-grid patterns. Rendered at 8
times the resolution and box-filtered down, the same renderer's drawing has those artifacts
reduced eightfold (the fringe below 8/255), so it is the drawing's area coverage to within the
criterion: an exact reference by an independent renderer.

A test is selected without looking at vecmsaa: when resvg here renders it identically to its
reference (the same behaviour as the resvg that made the suite) and that render fails the
project criterion against the supersampled render (the reference carries the artifact). Tests
that ``exact-refs/`` beside the suite or vecmsaa.tools.suite_truth already cover are skipped, and so are tests with filters
raster images, bitmap glyphs, aliased shapes or patterns: those are defined on device pixels
(a convolution kernel, an image's resampling, pixel centres), or resvg makes them so (pattern
tiles of whole pixels), so a render at another resolution is a different drawing, not a finer one.
Needs the resvg binary.

A test in which a shape repeats an earlier sibling exactly gets, as the issue's ``exact-refs/``
do for covered shapes, resvg's 1x render with the copy removed instead (:func:`without_duplicates`),
chosen for the copy alone, like those.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from vecmsaa.tools.compare import channel_difference, compare_images  # noqa: E402
from vecmsaa.tools.suite import EXACT_REFS, SUITE_FONTS, collect, tests_root  # noqa: E402
from vecmsaa.tools.suite_truth import TRUTHS  # noqa: E402

FACTOR = 8
#: what is defined on device pixels: filters, raster images, bitmap glyphs (sbix, CBDT fonts),
#: aliased shapes (shape-rendering crispEdges / optimizeSpeed), and patterns, whose tiles resvg
#: renders at a whole number of device pixels (so its tiling drifts with the resolution)
RESOLUTION_BOUND = (b"<filter", b"filter=", b"<image", b"<feImage", b"SBIX",
                    b'Noto Color Emoji"', b"Noto Color Emoji,", b"crispEdges", b"optimizeSpeed",
                    b"<pattern")
RESVG_FONT_FLAGS = {"font_family": "--font-family", "serif_family": "--serif-family",
                    "sans_serif_family": "--sans-serif-family",
                    "cursive_family": "--cursive-family", "fantasy_family": "--fantasy-family",
                    "monospace_family": "--monospace-family"}


def resvg(binary, suite, svg, width, height, out):
    args = [binary, "-w", str(width), "-h", str(height), "--skip-system-fonts",
            "--use-fonts-dir", os.path.join(suite, "fonts"),
            "--resources-dir", os.path.join(suite, "resources")]
    for key, flag in RESVG_FONT_FLAGS.items():
        args += [flag, SUITE_FONTS[key]]
    run = subprocess.run(args + [svg, out], capture_output=True, timeout=120)
    if run.returncode != 0 or not os.path.exists(out):
        return None
    with Image.open(out) as im:
        return np.asarray(im.convert("RGBA"))


def box_down(rgba, factor):
    """Box-filter straight RGBA down by ``factor`` (averaged premultiplied)."""
    h, w = rgba.shape[0] // factor, rgba.shape[1] // factor
    a = rgba.astype(np.float64) / 255
    pm = np.concatenate([a[..., :3] * a[..., 3:], a[..., 3:]], -1)
    pm = pm.reshape(h, factor, w, factor, 4).mean(axis=(1, 3))
    alpha = pm[..., 3:]
    rgb = np.where(alpha > 0, pm[..., :3] / np.maximum(alpha, 1e-12), 0)
    return np.round(np.concatenate([rgb, alpha], -1) * 255).astype(np.uint8)


SHAPES = ("path", "rect", "circle", "ellipse", "line", "polyline", "polygon")


def without_duplicates(source: bytes):
    """The document without the shapes that repeat an earlier sibling exactly (every attribute
    but ``id``, no opacity), or None when there are none. Painting an opaque shape again on
    itself changes nothing, so the copy is a covered element: only per-pixel compositing shows
    it, as a fringe along its edges."""
    import re

    seen, drop = set(), []
    for m in re.finditer(rb"<(" + b"|".join(t.encode() for t in SHAPES) + rb")\b([^>]*?)/>",
                         source):
        attrs = re.sub(rb'\s+id="[^"]*"', b"", m.group(2))
        key = (m.group(1), b" ".join(attrs.split()))
        if b"opacity" in attrs:
            continue
        if key in seen:
            drop.append(m.span())
        seen.add(key)
    if not drop:
        return None
    for start, end in reversed(drop):
        source = source[:start] + source[end:]
    return source


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("suite", nargs="?", default=os.path.join(HERE, "..", "..", "shared",
                                                             "resvg-suite"))
    ap.add_argument("--resvg", default="/tmp/resvgbin/resvg")
    ap.add_argument("--out", default=os.path.join(HERE, "..", "vecmsaa", "data", "exact-refs"))
    ap.add_argument("--only", action="append", default=[])
    args = ap.parse_args(argv)
    suite, tests = tests_root(args.suite)
    written = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name in collect(tests, only=args.only):
            if os.path.exists(os.path.join(suite, EXACT_REFS, name + ".png")) or name in TRUTHS:
                continue
            svg = os.path.join(tests, name + ".svg")
            with open(svg, "rb") as f:
                source = f.read()
            if name.startswith("filters/") or any(tag in source for tag in RESOLUTION_BOUND):
                continue
            with Image.open(os.path.join(tests, name + ".png")) as im:
                ref = np.asarray(im.convert("RGBA"))
            h, w = ref.shape[:2]
            one = resvg(args.resvg, suite, svg, w, h, os.path.join(tmp, "one.png"))
            if one is None or one.shape != ref.shape:
                continue
            diff = channel_difference(one, ref)
            if diff is None or diff.max() > 0:
                continue            # this resvg draws the test differently from the suite's
            single = without_duplicates(source)
            if single is not None:      # the method: resvg with the copy removed
                with open(os.path.join(tmp, "single.svg"), "wb") as f:
                    f.write(single)
                exact = resvg(args.resvg, suite, os.path.join(tmp, "single.svg"), w, h,
                              os.path.join(tmp, "single.png"))
                if exact is None or exact.shape != ref.shape:
                    continue
            else:
                big = resvg(args.resvg, suite, svg, w * FACTOR, h * FACTOR,
                            os.path.join(tmp, "big.png"))
                if big is None or big.shape[:2] != (h * FACTOR, w * FACTOR):
                    continue
                exact = box_down(big, FACTOR)
            if single is None and compare_images(one, exact).passed():
                continue            # no artifact the criterion sees
            path = os.path.join(args.out, name + ".png")
            os.makedirs(os.path.dirname(path), exist_ok=True)
            Image.fromarray(exact).save(path, optimize=True)
            written += 1
            print(name, compare_images(one, exact).describe(), flush=True)
    print(f"{written} exact references written to {args.out}")


if __name__ == "__main__":
    main()
