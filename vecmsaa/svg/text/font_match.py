"""Font matching for text: CSS font properties → :class:`FontSpec` → a face per character.

The ``font`` shorthand is read here (:func:`parse_font_shorthand`, which the cascade in
:mod:`vecmsaa.svg.document` spreads into longhands); weight (with bolder/lighter), style, stretch,
size, feature and variation settings, letter/word spacing and small caps make a FontSpec. The
family list is matched in the font database (:mod:`vecmsaa.fonts.db`); characters the face lacks
fall back to other faces, combining marks stay with their base's face.
"""
from __future__ import annotations

import functools

import itertools
import math
import re
import unicodedata
from dataclasses import dataclass

from ...diagnostics import warn
from ...fonts import FontError
from ...fonts.db import FontDatabase, database_from_options, parse_family_list
from ..units import ANGLE_DEG

WEIGHTS = {"normal": 400, "bold": 700, **{str(w): w for w in range(100, 1000, 100)}}
STRETCHES = {"ultra-condensed": 50.0, "extra-condensed": 62.5, "condensed": 75.0,
             "semi-condensed": 87.5, "normal": 100.0, "semi-expanded": 112.5,
             "expanded": 125.0, "extra-expanded": 150.0, "ultra-expanded": 200.0}


FONT_SIZE_KEYWORDS = {"xx-small", "x-small", "small", "medium", "large", "x-large",
                      "xx-large", "xxx-large", "larger", "smaller"}
#: what the CSS ``font`` shorthand resets when it does not set it
FONT_RESETS = {"font-style": "normal", "font-variant": "normal", "font-weight": "normal",
               "font-stretch": "normal", "line-height": "normal", "font-kerning": "auto",
               "font-size-adjust": "none", "font-feature-settings": "normal",
               "font-variation-settings": "normal", "font-optical-sizing": "auto"}


_SIZED = re.compile(r"(?i)[+]?(\d+\.?\d*|\.\d+)(px|pt|pc|mm|cm|in|em|ex|%)(/|$)|"
                    r"(xx-small|x-small|small|medium|large|x-large|xx-large|xxx-large|larger|"
                    r"smaller)(/|$)")
_OBLIQUE_ANGLE = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)(deg|grad|rad|turn)$")


def parse_font_shorthand(value):
    """CSS ``font`` → {longhand: value}, or None when it is not valid. Before the size come
    at most one each of style, variant, weight and stretch in any order, ``normal`` standing
    for any of them: four at most (CSS Fonts 4 §2.8); the family list must be valid."""
    tokens = re.findall(r"""("[^"]*"|'[^']*'|[^\s"']+)""", value.strip())
    longhands = {}
    normals = 0
    for i, tok in enumerate(tokens):
        low = tok.lower()
        if longhands.get("font-style") == "oblique" and _OBLIQUE_ANGLE.match(low):
            # CSS Fonts 4 §2.8: oblique takes an angle, here as in font-style
            longhands["font-style"] = f"oblique {low}"
            continue
        size = low.split("/")[0]
        if size in FONT_SIZE_KEYWORDS or re.match(r"^[+]?(\d+\.?\d*|\.\d+)(px|pt|pc|mm|cm|in|"
                                                  r"em|ex|%)?$", size):
            # a unitless number is a weight (CSS Fonts 4: any from 1 to 1000) where a size
            # follows; else, past the nine multiples of 100, a unitless size as before
            if weight_number(size) is not None and "/" not in tok and (
                    size in WEIGHTS or any(_SIZED.match(t) for t in tokens[i + 1:])):
                if "font-weight" in longhands:
                    return None
                longhands["font-weight"] = size
                continue
            if len(longhands) + normals > 4:
                return None
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
            if not family or not valid_family_list(family):
                return None
            longhands["font-family"] = family
            return {**FONT_RESETS, **longhands}
        if low == "normal":
            normals += 1
            continue
        if low in ("italic", "oblique"):
            name = "font-style"
        elif low == "small-caps":
            name = "font-variant"
        elif low in ("bold", "bolder", "lighter"):
            name = "font-weight"
        elif low in STRETCHES:
            name = "font-stretch"
        else:
            return None
        if name in longhands:
            return None
        longhands[name] = low
    return None



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
    #: the angle of ``font-style: oblique`` in degrees (None for normal and italic)
    oblique: float | None = None
    #: font-optical-sizing: auto (opsz follows the font size)
    optical_sizing: bool = True


_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def weight_number(value):
    """A font-weight ``<number>`` (CSS Fonts 4 §2.2: any number from 1 to 1000, ``650``,
    ``+700``, ``3e2``, ``650.5``), or None when ``value`` is none."""
    if not _NUMBER.fullmatch(value):
        return None
    w = float(value)
    if not 1 <= w <= 1000:
        return None
    return int(w) if w.is_integer() else w


def _weight(style):
    """Computed font-weight: the keywords and any number from 1 to 1000 (CSS Fonts 4 §2.2;
    resvg 0.44 and 0.48.1 take the nine multiples of 100 only, and keep the parent's weight
    for 650); ``bolder`` and ``lighter`` by §2.2's table of the parent's weight (as Chromium
    150; resvg adds or takes away 100, 300 from 400 up: lighter from 700 is 600, so Bold, where
    the table gives 400); an invalid value (1500, 0) keeps the parent's."""
    return style.computed(("computed", "font-weight"), _own_weight)


def _nearest_kerning(el, above):
    return el.get("kerning", above)


def kerning_attribute(el):
    """The SVG 1.1 ``kerning`` attribute that applies to ``el``: its own, else the nearest
    ancestor's (None: none), computed down the document tree."""
    return el.computed("kerning", _nearest_kerning)


def bolder(weight):
    """CSS Fonts 4 §2.2's table of ``bolder`` from the inherited weight."""
    return 400 if weight < 350 else 700 if weight < 550 else 900 if weight < 900 else weight


def lighter(weight):
    """CSS Fonts 4 §2.2's table of ``lighter`` from the inherited weight."""
    return weight if weight < 100 else 100 if weight < 550 else 400 if weight < 750 else 700


def _own_weight(style, parent):
    parent = 400 if parent is None else parent
    v = (style.specified.get("font-weight") or "").strip()
    if v in WEIGHTS:
        return WEIGHTS[v]
    if v == "bolder":
        return bolder(parent)
    if v == "lighter":
        return lighter(parent)
    w = weight_number(v)
    return parent if w is None else w


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


def parse_font_style(value):
    """A font-style value → (style to match, oblique angle in degrees or None), or None when
    it is not valid (CSS Fonts 4 §2.4: ``normal | italic | oblique <angle [-90deg,90deg]>?``;
    ``italic 10deg`` is invalid). ``oblique`` alone is 14deg. Faces are matched by CSS Fonts 4
    §5.2 step 4b with normal faces as oblique 0deg: ``oblique 0deg`` asks for exactly them,
    and so does a negative angle, as no face here slants backwards (the negated steps check
    oblique values of 0deg and up before any italic); positive angles take oblique, then
    italic faces."""
    words = value.strip().lower().split()
    if words in (["normal"], ["italic"]):
        return words[0], None
    if not words or words[0] != "oblique" or len(words) > 2:
        return None
    if len(words) == 1:
        return "oblique", 14.0
    m = _OBLIQUE_ANGLE.match(words[1])
    if not m:
        return None
    angle = float(words[1][:m.start(2)]) * ANGLE_DEG[m.group(2)]
    if not -90.0 <= angle <= 90.0:
        return None
    return ("oblique" if angle > 0 else "normal"), angle


def _font_style(style):
    """(style to match, oblique angle): the computed font-style (inherited; an invalid
    declaration is ignored)."""
    return style.get_valid("font-style", parse_font_style, ("normal", None))


def _quoted_settings(text, variations=False):
    """``"liga" 0, 'wght' 700`` → [(tag, value)] by CSS Fonts 4's grammar (§7.2
    font-feature-settings: a tag, then an integer >= 0, ``on`` or ``off``, or nothing for 1;
    §7.3 font-variation-settings: a tag and a number), [] for ``normal``, None when the value
    is invalid (an invalid declaration is ignored as a whole)."""
    text = (text or "").strip()
    if text == "normal":
        return []
    out = []
    for item in text.split(","):
        m = re.match(r"""\s*(["'])([\x20-\x7e]{4})\1\s*(\S*)\s*$""", item)
        if not m:
            return None
        val = m.group(3)
        if variations:
            try:
                value = float(val)
            except ValueError:
                return None
            if not math.isfinite(value):
                return None
        elif val in ("", "on", "off"):
            value = 0 if val == "off" else 1
        elif val.isdigit():
            value = int(val)
        else:
            return None
        out.append((m.group(2), value))
    return out


def _optical_sizing(style):
    """The computed font-optical-sizing: auto (True) or none (CSS Fonts 4 §7.4; inherited,
    an invalid declaration ignored)."""
    return style.get_valid("font-optical-sizing", {"auto": True, "none": False}.get, True)


def _settings(style, name):
    """The computed font-feature-settings or font-variation-settings (inherited; an invalid
    declaration is ignored; ``normal``, the initial value, is no settings)."""
    variations = name == "font-variation-settings"
    return style.get_valid(name, lambda v: _quoted_settings(v, variations), [])


def font_spec(style, ctx, el=None) -> FontSpec:
    """Font settings of a text content element ``el`` (the SVG 1.1 ``kerning`` attribute is
    looked up from it up the document tree)."""
    families = _family_list(style)
    # CSS Fonts 4 §7.2: the font-variant features first, font-feature-settings over them.
    features, small_caps = variant_features(style)
    for tag, value in _settings(style, "font-feature-settings"):
        features[tag] = value
    # font-kerning comes from CSS only (the cascade ignores the attribute, as resvg does).
    if (style.get("font-kerning") or "auto").strip() == "none":
        features["kern"] = 0
    # resvg also honours the SVG 1.1 kerning="0" attribute (the nearest one).
    kerning = None if el is None else kerning_attribute(el)
    if kerning is not None and kerning.strip() in ("0", "0px"):
        features["kern"] = 0
    variations = dict(_settings(style, "font-variation-settings"))
    size = style.font_size()
    letter = _spacing(style.get("letter-spacing"), ctx, style)
    word = _spacing(style.get("word-spacing"), ctx, style)
    if letter:
        # CSS: letter-spacing turns off optional ligatures.
        features.setdefault("liga", 0)
        features.setdefault("clig", 0)
    font_style, oblique = _font_style(style)
    return FontSpec(tuple(families), _weight(style), font_style, _stretch(style), size,
                    tuple(sorted(features.items())), tuple(sorted(variations.items())), letter,
                    word, small_caps, oblique, _optical_sizing(style))


#: CSS Fonts 4 §6.4–6.10: font-variant-* keywords → the OpenType features they turn on (1)
#: or off (0)
VARIANT_KEYWORDS = {
    "font-variant-ligatures": {
        "common-ligatures": {"liga": 1, "clig": 1}, "no-common-ligatures": {"liga": 0, "clig": 0},
        "discretionary-ligatures": {"dlig": 1}, "no-discretionary-ligatures": {"dlig": 0},
        "historical-ligatures": {"hlig": 1}, "no-historical-ligatures": {"hlig": 0},
        "contextual": {"calt": 1}, "no-contextual": {"calt": 0},
    },
    "font-variant-caps": {
        "small-caps": {"smcp": 1}, "all-small-caps": {"c2sc": 1, "smcp": 1},
        "petite-caps": {"pcap": 1}, "all-petite-caps": {"c2pc": 1, "pcap": 1},
        "unicase": {"unic": 1}, "titling-caps": {"titl": 1},
    },
    "font-variant-numeric": {
        "lining-nums": {"lnum": 1}, "oldstyle-nums": {"onum": 1},
        "proportional-nums": {"pnum": 1}, "tabular-nums": {"tnum": 1},
        "diagonal-fractions": {"frac": 1}, "stacked-fractions": {"afrc": 1},
        "ordinal": {"ordn": 1}, "slashed-zero": {"zero": 1},
    },
    "font-variant-position": {"sub": {"subs": 1}, "super": {"sups": 1}},
    "font-variant-east-asian": {
        "jis78": {"jp78": 1}, "jis83": {"jp83": 1}, "jis90": {"jp90": 1},
        "jis04": {"jp04": 1}, "simplified": {"smpl": 1}, "traditional": {"trad": 1},
        "full-width": {"fwid": 1}, "proportional-width": {"pwid": 1}, "ruby": {"ruby": 1},
    },
}
#: ``font-variant-ligatures: none``
NO_LIGATURES = {"liga": 0, "clig": 0, "dlig": 0, "hlig": 0, "calt": 0}


def _variant_value(prop, value):
    """Features of one font-variant-* value, or None when it is not valid (CSS: an invalid
    declaration is ignored). Each keyword group may appear once."""
    words = value.lower().split()
    if words == ["normal"]:
        return {}
    if words == ["none"] and prop == "font-variant-ligatures":
        return dict(NO_LIGATURES)
    table = VARIANT_KEYWORDS[prop]
    out = {}
    for w in words:
        f = table.get(w)
        if f is None or any(tag in out for tag in f):
            return None
        out.update(f)
    return out


def _variant_shorthand(value):
    """``font-variant`` (CSS Fonts 4 §6.11): normal, none, or keywords of the longhands (and
    ``position`` and ``caps``) → features, or None when invalid."""
    words = value.lower().split()
    if words == ["normal"]:
        return {}
    if words == ["none"]:
        return dict(NO_LIGATURES)
    out = {}
    for w in words:
        for table in VARIANT_KEYWORDS.values():
            if w in table:
                f = table[w]
                break
        else:
            return None
        if any(tag in out for tag in f):
            return None
        out.update(f)
    return out


def variant_features(style):
    """(OpenType features the font-variant properties ask for, small caps on?). The shorthand
    sets every longhand; a longhand given on the same element or below overrides its part."""
    features = {}
    for f in style.computed(("computed", "font-variant"), _own_variant_parts).values():
        features.update(f)
    return features, features.get("smcp") == 1


def _own_variant_parts(style, parent):
    """{longhand: its features} of a style, from its parent's (None at the root): a
    descendant's declaration overrides its ancestors'. The dicts are shared down the chain,
    never changed."""
    parts = {} if parent is None else parent
    spec = style.specified
    short = spec.get("font-variant")
    if short is not None and short.strip() == "initial":
        short = "normal"        # CSS-wide keywords: initial is normal, unset inherits
    if short is not None and short.strip() not in ("inherit", "unset", ""):
        f = _variant_shorthand(short.strip())
        if f is not None:
            # the shorthand resets every longhand, then sets those it names
            parts = {prop: {t: v for t, v in f.items() if t in _tags(prop)}
                     for prop in VARIANT_KEYWORDS}
            if f == NO_LIGATURES:
                parts["font-variant-ligatures"] = dict(NO_LIGATURES)
    for prop in VARIANT_KEYWORDS:
        v = spec.get(prop)
        if v is None or v.strip() in ("inherit", "unset", ""):
            continue
        if v.strip() == "initial":
            v = "normal"
        f = _variant_value(prop, v.strip())
        if f is not None:
            if parts is parent:
                parts = dict(parent)
            parts[prop] = f
    return parts


def _tags(prop):
    return {t for f in VARIANT_KEYWORDS[prop].values() for t in f} | (
        set(NO_LIGATURES) if prop == "font-variant-ligatures" else set())


#: CSS-wide keywords, which no unquoted family name may be
_CSS_WIDE = {"initial", "inherit", "unset", "default", "revert", "revert-layer"}


def family_names(text):
    """:func:`_family_names` of a value, a new list each call (parsed once per distinct
    value: a document's texts repeat a few values, and tokenizing one costs ~50 µs)."""
    names = _family_names(text)
    return None if names is None else list(names)


@functools.lru_cache(maxsize=1024)
def _family_names(text):
    """A font-family value → its list of names (a quoted name that spells a generic family
    in double quotes, as :func:`vecmsaa.fonts.db.parse_family_list` gives it), or None when
    it is not valid CSS (CSS Fonts 4 §2.1): a comma-separated list of strings and unquoted
    names, an unquoted name being one or more identifiers (``Mplus 1p`` is not one: ``1p``
    is no identifier; ``'Mplus 1p'`` is). The value is read with CSS's tokenizer, as a
    presentation attribute is parsed as a CSS value (SVG 2 §6.7, CSS Syntax 3): escapes are
    decoded (``\\4E oto Sans`` is Noto Sans) and a string left open at the end of the value
    ends there (``'Noto Sans``)."""
    import tinycss2

    from ...fonts.db import GENERIC_FAMILIES

    out, words, string = [], [], None
    for tok in [*tinycss2.parse_component_value_list(text or ""), None]:
        kind = "literal" if tok is None else tok.type
        if kind in ("whitespace", "comment") or (
                kind == "error" and tok.kind == "eof-in-string"):
            continue
        if tok is None or kind == "literal" and tok.value == ",":
            if string is not None and not words:
                name = " ".join(string.split())
                out.append(f'"{name}"' if name.lower() in GENERIC_FAMILIES else name)
            elif words and string is None:
                out.append(" ".join(words))
            else:
                return None
            words, string = [], None
        elif kind == "ident" and string is None and tok.lower_value not in _CSS_WIDE:
            words.append(tok.value)
        elif kind == "string" and string is None and not words:
            string = tok.value
        else:
            return None
    return tuple(f for f in out if f)


def valid_family_list(text):
    """Whether a font-family value is valid CSS (see :func:`family_names`)."""
    return family_names(text) is not None


def _family_list(style):
    """The computed font-family list (inherited; an invalid value is ignored with a warning;
    the initial value is ``serif``)."""
    names = style.get_valid("font-family", _valid_family_names, None)
    # a new list each call (get_valid's value is cached on the styles)
    return parse_family_list("serif") if names is None else list(names)


def _valid_family_names(value):
    names = family_names(value)
    if names is None:
        warn(f"font-family: {value[:40]} is not a valid family list: ignored")
    return names


def _spacing(value, ctx, style):
    v = (value or "normal").strip()
    if v == "normal":
        return 0.0
    # a percentage is of the viewport's normalized diagonal (SVG 2 §8.9: a length that is
    # neither horizontal nor vertical), as resvg takes it, not of its width
    return ctx.length(v, "xy", style, 0.0) or 0.0


def font_database(ctx) -> FontDatabase:
    """The database of the document's font options (looked up once per document: building
    the options' key per text cost a map of labels more than its shaping)."""
    db = ctx.cache.get("font database")
    if db is None:
        db = ctx.cache["font database"] = database_from_options(ctx.font_options)
    return db


def document_faces(ctx) -> dict:
    """{id(FaceInfo): (FaceInfo, Face or None)}: the faces loaded for the document's texts
    (load_face checks the file's time each call; a document is rendered from the files as
    they were when it first needed them). Keyed by id, the info kept alive beside its face:
    hashing a FaceInfo hashes all its fields."""
    return ctx.cache.setdefault("faces", {})


def face_location(face, spec):
    """Variation location: font-variation-settings, else wght/wdth/slnt from the CSS props."""
    if not face.axes:
        return ()
    loc = {}
    if "wght" in face.axes:
        loc["wght"] = spec.weight
    if "wdth" in face.axes:
        loc["wdth"] = spec.stretch
    if "opsz" in face.axes and spec.optical_sizing:
        loc["opsz"] = spec.size
    if spec.oblique and "slnt" in face.axes:
        # CSS Fonts 4 §5.2: slnt set to the oblique angle (OpenType's slnt counts
        # counter-clockwise, CSS's angle clockwise: oblique 10deg is slnt -10)
        loc["slnt"] = -spec.oblique
    if spec.style == "italic" and "ital" in face.axes:
        loc["ital"] = 1.0
    loc.update(dict(spec.variations))
    return face.clamp_location(loc)


def warn_font_fallback(db, spec, info):
    """Warn when none of a font-family list is available (what was used instead)."""
    if info is None:
        warn("no font available: text is not drawn")
    elif db.query(list(spec.families), spec.weight, spec.style, spec.stretch) is None:
        names = ", ".join(f"'{f}'" for f in spec.families)
        warn(f"font family {names} not found, using '{info.family}'")


def assign_faces(chars, specs, db, bounds=None, loaded=None, memo=None):
    """Face for every character. Each character's ``primary_face`` is its family list's best
    match (text decorations and baselines use its metrics). Faces are chosen per text chunk
    (``bounds``: the chunks' first indices and the end) and per font of the chunk: a
    character the font lacks takes the list's next family that has it (CSS Fonts 4 §5.2);
    for one no listed family has, the fallback face is the renderer's choice, and vecmsaa
    makes resvg's: the face for the first such character draws every one it can, and when
    it can draw the whole chunk it draws all of it, so a chunk of Latin and CJK text under a
    Latin font is one CJK run; else the next missing character picks the next face.
    Combining marks and emoji modifiers stay with their base character's face (when it has
    them), variation selectors always do. ``loaded``: a document_faces
    dict to load faces through (else one for this call); ``memo``: a dict in which short
    chunks' faces are kept for the calls that pass it (one per document, with ``loaded``:
    the faces it holds are those), else for this call."""
    primary, keys = {}, []
    loaded = {} if loaded is None else loaded
    memo = {} if memo is None else memo

    def load(info):
        hit = loaded.get(id(info))
        if hit is None:
            hit = loaded[id(info)] = (info, _load(info))
        return hit[1]

    primary_faces = {}                      # (per key: hashing a FaceInfo per character cost)
    by_spec = {}                            # id(spec) → (its key, face)
    canon = memo.setdefault("keys", {})     # key → that key: one object per value, kept
    for c, spec in zip(chars, specs):
        got = by_spec.get(id(spec))
        if got is None:
            key = (spec.families, spec.weight, spec.style, spec.stretch)
            face = primary_faces.get(key, primary_faces)
            if face is primary_faces:
                primary[key] = db.query_or_default(list(spec.families), spec.weight,
                                                   spec.style, spec.stretch)
                warn_font_fallback(db, spec, primary[key])
                face = primary_faces[key] = load(primary[key])
            key = canon.setdefault(key, key)               # one object per value
            got = by_spec[id(spec)] = key, face
        c.primary_face = got[1]
        keys.append(got[0])
    faces = [c.primary_face for c in chars]
    bounds = bounds or [0, len(chars)]
    # A chunk's faces depend on its characters and their keys alone: a short chunk's are
    # chosen once per distinct (characters, keys) and replayed (text where every character
    # has its own x is mostly repeats of a few one-character chunks; chart ticks and map
    # labels repeat across texts)
    chunks = memo.setdefault("chunks", {})
    for a, b in itertools.pairwise(bounds):
        mkey = None
        if b - a <= FACES_MEMO_CHUNK:
            mkey = "".join([c.ch for c in chars[a:b]]), tuple(map(id, keys[a:b]))
            chosen = chunks.get(mkey)
            if chosen is not None:
                for k, face in chosen:
                    faces[a + k] = face
                continue
        # (printable ASCII has no control, format character or selector)
        drawn = list(range(a, b)) if mkey is not None and mkey[0].isascii() \
            and mkey[0].isprintable() else \
            [i for i in range(a, b) if not needs_no_face(chars[i].ch)]
        picked = []
        for key in dict.fromkeys(keys[a:b]):
            spec = specs[keys.index(key, a)]
            chosen = _chunk_faces(chars, range(a, b), drawn, primary[key], spec, db, load)
            for i in range(a, b):
                if keys[i] == key and i in chosen:
                    faces[i] = chosen[i]
                    picked.append((i - a, chosen[i]))
        if mkey is not None:
            chunks[mkey] = picked
    # (ASCII has no mark, selector or modifier: most texts skip the test per character)
    for i in range(1, len(chars)) if not "".join([c.ch for c in chars]).isascii() else ():
        ch = chars[i].ch
        if faces[i - 1] is not None and (_is_variation_selector(ch) or (
                (unicodedata.category(ch).startswith("M") or 0x1F3FB <= ord(ch) <= 0x1F3FF)
                and faces[i - 1].has_char(ch))):
            faces[i] = faces[i - 1]
    return faces


#: the longest chunk whose faces assign_faces memoises
FACES_MEMO_CHUNK = 16


def _chunk_faces(chars, chunk, drawn, info, spec, db, load):
    """{index: face} for the characters of one chunk (indices ``chunk``; ``drawn``: those
    that are not controls) when its font is ``info`` (see :func:`assign_faces`); characters
    no face has are left out. A fallback face that draws the whole chunk draws its controls
    too."""
    face = load(info)
    if face is None:
        return {}
    got = {i: face for i in drawn if _draws(face, chars[i].ch)}
    listed = [f for f in (db.query([name], spec.weight, spec.style, spec.stretch)
                          for name in spec.families) if f is not None and f is not info]
    for i in drawn:
        if i not in got:
            for other in filter(None, map(load, listed)):
                if _draws(other, chars[i].ch):
                    got[i] = other
                    break
    used = [info, *listed]
    for i in drawn:
        if i in got:
            continue
        alt = db.fallback_for_char(chars[i].ch, (), spec.weight, spec.style, spec.stretch,
                                   exclude=tuple(used))
        if alt is None:
            continue
        used.append(alt)
        other = load(alt)
        if other is None:
            continue
        if all(_draws(other, chars[j].ch) for j in drawn):
            return {j: other for j in chunk}
        got.update((j, other) for j in drawn if j not in got and _draws(other, chars[j].ch))
    return got


def _draws(face, ch):
    """Whether a face draws a character: a space other than U+0020 it lacks is drawn as its
    U+0020 (HarfBuzz's space fallback)."""
    return face.has_char(ch) or (unicodedata.category(ch) == "Zs" and face.has_char(" "))


def needs_no_face(ch):
    """Whether a character needs no face of its own: controls, format characters and
    variation selectors (default ignorables, Unicode §5.21: a face that lacks a variation
    selector draws its base's default glyph; the selector picks no other face)."""
    return unicodedata.category(ch) in ("Cc", "Cf") or _is_variation_selector(ch)


def _is_variation_selector(ch):
    cp = ord(ch)
    return 0xFE00 <= cp <= 0xFE0F or 0xE0100 <= cp <= 0xE01EF


def _load(info):
    if info is None:
        return None
    try:
        return info.load()
    except FontError:
        return None
