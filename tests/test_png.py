"""PNG encoder: decoded by independent readers (Pillow, zlib) to the pixels it was given."""
from __future__ import annotations

import io
import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from vecmsaa.output import png


def decode(data: bytes) -> np.ndarray:
    with Image.open(io.BytesIO(data)) as im:
        im.load()
        assert im.mode == "RGBA"
        return np.asarray(im)


@pytest.mark.parametrize("h, w", [(1, 1), (1, 7), (9, 1), (37, 53), (700, 400)])
def test_pillow_decodes_the_same_pixels(h, w):
    rgba = np.random.default_rng(h * 1000 + w).integers(0, 256, (h, w, 4), dtype=np.uint8)
    assert np.array_equal(decode(png.encode_png(rgba)), rgba)


def test_many_pieces_form_one_valid_zlib_stream(monkeypatch):
    # pieces of a few rows each: every full-flush boundary and the final block are exercised
    monkeypatch.setattr(png, "PIECE_BYTES", 3 * 41 * 4)
    rgba = np.zeros((50, 41, 4), dtype=np.uint8)
    rgba[10:30, 5:20] = (200, 30, 10, 255)
    rgba[::7, :, 3] = np.arange(41, dtype=np.uint8)
    data = png.encode_png(rgba)
    assert np.array_equal(decode(data), rgba)
    # the chunks are well formed: lengths and CRCs, IHDR first, IEND last
    pos, kinds = 8, []
    while pos < len(data):
        n, = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        crc, = struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])
        assert crc == zlib.crc32(body, zlib.crc32(kind))
        kinds.append(kind)
        if kind == b"IDAT":
            raw = zlib.decompress(body)   # checks the Adler-32 too
            assert len(raw) == 50 * (41 * 4 + 1)
        pos += 12 + n
    assert kinds == [b"IHDR", b"IDAT", b"IEND"]


def test_bytes_do_not_depend_on_the_number_of_cores(monkeypatch):
    rgba = np.random.default_rng(3).integers(0, 256, (300, 200, 4), dtype=np.uint8)
    monkeypatch.setattr(png, "PIECE_BYTES", 20 * 200 * 4)
    many = png.encode_png(rgba)
    monkeypatch.setattr(png.os, "cpu_count", lambda: 1)
    assert png.encode_png(rgba) == many


@pytest.mark.parametrize("seed", range(4))
def test_adler32_of_pieces_concatenated_equals_zlib_on_the_whole(seed):
    rng = np.random.default_rng(seed)
    data = rng.integers(0, 256, int(rng.integers(0, 300000)), dtype=np.uint8).tobytes()
    cuts = sorted(rng.integers(0, len(data) + 1, 5))
    parts = [data[a:b] for a, b in zip([0] + cuts, cuts + [len(data)])]
    adler = 1
    for part in parts:
        adler = png.adler32_concat(adler, zlib.adler32(part), len(part))
    assert adler == zlib.adler32(data)
