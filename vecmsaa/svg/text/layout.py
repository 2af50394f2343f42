"""Text layout: shaping with HarfBuzz and placement of the clusters (SVG 1.1 §10 as resvg does it).

:func:`build_text` is the entry point: characters (:mod:`.content`) → faces (:mod:`.font_match`)
→ per text chunk, bidi runs shaped by HarfBuzz into clusters (kerning, ligatures, marks) with
the chunk's text as context → letter/word spacing, vertical writing modes, textLength →
cluster transforms along the line (dx/dy, rotate, text-anchor, baseline shifts) or along a
``textPath`` (:mod:`.on_path`) → glyph matrices → scene nodes (:mod:`.draw`).
"""
from __future__ import annotations

import math
import unicodedata
from bisect import bisect_right
from dataclasses import dataclass

from ...fonts.shape import join_runs, shape_run, visual_runs
from ...scene.transform import IDENTITY, compose, rotate_at, translate
from ..units import split_length, to_px
from .content import (apply_positions, apply_text_transform, collapse_white_space,
                      collect_chars, span_values)
from . import line
from .draw import draw_clusters
from .font_match import (assign_faces, document_faces, face_location, font_database,
                         font_spec, kerning_attribute, needs_no_face)
from .on_path import path_walker, position_on_path

#: scripts where letter-spacing would break joining (CSS Text 3 "cursive scripts"), as
#: code point ranges: Arabic, Syriac, NKo, Mandaic, Devanagari, Bengali, Gurmukhi, Ogham,
#: Mongolian, Syloti Nagri, Phags-pa, Arabic presentation forms
NO_LETTER_SPACING = ((0x0600, 0x08FF), (0x0900, 0x0A7F), (0x1680, 0x169F), (0x1800, 0x18AF),
                     (0xA800, 0xA87F), (0xFB50, 0xFDFF), (0xFE70, 0xFEFF))
WORD_SEPARATORS = {0x20, 0xA0, 0x1361, 0x10100, 0x10101, 0x1039F, 0x1091F}
#: a quarter turn counter-clockwise: upright glyphs on the line of vertical text, which is
#: turned clockwise
TURNED_BACK = rotate_at(-90.0, 0.0, 0.0)
#: ZWJ sequences shaped in one HarfBuzz call under ligatures turned off (_joined_ligatures)
JOINED_PER_SHAPING = 64


@dataclass(slots=True)
class Glyph:
    face: object
    location: tuple
    gid: int
    dx: float                 # offset inside its cluster (user units, y down)
    dy: float
    scale: float              # user units per font unit
    matrix: tuple | None = None


#: a cluster's carry when its later characters have no dx or dy (compared by identity)
NO_CARRY = (0.0, 0.0)


@dataclass(slots=True)
class Cluster:
    """Glyphs of one typographic character (ligature, base + marks): the unit that SVG
    positions, rotates and spaces (as resvg's GlyphCluster)."""
    char: int                 # index of its first character
    glyphs: list
    face: object
    size: float
    width: float              # the sum of its glyphs' advances
    advance: float            # width plus spacing
    ascent: float = 0.0       # user units, y up
    descent: float = 0.0
    pre: tuple = IDENTITY   # vertical writing: shift of rotated clusters
    path_ts: tuple = IDENTITY   # vertical writing: upright clusters turned back
    sx: float = 1.0           # lengthAdjust=spacingAndGlyphs
    squeezed_by: int | None = None  # the id of the element whose spacingAndGlyphs set sx
    frame: tuple = IDENTITY     # cluster transform in user units (without path_ts)
    placed: tuple = IDENTITY    # frame after path_ts: its em box and glyphs in user units
    visible: bool = True
    sideways: bool = False    # vertical writing, text-orientation: sideways
    upright: bool = False     # vertical writing, text-orientation: upright: shaped top to bottom
    shifted: bool = False     # moved by dx/dy/rotate or on a path: restarts decorations
    widest: float = 0.0       # its widest glyph's advance: on a path, the cluster's middle
    gap: float = 0.0          # textLength's spacing in its advance (after it)
    carry: tuple = NO_CARRY   # dx, dy of its characters after the first: move what follows


def shape_chunk(chars, faces, specs, start, end, text=None, upright=None, memo=None):
    """Clusters of chars[start:end] in visual order: the Unicode bidi algorithm's runs for a
    left-to-right paragraph (resvg's, whatever the ``direction`` property says), reordered;
    the characters ``upright`` marks (vertical text under text-orientation: upright) in runs
    of their own, shaped top to bottom (:func:`shaping_runs`).

    As resvg does, each bidi run is shaped whole with every face (and font settings) that
    its characters use, and each cluster is taken from the shaping by its own character's
    face: kerning and joining across tspans of different fonts come from the run's context.
    ``text`` is the characters joined (a caller shaping many chunks joins them once: joining
    per chunk made a text of one chunk per character quadratic).

    ``memo`` (a dict kept by the caller for one text, whose faces and specs stay alive): a
    chunk of at most MEMO_CHUNK characters is shaped once per distinct (characters, faces,
    specs, upright marks) and copied after that. A chunk is shaped with nothing around it
    (HarfBuzz's context is the chunk), so those are all its clusters depend on: text whose
    every character has its own x (PDF converters' output) is a few distinct one-character
    chunks repeated.
    """
    if text is None:
        text = "".join(c.ch for c in chars)
    if memo is not None and end - start <= MEMO_CHUNK:
        key = (text[start:end], tuple(map(id, faces[start:end])),
               tuple(map(id, specs[start:end])),
               None if upright is None else tuple(upright[start:end]))
        template = memo.get(key)
        if template is None:
            clusters = shape_chunk(chars, faces, specs, start, end, text, upright)
            memo[key] = _template(clusters, start)
            return clusters
        return _from_template(template, start)
    chunk = (start, end)
    clusters = []
    for s, e, d in shaping_runs(text, start, end, upright):
        # each character's shaping key, found once per (face, spec) pair (by which
        # _pick_clusters looks a character's up again)
        keys, key_of, missing = {}, {}, False
        for k in range(s, e):
            face = faces[k]
            if face is None:
                missing = True
                continue
            pair = id(face), id(specs[k])
            if pair not in key_of:
                key = key_of[pair] = _shaping_key(face, specs[k])
                keys.setdefault(key, k)
        if not keys:
            continue
        shaped = {key: _shape_clusters(chars, faces, specs, text, s, e, d, k, chunk)
                  for key, k in keys.items()}
        if len(keys) == 1 and not missing and _distinct_starts(shaped):
            # one shaping, every character drawn, clusters at distinct characters: the
            # picking takes each of them alone, in their order
            clusters.extend(*shaped.values())
        else:
            clusters.extend(_pick_clusters(shaped, key_of, faces, specs, e, d))
    return clusters


#: the longest chunk shape_chunk's memo keeps (longer ones rarely repeat)
MEMO_CHUNK = 16


def _template(clusters, start):
    """What shape_chunk's memo keeps of a chunk's clusters (fresh from the shaping): each
    cluster's fields that the shaping sets, its character counted from the chunk's start."""
    return [(c.char - start, [(g.face, g.location, g.gid, g.dx, g.dy, g.scale) for g in c.glyphs],
             c.face, c.size, c.width, c.advance, c.ascent, c.descent, c.upright, c.widest)
            for c in clusters]


def _from_template(template, start):
    """New clusters (and glyphs: the layout changes both) of a memo's template for the chunk
    starting at ``start``."""
    out = []
    for k, glyphs, face, size, width, advance, ascent, descent, upright, widest in template:
        c = Cluster(k + start, [Glyph(*g) for g in glyphs], face, size, width, advance, ascent,
                    descent)
        c.upright = upright
        c.widest = widest
        out.append(c)
    return out


def shaping_runs(text, start, end, upright):
    """The runs of text[start:end] to shape, in visual order, as (start, end, direction):
    each stretch of characters set upright (``upright[k]``; None: none) one run shaped top
    to bottom, with the font's vertical metrics and forms (CSS Writing Modes 3 §5.1, §7.1:
    HarfBuzz applies ``vert`` and the vertical advances and origins); the rest the bidi
    algorithm's runs. Upright characters count as strong left-to-right for bidi (§5.1), in
    a left-to-right paragraph: no reordering crosses them, so the stretches between them
    are reordered alone."""
    if upright is None or not any(upright[start:end]):
        return [(s + start, e + start, d) for s, e, d in visual_runs(text[start:end], "ltr")]
    runs = []
    k = start
    while k < end:
        stop = k + 1
        while stop < end and upright[stop] == upright[k]:
            stop += 1
        if upright[k]:
            runs.append((k, stop, "ttb"))
        else:
            runs.extend((s + k, e + k, d) for s, e, d in visual_runs(text[k:stop], "ltr"))
        k = stop
    return runs


def _distinct_starts(shaped):
    (got,) = shaped.values()
    return len({c.char for c in got}) == len(got)


def _pick_clusters(shaped, key_of, faces, specs, e, d):
    """The clusters of a run (ending at ``e``, direction ``d``) shaped with each of its keys
    (``shaped``: {key: clusters}, the first key the base), each character's taken from the
    shaping of its own key (``key_of``: by (id(face), id(spec)))."""
    index = {key: _ClusterIndex(got) for key, got in shaped.items()}
    base = index[next(iter(shaped))]
    covered = set()
    clusters = []
    for cl in base.clusters:
        # Characters of this base cluster, each taken from the shaping by its own face
        # (a ligature of the base font may split into several clusters of another).
        end = base.end(cl, e)
        picked = []
        for k in range(cl.char, end):
            face = faces[k]
            if k in covered or face is None:   # None: a zero or negative size
                continue
            own = index.get(key_of[id(face), id(specs[k])], base)
            pick = own.first.get(k)
            if pick is None:
                if k == cl.char:
                    pick, own = cl, base
                else:
                    continue
            picked.append(pick)
            covered.update(range(k, own.end(pick, e)))
        clusters.extend(reversed(picked) if d == "rtl" else picked)
    return clusters


def _shaping_key(face, spec):
    """What a character's shaping depends on besides the text: its face, feature settings
    and variation location (with a font size that sets ``opsz``, CSS Fonts 4 §7.1
    font-optical-sizing: a span of another size in a variable font is shaped and drawn at
    its own optical size)."""
    return id(face), spec.features, face_location(face, spec)


class _ClusterIndex:
    """The clusters of one shaping, looked up by character in constant time and their ends
    by bisection: per character scans of all clusters made long texts quadratic."""

    def __init__(self, clusters):
        self.clusters = clusters
        self.first = {}                      # character → its first cluster, in shaping order
        for c in clusters:
            self.first.setdefault(c.char, c)
        self.starts = sorted(self.first)

    def end(self, cluster, end):
        """First character after a cluster in logical order (``end`` for the last one)."""
        i = bisect_right(self.starts, cluster.char)
        return self.starts[i] if i < len(self.starts) else end


def shaped_run(face, spec, loc, text, s, e, direction, context):
    """text[s:e] shaped by HarfBuzz with ``face`` and ``spec``'s features at variation
    location ``loc`` (one ShapedRun; pieces where ligatures are off, _joined_ligatures)."""
    return join_runs([shape_run(face, text, a, b, location=loc, features=features,
                                direction=direction, context=context)
                      for a, b, features in _joined_ligatures(spec.features, text, s, e)])


def cluster_owners(text, faces, s, e, run):
    """{character: the character whose cluster it joins} for the characters of text[s:e]
    that ``run`` (its shaping) left in clusters of their own but that extend a grapheme."""
    # One cluster per grapheme (SVG 2's typographic character, the unit resvg positions,
    # rotates, spaces and sizes): HarfBuzz's character-level clusters leave a combining mark
    # it did not merge with its base on its own, which then turned about its own origin, got
    # letter-spacing between it and its base, and kept its own font size. Its glyphs join
    # the cluster of the character it extends.
    # A grapheme whose base character a ligature took (the र of the conjunct श्र, whose
    # matra ी HarfBuzz leaves in a cluster of its own) joins the ligature's cluster: the
    # ligature and the grapheme share a character, so they are one typographic character.
    owner = {}
    base = None
    starts = None
    # (ASCII text extends no cluster: most labels skip the test per character)
    # A mark or emoji modifier drawn by another face than its base's (the base's face lacks
    # it) stays a cluster of its own, taken from its own face's shaping: a skin-tone modifier
    # no face has is drawn as the missing glyph after its emoji (as resvg 0.48.1 and
    # Chromium 150 draw it), not lost in the emoji's cluster.
    for i in range(s, e) if not text[s:e].isascii() else ():
        if base is not None and (_extends(text[i]) or _joined(text, base, i)) and (
                faces[i] is faces[base] or needs_no_face(text[i])):
            if starts is None:
                starts = sorted(set(run.clusters.tolist()))
            k = bisect_right(starts, base) - 1
            owner[i] = starts[k] if k >= 0 else base
        else:
            base = i
    return owner


def _shape_clusters(chars, faces, specs, text, s, e, direction, k, context):
    """text[s:e] shaped with the face and settings of character k, as clusters; ``context``
    (the chunk) is what HarfBuzz sees around the run."""
    face = faces[k]
    spec = specs[k]
    loc = face_location(face, spec)
    run = shaped_run(face, spec, loc, text, s, e, direction, context)
    owner = cluster_owners(text, faces, s, e, run)
    out = []
    current = None
    pen = 0.0
    upem = face.units_per_em
    m = face.metrics
    # Top to bottom (upright vertical text): the pen moves down by the vertical advances
    # (HarfBuzz's are negative, y up), each glyph placed upright from it by its offsets,
    # which hold its vertical origin; the cluster is turned upright as a whole
    # (apply_writing_mode), its em box the font's ascender-to-descender height across the
    # column about its middle.
    down = direction == "ttb"
    advances = (-run.advances[:, 1] if down else run.advances[:, 0]).tolist()
    # (Python numbers from the arrays at once: numpy scalars per glyph cost more than the rest)
    for gid, cl, adv, off_x, off_y in zip(run.gids.tolist(), run.clusters.tolist(), advances,
                                          run.offsets[:, 0].tolist(), run.offsets[:, 1].tolist()):
        cl = owner.get(cl, cl)
        if current is None or current.char != cl:
            size = specs[cl].size
            scale = size / upem
            if down:
                top = (m.ascender - m.descender) * scale / 2
                bottom = -top
            else:
                top, bottom = m.ascender * scale, m.descender * scale
            current = Cluster(cl, [], face, size, 0.0, 0.0, top, bottom, upright=down)
            out.append(current)
            pen = 0.0
        dx, dy = off_x * scale, -off_y * scale
        current.glyphs.append(Glyph(face, loc, gid, dx, pen + dy, scale) if down else
                              Glyph(face, loc, gid, pen + dx, dy, scale))
        width = adv * scale
        pen += width
        current.width = current.advance = pen
        if width > current.widest:
            current.widest = width
    return out


def _joined_ligatures(features, text, s, e):
    """text[s:e] as pieces to shape, (start, end, features): ligatures turned off
    (letter-spacing does so, CSS Text 3 §8.2) stay on across a zero width joiner, which asks
    for the joined form (Unicode §23.2): emoji ZWJ sequences are ligatures. HarfBuzz takes a
    feature on ranges (counted from the piece's start); it sets each range's mask over the
    whole buffer, so a run with thousands of them was quadratic and then failed (3,000 ZWJ
    sequences in Twitter Color Emoji: uharfbuzz's MemoryError). A run with more than
    JOINED_PER_SHAPING sequences is cut between sequences into pieces holding that many
    (kerning across a cut is lost: HarfBuzz sees the other side as context only)."""
    features = dict(features)        # (a spec's features: (tag, value) pairs)
    off = [t for t in ("liga", "clig") if features.get(t) == 0]
    if not off or "\u200d" not in text[s:e]:
        return [(s, e, features)]
    joined = []                      # the sequences: overlapping ranges around joiners merged
    for j in range(s + 1, e - 1):
        if text[j] == "\u200d":
            a, b = j - 1, j + 2
            while a > s and _extends(text[a]):
                a -= 1
            while b < e and _extends(text[b]):
                b += 1
            if joined and a <= joined[-1][1]:
                joined[-1][1] = max(joined[-1][1], b)
            else:
                joined.append([a, b])
    if not joined:
        # joiners only at the run's ends (a chunk of its own, by an x per character): they
        # join nothing in it
        return [(s, e, features)]
    pieces = []
    for n in range(0, len(joined), JOINED_PER_SHAPING):
        group = joined[n:n + JOINED_PER_SHAPING]
        start = s if n == 0 else pieces[-1][1]
        end = group[-1][1] if n + JOINED_PER_SHAPING < len(joined) else e
        ranges = [(0, end - start, 0)] + [(a - start, b - start, 1) for a, b in group]
        pieces.append((start, end, {**features, **{t: ranges for t in off}}))
    return pieces


def _extends(ch):
    """Characters that extend a grapheme cluster (UAX #29 Extend, ZWJ, emoji modifiers):
    combining marks, joiners, variation selectors, tags."""
    cp = ord(ch)
    return (unicodedata.category(ch) in ("Mn", "Me", "Mc") or cp in (0x200C, 0x200D)
            or 0xFE00 <= cp <= 0xFE0F or 0x1F3FB <= cp <= 0x1F3FF or 0xE0020 <= cp <= 0xE007F
            or 0xE0100 <= cp <= 0xE01EF)


#: Extended_Pictographic (UAX #29, emoji-data.txt), by blocks: what a zero width joiner
#: joins into one emoji sequence
_PICTOGRAPHIC = ((0x00A9, 0x00A9), (0x00AE, 0x00AE), (0x203C, 0x203C), (0x2049, 0x2049),
                 (0x2122, 0x2122), (0x2139, 0x2139), (0x2194, 0x21AA), (0x231A, 0x23FF),
                 (0x24C2, 0x24C2), (0x25AA, 0x27BF), (0x2934, 0x2935), (0x2B05, 0x2B55),
                 (0x3030, 0x3030), (0x303D, 0x303D), (0x3297, 0x3299), (0x1F000, 0x1F0FF),
                 (0x1F10D, 0x1F1AD), (0x1F201, 0x1F64F), (0x1F680, 0x1F6FF),
                 (0x1F774, 0x1F7FF), (0x1F80C, 0x1FAFF), (0x1FC00, 0x1FFFD))


def _joined(text, base, i):
    """Whether text[i] continues the grapheme cluster that starts at ``base`` though it
    extends nothing (UAX #29): a pictograph after a zero width joiner (GB11: an emoji ZWJ
    sequence is one cluster even where the font has no glyph for it) and the second of a
    pair of regional indicators (GB12/13: a flag)."""
    cp = ord(text[i])
    if 0x1F1E6 <= cp <= 0x1F1FF:
        return i == base + 1 and 0x1F1E6 <= ord(text[base]) <= 0x1F1FF
    return text[i - 1] == "\u200d" and any(lo <= cp <= hi for lo, hi in _PICTOGRAPHIC)


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


def apply_writing_mode(clusters, chars, orientations):
    """Vertical text (``orientations``: each character's text-orientation): characters set
    upright are turned back upright, the pen on the middle of the column; the others keep
    the rotated line, centred on the column; under text-orientation: sideways every
    character keeps the rotated line, on its alphabetic baseline. Under upright every
    character is set upright, shaped top to bottom with its own vertical origin and
    advance; under mixed the Vertical_Orientation U ones (CJK) are, with their horizontal
    advance and their em box centred on it (as resvg 0.48.1)."""
    for c in clusters:
        if orientations[c.char] == "sideways":
            c.sideways = True
        elif c.upright:
            c.path_ts = TURNED_BACK
        elif _is_upright(ord(chars[c.char].ch)):
            # its em box centred on the advance: the glyph origin half the advance left of
            # the column's middle and half the advance plus the middle of the em box's
            # height down from the pen
            mid = (c.ascent + c.descent) / 2
            c.path_ts = compose(TURNED_BACK, translate(-c.width / 2, c.width / 2 + mid))
            c.ascent, c.descent = c.width / 2, -c.width / 2
        else:
            # Rotated characters sit on the central baseline (measured against resvg 0.48)
            c.pre = translate(0.0, (c.ascent + c.descent) / 2)


def text_orientation(style):
    """text-orientation (CSS Writing Modes 3 §5.1; inherited, CSS only): mixed, upright or
    sideways. sideways sets vertical text as horizontal text turned 90° clockwise, CJK
    included, in horizontal typographic mode, whose dominant baseline is the alphabetic one
    (§4.2), not the central one; upright sets every character upright, in vertical
    typographic mode, as mixed sets the CJK ones."""
    return style.get_valid("text-orientation", _text_orientation, "mixed")


def _text_orientation(value):
    # sideways-right: the name of sideways in CSS Writing Modes 3's drafts, which Chromium 150
    # and Gecko (its reftest text/vertical-01) still read as sideways
    if value == "sideways-right":
        return "sideways"
    return value if value in ("mixed", "upright", "sideways") else None


#: Unicode's Vertical_Orientation=U characters (UAX #50; Unicode 15.0's
#: VerticalOrientation.txt, adjacent ranges merged), as flat (first, last) pairs: CJK, kana,
#: hangul, emoji, and the symbols set upright in vertical text (circled digits, Roman
#: numerals, squares, stars, suits, ...). Tu and Tr characters (CJK punctuation, small kana,
#: brackets, long vowel mark) are turned like Latin, as resvg 0.48.1 turns them (only U is
#: upright there; Chromium sets them upright with the font's vertical forms).
_UPRIGHT = (
    0x00A7, 0x00A7, 0x00A9, 0x00A9, 0x00AE, 0x00AE, 0x00B1, 0x00B1, 0x00BC, 0x00BE,
    0x00D7, 0x00D7, 0x00F7, 0x00F7, 0x02EA, 0x02EB, 0x1100, 0x11FF, 0x1401, 0x167F,
    0x18B0, 0x18FF, 0x2016, 0x2016, 0x2020, 0x2021, 0x2030, 0x2031, 0x203B, 0x203C,
    0x2042, 0x2042, 0x2047, 0x2049, 0x2051, 0x2051, 0x2065, 0x2065, 0x20DD, 0x20E0,
    0x20E2, 0x20E4, 0x2100, 0x2101, 0x2103, 0x2109, 0x210F, 0x210F, 0x2113, 0x2114,
    0x2116, 0x2117, 0x211E, 0x2123, 0x2125, 0x2125, 0x2127, 0x2127, 0x2129, 0x2129,
    0x212E, 0x212E, 0x2135, 0x213F, 0x2145, 0x214A, 0x214C, 0x214D, 0x214F, 0x2189,
    0x218C, 0x218F, 0x221E, 0x221E, 0x2234, 0x2235, 0x2300, 0x2307, 0x230C, 0x231F,
    0x2324, 0x2328, 0x232B, 0x232B, 0x237D, 0x239A, 0x23BE, 0x23CD, 0x23CF, 0x23CF,
    0x23D1, 0x23DB, 0x23E2, 0x2422, 0x2424, 0x24FF, 0x25A0, 0x2619, 0x2620, 0x2767,
    0x2776, 0x2793, 0x2B12, 0x2B2F, 0x2B50, 0x2B59, 0x2B97, 0x2B97, 0x2BB8, 0x2BD1,
    0x2BD3, 0x2BEB, 0x2BF0, 0x2BFF, 0x2E50, 0x2E51, 0x2E80, 0x3000, 0x3003, 0x3007,
    0x3012, 0x3013, 0x3020, 0x302F, 0x3031, 0x3040, 0x3042, 0x3042, 0x3044, 0x3044,
    0x3046, 0x3046, 0x3048, 0x3048, 0x304A, 0x3062, 0x3064, 0x3082, 0x3084, 0x3084,
    0x3086, 0x3086, 0x3088, 0x308D, 0x308F, 0x3094, 0x3097, 0x309A, 0x309D, 0x309F,
    0x30A2, 0x30A2, 0x30A4, 0x30A4, 0x30A6, 0x30A6, 0x30A8, 0x30A8, 0x30AA, 0x30C2,
    0x30C4, 0x30E2, 0x30E4, 0x30E4, 0x30E6, 0x30E6, 0x30E8, 0x30ED, 0x30EF, 0x30F4,
    0x30F7, 0x30FB, 0x30FD, 0x3126, 0x3128, 0x31EF, 0x3200, 0x32FE, 0x3358, 0x337A,
    0x3380, 0xA4CF, 0xA960, 0xA97F, 0xAC00, 0xD7FF, 0xE000, 0xFAFF, 0xFE10, 0xFE1F,
    0xFE30, 0xFE48, 0xFE53, 0xFE57, 0xFE5F, 0xFE62, 0xFE67, 0xFE6F, 0xFF02, 0xFF07,
    0xFF0A, 0xFF0B, 0xFF0F, 0xFF19, 0xFF20, 0xFF3A, 0xFF3C, 0xFF3C, 0xFF3E, 0xFF3E,
    0xFF40, 0xFF5A, 0xFFE0, 0xFFE2, 0xFFE4, 0xFFE7, 0xFFF0, 0xFFF8, 0xFFFC, 0xFFFD,
    0x10980, 0x1099F, 0x11580, 0x115FF, 0x11A00, 0x11ABF, 0x13000, 0x1345F, 0x14400, 0x1467F,
    0x16FE0, 0x18D7F, 0x1AFF0, 0x1B2FF, 0x1CF00, 0x1CFCF, 0x1D000, 0x1D1FF, 0x1D2E0, 0x1D37F,
    0x1D800, 0x1DAAF, 0x1F000, 0x1F1FF, 0x1F202, 0x1F7FF, 0x1F900, 0x1FAFF, 0x20000, 0x2FFFD,
    0x30000, 0x3FFFD, 0xF0000, 0xFFFFD, 0x100000, 0x10FFFD,
)
_UPRIGHT_STARTS = _UPRIGHT[0::2]


def _is_upright(cp):
    """Unicode Vertical_Orientation U."""
    i = bisect_right(_UPRIGHT_STARTS, cp) - 1
    return i >= 0 and cp <= _UPRIGHT[2 * i + 1]


def apply_length_adjust(chunks, chars, text_length, inside, vertical):
    """textLength on the elements of ``text_length`` ({element id: (length, adjust)}; each
    character's ``inside``: the spans of those it is in, linked innermost first) over
    the text's chunks (``chunks``: (index of the first character, clusters) in text order),
    by SVG 2's text layout algorithm (§11.5.5, "apply 'textLength' attribute"), which comes
    after the dx/dy adjustment and before the absolute x/y positions and the anchoring: an
    element's characters are adjusted together wherever they are, their extent measured on
    the line they would make without their absolute positions (advances and the dx
    accumulated since the last absolute x), and every typographic character of the element,
    in every chunk, is spaced by one ``delta``. A chunk that an absolute position starts keeps
    its place: the length is that of the line before it is cut into chunks, not of each chunk.

    A descendant with a textLength of its own (SVG 2's "resolved descendant node") keeps it:
    descendants are adjusted before their ancestors, each resolved descendant counts as one
    character of the ancestor's spacing, the gap after it is the ancestor's, and the rest of
    the ancestor's content gets the ancestor's length less its resolved descendants' (§11.5.3:
    "the total advance values for the other content within that ancestor is the
    difference"). The spacing after an element's last character (``gap``) moves the text
    after it in its chunk but is no part of the chunk's extent for text-anchor."""
    if not text_length:
        return
    # the line: every cluster in order with the inline offset (dx, or dy in vertical text)
    # accumulated at it, which an absolute inline position or a textPath restarts
    line, offset = [], {}
    total = 0.0
    previous_path = None
    for first, clusters in chunks:
        start = chars[first]
        on_path = start.text_path is not None
        if ((start.y if vertical and not on_path else start.x) is not None
                or start.text_path is not previous_path):
            total = 0.0
        previous_path = start.text_path
        for c in clusters:
            ch = chars[c.char]
            total += ch.dy if vertical and not on_path else ch.dx
            offset[id(c)] = total
            total += c.carry[1] if vertical and not on_path else c.carry[0]
            line.append((c, on_path))
    members, depth = length_members(line, inside)
    for el_id in sorted(members, key=lambda k: -depth[k]):
        target, adjust = text_length[el_id]
        # the element's units in line order: its own clusters (and those of descendants
        # without a length), and its resolved descendants, each one unit of its length
        units, blocks = [], {}      # units: [first cluster, last cluster, length, block]
        for c0, c1, inner, on_path in members[el_id]:
            if inner is None:
                # its advance as laid out, letter- and word-spacing included (SVG 2 measures
                # the advances of the CSS layout; resvg takes the glyphs' alone, "discarding
                # any word-spacing and letter-spacing", which Chromium keeps)
                units.append([c0, c0, c0.advance, False, on_path])
            else:
                blocks[inner] = unit = [c0, c1, text_length[inner][0], True, on_path]
                units.append(unit)
        if not units:
            continue
        # SVG 2: a = min(pos, pos + advance), b = max(...) over the element's characters, at
        # their places on the line (a resolved descendant: its length from its first one,
        # which covers the offsets inside it)
        lo, hi = math.inf, -math.inf
        pen = 0.0
        for c0, c1, length, _, _ in units:
            pos = pen + offset[id(c0)]
            lo, hi = min(lo, pos, pos + length), max(hi, pos, pos + length)
            pen += length - (offset[id(c1)] - offset[id(c0)])
        extent = hi - lo
        own = [(u[0], u[4]) for u in units if not u[3]]
        if adjust == "spacingAndGlyphs":
            # the element's own clusters (with the dx between them) take the length its
            # resolved descendants leave
            kept = sum(text_length[k][0] for k in blocks)
            if extent - kept <= 0:
                continue
            factor = (target - kept) / (extent - kept)
            if factor < 0.001:
                continue
            for c, on_path in own:
                c.sx, c.squeezed_by = factor, el_id
                if on_path:
                    c.advance *= factor
                    c.width *= factor
                    c.widest *= factor
        else:
            n = len(units)
            delta = (target - extent) / (n - 1) if n > 1 else 0.0
            for c, _ in own:
                c.advance, c.gap = c.advance + delta, delta
            if n > 1:
                for _, last, _, _, _ in blocks.values():
                    # the block's own trailing gap becomes the ancestor's gap after it
                    last.advance, last.gap = last.advance - last.gap + delta, delta


def anchor_shift(anchor, clusters, chars, inline_dy=False, on_path=False):
    """The move of a chunk laid from 0 that text-anchor makes (SVG 2 "apply anchoring"): the
    chunk's extent is that of its characters where they are, each from its position (its dx
    included) to that plus its own advance, so the dx between characters counts and the
    spacing textLength puts after the last does not; start puts the extent's start, end its
    end and middle its middle where the first character is (its own dx kept). The inline
    offsets are dy in vertical text (``inline_dy``); on a path (``on_path``) a squeezed
    cluster's advance already holds its lengthAdjust scale."""
    if anchor not in ("middle", "end"):
        return 0.0
    pos = 0.0
    lo, hi = math.inf, -math.inf
    k = 1 if inline_dy else 0
    for c in clusters:
        ch = chars[c.char]
        sx = c.sx
        pos += (ch.dy if inline_dy else ch.dx) * sx
        advance = c.advance if on_path else c.advance * sx
        end = pos + advance - c.gap * sx
        lo, hi = min(lo, pos, end), max(hi, pos, end)
        pos += advance + c.carry[k] * sx
    first = chars[clusters[0].char]
    first = (first.dy if inline_dy else first.dx) * clusters[0].sx
    return first - (hi if anchor == "end" else (lo + hi) / 2)


def carry_offsets(clusters, chars, end):
    """The dx and dy of the characters of a typographic character after its first (a
    ligature's, a conjunct's): the character is placed by its first character's values, and
    SVG 2 ("adjust positions: dx, dy") adds every addressable character's to the shift of
    the characters after it. ``end``: the chunk's end."""
    starts = sorted(c.char for c in clusters)
    for c in clusters:
        i = bisect_right(starts, c.char)
        stop = starts[i] if i < len(starts) else end
        if stop - c.char > 1:
            dx = sum(chars[k].dx for k in range(c.char + 1, stop))
            dy = sum(chars[k].dy for k in range(c.char + 1, stop))
            if dx or dy:
                c.carry = (dx, dy)


def position_linear(clusters, chars, anchor, vertical):
    """Cluster transforms of a chunk laid along x from 0 (the anchor moves the start);
    returns the pen at its end. A cluster squeezed by lengthAdjust=spacingAndGlyphs (``sx``)
    takes its advance and its dx scaled with its glyphs: a chunk scaled alike throughout is
    that chunk scaled about its start, and spans of a text and of a tspan with lengths of
    their own follow each other."""
    x = anchor_shift(anchor, clusters, chars, vertical)
    y = 0.0
    for c in clusters:
        ch = chars[c.char]
        if vertical:
            y -= ch.dx
            x += ch.dy * c.sx
        else:
            x += ch.dx * c.sx
            y += ch.dy
        c.shifted = c.shifted or bool(ch.dx or ch.dy)
        if c.pre is IDENTITY and c.sx == 1.0 and math.isfinite(x) and math.isfinite(y):
            # the two compositions below written out for most clusters (neither shifted
            # by vertical writing nor squeezed): their products are exact here
            frame = (1.0, 0.0, 0.0, 1.0, x + 0.0, y + 0.0)
        else:
            frame = compose(compose(c.pre, translate(x, y)), (c.sx, 0.0, 0.0, 1.0, 0.0, 0.0))
        if ch.rotate:
            frame = compose(frame, rotate_at(ch.rotate, 0.0, 0.0))
            c.shifted = True
        c.frame = frame
        x += c.advance * c.sx
        if c.carry is not NO_CARRY:
            if vertical:
                y -= c.carry[0]
                x += c.carry[1] * c.sx
            else:
                x += c.carry[0] * c.sx
                y += c.carry[1]
    return x, y



def baseline_offset(span, face, spec, vertical=False):
    """Shift (user units, positive = down) of the baseline for dominant-/alignment-baseline
    and baseline-shift of this span's element and its ancestors."""
    m = face.metrics
    scale = spec.size / face.units_per_em
    shift = 0.0
    align = span.computed("alignment-baseline", _alignment_baseline, "auto")
    base = align if align not in ("auto", "baseline") else _dominant_baseline(span.style)
    table = {
        "middle": m.x_height / 2, "central": (m.ascender + m.descender) / 2,
        "hanging": m.ascender * 0.8, "mathematical": m.ascender * 0.5,
        "text-before-edge": m.ascender, "text-after-edge": m.descender,
        "ideographic": m.descender, "before-edge": m.ascender, "after-edge": m.descender,
    }
    if base in table and not vertical:
        shift += table[base] * scale
    # baseline-shift accumulates over the ancestors that set it
    return shift - span.computed(("baseline-shift", id(face)),
                                 lambda span, above: _baseline_shift(span, face, above), 0.0)


def _baseline_shift(span, face, above):
    """The baseline shifts (user units, positive = up) of a span and its ancestors, from
    theirs (``above``), with ``face``'s sub- and superscript offsets; on <text> itself
    baseline-shift is ignored (resvg)."""
    s = span.style
    v = (s.specified.get("baseline-shift") or "").strip()
    fs = length_fs = s.font_size()
    if v == "inherit":
        v, length_fs = _inherited_baseline_shift(s)
    if span.parent is None or v in ("", "baseline"):
        return above
    if v == "sub":
        return above - _os2(face, "ySubscriptYOffset", 0.2 * face.units_per_em) * fs \
            / face.units_per_em
    if v == "super":
        return above + _os2(face, "ySuperscriptYOffset", 0.34 * face.units_per_em) * fs \
            / face.units_per_em
    if v.endswith("%"):
        try:
            return above + float(v[:-1]) / 100 * fs
        except ValueError:
            return above
    parsed = split_length(v)
    return above if parsed is None else above + to_px(parsed[0], parsed[1], length_fs)


def _inherited_baseline_shift(style):
    """``baseline-shift: inherit``: the parent's computed value (the property is not
    inherited otherwise, so a parent without one gives ``baseline``), with the font size its
    lengths are computed in. A length is computed where it is declared (em of that element's
    font size); keywords and percentages stay as specified and take this element's (CSS
    Inline 3 §4.3: computed value "the specified keyword or a computed <length-percentage>")."""
    parent = style.parent
    while parent is not None:
        v = (parent.specified.get("baseline-shift") or "").strip()
        if v != "inherit":
            return (v or "baseline"), parent.font_size()
        parent = parent.parent
    return "baseline", style.font_size()


def _alignment_baseline(span, enclosing):
    """alignment-baseline for the characters of an element: its own, else that of the nearest
    enclosing text content element (up to <text>) that sets one (``enclosing``). The property
    is not inherited, but it aligns the element's whole box, so the characters of a nested
    span without its own move with the span that sets it (SVG 1.1 §10.9.2, CSS Inline 3 §4);
    one level down this is also where resvg looks (the element, then its parent)."""
    s = span.style
    # an invalid value is ignored, as if not specified (CSS: the declaration is dropped),
    # so the enclosing span's or the dominant baseline applies
    v = (s.get("alignment-baseline") or "").strip().lower() \
        if "alignment-baseline" in s.specified else ""
    if v in ("initial", "unset"):
        # the initial value, auto, as explicitly set: the box sits on its parent's baseline
        # (CSS Cascade 4 §7.1, §7.3: unset is initial for a property that is not inherited)
        return "auto"
    return v if v in ALIGNMENT_BASELINES else enclosing


#: alignment-baseline's values: SVG 1.1's. CSS Inline 3's text-top and text-bottom are
#: invalid here, as in resvg 0.48.1 and Chromium (session 23's three-way audit)
ALIGNMENT_BASELINES = frozenset((
    "auto", "baseline", "before-edge", "text-before-edge", "middle", "central", "after-edge",
    "text-after-edge", "ideographic", "alphabetic", "hanging", "mathematical"))


#: dominant-baseline's values: SVG 1.1's (before-edge and after-edge are alignment-baseline
#: values only); text-top and text-bottom are invalid, as for alignment-baseline
DOMINANT_BASELINES = frozenset((
    "auto", "use-script", "no-change", "reset-size", "ideographic", "alphabetic", "hanging",
    "mathematical", "central", "middle", "text-after-edge", "text-before-edge"))


def _dominant_baseline(style):
    """dominant-baseline (inherited; initial auto), with SVG 1.1's no-change and reset-size
    taking the parent's value, as an invalid value does (CSS; resvg takes auto on a span)."""
    return style.get_valid("dominant-baseline", _own_dominant_baseline, "auto")


def _own_dominant_baseline(value):
    if value in DOMINANT_BASELINES and value not in ("no-change", "reset-size"):
        return value
    return None


def _os2(face, name, default):
    t = face.ttfont
    if "OS/2" in t:
        v = getattr(t["OS/2"], name, None)
        if v:
            return abs(v)
    return default



def length_members(line, inside):
    """The members of each element with a length (by id) in line order (``line``: (cluster,
    on a path) in order; ``inside``: for each character the spans of those elements it is
    in, linked innermost first), as [first cluster, last cluster, the resolved descendant's
    id or None, on a path]: its own clusters (and those of descendants without a length;
    first = last) and each resolved descendant next below it, at its first cluster and with
    its last; and each element's depth (the number of elements with a length around it).

    A cluster is a member of its nearest element with a length, and starts a block in the
    ancestors' only where it is the first cluster of those it is in: a cluster's ancestors
    are looked at there alone, not all of them for each cluster (spans nested a thousand
    deep). Last clusters are carried up once, innermost elements first."""
    members, above, last_of, blocks = {}, {}, {}, {}   # last_of: (line index, cluster)
    for i, (c, on_path) in enumerate(line):
        link = inside[c.char]
        if link is None:
            continue
        inner = id(link[0].el)
        members.setdefault(inner, []).append([c, c, None, on_path])
        last_of[inner] = i, c
        while inner not in above:
            link = link[1]
            above[inner] = outer = None if link is None else id(link[0].el)
            if outer is None:
                break
            blocks[inner] = block = [c, c, inner, on_path]
            members.setdefault(outer, []).append(block)
            inner = outer
    depth = {}
    for k in above:
        path = []
        while k is not None and k not in depth:
            path.append(k)
            k = above[k]
        d = -1 if k is None else depth[k]
        for k in reversed(path):
            d += 1
            depth[k] = d
    for k in sorted(depth, key=lambda k: -depth[k]):
        outer = above[k]
        if outer is not None:
            blocks[k][1] = last_of[k][1]
            if last_of[k][0] > last_of.get(outer, (-1,))[0]:
                last_of[outer] = last_of[k]
    return members, depth


def text_lengths(chars, ctx):
    """{element id: (textLength, lengthAdjust)} of the elements with a valid textLength that
    hold characters, and for each character the spans of those it is in, linked (span,
    rest) innermost first (Span.computed: each span once)."""
    text_length = {}

    def own(span, above):
        value = span.el.get("textLength")
        if value is not None:
            # (a percentage: of the viewport's normalized diagonal, as for the spacings)
            length = ctx.length(value, "xy", span.style)
            if length is not None and length >= 0:
                adjust = (span.el.get("lengthAdjust") or "spacing").strip()
                text_length[id(span.el)] = (length, adjust)
                return span, above
        return above
    return text_length, span_values(chars, "lengths", own)


#: the part of what spacingAndGlyphs took from an anchored chunk that moves its end
_UNSQUEEZED_PART = {"middle": 0.5, "end": 0.0}


def element_spec(el, style, ctx):
    """The font spec of a text content element of computed ``style``: one object per value
    for the whole document (siblings that specify the same values share a Style
    (document.Style.child), and so one spec, made once: a map of labels has thousands of
    texts in one style; the Style is the key itself, kept alive by it)."""
    spec_cache = ctx.cache.setdefault("font specs", {})
    key = style, kerning_attribute(el), ctx.viewport
    s = spec_cache.get(key)
    if s is None:
        # one object per value: the shaping memo is keyed by identity, and texts in other
        # styles (each chart's axis its own) often have equal specs
        spec_values = ctx.cache.setdefault("font spec values", {})
        s = font_spec(style, ctx, el)
        s = spec_cache[key] = spec_values.setdefault(s, s)
    return s


def build_text(element, ctx):
    """Scene nodes of one ``<text>`` element (see the module doc)."""
    if line.ENABLED:
        # a <text> of characters alone, recognised before its characters are made
        nodes = line.simple_text(element, ctx)
        if nodes is not None:
            return nodes
    styles = {}
    chars = collapse_white_space(collect_chars(element, ctx, styles))
    ctx.count_characters(len(chars))
    if not chars:
        return []
    if line.ENABLED and element.children:
        # lines of one element each (Inkscape's tspans), each laid out as simple_text's
        nodes = line.span_lines(element, chars, styles, ctx)
        if nodes is not None:
            return nodes
    apply_positions(element, chars, ctx, styles)
    chars = apply_text_transform(chars, styles, ctx.style)
    # A textPath in error renders none of its characters (SVG 2 textPath): they take no
    # place in the text either, so the text around it is one chunk, as if the textPath were
    # not there (SVG 2 leaves the position after it open; resvg drops it so). They have
    # taken their values of the x/y/dx/dy/rotate lists above, which the text after it does
    # not get.
    walkers = {}
    for c in chars:
        if c.text_path is not None and id(c.text_path) not in walkers:
            walkers[id(c.text_path)] = path_walker(c.text_path, ctx)
    chars = [c for c in chars if c.text_path is None or walkers[id(c.text_path)] is not None]
    if not chars:
        return []
    db = font_database(ctx)
    # each element's spec (by style, kerning attribute, viewport: the spacings' percentages)
    spec_of = {}
    specs = []
    span = s = None
    for c in chars:
        if c.span is not span:          # (a span's characters follow each other)
            span = c.span
            el = span.el
            s = spec_of.get(id(el))
            if s is None:
                s = spec_of[id(el)] = element_spec(el, styles[id(el)], ctx)
        specs.append(s)
    bounds = [i for i, c in enumerate(chars)
              if i == 0 or c.x is not None or c.y is not None
              or c.text_path is not chars[i - 1].text_path]
    bounds.append(len(chars))
    faces = assign_faces(chars, specs, db, bounds, document_faces(ctx),
                         ctx.cache.setdefault("chunk faces", {}))
    # a zero, negative or non-finite size draws nothing
    faces = [f if math.isfinite(sp.size) and sp.size > 0 else None
             for f, sp in zip(faces, specs)]
    if all(f is None for f in faces):
        return []
    writing = (ctx.style.get("writing-mode") or "lr").strip()
    vertical = writing in ("tb", "tb-rl", "vertical-rl", "vertical-lr")
    orientations = None
    if vertical:
        # each character's text-orientation, read once per span (its characters share it)
        by_span = {}
        for c in chars:
            if id(c.span) not in by_span:
                by_span[id(c.span)] = text_orientation(c.span.style)
        orientations = [by_span[id(c.span)] for c in chars]
    upright = [o == "upright" for o in orientations] if vertical else None
    text_length, inside = text_lengths(chars, ctx)
    # baseline shift of every character (positive moves down)
    # from the element's first available font (CSS Inline 3 §4), not a fallback face: a
    # superscript CJK character in Latin text shifts as its Latin neighbours do (as resvg)
    shift_cache = {}
    shifts = []
    span = used = shift = None
    for k, (c, spec, face) in enumerate(zip(chars, specs, faces)):
        face = c.primary_face if face is not None and c.primary_face is not None else face
        if c.span is not span or face is not used:    # (else the character before's)
            span, used = c.span, face
            key = (id(span.el), id(face))
            if key not in shift_cache:
                shift_cache[key] = baseline_offset(
                    span, face, spec, vertical and orientations[k] != "sideways") \
                    if face is not None else 0.0
            shift = shift_cache[key]
        shifts.append(shift)

    # every chunk shaped and spaced first: textLength spans the chunks of its element
    chunks = []
    has_offsets = any(c.dx or c.dy for c in chars)
    text = "".join(c.ch for c in chars)
    # (for the whole document: a chunk's clusters depend on its characters, faces and specs
    # alone, and those are the document's, kept alive in ctx.cache: chart ticks and map
    # labels repeat across texts)
    shape_memo = ctx.cache.setdefault("shaped chunks", {})
    # (no spacing in any spec: apply_spacing would change nothing, a cluster's advance is
    # never -0.0, to which adding 0.0 would give 0.0)
    spaced = any(s.letter_spacing or s.word_spacing for s in {id(s): s for s in specs}.values())
    if (line.ENABLED and len(bounds) == 2 and not vertical and not text_length and not spaced
            and chars[0].text_path is None):
        # a plain line (chart ticks, map labels, a page's lines) laid out as arrays
        nodes = line.plain_line(element, chars, faces, specs, shifts, styles, ctx, text)
        if nodes is not None:
            return nodes
    for a, b in zip(bounds[:-1], bounds[1:]):
        clusters = shape_chunk(chars, faces, specs, a, b, text, upright, shape_memo)
        if not clusters:
            continue
        clusters[0].shifted = True       # a chunk starts a new decoration line
        if vertical:
            apply_writing_mode(clusters, chars, orientations)
        if spaced:
            apply_spacing(clusters, chars, specs)
        if has_offsets:
            carry_offsets(clusters, chars, b)
        chunks.append((a, clusters))
    apply_length_adjust(chunks, chars, text_length, inside, vertical)

    all_clusters = []
    last_x = last_y = 0.0
    # {element id: how much shorter its spacingAndGlyphs made the line so far}: a chunk
    # started by y alone (x alone in vertical text) continues from the unsqueezed end of the
    # elements it is not in, as resvg 0.48.1 and Chromium place it (Chromium moves the text
    # after an element by its textLength adjustment only to the end of their chunk; SVG 2's
    # algorithm does not move it at all)
    squeezed = {}
    anchors = {}                    # by element: a text of one chunk per character has few
    for a, clusters in chunks:
        first = chars[a]
        on_path = first.text_path is not None
        el = first.el
        anchor = anchors.get(id(el))
        if anchor is None:
            anchor = anchors[id(el)] = (styles[id(el)].get("text-anchor") or "start").strip()
        if on_path or (first.y if vertical else first.x) is not None:
            squeezed.clear()
        elif squeezed:
            around, link = set(), inside[a]
            while link is not None:
                around.add(id(link[0].el))
                link = link[1]
            undo = sum(v for k, v in squeezed.items() if k not in around)
            squeezed = {k: v for k, v in squeezed.items() if k in around}
            if vertical:
                last_y += undo
            else:
                last_x += undo
        if on_path:
            chunk_x = (first.y if vertical else first.x) or 0.0
            start = chunk_x + anchor_shift(anchor, clusters, chars, on_path=True)
            last_x, last_y = position_on_path(clusters, chars, first.text_path,
                                              walkers[id(first.text_path)], start, ctx,
                                              styles, shifts)
        else:
            x = first.x if first.x is not None else last_x
            y = first.y if first.y is not None else last_y
            cx, cy = position_linear(clusters, chars, anchor, vertical)
            chunk_ts = rotate_at(90.0, x, y) if vertical else IDENTITY
            spans = {}      # by the shift itself: shifts holds one object per element and face
            for c in clusters:
                shift = shifts[c.char]
                span = spans.get(id(shift))
                if span is None:
                    span = spans[id(shift)] = compose(chunk_ts, translate(x, y + shift))
                c.frame = compose(span, c.frame)
            if vertical:
                cx, cy = cy, cx
            last_x, last_y = x + cx, y + cy
            # the unsqueezed end of an anchored chunk is anchored unsqueezed too (resvg):
            # middle moves it by half of what the squeeze took, end not at all
            inline, part = (1 if vertical else 0), _UNSQUEEZED_PART.get(anchor, 1.0)
            for c in clusters if text_length and part else ():
                if c.squeezed_by is not None:
                    ch = chars[c.char]
                    length = (ch.dy if vertical else ch.dx) + c.advance + c.carry[inline]
                    squeezed[c.squeezed_by] = (squeezed.get(c.squeezed_by, 0.0)
                                               + length * (1.0 - c.sx) * part)
        all_clusters.extend(clusters)
    for c in all_clusters:
        c.placed = a, b, cc, d, e, f = compose(c.frame, c.path_ts)
        for g in c.glyphs:
            # compose(c.placed, (s, 0, 0, -s, dx, dy)) written out: a call per glyph cost
            # more than its arithmetic
            s, dx, dy = g.scale, g.dx, g.dy
            g.matrix = (a * s + cc * 0.0, b * s + d * 0.0, a * 0.0 + cc * -s,
                        b * 0.0 + d * -s, a * dx + cc * dy + e, b * dx + d * dy + f)
    return draw_clusters(element, chars, all_clusters, ctx, styles, vertical)
