"""A batch of several fills whose geometry is too big to hold whole (a page of text: 2,000
lines, 840 MB of edges and lenses) is built region by region as it is drawn
(render.FillBatch.source, Raster.fill_chunked): each region of whole strips gets the edges and
lenses of the fills whose box meets it, the other fills none. Checked against the whole
geometry drawn at once: the same bytes in every sample mode, band size and thread count,
every fill's geometry the rows build_batch gives it; and the geometry held at once is a
region's, not the batch's."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vecmsaa.geometry.primitives import batch_arrays, build_batch
from vecmsaa.raster import render
from vecmsaa.raster.render import MAX_SAGITTA, FillBatch, RenderOptions, render_float
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import Path

from test_streamed_fill import paths

SIZE = 24


def draw(scene, chunked, monkeypatch, region_bytes=1, region_rows=1024, **kw):
    """The scene drawn with every batch of several fills chunked (regions of one strip with
    ``region_bytes`` 1) or none; the region builds' fill lists are returned."""
    with monkeypatch.context() as m:
        m.setattr(render, "CHUNK_BYTES", 0 if chunked else 1 << 62)
        m.setattr(render, "CHUNK_FILL_ROWS", float("inf"))
        m.setattr(render, "CHUNK_REGION_BYTES", region_bytes)
        m.setattr(render, "CHUNK_REGION_ROWS", region_rows)
        calls = []
        build = render.region_fills
        m.setattr(render, "region_fills",
                  lambda *a: calls.append(a[-1].tolist()) or build(*a))
        opts = {k: v for k, v in kw.items() if k not in ("band_budget", "threads")}
        image = render_float(scene, RenderOptions(**opts), kw.get("band_budget",
                                                                  render.BAND_BUDGET),
                             kw.get("threads", 1))
    return image, calls


CONFIGS = [dict(mode="approx", samples=8), dict(mode="approx", samples=16),
           dict(mode="alpha", samples=8), dict(mode="a2c", samples=8), dict(mode="none"),
           dict(mode="alpha-sat", samples=8), dict(mode="persample", samples=4),
           dict(mode="approx", samples=4, filter="mitchell")]


@st.composite
def scenes(draw_):
    """2-6 fills side by side (one batch), opaque and translucent (opaque runs drawn front
    to back among them), aliased or not, in a clipped or translucent group or not."""
    fills = []
    for _ in range(draw_(st.integers(2, 6))):
        colour = draw_(st.tuples(*[st.sampled_from([0.0, 0.3, 1.0])] * 3))
        alpha = draw_(st.sampled_from([1.0, 1.0, 0.6]))
        fills.append(Fill(draw_(paths()), Solid((*colour, alpha)),
                          rule=draw_(st.sampled_from(["nonzero", "evenodd"])),
                          antialias=draw_(st.sampled_from([True, True, False]))))
    children = fills
    if draw_(st.booleans()):
        clip = Group([Fill(draw_(paths()), Solid((0, 0, 0, 1)))])
        children = [Group(children, clip=clip, opacity=draw_(st.sampled_from([1.0, 0.5])))]
    return Scene(SIZE, SIZE, Group(children), background=(1.0, 1.0, 1.0, 1.0))


@settings(max_examples=30, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(scene=scenes(), config=st.sampled_from(CONFIGS), region=st.sampled_from([1, 1 << 12]),
       band=st.sampled_from([(render.BAND_BUDGET, 1), (SIZE * 16 * 5, 2), (SIZE * 16 * 3, 1)]))
def test_chunked_batches_draw_the_bytes_of_the_whole_geometry(scene, config, region, band,
                                                               monkeypatch):
    budget, threads = band
    whole, none = draw(scene, False, monkeypatch, **config)
    chunked, calls = draw(scene, True, monkeypatch, region, band_budget=budget,
                          threads=threads, **config)
    assert none == [] and calls
    assert np.array_equal(whole.view(np.uint32), chunked.view(np.uint32))


def text_lines(lines, per_line, width=200):
    """``lines`` fills, one a line of ``per_line`` small rings (as glyphs: a circle of four
    cubics around a square hole) 10 px apart in y, as a page of <text> elements."""
    fills = []
    k = 0.5523
    for j in range(lines):
        path = Path()
        for i in range(per_line):
            cx, cy, r = 4 + (i * 7) % (width - 8), 6.0 + 10 * j, 3.0
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
        fills.append(Fill(path, Solid((0.1, 0.1, 0.1, 1.0 if j % 5 else 0.7))))
    return fills


def test_a_page_of_lines_holds_one_regions_geometry_at_a_time(monkeypatch):
    """60 lines of 40 rings: the batch holds no geometry; each region builds only the lines
    whose box meets it, each line is built in the regions it meets and no others (regions
    of 32 rows, two strips: the least above 4 times the lines' 6 rows; a line meets one or
    two), every lens of the whole build is drawn, and the image is the whole geometry's."""
    W, H = 200, 600
    fills = text_lines(60, 40, W)
    opts = RenderOptions("approx", 8)
    monkeypatch.setattr(render, "CHUNK_BYTES", 0)
    monkeypatch.setattr(render, "CHUNK_REGION_BYTES", 1)
    (batch,) = render._fill_batches(fills, opts, canvas=(0, 0, W, H))
    assert isinstance(batch, FillBatch) and batch.source is not None
    assert batch.edges is None and batch.prims is None
    assert batch.fill_rows == 6.0
    held = []
    build = render.region_fills

    def counted(*a):
        built = build(*a)
        held.append((a[-1].tolist(), len(built[0]), len(built[2])))
        return built
    monkeypatch.setattr(render, "region_fills", counted)
    target = np.zeros((H, W, 4), np.float32)
    render.Raster(opts, W, H, 16).fill(batch, target, 0)
    verbs, pts, voff, poff = batch_arrays([f.path for f in fills])
    whole = build_batch(verbs, pts, voff, poff, 0.0, MAX_SAGITTA,
                        np.array([0.0, 0.0, W, H]))
    lines_lenses = np.diff(whole[3])
    assert len(held) == H // 32 + 1     # (the last region: rows 576 .. 599)
    for i, (which, ne, nc) in enumerate(held):
        # each region: the lines meeting its 32 rows (the boxes: y 3 .. 9 + 10 j, and
        # QUAD_FALLBACK_TOL more: rows 2 + 10 j .. 9 + 10 j)
        assert which == [j for j in range(60) if 2 + 10 * j < 32 * i + 32
                         and 9 + 10 * j >= 32 * i]
        # (four lines at most, of the page's 60)
        assert nc == lines_lenses[which].sum() and nc <= 4 * lines_lenses.max()
    # every line built once for each region it meets: 1 or 2
    times = np.bincount(np.concatenate([w for w, *_ in held]), minlength=60)
    assert set(times.tolist()) <= {1, 2} and times.sum() < 1.3 * 60
    assert sum(nc for *_, nc in held) == (lines_lenses * times).sum()
    # the same bytes as the whole geometry drawn at once
    monkeypatch.setattr(render, "CHUNK_BYTES", 1 << 62)
    (one,) = render._fill_batches(fills, opts, canvas=(0, 0, W, H))
    assert one.source is None and len(one.prims) == lines_lenses.sum()
    expected = np.zeros((H, W, 4), np.float32)
    render.Raster(opts, W, H, 16).fill(one, expected, 0)
    assert target[..., 3].any() and np.array_equal(target, expected)


def test_region_fills_gives_the_listed_fills_their_rows_and_the_others_none():
    """region_fills of a list of fills (gaps shorter and longer than REGION_GAP): the listed
    fills' rows are build_batch's of the whole batch, offsets included; the others have
    none."""
    fills = text_lines(40, 3)
    verbs, pts, voff, poff = batch_arrays([f.path for f in fills])
    canvas = np.array([0.0, 0.0, 200.0, 400.0])
    edges, eoff, prims, poff_ = build_batch(verbs, pts, voff, poff, 0.0, MAX_SAGITTA, canvas)
    which = np.array([0, 1, 2, 5, 30, 31, 39])
    e, eo, p, po = render.region_fills(verbs, pts, voff, poff, canvas, which)
    assert len(eo) == len(po) == 41 and eo[0] == po[0] == 0
    for k in range(40):
        got_e, got_p = e[eo[k]:eo[k + 1]], p[po[k]:po[k + 1]]
        if k <= 5 or k >= 30:     # (3, 4 and 32 .. 38: gaps built along)
            assert np.array_equal(got_e, edges[eoff[k]:eoff[k + 1]])
            assert np.array_equal(got_p, prims[poff_[k]:poff_[k + 1]])
            assert len(got_p) > 0
        else:
            assert len(got_e) == len(got_p) == 0
    assert eo[-1] == len(e) and po[-1] == len(p)


def test_which_batches_are_chunked(monkeypatch):
    """Only batches of several fills drawn by render_msaa whose estimated geometry reaches
    CHUNK_BYTES, their mean height (weighted by that) at most CHUNK_FILL_ROWS; one reaching
    beyond FAR_X is built whole (clamp_far_edges moves its edges)."""
    fills = text_lines(30, 20)
    verbs, pts, voff, poff = batch_arrays([f.path for f in fills])
    # the estimate: 64 bytes a point, 2 lenses of 39 float64 a curve (80 cubics a line)
    want = np.diff(poff) * 64 + 80 * 2 * 8 * 39
    monkeypatch.setattr(render, "CHUNK_BYTES", int(want.sum()))
    cost, rows = render._chunked(fills, verbs, pts, voff, poff, RenderOptions("approx", 8))
    assert np.array_equal(cost, want) and rows == 6.0
    # 24 lines 6 rows tall (each 340 points, 80 cubics) and a path 600 rows tall (300 times
    # 7 points, 2 cubics): a mean of 141.6 rows
    tall = Path()
    for i in range(300):
        tall.moveTo((1, 0))
        tall.curveTo((2, 100), (1, 200), (3, 600))
        tall.curveTo((3, 500), (2, 1), (1, 0))
        tall.closePath()
    mixed = fills[:24] + [Fill(tall, Solid((1, 0, 0, 1)))]
    arrays = batch_arrays([f.path for f in mixed])
    monkeypatch.setattr(render, "CHUNK_BYTES", 0)
    assert render._chunked(mixed, *arrays, RenderOptions("approx", 8)) is None
    monkeypatch.setattr(render, "CHUNK_FILL_ROWS", 142)
    line, high = 340 * 64 + 80 * 624, 300 * (7 * 64 + 2 * 624)
    assert render._chunked(mixed, *arrays, RenderOptions("approx", 8))[1] == \
        pytest.approx((24 * line * 6 + high * 600) / (24 * line + high))
    monkeypatch.setattr(render, "CHUNK_BYTES", int(want.sum()))
    monkeypatch.setattr(render, "CHUNK_BYTES", int(want.sum()) + 1)
    assert render._chunked(fills, verbs, pts, voff, poff, RenderOptions("approx", 8)) is None
    monkeypatch.setattr(render, "CHUNK_BYTES", 0)
    for opts in (RenderOptions("analytic"), RenderOptions("approx", 16, color_samples=4)):
        assert render._chunked(fills, verbs, pts, voff, poff, opts) is None
    assert render._chunked(fills[:1], *batch_arrays([fills[0].path]),
                           RenderOptions("approx", 8)) is None
    far = Path()
    far.moveTo((0, 0))
    far.lineTo((3e7, 5))
    far.lineTo((0, 10))
    far.closePath()
    (batch,) = render._fill_batches(fills + [Fill(far, Solid((1, 0, 0, 1)))],
                                    RenderOptions("approx", 8), canvas=(0, 0, 200, 300))
    assert batch.source is None and batch.edges is not None
    (batch,) = render._fill_batches(fills, RenderOptions("approx", 8), canvas=(0, 0, 200, 300))
    assert batch.source is not None


@pytest.mark.parametrize("threads", [1, 2])
def test_a_chunked_page_in_bands_and_threads(threads, monkeypatch):
    """The page of lines in bands of 1-40 rows on one and two threads, regions of one strip
    and of several (CHUNK_REGION_BYTES a few lines' estimate): the whole geometry's bytes."""
    fills = text_lines(12, 9, 64)
    scene = Scene(64, 130, Group(fills), background=(1.0, 1.0, 1.0, 1.0))
    whole, _ = draw(scene, False, monkeypatch, samples=8)
    for band_rows in (1, 7, 40, 130):
        for region in (1, 3 << 16):
            got, calls = draw(scene, True, monkeypatch, region, band_budget=band_rows * 64 * 16,
                              threads=threads, samples=8)
            assert calls and np.array_equal(whole, got), (band_rows, region)
