"""On-disk cache of what the font database reads from each font file, as fontconfig keeps one.

Listing a folder of fonts reads the name, OS/2, head and post tables of every face (fontTools:
about half a millisecond a face, so 0.5-2 s for the 1000-3000 faces of a desktop); character
fallback reads each face's cmap (a few milliseconds a face). Both are kept here, one cache file
per font folder (``$XDG_CACHE_HOME/vecmsaa/fonts/<hash of the folder>.json``, else
``~/.cache/...``): a database is any set of folders (the system's, the suite's, both), and a
folder's file is shared by every set that holds it and rewritten only when that folder
changes.

Each font file's entry is keyed by its absolute path, size, modification and change times
(nanoseconds): a file whose stamp differs, or that is new, is read again, and one no longer in
the folder is dropped, so nothing stale is used. The whole cache is also tied to a version key
(this format, fontTools' version and the source of the modules that read the tables): a cache
another version wrote is ignored and rewritten.

JSON, so loading a cache file can run no code; one that is corrupt, truncated, foreign or
larger than :data:`MAX_CACHE_BYTES` is ignored (and rewritten). Writing is a temporary file in
the same folder renamed over the old one (write_bytes_atomic, as for images: one a killed
process left is removed by the next write): readers see the old or the new file whole, and of
processes writing at once the last rename wins (each file complete and true for the folder as
its writer saw it). A cache folder that cannot be created or written means no cache, silently.
``VECMSAA_FONT_CACHE=0`` turns the cache off; ``VECMSAA_FONT_CACHE=/some/folder`` puts it
there instead.
"""
from __future__ import annotations

import base64
import bisect
import json
import os
import sys
import zlib
from array import array

#: the environment variable: ``0`` for no cache, or an absolute folder to keep it in
CACHE_ENV = "VECMSAA_FONT_CACHE"
FORMAT = "vecmsaa font cache 1"
#: a cache file larger than this is not read (1261 faces with every coverage take 1.4 MB)
MAX_CACHE_BYTES = 64 << 20
_VERSION = None


def cache_folder():
    """The folder of the cache files, or None when the cache is off. The user's cache folder
    as for the compiled kernels (vecmsaa/aot.py): ``$XDG_CACHE_HOME``, else ``~/.cache``, with
    a ``vecmsaa/fonts`` folder in it; a relative XDG_CACHE_HOME is ignored (the XDG base
    directory specification: such a value is invalid)."""
    env = os.environ.get(CACHE_ENV, "")
    if env == "0":
        return None
    if os.path.isabs(env):
        return env
    base = os.environ.get("XDG_CACHE_HOME", "")
    if not os.path.isabs(base):
        base = os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "vecmsaa", "fonts")


def version_key() -> str:
    """What the cached records depend on: this format, fontTools (it parses the tables and the
    cmap) and the source of the modules that read them."""
    global _VERSION
    if _VERSION is None:
        import fontTools

        parts = [f"{FORMAT}\0{fontTools.version}".encode()]
        here = os.path.dirname(os.path.abspath(__file__))
        for name in ("db.py", "face.py", "facecache.py"):
            with open(os.path.join(here, name), "rb") as f:
                parts.append(f.read())
        _VERSION = _checksum(b"\0".join(parts))
    return _VERSION


def _checksum(data: bytes) -> str:
    """64 bits telling versions and folders apart (CRC-32 and Adler-32: hashlib's import alone
    costs a text render 10 ms and 4 MB; nothing here guards against a forger, who could as
    well write the cache)."""
    return f"{zlib.crc32(data):08x}{zlib.adler32(data):08x}"


def file_stamp(path):
    """(size, mtime_ns, ctime_ns) of a file, or None when it cannot be read. The change time
    catches a rewrite that kept size and modification time (``cp -p``, tar, touch -r)."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return [st.st_size, st.st_mtime_ns, st.st_ctime_ns]


# -- coverage: the characters a face maps, as sorted range boundaries ---------------------------
#: read_coverage's stand-in glyph order (one name for every glyph id a font can have)
_NO_NAMES = [""] * 65536


def read_coverage(path: str, index: int) -> list:
    """The characters of a face's best Unicode cmap (the one :class:`vecmsaa.fonts.face.Face`
    answers ``has_char`` from, read by the same fontTools call) as range boundaries
    ``[start0, end0, start1, end1, ...]``, each range ``start <= cp < end``. A file or cmap
    fontTools cannot read covers nothing (such a face answers no character either)."""
    from fontTools.ttLib import TTFont

    try:
        font = TTFont(path, fontNumber=index, lazy=True)
        # glyph names only label the cmap's values (its keys are the codes whose glyph id is
        # not 0): a stand-in glyph order spares reading them (the post table's, or the CFF
        # charset's: three quarters of the time), one name for all, found by index
        font.setGlyphOrder(_NO_NAMES)
        try:
            cps = sorted((font.getBestCmap() or {}).keys())
        finally:
            font.close()
            # the cmap's subtables point back at the font: without this reference cycle the
            # tables go now, rather than when the collector (paused during a render) runs
            font.tables.clear()
    except Exception:
        return []
    bounds = []
    for cp in cps:
        if bounds and bounds[-1] == cp:
            bounds[-1] = cp + 1
        else:
            bounds += [cp, cp + 1]
    return bounds


def covers(bounds, cp: int) -> bool:
    """Whether range boundaries from :func:`read_coverage` hold ``cp``."""
    return bisect.bisect_right(bounds, cp) & 1 == 1


def _encode_coverage(bounds) -> str:
    a = array("I", bounds)
    if sys.byteorder == "big":
        a.byteswap()
    return base64.b64encode(zlib.compress(a.tobytes())).decode("ascii")


def _decode_coverage(text: str) -> list:
    a = array("I")
    a.frombytes(zlib.decompress(base64.b64decode(text.encode("ascii"), validate=True)))
    if sys.byteorder == "big":
        a.byteswap()
    return a.tolist()      # (zlib's checksum has told a damaged one)


# -- one folder's cache -------------------------------------------------------------------------
class FolderCache:
    """The cached records of one font folder's files. ``faces(path, read)`` gives a file's
    FaceInfo list (from the cache when its stamp matches, else ``read(path)``, remembered);
    ``coverage(info)`` a face's coverage; ``save()`` writes what changed, keeping only the files
    asked for since it was opened."""

    def __init__(self, folder: str):
        self.folder = os.path.abspath(folder)
        root = cache_folder()
        self.file = None if root is None else os.path.join(
            root, _checksum(os.fsencode(self.folder)) + ".json")
        old = self._read() if self.file else None
        self._old = old or {}
        self._new = {}              # path -> [stamp, [FaceInfo, ...], [coverage or None, ...]]
        self._decoded = {}          # (path, index) -> bounds
        self.changed = self.file is not None and old is None

    def _read(self):
        """{path: entry} from the cache file, None when there is none that can be used."""
        try:
            with open(self.file, "rb") as f:
                if os.fstat(f.fileno()).st_size > MAX_CACHE_BYTES:
                    return None
                doc = json.loads(f.read())
            if not (isinstance(doc, dict) and doc.get("format") == FORMAT
                    and doc.get("version") == version_key() and doc.get("folder") == self.folder
                    and isinstance(doc.get("files"), dict)):
                return None
            files = {}
            for path, (stamp, records, coverage) in doc["files"].items():
                # (a stamp of any other shape matches no file's)
                if not (isinstance(coverage, list) and len(coverage) == len(records)
                        and all(c is None or isinstance(c, str) for c in coverage)):
                    return None
                files[path] = [stamp, [_face_info(path, r) for r in records], coverage]
            return files
        except Exception:   # missing, unreadable, corrupt, truncated or foreign: no cache
            return None

    def faces(self, path: str, read) -> list:
        """The FaceInfo records of the font file at ``path`` (absolute)."""
        stamp = file_stamp(path)
        entry = self._old.get(path)
        if entry is None or stamp is None or entry[0] != stamp:
            infos = read(path)
            if stamp is None or file_stamp(path) != stamp:   # changing as it was read
                return infos
            entry = [stamp, infos, [None] * len(infos)]
            self.changed = self.file is not None
        self._new[path] = entry
        return entry[1]

    def coverage(self, info):
        """The coverage boundaries of one face of a file this cache gave, read from its
        cmap the first time (and kept, when the file is still as it was listed)."""
        key = (info.path, info.index)
        bounds = self._decoded.get(key)
        if bounds is not None:
            return bounds
        entry = self._new.get(info.path)
        slot = entry[1].index(info) if entry is not None and info in entry[1] else None
        text = entry[2][slot] if slot is not None else None
        if text is not None:
            try:
                bounds = _decode_coverage(text)
            except Exception:
                bounds = None
        if bounds is None:
            bounds = read_coverage(info.path, info.index)
            if slot is not None and file_stamp(info.path) == entry[0]:
                entry[2][slot] = _encode_coverage(bounds)
                self.changed = self.file is not None
        self._decoded[key] = bounds
        return bounds

    def save(self):
        """Write the cache when it changed (the files asked for, no others); any failure
        leaves it unwritten."""
        if self.file is None or (not self.changed and self._new.keys() == self._old.keys()):
            return
        self._old = dict(self._new)
        self.changed = False
        doc = {"format": FORMAT, "version": version_key(), "folder": self.folder,
               "files": {p: [stamp, [_face_record(i) for i in infos], coverage]
                         for p, (stamp, infos, coverage) in self._new.items()}}
        # (ASCII: a file name that is not UTF-8 is kept as escaped surrogates)
        data = json.dumps(doc, separators=(",", ":")).encode("ascii")
        from ..files import write_bytes_atomic

        try:
            write_bytes_atomic(data, self.file, make_folders=True)
        except OSError:
            pass                   # a read-only or full cache folder: no cache


def _face_record(info) -> list:
    return [info.index, list(info.families), info.postscript_name, info.weight, info.style,
            info.stretch, info.monospace]


def _face_info(path, record):
    from .db import FaceInfo

    index, families, ps, weight, style, stretch, mono = record
    if not (type(index) is int and isinstance(families, list)
            and all(isinstance(f, str) for f in families) and isinstance(ps, str)
            and type(weight) is int and style in ("normal", "italic", "oblique")
            and type(stretch) is float and type(mono) is bool):
        raise ValueError("bad face record")
    return FaceInfo(path, index, tuple(families), ps, weight, style, stretch, mono)
