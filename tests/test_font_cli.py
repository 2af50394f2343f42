"""``vecmsaa font``: outputs checked against the font's own tables and FreeType's advances."""
from __future__ import annotations

import math
import os
import struct
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from vecmsaa.cli.main import main

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
TTF = os.path.join(FIXTURES, "NotoSans-Subset.ttf")
CFF = os.path.join(FIXTURES, "NotoSans-Subset-CFF.otf")
VAR = os.path.join(FIXTURES, "RobotoFlex-Subset.ttf")


def hhea(path):
    data = open(path, "rb").read()
    for i in range(struct.unpack(">H", data[4:6])[0]):
        rec = data[12 + 16 * i: 28 + 16 * i]
        if rec[:4] == b"hhea":
            off = struct.unpack(">I", rec[8:12])[0]
            return struct.unpack(">hh", data[off + 4:off + 8])
    raise KeyError


def upem(path):
    data = open(path, "rb").read()
    for i in range(struct.unpack(">H", data[4:6])[0]):
        rec = data[12 + 16 * i: 28 + 16 * i]
        if rec[:4] == b"head":
            off = struct.unpack(">I", rec[8:12])[0]
            return struct.unpack(">H", data[off + 18:off + 20])[0]
    raise KeyError


def run_font(tmp_path, *args):
    tmp_path.mkdir(parents=True, exist_ok=True)
    out = tmp_path / "out.png"
    code = main(["font", *map(str, args), "-o", str(out), "--mode", "analytic"])
    return code, out


@pytest.mark.parametrize("path", [TTF, CFF])
def test_one_line_is_tight_around_the_line_box(tmp_path, path):
    freetype = pytest.importorskip("freetype")
    size, margin, text = 32, 4, "Hamburg"
    code, out = run_font(tmp_path, path, "--text", text, "--size", size, "--margin", margin,
                         "--features", "kern=0")
    assert code == 0
    img = np.asarray(Image.open(out))
    face = freetype.Face(path)
    face.set_char_size(size * 64, 0, 72, 72)
    advance = 0.0
    for ch in text:
        face.load_char(ch, freetype.FT_LOAD_NO_HINTING)
        advance += face.glyph.linearHoriAdvance / 65536
    asc, desc = hhea(path)
    scale = size / upem(path)
    assert img.shape[1] == math.ceil(advance + 2 * margin)
    assert img.shape[0] == math.ceil((asc - desc) * scale + 2 * margin)
    # dark on light: opaque white corners, black ink
    assert tuple(img[0, 0]) == (255, 255, 255, 255)
    assert img[..., :3].min() < 10


def test_colours_and_transparent_background(tmp_path):
    code, out = run_font(tmp_path, TTF, "--text", "H", "--size", 40,
                         "--foreground", "#ff0000", "--background", "transparent")
    assert code == 0
    img = np.asarray(Image.open(out))
    assert img[0, 0, 3] == 0
    solid = img[img[..., 3] == 255]
    assert len(solid) and (solid[:, :3] == (255, 0, 0)).all()


def test_waterfall_has_a_row_per_size(tmp_path):
    code, out = run_font(tmp_path, TTF, "--waterfall", "10,20,40", "--text", "Hi")
    assert code == 0
    img = np.asarray(Image.open(out).convert("L"))
    ink_rows = (img < 128).any(axis=1)
    # three bands of ink separated by empty rows
    bands = np.count_nonzero(np.diff(ink_rows.astype(int)) == 1)
    assert bands >= 3


def test_glyph_pages(tmp_path):
    from vecmsaa.fonts import load_face

    n = load_face(TTF).num_glyphs
    pages = -(-n // 64)
    code, out = run_font(tmp_path, TTF, "--glyphs", "--per-page", 64, "--page", pages)
    assert code == 0 and out.exists()
    code, out2 = run_font(tmp_path / "x", TTF, "--glyphs", "--per-page", 64, "--page",
                          pages + 1)
    assert code == 1 and not out2.exists()


def test_specimen_and_variations(tmp_path):
    code, out = run_font(tmp_path, VAR, "--specimen", "--variations", "wght=900")
    assert code == 0 and out.exists()
    light = run_font(tmp_path / "l", VAR, "--text", "AHOe", "--size", 40,
                     "--variations", "wght=100")[1]
    heavy = run_font(tmp_path / "h", VAR, "--text", "AHOe", "--size", 40,
                     "--variations", "wght=1000")[1]
    ink = [(255 - np.asarray(Image.open(p).convert("L")).astype(int)).sum() for p in (light,
                                                                                       heavy)]
    assert ink[1] > 1.5 * ink[0]


def test_broken_font_one_error_line_no_output(tmp_path):
    bad = tmp_path / "bad.ttf"
    bad.write_bytes(b"OTTO" + b"\0" * 40)
    out = tmp_path / "out.png"
    proc = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "font", str(bad), "--text",
                           "x", "-o", str(out)], capture_output=True, text=True)
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "error" in lines[0]
    assert not out.exists()


def test_unsupported_option_values_fail_cleanly(tmp_path):
    for args in (["--variations", "wght"], ["--features", "toolong=1"],
                 ["--foreground", "notacolour"], ["--waterfall", "0,10"]):
        code, out = run_font(tmp_path, TTF, "--text", "x", *args)
        assert code == 2 and not out.exists(), args   # bad option values: usage errors
    out = tmp_path / "s.png"
    # 3 samples: no multisample pattern exists for it — a usage error, as for every command
    with pytest.raises(SystemExit) as exc:
        main(["font", TTF, "--text", "x", "--mode", "approx", "--samples", "3", "-o", str(out)])
    assert exc.value.code == 2
    assert not out.exists()


def test_pattern_and_filter_ask_for_samples(tmp_path):
    """--pattern/--filter draw the sheet with samples (the MSAA default mode) at those positions
    and weights: the same as the MSAA mode asked for with them, unlike the exact-area default."""
    outs = {}
    for name, flags in (("default", []), ("approx", ["--mode", "approx"]),
                        ("flags", ["--pattern", "quincunx", "--filter", "gaussian"]),
                        ("both", ["--mode", "approx", "--pattern", "quincunx",
                                  "--filter", "gaussian"])):
        out = tmp_path / f"{name}.png"
        assert main(["font", TTF, "--text", "Ag", "--size", "24", *flags, "-o", str(out)]) == 0
        outs[name] = np.asarray(Image.open(out))
    assert np.array_equal(outs["flags"], outs["both"])
    assert not np.array_equal(outs["flags"], outs["approx"])
    assert not np.array_equal(outs["flags"], outs["default"])
