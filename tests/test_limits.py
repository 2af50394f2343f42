"""Hostile input: bounded time and memory, broken parts that do not fail the whole document.

Every input is small and generated here; each test states the independent truth it checks
(exact geometry, counts known by construction, or a render of an equivalent document).
"""
from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
from fontTools.fontBuilder import FontBuilder
from fontTools.misc.psCharStrings import T2CharString
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import TTFont
from fontTools.ttLib.tables._g_l_y_f import Glyph, GlyphComponent

from vecmsaa.api import render_svg_array
from vecmsaa.fonts import FontError, FontWarning, face_count, load_face
from vecmsaa.fonts.db import read_face_infos
from vecmsaa.fonts.face import MAX_COMPONENT_COPIES
from vecmsaa.svg import SvgError

SVG = 'xmlns="http://www.w3.org/2000/svg"'


# -- command line -----------------------------------------------------------------------------
def test_reference_sample_counts_are_bounded():
    """The reference mode's memory grows with its samples (2^20: 12 GB within a minute)."""
    import argparse

    from vecmsaa.cli.options import sample_count
    for ok in ("8", "256", "1024", "4096"):
        assert sample_count(ok) == int(ok)
    for bad in ("8100", "65536", "1048576", "300"):
        with pytest.raises(argparse.ArgumentTypeError, match="from 256 to 4096"):
            sample_count(bad)


# -- fonts ------------------------------------------------------------------------------------
def _square():
    pen = TTGlyphPen(None)
    pen.moveTo((100, 0))
    pen.lineTo((100, 700))
    pen.lineTo((500, 700))
    pen.lineTo((500, 0))
    pen.closePath()
    return pen.glyph()


def _composite(*names):
    g = Glyph()
    g.numberOfContours = -1
    g.components = []
    for i, name in enumerate(names):
        c = GlyphComponent()
        c.glyphName, c.x, c.y, c.flags = name, 10 * i, 0, 0x4
        g.components.append(c)
    return g


def hostile_font(path, levels=25, self_reference=False):
    """A font whose 'A' is a square and whose 'B' is broken: a composite of two copies of the
    level below, ``levels`` deep (2^levels squares), or a composite containing itself."""
    order = [".notdef", "space", "A", "B"] + [f"L{i}" for i in range(levels + 1)]
    glyphs = {".notdef": _square(), "space": Glyph(), "A": _square(), "L0": _square(),
              "B": _composite("A" if self_reference else f"L{levels}")}
    for i in range(1, levels + 1):
        glyphs[f"L{i}"] = _composite(f"L{i - 1}", f"L{i - 1}")
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", 0x41: "A", 0x42: "B"})
    fb.setupGlyf(glyphs)
    fb.setupHorizontalMetrics({n: (600, 0) for n in order})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Hostile", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    fb.font.recalcBBoxes = False     # bounds of 2^25 copies would take as long as drawing them
    fb.save(str(path))
    if self_reference:
        font = TTFont(str(path), recalcBBoxes=False)
        font["glyf"]["B"].components[0].glyphName = "B"
        font.save(str(path))
    return path


@pytest.mark.parametrize("self_reference", [False, True])
def test_broken_composite_glyph_is_empty_with_a_warning(tmp_path, self_reference):
    face = load_face(hostile_font(tmp_path / "h.ttf", self_reference=self_reference))
    with pytest.warns(FontWarning, match="broken glyph 'B'"):
        verbs, points = face.outline(face.glyph_for_char("B"))
    assert len(verbs) == 0 and len(points) == 0
    assert len(face.outline(face.glyph_for_char("A"))[1]) == 4       # the square's corners


def test_composite_within_the_limit_draws_every_copy(tmp_path):
    levels = int(np.log2(MAX_COMPONENT_COPIES))
    face = load_face(hostile_font(tmp_path / "h.ttf", levels=levels + 1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        points = face.outline(face.glyph_ids[f"L{levels}"])[1]
    assert len(points) == 4 * 2 ** levels                            # 2^levels squares
    with pytest.warns(FontWarning, match="copies"):
        assert len(face.outline(face.glyph_ids[f"L{levels + 1}"])[1]) == 0


@pytest.mark.parametrize("self_reference", [False, True])
def test_text_with_a_broken_glyph_draws_the_rest(tmp_path, self_reference):
    hostile_font(tmp_path / "h.ttf", self_reference=self_reference)
    fonts = dict(use_fonts_dir=str(tmp_path), skip_system_fonts=True)

    def text(s):
        return (f'<svg {SVG} width="120" height="40"><text x="5" y="30" font-size="20" '
                f'font-family="Hostile" xml:space="preserve">{s}</text></svg>')

    with pytest.warns(FontWarning):
        got = render_svg_array(text("AB A"), **fonts)
    # B has the advance of a space: the picture is that of "A  A"
    want = render_svg_array(text("A  A"), **fonts)
    assert (want[..., 3] > 0).any()
    assert np.array_equal(got, want)


def test_command_line_reports_a_broken_glyph_in_one_line(tmp_path):
    font = hostile_font(tmp_path / "h.ttf", self_reference=True)
    out = tmp_path / "o.png"
    run = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "font", str(font), "--text", "AB",
                          "-o", str(out)], capture_output=True, text=True)
    assert run.returncode == 0 and out.exists()
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vecmsaa font: warning: broken glyph 'B'")
    quiet = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "font", str(font), "--text", "AB",
                            "-q", "-o", str(out)], capture_output=True, text=True)
    assert quiet.returncode == 0 and quiet.stderr == ""


def _truncate_table(path, tag: bytes, length: int):
    """The font file with table ``tag``'s directory length cut to ``length`` bytes."""
    raw = bytearray(path.read_bytes())
    for i in range(int.from_bytes(raw[4:6], "big")):
        entry = 12 + 16 * i
        if raw[entry:entry + 4] == tag:
            raw[entry + 12:entry + 16] = length.to_bytes(4, "big")
    path.write_bytes(bytes(raw))
    return path


def test_corrupt_metrics_draw_empty_with_one_warning(tmp_path):
    font = _truncate_table(hostile_font(tmp_path / "h.ttf"), b"hmtx", 2)
    face = load_face(font)
    with pytest.warns(FontWarning, match="hmtx") as caught:
        assert face.advance(face.glyph_for_char("A")) == 0.0
        assert len(face.outline(face.glyph_for_char("A"))[1]) == 0
        assert len(face.outline(face.glyph_for_char("B"))[1]) == 0
    assert all("hmtx" in str(w.message) for w in caught)     # the same cause, not a later one
    for what in (["--glyphs"], ["--text", "AB"]):
        run = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "font", str(font), *what,
                              "-o", str(tmp_path / "o.png")], capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        assert "Traceback" not in run.stderr and "hmtx" in run.stderr


def cff_fan_out_font(path, levels):
    """A CFF font whose glyph 'B' calls global subroutine levels-1, each subroutine k calling
    k-1 twice and subroutine 0 drawing one line: 2^(levels-1) lines; 'A' is a square."""
    fb = FontBuilder(1000, isTTF=False)
    order = [".notdef", "A", "B"]
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({ord("A"): "A", ord("B"): "B"})
    square = [100, 0, "rmoveto", 0, 700, "rlineto", 400, 0, "rlineto", 0, -700, "rlineto",
              "endchar"]
    fb.setupCFF("Hostile-Regular", {"FullName": "Hostile"},
                {n: T2CharString(program=list(square)) for n in order}, {})
    fb.setupHorizontalMetrics({n: (600, 0) for n in order})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Hostile", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    cff = fb.font["CFF "].cff
    charstrings, subrs = cff.topDictIndex[0].CharStrings, cff.GlobalSubrs
    bias = 107                                   # Type 2 subroutine bias below 1240 subrs

    def program(tokens):
        return T2CharString(program=tokens, private=charstrings["A"].private, globalSubrs=subrs)

    subrs.append(program([1, 1, "rlineto", "return"]))
    for k in range(1, levels):
        subrs.append(program([k - 1 - bias, "callgsubr", k - 1 - bias, "callgsubr", "return"]))
    charstrings["B"] = program([100, 0, "rmoveto", levels - 1 - bias, "callgsubr", "endchar"])
    fb.font.recalcBBoxes = False                 # the bounds would run the fan-out
    fb.save(str(path))
    return path


def test_cff_subroutine_fan_out_is_bounded(tmp_path):
    small = load_face(cff_fan_out_font(tmp_path / "small.otf", levels=10))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(small.outline(small.glyph_for_char("B"))[1]) == 1 + 2 ** 9   # every line
    bomb = load_face(cff_fan_out_font(tmp_path / "bomb.otf", levels=60))        # 2^59 lines
    with pytest.warns(FontWarning, match="subroutines"):
        assert len(bomb.outline(bomb.glyph_for_char("B"))[1]) == 0
    assert len(bomb.outline(bomb.glyph_for_char("A"))[1]) == 4


def test_collection_claiming_two_billion_faces_is_refused_at_once(tmp_path):
    bomb = tmp_path / "bomb.ttc"
    bomb.write_bytes(b"ttcf\x00\x01\x00\x00\x80\x00\x00\x00" + b"\x00" * 16)   # 28 bytes
    with pytest.raises(FontError, match="claims 2147483648 faces"):
        face_count(bomb)
    assert read_face_infos(str(bomb)) == []      # a font folder scan skips it


def test_nan_variation_falls_back_to_the_default_instance():
    import os
    path = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts",
                        "RobotoFlex-Subset.ttf")
    face = load_face(path)
    assert face.clamp_location({"wght": float("nan")}) == ()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.array_equal(face.outline(face.glyph_for_char("H"),
                                           face.clamp_location({"wght": float("nan")}))[1],
                              face.outline(face.glyph_for_char("H"))[1])


# -- documents --------------------------------------------------------------------------------
@pytest.mark.parametrize("transform", ["rotate(1e400)", "skewX(1e999)", "scale(1e400 1)"])
def test_overflowing_transform_is_ignored_as_malformed(transform):
    """resvg: a number that overflows is an invalid transform list, which is ignored."""
    def doc(t):
        return (f'<svg {SVG} width="40" height="20"><rect x="2" y="2" width="10" height="10"'
                f'{t}/><rect x="22" y="2" width="10" height="10" fill="blue"/></svg>')
    assert np.array_equal(render_svg_array(doc(f' transform="{transform}"')), render_svg_array(doc("")))


def test_huge_size_in_an_error_message_is_short():
    with pytest.raises(SvgError) as info:
        render_svg_array(f'<svg {SVG} width="1e308" height="10"/>')
    assert "1e+308x10" in str(info.value) and len(str(info.value)) < 150


@pytest.mark.parametrize("filtered", [False, True])
def test_deep_nesting_renders(filtered):
    """400 nested groups in a document without a size (its extent is measured by building it),
    and 200 nested filtered groups: the same pixels as the rectangle alone."""
    g = '<g filter="url(#f)">' if filtered else "<g>"
    n = 200 if filtered else 400
    size = ' width="20" height="20"' if filtered else ""
    rect = '<rect width="10" height="10" fill="red"/>'
    defs = '<filter id="f" x="0" y="0" width="1" height="1"><feOffset/></filter>'
    deep = render_svg_array(f'<svg {SVG}{size}>{defs}{g * n}{rect}{"</g>" * n}</svg>')
    flat = render_svg_array(f'<svg {SVG}{size}>{rect}</svg>')
    assert deep.shape == flat.shape and np.array_equal(deep, flat)


def test_nested_filtered_groups_build_each_element_a_bounded_number_of_times(monkeypatch):
    """n nested groups, each with a filter in objectBoundingBox units: each needs its box to
    be drawn, and in the bounding-box pass, to decide whether its filter lets it be drawn at
    all (an element not drawn is out of its ancestors' boxes). Each element's box and
    geometry are computed once, so the n + 1 elements are built a bounded number of times
    each (drawn, and once as geometry), not n^2 / 2 times (each level's box walking its
    subtree) or 2^n (each level's decision building its subtree again)."""
    from vecmsaa.svg.builder import Builder
    builders = []
    init = Builder.__init__

    def record(self, *args, **kwargs):
        init(self, *args, **kwargs)
        builders.append(self)
    monkeypatch.setattr(Builder, "__init__", record)
    g = '<g filter="url(#f)">'
    defs = ('<filter id="f" x="0" y="0" width="1" height="1" primitiveUnits="objectBoundingBox">'
            '<feOffset dx="0"/></filter>')
    for n in (40, 200):
        builders.clear()
        img = render_svg_array(f'<svg {SVG} width="20" height="20">{defs}{g * n}'
                               f'<rect width="10" height="10"/>{"</g>" * n}</svg>')
        assert (img[:10, :10, 3] == 255).all() and img[..., 3].sum() == 100 * 255
        assert sum(b.nodes_made for b in builders) <= 3 * (n + 1)


def test_deep_nesting_of_fill_box_transforms_renders():
    """200 nested groups, each turned a quarter about the centre of its own object bounding box
    (transform-box: fill-box): each group's box is built once, not once per ancestor (2^200
    builds, past the node budget); four quarter turns about the rect's centre leave it where
    it is."""
    from vecmsaa.api import load_svg
    from vecmsaa.scene.bounds import path_bounds
    g = '<g style="transform-box: fill-box; transform-origin: center; transform: rotate(90deg)">'
    n = 200
    rect = '<rect x="4" y="2" width="10" height="6" fill="red"/>'
    (fill,) = load_svg(f'<svg {SVG} width="20" height="20">{g * n}{rect}{"</g>" * n}</svg>').fills()
    assert path_bounds(fill.path) == pytest.approx((4, 2, 14, 8), abs=1e-9)


def test_nesting_beyond_the_limit_is_a_clean_error():
    from vecmsaa.svg.document import MAX_DEPTH
    n = MAX_DEPTH + 1
    with pytest.raises(SvgError, match=f"deeper than {MAX_DEPTH}"):
        render_svg_array(f'<svg {SVG} width="10" height="10">{"<g>" * n}{"</g>" * n}</svg>')


# -- CSS --------------------------------------------------------------------------------------
def test_selector_too_long_to_compile_is_dropped_unparsed(monkeypatch):
    """cssselect2 cannot compile a selector of 67 or more combinators (Python's parser nests
    too deep) and takes time quadratic in its length to try (20,000: minutes): such a rule is
    dropped before parsing; the document's other rules apply."""
    import cssselect2
    parsed = []
    real = cssselect2.compile_selector_list
    monkeypatch.setattr(cssselect2, "compile_selector_list",
                        lambda prelude, *a: parsed.append(len(prelude)) or real(prelude, *a))
    long = " ".join(["g"] * 2000) + " rect"
    doc = (f'<svg {SVG} width="4" height="4"><style>{long} {{fill: red}} g > rect {{fill: '
           f'#00f}}</style><g><rect width="4" height="4"/></g></svg>')
    out = render_svg_array(doc)
    assert (out[..., :3] == (0, 0, 255)).all()
    assert parsed and max(parsed) < 100


@pytest.mark.parametrize("rule, body", [
    # every rect scans all its earlier siblings (200 rects: 20,000 steps)
    ("g ~ rect", '<g/>' + '<rect width="1" height="1"/>' * 200),
    # descendant combinators backtrack: C(30, 6) ways to place six g's over 30 ancestors
    ("x g g g g g g rect", "<g>" * 30 + '<rect width="1" height="1"/>' + "</g>" * 30),
])
def test_costly_selector_matching_is_a_clean_error(monkeypatch, rule, body):
    from vecmsaa.svg import document
    monkeypatch.setattr(document, "MAX_SELECTOR_STEPS", 10_000)
    doc = f'<svg {SVG} width="4" height="4"><style>{rule} {{fill: red}}</style>{body}</svg>'
    with pytest.raises(SvgError, match="CSS selectors take more than 10000 steps"):
        render_svg_array(doc)


def test_selector_matching_within_the_limit_applies_the_rules(monkeypatch):
    from vecmsaa.svg import document
    monkeypatch.setattr(document, "MAX_SELECTOR_STEPS", 10_000, raising=False)
    doc = (f'<svg {SVG} width="4" height="4"><style>g ~ rect {{fill: #00f}} a g g rect {{fill: '
           f'red}} g:first-of-type g > rect:last-of-type {{stroke: #0f0}}</style><g/>'
           f'{"<g>" * 5}<rect width="4" height="4"/><rect width="4" height="4"/>{"</g>" * 5}'
           f'<rect width="4" height="2"/></svg>')
    out = render_svg_array(doc)
    assert (out[:2, :, :3] == (0, 0, 255)).all()          # the last rect: g ~ rect
    assert (out[2, 1:3, :3] == 0).all()                    # "a g g rect": no <a>, black
    assert (out[3, 1:3, 1] > 100).all() and (out[3, 1:3, 0] == 0).all()   # green stroke edge


# -- images -----------------------------------------------------------------------------------
def _png(array, mode=None):
    import io

    from PIL import Image
    buf = io.BytesIO()
    im = Image.fromarray(array)
    (im.convert(mode) if mode else im).save(buf, "PNG")
    return buf.getvalue()


def _image_doc(png, copies=1, size=64):
    import base64
    href = "data:image/png;base64," + base64.b64encode(png).decode()
    images = "".join(f'<image href="{href}" width="{size}" height="{size}"/>'
                     for _ in range(copies))
    return f'<svg {SVG} width="{size}" height="{size}">{images}</svg>'


def test_large_image_drawn_small_is_decoded_once_and_averaged(monkeypatch):
    """A 4096² 1-bit noise image drawn at 64² in ten places: one decode; each device pixel is
    the mean of its 64² texels (box reduction), close to the noise's 50 % grey, where plain
    bilinear sampling of the full image would pick single texels (0 or 255)."""
    from PIL import Image
    rng = np.random.default_rng(16)
    png = _png(rng.integers(0, 2, (4096, 4096), dtype=np.uint8) * 255, "1")
    opened = []
    real_open = Image.open
    monkeypatch.setattr(Image, "open", lambda *a, **k: opened.append(1) or real_open(*a, **k))
    out = render_svg_array(_image_doc(png, copies=10))
    assert len(opened) == 1
    grey = out[1:-1, 1:-1, :3].astype(float)
    assert (out[..., 3] == 255).all()
    assert abs(grey.mean() - 127.5) < 3 and np.abs(grey - 127.5).max() < 40


def test_images_over_the_decoded_pixel_budget_are_skipped(monkeypatch):
    from vecmsaa.svg import image
    monkeypatch.setattr(image, "MAX_DECODED_PIXELS", 64 * 64)
    red = _png(np.full((64, 64, 3), (255, 0, 0), np.uint8))
    blue = _png(np.full((64, 64, 3), (0, 0, 255), np.uint8))
    doc = _image_doc(red, copies=3).replace("</svg>", _image_doc(blue)[_image_doc(blue).index(
        "<image"):])
    out = render_svg_array(doc)
    assert (out[..., 0] == 255).all() and (out[..., 2] == 0).all()   # red drawn, blue not


def test_texels_over_the_document_budget_are_skipped(monkeypatch):
    """Each reduction of an image is a texel set of its own (16 bytes a texel): a 64² image
    drawn at 64 px fills a 64² budget, the same image drawn at 16 px (2x2 reduced) is past
    it and not drawn, with a warning."""
    from vecmsaa.svg import image
    monkeypatch.setattr(image, "MAX_TEXEL_PIXELS", 64 * 64)
    red = _png(np.full((64, 64, 3), (255, 0, 0), np.uint8))
    doc = _image_doc(red).replace("</svg>", '<image href="data:image/png;base64,'
                                  + __import__("base64").b64encode(red).decode()
                                  + '" width="16" height="16" opacity="0.5"/></svg>')
    with pytest.warns(UserWarning, match="texels"):
        out = render_svg_array(doc)
    assert (out[..., :3] == (255, 0, 0)).all() and (out[..., 3] == 255).all()
    monkeypatch.setattr(image, "MAX_TEXEL_PIXELS", 64 * 64 + 32 * 32)
    out = render_svg_array(doc)
    assert out[0, 0, 0] == 255 and out[8, 8, 3] == 255


def test_svg_images_share_their_documents_image_budget(monkeypatch):
    """An SVG image inside the document decodes its images into the document's budget: a
    nested document per image restarted it (a few KB of nested data: URLs, gigabytes)."""
    import base64

    from vecmsaa.svg import image
    monkeypatch.setattr(image, "MAX_DECODED_PIXELS", 64 * 64)
    red = _png(np.full((64, 64, 3), (255, 0, 0), np.uint8))
    blue = _png(np.full((64, 64, 3), (0, 0, 255), np.uint8))
    inner = _image_doc(red).encode()
    doc = (f'<svg {SVG} width="64" height="64"><image width="64" height="64" href="data:image/'
           f'svg+xml;base64,{base64.b64encode(inner).decode()}"/><image width="64" height="64" '
           f'href="data:image/png;base64,{base64.b64encode(blue).decode()}"/></svg>')
    with pytest.warns(UserWarning, match="decode to more than 4096 pixels"):
        out = render_svg_array(doc)
    assert (out[..., 0] == 255).all() and (out[..., 2] == 0).all()   # red drawn, blue not


def test_texels_are_made_without_whole_image_temporaries():
    """Texels are 16 bytes a pixel; converting the whole image at once held float32 and uint8
    copies beside them (about 40 bytes a pixel at the peak)."""
    import tracemalloc

    from PIL import Image

    from vecmsaa.svg.image import image_texels
    rng = np.random.default_rng(18)
    rgba = rng.integers(0, 256, (1024, 1024, 4), dtype=np.uint8)
    im = Image.fromarray(rgba, "RGBA")
    tracemalloc.start()
    try:
        texels = image_texels(im)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1.2 * texels.nbytes
    a = rgba.astype(np.float32) / 255.0
    assert np.array_equal(texels[1:-1, 1:-1, 3], a[..., 3])
    assert np.array_equal(texels[1:-1, 1:-1, :3], a[..., :3] * a[..., 3:4])


def _svg_image_doc(inner, uses, size=10):
    import base64
    href = "data:image/svg+xml;base64," + base64.b64encode(inner.encode()).decode()
    return (f'<svg {SVG} xmlns:xlink="http://www.w3.org/1999/xlink" width="{size}" '
            f'height="{size}"><image id="i" width="{size}" height="{size}" href="{href}"/>'
            + '<use href="#i"/>' * uses + '</svg>')


def test_svg_image_elements_count_against_the_documents_limit(monkeypatch):
    """An SVG image's elements are the document's: an image used 100 times, of 100 rects,
    builds 10,000 elements (fan-out over nested images: 100 KB built a billion)."""
    from vecmsaa.svg import builder
    monkeypatch.setattr(builder, "MAX_NODES", 5000)
    inner = f'<svg {SVG} width="10" height="10">' + '<rect width="1" height="1"/>' * 100 + '</svg>'
    render_svg_array(_svg_image_doc(inner, 30))
    with pytest.raises(SvgError, match="too many elements"):
        render_svg_array(_svg_image_doc(inner, 100))


def test_svg_image_drawn_many_times_is_parsed_once(monkeypatch):
    from vecmsaa.svg import sizing
    parsed = []
    real = sizing.open_svg
    monkeypatch.setattr(sizing, "open_svg", lambda *a, **k: parsed.append(1) or real(*a, **k))
    inner = f'<svg {SVG} width="10" height="10"><rect width="5" height="10" fill="#00f"/></svg>'
    out = render_svg_array(_svg_image_doc(inner, 20))
    assert len(parsed) == 2                 # the document and its image
    assert (out[:, :5, 2] == 255).all() and (out[:, 5:, 3] == 0).all()


# -- dashes -----------------------------------------------------------------------------------
@pytest.mark.parametrize("cap, dashes, covered", [
    ("butt", "0.01 0.03", 0.25),            # a quarter of each 0.04 px period is on
    ("square", "0.01 0.05", 1.0),           # 10 px square caps cover the gaps
    ("butt", "0", None),                    # all zeros: a solid stroke
    ("butt", "0 0.001", 0.0),               # zero-length butt dashes draw nothing
])
def test_sub_pixel_dashes_are_a_coverage(cap, dashes, covered):
    def doc(d):
        return (f'<svg {SVG} width="120" height="20"><path d="M10 10 H110" stroke="black" '
                f'stroke-width="10" stroke-linecap="{cap}" stroke-dasharray="{d}"/></svg>')
    alpha = render_svg_array(doc(dashes))[8:13, 20:100, 3].astype(float) / 255
    want = 1.0 if covered is None else covered
    assert np.abs(alpha - want).max() <= 1.5 / 255


def test_huge_dashed_circle_is_bounded_and_half_covered():
    """r = 1e6 with dasharray 0.001: 3e9 dashes of 2.5e-7 device px, drawn as coverage 1/2."""
    out = render_svg_array(f'<svg {SVG} width="100" height="100" viewBox="-1.1e6 -1.1e6 2.2e6 '
                           f'2.2e6"><circle r="1e6" fill="none" stroke="black" stroke-width="1e5"'
                           f' stroke-dasharray="0.001"/></svg>')
    ring = out[50, 2:7, 3].astype(float) / 255          # the stroke's left side, 4.5 px wide
    assert np.abs(ring[1:-1] - 0.5).max() <= 2 / 255


def test_path_cut_into_too_many_dashes_is_a_coverage():
    from vecmsaa.geometry.stroke import MAX_DASHES
    n = 4 * MAX_DASHES      # a line of 4 * MAX_DASHES periods of 2 px, mostly off the canvas
    out = render_svg_array(f'<svg {SVG} width="40" height="20"><path d="M0 10 H{2 * n}" '
                           f'stroke="black" stroke-width="8" stroke-dasharray="1 1"/></svg>')
    assert np.abs(out[8:13, 5:35, 3].astype(float) / 255 - 0.5).max() <= 2 / 255


# -- text -------------------------------------------------------------------------------------
def test_text_longer_than_the_limit_is_a_clean_error(monkeypatch):
    from vecmsaa.svg import builder
    monkeypatch.setattr(builder, "MAX_TEXT_CHARS", 100)

    def doc(n):
        return f'<svg {SVG} width="400" height="20"><text y="15">{"ab" * (n // 2)}</text></svg>'
    render_svg_array(doc(100))
    with pytest.raises(SvgError, match="longer than 100 characters"):
        render_svg_array(doc(102))


def test_text_of_one_chunk_per_character_reads_each_character_a_few_times(monkeypatch):
    """A list of x values starts a chunk at every character (SVG 2 §11.8.1); joining the whole
    text per chunk read n² characters (100,000 characters: minutes)."""
    from vecmsaa.svg.text import content

    reads = []

    slot = content.Char.__dict__["ch"]     # (Char has slots: its member descriptor)

    class Counted:
        def __get__(self, obj, owner=None):
            if obj is None:
                return self
            reads.append(1)
            return slot.__get__(obj, owner)

        def __set__(self, obj, value):
            slot.__set__(obj, value)

    descriptor = Counted()
    monkeypatch.setattr(content.Char, "ch", descriptor, raising=False)

    def doc(n):
        xs = " ".join(str(i) for i in range(n))
        return f'<svg {SVG} width="400" height="20"><text x="{xs}" y="15">{"x" * n}</text></svg>'
    counts = []
    for n in (200, 800):
        del reads[:]
        render_svg_array(doc(n))
        counts.append(len(reads))
    assert counts[0] > 0 and counts[1] < 6 * counts[0]     # 4x the characters: linear, not 16x


def test_glyph_placement_holds_no_per_point_copy_of_the_matrices():
    """Placing many glyphs repeated each glyph's 6-entry matrix for every point (48 bytes a
    point beside the 16 of the result): 200,000 characters took 400 MB for it alone."""
    import os
    import tracemalloc

    from vecmsaa.fonts.layout import glyphs_arrays
    face = load_face(os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts",
                                  "NotoSans-Subset.ttf"))
    gids = [g for g in range(1, min(face.num_glyphs, 40)) if len(face.outline(g, ())[1])] * 200
    shifts = np.arange(len(gids), dtype=np.float64)
    mats = [(1.0, 0.0, 0.0, 1.0, x, -x) for x in shifts]
    tracemalloc.start()
    try:
        verbs, out = glyphs_arrays(face, (), gids, mats)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4 * out.nbytes
    counts = [len(face.outline(g, ())[1]) for g in gids]
    points = np.concatenate([face.outline(g, ())[1] for g in gids])
    shift = np.repeat(shifts, counts)
    assert np.array_equal(out, points + np.stack([shift, -shift], axis=1))


# -- reference fan-out ------------------------------------------------------------------------
def test_mask_chain_fan_out_is_a_clean_error():
    """Each mask's content uses the next mask twice: 2^14 mask layers for one rectangle."""
    masks = "".join(f'<mask id="k{i}"><rect width="10" height="10" fill="white" mask="url(#k'
                    f'{i + 1})"/><rect width="5" height="10" fill="white" mask="url(#k{i + 1})"/>'
                    f'</mask>' for i in range(14))
    doc = (f'<svg {SVG} width="10" height="10">{masks}<mask id="k14"><rect width="10" '
           f'height="10" fill="white"/></mask><rect width="10" height="10" mask="url(#k0)"/></svg>')
    with pytest.raises(SvgError, match="fan-out"):
        render_svg_array(doc)


def test_nested_references_within_the_limit_render():
    """Three levels of masks (6 nested instances): white rect under a chain of full masks."""
    masks = "".join(f'<mask id="k{i}"><rect width="10" height="10" fill="white" mask="url(#k'
                    f'{i + 1})"/></mask>' for i in range(3))
    doc = (f'<svg {SVG} width="10" height="10">{masks}<mask id="k3"><rect width="10" '
           f'height="10" fill="white"/></mask><rect width="10" height="10" mask="url(#k0)"/></svg>')
    assert (render_svg_array(doc)[..., 3] == 255).all()



def mask_chain(n, nested_content=0):
    """A rect under a chain of ``n`` masks, each mask's own ``mask`` the next; the last one's
    white rect under ``nested_content`` groups."""
    masks = "".join(f'<mask id="k{i}" mask="url(#k{i + 1})"><rect width="10" height="10" '
                    f'fill="white"/></mask>' for i in range(n - 1))
    last = ('<g>' * nested_content + '<rect width="10" height="10" fill="white"/>'
            + '</g>' * nested_content)
    return (f'<svg {SVG} width="10" height="10">{masks}<mask id="k{n - 1}">{last}</mask>'
            f'<rect width="10" height="10" mask="url(#k0)"/></svg>')


def test_reference_chains_longer_than_element_nesting_are_a_clean_error():
    """A chain of masks nests layers as deep as it is long (5,000 raised RecursionError while
    drawing); chains as long as elements may nest, the last mask's content nested as deep
    again, render (every mask white: the rect is drawn)."""
    from vecmsaa.svg.document import MAX_DEPTH
    with pytest.raises(SvgError, match="nest deeper"):
        render_svg_array(mask_chain(MAX_DEPTH + 1))
    assert (render_svg_array(mask_chain(MAX_DEPTH, MAX_DEPTH - 4))[..., 3] == 255).all()


# -- filters ----------------------------------------------------------------------------------
def render_peak(scene, **options):
    """(RGBA8 image, tracemalloc's peak in bytes) of rendering ``scene`` once its kernels are
    loaded (a first render, untraced)."""
    import tracemalloc

    from vecmsaa.raster.render import render_scene_rgba8

    render_scene_rgba8(scene, **options)
    tracemalloc.start()
    try:
        image = render_scene_rgba8(scene, **options)
        return image, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def filter_cost(svg_of, size):
    """(filtered image, unfiltered image, peak of the filtered render over the unfiltered one
    in float32 RGBA canvases of size x size) of the documents ``svg_of(True)`` and
    ``svg_of(False)``, rendered on one thread."""
    from vecmsaa.api import load_svg

    image, held = render_peak(load_svg(svg_of(True)), threads=1)
    plain, unfiltered = render_peak(load_svg(svg_of(False)), threads=1)
    return image, plain, (held - unfiltered) / (size * size * 16)


def filtered_rect(primitives, size):
    """svg_of for filter_cost: a teal size x size rect, with a filter of ``primitives``
    whose region is its box when ``filtered``."""
    return lambda filtered: (f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" '
                             f'y="0" width="1" height="1">{primitives}</filter><rect '
                             f'width="{size}" height="{size}" fill="teal"'
                             f'{FILTERED if filtered else ""}/></svg>')


FILTERED = ' filter="url(#f)"'


def test_many_filtered_elements_hold_one_filtered_buffer_at_a_time():
    """Elements each with a filter over the whole canvas, rendered in bands (a small band
    budget, two threads): keeping every filtered layer until its last band would hold one
    canvas per element. Thirty must cost at most a few canvases more than one, and give the
    one-band image."""
    from vecmsaa.api import load_svg
    from vecmsaa.raster.render import render_scene_rgba8

    size = 300
    canvas = size * size * 16                     # one float32 RGBA canvas

    def scene(count):
        rects = "".join(f'<rect x="{(i * 37) % 280}" y="{(i * 53) % 280}" width="20" '
                        f'height="20" filter="url(#f)"/>' for i in range(count))
        return load_svg(f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" '
                        f'y="0" width="{size}" height="{size}" filterUnits="userSpaceOnUse">'
                        f'<feGaussianBlur stdDeviation="2"/></filter>{rects}</svg>')

    def banded_peak(s):
        return render_peak(s, threads=2, band_budget=canvas // 8)

    many = scene(30)
    image, peak = banded_peak(many)
    assert np.array_equal(image, render_scene_rgba8(many, threads=1, band_budget=64 * canvas))
    extra = (peak - banded_peak(scene(1))[1]) / canvas
    assert extra < 4, f"{extra:.1f} canvases more for 30 filtered elements than for one"


@pytest.mark.parametrize("filtered", [False, True])
def test_deeply_nested_layers_hold_a_bounded_total(monkeypatch, filtered):
    """Each nesting level of groups with opacity keeps a buffer of a band's rows: 120 levels
    at a full band each would hold 120 canvases. Under a layers budget of two canvases the
    bands thin out (and so does the drawing of a filtered group's content, at its region's
    size), holding a few canvases in all, with the pixels of the unbudgeted render (a band's
    pixels do not depend on where it starts)."""
    from vecmsaa.api import load_svg
    from vecmsaa.raster import render

    size, n = 200, 120
    canvas = size * size * 16                     # one float32 RGBA canvas
    inner = ('<rect x="20" y="20" width="160" height="160" fill="teal"/>'
             '<circle cx="100" cy="100" r="60" fill="orange"/>')
    body = '<g opacity="0.99">' * n + inner + "</g>" * n
    if filtered:
        body = f'<g filter="url(#f)">{body}</g>'
    scene = load_svg(f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" y="0" '
                     f'width="1" height="1"><feOffset dx="3"/></filter>{body}</svg>')

    def peak():
        return render_peak(scene, threads=1)
    monkeypatch.setattr(render, "LAYERS_BUDGET", 1 << 40)
    whole, _ = peak()
    monkeypatch.setattr(render, "LAYERS_BUDGET", 2 * canvas)
    image, held = peak()
    assert np.array_equal(image, whole)
    assert held / canvas < 8, f"{held / canvas:.1f} canvases held by {n} nested layers"


def test_a_long_filter_chain_holds_a_few_results_not_one_per_primitive():
    """Each primitive reads the previous result (and the source): after that read it is let
    go, so a chain of 60 costs about what a chain of 2 does."""
    from vecmsaa.api import load_svg

    size = 200
    canvas = size * size * 16

    def peak(count):
        prims = '<feComposite in="SourceGraphic" operator="over"/>' * count
        scene = load_svg(f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" '
                         f'y="0" width="1" height="1">{prims}</filter><rect width="{size}" '
                         f'height="{size}" fill="teal" filter="url(#f)"/></svg>')
        return render_peak(scene, threads=1)[1]
    extra = (peak(60) - peak(2)) / canvas
    assert extra < 3, f"{extra:.1f} canvases more for 60 primitives than for 2"


def test_nested_style_elements_read_their_own_text_only():
    """A fuzzer's find: 12,902 unclosed <style>s nest, and each one's descendants' text made
    the CSS quadratic (2 GB). A style element's CSS is its child text content (HTML/CSSOM)."""
    import tracemalloc

    from vecmsaa.svg.document import load_document

    count = 1000
    nested = '<style>#r { fill: blue }' * count + '</style>' * count
    tracemalloc.start()
    try:
        doc = load_document(f'<svg {SVG} width="10" height="10">{nested}'
                            f'<rect id="r" width="10" height="10"/></svg>'.encode())
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert doc.ids["r"].specified["fill"] == "blue"
    # the old reading: 1000 * 1001 / 2 copies of the 24-character rule, 12 MB of CSS text
    assert peak < 8_000_000, f"{peak / 1e6:.1f} MB"


@pytest.mark.parametrize("sigma, images", [(5, 1), (1, 3)])
def test_a_blur_filter_holds_its_content_and_little_more(sigma, images):
    """A blur of a filter region as large as the image: the content (one float32 RGBA
    canvas) is converted to linearRGB, blurred and converted back in place (the box blur
    keeps a row or a block of columns aside, the recursive one an f64 copy, two canvases),
    and a band of it is composited without a copy. Before: the content, SourceAlpha, the
    result's buffer, the linear copy, two blur passes and the sRGB copy (7.8 canvases)."""
    size = 400
    image, _, extra = filter_cost(
        filtered_rect(f'<feGaussianBlur stdDeviation="{sigma}"/>', size), size)
    # the blur is there: the corner is half-transparent, the centre opaque
    assert 0 < image[0, 0, 3] < 200 and image[size // 2, size // 2, 3] == 255
    # the content's canvas, the blur's own (images - 1), and under one for the rasteriser
    assert extra < images + 1, f"{extra:.1f} canvases for a blur's filter"


def test_nested_filtered_groups_hold_a_few_buffers_not_one_per_level():
    """Twelve groups nested each with a blur: each level's content buffer (the filter
    region, one canvas here) was made before the group inside was filtered, so all twelve
    were held at once. The group inside is filtered first now: twelve levels cost a few
    canvases more than one, and the pixels are those of blurring twelve times."""
    from vecmsaa.api import load_svg

    size = 300
    canvas = size * size * 16

    def render(levels):
        body = '<rect x="100" y="100" width="100" height="100" fill="teal"/>'
        for _ in range(levels):
            body = f'<g filter="url(#f)">{body}</g>'
        scene = load_svg(f'<svg {SVG} width="{size}" height="{size}"><filter id="f" '
                         f'filterUnits="userSpaceOnUse" x="0" y="0" width="{size}" '
                         f'height="{size}"><feGaussianBlur stdDeviation="3"/></filter>'
                         f'{body}</svg>')
        return render_peak(scene, threads=1)
    image, deep = render(12)
    one, single = render(1)
    # twelve blurs of sigma 3 spread like one of sigma 3·√12 ≈ 10.4: wider than one blur
    assert image[100 - 25, 150, 3] > one[100 - 25, 150, 3]
    extra = (deep - single) / canvas
    assert extra < 3, f"{extra:.1f} canvases more for twelve nested filtered groups than one"


def test_a_turbulence_filter_holds_its_result_only():
    """feTurbulence over the whole image reads no content: the content is not drawn, the
    noise is written in f32 and premultiplied in place. One canvas and change (before: the
    content, an f64 noise image, its f32 copy, the premultiplied copy and a cleaned copy,
    7.6 canvases)."""
    size = 400
    image, _, extra = filter_cost(
        filtered_rect('<feTurbulence baseFrequency="0.05"/>', size), size)
    assert len(np.unique(image[..., 3])) > 50          # noise, not the teal rect
    assert extra < 1.5, f"{extra:.1f} canvases for a turbulence filter"


@pytest.mark.parametrize("primitive, bound", [
    ('<feColorMatrix type="saturate" values="0.3"/>', 3),
    ('<feComponentTransfer><feFuncR type="linear" slope="0.5"/><feFuncA type="table" '
     'tableValues="0 1 0.5"/></feComponentTransfer>', 3),
    ('<feMorphology operator="dilate" radius="3"/>', 6),
    ('<feDropShadow dx="4" dy="4" stdDeviation="3"/>', 4.5),
    ('<feOffset dx="3"/><feComposite in2="SourceGraphic" operator="over"/>', 3)])
def test_a_filter_primitive_holds_a_few_canvases(primitive, bound):
    """feColorMatrix and feComponentTransfer work on straight colour: one copy of the
    content, clamped and premultiplied in place (the matrix written into the content, which
    no one reads after). Before: the masked copy, the unpremultiplied one, the product, the
    sum, the clamped, cast and premultiplied copies (8.6 and 7.8 canvases with the content).
    feMorphology's sliding extremes combine views of the padded image, where np.take copied
    both operands of each step (11.6 canvases; now the content, a pass's result, the padded
    image, its next step and the running extreme). feDropShadow and feComposite's
    source-over write into the shadow and into an input no one reads after (8.9 and 7.9
    canvases before)."""
    size = 400
    image, plain, extra = filter_cost(
        lambda filtered: f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" '
                         f'y="0" width="1" height="1">{primitive}</filter><g'
                         f'{FILTERED if filtered else ""}>'
                         f'<rect width="{size}" height="{size}" fill="rgb(0,128,255)" '
                         f'fill-opacity="0.5"/>'
                         f'<circle cx="200" cy="200" r="50" fill="orange"/></g></svg>', size)
    assert not np.array_equal(image, plain)               # the filter did something
    assert extra < bound, f"{extra:.1f} canvases for {primitive}"


def test_the_part_of_a_filter_region_inside_the_image_is_kept_in_its_own_buffer():
    """A filter region beyond the image is cut to the image after filtering: the inside is
    moved to the front of the region's buffer, which is then shrunk, so no second buffer is
    held (the copy held the region and the image at once), and what is kept is the image's
    part only. With another reference to the buffer it is copied instead."""
    import tracemalloc

    from vecmsaa.raster.render import _cropped

    rng = np.random.default_rng(7)
    region = rng.random((600, 500, 4), dtype=np.float32)
    want = region[150:450, 100:400].copy()
    tracemalloc.start()
    try:
        start = tracemalloc.get_traced_memory()[0]
        got = _cropped([region.copy()], 150, 450, 100, 400)
        now, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert np.array_equal(got, want)
    assert now - start <= want.nbytes + 4096, "more than the image's part kept"
    assert peak - start <= region.nbytes + 4096, "a second buffer during the crop"
    # a view of it still held elsewhere: the buffer cannot shrink, the view is untouched
    shared = region.copy()
    view = shared[:10]
    first = view.copy()
    got = _cropped([shared], 150, 450, 100, 400)
    assert np.array_equal(got, want) and np.array_equal(view, first)


def test_an_image_drawn_many_times_is_in_the_texture_once():
    """One <image> used 30 times (and drawn once more by a second <image> of the same URL)
    puts its texels in the kernels' texture once: the texture of the batch holding the 31
    draws is one 512 x 512 RGBA float32 image (4 MiB), not 31 of them (130 MiB; 30 uses of a
    2048² PNG took 2 GB)."""
    import base64
    import io

    from PIL import Image

    from vecmsaa.api import load_svg
    from vecmsaa.raster.render import FillBatch, RenderOptions, prepare_items

    texels = (np.random.RandomState(1).rand(512, 512, 4) * 255).astype(np.uint8)
    png = io.BytesIO()
    Image.fromarray(texels).save(png, "PNG")
    uri = "data:image/png;base64," + base64.b64encode(png.getvalue()).decode()
    uses = "".join(f'<use href="#i" x="{5 * i}" y="{5 * i}"/>' for i in range(30))
    scene = load_svg(('<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400">'
                      f'<defs><image id="i" width="200" height="200" href="{uri}"/></defs>'
                      f'{uses}<image width="50" height="50" href="{uri}"/></svg>').encode())
    batches = [i for i in prepare_items(scene.root, RenderOptions()) if isinstance(i, FillBatch)]
    assert sum(len(b.kinds) for b in batches) == 31
    one_image = 512 * 512 * 4 * 4
    assert sum(b.tex.nbytes for b in batches) < 1.1 * one_image


# -- feConvolveMatrix -------------------------------------------------------------------------
def _convolved(order, values, size):
    """A size x size teal rect through feConvolveMatrix over exactly its own pixels."""
    return (f'<svg {SVG} width="{size}" height="{size}"><filter id="f" x="0" y="0" width="1" '
            f'height="1"><feConvolveMatrix order="{order}" kernelMatrix="{values}"/></filter>'
            f'<rect width="{size}" height="{size}" fill="teal" filter="url(#f)"/></svg>').encode()


def test_a_convolution_past_the_work_limit_is_transparent_with_a_warning():
    """order="300" with 90,000 nonzero entries over an 800^2 region is 5.8 x 10^10 products a
    channel (minutes); Filter Effects 1 recommends small orders and sets no bound. Past
    filter_effects.MAX_CONVOLVE_WORK the primitive is what an invalid kernel is (transparent
    black, as usvg's) and one line says so. The same order with one nonzero entry (the
    identity: Filter Effects 1's sum gives each pixel itself) is within the limit and exact."""
    ones = " ".join(["1"] * 90000)
    with pytest.warns(UserWarning, match="convolution limit") as caught:
        img = render_svg_array(_convolved(300, ones, 800))
    assert len(caught) == 1 and not img.any()
    identity = ["0"] * 90000
    identity[150 * 300 + 150] = "1"           # the target's own entry (targetX = targetY = 150)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        img = render_svg_array(_convolved(300, " ".join(identity), 800))
    plain = render_svg_array(f'<svg {SVG} width="800" height="800"><rect width="800" '
                             f'height="800" fill="teal"/></svg>'.encode())
    assert np.abs(img.astype(int) - plain).max() <= 1


def test_the_convolution_limit_counts_nonzero_entries_times_pixels(monkeypatch):
    """Eight nonzero entries of nine over a 40^2 region are 12,800 entry-pixels: drawn (a
    mean of equal pixels, the rect itself) with the limit at 12,800, transparent below it."""
    from vecmsaa.raster import filter_effects
    doc = _convolved(3, "1 1 1 1 1 1 1 1 0", 40)
    plain = render_svg_array(f'<svg {SVG} width="40" height="40"><rect width="40" height="40" '
                             f'fill="teal"/></svg>'.encode())
    monkeypatch.setattr(filter_effects, "MAX_CONVOLVE_WORK", 8 * 40 * 40)
    img = render_svg_array(doc)
    assert img.any() and np.abs(img.astype(int) - plain).max() <= 1
    monkeypatch.setattr(filter_effects, "MAX_CONVOLVE_WORK", 8 * 40 * 40 - 1)
    with pytest.warns(UserWarning, match="convolution limit"):
        assert not render_svg_array(doc).any()


# -- work growing with the document -----------------------------------------------------------
def python_calls(fn):
    """Python function calls (generators' resumptions included) made running ``fn``: the
    work, counted without timing anything."""
    count = [0]

    def profile(frame, event, arg):
        if event == "call":
            count[0] += 1
    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return count[0]


def linear_work(doc_of, n, run=None):
    """Whether building ``doc_of(2 n)`` (or ``run`` on it) takes at most 2.5 times the Python
    calls of ``doc_of(n)`` (twice: linear; four times: quadratic)."""
    from vecmsaa.api import load_svg
    run = run or (lambda doc: load_svg(doc))
    run(doc_of(4))                  # imports, kernels
    small, large = (python_calls(lambda: run(doc_of(k))) for k in (n, 2 * n))
    return large < 2.5 * small


def test_filter_href_chains_are_followed_in_linear_work():
    """A rect filtered by the last of n filters each referencing the one before (a chain of
    4,000: 1.6 s, every link checked against all before it)."""
    def doc(n):
        chain = "".join(f'<filter id="f{i}" href="#f{i - 1}"/>' for i in range(1, n))
        return (f'<svg {SVG} width="10" height="10"><filter id="f0"><feOffset dx="1"/></filter>'
                f'{chain}<rect width="5" height="5" filter="url(#f{n - 1})"/></svg>')
    assert linear_work(doc, 1000)


def test_nested_layers_box_their_content_once(monkeypatch):
    """Each <svg> nested in another clips to its viewport, a rectangle: whether it covers the
    content asks the box of all the layers inside it (1,000 nested: 500,500 boxes, 3 s). Each
    layer's is taken once; the drawing is the innermost rect."""
    from vecmsaa.raster import render
    calls = []
    real = render._items_box
    monkeypatch.setattr(render, "_items_box", lambda items: calls.append(1) or real(items))
    n = 200
    doc = (f'<svg {SVG} width="10" height="10">' + '<svg width="9" height="9">' * n
           + '<rect x="2" y="2" width="4" height="4"/>' + '</svg>' * n + '</svg>')
    out = render_svg_array(doc, threads=1)
    assert (out[2:6, 2:6, 3] == 255).all() and out[..., 3].sum() == 16 * 255
    assert len(calls) <= 2 * n


def test_fills_of_one_gradient_share_its_ramp(monkeypatch):
    """Each gradient fill had its own 32 KB colour ramp (40,000 rects of one gradient: 1.4 GB
    drawing 200 px); fills of equal stops and opacity share one. 40 rects of one red-to-blue
    gradient, every other one at fill-opacity 0.5: two ramps; each pixel is the straight
    sRGB mix at its centre (SVG 1.1 §13.2.2), within 1/255."""
    from vecmsaa.raster import shaders
    ramps = []
    real = shaders.gradient_lut
    monkeypatch.setattr(shaders, "gradient_lut", lambda *a: ramps.append(1) or real(*a))
    n = 40
    rects = "".join(f'<rect x="{10 * k}" width="10" height="2" fill="url(#g)" '
                    f'fill-opacity="{0.5 if k % 2 else 1}"/>' for k in range(n))
    doc = (f'<svg {SVG} width="{10 * n}" height="2"><linearGradient id="g"><stop '
           f'stop-color="#f00"/><stop offset="1" stop-color="#00f"/></linearGradient>'
           f'{rects}</svg>')
    out = render_svg_array(doc, threads=1).astype(int)
    t = (np.arange(10) + 0.5) / 10
    mix = np.stack([255 * (1 - t), 0 * t, 255 * t], axis=1)
    for k in range(n):
        block = out[:, 10 * k:10 * k + 10]
        assert np.abs(block[..., :3] - mix).max() <= 1
        assert np.abs(block[..., 3] - (127.5 if k % 2 else 255)).max() <= 1
    assert len(ramps) == 2


#: a 48 px render of this path (an arc sized up to reach y = 5e9: a circle 10^9 px across)
#: had its hairline kernel reserve over 2 GB of address space (room for max_steps[0] steps
#: of each of thousands of chords, where a path's staircases take max_steps[1] steps in all)
_HUGE_ARC = "M 40 100 A 60 60 0 0 1 100 4999999999 60 60 0 0 1 160 100"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/status")
def test_a_hairline_of_a_huge_arc_fits_in_a_bounded_address_space():
    # in a child process: the address-space limit would stay with this one
    code = f"""
import resource
from vecmsaa.geometry.hairline import hairline_path
from vecmsaa.svg.pathdata import parse_path_data
hairline_path(parse_path_data("M 0 0 L 10 10"), (1, 0, 0, 1, 0, 0))    # the kernels loaded
size = [ln for ln in open("/proc/self/status") if ln.startswith("VmSize")][0]
limit = int(size.split()[1]) * 1024 + (512 << 20)
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
verbs, points, rv, rp, owners = hairline_path(parse_path_data({_HUGE_ARC!r}),
                                              (0.24, 0, 0, 0.24, 0, 0))
print(len(verbs) > 0, len(rv) > 1)
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.split() == ["True", "True"]
