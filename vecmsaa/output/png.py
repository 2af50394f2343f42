"""PNG output: deterministic bytes, written whole or not at all (files.write_bytes_atomic)."""
from __future__ import annotations

import os
import struct
import threading
import zlib

import numpy as np
from isal import isal_zlib

from ..files import write_bytes_atomic


#: deflate level of the IDAT stream, with ISA-L's deflate (python-isal: 1 ms to import). The
#: tiger's 268 MB of filtered rows at 8192 px: ISA-L level 1 in 0.12 s for 3.65 MB, where zlib
#: level 3 took 1.22 s for 4.09 MB and level 1 0.99 s for 4.19 MB (city-3: 0.14 s, 1.61 MB
#: against 1.41 s, 2.14 MB); ISA-L's level 3 is slower than zlib's
COMPRESS_LEVEL = 1
#: filtered bytes per independently compressed piece of the IDAT stream
PIECE_BYTES = 1 << 20


def encode_png(rgba: np.ndarray) -> bytes:
    """Straight RGBA uint8 (H, W, 4) → PNG bytes. Fixed settings and no metadata, so the same
    pixels always give the same bytes (see PngStream)."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    stream = PngStream(rgba.shape[1], rgba.shape[0])
    stream.write_rows(0, rgba, threads=os.cpu_count() or 1)
    return stream.finish()


class PngStream:
    """A PNG encoded as its rows arrive, in any order and from several threads, without the
    whole image: ``write_rows(y0, rows)`` for every row once, then ``finish()`` → bytes.

    Every row uses the Sub filter (each byte minus the one a pixel to its left: one numpy
    subtraction, where a per-row filter choice costs Pillow most of its encoding time), and
    the zlib stream is deflated in pieces of whole rows, each ending in a full flush so that
    their concatenation is one valid stream (pigz does the same); a piece is filtered and
    deflated by the thread that completes it. The pieces depend only on the image size, so
    the bytes do not depend on the order rows arrive in or on the number of threads."""

    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        self.per_piece = max(1, PIECE_BYTES // (width * 4 + 1))
        self.count = max(1, -(-height // self.per_piece))
        self.pending = {}     # piece → (its rows so far, rows still missing)
        self.done = [None] * self.count
        self.lock = threading.Lock()

    def write_rows(self, y0: int, rows: np.ndarray, threads: int = 1) -> None:
        """Rows y0 .. y0 + len(rows) - 1 (uint8 (n, W, 4)); the pieces they complete are
        deflated on up to ``threads`` threads (ISA-L releases the GIL)."""
        full = []
        y1 = y0 + rows.shape[0]
        with self.lock:
            for i in range(y0 // self.per_piece, -(-y1 // self.per_piece)):
                p0 = i * self.per_piece
                p1 = min(p0 + self.per_piece, self.height)
                a, b = max(p0, y0), min(p1, y1)
                if a == p0 and b == p1:
                    full.append((i, rows[a - y0:b - y0]))
                    continue
                part, missing = self.pending.get(i) or (
                    np.empty((p1 - p0, self.width, 4), dtype=np.uint8), p1 - p0)
                part[a - p0:b - p0] = rows[a - y0:b - y0]
                missing -= b - a
                if missing:
                    self.pending[i] = part, missing
                else:
                    self.pending.pop(i, None)
                    full.append((i, part))
        if len(full) > 1 and threads > 1:
            from concurrent.futures import ThreadPoolExecutor   # 20-60 ms: only when used
            with ThreadPoolExecutor(min(len(full), threads)) as pool:
                list(pool.map(lambda job: self._deflate(*job), full))
        else:
            for job in full:
                self._deflate(*job)

    def _deflate(self, i: int, rows: np.ndarray) -> None:
        rows = rows.reshape(rows.shape[0], self.width * 4)
        filtered = np.empty((rows.shape[0], self.width * 4 + 1), dtype=np.uint8)
        filtered[:, 0] = 1   # filter type: Sub
        filtered[:, 1:5] = rows[:, :4]
        np.subtract(rows[:, 4:], rows[:, :-4], out=filtered[:, 5:])
        c = isal_zlib.compressobj(COMPRESS_LEVEL, isal_zlib.DEFLATED, -15)   # raw deflate
        data = c.compress(filtered)
        data += c.flush(isal_zlib.Z_FINISH if i == self.count - 1 else isal_zlib.Z_FULL_FLUSH)
        self.done[i] = data, isal_zlib.adler32(filtered), filtered.size

    def finish(self) -> bytes:
        if self.height == 0:
            self._deflate(0, np.empty((0, self.width, 4), dtype=np.uint8))
        if self.pending or None in self.done:
            raise ValueError("PngStream.finish: rows are missing")
        adler = 1
        for _, piece_adler, size in self.done:
            adler = adler32_concat(adler, piece_adler, size)
        # zlib header: deflate, 32 KiB window, the fastest level (FCHECK: a multiple of 31)
        idat = b"\x78\x01" + b"".join(d[0] for d in self.done) + struct.pack(">I", adler)
        ihdr = struct.pack(">IIBBBBB", self.width, self.height, 8, 6, 0, 0, 0)   # RGBA8
        return b"".join((b"\x89PNG\r\n\x1a\n", _chunk(b"IHDR", ihdr),
                         _chunk(b"IDAT", idat), _chunk(b"IEND", b"")))


def adler32_concat(first: int, second: int, second_len: int) -> int:
    """Adler-32 of A + B from Adler-32(A), Adler-32(B) and len(B). With A's sums (a1, b1), B's
    bytes add sum(B) = a2 - 1 to a, and to b their own running sums, which B's b2 counts from
    a = 1 instead of a1: b = b1 + b2 + len(B)·(a1 - 1) (mod 65521)."""
    a1, b1 = first & 0xFFFF, first >> 16
    a2, b2 = second & 0xFFFF, second >> 16
    a = (a1 + a2 - 1) % 65521
    b = (b1 + b2 + second_len * (a1 - 1)) % 65521
    return (b << 16) | a


def _chunk(kind: bytes, data: bytes) -> bytes:
    crc = zlib.crc32(data, zlib.crc32(kind))
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)


def write_png(rgba: np.ndarray, path, make_folders: bool = False) -> None:
    write_bytes_atomic(encode_png(rgba), path, make_folders)
