"""Strokes at most a device pixel wide as Skia's antialiased hairlines (geometry.hairline).

The expected coverages are written out by hand from Skia's rule (SkScan_Antihair): per step
of the major axis, the line's minor coordinate c at the step's centre; the band [c - ½, c + ½]
across the step gives each pixel its overlap with the band, times the fraction of the step
the segment covers. Images are drawn in the exact-area mode."""
import math

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.geometry.hairline import hairline_coverage
from vecmsaa.scene.transform import IDENTITY

TOL = 1.5 / 255


def coverage(body, size=24, mode="analytic"):
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}">'
           f'{body}</svg>').encode()
    return render_svg_array(svg, mode=mode)[..., 3] / 255.0


def line(x0, y0, x1, y1, extra=""):
    return (f'<path d="M{x0} {y0} L{x1} {y1}" fill="none" stroke="black" '
            f'stroke-width="1" {extra}/>')


def test_coverage_is_skias_fast_length_rule():
    assert hairline_coverage(1.0, IDENTITY, True) == 1.0
    # int(0.5 * 256) = 128, (255 * 128) >> 8 = 127: tiny-skia's pre-scaled alpha
    assert hairline_coverage(0.5, IDENTITY, True) == pytest.approx(127 / 255)
    assert hairline_coverage(1.01, IDENTITY, True) is None
    assert hairline_coverage(0.5, IDENTITY, False) is None          # crispEdges
    assert hairline_coverage(0.0, IDENTITY, True) is None           # no stroke in SVG
    c, s = math.cos(math.pi / 4), math.sin(math.pi / 4)
    # (0.707, 0.707): 0.707 + 0.354 > 1, so a 45° rotated 1-unit stroke is no hairline
    assert hairline_coverage(1.0, (c, s, -s, c, 0, 0), True) is None
    # (0.6, 0) and (0, 2.4) under scale(1 4) with width 0.6: the longer one decides
    assert hairline_coverage(0.6, (1, 0, 0, 4, 0, 0), True) is None
    # (0.4, 0.2): 0.4 + 0.1 = 0.5 each under rotate(atan(½)) · scale(0.4 · √5 / 2)
    assert hairline_coverage(1.0, (0.4, 0.2, -0.2, 0.4, 3, 7), True) == \
        pytest.approx(((255 * int(0.5 * 256)) >> 8) / 255)


def test_45_degree_line_is_one_full_pixel_per_step():
    """|dx| = |dy|: stepped by rows; x at each row's centre is that row's pixel centre."""
    a = coverage(line(2, 2, 10, 10))
    expected = np.zeros_like(a)
    for r in range(2, 10):
        expected[r, r] = 1.0
    np.testing.assert_allclose(a, expected, atol=TOL)


def test_shallow_line_splits_each_column_between_two_rows():
    # slope ¼, from (0.5, 5.5) to (20.5, 10.5): the centre of column i is y = 5.5 + i / 4
    a = coverage(line(0.5, 5.5, 20.5, 10.5))
    assert a[5, 0] == pytest.approx(0.5, abs=TOL)          # half the column, band [5, 6]
    assert a[:, 0].sum() == pytest.approx(0.5, abs=TOL)
    assert (a[5, 1], a[6, 1]) == pytest.approx((0.75, 0.25), abs=TOL)   # band [5.25, 6.25]
    assert (a[5, 2], a[6, 2]) == pytest.approx((0.5, 0.5), abs=TOL)
    assert (a[5, 3], a[6, 3]) == pytest.approx((0.25, 0.75), abs=TOL)
    assert a[6, 4] == pytest.approx(1.0, abs=TOL)          # band [6, 7]
    assert a[10, 20] == pytest.approx(0.5, abs=TOL)        # the last half column, [10, 11]
    # one pixel of ink in every whole column
    np.testing.assert_allclose(a[:, 1:20].sum(axis=0), 1.0, atol=2 * TOL)
    assert a[:, 21:].max() == 0


def test_steep_line_with_fractional_ends():
    # slope ¼ in x per row, from (3.25, 1.5) to (5.25, 9.5): row r's centre at
    # x = 3.25 + (r - 1) / 4; the first and last rows half covered
    a = coverage(line(3.25, 1.5, 5.25, 9.5))
    assert (a[1, 2], a[1, 3]) == pytest.approx((0.125, 0.375), abs=TOL)   # [2.75, 3.75] · ½
    assert (a[2, 3]) == pytest.approx(1.0, abs=TOL)                       # [3, 4]
    assert (a[3, 3], a[3, 4]) == pytest.approx((0.75, 0.25), abs=TOL)     # [3.25, 4.25]
    assert (a[9, 4], a[9, 5]) == pytest.approx((0.125, 0.375), abs=TOL)   # [4.75, 5.75] · ½
    assert a[0].max() == 0 and a[10:].max() == 0


def test_caps_lengthen_the_ends_by_half_a_pixel_or_pi_over_8():
    a = coverage(line(2, 4.5, 6, 4.5, 'stroke-linecap="square"'))
    np.testing.assert_allclose(a[4, 1:8], [0.5, 1, 1, 1, 1, 0.5, 0], atol=TOL)
    a = coverage(line(2, 4.5, 6, 4.5, 'stroke-linecap="round"'))
    np.testing.assert_allclose(a[4, 1:7], [math.pi / 8, 1, 1, 1, 1, math.pi / 8], atol=TOL)
    a = coverage(line(2, 4.5, 6, 4.5))
    np.testing.assert_allclose(a[4, 1:8], [0, 1, 1, 1, 1, 0, 0], atol=TOL)


def test_thinner_stroke_is_the_same_hairline_faded():
    a = coverage(line(0.5, 5.5, 20.5, 10.5).replace('stroke-width="1"',
                                                     'stroke-width="0.5"'))
    b = coverage(line(0.5, 5.5, 20.5, 10.5))
    np.testing.assert_allclose(a, b * 127 / 255, atol=TOL)


def test_segments_of_both_major_axes_unite():
    """An x-major and a y-major segment meeting: their polygons have one orientation, so the
    pixels both cover are covered (not cancelled by opposite windings), and never more."""
    a = coverage('<path d="M2 2.5 L12 4.5 L14.5 16" fill="none" stroke="black"/>')
    b = coverage(line(2, 2.5, 12, 4.5))
    c = coverage(line(12, 4.5, 14.5, 16))
    assert a.max() <= 1.0 + TOL
    assert (a >= np.maximum(b, c) - TOL).all()


def test_runs_of_paths_draw_what_single_paths_draw():
    """Sibling paths sharing a style go to the batch kernel; the same paths with a style
    attribute each go through stroke(): the same pixels."""
    ds = ["M1 1 L30 9 L12 30", "M3 20 h20 v5 h-20 z", "M5 5 L5 5", "M2 28 L29 2 M4 4 l1 20"]
    run = "".join(f'<path d="{d}"/>' for d in ds)
    alone = "".join(f'<path d="{d}" style="stroke-linecap: round"/>' for d in ds)
    g = '<g fill="none" stroke="black" stroke-width="0.7" {}>{}</g>'
    a = coverage(g.format('stroke-linecap="round"', run), size=32, mode="persample")
    b = coverage(g.format("", alone), size=32, mode="persample")
    np.testing.assert_array_equal(a, b)
    assert a.max() > 0


def _count_calls(monkeypatch, module, name):
    calls = []
    original = getattr(module, name)

    def counted(*args, **kws):
        calls.append(name)
        return original(*args, **kws)
    monkeypatch.setattr(module, name, counted)
    return calls


@pytest.mark.parametrize("fill", ["none", "teal"])
def test_runs_of_curved_paths_draw_what_single_paths_draw(fill, monkeypatch):
    """Sibling curved paths sharing a style (quadratics, cubics, arcs: conics) go to the
    batch kernel in one call, none through hairline_segments; the same paths with a style
    attribute each go through stroke(): the same pixels, filled or not. A circle's stroke
    alone is one kernel call too."""
    from vecmsaa.geometry import hairline_kernels
    from vecmsaa.svg import builder
    ds = ["M1 1 Q30 2 12 30", "M3 20 C10 0 20 40 29 20 Z", "M16 16 A9 5 30 1 1 16 17",
          "M2 28 L29 2 M4 4 a4 4 0 0 0 8 0", "M5 5 L5 5"]
    run = "".join(f'<path d="{d}"/>' for d in ds)
    alone = "".join(f'<path d="{d}" style="stroke-linecap: square"/>' for d in ds)
    g = f'<g fill="{fill}" stroke="black" stroke-width="0.7" {{}}>{{}}</g>'
    kernel = _count_calls(monkeypatch, hairline_kernels, "hairline_paths_batch")
    segments = _count_calls(monkeypatch, builder, "hairline_segments")
    a = coverage(g.format('stroke-linecap="square" stroke-opacity="0.7"', run), size=32)
    assert (len(kernel), len(segments)) == (1, 0)
    # (each through element() and stroke(): sibling shapes are otherwise one run too)
    monkeypatch.setattr(builder.Builder, "shape_runs", False)
    b = coverage(g.format('stroke-opacity="0.7"', alone), size=32)
    assert (len(kernel), len(segments)) == (1 + len(ds), 0)
    np.testing.assert_array_equal(a, b)
    assert a.max() > 0
    c = coverage('<circle cx="12" cy="12" r="7" fill="none" stroke="black" '
                 'stroke-width="0.5"/>')
    assert (len(kernel), len(segments)) == (2 + len(ds), 0)
    assert c.max() > 0


def test_very_long_hairline_is_bounded():
    """A line a hundred million pixels long: steps past the limits become one parallelogram,
    so the outline stays a few points; inside the picture still one pixel of ink a column."""
    a = coverage(line(-1e8, -0.25e8 + 5.5, 1e8, 0.25e8 + 5.5))
    np.testing.assert_allclose(a.sum(axis=0), 1.0, atol=0.1)


def test_overlapping_segments_of_one_path_add_up_as_skias_blend_each():
    """Skia blends each segment of a hairline on its own: where two segments of one path
    cross, a stroke of opacity ½ leaves 1 - ½ · ½ = ¾ there, ½ elsewhere on either."""
    for d in ("M2 10.5 H20 M10.5 2 V20",            # two subpaths
              "M2 10.5 H20 V2 H10.5 V20"):          # one, crossing itself
        a = coverage(f'<path d="{d}" fill="none" stroke="black" stroke-opacity="0.5"/>')
        assert a[10, 10] == pytest.approx(0.75, abs=TOL)
        assert a[10, 5] == pytest.approx(0.5, abs=TOL)
        assert a[15, 10] == pytest.approx(0.5, abs=TOL)


def test_segments_meeting_within_a_step_blend_as_skias_each():
    """Skia blends each segment on its own, so where two segments of one path share a step
    the pixel is a + b - ab (with the paint's alpha in a and b), not a + b: a straight line
    cut at x = 3.5 leaves ½ + ½ - ¼ = ¾ in column 3, ¼ + ¼ - 1/16 = 7/16 at opacity ½."""
    a = coverage('<path d="M0 5.5 L3.5 5.5 L8 5.5" fill="none" stroke="black"/>')
    np.testing.assert_allclose(a[5, :9], [1, 1, 1, 0.75, 1, 1, 1, 1, 0], atol=TOL)
    a = coverage('<path d="M0 5.5 L3.5 5.5 L8 5.5" fill="none" stroke="black" '
                 'stroke-opacity="0.5"/>')
    assert a[5, 3] == pytest.approx(7 / 16, abs=TOL)
    assert a[5, 2] == pytest.approx(0.5, abs=TOL)
    # three segments in column 3 (0.2, 0.4 and 0.4 of it): 1 - 0.8 · 0.6 · 0.6
    a = coverage('<path d="M0 5.5 L3.2 5.5 L3.6 5.5 L8 5.5" fill="none" stroke="black"/>')
    assert a[5, 3] == pytest.approx(1 - 0.8 * 0.6 * 0.6, abs=TOL)
    # a bend in the step: the second segment's band at the column's centre (x = 3.5) is
    # [5, 6], so row 5 takes ½ from each; in column 4 its centre y = 5.5 + 4/9 splits it
    a = coverage('<path d="M0 5.5 L3.5 5.5 L8 7.5" fill="none" stroke="black"/>')
    assert (a[5, 3], a[6, 3]) == pytest.approx((0.75, 0), abs=TOL)
    assert (a[5, 4], a[6, 4]) == pytest.approx((5 / 9, 4 / 9), abs=TOL)


def test_closed_subpath_has_no_caps():
    """A closed subpath has no ends to cap (SVG's stroke-linecap; Chromium draws it so):
    the rectangle's left side is the closing line x = 2 alone with any cap. (tiny-skia
    lengthens the first line's start and the last line's end, and closes to the moved start,
    which slants the closing line: resvg's departure.)"""
    d = '<path d="M2 4.5 H10 V6.5 H2 Z" fill="none" stroke="black" {}/>'
    butt = coverage(d.format(""))
    assert (butt[5, 1], butt[5, 2]) == pytest.approx((0.5, 0.5), abs=TOL)
    for cap in ("round", "square"):
        np.testing.assert_array_equal(coverage(d.format(f'stroke-linecap="{cap}"')), butt)


def _skia_hairline(segments, size, alpha):
    """Skia's rule written out in floating point: per segment and step of its major axis,
    one pixel of ink split between the two pixels the band [c - ½, c + ½] overlaps (c at the
    step's centre), times the part of the step the segment covers; each segment blended on
    its own with ``alpha``."""
    out = np.zeros((size, size))
    for x0, y0, x1, y1 in segments:
        cov = np.zeros((size, size))
        ymaj = abs(x1 - x0) <= abs(y1 - y0)
        u0, v0, u1, v1 = (y0, x0, y1, x1) if ymaj else (x0, y0, x1, y1)
        if u0 > u1:
            u0, v0, u1, v1 = u1, v1, u0, v0
        for col in range(math.floor(u0), math.ceil(u1)):
            f = min(u1, col + 1) - max(u0, col)
            c = v0 + (v1 - v0) / (u1 - u0) * (col + 0.5 - u0)
            r = math.floor(c - 0.5)
            for row, share in ((r, r + 1 - (c - 0.5)), (r + 1, (c - 0.5) - r)):
                cov[(col, row) if ymaj else (row, col)] += f * share
        out += alpha * cov * (1 - out)
    return out


@pytest.mark.parametrize("seed", range(6))
def test_polylines_of_short_segments_are_skias_blend_of_each(seed, monkeypatch):
    """Brute force: random polylines of 0.3-2 px segments turning a little (many meet within
    a step), drawn with staircases only (no parallelograms), against Skia's rule computed
    segment by segment (_skia_hairline)."""
    from vecmsaa.geometry import hairline
    monkeypatch.setattr(hairline, "STAIR_SLOPE", 0.0)
    rng = np.random.default_rng(seed)
    ang = rng.uniform(0, 2 * np.pi) + np.cumsum(rng.uniform(-0.3, 0.3, 40))
    step = rng.uniform(0.3, 2.0, 40)
    pts = np.c_[16 + np.cumsum(step * np.cos(ang)), 16 + np.cumsum(step * np.sin(ang))]
    pts = np.clip(pts, 2, 30)
    opacity = [1.0, 0.6][seed % 2]
    d = "M" + " L".join(f"{x:.6f} {y:.6f}" for x, y in pts)
    a = coverage(f'<path d="{d}" fill="none" stroke="black" stroke-opacity="{opacity}"/>',
                 size=32)
    segs = [(*pts[i], *pts[i + 1]) for i in range(len(pts) - 1)]
    np.testing.assert_allclose(a, _skia_hairline(segs, 32, opacity), atol=TOL)


@pytest.mark.parametrize("mode", ["approx", "analytic"])
def test_long_staircases_cut_into_runs_draw_the_same_pixels(mode, monkeypatch):
    """A staircase is cut into runs of about RUN_ROWS rows (the raster reads a fill's edges
    once per strip of rows its box meets); the pieces share no pixel, so cutting every 3 rows
    draws the bytes one run draws, at one and two threads."""
    from vecmsaa.geometry import hairline
    svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="96" height="96">'
           '<path d="M2.3 1.7 L90.6 80.2 L7.1 93.4 L60.5 3.3 L61.2 90" fill="none" '
           'stroke="teal" stroke-width="0.7" stroke-opacity="0.8"/></svg>').encode()
    rows = np.array([[2.3, 1.7, 90.6, 80.2], [90.6, 80.2, 7.1, 93.4]])
    monkeypatch.setattr(hairline, "RUN_ROWS", 3)
    assert len(hairline.hairline_outline(rows)) > 10
    cut = [render_svg_array(svg, mode=mode, threads=t) for t in (1, 2)]
    monkeypatch.setattr(hairline, "RUN_ROWS", 1 << 30)
    assert len(hairline.hairline_outline(rows)) == 2
    whole = render_svg_array(svg, mode=mode, threads=1)
    for a in cut:
        np.testing.assert_array_equal(a, whole)


def _random_path_data(rng, size):
    """A path of random lines, quadratics, cubics, arcs (conics, some large: several cubics
    each), closes and moves, some subpaths a point or a zero-length segment."""
    def pt():
        return " ".join(f"{v:.3f}" for v in rng.uniform(-0.2 * size, 1.2 * size, 2))
    out = [f"M{pt()}"]
    for _ in range(rng.integers(1, 9)):
        k = rng.integers(0, 9)
        if k == 0:
            out.append(f"L{pt()}")
        elif k == 1:
            out.append(f"Q{pt()} {pt()}")
        elif k == 2:
            out.append(f"C{pt()} {pt()} {pt()}")
        elif k in (3, 4):
            rx, ry = rng.uniform(0.2, 2.0 * size, 2)
            out.append(f"A{rx:.3f} {ry:.3f} {rng.uniform(0, 360):.1f} {rng.integers(2)} "
                       f"{rng.integers(2)} {pt()}")
        elif k == 5:
            out.append("Z")
        elif k == 6:
            out.append(f"M{pt()}")
        elif k == 7:
            out.append("l0 0")
        else:
            out.append(f"H{rng.uniform(0, size):.3f}")
    return " ".join(out)


@pytest.mark.parametrize("seed", range(4))
def test_batch_of_curved_paths_is_each_paths_outline(seed):
    """hairline_batch on a batch of paths of every verb (conics of arcs and circles included)
    gives, run for run and array for array, each path's hairline_outline of its
    hairline_segments, under random transforms, caps and alphas, for any choice and order of
    the batch's paths (the owner of each run says whose it is)."""
    from vecmsaa.geometry import hairline, hairline_kernels
    from vecmsaa.svg.pathdata import parse_path_data
    from vecmsaa.svg.shapes import ellipse_path
    rng = np.random.default_rng(seed)
    paths = [parse_path_data(_random_path_data(rng, 40)) for _ in range(30)]
    paths += [ellipse_path(*rng.uniform(0, 40, 2), *rng.uniform(0.1, 30, 2))
              for _ in range(6)]
    paths.append(parse_path_data("M1 1 L30 9 L12 30 Z"))        # lines alone
    arrays = [p._freeze() for p in paths]
    verbs = np.concatenate([v for v, _ in arrays])
    points = np.concatenate([p for _, p in arrays])
    vstart = np.cumsum([0] + [len(v) for v, _ in arrays])
    pstart = np.cumsum([0] + [len(p) for _, p in arrays])
    assert {2, 3, 5} <= set(verbs.tolist())         # quadratics, cubics, conics
    for trial in range(6):
        a, b, c, d = rng.uniform(-3, 3, 4) * (rng.uniform() < 0.8 or 0.01)
        m = (a, b, c, d, *rng.uniform(-20, 20, 2))
        cap = ("butt", "round", "square")[trial % 3]
        alpha = (1.0, 0.5, 0.25)[trial // 2 % 3]
        which = rng.permutation(len(paths))[:rng.integers(1, len(paths) + 1)]
        ov, op, rv, rp, owner = hairline.hairline_batch(verbs, points, vstart, pstart, which,
                                                        m, cap, alpha)
        assert (np.diff(owner) >= 0).all() and len(rv) == len(owner) + 1
        drawn = 0
        for w, i in enumerate(which):
            rows, subs = hairline.hairline_segments(paths[i], m, cap)
            ev, ep, erv, erp = hairline_kernels.hairline_rows(
                rows, subs, hairline.STAIR_SLOPE, hairline.MAX_STEPS, alpha,
                hairline.RUN_ROWS)
            mine = np.flatnonzero(owner == w)
            assert len(mine) == len(erv) - 1
            if len(mine) == 0:
                continue
            r0, r1 = mine[0], mine[-1] + 1
            np.testing.assert_array_equal(rv[r0:r1 + 1] - rv[r0], erv)
            np.testing.assert_array_equal(rp[r0:r1 + 1] - rp[r0], erp)
            np.testing.assert_array_equal(ov[rv[r0]:rv[r1]], ev)
            np.testing.assert_array_equal(op[rp[r0]:rp[r1]], ep)
            drawn += len(ev) > 0
        assert drawn > 0
        # one path alone, as builder._hairline_fills draws it
        i = which[0]
        one = hairline.hairline_path(paths[i], m, cap, alpha)
        rows, subs = hairline.hairline_segments(paths[i], m, cap)
        for x, y in zip(one[:4], hairline_kernels.hairline_rows(
                rows, subs, hairline.STAIR_SLOPE, hairline.MAX_STEPS, alpha,
                hairline.RUN_ROWS)):
            np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("seed", range(3))
def test_room_reserved_for_a_subpath_holds_its_outline(seed):
    """_emit_rows grows its arrays once a subpath, by _rows_room's bound, and then writes
    without checks: on random subpaths (short and long segments, turns, segments meeting
    within a step, points, huge and non-finite coordinates) under small step and run limits,
    the outline the kernel makes of each subpath alone never exceeds the bound: verbs 5, points
    4 a piece, runs as counted (a subpath's outline starts empty; the steps' budget,
    max_steps[1], as small as 1, bounds the room too)."""
    from vecmsaa.geometry import hairline_kernels
    room = hairline_kernels._rows_room.py_func
    rng = np.random.default_rng(seed)
    drawn = 0
    for trial in range(60):
        n = int(rng.integers(1, 30))
        scale = [0.7, 5.0, 60.0][trial % 3]
        pts = np.cumsum(rng.normal(0, scale, (n + 1, 2)), axis=0) + 50
        if trial % 4 == 0:
            pts[rng.integers(0, n + 1)] = pts[rng.integers(0, n + 1)]   # a point segment
        if trial % 10 == 1:
            pts[rng.integers(0, n + 1)] = [1e12, -3e11]
        if trial % 10 == 2:
            pts[rng.integers(0, n + 1), 0] = np.nan
        if trial % 10 == 3:
            pts[rng.integers(0, n + 1)] = [rng.choice([-3e19, 3e19, 2e300]), 40]
        rows = np.ascontiguousarray(np.c_[pts[:-1], pts[1:]])
        max_steps = np.array([int(rng.integers(1, 40)), int(rng.integers(1, 400))], np.int64)
        run_rows = int(rng.integers(1, 8))
        alpha = float(rng.choice([1.0, 0.5]))
        v, p, rv, rp = hairline_kernels.hairline_rows(
            rows, np.array([0, n], np.int64), float(rng.choice([0.0, 0.25])), max_steps,
            alpha, run_rows)
        quads, runs = room(rows, n, max_steps, run_rows, 0)   # (none counted before it)
        assert len(v) <= 5 * quads and len(p) <= 4 * quads
        assert len(rv) - 1 <= runs
        drawn += len(p) > 0
    assert drawn > 40
