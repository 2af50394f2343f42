"""Accuracy against FreeType: per-glyph ink and error maps.

FreeType (freetype-py) with ``FT_LOAD_NO_HINTING`` renders exact area coverage (its "smooth"
rasteriser), the independent truth vecmsaa's glyphs are measured against. The *ink* of a glyph
is the sum of its coverage in pixel units (px²); for a glyph without overlapping contours it
equals the outline's area, which :func:`outline_area` computes exactly as a third opinion.

freetype-py is a test/bench dependency, imported only here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.arclength import path_length
from ..scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path
from .compare import triptych, write_triptych

# Gauss–Legendre nodes/weights on [0, 1]: exact for x(t)·y'(t) of a cubic (degree 5).
_GL_T = (np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                   0.8611363115940526]) + 1) / 2
_GL_W = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                  0.3478548451374538]) / 2


def _bezier(ctrl, t):
    """Point and derivative of a Bézier with control points ctrl (k, 2) at parameters t."""
    n = len(ctrl) - 1
    from math import comb
    t = t[:, None]
    pt = sum(comb(n, i) * (1 - t) ** (n - i) * t ** i * ctrl[i] for i in range(n + 1))
    d = sum(comb(n - 1, i) * (1 - t) ** (n - 1 - i) * t ** i * (ctrl[i + 1] - ctrl[i])
            for i in range(n)) * n
    return pt, d


def outline_area(verbs, points) -> float:
    """Signed area enclosed by a path (closing every subpath), by Green's theorem.

    Exact for lines, quadratics and cubics (polynomial integrand, Gauss–Legendre). Positive for
    counter-clockwise contours in a y-up system.
    """
    total = 0.0
    i = 0
    start = cur = None
    for verb in verbs:
        k = VERB_POINTS[verb]
        pts = np.asarray(points[i:i + k], dtype=np.float64)
        i += k
        if verb == MOVE:
            if start is not None:
                total += _cross(cur, start)
            start = cur = pts[0]
        elif verb == LINE:
            total += _cross(cur, pts[0])
            cur = pts[0]
        elif verb in (QUAD, CUBIC):
            ctrl = np.vstack([cur, pts])
            p, d = _bezier(ctrl, _GL_T)
            total += float(np.sum(_GL_W * (p[:, 0] * d[:, 1] - p[:, 1] * d[:, 0])))
            cur = pts[-1]
        elif verb == CLOSE:
            total += _cross(cur, start)
            cur = start
    if start is not None:
        total += _cross(cur, start)
    return 0.5 * total


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


@dataclass
class FreeTypeGlyph:
    """FreeType's coverage of one glyph: (H, W) in [0, 1]; the pen origin is at pixel
    (-left, top) of the bitmap, i.e. the bitmap's top-left corner is at (left, -top) px."""
    coverage: np.ndarray
    left: int
    top: int

    @property
    def ink(self) -> float:
        return float(self.coverage.sum())


def freetype_glyph(path, gid: int, size: float, index: int = 0, location=None,
                   oversample: int = 1) -> FreeTypeGlyph:
    """Unhinted anti-aliased FreeType rendering of glyph ``gid`` at ``size`` px per em.

    FreeType flattens curves into few chords (about 1/16 px tolerance), which loses up to 10%
    of the ink of small round glyphs (a '.' at 10 px). ``oversample=k`` renders at k times the
    size and sums k x k blocks: the same exact-area coverage on the ``size`` grid with the
    flattening error k times smaller.
    """
    import freetype

    k = int(oversample)
    face = freetype.Face(str(path), index=index)
    face.set_char_size(int(round(size * k * 64)), 0, 72, 72)
    if location:
        info = face.get_variation_info()
        coords = [dict(location).get(ax.tag, ax.default) for ax in info.axes]
        face.set_var_design_coords(coords)
    face.load_glyph(int(gid), freetype.FT_LOAD_NO_HINTING | freetype.FT_LOAD_RENDER
                    | freetype.FT_LOAD_NO_BITMAP)
    slot = face.glyph
    bm = slot.bitmap
    rows, width, pitch = bm.rows, bm.width, bm.pitch
    if not (rows and width):
        return FreeTypeGlyph(np.zeros((0, 0)), 0, 0)
    buf = np.array(bm.buffer, dtype=np.uint8)
    cov = buf.reshape(rows, abs(pitch))[:, :width].astype(np.float64) / 255.0
    left, top = slot.bitmap_left, slot.bitmap_top
    if k == 1:
        return FreeTypeGlyph(cov, left, top)
    # Big bitmap spans x in [left, left+width), y (down) in [-top, -top+rows) big pixels;
    # snap that box outwards to multiples of k so that small pixels stay on the origin's grid.
    x0, y0 = left // k, (-top) // k
    x1, y1 = -(-(left + width) // k), -(-(-top + rows) // k)
    big = np.zeros(((y1 - y0) * k, (x1 - x0) * k))
    ox, oy = left - x0 * k, -top - y0 * k
    big[oy:oy + rows, ox:ox + width] = cov
    small = big.reshape(y1 - y0, k, x1 - x0, k).sum(axis=(1, 3)) / (k * k)
    return FreeTypeGlyph(small, int(x0), int(-y0))


def glyph_device_arrays(face, gid: int, size: float, origin, location=()):
    """(verbs, points) of one glyph at ``size`` px with its pen origin at ``origin`` (y down)."""
    from ..fonts.layout import glyphs_arrays, placement

    scale = size / face.units_per_em
    return glyphs_arrays(face, face.clamp_location(location), [gid],
                         placement([origin], scale))


@dataclass
class GlyphComparison:
    gid: int
    size: float
    freetype: np.ndarray       # (H, W) coverage, padded by ``pad`` pixels
    ours: np.ndarray | None    # same shape, vecmsaa's coverage (None when not rendered)
    area: float                # exact outline area in px²
    perimeter: float = 0.0     # outline length in px

    @property
    def freetype_ink(self) -> float:
        return float(self.freetype.sum())

    @property
    def ours_ink(self) -> float:
        return float(self.ours.sum()) if self.ours is not None else float("nan")

    def ink_error(self) -> float:
        """Relative ink difference of vecmsaa's rendering to FreeType's."""
        ft = self.freetype_ink
        return abs(self.ours_ink - ft) / ft if ft else 0.0

    def area_error(self) -> float:
        ft = self.freetype_ink
        return abs(self.area - ft) / ft if ft else 0.0

    def error_map(self) -> np.ndarray:
        """(H, W) ours − FreeType coverage."""
        return self.ours - self.freetype


def compare_glyph(face, gid: int, size: float, *, mode: str | None = "analytic",
                  samples: int = 8, location=(), pad: int = 2,
                  oversample: int = 1) -> GlyphComparison:
    """Render one glyph with FreeType and (unless ``mode`` is None) with vecmsaa on the same
    pixel grid; the bitmap is padded by ``pad`` pixels so no ink falls outside."""
    from ..scene.nodes import Fill, Group, Scene

    loc = face.clamp_location(location)
    ft = freetype_glyph(face.path, gid, size, face.index, dict(loc), oversample)
    h, w = ft.coverage.shape
    cov = np.zeros((h + 2 * pad, w + 2 * pad))
    if h and w:
        cov[pad:pad + h, pad:pad + w] = ft.coverage
    origin = (pad - ft.left, pad + ft.top)
    verbs, points = glyph_device_arrays(face, gid, size, origin, loc)
    area = abs(outline_area(verbs, points))
    perimeter = path_length(Path.from_arrays(verbs, points))
    ours = None
    if mode is not None:
        from ..raster.render import render_scene

        scene = Scene(cov.shape[1], cov.shape[0],
                      Group([Fill(Path.from_arrays(verbs, points))]), (0.0, 0.0, 0.0, 0.0))
        ours = np.asarray(render_scene(scene, mode=mode, samples=samples))[..., 3].astype(
            np.float64)
    return GlyphComparison(int(gid), float(size), cov, ours, area, perimeter)


def coverage_rgba(coverage: np.ndarray) -> np.ndarray:
    """A (H, W) coverage in [0, 1] as black ink: straight RGBA uint8 with that alpha."""
    img = np.zeros(coverage.shape + (4,), np.uint8)
    img[..., 3] = np.round(np.clip(coverage, 0.0, 1.0) * 255)
    return img


def error_image(comparison: GlyphComparison) -> np.ndarray:
    """FreeType | difference | vecmsaa (:func:`vecmsaa.tools.compare.triptych`), the
    difference signed: red where vecmsaa has more ink, blue where it has less."""
    return triptych(coverage_rgba(comparison.freetype), coverage_rgba(comparison.ours),
                    signed=True)


def ink_table(face, sizes, text=None, *, mode="analytic", samples=8, location=(),
              oversample=1):
    """Rows (char, gid, size, freetype ink, area, ours ink, relative error) for the bench."""
    text = text or "".join(chr(c) for c in range(0x21, 0x7F))
    rows = []
    for ch in text:
        gid = face.glyph_for_char(ch)
        if not gid:
            continue
        for size in sizes:
            c = compare_glyph(face, gid, size, mode=mode, samples=samples, location=location,
                              oversample=oversample)
            if c.freetype_ink == 0:
                continue
            rows.append((ch, gid, size, c.freetype_ink, c.area, c.ours_ink,
                         c.ink_error() if mode else c.area_error()))
    return rows


def ink_summary(face, sizes, modes, text=None, samples=8, oversample=None):
    """{mode: {size: (max per-glyph error, mean |error|, total-ink error)}} against FreeType
    (``oversample=None`` picks about 400 px per em for the reference; 1 is FreeType as is)."""
    out = {}
    for mode in modes:
        per_size = {}
        for size in sizes:
            k = oversample or max(1, -(-400 // int(size)))
            rows = ink_table(face, [size], text, mode=mode, samples=samples, oversample=k)
            errs = np.array([(r[5] - r[3]) / r[3] for r in rows])
            total = sum(r[5] for r in rows) / sum(r[3] for r in rows) - 1
            per_size[size] = (float(np.abs(errs).max()), float(np.abs(errs).mean()),
                              float(total))
        out[mode] = per_size
    return out


def write_error_maps(face, text, sizes, folder, mode="analytic", samples=8):
    """PNG error images (see :func:`error_image`) for each character and size; returns paths.
    """
    import os

    paths = []
    for ch in text:
        gid = face.glyph_for_char(ch)
        for size in sizes:
            c = compare_glyph(face, gid, size, mode=mode, samples=samples,
                              oversample=max(1, -(-400 // int(size))))
            if not c.freetype.size:
                continue
            path = os.path.join(folder, f"{mode}-{size}px-U{ord(ch):04X}.png")
            write_triptych(path, coverage_rgba(c.freetype), coverage_rgba(c.ours), signed=True)
            paths.append(path)
    return paths


def main(argv=None) -> int:
    """``python -m vecmsaa.tools.font_reference FONT``: the ink table against FreeType."""
    import argparse

    from ..fonts.face import load_face

    p = argparse.ArgumentParser(prog="python -m vecmsaa.tools.font_reference",
                                description="Per-glyph ink of vecmsaa against FreeType.")
    p.add_argument("font")
    p.add_argument("--sizes", default="10,12,16,24,36,48,72")
    p.add_argument("--modes", default="analytic,approx")
    p.add_argument("--samples", type=int, default=8)
    p.add_argument("--text", default=None, help="characters (default: printable ASCII)")
    p.add_argument("--direct", action="store_true",
                   help="compare with FreeType at the size itself (no oversampled reference)")
    p.add_argument("--maps", metavar="DIR",
                   help="also write error images (FreeType | difference | vecmsaa; red: more "
                        "ink than FreeType, blue: less) here")
    args = p.parse_args(argv)
    face = load_face(args.font)
    sizes = [float(s) for s in args.sizes.split(",")]
    modes = args.modes.split(",")
    summary = ink_summary(face, sizes, modes, args.text, args.samples,
                          1 if args.direct else None)
    print(f"{'mode':<10} {'size':>5} {'max |err|':>10} {'mean |err|':>11} {'total':>8}")
    for mode, per_size in summary.items():
        for size, (worst, mean, total) in per_size.items():
            print(f"{mode:<10} {size:>5g} {worst:>10.3%} {mean:>11.3%} {total:>8.3%}")
    if args.maps:
        for mode in modes:
            write_error_maps(face, args.text or "agH&", sizes, args.maps, mode, args.samples)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
