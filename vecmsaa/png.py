"""PNG output: deterministic bytes, written whole or not at all."""
from __future__ import annotations

import errno
import io
import os
import sys
import tempfile

import numpy as np


#: zlib level: at 2048 px, 4 takes 6-17% less time than 6 for 0-7% larger files; 1-3 save
#: about a third of the time but grow the files by 20-85% (docs/bench.md, PNG output)
COMPRESS_LEVEL = 4


def encode_png(rgba: np.ndarray) -> bytes:
    """Straight RGBA uint8 (H, W, 4) → PNG bytes. Fixed settings and no metadata, so the same
    pixels always give the same bytes."""
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(rgba, dtype=np.uint8), "RGBA").save(
        buf, format="PNG", optimize=False, compress_level=COMPRESS_LEVEL)
    return buf.getvalue()


def write_bytes_atomic(data: bytes, path, make_folders: bool = False) -> None:
    """Write to a temporary file beside ``path`` and rename it into place; ``-`` is stdout.
    A missing folder is an error (as for rsvg-convert) unless ``make_folders``."""
    if str(path) == "-":
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if make_folders:
        os.makedirs(folder, exist_ok=True)
    elif not os.path.isdir(folder):
        raise FileNotFoundError(errno.ENOENT, "no such folder", folder)
    fd, tmp = tempfile.mkstemp(prefix=".vecmsaa-", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_png(rgba: np.ndarray, path, make_folders: bool = False) -> None:
    write_bytes_atomic(encode_png(rgba), path, make_folders)
