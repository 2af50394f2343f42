"""SVG ``<text>``: characters → fonts → HarfBuzz → positioned glyph outlines → scene fills.

The steps follow SVG 1.1 §10 as resvg (usvg) implements them:

1. *Collect* the characters of ``<text>`` with their innermost element (``tspan``, ``tref``,
   ``textPath``, ``a``), collapsing white space unless ``xml:space="preserve"``.
2. *Position attributes*: ``x``, ``y``, ``dx``, ``dy``, ``rotate`` lists address characters in
   order from the element that carries them; inner elements override outer ones.
3. *Chunks*: every character with an absolute ``x`` or ``y`` (and every ``textPath``) starts a
   text chunk, the unit of ``text-anchor``.
4. *Fonts*: per character, the CSS font-family list is matched in the font database
   (:mod:`vecmsaa.fonts.db`); characters the face lacks fall back to other faces.
5. *Shaping*: runs of one face and font settings are shaped by HarfBuzz (kerning, ligatures,
   marks, bidi runs) with the chunk's text as context.
6. *Placement*: pen advance with letter/word spacing, dx/dy, baseline shifts, rotate, textPath
   (glyph midpoints on the path, tangent rotation), textLength, vertical writing modes.
7. *Drawing*: glyph outlines (user units) grouped by element are filled and stroked through
   the builder (``ctx.draw``), with text decorations as rectangles under/over the glyphs.
"""
from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field

import numpy as np

from ..fonts import FontError
from ..fonts.db import FontDatabase, database_from_options, parse_family_list
from ..fonts.layout import glyphs_arrays
from ..fonts.shape import bidi_runs, shape_run, visual_order
from ..path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path, compose, rect_path

TEXT_CONTENT = {"tspan", "tref", "textPath", "a"}
WEIGHTS = {"normal": 400, "bold": 700}
STRETCHES = {"ultra-condensed": 50.0, "extra-condensed": 62.5, "condensed": 75.0,
             "semi-condensed": 87.5, "normal": 100.0, "semi-expanded": 112.5,
             "expanded": 125.0, "extra-expanded": 150.0, "ultra-expanded": 200.0}
SPACES = {" ", "\u00a0", "\u3000"}


# -- 1. characters ---------------------------------------------------------------------------
@dataclass
class Char:
    ch: str
    el: object                 # innermost text content element
    chain: tuple               # elements from <text> to ``el``
    preserve: bool
    x: float | None = None
    y: float | None = None
    dx: float = 0.0
    dy: float = 0.0
    rotate: float = 0.0
    text_path: object = None   # the enclosing <textPath> element
    new_chunk: bool = False


def _space_preserved(el, inherited):
    v = el.get("xml:space", el.get("space"))
    if v == "preserve":
        return True
    if v == "default":
        return False
    return inherited


def collect_chars(text_el, ctx, styles):
    """All characters of a <text> element with their element chains (before white-space)."""
    out = []

    def add(string, el, chain, preserve, text_path):
        for ch in string:
            out.append(Char(ch, el, chain, preserve, text_path=text_path))

    def walk(el, chain, style, preserve, text_path):
        styles[id(el)] = style
        add(el.text, el, chain, preserve, text_path)
        for child in el.children:
            if child.tag in TEXT_CONTENT and _conditions(child):
                cstyle = style.child(child)
                if cstyle.get("display").strip() != "none":
                    cpres = _space_preserved(child, preserve)
                    tp = text_path
                    if child.tag == "textPath":
                        # A textPath inside a textPath is ignored (with its text).
                        if text_path is None:
                            tp = child
                            walk(child, chain + (child,), cstyle, cpres, tp)
                    elif child.tag == "tref":
                        styles[id(child)] = cstyle
                        target = _lookup(child)
                        if target is not None:
                            add(_all_text(target), child, chain + (child,), cpres, tp)
                    else:
                        walk(child, chain + (child,), cstyle, cpres, tp)
            add(child.tail, el, chain, preserve, text_path)

    walk(text_el, (text_el,), ctx.style, _space_preserved(text_el, False), None)
    return out


def _conditions(el):
    from .builder import conditions_pass
    return conditions_pass(el)


def _lookup(el):
    ref = (el.get("href") or "").strip()
    if not ref.startswith("#") or el.source is None:
        return None
    return el.source.lookup(ref)


def _all_text(el):
    parts = [el.text]
    for c in el.children:
        parts.append(_all_text(c))
        parts.append(c.tail)
    return "".join(parts)


def collapse_white_space(chars):
    """SVG 1.1 xml:space: default drops newlines, turns tabs into spaces, strips leading and
    trailing spaces and collapses runs of spaces (across element boundaries); ``preserve``
    turns newlines and tabs into spaces and keeps everything."""
    out = []
    for c in chars:
        if c.preserve:
            if c.ch in "\n\r\t":
                c.ch = " "
            out.append(c)
            continue
        if c.ch in "\n\r":
            continue
        if c.ch == "\t":
            c.ch = " "
        if c.ch == " " and (not out or out[-1].ch == " "):
            continue
        out.append(c)
    while out and out[-1].ch == " " and not out[-1].preserve:
        out.pop()
    return out


# -- 2. position attributes -------------------------------------------------------------------
def _numbers(text):
    return [t for t in re.split(r"[\s,]+", (text or "").strip()) if t]


def apply_positions(text_el, chars, ctx, styles):
    """x/y/dx/dy/rotate lists, outer elements first so inner ones override."""
    order = []

    def walk(el):
        order.append(el)
        for c in el.children:
            if c.tag in TEXT_CONTENT:
                walk(c)
    walk(text_el)
    by_el = {}
    for i, c in enumerate(chars):
        for e in c.chain:
            by_el.setdefault(id(e), []).append(i)
    for el in order:
        idx = by_el.get(id(el))
        if not idx:
            continue
        style = styles.get(id(el), ctx.style)
        if el.tag != "textPath":
            for name, axis in (("x", "x"), ("y", "y"), ("dx", "x"), ("dy", "y")):
                vals = _numbers(el.get(name))
                for k, tok in zip(idx, vals):
                    v = ctx.length(tok, axis, style)
                    if v is not None:
                        setattr(chars[k], name, v)
        rot = []
        for tok in _numbers(el.get("rotate")):
            try:
                r = float(tok)
            except ValueError:
                rot = []
                break
            rot.append(r if math.isfinite(r) else 0.0)
        if rot:
            for j, k in enumerate(idx):
                chars[k].rotate = rot[min(j, len(rot) - 1)]


# -- 4. fonts ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class FontSpec:
    families: tuple
    weight: int
    style: str
    stretch: float
    size: float
    features: tuple
    variations: tuple
    letter_spacing: float
    word_spacing: float
    small_caps: bool


def _weight(style):
    """Computed font-weight, resolving bolder/lighter against the parent (CSS Fonts 3)."""
    v = (style.specified.get("font-weight") or "").strip()
    parent = _weight(style.parent) if style.parent is not None else 400
    if not v or v == "inherit":
        return parent
    if v in WEIGHTS:
        return WEIGHTS[v]
    if v == "bolder":
        return 400 if parent < 350 else 700 if parent < 550 else 900
    if v == "lighter":
        return 100 if parent < 550 else 400 if parent < 750 else 700
    try:
        w = float(v)
    except ValueError:
        return parent
    return int(w) if 1 <= w <= 1000 else parent


def _stretch(style):
    v = (style.get("font-stretch") or "normal").strip()
    if v in STRETCHES:
        return STRETCHES[v]
    if v.endswith("%"):
        try:
            return float(v[:-1])
        except ValueError:
            pass
    return 100.0


def _font_style(style):
    v = (style.get("font-style") or "normal").strip().split()
    return v[0] if v and v[0] in ("italic", "oblique") else "normal"


def _quoted_settings(text, default_value):
    """``"liga" 0, 'wght' 700`` → [(tag, value)]."""
    out = []
    for item in (text or "").split(","):
        m = re.match(r"""\s*["']([^"']{4})["']\s*(\S*)\s*$""", item)
        if not m:
            continue
        val = m.group(2)
        if val in ("", "on"):
            value = default_value
        elif val == "off":
            value = 0
        else:
            try:
                value = float(val)
            except ValueError:
                continue
        out.append((m.group(1), value))
    return out


def font_spec(style, ctx, chain=()) -> FontSpec:
    """Font settings of a text content element; ``chain`` is it and its ancestors, innermost
    last (the SVG 1.1 ``kerning`` attribute is looked up along it)."""
    families = parse_family_list(style.get("font-family") or "serif")
    features = {}
    for tag, value in _quoted_settings(style.get("font-feature-settings"), 1):
        features[tag] = int(value)
    # resvg honours SVG 1.1 kerning="0", and font-kerning only from CSS (it is not a
    # presentation attribute there).
    for el in reversed(chain):
        value = el.specified.get("font-kerning")
        if value is None:
            continue
        from_attribute = el.get("font-kerning") is not None and "font-kerning" not in (
            el.get("style") or "")
        if not from_attribute and value.strip() == "none":
            features["kern"] = 0
        break
    for el in reversed(chain):
        kerning = el.get("kerning")
        if kerning is not None:
            if kerning.strip() in ("0", "0px"):
                features["kern"] = 0
            break
    variant = (style.get("font-variant") or "normal").strip()
    caps = (style.get("font-variant-caps") or "normal").strip()
    small_caps = variant == "small-caps" or caps == "small-caps"
    if small_caps:
        features["smcp"] = 1
    variations = dict(_quoted_settings(style.get("font-variation-settings"), 1))
    size = style.font_size()
    letter = _spacing(style.get("letter-spacing"), ctx, style)
    word = _spacing(style.get("word-spacing"), ctx, style)
    if letter:
        # CSS: letter-spacing turns off optional ligatures.
        features.setdefault("liga", 0)
        features.setdefault("clig", 0)
    return FontSpec(tuple(families), _weight(style), _font_style(style), _stretch(style), size,
                    tuple(sorted(features.items())), tuple(sorted(variations.items())), letter,
                    word, small_caps)


def _spacing(value, ctx, style):
    v = (value or "normal").strip()
    if v == "normal":
        return 0.0
    return ctx.length(v, "x", style, 0.0) or 0.0


def font_database(ctx) -> FontDatabase:
    return database_from_options(ctx.font_options)


def face_location(face, spec):
    """Variation location: font-variation-settings, else wght/wdth/slnt from the CSS props."""
    if not face.axes:
        return ()
    loc = {}
    if "wght" in face.axes:
        loc["wght"] = spec.weight
    if "wdth" in face.axes:
        loc["wdth"] = spec.stretch
    if "opsz" in face.axes:
        loc["opsz"] = spec.size
    loc.update(dict(spec.variations))
    return face.clamp_location(loc)


def assign_faces(chars, specs, db):
    """Face for every character: the family list's best match, else a fallback face."""
    faces = []
    primary = {}
    for c, spec in zip(chars, specs):
        key = (spec.families, spec.weight, spec.style, spec.stretch)
        info = primary.get(key)
        if key not in primary:
            info = db.query_or_default(list(spec.families), spec.weight, spec.style,
                                       spec.stretch)
            primary[key] = info
        face = _load(info)
        if face is not None and not face.has_char(c.ch) and not _is_control(c.ch):
            alt = db.fallback_for_char(c.ch, list(spec.families), spec.weight, spec.style,
                                       spec.stretch, exclude=(info,))
            if alt is not None:
                face = _load(alt) or face
        faces.append(face)
    # Combining marks stay with their base character's face when that face has them.
    for i in range(1, len(chars)):
        if unicodedata.category(chars[i].ch).startswith("M") and faces[i - 1] is not None \
                and faces[i - 1].has_char(chars[i].ch):
            faces[i] = faces[i - 1]
    return faces


def _is_control(ch):
    return unicodedata.category(ch) in ("Cc", "Cf", "Zs") and ch != "\u00a0"


def _load(info):
    if info is None:
        return None
    try:
        return info.load()
    except FontError:
        return None


# -- 5/6. shaping and placement ----------------------------------------------------------------
@dataclass
class Glyph:
    face: object
    location: tuple
    gid: int
    char: int                 # index of its cluster's first character
    advance: float            # user units along the line
    x: float = 0.0            # pen position (user units)
    y: float = 0.0
    off_x: float = 0.0
    off_y: float = 0.0
    scale: float = 1.0        # user units per font unit
    rotate: float = 0.0       # degrees
    matrix: tuple | None = None   # font units → user units, when done
    cluster_start: bool = True
    hidden: bool = False
    advance_v: float = 0.0    # vertical writing: pen advance down the column
    path_anchor: float = 0.0  # textPath: text-anchor shift along the path
    sx: float = 1.0           # lengthAdjust=spacingAndGlyphs horizontal scale
    spacing: float = 0.0      # letter/word spacing added after this cluster
    size: float = 0.0         # font size in user units
    frame: tuple = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)   # cluster frame: origin and direction
    shifted: bool = False     # moved by dx/dy/rotate or on a path (breaks decorations)


def shape_chunk(chars, faces, specs, start, end, direction):
    """Glyphs of chars[start:end] in visual order."""
    text = "".join(c.ch for c in chars)
    glyphs = []
    for s, e, d in visual_order(bidi_runs(text[start:end], direction), direction):
        s, e = s + start, e + start
        pieces = []
        k = s
        while k < e:
            j = k + 1
            key = (id(faces[k]), specs[k].size, specs[k].features, specs[k].variations)
            while j < e and (id(faces[j]), specs[j].size, specs[j].features,
                             specs[j].variations) == key:
                j += 1
            pieces.append((k, j))
            k = j
        if d == "rtl":
            pieces.reverse()
        for a, b in pieces:
            face = faces[a]
            if face is None:
                continue
            spec = specs[a]
            loc = face_location(face, spec)
            run = shape_run(face, text, a, b, location=loc, features=dict(spec.features),
                            direction=d)
            scale = spec.size / face.units_per_em
            prev = None
            for gid, cl, adv, off in zip(run.gids, run.clusters, run.advances, run.offsets):
                glyphs.append(Glyph(face, loc, int(gid), int(cl), float(adv[0]) * scale,
                                    off_x=float(off[0]) * scale, off_y=float(off[1]) * scale,
                                    scale=scale, cluster_start=int(cl) != prev,
                                    size=spec.size))
                prev = int(cl)
    return glyphs


def baseline_offset(style, face, spec, root_style):
    """Shift (user units, positive = down) of the baseline for dominant-/alignment-baseline
    and baseline-shift of this element and its ancestors."""
    m = face.metrics
    scale = spec.size / face.units_per_em
    shift = 0.0
    align = (style.get("alignment-baseline") or "auto").strip()
    base = align if align not in ("auto", "baseline") else (
        style.get("dominant-baseline") or "auto").strip()
    table = {
        "middle": m.x_height / 2, "central": (m.ascender + m.descender) / 2,
        "hanging": m.ascender * 0.8, "mathematical": m.ascender * 0.5,
        "text-top": m.ascender, "text-before-edge": m.ascender,
        "text-bottom": m.descender, "text-after-edge": m.descender,
        "ideographic": m.descender, "before-edge": m.ascender, "after-edge": m.descender,
    }
    if base in table:
        shift += table[base] * scale
    # baseline-shift accumulates over the ancestors that set it
    s = style
    total = 0.0
    # baseline-shift of the text content elements; on <text> itself it is ignored (resvg)
    while s is not None and s is not root_style:
        v = (s.specified.get("baseline-shift") or "").strip()
        if v and v not in ("baseline", "inherit"):
            fs = s.font_size()
            if v == "sub":
                total -= _os2(face, "ySubscriptYOffset", 0.2 * face.units_per_em) * fs \
                    / face.units_per_em
            elif v == "super":
                total += _os2(face, "ySuperscriptYOffset", 0.34 * face.units_per_em) * fs \
                    / face.units_per_em
            elif v.endswith("%"):
                try:
                    total += float(v[:-1]) / 100 * fs
                except ValueError:
                    pass
            else:
                from .units import split_length, to_px
                parsed = split_length(v)
                if parsed is not None:
                    total += to_px(parsed[0], parsed[1], fs)
        s = s.parent
    return shift - total


def _os2(face, name, default):
    t = face.ttfont
    if "OS/2" in t:
        v = getattr(t["OS/2"], name, None)
        if v:
            return abs(v)
    return default


# -- textPath ---------------------------------------------------------------------------------
# Gauss–Legendre nodes and weights on [-1, 1] for arc lengths of cubic segments.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)


class PathWalker:
    """Points and tangents of a path at arc lengths, located the way resvg does.

    resvg turns every segment into a cubic (a line becomes a cubic with its inner control
    points at 0.33 and 0.66) and finds the parameter for an arc length with kurbo's ITP root
    finder stopped at a fixed accuracy (0.5 user units over the text's scale). That tolerance
    moves glyphs by up to a third of a pixel, visibly, so the same search is done here.
    """

    def __init__(self, path: Path, scale: float = 1.0):
        self.accuracy = 0.5 / max(scale, 1.0)
        self.cubics = []
        v, p = path.verbs, path.points
        i = 0
        cur = start = None
        for verb in v:
            k = VERB_POINTS[verb]
            q = p[i:i + k]
            i += k
            if verb == MOVE:
                cur = start = q[0]
                continue
            if verb == LINE or (verb == CLOSE and start is not None):
                end = q[0] if verb == LINE else start
                c = np.array([cur, cur + (end - cur) * 0.33, cur + (end - cur) * 0.66, end])
            elif verb == QUAD:
                c = np.array([cur, cur + 2 / 3 * (q[0] - cur), q[1] + 2 / 3 * (q[0] - q[1]),
                              q[1]])
            elif verb == CUBIC:
                c = np.array([cur, q[0], q[1], q[2]])
            else:
                continue
            self.cubics.append(c)
            cur = c[3]
        self.lengths = [self._arclen(c, 1.0) for c in self.cubics]
        self.length = float(sum(self.lengths))

    @staticmethod
    def _deriv(c, t):
        t = np.asarray(t)[..., None]
        return 3 * ((1 - t) ** 2 * (c[1] - c[0]) + 2 * t * (1 - t) * (c[2] - c[1])
                    + t ** 2 * (c[3] - c[2]))

    def _arclen(self, c, t1):
        u = (_GL_X + 1) / 2 * t1
        return float(np.sum(_GL_W * np.hypot(*self._deriv(c, u).T)) * t1 / 2)

    def _inv_arclen(self, c, total, arc):
        """kurbo's ParamCurveArclen::inv_arclen: ITP search to ``accuracy``."""
        if arc <= 0:
            return 0.0
        if arc >= total:
            return 1.0
        eps = self.accuracy / total
        a, b = 0.0, 1.0
        ya, yb = -arc, total - arc
        n_half = max(math.ceil(math.log2((b - a) / eps)) - 1, 0)
        scaled = eps * float(1 << (1 + n_half))
        k1 = 0.2
        while b - a > 2 * eps:
            mid = 0.5 * (a + b)
            r = scaled - 0.5 * (b - a)
            xf = (yb * a - ya * b) / (yb - ya)
            sigma = mid - xf
            delta = k1 * (b - a) ** 2
            xt = xf + math.copysign(delta, sigma) if delta <= abs(mid - xf) else mid
            x = xt if abs(xt - mid) <= r else mid - math.copysign(r, sigma)
            y = self._arclen(c, x) - arc
            if y > 0:
                b, yb = x, y
            elif y < 0:
                a, ya = x, y
            else:
                return x
            scaled *= 0.5
        return 0.5 * (a + b)

    def at(self, s):
        """(x, y, tangent angle in degrees) at arc length s, or None off the path."""
        if s < 0:
            return None
        length = 0.0
        for c, L in zip(self.cubics, self.lengths):
            if length <= s <= length + L:
                t = min(max(self._inv_arclen(c, L, s - length), 0.0), 1.0)
                u = 1 - t
                pt = u ** 3 * c[0] + 3 * u * u * t * c[1] + 3 * u * t * t * c[2] + t ** 3 * c[3]
                d = self._deriv(c, t)
                return float(pt[0]), float(pt[1]), math.degrees(math.atan2(d[1], d[0]))
            length += L
        return None


# -- the entry point ----------------------------------------------------------------------------
def build_text(element, ctx):
    """Scene nodes of one ``<text>`` element (see the module doc)."""
    styles = {}
    chars = collect_chars(element, ctx, styles)
    chars = collapse_white_space(chars)
    if not chars:
        return []
    apply_positions(element, chars, ctx, styles)
    db = font_database(ctx)
    spec_cache = {}
    specs = []
    for c in chars:
        s = spec_cache.get(id(c.el))
        if s is None:
            chain = tuple(reversed(list(element.ancestors()))) + c.chain
            s = spec_cache[id(c.el)] = font_spec(styles[id(c.el)], ctx, chain)
        specs.append(s)
    faces = assign_faces(chars, specs, db)
    if all(f is None for f in faces):
        return []
    root_style = ctx.style
    direction = (root_style.get("direction") or "ltr").strip()
    direction = "rtl" if direction == "rtl" else "ltr"
    writing = (root_style.get("writing-mode") or "lr").strip()
    vertical = writing in ("tb", "tb-rl", "vertical-rl", "vertical-lr")

    # chunks
    bounds = []
    for i, c in enumerate(chars):
        starts = i == 0 or c.x is not None or c.y is not None or (
            c.text_path is not chars[i - 1].text_path)
        if starts:
            bounds.append(i)
    bounds.append(len(chars))

    placed = []
    pen_x = pen_y = 0.0
    for a, b in zip(bounds[:-1], bounds[1:]):
        first = chars[a]
        if first.text_path is not None:
            # On a path, x is an offset along it and y is ignored (as in resvg).
            pen_x, pen_y = first.x or 0.0, 0.0
        else:
            if first.x is not None:
                pen_x = first.x
            if first.y is not None:
                pen_y = first.y
        glyphs = shape_chunk(chars, faces, specs, a, b, direction)
        if glyphs:
            glyphs[0].shifted = True     # a chunk starts a new decoration line
        pen_x, pen_y = place_chunk(glyphs, chars, specs, styles, a, b, pen_x, pen_y,
                                   vertical, direction, ctx)
        placed.append((a, b, glyphs))
    # textLength on the <text> element and tspans
    apply_text_length(element, chars, placed, ctx, styles)
    # textPath placement
    for a, b, glyphs in placed:
        tp = chars[a].text_path
        if tp is not None:
            place_on_path(tp, glyphs, chars, ctx, styles)
    for _, _, glyphs in placed:
        for g in glyphs:
            if g.matrix is None:
                g.frame = compose(_translate(g.x, g.y), _rotate_at(g.rotate, 0.0, 0.0))
                g.matrix = compose(g.frame, (g.scale * g.sx, 0.0, 0.0, -g.scale, g.off_x,
                                             -g.off_y))
    return draw_glyphs(element, chars, placed, ctx, styles, vertical)


def place_chunk(glyphs, chars, specs, styles, a, b, pen_x, pen_y, vertical, direction, ctx):
    """Pen positions of one chunk's glyphs, then text-anchor; returns the new pen."""
    x0, y0 = pen_x, pen_y
    x, y = pen_x, pen_y
    done_dxdy = set()
    for g in glyphs:
        c = chars[g.char]
        spec = specs[g.char]
        if g.cluster_start and g.char not in done_dxdy:
            done_dxdy.add(g.char)
            x += c.dx
            y += c.dy
            g.shifted = g.shifted or bool(c.dx or c.dy or c.rotate)
        style = styles[id(c.el)]
        shift = baseline_offset(style, g.face, spec, ctx.style)
        if vertical:
            g.x, g.y = x, y
            _vertical_glyph(g, spec, shift)
            y += g.advance_v
        else:
            g.x, g.y = x, y + shift
            g.rotate = c.rotate
            x += g.advance
        if g.cluster_start:
            extra = spec.letter_spacing
            if c.ch in SPACES:
                extra += spec.word_spacing
            g.spacing = extra
            if vertical:
                y += extra
            else:
                x += extra
    # text-anchor of the chunk (the style of its first character's element)
    anchor = (styles[id(chars[a].el)].get("text-anchor") or "start").strip()
    if direction == "rtl" and not vertical:
        anchor = {"start": "end", "end": "start"}.get(anchor, anchor)
    width = (y - y0) if vertical else (x - x0)
    k = {"middle": 0.5, "end": 1.0}.get(anchor, 0.0)
    if k and chars[a].text_path is None:
        for g in glyphs:
            if vertical:
                g.y -= width * k
            else:
                g.x -= width * k
        if vertical:
            y -= width * k
        else:
            x -= width * k
    elif k:
        for g in glyphs:
            g.path_anchor = width * k
    return x, y


def _vertical_glyph(g, spec, shift):
    """Vertical writing: upright CJK, other glyphs turned 90° clockwise (text-orientation:
    mixed); the pen moves down by the advance."""
    face = g.face
    m = face.metrics
    cp = face.reverse_cmap.get(g.gid)
    upright = cp is not None and _is_upright(cp)
    if upright:
        g.advance_v = spec.size   # one em per ideograph
        # centre the glyph horizontally on the pen, top at the pen
        g.x -= g.advance / 2
        g.y += m.ascender * g.scale
        g.off_x = 0.0
        g.off_y = 0.0
    else:
        g.advance_v = g.advance
        g.rotate = 90.0
        # rotated: the baseline runs down the column, centred on its central baseline
        central = (m.ascender + m.descender) / 2 * g.scale
        g.x -= central
        g.off_x, g.off_y = 0.0, 0.0


def _is_upright(cp):
    return (0x1100 <= cp <= 0x11FF or 0x2E80 <= cp <= 0xA4CF or 0xAC00 <= cp <= 0xD7AF
            or 0xF900 <= cp <= 0xFAFF or 0xFE30 <= cp <= 0xFE4F or 0xFF00 <= cp <= 0xFFEF
            or 0x1F000 <= cp <= 0x1FAFF or 0x20000 <= cp <= 0x3FFFF)



def apply_text_length(text_el, chars, placed, ctx, styles):
    """textLength/lengthAdjust on <text> (whole text) and on tspans (their characters)."""
    targets = [text_el]

    def walk(el):
        for c in el.children:
            if c.tag in TEXT_CONTENT:
                if c.get("textLength") is not None:
                    targets.append(c)
                walk(c)
    walk(text_el)
    for el in targets:
        value = el.get("textLength")
        if value is None:
            continue
        length = ctx.length(value, "x", styles.get(id(el), ctx.style))
        if length is None or length < 0:
            continue
        gl = [g for _, _, gs in placed for g in gs
              if any(e is el for e in chars[g.char].chain)]
        if not gl:
            continue
        x0 = min(g.x for g in gl)
        x1 = max(g.x + g.advance for g in gl)
        natural = x1 - x0
        if natural <= 0:
            continue
        adjust = (el.get("lengthAdjust") or "spacing").strip()
        if adjust == "spacingAndGlyphs":
            k = length / natural
            for g in gl:
                g.x = x0 + (g.x - x0) * k
                g.off_x *= k
                g.sx = k
        else:
            clusters = sorted({g.char for g in gl})
            if len(clusters) < 2:
                continue
            step = (length - natural) / (len(clusters) - 1)
            rank = {c: i for i, c in enumerate(clusters)}
            for g in gl:
                g.x += step * rank[g.char]
        # Glyphs after the adjusted element in the same chunk move with its end.
        delta = length - natural
        last = max(g.char for g in gl)
        for _, _, gs in placed:
            if any(g in gl for g in gs):
                for g in gs:
                    if g.char > last:
                        g.x += delta


def place_on_path(tp, glyphs, chars, ctx, styles):
    """Glyphs along a textPath: each glyph's midpoint on the path, rotated to its tangent."""
    target = _lookup(tp)
    path = ctx.path_of(target) if target is not None else None
    if path is None or path.is_empty():
        for g in glyphs:
            g.hidden = True
        return
    a, b, c, d = ctx.transform[:4]
    walker = PathWalker(path, math.sqrt(math.hypot(a, b) * math.hypot(c, d)))
    style = styles.get(id(tp), ctx.style)
    offset = 0.0
    so = tp.get("startOffset")
    if so is not None:
        so = so.strip()
        if so.endswith("%"):
            try:
                offset = float(so[:-1]) / 100 * walker.length
            except ValueError:
                offset = 0.0
        else:
            offset = ctx.length(so, "x", style, 0.0) or 0.0
    for g in glyphs:
        adv = g.advance * g.sx
        mid = offset + g.x - g.path_anchor + adv / 2
        at = walker.at(mid)
        if at is None:
            g.hidden = True
            continue
        px, py, ang = at
        hw = adv / 2
        # Rotated about the glyph's midpoint on the path, then shifted off the path (dy,
        # baselines) and turned by its own rotate value about its origin.
        m = compose(_translate(px - hw, py), _rotate_at(ang, hw, 0.0))
        m = compose(m, _translate(0.0, g.y))
        m = compose(m, _rotate_at(g.rotate, 0.0, 0.0))
        g.frame = m
        g.shifted = True
        g.matrix = compose(m, (g.scale * g.sx, 0.0, 0.0, -g.scale, g.off_x, -g.off_y))


def _translate(x, y):
    return (1.0, 0.0, 0.0, 1.0, x, y)


def _rotate_at(deg, cx, cy):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return (c, s, -s, c, cx - c * cx + s * cy, cy - s * cx - c * cy)


# -- 7. drawing -------------------------------------------------------------------------------
def draw_glyphs(text_el, chars, placed, ctx, styles, vertical):
    glyphs = [g for _, _, gs in placed for g in gs if not g.hidden]
    if not glyphs:
        return []
    # glyph outlines grouped per (element) in document order of their first character
    by_el = {}
    order = []
    for g in glyphs:
        el = chars[g.char].el
        if id(el) not in by_el:
            by_el[id(el)] = (el, [])
            order.append(id(el))
        by_el[id(el)][1].append(g)
    paths = {}
    bbox = None
    for key in order:
        el, gl = by_el[key]
        path = _glyph_path(gl)
        paths[key] = path
        b = path.bounds()
        if b is not None:
            bbox = b if bbox is None else (min(bbox[0], b[0]), min(bbox[1], b[1]),
                                           max(bbox[2], b[2]), max(bbox[3], b[3]))
    if bbox is None:
        return []
    decorations = text_decorations(text_el, chars, glyphs, styles, vertical)
    nodes_by_el = {}
    for key in order:
        el, gl = by_el[key]
        style = styles[id(el)]
        if style.get("visibility").strip() in ("hidden", "collapse"):
            continue
        if paths[key].is_empty():
            continue
        nodes_by_el.setdefault(id(el), []).extend(_color_or_plain(gl, paths[key], style, ctx,
                                                                  bbox))
    out = []
    for kind in ("underline", "overline"):
        for deco_style, path in decorations.get(kind, []):
            out.extend(ctx.draw(path, deco_style, bbox))
    out.extend(_wrap_tree(text_el, nodes_by_el, ctx, styles, top=True))
    for deco_style, path in decorations.get("line-through", []):
        out.extend(ctx.draw(path, deco_style, bbox))
    return out


def _glyph_path(glyphs):
    """One user-space path for glyphs, each placed by its matrix (fonts.layout)."""
    verbs, points = [], []
    by_face = {}
    for g in glyphs:
        by_face.setdefault((id(g.face), g.location), (g.face, g.location, [], []))
        entry = by_face[(id(g.face), g.location)]
        entry[2].append(g.gid)
        entry[3].append(g.matrix)
    for face, loc, gids, mats in by_face.values():
        v, p = glyphs_arrays(face, loc, gids, mats)
        verbs.append(v)
        points.append(p)
    return Path.from_arrays(np.concatenate(verbs), np.concatenate(points))


def _color_or_plain(glyphs, path, style, ctx, bbox):
    """COLR glyphs draw their layers with palette colours; everything else through ctx.draw.
    """
    from ..fonts.color import colr_layers

    colored = [g for g in glyphs if colr_layers(g.face).get(g.gid)]
    if not colored or ctx.in_clip or ctx.geometry_only:
        return ctx.draw(path, style, bbox)
    plain = [g for g in glyphs if not colr_layers(g.face).get(g.gid)]
    out = ctx.draw(_glyph_path(plain), style, bbox) if plain else []
    from ..fonts.color import color_fills
    from ..scene import Solid
    ref = ctx.resolve_paint(style, "fill", bbox)
    paint = ref.paint if ref is not None else Solid()
    for g in colored:
        for f in color_fills(g.face, g.location, [g.gid], [g.matrix], paint):
            f.path = f.path.transformed(ctx.transform)
            out.append(f)
    return out


def _wrap_tree(el, nodes_by_el, ctx, styles, top=False):
    """Nodes of an element's subtree in order, each tspan wrapped for opacity/clip/mask."""
    nodes = list(nodes_by_el.get(id(el), []))
    for c in el.children:
        if c.tag in TEXT_CONTENT and id(c) in styles:
            nodes.extend(_wrap_tree(c, nodes_by_el, ctx, styles))
    if top or not nodes:
        return nodes
    return ctx.wrap(el, styles[id(el)], nodes)


def text_decorations(text_el, chars, glyphs, styles, vertical):
    """{kind: [(style of the declaring element, user-space path)]}.

    As in resvg: a text span (characters of one innermost element) is decorated by every
    kind declared on it or an ancestor, painted with the declaring element's fill and stroke,
    sized by the span's own font (rectangle centred on the underline, ascender or strike-out
    line, underline thickness); the line runs over consecutive clusters and restarts at each
    cluster moved by dx/dy/rotate or placed on a path.
    """
    out = {}
    clusters = [g for g in glyphs if g.cluster_start]
    # Declared outside <text> (on a <g>), a decoration is painted with the text's own style.
    outer = {}
    for anc in text_el.ancestors():
        value = (anc.specified.get("text-decoration") or "").split()
        for kind in ("underline", "overline", "line-through"):
            if kind in value:
                outer.setdefault(kind, text_el)
    span_kinds = {}
    for g in clusters:
        el = chars[g.char].el
        if id(el) in span_kinds:
            continue
        kinds = {}
        for anc in reversed(chars[g.char].chain):
            value = (anc.specified.get("text-decoration") or "").split()
            for kind in ("underline", "overline", "line-through"):
                if kind in value and kind not in kinds:
                    kinds[kind] = anc
        for kind, decl in outer.items():
            kinds.setdefault(kind, decl)
        span_kinds[id(el)] = kinds
    for kind in ("underline", "overline", "line-through"):
        by_decl = {}
        run = None       # [frame, width, g0, declaring element]
        runs = []
        prev_el = None
        for g in clusters:
            el = chars[g.char].el
            decl = span_kinds[id(el)].get(kind)
            adv = _cluster_advance(g, glyphs, chars)
            if decl is None:
                run = None
            elif run is None or g.shifted or el is not prev_el:
                run = [g.frame, adv, g, decl]
                runs.append(run)
            else:
                run[1] += adv
            prev_el = el
        for frame, width, g0, decl in runs:
            face = g0.face
            m = face.metrics
            scale = g0.size / face.units_per_em
            if kind == "underline":
                dy = -m.underline_position * scale
            elif kind == "overline":
                dy = -m.ascender * scale
            else:
                dy = -m.strikeout_position * scale
            thick = m.underline_thickness * scale
            if vertical:
                dy = {"underline": (m.ascender - m.descender) * scale / 2,
                      "overline": -(m.ascender - m.descender) * scale / 2}.get(kind, 0.0)
            rect = rect_path(0.0, dy - thick / 2, width, thick).transformed(frame)
            entry = by_decl.setdefault(id(decl), (styles[id(decl)], Path()))
            entry[1].extend(rect)
        out[kind] = list(by_decl.values())
    return out


def _cluster_advance(g, glyphs, chars):
    """Advance of a whole cluster (ligatures, marks) starting with glyph g, with its letter
    and word spacing."""
    i = glyphs.index(g)
    adv = g.advance
    for h in glyphs[i + 1:]:
        if h.cluster_start or h.char != g.char:
            break
        adv += h.advance
    return adv * g.sx + g.spacing
