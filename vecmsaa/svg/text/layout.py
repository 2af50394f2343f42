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
from dataclasses import dataclass

import numpy as np

from ...fonts import FontError
from ...fonts.db import FontDatabase, database_from_options, parse_family_list
from ...fonts.layout import glyphs_arrays
from ...fonts.shape import bidi_runs, shape_run
from ...scene.path import CLOSE, CUBIC, LINE, MOVE, QUAD, VERB_POINTS, Path, rect_path
from ...scene.transform import compose

TEXT_CONTENT = {"tspan", "tref", "textPath", "a"}
WEIGHTS = {"normal": 400, "bold": 700}
STRETCHES = {"ultra-condensed": 50.0, "extra-condensed": 62.5, "condensed": 75.0,
             "semi-condensed": 87.5, "normal": 100.0, "semi-expanded": 112.5,
             "expanded": 125.0, "extra-expanded": 150.0, "ultra-expanded": 200.0}
#: tref may take the characters of SVG elements only
SVG_ELEMENTS = {"svg", "g", "defs", "symbol", "use", "switch", "a", "rect", "circle", "ellipse",
                "line", "polyline", "polygon", "path", "text", "tspan", "tref", "textPath",
                "image", "title", "desc", "metadata", "style", "clipPath", "mask", "marker",
                "pattern", "linearGradient", "radialGradient", "stop", "filter", "view",
                "foreignObject"}


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


FONT_SIZE_KEYWORDS = {"xx-small", "x-small", "small", "medium", "large", "x-large",
                      "xx-large", "xxx-large", "larger", "smaller"}
#: what the CSS ``font`` shorthand resets when it does not set it
FONT_RESETS = {"font-style": "normal", "font-variant": "normal", "font-weight": "normal",
               "font-stretch": "normal", "line-height": "normal", "font-kerning": "auto",
               "font-size-adjust": "none", "font-feature-settings": "normal",
               "font-variation-settings": "normal"}


def parse_font_shorthand(value):
    """CSS ``font`` → {longhand: value}, or None when it is not valid."""
    tokens = re.findall(r"""("[^"]*"|'[^']*'|[^\s"']+)""", value.strip())
    longhands = {}
    for i, tok in enumerate(tokens):
        low = tok.lower()
        size = low.split("/")[0]
        if size in FONT_SIZE_KEYWORDS or re.match(r"^[+]?(\d+\.?\d*|\.\d+)(px|pt|pc|mm|cm|in|"
                                                  r"em|ex|%)?$", size):
            if re.match(r"^\d+$", size) and size in ("100", "200", "300", "400", "500", "600",
                                                     "700", "800", "900"):
                longhands["font-weight"] = size
                continue
            longhands["font-size"] = tok.split("/")[0]
            rest = tokens[i + 1:]
            # a line height may follow as "/1.2", "/ 1.2" or be glued: "12px/1.2"
            if tok.endswith("/") and rest:
                rest = rest[1:]
            elif rest and rest[0] == "/":
                rest = rest[2:]
            elif rest and rest[0].startswith("/"):
                rest = rest[1:]
            family = " ".join(rest)
            if not family:
                return None
            longhands["font-family"] = family
            return {**FONT_RESETS, **longhands}
        if low in ("italic", "oblique"):
            longhands["font-style"] = low
        elif low == "small-caps":
            longhands["font-variant"] = low
        elif low in ("bold", "bolder", "lighter"):
            longhands["font-weight"] = low
        elif low in STRETCHES:
            longhands["font-stretch"] = low
        elif low != "normal":
            return None
    return None


def _content_elements(text_el):
    stack = [text_el]
    while stack:
        el = stack.pop()
        yield el
        stack.extend(c for c in el.children if c.tag in TEXT_CONTENT)


def expand_font_shorthand(text_el):
    """Spread a ``font`` shorthand on <text> and its content elements into the longhands it
    sets (a longhand the element specifies itself wins). The document leaves ``font`` to the
    text module."""
    stack = [text_el]
    while stack:
        el = stack.pop()
        value = el.specified.get("font")
        if value:
            parsed = parse_font_shorthand(value)
            if parsed:
                for name, v in parsed.items():
                    el.specified.setdefault(name, v)
            del el.specified["font"]
        stack.extend(c for c in el.children if c.tag in TEXT_CONTENT)


def collect_chars(text_el, ctx, styles):
    """The text nodes of a <text> element, in document order, as
    [(characters, depth, preserve)]: depth 0 for <text>'s own text, +1 per nested element."""
    nodes = []

    def add(string, el, chain, depth, preserve, text_path):
        if string:
            nodes.append(([Char(ch, el, chain, preserve, text_path=text_path)
                           for ch in string], depth, preserve))

    def walk(el, chain, style, preserve, text_path, depth):
        styles[id(el)] = style
        add(el.text, el, chain, depth, preserve, text_path)
        for child in el.children:
            if child.tag in TEXT_CONTENT and _conditions(child):
                cstyle = style.child(child)
                if cstyle.get("display").strip() != "none":
                    cpres = _space_preserved(child, preserve)
                    tp = text_path
                    if child.tag == "textPath":
                        # textPath must be a direct child of <text> (as in resvg)
                        if text_path is None and el is text_el:
                            tp = child
                            walk(child, chain + (child,), cstyle, cpres, tp, depth + 1)
                    elif child.tag == "tref":
                        styles[id(child)] = cstyle
                        target = _lookup(child)
                        if target is not None and target.tag in SVG_ELEMENTS:
                            add(_all_text(target), child, chain + (child,), depth + 1, cpres,
                                tp)
                    else:
                        walk(child, chain + (child,), cstyle, cpres, tp, depth + 1)
            add(child.tail, el, chain, depth, preserve, text_path)

    preserve = False
    for el in [text_el] + list(text_el.ancestors()):
        if el.get("xml:space", el.get("space")) is not None:
            preserve = _space_preserved(el, False)
            break
    walk(text_el, (text_el,), ctx.style, preserve, None, 0)
    return nodes


def _conditions(el):
    from ..builder import conditions_pass
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


def collapse_white_space(nodes):
    """White space as resvg handles it (it mimics Chrome): in each text node newlines and tabs
    become spaces and, unless ``xml:space="preserve"``, runs of spaces collapse; then between
    neighbouring nodes a node entered one level deeper loses its leading space, and of two
    spaces meeting otherwise the first goes; the text's first leading and last trailing spaces
    go. Returns the characters."""
    texts = []
    for chars, depth, preserve in nodes:
        kept = []
        for c in chars:
            if c.ch in "\r\n\t":
                c.ch = " "
            if not preserve and c.ch == " " and kept and kept[-1].ch == " ":
                continue
            kept.append(c)
        texts.append([kept, depth, preserve])
    if len(texts) == 1:
        chars, _, preserve = texts[0]
        if not preserve:
            if chars and chars[0].ch == " ":
                chars.pop(0)
            if chars and chars[-1].ch == " ":
                chars.pop()
    last_non_empty = None
    n = len(texts) - 1
    for i in range(n):
        first = texts[i]
        second = texts[i + 1]
        if not first[0] and last_non_empty is not None:
            first = last_non_empty
        t1, depth1, pres1 = first
        t2, depth2, pres2 = second
        c1 = t1[0].ch if t1 else None
        c2 = t1[-1].ch if t1 else None
        c3 = t2[0].ch if t2 else None
        c4 = t2[-1].ch if t2 else None
        if depth1 < depth2:
            if c3 == " " and not pres2:
                t2.pop(0)
        elif c2 == " " and c3 == " ":
            if not pres1 and not pres2:
                t1.pop()
            elif pres1 and not pres2:
                t2.pop(0)
        if i == 0 and c1 == " " and not pres1 and t1:
            t1.pop(0)
        elif i == n - 1 and c4 == " " and t2 and not pres2:
            t2.pop()
        if i == n - 1 and c2 == " " and t1 and not t2 and t1[-1].ch == " ":
            t1.pop()
        if any(c.ch != " " for c in t1):
            last_non_empty = first
    return [c for chars, _, _ in texts for c in chars]


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
    # font-kerning comes from CSS only (the cascade ignores the attribute, as resvg does).
    if (style.get("font-kerning") or "auto").strip() == "none":
        features["kern"] = 0
    # resvg also honours the SVG 1.1 kerning="0" attribute.
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
    if spec.style == "oblique" and "slnt" in face.axes:
        loc["slnt"] = -14.0          # CSS: oblique without an angle is 14deg
    if spec.style == "italic" and "ital" in face.axes:
        loc["ital"] = 1.0
    loc.update(dict(spec.variations))
    return face.clamp_location(loc)


def assign_faces(chars, specs, db):
    """Face for every character: the family list's best match, else a fallback face."""
    faces = []
    primary = {}
    loaded = {}
    for c, spec in zip(chars, specs):
        key = (spec.families, spec.weight, spec.style, spec.stretch)
        info = primary.get(key)
        if key not in primary:
            info = db.query_or_default(list(spec.families), spec.weight, spec.style,
                                       spec.stretch)
            primary[key] = info
        if info not in loaded:
            loaded[info] = _load(info)
        face = loaded[info]
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
IDENTITY_M = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
#: scripts where letter-spacing would break joining (CSS Text 3 "cursive scripts"), as
#: code point ranges: Arabic, Syriac, NKo, Mandaic, Devanagari, Bengali, Gurmukhi, Ogham,
#: Mongolian, Syloti Nagri, Phags-pa, Arabic presentation forms
NO_LETTER_SPACING = ((0x0600, 0x08FF), (0x0900, 0x0A7F), (0x1680, 0x169F), (0x1800, 0x18AF),
                     (0xA800, 0xA87F), (0xFB50, 0xFDFF), (0xFE70, 0xFEFF))
WORD_SEPARATORS = {0x20, 0xA0, 0x1361, 0x10100, 0x10101, 0x1039F, 0x1091F}


@dataclass
class Glyph:
    face: object
    location: tuple
    gid: int
    dx: float                 # offset inside its cluster (user units, y down)
    dy: float
    scale: float              # user units per font unit
    matrix: tuple | None = None


@dataclass
class Cluster:
    """Glyphs of one typographic character (ligature, base + marks): the unit that SVG
    positions, rotates and spaces (as resvg's GlyphCluster)."""
    char: int                 # index of its first character
    glyphs: list
    face: object
    size: float
    width: float              # widest glyph advance
    advance: float            # width plus spacing
    ascent: float = 0.0       # user units, y up
    descent: float = 0.0
    pre: tuple = IDENTITY_M   # vertical writing: shift of rotated clusters
    path_ts: tuple = IDENTITY_M   # vertical writing: upright clusters turned back
    sx: float = 1.0           # lengthAdjust=spacingAndGlyphs
    frame: tuple = IDENTITY_M     # cluster transform in user units (without path_ts)
    visible: bool = True
    shifted: bool = False     # moved by dx/dy/rotate or on a path: restarts decorations


def shape_chunk(chars, faces, specs, start, end):
    """Clusters of chars[start:end] in visual order (LTR paragraph, bidi runs reversed).

    As resvg does, each bidi run is shaped whole with every face (and font settings) that
    its characters use, and each cluster is taken from the shaping by its own character's
    face: kerning and joining across tspans of different fonts come from the run's context.
    """
    text = "".join(c.ch for c in chars)
    clusters = []
    for s, e, d in bidi_runs(text[start:end], "ltr"):
        s, e = s + start, e + start
        keys = {}
        for k in range(s, e):
            if faces[k] is not None:
                keys.setdefault((id(faces[k]), specs[k].features, specs[k].variations), k)
        if not keys:
            continue
        shaped = {key: _shape_clusters(chars, faces, specs, text, s, e, d, k)
                  for key, k in keys.items()}
        base_key = next(iter(keys))
        base = shaped[base_key]
        covered = set()
        for cl in base:
            # Characters of this base cluster, each taken from the shaping by its own face
            # (a ligature of the base font may split into several clusters of another).
            end = _cluster_end(base, cl, e)
            picked = []
            for k in range(cl.char, end):
                if k in covered:
                    continue
                face = faces[k]
                key = (id(face), specs[k].features, specs[k].variations) \
                    if face is not None else base_key
                own = shaped.get(key, base)
                pick = next((c for c in own if c.char == k), None)
                if pick is None:
                    if k == cl.char:
                        pick, own = cl, base
                    else:
                        continue
                picked.append(pick)
                covered.update(range(k, _cluster_end(own, pick, e)))
            clusters.extend(reversed(picked) if d == "rtl" else picked)
    return clusters


def _cluster_end(clusters, cluster, end):
    """First character after a cluster in logical order (``end`` for the last one)."""
    later = [c.char for c in clusters if c.char > cluster.char]
    return min(later) if later else end


def _shape_clusters(chars, faces, specs, text, s, e, direction, k):
    """text[s:e] shaped with the face and settings of character k, as clusters."""
    face = faces[k]
    spec = specs[k]
    loc = face_location(face, spec)
    run = shape_run(face, text, s, e, location=loc, features=dict(spec.features),
                    direction=direction)
    out = []
    current = None
    pen = 0.0
    for gid, cl, adv, off in zip(run.gids, run.clusters, run.advances, run.offsets):
        cl = int(cl)
        size = specs[cl].size
        scale = size / face.units_per_em
        if current is None or current.char != cl:
            m = face.metrics
            current = Cluster(cl, [], face, size, 0.0, 0.0, m.ascender * scale,
                              m.descender * scale)
            out.append(current)
            pen = 0.0
        current.glyphs.append(Glyph(face, loc, int(gid), pen + float(off[0]) * scale,
                                    -float(off[1]) * scale, scale))
        width = float(adv[0]) * scale
        pen += width
        current.width = max(current.width, width)
        current.advance = current.width
    return out


def _spacing_allowed(ch):
    cp = ord(ch)
    return not any(lo <= cp <= hi for lo, hi in NO_LETTER_SPACING)


def apply_spacing(clusters, chars, specs):
    """letter-spacing after every cluster but the last (not in cursive scripts; a cluster
    whose advance drops to zero or below disappears) and word-spacing after separators."""
    if any(specs[c.char].letter_spacing for c in clusters):
        last = len(clusters) - 1
        for i, c in enumerate(clusters):
            if _spacing_allowed(chars[c.char].ch):
                if i != last:
                    c.advance += specs[c.char].letter_spacing
                if not c.advance > 0:
                    c.width = c.advance = 0.0
                    c.glyphs = []
    for c in clusters:
        if ord(chars[c.char].ch) in WORD_SEPARATORS:
            c.advance += specs[c.char].word_spacing


def apply_writing_mode(clusters, chars):
    """Vertical text: upright characters (CJK) are turned back upright about their centre,
    others keep the rotated line, centred on the column."""
    for c in clusters:
        if _is_upright(ord(chars[c.char].ch)):
            h = c.ascent - c.descent
            dy = c.width - h
            m = compose(_translate(c.width / 2, 0.0), _rotate_at(-90.0, 0.0, 0.0))
            c.path_ts = compose(m, _translate(-c.width / 2, -dy))
            c.ascent, c.descent = c.width / 2, -c.width / 2
        else:
            # Rotated characters sit on the central baseline (measured against resvg 0.48)
            c.pre = _translate(0.0, (c.ascent + c.descent) / 2)


#: CJK punctuation and small kana that UTR #50 marks Tu/Tr (transformed): resvg rotates them
#: like Latin, since only Vertical_Orientation=U counts as upright there
_TRANSFORMED = frozenset(
    [0x3001, 0x3002, 0x3030, 0x30A0, 0x30FC, 0x309B, 0x309C, 0xFF01, 0xFF08, 0xFF09, 0xFF0C,
     0xFF0E, 0xFF1A, 0xFF1B, 0xFF1F, 0xFF3B, 0xFF3D, 0xFF3F, 0xFF5B, 0xFF5D]
    + list(range(0x3008, 0x3012)) + list(range(0x3014, 0x3020)) + list(range(0xFF1C, 0xFF1F))
    + list(range(0xFF5F, 0xFF61)) + list(range(0x31F0, 0x3200))
    + [0x3041, 0x3043, 0x3045, 0x3047, 0x3049, 0x3063, 0x3083, 0x3085, 0x3087, 0x308E, 0x3095,
       0x3096, 0x30A1, 0x30A3, 0x30A5, 0x30A7, 0x30A9, 0x30C3, 0x30E3, 0x30E5, 0x30E7, 0x30EE,
       0x30F5, 0x30F6])


def _is_upright(cp):
    """Unicode Vertical_Orientation U (the common blocks): CJK, kana, hangul, emoji."""
    if cp in _TRANSFORMED:
        return False
    return (0x1100 <= cp <= 0x11FF or 0x2E80 <= cp <= 0x2FFF or 0x3000 <= cp <= 0xA4CF
            or 0xAC00 <= cp <= 0xD7AF or 0xF900 <= cp <= 0xFAFF or 0xFE30 <= cp <= 0xFE4F
            or 0xFF01 <= cp <= 0xFF60 or 0x1F000 <= cp <= 0x1FAFF or 0x20000 <= cp <= 0x3FFFF)


def apply_length_adjust(clusters, chars, text_length, on_path):
    """textLength on the elements of ``text_length`` ({element id: (length, adjust)})."""
    for el_id, (target, adjust) in text_length.items():
        idx = [i for i, c in enumerate(clusters)
               if any(id(e) == el_id for e in chars[c.char].chain)]
        if not idx:
            continue
        width = sum(clusters[i].width for i in idx)
        if adjust == "spacingAndGlyphs":
            if width <= 0:
                continue
            factor = target / width
            if factor < 0.001:
                continue
            for i in idx:
                clusters[i].sx = factor
                if on_path:
                    clusters[i].advance *= factor
                    clusters[i].width *= factor
        else:
            factor = (target - width) / (len(idx) - 1) if len(idx) > 1 else 0.0
            for i in idx:
                clusters[i].advance = clusters[i].width + factor


def _anchor(anchor, width):
    return {"middle": -width / 2, "end": -width}.get(anchor, 0.0)


def position_linear(clusters, chars, anchor, vertical):
    """Cluster transforms of a chunk laid along x from 0 (the anchor moves the start);
    returns the pen at its end."""
    x = _anchor(anchor, sum(c.advance for c in clusters))
    y = 0.0
    for c in clusters:
        ch = chars[c.char]
        if vertical:
            y -= ch.dx
            x += ch.dy
        else:
            x += ch.dx
            y += ch.dy
        c.shifted = c.shifted or bool(ch.dx or ch.dy)
        frame = compose(compose(c.pre, (c.sx, 0.0, 0.0, 1.0, 0.0, 0.0)), _translate(x, y))
        if ch.rotate:
            frame = compose(frame, _rotate_at(ch.rotate, 0.0, 0.0))
            c.shifted = True
        c.frame = frame
        x += c.advance
    return x, y


def position_on_path(clusters, chars, text_path, chunk_x, anchor, ctx, styles, shifts):
    """Clusters along a textPath: each cluster's midpoint on the path, turned to its tangent,
    then moved off the path by dy and baseline shifts; returns the pen at the end."""
    target = _lookup(text_path)
    path = ctx.path_of(target) if target is not None else None
    walker = None
    if path is not None and not path.is_empty():
        a, b, cc, d = ctx.transform[:4]
        # resvg's tolerance follows the text's transform in the SVG's own units, before the
        # output is scaled to its pixel size: divide that scaling out.
        walker = PathWalker(path, math.sqrt(math.hypot(a, b) * math.hypot(cc, d))
                            / ctx.root_scale)
    # a path with infinite coordinates (or a length that overflows) is not drawn, and has no
    # length to lay text along
    if walker is None or not math.isfinite(walker.length):
        for c in clusters:
            c.visible = False
        return 0.0, 0.0
    style = styles.get(id(text_path), ctx.style)
    offset = 0.0
    start = text_path.get("startOffset")
    if start is not None:
        start = start.strip()
        if start.endswith("%"):
            try:
                offset = float(start[:-1]) / 100 * walker.length
            except ValueError:
                offset = 0.0
        else:
            offset = ctx.length(start, "x", style, 0.0) or 0.0
    advance = chunk_x + offset + _anchor(anchor, sum(c.advance for c in clusters))
    dy = 0.0
    last = (0.0, 0.0)
    for c in clusters:
        ch = chars[c.char]
        advance += ch.dx
        hw = c.width / 2
        at = walker.at(advance + hw)
        advance += c.advance
        dy += ch.dy
        if at is None:
            c.visible = False
            continue
        px, py, ang = at
        frame = compose(_translate(px - hw, py), _rotate_at(ang, hw, 0.0))
        frame = compose(frame, _translate(0.0, dy + shifts[c.char]))
        if ch.rotate:
            frame = compose(frame, _rotate_at(ch.rotate, 0.0, 0.0))
        c.frame = compose(frame, compose(c.pre, (c.sx, 0.0, 0.0, 1.0, 0.0, 0.0)))
        c.shifted = True
        last = (px + c.advance, py)
    return last


def _translate(x, y):
    return (1.0, 0.0, 0.0, 1.0, x, y)


def _rotate_at(deg, cx, cy):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return (c, s, -s, c, cx - c * cx + s * cy, cy - s * cx - c * cy)


def baseline_offset(style, face, spec, root_style, vertical=False):
    """Shift (user units, positive = down) of the baseline for dominant-/alignment-baseline
    and baseline-shift of this element and its ancestors."""
    m = face.metrics
    scale = spec.size / face.units_per_em
    shift = 0.0
    align = (style.get("alignment-baseline") or "auto").strip()
    base = align if align not in ("auto", "baseline") else _dominant_baseline(style)
    table = {
        "middle": m.x_height / 2, "central": (m.ascender + m.descender) / 2,
        "hanging": m.ascender * 0.8, "mathematical": m.ascender * 0.5,
        "text-top": m.ascender, "text-before-edge": m.ascender,
        "text-bottom": m.descender, "text-after-edge": m.descender,
        "ideographic": m.descender, "before-edge": m.ascender, "after-edge": m.descender,
    }
    if base in table and not vertical:
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
                from ..units import split_length, to_px
                parsed = split_length(v)
                if parsed is not None:
                    total += to_px(parsed[0], parsed[1], fs)
        s = s.parent
    return shift - total


def _dominant_baseline(style):
    """dominant-baseline, with SVG 1.1's no-change/reset-size taking the parent's value."""
    s = style
    while s is not None:
        v = (s.get("dominant-baseline") or "auto").strip()
        if v not in ("no-change", "reset-size"):
            return v
        s = s.parent
    return "auto"


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
    if any("font" in el.specified for el in _content_elements(element)):
        expand_font_shorthand(element)
        ctx.style = ctx.style.parent.child(element) if ctx.style.parent is not None \
            else ctx.style
    chars = collect_chars(element, ctx, styles)
    chars = collapse_white_space(chars)
    if not chars:
        return []
    apply_positions(element, chars, ctx, styles)
    db = font_database(ctx)
    spec_cache = {}
    specs = []
    outer = tuple(reversed(list(element.ancestors())))
    for c in chars:
        s = spec_cache.get(id(c.el))
        if s is None:
            s = spec_cache[id(c.el)] = font_spec(styles[id(c.el)], ctx, outer + c.chain)
        specs.append(s)
    faces = assign_faces(chars, specs, db)
    # a zero, negative or non-finite size draws nothing
    faces = [f if math.isfinite(sp.size) and sp.size > 0 else None
             for f, sp in zip(faces, specs)]
    if all(f is None for f in faces):
        return []
    writing = (ctx.style.get("writing-mode") or "lr").strip()
    vertical = writing in ("tb", "tb-rl", "vertical-rl", "vertical-lr")
    text_length = {}
    for el in [element] + [e for c in chars for e in c.chain[1:]]:
        value = el.get("textLength")
        if value is None or id(el) in text_length:
            continue
        length = ctx.length(value, "x", styles.get(id(el), ctx.style))
        if length is not None and length >= 0:
            text_length[id(el)] = (length, (el.get("lengthAdjust") or "spacing").strip())
    # baseline shift of every character (positive moves down)
    shift_cache = {}
    shifts = []
    for c, spec, face in zip(chars, specs, faces):
        key = (id(c.el), id(face))
        if key not in shift_cache:
            shift_cache[key] = baseline_offset(styles[id(c.el)], face, spec, ctx.style,
                                               vertical) if face is not None else 0.0
        shifts.append(shift_cache[key])

    bounds = [i for i, c in enumerate(chars)
              if i == 0 or c.x is not None or c.y is not None
              or c.text_path is not chars[i - 1].text_path]
    bounds.append(len(chars))
    all_clusters = []
    last_x = last_y = 0.0
    for a, b in zip(bounds[:-1], bounds[1:]):
        first = chars[a]
        on_path = first.text_path is not None
        clusters = shape_chunk(chars, faces, specs, a, b)
        if not clusters:
            continue
        clusters[0].shifted = True       # a chunk starts a new decoration line
        if vertical:
            apply_writing_mode(clusters, chars)
        apply_spacing(clusters, chars, specs)
        apply_length_adjust(clusters, chars, text_length, on_path)
        anchor = (styles[id(first.el)].get("text-anchor") or "start").strip()
        if on_path:
            chunk_x = (first.y if vertical else first.x) or 0.0
            last_x, last_y = position_on_path(clusters, chars, first.text_path, chunk_x,
                                              anchor, ctx, styles, shifts)
        else:
            x = first.x if first.x is not None else last_x
            y = first.y if first.y is not None else last_y
            cx, cy = position_linear(clusters, chars, anchor, vertical)
            chunk_ts = _rotate_at(90.0, x, y) if vertical else IDENTITY_M
            for c in clusters:
                span = compose(chunk_ts, _translate(x, y + shifts[c.char]))
                c.frame = compose(span, c.frame)
            if vertical:
                cx, cy = cy, cx
            last_x, last_y = x + cx, y + cy
        all_clusters.extend(clusters)
    for c in all_clusters:
        base = compose(c.frame, c.path_ts)
        for g in c.glyphs:
            g.matrix = compose(base, (g.scale, 0.0, 0.0, -g.scale, g.dx, g.dy))
    return draw_clusters(element, chars, all_clusters, ctx, styles, vertical)


# -- 7. drawing -------------------------------------------------------------------------------
def text_bbox(clusters):
    """Object bounding box of text as resvg computes it: the union of the clusters' em boxes
    (ascent to descent over the advance), not of the glyph outlines."""
    corners = []
    for c in clusters:
        if not c.visible:
            continue
        adv = c.advance if c.advance > 0 else 1.0
        a, b, cc, d, e, f = compose(c.frame, c.path_ts)
        for x, y in ((0.0, -c.ascent), (adv, -c.ascent), (0.0, -c.descent),
                     (adv, -c.descent)):
            corners.append((a * x + cc * y + e, b * x + d * y + f))
    if not corners:
        return None
    pts = np.asarray(corners)
    return (float(pts[:, 0].min()), float(pts[:, 1].min()), float(pts[:, 0].max()),
            float(pts[:, 1].max()))


def draw_clusters(text_el, chars, clusters, ctx, styles, vertical):
    visible = [c for c in clusters if c.visible]
    if not visible:
        return []
    by_el = {}
    for c in visible:
        el = chars[c.char].el
        by_el.setdefault(id(el), (el, []))[1].extend(c.glyphs)
    bbox = text_bbox(visible)
    if bbox is None:
        return []
    decorations = text_decorations(text_el, chars, clusters, styles, vertical)
    for kind in decorations:
        for _, path in decorations[kind]:
            b = path.bounds()
            if b is not None:
                bbox = (min(bbox[0], b[0]), min(bbox[1], b[1]), max(bbox[2], b[2]),
                        max(bbox[3], b[3]))
    if ctx.geometry_only:
        # The object bounding box of text is resvg's: the clusters' em boxes, not the ink.
        x0, y0, x1, y1 = bbox
        return ctx.draw(rect_path(x0, y0, x1 - x0, y1 - y0), ctx.style, bbox)
    nodes_by_el = {}
    for key, (el, glyphs) in by_el.items():
        style = styles[id(el)]
        if not glyphs or style.get("visibility").strip() in ("hidden", "collapse"):
            continue
        path = _glyph_path(glyphs)
        nodes = _color_or_plain(glyphs, path, style, ctx, bbox)
        if (style.get("text-rendering") or "auto").strip() == "optimizeSpeed":
            _no_antialias(nodes)     # resvg draws such text aliased, like crispEdges
        nodes_by_el.setdefault(key, []).extend(nodes)
    out = []
    for kind in ("underline", "overline"):
        for deco_style, path in decorations.get(kind, []):
            out.extend(ctx.draw(path, deco_style, bbox))
    out.extend(_wrap_tree(text_el, nodes_by_el, ctx, styles, top=True))
    for deco_style, path in decorations.get("line-through", []):
        out.extend(ctx.draw(path, deco_style, bbox))
    return out


def _no_antialias(nodes):
    from ...scene.nodes import Fill
    stack = list(nodes)
    while stack:
        n = stack.pop()
        if isinstance(n, Fill):
            n.antialias = False
        else:
            stack.extend(getattr(n, "children", []))


def _glyph_path(glyphs):
    """One user-space path for glyphs, each placed by its matrix (fonts.layout)."""
    verbs, points = [], []
    by_face = {}
    for g in glyphs:
        entry = by_face.setdefault((id(g.face), g.location), (g.face, g.location, [], []))
        entry[2].append(g.gid)
        entry[3].append(g.matrix)
    for face, loc, gids, mats in by_face.values():
        v, p = glyphs_arrays(face, loc, gids, mats)
        verbs.append(v)
        points.append(p)
    return Path.from_arrays(np.concatenate(verbs), np.concatenate(points))


def _color_or_plain(glyphs, path, style, ctx, bbox):
    """Colour glyphs (COLR layers, sbix/CBDT bitmaps) draw their own colours; everything else
    is the outline path filled and stroked through ctx.draw."""
    from ...fonts.color import color_glyph_fills, is_color_glyph
    from ...scene.nodes import Fill, Solid

    special = [g for g in glyphs if is_color_glyph(g.face, g.gid)]
    if not special:
        return ctx.draw(path, style, bbox) if not path.is_empty() else []
    plain = [g for g in glyphs if not is_color_glyph(g.face, g.gid)]
    out = []
    plain_path = _glyph_path(plain) if plain else None
    if plain_path is not None and not plain_path.is_empty():
        out.extend(ctx.draw(plain_path, style, bbox))
    ref = ctx.resolve_paint(style, "fill", bbox)
    paint = ref.paint if ref is not None else Solid()
    for g in special:
        for fill in color_glyph_fills(g.face, g.location, g.gid, g.matrix, paint,
                                      ctx.transform):
            if ctx.in_clip or ctx.geometry_only:
                fill = Fill(fill.path, Solid((0.0, 0.0, 0.0, 1.0)))
            out.append(fill)
    return out


def _wrap_tree(el, nodes_by_el, ctx, styles, top=False):
    """Nodes of an element's subtree in document order. Like resvg, opacity, clip-path, mask
    and filter on tspan-level elements are not applied (only on <text> itself, by the
    builder)."""
    nodes = list(nodes_by_el.get(id(el), []))
    for c in el.children:
        if c.tag in TEXT_CONTENT and id(c) in styles:
            nodes.extend(_wrap_tree(c, nodes_by_el, ctx, styles))
    return nodes


def text_decorations(text_el, chars, clusters, styles, vertical):
    """{kind: [(style of the declaring element, user-space path)]}.

    As in resvg: a text span (characters of one innermost element) is decorated by every
    kind declared on it or an ancestor, painted with the declaring element's fill and stroke
    (the text's own style when declared outside <text>), sized by the span's own font (a
    rectangle centred on the underline, ascender or strike-out line, underline thickness);
    the line runs over consecutive clusters and restarts at each cluster moved by
    dx/dy/rotate, placed on a path or starting a chunk.
    """
    out = {}
    outer = {}
    for anc in text_el.ancestors():
        value = (anc.specified.get("text-decoration") or "").split()
        for kind in ("underline", "overline", "line-through"):
            if kind in value:
                outer.setdefault(kind, text_el)
    span_kinds = {}
    for c in clusters:
        el = chars[c.char].el
        if id(el) in span_kinds:
            continue
        kinds = {}
        for anc in reversed(chars[c.char].chain):
            value = (anc.specified.get("text-decoration") or "").split()
            for kind in ("underline", "overline", "line-through"):
                if kind in value and kind not in kinds:
                    kinds[kind] = anc
        for kind, decl in outer.items():
            kinds.setdefault(kind, decl)
        span_kinds[id(el)] = kinds
    for kind in ("underline", "overline", "line-through"):
        by_decl = {}
        runs = []
        run = None
        prev_el = None
        for c in clusters:
            el = chars[c.char].el
            decl = span_kinds[id(el)].get(kind)
            if decl is None or not c.visible:
                run = None
            elif run is None or c.shifted or el is not prev_el:
                run = [c, c.advance, decl]
                runs.append(run)
            else:
                run[1] += c.advance
            prev_el = el
        for c0, width, decl in runs:
            m = c0.face.metrics
            scale = c0.size / c0.face.units_per_em
            if vertical:
                half = (m.ascender - m.descender) * scale / 2
                dy = {"underline": half, "overline": -half}.get(kind, 0.0)
            elif kind == "underline":
                dy = -m.underline_position * scale
            elif kind == "overline":
                dy = -m.ascender * scale
            else:
                dy = -m.strikeout_position * scale
            thick = m.underline_thickness * scale
            rect = rect_path(0.0, dy - thick / 2, width, thick).transformed(c0.frame)
            entry = by_decl.setdefault(id(decl), (styles[id(decl)], Path()))
            entry[1].extend(rect)
        out[kind] = list(by_decl.values())
    return out
