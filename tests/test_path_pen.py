"""scene.path.Path as a fontTools pen: it writes the common calls out itself (so that a render
without text does not import fontTools), and must record what fontTools' own BasePen
decomposition gives for every call sequence: strings of quadratic off-curve points, contours
with no on-curve point, super-Béziers, components. The reference is a pen built on fontTools'
BasePen recording the same verbs."""
from __future__ import annotations

import os

import numpy as np
from fontTools.pens.basePen import BasePen
from fontTools.ttLib import TTFont
from hypothesis import given, settings
from hypothesis import strategies as st

from vecmsaa.scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, Path

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")


class ReferencePen(BasePen):
    """fontTools' BasePen, recording (verb, points) as Path stores them."""

    def __init__(self, glyphSet=None):
        super().__init__(glyphSet)
        self.verbs, self.points, self.open = [], [], False
        self.subpath_start = None

    def _start(self):
        # a drawing command without a moveTo: after a close at the closed subpath's start
        # (SVG's closepath), after an endPath or before anything at (0, 0)
        if not self.open:
            at = self._getCurrentPoint() or self.subpath_start or (0.0, 0.0)
            self._moveTo(at)

    def _moveTo(self, pt):
        self.verbs.append(MOVE)
        self.points.append(pt)
        self.open = True
        self.subpath_start = pt

    def _lineTo(self, pt):
        self._start()
        self.verbs.append(LINE)
        self.points.append(pt)

    def _qCurveToOne(self, pt1, pt2):
        self._start()
        self.verbs.append(QUAD)
        self.points += [pt1, pt2]

    def _curveToOne(self, pt1, pt2, pt3):
        self._start()
        self.verbs.append(CUBIC)
        self.points += [pt1, pt2, pt3]

    def _closePath(self):
        if self.open:
            self.verbs.append(CLOSE)
        self.open = False

    def _endPath(self):
        self.open = False
        self.subpath_start = None


def assert_same(path, ref):
    assert path.verbs.tolist() == ref.verbs
    np.testing.assert_array_equal(path.points, np.asarray(ref.points, float).reshape(-1, 2))


point = st.tuples(st.integers(-50, 50), st.integers(-50, 50)).map(
    lambda p: (p[0] / 4.0, p[1] / 4.0))
call = st.one_of(
    st.tuples(st.just("moveTo"), st.lists(point, min_size=1, max_size=1)),
    st.tuples(st.just("lineTo"), st.lists(point, min_size=1, max_size=1)),
    st.tuples(st.just("qCurveTo"), st.lists(point, min_size=1, max_size=6)),
    st.tuples(st.just("qCurveTo*"), st.lists(point, min_size=1, max_size=6)),  # no on-curve point
    st.tuples(st.just("curveTo"), st.lists(point, min_size=1, max_size=7)),
    st.tuples(st.just("closePath"), st.just([])),
    st.tuples(st.just("endPath"), st.just([])))


@settings(max_examples=300, deadline=None)
@given(st.lists(call, max_size=12))
def test_path_records_what_fonttools_basepen_decomposes(calls):
    path, ref = Path(), ReferencePen()
    for name, pts in calls:
        for pen in (path, ref):
            if name == "qCurveTo*":
                pen.qCurveTo(*pts, None)
            else:
                getattr(pen, name)(*pts)
    assert_same(path, ref)


def test_every_glyph_with_components_draws_as_through_fonttools():
    """Every glyph of a TrueType font (composites among them: accented letters) and of a
    CFF one, through their glyph sets, component transforms included."""
    composites = 0
    for name in ("NotoSans-Subset.ttf", "NotoSans-Subset-CFF.otf"):
        font = TTFont(os.path.join(FIXTURES, name))
        gs = font.getGlyphSet()
        for glyph in font.getGlyphOrder():
            path, ref = Path(glyphSet=gs), ReferencePen(gs)
            gs[glyph].draw(path)
            gs[glyph].draw(ref)
            assert_same(path, ref)
        if "glyf" in font:
            composites += sum(font["glyf"][g].isComposite() for g in font.getGlyphOrder())
    assert composites > 10


def _subpaths(path):
    """(verb, points) per recorded segment, points as tuples."""
    out, i = [], 0
    pts = [tuple(p) for p in path.points.tolist()]
    for v in path.verbs.tolist():
        n = (1, 1, 2, 3, 0, 3)[v]
        out.append((v, pts[i:i + n]))
        i += n
    return out


def test_drawing_after_closepath_starts_at_the_closed_subpaths_start():
    """SVG 2 §9.3.4 (closepath): after it, the current point is the subpath's initial point,
    and a drawing command without a moveto starts the next subpath there. The same holds for
    a conic (Path's own call), which had no current point to start from, and for a path built
    from lists, whose subpath start the pen did not see."""
    from vecmsaa.scene.path import CONIC
    for make in ("pen", "lists"):
        if make == "pen":
            p = Path()
            p.moveTo((1, 2)); p.lineTo((5, 2)); p.lineTo((5, 6))
        else:
            p = Path.from_lists([MOVE, LINE, LINE], [(1, 2), (5, 2), (5, 6)])
        p.closePath()
        p.conicTo((9, 9), (3, 7), 0.5)
        p.closePath()
        p.lineTo((0, 4))
        segs = _subpaths(p)
        assert segs[4] == (MOVE, [(1, 2)]), make
        assert segs[5][0] == CONIC and segs[5][1][-1] == (3, 7), make
        assert segs[7] == (MOVE, [(1, 2)]), make
        assert segs[8] == (LINE, [(0, 4)]), make
