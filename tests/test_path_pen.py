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

    def _start(self):
        if not self.open:       # (Path starts a drawing command after a close at (0, 0))
            self.verbs.append(MOVE)
            self.points.append(self._getCurrentPoint() or (0.0, 0.0))
            self.open = True

    def _moveTo(self, pt):
        self.verbs.append(MOVE)
        self.points.append(pt)
        self.open = True

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
