"""A layer whose only effect is opacity, over one fill, drawn as that fill with the opacity in
its paint (render._opacity_fold): against the layer composite it replaces (the fold refused)
and against the specification's definition (the element rendered alone offscreen, composited
with its opacity over what lies below), on random documents in every kind of mode."""
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg
from vecmsaa.output.rgba8 import to_rgba8
from vecmsaa.raster import render as render_module
from vecmsaa.raster.render import render_scene
from vecmsaa.scene.nodes import Fill

W, H = 48, 40

#: (mode, samples, filter, color samples): the multisample kernels, the saturating blend,
#: the exact modes, CSAA and the sample images of a wide resolve filter
CONFIGS = [("approx", 8, None, None), ("persample", 8, None, None), ("analytic", 1, None, None),
           ("alpha", 8, None, None), ("a2c", 8, None, None), ("alpha-sat", 8, None, None),
           ("none", 1, None, None), ("reference", 256, None, None), ("approx", 8, None, 2),
           ("approx", 4, "gaussian", None)]
IDS = ["approx", "persample", "analytic", "alpha", "a2c", "alpha-sat", "none", "reference",
       "csaa", "gaussian"]

DEFS = ('<defs><linearGradient id="lg" x1="0" y1="0" x2="1" y2="0.4">'
        '<stop offset="0" stop-color="#e33"/><stop offset="0.6" stop-color="#3e3" '
        'stop-opacity="0.5"/><stop offset="1" stop-color="#33e"/></linearGradient>'
        '<radialGradient id="rg" cx="0.4" cy="0.5" r="0.6" spreadMethod="reflect">'
        '<stop offset="0" stop-color="#fd0"/><stop offset="1" stop-color="#08a" '
        'stop-opacity="0.7"/></radialGradient>'
        '<pattern id="pt" width="5" height="4" patternUnits="userSpaceOnUse">'
        '<rect width="3" height="2" fill="#a0f"/><circle cx="4" cy="3" r="1.3" fill="#0a6" '
        'fill-opacity="0.6"/></pattern></defs>')


def _path(r: random.Random) -> str:
    """A random closed path: a polygon (self-intersecting as often as not) or curves, at
    fractional coordinates (pixels partly covered)."""
    x, y = r.uniform(-4, W), r.uniform(-4, H)
    d = [f"M{x:.2f} {y:.2f}"]
    for _ in range(r.randint(2, 6)):
        kind = r.choice("LLQC")
        pts = [(r.uniform(-6, W + 6), r.uniform(-6, H + 6)) for _ in range(" LQC".index(kind))]
        d.append(kind + " ".join(f"{px:.2f} {py:.2f}" for px, py in pts))
    return " ".join(d) + " Z"


def _paint(r: random.Random) -> str:
    return r.choice([f"#{r.randrange(1 << 24):06x}", "url(#lg)", "url(#rg)", "url(#pt)",
                     "rgba(200,40,90,0.6)"])


def _shape(r: random.Random, extra: str = "") -> str:
    rule = ' fill-rule="evenodd"' if r.random() < 0.4 else ""
    crisp = ' shape-rendering="crispEdges"' if r.random() < 0.15 else ""
    fop = f' fill-opacity="{r.uniform(0.3, 1):.2f}"' if r.random() < 0.3 else ""
    return f'<path d="{_path(r)}" fill="{_paint(r)}"{rule}{crisp}{fop}{extra}/>'


def _element(r: random.Random) -> str:
    """An element of opacity alone over one fill (folded), written several ways, or one the
    fold must leave alone (a fill and its stroke, two fills, a clip)."""
    o = f"{r.uniform(0.1, 0.95):.2f}"
    kind = r.randrange(6)
    if kind == 0:
        return _shape(r, f' opacity="{o}"')
    if kind == 1:
        return f'<g opacity="{o}">{_shape(r)}</g>'
    if kind == 2:
        return f'<g opacity="{o}"><g><g opacity="0.7">{_shape(r)}</g></g></g>'
    if kind == 3:
        return _shape(r, f' opacity="{o}" stroke="#123" stroke-width="2.5"')
    if kind == 4:
        return f'<g opacity="{o}">{_shape(r)}{_shape(r)}</g>'
    return _shape(r)


def _document(seed: int, top: str | None = None) -> str:
    r = random.Random(seed)
    below = "".join(_shape(r) for _ in range(r.randint(1, 3)))
    mid = "".join(_element(r) for _ in range(r.randint(2, 5)))
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}">{DEFS}'
            f'<rect width="{W}" height="{H}" fill="#f4f0e0"/>{below}{mid}{top or ""}</svg>')


def _render(svg: str, config) -> np.ndarray:
    mode, samples, filt, colors = config
    return render_scene(load_svg(svg), mode, samples, filt, color_samples=colors)


def _worst(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.abs(to_rgba8(a).astype(np.int32) - to_rgba8(b).astype(np.int32)).max())


def _unfolded(group):
    return None


_fold = render_module._opacity_fold


SEEDS = range(12)


@pytest.mark.parametrize("config", CONFIGS, ids=IDS)
def test_folded_opacity_draws_what_the_layer_composite_draws(config, monkeypatch):
    # brute force: each random document with the fold and with every such layer drawn into
    # its buffer and composited; float rounding only (at most 1 in RGBA8), and the fold taken
    folded = []

    def counting(group):
        got = _fold(group)
        folded.append(got is not None)
        return got
    for seed in SEEDS:
        svg = _document(seed)
        monkeypatch.setattr(render_module, "_opacity_fold", counting)
        with_fold = _render(svg, config)
        monkeypatch.setattr(render_module, "_opacity_fold", _unfolded)
        assert _worst(with_fold, _render(svg, config)) <= 1, seed
    assert folded.count(True) >= 10 and folded.count(False) >= 5


@pytest.mark.parametrize("config", CONFIGS[:-1], ids=IDS[:-1])
def test_folded_opacity_is_the_offscreen_composite_of_the_specification(config):
    # the specification's opacity: the element rendered alone onto a transparent offscreen,
    # composited with its opacity over what lies below it (here a random document). Not with
    # a wide resolve filter: there every layer composites in each sample image, and a pixel is
    # a weighted sum of its neighbours' sample images, which compositing does not commute with
    for seed in range(6):
        r = random.Random(1000 + seed)
        shape, o = _shape(r), r.uniform(0.1, 0.95)
        below = _render(_document(seed), config)
        alone = _render(f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}">'
                        f'{DEFS}{shape}</svg>', config)
        truth = alone * np.float32(o) + below * (1 - np.float32(o) * alone[..., 3:4])
        top = shape.replace("/>", f' opacity="{o!r}"/>')
        assert _worst(_render(_document(seed, top), config), truth) <= 1, seed


def _twice(group):
    fills = _fold(group)
    if fills is None:
        return None
    f = fills[0]
    return [Fill(f.path, f.paint, f.rule, f.opacity * group.opacity, f.antialias)]


def _every_child(group):
    """A wrong fold: a layer of several fills (a shape and its stroke) as those fills, each
    with the opacity (where they overlap, the one below shows through the one above)."""
    if group.clip is not None or group.mask is not None or group.blend != "normal" \
            or group.isolate or group.filters or len(group.children) < 2 \
            or any(type(c) is not Fill for c in group.children):
        return _fold(group)
    return [Fill(c.path, c.paint, c.rule, c.opacity * group.opacity, c.antialias)
            for c in group.children]


@pytest.mark.parametrize("wrong", [_twice, _every_child], ids=["twice", "fill-and-stroke"])
@pytest.mark.parametrize("config", CONFIGS[:3], ids=IDS[:3])
def test_a_wrong_fold_is_caught(config, wrong, monkeypatch):
    # the comparison above fails for a fold that applies the opacity twice, or folds a
    # fill and its stroke each on its own
    worst = 0
    for seed in SEEDS:
        svg = _document(seed)
        monkeypatch.setattr(render_module, "_opacity_fold", wrong)
        bad = _render(svg, config)
        monkeypatch.setattr(render_module, "_opacity_fold", _unfolded)
        worst = max(worst, _worst(bad, _render(svg, config)))
    assert worst > 8


@pytest.mark.parametrize("mode", ["approx", "analytic", "alpha-sat"])
def test_folded_documents_are_the_same_for_any_band_and_thread_count(mode):
    scene = load_svg(_document(3))
    one = render_scene(scene, mode)
    for budget, threads in ((W * 16 * 3, 2), (W * 16 * 7, 1), (W * 16 * 16, 3)):
        assert np.array_equal(render_scene(scene, mode, band_budget=budget, threads=threads),
                              one)


def test_what_is_folded():
    # opacity alone over one fill, through plain and opacity-only groups, multiplied in;
    # nothing else
    def svg(body):
        return load_svg(f'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8">'
                        f'{body}</svg>').root.children[0]
    (f,) = _fold(svg('<g opacity="0.5"><g><path d="M0 0H4V4Z" fill-opacity="0.5" '
                    'opacity="0.5"/></g></g>'))
    assert f.opacity == 0.125
    for body in ('<g opacity="0.5"><path d="M0 0H4V4Z"/><path d="M0 0H4V4Z"/></g>',
                 '<path d="M0 0H4V4Z" opacity="0.5" stroke="red"/>',
                 '<g opacity="0.5" style="mix-blend-mode:multiply"><path d="M0 0H4V4Z"/></g>',
                 '<g opacity="0.5" style="isolation:isolate"><path d="M0 0H4V4Z"/></g>',
                 '<clipPath id="c"><rect width="3" height="3"/></clipPath>'
                 '<path d="M0 0H4V4Z" opacity="0.5" clip-path="url(#c)"/>'):
        layer = svg(body)
        while not layer.needs_layer():
            layer = layer.children[-1]
        assert _fold(layer) is None, body


def _scattered(seed: int) -> str:
    """Many small folded elements, crowded enough that some share pixels (edge to edge,
    a pixel apart, overlapping) and others not, with plain fills between some of them."""
    r = random.Random(seed)
    out = []
    for i in range(60):
        x, y = r.uniform(-3, W), r.uniform(-3, H)
        s = r.choice((1.5, 3, 6))
        d = (f"M{x:.2f} {y:.2f} l{s:.2f} {r.uniform(0, s):.2f} q{-s:.2f} {s:.2f} "
             f"{r.uniform(-s, 0):.2f} {r.uniform(0, s):.2f}Z" if r.random() < 0.7 else
             f"M{round(x)} {round(y)}h{round(s)}v{round(s)}h{-round(s)}Z")
        crisp = ' shape-rendering="crispEdges"' if r.random() < 0.2 else ""
        extra = f' opacity="{r.uniform(0.2, 0.9):.2f}"' if r.random() < 0.85 else ""
        out.append(f'<path d="{d}" fill="{_paint(r)}"{crisp}{extra}/>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}">{DEFS}'
            f'<rect width="{W}" height="{H}" fill="#f4f0e0"/>{"".join(out)}</svg>')


@pytest.mark.parametrize("config", CONFIGS, ids=IDS)
def test_folded_fills_sharing_no_pixel_draw_as_one_batch_to_the_same_bytes(config, monkeypatch):
    # brute force: runs of folded fills whose pixel boxes are disjoint, drawn as one batch,
    # against each drawn as a batch of its own (DISJOINT_RUN = 1); and the runs taken
    sizes = []
    make = render_module._fill_batches

    def counting(fills, *args):
        sizes.append(len(fills))
        return make(fills, *args)
    for seed in range(4):
        svg = _scattered(seed)
        monkeypatch.setattr(render_module, "_fill_batches", counting)
        runs = _render(svg, config)
        monkeypatch.setattr(render_module, "_fill_batches", make)
        monkeypatch.setattr(render_module, "DISJOINT_RUN", 1)
        assert np.array_equal(_render(svg, config), runs), seed
        monkeypatch.setattr(render_module, "DISJOINT_RUN", 32)
    if config[0] != "analytic":
        assert max(sizes) >= 4


@pytest.mark.parametrize("config", CONFIGS[:2], ids=IDS[:2])
def test_a_pixel_box_too_small_is_caught(config, monkeypatch):
    # the comparison above fails when fills that share pixels are drawn as one batch
    box = render_module._pixel_box

    def shrunk(fill):
        got = box(fill)
        return got and (got[0] + 3, got[1] + 3, got[2] - 3, got[3] - 3)
    differ = 0
    for seed in range(4):
        svg = _scattered(seed)
        monkeypatch.setattr(render_module, "_pixel_box", shrunk)
        wrong = _render(svg, config)
        monkeypatch.setattr(render_module, "_pixel_box", box)
        differ += not np.array_equal(_render(svg, config), wrong)
    assert differ >= 2
