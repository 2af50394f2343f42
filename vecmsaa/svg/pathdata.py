"""SVG path data (the ``d`` attribute) → :class:`vecmsaa.scene.path.Path`.

The grammar is SVG 2's (section 9.3.9, BNF in SVG 1.1 F.6 / 8.3.9). Error handling follows
SVG 2 9.5.4: the path is rendered up to the last complete segment before the first error.
Arcs become conics (exact rational quadratics, at most 90° each) through the endpoint → centre conversion of
SVG 1.1 appendix F.6.5 with the radii correction of F.6.6.

Speed matters (OSM maps carry megabytes of path data, tens of thousands of paths), so one
compiled kernel reads the bytes of ``d`` and writes the verb, point and command arrays: no
Python objects per number or segment. Numbers are converted in the kernel when that is exact
(at most 15 significant digits and a decimal exponent within ±22: one correctly rounded
multiplication or division of two exact doubles, as in Clinger's fast path); a path with any
other number is read again with its numbers converted by Python's ``float`` (correctly rounded),
so the result is the same double for every spelling.
"""
from __future__ import annotations

import math

import numpy as np
from ..jit import njit

from ..scene.path import CLOSE, CONIC, CUBIC, LINE, MOVE, QUAD, Path, SharedPoints

# byte codes
_PLUS, _MINUS, _DOT, _COMMA, _ZERO, _ONE, _NINE = 43, 45, 46, 44, 48, 49, 57
_E_LOWER, _E_UPPER = 101, 69
#: command letters in the order of their codes below: upper case | 32 is lower case
_LETTERS = b"MLHVCSQTAZ"
_M, _L, _H, _V, _C, _S, _Q, _T, _A, _Z = range(10)
#: numbers each command consumes per repetition, by code
_ARITY = np.array([2, 2, 1, 1, 6, 4, 4, 2, 7, 0], np.int64)
_POW10 = np.array([10.0 ** k for k in range(23)])   # exact doubles 1 … 1e22
_MAX_EXACT = 2 ** 53

# kernel modes: convert numbers (stop at one that is not exact), record where the numbers
# are (no geometry), or take the numbers from ``given``
_CONVERT, _SPANS, _GIVEN = 0, 1, 2
_NOT_EXACT = 1              # status: some number needs Python's float


def _command_code(c):
    """Code of a command letter (0–9, see _LETTERS), + 16 when relative; -1 for any other byte."""
    upper = c - 32 if 97 <= c <= 122 else c
    code = _LETTERS.find(bytes([upper])) if 65 <= upper <= 90 else -1
    return code + 16 if code >= 0 and upper != c else code


#: the command code (_command_code) of every byte, and whether it is white space: table
#: lookups in the kernel (numba bakes global arrays in as constants), not chains of tests
_COMMAND = np.array([_command_code(c) for c in range(256)], np.int64)
_WSP = np.array([c in b" \t\n\r\f" for c in range(256)], np.bool_)


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _number(buf, pos, end):
    """The SVG number starting at pos (``[+-]?(\\d+\\.?\\d*|\\.\\d+)([eE][+-]?\\d+)?``, longest
    match) → (end of it or -1 when there is none, its value, whether the value is exact)."""
    i = pos
    neg = False
    if i < end and (buf[i] == _PLUS or buf[i] == _MINUS):
        neg = buf[i] == _MINUS
        i += 1
    mant = 0
    sig = 0                     # significant digits taken into mant
    scale = 0                   # decimal exponent of mant's last digit
    digits = 0
    while i < end and _ZERO <= buf[i] <= _NINE:
        d = buf[i] - _ZERO
        if sig < 19 and (mant or d):
            mant = mant * 10 + d
            sig += 1
        elif sig >= 19:
            scale += 1          # digits beyond 19: too many for the fast path anyway
            sig += 1
        digits += 1
        i += 1
    if i < end and buf[i] == _DOT:
        i += 1
        while i < end and _ZERO <= buf[i] <= _NINE:
            d = buf[i] - _ZERO
            if sig < 19 and (mant or d):
                mant = mant * 10 + d
                sig += 1
                scale -= 1
            elif sig < 19:
                scale -= 1      # a leading zero of the fraction
            else:
                sig += 1
            digits += 1
            i += 1
    if digits == 0:
        return -1, 0.0, True
    if i < end and (buf[i] == _E_LOWER or buf[i] == _E_UPPER):
        j = i + 1
        eneg = False
        if j < end and (buf[j] == _PLUS or buf[j] == _MINUS):
            eneg = buf[j] == _MINUS
            j += 1
        if j < end and _ZERO <= buf[j] <= _NINE:
            ex = 0
            while j < end and _ZERO <= buf[j] <= _NINE:
                if ex < 100000:
                    ex = ex * 10 + (buf[j] - _ZERO)
                j += 1
            scale += -ex if eneg else ex
            i = j
    if mant == 0 and sig == 0:
        value = 0.0
        exact = True
    elif sig <= 15 and mant <= _MAX_EXACT and -22 <= scale <= 22:
        value = mant * _POW10[scale] if scale >= 0 else mant / _POW10[-scale]
        exact = True
    else:
        value = 0.0
        exact = False
    return i, -value if neg else value, exact


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _skip_wsp(buf, pos, end):
    while pos < end and _WSP[buf[pos]]:
        pos += 1
    return pos


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _skip_sep(buf, pos, end):
    """comma-wsp (optional): wsp*, at most one comma, wsp*."""
    pos = _skip_wsp(buf, pos, end)
    if pos < end and buf[pos] == _COMMA:
        pos = _skip_wsp(buf, pos + 1, end)
    return pos


@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _arc(pts, npts, x1, y1, rx, ry, phi_deg, large_arc, sweep, x2, y2):
    """Writes an elliptical arc's conic pieces (≤ 90° each, as usvg cuts them: three points
    per piece, as scene.path stores a CONIC) into pts
    from npts on → new npts; -1 when the arc is a straight line: a zero radius, or endpoints
    that coincide. SVG omits the latter arc, but its command still makes the subpath more
    than a moveto, so the zero-length line stands for it: round and square caps are drawn,
    as browsers (Blink emits the line, Gecko caps the subpath) and resvg (kurbo counts it a
    straight line) draw them, and a marker vertex is there."""
    if x1 == x2 and y1 == y2:
        return -1
    if not (math.isfinite(x1) and math.isfinite(y1) and math.isfinite(rx)
            and math.isfinite(ry) and math.isfinite(phi_deg) and math.isfinite(x2)
            and math.isfinite(y2)):
        return -1   # an infinite coordinate (1e999): no arc to speak of, a straight line
    rx = abs(rx)
    ry = abs(ry)
    if rx == 0.0 or ry == 0.0:
        return -1
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
    half = abs(x1p)
    if abs(y1p) > half:
        half = abs(y1p)
    if half == 0.0 or not 1e-150 < min(rx, ry) / half or max(rx, ry) / half > 1e150:
        return -1
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
    if 0.0 > num:
        num = 0.0
    coef = math.sqrt(num / den) if den > 0 else 0.0
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
    # as many pieces as usvg cuts (kurbo's Arc::append_iter at usvg's tolerance of 0.1; mid
    # markers go between them): 90° each, so a half turn a hair over 180° is still two. usvg
    # cuts more for radii over ~367 units; here at most four (the buffers hold four a command)
    n_err = max((1.1163 * max(rx, ry) / 0.1) ** (1.0 / 6.0), 3.999999)
    n = max(1, min(4, int(math.ceil(n_err * abs(dtheta) / (2.0 * math.pi)))))
    delta = dtheta / n
    # each piece is a conic (control point, point at t = ½, end; see scene.path): on the unit
    # circle the control point is the mid-angle direction over cos(delta/2), the weight
    sec = 1.0 / math.cos(delta / 2.0)
    for i in range(n):
        m = theta1 + (i + 0.5) * delta
        b = theta1 + (i + 1) * delta
        cos_m, sin_m = math.cos(m), math.sin(m)
        for k in range(3):
            if k == 0:
                ex, ey = cos_m * sec, sin_m * sec
            elif k == 1:
                ex, ey = cos_m, sin_m
            else:
                ex, ey = math.cos(b), math.sin(b)
            # scale by radii, rotate by phi, translate
            ex *= rx
            ey *= ry
            pts[npts] = cos_phi * ex - sin_phi * ey + cx
            pts[npts + 1] = sin_phi * ex + cos_phi * ey + cy
            npts += 2
    pts[npts - 2] = x2      # land exactly on the requested endpoint
    pts[npts - 1] = y2
    return npts


@njit(cache=True)
def _parse_batch(buf, starts, mode, given, spans):
    """The path data buf[starts[i]:starts[i + 1]] of several paths → (verbs, flat points,
    command indices: whole buffers, to be cut at the ends of the last path; where each path's
    verbs and coordinates start (n + 1 each), status of each path, numbers read in each); a
    path with status _NOT_EXACT is left empty here. Modes _SPANS and _GIVEN are for one path
    at a time.

    Each path's data is read as SVG 2 9.3.9 and 9.5.4 say (see the module doc). mode
    _CONVERT converts numbers here and stops with status _NOT_EXACT at one it cannot; _SPANS
    writes where each number is into ``spans`` (start, end pairs; flags are not numbers here)
    and nothing else; _GIVEN takes the k-th number's value from ``given``. The control flow
    depends on how many numbers there are, never on their values, so the three modes see the
    same numbers.

    One kernel, the only entry point: numba optimises a kernel together with everything it
    calls, so each level of calls or further entry would compile the parser again."""
    npaths = len(starts) - 1
    longest = 0
    for i in range(npaths):
        longest = max(longest, starts[i + 1] - starts[i])
    nums = np.empty(longest + 1, np.float64)     # a command's numbers
    # verbs and origin get ≤ 1 entry a byte and 2 a path; pts ≤ 2 coordinates a byte but
    # for arcs (≤ 24 coordinates a command of ≥ 9 bytes): grown below when 3 a byte + 32 might
    # not fit
    vcap = len(buf) + 2 * npaths + 2
    verbs = np.empty(vcap, np.uint8)
    origin = np.empty(vcap, np.int64)
    pcap = 2 * len(buf) + 32
    pts = np.empty(pcap, np.float64)
    vstart = np.empty(npaths + 1, np.int64)
    pstart = np.empty(npaths + 1, np.int64)
    path_status = np.zeros(npaths, np.int64)
    numbers = np.zeros(npaths, np.int64)
    nv = npts = np.int64(0)      # (not the literal 0: _arc would be compiled for it too)
    for path in range(npaths):
        pos, n = starts[path], starts[path + 1]
        need = npts + 3 * (n - pos) + 32
        if need > pcap:                 # only arcs write more than 2 coordinates a byte
            pcap = max(need, 2 * pcap)
            grown = np.empty(pcap, np.float64)
            for j in range(npts):   # (a loop: a slice assignment costs seconds of compile time)
                grown[j] = pts[j]
            pts = grown
        vstart[path] = nv
        pstart[path] = npts
        k = 0                       # numbers read so far (indexes given and spans)
        status = 0
        geometry = mode != _SPANS
        pos = _skip_wsp(buf, pos, n)
        if pos < n and _COMMAND[buf[pos]] < 0:
            pos = n                 # junk before the first command: an empty path
        cx = cy = sx = sy = rx = ry = 0.0
        prev_kind = 0               # _C after C/S, _Q after Q/T, -1 otherwise
        subpath_open = False
        command_index = 0
        first = True
        while pos < n:
            code = _COMMAND[buf[pos]]
            upper = code & 15
            relative = code >= 16
            a0 = pos + 1
            a1 = a0
            while a1 < n and _COMMAND[buf[a1]] < 0:
                a1 += 1
            pos = a1
            if first and upper != _M:
                break               # path data must begin with a moveto
            first = False
            # -- the arguments: numbers, or for arcs numbers and single-digit flags ----------
            count = 0
            p = _skip_wsp(buf, a0, a1)
            field = 0                   # an arc's fields 3 and 4 are flags
            while True:
                q = p if count == 0 else _skip_sep(buf, p, a1)
                if upper == _A and (field == 3 or field == 4):
                    if q < a1 and (buf[q] == _ZERO or buf[q] == _ONE):
                        nums[count] = 1.0 if buf[q] == _ONE else 0.0
                        e = q + 1
                    else:
                        break
                else:
                    e, v, exact = _number(buf, q, a1)
                    if e < 0:
                        break
                    if mode == _GIVEN:
                        v = given[k]
                    elif mode == _SPANS:
                        spans[2 * k] = q
                        spans[2 * k + 1] = e
                    elif not exact:
                        status = _NOT_EXACT
                        break
                    nums[count] = v
                    k += 1
                count += 1
                p = e
                field = (field + 1) % 7
            if status:
                break
            # a comma may follow a command's last number (svgtypes and browsers read
            # "M20 20,L180 20"; SVG's grammar leaves separators between commands open)
            ok = (_skip_sep(buf, p, a1) if count else _skip_wsp(buf, p, a1)) == a1
            if upper != _A and not ok and count and (buf[p] == _E_LOWER or buf[p] == _E_UPPER):
                count -= 1      # "1e" is a broken number, not "1" followed by junk
            arity = _ARITY[upper]
            if arity == 0:
                nums_ok = count == 0
                reps = 0
            else:
                reps = count // arity
                nums_ok = reps > 0 and reps * arity == count
            if not geometry:
                if not (ok and nums_ok):
                    break
                continue
            if upper == _Z:
                if subpath_open:
                    verbs[nv] = CLOSE
                    origin[nv] = command_index
                    nv += 1
                    command_index += 1
                cx, cy = sx, sy
                subpath_open = False
                prev_kind = -1
                if not (ok and nums_ok):
                    break
                continue
            for r in range(reps):
                i = r * arity
                if upper == _M:
                    x, y = nums[i], nums[i + 1]
                    if relative:
                        x += cx
                        y += cy
                    verbs[nv] = MOVE if r == 0 else LINE   # extra pairs are implicit linetos
                    origin[nv] = command_index
                    nv += 1
                    pts[npts] = x
                    pts[npts + 1] = y
                    npts += 2
                    if r == 0:
                        sx, sy = x, y
                        subpath_open = True
                    cx, cy = x, y
                    prev_kind = -1
                    command_index += 1
                    continue
                if not subpath_open:
                    # a drawing command right after closepath starts a subpath at its start point
                    verbs[nv] = MOVE
                    origin[nv] = command_index
                    nv += 1
                    pts[npts] = cx
                    pts[npts + 1] = cy
                    npts += 2
                    subpath_open = True
                if upper == _L or upper == _H or upper == _V:
                    if upper == _L:
                        x, y = nums[i], nums[i + 1]
                        if relative:
                            x += cx
                            y += cy
                    elif upper == _H:
                        x = nums[i] + cx if relative else nums[i]
                        y = cy
                    else:
                        x = cx
                        y = nums[i] + cy if relative else nums[i]
                    verbs[nv] = LINE
                    pts[npts] = x
                    pts[npts + 1] = y
                    npts += 2
                    prev_kind = -1
                elif upper == _C or upper == _S:
                    if upper == _C:
                        x1, y1 = nums[i], nums[i + 1]
                        x2, y2, x, y = nums[i + 2], nums[i + 3], nums[i + 4], nums[i + 5]
                        if relative:
                            x1 += cx
                            y1 += cy
                    else:
                        x2, y2, x, y = nums[i], nums[i + 1], nums[i + 2], nums[i + 3]
                        if prev_kind == _C:
                            x1, y1 = 2 * cx - rx, 2 * cy - ry
                        else:
                            x1, y1 = cx, cy
                    if relative:
                        x2 += cx
                        y2 += cy
                        x += cx
                        y += cy
                    verbs[nv] = CUBIC
                    pts[npts] = x1
                    pts[npts + 1] = y1
                    pts[npts + 2] = x2
                    pts[npts + 3] = y2
                    pts[npts + 4] = x
                    pts[npts + 5] = y
                    npts += 6
                    rx, ry = x2, y2
                    prev_kind = _C
                elif upper == _Q or upper == _T:
                    if upper == _Q:
                        x1, y1, x, y = nums[i], nums[i + 1], nums[i + 2], nums[i + 3]
                        if relative:
                            x1 += cx
                            y1 += cy
                    else:
                        x, y = nums[i], nums[i + 1]
                        if prev_kind == _Q:
                            x1, y1 = 2 * cx - rx, 2 * cy - ry
                        else:
                            x1, y1 = cx, cy
                    if relative:
                        x += cx
                        y += cy
                    verbs[nv] = QUAD
                    pts[npts] = x1
                    pts[npts + 1] = y1
                    pts[npts + 2] = x
                    pts[npts + 3] = y
                    npts += 4
                    rx, ry = x1, y1
                    prev_kind = _Q
                else:               # A
                    x, y = nums[i + 5], nums[i + 6]
                    if relative:
                        x += cx
                        y += cy
                    start = npts
                    end = _arc(pts, npts, cx, cy, nums[i], nums[i + 1], nums[i + 2],
                               nums[i + 3] != 0.0, nums[i + 4] != 0.0, x, y)
                    if end < 0:
                        verbs[nv] = LINE
                        origin[nv] = command_index
                        nv += 1
                        pts[npts] = x
                        pts[npts + 1] = y
                        npts += 2
                    else:
                        for _ in range((end - start) // 6):
                            verbs[nv] = CONIC
                            origin[nv] = command_index
                            nv += 1
                        npts = end
                    cx, cy = x, y
                    prev_kind = -1
                    command_index += 1
                    continue
                origin[nv] = command_index
                nv += 1
                cx, cy = x, y
                command_index += 1
            if not (ok and nums_ok):
                break
        numbers[path] = k
        if status:
            path_status[path] = status
            nv, npts = vstart[path], pstart[path]    # (the path is left empty)
    vstart[npaths] = nv
    pstart[npaths] = npts
    return verbs, pts, origin, vstart, pstart, path_status, numbers


_NO_NUMBERS = np.empty(0, np.float64)
_NO_SPANS = np.empty(0, np.int64)


def parse_path_data(d: str) -> Path:
    """The path described by an SVG ``d`` attribute (empty Path for an empty or invalid one)."""
    return _parse(d)[0]


def parse_path_data_with_commands(d: str):
    """Like :func:`parse_path_data`, plus, for every recorded verb, the index of the path
    command (counting implicit repetitions as their own commands) it came from.

    An arc becomes several cubics; this tells which verbs belong to one command. (SVG markers
    do not use it: resvg places mid markers between an arc's pieces too.)
    """
    return _parse(d)


def _parse(d: str):
    """→ (Path, command index of every verb)."""
    return PathBatch([d]).get(0)


def _parse_exactly(text: str):
    """_parse for data with numbers the kernel cannot convert exactly: the kernel finds them,
    Python's float converts them, the kernel reads the path with those values."""
    buf = np.frombuffer(text.encode("utf-8", "replace"), np.uint8)
    starts = np.array([0, len(buf)], np.int64)
    spans = np.empty(2 * len(buf) + 2, np.int64)
    count = _parse_batch(buf, starts, _SPANS, _NO_NUMBERS, spans)[6][0]
    raw = buf.tobytes()
    given = np.array([float(raw[a:b]) for a, b in spans[:2 * count].reshape(-1, 2).tolist()],
                     np.float64)
    bad = np.flatnonzero(~np.isfinite(given))
    if len(bad):    # a number past double range is an error: the data is read up to it
        return _parse_exactly(raw[:spans[2 * bad[0]]].decode("utf-8", "replace"))
    verbs, pts, origin, vstart, pstart = _parse_batch(buf, starts, _GIVEN, given, _NO_SPANS)[:5]
    nv, npts = vstart[-1], pstart[-1]
    return Path._of_arrays(verbs[:nv].copy(), pts[:npts].reshape(-1, 2).copy()), origin[:nv].copy()


class PathBatch:
    """The path data of many elements, read in one kernel call (a call per path would cost
    more than reading it: maps have tens of thousands of short paths)."""

    def __init__(self, texts):
        joined = "".join(texts)
        starts = np.zeros(len(texts) + 1, np.int64)
        if joined.isascii():        # (path data nearly always is: a character is a byte)
            np.cumsum(np.fromiter(map(len, texts), np.int64, len(texts)), out=starts[1:])
            buf = np.frombuffer(joined.encode("ascii"), np.uint8)
        else:
            raw = [t.encode("utf-8", "replace") for t in texts]
            np.cumsum([len(r) for r in raw], out=starts[1:])
            buf = np.frombuffer(b"".join(raw), np.uint8)
        verbs, pts, origin, vstart, pstart, status, _ = _parse_batch(
            buf, starts, _CONVERT, _NO_NUMBERS, _NO_SPANS)
        nv, npts = vstart[-1], pstart[-1]
        self.texts = texts
        self.verbs, self.origin = verbs[:nv].copy(), origin[:nv].copy()
        self.points = SharedPoints(pts[:npts].reshape(-1, 2).copy())
        # the offsets as int64 arrays too (the kernels over the batch take them) and as
        # lists (indexed path by path)
        self.offsets = vstart, pstart // 2
        self.vstart, self.pstart = vstart.tolist(), self.offsets[1].tolist()
        self.status = status.tolist()
        self._drawing = None

    def drawing(self) -> list:
        """Per path whether it has a verb besides MOVE and CLOSE (is not Path.is_empty)."""
        if self._drawing is None:
            counts = np.zeros(len(self.verbs) + 1, np.int64)
            np.cumsum((self.verbs != MOVE) & (self.verbs != CLOSE), out=counts[1:])
            at = self.offsets[0]
            self._drawing = (counts[at[1:]] > counts[at[:-1]]).tolist()
        return self._drawing

    def get(self, i):
        """(Path, command index of every verb) of the i-th text."""
        if self.status[i]:
            return _parse_exactly(self.texts[i])
        v0, v1 = self.vstart[i], self.vstart[i + 1]
        return self.path(i), self.origin[v0:v1]

    def path(self, i) -> Path:
        """The Path of the i-th text."""
        if self.status[i]:
            return _parse_exactly(self.texts[i])[0]
        return Path._of_shared(self.verbs[self.vstart[i]:self.vstart[i + 1]], self.points,
                               self.pstart[i], self.pstart[i + 1])


def arc_to_cubics(x1, y1, rx, ry, phi_deg, large_arc, sweep, x2, y2):
    """An elliptical arc as cubic Bézier pieces ``[(c1, c2, end), ...]`` of at most 90° each.

    Returns None when the arc is a straight line (a zero radius, or endpoints that coincide:
    see _arc).
    """
    x1, y1, rx, ry, phi_deg, x2, y2 = map(float, (x1, y1, rx, ry, phi_deg, x2, y2))
    if not all(map(math.isfinite, (x1, y1, rx, ry, phi_deg, x2, y2))):
        return None
    # read as path data (repr round-trips every double), which runs the kernel's _arc
    flags = f"{int(bool(large_arc))} {int(bool(sweep))}"
    path = parse_path_data(f"M {x1!r} {y1!r} A {rx!r} {ry!r} {phi_deg!r} {flags} {x2!r} {y2!r}")
    if path.verbs[-1] != CONIC:
        return None
    xy = path.without_conics().points[1:].reshape(-1, 3, 2).tolist()
    return [tuple(tuple(p) for p in piece) for piece in xy]
