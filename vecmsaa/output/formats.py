"""Image formats other than PNG, through Pillow: WebP (lossless), JPEG (flattened onto a
background colour, JPEG has no alpha) and TIFF (deflate). PNG stays with :mod:`.png`, whose
bytes are fixed by the pixels alone."""
from __future__ import annotations

import io
import os

# numpy, Pillow and the PNG encoder are imported where used: the command line reads FORMATS
# to build its --help, and importing numpy for that tripled the time of 'vecmsaa --help'
# (1.2 s → 3.0 s measured on a loaded machine)

#: file name endings → format name (as ``--format`` takes it)
EXTENSIONS = {".png": "png", ".webp": "webp", ".jpg": "jpeg", ".jpeg": "jpeg", ".tif": "tiff",
              ".tiff": "tiff"}
FORMATS = ("png", "webp", "jpeg", "tiff")
#: the extension written for each format when the name is chosen for the user (--out-dir)
EXTENSION = {"png": ".png", "webp": ".webp", "jpeg": ".jpg", "tiff": ".tif"}
JPEG_QUALITY = 92


def format_of(path) -> str | None:
    """The format a file name asks for by its ending, or None when it names none."""
    return EXTENSIONS.get(os.path.splitext(os.fspath(path))[1].lower())


def flatten(rgba, background=(255, 255, 255)):
    """Straight RGBA uint8 → RGB uint8 composited over an opaque ``background`` (rounded)."""
    import numpy as np

    a = rgba[..., 3:4].astype(np.uint32)
    bg = np.asarray(background[:3], dtype=np.uint32)
    rgb = rgba[..., :3].astype(np.uint32) * a + bg * (255 - a)
    return ((rgb + 127) // 255).astype(np.uint8)


def encode(rgba, fmt: str = "png", background=(255, 255, 255)) -> bytes:
    """Straight RGBA uint8 (H, W, 4) → the bytes of ``fmt`` (one of FORMATS). ``background``
    (RGB 0–255) is what JPEG flattens transparency onto."""
    import numpy as np

    from .png import encode_png

    if fmt == "png":
        return encode_png(rgba)
    if fmt not in FORMATS:
        raise ValueError(f"unknown image format {fmt!r} (known: {', '.join(FORMATS)})")
    from PIL import Image   # only for the formats that need it

    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    buf = io.BytesIO()
    if fmt == "jpeg":
        Image.fromarray(flatten(rgba, background), "RGB").save(buf, "JPEG", quality=JPEG_QUALITY)
    elif fmt == "webp":
        Image.fromarray(rgba, "RGBA").save(buf, "WEBP", lossless=True, exact=True)
    else:
        Image.fromarray(rgba, "RGBA").save(buf, "TIFF", compression="tiff_adobe_deflate")
    return buf.getvalue()
