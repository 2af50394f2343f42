"""One font face: its outlines (through fontTools) and the metrics read from its tables.

A :class:`Face` wraps one face of a font file (a .ttc/.otc collection holds several, chosen by
``index``). Outlines come from fontTools' glyph set, which covers TrueType ``glyf`` (quadratic,
composite), ``CFF``/``CFF2`` (cubic) and variable fonts (gvar/CFF2 blends at a location). Each
glyph is drawn once per (face, location, gid) into a :class:`vecmsaa.scene.path.Path` and kept as flat
arrays in font units, y up; :func:`vecmsaa.fonts.layout.glyphs_path` places many of them at once.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from fontTools.misc.psCharStrings import T2OutlineExtractor

from .. import diagnostics
from ..diagnostics import RenderWarning
from ..scene.path import Path


class FontError(Exception):
    """A font file that cannot be read or has nothing vecmsaa can draw."""


class FontWarning(RenderWarning):
    """A part of a usable font is broken (one glyph, a variation): it is drawn empty.
    Reported through :mod:`vecmsaa.diagnostics`, so the command line prints it as one line
    naming the input, like every other warning."""


#: Bounds on one TrueType composite glyph: how deep components nest and how many simple-glyph
#: copies the glyph expands to. Real fonts stay far below (accented letters: depth 1-2, a few
#: copies); a hostile font doubling its copies per level would otherwise draw 2^depth contours.
MAX_COMPONENT_DEPTH = 16
MAX_COMPONENT_COPIES = 4096
#: Bounds on one CFF/CFF2 glyph program: bytes of charstring run, subroutines included, and
#: how deep subroutine calls nest (Type 2 allows 10). Real glyphs run a few kilobytes; a
#: hostile font whose subroutines each call the next twice would run 2^depth of them.
MAX_CHARSTRING_BYTES = 1 << 18
MAX_SUBR_DEPTH = 64
#: A collection (.ttc/.otc) holding more faces than this is refused; real ones hold < 100.
MAX_COLLECTION_FACES = 1024


#: CSS font-stretch keywords by OS/2 usWidthClass (1..9), as percentages.
WIDTH_CLASS_PERCENT = {1: 50.0, 2: 62.5, 3: 75.0, 4: 87.5, 5: 100.0, 6: 112.5, 7: 125.0,
                       8: 150.0, 9: 200.0}


@dataclass(frozen=True)
class Metrics:
    """Vertical metrics in font units, y up (descender negative)."""
    units_per_em: int
    ascender: float
    descender: float
    line_gap: float
    x_height: float
    cap_height: float
    underline_position: float
    underline_thickness: float
    strikeout_position: float
    strikeout_thickness: float


def normalize_location(location) -> tuple:
    """A variation location as a hashable, sorted tuple of (axis tag, user value)."""
    if not location:
        return ()
    return tuple(sorted((str(k), float(v)) for k, v in dict(location).items()))


def parse_variations(text: str | None) -> dict:
    """``"wght=700,wdth=80"`` → ``{"wght": 700.0, "wdth": 80.0}``."""
    out = {}
    for item in (text or "").replace(";", ",").split(","):
        item = item.strip()
        if not item:
            continue
        tag, sep, value = item.partition("=")
        if not sep or not tag.strip():
            raise ValueError(f"bad variation {item!r}: expected TAG=VALUE")
        try:
            out[tag.strip()[:4].ljust(4)] = float(value)
        except ValueError:
            raise ValueError(f"bad variation value in {item!r}") from None
    return out


class Face:
    """One face of a font file, with cached glyph outlines."""

    def __init__(self, path, index: int = 0):
        from fontTools.ttLib import TTFont, TTLibError

        self.path = os.fspath(path)
        self.index = int(index)
        try:
            with open(self.path, "rb") as f:
                self.data = f.read()
        except OSError as exc:
            raise FontError(f"cannot read font {self.path}: {exc.strerror or exc}") from None
        try:
            import io
            self.ttfont = TTFont(io.BytesIO(self.data), fontNumber=self.index, lazy=True)
            head = self.ttfont["head"]
            self.glyph_order = self.ttfont.getGlyphOrder()
        except TTLibError as exc:
            raise FontError(f"not a usable font: {self.path}: {exc}") from None
        except Exception as exc:  # fontTools raises many kinds on corrupt data
            raise FontError(f"broken font {self.path}: {type(exc).__name__}: {exc}") from None
        try:
            self._read_tables(head)
        except FontError:
            raise
        except Exception as exc:  # tables load lazily: corrupt ones raise on first use
            raise FontError(f"broken font {self.path}: {type(exc).__name__}: {exc}") from None

    def _read_tables(self, head):
        if not any(t in self.ttfont for t in ("glyf", "CFF ", "CFF2")) and not any(
                t in self.ttfont for t in ("sbix", "CBDT")):
            raise FontError(f"unsupported font {self.path}: no glyf, CFF or CFF2 outlines")
        self.units_per_em = int(head.unitsPerEm) or 1000
        self.has_outlines = any(t in self.ttfont for t in ("glyf", "CFF ", "CFF2"))
        # vertical advances (vhea + vmtx) or origins (VORG) of its own, for vertical shaping
        self.has_vertical_metrics = (("vhea" in self.ttfont and "vmtx" in self.ttfont)
                                     or "VORG" in self.ttfont)
        self.num_glyphs = len(self.glyph_order)
        self._glyph_sets = {}
        self._outlines = {}
        self._outline_boxes = {}
        self._component_sizes = {}
        self._hb_face = None
        self._hb_fonts = {}
        self._read_names()
        self._read_style()
        self.metrics = self._read_metrics()
        self.axes = {a.axisTag: (a.minValue, a.defaultValue, a.maxValue)
                     for a in self.ttfont["fvar"].axes} if "fvar" in self.ttfont else {}

    # -- names and style -------------------------------------------------------------------
    def _read_names(self):
        name = self.ttfont["name"] if "name" in self.ttfont else None

        def get(*ids):
            if name is None:
                return None
            for i in ids:
                rec = name.getDebugName(i)
                if rec:
                    return rec
            return None

        self.family = get(16, 1) or os.path.splitext(os.path.basename(self.path))[0]
        self.subfamily = get(17, 2) or "Regular"
        self.full_name = get(4) or f"{self.family} {self.subfamily}"
        self.postscript_name = get(6) or self.full_name.replace(" ", "")
        # Every family name the face answers to (legacy, typographic, WWS, localized).
        families = set()
        if name is not None:
            for rec in name.names:
                if rec.nameID in (1, 16, 21):
                    try:
                        families.add(rec.toUnicode())
                    except UnicodeDecodeError:
                        pass
        families.add(self.family)
        self.family_names = frozenset(f for f in families if f)

    def _read_style(self):
        os2 = self.ttfont["OS/2"] if "OS/2" in self.ttfont else None
        head = self.ttfont["head"]
        sub = self.subfamily.lower()
        self.weight = int(os2.usWeightClass) if os2 is not None else (
            700 if "bold" in sub else 400)
        if os2 is not None and 1 <= os2.usWidthClass <= 9:
            self.stretch = WIDTH_CLASS_PERCENT[os2.usWidthClass]
        else:
            self.stretch = 100.0
        italic = bool(head.macStyle & 2) or "italic" in sub
        oblique = "oblique" in sub
        if os2 is not None:
            italic = italic or bool(os2.fsSelection & 1)
            oblique = oblique or bool(os2.fsSelection & (1 << 9))
        self.style = "oblique" if oblique and not italic else ("italic" if italic else "normal")
        self.monospace = bool("post" in self.ttfont and self.ttfont["post"].isFixedPitch)

    def _read_metrics(self) -> Metrics:
        t = self.ttfont
        upem = self.units_per_em
        os2 = t["OS/2"] if "OS/2" in t else None
        hhea = t["hhea"] if "hhea" in t else None
        if os2 is not None and os2.fsSelection & (1 << 7):   # USE_TYPO_METRICS
            asc, desc, gap = os2.sTypoAscender, os2.sTypoDescender, os2.sTypoLineGap
        elif hhea is not None and (hhea.ascent or hhea.descent):
            asc, desc, gap = hhea.ascent, hhea.descent, hhea.lineGap
        elif os2 is not None:
            asc, desc, gap = os2.sTypoAscender, os2.sTypoDescender, os2.sTypoLineGap
        else:
            asc, desc, gap = 0.8 * upem, -0.2 * upem, 0
        x_height = getattr(os2, "sxHeight", 0) if os2 is not None else 0
        cap_height = getattr(os2, "sCapHeight", 0) if os2 is not None else 0
        if not x_height:
            # no OS/2 x-height (a version 0 or 1 table, or 0): CSS leaves the fallback to the
            # renderer; resvg (so the suite's references) takes 45% of the ascent-to-descent
            # height, as Firefox does, not the height of the 'x' glyph
            x_height = int(0.45 * (asc - desc)) or 0.5 * upem
        if not cap_height:
            cap_height = self._glyph_height("H") or 0.7 * upem
        post = t["post"] if "post" in t else None
        # without a post table (or a zero thickness in it) resvg's defaults: a twelfth of the
        # em thick, a ninth below the baseline (CSS leaves them to the renderer)
        ul_thick = post.underlineThickness if post is not None and post.underlineThickness \
            else upem // 12
        ul_pos = post.underlinePosition if post is not None else -(upem // 9)
        so_thick = os2.yStrikeoutSize if os2 is not None and os2.yStrikeoutSize else ul_thick
        so_pos = os2.yStrikeoutPosition if os2 is not None else x_height / 2
        return Metrics(upem, float(asc), float(desc), float(gap), float(x_height),
                       float(cap_height), float(ul_pos), float(ul_thick), float(so_pos),
                       float(so_thick))

    def _glyph_height(self, char):
        gid = self.glyph_for_char(char)
        if not gid:
            return None
        _, pts = self.outline(gid)
        return float(pts[:, 1].max()) if len(pts) else None

    # -- characters and glyphs -------------------------------------------------------------
    @property
    def cmap(self) -> dict:
        """Code point → glyph name (the best Unicode cmap subtable), read once."""
        cmap = getattr(self, "_cmap", None)
        if cmap is None:
            try:
                cmap = self.ttfont.getBestCmap() or {}
            except Exception:
                cmap = {}
            self._cmap = cmap
        return cmap

    @property
    def reverse_cmap(self) -> dict:
        """Glyph id → smallest code point mapped to it."""
        rev = getattr(self, "_reverse_cmap", None)
        if rev is None:
            rev = {}
            ids = self.glyph_ids
            for cp, gname in sorted(self.cmap.items(), reverse=True):
                gid = ids.get(gname)
                if gid is not None:
                    rev[gid] = cp
            self._reverse_cmap = rev
        return rev

    @property
    def glyph_ids(self) -> dict:
        ids = getattr(self, "_glyph_ids", None)
        if ids is None:
            ids = self._glyph_ids = {n: i for i, n in enumerate(self.glyph_order)}
        return ids

    def glyph_for_char(self, char) -> int:
        """Glyph id for one character, 0 (.notdef) when the face lacks it."""
        name = self.cmap.get(ord(char) if isinstance(char, str) else int(char))
        return self.glyph_ids.get(name, 0) if name is not None else 0

    def has_char(self, char) -> bool:
        return (ord(char) if isinstance(char, str) else int(char)) in self.cmap

    def clamp_location(self, location) -> tuple:
        """Keep only the face's own axes, clamped to their ranges, as a normalized tuple."""
        if not self.axes or not location:
            return ()
        out = {}
        for tag, value in dict(location).items():
            if tag in self.axes and math.isfinite(float(value)):   # 'wght' NaN: the default
                lo, _, hi = self.axes[tag]
                out[tag] = min(max(float(value), lo), hi)
        return normalize_location(out)

    def glyph_set(self, location: tuple = ()):
        gs = self._glyph_sets.get(location)
        if gs is None:
            try:
                gs = self.ttfont.getGlyphSet(location=dict(location) if location else None)
            except Exception as exc:  # corrupt glyf/CFF/gvar/hmtx tables load here
                # kept, so later calls raise the same error rather than whatever fontTools'
                # half-read table does next
                gs = FontError(f"broken outlines in {self.path}: {type(exc).__name__}: {exc}")
            self._glyph_sets[location] = gs
        if isinstance(gs, FontError):
            raise gs
        return gs

    def outline(self, gid: int, location: tuple = ()):
        """(verbs, points) of a glyph in font units, y up; drawn once and cached. A broken
        glyph (corrupt data, a recursive or exploding composite) is empty, with a
        :class:`FontWarning`: the rest of the text still draws."""
        key = (gid, location)
        hit = self._outlines.get(key)
        if hit is not None:
            return hit
        if not self.has_outlines:       # bitmap-only font (CBDT): see fonts.color
            return empty_outline()
        name = self.glyph_order[gid] if 0 <= gid < self.num_glyphs else ".notdef"
        try:
            gs = self.glyph_set(location)
            path = Path(glyphSet=gs)
            if name in gs:
                self._check_components(name)
                self._bound_charstring(gs, name)
                gs[name].draw(path)
            hit = (path.verbs, path.points)
        except Exception as exc:
            if self._glyph_sets.get(location) is exc:     # the whole face: one line for all
                diagnostics.warn(f"{exc}; its glyphs are drawn empty", FontWarning)
            else:
                diagnostics.warn(f"broken glyph {name!r} in {self.path} drawn empty: "
                                 f"{_reason(exc)}", FontWarning)
            hit = empty_outline()
        self._outlines[key] = hit
        return hit

    def outline_box(self, gid: int, location: tuple = ()):
        """(x0, y0, x1, y1): the bounds of a glyph outline's points, control points
        included (so the outline lies inside), in font units; None when it is empty."""
        key = (gid, location)
        try:
            return self._outline_boxes[key]
        except KeyError:
            pass
        p = self.outline(gid, location)[1]
        box = None
        if len(p):
            lo, hi = p.min(axis=0), p.max(axis=0)
            box = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
        self._outline_boxes[key] = box
        return box

    @staticmethod
    def _bound_charstring(gs, name):
        """Make a CFF/CFF2 glyph's program stop with FontError past MAX_CHARSTRING_BYTES or
        MAX_SUBR_DEPTH (fontTools' interpreter has no bound); glyf glyph sets are left as
        they are."""
        charstrings = getattr(gs, "charStrings", None)
        if charstrings is not None:
            charstrings[name].outlineExtractor = _BoundedT2Extractor

    def _check_components(self, name):
        """Raise FontError when a TrueType composite nests deeper than MAX_COMPONENT_DEPTH,
        refers to itself, or expands to more than MAX_COMPONENT_COPIES simple glyphs; sizes
        are memoized per glyph, so checking costs one visit of each component glyph."""
        if "glyf" not in self.ttfont:
            return
        glyf, sizes = self.ttfont["glyf"], self._component_sizes

        def size(n, depth):                  # → (simple-glyph copies, nesting depth)
            hit = sizes.get(n)
            if hit is None:
                if depth > MAX_COMPONENT_DEPTH:
                    raise FontError(f"components nest deeper than {MAX_COMPONENT_DEPTH}")
                g = glyf[n]
                if not g.isComposite():
                    hit = (1, 0)
                else:
                    sizes[n] = (0, -1)       # being visited: a cycle meets this mark
                    try:
                        parts = [size(c.glyphName, depth + 1) for c in g.components]
                    except FontError:
                        del sizes[n]
                        raise
                    hit = (sum(p[0] for p in parts), 1 + max(p[1] for p in parts))
                sizes[n] = hit
            elif hit[1] < 0:
                raise FontError(f"glyph {n!r} contains itself")
            if hit[0] > MAX_COMPONENT_COPIES or depth + hit[1] > MAX_COMPONENT_DEPTH:
                sizes[n] = hit
                raise FontError(f"components expand to {hit[0]} copies at depth {hit[1]} "
                                f"(limits {MAX_COMPONENT_COPIES} and {MAX_COMPONENT_DEPTH})")
            return hit

        try:
            size(name, 0)
        except KeyError as exc:
            raise FontError(f"missing component {exc}") from None

    def advance(self, gid: int, location: tuple = ()) -> float:
        """Horizontal advance in font units (including variations); 0 with a
        :class:`FontWarning` where the metrics are broken, as a broken glyph draws empty."""
        name = self.glyph_order[gid] if 0 <= gid < self.num_glyphs else ".notdef"
        try:
            if not self.has_outlines:
                return float(self.ttfont["hmtx"][name][0]) if "hmtx" in self.ttfont else 0.0
            gs = self.glyph_set(location)
            return float(gs[name].width) if name in gs else 0.0
        except Exception as exc:
            where = "" if isinstance(exc, FontError) else f"broken metrics in {self.path}: "
            diagnostics.warn(f"{where}{_reason(exc)}; advances taken as 0", FontWarning)
            return 0.0

    # -- HarfBuzz --------------------------------------------------------------------------
    def hb_font(self, location: tuple = ()):
        """A uharfbuzz Font for this face at a variation location, scaled to font units."""
        font = self._hb_fonts.get(location)
        if font is None:
            import uharfbuzz as hb

            if self._hb_face is None:
                self._hb_face = hb.Face(hb.Blob(self.data), self.index)
            font = hb.Font(self._hb_face)
            font.scale = (self.units_per_em, self.units_per_em)
            if location:
                font.set_variations(dict(location))
            self._hb_fonts[location] = font
        return font

    def __repr__(self):
        return f"Face({self.full_name!r}, {os.path.basename(self.path)}#{self.index})"


def _reason(exc: Exception) -> str:
    """Why a glyph or metric could not be read: a FontError's own words, else the exception."""
    return str(exc) if isinstance(exc, FontError) else f"{type(exc).__name__}: {exc}"


class _BoundedT2Extractor(T2OutlineExtractor):
    """fontTools' Type 2 outline interpreter, counting the bytes each glyph runs."""

    def reset(self):
        super().reset()
        self._run = 0

    def execute(self, charString):
        self._run += len(charString.bytecode or charString.program or ())
        if self._run > MAX_CHARSTRING_BYTES or self.subrLevel >= MAX_SUBR_DEPTH:
            raise FontError(f"glyph program runs past {MAX_CHARSTRING_BYTES} bytes or "
                            f"{MAX_SUBR_DEPTH} nested subroutines")
        super().execute(charString)


@lru_cache(maxsize=64)
def _load(path: str, index: int, mtime: float) -> Face:
    count = face_count(path)
    if not 0 <= index < count:
        raise FontError(f"{path} has {count} face(s); --face-index {index} is out of range")
    return Face(path, index)


def load_face(path, index: int = 0) -> Face:
    """The cached :class:`Face` for a file and face index; raises :class:`FontError`."""
    path = os.path.abspath(os.fspath(path))
    try:
        mtime = os.stat(path).st_mtime
    except OSError as exc:
        raise FontError(f"cannot read font {path}: {exc.strerror or exc}") from None
    return _load(path, int(index), mtime)


def face_count(path) -> int:
    """How many faces a font file holds (collections hold several)."""
    try:
        with open(path, "rb") as f:
            head = f.read(12)
    except OSError as exc:
        raise FontError(f"cannot read font {path}: {exc.strerror or exc}") from None
    if head[:4] == b"ttcf" and len(head) >= 12:
        count = int.from_bytes(head[8:12], "big")
        if count > MAX_COLLECTION_FACES or 12 + 4 * count > os.path.getsize(path):
            raise FontError(f"font collection {path} claims {count} faces (limit "
                            f"{MAX_COLLECTION_FACES}, and its offsets must fit in the file)")
        return count
    return 1


def empty_outline():
    return np.zeros(0, np.uint8), np.zeros((0, 2), np.float64)
