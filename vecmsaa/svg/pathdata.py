"""SVG path data (the ``d`` attribute) → :class:`vecmsaa.scene.path.Path`.

The grammar is SVG 2's (section 9.3.9, BNF in SVG 1.1 F.6 / 8.3.9). Error handling follows
SVG 2 9.5.4: the path is rendered up to the last complete segment before the first error.
Arcs become cubic Béziers (at most 90° each) through the endpoint → centre conversion of
SVG 1.1 appendix F.6.5 with the radii correction of F.6.6.

Speed matters (OSM maps carry megabytes of path data), so the string is cut at command letters
with one regex split, and arguments written plainly (numbers between white space or single
commas) are converted by ``map(float, str.split())`` in C; only other spellings ("-1-2", ".5.5",
errors) and arcs (whose flags may be written without separators) go through the regex
scanners. Points are collected as one flat list of floats and verbs as bytes, which become the
Path's arrays without per-point Python objects.
"""
from __future__ import annotations

import math
import re
from itertools import accumulate

import numpy as np

from ..scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, Path

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
# comma-wsp between numbers is optional ("-1-2", ".5.5" are two numbers each)
_SEP = r"(?:[ \t\r\n\f]*,[ \t\r\n\f]*|[ \t\r\n\f]+)?"
_WSP = r"[ \t\r\n\f]*"
_COMMANDS = "MmLlHhVvCcSsQqTtAaZz"
_SPLIT = re.compile(r"([MmLlHhVvCcSsQqTtAaZz])")
_NUMBER_RE = re.compile(_NUMBER)
_LEADING_WSP = re.compile(_WSP)
_ARG_NUMBER = re.compile(f"{_SEP}({_NUMBER})")
_ARG_FLAG = re.compile(f"{_SEP}([01])")
# only characters that can occur in plainly written numbers and separators
_PLAIN_ARGS = re.compile(r"[0-9.eE+\-, \t\r\n\f]*")


#: numbers each command consumes per repetition
_ARITY = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "T": 2, "A": 7, "Z": 0}


def parse_path_data(d: str) -> Path:
    """The path described by an SVG ``d`` attribute (empty Path for an empty or invalid one)."""
    return _parse(d)[0]


def parse_path_data_with_commands(d: str):
    """Like :func:`parse_path_data`, plus, for every recorded verb, the index of the path
    command (counting implicit repetitions as their own commands) it came from.

    An arc becomes several cubics; this tells which verbs belong to one command. (SVG markers
    do not use it: resvg places mid markers between an arc's pieces too.)
    """
    path, origin = _parse(d)
    return path, np.asarray(origin, dtype=np.int64)


def _parse(d: str):
    """→ (Path, list of the command index of every verb)."""
    verbs = bytearray()
    pts: list[float] = []       # x0, y0, x1, y1, ...
    origin: list[int] = []
    parts = _SPLIT.split(d)
    # parts = [text before first command, cmd, args, cmd, args, ...]
    if parts[0].strip(" \t\r\n\f"):
        return _finish(verbs, pts, origin)
    cx = cy = 0.0               # current point
    sx = sy = 0.0               # start of the current subpath
    # control point that smooth curves reflect, and which kind of curve left it
    rx = ry = 0.0
    prev_kind = ""              # "C" after C/S, "Q" after Q/T, "" otherwise
    subpath_open = False        # a MOVE has been recorded for the current subpath
    command_index = 0
    first = True

    for k in range(1, len(parts), 2):
        letter = parts[k]
        args_text = parts[k + 1]
        upper = letter.upper()
        relative = letter != upper
        arity = _ARITY[upper]
        if first and upper != "M":
            break               # path data must begin with a moveto
        first = False

        if upper == "A":
            nums, ok = _scan_arcs(args_text)
        else:
            nums, ok, end = _scan_numbers(args_text)
            if not ok and nums and args_text[end:end + 1] in ("e", "E") and \
                    args_text[end - 1] not in " \t\r\n\f,":
                # "1e" is a broken number, not "1" followed by junk (as browsers read it)
                nums.pop()
        if arity == 0:
            nums_ok = not nums
            count = 0
        else:
            count = len(nums) // arity
            nums_ok = count > 0 and count * arity == len(nums)

        if upper == "Z":
            if subpath_open:
                verbs.append(CLOSE)
                origin.append(command_index)
                command_index += 1
            cx, cy = sx, sy
            subpath_open = False
            prev_kind = ""
            if not (ok and nums_ok):
                break
            continue

        if (upper == "L" and count > 0) or (upper == "M" and count > 1):
            # polylines dominate map data: handle a whole run of points at once
            start = 0
            if upper == "M":
                x, y = nums[0], nums[1]
                if relative:
                    x += cx
                    y += cy
                verbs.append(MOVE)
                pts += (x, y)
                origin.append(command_index)
                sx, sy = cx, cy = x, y
                subpath_open = True
                command_index += 1
                start = 1
            elif not subpath_open:
                verbs.append(MOVE)
                pts += (cx, cy)
                origin.append(command_index)
                subpath_open = True
            run = count - start
            if relative:
                xy = [0.0] * (2 * run)
                xy[0::2] = list(accumulate(nums[2 * start:2 * count:2], initial=cx))[1:]
                xy[1::2] = list(accumulate(nums[2 * start + 1:2 * count:2], initial=cy))[1:]
            else:
                xy = nums[2 * start:2 * count]
            pts += xy
            verbs += bytes((LINE,)) * run
            origin.extend(range(command_index, command_index + run))
            command_index += run
            cx, cy = xy[-2], xy[-1]
            prev_kind = ""
            if not (ok and nums_ok):
                break
            continue

        for i in range(0, count * arity, arity):
            if upper == "M":
                x, y = nums[i], nums[i + 1]
                if relative:
                    x += cx
                    y += cy
                if i == 0:
                    verbs.append(MOVE)
                    pts += (x, y)
                    origin.append(command_index)
                    sx, sy = x, y
                    subpath_open = True
                else:           # extra pairs after a moveto are implicit linetos
                    verbs.append(LINE)
                    pts += (x, y)
                    origin.append(command_index)
                cx, cy = x, y
                prev_kind = ""
                command_index += 1
                continue
            if not subpath_open:
                # a drawing command right after closepath starts a subpath at its start point
                verbs.append(MOVE)
                pts += (cx, cy)
                origin.append(command_index)
                subpath_open = True
            if upper == "L":
                x, y = nums[i], nums[i + 1]
                if relative:
                    x += cx
                    y += cy
                verbs.append(LINE)
                pts += (x, y)
                prev_kind = ""
            elif upper == "H":
                x = nums[i] + cx if relative else nums[i]
                y = cy
                verbs.append(LINE)
                pts += (x, y)
                prev_kind = ""
            elif upper == "V":
                x = cx
                y = nums[i] + cy if relative else nums[i]
                verbs.append(LINE)
                pts += (x, y)
                prev_kind = ""
            elif upper == "C" or upper == "S":
                if upper == "C":
                    x1, y1, x2, y2, x, y = nums[i:i + 6]
                    if relative:
                        x1 += cx
                        y1 += cy
                else:
                    x2, y2, x, y = nums[i:i + 4]
                    if prev_kind == "C":
                        x1, y1 = 2 * cx - rx, 2 * cy - ry
                    else:
                        x1, y1 = cx, cy
                if relative:
                    x2 += cx
                    y2 += cy
                    x += cx
                    y += cy
                verbs.append(CUBIC)
                pts += (x1, y1, x2, y2, x, y)
                rx, ry = x2, y2
                prev_kind = "C"
            elif upper == "Q" or upper == "T":
                if upper == "Q":
                    x1, y1, x, y = nums[i:i + 4]
                    if relative:
                        x1 += cx
                        y1 += cy
                else:
                    x, y = nums[i:i + 2]
                    if prev_kind == "Q":
                        x1, y1 = 2 * cx - rx, 2 * cy - ry
                    else:
                        x1, y1 = cx, cy
                if relative:
                    x += cx
                    y += cy
                verbs.append(QUAD)
                pts += (x1, y1, x, y)
                rx, ry = x1, y1
                prev_kind = "Q"
            else:               # A
                arx, ary, rotation, large, sweep, x, y = nums[i:i + 7]
                if relative:
                    x += cx
                    y += cy
                pieces = arc_to_cubics(cx, cy, arx, ary, rotation, large != 0.0, sweep != 0.0,
                                       x, y)
                if pieces is None:
                    verbs.append(LINE)
                    pts += (x, y)
                    origin.append(command_index)
                for (x1, y1), (x2, y2), (x3, y3) in pieces or ():
                    verbs.append(CUBIC)
                    pts += (x1, y1, x2, y2, x3, y3)
                    origin.append(command_index)
                cx, cy = x, y
                prev_kind = ""
                command_index += 1
                continue
            origin.append(command_index)
            cx, cy = x, y
            command_index += 1
        if not (ok and nums_ok):
            break
    return _finish(verbs, pts, origin)


def _finish(verbs, pts, origin):
    return (Path._of_arrays(np.frombuffer(verbs, dtype=np.uint8),
                            np.array(pts, dtype=np.float64).reshape(-1, 2)),
            origin)


def _scan_arcs(text: str):
    """Arguments of an arc command: (numbers, whether the whole text was valid).

    Flags are single characters '0'/'1' and need no separator ("a10 10 0 1100 10" is valid),
    so arcs cannot use the plain number regex.
    """
    nums: list[float] = []
    pos = 0
    end = len(text)
    # leading wsp only (no comma) before the first argument
    while pos < end and text[pos] in " \t\r\n\f":
        pos += 1
    field = 0
    while True:
        matcher = _ARG_FLAG if field in (3, 4) else _ARG_NUMBER
        m = matcher.match(text, pos)
        if m is None or (not nums and m.start(1) != pos):
            break
        nums.append(float(m.group(1)))
        pos = m.end()
        field = (field + 1) % 7
    rest = text[pos:]
    ok = not rest.strip(" \t\r\n\f")
    # a partial arc before the error is dropped by the caller (count * arity)
    return nums, ok


def _scan_numbers(text: str):
    """The numbers of one command's arguments, whether the whole text is valid (numbers with
    optional separators, white space around; no leading or trailing comma), and where valid
    input ends. Each number is matched once, greedily: linear time. (One regex for the whole
    argument list backtracks exponentially on a long digit run followed by junk, because
    adjacent numbers may split the run anywhere.)"""
    if _PLAIN_ARGS.fullmatch(text):
        # Over these characters float() accepts exactly one SVG number per token; commas
        # are valid when each lies between numbers (no empty piece around one).
        if "," not in text or all(p.strip(" \t\r\n\f") for p in text.split(",")):
            try:
                return list(map(float, text.replace(",", " ").split())), True, len(text)
            except ValueError:
                pass            # "-1-2", ".5.5", "1e": the scanner below sorts them out
    nums = []
    pos = _LEADING_WSP.match(text).end()
    m = _NUMBER_RE.match(text, pos)
    while m:
        nums.append(float(m.group(m.lastindex or 0)))
        pos = m.end()
        m = _ARG_NUMBER.match(text, pos)
    ok = _LEADING_WSP.match(text, pos).end() == len(text)
    return nums, ok, pos


def arc_to_cubics(x1, y1, rx, ry, phi_deg, large_arc, sweep, x2, y2):
    """An elliptical arc as cubic Bézier pieces ``[(c1, c2, end), ...]`` of at most 90° each.

    Returns None when the arc is a straight line (a zero radius), and [] when the endpoints
    coincide (SVG omits such an arc).
    """
    if x1 == x2 and y1 == y2:
        return []
    if not all(map(math.isfinite, (x1, y1, rx, ry, phi_deg, x2, y2))):
        return None  # an infinite coordinate (1e999): no arc to speak of, a straight line
    rx = abs(rx)
    ry = abs(ry)
    if rx == 0.0 or ry == 0.0:
        return None
    phi = math.radians(phi_deg % 360.0)
    cos_phi = math.cos(phi)
    sin_phi = math.sin(phi)
    # F.6.5 step 1: (x1', y1')
    dx2 = (x1 - x2) / 2.0
    dy2 = (y1 - y2) / 2.0
    x1p = cos_phi * dx2 + sin_phi * dy2
    y1p = -sin_phi * dx2 + cos_phi * dy2
    # Radii beyond 1e±150 of the half-chord would underflow or overflow when squared below:
    # such an arc is, to any precision we draw, its chord (as a zero radius is by the spec).
    half = max(abs(x1p), abs(y1p))
    if half == 0.0 or not 1e-150 < min(rx, ry) / half or max(rx, ry) / half > 1e150:
        return None
    # F.6.6: scale radii up when no ellipse reaches both endpoints
    lam = (x1p * x1p) / (rx * rx) + (y1p * y1p) / (ry * ry)
    if lam > 1.0:
        s = math.sqrt(lam)
        rx *= s
        ry *= s
    # step 2: centre (cx', cy')
    rx2, ry2 = rx * rx, ry * ry
    num = rx2 * ry2 - rx2 * y1p * y1p - ry2 * x1p * x1p
    den = rx2 * y1p * y1p + ry2 * x1p * x1p
    coef = math.sqrt(max(num, 0.0) / den) if den > 0 else 0.0
    if large_arc == sweep:
        coef = -coef
    cxp = coef * rx * y1p / ry
    cyp = -coef * ry * x1p / rx
    # step 3: centre (cx, cy)
    cx = cos_phi * cxp - sin_phi * cyp + (x1 + x2) / 2.0
    cy = sin_phi * cxp + cos_phi * cyp + (y1 + y2) / 2.0
    # step 4: start angle and sweep, measured on the unit circle
    ux, uy = (x1p - cxp) / rx, (y1p - cyp) / ry
    vx, vy = (-x1p - cxp) / rx, (-y1p - cyp) / ry
    theta1 = math.atan2(uy, ux)
    dtheta = math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)
    if not sweep and dtheta > 0:
        dtheta -= 2 * math.pi
    elif sweep and dtheta < 0:
        dtheta += 2 * math.pi
    n = max(1, int(math.ceil(abs(dtheta) / (math.pi / 2) - 1e-9)))
    delta = dtheta / n
    # handle length of a cubic approximating a unit circular arc of angle delta
    t = 4.0 / 3.0 * math.tan(delta / 4.0)
    pieces = []
    a = theta1
    cos_a, sin_a = math.cos(a), math.sin(a)
    for i in range(n):
        b = theta1 + (i + 1) * delta
        cos_b, sin_b = math.cos(b), math.sin(b)
        # unit-circle control points, then scale by radii, rotate by phi, translate
        unit = ((cos_a - t * sin_a, sin_a + t * cos_a),
                (cos_b + t * sin_b, sin_b - t * cos_b),
                (cos_b, sin_b))
        piece = []
        for ex, ey in unit:
            ex *= rx
            ey *= ry
            piece.append((cos_phi * ex - sin_phi * ey + cx, sin_phi * ex + cos_phi * ey + cy))
        if i == n - 1:
            piece[2] = (x2, y2)  # land exactly on the requested endpoint
        pieces.append(tuple(piece))
        cos_a, sin_a = cos_b, sin_b
    return pieces
