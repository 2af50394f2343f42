"""PNG output: deterministic bytes, written whole or not at all."""
from __future__ import annotations

import errno
import os
import stat
import struct
import sys

import numpy as np


#: zlib level of the IDAT stream
COMPRESS_LEVEL = 6
#: filtered bytes per independently compressed piece of the IDAT stream
PIECE_BYTES = 1 << 20


def encode_png(rgba: np.ndarray) -> bytes:
    """Straight RGBA uint8 (H, W, 4) → PNG bytes. Fixed settings and no metadata, so the same
    pixels always give the same bytes.

    Every row uses the Sub filter (each byte minus the one a pixel to its left: one numpy
    subtraction, where a per-row filter choice costs Pillow most of its encoding time), and
    the zlib stream is deflated in pieces of whole rows on all cores, each piece ending in a
    full flush so that their concatenation is one valid stream (pigz does the same). The pieces
    depend only on the image, so the bytes do not depend on the number of cores."""
    import zlib

    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    h, w = rgba.shape[:2]
    rows = rgba.reshape(h, w * 4)
    filtered = np.empty((h, w * 4 + 1), dtype=np.uint8)
    filtered[:, 0] = 1   # filter type: Sub
    filtered[:, 1:5] = rows[:, :4]
    np.subtract(rows[:, 4:], rows[:, :-4], out=filtered[:, 5:])
    per_piece = max(1, PIECE_BYTES // filtered.shape[1])
    pieces = [filtered[i:i + per_piece] for i in range(0, h, per_piece)] or [filtered]

    def deflate(i):
        c = zlib.compressobj(COMPRESS_LEVEL, zlib.DEFLATED, -15)   # raw deflate
        data = c.compress(pieces[i])
        return data + c.flush(zlib.Z_FINISH if i == len(pieces) - 1 else zlib.Z_FULL_FLUSH)
    if len(pieces) > 1:
        from concurrent.futures import ThreadPoolExecutor   # zlib releases the GIL
        with ThreadPoolExecutor(min(len(pieces), os.cpu_count() or 1)) as pool:
            deflated = list(pool.map(deflate, range(len(pieces))))
    else:
        deflated = [deflate(0)]
    adler = zlib.adler32(filtered)
    # zlib header: deflate, 32 KiB window, default level (FCHECK makes it a multiple of 31)
    idat = b"\x78\x9c" + b"".join(deflated) + struct.pack(">I", adler)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)   # 8-bit RGBA, no interlace
    return b"".join((b"\x89PNG\r\n\x1a\n", _chunk(b"IHDR", ihdr), _chunk(b"IDAT", idat),
                     _chunk(b"IEND", b"")))


def _chunk(kind: bytes, data: bytes) -> bytes:
    import zlib
    crc = zlib.crc32(data, zlib.crc32(kind))
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)


#: temporary files are named ``.<target>.<pid>`` + this; one left by a killed process is
#: removed by the next write to the same target (see :func:`write_bytes_atomic`)
TEMP_SUFFIX = ".vecmsaa-tmp"


def write_bytes_atomic(data: bytes, path, make_folders: bool = False) -> None:
    """Write ``data`` to ``path`` whole or not at all; ``-`` is stdout.

    A regular file (or a new name) is written to a temporary file beside it and renamed into
    place, so a reader never sees half a file. A symbolic link is followed: its target is
    written, the link stays. Anything else that exists and is not a folder (a FIFO, a device
    such as ``/dev/null`` or ``/dev/stdout``) is written through, never replaced. A missing
    folder is an error (as for rsvg-convert) unless ``make_folders``. A process killed between
    write and rename leaves ``.<name>.<pid>.vecmsaa-tmp``; the next write to that name removes
    it once that process is gone."""
    if str(path) == "-":
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    path = os.path.realpath(os.fspath(path))   # a symlink's target, not the link
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "is a folder", path)
    if st is not None and not stat.S_ISREG(st.st_mode):
        with open(path, "wb") as f:   # FIFO, device: write through
            f.write(data)
        return
    folder, name = os.path.split(path)
    if make_folders:
        os.makedirs(folder, exist_ok=True)
    elif not os.path.isdir(folder):
        raise FileNotFoundError(errno.ENOENT, "no such folder", folder)
    _remove_stale_temps(folder, name)
    tmp = os.path.join(folder, f".{name}.{os.getpid()}{TEMP_SUFFIX}")
    # O_EXCL: never write through a file (or link) someone else put at that name; the mode
    # is the one a plain open() would give (0666 less the umask)
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _remove_stale_temps(folder: str, name: str) -> None:
    """Remove ``.<name>.<pid>.vecmsaa-tmp`` files whose process no longer exists."""
    prefix = f".{name}."
    try:
        entries = os.listdir(folder)
    except OSError:
        return
    for entry in entries:
        if not (entry.startswith(prefix) and entry.endswith(TEMP_SUFFIX)):
            continue
        pid = entry[len(prefix):-len(TEMP_SUFFIX)]
        if not pid.isdigit() or _process_exists(int(pid)):
            continue
        try:
            os.unlink(os.path.join(folder, entry))
        except OSError:
            pass


def _process_exists(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True


def write_png(rgba: np.ndarray, path, make_folders: bool = False) -> None:
    write_bytes_atomic(encode_png(rgba), path, make_folders)
