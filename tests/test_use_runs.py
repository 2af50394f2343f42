"""Long runs of sibling <use>s (matplotlib's markers and glyphs, cairo's glyph pages) made as
arrays (Builder._use_arrays): each prepared content's fills and stroke outlines one source,
every instance's transform composed on columns, the runs gathered and mapped in one call into
a FillRuns. Checked against three other ways of building the same document: the per-instance
route (Fills, as when the stretch is too short for a FillRuns), each <use> through element(),
and each use's content built where it stands (no prepared content); to the bit."""
import math
import random
import struct

import numpy as np
import pytest

from vecmsaa.api import _Loaded, load_svg, render_svg_array
from vecmsaa.scene.nodes import Fill, FillRuns, Group, Mask, Solid
from vecmsaa.scene.path import Path
from vecmsaa.scene.transform import compose
from vecmsaa.svg import builder as builder_module
from vecmsaa.svg.builder import Builder, _compose_rows

NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'

#: what runs of uses point at: cairo's glyph symbols (a path under a scale), matplotlib's
#: marker path with a stroke of its own, a group whose shapes have transforms of their own
#: and strokes (chains of two lengths in one content), a thin stroke (a hairline: stroked per
#: instance), a dashed one (per instance), content built per instance (text, a nested use, a
#: clipping symbol) and a missing target
DEFS = (
    '<defs><symbol overflow="visible" id="s0"><path style="stroke:none;" '
    'd="M2 0L8 0L5 9Z" transform="scale(0.5,-0.5)"/></symbol>'
    '<symbol overflow="visible" id="s1"><path d="M0 0h6v-6h-6z M1 -1h2v-2h-2z" '
    'fill-rule="evenodd"/></symbol>'
    '<symbol id="clipped" viewBox="0 0 10 10" width="6" height="6"><circle cx="5" cy="5" '
    'r="7"/></symbol>'
    '<path id="mk" d="M 0 1.4 C 0.4 1.4 1.4 0.4 1.4 0 C 1.4 -0.4 0.4 -1.4 0 -1.4 '
    'C -0.4 -1.4 -1.4 -0.4 -1.4 0 C -1.4 0.4 -0.4 1.4 0 1.4 z" style="stroke: #1f77b4"/>'
    '<g id="g"><rect width="4" height="3" transform="rotate(15)"/><g transform="skewX(10)">'
    '<circle cx="3" cy="3" r="2" fill="none" stroke="navy" stroke-width="0.7" '
    'transform="translate(1 -1)"/></g><path d="M0 0 L4 0 L2 3z" fill="olive"/></g>'
    '<path id="p" d="M0 0 Q 5 -8 10 0" stroke="red" stroke-width="0.05" fill="teal"/>'
    '<path id="sq" d="M -1 -1 H 1 V 1 H -1 z" stroke="black" stroke-dasharray="0.5 0.2"/>'
    '<path id="ln" d="M0 0 L3 3" stroke="green" stroke-width="1.5" '
    'stroke-linecap="round"/>'
    '<text id="t" x="0" y="0" font-size="4">a</text><use id="u" href="#s0" x="1"/>'
    '</defs>')

#: targets a stretch's uses point at (#p and #sq: strokes made per instance), and those that
#: send a use through element() (a clipping symbol, text, a nested use, none)
TARGETS = ["#s0", "#s1", "#mk", "#g"] * 12 + ["#p", "#sq", "#ln", "#ln"]
BREAKING_TARGETS = ["#clipped", "#t", "#u", "#none"]

MARKER_STYLE = ("fill: #1f77b4; fill-opacity: 0.6; stroke: #1f77b4; stroke-opacity: 0.6; "
                "stroke-width: {}")


def random_run(rng, n):
    """n sibling <use>s as the exporters write them (href, x, y; matplotlib's shared marker
    style or a translation and a scale each), now and then one with a transform, style,
    condition or target that sends it through element(), or with x and y of 0 (then under
    an identity transform its content's own points are drawn)."""
    def coord():
        v = rng.uniform(-5, 95)
        return rng.choice([f"{v:.3f}"] * 12 + ["0", "", f"{v / 10:.2f}em", f"{v:.0f}%",
                                                f"calc({v:.1f}px + 1px)", "junk"])
    out = []
    for _ in range(n):
        breaking = rng.random() < 0.004
        attrs = f'xlink:href="{rng.choice(BREAKING_TARGETS if breaking else TARGETS)}"'
        if rng.random() < 0.9:
            attrs += f' x="{coord()}"'
        if rng.random() < 0.9:
            attrs += f' y="{coord()}"'
        if rng.random() < 0.004:
            attrs += rng.choice([' transform="scale(0)"', ' style="opacity:0.5"',
                                 ' display="none"', ' systemLanguage="xx"',
                                 ' mask="url(#none)"'])
        else:
            attrs += rng.choice(
                [""] * 30 +
                [f' style="{MARKER_STYLE.format(w)}"' for w in ("0.8", "0.8", "1.2", "0.1",
                                                                 "3")] +
                [f' transform="translate({rng.uniform(0, 90):.4f} 3) scale(0.5 -0.5)"'] * 3 +
                [' transform="rotate(30)"', ' transform="scale(2)"',
                 ' transform="skewY(-20)"', ' width="3"', ' fill="red"',
                 ' style="stroke: gold; stroke-dasharray: 1"'])
        out.append(f"<use {attrs}/>")
    return "".join(out)


GROUPS = ['', 'transform="scale(1.7)"', 'transform="rotate(20 50 50)"',
          'style="fill:rgb(0%,0%,0%);fill-opacity:1;"', 'opacity="0.5"', 'clip-path="url(#c)"',
          'stroke="gold" stroke-width="1.3"', 'transform="matrix(0 -1 1 0 0 100)"',
          'transform="translate(3 50) scale(0.4 -0.4)"', 'shape-rendering="crispEdges"',
          'vector-effect="non-scaling-stroke" stroke="red" stroke-width="2"']


def random_document(seed):
    rng = random.Random(seed)
    body = []
    for _ in range(rng.randint(1, 2)):
        body.append(f"<g {rng.choice(GROUPS)}>{random_run(rng, rng.randint(150, 400))}</g>")
    sheet = rng.choice(["", "<style>*{stroke-linejoin: round; stroke-linecap: butt}</style>",
                        "<style>use{stroke-linecap: square}</style>"])
    return (f'<svg {NS} width="100" height="100">{sheet}<clipPath id="c"><rect width="50" '
            f'height="60"/></clipPath>{DEFS}{"".join(body)}</svg>')


def canon(node):
    """A node as comparable values, FillRuns expanded to their Fills: a Fill's verbs and
    points as bytes (to the bit), its paint, rule, opacity and antialiasing; a Group's
    effects and children."""
    if isinstance(node, Fill):
        v, p = node.path._freeze()
        paint = node.paint.color if isinstance(node.paint, Solid) else repr(node.paint)
        return ("fill", v.tobytes(), p.shape, np.ascontiguousarray(p).tobytes(), paint,
                node.rule, node.opacity, node.antialias)
    if isinstance(node, Group):
        children = []
        for child in node.children:
            children.extend(child.fills() if isinstance(child, FillRuns) else [child])
        return ("group", node.opacity, node.blend, node.isolate, canon(node.clip),
                canon(node.mask), repr(node.filters), [canon(c) for c in children])
    if isinstance(node, Mask):
        return ("mask", node.kind, canon(node.content))
    return node


def runs_in(group) -> list:
    """The FillRuns in a group's tree."""
    out = []
    for child in group.children:
        if isinstance(child, Group):
            out += runs_in(child)
        elif isinstance(child, FillRuns):
            out.append(child)
    return out


def per_instance(monkeypatch):
    """Every stretch made instance by instance (_use_instances' route for short ones)."""
    monkeypatch.setattr(builder_module, "MIN_JOINED_RUNS", 10 ** 9)


#: (the stretches of the random documents made FillRuns from this many runs, so that most
#: are, and those between strokes made per instance are cut into FillRuns and Fills)
FEW_RUNS = 48


@pytest.mark.parametrize("seed", range(12))
def test_long_runs_of_uses_are_the_fills_of_each_use(seed, monkeypatch):
    """Random runs of uses (targets of every kind, transforms, x and y, styles, strokes made
    once per linear part and per instance) built as arrays, instance by instance, each
    through element() and each content where it stands: the same fills to the bit."""
    svg = random_document(seed)
    monkeypatch.setattr(builder_module, "MIN_JOINED_RUNS", FEW_RUNS)
    made = []
    for width in (100, 37, 410):
        arrays = load_svg(svg, width=width).root
        made.append(len(runs_in(arrays)))
        arrays = canon(arrays)
        with monkeypatch.context() as m:
            per_instance(m)
            assert canon(load_svg(svg, width=width).root) == arrays, (seed, width)
        with monkeypatch.context() as m:
            m.setattr(Builder, "shape_runs", False)     # (each use through element())
            assert canon(load_svg(svg, width=width).root) == arrays, (seed, width)
        with monkeypatch.context() as m:
            m.setattr(Builder, "_prepare_instance", lambda *a: None)
            assert canon(load_svg(svg, width=width).root) == arrays, (seed, width)
    assert any(made), seed


@pytest.mark.parametrize("seed", range(3))
def test_long_runs_of_uses_draw_the_bytes_of_each_use(seed, monkeypatch):
    svg = random_document(100 + seed)
    monkeypatch.setattr(builder_module, "MIN_JOINED_RUNS", FEW_RUNS)
    kws = [dict(width=100), dict(width=173, threads=2), dict(width=90, mode="analytic")]
    images = [render_svg_array(svg, **kw) for kw in kws]
    per_instance(monkeypatch)
    for kw, image in zip(kws, images):
        assert np.array_equal(image, render_svg_array(svg, **kw)), kw


def markers(n, style="0.8", extra=""):
    """matplotlib's scatter: n <use>s of one marker path with the run's shared style."""
    return "".join(f'<use xlink:href="#mk" x="{3 + i % 37 * 2.6:.4f}" '
                   f'y="{3 + i // 37 * 1.7:.4f}" style="{MARKER_STYLE.format(style)}"{extra}/>'
                   for i in range(n))


class Counts:
    """Fills and Paths made, prepared contents' plans, stroke outlines and point mappings,
    counted through the builder module."""
    def __init__(self, monkeypatch):
        self.made = {"Fill": 0, "Path": 0, "plan": 0, "outline": 0, "apply_each": 0}
        made = self.made
        fill_init = Fill.__init__

        def counting_init(self, *args, **kw):
            made["Fill"] += 1
            fill_init(self, *args, **kw)

        class CountingPath(Path):
            def __new__(cls, *args, **kw):
                made["Path"] += 1
                return super().__new__(cls)

        def counted(name, f):
            def call(*a, **kw):
                made[name] += 1
                return f(*a, **kw)
            return call
        monkeypatch.setattr(Fill, "__init__", counting_init)
        monkeypatch.setattr(builder_module, "Path", CountingPath)
        monkeypatch.setattr(Builder, "_use_plan", counted("plan", Builder._use_plan))
        monkeypatch.setattr(Builder, "_scaling_outline",
                            counted("outline", Builder._scaling_outline))
        monkeypatch.setattr(builder_module, "apply_each",
                            counted("apply_each", builder_module.apply_each))


def test_a_plots_markers_make_no_fill_or_path_per_marker(monkeypatch):
    """2,000 markers with a fill and a stroke each: one FillRuns of 4,000 runs, made with
    one plan (the content under one linear part), one stroke outline and one mapping, and
    no Fill or Path object per marker; as the per-instance route's Fills, to the bit."""
    svg = f'<svg {NS} width="100" height="100">{DEFS}<g>{markers(2000)}</g></svg>'
    counts = Counts(monkeypatch)
    root = load_svg(svg, width=300).root
    (node,) = root.children             # (the plain group's nodes are the root's)
    assert type(node) is FillRuns and len(node) == 4000
    assert len(node.styles) == 2 and np.array_equal(node.kind, np.tile([0, 1], 2000))
    assert counts.made == {"Fill": 0, "Path": 0, "plan": 1, "outline": 1, "apply_each": 1}
    monkeypatch.undo()
    per_instance(monkeypatch)
    assert canon(load_svg(svg, width=300).root) == canon(root)


def test_a_glyph_page_makes_a_plan_per_glyph(monkeypatch):
    """A page of 3,000 glyph <use>s of two symbols (pdftocairo): one FillRuns, a plan per
    glyph, no Fill or Path per use; uses with transforms of their own (matplotlib's labels)
    of one linear part add one plan per glyph, not one per use."""
    uses = "".join(f'<use xlink:href="#s{i % 2}" x="{i % 17 * 5.25:.2f}" y="{1 + i // 17 * 0.6}"'
                   + (f' transform="translate({i % 7} 2) scale(0.5 -0.5)"' if i % 3 == 0
                      else "") + "/>" for i in range(3000))
    svg = f'<svg {NS} width="100" height="100">{DEFS}<g>{uses}</g></svg>'
    counts = Counts(monkeypatch)
    root = load_svg(svg, width=100).root
    (node,) = runs_in(root)
    assert len(node) == 3000
    assert counts.made == {"Fill": 0, "Path": 0, "plan": 4, "outline": 0, "apply_each": 1}
    monkeypatch.undo()
    with monkeypatch.context() as m:
        per_instance(m)
        assert canon(load_svg(svg, width=100).root) == canon(root)
    monkeypatch.setattr(Builder, "shape_runs", False)
    assert canon(load_svg(svg, width=100).root) == canon(root)


def test_strokes_made_per_instance_split_the_runs(monkeypatch):
    """Markers whose strokes are dashed (stroked per instance) between stretches of others:
    FillRuns where a stretch is long enough, Fills between, in order."""
    dashed = ' stroke-dasharray="0.4 0.3"'
    body = markers(600) + markers(3, extra=dashed) + markers(10) + \
        markers(1, extra=dashed) + markers(700, style="1.1")
    svg = f'<svg {NS} width="100" height="100">{DEFS}<g>{body}</g></svg>'
    root = load_svg(svg, width=300).root
    kinds = [type(node).__name__ for node in root.children]
    assert kinds[0] == "FillRuns" and kinds[-1] == "FillRuns" and len(kinds) > 2
    assert len(root.children[0]) == 1200 and len(root.children[-1]) == 1400
    assert set(kinds[1:-1]) == {"Fill"}
    per_instance(monkeypatch)
    assert canon(load_svg(svg, width=300).root) == canon(root)


def _loaded_nodes(svg):
    loaded = _Loaded(svg, 96, None, {})
    loaded.scene(100, None, None, None, False, True)
    return loaded.builder.nodes_made


def test_a_run_counts_each_use_and_its_content_once(monkeypatch):
    """MAX_NODES counts each use and its content's elements once, as element() counts them."""
    groups = "".join(f'<use href="#g" x="{i}"/>' for i in range(300))
    svg = f'<svg {NS} width="100" height="100">{DEFS}<g>{markers(700)}{groups}</g></svg>'
    arrays = _loaded_nodes(svg)
    monkeypatch.setattr(Builder, "shape_runs", False)
    assert _loaded_nodes(svg) == arrays
    # (each use, its content's elements: a path; a group of a rect, a group, a circle and
    # a path)
    assert arrays >= 700 * 2 + 300 * 5


def _bits(rows):
    """Each row's bytes, NaN written as one value (its sign and payload follow the order of
    an operation's operands, which a C compiler may swap)."""
    return [struct.pack("<6d", *(math.nan if v != v else v for v in row)) for row in rows]


def test_compose_rows_is_compose_of_each_row():
    """_compose_rows gives each row the bytes compose() gives it alone, for matrices of
    scalars and of columns, with signed zeros, infinities and NaN among them."""
    rng = random.Random(5)
    specials = [0.0, -0.0, 1.0, -1.0, 1e-300, 1e300, math.inf, -math.inf, math.nan, 0.1]

    def value():
        return rng.choice(specials) if rng.random() < 0.3 else rng.uniform(-1e3, 1e3)
    rows = [tuple(value() for _ in range(6)) for _ in range(400)]
    m = tuple(value() for _ in range(6))
    got = _compose_rows(np.array(rows), m)
    assert _bits(got) == _bits([compose(r, m) for r in rows])
    ms = [tuple(value() for _ in range(6)) for _ in range(400)]
    got = _compose_rows(np.array(rows), np.array(ms).T)
    assert _bits(got) == _bits([compose(r, mm) for r, mm in zip(rows, ms)])
