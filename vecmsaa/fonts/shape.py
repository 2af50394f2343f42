"""Text shaping with HarfBuzz (uharfbuzz), split into bidi runs.

HarfBuzz does kerning, ligatures, mark positioning and complex scripts for one run of one
direction. Mixed-direction text is cut into runs first by a simple bidi pass (strong types from
``unicodedata``; neutrals join the run before them, or the paragraph direction between runs of
different direction); runs come back in visual order, each already in visual order inside.
That is not the full Unicode bidi algorithm (no explicit embeddings, no number rules), but it
draws ordinary mixed Latin/Arabic/Hebrew lines right.
"""
from __future__ import annotations

import unicodedata
from dataclasses import dataclass

import numpy as np

RTL_TYPES = frozenset(("R", "AL"))
LTR_TYPES = frozenset(("L",))


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


def char_direction(ch: str) -> str | None:
    t = unicodedata.bidirectional(ch)
    if t in RTL_TYPES:
        return "rtl"
    if t in LTR_TYPES:
        return "ltr"
    return None


def paragraph_direction(text: str, default: str = "ltr") -> str:
    """Direction of the first strong character (Unicode rule P2), else ``default``."""
    for ch in text:
        d = char_direction(ch)
        if d:
            return d
    return default


def bidi_runs(text: str, base: str = "ltr"):
    """[(start, end, direction)] in logical order. Neutrals between two runs of the same
    direction join them; between different directions they take the paragraph direction."""
    if not text:
        return []
    dirs = [char_direction(c) for c in text]
    n = len(text)
    # Resolve neutrals: same strong type on both sides → that type; otherwise the base.
    resolved = list(dirs)
    i = 0
    while i < n:
        if resolved[i] is None:
            j = i
            while j < n and dirs[j] is None:
                j += 1
            before = next((dirs[k] for k in range(i - 1, -1, -1) if dirs[k]), base)
            after = dirs[j] if j < n else base
            fill = before if before == after else base
            for k in range(i, j):
                resolved[k] = fill
            i = j
        else:
            i += 1
    # Combining marks always follow their base character's run.
    for k in range(1, n):
        if unicodedata.category(text[k]).startswith("M"):
            resolved[k] = resolved[k - 1]
    runs = []
    start = 0
    for k in range(1, n + 1):
        if k == n or resolved[k] != resolved[start]:
            runs.append((start, k, resolved[start]))
            start = k
    return runs


def visual_order(runs, base: str):
    """Reorder logical runs for display (two embedding levels: the base and the other)."""
    if base == "rtl":
        # In an RTL paragraph LTR runs stay LTR inside, but the run sequence is reversed.
        return list(reversed(runs))
    return list(runs)


def shape_run(face, text: str, start: int, end: int, *, location=(), features=None,
              direction="ltr", script=None, language=None) -> ShapedRun:
    """Shape text[start:end] as one run (context outside the range is given to HarfBuzz)."""
    import uharfbuzz as hb

    buf = hb.Buffer()
    buf.cluster_level = hb.BufferClusterLevel.MONOTONE_CHARACTERS
    # Give HarfBuzz the whole string as context so that joining (Arabic) sees neighbours.
    codepoints = [ord(c) for c in text]
    buf.add_codepoints(codepoints, start, end - start)
    buf.guess_segment_properties()
    buf.direction = direction
    if script:
        buf.script = script
    if language:
        buf.language = language
    hb.shape(face.hb_font(location), buf, features or {})
    infos = buf.glyph_infos
    positions = buf.glyph_positions
    n = len(infos)
    gids = np.fromiter((i.codepoint for i in infos), np.int64, n)
    clusters = np.fromiter((i.cluster for i in infos), np.int64, n)
    pos = np.array([(p.x_advance, p.y_advance, p.x_offset, p.y_offset) for p in positions],
                   dtype=np.float64).reshape(-1, 4)
    return ShapedRun(face, location, gids, clusters, pos[:, :2].copy(), pos[:, 2:].copy(),
                     direction, start, end)


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
        runs, base = [(0, len(text), direction)], direction
    else:
        base = paragraph_direction(text)
        runs = bidi_runs(text, base)
    return [shape_run(face, text, s, e, location=location, features=features, direction=d,
                      script=script, language=language)
            for s, e, d in visual_order(runs, base)]
