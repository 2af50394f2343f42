"""Text shaping with HarfBuzz (uharfbuzz), split into bidi runs.

HarfBuzz does kerning, ligatures, mark positioning and complex scripts for one run of one
direction. Mixed-direction text is cut into runs by the Unicode bidirectional algorithm (UAX #9
in full, isolates and bracket pairs included, by python-bidi's Rust unicode-bidi crate, as
resvg uses it; rule L1 here): the runs are the stretches of one resolved embedding level, odd
levels right to left, reordered for display by
rule L2 (from the highest level down to the lowest odd one, every stretch at that level or
above is reversed). So digits and neutrals inside right-to-left text keep their order
("مرحبا 2024 عالم" shows 2024), and a Latin word with digits inside Arabic stays whole.
HarfBuzz mirrors brackets in right-to-left runs (L4).
"""
from __future__ import annotations

import itertools
import operator
import re
import unicodedata
from dataclasses import dataclass

import numpy as np
from bidi import get_display

#: bidi classes that can make any character's level differ from an LTR paragraph's 0
_NOT_PLAIN_LTR = frozenset(("R", "AL", "AN", "RLE", "RLO", "LRE", "LRO", "RLI", "LRI", "FSI",
                            "PDF", "PDI"))
#: characters of context handed to HarfBuzz on either side of a run: it keeps at most
#: HB_BUFFER_CONTEXT_LENGTH (5, hb-buffer.hh) of them, so a wider window shapes the same and
#: only costs its length per run (a whole line of many bidi runs as every run's context was
#: quadratic: 24,000 characters of Latin, CJK and Arabic digits took 11.7 s)
CONTEXT_CHARS = 8


@dataclass
class ShapedRun:
    """Glyphs of one run, in visual order; positions in font units (y up, HarfBuzz's)."""
    face: object
    location: tuple
    gids: np.ndarray          # (N,) int
    clusters: np.ndarray      # (N,) int: index into the whole text of the glyph's first char
    advances: np.ndarray      # (N, 2) float: x_advance, y_advance
    offsets: np.ndarray       # (N, 2) float: x_offset, y_offset
    direction: str            # ltr | rtl | ttb | btt
    start: int                # text range [start, end) of the run
    end: int

    @property
    def width(self) -> float:
        return float(self.advances[:, 0].sum())


def parse_features(text) -> dict:
    """``"liga=0,ss01,-kern,+smcp"`` → HarfBuzz feature dict ``{"liga": 0, "ss01": 1, ...}``."""
    if isinstance(text, dict):
        return dict(text)
    out = {}
    for item in (text or "").split(","):
        item = item.strip()
        if not item:
            continue
        value = 1
        if item[0] in "+-":
            value = 0 if item[0] == "-" else 1
            item = item[1:]
        tag, sep, v = item.partition("=")
        if sep:
            v = v.strip().lower()
            if v in ("on", "true"):
                value = 1
            elif v in ("off", "false"):
                value = 0
            else:
                try:
                    value = int(v)
                except ValueError:
                    raise ValueError(f"bad feature value in {item!r}") from None
        tag = tag.strip()
        if not 1 <= len(tag) <= 4:
            raise ValueError(f"bad feature tag {tag!r}")
        out[tag.ljust(4)] = value
    return out


def paragraph_direction(text: str, default: str = "ltr") -> str:
    """Direction of the first strong character (Unicode rule P2), else ``default``."""
    for ch in text:
        t = unicodedata.bidirectional(ch)
        if t in ("R", "AL"):
            return "rtl"
        if t == "L":
            return "ltr"
    return default


def bidi_levels(text: str, base: str = "ltr") -> list[int]:
    """The resolved embedding level of every character for a paragraph of direction
    ``base``: UAX #9 in full (explicit embeddings and isolates, weak and neutral types,
    bracket pairs N0) by python-bidi's Rust extension, the unicode-bidi crate, whose
    ``debug`` output lists the levels; then rule L1 here. Characters that rule X9 removes
    take the level of the character before them (as the crate assigns them)."""
    base_level = 1 if base == "rtl" else 0
    # (no ASCII character is of those classes: most labels skip the test per character)
    if base_level == 0 and (text.isascii() or not any(
            unicodedata.bidirectional(c) in _NOT_PLAIN_LTR for c in text)):
        return [0] * len(text)
    info = get_display(text, base_dir="R" if base_level else "L", debug=True)
    levels = _crate_levels(info, text)
    # L1: segment and paragraph separators, and whitespace and isolate marks before them or
    # at the end of the line, go back to the paragraph level
    trailing = True
    for k in range(len(text) - 1, -1, -1):
        t = unicodedata.bidirectional(text[k])
        if t in ("S", "B"):
            levels[k] = base_level
            trailing = True
        elif trailing and t in _L1_WHITESPACE:
            levels[k] = base_level
        else:
            trailing = False
    return levels


#: whitespace and formatting characters that rule L1 resets with a following separator (the
#: X9-removed ones count, as the crate reports them with the previous character's level)
_L1_WHITESPACE = frozenset(("WS", "FSI", "LRI", "RLI", "PDI", "BN", "LRE", "RLE", "LRO", "RLO",
                            "PDF"))


def _crate_levels(info: str, text: str) -> list[int]:
    """Per-character levels from the crate's ``BidiInfo`` debug text (one level per UTF-8
    byte: each character takes its first byte's)."""
    block = re.search(r"\blevels:\s*\[(.*?)\]", info, re.S)
    per_byte = [int(v) for v in re.findall(r"Level\(\s*(\d+)", block.group(1))] if block else []
    if len(per_byte) != len(text.encode("utf-8")):
        raise RuntimeError("python-bidi's debug output changed: cannot read bidi levels")
    levels, i = [], 0
    for ch in text:
        levels.append(per_byte[i])
        i += len(ch.encode("utf-8"))
    return levels


def level_runs(text: str, base: str = "ltr"):
    """[(start, end, level)] in logical order: the stretches of one resolved level."""
    levels = bidi_levels(text, base)
    runs = []
    start = 0
    for k in range(1, len(text) + 1):
        if k == len(text) or levels[k] != levels[start]:
            runs.append((start, k, levels[start]))
            start = k
    return runs


def _direction(level):
    return "rtl" if level % 2 else "ltr"


def bidi_runs(text: str, base: str = "ltr"):
    """[(start, end, direction)] in logical order."""
    return [(s, e, _direction(lv)) for s, e, lv in level_runs(text, base)]


def visual_runs(text: str, base: str = "ltr"):
    """[(start, end, direction)] in display order, left to right (rule L2 on whole runs; each
    right-to-left run is reversed inside by its shaping)."""
    runs = level_runs(text, base)
    if not runs:
        return []
    levels = [lv for _, _, lv in runs]
    lowest_odd = min((lv for lv in levels if lv % 2), default=None)
    if lowest_odd is not None:
        for level in range(max(levels), lowest_odd - 1, -1):
            i = 0
            while i < len(runs):
                if runs[i][2] >= level:
                    j = i
                    while j < len(runs) and runs[j][2] >= level:
                        j += 1
                    runs[i:j] = runs[i:j][::-1]
                    i = j
                else:
                    i += 1
    return [(s, e, _direction(lv)) for s, e, lv in runs]


_chain = itertools.chain.from_iterable
_GID_CLUSTER = operator.attrgetter("codepoint", "cluster")


def shape_run(face, text: str, start: int, end: int, *, location=(), features=None,
              direction="ltr", script=None, language=None, context=None) -> ShapedRun:
    """Shape text[start:end] as one run; text[lo:hi] around it, ``context`` = (lo, hi) (default
    the whole text), is given to HarfBuzz as context (the CONTEXT_CHARS next to the run: all
    it reads). Ranges in ``features`` (start, end, value) count from ``start``."""
    import uharfbuzz as hb

    buf = hb.Buffer()
    buf.cluster_level = hb.BufferClusterLevel.MONOTONE_CHARACTERS
    # Give HarfBuzz the context so that joining (Arabic) sees neighbours.
    lo, hi = context if context is not None else (0, len(text))
    lo, hi = max(lo, start - CONTEXT_CHARS), min(hi, end + CONTEXT_CHARS)
    if features:
        # HarfBuzz's ranges are in cluster values, which count from the buffer's first
        # character, the context's
        features = {tag: [(a + start - lo, b + start - lo, v) for a, b, v in value]
                    if isinstance(value, list) else value for tag, value in features.items()}
    codepoints = [ord(c) for c in text[lo:hi]]
    buf.add_codepoints(codepoints, start - lo, end - start)
    buf.guess_segment_properties()
    buf.direction = direction
    if script:
        buf.script = script
    if language:
        buf.language = language
    font = face.hb_font(location)
    hb.shape(font, buf, features or {})
    infos = buf.glyph_infos
    positions = buf.glyph_positions
    n = len(infos)
    # (uharfbuzz gives a Python object per glyph, no arrays: each read once, its values
    # chained into one array; ``position``: x_offset, y_offset, x_advance, y_advance)
    ids = np.fromiter(_chain(map(_GID_CLUSTER, infos)), np.int64, 2 * n).reshape(-1, 2)
    gids = ids[:, 0].copy()
    clusters = ids[:, 1] + lo
    pos = np.fromiter(_chain([p.position for p in positions]), np.float64, 4 * n).reshape(-1, 4)
    if direction in ("ttb", "btt") and not face.has_vertical_metrics:
        # A face without vmtx or VORG advances by its ascender-to-descender height (HarfBuzz's
        # fallback) and hangs every glyph from the ascender, its vertical origin half the
        # advance across and the ascender up, as Chromium does (OpenTypeVerticalData): the
        # em box fills the advance. HarfBuzz centres each glyph's ink in the advance instead,
        # so its origin (subtracted in the offsets) is swapped for the ascender.
        ascender = font.get_font_extents("ltr").ascender
        pos[:, 1] += [font.get_glyph_v_origin(g)[1] - ascender for g in gids.tolist()]
    return ShapedRun(face, location, gids, clusters, pos[:, 2:].copy(), pos[:, :2].copy(),
                     direction, start, end)


def join_runs(runs):
    """Runs shaped apart from consecutive pieces of one run (same face, direction) as one,
    its glyphs in visual order: right to left (and bottom to top) the last piece's first."""
    if len(runs) == 1:
        return runs[0]
    first, last = runs[0], runs[-1]
    ordered = runs[::-1] if first.direction in ("rtl", "btt") else runs
    return ShapedRun(first.face, first.location,
                     *(np.concatenate([getattr(r, f) for r in ordered])
                       for f in ("gids", "clusters", "advances", "offsets")),
                     first.direction, first.start, last.end)


def shape_text(face, text: str, *, location=(), features=None, direction=None, script=None,
               language=None):
    """Shape a line: bidi split, HarfBuzz per run, runs in visual order.

    ``direction`` forces one direction for the whole line (``ltr``, ``rtl``, ``ttb``, ``btt``)
    and skips the bidi split; ``None`` resolves runs and their order from the text. Returns a list of :class:`ShapedRun`.
    """
    features = parse_features(features)
    location = face.clamp_location(location) if not isinstance(location, tuple) else location
    if direction:
        # A forced direction shapes the whole line as one run, as hb-view does.
        runs = [(0, len(text), direction)]
    else:
        runs = visual_runs(text, paragraph_direction(text))
    return [shape_run(face, text, s, e, location=location, features=features, direction=d,
                      script=script, language=language)
            for s, e, d in runs]
