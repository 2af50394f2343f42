"""CSS colour values (CSS Color 4): named and system colours, hex forms, rgb()/rgba(),
hsl()/hsla(), hwb(), lab(), lch(), oklab(), oklch(), color() in the predefined RGB and XYZ
spaces, ``transparent``.

:func:`parse_color` returns straight sRGB RGBA floats in [0, 1], ``"currentColor"`` for the
keyword (resolved by the caller, who knows the ``color`` property), or ``None`` when the text is
not a colour. rgb(), hsl() and hwb() channels are clamped to their ranges when parsed (CSS Color
4 §5.1, §7, §8); colours given in a wider space (lab, lch, oklab, oklch, color()) are brought into
sRGB with the CSS gamut-mapping algorithm (§13.2: chroma reduced in OKLCh until clipping is
within a just-noticeable difference). Both syntaxes are read: the legacy one with commas, and the
modern one with spaces, an optional ``/ alpha`` and the ``none`` keyword (= 0).
"""
from __future__ import annotations

import functools
import math
import re

from .units import ANGLE_DEG

NAMED = {
    "aliceblue": (240, 248, 255), "antiquewhite": (250, 235, 215), "aqua": (0, 255, 255),
    "aquamarine": (127, 255, 212), "azure": (240, 255, 255), "beige": (245, 245, 220),
    "bisque": (255, 228, 196), "black": (0, 0, 0), "blanchedalmond": (255, 235, 205),
    "blue": (0, 0, 255), "blueviolet": (138, 43, 226), "brown": (165, 42, 42),
    "burlywood": (222, 184, 135), "cadetblue": (95, 158, 160), "chartreuse": (127, 255, 0),
    "chocolate": (210, 105, 30), "coral": (255, 127, 80), "cornflowerblue": (100, 149, 237),
    "cornsilk": (255, 248, 220), "crimson": (220, 20, 60), "cyan": (0, 255, 255),
    "darkblue": (0, 0, 139), "darkcyan": (0, 139, 139), "darkgoldenrod": (184, 134, 11),
    "darkgray": (169, 169, 169), "darkgreen": (0, 100, 0), "darkgrey": (169, 169, 169),
    "darkkhaki": (189, 183, 107), "darkmagenta": (139, 0, 139), "darkolivegreen": (85, 107, 47),
    "darkorange": (255, 140, 0), "darkorchid": (153, 50, 204), "darkred": (139, 0, 0),
    "darksalmon": (233, 150, 122), "darkseagreen": (143, 188, 143),
    "darkslateblue": (72, 61, 139), "darkslategray": (47, 79, 79),
    "darkslategrey": (47, 79, 79), "darkturquoise": (0, 206, 209), "darkviolet": (148, 0, 211),
    "deeppink": (255, 20, 147), "deepskyblue": (0, 191, 255), "dimgray": (105, 105, 105),
    "dimgrey": (105, 105, 105), "dodgerblue": (30, 144, 255), "firebrick": (178, 34, 34),
    "floralwhite": (255, 250, 240), "forestgreen": (34, 139, 34), "fuchsia": (255, 0, 255),
    "gainsboro": (220, 220, 220), "ghostwhite": (248, 248, 255), "gold": (255, 215, 0),
    "goldenrod": (218, 165, 32), "gray": (128, 128, 128), "grey": (128, 128, 128),
    "green": (0, 128, 0), "greenyellow": (173, 255, 47), "honeydew": (240, 255, 240),
    "hotpink": (255, 105, 180), "indianred": (205, 92, 92), "indigo": (75, 0, 130),
    "ivory": (255, 255, 240), "khaki": (240, 230, 140), "lavender": (230, 230, 250),
    "lavenderblush": (255, 240, 245), "lawngreen": (124, 252, 0),
    "lemonchiffon": (255, 250, 205), "lightblue": (173, 216, 230), "lightcoral": (240, 128, 128),
    "lightcyan": (224, 255, 255), "lightgoldenrodyellow": (250, 250, 210),
    "lightgray": (211, 211, 211), "lightgreen": (144, 238, 144), "lightgrey": (211, 211, 211),
    "lightpink": (255, 182, 193), "lightsalmon": (255, 160, 122),
    "lightseagreen": (32, 178, 170), "lightskyblue": (135, 206, 250),
    "lightslategray": (119, 136, 153), "lightslategrey": (119, 136, 153),
    "lightsteelblue": (176, 196, 222), "lightyellow": (255, 255, 224), "lime": (0, 255, 0),
    "limegreen": (50, 205, 50), "linen": (250, 240, 230), "magenta": (255, 0, 255),
    "maroon": (128, 0, 0), "mediumaquamarine": (102, 205, 170), "mediumblue": (0, 0, 205),
    "mediumorchid": (186, 85, 211), "mediumpurple": (147, 112, 219),
    "mediumseagreen": (60, 179, 113), "mediumslateblue": (123, 104, 238),
    "mediumspringgreen": (0, 250, 154), "mediumturquoise": (72, 209, 204),
    "mediumvioletred": (199, 21, 133), "midnightblue": (25, 25, 112),
    "mintcream": (245, 255, 250), "mistyrose": (255, 228, 225), "moccasin": (255, 228, 181),
    "navajowhite": (255, 222, 173), "navy": (0, 0, 128), "oldlace": (253, 245, 230),
    "olive": (128, 128, 0), "olivedrab": (107, 142, 35), "orange": (255, 165, 0),
    "orangered": (255, 69, 0), "orchid": (218, 112, 214), "palegoldenrod": (238, 232, 170),
    "palegreen": (152, 251, 152), "paleturquoise": (175, 238, 238),
    "palevioletred": (219, 112, 147), "papayawhip": (255, 239, 213),
    "peachpuff": (255, 218, 185), "peru": (205, 133, 63), "pink": (255, 192, 203),
    "plum": (221, 160, 221), "powderblue": (176, 224, 230), "purple": (128, 0, 128),
    "rebeccapurple": (102, 51, 153), "red": (255, 0, 0), "rosybrown": (188, 143, 143),
    "royalblue": (65, 105, 225), "saddlebrown": (139, 69, 19), "salmon": (250, 128, 114),
    "sandybrown": (244, 164, 96), "seagreen": (46, 139, 87), "seashell": (255, 245, 238),
    "sienna": (160, 82, 45), "silver": (192, 192, 192), "skyblue": (135, 206, 235),
    "slateblue": (106, 90, 205), "slategray": (112, 128, 144), "slategrey": (112, 128, 144),
    "snow": (255, 250, 250), "springgreen": (0, 255, 127), "steelblue": (70, 130, 180),
    "tan": (210, 180, 140), "teal": (0, 128, 128), "thistle": (216, 191, 216),
    "tomato": (255, 99, 71), "turquoise": (64, 224, 208), "violet": (238, 130, 238),
    "wheat": (245, 222, 179), "white": (255, 255, 255), "whitesmoke": (245, 245, 245),
    "yellow": (255, 255, 0), "yellowgreen": (154, 205, 50),
}

#: CSS Color 4 §6.2 system colours, with the values of a light default theme
SYSTEM = {
    "canvas": (255, 255, 255), "canvastext": (0, 0, 0), "linktext": (0, 0, 238),
    "visitedtext": (85, 26, 139), "activetext": (255, 0, 0), "buttonface": (240, 240, 240),
    "buttontext": (0, 0, 0), "buttonborder": (118, 118, 118), "field": (255, 255, 255),
    "fieldtext": (0, 0, 0), "highlight": (0, 120, 215), "highlighttext": (255, 255, 255),
    "selecteditem": (0, 120, 215), "selecteditemtext": (255, 255, 255), "mark": (255, 255, 0),
    "marktext": (0, 0, 0), "graytext": (109, 109, 109), "accentcolor": (0, 120, 215),
    "accentcolortext": (255, 255, 255),
}
#: §6.3 deprecated CSS 2 system colours and the system colour each now means
for _old, _new in {
        "activeborder": "buttonborder", "activecaption": "canvas", "appworkspace": "canvas",
        "background": "canvas", "buttonhighlight": "buttonface", "buttonshadow": "buttonface",
        "captiontext": "canvastext", "inactiveborder": "buttonborder",
        "inactivecaption": "canvas", "inactivecaptiontext": "graytext",
        "infobackground": "canvas", "infotext": "canvastext", "menu": "canvas",
        "menutext": "canvastext", "scrollbar": "canvas", "threeddarkshadow": "buttonborder",
        "threedface": "buttonface", "threedhighlight": "buttonborder",
        "threedlightshadow": "buttonborder", "threedshadow": "buttonborder", "window": "canvas",
        "windowframe": "buttonborder", "windowtext": "canvastext"}.items():
    SYSTEM[_old] = SYSTEM[_new]

_FUNC = re.compile(r"^([a-z]+)\(\s*(.*?)\s*\)$", re.I | re.S)
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?(%|deg|rad|grad|turn)?$", re.I)
NONE = "none"


def _clamp(v, lo=0.0, hi=1.0):
    return min(hi, max(lo, v))


def _split(text, max_channels=3):
    """Function arguments → (channel tokens, alpha token or None, legacy comma syntax)."""
    if "," in text:
        parts = [p.strip() for p in text.split(",")]
        if "/" in text or any(not p or len(p.split()) != 1 for p in parts) or len(parts) > 4:
            return None
        return parts[:3], (parts[3] if len(parts) == 4 else None), True
    channels, slash, alpha = text.partition("/")
    channels = channels.split()
    alpha = alpha.split()
    if slash and len(alpha) != 1:
        return None
    if not slash and len(channels) == max_channels + 1:
        alpha = [channels.pop()]   # "rgb(0 0 255 0.5)": the alpha without its slash, as resvg reads it
    return channels, (alpha[0] if alpha else None), False


def _number(token, legacy=False):
    """(value, unit) of a number, percentage or angle; ``none`` is (0, "") in modern syntax."""
    if token.lower() == NONE and not legacy:
        return 0.0, ""
    m = _NUMBER.match(token)
    if not m:
        return None
    unit = (m.group(3) or "").lower()
    return float(token[:len(token) - len(unit)]), unit


def _scaled(token, percent_of, legacy=False):
    """A channel that is a number or a percentage of ``percent_of``."""
    parsed = _number(token, legacy)
    if parsed is None or parsed[1] not in ("", "%"):
        return None
    v, unit = parsed
    return v * percent_of / 100 if unit == "%" else v


def _hue(token, legacy=False):
    parsed = _number(token, legacy)
    if parsed is None or parsed[1] == "%":
        return None
    return parsed[0] * ANGLE_DEG[parsed[1]]


def _hue_to_rgb(h):
    """The fully saturated sRGB colour of hue ``h`` degrees (hsl(h 100% 50%))."""
    return _hsl_to_rgb(h, 1.0, 0.5)


def _hsl_to_rgb(h, s, light):
    """CSS Color 4 §7.1: hsl → sRGB, ``h`` in degrees, ``s`` and ``light`` in [0, 1]."""
    h = (h % 360) / 30

    def f(n):
        k = (n + h) % 12
        a = s * min(light, 1 - light)
        return light - a * max(-1.0, min(k - 3, 9 - k, 1.0))
    return f(0), f(8), f(4)


def _hwb_to_rgb(h, white, black):
    """CSS Color 4 §8.1: whiteness and blackness that add up to 1 or more give a grey."""
    if white + black >= 1:
        grey = white / (white + black)
        return grey, grey, grey
    return tuple(c * (1 - white - black) + white for c in _hue_to_rgb(h))


# -- colour spaces (CSS Color 4 §10, conversions as in its sample code §18) ---------------------
def _inv3(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def _mul(m, v):
    return [m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]]


def _matmul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]


def _white(x, y):
    return [x / y, 1.0, (1 - x - y) / y]


D65 = _white(0.3127, 0.3290)
D50 = _white(0.3457, 0.3585)


def _rgb_to_xyz(primaries, white):
    """Linear RGB → XYZ matrix from the primaries' chromaticities and the white point."""
    cols = [[x / y, 1.0, (1 - x - y) / y] for x, y in primaries]
    p = [[cols[c][r] for c in range(3)] for r in range(3)]
    s = _mul(_inv3(p), white)
    return [[p[r][c] * s[c] for c in range(3)] for r in range(3)]


def _bradford(src, dst):
    """Chromatic adaptation between white points (the Bradford cone response)."""
    cone = [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]
    s, d = _mul(cone, src), _mul(cone, dst)
    scale = [[d[i] / s[i] if i == j else 0.0 for j in range(3)] for i in range(3)]
    return _matmul(_inv3(cone), _matmul(scale, cone))


def _srgb_decode(c):
    a = abs(c)
    return c / 12.92 if a <= 0.04045 else math.copysign(((a + 0.055) / 1.055) ** 2.4, c)


def _srgb_encode(c):
    a = abs(c)
    return 12.92 * c if a <= 0.0031308 else math.copysign(1.055 * a ** (1 / 2.4) - 0.055, c)


def _gamma(g):
    return lambda c: math.copysign(abs(c) ** g, c)


def _prophoto_decode(c):
    return c / 16 if abs(c) <= 16 / 512 else math.copysign(abs(c) ** 1.8, c)


_REC_A, _REC_B = 1.09929682680944, 0.018053968510807


def _rec2020_decode(c):
    a = abs(c)
    if a < _REC_B * 4.5:
        return c / 4.5
    return math.copysign(((a + _REC_A - 1) / _REC_A) ** (1 / 0.45), c)


def _identity(c):
    return c


_SRGB_PRIMARIES = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06))
SRGB_TO_XYZ = _rgb_to_xyz(_SRGB_PRIMARIES, D65)
XYZ_TO_SRGB = _inv3(SRGB_TO_XYZ)
D50_TO_D65 = _bradford(D50, D65)
#: color() spaces: (transfer function to linear light, linear → XYZ D65 matrix)
SPACES = {
    "srgb": (_srgb_decode, SRGB_TO_XYZ),
    "srgb-linear": (_identity, SRGB_TO_XYZ),
    "display-p3": (_srgb_decode, _rgb_to_xyz(((0.680, 0.320), (0.265, 0.690), (0.150, 0.060)),
                                             D65)),
    "a98-rgb": (_gamma(563 / 256), _rgb_to_xyz(((0.64, 0.33), (0.21, 0.71), (0.15, 0.06)), D65)),
    "prophoto-rgb": (_prophoto_decode, _matmul(D50_TO_D65, _rgb_to_xyz(
        ((0.734699, 0.265301), (0.159597, 0.840403), (0.036598, 0.000105)), D50))),
    "rec2020": (_rec2020_decode, _rgb_to_xyz(((0.708, 0.292), (0.170, 0.797), (0.131, 0.046)),
                                             D65)),
    "xyz": (_identity, [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]),
    "xyz-d65": (_identity, [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]),
    "xyz-d50": (_identity, D50_TO_D65),
}
# OKLab (Ottosson 2020, as in CSS Color 4 §9.2): linear sRGB → LMS, then cube roots → Lab
_OK_M1 = [[0.4122214708, 0.5363325363, 0.0514459929], [0.2119034982, 0.6806995451, 0.1073969566],
          [0.0883024619, 0.2817188376, 0.6299787005]]
_OK_M2 = [[0.2104542553, 0.7936177850, -0.0040720468],
          [1.9779984951, -2.4285922050, 0.4505937099],
          [0.0259040371, 0.7827717662, -0.8086757660]]
_OK_M1_INV, _OK_M2_INV = _inv3(_OK_M1), _inv3(_OK_M2)


def _lab_to_linear_srgb(L, a, b):
    """CIE Lab (D50, L in 0..100) → linear sRGB (CSS Color 4 §9.3)."""
    kappa, eps = 24389 / 27, 216 / 24389
    fy = (L + 16) / 116
    fx, fz = a / 500 + fy, fy - b / 200
    x = fx ** 3 if fx ** 3 > eps else (116 * fx - 16) / kappa
    y = fy ** 3 if L > kappa * eps else L / kappa
    z = fz ** 3 if fz ** 3 > eps else (116 * fz - 16) / kappa
    xyz50 = [x * D50[0], y * D50[1], z * D50[2]]
    return _mul(XYZ_TO_SRGB, _mul(D50_TO_D65, xyz50))


def _oklab_to_linear_srgb(L, a, b):
    lms = [c ** 3 for c in _mul(_OK_M2_INV, [L, a, b])]
    return _mul(_OK_M1_INV, lms)


def _linear_srgb_to_oklab(rgb):
    return _mul(_OK_M2, [math.copysign(abs(c) ** (1 / 3), c) for c in _mul(_OK_M1, rgb)])


def _gamut_map(linear):
    """Linear sRGB, possibly out of gamut → sRGB in [0, 1]^3 by CSS Color 4 §13.2.2: hold
    OKLCh lightness and hue, reduce chroma by bisection until clipping the colour moves it less
    than a just-noticeable difference (ΔEOK 0.02)."""
    encode = _srgb_encode
    srgb = [encode(c) for c in linear]
    if all(-1e-6 <= c <= 1 + 1e-6 for c in srgb):
        return [_clamp(c) for c in srgb]
    L, a, b = _linear_srgb_to_oklab(linear)
    if L >= 1:
        return [1.0, 1.0, 1.0]
    if L <= 0:
        return [0.0, 0.0, 0.0]
    chroma, hue = math.hypot(a, b), math.atan2(b, a)
    jnd, epsilon = 0.02, 0.0001

    def at(c):
        return _oklab_to_linear_srgb(L, c * math.cos(hue), c * math.sin(hue))

    def clipped_and_error(lin):
        clip = [_clamp(encode(v)) for v in lin]
        back = _linear_srgb_to_oklab([_srgb_decode(v) for v in clip])
        return clip, math.dist(back, _linear_srgb_to_oklab(lin))

    clip, error = clipped_and_error(linear)
    if error < jnd:
        return clip
    lo, hi, lo_in_gamut = 0.0, chroma, True
    while hi - lo > epsilon:
        mid = (lo + hi) / 2
        current = at(mid)
        if lo_in_gamut and all(-1e-6 <= encode(v) <= 1 + 1e-6 for v in current):
            lo = mid
            continue
        clip, error = clipped_and_error(current)
        if error < jnd:
            if jnd - error < epsilon:
                return clip
            lo_in_gamut = False
            lo = mid
        else:
            hi = mid
    return clip


def _alpha(token, legacy=False):
    value = _scaled(token, 1.0, legacy)
    return None if value is None else _clamp(value)


def _function(func, body):
    """sRGB RGB floats of a colour function's channels, or None."""
    split = _split(body, 4 if func == "color" else 3)
    if split is None:
        return None
    channels, alpha_token, legacy = split
    if func == "color":
        if legacy or len(channels) != 4 or channels[0].lower() not in SPACES:
            return None
        decode, to_xyz = SPACES[channels[0].lower()]
        values = [_scaled(t, 1.0) for t in channels[1:]]
        if None in values:
            return None
        rgb = _gamut_map(_mul(XYZ_TO_SRGB, _mul(to_xyz, [decode(v) for v in values])))
    elif len(channels) != 3:
        return None
    elif func in ("rgb", "rgba"):
        values = [_scaled(t, 255.0, legacy) for t in channels]
        if None in values:
            return None
        rgb = [_clamp(v / 255) for v in values]
    elif func in ("hsl", "hsla", "hwb"):
        if legacy and func == "hwb":
            return None
        h = _hue(channels[0], legacy)
        s, light = (_scaled(t, 100.0, legacy) for t in channels[1:])
        if None in (h, s, light):
            return None
        if func == "hwb":
            rgb = _hwb_to_rgb(h, _clamp(s / 100), _clamp(light / 100))
        else:
            rgb = _hsl_to_rgb(h, _clamp(s / 100), _clamp(light / 100))
    elif func in ("lab", "lch", "oklab", "oklch") and not legacy:
        ok = func.startswith("ok")
        L = _scaled(channels[0], 1.0 if ok else 100.0)
        if func.endswith("lab"):
            a, b = (_scaled(t, 0.4 if ok else 125.0) for t in channels[1:])
        else:
            c, h = _scaled(channels[1], 0.4 if ok else 150.0), _hue(channels[2])
            if None in (c, h):
                return None
            c = max(c, 0.0)
            a, b = c * math.cos(math.radians(h)), c * math.sin(math.radians(h))
        if None in (L, a, b):
            return None
        L = _clamp(L, 0.0, 1.0 if ok else 100.0)
        rgb = _gamut_map((_oklab_to_linear_srgb if ok else _lab_to_linear_srgb)(L, a, b))
    else:
        return None
    alpha = 1.0
    if alpha_token is not None:
        # resvg (svgtypes) rejects a percentage alpha in the comma-separated rgb form, so
        # rgba(0, 127, 0, 50%) is an invalid colour there; the CSS 4 form "/ 50%" is kept.
        if legacy and func.startswith("rgb") and alpha_token.endswith("%"):
            return None
        alpha = _alpha(alpha_token, legacy)
        if alpha is None:
            return None
    return (*(float(c) for c in rgb), alpha)


# -- colours in SVG documents, as resvg reads them ----------------------------------------------
# resvg (svgtypes) reads an SVG 1.1 colour grammar: names (with ``transparent``), hex forms and
# rgb()/rgba()/hsl()/hsla() with commas or spaces between the channels. The first rgb() channel
# decides its kind: after a percentage the others are numbers or percentages (a number n counts
# as n × 255), after a number they must be numbers. Channels round and clamp to 8 bits; the
# alpha is a number. CSS Color 4's other forms (a ``/`` alpha, a percentage alpha, angle units,
# hwb(), lab(), color(), system colours) are invalid there: an invalid fill paints black, an
# invalid stroke none. Documents are read this way so that they render as resvg renders them;
# parse_color above reads the full CSS Color 4 syntax for colours given as options.
_SVG_NUMBER = re.compile(r"[ \t\n\r]*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE](?![mx])[+-]?\d+)?)")
_SVG_SPACES = re.compile(r"[ \t\n\r]*")
_SVG_IDENT = re.compile(r"[0-9A-Za-z_-]*")


_HEX_DIGITS = re.compile(r"[0-9A-Fa-f]*")


def _hex_color(h: str):
    """#RGB, #RGBA, #RRGGBB or #RRGGBBAA (the digits after the #) as floats, else None."""
    if len(h) not in (3, 4, 6, 8):
        return None
    if len(h) in (3, 4):
        h = "".join(c * 2 for c in h)
    vals = [int(h[i:i + 2], 16) / 255 for i in range(0, len(h), 2)]
    return tuple(vals) if len(vals) == 4 else (*vals, 1.0)


def _byte(v):
    """A channel in [0, 1] as svgtypes stores it: rounded half away from zero, saturated.
    Saturated before rounding: a number like 1e999 reads as infinity, which floor refuses."""
    return math.floor(min(255.0, max(0.0, v + 0.5))) / 255


class _SvgColorReader:
    """svgtypes' colour stream: numbers, spaces and optional commas between list items."""

    def __init__(self, text):
        self.text, self.pos = text, 0

    def spaces(self):
        self.pos = _SVG_SPACES.match(self.text, self.pos).end()

    def number(self):
        m = _SVG_NUMBER.match(self.text, self.pos)
        if m is None:
            raise ValueError
        self.pos = m.end()
        return float(m.group(1))

    def percent(self):
        if self.text.startswith("%", self.pos):
            self.pos += 1
            return True
        return False

    def separator(self):
        self.spaces()
        if self.text.startswith(",", self.pos):
            self.pos += 1

    def list_number(self, percent_allowed=False):
        if self.pos >= len(self.text):
            raise ValueError
        n = self.number()
        if percent_allowed and self.percent():
            n /= 100
        self.separator()
        return n

    def expect(self, char):
        if not self.text.startswith(char, self.pos):
            raise ValueError
        self.pos += 1

    def alpha(self):
        self.spaces()
        if self.text.startswith(")", self.pos):
            return 1.0
        return _byte(self.list_number() * 255)

    def color(self):
        self.spaces()
        if self.text.startswith("#", self.pos):
            m = _HEX_DIGITS.match(self.text, self.pos + 1)
            self.pos = m.end()
            color = _hex_color(m.group())
            if color is None:
                raise ValueError
            return color
        m = _SVG_IDENT.match(self.text, self.pos)
        self.pos = m.end()
        name = m.group().lower()
        if name in ("rgb", "rgba"):
            self.expect("(")
            first = self.number()
            if self.percent():
                self.separator()
                rgb = [_byte(first / 100 * 255)]
                rgb += [_byte(self.list_number(True) * 255) for _ in range(2)]
            else:
                self.separator()
                rgb = [_byte(first)] + [_byte(self.list_number()) for _ in range(2)]
        elif name in ("hsl", "hsla"):
            self.expect("(")
            hue = self.list_number() % 360
            s, light = (_clamp(self.list_number(True)) for _ in range(2))
            rgb = [_byte(c * 255) for c in _hsl_to_rgb(hue, s, light)]
        elif name in NAMED or name == "transparent":
            self.spaces()
            if name == "transparent":
                return (0.0, 0.0, 0.0, 0.0)
            return (*(c / 255 for c in NAMED[name]), 1.0)
        else:
            raise ValueError
        alpha = self.alpha()
        self.spaces()
        self.expect(")")
        return (*rgb, alpha)


@functools.lru_cache(maxsize=4096)
def parse_svg_color(text: str):
    """A colour in an SVG document (fill, stroke, stop-color, flood-color, lighting-color,
    color, CSS filter functions), read as resvg reads it (see above): (r, g, b, a) floats, the
    string "currentColor" (the keyword, case-sensitive as in resvg), or None when invalid.
    Answers are kept by text (immutable values; the tiger reads ≈ 100 colours a load, of
    which a few dozen differ)."""
    return _parse_svg_color(text)


def _parse_svg_color(text: str):
    s = text.strip()
    if s == "currentColor":
        return "currentColor"
    reader = _SvgColorReader(s)
    try:
        color = reader.color()
    except ValueError:
        return None
    reader.spaces()
    return color if reader.pos == len(s) and s else None


def parse_color(text: str):
    """Parse a CSS colour. Returns (r, g, b, a) floats, the string "currentColor", or None."""
    s = text.strip()
    if not s:
        return None
    low = s.lower()
    if low == "currentcolor":
        return "currentColor"
    if low == "transparent":
        return (0.0, 0.0, 0.0, 0.0)
    named = NAMED.get(low) or SYSTEM.get(low)
    if named:
        r, g, b = named
        return (r / 255, g / 255, b / 255, 1.0)
    if s[0] == "#":
        return _hex_color(s[1:]) if _HEX_DIGITS.fullmatch(s[1:]) else None
    m = _FUNC.match(s)
    if not m:
        return None
    return _function(m.group(1).lower(), m.group(2))
