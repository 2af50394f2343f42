"""Temporal stability (seed 002: "study sequences of images"): how much each coverage mode
flickers and crawls when a drawing moves slowly.

A still image hides what a sequence shows: an edge crossing a pixel by 1/64 px a frame should
change that pixel's value by a steady 1/64 of the colour difference each frame. Sampling adds a
staircase (a value that sticks, then jumps by 1/n), and a pattern's sample positions decide
where the jumps fall. Three measures, each against ground truth:

- **flicker**: per pixel, the frame-to-frame change minus the reference's frame-to-frame change
  (256 stratified samples per pixel), in 8-bit levels; the mean over pixels that change in
  either, and the 99th percentile;
- **crawl**: a straight edge 1/16 off horizontal moving down by one pixel over the sequence;
  per column the edge's position is the column's coverage sum, and its exact value is the area
  of the half-plane inside the column, computed in closed form; the difference's mean over
  columns and frames (**offset**: the whole image shifted) and its RMS about that mean, in
  pixels;
- **jitter**: the same difference's frame-to-frame change (a steady offset does not crawl).

``python -m vecmsaa.tools.sequence -o OUT`` (or ``vecmsaa bench --sequence -o OUT``) writes
sequence.md, sequence.json, an animated WebP per case for viewing (the reference beside every
mode) and sequence.png, a bar plot of the flicker.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

from ..raster.modes import MSAA_MODES, PATTERN_NAMES
from ..scene.nodes import Fill, Group, Scene, Solid
from ..scene.path import Path
from ..scene.transform import compose, rotate_at, translate

#: coverage modes compared (the reference is the truth)
SEQUENCE_MODES = MSAA_MODES + ("analytic",)
FRAMES = 64
SIZE = 96


def _scale_at(factor, cx, cy):
    return compose(translate(cx, cy), compose((factor, 0.0, 0.0, factor, 0.0, 0.0),
                                              translate(-cx, -cy)))


def motion(name: str, t: float, size: int):
    """The affine (a, b, c, d, e, f) at time t in [0, 1]: slow, sub-pixel movements."""
    c = size / 2
    if name == "pan":        # one pixel right and 0.37 down over the sequence
        return translate(t, 0.37 * t)
    if name == "zoom":       # 1 -> 1.05 about the centre: edges move up to 2.4 px
        return _scale_at(1.0 + 0.05 * t, c, c)
    if name == "rotate":     # 0 -> 2 degrees about the centre
        return rotate_at(2.0 * t, c, c)
    raise ValueError(f"unknown motion {name!r}")


MOTIONS = ("pan", "zoom", "rotate")


def scenes(size: int) -> dict:
    """The drawings that move: Figure 1 (a shared curved boundary), thin map-like lines and
    small text (glyph-shaped outlines, about 9 px per em)."""
    from .accuracy import figure1_scene
    from .bench import text_scene, thin_lines_scene
    return {"figure1": figure1_scene(size), "thin-lines": thin_lines_scene(size, count=60),
            "text": text_scene(size, em=9.0)}


def moved(scene: Scene, m) -> Scene:
    """The scene's solid fills with every path mapped through ``m``."""
    fills = [Fill(f.path.transformed(m), f.paint, f.rule, f.opacity, f.antialias)
             for f in scene.fills()]
    return Scene(scene.width, scene.height, Group(fills), background=scene.background)


def render_frames(frames, mode: str, samples: int, pattern: str = "d3d") -> np.ndarray:
    """(T, H, W, 4) premultiplied float32 renders of the frames."""
    from ..raster.render import render_scene
    return np.stack([render_scene(f, mode=mode, samples=samples, pattern=pattern)
                     for f in frames])


def flicker(sequence: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    """(mean, 99th percentile) over changing pixels of |Δ frame − Δ reference|, in 8-bit
    levels, the largest over the channels."""
    d = np.diff(sequence, axis=0) - np.diff(reference, axis=0)
    err = np.abs(d).max(axis=-1) * 255.0
    moving = (np.abs(np.diff(sequence, axis=0)).max(axis=-1) > 0) | \
             (np.abs(np.diff(reference, axis=0)).max(axis=-1) > 0)
    if not moving.any():
        return 0.0, 0.0
    return float(err[moving].mean()), float(np.percentile(err[moving], 99))


# -- a slowly moving straight edge --------------------------------------------------------------
EDGE_SLOPE = 1.0 / 16


def edge_frames(size: int, count: int) -> list[Scene]:
    """A black half-plane y > y0 + slope·x on white, y0 going from size/2 to size/2 + 1. It
    reaches 2 px beyond the image on the left, right and bottom: patterns with samples on the
    pixel's edges (quincunx, FLIPQUAD) and wide filters see that far."""
    out = []
    for k in range(count):
        y0 = size / 2 + k / count
        p = Path()
        p.moveTo((-2.0, y0 - 2 * EDGE_SLOPE))
        p.lineTo((size + 2.0, y0 + EDGE_SLOPE * (size + 2)))
        p.lineTo((size + 2.0, size + 2.0))
        p.lineTo((-2.0, size + 2.0))
        p.closePath()
        out.append(Scene(size, size, Group([Fill(p, Solid((0, 0, 0, 1)))]),
                         background=(0, 0, 0, 0)))
    return out


def exact_edge_columns(size: int, count: int) -> np.ndarray:
    """(T, W): per frame and pixel column, the exact area of the half-plane inside the
    column's [0, size] rows (the line y = y0 + slope·x stays inside them)."""
    # area below the line over the column [x, x+1]: size - the line's height at x + 1/2
    centres = np.arange(size, dtype=np.float64) + 0.5
    y0 = size / 2 + np.arange(count)[:, None] / count
    return size - (y0 + EDGE_SLOPE * centres)


def crawl(mode: str, samples: int, pattern: str = "d3d", size: int = 64,
          count: int = FRAMES) -> tuple[float, float, float]:
    """(offset, crawl, jitter) of the moving edge, in pixels: the mean of its position error
    (a pattern whose samples are not centred on the pixel shifts the whole image, e.g. the
    jittered and Poisson patterns, and the D3D 16 table by 1/32 px before it was centred),
    the RMS of the error about that mean, and the RMS of its frame-to-frame change."""
    alpha = render_frames(edge_frames(size, count), mode, samples, pattern)[..., 3]
    err = alpha.sum(axis=1) - exact_edge_columns(size, count)
    offset = float(err.mean())
    return (offset, float(np.sqrt(((err - offset) ** 2).mean())),
            float(np.sqrt((np.diff(err, axis=0) ** 2).mean())))


# -- the whole study ------------------------------------------------------------------------------
def configurations(samples, patterns):
    """(mode, samples, pattern) compared: every multisample mode at each count and pattern
    (a pattern of one sample count at that count, once; a2c only with a pixel's own samples);
    ``none`` (one sample at the centre) and ``analytic`` once, with samples 0."""
    from ..raster.sample_patterns import FIXED_SAMPLES, sample_pattern
    for mode in SEQUENCE_MODES:
        if mode in ("none", "analytic"):
            yield mode, 0, "d3d"
            continue
        for pattern in patterns:
            for n in sorted({FIXED_SAMPLES.get(pattern, n) for n in samples}):
                if mode == "a2c" and not sample_pattern(pattern, n).per_pixel:
                    continue
                yield mode, n, pattern
def study(out_dir: str, size: int = SIZE, count: int = FRAMES, samples=(8, 16),
          patterns=PATTERN_NAMES, log=print) -> list[dict]:
    """Every scene x motion x mode x samples x pattern; writes the files named above and
    returns the rows."""
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for scene_name, scene in scenes(size).items():
        for motion_name in MOTIONS:
            frames = [moved(scene, motion(motion_name, k / (count - 1), size))
                      for k in range(count)]
            reference = render_frames(frames, "reference", 256)
            shown = {"reference": reference}
            for mode, n, pattern in configurations(samples, patterns):
                seq = render_frames(frames, mode, n or 8, pattern)
                mean, p99 = flicker(seq, reference)
                rows.append(dict(scene=scene_name, motion=motion_name, mode=mode, samples=n,
                                 pattern=pattern, flicker=mean, flicker_p99=p99))
                if pattern == "d3d" and n in (0, samples[0]):
                    shown[mode] = seq
            log(f"  {scene_name} {motion_name}: done")
            write_webp(os.path.join(out_dir, f"{scene_name}-{motion_name}.webp"), shown)
    for mode, n, pattern in configurations(samples, patterns):
        offset, position, jitter = crawl(mode, n or 8, pattern, count=count)
        rows.append(dict(scene="edge", motion="crawl", mode=mode, samples=n, pattern=pattern,
                         offset=offset, crawl=position, jitter=jitter))
    with open(os.path.join(out_dir, "sequence.json"), "w") as f:
        json.dump(rows, f, indent=1)
    with open(os.path.join(out_dir, "sequence.md"), "w") as f:
        f.write(table(rows))
    write_plot(os.path.join(out_dir, "sequence.png"), rows)
    return rows


def table(rows) -> str:
    """Markdown: flicker per mode (columns) and case (rows), then the edge's crawl."""
    keys = sorted({(r["mode"], r["samples"], r["pattern"]) for r in rows},
                  key=lambda k: (SEQUENCE_MODES.index(k[0]), k[1], k[2]))
    label = {k: (k[0] if not k[1] else f"{k[0]} {k[1]} {k[2]}") for k in keys}
    cases = sorted({(r["scene"], r["motion"]) for r in rows if "flicker" in r})
    lines = ["Flicker: mean |Δframe − Δreference| over changing pixels, 8-bit levels "
             "(99th percentile in brackets)", "",
             "| case | " + " | ".join(label[k] for k in keys) + " |",
             "|---|" + "---|" * len(keys)]
    by = {(r["scene"], r["motion"], r["mode"], r["samples"], r["pattern"]): r for r in rows}
    for case in cases:
        cells = []
        for k in keys:
            r = by.get(case + k)
            cells.append(f"{r['flicker']:.2f} ({r['flicker_p99']:.0f})" if r else "")
        lines.append(f"| {case[0]} {case[1]} | " + " | ".join(cells) + " |")
    lines += ["", "A moving edge's position per column against its exact coverage, in pixels: "
              "mean (offset), RMS about the mean (crawl), RMS frame-to-frame change (jitter)",
              "", "| mode | offset | crawl | jitter |", "|---|---|---|---|"]
    for k in keys:
        r = by.get(("edge", "crawl") + k)
        if r:
            lines.append(f"| {label[k]} | {r['offset']:+.4f} | {r['crawl']:.4f} | "
                         f"{r['jitter']:.4f} |")
    return "\n".join(lines) + "\n"


def write_webp(path: str, shown: dict) -> None:
    """An animated WebP: the reference and each mode side by side, 3× magnified."""
    from PIL import Image

    from ..output.rgba8 import to_rgba8

    names = list(shown)
    t, h, w = shown[names[0]].shape[:3]
    images = []
    for k in range(t):
        row = np.concatenate([to_rgba8(shown[n][k]) for n in names], axis=1)
        images.append(Image.fromarray(row).resize((row.shape[1] * 3, h * 3), Image.NEAREST))
    images[0].save(path, save_all=True, append_images=images[1:], duration=60, loop=0,
                   lossless=True)


def write_plot(path: str, rows) -> None:
    """Bars of the mean flicker per mode (d3d pattern, first sample count), one group per
    case, drawn with Pillow."""
    from PIL import Image, ImageDraw

    cases = sorted({(r["scene"], r["motion"]) for r in rows if "flicker" in r})
    first = min(r["samples"] for r in rows if r["samples"])
    bars = SEQUENCE_MODES
    value = {(r["scene"], r["motion"], r["mode"]): r["flicker"] for r in rows
             if "flicker" in r and r["pattern"] == "d3d" and r["samples"] in (0, first)}
    top = max(value.values()) or 1.0
    bw, gap, height = 10, 16, 220
    width = len(cases) * (len(bars) * bw + gap) + 40
    img = Image.new("RGB", (width, height + 90), "white")
    draw = ImageDraw.Draw(img)
    palette = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
               (140, 86, 75)]
    for i, case in enumerate(cases):
        x0 = 30 + i * (len(bars) * bw + gap)
        for j, mode in enumerate(bars):
            v = value.get(case + (mode,), 0.0)
            y = height - int(v / top * (height - 20))
            draw.rectangle([x0 + j * bw, y, x0 + (j + 1) * bw - 2, height],
                           fill=palette[j % len(palette)])
        draw.text((x0, height + 4), case[0][:8], fill="black")
        draw.text((x0, height + 16), case[1], fill="black")
    for j, mode in enumerate(bars):
        draw.rectangle([30 + j * 90, height + 40, 40 + j * 90, height + 50],
                       fill=palette[j % len(palette)])
        draw.text((44 + j * 90, height + 39), mode, fill="black")
    draw.text((30, 4), f"mean flicker (8-bit levels), {first} samples, top {top:.1f}",
              fill="black")
    img.save(path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m vecmsaa.tools.sequence",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--out-dir", required=True)
    ap.add_argument("--size", type=int, default=SIZE, help=f"frame size [{SIZE}]")
    ap.add_argument("--frames", type=int, default=FRAMES, help=f"frames [{FRAMES}]")
    args = ap.parse_args(argv)
    study(args.out_dir, args.size, args.frames,
          log=lambda s: print(s, file=sys.stderr, flush=True))
    print(f"results in {args.out_dir}/ (sequence.md, sequence.json, sequence.png, *.webp)",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
