"""Runs of shapes across plain groups (Builder.children walks the children of a <g> or <a>
that has no transform, clip, mask, filter, opacity, blending or isolation of its own as its
own, so that one _shape_run takes a Graphviz layout's node and edge groups, other elements
in between kept in their places) and strokes of different styles queued together where
their outlines are alike: random documents of nested groups built both ways (shape runs off:
every element through element()) compared exactly, scenes to the bit and images to the
byte, and the work counted."""
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg, render_svg
from vecmsaa.svg import builder as builder_module
from vecmsaa.svg.builder import Builder

from test_shape_runs import DEFS, NS, STYLES, both_ways, random_shape

#: what a group may specify: nothing or inherited properties (walked as its parent's
#: children), or what makes it a layer or moves it (built through element())
GROUPS = ['', '', '', 'class="node"', 'fill="purple" stroke="gold"', 'id="x"',
          'stroke="black" stroke-width="0.2"', 'transform="translate(5 3)"',
          'opacity="0.5"', 'clip-path="url(#c)"', 'display="none"', 'visibility="hidden"',
          'systemLanguage="xx"', 'style="mix-blend-mode: multiply"', 'isolation="isolate"',
          'font-size="30"', 'fill-opacity="0.3"']

#: elements that are no shape, met among shapes
OTHERS = ['<title>t</title>', '<text x="5" y="20" font-size="9">ab</text>',
          '<use xlink:href="#u" x="3"/>', '<desc>d</desc>', '<image width="3" height="3"/>',
          '<path d="M0 0 L30 30 L0 30 Z"/>', '<svg width="10" height="10"><rect width="5" '
          'height="5"/></svg>']


def random_body(rng, depth):
    out = []
    for _ in range(rng.randint(1, 5)):
        r = rng.random()
        if r < 0.35 and depth < 4:
            tag = rng.choice(["g", "g", "g", "a"])
            out.append(f"<{tag} {rng.choice(GROUPS)}>{random_body(rng, depth + 1)}</{tag}>")
        elif r < 0.5:
            out.append(rng.choice(OTHERS))
        else:
            shared = rng.choice(STYLES)
            for _ in range(rng.choice([1, 2, 3, 8])):
                style = shared if rng.random() < 0.7 else rng.choice(STYLES)
                out.append(f"{random_shape(rng)} {style}/>")
    return "".join(out)


def random_document(rng):
    defs = DEFS.replace("</defs>", '<circle id="u" r="4" fill="teal"/></defs>')
    return (f'<svg {NS} width="100" height="100">{defs}'
            f'<g {rng.choice(GROUPS[:8])}>{random_body(rng, 0)}</g>{random_body(rng, 1)}</svg>')


@pytest.mark.parametrize("seed", range(40))
def test_runs_across_groups_draw_as_each_element_alone(seed, monkeypatch):
    rng = random.Random(seed)
    svg = random_document(rng)
    for width in (100, 37, 410):
        runs, alone = both_ways(svg, monkeypatch, width=width,
                                use_fonts_dir=FONTS, skip_system_fonts=True)
        assert runs == alone, (seed, width)


FONTS = "/work/shared/resvg-suite/fonts"


@pytest.mark.parametrize("seed", range(6))
def test_runs_across_groups_render_the_same_bytes(seed, monkeypatch):
    rng = random.Random(100 + seed)
    svg = random_document(rng)
    images = []
    for on in (True, False):
        monkeypatch.setattr(Builder, "shape_runs", on)
        images.append(np.asarray(render_svg(svg, width=150)))
    assert np.array_equal(*images)


def graph(n):
    """A Graphviz layout's groups: a <g> per node (title, ellipse, label) and per edge
    (title, path, arrowhead polygon), strokes a hairline at the widths used below."""
    rng = random.Random(n)
    body = ['<polygon fill="white" stroke="none" points="0,400 400,400 400,0 0,0"/>']
    for i in range(n):
        x, y = rng.uniform(20, 380), rng.uniform(20, 380)
        body.append(f'<g id="node{i}" class="node"><title>n{i}</title><ellipse fill="none" '
                    f'stroke="black" cx="{x:.1f}" cy="{y:.1f}" rx="20" ry="9"/>'
                    f'<text x="{x:.1f}" y="{y:.1f}" font-size="7">n</text></g>')
        body.append(f'<g class="edge"><title>a</title><path fill="none" stroke="black" '
                    f'd="M{x:.1f},{y:.1f}C{x:.1f},{y + 9:.1f} {x + 5:.1f},{y + 9:.1f} '
                    f'{x + 5:.1f},{y + 20:.1f}"/><polygon fill="black" stroke="black" '
                    f'points="{x:.1f},{y + 20:.1f} {x + 5:.1f},{y + 25:.1f} '
                    f'{x + 10:.1f},{y + 20:.1f}"/></g>')
    return f'<svg {NS} width="400" height="400"><g class="graph">{"".join(body)}</g></svg>'


def counting(calls, name, f):
    def wrapped(*a, **k):
        calls[name] += 1
        return f(*a, **k)
    return wrapped


def test_graph_groups_are_one_run(monkeypatch):
    """300 node groups and 300 edge groups: one _shape_run for all their shapes, their
    hairlines (ellipses, paths and polygons: three styles of one stroke) a kernel call for
    each kind and no stroke() per shape, element() only for the titles
    and labels; the same nodes as element() makes of each group."""
    svg = graph(300)
    calls = {"element": 0, "run": 0, "stroke": 0, "hairline": 0}
    monkeypatch.setattr(Builder, "element", counting(calls, "element", Builder.element))
    monkeypatch.setattr(Builder, "_shape_run", counting(calls, "run", Builder._shape_run))
    monkeypatch.setattr(Builder, "stroke", counting(calls, "stroke", Builder.stroke))
    monkeypatch.setattr(builder_module, "hairline_batch",
                        counting(calls, "hairline", builder_module.hairline_batch))
    monkeypatch.setattr(Builder, "shape_runs", True)
    kw = dict(width=100, use_fonts_dir=FONTS, skip_system_fonts=True)
    runs = load_svg(svg, **kw)
    # (ellipses, paths of the document's path batch and polygons: three kinds of geometry,
    # a style each; stroke() once per label, whose glyphs draw_path strokes with none)
    assert calls == {"element": 600 + 300, "run": 1, "stroke": 300, "hairline": 3}
    monkeypatch.setattr(Builder, "shape_runs", False)
    for name in calls:
        calls[name] = 0
    from test_shape_runs import canon
    alone = load_svg(svg, **kw)
    # (element-wise: the graph's group and background, every group and its three children;
    # a stroke() for each shape (the background's of none too) and each label)
    assert calls["element"] == 2 + 600 + 1800 and calls["stroke"] == 1 + 900 + 300
    assert canon(runs.root) == canon(alone.root)


def classes(n, k):
    """n paths of k classes, each its own fill and the same stroke (an Illustrator export)."""
    rng = random.Random(k)
    style = "".join(f".st{i}{{fill:#{rng.randrange(1 << 24):06x};stroke:#000;"
                    f"stroke-miterlimit:10;}}" for i in range(k))
    paths = "".join(f'<path class="st{rng.randrange(k)}" d="M{rng.uniform(0, 90):.1f},'
                    f'{rng.uniform(0, 90):.1f}c5,-3 10,2 12,8s-4,9 -10,7z"/>'
                    for _ in range(n))
    return f'<svg {NS} width="100" height="100"><style>{style}</style>{paths}</svg>'


@pytest.mark.parametrize("width, which", [(100, "hairline"), (300, "stroke_segments")])
def test_strokes_of_different_classes_share_kernel_calls(width, which, monkeypatch):
    """400 paths of 40 classes that differ in fill only: their strokes (hairlines at 100 px,
    curved outlines 3 px wide at 300 px) queued together, not per class: the curve
    stroker's in one call, as one class's are, the hairlines a call for each HAIRLINE_CHUNK
    paths (one class's: one call); the same nodes as element() makes of each path."""
    calls = {which: 0}
    if which == "hairline":
        monkeypatch.setattr(builder_module, "hairline_batch",
                            counting(calls, which, builder_module.hairline_batch))
    else:
        kernels = builder_module.stroke_kernels
        monkeypatch.setattr(kernels, which, counting(calls, which, getattr(kernels, which)))
    monkeypatch.setattr(Builder, "shape_runs", True)
    load_svg(classes(400, 1), width=width)
    one_class = calls[which]
    calls[which] = 0
    load_svg(classes(400, 40), width=width)
    assert one_class == 1
    chunks = -(-400 // builder_module.HAIRLINE_CHUNK) if which == "hairline" else 1
    assert calls[which] == chunks < 40
    runs, alone = both_ways(classes(400, 40), monkeypatch, width=width)
    assert runs == alone


@pytest.mark.parametrize("tag", ["polygon", "polyline"])
def test_points_paths_are_shape_paths(tag):
    """_shape_run's polylines and polygons (_points_path: arrays, the list read by one
    finditer) record what shape_path's pen records, to the bit, for lists as exporters
    write them and lists in error (drawn up to the error: SVG 2), with too few points, odd
    counts, numbers past a double, a trailing comma."""
    from vecmsaa.svg.document import load_document
    from vecmsaa.svg.shapes import shape_path
    rng = random.Random(9)
    texts = ["", " ", "1,2", "1,2 3,4", "1 2 3 4 5", "10px,10 20,20", "1,,2 3,4 5,6",
             "1e400,2 3,4 5,6", "1,2 3,4 5,6 1e400", "0.5.5 1.5-2e1,3", "1,2,3,4,",
             " 1 , 2\t3\n4  ", "1,2 3,4 x 5,6", "-.5+.5 1e-3,1E+2 7 8", ".1.2.3.4"]
    for _ in range(60):
        n = rng.choice([2, 3, 4, 9, 70])
        texts.append(rng.choice([" ", ",", ", "]).join(
            f"{rng.uniform(-1e3, 1e3):.{rng.randint(0, 6)}f}" for _ in range(n)))
    body = "".join(f'<{tag} points="{t}"/>' for t in texts)
    doc = load_document(f'<svg {NS}>{body}</svg>'.encode())
    for el in doc.root.children:
        want = shape_path(el, None)
        got = builder_module._points_path(tag, el)
        if want is None:
            assert got is None, el.get("points")
            continue
        (wv, wp), (gv, gp) = want._freeze(), got._freeze()
        assert wv.dtype == gv.dtype and wv.tobytes() == gv.tobytes(), el.get("points")
        assert wp.shape == gp.shape and wp.tobytes() == gp.tobytes(), el.get("points")
