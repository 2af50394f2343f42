"""A fill of many curves is drawn streamed (render.FillBatch.runs, Raster.fill_streamed): its
path cut into runs (primitives.path_runs) that are built (build_run) and scanned (scan_run)
one at a time into the winding sums of a region of rows, then swept (sweep_fill). Checked
against the one-piece path (build_batch and render_msaa of the whole geometry): the same
geometry run by run, the same bytes in every sample mode, band size and thread count; and
the geometry held at once is bounded by the run length, not by the fill's size."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vecmsaa.geometry.primitives import (P_BBOX, PRIM_FIELDS, batch_arrays, build_batch,
                                         build_run, path_runs)
from vecmsaa.raster import render
from vecmsaa.raster.render import MAX_SAGITTA, FillBatch, RenderOptions, render_float
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import Path

SIZE = 24
coord = st.floats(min_value=-6.0, max_value=SIZE + 6.0, allow_nan=False, width=32)
# off the sample grid: an exact tie is decided by convention, the same on both paths anyway
point = st.tuples(coord, coord).map(lambda p: (p[0] + 1.2345e-6 * math.pi,
                                               p[1] + 2.7182e-6 * math.e))


@st.composite
def paths(draw):
    """A path of 1-4 subpaths of lines, quadratics, cubics and conics, closed or left open
    (build_batch closes those itself, at the next move or the path's end)."""
    path = Path()
    for _ in range(draw(st.integers(1, 4))):
        path.moveTo(draw(point))
        for _ in range(draw(st.integers(1, 5))):
            kind = draw(st.sampled_from(["line", "quad", "cubic", "conic"]))
            if kind == "line":
                path.lineTo(draw(point))
            elif kind == "quad":
                path.qCurveTo(draw(point), draw(point))
            elif kind == "cubic":
                path.curveTo(draw(point), draw(point), draw(point))
            else:
                path.conicTo(draw(point), draw(point), draw(st.sampled_from([0.3, 0.7071, 2.0])))
        if draw(st.booleans()):
            path.closePath()
    return path


def rows_of(built):
    edges, _, prims, _ = built
    return np.asarray(edges), np.asarray(prims)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(paths(), st.integers(1, 7))
def test_the_runs_give_build_batchs_rows_in_its_order(path, run_verbs):
    verbs, pts, voff, poff = batch_arrays([path])
    canvas = np.array([0.0, 0.0, SIZE, SIZE])
    edges, prims = rows_of(build_batch(verbs, pts, voff, poff, 0.0, MAX_SAGITTA, canvas))
    ints, flts = path_runs(verbs, pts, run_verbs)
    assert len(ints) == -(-len(verbs) // run_verbs)
    ends = np.append(ints[1:, 0], len(verbs))
    got_e, got_p = [], []
    for i in range(len(ints)):
        run = np.array((ints[i, 0], ends[i], ints[i, 1]), np.int64)
        state = np.array((*flts[i, :4], float(ints[i, 2])))
        # every row of the run's verbs: rows -inf .. inf
        e, p = build_run(verbs, pts, run, state, i == len(ints) - 1, MAX_SAGITTA, canvas,
                         -np.inf, np.inf)
        got_e.append(e)
        got_p.append(p)
        # the run's extent holds its points and where it starts
        k = slice(ints[i, 1], ints[i + 1, 1] if i + 1 < len(ints) else len(pts))
        ys = np.concatenate([pts[k, 1], flts[i, [1, 3]]])
        assert flts[i, 4] == ys.min() and flts[i, 5] == ys.max()
    assert np.array_equal(np.concatenate(got_e), edges)
    assert np.array_equal(np.concatenate(got_p).reshape(-1, PRIM_FIELDS), prims)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(paths(), st.integers(0, 40), st.integers(1, 6))
def test_build_run_leaves_out_only_curves_that_miss_the_rows(path, ylo, rows):
    """What build_run leaves out for the rows ylo .. ylo + rows lies wholly above or below
    them: the kept rows are build_batch's rows that can touch them, and more."""
    verbs, pts, voff, poff = batch_arrays([path])
    canvas = np.array([0.0, 0.0, SIZE, SIZE])
    edges, prims = rows_of(build_batch(verbs, pts, voff, poff, 0.0, MAX_SAGITTA, canvas))
    ints, flts = path_runs(verbs, pts, len(verbs))
    run = np.array((0, len(verbs), 0), np.int64)
    e, p = build_run(verbs, pts, run, np.array((*flts[0, :4], 0.0)), True, MAX_SAGITTA,
                     canvas, float(ylo), float(ylo + rows))

    def meeting(es):
        ya, yb = es[:, 1], es[:, 3]
        return es[~(((ya < ylo) & (yb < ylo)) | ((ya >= ylo + rows) & (yb >= ylo + rows)))]

    def lenses_meeting(ps):
        return ps[~((ps[:, P_BBOX + 3] < ylo) | (ps[:, P_BBOX + 1] >= ylo + rows))]
    assert np.array_equal(meeting(e), meeting(edges))
    assert np.array_equal(lenses_meeting(p), lenses_meeting(prims))


CONFIGS = [dict(mode="approx", samples=8), dict(mode="approx", samples=16),
           dict(mode="alpha", samples=8), dict(mode="a2c", samples=8), dict(mode="none"),
           dict(mode="alpha-sat", samples=8), dict(mode="persample", samples=4),
           dict(mode="approx", samples=4, filter="mitchell")]


def draw(scene, streamed, monkeypatch, run_verbs=3, region_rows=1, **kw):
    with monkeypatch.context() as m:
        if streamed:
            m.setattr(render, "STREAM_CURVES", 1)
            m.setattr(render, "RUN_VERBS", run_verbs)
            m.setattr(render, "STREAM_MIN_ROWS", 1)
            m.setattr(render, "STREAM_BUDGET", region_rows)
        else:
            m.setattr(render, "STREAM_CURVES", 1 << 62)
        calls = []
        build = render.build_run
        m.setattr(render, "build_run", lambda *a: calls.append(a[-2:]) or build(*a))
        opts = {k: v for k, v in kw.items() if k not in ("band_budget", "threads")}
        image = render_float(scene, RenderOptions(**opts), kw.get("band_budget",
                                                                  render.BAND_BUDGET),
                             kw.get("threads", 1))
    return image, calls


@st.composite
def scenes(draw_):
    fills = []
    for _ in range(draw_(st.integers(1, 3))):
        colour = draw_(st.tuples(*[st.sampled_from([0.0, 0.3, 1.0])] * 3))
        alpha = draw_(st.sampled_from([1.0, 0.6]))
        fills.append(Fill(draw_(paths()), Solid((*colour, alpha)),
                          rule=draw_(st.sampled_from(["nonzero", "evenodd"])),
                          antialias=draw_(st.sampled_from([True, True, False]))))
    # a fill alone in its batch (an isolated layer of its own, or alone in the document) is
    # streamed; fills side by side make one batch, which is not
    children = [Group([f], opacity=draw_(st.sampled_from([1.0, 0.5])), isolate=True)
                if draw_(st.booleans()) else f for f in fills]
    if draw_(st.booleans()):
        clip = Group([Fill(draw_(paths()), Solid((0, 0, 0, 1)))])
        children = [Group(children, clip=clip)]
    return Scene(SIZE, SIZE, Group(children), background=(1.0, 1.0, 1.0, 1.0))


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(scene=scenes(), config=st.sampled_from(CONFIGS), run_verbs=st.integers(1, 9),
       region=st.integers(1, 30),
       band=st.sampled_from([(render.BAND_BUDGET, 1), (SIZE * 16 * 5, 2), (SIZE * 16 * 3, 1)]))
def test_streamed_fills_draw_the_bytes_of_the_whole_geometry(scene, config, run_verbs,
                                                             region, band, monkeypatch):
    budget, threads = band
    whole, _ = draw(scene, False, monkeypatch, **config)
    samples = config.get("samples", 1)
    streamed, calls = draw(scene, True, monkeypatch, run_verbs, region * SIZE * samples,
                           band_budget=budget, threads=threads, **config)
    assert np.array_equal(whole.view(np.uint32), streamed.view(np.uint32))


def test_the_streamed_path_is_taken_in_runs_and_regions(monkeypatch):
    """The identity test above draws in many runs and regions (not one of each)."""
    path = Path()
    for i in range(12):
        path.moveTo((2 + i, 1 + 1.7 * i))
        path.curveTo((9 + i, 0), (12, 9 + i), (3, 4 + i))
        path.qCurveTo((20, 2 * i), (6, 20))
    scene = Scene(SIZE, SIZE, Group([Fill(path, Solid((0, 0, 0, 1)))]))
    whole, none = draw(scene, False, monkeypatch, samples=8)
    streamed, calls = draw(scene, True, monkeypatch, 4, 3 * SIZE * 8, samples=8)
    assert none == [] and np.array_equal(whole, streamed)
    regions = {c for c in calls}
    assert len(regions) >= 5 and len(calls) > len(regions)


@pytest.mark.parametrize("region", [1, 2, 3])
@pytest.mark.parametrize("run_verbs", [1, 2, 5])
def test_runs_that_end_or_begin_inside_a_regions_first_or_last_row_are_drawn(region,
                                                                             run_verbs,
                                                                             monkeypatch):
    """Small curved shapes whose tops and bottoms fall at every fraction of a row: a run's
    y extent meeting a region by less than a row still adds its winding there."""
    path = Path()
    for i in range(40):
        x, y = 1 + (i * 5) % 21, 0.3 + i * 0.55
        path.moveTo((x, y))
        path.qCurveTo((x + 3, y + 0.2), (x + 2.5, y + 0.9))
        path.curveTo((x + 2, y + 1.3), (x + 0.4, y + 1.2), (x, y + 0.7))
        path.closePath()
    scene = Scene(SIZE, SIZE, Group([Fill(path, Solid((0.2, 0.4, 0.9, 1)))]))
    for config in (dict(samples=8), dict(mode="alpha", samples=8)):
        whole, _ = draw(scene, False, monkeypatch, **config)
        streamed, calls = draw(scene, True, monkeypatch, run_verbs, region * SIZE * 8,
                               **config)
        assert calls and np.array_equal(whole.view(np.uint32), streamed.view(np.uint32))


def glyph_row(n):
    """n small rings (a circle of four cubics around a square hole, like an 'o'), side by
    side on a 64 px line and over one another, as the glyphs of one text element."""
    path = Path()
    k = 0.5523
    for i in range(n):
        cx, cy, r = 4 + (i * 7) % 56, 10.0, 3.0
        path.moveTo((cx + r, cy))
        path.curveTo((cx + r, cy + k * r), (cx + k * r, cy + r), (cx, cy + r))
        path.curveTo((cx - k * r, cy + r), (cx - r, cy + k * r), (cx - r, cy))
        path.curveTo((cx - r, cy - k * r), (cx - k * r, cy - r), (cx, cy - r))
        path.curveTo((cx + k * r, cy - r), (cx + r, cy - k * r), (cx + r, cy))
        path.closePath()
        path.moveTo((cx - 1, cy - 1))
        path.lineTo((cx - 1, cy + 1))
        path.lineTo((cx + 1, cy + 1))
        path.lineTo((cx + 1, cy - 1))
        path.closePath()
    return path


@pytest.mark.parametrize("n", [5000, 20000])
def test_a_fill_of_many_glyphs_holds_one_runs_geometry_at_a_time(n, monkeypatch):
    path = glyph_row(n)
    opts = RenderOptions("approx", 8)
    (batch,) = render._fill_batches([Fill(path, Solid((0, 0, 0, 1)))], opts,
                                    canvas=(0, 0, 64, 20))
    assert isinstance(batch, FillBatch) and batch.runs is not None
    assert batch.edges is None and batch.prims is None
    held = []
    build = render.build_run

    def counted(*a):
        edges, prims = build(*a)
        held.append((len(edges), len(prims)))
        return edges, prims
    monkeypatch.setattr(render, "build_run", counted)
    target = np.zeros((20, 64, 4), np.float32)
    render.Raster(opts, 64, 20, 16).fill(batch, target, 0)
    # all of the path's lenses were drawn: at least one per cubic (a quarter of a ring 6 px
    # across bulges under a pixel: one piece), and far more than a run's
    lenses = sum(p for _, p in held)
    assert lenses >= 4 * n
    # a run of RUN_VERBS verbs holds at most the rows build_batch reserves for them: two
    # edges a point and five lenses a curve
    assert max(p for _, p in held) <= 5 * render.RUN_VERBS
    assert max(e for e, _ in held) <= 2 * 3 * render.RUN_VERBS
    assert len(held) >= lenses / (5 * render.RUN_VERBS)
    # and the image is the whole geometry's
    monkeypatch.setattr(render, "STREAM_CURVES", 1 << 62)
    (whole,) = render._fill_batches([Fill(path, Solid((0, 0, 0, 1)))], opts,
                                    canvas=(0, 0, 64, 20))
    assert whole.runs is None and len(whole.prims) == lenses
    expected = np.zeros((20, 64, 4), np.float32)
    render.Raster(opts, 64, 20, 16).fill(whole, expected, 0)
    assert np.array_equal(target, expected)


def test_small_fills_and_other_kernels_are_not_streamed():
    path = glyph_row(10)
    assert not render._streams([Fill(path)], path.verbs, RenderOptions("approx", 8))
    big = glyph_row(render.STREAM_CURVES // 4 + 1)
    assert render._streams([Fill(big)], big.verbs, RenderOptions("approx", 8))
    # the exact modes flatten, CSAA has its own kernel, and a batch of several fills keeps
    # its fills' samples apart between them (render_msaa)
    assert not render._streams([Fill(big)], big.verbs, RenderOptions("analytic"))
    assert not render._streams([Fill(big)], big.verbs, RenderOptions("approx", 16,
                                                                     color_samples=4))
    assert not render._streams([Fill(big), Fill(path)], big.verbs, RenderOptions("approx", 8))


def test_a_streamed_fill_reaching_far_beyond_the_canvas_is_built_whole():
    """Edges beyond x = ±FAR_X are moved by clamp_far_edges, which takes the whole geometry."""
    path = glyph_row(render.STREAM_CURVES // 4 + 1)
    path.moveTo((0, 0))
    path.lineTo((1e9, 5))
    path.lineTo((0, 10))
    path.closePath()
    (batch,) = render._fill_batches([Fill(path, Solid((0, 0, 0, 1)))],
                                    RenderOptions("approx", 8), canvas=(0, 0, 64, 20))
    assert batch.runs is None and batch.edges is not None
