"""Font faces, outlines, shaping, layout and the font database.

Truth comes from outside vecmsaa's font code: table fields read with ``struct`` straight from
the font bytes, FreeType's advances and outlines, hand-built glyphs.
"""
from __future__ import annotations

import os
import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vecmsaa.fonts import (FontError, layout_line, line_fills, load_face, parse_features,
                           parse_variations, shape_text)
from vecmsaa.fonts.db import FontDatabase, best_match, parse_family_list, FaceInfo
from vecmsaa.fonts.shape import bidi_runs, visual_runs
from vecmsaa.scene.path import CUBIC, QUAD
from vecmsaa.tools.suite import suite_from_environment

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
TTF = os.path.join(FIXTURES, "NotoSans-Subset.ttf")
CFF = os.path.join(FIXTURES, "NotoSans-Subset-CFF.otf")
VAR = os.path.join(FIXTURES, "RobotoFlex-Subset.ttf")
TTC = os.path.join(FIXTURES, "Collection.ttc")
SUITE_FONTS = os.path.join(suite_from_environment(os.path.join(
    os.path.dirname(__file__), "..", "..", "shared", "resvg-suite")), "fonts")
needs_suite = pytest.mark.skipif(not os.path.isdir(SUITE_FONTS),
                                 reason="../shared/resvg-suite/fonts not present")


def read_table(path, tag):
    """Raw bytes of one sfnt table, found through the table directory by hand."""
    data = open(path, "rb").read()
    num_tables = struct.unpack(">H", data[4:6])[0]
    for i in range(num_tables):
        rec = data[12 + 16 * i: 28 + 16 * i]
        if rec[:4] == tag.encode():
            offset, length = struct.unpack(">II", rec[8:16])
            return data[offset:offset + length]
    raise KeyError(tag)


def freetype_face(path, size=None):
    freetype = pytest.importorskip("freetype")
    face = freetype.Face(path)
    if size:
        face.set_char_size(int(size * 64), 0, 72, 72)
    return face


@pytest.mark.parametrize("path", [TTF, CFF])
def test_metrics_match_the_tables(path):
    face = load_face(path)
    units_per_em = struct.unpack(">H", read_table(path, "head")[18:20])[0]
    ascent, descent, gap = struct.unpack(">hhh", read_table(path, "hhea")[4:10])
    assert face.units_per_em == units_per_em
    assert (face.metrics.ascender, face.metrics.descender, face.metrics.line_gap) == (
        ascent, descent, gap)
    os2 = read_table(path, "OS/2")
    assert face.weight == struct.unpack(">H", os2[4:6])[0]


@pytest.mark.parametrize("path,kind", [(TTF, QUAD), (CFF, CUBIC)])
def test_outline_points_match_freetype(path, kind):
    """Every on-curve point FreeType loads (unscaled) is an endpoint of our outline."""
    freetype = pytest.importorskip("freetype")
    face = load_face(path)
    ft = freetype_face(path)
    for ch in "Bag&8":
        gid = face.glyph_for_char(ch)
        verbs, points = face.outline(gid)
        assert kind in verbs
        ft.load_glyph(gid, freetype.FT_LOAD_NO_SCALE | freetype.FT_LOAD_NO_HINTING)
        outline = ft.glyph.outline
        on_curve = {tuple(p) for p, tag in zip(outline.points, outline.tags) if tag & 1}
        ours = {(round(x), round(y)) for x, y in points}
        assert on_curve <= ours, ch
        xs, ys = zip(*outline.points)
        assert (points[:, 0].min(), points[:, 0].max()) == (min(xs), max(xs))
        assert (points[:, 1].min(), points[:, 1].max()) == (min(ys), max(ys))


def test_outlines_are_cached_per_glyph_and_location():
    face = load_face(VAR)
    gid = face.glyph_for_char("H")
    assert face.outline(gid) is face.outline(gid)
    heavy = face.clamp_location({"wght": 900})
    assert face.outline(gid, heavy) is face.outline(gid, heavy)
    assert face.outline(gid, heavy)[1].shape == face.outline(gid)[1].shape


def test_placed_glyphs_are_each_outline_through_its_own_matrix():
    """glyphs_arrays gives every glyph's outline, in order, each point mapped by its glyph's
    affine matrix x' = a x + c y + e, y' = b x + d y + f in plain floats, bit for bit; empty
    glyphs (the space) among them."""
    import vecmsaa.fonts.layout as font_layout
    face = load_face(TTF)
    rng = np.random.default_rng(3)
    gids = [face.glyph_for_char(ch) for ch in "Hxg Ho g"] * 3
    mats = [tuple(float(v) for v in rng.normal(size=6) * 20) for _ in gids]
    verbs, points = font_layout.glyphs_arrays(face, (), gids, mats)
    want_verbs, want_points = [], []
    for gid, (a, b, c, d, e, f) in zip(gids, mats):
        v, p = face.outline(gid)
        want_verbs.extend(v.tolist())
        want_points.extend([a * x + c * y + e, b * x + d * y + f] for x, y in p.tolist())
    assert verbs.tolist() == want_verbs
    assert points.tolist() == want_points and len(want_points) > 4 * 64


def test_fixed_pitch_is_the_post_tables_flag():
    """read_face_infos reads isFixedPitch from the post header's bytes; fontTools decoding the
    whole table says the same for every fixture and suite font (a monospaced one among them),
    and a truncated header is an error (the face is skipped, as when fontTools fails)."""
    import glob
    from fontTools.ttLib import TTFont
    from vecmsaa.fonts.db import _fixed_pitch
    paths = sorted(glob.glob(os.path.join(FIXTURES, "*.[ot]t[fc]")) +
                   glob.glob(os.path.join(SUITE_FONTS, "*.[ot]t[fc]")))
    answers = []
    for path in paths:
        font = TTFont(path, lazy=True, fontNumber=0)
        answers.append(_fixed_pitch(font))
        assert answers[-1] == bool("post" in font and font["post"].isFixedPitch), path
    assert len(paths) > 4 and (True in answers or not os.path.isdir(SUITE_FONTS))

    class Truncated:
        reader = {"post": b"\0" * 20}

        def __contains__(self, tag):
            return tag == "post"
    with pytest.raises(ValueError):
        _fixed_pitch(Truncated())


def test_variable_location_matches_freetype():
    """Outline bounds at wght=900, wdth=60 agree with FreeType's variation engine."""
    freetype = pytest.importorskip("freetype")
    face = load_face(VAR)
    loc = face.clamp_location({"wght": 900, "wdth": 60})
    ft = freetype_face(VAR)
    axes = [a.tag for a in ft.get_variation_info().axes]
    ft.set_var_design_coords([dict(loc)[t] for t in axes])
    for ch in "AHOe":
        gid = face.glyph_for_char(ch)
        ft.load_glyph(gid, freetype.FT_LOAD_NO_SCALE | freetype.FT_LOAD_NO_HINTING)
        pts = np.array(ft.glyph.outline.points, dtype=float)
        ours = face.outline(gid, loc)[1]
        assert np.allclose(ours.min(axis=0), pts.min(axis=0), atol=1.0)
        assert np.allclose(ours.max(axis=0), pts.max(axis=0), atol=1.0)
        # and it really moved away from the default master
        assert not np.allclose(face.outline(gid)[1].max(axis=0), ours.max(axis=0), atol=1.0)


def test_unshaped_advances_match_freetype():
    """With kerning off, a line's width is the sum of FreeType's linear advances."""
    freetype = pytest.importorskip("freetype")
    ft = freetype_face(TTF, 40)
    text = "Hamburgefonstiv"
    expected = 0.0
    for ch in text:
        ft.load_char(ch, freetype.FT_LOAD_NO_HINTING)
        expected += ft.glyph.linearHoriAdvance / 65536.0
    line = layout_line(load_face(TTF), text, 40, features="kern=0")
    # linearHoriAdvance is 16.16 fixed point: 1/65536 px per glyph.
    assert line.advance == pytest.approx(expected, abs=len(text) / 65536 * 40)


def test_kerning_tightens_av_and_can_be_switched_off():
    face = load_face(TTF)
    kerned = layout_line(face, "AVAV", 100).advance
    plain = layout_line(face, "AVAV", 100, features={"kern": 0}).advance
    assert kerned < plain


def test_feature_changes_glyphs():
    face = load_face(TTF)
    plain = shape_text(face, "abc")[0].gids
    small_caps = shape_text(face, "abc", features="smcp")[0].gids
    assert not np.array_equal(plain, small_caps)


def test_combining_mark_composes_to_precomposed_glyph():
    face = load_face(TTF)
    assert list(shape_text(face, "e\u0301")[0].gids) == [face.glyph_for_char("é")]


def test_parse_options():
    assert parse_features("liga=0,ss01,-kern,+smcp") == {
        "liga": 0, "ss01": 1, "kern": 0, "smcp": 1}
    assert parse_variations("wght=700, wdth=80") == {"wght": 700.0, "wdth": 80.0}
    with pytest.raises(ValueError):
        parse_variations("wght")
    assert parse_family_list("'Noto Sans', serif,  \"A  B\"") == ["Noto Sans", "serif", "A B"]


def test_bidi_runs_split_and_order():
    text = "abc \u05d0\u05d1\u05d2 def"
    assert bidi_runs(text) == [(0, 4, "ltr"), (4, 7, "rtl"), (7, 11, "ltr")]
    assert bidi_runs("\u05d0\u05d1 abc", "rtl") == [(0, 3, "rtl"), (3, 6, "ltr")]


# python-bidi's Rust extension (the unicode-bidi crate) reorders a line for display; ours takes
# the crate's levels and does rules L1 and L2 itself (runs, then their order): the two agree.
BIDI_ALPHABET = (list("abcXYZ") + list("\u05d0\u05d1\u05d2\u05d3") + list("\u0645\u0631\u062d\u0628")
                 + list("0123") + list("\u0660\u0661\u0662") + list("  ,.-+%:/")
                 + ["\u064e", "\u05b8"] + list("()[]") + ["\u2066", "\u2067", "\u2068", "\u2069"])


@pytest.mark.parametrize("text, base, levels", [
    # UAX #9 N0, the specification's first example (R = Hebrew, L = Latin): the brackets
    # around "CD[&ef]!" take the paragraph's direction, "[&ef]"'s the embedding's
    ("\u05d0\u05d1(\u05d2\u05d3[&ef]!)gh", "rtl", [1, 1, 1, 1, 1, 1, 1, 2, 2, 1, 1, 1, 2, 2]),
    # UAX #9 N0 example 3: "book(s)" inside right-to-left text keeps its parentheses
    ("\u05d0 book(s)", "rtl", [1, 1, 2, 2, 2, 2, 2, 2, 2]),
    # X5a-X6a: an RLI ... PDI isolate is resolved alone and its marks sit at the outer level
    ("a\u2067\u05d0 b\u2069c", "ltr", [0, 0, 1, 1, 2, 0, 0]),
    # L1: whitespace at the end of the line goes back to the paragraph level
    ("abc \u05d0\u05d1 ", "ltr", [0, 0, 0, 0, 1, 1, 0]),
])
def test_bidi_levels_follow_uax9(text, base, levels):
    from vecmsaa.fonts.shape import bidi_levels
    assert bidi_levels(text, base) == levels


@settings(max_examples=400, deadline=None)
@given(st.text(alphabet=st.sampled_from(BIDI_ALPHABET), min_size=1, max_size=16),
       st.sampled_from(["ltr", "rtl"]))
def test_visual_runs_match_an_independent_uax9(text, base):
    import bidi
    ours = "".join(text[s:e] if d == "ltr" else text[s:e][::-1]
                   for s, e, d in visual_runs(text, base))
    assert ours == bidi.get_display(text, base_dir="L" if base == "ltr" else "R")


@needs_suite
@pytest.mark.parametrize("text, inner", [
    ("\u0645\u0631\u062d\u0628\u0627 2024 \u0639\u0627\u0644\u0645", "2024"),  # issue 12
    ("\u0645\u0631\u062d\u0628\u0627 SVG2 \u0639\u0627\u0644\u0645", "SVG2"),
])
def test_numbers_and_latin_inside_arabic_keep_their_order(text, inner):
    """UAX #9 W2/W7, I1, L2: the digits (and a Latin word ending in a digit) inside a
    right-to-left paragraph are one left-to-right run, placed between the Arabic words."""
    face = load_face(os.path.join(SUITE_FONTS, "NotoSans-Regular.ttf"))
    start = text.index(inner)
    runs = shape_text(face, text)
    ltr = [r for r in runs if r.direction == "ltr"]
    assert [(r.start, r.end) for r in ltr] == [(start, start + len(inner))]
    assert list(ltr[0].clusters) == list(range(start, start + len(inner)))
    # visually: the last Arabic word, then the run, then the first word
    assert [r.start for r in runs] == [start + len(inner), start, 0]


@needs_suite
def test_rtl_run_is_reversed_and_ligated():
    face = load_face(os.path.join(SUITE_FONTS, "Amiri-Regular.ttf"))
    runs = shape_text(face, "abc \u0644\u0627 def")
    assert [r.direction for r in runs] == ["ltr", "rtl", "ltr"]
    rtl = runs[1]
    # Visual order inside an RTL run: clusters decrease left to right.
    assert list(rtl.clusters) == sorted(rtl.clusters, reverse=True)
    # Joining: a lam before alef takes a different (initial/ligature) form than alone.
    alone = shape_text(face, "\u0644")[0].gids[0]
    lam = rtl.gids[list(rtl.clusters).index(4)]
    assert lam != alone


@needs_suite
def test_runs_see_harfbuzz_context_only_next_to_them(monkeypatch):
    """Each bidi run hands HarfBuzz its own characters and at most CONTEXT_CHARS either side
    (HarfBuzz keeps 5: hb-buffer.hh), not the whole line: a long line of many runs was
    quadratic in its length. Every run still shapes as HarfBuzz shapes it with the whole
    line as context (Arabic joining across a run's edge, ZWJ ligature ranges under liga=0),
    read here straight from uharfbuzz."""
    import uharfbuzz as hb
    face = load_face(os.path.join(SUITE_FONTS, "Amiri-Regular.ttf"))
    # (x + ZWJ before an Arabic run: the ZWJ ends the Latin run and is the Arabic run's
    # pre-context, which makes its first letter join)
    text = "ab \u0644\u0627\u0645 12 x\u200d\u0628\u0628 x\u200dy \u0639\u0627 3 " * 40
    added = []
    real = hb.Buffer.add_codepoints

    class Recording(hb.Buffer):
        def add_codepoints(self, codepoints, *args):
            added.append(len(codepoints))
            return real(self, codepoints, *args)

    monkeypatch.setattr(hb, "Buffer", Recording)
    runs = shape_text(face, text, features={"liga": 0})
    monkeypatch.undo()
    assert len(runs) > 100
    # linear in the line: each run and a few characters either side (16 is generous)
    assert sum(added) <= len(text) + 2 * 16 * len(runs)
    font = face.hb_font(())
    for r in runs:
        buf = hb.Buffer()
        buf.cluster_level = hb.BufferClusterLevel.MONOTONE_CHARACTERS
        buf.add_codepoints([ord(c) for c in text], r.start, r.end - r.start)
        buf.guess_segment_properties()
        buf.direction = r.direction
        hb.shape(font, buf, {"liga": 0})
        assert list(r.gids) == [i.codepoint for i in buf.glyph_infos]
        assert list(r.clusters) == [i.cluster for i in buf.glyph_infos]
        assert r.advances[:, 0].tolist() == [p.x_advance for p in buf.glyph_positions]

def test_line_fills_share_one_path_and_sit_on_the_baseline():
    face = load_face(TTF)
    line = layout_line(face, "Hxg", 50)
    fills = line_fills(line, (10, 100))
    assert len(fills) == 1
    x0, y0, x1, y1 = fills[0].path.bounds()
    scale = 50 / face.units_per_em
    cap = face.outline(face.glyph_for_char("H"))[1][:, 1].max()
    assert y0 == pytest.approx(100 - cap * scale)    # H top is the highest point
    assert y1 > 100                                  # g descends below the baseline
    assert x1 <= 10 + line.advance + 1


def test_broken_font_is_a_font_error(tmp_path):
    bad = tmp_path / "bad.ttf"
    bad.write_bytes(b"\x00\x01\x00\x00" + b"garbage" * 10)
    with pytest.raises(FontError):
        load_face(bad)
    with pytest.raises(FontError):
        load_face(tmp_path / "missing.ttf")
    with pytest.raises(FontError):
        load_face(TTF, 3)


def _info(weight=400, style="normal", stretch=100.0, name="x"):
    return FaceInfo(name, 0, ("F",), name, weight, style, stretch, False)


@pytest.mark.parametrize("wanted,available,expected", [
    (400, [300, 500, 700], 500),        # 400 tries 500 first
    (500, [300, 400, 700], 400),
    (300, [100, 400, 700], 100),        # lighter first
    (600, [400, 500, 800], 800),        # heavier first
    (600, [400, 500], 500),
    (700, [700, 900], 700),
])
def test_css_weight_matching(wanted, available, expected):
    faces = [_info(w, name=str(w)) for w in available]
    assert best_match(faces, weight=wanted).weight == expected


def test_css_style_and_stretch_matching():
    faces = [_info(style="normal", name="n"), _info(style="oblique", name="o"),
             _info(style="italic", stretch=75, name="ci")]
    assert best_match(faces, style="italic").path == "o"          # stretch 100 comes first
    assert best_match(faces, style="italic", stretch=75).path == "ci"
    assert best_match(faces, style="normal", stretch=87.5).path == "ci"   # narrower first
    assert best_match(faces, style="normal", stretch=150).path == "n"


def test_database_generic_families_and_fallback():
    db = FontDatabase()
    db.load_dir(FIXTURES)
    assert db.query("sans-serif").family == "Noto Sans"       # first preferred present
    assert db.query("'Nope', Roboto Flex").family == "Roboto Flex"
    assert db.query("Nope") is None
    db.set_generic("serif", "Roboto Flex")
    assert db.query("serif").family == "Roboto Flex"
    # Roboto Flex's subset has no 'z': fall back to a face that has it.
    info = db.fallback_for_char("z", ["Roboto Flex"])
    assert info is not None and info.load().has_char("z")


def test_database_answers_follow_loaded_faces_and_generics():
    # queries are remembered; loading faces or mapping a generic starts afresh
    db = FontDatabase()
    assert db.query("Roboto Flex") is None and db.query("serif") is None
    db.load_dir(FIXTURES)
    assert db.query("Roboto Flex").family == "Roboto Flex"
    db.set_generic("serif", "Roboto Flex")
    assert db.query("serif").family == "Roboto Flex"
    db.set_generic("serif", "Noto Sans")
    assert db.query("serif").family == "Noto Sans"


def test_collection_faces():
    from vecmsaa.fonts import face_count

    data = open(TTC, "rb").read()
    assert data[:4] == b"ttcf"
    count = struct.unpack(">I", data[8:12])[0]
    assert face_count(TTC) == count == 2
    assert load_face(TTC, 0).family == "Noto Sans"
    second = load_face(TTC, 1)
    assert second.family == "Roboto Flex" and "wght" in second.axes
    with pytest.raises(FontError):
        load_face(TTC, 2)


def _font_with_names(tmp_path, names):
    """The fixture font with its name table's family records replaced by ``names``
    ({name ID: string})."""
    from fontTools.ttLib import TTFont
    font = TTFont(os.path.join(FIXTURES, "NotoSans-Subset.ttf"))
    table = font["name"]
    table.names = [r for r in table.names if r.nameID not in (1, 16, 21)]
    for nid, text in names.items():
        table.setName(text, nid, 3, 1, 0x409)
    path = tmp_path / "named.ttf"
    font.save(path)
    return str(path)


@pytest.mark.parametrize("names, answers, not_answers", [
    ({1: "Face Blk", 16: "Face"}, ["Face"], ["Face Blk"]),     # typographic family wins
    ({1: "Face Blk"}, ["Face Blk"], ["Face"]),                  # else the legacy family
    ({1: "Face Blk", 16: "Face", 21: "Face WWS"}, ["Face"], ["Face WWS"]),
])
def test_a_face_answers_to_its_typographic_family(tmp_path, names, answers, not_answers):
    # OpenType name table: ID 16 is the family of the whole weight/width range, ID 1 the
    # legacy four-style family, used when there is no ID 16
    db = FontDatabase()
    db.load_file(_font_with_names(tmp_path, names))
    for family in answers:
        assert db.query([family]) is not None
    for family in not_answers:
        assert db.query([family]) is None
