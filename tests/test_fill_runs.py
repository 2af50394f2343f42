"""FillRuns: a long run of shapes and their strokes handed from the SVG builder to the raster
as one batch's arrays (scene.nodes.FillRuns), not as a Fill per run of each outline."""
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg, render_svg_array
from vecmsaa.geometry.primitives import batch_arrays
from vecmsaa.raster import render as render_module
from vecmsaa.scene.nodes import Fill, FillRuns, Group, Scene, Solid, translated
from vecmsaa.scene.path import Path
from vecmsaa.svg import builder as builder_module

NS = 'xmlns="http://www.w3.org/2000/svg"'


def scatter(n, seed=1, extra=""):
    """A D3 scatter plot's circles: filled, with strokes under a pixel wide (hairlines)."""
    rng = random.Random(seed)
    return "".join(f'<circle cx="{rng.uniform(0, 100):.2f}" cy="{rng.uniform(0, 100):.2f}" '
                   f'r="{rng.choice(["2.1", "3", "6.0", "0.5"])}" fill="steelblue" '
                   f'fill-opacity="0.6" stroke="#333" stroke-width="0.5"{extra}/>'
                   for _ in range(n))


def classes(n, seed=2):
    """An Illustrator export's class-styled paths: polygons, each class a fill colour and a
    1-unit black stroke (stroked by the lines stroke kernel, not as hairlines)."""
    rng = random.Random(seed)
    style = "".join(f".st{k}{{fill:#{rng.randrange(1 << 24):06x};stroke:#000;"
                    f"stroke-miterlimit:10;}}" for k in range(5))
    paths = []
    for _ in range(n):
        x, y = rng.uniform(0, 95), rng.uniform(0, 95)
        pts = " ".join(f"{x + rng.uniform(0, 6):.2f},{y + rng.uniform(0, 6):.2f}"
                       for _ in range(rng.randint(3, 6)))
        paths.append(f'<polygon class="st{rng.randrange(5)}" points="{pts}"/>')
    return f"<style>{style}</style>{''.join(paths)}"


def document(body, size=100):
    return f'<svg {NS} width="{size}" height="{size}">{body}</svg>'


def fills_of(nodes):
    """(verbs bytes, points bytes, paint, rule, opacity, antialias) of each fill, FillRuns
    expanded, groups walked in order."""
    out = []
    for node in nodes:
        if isinstance(node, Group):
            out += fills_of(node.children)
        elif isinstance(node, FillRuns):
            out += fills_of(node.fills())
        else:
            v, p = node.path._freeze()
            paint = node.paint.color if isinstance(node.paint, Solid) else repr(node.paint)
            out.append((v.tobytes(), p.shape, p.tobytes(), paint, node.rule, node.opacity,
                        node.antialias))
    return out


def runs_in(group) -> int:
    """The FillRuns in a group's tree."""
    return sum(runs_in(c) if isinstance(c, Group) else isinstance(c, FillRuns)
               for c in group.children)


def without_runs(monkeypatch):
    """The builder made to give Fills only (a stretch needs more runs than any here)."""
    monkeypatch.setattr(builder_module, "MIN_JOINED_RUNS", 10 ** 9)


@pytest.mark.parametrize("body", [scatter(300), classes(300),
                                  # (map data: unstyled paths under a styled group)
                                  '<g fill="none" stroke="#333" stroke-width="0.4">' +
                                  "".join(f'<path d="M{i % 97} {i % 89}l5 3l-2 4z"/>'
                                          for i in range(700)) + "</g>"])
@pytest.mark.parametrize("width", [100, 37, 410])
def test_fill_runs_expand_to_the_fills_made_without_them(body, width, monkeypatch):
    """A FillRuns' fills() are the Fills the builder makes when it makes no FillRuns: the
    same paths (verbs and points to the bit), paints, rules, opacities, in the same order."""
    svg = document(body)
    joined = load_svg(svg, width=width).root
    assert runs_in(joined) >= 1
    without_runs(monkeypatch)
    alone = load_svg(svg, width=width).root
    assert runs_in(alone) == 0
    assert fills_of([joined]) == fills_of([alone])
    assert len(Scene(1, 1, joined).fills()) == len(fills_of([alone]))


def test_a_scatter_plot_is_one_node_not_a_fill_per_run():
    """2,000 circles with hairline strokes (a fill per circle, a few runs per stroke) make
    one FillRuns at the root, holding every run: no Fill object per run."""
    scene = load_svg(document(scatter(2000)), width=100)
    (node,) = scene.root.children
    assert type(node) is FillRuns
    runs = len(node)
    assert runs > 2 * 2000
    assert len(node.voff) == len(node.poff) == runs + 1
    assert node.voff[-1] == len(node.verbs) and node.poff[-1] == len(node.points)
    # two styles: the circles' fill and their strokes' (each hairline run its own coverage
    # in its paint's alpha: one style for all of them)
    assert len(node.styles) == 2
    assert sorted(set(node.kind.tolist())) == [0, 1]
    # every run draws something: a verb besides moveto and close
    v, vo = node.verbs, node.voff.tolist()
    assert all(bytes(v[a:b]).translate(None, bytes((0, 4))) for a, b in zip(vo, vo[1:]))


def test_few_runs_stay_fills():
    """A small document keeps its Fills (the stretch is shorter than MIN_JOINED_RUNS)."""
    scene = load_svg(document(scatter(20)), width=100)
    assert all(type(c) is Fill for c in scene.root.children)


def _render(svg, **kw):
    return render_svg_array(svg, **kw)


WRAPPERS = ["{}", '<g opacity="0.5">{}</g>',
            '<clipPath id="c"><circle cx="50" cy="50" r="40"/></clipPath>'
            '<g clip-path="url(#c)">{}</g>',
            '<mask id="m"><rect width="60" height="100" fill="#888"/></mask>'
            '<g mask="url(#m)">{}</g>',
            '<filter id="f" x="0" y="0" width="1" height="1"><feOffset dx="3" dy="2"/>'
            '</filter><g filter="url(#f)">{}</g>',
            '<filter id="b"><feGaussianBlur stdDeviation="1"/></filter>'
            '<g filter="url(#b)"><rect x="-10.5" width="30" height="20" fill="red"/>{}</g>',
            # (a plain Fill before and after the runs in the same batch; fills of opacity 0)
            '<rect x="3" y="4" width="50" height="20" fill="gold" pathLength="3"/>{}'
            '<rect x="30" y="40" width="50" height="20" fill="green" pathLength="3"/>',
            '<g fill-opacity="0">{}</g>']


@pytest.mark.parametrize("wrapper", WRAPPERS)
@pytest.mark.parametrize("body", ['<g shape-rendering="crispEdges">' + classes(300) + "</g>",
                                  scatter(250), classes(300)])
def test_fill_runs_draw_the_bytes_of_their_fills(wrapper, body, monkeypatch):
    """Rendered with FillRuns or with the Fills they stand for, the same bytes, in groups
    of every kind (layers, clips, masks, filters that move their content)."""
    svg = document(wrapper.format(body))
    assert runs_in(load_svg(svg, width=100).root) == 1
    kws = [dict(width=100), dict(width=173, threads=2)]
    joined = [_render(svg, **kw) for kw in kws]
    without_runs(monkeypatch)
    for kw, image in zip(kws, joined):
        assert np.array_equal(image, _render(svg, **kw)), kw


@pytest.mark.parametrize("mode", ["analytic", "alpha", "persample", "none", "a2c",
                                  "alpha-sat"])
def test_fill_runs_draw_the_same_bytes_in_every_mode(mode, monkeypatch):
    svg = document(scatter(300) + classes(300))
    # (one run: the <style> between them, which draws nothing, does not end it)
    assert runs_in(load_svg(svg, width=100).root) == 1
    joined = _render(svg, width=120, mode=mode)
    without_runs(monkeypatch)
    assert np.array_equal(joined, _render(svg, width=120, mode=mode))


def test_kept_arrays_are_the_batch_arrays_of_the_paths_kept():
    """_kept_arrays (rows gathered by offsets) against batch_arrays of the paths kept."""
    rng = np.random.default_rng(5)
    paths = []
    for _ in range(60):
        n = int(rng.integers(0, 5))
        verbs = np.array([0] + [1] * n, np.uint8)
        paths.append(Path._of_arrays(verbs, rng.normal(size=(n + 1, 2))))
    arrays = batch_arrays(paths)
    for keep in (rng.random(60) < 0.5, np.zeros(60, bool), np.ones(60, bool)):
        got = render_module._kept_arrays(arrays, keep)
        want = batch_arrays([p for p, k in zip(paths, keep) if k])
        for a, b in zip(got, want):
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_joined_arrays_are_the_batch_arrays_of_all_paths():
    rng = np.random.default_rng(6)
    paths = [Path._of_arrays(np.array([0, 1, 1, 4], np.uint8), rng.normal(size=(3, 2)))
             for _ in range(30)]
    parts = [batch_arrays(paths[a:b]) for a, b in ((0, 7), (7, 8), (8, 30))]
    for a, b in zip(render_module._joined_arrays(parts), batch_arrays(paths)):
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_translated_fill_runs_are_their_fills_translated():
    scene = load_svg(document(scatter(300)), width=100)
    (node,) = scene.root.children
    moved = translated(node, 3.25, -4.5)
    assert type(moved) is FillRuns
    want = [translated(f, 3.25, -4.5) for f in node.fills()]
    assert fills_of([moved]) == fills_of(want)
    assert np.array_equal(node.points, scene.root.children[0].points)   # (not moved itself)


def random_run(seed, n=700):
    """A run of simple shapes as exporters write them, mixed: circles, ellipses, rects (some
    rounded), lines, polylines, polygons and paths, each with one of several styles (plain
    fills, evenodd, crispEdges, hairline and wide strokes, dashes, no fill, opacity 0)."""
    rng = random.Random(seed)
    styles = ['fill="steelblue" fill-opacity="0.6" stroke="#333" stroke-width="0.5"',
              'fill="#c33" fill-rule="evenodd"', 'fill="none" stroke="navy" stroke-width="2"',
              'fill="gold" shape-rendering="crispEdges" stroke="black" stroke-width="0.3"',
              'fill="green" stroke="black" stroke-width="1.5" stroke-dasharray="2 1"',
              'fill="purple" fill-opacity="0"', 'fill="#0a0"']
    out = []
    for _ in range(n):
        x, y = rng.uniform(0, 95), rng.uniform(0, 95)
        style = rng.choice(styles)
        kind = rng.randrange(7)
        if kind == 0:
            out.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{rng.uniform(0.3, 4):.2f}" '
                       f'{style}/>')
        elif kind == 1:
            out.append(f'<ellipse cx="{x:.2f}" cy="{y:.2f}" rx="{rng.uniform(0.5, 5):.2f}" '
                       f'ry="{rng.uniform(0.5, 3):.2f}" {style}/>')
        elif kind == 2:
            rx = f' rx="{rng.uniform(0.2, 1):.2f}"' if rng.random() < 0.3 else ""
            out.append(f'<rect x="{x:.2f}" y="{y:.2f}" width="{rng.uniform(0, 6):.2f}" '
                       f'height="{rng.uniform(0.1, 6):.2f}"{rx} {style}/>')
        elif kind == 3:
            out.append(f'<line x1="{x:.2f}" y1="{y:.2f}" x2="{x + rng.uniform(-5, 5):.2f}" '
                       f'y2="{y + rng.uniform(-5, 5):.2f}" {style}/>')
        elif kind in (4, 5):
            pts = " ".join(f"{x + rng.uniform(0, 6):.2f},{y + rng.uniform(0, 6):.2f}"
                           for _ in range(rng.randint(2, 5)))
            tag = "polyline" if kind == 4 else "polygon"
            out.append(f'<{tag} points="{pts}" {style}/>')
        else:
            out.append(f'<path d="M{x:.2f} {y:.2f}q3 -4 5 0t4 2l-2 3z'
                       f'{"m1 1h2v2" if rng.random() < 0.5 else ""}" {style}/>')
    return "".join(out)


RUN_WRAPPERS = ["{}", '<g transform="translate(3.5 -2) rotate(17) scale(1.3 0.8)">{}</g>',
                '<svg viewBox="3 1 90 70" width="100" height="100" '
                'preserveAspectRatio="none">{}</svg>']


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("wrapper", RUN_WRAPPERS)
def test_random_runs_as_arrays_are_the_fills_made_one_by_one(seed, wrapper, monkeypatch):
    """Random runs of mixed shapes, styles and transforms: the FillRuns made straight from
    the shapes' arrays expand to the Fills the builder makes without FillRuns (the same
    verbs and points to the bit, styles, order) and to those of each element built alone,
    and draw the same bytes."""
    svg = document(wrapper.format(random_run(seed)))
    joined = load_svg(svg, width=100).root
    assert runs_in(joined) >= 1
    images = [_render(svg, width=100), _render(svg, width=90, threads=2)]
    without_runs(monkeypatch)
    alone = load_svg(svg, width=100).root
    assert runs_in(alone) == 0
    assert fills_of([joined]) == fills_of([alone])
    assert np.array_equal(images[0], _render(svg, width=100))
    assert np.array_equal(images[1], _render(svg, width=90, threads=2))
    # and the Fills of each element built alone (element(), no shape runs at all)
    monkeypatch.setattr(builder_module.Builder, "shape_runs", False)
    assert fills_of([load_svg(svg, width=100).root]) == fills_of([joined])


def test_a_run_of_shapes_makes_no_path_or_fill_per_shape(monkeypatch):
    """2,000 circles and 2,000 paths with fills (and hairline strokes) in a run: their
    geometry goes from the shapes' and the path batch's arrays to the FillRuns' without a
    Path or a Fill object per shape."""
    made = {"Fill": 0, "Path": 0}
    fill_init = Fill.__init__

    def counting_init(self, *args, **kw):
        made["Fill"] += 1
        fill_init(self, *args, **kw)

    class CountingPath(Path):
        """Path as the builder makes it, counted (a __new__ set on Path itself and deleted
        after would leave Path refusing its arguments)."""
        def __new__(cls, *args, **kw):
            made["Path"] += 1
            return super().__new__(cls)
    body = scatter(2000) + "".join(f'<path d="M{i % 90} {i % 80}l5 3l-2 4z" fill="teal"/>'
                                   for i in range(2000))
    svg = document(body)
    monkeypatch.setattr(Fill, "__init__", counting_init)
    monkeypatch.setattr(builder_module, "Path", CountingPath)
    scene = load_svg(svg, width=100)
    (node,) = scene.root.children
    assert type(node) is FillRuns and len(node) > 2000 + 2 * 2000
    # (a Path of the first path's data, read before the document's path batch)
    assert made["Fill"] == 0 and made["Path"] <= 1


def test_a_batch_of_runs_reads_its_paints_per_style(monkeypatch):
    """The raster's batch of a FillRuns of 2,000 circles and their strokes (two styles) hands
    its paint table two fills' paints (shaders.style_arrays' styles, or PaintTable.add_fills'
    fills), not one per run."""
    from vecmsaa.raster import shaders
    read = []
    add_fills = shaders.PaintTable.add_fills

    def counting_add(self, fills, pattern_tile):
        read.append(len(fills))
        return add_fills(self, fills, pattern_tile)
    monkeypatch.setattr(shaders.PaintTable, "add_fills", counting_add)
    style_arrays = getattr(render_module, "style_arrays", None)
    if style_arrays is not None:
        def counting_styles(styles, kind, pattern_tile):
            read.append(len(styles))
            return style_arrays(styles, kind, pattern_tile)
        monkeypatch.setattr(render_module, "style_arrays", counting_styles)
    _render(document(scatter(2000)), width=100)
    assert sum(read) == 2


def test_style_arrays_are_the_paint_table_of_each_fill():
    """shaders.style_arrays of styles and each fill's index is PaintTable.add_fills of the
    fills one by one, to the byte: solids, gradients (shared ramps), images (shared
    texture), styles unused or used out of order."""
    from vecmsaa.raster.shaders import PaintTable, style_arrays
    from vecmsaa.scene.nodes import ImagePaint, LinearGradient, RadialGradient
    rng = np.random.default_rng(8)
    stops = [np.array([[0, 1, 0, 0, 1], [1, 0, 0, 1, 0.5]]),
             np.array([[0, 0, 1, 0, 1], [0.4, 1, 1, 0, 1], [1, 0, 0, 0, 1]])]
    image = rng.random((3, 4, 4)).astype(np.float32)
    red = Solid((1, 0, 0, 0.8))
    paints = [red, red, Solid((0, 0.5, 1, 1)), LinearGradient(0, 0, 10, 5, stops[0]),
              LinearGradient(1, 2, 3, 4, stops[1], "reflect"),
              RadialGradient(5, 5, 4, 4, 4, stops[0]), ImagePaint(image, (2, 0, 0, 2, 1, 1)),
              ImagePaint(image)]
    styles = [Fill(None, paint, "nonzero", opacity, True)
              for paint in paints for opacity in (1.0, 0.5)]
    for solids_only in (True, False):
        use = [i for i, f in enumerate(styles)
               if not solids_only or type(f.paint) is Solid]
        kind = np.array([use[int(i)] for i in rng.integers(0, len(use) - 1, 500)], np.int64)
        table = PaintTable()
        table.add_fills([styles[k] for k in kind.tolist()], None)
        want = table.arrays()
        got = style_arrays(styles, kind, None)
        for a, b in zip(got, want):
            assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
