"""SVG path data parsing, checked against svgpathtools (an independent parser) and the SVG spec."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from vecmsaa.scene.path import CLOSE, CONIC, LINE, MOVE, VERB_POINTS
from vecmsaa.svg.pathdata import arc_to_cubics, parse_path_data, parse_path_data_with_commands

svgpathtools = pytest.importorskip("svgpathtools")


# -- helpers -------------------------------------------------------------------------------

def segments(path):
    """Drawn segments as lists of control points (complex), CLOSE as a line back to the start;
    zero-length lines dropped (svgpathtools and the SVG model disagree about keeping them)."""
    out = []
    i = 0
    cur = start = None
    for verb in path.verbs:
        n = VERB_POINTS[verb]
        pts = [complex(x, y) for x, y in path.points[i:i + n]]
        i += n
        if verb == MOVE:
            cur = start = pts[0]
            continue
        if verb == CLOSE:
            pts = [start]
        seg = [cur] + pts if verb != CONIC else Conic([cur] + pts)
        if not (verb in (LINE, CLOSE) and seg[0] == seg[1]):
            out.append(seg)
        cur = seg[-1]
    return out


class Conic(list):
    """(b0, b1, b2) of a stored conic, from its (b1, point at t = ½, b2): the weight from where
    that midpoint lies between the chord's midpoint and b1 (λ = w / (1 + w))."""

    def __init__(self, pts):
        b0, b1, mid, b2 = pts
        c = (b0 + b2) / 2
        lam = ((mid - c) / (b1 - c)).real if b1 != c else 0.0
        super().__init__([b0, b1, b2])
        self.w = lam / (1 - lam)

    def point(self, t):
        b0, b1, b2 = self
        a, b, c = (1 - t) ** 2, 2 * self.w * t * (1 - t), t * t
        return (a * b0 + b * b1 + c * b2) / (a + b + c)


def bezier_point(ctrl, t):
    if isinstance(ctrl, Conic):
        return ctrl.point(t)
    while len(ctrl) > 1:
        ctrl = [a + (b - a) * t for a, b in zip(ctrl, ctrl[1:])]
    return ctrl[0]


def reference_segments(d):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            ref = svgpathtools.parse_path(d)
        except AssertionError:
            # svgpathtools refuses an arc that ends where it starts (SVG F.5 omits it:
            # test_arc_to_its_own_start_draws_nothing)
            assume(False)
    return [s for s in ref if not (isinstance(s, svgpathtools.Line) and s.start == s.end)]


# -- random paths against svgpathtools -----------------------------------------------------

coord = st.integers(-2000, 2000).map(lambda v: v / 8)
radius = st.integers(1, 800).map(lambda v: v / 4)


def _fmt(v, compact):
    s = repr(float(v))
    if s.endswith(".0"):
        s = s[:-2]
    if compact and s.startswith("0."):
        s = s[1:]
    elif compact and s.startswith("-0."):
        s = "-" + s[2:]
    return s


@st.composite
def path_commands(draw):
    """(compact d for our parser, plainly spaced d for the reference parser)."""
    n = draw(st.integers(1, 12))
    cmds = [("M", [draw(coord), draw(coord)])]
    for _ in range(n):
        letter = draw(st.sampled_from("LHVCSQTAZ"))
        reps = draw(st.integers(1, 3)) if letter != "Z" else 1
        args = []
        for _ in range(reps):
            if letter in "LT":
                args += [draw(coord), draw(coord)]
            elif letter in "HV":
                args += [draw(coord)]
            elif letter == "C":
                args += [draw(coord) for _ in range(6)]
            elif letter in "SQ":
                args += [draw(coord) for _ in range(4)]
            elif letter == "A":
                args += [draw(radius), draw(radius), draw(st.integers(-360, 360)),
                         draw(st.integers(0, 1)), draw(st.integers(0, 1)), draw(coord), draw(coord)]
        if draw(st.booleans()):
            letter = letter.lower()
        cmds.append((letter, args))
    compact_parts, plain_parts = [], []
    for letter, args in cmds:
        compact = letter + draw(st.sampled_from(["", " ", "\n"]))
        prev, prev_is_flag = None, False
        for j, v in enumerate(args):
            s = _fmt(v, True)
            is_flag = letter in "Aa" and j % 7 in (3, 4)
            glue_ok = prev is not None and (s.startswith("-") or (s.startswith(".") and ("." in prev))
                                            or (prev in "01" and prev_is_flag))
            sep = draw(st.sampled_from(["", " ", ","])) if glue_ok else \
                (draw(st.sampled_from([" ", ",", " ,\t"])) if prev is not None else "")
            compact += sep + s
            prev, prev_is_flag = s, is_flag
        compact_parts.append(compact)
        plain_parts.append(letter + " " + " ".join(_fmt(v, False) for v in args))
    return " ".join(compact_parts), " ".join(plain_parts)


def _points_close(a, b, tol):
    return abs(a - b) <= tol * (1 + abs(a))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(path_commands())
def test_random_paths_match_svgpathtools(pair):
    compact, plain = pair
    ours = segments(parse_path_data(compact))
    ref = reference_segments(plain)
    # our arcs are several cubics; walk both lists, consuming our pieces per reference arc
    i = 0
    for seg in ref:
        if isinstance(seg, svgpathtools.Arc) and seg.start == seg.end:
            continue  # SVG F.5: identical endpoints omit the arc (svgpathtools keeps it)
        if isinstance(seg, svgpathtools.Arc):
            pieces = []
            while i < len(ours) and (not pieces or not _points_close(pieces[-1][-1], seg.end, 1e-9)):
                pieces.append(ours[i])
                i += 1
            assert pieces and _points_close(pieces[0][0], seg.start, 1e-9)
            assert _points_close(pieces[-1][-1], seg.end, 1e-9)
            assert len(pieces) <= 4  # at most 90° per piece
            # every sampled point lies on the reference ellipse, and the pieces cover the arc
            c, rot = seg.center, np.exp(-1j * math.radians(seg.rotation))
            r = max(seg.radius.real, seg.radius.imag)
            for piece in pieces:
                for t in np.linspace(0, 1, 9):
                    u = (bezier_point(piece, t) - c) * rot
                    # exactly (conics), not within a cubic's 3e-4 of the ellipse
                    assert abs(math.hypot(u.real / seg.radius.real, u.imag / seg.radius.imag) - 1) < 1e-6
            ref_samples = [seg.point(t) for t in np.linspace(0, 1, 9)]
            ours_dense = [bezier_point(p, t) for p in pieces for t in np.linspace(0, 1, 200)]
            for q in ref_samples:
                assert min(abs(q - o) for o in ours_dense) < 0.02 * r + 1e-9
            continue
        assert i < len(ours), f"missing segment {seg}"
        mine = ours[i]
        i += 1
        for t in (0.0, 0.3, 0.5, 0.8, 1.0):
            assert _points_close(bezier_point(mine, t), seg.point(t), 1e-9), (compact, plain)
    assert i == len(ours)


def test_arc_to_its_own_start_draws_nothing():
    assert segments(parse_path_data("M0 0 A.25.25 0 000 0")) == []
    assert segments(parse_path_data("M1 1 A5 5 0 0 1 1 1 L2 2")) == [[1 + 1j, 2 + 2j]]


# -- number and flag syntax ----------------------------------------------------------------

@pytest.mark.parametrize("d, expected", [
    ("M.5.5-1-2", [(0.5, 0.5), (-1, -2)]),
    ("M1e-3,2E2 3e+1-4", [(0.001, 200), (30, -4)]),
    ("M 1. 2. L 3.e1 4", [(1, 2), (30, 4)]),
    ("m1 1 2 2", [(1, 1), (3, 3)]),
    ("M0 0\n\t,1 1", [(0, 0), (1, 1)]),
])
def test_number_syntax(d, expected):
    assert parse_path_data(d).points.tolist() == [list(map(float, p)) for p in expected]


def test_compact_arc_flags():
    a = parse_path_data("M0 0a10 10 0 1100 10")
    b = parse_path_data("M0 0 a 10 10 0 1 1 0 10")
    np.testing.assert_array_equal(a.points, b.points)
    assert a.verbs.tolist() == b.verbs.tolist()


def test_smooth_reflection_without_previous_curve_uses_current_point():
    # S after a line: first control point is the current point (SVG 9.3.6)
    p = parse_path_data("M0 0 L 10 0 S 20 10 30 0")
    assert p.points[2].tolist() == [10.0, 0.0]
    # T after a cubic (not a quadratic): control point is the current point
    p = parse_path_data("M0 0 C 1 1 2 2 3 0 T 10 0")
    assert p.points[4].tolist() == [3.0, 0.0]


def test_drawing_after_close_starts_at_subpath_start():
    p = parse_path_data("M 5 5 L 10 5 L 10 10 Z l 1 1")
    assert p.verbs.tolist() == [MOVE, LINE, LINE, CLOSE, MOVE, LINE]
    assert p.points[-2:].tolist() == [[5, 5], [6, 6]]


# -- arcs ----------------------------------------------------------------------------------

def test_arc_radii_scaled_up_when_too_small():
    # F.6.6: radii too small for the endpoints are scaled until the arc is a half ellipse
    p = parse_path_data("M0 0 A 1 1 0 0 1 10 0")
    for seg in segments(p):
        for t in np.linspace(0, 1, 11):
            assert abs(abs(bezier_point(seg, t) - 5) - 5) < 5 * 3e-4


def test_arc_zero_radius_is_line_and_coincident_endpoints_a_zero_length_line():
    assert parse_path_data("M0 0 A 0 5 0 0 1 10 0").verbs.tolist() == [MOVE, LINE]
    # SVG omits an arc that ends where it starts; its command still leaves a zero-length
    # segment (for caps and markers), as a zero radius leaves the chord
    path = parse_path_data("M0 0 A 5 5 0 0 1 0 0 L 1 1")
    assert path.verbs.tolist() == [MOVE, LINE, LINE]
    assert path.points.tolist() == [[0, 0], [0, 0], [1, 1]]
    assert arc_to_cubics(3, 4, 5, 5, 0, False, True, 3, 4) is None


def test_arc_pieces_share_one_command_index():
    _, origin = parse_path_data_with_commands("M0 0 L 1 0 A 5 5 0 1 1 1 1 L 3 3")
    # verbs: MOVE, LINE, arc pieces..., LINE
    assert len(origin) > 4 and len(set(origin[2:-1].tolist())) == 1
    assert origin[1] < origin[2] < origin[-1]


def test_arc_to_cubics_full_sweep_pieces():
    pieces = arc_to_cubics(10, 0, 10, 10, 0, True, True, -10, 1e-9)
    assert 2 <= len(pieces) <= 4


# -- error recovery (SVG 2, 9.5.4: render up to the last complete segment) -------------------

@pytest.mark.parametrize("bad, good", [
    ("M 10 10 L 20 20 30", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 Z, L 5 5", "M 10 10 L 20 20 Z"),
    ("M 10 10 L 20 20,, L 5 5", "M 10 10 L 20 20"),
    ("M 10 10 L ,20 20", "M 10 10"),
    ("M 10 10 L 20 20 X 5 5", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 L", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 L 1 1e", "M 10 10 L 20 20"),
    ("M 10 10 C 1 2 3 4 5 6 7", "M 10 10 C 1 2 3 4 5 6"),
    ("M 10 10 A 5 5 0 2 0 20 20", "M 10 10"),
    ("M 10 10 A 5 5 0 1 0 20 20 5", "M 10 10 A 5 5 0 1 0 20 20"),
    ("M 10 10 Z 5", "M 10 10 Z"),
    ("M,10 10 L 20 20", ""),
    ("L 10 10", ""),
    ("x M 10 10", ""),
    ("M 10", ""),
    ("M 10 10 L 20 20 M", "M 10 10 L 20 20"),
    ("M 10 10 20 20 30", "M 10 10 20 20"),
])
def test_error_recovery_keeps_prefix(bad, good):
    assert_parses_as(bad, good)


def assert_parses_as(text, same_as):
    a, b = parse_path_data(text), parse_path_data(same_as)
    assert a.verbs.tolist() == b.verbs.tolist()
    np.testing.assert_array_equal(a.points, b.points)


def test_empty_and_whitespace():
    assert parse_path_data("").is_empty()
    assert parse_path_data("  \n ").is_empty()
    assert len(parse_path_data("none")) == 0


def test_a_long_digit_run_before_junk_parses_in_linear_time():
    # a single regex over the whole argument list backtracks exponentially here (fuzz find);
    # 2000 digits would take longer than the universe's age — the test finishes at once
    path = parse_path_data("M0 0L" + "1" * 2000 + "x")
    assert path.verbs.tolist() == [0]


def test_an_arc_after_an_infinite_coordinate_does_not_raise():
    assert parse_path_data("m0 1e999v 0a9 5 0 1 0 10 0").is_empty()


@pytest.mark.parametrize("bad, good", [
    ("M 10 10 L 20 20 L 30 1e400 Z", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 30 -1e999", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 A 1e400 5 0 0 1 30 30", "M 10 10 L 20 20"),
    ("M 10 10 L 20 20 L 30 1e-400", "M 10 10 L 20 20 L 30 0"),
])
def test_a_number_past_double_range_is_an_error(bad, good):
    # a number that does not fit a double is no number: the data is drawn up to the
    # command holding it, as after any error (SVG 2 path data error handling)
    assert_parses_as(bad, good)


@pytest.mark.parametrize("with_comma, without", [
    ("M 10 10, L 20 20", "M 10 10 L 20 20"),
    ("M10,10,L20,20,Z", "M10,10 L20,20 Z"),
    ("M 10 10 A 5 5 0 0 1 20 20 ,L 30 30", "M 10 10 A 5 5 0 0 1 20 20 L 30 30"),
    ("M 10 10 L 20 20,", "M 10 10 L 20 20"),
])
def test_a_comma_after_a_commands_last_number(with_comma, without):
    assert_parses_as(with_comma, without)


# -- the compiled reader: exact numbers, one call per document ------------------------------

@pytest.mark.parametrize("text", [
    "0.1", "-0", "1e22", "1e-22", "123456789012345", "0.000000000000000000001234",
    "1234567890123456789", "0.1000000000000000055511151231257827", "1e23", "4.9e-324",
    "1e-400", "1.7976931348623157e308", "9007199254740993", ".5e+3", "-7.e-2",
])
def test_numbers_are_the_doubles_python_reads(text):
    # Python's float is correctly rounded: the kernel's fast path and its fallback must agree
    path = parse_path_data(f"M {text} {text}")
    assert path.points.tobytes() == np.array([[float(text), float(text)]]).tobytes()


def test_a_batch_reads_every_path_as_alone():
    from vecmsaa.svg.pathdata import PathBatch
    texts = ["M0 0 L10 10 z", "", "M 1.23456789012345678 2 a5 5 0 1 1 10 10", "junk",
             "M.5.5-1-2 h3 v-4 Q 1 2 3 4 T 5 6 z m 1 1 l 2 2", "M 1e999 1 L 2 2",
             "M0 0 C 1 1 2 2 3 3 S 4 4 5 5"]
    batch = PathBatch(texts)
    for i, text in enumerate(texts):
        got, got_origin = batch.get(i)
        alone, origin = parse_path_data_with_commands(text)
        assert got.verbs.tolist() == alone.verbs.tolist()
        assert got.points.tobytes() == alone.points.tobytes()
        assert got_origin.tolist() == origin.tolist()
    # the long number came through Python's float, not the fast path
    assert batch.get(2)[0].points[0].tolist() == [1.23456789012345678, 2.0]


def test_paths_of_a_batch_transform_as_alone():
    # transformed one by one at first, then from the whole batch at once once a matrix has
    # been asked for often: the points must be a*x + c*y + e, b*x + d*y + f either way
    from vecmsaa.scene.path import SharedPoints
    from vecmsaa.svg.pathdata import PathBatch
    rng = np.random.default_rng(7)
    texts = ["M " + " ".join(f"{x:.3f},{y:.3f}" for x, y in rng.uniform(-50, 50, (n, 2)))
             for n in rng.integers(1, 40, 300)] + [""]
    batch = PathBatch(texts)
    assert len(batch.points.points) < 300 * SharedPoints.CALL_COST   # it does switch
    m = (0.5, 0.25, -0.75, 2.0, 3.0, -4.0)
    a, b, c, d, e, f = m
    for rep in range(2):
        for i, text in enumerate(texts):
            p = batch.get(i)[0]
            got = p.transformed(m)
            x, y = p.points[:, 0], p.points[:, 1]
            want = np.stack([a * x + c * y + e, b * x + d * y + f], axis=1)
            assert got.points.tobytes() == want.tobytes()
            assert got.verbs.tobytes() == p.verbs.tobytes()
    assert m in batch.points._all
    # drawing into a path detaches it from the batch
    p = batch.get(0)[0]
    p.lineTo((1.0, 2.0))
    assert p.transformed(m).points[-1].tolist() == [a + 2 * c + e, b + 2 * d + f]


def test_a_run_of_stroked_paths_draws_what_each_path_draws_alone():
    # sibling <path>s with no style of their own are built as a run (their polyline strokes
    # in one kernel call, curves, arcs and "M x y Z" dots through the stroker one by one); a
    # presentation attribute of its own sends each through the builder's general path
    from vecmsaa.api import render_svg_array
    paths = ["M 2 3 L 30 5 L 28 20", "M 5 25 C 10 5 25 40 35 30", "M 20 20 Z",
             "M 3 35 L 12 38 Z", "M 30 10 Q 38 2 38 18", "M 8 8 A 4 4 0 0 1 16 12",
             "M 36 36 L 37 37", "M 12 12 L 12 12"]

    def doc(own):
        body = "".join(f'<path d="{d}"{own}/>' for d in paths)
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40"><g '
                f'fill="none" stroke="#000" stroke-width="3" stroke-linecap="round">{body}'
                f'</g></svg>').encode()

    run = render_svg_array(doc(""), width=120)
    alone = render_svg_array(doc(' stroke-linejoin="miter"'), width=120)
    assert run[..., 3].any()
    assert np.array_equal(run, alone)


@pytest.mark.parametrize("paint", [
    'fill="#08f"', 'fill="#08f" stroke="#000" stroke-width="2"',
    'fill="#08f" stroke="#000" stroke-width="2" paint-order="stroke"',
    'fill="none" stroke="#000" stroke-width="3"'])
@pytest.mark.parametrize("width", [40, 120])
def test_a_filled_run_of_paths_draws_what_each_path_draws_alone(paint, width):
    # a run of sibling <path>s consecutive in the document's path data is built a stretch
    # at a time; the paths among them that need deciding alone (nothing drawn, a dot, a
    # lone line that fills nothing, a curve for the stroker, numbers read by Python's float)
    # and runs whose paths are not consecutive (a path inside a path) go through the general
    # code: the picture is that of each path built with a style of its own. At 40 px the
    # paths are in device space as they are, at 120 px mapped.
    from vecmsaa.api import render_svg_array
    paths = ["M 2 3 L 30 5 L 28 20 Z", "M 5 25 C 10 5 25 40 35 30", "", "M 20 20 Z",
             "M 3 35 L 12 38 L 9 30", "M 30 10 Q 38 2 38 18", "M 36 36 L 37 37",
             "M 8 8 A 4 4 0 0 1 16 12 Z", "M 1.00000000000000000001 1 L 10 1 L 10 6",
             "M 22 30 L 30 30 L 30 38 Z"]

    def doc(own, inner=""):
        body = "".join(f'<path d="{d}"{own}/>' for d in paths)
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40"><g '
                f'{paint}>{body}<path d="M 24 2 L 38 2 L 31 9 Z"{own}>{inner}</path>'
                f'{body}</g></svg>').encode()

    alone = render_svg_array(doc(' stroke-linejoin="miter"'), width=width)
    assert alone[..., 3].any()
    assert np.array_equal(render_svg_array(doc(""), width=width), alone)
    # a path inside a path (not drawn): the run's paths are not consecutive in the batch
    nested = render_svg_array(doc("", '<path d="M 0 0 L 40 40"/>'), width=width)
    assert np.array_equal(nested, alone)
