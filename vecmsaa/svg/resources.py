"""External resources: ``data:`` URLs and files, confined to allowed folders.

A document may reference files in its own folder (and below) and in ``resources_dir``; nothing
else is read: no network, no absolute paths elsewhere, no ``..`` escapes.
"""
from __future__ import annotations

import base64
import os
import re
import urllib.parse

from ..diagnostics import warn

MAX_RESOURCE_BYTES = 64 * 1024 * 1024


class Images:
    """Raster images decoded for a document and the SVG images inside it (svg.image): bytes →
    Pillow image, with the pixels decoded so far, and (bytes, reduction) → texels for the
    scene, with their pixels; SVG images parsed. Nested SVG images share their document's, so that their
    budgets (svg.image.MAX_DECODED_PIXELS, MAX_TEXEL_PIXELS) are the document's."""

    def __init__(self):
        self.decoded = {}
        self.decoded_pixels = 0
        self.texels = {}
        self.texel_pixels = 0
        self.documents = {}     # (bytes, fragment, nesting) → SVG image's SizedDocument or None


class Resources:
    def __init__(self, base_dir=None, resources_dir=None, images=None):
        self.roots = []
        for d in (base_dir, resources_dir):
            if d:
                real = os.path.realpath(os.fspath(d))
                if real not in self.roots:
                    self.roots.append(real)
        self.base_dir = os.path.realpath(os.fspath(base_dir)) if base_dir else None
        self.resources_dir = (os.path.realpath(os.fspath(resources_dir))
                              if resources_dir else None)
        self.images = images if images is not None else Images()

    def fetch(self, url):
        """(bytes, mime or None, folder of the file or None); None when not allowed/found."""
        url = (url or "").strip()
        if not url:
            return None
        if url[:5].lower() == "data:":
            got = decode_data_url(url)
            if got is None:
                warn("a data: URL that does not decode was skipped")
            return got
        real = self.locate(url)
        if real is None:
            return None
        if os.path.getsize(real) > MAX_RESOURCE_BYTES:
            warn(f"{_short(url)} refused: larger than {MAX_RESOURCE_BYTES >> 20} MiB")
            return None
        with open(real, "rb") as f:
            return f.read(), None, os.path.dirname(real)

    def locate(self, url):
        """The real path of the file a (non-data) URL names, when it exists in an allowed
        folder; None otherwise (with a warning why). Batches on a cluster send exactly these
        files along."""
        url = (url or "").strip()
        parsed = urllib.parse.urlsplit(url)
        if parsed.scheme and parsed.scheme.lower() != "file" and len(parsed.scheme) > 1:
            warn(f"{_short(url)} refused: network URLs are not fetched")
            return None   # http, https, ftp...: no network access
        path = urllib.parse.unquote(parsed.path if parsed.scheme else url.split("#")[0])
        candidates = []
        if os.path.isabs(path):
            candidates.append(path)
        else:
            for base in (self.base_dir, self.resources_dir):
                if base:
                    candidates.append(os.path.join(base, path))
        outside = False
        for cand in candidates:
            real = os.path.realpath(cand)
            if not any(real == r or real.startswith(r + os.sep) for r in self.roots):
                outside = True
                continue
            if os.path.isfile(real):
                return real
        if outside:
            warn(f"{_short(url)} refused: outside the document's folder and --resources-dir")
        else:
            warn(f"{_short(url)} not found")
        return None


def _short(url: str) -> str:
    """A URL as a message shows it: at most 80 characters."""
    return url if len(url) <= 80 else url[:77] + "..."


def decode_data_url(url):
    # the URL Standard's parser: a fragment (from the first "#") is no part of the body (Fetch's
    # data: URL processor serializes the URL without it; an SVG image's view, see image.py), so
    # an unescaped "#" in an SVG ("fill='#00f'") ends the body there, as in browsers and resvg
    header, sep, payload = url[5:].partition("#")[0].partition(",")
    if not sep:
        return None
    parts = [p.strip() for p in header.split(";")]
    mime = parts[0].lower() if parts and parts[0] else None
    # Fetch's data: URL processor: the body is percent-decoded first (base64 too: `%2B` is
    # `+`), then base64-decoded forgivingly (HTML's "forgiving-base64 decode": ASCII
    # whitespace removed, the padding optional)
    data = urllib.parse.unquote_to_bytes(payload)
    if any(p.lower() == "base64" for p in parts[1:]):
        text = b"".join(data.split())
        if len(text) % 4 == 0 and text.endswith(b"="):
            text = text[:-2] if text.endswith(b"==") else text[:-1]
        if len(text) % 4 == 1 or not _BASE64.fullmatch(text):
            return None
        data = base64.b64decode(text + b"=" * (-len(text) % 4))
    return data, mime, None


_BASE64 = re.compile(rb"[A-Za-z0-9+/]*")
