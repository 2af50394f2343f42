"""Outlines: one path type for every source, filled through the fontTools pen protocol.

A :class:`Path` is a pen (``moveTo``, ``lineTo``, ``qCurveTo``, ``curveTo``, ``closePath``,
``endPath``, and ``conicTo`` beside the protocol) that records flat arrays: ``verbs`` (one byte
per segment) and ``points`` (float64, N x 2). SVG paths, glyph outlines and stroke outlines all
arrive here, so everything after this module sees one representation.

A CONIC is a rational quadratic Bézier (b0, b1, b2) with weight w on b1, the exact form of an
elliptical arc (w = cos(θ/2) for an arc of θ ≤ 90°). It is stored as three points: b1, the
curve's point at t = ½ and b2. The weight is in where that midpoint lies on the line from the
chord's midpoint to b1 (:func:`conic_weight`), a ratio that affine maps keep, so transforming
the points transforms the conic and nothing else needs to know. Consumers that take only
lines and Béziers (strokes, dashes, markers, pens) use :meth:`Path.without_conics`.
"""
from __future__ import annotations

import numpy as np

from .transform import IDENTITY, apply

MOVE, LINE, QUAD, CUBIC, CLOSE, CONIC = 0, 1, 2, 3, 4, 5
#: how many points each verb consumes
VERB_POINTS = (1, 1, 2, 3, 0, 3)

_NOT_DRAWING = bytes((MOVE, CLOSE))
#: conics_as_cubics' ``keep`` that keeps no conic
_KEEP_NONE = np.zeros(0, np.bool_)


class Path:
    """A pen that records an outline as flat verb and point arrays.

    The pen protocol is fontTools' (``fontTools.pens.basePen.BasePen``), written out here for
    its common calls so that a render without text does not import fontTools (≈ 8 ms of
    every start); what only glyph outlines use — qCurveTo/curveTo with several off-curve
    points (TrueType implied on-curve points, super-Béziers) and components — goes to
    fontTools' own decomposition, imported then. The recorded segments are always single
    lines, quadratics, cubics and conics.
    """

    # The state of a path made from arrays, as class attributes: such a path (tens of
    # thousands on map data) then sets only ``_arrays`` (and ``_shared``) of its own.
    glyphSet = None
    _current = None             # the pen's current point
    _start = None               # the open subpath's first point (current after closePath);
                                # None: not recorded (a path from lists), found when needed
    _verbs = None
    _pts = None
    _arrays = None
    _open = False
    _shared = None

    def __init__(self, glyphSet=None):
        self.glyphSet = glyphSet    # where addComponent finds component glyphs
        # Recorded as Python lists while drawing (cheap appends) and as arrays once read;
        # a path built from arrays keeps only those until someone draws into it again.
        self._verbs: list[int] | None = []
        self._pts: list[tuple[float, float]] | None = []
        self._arrays = None
        self._open = False
        self._shared = None     # (SharedPoints, start, end) when the points are a slice of them

    # -- the pen protocol ------------------------------------------------------------------
    def moveTo(self, pt):
        self._thaw()
        self._verbs.append(MOVE)
        self._pts.append(pt)
        self._open = True
        self._current = self._start = pt

    def lineTo(self, pt):
        self._implicit_move()
        self._verbs.append(LINE)
        self._pts.append(pt)
        self._current = pt

    def qCurveTo(self, *points):
        if len(points) == 2 and points[1] is not None:
            self._implicit_move()
            self._verbs.append(QUAD)
            self._pts.extend(points)
            self._current = points[1]
        elif len(points) == 1:
            self.lineTo(points[0])
        else:       # a string of off-curve points, or a contour of nothing else
            from fontTools.pens.basePen import decomposeQuadraticSegment
            if points[-1] is None:      # (its on-curve start is implied between last and first)
                start = (0.5 * (points[-2][0] + points[0][0]), 0.5 * (points[-2][1] + points[0][1]))
                self.moveTo(start)
                points = points[:-1] + (start,)
            for pt1, pt2 in decomposeQuadraticSegment(points):
                self.qCurveTo(pt1, pt2)

    def curveTo(self, *points):
        if len(points) == 3:
            self._implicit_move()
            self._verbs.append(CUBIC)
            self._pts.extend(points)
            self._current = points[2]
        elif len(points) > 3:       # a super-Bézier
            from fontTools.pens.basePen import decomposeSuperBezierSegment
            for pt1, pt2, pt3 in decomposeSuperBezierSegment(points):
                self.curveTo(pt1, pt2, pt3)
        else:
            self.qCurveTo(*points)

    def conicTo(self, pt1, pt2, w):
        """A rational quadratic from the current point through control pt1 (weight w > 0) to
        pt2 (Skia's conicTo)."""
        self._implicit_move()
        (x0, y0), (x1, y1), (x2, y2) = self._current, pt1, pt2
        k = w / (1.0 + w)
        mid = ((1.0 - k) * 0.5 * (x0 + x2) + k * x1, (1.0 - k) * 0.5 * (y0 + y2) + k * y1)
        self._verbs.append(CONIC)
        self._pts.extend((pt1, mid, pt2))
        self._current = pt2

    def closePath(self):
        self._thaw()
        if self._open:
            self._verbs.append(CLOSE)
            # the current point is the subpath's start, as after SVG's and PostScript's closepath
            self._current = self._start if self._start is not None else self._subpath_start()
        self._open = False

    def _subpath_start(self):
        """The point of the last moveTo recorded (None without one)."""
        i = len(self._pts)
        for v in reversed(self._verbs):
            i -= VERB_POINTS[v]
            if v == MOVE:
                return self._pts[i]
        return None

    def endPath(self):
        self._thaw()
        self._open = False
        self._current = self._start = None

    def addComponent(self, glyphName, transformation):
        """Draw the component glyph from ``glyphSet`` transformed (a missing one is skipped,
        as fontTools' pens do by default)."""
        from fontTools.pens.transformPen import TransformPen
        try:
            glyph = self.glyphSet[glyphName]
        except (KeyError, TypeError):
            return
        glyph.draw(TransformPen(self, transformation))

    def _implicit_move(self):
        self._thaw()
        if not self._open:
            # A drawing command after closePath starts a subpath at the closed one's start
            # (SVG's rule); one with no point drawn before starts at the origin.
            cur = self._current or (0.0, 0.0)
            self._verbs.append(MOVE)
            self._pts.append(cur)
            self._open = True
            self._current = self._start = cur

    def _thaw(self):
        """Make the lists current before appending; the arrays go stale. A path made from
        arrays gets its pen state (open subpath, current point) here, when first drawn into:
        most never are."""
        if self._verbs is None:
            v, p = self._arrays
            self._verbs = v.tolist()
            self._pts = list(map(tuple, p.tolist()))
            self._open = bool(self._verbs) and self._verbs[-1] != CLOSE
            if self._pts:
                self._current = self._pts[-1]
        self._arrays = None
        self._shared = None

    # -- recorded arrays -------------------------------------------------------------------
    @property
    def verbs(self) -> np.ndarray:
        return self._freeze()[0]

    @property
    def points(self) -> np.ndarray:
        return self._freeze()[1]

    def _freeze(self):
        if self._arrays is None:
            v = np.asarray(self._verbs, dtype=np.uint8)
            p = np.asarray(self._pts, dtype=np.float64).reshape(-1, 2)
            self._arrays = (v, p)
        return self._arrays

    @classmethod
    def _blank(cls) -> "Path":
        """An empty Path without running the pen constructors, whose keyword handling costs
        more than the rest of building a short path (map data makes tens of thousands)."""
        path = cls.__new__(cls)
        path.__dict__.update(_BLANK_STATE)
        return path

    @classmethod
    def from_lists(cls, verbs: list, pts: list) -> "Path":
        """A Path that takes ownership of ready-made verb and (x, y)-tuple lists (the fast way
        for parsers and the stroker: no per-point pen calls, no array round trip)."""
        path = cls._blank()
        path._verbs = verbs
        path._pts = pts
        path._open = bool(verbs) and verbs[-1] != CLOSE
        if pts:
            path._current = pts[-1]
        return path

    @classmethod
    def from_arrays(cls, verbs, points) -> "Path":
        """A Path holding the given arrays as they are (no per-point Python objects)."""
        return cls._of_arrays(np.ascontiguousarray(verbs, dtype=np.uint8),
                              np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2))

    @classmethod
    def _of_arrays(cls, v, p) -> "Path":
        """from_arrays for arrays already in the stored form (contiguous uint8 verbs, float64
        points of shape (N, 2)): the conversions cost a third of a short path's wrapping."""
        path = cls.__new__(cls)
        path._arrays = (v, p)
        return path

    @classmethod
    def _of_shared(cls, v, shared: "SharedPoints", start: int, end: int) -> "Path":
        """A Path whose points are ``shared.points[start:end]`` (contiguous uint8 verbs): its
        transformed copies come from transforming the shared points together."""
        path = cls._of_arrays(v, shared.points[start:end])
        path._shared = (shared, start, end)
        return path

    def __len__(self):
        return len(self.verbs)

    def is_empty(self) -> bool:
        """No verb besides MOVE and CLOSE: nothing to draw. On the verb bytes, which costs far
        less than numpy calls on the short paths of maps."""
        return not self.verbs.tobytes().translate(None, _NOT_DRAWING)

    def transformed(self, m) -> "Path":
        if m == IDENTITY:
            return self
        v, p = self._freeze()
        if self._shared is not None:
            shared, start, end = self._shared
            return Path._of_arrays(v, shared.transformed(m, start, end))
        return Path._of_arrays(v, apply(m, p) if len(p) else p)

    def bounds(self):
        """Control-point bounds (x0, y0, x1, y1), or None for an empty path."""
        p = self.points
        if len(p) == 0:
            return None
        return (float(p[:, 0].min()), float(p[:, 1].min()),
                float(p[:, 0].max()), float(p[:, 1].max()))

    def without_conics(self) -> "Path":
        """This path with every conic replaced by the cubic that approximates it (the same one
        the arc code made before conics: handles at 4w / (3(1 + w)) of the way to b1, which is
        4/3 tan(θ/4) for a circular arc of θ), for consumers that take only Béziers."""
        v, p = self._freeze()
        if CONIC not in v.tobytes():
            return self
        from .conics import conics_as_cubics     # (conics.py imports this module)
        return Path._of_arrays(*conics_as_cubics(v, p, _KEEP_NONE, 0.0, 1))

    def draw(self, pen):
        """Replay into another pen (fontTools protocol; conics arrive as cubics)."""
        v, p = self.without_conics()._freeze()
        i = 0
        open_ = False
        for verb in v:
            n = VERB_POINTS[verb]
            pts = [tuple(q) for q in p[i:i + n]]
            i += n
            if verb == MOVE:
                if open_:
                    pen.endPath()
                pen.moveTo(pts[0])
                open_ = True
            elif verb == LINE:
                pen.lineTo(pts[0])
            elif verb == QUAD:
                pen.qCurveTo(*pts)
            elif verb == CUBIC:
                pen.curveTo(*pts)
            else:
                pen.closePath()
                open_ = False
        if open_:
            pen.endPath()

    def extend(self, other: "Path"):
        """Append all subpaths of another path."""
        v, p = other._freeze()
        if not len(v):
            return
        self._thaw()
        self._verbs.extend(v.tolist())
        self._pts.extend(map(tuple, p.tolist()))
        self._open = v[-1] != CLOSE
        self._current = tuple(p[-1].tolist()) if len(p) else None
        self._start = None

    def __repr__(self):
        return f"Path({len(self)} segments)"


class SharedPoints:
    """The points of many paths in one (N, 2) float64 array (a document's path data), which
    they are slices of. A matrix that many of them are transformed by is applied to all the
    points at once: one kernel call costs what a few thousand points do, and maps transform
    tens of thousands of short paths by the same matrix. Until a matrix has cost, in calls
    and points, as much as transforming everything, its paths are transformed one by one, so
    the total is at most twice that of transforming each path alone."""

    #: the cost of one kernel call, in points transformed
    CALL_COST = 2000

    def __init__(self, points):
        self.points = points
        self._spent = {}        # matrix -> cost of transforming its paths one by one so far
        self._all = {}          # matrix -> all the points transformed by it

    def transformed(self, m, start, end):
        """``apply(m, self.points[start:end])``, from the whole array when m has earned it."""
        done = self._all.get(m)
        if done is None:
            spent = self._spent.get(m, 0) + self.CALL_COST + (end - start)
            if spent < len(self.points):
                self._spent[m] = spent
                return apply(m, self.points[start:end]) if end > start else \
                    self.points[start:end]
            done = self._all[m] = apply(m, self.points)
        return done[start:end]

    def all_transformed(self, m, calls):
        """``apply(m, self.points)`` when transforming ``calls`` more paths by m one by one
        would cost at least that (as transformed() counts), else None."""
        done = self._all.get(m)
        if done is None and self._spent.get(m, 0) + calls * self.CALL_COST >= len(self.points):
            done = self._all[m] = apply(m, self.points)
        return done


def conic_weight(b0, b1, mid, b2):
    """The weights of conics (b0, b1, b2) given their points at t = ½ ((n, 2) arrays each).

    The midpoint is (1 − λ)·c + λ·b1 with c the chord's midpoint and λ = w / (1 + w); λ is a
    ratio of lengths on one line, which affine maps keep. Clamped to (0, 1]: an arc of ≤ 90°
    has w ≥ cos 45°, and rounding must not turn a tiny arc's w ≈ 1 into a hyperbola."""
    c = 0.5 * (b0 + b2)
    d = b1 - c
    dd = (d * d).sum(axis=-1)
    lam = np.divide(((mid - c) * d).sum(axis=-1), dd, out=np.zeros_like(dd), where=dd > 0)
    lam = np.clip(lam, 1e-12, 0.5)
    return lam / (1.0 - lam)


def rect_path(x, y, w, h) -> Path:
    """The rectangle's outline, corners from (x, y) clockwise (y down), closed. Made as
    arrays: the pen's five calls cost more than the rest of a filtered or clipped element's
    region, clip rectangle or bounding box (thousands of markers make one each)."""
    return Path._of_arrays(_RECT_VERBS, np.array(rect_corners(x, y, w, h), np.float64))


def rect_corners(x, y, w, h):
    """rect_path's points as (x, y) pairs: of numbers for one rectangle, of arrays for many
    (the same operations element by element: svg.builder makes a run's rectangles so)."""
    r, b = x + w, y + h
    return (x, y), (r, y), (r, b), (x, b)


#: rect_path's verbs, shared by its paths (a Path's arrays are not written to: drawing into
#: a path made from arrays copies them into lists first)
_RECT_VERBS = np.array((MOVE, LINE, LINE, LINE, CLOSE), np.uint8)


#: the attributes of a fresh Path (Path._blank copies them; the lists are replaced there)
_BLANK_STATE = vars(Path())
