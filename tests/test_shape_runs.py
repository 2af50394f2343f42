"""Runs of sibling shapes (Builder._shape_run: basic shapes and styled paths whose styles need
nothing of element() of their own) give the nodes that element() gives each of them alone:
random runs of shapes and styles built both ways (Builder.shape_runs off: every element
through element()) and their scenes compared exactly, paths' arrays to the bit."""
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg
from vecmsaa.scene.nodes import Fill, FillRuns, Group, Mask, Solid
from vecmsaa.svg import builder as builder_module
from vecmsaa.svg.builder import Builder

NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'

DEFS = ('<defs><linearGradient id="g"><stop stop-color="red"/><stop offset="1"/>'
        '</linearGradient><marker id="m" markerWidth="4" markerHeight="4">'
        '<rect width="2" height="2"/></marker><clipPath id="c"><rect width="50" height="60"/>'
        '</clipPath><style>.a { fill: teal; stroke: navy } .b { stroke-width: 3; '
        'stroke-linejoin: round } .c { fill-opacity: 0.5; stroke: #333; stroke-width: 0.4 }'
        '</style></defs>')

#: styles a shape may specify: some shared by many siblings, some that send it element()'s way
#: (transform, opacity, clip, markers, paint servers, context paints) or that stroke it other
#: than with the lines kernels (dashes, non-scaling, hairlines, curves)
STYLES = [
    '', 'fill="steelblue" fill-opacity="0.6" stroke="#333" stroke-width="0.5"',
    'fill="none" stroke="black"', 'fill="black" stroke="black"', 'class="a"', 'class="a b"',
    'class="c"', 'stroke="red" stroke-width="4" stroke-linecap="square"',
    'stroke="blue" stroke-width="2" stroke-linejoin="bevel" paint-order="stroke"',
    'fill-rule="evenodd" stroke="green" stroke-width="0.05"',
    'stroke="green" stroke-dasharray="3 1" stroke-width="2"',
    'stroke="green" vector-effect="non-scaling-stroke" stroke-width="1.5"',
    'shape-rendering="crispEdges" stroke="purple"', 'style="fill: orange; stroke: none"',
    'transform="translate(3 4)" fill="red"', 'opacity="0.5" stroke="red"',
    'clip-path="url(#c)" fill="olive"', 'marker-start="url(#m)" stroke="black"',
    'fill="url(#g)"', 'stroke="url(#g)" stroke-width="3"', 'display="none"',
    'visibility="hidden" stroke="red"', 'fill="currentColor" color="maroon"',
    'stroke="black" stroke-width="1em" font-size="3"', 'stroke="black" stroke-width="2%"',
    'stroke="black" stroke-linecap="round" stroke-width="6"',
]

PATHS = ["M10 10 L40 12 L30 35 Z", "", "M5 5 L25 5", "M10 40 C20 30 30 50 40 40",
         "M60 10 l10 0 M80 10 l0 10 z", "M50 50", "M20 70 Z", "M0 0 h90 v90 h-90 z",
         "M10 80 A 20 10 30 0 1 50 70", "M1e400 5 L 20 20", "M 5 5 Q 30 0 40 40 T 70 70"]


def random_shape(rng):
    """A random basic shape or path, its geometry attributes as exporters write them (and
    some of the other ways SVG lets them be written)."""
    def num(lo, hi):
        v = rng.uniform(lo, hi)
        return rng.choice([f"{v:.2f}", f"{v:.0f}", f"{v / 10:.3f}em", f"{v:.1f}%",
                           f"{v * 0.2646:.3f}mm", f"calc({v:.1f}px + 1px)", f"{v:.2e}"]
                          if rng.random() < 0.15 else [f"{v:.2f}"])
    kind = rng.choice(["circle", "circle", "ellipse", "rect", "rect", "line", "polyline",
                       "polygon", "path", "path"])
    if kind == "circle":
        r = rng.choice([num(0.5, 9), num(0.5, 9), "0", "-2", ""])
        return f'<circle cx="{num(0, 100)}" cy="{num(0, 100)}" r="{r}"'
    if kind == "ellipse":
        rx = rng.choice([num(1, 20), "-1", "auto", None])
        ry = rng.choice([num(1, 20), "0", None])
        attrs = "".join(f' {k}="{v}"' for k, v in (("rx", rx), ("ry", ry)) if v is not None)
        return f'<ellipse cx="{num(0, 100)}" cy="{num(0, 100)}"{attrs}'
    if kind == "rect":
        attrs = f'<rect x="{num(0, 80)}" y="{num(0, 80)}" width="{num(0, 40)}" ' \
                f'height="{rng.choice([num(0, 40), num(0, 40), "0"])}"'
        if rng.random() < 0.4:
            attrs += f' rx="{rng.choice([num(0, 10), "0", "-3"])}"'
        if rng.random() < 0.3:
            attrs += f' ry="{rng.choice([num(0, 10), "0"])}"'
        return attrs
    if kind == "line":
        return f'<line x1="{num(0, 100)}" y1="{num(0, 100)}" x2="{num(0, 100)}" ' \
               f'y2="{num(0, 100)}"'
    if kind in ("polyline", "polygon"):
        pts = " ".join(f"{rng.uniform(0, 100):.1f},{rng.uniform(0, 100):.1f}"
                       for _ in range(rng.choice([1, 2, 3, 5])))
        return f'<{kind} points="{pts}"'
    return f'<path d="{rng.choice(PATHS)}"'


def random_document(rng):
    """Runs of siblings sharing a style (a D3 scatter, class-styled exports), runs of mixed
    styles, and now and then an element of its own (a condition, pathLength, text, a
    group), in groups under random transforms."""
    body = []
    for _ in range(rng.randint(1, 4)):
        group = rng.choice(['', 'transform="scale(1.7)"', 'transform="rotate(20 50 50)"',
                            'fill="purple" stroke="gold"', 'transform="matrix(0 -1 1 0 0 100)"'])
        body.append(f"<g {group}>")
        for _ in range(rng.randint(1, 5)):
            shared = rng.choice(STYLES)
            for _ in range(rng.choice([rng.randint(1, 12), 40])):
                style = shared if rng.random() < 0.7 else rng.choice(STYLES)
                extra = rng.choice([""] * 12 + [' systemLanguage="xx"', ' pathLength="10"',
                                                ' id="e"', ' requiredExtensions="x"'])
                body.append(f"{random_shape(rng)} {style}{extra}/>")
            if rng.random() < 0.2:
                body.append(rng.choice(['<g><rect width="5" height="5"/></g>',
                                        '<text x="5" y="20">a</text>', '<title>t</title>']))
        body.append("</g>")
    return f'<svg {NS} width="100" height="100">{DEFS}{"".join(body)}</svg>'


def canon(node):
    """A node as comparable values: a Fill's verbs and points as bytes (to the bit), its
    paint, rule, opacity and antialiasing; a Group's effects and children."""
    if isinstance(node, Fill):
        v, p = node.path._freeze()
        paint = node.paint.color if isinstance(node.paint, Solid) else repr(node.paint)
        return ("fill", v.tobytes(), p.shape, p.tobytes(), paint, node.rule, node.opacity,
                node.antialias)
    if isinstance(node, Group):
        return ("group", node.opacity, node.blend, node.isolate, canon(node.clip),
                canon(node.mask), repr(node.filters), [canon(c) for c in expanded(node.children)])
    if isinstance(node, Mask):
        return ("mask", node.kind, canon(node.content))
    return node


def expanded(nodes):
    """nodes with each FillRuns replaced by its Fills."""
    out = []
    for node in nodes:
        out.extend(node.fills() if isinstance(node, FillRuns) else [node])
    return out


def both_ways(svg, monkeypatch, **kw):
    scenes = []
    for on in (True, False):
        monkeypatch.setattr(Builder, "shape_runs", on)
        scenes.append(canon(load_svg(svg, **kw).root))
    return scenes


@pytest.mark.parametrize("seed", range(40))
def test_runs_of_shapes_draw_as_each_shape_alone(seed, monkeypatch):
    rng = random.Random(seed)
    svg = random_document(rng)
    for width in (100, 37, 410):
        runs, alone = both_ways(svg, monkeypatch, width=width)
        assert runs == alone, (seed, width)


def test_shape_run_makes_each_shapes_geometry_once_for_all(monkeypatch):
    """A run of 300 circles and 300 rectangles sharing two styles: no element() call, no
    pen path per shape (shapes.shape_path), both kinds' points made in one call each, and
    the rectangles' strokes (lines, wider than a pixel) in one kernel call; the same nodes
    as element() makes."""
    rng = random.Random(7)
    circles = "".join(f'<circle cx="{rng.uniform(0, 100):.2f}" cy="{rng.uniform(0, 100):.2f}" '
                      f'r="{rng.uniform(1, 5):.1f}" fill="steelblue" fill-opacity="0.6"/>'
                      for _ in range(300))
    rects = "".join(f'<rect x="{rng.uniform(0, 90):.1f}" y="{rng.uniform(0, 90):.1f}" '
                    f'width="5" height="3" class="r"/>' for _ in range(300))
    svg = (f'<svg {NS} width="100" height="100"><style>.r {{ fill: red; stroke: blue; '
           f'stroke-width: 2 }}</style>{circles}{rects}</svg>')
    calls = {"element": 0, "shape_path": 0, "points": 0, "batch": 0}

    def counting(name, f):
        def wrapped(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return wrapped
    monkeypatch.setattr(Builder, "element", counting("element", Builder.element))
    monkeypatch.setattr(builder_module, "shape_path", counting("shape_path",
                                                               builder_module.shape_path))
    monkeypatch.setattr(builder_module, "_bulk_points",
                        counting("points", builder_module._bulk_points))
    kernels = builder_module.stroke_kernels
    monkeypatch.setattr(kernels, "stroke_lines_batch", counting("batch",
                                                                 kernels.stroke_lines_batch))
    runs, alone = both_ways(svg, monkeypatch, width=200)
    assert runs == alone
    assert len(runs[-1]) == 900            # a fill per circle, a fill and a stroke per rect
    # the runs: one call for each kind's points, one stroke kernel call; the second build
    # (shape runs off) went through element() and shape_path once per shape, and stroked
    # each rectangle alone (stroke_lines is stroke_lines_batch for one path); the <style>
    # element goes through element() in both
    assert calls == {"element": 2 + 600, "shape_path": 600, "points": 2, "batch": 1 + 300}


def test_shapes_made_in_bulk_have_shapes_pens_points():
    """ellipse_path and rect_path (made as arrays) record what the pen records for SVG's
    outlines of the shapes (a moveto, four quarter conics weighted cos 45° through the box's
    corners, a close; the corners clockwise), and the points a run makes of many shapes at
    once (_bulk_points) or row by row are theirs, to the bit, exactly representable or not;
    each conic's point at t = ½ is the ellipse's at 45°."""
    from vecmsaa.scene.path import Path, rect_corners, rect_path
    from vecmsaa.svg.shapes import QUARTER_W, ellipse_path, ellipse_points
    rng = np.random.default_rng(3)
    params = np.column_stack([rng.uniform(-1e3, 1e3, 200), rng.uniform(-1e3, 1e3, 200),
                              rng.uniform(1e-3, 50, 200), rng.uniform(1e-3, 50, 200)])
    params[:3] = [[1, 2, 3, 4], [0.1, 0.2, 0.3, 0.7], [-5.5, 1e-300, 1e300, 2.0]]
    bulk = builder_module._bulk_points(ellipse_points, params.tolist())
    for row, got in zip(params.tolist(), bulk):
        cx, cy, rx, ry = row
        pen = Path()
        pen.moveTo((cx + rx, cy))
        pen.conicTo((cx + rx, cy + ry), (cx, cy + ry), QUARTER_W)
        pen.conicTo((cx - rx, cy + ry), (cx - rx, cy), QUARTER_W)
        pen.conicTo((cx - rx, cy - ry), (cx, cy - ry), QUARTER_W)
        pen.conicTo((cx + rx, cy - ry), (cx + rx, cy), QUARTER_W)
        pen.closePath()
        made = ellipse_path(*row)
        assert made.verbs.tobytes() == pen.verbs.tobytes()
        assert made.points.tobytes() == pen.points.tobytes() == got.tobytes()
        assert np.array(ellipse_points(*row)).tobytes() == got.tobytes()
        half = np.sqrt(0.5) * np.array([(rx, ry), (-rx, ry), (-rx, -ry), (rx, -ry)])
        assert np.allclose(got[2::3], half + (cx, cy), rtol=0,
                           atol=1e-14 * max(map(abs, row)))
    rects = builder_module._bulk_points(rect_corners, params.tolist())
    for row, got in zip(params.tolist(), rects):
        x, y, w, h = row
        pen = Path()
        pen.moveTo((x, y))
        for q in ((x + w, y), (x + w, y + h), (x, y + h)):
            pen.lineTo(q)
        pen.closePath()
        made = rect_path(*row)
        assert made.verbs.tobytes() == pen.verbs.tobytes()
        assert made.points.tobytes() == pen.points.tobytes() == got.tobytes()
        assert np.array(rect_corners(*row)).tobytes() == got.tobytes()


def test_shape_run_strokes_hairlines_at_once_and_reads_lengths_in_bulk(monkeypatch):
    """A D3 scatter's circles (plain-number lengths, strokes under a pixel wide): no length()
    call per circle (their lengths read as columns), one hairline kernel call for all of
    their strokes, each stroke's runs in its circle's place; the same nodes as element()
    makes of each circle."""
    rng = random.Random(11)
    circles = "".join(f'<circle cx="{rng.uniform(0, 100):.2f}" cy="{rng.uniform(0, 100):.2f}" '
                      f'r="{rng.choice(["2.1", "3", "6.0", "0.5"])}" fill="steelblue" '
                      f'fill-opacity="0.6" stroke="#333" stroke-width="0.5"/>'
                      for _ in range(300))
    svg = f'<svg {NS} width="100" height="100">{circles}</svg>'
    calls = {"length": 0, "hairline": 0}

    def counting(name, f):
        def wrapped(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return wrapped
    monkeypatch.setattr(Builder, "length", counting("length", Builder.length))
    monkeypatch.setattr(builder_module, "hairline_batch",
                        counting("hairline", builder_module.hairline_batch))
    monkeypatch.setattr(Builder, "shape_runs", True)
    runs = canon(load_svg(svg, width=100).root)
    assert calls["hairline"] == 1
    assert calls["length"] <= 2              # (the style's stroke width, and no circle's)
    monkeypatch.setattr(Builder, "shape_runs", False)
    alone = canon(load_svg(svg, width=100).root)
    assert runs == alone
    # every circle's stroke drawn, in runs (a hairline circle's are several) after its fill
    fills = [node for node in runs[-1] if node[4] == (0.2, 0.2, 0.2, 1.0)]
    assert len(runs[-1]) - len(fills) == 300 and len(fills) > 300


@pytest.mark.parametrize("texts", [
    ["1", "2.5", "-3", "+4", ".5", "6."], ["1", None, "2"], [None, None], ["1", ""],
    ["1", "1.2.3"], ["+"], ["1", "2e3"], ["1", " 2"], ["1", "3px"], ["1", "50%"],
    ["1", "2em"], ["1", "calc(1px + 2px)"], ["1", "-"], ["1e400"], ["1", "\u0661"]])
def test_lengths_read_in_bulk_are_lengths_read_one_by_one(texts):
    """_shape_lengths' columns are Builder.length's of each text, whether all of them are
    plain numbers (read at once) or one is not (then each goes through length())."""
    svg = (f'<svg {NS} width="100" height="80" font-size="10">' +
           "".join('<circle/>' for _ in texts) + '</svg>')
    from vecmsaa.api import _Loaded
    loaded = _Loaded(svg, 96, None, {})
    builder, doc = loaded.builder, loaded.builder.doc
    elements = list(doc.root.children)
    for el, text in zip(elements, texts):
        if text is not None:
            el.attrs["cx"] = el.attrs["r"] = text
    root_style = doc.document_style(doc.root)
    styles = [root_style.child(el) for el in elements]
    cx, r = builder._shape_lengths(elements, styles, (("cx", "x", 0.0), ("r", "xy", None)),
                                   (100.0, 80.0))
    for el, style, x, radius in zip(elements, styles, cx, r):
        want_x = builder.length(el.attrs.get("cx"), "x", style, (100.0, 80.0), 0.0)
        want_r = builder.length(el.attrs.get("r"), "xy", style, (100.0, 80.0), None)
        assert repr(x) == repr(want_x) and repr(radius) == repr(want_r), texts


#: targets of <use> as cairo writes its glyphs (a symbol of one path, overflow visible), and
#: the others a run of uses may meet: a clipping symbol, groups and shapes with transforms
#: and strokes, content that is built per instance (text, a nested use), a missing target
USE_DEFS = (
    '<defs><symbol overflow="visible" id="s0"><path style="stroke:none;" '
    'd="M2 0L8 0L5 9Z" transform="scale(0.5,-0.5)"/></symbol>'
    '<symbol overflow="visible" id="s1"><path d="M0 0h6v-6h-6z M1 -1h2v-2h-2z" '
    'fill-rule="evenodd"/></symbol>'
    '<symbol id="clipped" viewBox="0 0 10 10" width="6" height="6"><circle cx="5" cy="5" '
    'r="7"/></symbol>'
    '<g id="g"><rect width="4" height="3" transform="rotate(15)"/><circle cx="3" cy="3" r="2" '
    'fill="none" stroke="navy" stroke-width="0.7"/></g>'
    '<path id="p" d="M0 0 Q 5 -8 10 0" stroke="red" stroke-width="0.1" fill="teal"/>'
    '<text id="t" x="0" y="0" font-size="4">a</text><use id="u" href="#s0" x="1"/>'
    '<path id="mk" d="M 0 1.4 C 0.4 1.4 1.4 0.4 1.4 0 C 1.4 -0.4 0.4 -1.4 0 -1.4 '
    'C -0.4 -1.4 -1.4 -0.4 -1.4 0 C -1.4 0.4 -0.4 1.4 0 1.4 z" style="stroke: #1f77b4"/>'
    '<path id="sq" d="M -1 -1 H 1 V 1 H -1 z" stroke-dasharray="0.5 0.2"/>'
    '<g id="inh" opacity="inherit"><rect width="3" height="3" transform="inherit"/></g>'
    '<rect id="inh2" width="2" height="5" style="vector-effect: INHERIT"/>'
    '<path id="em" d="M0 0 L5 5 L10 0" fill="none" stroke="black" stroke-width="0.2em"/>'
    '</defs>')

USE_TARGETS = ["#s0", "#s1", "#s0", "#s1", "#clipped", "#g", "#p", "#t", "#u", "#none", "",
               "#mk", "#mk", "#sq", "#inh", "#inh2", "#em", "#p"]


def random_uses(rng):
    """Runs of <use> siblings as cairo writes them (href, x, y), now and then one with a
    width, a transform or a style of its own, or lengths in units, between paths."""
    def coord():
        v = rng.uniform(-5, 95)
        return rng.choice([f"{v:.3f}"] * 8 + ["0", "", f"{v / 10:.2f}em", f"{v:.0f}%",
                                               f"calc({v:.1f}px + 1px)", "junk"])
    out = []
    for _ in range(rng.randint(1, 60)):
        attrs = f'xlink:href="{rng.choice(USE_TARGETS)}"'
        if rng.random() < 0.9:
            attrs += f' x="{coord()}"'
        if rng.random() < 0.9:
            attrs += f' y="{coord()}"'
        # (matplotlib's markers: a style of fill and stroke shared by the run's uses; its
        # glyphs: a translation and a scale each)
        attrs += rng.choice([""] * 20 + [' width="3"', ' transform="scale(2)"',
                                          ' fill="red"', ' style="opacity:0.5"', ' id="q"',
                                          ' systemLanguage="xx"', ' display="none"',
                                          ' transform="scale(0)"', ' mask="url(#none)"'] +
                            [' style="fill: #1f77b4; fill-opacity: 0.6; stroke: #1f77b4; '
                             'stroke-opacity: 0.6; stroke-width: 0.8"'] * 6 +
                            [f' transform="translate({rng.uniform(0, 90):.4f} 3) '
                             f'scale(0.5 -0.5)"'] * 3)
        out.append(f"<use {attrs}/>")
        if rng.random() < 0.05:
            out.append('<path d="M0 0 L9 9 L0 9z"/>')
    return "".join(out)


@pytest.mark.parametrize("seed", range(30))
def test_runs_of_uses_draw_as_each_use_alone(seed, monkeypatch):
    """Builder._use_run's nodes are element()'s for each <use>, to the bit, in groups of
    every kind of style (display none, opacity, a clip) and under transforms."""
    rng = random.Random(seed)
    body = []
    for _ in range(rng.randint(1, 3)):
        group = rng.choice(['', 'transform="scale(1.7)"', 'transform="rotate(20 50 50)"',
                            'style="fill:rgb(0%,0%,0%);fill-opacity:1;"', 'opacity="0.5"',
                            'clip-path="url(#c)"', 'stroke="gold" stroke-width="0.3"',
                            'display="none"', 'transform="matrix(0 -1 1 0 0 100)"',
                            'transform="translate(3 50) scale(0.4 -0.4)"',
                            'opacity="0.5" fill="teal"',
                            'vector-effect="non-scaling-stroke" stroke="red" stroke-width="2"'])
        uses = random_uses(rng)
        body.append(f"<g {group}>{uses}</g>")
        if rng.random() < 0.5:
            # the same uses in viewports of one size fitted at other scales (the same styles
            # and viewport: a stroke's outline made once may not be reused at another scale)
            for fit in rng.sample(["none", "xMidYMid", "xMinYMin slice", "xMaxYMax"], 2):
                body.append(f'<svg width="90" height="30" viewBox="0 0 40 40" '
                            f'preserveAspectRatio="{fit}">{uses}</svg>')
    # (matplotlib's sheet gives every element values most of them inherit anyway)
    sheet = rng.choice(["", "<style>*{stroke-linejoin: round; stroke-linecap: butt}</style>",
                        "<style>use{stroke-linecap: square}</style>",
                        "<style>*{font-size: 1.5em}</style>",
                        "<style>*{stroke-width: 0.5em}</style>"])
    svg = (f'<svg {NS} width="100" height="100">{sheet}<clipPath id="c"><rect width="50" '
           f'height="60"/></clipPath>{USE_DEFS}{"".join(body)}</svg>')
    for width in (100, 37, 410):
        runs, alone = both_ways(svg, monkeypatch, width=width)
        assert runs == alone, (seed, width)
        # and as each use's content built where it stands (no prepared content: its strokes
        # stroked under each instance's transform)
        monkeypatch.setattr(Builder, "_prepare_instance", lambda *a: None)
        built = canon(load_svg(svg, width=width).root)
        monkeypatch.undo()
        assert runs == built, (seed, width)


def test_a_page_of_glyph_uses_maps_its_points_in_one_call(monkeypatch):
    """A run of glyph <use>s (pdftocairo's page) maps every instance's points in one
    apply_each call, none through a point mapper of its own, and draws as each use alone."""
    uses = "".join(f'<use xlink:href="#s{i % 2}" x="{i % 17 * 5.25:.2f}" y="{i // 17 * 6}"/>'
                   for i in range(200))
    svg = f'<svg {NS} width="100" height="100">{USE_DEFS}<g>{uses}</g></svg>'
    calls = {"each": 0, "mapper": 0}
    each = builder_module.apply_each

    def counted_each(*a):
        calls["each"] += 1
        return each(*a)
    monkeypatch.setattr(builder_module, "apply_each", counted_each)
    mapper = builder_module.point_mapper

    def counted_mapper(pts):
        mapped = mapper(pts)

        def wrapped(m):
            calls["mapper"] += 1
            return mapped(m)
        return wrapped
    monkeypatch.setattr(builder_module, "point_mapper", counted_mapper)
    runs, alone = both_ways(svg, monkeypatch, width=100)
    assert runs == alone
    assert calls["each"] == 1
    # (the general way maps all 200 one by one)
    assert calls["mapper"] == 200
    assert len(runs[-1]) == 200


def test_a_plots_markers_are_stroked_once(monkeypatch):
    """matplotlib's scatter: thousands of <use>s of one marker path, with the style of fill
    and stroke their run shares. The stroke's outline is made once (it depends on the
    transform's linear part, which the uses share) and the instances' outlines and fills
    mapped in one call; the scene is what building each use's content where it stands gives."""
    style = ('fill: #1f77b4; fill-opacity: 0.6; stroke: #1f77b4; stroke-opacity: 0.6; '
             'stroke-width: 0.8')
    uses = "".join(f'<use xlink:href="#mk" x="{3 + i % 19 * 5.1:.4f}" y="{3 + i // 19 * 4.7:.4f}" '
                   f'style="{style}"/>' for i in range(300))
    svg = f'<svg {NS} width="100" height="100">{USE_DEFS}<g clip-path="url(#c)">{uses}</g>' \
          f'<clipPath id="c"><rect width="80" height="90"/></clipPath></svg>'
    calls = {"outline": 0, "each": 0}
    outline, each = Builder._scaling_outline, builder_module.apply_each

    def counted_outline(*a):
        calls["outline"] += 1
        return outline(*a)

    def counted_each(*a):
        calls["each"] += 1
        return each(*a)
    monkeypatch.setattr(Builder, "_scaling_outline", counted_outline)
    monkeypatch.setattr(builder_module, "apply_each", counted_each)
    runs = canon(load_svg(svg, width=400).root)
    assert calls == {"outline": 1, "each": 1}
    fills = runs[-1][0][-1]         # (the clipped group's children)
    assert len(fills) == 600        # a fill and a stroke each
    monkeypatch.setattr(Builder, "_prepare_instance", lambda *a: None)
    assert canon(load_svg(svg, width=400).root) == runs
    assert calls["outline"] == 1 + 300      # (stroke() strokes each use's path anew)
