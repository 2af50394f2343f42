"""Solid strokes of curved paths stroked many at once (geometry.stroke.stroke_batch: the
curve stroker's kernels called once for a batch of paths, as Builder._shape_run strokes a
run's circles, ellipses and curved paths): each path's outline is the one stroke_path makes
of it alone, to the bit; the outlines are the exact stroke's (winding numbers at points of
known distance from a circle); a run of curved strokes is one stroker call."""
import math
import random

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from truth import segments, winding_at
from vecmsaa.geometry import stroke_kernels
from vecmsaa.geometry.stroke import stroke_batch, stroke_path
from vecmsaa.scene.path import CONIC, CUBIC, QUAD, Path
from vecmsaa.svg.builder import Builder, _batch_of
from vecmsaa.svg.pathdata import parse_path_data
from vecmsaa.svg.shapes import ellipse_path

from test_shape_runs import NS, both_ways

_CURVES = bytes((QUAD, CUBIC, CONIC))

# coordinates: small integers (coincident points, degenerate curves, cusps), fractions,
# and huge and tiny magnitudes
_coord = st.one_of(st.integers(0, 12).map(float), st.floats(-50, 50, allow_nan=False),
                   st.sampled_from([1e12, -3e11, 1e-9, 2.5e-12, 7e6]))
_pt = st.tuples(_coord, _coord)


def _fmt(v):
    return repr(float(v))


@st.composite
def _curved_path_data(draw):
    """Path data with at least one curve command: lines, quadratics, cubics (degenerate ones:
    control points on the ends or on one line), arcs (circular and elliptical, rotated,
    large and small, zero radii), closes and subpaths of their own."""
    out = [f"M {_fmt(draw(_coord))} {_fmt(draw(_coord))}"]
    for i in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from("LQCAAZMC" if i else "QCA"))
        if kind in "LM":
            x, y = draw(_pt)
            out.append(f"{kind} {_fmt(x)} {_fmt(y)}")
        elif kind == "Q":
            out.append("Q " + " ".join(_fmt(v) for p in (draw(_pt), draw(_pt)) for v in p))
        elif kind == "C":
            a, b = draw(_pt), draw(_pt)
            c = draw(st.one_of(_pt, st.just(a), st.just(b)))      # (coincident controls)
            out.append("C " + " ".join(_fmt(v) for p in (a, c, b) for v in p))
        elif kind == "A":
            rx = draw(st.one_of(st.floats(0, 40), st.sampled_from([0.0, 1e-6, 1e9])))
            ry = draw(st.one_of(st.just(rx), st.floats(0, 40)))
            x, y = draw(_pt)
            out.append(f"A {_fmt(rx)} {_fmt(ry)} {draw(st.integers(-90, 90))} "
                       f"{draw(st.integers(0, 1))} {draw(st.integers(0, 1))} {_fmt(x)} {_fmt(y)}")
        else:
            out.append("Z")
    return " ".join(out)


def _curved(path):
    return not set(path.verbs.tobytes()).isdisjoint(_CURVES)


def _expect(paths, which, width, join, cap, limit, tol):
    return [stroke_path(paths[i], width, join=join, cap=cap, miterlimit=limit, tolerance=tol)
            for i in which]


def _check_batch(paths, which, width, join, cap, limit, tol):
    verbs, points, vstart, pstart = _batch_of([p._freeze() for p in paths])
    ov, op, vo, po = stroke_batch(verbs, points, vstart, pstart, np.array(which, np.int64),
                                  width / 2.0, tol, stroke_kernels.JOIN_CODES[join],
                                  stroke_kernels.CAP_CODES[cap], max(1.0, limit))
    assert len(vo) == len(po) == len(which) + 1
    assert vo[-1] == len(ov) and po[-1] == len(op)
    for k, alone in enumerate(_expect(paths, which, width, join, cap, limit, tol)):
        v, p = alone._freeze()
        if alone.is_empty():        # (a run without verbs: _run_fills makes no Fill of it)
            assert vo[k + 1] == vo[k] and po[k + 1] == po[k], k
            continue
        assert ov[vo[k]:vo[k + 1]].tobytes() == v.tobytes(), k
        assert op[po[k]:po[k + 1]].tobytes() == p.tobytes(), k


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_curved_path_data(), min_size=1, max_size=6),
       st.sampled_from(["miter", "miter-clip", "round", "bevel", "arcs"]),
       st.sampled_from(["butt", "round", "square"]),
       st.sampled_from([0.01, 0.7, 3.0, 40.0, 1e8]), st.sampled_from([0.5, 1.0, 4.0, 10.0]),
       st.sampled_from([0.25, 0.01, 1.0]), st.randoms(use_true_random=False))
@example(["M 0 0 C 0 0 0 0 0 0", "M 5 5 Q 5 5 5 5 Z", "M 1 1 A 0 0 0 0 1 1 1"], "miter",
         "butt", 3.0, 4.0, 0.25, random.Random(0))
@example(["M 0 0 A 10 10 0 1 1 0 0.001 Z M 3 3 C 3 3 9 9 9 9"], "round", "round", 2.0, 4.0,
         0.25, random.Random(1))
def test_batch_outlines_are_each_paths_own(ds, join, cap, width, limit, tol, rnd):
    """The outlines stroke_batch makes of paths with curves, in an order of their own and
    some twice, are stroke_path's of each path alone, to the bit (a path drawing nothing:
    an empty run, where stroke_path's outline is empty)."""
    paths = [p for p in map(parse_path_data, ds) if _curved(p)]
    paths += [ellipse_path(rnd.uniform(-50, 50), rnd.uniform(-50, 50), rx, ry)
              for rx, ry in ((rnd.uniform(0.1, 30), rnd.uniform(0.1, 30)), (2.0, 2.0),
                             (1e-7, 1e-7), (1e10, 3.0))]
    which = [rnd.randrange(len(paths)) for _ in range(rnd.randint(1, 2 * len(paths)))]
    _check_batch(paths, which, width, join, cap, limit, tol)


def test_batch_of_no_paths_and_of_paths_drawing_nothing():
    paths = [parse_path_data("M 3 3 Q 3 3 3 3"), parse_path_data("M 1 1 C 5 5 6 0 9 9")]
    _check_batch(paths, [], 2.0, "miter", "butt", 4.0, 0.25)
    _check_batch(paths, [0, 1, 0], 2.0, "miter", "butt", 4.0, 0.25)
    _check_batch(paths, [0, 1, 0], 2.0, "miter", "round", 4.0, 0.25)


def test_batch_outline_of_circles_is_their_ring():
    """The nonzero fill of each circle's outline in a batch is the ring of points within the
    half width of the circle (winding numbers at points off the ring by a tenth of the half
    width inside and outside, all around, and halfway to the centre)."""
    rng = np.random.default_rng(5)
    circles = [(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(1, 30))
               for _ in range(25)]
    paths = [ellipse_path(cx, cy, r, r) for cx, cy, r in circles]
    hw = 0.75
    verbs, points, vstart, pstart = _batch_of([p._freeze() for p in paths])
    ov, op, vo, po = stroke_batch(verbs, points, vstart, pstart,
                                  np.arange(len(paths), dtype=np.int64), hw, 0.01, 0, 0, 4.0)
    for k, (cx, cy, r) in enumerate(circles):
        outline = segments(Path._of_arrays(ov[vo[k]:vo[k + 1]], op[po[k]:po[k + 1]]))
        for a in np.linspace(0, 2 * math.pi, 17)[:-1] + 0.1:     # (off the conics' ends)
            for d, inside in ((-1.1, False), (-0.9, True), (0.0, True), (0.9, True),
                              (1.1, False), (-0.5 * r / hw, False)):
                rr = r + d * hw
                got = winding_at(outline, cx + rr * math.cos(a), cy + rr * math.sin(a))
                assert (got != 0) == inside, (k, a, d)


def test_run_of_curved_strokes_is_one_stroker_call(monkeypatch):
    """A run of 200 circles, 50 ellipses and 50 curved paths sharing a stroke 2 px wide: no
    stroke() per shape, each kind's outlines from one call of the curve stroker (circles
    and ellipses are one block of geometry, the paths another), the same nodes as element()
    makes of each (the second build, shape runs off: a stroker call per shape)."""
    rng = random.Random(3)
    shapes = [f'<circle cx="{rng.uniform(0, 100):.2f}" cy="{rng.uniform(0, 100):.2f}" '
              f'r="{rng.uniform(1, 5):.1f}"/>' for _ in range(200)]
    shapes += [f'<ellipse cx="{rng.uniform(0, 100):.1f}" cy="{rng.uniform(0, 100):.1f}" '
               f'rx="{rng.uniform(1, 9):.1f}" ry="{rng.uniform(1, 9):.1f}"/>'
               for _ in range(50)]
    # (paths specifying a style: those that specify none are runs of their own, _path_run)
    shapes += [f'<path d="M{rng.uniform(0, 90):.1f},{rng.uniform(0, 90):.1f}c5,-3 10,2 12,8'
               f's-4,9 -10,7z" fill-rule="evenodd"/>' for _ in range(50)]
    rng.shuffle(shapes)
    svg = (f'<svg {NS} width="100" height="100"><g fill="teal" stroke="navy" '
           f'stroke-width="1" stroke-linejoin="round">{"".join(shapes)}</g></svg>')
    calls = {"stroke": 0, "stroke_segments": 0, "path_segments_batch": 0}

    def counting(name, f):
        def wrapped(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return wrapped
    monkeypatch.setattr(Builder, "stroke", counting("stroke", Builder.stroke))
    for name in ("stroke_segments", "path_segments_batch"):
        monkeypatch.setattr(stroke_kernels, name,
                            counting(name, getattr(stroke_kernels, name)))
    runs, alone = both_ways(svg, monkeypatch, width=200)        # (strokes 2 px wide)
    assert runs == alone
    assert len(runs[-1]) == 600          # a fill and a stroke per shape
    assert calls == {"stroke": 300, "stroke_segments": 2 + 300,
                     "path_segments_batch": 2 + 300}


def test_run_of_unstyled_curved_paths_is_one_stroker_call(monkeypatch):
    """A run of paths that specify no style (Builder._path_run: map data), 120 with curves
    and 80 of lines only among them, under a stroke 3 px wide: the curved ones' outlines
    from one call of the curve stroker, the others' from one call of the lines stroker, no
    stroke() per path; the same nodes as element() makes of each."""
    rng = random.Random(4)
    paths = []
    for k in range(200):
        x, y = rng.uniform(0, 90), rng.uniform(0, 90)
        paths.append(f'<path d="M{x:.1f},{y:.1f}l5,-3 4,6z"/>' if k % 5 < 2 else
                     f'<path d="M{x:.1f},{y:.1f}c5,-3 10,2 12,8s-4,9 -10,7"/>')
    svg = (f'<svg {NS} width="100" height="100"><g fill="none" stroke="navy" '
           f'stroke-width="1.5" stroke-linecap="round">{"".join(paths)}</g></svg>')
    calls = {"stroke": 0, "stroke_segments": 0, "stroke_lines_batch": 0}

    def counting(name, f):
        def wrapped(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return wrapped
    monkeypatch.setattr(Builder, "stroke", counting("stroke", Builder.stroke))
    for name in ("stroke_segments", "stroke_lines_batch"):
        monkeypatch.setattr(stroke_kernels, name,
                            counting(name, getattr(stroke_kernels, name)))
    runs, alone = both_ways(svg, monkeypatch, width=200)
    assert runs == alone
    assert len(runs[-1]) == 200
    # (the second build: stroke() per path, stroke_lines is stroke_lines_batch for one path)
    assert calls == {"stroke": 200, "stroke_segments": 1 + 120, "stroke_lines_batch": 1 + 80}
