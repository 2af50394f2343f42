"""Numbers, lengths, transforms, viewBox and preserveAspectRatio."""
from __future__ import annotations

import functools
import math
import re

from ..scene.transform import IDENTITY, compose, cos_sin_degrees

NUMBER_RE = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
#: a CSS <length>: the unit follows the number directly ("50 px" is two tokens, no length)
_LENGTH = re.compile(rf"^\s*({NUMBER_RE})(px|pt|pc|mm|cm|in|em|ex|%)?\s*$", re.I)

#: units whose size in px follows the output resolution (``dpi``; CSS fixes them at 96 dpi)
PHYSICAL_UNITS = ("pt", "pc", "mm", "cm", "in")
#: size of one unit in CSS px at 96 dpi
UNIT_PX = {"": 1.0, "px": 1.0, "pt": 4 / 3, "pc": 16.0, "mm": 96 / 25.4, "cm": 96 / 2.54,
           "in": 96.0}


_LIST_LENGTH = re.compile(rf"[ \t\n\r]*({NUMBER_RE})(%|em|ex|px|in|cm|mm|pt|pc)?[ \t\n\r]*,?")


def parse_length_list(text) -> list[tuple[float, str]]:
    """A list of lengths separated by spaces and/or one comma, as resvg (svgtypes) reads it:
    the lengths before the first one that does not parse (``none`` is an empty list)."""
    out, pos, text = [], 0, text or ""
    while pos < len(text):
        m = _LIST_LENGTH.match(text, pos)
        # a number too large for a double (1e400) does not parse either
        if m is None or not math.isfinite(float(m.group(1))):
            break
        out.append((float(m.group(1)), m.group(2) or ""))
        pos = m.end()
    return out


def parse_number(text, default=None):
    if text is None:
        return default
    try:
        v = float(text.strip())
    except (ValueError, AttributeError):
        return default
    return v if math.isfinite(v) else default


_LIST_ITEM = re.compile(rf"[ \t\n\r]*({NUMBER_RE})[ \t\n\r]*,?")


def parse_number_list(text):
    """A list of numbers separated by whitespace and at most one comma (SVG's comma-wsp; a
    trailing comma is let pass, as resvg's svgtypes does), or None when anything else is
    in it: ``5px``, ``5,,3``, ``x5`` and ``0.5;`` are no lists (the attribute is then
    invalid, as in resvg)."""
    if text is None:
        return None
    out, pos = _leading_numbers(text)
    return out if not text[pos:].strip(" \t\n\r") else None


def parse_number_prefix(text) -> list[float]:
    """The numbers of a list before the first thing that is not one: a ``points`` list (SVG
    2: a polyline in error draws the points before the error, as path data does: ``10px,10
    ...`` has none, ``10,,20`` one) and ``stdDeviation`` as resvg reads it (``5px`` is 5,
    ``x5`` nothing)."""
    return _leading_numbers(text or "")[0]


def _leading_numbers(text: str) -> tuple[list[float], int]:
    """The list items (numbers and their separators) one after another from the start of
    ``text``, and where the first thing that is not one begins."""
    out, pos = [], 0
    while pos < len(text):
        m = _LIST_ITEM.match(text, pos)
        # a number too large for a double (1e400) is not one: the list stops (or is invalid)
        if m is None or not math.isfinite(float(m.group(1))):
            break
        out.append(float(m.group(1)))
        pos = m.end()
    return out, pos


def url_argument(text):
    """The URL inside url(...) (``text``, without the parentheses): a quoted string, or
    unquoted text without whitespace, quotes, parentheses or backslashes (CSS Syntax: anything
    else in an unquoted url is a bad url, so invalid); None for a bad url."""
    a = text.strip()
    if len(a) >= 2 and a[0] == a[-1] and a[0] in "'\"" and a[0] not in a[1:-1]:
        return a[1:-1].strip()
    if any(ch.isspace() or ch in "'\"()\\" for ch in a):
        return None
    return a


def split_length(text):
    """'12.5mm' → (12.5, 'mm'); None when not a length."""
    if text is None:
        return None
    m = _LENGTH.match(text)
    if not m:
        return None
    v = float(m.group(1))
    if not math.isfinite(v):
        return None
    return v, (m.group(2) or "").lower()


_CALC_TOKEN = re.compile(rf"\s*(?:({NUMBER_RE})([a-zA-Z]+|%)?|(calc\()|([-+*/()]))", re.I)
#: parentheses nested deeper than this make a calc() invalid (CSS Values 4 leaves the limit to
#: the user agent); the evaluator below recurses once per level
CALC_MAX_DEPTH = 64


def eval_calc(text, resolve):
    """The value of a CSS ``calc()`` expression (CSS Values 4 §10) in px, or None when it is
    not one or its types do not add up. ``resolve(number, unit)`` gives a dimension or
    percentage in px (None for an unknown unit). Sums take lengths with lengths; a product
    takes a number on one side, a quotient a number on the right; the result is a length
    (a bare number is taken as user units, as in an SVG attribute)."""
    text = text.strip()
    if not text[:5].lower() == "calc(":
        return None
    tokens = []
    pos = depth = 0
    while pos < len(text):
        m = _CALC_TOKEN.match(text, pos)
        if not m or m.end() == pos:
            if text[pos:].strip() == "":
                break
            return None
        if m.group(1) is not None:
            unit = (m.group(2) or "").lower()
            if unit:
                v = resolve(float(m.group(1)), unit)
                if v is None:
                    return None
                tokens.append(("L", v))
            else:
                tokens.append(("N", float(m.group(1))))
        elif m.group(3) or m.group(4) == "(":
            tokens.append(("(", None))
            depth += 1
            if depth > CALC_MAX_DEPTH:
                return None
        else:
            tokens.append((m.group(4), None))
            depth -= m.group(4) == ")"
        pos = m.end()
    # operators of CSS calc: + and - need spaces around them; a sign without one belongs to
    # the number ("10px -5px" is not a sum); the tokenizer read "-5px" as a number, so a
    # value following a value without an operator is an error
    at = [0]

    def peek():
        return tokens[at[0]][0] if at[0] < len(tokens) else None

    def take():
        at[0] += 1
        return tokens[at[0] - 1]

    def value():
        kind, v = take() if at[0] < len(tokens) else (None, None)
        if kind in ("L", "N"):
            return kind, v
        if kind == "(":
            got = total()
            if got is None or peek() != ")":
                return None
            take()
            return got
        return None

    def product():
        left = value()
        while left is not None and peek() in ("*", "/"):
            op = take()[0]
            right = value()
            if right is None:
                return None
            if op == "*":
                if left[0] == "L" and right[0] == "L":
                    return None
                left = ("L" if "L" in (left[0], right[0]) else "N", left[1] * right[1])
            else:
                if right[0] != "N" or right[1] == 0:
                    return None
                left = (left[0], left[1] / right[1])
        return left

    def total():
        left = product()
        while left is not None and peek() in ("+", "-"):
            op = take()[0]
            right = product()
            if right is None or right[0] != left[0]:
                return None
            left = (left[0], left[1] + right[1] if op == "+" else left[1] - right[1])
        return left

    got = value()
    if got is None or at[0] != len(tokens) or not math.isfinite(got[1]):
        return None
    return got[1]


def parse_fraction(text):
    """An objectBoundingBox coordinate: a number or a percentage, as a fraction of the box;
    None when it does not parse."""
    parsed = split_length(text) if text is not None else None
    if parsed is None:
        return None
    v, unit = parsed
    return v / 100 if unit == "%" else v


def box_coord(builder, value, axis, obb, style, viewport, default):
    """A coordinate of a gradient, pattern, mask or filter region (``builder`` reads lengths):
    in objectBoundingBox units (``obb``) a fraction of the box, where a percentage is a
    fraction and a length with a unit is its number of user units (2mm is 7.56 boxes, as in
    browsers and resvg: the unit box is the user space); ``default`` where ``value`` is
    missing or not a length."""
    if value is None or split_length(value) is None:
        value = default
    if obb and split_length(value)[1] == "%":
        return parse_fraction(value)
    return builder.length(value, axis, style, viewport)


def to_px(value, unit, font_size=16.0, reference=0.0, dpi=96.0):
    """Convert (value, unit) to user units; ``reference`` is what 100% means, ``dpi`` what
    1in is in px (it scales the physical units)."""
    if unit == "%":
        return value * reference / 100.0
    if unit == "em":
        return value * font_size
    if unit == "ex":
        return value * font_size / 2
    px = value * UNIT_PX[unit]
    return px * (dpi / 96.0) if unit in PHYSICAL_UNITS else px


# one comma at most between functions, none before the first (",," and a leading comma make
# the list malformed, as in resvg 0.48.1 and Chromium 150; a trailing one is let pass, as resvg)
_TRANSFORM_FN = re.compile(r"\s*([a-zA-Z]+)\s*\(([^)]*)\)\s*,?")
# numbers may follow each other without a separator where SVG's grammar allows it ("10-5")
_TRANSFORM_ARG = re.compile(rf"\s*({NUMBER_RE})([a-zA-Z%]*)\s*(?:,|(?=[\s+\-.])|$)")
#: angle units of CSS Values 4, in degrees
ANGLE_DEG = {"": 1.0, "deg": 1.0, "grad": 0.9, "rad": 180 / math.pi, "turn": 360.0}
#: (minimum, maximum) argument counts and each argument's kind: a(ngle), l(ength), n(umber)
_TRANSFORM_ARGS = {"matrix": (6, 6, "nnnnnn"), "translate": (1, 2, "ll"), "translateX": (1, 1, "l"),
                   "translateY": (1, 1, "l"), "scale": (1, 2, "nn"), "scaleX": (1, 1, "n"),
                   "scaleY": (1, 1, "n"), "rotate": (1, 3, "all"), "skew": (1, 2, "aa"),
                   "skewX": (1, 1, "a"), "skewY": (1, 1, "a")}
#: the functions of the transform, gradientTransform and patternTransform attributes, whose
#: arguments are numbers without units (SVG 1.1's grammar, which resvg 0.48.1 and Chromium 150
#: both keep for the attributes: rotate(10deg), translate(20px), skew(10) make them malformed)
SVG_TRANSFORM_FUNCTIONS = {"matrix", "translate", "scale", "rotate", "skewX", "skewY"}


def _transform_args(name, text, box=None, font_size=None, attribute=False):
    """The arguments of one transform function as floats (angles in degrees, lengths in px),
    or None when their number, kind or units are wrong. ``box``: the (width, height) of the
    reference box that percentages in translate functions are of (CSS Transforms 1 §7.1),
    None where they are invalid; ``font_size`` what em is (None: em and ex are invalid);
    ``attribute``: SVG's attribute grammar, where any unit is wrong."""
    lo, hi, kinds = _TRANSFORM_ARGS[name]
    out = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TRANSFORM_ARG.match(text, pos)
        if not m or len(out) == hi:
            return None
        value, unit = float(m.group(1)), m.group(2).lower()
        kind = kinds[len(out)]
        if attribute and unit:
            return None
        if kind == "a" and unit in ANGLE_DEG:
            value *= ANGLE_DEG[unit]
        elif kind == "l" and unit in UNIT_PX:
            value *= UNIT_PX[unit]
        elif kind == "l" and unit == "%" and box is not None and name != "rotate":
            value *= box[1 if name == "translateY" or len(out) == 1 else 0] / 100
        elif kind == "l" and unit in ("em", "ex") and font_size is not None:
            value *= font_size if unit == "em" else font_size / 2    # ex as to_px has it
        elif kind == "n" and unit in ("", "%"):
            value = value / 100 if unit == "%" else value
        else:
            return None
        out.append(value)
        pos = m.end()
    if not lo <= len(out) <= hi or (name == "rotate" and len(out) == 2):
        return None
    return out


@functools.lru_cache(maxsize=4096)
def parse_transform(text, box=None, font_size=None, attribute=False):
    """A transform list → affine matrix; None when the text is malformed. Cached by its
    arguments: the bounding-box walks parse an element's transform once per walk that reaches
    it (quadratic in nesting depth), and documents repeat a few transforms many times.

    SVG's syntax (unitless numbers, spaces or commas) and CSS Transforms' (the functions
    translateX/Y, scaleX/Y, skew; angles in deg, grad, rad or turn; lengths with absolute units;
    scale factors as percentages; translations as percentages of ``box``, the (width, height)
    of the element's reference box, or in em and ex of ``font_size``) are both read; with
    ``attribute`` (the text of a transform, gradientTransform or patternTransform attribute)
    only SVG's, :data:`SVG_TRANSFORM_FUNCTIONS` of unitless numbers."""
    m = IDENTITY
    if text is None:
        return IDENTITY
    s = text.strip()
    pos = 0
    while pos < len(s):
        mt = _TRANSFORM_FN.match(s, pos)
        if not mt or mt.group(1) not in (SVG_TRANSFORM_FUNCTIONS if attribute else _TRANSFORM_ARGS):
            return None
        name = mt.group(1)
        nums = _transform_args(name, mt.group(2), box, font_size, attribute)
        if nums is None or not all(map(math.isfinite, nums)):
            return None   # an overflowing number (1e400 → inf) is malformed, as in resvg
        pos = mt.end()
        n = len(nums)
        if name == "matrix":
            t = tuple(nums)
        elif name.startswith("translate"):
            tx, ty = (nums[0], nums[1] if n == 2 else 0.0) if name == "translate" else (
                (nums[0], 0.0) if name == "translateX" else (0.0, nums[0]))
            t = (1, 0, 0, 1, tx, ty)
        elif name.startswith("scale"):
            sx, sy = (nums[0], nums[1] if n == 2 else nums[0]) if name == "scale" else (
                (nums[0], 1.0) if name == "scaleX" else (1.0, nums[0]))
            t = (sx, 0, 0, sy, 0, 0)
        elif name == "rotate":
            c, sn = cos_sin_degrees(nums[0])
            t = (c, sn, -sn, c, 0, 0)
            if n == 3:
                cx, cy = nums[1], nums[2]
                t = compose(compose((1, 0, 0, 1, cx, cy), t), (1, 0, 0, 1, -cx, -cy))
        else:
            ax = nums[0] if name in ("skew", "skewX") else 0.0
            ay = nums[0] if name == "skewY" else (nums[1] if name == "skew" and n == 2 else 0.0)
            t = (1, math.tan(math.radians(ay)), math.tan(math.radians(ax)), 1, 0, 0)
        m = compose(m, tuple(float(x) for x in t))
    return m


_CSS_DIMENSION = re.compile(rf"^({NUMBER_RE})([a-zA-Z%]*)$")


def individual_transform(translate_text, rotate_text, scale_text, box, font_size=16.0):
    """The matrix of CSS Transforms 2's individual transform properties, translate, then
    rotate, then scale (§3.1: they apply before ``transform``, all about the origin), as
    seen in the plane: a rotation about another axis than z is the 3-D rotation's x-y part
    (the flat projection a renderer without perspective shows). ``box`` is the reference
    box's (width, height) for translate's percentages, ``font_size`` what em is. A value that
    is not of the property's grammar is none (the declaration is dropped)."""
    m = IDENTITY

    def dims(text):
        out = []
        for token in text.split():
            d = _CSS_DIMENSION.match(token)
            if not d:
                return None
            out.append((float(d.group(1)), d.group(2).lower()))
        return out

    parts = dims(translate_text) if translate_text else None
    if parts and 1 <= len(parts) <= 3:
        xy = []
        for i, (v, unit) in enumerate(parts):
            if unit == "%" and i < 2:
                v = v * box[i] / 100
            elif unit in UNIT_PX and (unit or v == 0):
                v = v * UNIT_PX[unit]
            elif unit in ("em", "ex"):
                v = v * (font_size if unit == "em" else font_size / 2)   # ex as to_px has it
            else:
                xy = None
                break
            xy.append(v)
        if xy:
            m = compose(m, (1.0, 0.0, 0.0, 1.0, xy[0], xy[1] if len(xy) > 1 else 0.0))
    parts = dims(rotate_text) if rotate_text else None
    if rotate_text and parts is None:
        words = rotate_text.lower().split()            # an axis keyword and an angle
        axis = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}
        keys = [w for w in words if w in axis]
        rest = [w for w in words if w not in axis]
        if len(keys) == 1 and len(rest) == 1 and len(words) == 2:
            d = _CSS_DIMENSION.match(rest[0])
            if d:
                parts = [(float(c), "") for c in axis[keys[0]]]
                parts.append((float(d.group(1)), d.group(2).lower()))
    if parts and len(parts) in (1, 4):
        v, unit = parts[-1]
        vector = [p[0] for p in parts[:3] if p[1] == ""] if len(parts) == 4 else [0, 0, 1]
        if ((unit in ANGLE_DEG and (unit or v == 0)) and len(vector) == 3
                and any(vector)):
            n = math.sqrt(sum(c * c for c in vector))
            x, y, z = (c / n for c in vector)
            c, sn = cos_sin_degrees(v * ANGLE_DEG[unit])
            # Rodrigues' rotation matrix, rows x and y, columns x and y
            r00, r01 = c + x * x * (1 - c), x * y * (1 - c) - z * sn
            r10, r11 = y * x * (1 - c) + z * sn, c + y * y * (1 - c)
            m = compose(m, (r00, r10, r01, r11, 0.0, 0.0))
    parts = dims(scale_text) if scale_text else None
    if parts and 1 <= len(parts) <= 3 and all(unit in ("", "%") for _, unit in parts):
        f = [v / 100 if unit == "%" else v for v, unit in parts]
        m = compose(m, (f[0], 0.0, 0.0, f[1] if len(f) > 1 else f[0], 0.0, 0.0))
    return m


def scale(sx, sy=None):
    return (float(sx), 0.0, 0.0, float(sx if sy is None else sy), 0.0, 0.0)


def row_scale(m):
    """Per-axis scale factors as resvg computes a pattern tile's resolution (tiny-skia's
    ``Transform::get_scale``): the lengths of the matrix *rows*, (|(a, c)|, |(b, d)|). They
    equal the lengths of its columns (the images of the unit vectors) for rotations and
    scales, and differ under skew."""
    a, b, c, d, _, _ = m
    return math.hypot(a, c), math.hypot(b, d)


def row_scale_f32(m):
    """:func:`row_scale` as resvg computes it, in f32 from the f32 matrix entries: where
    resvg steps in whole pixels (pattern tiles, feOffset) the step then falls where its
    does (a rotation's norm is 1 or 0.99999994 by angle, not 0.9999999999999999 or 1)."""
    import numpy as np

    with np.errstate(over="ignore"):    # entries past f32 give inf, which callers check
        a, b, c, d = (np.float32(v) for v in m[:4])
        return float(np.sqrt(a * a + c * c)), float(np.sqrt(b * b + d * d))


def f32_matrix(m):
    """A matrix's entries rounded to f32 (as floats)."""
    import numpy as np

    return tuple(float(np.float32(v)) for v in m)


def concat_f32(a, b):
    """a ∘ b as tiny-skia concatenates: each entry a sum of products in f64, rounded to f32."""
    import numpy as np

    a0, a1, a2, a3, a4, a5 = a
    b0, b1, b2, b3, b4, b5 = b
    return tuple(float(np.float32(v)) for v in (
        a0 * b0 + a2 * b1, a1 * b0 + a3 * b1, a0 * b2 + a2 * b3, a1 * b2 + a3 * b3,
        a0 * b4 + a2 * b5 + a4, a1 * b4 + a3 * b5 + a5))


def f32_chain(chain, transform):
    """An element's device matrix ``transform`` as resvg composes it: the root's and each
    element's transform (``chain``, outermost first) each in f32, concatenated in f32 (not
    the f64 product rounded): under a rotation the two differ by an ulp of the row norm, and
    a pattern tile of n + 1/2 px rounds to n in one and n + 1 in the other (17 units at 1.5
    px each under rotate(13) on the element and rotate(32) on the pattern: 26 px in resvg,
    25 from the product), a morphology radius of 4 units at 1.5 px under rotate(25) takes
    7 px windows in one and 6 in the other. What the chain does not hold (a use's x/y,
    nested viewports) comes last."""
    import numpy as np

    from ..scene.transform import invert

    with np.errstate(over="ignore", invalid="ignore"):
        product = IDENTITY
        for m in chain:
            product = compose(product, m)
        try:
            rest = compose(invert(product), transform)
        except ValueError:
            return f32_matrix(transform)
        out = IDENTITY
        for m in chain + (rest,):
            out = concat_f32(out, f32_matrix(m))
        return out


def mean_scale(m):
    """The factor by which the matrix scales lengths on average (sqrt of |det|)."""
    a, b, c, d, _, _ = m
    return math.sqrt(abs(a * d - b * c))


def parse_viewbox(text):
    if not text:
        return None
    # (a number that overflows to infinity is no list item: the list, so the viewBox, is
    # invalid, as with a negative size)
    nums = parse_number_list(text)
    if nums is None or len(nums) != 4 or not (nums[2] > 0 and nums[3] > 0):
        return None
    return tuple(nums)


def zero_size_viewbox(text):
    """Whether ``text`` is a viewBox list with a zero width or height and no negative one
    (SVG 2: such a viewBox disables rendering of its element; a negative size only makes
    the attribute invalid)."""
    nums = parse_number_list(text) if text else None
    return nums is not None and len(nums) == 4 and min(nums[2], nums[3]) == 0


def parse_aspect(text):
    """preserveAspectRatio → (align, slice); align is 'none' or like 'xMidYMid'."""
    parts = (text or "").split()
    if parts and parts[0] == "defer":
        parts = parts[1:]
    valid = {"none"} | {f"x{a}Y{b}" for a in ("Min", "Mid", "Max") for b in ("Min", "Mid", "Max")}
    # `<align> [meet | slice]` and nothing more; anything else is invalid: the initial value
    if not parts or parts[0] not in valid or parts[1:] not in ([], ["meet"], ["slice"]):
        return "xMidYMid", False
    return parts[0], parts[1:] == ["slice"]


def viewbox_transform(viewbox, aspect, width, height):
    """Matrix mapping the viewBox onto a (0, 0, width, height) viewport."""
    vx, vy, vw, vh = viewbox
    align, slice_ = aspect
    sx, sy = width / vw, height / vh
    if align == "none":
        return (sx, 0.0, 0.0, sy, -vx * sx, -vy * sy)
    s = max(sx, sy) if slice_ else min(sx, sy)
    tx, ty = -vx * s, -vy * s
    dw, dh = width - vw * s, height - vh * s
    tx += {"Min": 0.0, "Mid": dw / 2, "Max": dw}[align[1:4]]
    ty += {"Min": 0.0, "Mid": dh / 2, "Max": dh}[align[5:8]]
    return (s, 0.0, 0.0, s, tx, ty)


def viewbox_transform_f32(viewbox, aspect, width, height):
    """:func:`viewbox_transform` as usvg computes it for a nested viewport, every step in f32
    (tiny-skia's view_box_to_transform): (160 - 100 × 1.2) / 2 is 19.9999962 there, so
    content 10 units into a viewBox of -20 -20 100 100 meeting 120 x 160 sits at 43.9999962
    + 12, and a filter region's edge at 1.5 px per unit falls on row 113, not 114."""
    import numpy as np

    f = np.float32
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        vx, vy, vw, vh = (f(v) for v in viewbox)
        width, height = f(width), f(height)
        align, slice_ = aspect
        sx, sy = f(width / vw), f(height / vh)
        if align != "none":
            sx = sy = max(sx, sy) if slice_ else min(sx, sy)
        tx, ty = f(-vx * sx), f(-vy * sy)
        if align != "none":
            dw, dh = f(width - f(vw * sx)), f(height - f(vh * sy))
            tx = f(tx + {"Min": f(0), "Mid": f(dw / f(2)), "Max": dw}[align[1:4]])
            ty = f(ty + {"Min": f(0), "Mid": f(dh / f(2)), "Max": dh}[align[5:8]])
    return (float(sx), 0.0, 0.0, float(sy), float(tx), float(ty))


#: an <alpha-value>: a number or a percentage, the ``%`` right after the number ("50 %" is two
#: tokens, so no value: CSS Syntax 3 §4.3.3), whitespace around it
_OPACITY = re.compile(rf"[ \t\n\r\f]*({NUMBER_RE})(%?)[ \t\n\r\f]*")


def valid_opacity(value) -> bool:
    """Whether ``value`` is an <alpha-value> (what parse_opacity reads as one)."""
    return _OPACITY.fullmatch(value) is not None


@functools.lru_cache(maxsize=256)
def parse_opacity(value):
    """An opacity property's value clamped to [0, 1]; 1 when it is missing or invalid."""
    m = _OPACITY.fullmatch(value) if value is not None else None
    if m is None:
        return 1.0
    f = float(m.group(1)) / (100 if m.group(2) else 1)
    if not math.isfinite(f):
        return 1.0
    return min(1.0, max(0.0, f))
