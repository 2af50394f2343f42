"""Layers of fills alone whose footprints do not meet, drawn together (render.LayerRun):
against each layer drawn into its own buffer and composited (render.LAYER_RUNS off), on
random documents of small clipped and faded groups, crowded and spread, in every kind of
mode; and the same bytes for any band and thread count. Layer buffers that end at the last
column read (render.NARROW_LAYERS) against full-width ones, the same way."""
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg
from vecmsaa.raster import render as render_module
from vecmsaa.raster.render import LayerRun, RenderOptions, prepare_items, render_scene
# (mode, samples, filter, color samples): every kernel, as for the opacity folds
from test_opacity_fold import CONFIGS, IDS

W, H = 96, 64


DEFS = ('<defs><linearGradient id="lg" x1="0" y1="0" x2="1" y2="0.4">'
        '<stop offset="0" stop-color="#e33"/><stop offset="1" stop-color="#33e" '
        'stop-opacity="0.6"/></linearGradient>'
        '<clipPath id="bb" clipPathUnits="objectBoundingBox"><circle cx="0.5" cy="0.5" '
        'r="0.5"/></clipPath></defs>')


def _shape(r: random.Random, x: float, y: float, size: float) -> str:
    """A small shape about (x, y): a polygon (self-intersecting as often as not), curves,
    a circle or a stroked line, at fractional coordinates."""
    paint = r.choice([f"#{r.randrange(1 << 24):06x}", "url(#lg)", "rgba(200,40,90,0.6)"])
    extra = ' fill-rule="evenodd"' if r.random() < 0.3 else ""
    if r.random() < 0.15:
        extra += ' shape-rendering="crispEdges"'
    kind = r.randrange(4)
    if kind == 0:
        return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{size / 2:.2f}" fill="{paint}"{extra}/>'
    if kind == 1:
        return (f'<path d="M{x - size / 2:.2f} {y - size / 2:.2f} L{x + size / 2:.2f} '
                f'{y + size / 2:.2f}" stroke="{paint}" stroke-width="1.7"/>')
    d = [f"M{x + r.uniform(-size, size) / 2:.2f} {y + r.uniform(-size, size) / 2:.2f}"]
    for _ in range(r.randint(2, 5)):
        verb = r.choice("LLQC") if kind == 3 else "L"
        pts = [(x + r.uniform(-size, size) / 2, y + r.uniform(-size, size) / 2)
               for _ in range(" LQC".index(verb))]
        d.append(verb + " ".join(f"{px:.2f} {py:.2f}" for px, py in pts))
    return f'<path d="{" ".join(d)} Z" fill="{paint}"{extra}/>'


def _clipped(i: int, clip: str, opacity: str, shapes: str) -> tuple[str, str]:
    """(defs, group) of a group with ``opacity`` clipped by a clipPath of ``clip``."""
    return (f'<clipPath id="c{i}">{clip}</clipPath>',
            f'<g clip-path="url(#c{i})"{opacity}>{shapes}</g>')


def _group(r: random.Random, i: int, crowded: bool) -> tuple[str, str]:
    """(defs, element) of one small group: its shapes under a clip (around them, within
    them, of their bounding box) or opacity or both, or now and then a group a run must
    leave alone (a nested group, a mask, a rectangle clip) or a plain shape between them."""
    size = r.uniform(4, 12)
    x, y = r.uniform(-2, W + 2), r.uniform(-2, H + 2)
    if not crowded:
        # mostly apart: on a grid of cells, so that many consecutive groups can share a run
        x, y = (i % 6) * 16 + 8 + r.uniform(-1, 1), (i // 6 % 4) * 16 + 8 + r.uniform(-1, 1)
        size = r.uniform(3, 6)
    shapes = "".join(_shape(r, x + r.uniform(-2, 2), y + r.uniform(-2, 2), size)
                     for _ in range(r.randint(1, 3)))
    opacity = f' opacity="{r.uniform(0.2, 0.95):.2f}"' if r.random() < 0.5 else ""
    # apart, mostly groups a run may take (the rest end a run)
    kind = r.randrange(11) if crowded or r.random() < 0.3 else r.randrange(6)
    if kind <= 2:
        # about as tall as the content, or (now and then) much taller
        cr = size / 2 + r.uniform(1, 2.5) if r.random() < 0.8 else size * 1.5
        return _clipped(i, f'<circle cx="{x + r.uniform(-0.5, 0.5):.2f}" '
                           f'cy="{y + r.uniform(-0.5, 0.5):.2f}" r="{cr:.2f}"/>', opacity, shapes)
    if kind == 3:
        return "", f'<g clip-path="url(#bb)"{opacity}>{shapes}</g>'
    if kind == 4:
        return "", f'<g opacity="{r.uniform(0.2, 0.95):.2f}">{shapes}</g>'
    if kind == 5:
        p = " ".join(f"{x + r.uniform(-size, size) * 0.6:.2f},{y + r.uniform(-size, size) * 0.6:.2f}"
                     for _ in range(5))
        return _clipped(i, f'<polygon points="{p}" fill-rule="evenodd" clip-rule="evenodd"/>',
                        opacity, shapes)
    if kind == 6:
        return "", f'<g opacity="0.6"><g opacity="0.8">{shapes}</g></g>'
    if kind == 7:
        return _clipped(i, f'<rect x="{x - size:.2f}" y="{y - size:.2f}" '
                           f'width="{size * 1.5:.2f}" height="{size * 1.5:.2f}"/>', opacity, shapes)
    if kind == 8:
        return (f'<mask id="m{i}"><circle cx="{x:.2f}" cy="{y:.2f}" r="{size / 2:.2f}" '
                f'fill="#ccc"/></mask>', f'<g mask="url(#m{i})">{shapes}</g>')
    if kind == 9:
        # a wide clip about a clipped group (nested layer buffers)
        return (f'<clipPath id="c{i}"><ellipse cx="{x:.2f}" cy="{y:.2f}" rx="{size * 3:.2f}" '
                f'ry="{size / 2 + 1:.2f}"/></clipPath><clipPath id="d{i}"><circle '
                f'cx="{x + 1:.2f}" cy="{y:.2f}" r="{size / 2:.2f}"/></clipPath>',
                f'<g clip-path="url(#c{i})"><g clip-path="url(#d{i})"{opacity}>{shapes}</g>'
                f'{_shape(r, x - 3, y, size)}</g>')
    return "", shapes


def _document(seed: int, crowded: bool) -> str:
    r = random.Random(seed)
    defs, body = [], []
    for i in range(r.randint(12, 30)):
        d, e = _group(r, i, crowded)
        defs.append(d)
        body.append(e)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}">{DEFS}'
            f'<defs>{"".join(defs)}</defs><rect width="{W}" height="{H}" fill="#f4f0e0"/>'
            f'{"".join(body)}</svg>')


def _take_more(monkeypatch):
    """Runs taken wherever they may be (RUN_MORE and RUN_TRIES only weigh their speed): clips
    much taller than their content too, and every layer tried."""
    monkeypatch.setattr(render_module, "RUN_MORE", 100.0)
    monkeypatch.setattr(render_module, "RUN_TRIES", 10 ** 9)


def _render(scene, config, **kw) -> np.ndarray:
    mode, samples, filt, colors = config
    return render_scene(scene, mode, samples, filt, color_samples=colors, **kw)


def _runs(scene) -> int:
    return sum(len(item.layers) for item in prepare_items(scene.root, RenderOptions(),
                                                           canvas=(0, 0, W, H))
               if isinstance(item, LayerRun))


SEEDS = [(seed, crowded) for seed in range(6) for crowded in (False, True)]


@pytest.mark.parametrize("config", CONFIGS, ids=IDS)
def test_runs_draw_what_the_layers_draw(config, monkeypatch):
    # brute force: each random document with its layers drawn in runs and with every
    # layer drawn on its own; the same bytes, and runs taken
    _take_more(monkeypatch)
    in_runs = 0
    for seed, crowded in SEEDS:
        scene = load_svg(_document(seed, crowded))
        in_runs += _runs(scene)
        got = _render(scene, config)
        monkeypatch.setattr(render_module, "LAYER_RUNS", False)
        assert np.array_equal(got, _render(scene, config)), (seed, crowded)
        monkeypatch.setattr(render_module, "LAYER_RUNS", True)
    assert in_runs >= 80


def _shrunk(group, opts):
    """A wrong footprint: five pixels short on every side, so that layers whose pixels
    meet are drawn in one run. (The footprint's margins, three pixels beyond the points'
    extremes, are those of the pixels a kernel writes and draw_run reads; these documents'
    shapes seldom put coverage in the outermost ones, so four short goes unseen here.)"""
    got = _run_layer(group, opts)
    if got is None:
        return None
    x0, y0, x1, y1 = got[3]
    return got[:3] + ((x0 + 5, y0 + 5, x1 - 5, y1 - 5),)


_run_layer = render_module._run_layer


def _overlapping(seed: int) -> str:
    """Faded and clipped groups a run may take, many of them overlapping their neighbours."""
    r = random.Random(seed)
    body = []
    for _ in range(24):
        x, y, size = r.uniform(8, W - 8), r.uniform(8, H - 8), r.uniform(5, 10)
        shapes = "".join(_shape(r, x + r.uniform(-2, 2), y + r.uniform(-2, 2), size)
                         for _ in range(r.randint(1, 2)))
        body.append(f'<g opacity="{r.uniform(0.3, 0.9):.2f}">{shapes}</g>' if r.random() < 0.5
                    else f'<g clip-path="url(#bb)">{shapes}</g>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}">{DEFS}'
            f'{"".join(body)}</svg>')


@pytest.mark.parametrize("config", CONFIGS[:3], ids=IDS[:3])
def test_a_footprint_too_small_is_caught(config, monkeypatch):
    _take_more(monkeypatch)
    worst = 0
    for seed in range(4):
        scene = load_svg(_overlapping(seed))
        monkeypatch.setattr(render_module, "_run_layer", _shrunk)
        bad = _render(scene, config)
        monkeypatch.setattr(render_module, "_run_layer", _run_layer)
        monkeypatch.setattr(render_module, "LAYER_RUNS", False)
        worst = max(worst, float(np.abs(bad - _render(scene, config)).max()))
        monkeypatch.setattr(render_module, "LAYER_RUNS", True)
    assert worst > 0.05


@pytest.mark.parametrize("mode", ["approx", "analytic", "alpha-sat"])
def test_runs_are_the_same_for_any_band_and_thread_count(mode, monkeypatch):
    _take_more(monkeypatch)
    for seed, crowded in SEEDS[:4]:
        scene = load_svg(_document(seed, crowded))
        one = render_scene(scene, mode)
        for budget, threads in ((W * 16 * 3, 2), (W * 16 * 7, 1), (W * 16 * 16, 3),
                                (W * 16 * 5, 3)):
            assert np.array_equal(render_scene(scene, mode, band_budget=budget,
                                               threads=threads), one), (seed, budget)


def test_what_a_run_takes():
    # fills alone under opacity and at most a clip of fills alone; not a rectangle clip,
    # a mask, a nested group, a blend mode, nor a clip much taller than its content
    def group(body):
        return load_svg(f'<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64">'
                        f'{body}</svg>').root.children[0]
    opts = RenderOptions()
    circle = '<circle cx="20" cy="20" r="6"/>'
    assert render_module._run_layer(group(f'<g opacity="0.5">{circle}{circle}</g>'), opts)
    assert render_module._run_layer(group(
        f'<clipPath id="c"><circle cx="20" cy="20" r="6.5"/></clipPath>'
        f'<g clip-path="url(#c)">{circle}</g>'), opts)
    for body in ('<clipPath id="c"><rect width="30" height="30"/></clipPath>'
                 f'<g clip-path="url(#c)">{circle}</g>',
                 '<clipPath id="c"><circle cx="20" cy="20" r="19"/></clipPath>'
                 f'<g clip-path="url(#c)">{circle}</g>',
                 f'<mask id="m"><rect width="30" height="30" fill="#fff"/></mask>'
                 f'<g mask="url(#m)">{circle}</g>',
                 f'<g opacity="0.5"><g opacity="0.5">{circle}</g>{circle}</g>',
                 f'<g opacity="0.5" style="mix-blend-mode:multiply">{circle}{circle}</g>'):
        assert render_module._run_layer(group(body), opts) is None, body


@pytest.mark.parametrize("config", CONFIGS, ids=IDS)
def test_narrow_layer_buffers_draw_what_full_ones_draw(config, monkeypatch):
    # brute force: clips and masks reaching right of their content (a wide ellipse about a
    # clipped group, circles larger than their shapes), drawn into buffers ending at the
    # content's last column and into buffers of the whole width; the same bytes
    for seed, crowded in SEEDS:
        scene = load_svg(_document(seed, crowded))
        got = _render(scene, config)
        monkeypatch.setattr(render_module, "NARROW_LAYERS", False)
        assert np.array_equal(got, _render(scene, config)), (seed, crowded)
        monkeypatch.setattr(render_module, "NARROW_LAYERS", True)


def test_a_buffer_too_narrow_is_caught(monkeypatch):
    # buffers ending three columns before the last one read (an error in where a layer's
    # columns end) lose pixels of the content
    layer_buffer = render_module.Raster.layer_buffer

    def short(self, rows, c, d):
        buf = layer_buffer(self, rows, c, d)
        if d < 4 or buf.shape[1] != d:
            return buf
        return buf.reshape(-1)[:rows * (d - 3) * 4].reshape(rows, d - 3, 4)
    worst = 0.0
    for seed, crowded in SEEDS:
        scene = load_svg(_document(seed, crowded))
        good = render_scene(scene)
        monkeypatch.setattr(render_module.Raster, "layer_buffer", short)
        bad = render_scene(scene)
        monkeypatch.setattr(render_module.Raster, "layer_buffer", layer_buffer)
        worst = max(worst, float(np.abs(bad - good).max()))
    assert worst > 0.05


def test_solid_rows_are_the_paint_tables_arrays():
    # a batch of solid fills takes its paint arrays from solid_rows (a run's batch of many
    # small layers' fills); they are PaintTable's arrays exactly, shared paints, repeated
    # opacities and all
    from vecmsaa.raster.shaders import PaintTable, solid_arrays, solid_row
    from vecmsaa.scene.nodes import Fill, Solid
    from vecmsaa.scene.path import Path
    r = random.Random(7)
    paints = [Solid((r.random(), r.random(), r.random(), r.choice([1.0, r.random()])))
              for _ in range(5)]
    fills = [Fill(Path(), r.choice(paints), "nonzero", r.choice([1.0, 0.5, r.random()]), True)
             for _ in range(40)]
    table = PaintTable()
    table.add_fills(fills, None)
    for want, got in zip(table.arrays(), solid_arrays([solid_row(f.paint, f.opacity)
                                                       for f in fills])):
        assert want.dtype == got.dtype and want.shape == got.shape
        assert np.array_equal(want.view(np.uint8), got.view(np.uint8))
