"""``vecmsaa bench --conics``: exact conics against the cubics arcs used to be.

Circles and ellipses from a few pixels to thousands of pixels across, each drawn as conics (the
default) and as the cubic approximation (``Path.without_conics``), in the MSAA modes and the
exact-area mode, against the exact shape:

- *sample error*: the fraction of the edge pixels' samples on the wrong side of the ellipse
  (point in ellipse at every sample position: what the MSAA modes should decide exactly);
- *coverage error*: max and mean |coverage − exact area of ellipse ∩ pixel| over edge pixels
  (closed form: the disc's section integrated between its breakpoints);
- *time*: a canvas of 400 circles and ellipses, best of a few renders.

Big shapes are measured in a window on their edge at 22.5° from an axis, where a cubic quarter
strays most from the ellipse (2.7e-4 of the radius).

*Stroked circles* ("ring" rows): the circle stroked with width w, conic (its outline: two
concentric circles, exact) against the stroke of its cubics (offset cubics fitted within the
stroker's 0.25 px tolerance); the truth is the ring between the discs of radius r ± w/2 (its
samples, and its area in each pixel as the difference of the two discs').
"""
from __future__ import annotations

import json
import math
import os
import time

import numpy as np

from ..geometry.stroke import stroke_path
from ..raster.render import render_scene
from ..raster.sample_patterns import pattern_offsets
from ..scene.nodes import Fill, Group, Scene, Solid
from ..svg.shapes import ellipse_path

RADII = (4.0, 16.0, 64.0, 256.0, 1024.0, 4096.0)
#: (radius, stroke width) of the stroked circles
RINGS = ((8.0, 2.0), (64.0, 1.0), (64.0, 8.0), (1024.0, 4.0), (4096.0, 2.0))
MODES = (("persample", 16), ("approx", 16), ("approx", 4), ("alpha", 16), ("a2c", 16),
         ("analytic", 1))
WINDOW = 48


def band_area(r, x0, x1, y0, y1):
    """Exact area of the disc of radius r about the origin within [x0, x1] × [y0, y1]. The
    section's height at X is min(y1, s) − max(y0, −s), s = √(r² − X²); between breakpoints
    each bound is a constant or ±s, whose integral is (X·s + r²·asin(X/r)) / 2."""
    a, b = max(x0, -r), min(x1, r)
    if a >= b:
        return 0.0
    cuts = {a, b}
    for y in (y0, y1):
        if abs(y) < r:
            h = math.sqrt(r * r - y * y)
            cuts.update(x for x in (-h, h) if a < x < b)
    cuts = sorted(cuts)

    def S(x):
        x = min(max(x, -r), r)
        return 0.5 * (x * math.sqrt(r * r - x * x) + r * r * math.asin(x / r))

    area = 0.0
    for u, v in zip(cuts, cuts[1:]):
        m = 0.5 * (u + v)
        s = math.sqrt(max(r * r - m * m, 0.0))
        if min(y1, s) <= max(y0, -s):
            continue
        ints = S(v) - S(u)
        area += (ints if s < y1 else y1 * (v - u)) - (-ints if -s > y0 else y0 * (v - u))
    return area


def exact_coverage(cx, cy, rx, ry, w, h):
    k = rx / ry
    return np.array([[band_area(rx, px - cx, px + 1 - cx, (py - cy) * k, (py + 1 - cy) * k) / k
                      for px in range(w)] for py in range(h)])


def sample_truth(cx, cy, rx, ry, w, h, samples, hw=0.0):
    """(h, w, n) booleans: each sample inside the ellipse (hw > 0: a circle's ring of
    half width hw, between the discs of radius rx ± hw)."""
    off = pattern_offsets("d3d", samples)
    ys, xs = np.mgrid[0:h, 0:w]
    if hw > 0:
        out = []
        for ox, oy in off:
            d2 = (xs + 0.5 + ox - cx) ** 2 + (ys + 0.5 + oy - cy) ** 2
            out.append((d2 < (rx + hw) ** 2) & ~(d2 < (rx - hw) ** 2))
        return np.stack(out, axis=-1)
    return np.stack([(((xs + 0.5 + ox - cx) / rx) ** 2 + ((ys + 0.5 + oy - cy) / ry) ** 2) < 1.0
                     for ox, oy in off], axis=-1)


def cases():
    """(name, cx, cy, rx, ry, w, h, hw): whole small shapes, windows on big ones' edges;
    hw > 0 for a stroked circle (stroke width 2·hw)."""
    out = []
    for r in RADII:
        for shape, ry in (("circle", r), ("ellipse", r / 2)):
            rx = r
            if 2 * rx + 4 <= WINDOW:
                w = h = int(2 * rx + 4)
                out.append((f"{shape} r={r:g}", w / 2 + 0.3, h / 2 - 0.2, rx, ry, w, h, 0.0))
            else:
                a = math.pi / 8
                out.append((f"{shape} r={r:g}", WINDOW / 2 - rx * math.cos(a) + 0.3,
                            WINDOW / 2 + ry * math.sin(a) - 0.2, rx, ry, WINDOW, WINDOW, 0.0))
    for r, sw in RINGS:
        name = f"ring r={r:g} w={sw:g}"
        if 2 * (r + sw) + 4 <= WINDOW:
            w = h = int(2 * (r + sw) + 4)
            out.append((name, w / 2 + 0.3, h / 2 - 0.2, r, r, w, h, sw / 2))
        else:
            a = math.pi / 8
            out.append((name, WINDOW / 2 - r * math.cos(a) + 0.3,
                        WINDOW / 2 + r * math.sin(a) - 0.2, r, r, WINDOW, WINDOW, sw / 2))
    return out


def _render(path, w, h, mode, samples):
    img = render_scene(Scene(w, h, Group([Fill(path, Solid((0, 0, 0, 1)))])), mode=mode,
                       samples=samples)
    return img[..., 3].astype(np.float64)


def _sample_error(path, cx, cy, rx, ry, w, h, samples, mode, hw=0.0):
    """Fraction of the edge pixels' samples decided wrongly, from the resolved coverage (box
    filter: coverage × n is the count inside; a wrong count is at least that many errors)."""
    truth = sample_truth(cx, cy, rx, ry, w, h, samples, hw)
    inside = truth.sum(-1)
    edge = (inside > 0) & (inside < samples)
    got = np.rint(_render(path, w, h, mode, samples) * samples)
    return float(np.abs(got - inside)[edge].sum() / max(1, edge.sum() * samples))


def error_rows(log=print):
    rows = []
    for name, cx, cy, rx, ry, w, h, hw in cases():
        conic = ellipse_path(cx, cy, rx, ry)
        if hw > 0:      # the ring between two discs; the paths are the strokes' outlines
            exact = exact_coverage(cx, cy, rx + hw, rx + hw, w, h) - \
                exact_coverage(cx, cy, rx - hw, rx - hw, w, h)
            paths = (("conic", stroke_path(conic, 2 * hw)),
                     ("cubic", stroke_path(conic.without_conics(), 2 * hw)))
        else:
            exact = exact_coverage(cx, cy, rx, ry, w, h)
            paths = (("conic", conic), ("cubic", conic.without_conics()))
        edge = (exact > 1e-9) & (exact < 1 - 1e-9)
        for mode, samples in MODES:
            row = {"case": name, "mode": mode, "samples": samples}
            for kind, path in paths:
                cov = _render(path, w, h, mode, samples)
                err = np.abs(cov - exact)[edge]
                row[f"{kind}_max"] = float(err.max())
                row[f"{kind}_mean"] = float(err.mean())
                if mode != "analytic":
                    row[f"{kind}_samples"] = _sample_error(path, cx, cy, rx, ry, w, h, samples,
                                                           mode, hw)
            rows.append(row)
            log(f"conics: {name} {mode}/{samples}: mean error conic {row['conic_mean']:.5f} "
                f"cubic {row['cubic_mean']:.5f}")
    return rows


def shapes_scene(size, conics=True, count=400, seed=11):
    rng = np.random.default_rng(seed)
    fills = []
    for _ in range(count):
        cx, cy = rng.uniform(0, size, 2)
        r = float(rng.uniform(2, size / 8))
        path = ellipse_path(float(cx), float(cy), r, r * float(rng.uniform(0.3, 1.0)))
        fills.append(Fill(path if conics else path.without_conics(),
                          Solid(tuple(rng.uniform(0, 1, 3)) + (0.7,))))
    return Scene(size, size, Group(fills))


def time_rows(size=1024, repeat=3, log=print):
    rows = []
    for mode, samples in MODES:
        row = {"mode": mode, "samples": samples}
        for kind in ("conic", "cubic"):
            scene = shapes_scene(size, conics=kind == "conic")
            render_scene(scene, mode=mode, samples=samples)        # compile, warm caches
            best = math.inf
            for _ in range(repeat):
                t = time.perf_counter()
                render_scene(scene, mode=mode, samples=samples)
                best = min(best, time.perf_counter() - t)
            row[f"{kind}_ms"] = 1000 * best
        rows.append(row)
        log(f"conics: time {mode}/{samples}: conic {row['conic_ms']:.1f} ms, "
            f"cubic {row['cubic_ms']:.1f} ms")
    return rows


def markdown(result) -> str:
    """One row per shape: the sample error of persample/16 (approx/16 is the same) and the
    mean coverage error of the others, conic / cubic; then the times."""
    by = {(r["case"], r["mode"], r["samples"]): r for r in result["errors"]}
    names = list(dict.fromkeys(r["case"] for r in result["errors"]))
    cov_modes = [(m, n) for m, n in MODES if m != "persample"]
    out = ["| shape | persample/16: samples wrong | "
           + " | ".join(f"{m}/{n}: coverage" for m, n in cov_modes) + " |",
           "|---|" + "---:|" * (1 + len(cov_modes))]
    for name in names:
        p = by[(name, "persample", 16)]
        cells = [f"{p['conic_samples']:.4f} / {p['cubic_samples']:.4f}"]
        cells += [f"{by[(name, m, n)]['conic_mean']:.4f} / {by[(name, m, n)]['cubic_mean']:.4f}"
                  for m, n in cov_modes]
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    out += ["", "| mode | conic (ms) | cubic (ms) |", "|---|---:|---:|"]
    for r in result["times"]:
        out.append(f"| {r['mode']}/{r['samples']} | {r['conic_ms']:.0f} | {r['cubic_ms']:.0f} |")
    return "\n".join(out) + "\n"


def study(out_dir, size=1024, repeat=3, log=print):
    os.makedirs(out_dir, exist_ok=True)
    result = {"errors": error_rows(log), "times": time_rows(size, repeat, log),
              "time_size": size}
    with open(os.path.join(out_dir, "conics.json"), "w") as f:
        json.dump(result, f, indent=1)
    with open(os.path.join(out_dir, "conics.md"), "w") as f:
        f.write(markdown(result))
    return result
