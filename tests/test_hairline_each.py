"""Hairlines of many paths each under a transform of its own in one kernel call
(geometry.hairline.hairline_each), and the runs of sibling <use>s whose strokes are hairlines
made with it (Builder._use_arrays: matplotlib's markers at small output sizes): to the bit
what stroking each path alone under its transform gives (hairline_batch of that path: the
per-instance route transforms the points and strokes them), signed zeros included."""
import math
import random

import numpy as np
import pytest

from vecmsaa.api import load_svg, render_svg_array
from vecmsaa.geometry import hairline_kernels
from vecmsaa.geometry.hairline import (CAP_OUTSET, hairline_batch, hairline_coverage,
                                       hairline_each, use_alpha)
from vecmsaa.scene.nodes import FillRuns
from vecmsaa.scene.transform import compose, cos_sin_degrees
from vecmsaa.svg import builder as builder_module
from vecmsaa.svg.pathdata import parse_path_data

from test_use_runs import FEW_RUNS, canon, per_instance

CHUNK = builder_module.HAIRLINE_CHUNK
NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'


def random_d(rng):
    """Path data of one to three subpaths of lines, quadratics, cubics and arcs (conics in
    the Path), open or closed, now and then a segment of no length or a lone move."""
    def pt():
        return f"{rng.uniform(-6, 6):.3f} {rng.uniform(-6, 6):.3f}"
    parts = []
    for _ in range(rng.randint(1, 3)):
        start = pt()
        parts.append(f"M{start}")
        for _ in range(rng.randint(0, 5)):
            kind = rng.choice("LLQCAZ0")
            if kind == "L":
                parts.append(f"L{pt()}")
            elif kind == "Q":
                parts.append(f"Q{pt()} {pt()}")
            elif kind == "C":
                parts.append(f"C{pt()} {pt()} {pt()}")
            elif kind == "A":
                parts.append(f"A{rng.uniform(0.5, 5):.2f} {rng.uniform(0.5, 5):.2f} "
                             f"{rng.uniform(0, 90):.1f} {rng.randint(0, 1)} "
                             f"{rng.randint(0, 1)} {pt()}")
            elif kind == "0":
                parts.append(f"L{start}")           # (back to the start: maybe no length)
            else:
                parts.append("Z")
    return " ".join(parts)


def random_matrix(rng):
    """A transform to the device: a scale (about the hairline threshold or far from it),
    mirrored or not, rotated by a whole quarter turn (exact zeros, some negative) or any
    angle, maybe skewed, translated by a fraction of a pixel or far."""
    s = rng.choice([0.05, 0.3, 0.55, 1.0, 1.7, 40.0]) * rng.uniform(0.8, 1.2)
    m = (s, 0.0, 0.0, s * rng.choice([1.0, -1.0]), 0.0, 0.0)
    if rng.random() < 0.5:
        m = compose((-1.0, 0.0, 0.0, 1.0, 0.0, 0.0), m)
    angle = rng.choice([0.0, 90.0, 180.0, 270.0, -90.0, rng.uniform(-180, 180)])
    c, s_ = cos_sin_degrees(angle)
    m = compose((c, s_, -s_, c, 0.0, 0.0), m)
    if rng.random() < 0.2:
        m = compose((1.0, 0.0, math.tan(math.radians(rng.uniform(-40, 40))), 1.0, 0.0, 0.0), m)
    t = rng.choice([0.0, -0.0, 0.5, rng.uniform(-3, 30), rng.uniform(-1e4, 1e4)])
    return compose((1.0, 0.0, 0.0, 1.0, t, rng.uniform(-3, 30)), m)


@pytest.mark.parametrize("seed", range(6))
def test_each_path_under_its_own_transform_is_that_path_alone(seed):
    """hairline_each's runs of path which[w] under ms[w], cap and alpha its own, are the
    runs hairline_batch makes of that path alone under that transform: the same verbs,
    the same point bytes, run by run (empty runs too), for random paths (curves, arcs,
    closes, lone moves) under mirrored, rotated, skewed, scaled and translated transforms."""
    rng = random.Random(seed)
    paths = [parse_path_data(random_d(rng)) for _ in range(12)]
    arrays = [p._freeze() for p in paths]
    verbs = np.concatenate([v for v, _ in arrays]).astype(np.uint8)
    points = np.ascontiguousarray(np.concatenate([p for _, p in arrays]), np.float64)
    vstart = np.zeros(len(paths) + 1, np.int64)
    pstart = np.zeros(len(paths) + 1, np.int64)
    np.cumsum([len(v) for v, _ in arrays], out=vstart[1:])
    np.cumsum([len(p) for _, p in arrays], out=pstart[1:])
    n = 150
    which = np.array([rng.randrange(len(paths)) for _ in range(n)], np.int64)
    ms = [random_matrix(rng) for _ in range(n)]
    caps = [rng.choice(["butt", "round", "square"]) for _ in range(n)]
    alphas = [rng.choice([1.0, 0.6, 0.25, 0.0]) for _ in range(n)]
    ov, op, rv, rp, owner = hairline_each(
        verbs, points, vstart, pstart, which, np.array(ms, np.float64),
        np.array([CAP_OUTSET[c] for c in caps]), np.array([use_alpha(a) for a in alphas]))
    assert len(rv) == len(owner) + 1 and (np.diff(owner) >= 0).all()
    drawn = 0
    for w in range(n):
        i = int(which[w])
        one = np.array([i], np.int64)
        want_v, want_p, want_rv, want_rp, want_owner = hairline_batch(
            verbs, points, vstart, pstart, one, ms[w], caps[w], alphas[w])
        r0, r1 = np.searchsorted(owner, [w, w + 1])
        got_rv, got_rp = rv[r0:r1 + 1], rp[r0:r1 + 1]
        assert np.array_equal(got_rv - got_rv[0], want_rv), (seed, w)
        assert np.array_equal(got_rp - got_rp[0], want_rp), (seed, w)
        assert ov[got_rv[0]:got_rv[-1]].tobytes() == want_v.tobytes(), (seed, w)
        assert op[got_rp[0]:got_rp[-1]].tobytes() == want_p.tobytes(), (seed, w)
        drawn += len(want_v) > 0
    assert drawn > n // 2


#: marker targets: matplotlib's circle (cubics, closed, filled), an open polyline, an arc
#: and a quadratic (conics), two subpaths with a close, a line of no length (a hairline of
#: it draws nothing with butt caps: no run)
DEFS = (
    '<defs>'
    '<path id="mk" d="M 0 1.4 C 0.4 1.4 1.4 0.4 1.4 0 C 1.4 -0.4 0.4 -1.4 0 -1.4 '
    'C -0.4 -1.4 -1.4 -0.4 -1.4 0 C -1.4 0.4 -0.4 1.4 0 1.4 z"/>'
    '<path id="pl" d="M-2 -1 L1 2 L2 -1.5" fill="none"/>'
    '<path id="arc" d="M0 0 A2 1 30 0 1 3 1 Q4 3 1 2"/>'
    '<path id="two" d="M-1 -1 H1 V1 Z M2 2 L3 2.5" fill="none"/>'
    '<path id="dot" d="M1 1 L1 1" fill="none"/>'
    '</defs>')


def random_markers(rng, n):
    """n sibling <use>s: translated (x, y), some with a transform of their own (mirrored,
    rotated, scaled), stroke widths about the hairline threshold of the document's scale,
    caps and stroke opacities varied, a few dashed (stroked per instance)."""
    out = []
    for _ in range(n):
        target = rng.choice(["#mk"] * 4 + ["#pl", "#arc", "#two", "#dot"])
        attrs = f'xlink:href="{target}" x="{rng.uniform(-2, 100):.4f}" ' \
            f'y="{rng.uniform(-2, 100):.4f}"'
        if rng.random() < 0.3:
            attrs += ' transform="' + rng.choice([
                "scale(-1 1)", "scale(1 -1)", "rotate(90)", "rotate(180)", "rotate(-37)",
                "scale(0.5)", "scale(2.5)", "matrix(0 -1 1 0 3 4)", "skewX(25)",
                f"translate({rng.uniform(0, 50):.3f} 1) scale(0.7 -0.7)"]) + '"'
        width = rng.choice(["0.3", "0.6", "0.9", "1", "1.1", "1.4", "2", "0.05"])
        style = (f"fill: #1f77b4; fill-opacity: 0.6; stroke: #d62728; "
                 f"stroke-opacity: {rng.choice(['1', '0.6', '0.3'])}; stroke-width: {width}; "
                 f"stroke-linecap: {rng.choice(['butt', 'round', 'square'])}")
        if rng.random() < 0.01:
            style += "; stroke-dasharray: 0.5 0.3"
        out.append(f'<use {attrs} style="{style}"/>')
    return "".join(out)


def counted(monkeypatch, name):
    calls = []
    original = getattr(hairline_kernels, name)

    def count(*args):
        calls.append(len(args[4]))          # (the paths stroked: which)
        return original(*args)
    monkeypatch.setattr(hairline_kernels, name, count)
    return calls


@pytest.mark.parametrize("seed", range(4))
def test_hairline_markers_are_each_instance_stroked_alone(seed, monkeypatch):
    """Random runs of markers under transforms of every kind, their strokes about the
    hairline threshold, a few dashed (stroked per instance): as arrays, the hairlines of the
    stretch are a kernel call for each HAIRLINE_CHUNK of them, a single path's call only for
    a dashed one; the fills are
    those of the per-instance route (a hairline_batch call for each hairline), to the
    bit."""
    rng = random.Random(seed)
    svg = (f'<svg {NS} width="100" height="100">{DEFS}<g>{random_markers(rng, 700)}</g>'
           f'</svg>')
    for width in (100, 41, 230):
        with monkeypatch.context() as m:
            m.setattr(builder_module, "MIN_JOINED_RUNS", FEW_RUNS)
            each = counted(m, "hairline_paths_each")
            alone = counted(m, "hairline_paths_batch")
            root = load_svg(svg, width=width).root
        # (the group's uses are one stretch: its dashed strokes made per instance, Fills
        # between its FillRuns; a dashed stroke's hairline, made per instance, is a single
        # path's call)
        assert any(isinstance(node, FillRuns) for node in root.children), (seed, width)
        assert each[:-1] == [CHUNK] * (len(each) - 1) and 0 < each[-1] <= CHUNK
        assert len(alone) <= svg.count("dasharray"), (seed, width)
        with monkeypatch.context() as m:
            per_instance(m)
            each2 = counted(m, "hairline_paths_each")
            alone2 = counted(m, "hairline_paths_batch")
            assert canon(load_svg(svg, width=width).root) == canon(root), (seed, width)
        # each hairline instance once, alone, in the per-instance route; together before
        assert each2 == [] and alone2 == [1] * len(alone2)
        assert sum(each) + len(alone) == len(alone2) and sum(each) > 50, (seed, width)


def test_hairline_markers_draw_the_bytes_of_each_instance(monkeypatch):
    """The image of a run of hairline markers (matplotlib's scatter at a small size) is the
    per-instance route's, in the sampled and the exact-area modes and on two threads."""
    svg = (f'<svg {NS} width="100" height="100">{DEFS}<g>'
           f'{random_markers(random.Random(9), 800)}</g></svg>')
    kws = [dict(width=60), dict(width=150, threads=2), dict(width=45, mode="analytic")]
    images = [render_svg_array(svg, **kw) for kw in kws]
    per_instance(monkeypatch)
    for kw, image in zip(kws, images):
        assert np.array_equal(image, render_svg_array(svg, **kw)), kw


def test_a_scatter_of_hairline_markers_is_one_fill_runs(monkeypatch):
    """2,000 matplotlib markers whose 1-unit strokes are hairlines at 40 px for 100 units
    (fast length 0.4: coverage a hairline): one FillRuns, each marker's fill and then its
    stroke's runs, the strokes in a kernel call for each HAIRLINE_CHUNK paths."""
    marks = "".join(f'<use xlink:href="#mk" x="{3 + i % 37 * 2.6:.4f}" '
                    f'y="{3 + i // 37 * 1.7:.4f}" style="fill: #1f77b4; stroke: #1f77b4"/>'
                    for i in range(2000))
    assert hairline_coverage(1.0, (0.4, 0, 0, 0.4, 0, 0), True) is not None
    svg = f'<svg {NS} width="100" height="100">{DEFS}<g>{marks}</g></svg>'
    each = counted(monkeypatch, "hairline_paths_each")
    root = load_svg(svg, width=40).root
    (node,) = root.children
    assert type(node) is FillRuns and sum(each) == 2000
    assert each == [CHUNK] * (2000 // CHUNK) + ([2000 % CHUNK] if 2000 % CHUNK else [])
    # styles: the fill, the hairline's (nonzero; its opacity the coverage); each marker's
    # fill run first, then its stroke's, one run or more
    assert len(node.styles) == 2 and node.styles[1][1] == "nonzero"
    kind = node.kind.tolist()
    assert kind[0] == 0 and kind.count(0) == 2000
    assert all(a != 0 or b == 1 for a, b in zip(kind, kind[1:] + [0]))
