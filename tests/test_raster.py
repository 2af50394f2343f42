"""Raster behaviour against independent truth (tests/truth.py): root-finding winding numbers,
exact polygon areas, exact half-plane masks."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from truth import distance_to_outline, polygon_pixel_coverage, segments, winding_at
from vecmsaa.geometry.primitives import QUAD_FALLBACK_TOL
from vecmsaa.scene.path import Path
from vecmsaa.raster.sample_patterns import standard_pattern
from vecmsaa.output.png import encode_png
from vecmsaa.raster.modes import MODES
from vecmsaa.raster import render as render_module
from vecmsaa.raster.render import (RenderOptions, render_scene, render_scene_png,
                                   render_scene_rgba8)
from vecmsaa.output.rgba8 import to_rgba8
from vecmsaa.scene.nodes import Fill, Group, LinearGradient, Mask, Scene, Solid

SIZE = 16
coord = st.floats(min_value=-2.0, max_value=SIZE + 2.0, allow_nan=False, width=32)
# Shift by an irrational amount: samples sit on multiples of 1/16, and hypothesis likes round
# numbers; an exact tie (vertex on a sample row) is decided by convention, not by geometry.
point = st.tuples(coord, coord).map(lambda p: (p[0] + 1.2345e-6 * math.pi, p[1] + 2.7182e-6 * math.e))


@st.composite
def closed_paths(draw, max_segments=5):
    path = Path()
    path.moveTo(draw(point))
    for _ in range(draw(st.integers(1, max_segments))):
        kind = draw(st.sampled_from(["line", "quad", "cubic"]))
        if kind == "line":
            path.lineTo(draw(point))
        elif kind == "quad":
            path.qCurveTo(draw(point), draw(point))
        else:
            path.curveTo(draw(point), draw(point), draw(point))
    path.closePath()
    return path


def circle_path(c, r):
    """The usual four-cubic circle (radial error below 0.027%)."""
    k = 4 / 3 * (math.sqrt(2) - 1) * r
    x, y = c
    path = Path()
    path.moveTo((x + r, y))
    path.curveTo((x + r, y + k), (x + k, y + r), (x, y + r))
    path.curveTo((x - k, y + r), (x - r, y + k), (x - r, y))
    path.curveTo((x - r, y - k), (x - k, y - r), (x, y - r))
    path.curveTo((x + k, y - r), (x + r, y - k), (x + r, y))
    path.closePath()
    return path


def alpha_of(path, mode, samples=8, rule="nonzero", size=SIZE):
    scene = Scene(size, size, Group([Fill(path, Solid((0, 0, 0, 1)), rule=rule)]))
    return render_scene(scene, mode=mode, samples=samples)[..., 3].astype(np.float64)


def brute_force_alpha(path, offsets, rule="nonzero", size=SIZE):
    """Fraction of pattern samples inside the path, by crossing counts with polynomial roots,
    and the outline's segments."""
    segs = segments(path)
    inside = np.zeros((size, size))
    for py in range(size):
        for px in range(size):
            for ox, oy in offsets:
                x, y = px + 0.5 + ox, py + 0.5 + oy
                w = winding_at(segs, x, y)
                hit = (w != 0) if rule == "nonzero" else (w % 2 == 1)
                inside[py, px] += hit
    inside /= len(offsets)
    return inside, segs


def assert_matches_brute_force(path, mode, samples, rule):
    got = alpha_of(path, mode, samples, rule)
    offsets = standard_pattern(1 if mode == "none" else samples)
    want, segs = brute_force_alpha(path, offsets, rule)
    bad = np.argwhere(np.abs(got - want) > 1e-6)
    # a disagreement is acceptable only where a sample lies on the outline itself, or, with a
    # cubic, within the tolerance of the quadratics that stand in for a degenerate one
    # (primitives.QUAD_FALLBACK_TOL: a sample 0.0017 px from a looped cubic once failed 1e-4)
    cubic = any(kind == "cubic" for kind, _ in segs)
    tol = QUAD_FALLBACK_TOL if cubic else 1e-4
    for py, px in bad:
        d = min(distance_to_outline(segs, px + 0.5 + ox, py + 0.5 + oy, 4000)
                for ox, oy in offsets)
        assert d < tol, f"pixel {(px, py)}: {got[py, px]} vs exact {want[py, px]}"
    # a few pixels at most, but for a cubic thinner than the fallback tolerance: it may stand
    # on a column of samples along its whole length (_sliver_on_a_sample_column)
    assert cubic or len(bad) <= max(1, got.size // 100)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(closed_paths(), st.sampled_from(["nonzero", "evenodd"]))
def test_persample_equals_point_in_region_at_the_same_samples(path, rule):
    assert_matches_brute_force(path, "persample", 8, rule)


def _sliver_in_a_corner():
    """Hypothesis's example: a quadratic whose control point lies 9e-20 px above the corner its
    two straight neighbours meet at (after three zero-length lines, which play no part). Its
    end tangent is horizontal but for a slope of 4e-20: it crossed the lens's rows 1e19 px
    away, and that pixel index did not fit an int64."""
    x, y = 3.878296130856599e-06, 7.388833666117377e-06
    path = Path()
    path.moveTo((x, y))
    for _ in range(3):
        path.lineTo((x, y))
    path.lineTo((x, 1.000007388833666))
    path.qCurveTo((x, 7.388833666117288e-06), (2.000003878296131, y))
    path.closePath()
    return path


def _sliver_on_a_sample_column():
    """Hypothesis's example: a looped cubic 2e-5 px wide standing on x = 0, the 16-sample
    pattern's left column (offset -8/16), over three pixels. The samples on that column are
    inside it, within the fallback tolerance of its outline, in each of the three pixels."""
    x, y = 3.878296130856599e-06, 7.388833666117377e-06
    path = Path()
    path.moveTo((x, y))
    path.curveTo((x, 8.00000738883367), (-5.71568601e-05, y), (x, y))
    for _ in range(3):
        path.lineTo((x, y))
    path.closePath()
    return path


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(closed_paths(), st.sampled_from(["nonzero", "evenodd"]), st.sampled_from([8, 16]))
@example(_sliver_in_a_corner(), "nonzero", 8)
@example(_sliver_on_a_sample_column(), "nonzero", 16)
def test_approx_equals_point_in_region_at_the_same_samples(path, rule, samples):
    # random curves at 16 px turn within pixels, end inside them and share them: the half-plane
    # is wrong there, and approx must notice and evaluate those samples
    assert_matches_brute_force(path, "approx", samples, rule)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(closed_paths())
def test_none_mode_samples_the_pixel_centre(path):
    assert_matches_brute_force(path, "none", 1, "nonzero")


@pytest.mark.parametrize("ulps", [12, -12, 1, -1])
@pytest.mark.parametrize("mirror", [False, True])
def test_lenses_whose_tangent_or_chord_is_nearly_horizontal(ulps, mirror):
    # A lens is bounded by half-planes (chord, end tangents) whose crossing of each sample
    # row becomes a pixel index. A line that is horizontal but for a slope of ~1e-21 crosses
    # a row a few pixels away 1e21 px off, beyond int64: that crossing must still mean "far
    # to that side" (it came out as -2**63, the far left, and a lens lost its samples). Near
    # y = 0 a slope that small is a few ulps; the usual irrational shift keeps vertices off
    # the sample rows. Mirrored in x and with the ulps of either sign, both sides of each
    # line are the lens's side.
    x0, y0 = 1.2345e-6 * math.pi, 2.7182e-6 * math.e
    y1 = y0
    for _ in range(abs(ulps)):
        y1 = math.nextafter(y1, math.copysign(math.inf, ulps))

    def x(v):
        return SIZE - (v + x0) if mirror else v + x0
    # the end tangent at (9, 0): the control point lies a few ulps above or below the corner
    tangent = Path()
    tangent.moveTo((x(1.0), y0))
    tangent.lineTo((x(1.0), 9.0 + y0))
    tangent.qCurveTo((x(1.0), y1), (x(9.0), y0))
    tangent.closePath()
    # the chord (1, 0) -> (9, 0 + a few ulps), the lens 0.95 px deep below it (one piece:
    # a deeper curve is split into pieces whose chords slope)
    chord = Path()
    chord.moveTo((x(1.0), y0))
    chord.qCurveTo((x(5.0), 1.9 + y0), (x(9.0), y1))
    chord.closePath()
    for path in (tangent, chord):
        for mode, samples in (("persample", 8), ("approx", 16), ("none", 1)):
            assert_matches_brute_force(path, mode, samples, "nonzero")


def test_an_edge_beyond_the_int64_range_crosses_no_visible_pixel():
    # scan_edges turns a sample's crossing into a pixel index; an edge reaching x = 1e30
    # crosses the rows beyond int64, which converted to -2**63 and put those crossings in
    # column 0 (the edge drawn at the left border: the triangle, whose left edge is at
    # x = 0.5, came out empty). The kernel on its own, against crossing counts.
    from vecmsaa.raster.scan import msaa_scratch, scan_edges
    W, rows = 4, 16
    offsets = standard_pattern(8)
    sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
    for far in (1e30, -1e30):
        x0 = 0.5 if far > 0 else W - 0.5
        path = Path()
        path.moveTo((x0, 0.0))
        path.lineTo((far, 8.0))
        path.lineTo((x0, 16.0))
        path.closePath()
        segs = segments(path)
        edges = np.array([c.ravel() for _, c in segs])
        delta, _, dirty, dlist, dcount = msaa_scratch(rows, W, len(sx))[:5]
        scan_edges(edges, np.empty((0, 2)), 0, len(edges), 0, rows, W, sx, sy, delta, dirty,
                   dlist, dcount, np.zeros(rows, dtype=np.bool_), np.zeros(len(sx), dtype=np.int64))
        winding = np.cumsum(delta[:, :W], axis=1)
        for py in range(rows):
            for px in range(W):
                for s in range(len(sx)):
                    want = winding_at(segs, px + sx[s], py + sy[s])
                    assert winding[py, px, s] == want, (far, px, py, s)


def _edges_across_strips(chunk):
    """Edges for the strip tests below, as fills (edge ranges of one array, most not starting
    on a chunk boundary): closed polygons (a zigzag whose every edge crosses many strips;
    triangles and horizontal edges with their ends exactly on strip boundaries; a fan of
    edges from one point; a chunk of its own whose lowest point is exactly a strip's top)
    and, for the comparison without chunks only, edges no polygon closes: coordinates of
    1e300 and -1e300, of 1e-300, vertical and NaN ones (one in a chunk of its own, whose
    other edges lie strips below: the NaN edge adds windings at column 0 from row 0)."""
    polygons = []
    zigzag = [(0.3, 0.2)]
    for i in range(1, 241):
        zigzag.append((0.3 + 11.0 * (i % 2) + 0.001 * i, 0.2 + 47.5 * (i % 2) - 0.1 * i % 3))
    polygons.append(zigzag)
    for y in (4.0, 8.0, 12.0, 16.0, 32.0):
        polygons.append([(1.25, y), (9.5, y - 4.0), (6.75, y + 4.0)])    # ends on boundaries
        polygons.append([(0.5, y), (10.5, y), (10.5, y + 0.5), (0.5, y + 0.5)])
    polygons.append([(6.0, 24.0)] + [(6.0 + 5.0 * math.cos(a), 24.0 + 23.0 * math.sin(a))
                                     for a in np.linspace(0.0, 6.0, 30)])
    fills, edges = [], []

    def add(new_edges):
        fills.append((len(edges), len(edges) + len(new_edges)))
        edges.extend(new_edges)

    def align():
        if len(edges) % chunk:
            add([(0.5, 44.25, 0.5, 44.25)] * (chunk - len(edges) % chunk))

    for poly in polygons:
        add([(*poly[i], *poly[(i + 1) % len(poly)]) for i in range(len(poly))])
    align()
    low = [(1.003 + 0.6 * i, 20.0 if i % 2 == 0 else 10.5 + 0.5 * i) for i in range(chunk)]
    add([(*low[i], *low[(i + 1) % chunk]) for i in range(chunk)])
    closed = len(edges)
    add([(3.0, -1e300, 5.0, 1e300), (2.0, 1e-300, 7.0, 40.0), (1e30, 3.0, 2.0, 20.0),
         (4.5, 0.0, 4.5, 48.0), (3.0, float("nan"), 5.0, 9.0), (8.0, 16.0, 2.0, -1e-300),
         (float("nan"), 2.0, 3.0, 30.0), (5.0, 32.0, 5.0, 32.0), (1.0, 47.9, 9.0, 1e300)])
    # a fill that shares its first chunk with the one before it
    fills.append((fills[-1][0] - 3, fills[-1][0] + 2))
    align()
    add([(3.0, 9.0, 5.0, float("nan"))] + [(2.0, 44.0 + 0.1 * i, 9.0, 45.0)
                                           for i in range(chunk - 1)])
    return np.array(edges, dtype=np.float64), fills, closed


@pytest.mark.parametrize("samples", [8, 16])
def test_edge_chunks_change_no_strip_and_give_the_exact_winding(samples):
    # scan_edges skips chunks of consecutive edges whose y extent misses the strip
    # (scan.band_chunks): each strip of each fill must get the same winding deltas and dirty
    # pixels as when it reads every edge, and the windings must be the exact ones (crossing
    # counts of the closed polygons' outlines at every sample)
    from vecmsaa.raster.scan import (CHUNKED_EDGES, EDGE_CHUNK, band_chunks, msaa_scratch,
                                     scan_edges)
    edges, fills, closed = _edges_across_strips(EDGE_CHUNK)
    assert len(edges) >= CHUNKED_EDGES
    W, H, rows = 12, 48, 4
    # the chunks of a band holding every strip below, for one fill whose box holds them all
    chunks = band_chunks(edges, np.array([0, len(edges)]), np.array([[0.0, -1e308, W, 1e308]]),
                         -rows, H + 2 * rows, rows)
    assert len(chunks) == -(-len(edges) // EDGE_CHUNK)
    offsets = standard_pattern(samples)
    sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
    n = len(sx)
    winding = np.zeros((H, W, n))
    for e0, e1 in fills:
        for sy0 in range(-rows, H + rows, rows):
            got = []
            for chunk_y in (chunks, np.empty((0, 2))):
                delta, _, dirty, dlist, dcount = msaa_scratch(rows, W, n)[:5]
                scan_edges(edges, chunk_y, e0, e1, sy0, rows, W, sx, sy, delta, dirty, dlist,
                           dcount, np.zeros(rows, dtype=np.bool_), np.zeros(n, dtype=np.int64))
                got.append((delta.copy(), dirty.copy(),
                            [sorted(dlist[r, :dcount[r]]) for r in range(rows)]))
            (d_a, dirty_a, list_a), (d_b, dirty_b, list_b) = got
            assert np.array_equal(d_a, d_b), (e0, e1, sy0)
            assert np.array_equal(dirty_a, dirty_b) and list_a == list_b, (e0, e1, sy0)
            if e1 <= closed and 0 <= sy0 < H:
                winding[sy0:sy0 + rows] += np.cumsum(d_a[:, :W], axis=1)
    assert np.array_equal(winding, _polygon_winding(edges[:closed], W, H, sx, sy))


def _polygon_winding(edges, W, H, sx, sy):
    """Winding number of straight edges (x0, y0, x1, y1) at every sample of a W x H image:
    truth.winding_at's rule for straight segments (a crossing at t in [0, 1) left of or at the
    sample, signed by the direction), every sample at once."""
    X = np.arange(W)[None, :, None] + sx[None, None, :]
    Y = np.arange(H)[:, None, None] + sy[None, None, :]
    want = np.zeros((H, W, len(sx)))
    for x0, y0, x1, y1 in edges:
        if y0 == y1:
            continue
        t = (Y - y0) / (y1 - y0)
        xt = x0 + t * (x1 - x0)
        want += np.where((t >= 0) & (t < 1) & (xt <= X), 1 if y1 > y0 else -1, 0)
    return want


@pytest.mark.parametrize("samples", [8, 16])
def test_a_batch_of_tall_many_edged_fills_matches_its_samples_in_any_bands(samples):
    # a batch with enough edges that each band works out edge chunks (scan.CHUNKED_EDGES),
    # its fills crossing every strip (a zigzag of 300 edges from top to bottom) or ending on
    # strip boundaries (16 rows at this width): the same bytes for any band size and thread
    # count, and each pixel's coverage the share of its samples inside (crossing counts)
    from vecmsaa.raster.scan import CHUNKED_EDGES
    W, H = 40, 96
    zigzag = Path()
    zigzag.moveTo((0.5 + 1e-3 * math.pi, 0.25))
    for i in range(1, 300):
        zigzag.lineTo((0.5 + 39.0 * (i % 2) + 0.013 * i + 1e-3 * math.pi,
                       0.25 + 95.5 * (i % 2) - 0.3 * (i % 5)))
    zigzag.closePath()
    steps = Path()
    for y in (16.0, 32.0, 48.0, 64.0):
        steps.moveTo((2.0 + 1e-3 * math.e, y))
        steps.lineTo((37.5 + 1e-3 * math.pi, y - 16.0))
        steps.lineTo((20.0 + 1e-3 * math.e, y + 16.0))
        steps.closePath()
    foot = Path()      # in the lowest band only (of bands under 84 rows)
    foot.moveTo((3.3, 84.2))
    foot.lineTo((30.1, 90.7))
    foot.lineTo((12.9, 95.6))
    foot.closePath()
    fills = [Fill(zigzag, Solid((0.2, 0.4, 0.8, 1.0)), rule="evenodd"),
             Fill(steps, Solid((0.9, 0.3, 0.1, 1.0))), Fill(foot, Solid((0.1, 0.7, 0.2, 1.0)))]
    scene = Scene(W, H, Group(fills))
    edges = []
    for fill in fills:
        edges += [c.ravel() for _, c in segments(fill.path)]
    assert len(edges) >= CHUNKED_EDGES
    one = render_scene(scene, mode="persample", samples=samples)
    for threads, band_rows in ((1, 16), (2, 16), (1, 32), (2, 48), (1, 80)):
        assert np.array_equal(render_scene(scene, mode="persample", samples=samples,
                                           threads=threads, band_budget=band_rows * W * 16),
                              one), (threads, band_rows)
    offsets = standard_pattern(samples)
    sx, sy = offsets[:, 0] + 0.5, offsets[:, 1] + 0.5
    zig = _polygon_winding([c.ravel() for _, c in segments(zigzag)], W, H, sx, sy)
    tri = _polygon_winding([c.ravel() for _, c in segments(steps)], W, H, sx, sy)
    in_foot = _polygon_winding([c.ravel() for _, c in segments(foot)], W, H, sx, sy) != 0
    in_zig = zig % 2 == 1
    in_tri = tri != 0
    # each drawn over the ones before, all opaque: per sample, the last one inside
    colour = np.where(in_foot[..., None], [0.1, 0.7, 0.2],
                      np.where(in_tri[..., None], [0.9, 0.3, 0.1],
                               np.where(in_zig[..., None], [0.2, 0.4, 0.8], 0.0)))
    cover = (in_foot | in_tri | in_zig).mean(axis=2)
    want = np.concatenate([colour.mean(axis=2), cover[..., None]], axis=2)
    assert np.abs(one - want).max() < 1e-5


def test_persample_on_a_loop_cubic_and_a_serpentine():
    loop = Path()
    loop.moveTo((2, 14))
    loop.curveTo((20, 0), (-4, 0), (14, 14))   # control polygon crosses itself: a loop
    loop.closePath()
    serp = Path()
    serp.moveTo((1, 8))
    serp.curveTo((6, -6), (10, 22), (15, 8))  # S-shaped
    serp.lineTo((15, 15))
    serp.lineTo((1, 15))
    serp.closePath()
    shift = (1, 0, 0, 1, 1.2345e-6 * math.pi, 2.7182e-6 * math.e)  # no vertex on a sample row
    for path in (loop.transformed(shift), serp.transformed(shift)):
        for rule in ("nonzero", "evenodd"):
            assert_matches_brute_force(path, "persample", 16, rule)


def test_a_small_loop_whose_end_tangents_are_close():
    # the loop between this cubic's double-point parameters turns by ~283°, its end tangents
    # only 77° apart, and its chord has no length: taken as one lens, its sliver on the far
    # side of the chord's row (y < 8.514) was lost: pixel centres up to 0.086 px inside drew
    # empty (hypothesis found it). Pixel centres over that sliver, and 8 samples a pixel.
    path = Path()
    path.moveTo((0.0, 0.0))
    path.lineTo((11.3984, 14.7356))
    path.curveTo((10.0, 0.15), (15.5, 18.0), (6.75, 0.125))
    path.closePath()
    for dx in (-0.2, -0.1, 0.0, 0.1):
        for dy in (0.0, 0.02, 0.04):
            shifted = path.transformed((1, 0, 0, 1, dx + 1.2345e-6, dy + 2.7182e-6))
            assert_matches_brute_force(shifted, "none", 1, "nonzero")
    assert_matches_brute_force(path, "persample", 8, "evenodd")


@st.composite
def star_polygons(draw):
    """Simple (non-self-intersecting) polygons: points at increasing angles around a centre."""
    n = draw(st.integers(3, 8))
    cx = draw(st.floats(4, 12))
    cy = draw(st.floats(4, 12))
    angles = sorted(draw(st.lists(st.floats(0, 2 * math.pi - 1e-3), min_size=n, max_size=n,
                                  unique=True)))
    radii = draw(st.lists(st.floats(0.5, 6), min_size=n, max_size=n))
    return [(cx + r * math.cos(a), cy + r * math.sin(a)) for a, r in zip(angles, radii)]


def polygon_path(points) -> Path:
    path = Path()
    path.moveTo(points[0])
    for p in points[1:]:
        path.lineTo(p)
    path.closePath()
    return path


@settings(max_examples=25, deadline=None)
@given(star_polygons())
def test_analytic_equals_exact_polygon_area_per_pixel(poly):
    got = alpha_of(polygon_path(poly), "analytic")
    want = polygon_pixel_coverage(poly, SIZE, SIZE)
    np.testing.assert_allclose(got, want, atol=2e-5)


def test_analytic_circle_area_matches_pi_r_squared():
    r = 20.0
    path = circle_path((32.0, 32.0), r)
    # the 4-cubic circle's exact area (its radial error is at most 0.027%: area within 0.06%)
    for mode in ("analytic", "reference", "persample", "approx"):
        total = alpha_of(path, mode, 16, size=64).sum()
        assert abs(total - math.pi * r * r) / (math.pi * r * r) < 1.5e-3, mode


@settings(max_examples=30, deadline=None)
@given(closed_paths(max_segments=6), st.sampled_from(MODES), st.sampled_from([1, 2, 4, 8, 16]),
       st.sampled_from(["nonzero", "evenodd"]))
def test_coverage_is_finite_and_within_zero_one(path, mode, samples, rule):
    a = alpha_of(path, mode, samples, rule)
    assert np.isfinite(a).all()
    assert a.min() >= -1e-6 and a.max() <= 1 + 1e-6


def test_degenerate_paths_draw_nothing_and_never_nan():
    cases = []
    p = Path()  # coincident control points everywhere
    p.moveTo((5, 5))
    p.curveTo((5, 5), (5, 5), (5, 5))
    p.closePath()
    cases.append(p)
    p = Path()  # collinear cubic, going back over itself
    p.moveTo((1, 1))
    p.curveTo((10, 10), (3, 3), (14, 14))
    p.closePath()
    cases.append(p)
    p = Path()  # quadratic with the control point on the chord
    p.moveTo((1, 8))
    p.qCurveTo((8, 8), (15, 8))
    p.closePath()
    cases.append(p)
    for path in cases:
        for mode in MODES:
            a = alpha_of(path, mode)
            assert np.isfinite(a).all()
            assert a.sum() < 1e-3, mode


def test_d3d_standard_patterns():
    # Direct3D 10.1 standard sample positions (1/16 pixel units), as published
    assert standard_pattern(4).tolist() == (np.array([(-2, -6), (6, -2), (-6, 2), (2, 6)]) / 16).tolist()
    for n in (2, 4, 8, 16):
        offs = standard_pattern(n)
        assert len(set(offs[:, 1])) == n   # every sample on its own scanline
        assert np.abs(offs).max() <= 0.5


@pytest.mark.parametrize("samples", [2, 4, 8, 16])
def test_standard_patterns_draw_edges_where_they_are(samples):
    """A rectangle at many sub-pixel positions: the alpha-weighted centroid of its render is
    its exact centroid on average (an unbiased pattern). The D3D 16 table's own offsets have
    the mean (-1/32, -1/32) px and drew every rectangle 1/32 px right and down."""
    from vecmsaa.api import render_svg_array

    steps = 37          # prime: no position puts an edge exactly on a sample
    bias = np.zeros(2)
    for i in range(steps):
        x, y = 3 + i / steps, 4 + ((i * 5) % steps) / steps
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="24" height="24">'
               f'<rect x="{x}" y="{y}" width="10.5" height="9.25"/></svg>')
        alpha = render_svg_array(svg.encode(), samples=samples)[..., 3].astype(np.float64)
        ys, xs = np.mgrid[0:24, 0:24] + 0.5
        centroid = np.array([(alpha * xs).sum(), (alpha * ys).sum()]) / alpha.sum()
        bias += centroid - (x + 10.5 / 2, y + 9.25 / 2)
    assert np.abs(bias / steps).max() < 0.008


def figure1(size=64):
    """Paper's Figure 1: red and green share one curved boundary; blue overlaps both."""
    s = size / 64.0
    red = Path()
    red.moveTo((0, 0))
    red.lineTo((64 * s, 0))
    red.lineTo((64 * s, 20 * s))
    red.qCurveTo((32 * s, 70 * s), (0, 20 * s))
    red.closePath()
    green = Path()
    green.moveTo((0, 20 * s))
    green.qCurveTo((32 * s, 70 * s), (64 * s, 20 * s))
    green.lineTo((64 * s, 64 * s))
    green.lineTo((0, 64 * s))
    green.closePath()
    return red, green


def test_shared_curved_boundary_has_no_seam_in_msaa_modes_but_alpha_blending_leaks():
    red, green = figure1()
    scene = Scene(64, 64, Group([Fill(red, Solid((1, 0, 0, 1))), Fill(green, Solid((0, 1, 0, 1)))]))
    for mode in ("persample", "approx", "a2c", "none", "reference"):
        a = render_scene(scene, mode=mode, samples=8)[..., 3]
        assert a.min() > 1 - 1e-5, mode  # opaque everywhere: no background through the seam
    leak = 1 - render_scene(scene, mode="alpha", samples=8)[..., 3]
    assert leak.max() > 0.1        # conflation: the seam lets the background through
    leak = 1 - render_scene(scene, mode="analytic")[..., 3]
    assert leak.max() > 0.1


def test_huge_and_tiny_coordinates():
    # a circle of radius 1e7 whose edge crosses the canvas behaves like a half-plane
    R = 1e7
    path = circle_path((-R + 8.3, 8.0), R)
    for mode in ("approx", "persample", "analytic", "alpha"):
        a = alpha_of(path, mode, 16)
        assert np.isfinite(a).all()
        cols = a.mean(axis=0)
        np.testing.assert_allclose(cols[:8], 1.0, atol=1e-3)
        np.testing.assert_allclose(cols[9:], 0.0, atol=1e-3)
        assert abs(cols[8] - 0.3) < 0.07, (mode, cols[8])
    # a shape of size 1e-6 px covers next to nothing
    tiny = Path()
    tiny.moveTo((5, 5))
    tiny.curveTo((5 + 1e-6, 5), (5 + 1e-6, 5 + 1e-6), (5, 5 + 1e-6))
    tiny.closePath()
    for mode in MODES:
        a = alpha_of(tiny, mode)
        assert np.isfinite(a).all() and a.sum() < 1e-3


@pytest.mark.parametrize("mode", ["approx", "persample", "alpha", "a2c"])
def test_msaa_modes_close_to_exact_area_on_a_smooth_shape(mode):
    r = 11.0
    path = circle_path((16.0, 16.0), r)
    exact = alpha_of(path, "reference", size=32)
    got = alpha_of(path, mode, 16, size=32)
    edge = (exact > 0.01) & (exact < 0.99)
    # 16 samples resolve coverage to 1/16; approx and a2c add their approximation on top
    assert np.abs(got - exact)[edge].mean() < 0.06


@pytest.mark.parametrize("mode", ["none", "persample", "approx", "alpha", "a2c", "reference"])
def test_abutting_shapes_hit_every_sample_exactly_once(mode):
    # two half-transparent triangles sharing a diagonal edge (and the square's outline): a
    # double-hit sample would show alpha 0.75, a missed one 0; each must be exactly 0.5
    a, b, c, d = (1.3, 1.7), (14.6, 2.2), (13.9, 14.8), (2.1, 13.4)
    t1, t2 = Path(), Path()
    t1.moveTo(a)
    t1.lineTo(b)
    t1.lineTo(c)
    t1.closePath()
    t2.moveTo(a)
    t2.lineTo(c)
    t2.lineTo(d)
    t2.closePath()
    half = Solid((0, 0, 0, 0.5))
    scene = Scene(SIZE, SIZE, Group([Fill(t1, half), Fill(t2, half)]))
    alpha = render_scene(scene, mode=mode, samples=16)[..., 3]
    inside = alpha_of(_quad(a, b, c, d), mode, 16)
    np.testing.assert_allclose(alpha, 0.5 * inside, atol=1e-6)


def _quad(a, b, c, d):
    p = Path()
    p.moveTo(a)
    for q in (b, c, d):
        p.lineTo(q)
    p.closePath()
    return p


def test_rgba8_is_the_straight_colour_rounded_half_up():
    """to_rgba8 against the definition in numpy float32: clamp to [0, 1] (NaN as 0), divide
    by alpha, scale by 255, round half up; transparent pixels are 0 in every channel."""
    rng = np.random.default_rng(7)
    special = np.array([np.nan, -np.inf, np.inf, 0.0, -0.0, 1e-13, 1e-11, 1.0, 1 - 2 ** -24,
                        1 + 2 ** -23, 0.5, 2.0, -1.0, 0.5 / 255, 254.5 / 255], np.float32)
    img = np.where(rng.random((60, 70, 4)) < 0.5, rng.choice(special, (60, 70, 4)),
                   rng.random((60, 70, 4)) * 1.4 - 0.2).astype(np.float32)
    with np.errstate(invalid="ignore", divide="ignore"):
        img[:20, :, :3] *= img[:20, :, 3:]      # premultiplied as renders are
        c = np.clip(np.nan_to_num(img, nan=0.0), 0, 1).astype(np.float32)
        a = c[..., 3:]
        straight = np.where(a > 0, c[..., :3] / np.maximum(a, np.float32(1e-12)), 0)
        want = np.floor(np.minimum(np.concatenate([straight, a], axis=2).astype(np.float32)
                                   * np.float32(255) + np.float32(0.5), 255))
    want[(a <= 0)[..., 0]] = 0
    assert np.array_equal(to_rgba8(img), want.astype(np.uint8))


def test_rgba8_of_many_premultiplied_pixels_is_the_float32_division():
    """The conversion of a million premultiplied pixels (alphas of every magnitude down to
    below 1e-12, colours up to their alpha, a width that leaves a remainder after any vector
    width) equals numpy's float32 arithmetic: straight = colour / alpha, then x 255 + 0.5,
    truncated; alpha 0 gives 0."""
    rng = np.random.default_rng(11)
    h, w = 1000, 1001
    a = np.float32(10.0) ** -rng.uniform(0, 13, (h, w)).astype(np.float32)
    a[rng.random((h, w)) < 0.2] = 1.0
    a[rng.random((h, w)) < 0.1] = 0.0
    img = np.empty((h, w, 4), np.float32)
    img[..., 3] = a
    img[..., :3] = rng.random((h, w, 3)).astype(np.float32) * a[..., None]
    d = np.maximum(a, np.float32(1e-12))[..., None]
    straight = np.minimum((img[..., :3] / d) * np.float32(255) + np.float32(0.5), np.float32(255))
    want = np.empty((h, w, 4), np.uint8)
    want[..., :3] = np.where(a[..., None] > 0, straight, 0).astype(np.uint8)
    want[..., 3] = (a * np.float32(255) + np.float32(0.5)).astype(np.uint8)
    assert np.array_equal(to_rgba8(img), want)


def test_paint_is_evaluated_once_per_pixel_at_its_centre():
    from vecmsaa.scene.path import rect_path
    from vecmsaa.scene.nodes import LinearGradient
    stops = np.array([[0, 0, 0, 0, 1], [1, 1, 1, 1, 1]], dtype=float)
    grad = LinearGradient(0.0, 0.0, 16.0, 0.0, stops)
    # the rectangle's left and right edges cut pixel columns 3 and 12 at 0.4: partial coverage
    scene = Scene(SIZE, SIZE, Group([Fill(rect_path(3.6, 0, 9.0, SIZE), grad)]))
    img = render_scene(scene, mode="approx", samples=8)
    for x in range(4, 12):
        # fully covered columns: the gradient's value at the pixel centre (1/1024 ramp steps)
        assert abs(img[5, x, 0] - (x + 0.5) / 16) < 2e-3
    # a partly covered pixel carries its centre colour times its coverage
    cov = img[5, 3, 3]
    assert 0.3 < cov < 0.5 and abs(img[5, 3, 0] / cov - 3.5 / 16) < 2e-3


@pytest.mark.parametrize("mode", ["analytic", "approx", "persample"])
def test_crisp_edges_give_whole_pixels(mode):
    from vecmsaa.scene.path import rect_path
    scene = Scene(SIZE, SIZE, Group([Fill(rect_path(2.3, 3.6, 8.5, 6.2), Solid((0, 0, 0, 1)),
                                          antialias=False)]))
    a = render_scene(scene, mode=mode, samples=8)[..., 3]
    assert set(np.unique(np.round(a, 6))) <= {0.0, 1.0}
    # columns 3..10 and rows 4..9 are covered by more than half (x 2.3..10.8, y 3.6..9.8)
    assert a.sum() == pytest.approx(8 * 6, abs=8)


def layered_scene(size=37):
    """Curved shapes crossing many rows, in layers of every kind: group opacity, a clip path
    (with a clip of its own), a luminance mask with a gradient, a blend mode; some layers cover
    only a few rows, so bands skip them."""
    from vecmsaa.scene.path import rect_path
    stops = np.array([[0, 1, 1, 1, 1], [1, 0.2, 0.2, 0.2, 0.5]], dtype=float)
    ramp = LinearGradient(0.0, 0.0, 0.0, size, stops)
    disc = Fill(circle_path((size * 0.45, size * 0.5), size * 0.4), Solid((0.9, 0.3, 0.1, 1)))
    ring = Fill(circle_path((size * 0.6, size * 0.4), size * 0.3), Solid((0.1, 0.5, 0.9, 0.8)),
                rule="evenodd")
    ring.path.moveTo((size * 0.6 + size * 0.15, size * 0.4))
    ring.path.curveTo((size * 0.75, size * 0.6), (size * 0.4, size * 0.6), (size * 0.45, size * 0.4))
    ring.path.closePath()
    band_clip = Group([Fill(rect_path(0, size * 0.3, size, size * 0.2))],
                      clip=Group([Fill(circle_path((size * 0.5, size * 0.4), size * 0.35))]))
    return Scene(size, size, Group([
        Fill(rect_path(0, 0, size, size), ramp),
        Group([disc, ring], opacity=0.6),
        Group([Fill(circle_path((size * 0.3, size * 0.6), size * 0.3), Solid((0, 0.8, 0.2, 1)))],
              clip=band_clip),
        Group([Fill(rect_path(size * 0.1, size * 0.1, size * 0.8, size * 0.8),
                    Solid((0.5, 0.1, 0.7, 1)))],
              mask=Mask(Group([Fill(circle_path((size * 0.5, size * 0.5), size * 0.45), ramp)]))),
        Group([Fill(circle_path((size * 0.7, size * 0.7), size * 0.25), Solid((1, 0.9, 0, 0.9)))],
              blend="multiply"),
    ]), background=(1, 1, 1, 0.5))


@pytest.mark.parametrize("mode", MODES)
def test_bands_give_the_same_image_as_one_band(mode):
    scene = layered_scene()
    whole = render_scene(scene, mode=mode, samples=8)     # the default budget: one band
    rgba8 = to_rgba8(whole)
    for band_rows in (1, 3, 7):
        budget = band_rows * scene.width * 16
        assert np.array_equal(render_scene(scene, mode=mode, samples=8, band_budget=budget),
                              whole)
        assert np.array_equal(render_scene_rgba8(scene, mode=mode, samples=8,
                                                 band_budget=budget), rgba8)


def test_buffers_kept_from_another_render_give_the_same_image(monkeypatch):
    """A render on the band and strip buffers an earlier render of another scene of the same
    size gave back (render.KEEP_BYTES: occlusion stamps of its runs, pool slots, band
    contents) is byte for byte the render on new buffers, on 1 and 2 threads."""
    # runs of opaque fills (occlusion stamps) in both, layers in one
    discs = [Fill(circle_path((30 + 9 * math.cos(k), 30 + 9 * math.sin(k)), 8 + k),
                  Solid((0.1 * k, 0.4, 0.6, 1))) for k in range(6)]
    scenes = (Scene(61, 61, Group([layered_scene(61).root, *discs[:3]])),
              Scene(61, 61, Group(discs[::-1])))
    monkeypatch.setattr(render_module, "KEEP_BYTES", 0)
    render_module._kits.clear()
    fresh = [render_scene_png(s, band_budget=7 * 61 * 16) for s in scenes]
    assert not render_module._kits
    monkeypatch.undo()
    for threads in (1, 2, 1):
        for s, png in zip(scenes + scenes, fresh + fresh):
            assert render_scene_png(s, threads=threads, band_budget=7 * 61 * 16) == png
            assert render_module._kits


def test_a_kept_band_buffer_takes_the_next_renders_background(monkeypatch):
    """A band buffer given back by a render holds that render's background (its last band
    refilled it); a render with another background on it is byte for byte the render on new
    buffers, and so is one with the same background (which uses what the buffer holds)."""
    discs = Group([Fill(circle_path((30 + 9 * math.cos(k), 30 + 9 * math.sin(k)), 8 + k),
                        Solid((0.1 * k, 0.4, 0.6, 0.5 + 0.1 * k))) for k in range(6)])
    scenes = [Scene(61, 61, discs, background=bg)
              for bg in ((1, 1, 1, 0.5), (0, 0, 0, 0), (0.2, 0.4, 0.6, 1))]
    monkeypatch.setattr(render_module, "KEEP_BYTES", 0)
    render_module._kits.clear()
    fresh = [render_scene_png(s, band_budget=7 * 61 * 16) for s in scenes]
    monkeypatch.undo()
    for threads in (1, 2):
        for k in (0, 0, 1, 2, 2, 0, 1, 1):
            assert render_scene_png(scenes[k], threads=threads, band_budget=7 * 61 * 16) == \
                fresh[k]
            assert render_module._kits


@pytest.mark.parametrize("mode,samples", [("persample", 8), ("approx", 16), ("alpha", 16),
                                          ("a2c", 16), ("none", 1)])
def test_strip_buffers_are_left_clean_by_curved_fills(mode, samples):
    """The sweeps read and clear a pixel's lens windings only where scan_lenses flagged it
    (scan.DIRTY_LENS): after a render of overlapping curved fills, translucent ones and runs
    of opaque ones, every strip buffer given back holds no winding and no dirty pixel, as
    msaa_scratch promises the next render (a lens winding left behind would be added to a
    later fill's samples)."""
    fills = [Fill(circle_path((30 + 9 * math.cos(k), 30 + 9 * math.sin(k)), 5 + 3 * k),
                  Solid((0.1 * k, 0.4, 0.6, 1.0 if k % 3 else 0.7)),
                  rule="evenodd" if k % 2 else "nonzero") for k in range(7)]
    render_module._kits.clear()
    render_scene(Scene(61, 61, Group(fills)), mode=mode, samples=samples,
                 band_budget=7 * 61 * 16)
    kits = [kit for kept in render_module._kits.values() for kit in kept]
    assert kits
    for scratch, *_ in kits:
        delta, local, dirty, _, dcount = scratch[:5]
        assert not delta.any() and not local.any()
        assert not dirty.any() and not dcount.any()


def test_strip_buffers_begin_on_a_cache_line():
    from vecmsaa.raster.scan import CACHE_LINE, line_aligned, msaa_scratch
    for n in (1, 8, 16):
        scratch = msaa_scratch(3, 37, n)
        for buf, shape in ((scratch[0], (3, 38, n)), (scratch[1], (3, 38, n)),
                           (scratch[8], (3 * 37, n, 4))):
            assert buf.shape == shape and buf.dtype == np.float32
            assert buf.ctypes.data % CACHE_LINE == 0 and buf.flags.c_contiguous
    ones = line_aligned((5, 7), np.int32, fill=-1)
    assert ones.ctypes.data % CACHE_LINE == 0 and (ones == -1).all()


FILTERED_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="96" height="80">'
                '<filter id="f"><feGaussianBlur stdDeviation="3"/><feOffset dx="2" dy="3"/>'
                '</filter><rect width="96" height="80" fill="#eee"/>'
                '<g filter="url(#f)" opacity="0.7"><circle cx="40" cy="36" r="26" fill="#36c"/>'
                '</g><path d="M5 70 C30 10 60 90 90 20" stroke="#c30" stroke-width="4" '
                'fill="none"/></svg>')


#: geometry far larger than the image, around it and across it (culled: primitives.build_batch),
#: filled, stroked, in a filter's region and as a clip
HUGE_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="90" height="70">'
            '<filter id="f" x="-1" y="-1" width="3" height="3"><feOffset dx="-20" dy="5"/>'
            '</filter><clipPath id="c"><circle cx="45" cy="-1e6" r="1.00003e6"/></clipPath>'
            '<circle cx="-1e6" cy="35" r="1.00004e6" fill="#36c"/>'
            '<path d="M0 0 C 1e6 1e6 -1e6 1e6 0 70 Z" fill="#c30" fill-opacity="0.6"/>'
            '<ellipse cx="45" cy="1e6" rx="3e6" ry="999940" fill="none" stroke="#393" '
            'stroke-width="9"/><g clip-path="url(#c)"><rect width="90" height="70" '
            'fill="#fc0" opacity="0.5"/></g><g filter="url(#f)"><path d="M100 30 Q 1e6 2e6 '
            '100 40 Z" fill="#909"/></g></svg>')


# markers drawn in the path's pass (content inside the viewport: m, the turned n) and in
# clipped layers (crossing it: k), over one another, a gradient and each other's strokes
MARKERS_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="90" height="70">'
    '<linearGradient id="g"><stop stop-color="#fc0"/><stop offset="1" stop-color="#09c"/>'
    '</linearGradient><filter id="b"><feGaussianBlur stdDeviation="0.7"/></filter>'
    '<marker id="m" markerUnits="userSpaceOnUse" markerWidth="10" markerHeight="10" refX="5" '
    'refY="5"><circle cx="5" cy="5" r="3.3" fill="#c33" fill-opacity="0.8"/><path d="M2.5 5h5"'
    ' stroke="#fff"/></marker>'
    '<marker id="n" markerWidth="7" markerHeight="5" refX="3" refY="2.5" orient="auto">'
    '<path d="M1 1.2 L5.5 2.5 L1 3.8 Z" fill="#036"/></marker>'
    '<marker id="k" markerUnits="userSpaceOnUse" markerWidth="8" markerHeight="8" refX="4" '
    'refY="4"><circle cx="4" cy="4" r="5" fill="#393" filter="url(#b)"/></marker>'
    '<rect x="5" y="5" width="80" height="60" fill="url(#g)"/>'
    '<polyline points="8,10 30.3,12.7 31.1,14.2 52,40 60.5,20.25 84,61 20,58 8,10" fill="none"'
    ' stroke="#333" stroke-width="1.5" marker-mid="url(#m)" marker-end="url(#k)"/>'
    '<path d="M10 30 C 30 5 60 65 80 30" fill="none" stroke="#906" stroke-width="1.2" '
    'marker-start="url(#n)" marker-mid="url(#n)" marker-end="url(#n)"/></svg>')


def scatter_svg(count=1500, width=90, height=70, seed=5):
    """Many small circles with 0.5 px strokes (hairlines: several small fills each), as a
    D3 scatter plot draws them, some opaque in runs (occlusion runs), some translucent, a
    few crossing the canvas edges: thousands of fills of a few pixels, most meeting one or
    two strips."""
    rng = np.random.default_rng(seed)
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">']
    for i in range(count):
        x, y = rng.uniform(-3, width + 3), rng.uniform(-3, height + 3)
        r = rng.uniform(0.4, 3.5)
        opaque = (i // 7) % 2 == 0
        fill = f'fill="#{rng.integers(0, 1 << 24):06x}"' + ("" if opaque else
                                                           ' fill-opacity="0.6"')
        stroke = ' stroke="#222" stroke-width="0.5"' if i % 3 else ""
        parts.append(f'<circle cx="{x:.3f}" cy="{y:.3f}" r="{r:.3f}" {fill}{stroke}/>')
    parts.append('</svg>')
    return "".join(parts)


@pytest.mark.parametrize("source", ["layered", "filtered", "huge", "markers", "scatter",
                                    "Ghostscript_Tiger", "alexandria-city-1"])
def test_threads_and_bands_give_the_same_bytes(source, request, monkeypatch):
    """Bands rendered on 1, 2 or 3 threads with several band budgets, and kernel strips
    smaller than the bands: the same image, byte for byte (each thread has its own kernel
    buffers; a filtered layer is filtered once)."""
    from vecmsaa.api import load_svg
    if source == "layered":
        scene = layered_scene(61)
    elif source == "filtered":
        scene = load_svg(FILTERED_SVG)
    elif source == "huge":
        scene = load_svg(HUGE_SVG)
    elif source == "markers":
        scene = load_svg(MARKERS_SVG, width=211)
        clipped = [g for g in scene.root.children if isinstance(g, Group) and g.clip]
        assert len(clipped) == 1 and len(scene.root.children) == 18
    elif source == "scatter":
        scene = load_svg(scatter_svg(), width=211)
    else:
        path = request.getfixturevalue("shared_dir") / "corpus" / f"{source}.svg"
        if not path.is_file():
            pytest.skip(f"{path.name} is not in the corpus")
        scene = load_svg(str(path), width=203)
    one = render_scene_rgba8(scene, threads=1)
    assert one[..., 3].any()
    for threads in (2, 3):
        for band_rows in (1, 5, 64):
            budget = band_rows * scene.width * 16
            assert np.array_equal(render_scene_rgba8(scene, threads=threads,
                                                     band_budget=budget), one), (threads, band_rows)
    # kernel strips of 1-3 rows (16 or 8 samples) in bands of 63-64 rows: strip boundaries
    # inside every band
    monkeypatch.setattr(render_module, "STRIP_BUDGET", 3 * scene.width * 8)
    assert np.array_equal(render_scene_rgba8(scene, threads=2,
                                             band_budget=64 * scene.width * 16), one)
    # and one strip for the whole image (the strips' rows cap lifted)
    monkeypatch.setattr(render_module, "STRIP_BUDGET", 1 << 20)
    monkeypatch.setattr(render_module, "MSAA_STRIP_ROWS", 256)
    assert np.array_equal(render_scene_rgba8(scene, threads=1), one)
    monkeypatch.undo()
    # every batch of several fills built and drawn region by region (Raster.fill_chunked),
    # regions of one strip (or of 4 mean fill heights) and of up to 1024 rows
    monkeypatch.setattr(render_module, "CHUNK_BYTES", 0)
    monkeypatch.setattr(render_module, "CHUNK_FILL_ROWS", float("inf"))
    for region in (1, 1 << 16):
        monkeypatch.setattr(render_module, "CHUNK_REGION_BYTES", region)
        for threads, band_rows in ((1, 5), (2, 64), (3, 1), (2, 2048)):
            assert np.array_equal(render_scene_rgba8(scene, threads=threads, band_budget=
                                                     band_rows * scene.width * 16), one), \
                (region, threads, band_rows)
    monkeypatch.undo()
    # PNG rows deflated as bands arrive: the bytes of the whole image's encoding
    png = encode_png(one)
    assert render_scene_png(scene) == png
    assert render_scene_png(scene, threads=3, band_budget=3 * scene.width * 16) == png
    assert np.array_equal(render_scene(scene, mode="analytic", threads=3, band_budget=
                                       7 * scene.width * 16),
                          render_scene(scene, mode="analytic"))


LAYERS_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="120" height="60">'
    '<clipPath id="c1"><circle cx="20" cy="30" r="10"/></clipPath>'
    '<clipPath id="c2"><rect x="35" y="5" width="40" height="50"/></clipPath>'
    '<mask id="m"><rect x="50" y="0" width="20" height="60" fill="#fff" fill-opacity="0.5"/>'
    '</mask>'
    '<rect width="120" height="60" fill="#888"/>'
    '<g clip-path="url(#c1)"><rect x="5" y="5" width="40" height="50" fill="#f00"/></g>'
    '<g clip-path="url(#c2)"><rect x="38" y="0" width="42" height="60" fill="#00f"/>'
    '<g mask="url(#m)"><rect x="45" y="10" width="30" height="40" fill="#0f0"/></g></g>'
    '<g opacity="0.5"><rect x="90" y="10" width="20" height="40" fill="#0a0"/></g></svg>')


def test_layers_band_by_band_on_kept_buffers():
    # layers, clips and masks are drawn on buffers kept from layer to layer and band to band,
    # cleared only in the columns their content can reach: what the last one drew there
    # (the red square, unclipped, reaches under the second group) must not show, at any
    # band size or thread count
    from vecmsaa.api import load_svg
    scene = load_svg(LAYERS_SVG.encode(), width=240)
    whole = render_scene(scene, band_budget=1 << 30)
    grey = np.float32(0x88 / 255)
    # device x 74-75 (user 37): inside the second clip, left of its content, outside the
    # first clip: the background; device x 40 (user 20): the first clip's centre, red
    assert np.array_equal(whole[60, 74:76], np.tile([grey, grey, grey, 1], (2, 1)))
    assert np.array_equal(whole[60, 40], np.float32([1, 0, 0, 1]))
    # the half-transparent group: its green at half opacity over the grey
    g = np.float32(0xaa / 255) * np.float32(0.5)
    want = np.float32([grey * np.float32(0.5), g + grey * np.float32(0.5),
                       grey * np.float32(0.5), 1])
    assert np.allclose(whole[60, 200], want, atol=1e-6)
    for budget in (240 * 16 * 16, 240 * 16 * 7):
        for threads in (1, 2):
            assert np.array_equal(render_scene(scene, band_budget=budget, threads=threads),
                                  whole), (budget, threads)


def random_paths(rng, count, empty, most):
    """``count`` random paths of lines, quadratics, cubics (loops among them) and conics, up
    to ``most`` - 1 segments, every third open; path i has no segment at all possibly when
    ``empty(i)``."""
    paths = []
    for i in range(count):
        path = Path()
        path.moveTo(tuple(rng.uniform(0, 100, 2)))
        for _ in range(int(rng.integers(0 if empty(i) else 1, most))):
            kind = rng.integers(4)
            pts = [tuple(rng.uniform(0, 100, 2)) for _ in range(3)]
            if kind == 0:
                path.lineTo(pts[0])
            elif kind == 1:
                path.qCurveTo(pts[0], pts[1])
            elif kind == 2:
                path.curveTo(*pts)
            else:
                path.conicTo(pts[0], pts[1], float(rng.uniform(0.2, 3)))
        if i % 3:
            path.closePath()
        paths.append(path)
    return paths


@pytest.mark.parametrize("threads", [2, 3, 5, 40])
def test_geometry_built_in_parts_is_the_geometry_built_whole(threads, monkeypatch):
    """A batch's edges and lenses built in parts on a band pool's threads
    (render.build_in_parts) and joined are those of the batch built at once: every array,
    offsets included, equal. Paths of lines, quadratics, cubics (loops among them) and conics,
    open and closed, one that draws nothing, and more threads than paths."""
    from vecmsaa.geometry.primitives import batch_arrays, build_batch
    paths = random_paths(np.random.default_rng(7), 30, empty=lambda i: i == 4, most=8)
    arrays = batch_arrays(paths)
    monkeypatch.setattr(render_module, "SPLIT_COST", 0)
    monkeypatch.setattr(render_module, "CURVE_SHARE", 0.0)
    # (a canvas that culls some of the paths' pieces: their geometry is built all the same)
    canvas = np.array([20.0, 30.0, 60.0, 70.0])
    for batch in (arrays, batch_arrays(paths[:2])):
        for tol in (0.0, 0.25):
            whole = build_batch(*batch, tol, render_module.MAX_SAGITTA, canvas)
            with render_module.band_pool(threads) as pool:
                parts = render_module.build_in_parts(*batch, tol, pool, canvas)()
            assert len(whole[2]) > 0 or tol > 0
            for a, b in zip(parts, whole):
                assert a.dtype == b.dtype and np.array_equal(a, b)


def test_one_path_alone_has_the_arrays_it_has_in_a_batch():
    """batch_arrays of one path (a shortcut) gives the verbs, points and offsets that path
    has in a batch of many, with the same dtypes and layout; and _fill_batches keeps or drops
    a lone fill (one that draws nothing, one with a NaN) as it does in a batch."""
    from vecmsaa.geometry.primitives import batch_arrays
    paths = random_paths(np.random.default_rng(17), 20, empty=lambda i: i < 3, most=6)
    nan = Path()
    nan.moveTo((1.0, 2.0))
    nan.lineTo((float("nan"), 3.0))
    nan.lineTo((4.0, 5.0))
    paths += [Path(), nan]
    verbs, pts, voff, poff = batch_arrays(paths)
    for i, path in enumerate(paths):
        v, p, vo, po = batch_arrays([path])
        assert v.dtype == verbs.dtype and p.dtype == pts.dtype and p.shape[1:] == (2,)
        assert vo.dtype == voff.dtype and po.dtype == poff.dtype
        assert v.flags.c_contiguous and p.flags.c_contiguous
        assert np.array_equal(v, verbs[voff[i]:voff[i + 1]])
        assert np.array_equal(p, pts[poff[i]:poff[i + 1]], equal_nan=True)
        assert vo.tolist() == [0, voff[i + 1] - voff[i]]
        assert po.tolist() == [0, poff[i + 1] - poff[i]]
    opts = RenderOptions()
    fills = [Fill(path, Solid((1, 0, 0, 1))) for path in paths]
    together = render_module._fill_batches(fills, opts)[0]
    kept = [f for f in fills if render_module._fill_batches([f], opts)]
    assert len(kept) == len(together.rules) < len(fills)
    assert not any(k is fills[-1] or k is fills[-2] for k in kept)     # NaN, empty
    # a lone fill's batch (its box from a shortcut) has the row it has in the batch of all
    for i, fill in enumerate(kept):
        alone = render_module._fill_batches([fill], opts)[0]
        for name in ("box", "rules", "aa", "kinds", "params"):
            a, b = getattr(alone, name), getattr(together, name)[i:i + 1]
            assert a.dtype == b.dtype and a.flags.c_contiguous and np.array_equal(a, b), name
        assert alone.rows == (alone.box[0, 1], alone.box[0, 3])
    # a few fills together (a shortcut below SMALL_BATCH fills): their rows of the batch of
    # all, those that draw nothing or hold a NaN left out as there
    index = {id(f): i for i, f in enumerate(kept)}
    for group in (fills[3:5], fills[5:8], fills[-5:], fills[:3], fills[8:16]):
        few = render_module._fill_batches(group, opts)
        rows = [index[id(f)] for f in group if id(f) in index]
        assert len(few) == (1 if rows else 0)
        if rows:
            for name in ("box", "rules", "aa", "kinds", "params"):
                a, b = getattr(few[0], name), getattr(together, name)[rows]
                assert a.dtype == b.dtype and a.flags.c_contiguous and np.array_equal(a, b), name
            assert few[0].rows == (few[0].box[:, 1].min(), few[0].box[:, 3].max())


#: shapes filtered alone, of a few widths (the same width again and again, as markers are),
#: one filtered group inside another of the same width, and a clip around a filtered group
MANY_FILTERED_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="120" height="90">'
    '<filter id="b" x="-50%" y="-50%" width="200%" height="200%">'
    '<feGaussianBlur stdDeviation="0.8"/></filter>'
    '<filter id="s" x="-20%" y="-20%" width="150%" height="150%">'
    '<feGaussianBlur in="SourceAlpha" stdDeviation="2"/><feOffset dx="2" dy="2" result="o"/>'
    '<feFlood flood-color="#000" flood-opacity="0.4"/><feComposite in2="o" operator="in"/>'
    '<feMerge><feMergeNode/><feMergeNode in="SourceGraphic"/></feMerge></filter>'
    '<clipPath id="c"><rect x="60" y="50" width="14" height="12"/></clipPath>'
    + "".join(f'<circle cx="{8 + 11.3 * k % 100}" cy="{6 + 7.1 * k % 40}" r="{3 + k % 3}" '
              f'fill="#c{k % 10}3" filter="url(#b)"/>' for k in range(24))
    + '<g filter="url(#b)"><g filter="url(#b)"><rect x="20" y="60" width="9" height="9" '
      'fill="#3a6"/></g></g>'
      '<g clip-path="url(#c)"><g filter="url(#s)"><rect x="62" y="52" width="12" height="9" '
      'rx="2" fill="#eef" stroke="#336"/></g></g>'
    + "".join(f'<rect x="{70 + 9 * (k % 5)}" y="{50 + 8 * (k // 5)}" width="6" height="5" '
              f'fill="#e{k}f" filter="url(#s)"/>' for k in range(10))
    + '</svg>')


def test_filtered_layers_on_kept_strip_buffers_draw_as_on_fresh_ones(monkeypatch):
    """Filtered layers take their rasters' strip buffers from a few kept for the render, by
    width (Raster.local): nested ones of one width included, on any band size and thread
    count, they draw what rasters of fresh buffers draw."""
    from vecmsaa.api import load_svg
    scene = load_svg(MANY_FILTERED_SVG.encode(), width=240)
    kept = render_scene_rgba8(scene)
    assert kept[..., 3].any()
    for budget, threads in ((scene.width * 16 * 7, 2), (scene.width * 16 * 40, 3)):
        assert np.array_equal(render_scene_rgba8(scene, band_budget=budget, threads=threads),
                              kept)
    monkeypatch.setattr(render_module, "LOCAL_KIT_BYTES", 0)
    assert np.array_equal(render_scene_rgba8(scene), kept)
    monkeypatch.setattr(render_module, "LOCAL_KIT_BYTES", 4 << 20)
    monkeypatch.setattr(render_module, "LOCAL_KITS", 1)      # every other width evicts
    assert np.array_equal(render_scene_rgba8(scene, threads=2), kept)


def test_bands_are_taken_heaviest_first_unless_a_layer_is_filtered():
    """render.heaviest_first puts the band that most fills' edges reach first (the threads
    take bands in that order; the image does not depend on it), and keeps the bands top down
    where a filtered layer would be filtered again for a band above its last."""
    from vecmsaa.api import load_svg
    light = Fill(circle_path((30, 8), 5), Solid((1, 0, 0, 1)))
    heavy = [Fill(circle_path((4 + 3 * k, 50), 1), Solid((0, 0, 1, 1))) for k in range(18)]
    scene = Scene(61, 61, Group([light, *heavy]))
    items = render_module.prepare_items(scene.root, RenderOptions())
    order = render_module.heaviest_first(items, range(0, 61, 16), 16)
    assert sorted(order) == [0, 16, 32, 48] and order[0] == 48
    filtered = load_svg(FILTERED_SVG)
    items = render_module.prepare_items(filtered.root, RenderOptions())
    assert list(render_module.heaviest_first(items, range(0, 80, 16), 16)) == [0, 16, 32, 48, 64]


def many_layers_scene(size=97, count=60, seed=7):
    """Small clipped, masked and faded groups scattered over the image, some nested: many
    layers a band (the case BandPace keeps one thread for)."""
    rng = np.random.default_rng(seed)
    groups = []
    for k in range(count):
        x, y, r = *rng.uniform(5, size - 5, 2), rng.uniform(2, 9)
        shape = Fill(circle_path((x, y), r), Solid((*rng.uniform(0, 1, 3), 1)))
        kind = k % 4
        if kind == 0:
            groups.append(Group([shape], opacity=0.6))
        elif kind == 1:
            groups.append(Group([shape], clip=Group([Fill(circle_path((x + 1, y), r * 0.8))])))
        elif kind == 2:
            groups.append(Group([shape], mask=Mask(Group([Fill(circle_path((x, y + 1), r),
                                                               Solid((1, 1, 1, 0.7)))]))))
        else:
            groups.append(Group([Group([shape], opacity=0.5), shape], opacity=0.8))
    return Scene(size, size, Group(groups), background=(1, 1, 1, 1))


@pytest.mark.parametrize("decision", ["join", "alone"])
@pytest.mark.parametrize("source", ["many", "layered", "filtered", "markers"])
def test_paced_band_threads_give_the_same_bytes(source, decision, monkeypatch):
    """Whether the first band says the other threads join (and take the bands left heaviest
    first) or says this thread draws the rest alone (the bands left regrouped, up to the
    one-thread band size), the image is the one thread's, byte for byte."""
    from vecmsaa.api import load_svg
    scene = {"many": many_layers_scene, "layered": lambda: layered_scene(61),
             "filtered": lambda: load_svg(FILTERED_SVG),
             "markers": lambda: load_svg(MARKERS_SVG, width=211)}[source]()
    one = render_scene_rgba8(scene, threads=1)
    assert one[..., 3].any()
    monkeypatch.setattr(render_module, "ITEMS_PER_BAND_AT_ONCE", 0)
    monkeypatch.setattr(render_module, "PARALLEL_ITEM_SECONDS",
                        0.0 if decision == "join" else math.inf)
    monkeypatch.setattr(render_module, "MIN_SHARED_SECONDS",
                        0.0 if decision == "join" else math.inf)
    seen = []
    decide = render_module.BandPace.band_drawn

    def band_drawn(pace, seconds, drawn, *rows_and_cpu):
        seen.append(drawn)
        decide(pace, seconds, drawn, *rows_and_cpu)
    monkeypatch.setattr(render_module.BandPace, "band_drawn", band_drawn)
    # budgets of 5 rows (the threads' bands and one thread's alike), 64 and the default (one
    # thread's bands larger than the threads': the bands left are joined)
    for threads in (2, 3):
        for budget in (5 * scene.width * 16, 64 * scene.width * 16, render_module.BAND_BUDGET):
            assert np.array_equal(render_scene_rgba8(scene, threads=threads,
                                                     band_budget=budget), one), (threads, budget)
    assert seen and seen[-1] > 0        # the pace decided (on a band that drew something)
    assert np.array_equal(render_scene(scene, threads=2, band_budget=5 * scene.width * 16),
                          render_scene(scene))


def test_regrouped_bands_cover_every_row_once_in_bands_of_at_most_the_solo_rows():
    pace = render_module.BandPace([], range(0, 100, 10), 10, 35)
    left = [(90, 10), (20, 10), (0, 10), (30, 10), (40, 10), (70, 10), (60, 10), (50, 10)]
    bands = pace.regroup(left)
    assert bands == [(0, 10), (20, 30), (50, 30), (90, 10)]
    assert sorted(y for y0, rows in bands for y in range(y0, y0 + rows)) == \
        sorted(y for y0, rows in left for y in range(y0, y0 + rows))


def test_heaviest_first_weighs_every_fill_of_nested_layers():
    """heaviest_first's order against the weights summed fill by fill in plain Python: a fill's
    edges and lenses spread evenly over the bands its box reaches, plus AREA_COST for each
    pixel of its box's width in each band, fills inside layers, clips and masks included."""
    scene = many_layers_scene(size=230, count=90, seed=3)
    items = render_module.prepare_items(scene.root, RenderOptions())
    band_rows, starts = 16, range(0, 230, 16)
    weight = [0.0] * len(starts)
    todo = list(items)
    while todo:
        item = todo.pop()
        if not isinstance(item, render_module.FillBatch):
            todo += item.items + [p for p in (item.clip, item.mask) if p is not None]
            continue
        for k, (x0, y0, x1, y1) in enumerate(item.box.tolist()):
            first = min(max(math.floor(y0 / band_rows), 0), len(starts))
            last = min(max(math.floor(y1 / band_rows), -1), len(starts) - 1)
            work = int(item.edge_off[k + 1] - item.edge_off[k]) + \
                int(item.prim_off[k + 1] - item.prim_off[k])
            for band in range(first, last + 1):
                weight[band] += work / (last - first + 1) + \
                    render_module.AREA_COST * band_rows * (max(x1, 0) - max(x0, 0))
    order = render_module.heaviest_first(items, starts, band_rows)
    assert sorted(order) == list(starts)
    by_weight = [weight[y // band_rows] for y in order]
    # heaviest first, up to rounding between sums taken in another order
    assert all(a >= b - 1e-9 * max(1.0, b) for a, b in zip(by_weight, by_weight[1:]))
    assert by_weight[0] > by_weight[-1]


def _polyline_fill(points):
    return Fill(polygon_path(points), Solid((0, 0, 0, 1)))


def test_a_band_under_a_wide_fill_weighs_more_than_its_edges_say():
    """A band that a 2000 px wide rectangle covers (4 edges) comes before one holding a small
    polygon of 30 edges: a fill's box area counts (the sweep paints its pixels), not its edges
    alone."""
    wide = _polyline_fill([(0.0, 770.0), (2000.0, 770.0), (2000.0, 1010.0), (0.0, 1010.0)])
    ring = [(300 + 8 * math.cos(2 * math.pi * k / 30), 300 + 8 * math.sin(2 * math.pi * k / 30))
            for k in range(30)]
    scene = Scene(2000, 1200, Group([wide, _polyline_fill(ring)]))
    items = render_module.prepare_items(scene.root, RenderOptions())
    assert render_module.heaviest_first(items, range(0, 1200, 256), 256)[:2] == [768, 256]


@pytest.mark.parametrize("mode", ["approx", "analytic"])
@pytest.mark.parametrize("far", ["1e12", "1e20", "1e300"])
def test_an_edge_reaching_far_off_the_canvas_draws_what_it_covers(mode, far):
    # (20, 20) → (far, 20) → (100, 100): on the canvas the edge back from the far point is
    # horizontal at y = 100 (it rises 80 over `far`: under 1e-10 px by x = 200), so the
    # triangle covers what the quadrilateral (20, 20) (300, 20) (300, 100) (100, 100) covers.
    # Its crossings were taken from its far end and lost to rounding, and fell on any
    # column, into the frame drawn after it too (a black band across the canvas).
    from vecmsaa.api import render_svg_array
    frame = '<rect x="1" y="1" width="198" height="198" fill="none" stroke="black"/>'

    def draw(d):
        return render_svg_array(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">'
                                f'<path d="{d}" fill="green"/>{frame}</svg>'.encode(),
                                width=300, mode=mode)
    assert np.array_equal(draw(f"M 20 20 L {far} 20 L 100 100 Z"),
                          draw("M 20 20 L 300 20 L 300 100 L 100 100 Z"))


#: groups holding one filtered group and nothing else: clipped, masked, translucent, around
#: the canvas edge, a clip with a filtered shape of its own, and markers with a blurred dot
SOLE_FILTERED_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="70">'
    '<filter id="b" x="-50%" y="-50%" width="200%" height="200%">'
    '<feGaussianBlur stdDeviation="2.5"/></filter>'
    '<clipPath id="c"><circle cx="20" cy="20" r="13"/></clipPath>'
    '<clipPath id="e"><rect x="-5" y="45" width="30" height="30"/></clipPath>'
    '<clipPath id="f"><rect x="60" y="5" width="30" height="25" filter="url(#b)"/></clipPath>'
    '<mask id="m"><rect x="40" y="0" width="30" height="70" fill="#fff" fill-opacity="0.6"/>'
    '</mask>'
    '<marker id="k" markerWidth="8" markerHeight="8" refX="4" refY="4" '
    'markerUnits="userSpaceOnUse"><circle cx="4" cy="4" r="3" fill="#c33" filter="url(#b)"/>'
    '</marker>'
    '<rect width="100" height="70" fill="#ddd"/>'
    '<g clip-path="url(#c)"><g filter="url(#b)"><rect x="10" y="8" width="22" height="20" '
    'fill="#36c"/></g></g>'
    '<g mask="url(#m)" opacity="0.7"><g filter="url(#b)"><circle cx="50" cy="35" r="14" '
    'fill="#393"/></g></g>'
    '<g clip-path="url(#e)" opacity="0.5"><g filter="url(#b)"><rect x="-3" y="48" width="20" '
    'height="30" fill="#c60"/></g></g>'
    '<g clip-path="url(#f)"><g filter="url(#b)"><rect x="62" y="8" width="30" height="18" '
    'fill="#909"/></g></g>'
    '<polyline points="10,60 40,52 70,64 95,40" fill="none" stroke="#333" '
    'marker-mid="url(#k)"/></svg>')


def test_a_group_of_one_filtered_group_composites_its_filtered_pixels(monkeypatch):
    """A layer holding one filtered layer and nothing else composites that layer's filtered
    pixels with its own clip, mask and opacity, without drawing them onto a buffer first
    (render._sole_filtered): the bytes of drawing them onto one, at any band size and thread
    count."""
    from vecmsaa.api import load_svg
    scene = load_svg(SOLE_FILTERED_SVG.encode(), width=200)
    short = render_scene_rgba8(scene)
    items = render_module.prepare_items(scene.root, RenderOptions())
    assert sum(isinstance(i, render_module.Layer) and i.sole is not None for i in items) >= 4
    for budget, threads in ((200 * 16 * 5, 2), (200 * 16 * 33, 3)):
        assert np.array_equal(render_scene_rgba8(scene, band_budget=budget, threads=threads),
                              short)
    monkeypatch.setattr(render_module, "_sole_filtered", lambda layer: None)
    assert np.array_equal(render_scene_rgba8(scene), short)
    assert np.array_equal(render_scene_rgba8(scene, band_budget=200 * 16 * 5, threads=2), short)


def test_each_filtered_layer_is_filtered_once_a_render_for_any_bands(monkeypatch):
    """A layer is rendered and filtered once a render, whatever the bands: its filter regions
    (twice the content's size) reach rows below the pixels its blur can touch, and the bands
    there asked for its pixels after the band of their last row had let them go, filtering
    it again (200 bands: 24 times). The bytes are the one-band image's."""
    from collections import Counter
    from vecmsaa.api import load_svg
    scene = load_svg('<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">'
                     '<filter id="b" x="-50%" y="-50%" width="200%" height="200%">'
                     '<feGaussianBlur stdDeviation="2"/></filter>'
                     '<rect x="75" y="50" width="50" height="50" fill="teal" filter="url(#b)"/>'
                     '<g opacity="0.5"><circle cx="40" cy="120" r="20" fill="#c60" '
                     'filter="url(#b)"/></g></svg>')
    calls = Counter()
    filtered = render_module.render_filtered

    def counted(layer, raster):
        calls[id(layer)] += 1
        return filtered(layer, raster)
    monkeypatch.setattr(render_module, "render_filtered", counted)
    whole = render_scene_rgba8(scene, band_budget=1 << 30)
    assert len(calls) == 2
    for budget, threads in ((200 * 16, 1), (200 * 16 * 5, 1), (200 * 16 * 5, 2),
                            (200 * 16 * 33, 3)):
        calls.clear()
        assert np.array_equal(render_scene_rgba8(scene, band_budget=budget, threads=threads),
                              whole)
        assert max(calls.values()) == 1, (budget, threads)


def test_a_band_above_finds_the_pixels_the_band_of_their_last_row_was_done_with(monkeypatch):
    """Bands on threads: the band holding a filtered layer's last rows can be done with it
    before a band above has reached it. That band gets the same pixels, without filtering it
    again, and they go once it is drawn (BandsDrawn)."""
    from vecmsaa.api import load_svg
    scene = load_svg('<svg xmlns="http://www.w3.org/2000/svg" width="60" height="60">'
                     '<filter id="f"><feGaussianBlur '
                     'stdDeviation="3"/></filter><rect x="10" y="10" width="40" height="40" '
                     'fill="#36c" filter="url(#f)"/></svg>')
    opts = RenderOptions()
    (a, b, c, d), whole = render_module.filtered_part(
        render_module.prepare_items(scene.root, opts)[0], 0, 60, 60,
        render_module.Raster(opts, 60, 60, 4))
    layer, = render_module.prepare_items(scene.root, opts)
    count = []
    filtered = render_module.render_filtered
    monkeypatch.setattr(render_module, "render_filtered",
                        lambda *a: count.append(1) or filtered(*a))
    drawn = render_module.BandsDrawn(60)
    lower, upper = (render_module.Raster(opts, 60, 60, 4) for _ in range(2))
    for raster, start in ((lower, 30), (upper, 0)):
        raster.bands, raster.band_start = drawn, start
    low = render_module.filtered_part(layer, 30, 30, 60, lower)
    drawn.band_done(30, 30)
    assert layer.filtered[id(opts)][1] is not None      # kept for the band above
    high = render_module.filtered_part(layer, 0, 30, 60, upper)
    assert len(count) == 1 and high is not None and low is not None
    for y0, ((pa, pb, pc, pd), pixels) in ((0, high), (30, low)):
        # the one-band pixels of the same device rows
        assert (pc, pd) == (c, d) and np.array_equal(pixels, whole[y0 + pa - a:y0 + pb - a])
    drawn.band_done(0, 30)
    assert layer.filtered[id(opts)][1] is None          # let go, its box kept


def test_filtered_fills_moved_as_batched_draw_as_the_moved_group(monkeypatch):
    """Plain fills of a flat colour under filters placing nothing by device position are
    moved into the filter region as they are batched (render._flat_solid), not as a moved
    copy of the group: the same bytes, for regions at the canvas corner (no move) and off it,
    and for a filter with a light (moved as a group either way)."""
    from vecmsaa.api import load_svg
    corner = ('<svg xmlns="http://www.w3.org/2000/svg" width="60" height="40">'
              '<filter id="b" x="0" y="0" width="40" height="30" filterUnits="userSpaceOnUse">'
              '<feGaussianBlur stdDeviation="1.5"/><feOffset dx="-2" dy="3"/></filter>'
              '<filter id="l"><feDiffuseLighting><fePointLight x="30" y="10" z="20"/>'
              '</feDiffuseLighting><feComposite in2="SourceGraphic" operator="in"/></filter>'
              '<path d="M-0 0 L 20.5 0 L 0 15.25 Z" fill="#c60" filter="url(#b)"/>'
              '<circle cx="42" cy="22" r="9" fill="#36c" filter="url(#l)"/></svg>')
    scenes = [load_svg(doc.encode(), width=width) for doc, width in
              ((corner, 60), (corner, 137), (MANY_FILTERED_SVG, 240), (SOLE_FILTERED_SVG, 200))]
    batched = [render_scene_rgba8(s) for s in scenes]
    assert all(b[..., 3].any() for b in batched)
    monkeypatch.setattr(render_module, "_flat_solid", lambda group: False)
    for scene, want in zip(scenes, batched):
        assert np.array_equal(render_scene_rgba8(scene), want)


def test_content_outside_its_clip_is_not_prepared_and_not_drawn(monkeypatch):
    """Groups whose clip or mask misses their content draw nothing: their content is not
    prepared (render.Layer's bound), and the image is the one without them. Batches and
    nested groups outside the clip's rows are left out: the same bytes as keeping them, at
    any band size and thread count."""
    from vecmsaa.api import load_svg
    head = ('<svg xmlns="http://www.w3.org/2000/svg" width="90" height="80">'
            '<clipPath id="c"><circle cx="20" cy="15" r="9"/></clipPath>'
            '<clipPath id="d"><rect x="40" y="30" width="40" height="14"/></clipPath>'
            '<mask id="m"><rect x="0" y="60" width="90" height="20" fill="#fff"/></mask>'
            '<rect width="90" height="80" fill="#eee"/>'
            '<path d="M5 75 L85 5" stroke="#333" stroke-width="3"/>')
    seen = ('<g clip-path="url(#d)"><rect x="30" y="5" width="50" height="8" fill="#c00"/>'
            '<rect x="35" y="25" width="50" height="12" fill="#0a0"/>'
            '<g opacity="0.5"><circle cx="60" cy="70" r="6" fill="#00c"/>'
            '<circle cx="60" cy="40" r="6" fill="#00c"/></g>'
            '<g clip-path="url(#c)"><rect x="40" y="38" width="9" height="9" fill="#fa0"/>'
            '</g></g>'
            '<g mask="url(#m)"><rect x="10" y="20" width="20" height="20" fill="#0cc"/>'
            '<path d="M10 50 L 40 78" stroke="#c0c" stroke-width="4" shape-rendering='
            '"crispEdges"/></g>')
    unseen = ''.join(f'<g clip-path="url(#c)"><rect x="{50 + k}" y="{40 + 3 * k}" width="9" '
                     f'height="9" fill="#00f"/><path d="M{50 + k} {40 + 3 * k}l9 9" '
                     f'stroke="#fff"/></g>' for k in range(8)) + \
        '<g mask="url(#m)"><circle cx="30" cy="20" r="9" fill="#f0f"/></g>'
    doc = head + seen + unseen + '</svg>'
    scene = load_svg(doc.encode(), width=180)
    image = render_scene_rgba8(scene)
    assert np.array_equal(image, render_svg_rgba8(head + seen + '</svg>', 180))
    opts = RenderOptions()
    layers = [i for i in render_module.prepare_items(scene.root, opts)
              if isinstance(i, render_module.Layer)]
    assert len(layers) == 11 and all(not l.items and l.rows is None for l in layers[2:])
    assert len(layers[0].items) < 4          # the red rectangle left out
    for budget, threads in ((180 * 16 * 3, 2), (180 * 16 * 40, 3)):
        assert np.array_equal(render_scene_rgba8(scene, band_budget=budget, threads=threads),
                              image)
    monkeypatch.setattr(render_module, "_beyond", lambda lo, hi, bound: False)
    assert np.array_equal(render_scene_rgba8(scene), image)
    assert np.array_equal(render_scene_rgba8(scene, band_budget=180 * 16 * 3, threads=2), image)


def render_svg_rgba8(doc: str, width: int) -> np.ndarray:
    from vecmsaa.api import load_svg
    return render_scene_rgba8(load_svg(doc.encode(), width=width))


_RECT_CLIPS_SVG = b'''<svg xmlns="http://www.w3.org/2000/svg" width="120" height="90">
<clipPath id="big"><rect x="5.3" y="4.7" width="60" height="40"/></clipPath>
<clipPath id="tight"><rect x="20.5" y="50.2" width="31" height="21"/></clipPath>
<clipPath id="turned"><rect x="70" y="5" width="40" height="30" transform="rotate(20 90 20)"/>
</clipPath>
<clipPath id="crisp"><rect x="70.4" y="45.6" width="45" height="40" shape-rendering="crispEdges"/>
</clipPath>
<clipPath id="bbox" clipPathUnits="objectBoundingBox"><rect x="-0.2" y="-0.2" width="1.4"
 height="1.4"/></clipPath>
<mask id="m"><circle cx="10" cy="77" r="5" fill="#ccc"/></mask>
<mask id="obb" maskContentUnits="objectBoundingBox"><rect width="1" height="1" fill="#fff"
 opacity="0.6"/><circle cx=".5" cy=".5" r=".3"/></mask>
<g clip-path="url(#big)"><rect x="12" y="10" width="30" height="20" fill="#c30"/>
<g opacity="0.5"><circle cx="40" cy="25" r="9" fill="#03c"/></g></g>
<g clip-path="url(#tight)"><rect x="21" y="51" width="30" height="20" fill="#3a3"/></g>
<g clip-path="url(#turned)"><circle cx="90" cy="20" r="8" fill="#a0a"/></g>
<g clip-path="url(#crisp)"><circle cx="92" cy="65" r="10" fill="#0aa"/></g>
<g clip-path="url(#bbox)"><circle cx="30" cy="80" r="6" fill="#fa0" stroke="#000"/></g>
<g mask="url(#obb)"><rect x="75" y="55" width="40" height="30" fill="#f0f"/></g>
<g mask="url(#m)"><rect x="2" y="68" width="20" height="18" fill="#00f"/></g>
</svg>'''


@pytest.mark.parametrize("mode", ["approx", "persample", "alpha", "a2c", "analytic"])
def test_rectangle_clips_around_their_content_are_left_out_without_changing_a_pixel(
        mode, monkeypatch):
    # brute force: the same pixels with every rectangle clip drawn (the shortcut refused) and
    # with those that cover their content left out; the shortcut is taken where the content
    # lies a pixel inside (the big clip, the bounding-box clip, the masks' regions) and
    # refused where it reaches the rectangle's edge pixels (tight), for turned and aliased
    # rectangles, and in the exact modes
    from vecmsaa.api import load_svg
    scene = load_svg(_RECT_CLIPS_SVG, width=240)
    covers = render_module._clip_covers
    taken = []

    def counting(rect, items):
        got = covers(rect, items)
        taken.append(got)
        return got
    monkeypatch.setattr(render_module, "_clip_covers", counting)
    shortcut = render_scene(scene, mode, 8)
    if mode == "analytic":
        assert taken == []
    else:
        # big, bbox, the two masks' regions (and the obb mask's opacity layer has none);
        # tight refused
        assert taken.count(True) == 4 and taken.count(False) == 1, taken
    monkeypatch.setattr(render_module, "_clip_covers", lambda rect, items: False)
    assert np.array_equal(render_scene(scene, mode, 8), shortcut)


def test_small_batches_tables_and_boxes_are_the_general_ones():
    # a small batch's solid paint table (shaders.solid_arrays), its boxes from Python floats
    # (render._extremes) and its x range (FillBatch.cols) against PaintTable and numpy's
    # reductions over the same fills
    from vecmsaa.raster.shaders import PaintTable, solid_arrays, solid_row
    rng = np.random.default_rng(21)
    for n in (1, 2, 5):
        fills = [Fill(Path.from_arrays(np.array([0, 1, 1, 4], np.uint8),
                                       rng.uniform(-50, 50, (3, 2))),
                      Solid(tuple(rng.uniform(0, 1, 4))), opacity=float(rng.uniform(0, 1)))
                 for _ in range(n)]
        table = PaintTable()
        table.add_fills(fills, None)
        for got, want in zip(solid_arrays([solid_row(f.paint, f.opacity) for f in fills]),
                             table.arrays()):
            assert got.dtype == want.dtype and np.array_equal(got, want)
        arrays = render_module._shifted_arrays(fills, None)
        pts, poff = arrays[1], arrays[3]
        ext = render_module._extremes(pts, poff)
        for (x0, y0, x1, y1), a, b in zip(ext, poff[:-1], poff[1:]):
            assert (x0, y0, x1, y1) == (*pts[a:b].min(axis=0), *pts[a:b].max(axis=0))
        batch = render_module.FillBatch(fills, *arrays, RenderOptions(), extremes=ext)
        assert batch.cols == (batch.box[:, 0].min(), batch.box[:, 2].max())


@given(st.lists(st.tuples(st.sampled_from([-np.inf, -3.5, -0.25, 0.0, 2.0, 7.999, 8.0, 11.5,
                                           16.0, 30.0, 33.0, np.inf, np.nan]),
                          st.sampled_from([-np.inf, -1.0, 0.0, 0.5, 4.0, 8.0, 15.999, 16.0,
                                           19.0, 23.5, 24.0, 40.0, np.inf, np.nan]),
                          st.sampled_from([-np.inf, -2.0, 0.0, 3.0, 20.0, 29.0, 30.0, np.nan]),
                          st.floats(-3, 45, allow_nan=False, width=32)), max_size=40),
       st.integers(-5, 20), st.integers(0, 40), st.integers(1, 9))
@settings(max_examples=300, deadline=None)
def test_each_strip_visits_the_fills_whose_boxes_meet_it_in_batch_order(boxes, y0, H, strip):
    """strip_buckets and strip_fills (render_msaa's, render_csaa's and render_analytic's
    lists of the fills each strip draws) against the box test done on every fill and strip
    (the kernels' test before: box y1 >= the strip's first row, box y0 < its end, box x0 < W,
    box x1 >= 0; NaN and infinite boxes included), in batch order."""
    from vecmsaa.raster.scan import strip_buckets, strip_fills
    W = 30
    box = np.array([(x0, ya, x1, ya + dy) for x0, ya, x1, dy in boxes],
                   np.float64).reshape(-1, 4)
    for left in (True, False):
        start, order, last = strip_buckets(box, y0, H, W, strip, left)
        now, then = np.empty(len(order), np.int32), np.empty(len(order), np.int32)
        n = 0
        for s, sy0 in enumerate(range(y0, y0 + H, strip)):
            rows = min(strip, y0 + H - sy0)
            want = [k for k in range(len(box))
                    if not (box[k, 3] < sy0 or box[k, 1] >= sy0 + rows)
                    and not (box[k, 0] >= W or (left and box[k, 2] < 0.0))]
            now, then = then, now
            n = strip_fills(then, n, order, start[s], start[s + 1], last, s, now)
            assert now[:n].tolist() == want, (s, left)


def test_batch_extents_are_each_paths_drawing_finite_points_and_their_box():
    """batch_extents (which of a batch's paths _fill_batches keeps, and their points' boxes)
    against each path's verbs and points looked at one by one: kept where some verb is
    neither MOVE nor CLOSE and every coordinate is finite; the box the points' extremes."""
    from vecmsaa.geometry.primitives import batch_arrays, batch_extents
    from vecmsaa.scene.path import CLOSE, MOVE
    rng = np.random.default_rng(3)
    paths = []
    for i in range(60):
        p = Path()
        p.moveTo(tuple(rng.uniform(-50, 50, 2)))
        for _ in range(i % 4):
            p.lineTo(tuple(rng.uniform(-50, 50, 2)))
        if i % 5 == 0:
            p.closePath()
        paths.append(p)
    paths[7].lineTo((np.nan, 3.0))
    paths[11].lineTo((2.0, np.inf))
    paths[13].moveTo((-np.inf, 0.0))
    verbs, pts, voff, poff = batch_arrays(paths)
    keep, box = batch_extents(verbs, pts, voff, poff)
    for k in range(len(paths)):
        v = verbs[voff[k]:voff[k + 1]].tolist()
        q = pts[poff[k]:poff[k + 1]]
        draws = any(x not in (MOVE, CLOSE) for x in v)
        finite = all(math.isfinite(c) for c in q.ravel().tolist())
        assert keep[k] == (draws and finite), k
        if finite:
            assert box[k].tolist() == [min(q[:, 0]), min(q[:, 1]), max(q[:, 0]), max(q[:, 1])]
    assert keep[[7, 11, 13]].tolist() == [False, False, False]
    assert not keep[[i for i in range(60) if i % 4 == 0 and i not in (7, 11, 13)]].any()
