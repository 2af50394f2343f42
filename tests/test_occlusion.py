"""Runs of opaque fills drawn front to back (scan.render_msaa's occlusion) against a per-sample
compositor written from the definition, and against the same kernel drawing back to front."""
import math
from pathlib import Path as FsPath

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from truth import distance_to_outline, segments, winding_at
from vecmsaa.api import load_svg
from vecmsaa.geometry.primitives import QUAD_FALLBACK_TOL
from vecmsaa.raster.render import RenderOptions, render_float
from vecmsaa.raster.sample_patterns import standard_pattern
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import Path, rect_path

SIZE = 14
CORPUS = FsPath(__file__).resolve().parents[1].parent / "shared" / "corpus"
coord = st.floats(min_value=-2.0, max_value=SIZE + 2.0, allow_nan=False, width=32)
# off the sample grid (multiples of 1/16): an exact tie is decided by convention, not geometry
point = st.tuples(coord, coord).map(lambda p: (p[0] + 1.2345e-6 * math.pi,
                                               p[1] + 2.7182e-6 * math.e))


@st.composite
def layered_fills(draw):
    """3-6 fills, mostly opaque (runs of them), curved, overlapping, some abutting exactly."""
    fills = []
    for _ in range(draw(st.integers(3, 6))):
        path = Path()
        start = draw(point)
        path.moveTo(start)
        for _ in range(draw(st.integers(1, 4))):
            kind = draw(st.sampled_from(["line", "quad", "cubic"]))
            if kind == "line":
                path.lineTo(draw(point))
            elif kind == "quad":
                path.qCurveTo(draw(point), draw(point))
            else:
                path.curveTo(draw(point), draw(point), draw(point))
        path.closePath()
        alpha = draw(st.sampled_from([1.0, 1.0, 1.0, 0.6]))
        color = draw(st.tuples(*[st.sampled_from([0.0, 0.25, 0.5, 1.0])] * 3))
        rule = draw(st.sampled_from(["nonzero", "evenodd"]))
        fills.append(Fill(path, Solid((*color, alpha)), rule=rule))
    if draw(st.booleans()):
        # two opaque triangles sharing a diagonal over everything: no sample may show what is
        # under them
        a, b, c, d = draw(point), draw(point), draw(point), draw(point)
        for tri in ((a, b, c), (a, c, d)):
            p = Path()
            p.moveTo(tri[0])
            p.lineTo(tri[1])
            p.lineTo(tri[2])
            p.closePath()
            fills.append(Fill(p, Solid((0.1, 0.9, 0.3, 1.0))))
    return fills


def per_sample_composite(fills, offsets, background):
    """Each sample's colour: source-over of every fill whose outline winds around it, back to
    front (windings by root finding), then the box average: the definition of the image."""
    segs = [segments(f.path) for f in fills]
    img = np.zeros((SIZE, SIZE, 4))
    near = np.zeros((SIZE, SIZE), dtype=bool)
    for py in range(SIZE):
        for px in range(SIZE):
            for ox, oy in offsets:
                x, y = px + 0.5 + ox, py + 0.5 + oy
                c = np.array(background, dtype=float)
                for f, sg in zip(fills, segs):
                    w = winding_at(sg, x, y)
                    if (w != 0) if f.rule == "nonzero" else (w % 2 == 1):
                        r, g, b, a = f.paint.color
                        c = np.array([r * a, g * a, b * a, a]) + c * (1 - a)
                    if distance_to_outline(sg, x, y, 400) < QUAD_FALLBACK_TOL:
                        near[py, px] = True
                img[py, px] += c / len(offsets)
    return img, near


@settings(max_examples=10, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(layered_fills(), st.sampled_from(["persample", "approx"]), st.sampled_from([8, 16]))
def test_front_to_back_equals_the_per_sample_compositor(fills, mode, samples):
    # curved fills drawn one after another in one batch: a lens winding the sweeps did not
    # read and clear where scan_lenses left it (scan.DIRTY_LENS) would show in a later fill
    background = (0.3, 0.3, 0.8, 1.0)   # opaque: premultiplied is the same
    got = render_float(Scene(SIZE, SIZE, Group(fills), background=background),
                       RenderOptions(mode, samples))
    want, near = per_sample_composite(fills, standard_pattern(samples), background)
    bad = np.abs(got - want).max(axis=2) > 1e-5
    # only a sample on an outline may go either way: within the tolerance to which the
    # geometry approximates curves (a degenerate cubic as quadratics, QUAD_FALLBACK_TOL)
    assert not (bad & ~near).any(), np.argwhere(bad & ~near)[:5]


STROKES_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="120" height="90">'
               '<rect width="120" height="90" fill="#ddd"/>'
               '<rect x="10" y="10" width="50" height="40" fill="#c33"/>'
               '<rect x="60" y="10" width="50" height="40" fill="#3c3"/>'
               '<circle cx="60" cy="45" r="30" fill="#33c" stroke="#000" stroke-width="7"/>'
               '<path d="M5 80 C40 0 80 120 115 20" fill="none" stroke="#fa0" '
               'stroke-width="9" stroke-linecap="round"/>'
               '<circle cx="60" cy="45" r="12" fill="#fff" fill-opacity="0.5"/>'
               '<ellipse cx="40" cy="60" rx="25" ry="9" fill="#0aa" transform="rotate(20 40 60)"/>'
               '<rect x="30" y="30" width="20" height="20" fill="#808" '
               'shape-rendering="crispEdges"/></svg>')


def _both(scene, mode, samples=8, filter="box"):
    images = []
    for occlude in (False, True):
        opts = RenderOptions(mode, samples, filter)
        opts.occlude = occlude
        images.append(render_float(scene, opts))
    return images


@pytest.mark.parametrize("mode,samples,filter", [
    ("approx", 8, "box"), ("approx", 16, "tent"), ("persample", 4, "box"), ("a2c", 8, "box"),
    ("none", 1, "box"), ("alpha", 8, "box")])
def test_front_to_back_gives_the_same_pixels_as_back_to_front(mode, samples, filter):
    scene = load_svg(STROKES_SVG.encode(), width=240)
    back_to_front, front_to_back = _both(scene, mode, samples, filter)
    assert np.array_equal(back_to_front, front_to_back)


@pytest.mark.parametrize("name", ["Ghostscript_Tiger", "alexandria-city-1"])
def test_front_to_back_gives_the_same_pixels_on_real_drawings(name):
    path = CORPUS / f"{name}.svg"
    if not path.exists():
        pytest.skip("../shared/corpus is not here")
    back_to_front, front_to_back = _both(load_svg(str(path), width=600), "approx")
    assert np.array_equal(back_to_front, front_to_back)


def test_a_fill_behind_others_paints_around_them_in_every_row():
    # fills in front stamp the middle of each row; the fill behind them has edges at both
    # ends, so its spans run from its own pixels at the left end past theirs: every sample
    # as the definition has it (the flag of Denmark's red field around its cross, and a third
    # fill in front of part of the field with a gap to the cross)
    cross = Path()
    for i, (x, y) in enumerate([(0.3, 5.6), (5.2, 5.6), (5.2, 0.4), (7.7, 0.4), (7.7, 5.6),
                                (13.6, 5.6), (13.6, 8.3), (7.7, 8.3), (7.7, 13.7), (5.2, 13.7),
                                (5.2, 8.3), (0.3, 8.3)]):
        (cross.moveTo if i == 0 else cross.lineTo)((x, y))
    cross.closePath()
    fills = [Fill(rect_path(0.2, 0.3, 13.5, 13.3), Solid((0.8, 0.1, 0.2, 1))),
             Fill(rect_path(9.4, 1.3, 2.2, 11.1), Solid((0.1, 0.7, 0.2, 1))),
             Fill(cross, Solid((1, 1, 1, 1)))]
    background = (0.3, 0.3, 0.8, 1.0)
    scene = Scene(SIZE, SIZE, Group(fills), background=background)
    got = render_float(scene, RenderOptions("approx", 8))
    want, near = per_sample_composite(fills, standard_pattern(8), background)
    assert not near.all()
    assert not ((np.abs(got - want).max(axis=2) > 1e-5) & ~near).any()
    back_to_front, front_to_back = _both(scene, "approx")
    assert np.array_equal(back_to_front, front_to_back)


def _disc():
    """A curved blob of two cubics inside x, y in [2, 12]."""
    disc = Path()
    disc.moveTo((12.0, 7.0))
    disc.curveTo((12.0, 12.0), (2.0, 12.0), (2.0, 7.0))
    disc.curveTo((2.0, 2.0), (12.0, 2.0), (12.0, 7.0))
    disc.closePath()
    return disc


def test_a_fill_hidden_under_opaque_fills_is_not_scanned():
    # a curved shape under two opaque rectangles that together cover its box: its curve
    # pixels are never visited (the approx mode counts them)
    disc = _disc()
    cover = [Fill(rect_path(0, 0, 7, SIZE), Solid((1, 0, 0, 1))),
             Fill(rect_path(7, 0, SIZE - 7, SIZE), Solid((0, 1, 0, 1)))]
    counts = []
    for fills in ([Fill(disc, Solid((0, 0, 1, 1)))] + cover, cover):
        opts = RenderOptions("approx", 8)
        render_float(Scene(SIZE, SIZE, Group(fills)), opts)
        counts.append(opts.lens_stats[0])
    assert counts[0] == counts[1]
    opts = RenderOptions("approx", 8)
    render_float(Scene(SIZE, SIZE, Group([Fill(disc, Solid((0, 0, 1, 1)))])), opts)
    assert opts.lens_stats[0] > 0


def test_curve_pixels_under_opaque_fills_are_not_evaluated():
    # a disc whose right half lies under an opaque rectangle: no row of its box is covered
    # whole, yet the curve pixels under the rectangle are skipped (a lens's winding stays in
    # its pixel), and the image is the one drawn back to front
    disc = _disc()
    cover = Fill(rect_path(7, 0, SIZE - 7, SIZE), Solid((0, 1, 0, 1)))
    alone, covered = RenderOptions("approx", 8), RenderOptions("approx", 8)
    render_float(Scene(SIZE, SIZE, Group([Fill(disc, Solid((0, 0, 1, 1)))])), alone)
    render_float(Scene(SIZE, SIZE, Group([Fill(disc, Solid((0, 0, 1, 1))), cover])), covered)
    assert 0 < covered.lens_stats[0] < alone.lens_stats[0]
    # the curve pixels left of the rectangle's edge (x < 7) are all still evaluated
    left = RenderOptions("approx", 8)
    half = Fill(rect_path(0, 0, 7, SIZE), Solid((0, 1, 0, 1)))
    render_float(Scene(SIZE, SIZE, Group([Fill(disc, Solid((0, 0, 1, 1))), half])), left)
    assert covered.lens_stats[0] + left.lens_stats[0] >= alone.lens_stats[0]
    back_to_front, front_to_back = _both(
        Scene(SIZE, SIZE, Group([Fill(disc, Solid((0, 0, 1, 1))), cover])), "approx")
    assert np.array_equal(back_to_front, front_to_back)


def test_run_numbers_restart_without_changing_a_pixel():
    # runs stamp what they cover with their number; when the numbers run out the stamps are
    # cleared and numbering restarts. Stale stamps equal to the restarted numbers are planted:
    # kept, they would hide samples
    from vecmsaa.raster import scan
    from vecmsaa.raster.render import Raster, band_layout, draw_items, prepare_items
    scene = load_svg(STROKES_SVG.encode(), width=120)
    opts = RenderOptions("approx", 8)
    items = prepare_items(scene.root, opts)
    W, H = scene.width, scene.height

    def draw(first_run, planted):
        raster = Raster(opts, W, H, band_layout(W, 8, 1 << 24)[1])
        stamp, runs = raster.scratch[11], raster.scratch[13]
        stamp[:] = planted
        runs[0] = first_run
        img = np.zeros((H, W, 4), np.float32)
        draw_items(items, img, 0, raster)
        return img, runs[0]
    fresh, _ = draw(0, 0)
    restarted, last = draw(scan.RUN_LIMIT - 1, 2 * 1 + 1)
    assert last < scan.RUN_LIMIT - 1
    assert np.array_equal(fresh, restarted)
