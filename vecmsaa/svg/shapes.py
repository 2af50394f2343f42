"""Basic shapes (rect, circle, ellipse, line, polyline, polygon) → paths in user units."""
from __future__ import annotations

import numpy as np

from ..scene.path import CLOSE, CONIC, MOVE, Path, rect_path
from .units import parse_number, parse_number_prefix

#: the weight of a quarter-ellipse conic, cos 45°
QUARTER_W = 0.7071067811865476
#: ellipse_path's verbs: a moveto, four quarter conics, a close
ELLIPSE_VERBS = np.array((MOVE, CONIC, CONIC, CONIC, CONIC, CLOSE), np.uint8)
#: Path.conicTo's λ = w / (1 + w) for QUARTER_W, and its (1 − λ) / 2
_K = QUARTER_W / (1.0 + QUARTER_W)
_A = (1.0 - _K) * 0.5


def ellipse_path(cx, cy, rx, ry) -> Path:
    """Four exact quarter-ellipse conics (control points at the bounding box's corners),
    from (cx + rx, cy) through (cx, cy + ry) round, closed: what the pen's moveTo, four
    conicTo(corner, end, QUARTER_W) and closePath record, made as arrays."""
    return Path._of_arrays(ELLIPSE_VERBS, np.array(ellipse_points(cx, cy, rx, ry), np.float64))


def ellipse_points(cx, cy, rx, ry):
    """ellipse_path's 13 points as (x, y) pairs: the moveto, then each quarter conic's
    control point, its point at t = ½ (Path.conicTo's, the same operations in the same
    order) and its end. Of numbers for one ellipse, of arrays for many (element by element
    the same operations: svg.builder makes a run's circles and ellipses so)."""
    k, a = _K, _A
    xr, xl, yb, yt = cx + rx, cx - rx, cy + ry, cy - ry
    return ((xr, cy),
            (xr, yb), (a * (xr + cx) + k * xr, a * (cy + yb) + k * yb), (cx, yb),
            (xl, yb), (a * (cx + xl) + k * xl, a * (yb + cy) + k * yb), (xl, cy),
            (xl, yt), (a * (xl + cx) + k * xl, a * (cy + yt) + k * yt), (cx, yt),
            (xr, yt), (a * (cx + xr) + k * xr, a * (yt + cy) + k * yt), (xr, cy))


def rounded_rect_path(x, y, w, h, rx, ry) -> Path:
    if rx <= 0:
        return rect_path(x, y, w, h)
    p = Path()
    k = QUARTER_W
    # x + (w − rx), not x + w − rx: with rx clamped to w/2 the sides' lines must have exactly
    # zero length; a last-bit reversal would be a U-turn, which miter-clip extends
    x2, y2 = x + (w - rx), y + (h - ry)
    if ry <= 0:
        # SVG 2's rect path with corner arcs of zero height, each a straight line (an arc
        # with a zero radius is a line): the rectangle's outline, but the rounded path's
        # vertices (markers) and start at x + rx (dashes), as in resvg. (SVG 2 skips the
        # arcs, which leaves its steps' lines off the rectangle: no reading of its own.)
        p.moveTo((x + rx, y))
        for q in ((x2, y), (x + w, y), (x + w, y + h), (x2, y + h), (x + rx, y + h),
                  (x, y + h), (x, y), (x + rx, y)):
            p.lineTo(q)
        p.closePath()
        return p
    p.moveTo((x + rx, y))
    p.lineTo((x2, y))
    p.conicTo((x + w, y), (x + w, y + ry), k)
    p.lineTo((x + w, y2))
    p.conicTo((x + w, y + h), (x2, y + h), k)
    p.lineTo((x + rx, y + h))
    p.conicTo((x, y + h), (x, y2), k)
    p.lineTo((x, y + ry))
    p.conicTo((x, y), (x + rx, y), k)
    p.closePath()
    return p


def author_path_length(el):
    """The element's ``pathLength`` (SVG 2 paths §"The pathLength attribute": the author's
    length of the path, which distances along it are scaled by): a number ≥ 0, or None when
    it is absent or in error (not a number, or negative), and nothing is scaled."""
    v = parse_number(el.attrs.get("pathLength"))
    return v if v is not None and v >= 0 else None


#: the lengths of a <rect>'s geometry, (attribute, axis, default), in rect_params' order
RECT_LENGTHS = (("x", "x", 0.0), ("y", "y", 0.0), ("width", "x", None), ("height", "y", None),
                ("rx", "x", None), ("ry", "y", None))
#: those of a <circle>'s, (cx, cy, r)
CIRCLE_LENGTHS = (("cx", "x", 0.0), ("cy", "y", 0.0), ("r", "xy", 0.0))


def _rect_params(length):
    """(x, y, width, height, rx, ry) of a <rect>, radii clamped; None when it renders nothing.
    ``length(name, axis, default)`` as for shape_path."""
    return rect_params(*[length(*spec) for spec in RECT_LENGTHS])


def rect_params(x, y, w, h, rx, ry):
    """_rect_params of a <rect>'s lengths (RECT_LENGTHS, None where absent or not read)."""
    if w is None or h is None or w <= 0 or h <= 0:
        return None
    if rx is not None and rx < 0:
        rx = None
    if ry is not None and ry < 0:
        ry = None
    if rx is None and ry is None:
        rx = ry = 0.0
    elif rx is None:
        rx = ry
    elif ry is None:
        ry = rx
    return x, y, w, h, min(rx, w / 2), min(ry, h / 2)


def _ellipse_params(tag, length):
    """(cx, cy, rx, ry) of a <circle> or <ellipse>; None when it renders nothing."""
    if tag == "circle":
        cx, cy, r = [length(*spec) for spec in CIRCLE_LENGTHS]
        return None if r <= 0 else (cx, cy, r, r)
    rx, ry = length("rx", "x", None), length("ry", "y", None)
    # negative or missing radii mean "auto": take the other one (SVG 2)
    rx = None if rx is not None and rx < 0 else rx
    ry = None if ry is not None and ry < 0 else ry
    if rx is None and ry is None:
        return None
    rx = ry if rx is None else rx
    ry = rx if ry is None else ry
    if rx <= 0 or ry <= 0:
        return None
    return length("cx", "x", 0.0), length("cy", "y", 0.0), rx, ry


def shape_box(el, length):
    """The object bounding box of a rect, circle or ellipse from its own parameters (the
    geometry its outline is made from: exact, without making the outline), None when it
    renders nothing; False for other elements."""
    tag = el.tag
    if tag == "rect":
        r = _rect_params(length)
        return None if r is None else (r[0], r[1], r[0] + r[2], r[1] + r[3])
    if tag == "circle" or tag == "ellipse":
        e = _ellipse_params(tag, length)
        if e is None:
            return None
        cx, cy, rx, ry = e
        return cx - rx, cy - ry, cx + rx, cy + ry
    return False


def shape_path(el, length):
    """Path of a basic shape element in its user space, or None when it renders nothing.

    ``length(name, axis, default)`` resolves an attribute to user units (axis: x, y or xy).
    """
    tag = el.tag
    if tag == "rect":
        r = _rect_params(length)
        return None if r is None else rounded_rect_path(*r)
    if tag == "circle" or tag == "ellipse":
        e = _ellipse_params(tag, length)
        return None if e is None else ellipse_path(*e)
    if tag == "line":
        p = Path()
        p.moveTo((length("x1", "x", 0.0), length("y1", "y", 0.0)))
        p.lineTo((length("x2", "x", 0.0), length("y2", "y", 0.0)))
        p.endPath()
        return p
    if tag in ("polyline", "polygon"):
        nums = parse_number_prefix(el.get("points", ""))
        if len(nums) % 2:
            nums = nums[:-1]
        if len(nums) < 4:
            return None
        p = Path()
        p.moveTo((nums[0], nums[1]))
        for i in range(2, len(nums), 2):
            p.lineTo((nums[i], nums[i + 1]))
        if tag == "polygon":
            p.closePath()
        else:
            p.endPath()
        return p
    return None
