"""Sample patterns and resolve filters (raster/sample_patterns.py, raster/resolve.py) against
independent truth: exact half-plane areas, point-in-shape at the pattern's positions (tests/
truth.py's root-finding winding numbers, or a crossing count on polygons) and brute-force
filtering of those points."""
import math

import numpy as np
import pytest

from truth import polygon_pixel_coverage, segments, winding_at
from vecmsaa.raster.modes import FILTERS, PATTERN_NAMES
from vecmsaa.raster.render import render_scene, render_scene_rgba8
from vecmsaa.raster.resolve import RADIUS, filter_weight
from vecmsaa.raster.sample_patterns import FIXED_SAMPLES, sample_pattern
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import Path

COUNTS = (1, 2, 4, 8, 16)


def counts(name):
    return (FIXED_SAMPLES[name],) if name in FIXED_SAMPLES else COUNTS


ALL = [(name, n) for name in PATTERN_NAMES for n in counts(name)]


def positions(name, n, px, py):
    """(k, 2) sample positions and (k,) weights that pixel (px, py)'s value is made of, with
    the pattern's own filter (quincunx's tent, else the box): written from each pattern's
    definition (quincunx, FLIPQUAD) or its offsets, not from the raster's tables."""
    if name == "quincunx":
        pts = [(px + 0.5, py + 0.5)] + [(px + i, py + j) for j in (0, 1) for i in (0, 1)]
        return np.array(pts), np.array([0.5, 0.125, 0.125, 0.125, 0.125])
    if name == "flipquad":
        base = np.array([(1 / 3, 0.0), (1.0, 1 / 3), (2 / 3, 1.0), (0.0, 2 / 3)])
        if px % 2:
            base[:, 0] = 1 - base[:, 0]
        if py % 2:
            base[:, 1] = 1 - base[:, 1]
        return base + (px, py), np.full(4, 0.25)
    pat = sample_pattern(name, n)
    tw, th = pat.tile
    offs = pat.offsets[(py % th) * tw + px % tw]
    return offs + (px + 0.5, py + 0.5), np.full(len(offs), 1.0 / len(offs))


def distinct_positions(name, n, px, py):
    """The positions pixel (px, py) adds to the image's set of samples: every sample once
    (quincunx's top-left corner, FLIPQUAD's top and left edge samples are its own)."""
    pts = positions(name, n, px, py)[0]
    if name == "quincunx":
        return pts[:2]
    if name == "flipquad":
        return pts[(pts[:, 1] == py) | (pts[:, 0] == px)]
    return pts


def inside_polygon(poly, x, y):
    """Even-odd crossing count of points (x, y) against a polygon (vectorised)."""
    poly = np.asarray(poly, dtype=np.float64)
    inside = np.zeros(np.shape(x), dtype=bool)
    for (ax, ay), (bx, by) in zip(poly, np.roll(poly, -1, axis=0)):
        if ay == by:
            continue
        crosses = (ay <= y) != (by <= y)
        xc = ax + (y - ay) * (bx - ax) / (by - ay)
        inside ^= crosses & (x < xc)
    return inside


def polygon_path(poly):
    path = Path()
    path.moveTo(tuple(poly[0]))
    for p in poly[1:]:
        path.lineTo(tuple(p))
    path.closePath()
    return path


def scene_of(path, size):
    return Scene(size, size, Group([Fill(path, Solid((0, 0, 0, 1)))]))


# a quadrilateral with near-horizontal and near-vertical edges and a slanted one, off the
# sample grid (irrational offsets)
QUAD = np.array([(2.1 + 1e-3 * math.pi, 1.3), (13.7, 2.05 + 1e-4 * math.e), (12.9, 14.2),
                 (1.6, 11.1 + 1e-3 * math.sqrt(2))])


@pytest.mark.parametrize("name,n", ALL)
def test_offsets_lie_in_their_pixel_and_are_fixed(name, n):
    pat = sample_pattern(name, n)
    assert pat.offsets.shape[1:] == (FIXED_SAMPLES.get(name, n), 2)
    assert pat.offsets.min() >= -0.5 and pat.offsets.max() < 0.5
    # fixed seeds and constructions: the same positions every time
    assert np.array_equal(pat.offsets, sample_pattern(name, n).offsets)
    for k in range(len(pat.offsets)):
        assert len({tuple(p) for p in pat.offsets[k]}) == pat.samples


def _random_lines(lines=1500):
    """Random lines through (or near) a pixel, as unit normals and distances, with the exact
    area of the half-plane <x, n> + d < 0 in the pixel (offsets from its centre), clipped
    exactly (truth.polygon_pixel_coverage of a large polygon on that side)."""
    rng = np.random.default_rng(5)
    theta = rng.uniform(0, 2 * math.pi, lines)
    d = rng.uniform(-0.6, 0.6, lines)
    nx, ny = np.cos(theta), np.sin(theta)
    area = np.empty(lines)
    for i in range(lines):
        # the half-plane as a big square's part: the foot of the line, ±10 along it, 10 behind
        fx, fy = -d[i] * nx[i] + 0.5, -d[i] * ny[i] + 0.5
        tx, ty = -ny[i], nx[i]
        poly = [(fx + 10 * tx, fy + 10 * ty), (fx - 10 * tx, fy - 10 * ty),
                (fx - 10 * tx - 10 * nx[i], fy - 10 * ty - 10 * ny[i]),
                (fx + 10 * tx - 10 * nx[i], fy + 10 * ty - 10 * ny[i])]
        area[i] = polygon_pixel_coverage(poly, 1, 1)[0, 0]
    return nx, ny, d, area


LINES = None


def _half_plane_errors(offs):
    """|fraction of samples in <x, n> + d < 0  -  the half-plane's area in the pixel| for random
    lines through the pixel, and the same expected for n independent uniform samples."""
    global LINES
    if LINES is None:
        LINES = _random_lines()
    nx, ny, d, area = LINES
    n = len(offs)
    frac = ((offs[:, 0][None] * nx[:, None] + offs[:, 1][None] * ny[:, None] + d[:, None]) < 0
            ).mean(axis=1)
    err = np.abs(frac - area)
    # E|Binomial(n, p)/n - p| for independent uniform samples
    k = np.arange(n + 1)
    comb = np.array([math.comb(n, i) for i in k], dtype=np.float64)
    p = area[:, None]
    mc = (comb * p ** k * (1 - p) ** (n - k) * np.abs(k / n - p)).sum(axis=1)
    return err, mc


@pytest.mark.parametrize("name", ["d3d", "grid", "rgss", "rooks", "jittered", "poisson",
                                  "interleaved"])
def test_half_plane_coverage_beats_independent_samples_and_converges(name):
    """Over random edges through a pixel, a pattern's coverage error is below what n
    independent uniform samples would give (the Monte Carlo bound from the sample count), and
    falls as samples are added."""
    means = []
    for n in counts(name):
        if n < 4:
            continue
        pat = sample_pattern(name, n)
        for offs in pat.offsets:
            err, mc = _half_plane_errors(offs)
            assert err.mean() < mc.mean(), (name, n, err.mean(), mc.mean())
        means.append(err.mean())
    assert means == sorted(means, reverse=True)


@pytest.mark.parametrize("name", ["d3d", "rgss", "rooks", "interleaved"])
def test_patterns_with_distinct_rows_and_columns_resolve_axis_edges_to_one_over_n(name):
    """n samples on n distinct x (and y): a vertical (horizontal) edge's coverage is within 1/n
    of its area, where the ordered grid's √n columns give only 1/√n."""
    for n in counts(name):
        for offs in sample_pattern(name, n).offsets:
            for axis in (0, 1):
                for t in np.linspace(-0.5, 0.5, 97):
                    assert abs((offs[:, axis] < t).mean() - (t + 0.5)) <= 1.0 / n + 1e-12


def test_flipquad_and_quincunx_share_samples_with_their_neighbours():
    """Every FLIPQUAD sample on an inner pixel edge is one of the neighbour's four; quincunx's
    corners are its neighbours' corners: 2 stored samples stand for 4 (5) in the resolve."""
    for px in range(4):
        for py in range(4):
            here = {tuple(np.round(p, 9)) for p in positions("flipquad", 2, px, py)[0]}
            right = {tuple(np.round(p, 9)) for p in positions("flipquad", 2, px + 1, py)[0]}
            below = {tuple(np.round(p, 9)) for p in positions("flipquad", 2, px, py + 1)[0]}
            assert len(here & right) == 1 and len(here & below) == 1
            xs, ys = zip(*[(x - px, y - py) for x, y in here])
            assert len(set(xs)) == 4 and len(set(ys)) == 4


def brute_force(poly, name, n, size, filt=None):
    """Pixel values of a polygon from point-in-polygon at the pattern's positions: box-weighted
    per pixel (``filt`` None), or every position within a wide filter's reach weighted by it."""
    out = np.zeros((size, size))
    for py in range(size):
        for px in range(size):
            if filt is None:
                pts, w = positions(name, n, px, py)
            else:
                R = int(math.ceil(RADIUS[filt] + 0.5))
                pts = np.concatenate([distinct_positions(name, n, px + dx, py + dy)
                                      for dy in range(-R, R + 1) for dx in range(-R, R + 1)])
                w = filter_weight(filt, pts[:, 0] - px - 0.5, pts[:, 1] - py - 0.5)
                w = w / w.sum()
            out[py, px] = (w * inside_polygon(poly, pts[:, 0], pts[:, 1])).sum()
    return out


@pytest.mark.parametrize("name,n", [(name, n) for name, n in ALL if n >= 4 or name in FIXED_SAMPLES])
@pytest.mark.parametrize("mode", ["persample", "approx"])
def test_msaa_equals_point_in_shape_at_the_pattern_positions(name, n, mode):
    size = 16
    # the pattern's own filter: box, quincunx's tent
    got = render_scene(scene_of(polygon_path(QUAD), size), mode=mode, samples=n,
                       pattern=name)[..., 3]
    want = brute_force(QUAD, name, n, size)
    assert np.abs(got - want).max() < 1e-5


def test_interleaved_tiles_render_per_class_in_every_multisample_mode():
    """The interleaved tile is a pattern of the pixel's own samples per tile class, so a2c and
    CSAA take it too (one render per class): straight edges are point-sampled there."""
    size, n = 16, 4
    want = brute_force(QUAD, "interleaved", n, size)
    for opts in (dict(mode="a2c"), dict(mode="approx", color_samples=2)):
        got = render_scene(scene_of(polygon_path(QUAD), size), samples=n, pattern="interleaved",
                           **opts)[..., 3]
        assert np.abs(got - want).max() < 1e-5, opts


@pytest.mark.parametrize("name", ["d3d", "quincunx", "flipquad", "interleaved"])
def test_curves_are_point_sampled_at_the_pattern_positions(name):
    """A quadratic and a cubic outline (root-finding winding numbers as the truth)."""
    path = Path()
    path.moveTo((1.3, 2.2))
    path.qCurveTo((14.1, 0.7), (13.2, 9.9))
    path.curveTo((9.1, 17.3), (4.4, 3.1), (1.9, 13.7))
    path.closePath()
    segs = segments(path)
    size, n = 16, 4
    got = render_scene(scene_of(path, size), mode="approx", samples=n, pattern=name)[..., 3]
    want = np.zeros((size, size))
    for py in range(size):
        for px in range(size):
            pts, w = positions(name, n, px, py)
            want[py, px] = sum(wi * (winding_at(segs, x, y) != 0) for (x, y), wi in zip(pts, w))
    assert np.abs(got - want).max() < 1e-5





@pytest.mark.parametrize("filt", ["tent1", "gaussian", "mitchell"])
@pytest.mark.parametrize("name,n", [("grid", 4), ("d3d", 8), ("quincunx", 2), ("flipquad", 2),
                                    ("interleaved", 2)])
def test_wide_filters_weigh_the_neighbours_samples(filt, name, n):
    """A wide filter's pixel is the filter-weighted mean of every sample in its reach, the
    neighbours' and those beyond the image's border included (brute force)."""
    size = 14
    got = render_scene(scene_of(polygon_path(QUAD), size), mode="persample", samples=n,
                       pattern=name, filter=filt)[..., 3]
    want = np.clip(brute_force(QUAD, name, n, size, filt), 0, 1)
    assert np.abs(got - want).max() < 1e-5


@pytest.mark.parametrize("filt", ["tent1", "gaussian", "mitchell"])
def test_wide_filters_converge_to_the_dense_reference_filtered_the_same_way(filt):
    """16 samples and the filter against 32 x 32 points per pixel filtered the same way."""
    size = 14
    got = render_scene(scene_of(polygon_path(QUAD), size), mode="approx", samples=16,
                       filter=filt)[..., 3]
    g = (np.arange(32) + 0.5) / 32
    R = int(math.ceil(RADIUS[filt]))
    xs = np.arange(-R, size + R)[:, None] + g[None, :]
    X, Y = np.meshgrid(xs.ravel(), xs.ravel())
    inside = inside_polygon(QUAD, X, Y).astype(np.float64)
    want = np.zeros((size, size))
    for py in range(size):
        for px in range(size):
            w = filter_weight(filt, X - px - 0.5, Y - py - 0.5)
            want[py, px] = (w * inside).sum() / w.sum()
    want = np.clip(want, 0, 1)
    err = np.abs(got - want)
    assert err.max() < 0.1 and err.mean() < 0.01, (err.max(), err.mean())


@pytest.mark.parametrize("name,filt", [("quincunx", None), ("flipquad", None),
                                       ("interleaved", "box"), ("d3d", "mitchell"),
                                       ("poisson", "gaussian")])
def test_shared_samples_and_wide_filters_do_not_depend_on_bands_or_threads(name, filt):
    from test_raster import layered_scene
    scene = layered_scene(29)
    whole = render_scene_rgba8(scene, samples=4, pattern=name, filter=filt)
    assert whole[..., 3].any()
    for band_rows in (1, 3, 7):
        for threads in (1, 2):
            got = render_scene_rgba8(scene, samples=4, pattern=name, filter=filt,
                                     band_budget=band_rows * scene.width * 16, threads=threads)
            assert np.array_equal(got, whole), (band_rows, threads)


def test_impossible_combinations_are_refused():
    scene = scene_of(polygon_path(QUAD), 8)
    with pytest.raises(ValueError, match="a2c"):
        render_scene(scene, mode="a2c", pattern="quincunx")
    with pytest.raises(ValueError, match="analytic"):
        render_scene(scene, mode="analytic", filter="gaussian")
    with pytest.raises(ValueError, match="pattern"):
        render_scene(scene, pattern="hexagonal")
    assert set(FILTERS) == set(RADIUS)


def test_bench_scenes_have_the_edges_they_are_named_for():
    """The bench's slanted bands: near-horizontal edges in one scene, near-vertical in the
    other, and there FLIPQUAD's and quincunx's 2 stored samples (4 and 3 distinct rows resolved)
    beat the 2-sample ordered grid's single row."""
    from vecmsaa.tools.accuracy import edge_error, ground_truth
    from vecmsaa.tools.patterns import pattern_configs, slanted_bands
    assert {name for n, name in pattern_configs((2, 4, 8, 16))} == set(PATTERN_NAMES)
    flat = slanted_bands(48)
    for fill in flat.root.children:
        pts = fill.path.points
        slope = abs((pts[1, 1] - pts[0, 1]) / (pts[1, 0] - pts[0, 0]))
        assert math.tan(math.radians(0.9)) < slope < math.tan(math.radians(10.1))
    assert np.allclose(slanted_bands(48, vertical=True).root.children[0].path.points[:, ::-1],
                       flat.root.children[0].path.points)
    truth = ground_truth(flat)
    grid = edge_error(render_scene(flat, samples=2, pattern="grid"), truth)
    for name in ("flipquad", "quincunx"):
        assert edge_error(render_scene(flat, pattern=name), truth) < 0.7 * grid
