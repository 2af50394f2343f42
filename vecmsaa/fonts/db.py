"""Font database: which face to use for a CSS font-family list, weight, style and stretch.

Faces come from font folders (``--use-fonts-dir``), single files, and unless
``--skip-system-fonts`` the usual fontconfig folders. Generic families (serif, sans-serif,
cursive, fantasy, monospace) map to configurable family names (resvg's option names). Matching
follows CSS Fonts 3 §5.2: the first family in the list that exists wins, then within it the
closest stretch, then style, then weight. Missing characters fall back to the list's other
families, then to any face that has them.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field

from .face import FontError, WIDTH_CLASS_PERCENT, load_face
from .facecache import FolderCache, covers, read_coverage

FONT_EXTENSIONS = (".ttf", ".otf", ".ttc", ".otc")
GENERIC_FAMILIES = ("serif", "sans-serif", "cursive", "fantasy", "monospace")
#: Preferred family per generic, first present wins; the head of each list is the mapping the
#: resvg test suite uses.
DEFAULT_GENERICS = {
    "serif": ["Noto Serif", "DejaVu Serif", "Liberation Serif", "Times New Roman"],
    "sans-serif": ["Noto Sans", "DejaVu Sans", "Liberation Sans", "Arial"],
    "cursive": ["Yellowtail", "Comic Sans MS", "DejaVu Sans"],
    "fantasy": ["Sedgwick Ave Display", "Impact", "DejaVu Sans"],
    "monospace": ["Noto Mono", "DejaVu Sans Mono", "Liberation Mono", "Courier New"],
}
SYSTEM_FONT_DIRS = ("/usr/share/fonts", "/usr/local/share/fonts", "~/.fonts",
                    "~/.local/share/fonts", "/Library/Fonts", "/System/Library/Fonts",
                    "C:\\Windows\\Fonts")


@dataclass(frozen=True)
class FaceInfo:
    """What matching needs to know about one face, read from its tables once."""
    path: str
    index: int
    families: tuple            # every family name it answers to, as in the font
    postscript_name: str
    weight: int
    style: str                 # normal | italic | oblique
    stretch: float             # percent, 100 = normal
    monospace: bool

    @property
    def family(self) -> str:
        return self.families[0] if self.families else ""

    def load(self):
        return load_face(self.path, self.index)


def read_face_infos(path) -> list:
    """FaceInfo for every face of a font file (unreadable files give an empty list)."""
    from fontTools.ttLib import TTFont

    from .face import face_count

    out = []
    try:
        count = face_count(path)
    except FontError:
        return out
    for index in range(count):
        try:
            font = TTFont(path, fontNumber=index, lazy=True)
            name = font["name"]
            families = _family_names(name)
            os2 = font["OS/2"] if "OS/2" in font else None
            sub = (name.getDebugName(17) or name.getDebugName(2) or "").lower()
            weight = int(os2.usWeightClass) if os2 is not None else (
                700 if "bold" in sub else 400)
            stretch = WIDTH_CLASS_PERCENT.get(os2.usWidthClass, 100.0) if os2 else 100.0
            italic = bool(font["head"].macStyle & 2) or "italic" in sub or bool(
                os2 is not None and os2.fsSelection & 1)
            oblique = "oblique" in sub or bool(os2 is not None and os2.fsSelection & 512)
            style = "italic" if italic else ("oblique" if oblique else "normal")
            mono = _fixed_pitch(font)
            out.append(FaceInfo(os.path.abspath(path), index, tuple(families),
                                name.getDebugName(6) or "", weight, style, stretch, mono))
            font.close()
        except Exception:
            continue   # a broken file in a font folder is skipped, as fontconfig does
    return out


def _fixed_pitch(font) -> bool:
    """The ``post`` table's isFixedPitch, read from its header's bytes (offset 12, uint32):
    fontTools decodes the whole table for it, every glyph's name included (a third of the
    time a folder of fonts took to read). A header shorter than its 32 bytes is an error,
    as fontTools makes it (the face is skipped)."""
    if "post" not in font:
        return False
    data = font.reader["post"]
    if len(data) < 32:
        raise ValueError("truncated post table")
    return int.from_bytes(data[12:16], "big") != 0


def _stretch_order(wanted: float, available):
    """CSS: exact, then narrower-first when wanted <= 100% else wider-first."""
    avail = sorted(set(available))
    if wanted in avail:
        return [wanted]
    narrower = sorted((s for s in avail if s < wanted), reverse=True)
    wider = sorted(s for s in avail if s > wanted)
    return narrower + wider if wanted <= 100 else wider + narrower


def _style_order(wanted: str):
    return {"italic": ["italic", "oblique", "normal"],
            "oblique": ["oblique", "italic", "normal"]}.get(wanted, ["normal", "oblique", "italic"])


def _weight_key(wanted: float):
    """Sort key giving CSS weight preference (smaller is better)."""
    def key(w):
        if w == wanted:
            return (0, 0)
        if 400 <= wanted <= 500:
            if wanted < w <= 500:
                return (1, w - wanted)
            if w < wanted:
                return (2, wanted - w)
            return (3, w - wanted)
        if wanted < 400:
            return (1, wanted - w) if w < wanted else (2, w - wanted)
        return (1, w - wanted) if w > wanted else (2, wanted - w)
    return key


def best_match(faces, weight=400, style="normal", stretch=100.0):
    """CSS Fonts 3 §5.2 step 4 among the faces of one family."""
    if not faces:
        return None
    stretches = _stretch_order(float(stretch), [f.stretch for f in faces])
    faces = [f for f in faces if f.stretch == stretches[0]]
    for s in _style_order(style):
        with_style = [f for f in faces if f.style == s]
        if with_style:
            faces = with_style
            break
    return min(faces, key=lambda f: _weight_key(float(weight))(f.weight))


@dataclass
class FontDatabase:
    faces: list = field(default_factory=list)
    generics: dict = field(default_factory=lambda: {k: list(v)
                                                      for k, v in DEFAULT_GENERICS.items()})
    default_family: str = "sans-serif"

    def __post_init__(self):
        self._by_family = None
        self._queries = {}
        self._seen = set()
        self._caches = {}           # font file path -> the FolderCache its faces came from
        self._coverage = {}         # (path, index) -> coverage of faces from single files

    # -- loading ---------------------------------------------------------------------------
    def load_file(self, path):
        self._add_file(os.path.abspath(os.fspath(path)), None)

    def _add_file(self, path, cache):
        """The faces of a font file (absolute path), through a folder's cache when given."""
        if path in self._seen:
            return
        self._seen.add(path)
        if cache is None:
            self.faces.extend(read_face_infos(path))
        else:
            self.faces.extend(cache.faces(path, read_face_infos))
            self._caches[path] = cache
        self._by_family = None
        self._queries = {}

    def load_dir(self, folder):
        """Every font file under a folder, in name order, its faces read through the folder's
        cache (vecmsaa/fonts/facecache.py)."""
        folder = os.path.expanduser(os.fspath(folder))
        cache = FolderCache(folder)
        for root, dirs, files in os.walk(folder):
            dirs.sort()
            for fn in sorted(files):
                if fn.lower().endswith(FONT_EXTENSIONS):
                    path = os.path.abspath(os.path.join(root, fn))
                    if path in self._seen:     # (listed through another folder: kept in this
                        cache.faces(path, read_face_infos)   # one's cache all the same)
                    self._add_file(path, cache)
        cache.save()

    def load_system_fonts(self):
        for folder in SYSTEM_FONT_DIRS:
            folder = os.path.expanduser(folder)
            if os.path.isdir(folder):
                self.load_dir(folder)

    def set_generic(self, generic: str, family: str):
        """Map a generic family to one family name (e.g. ``--serif-family``)."""
        self.generics[generic] = [family]
        self._queries = {}

    # -- queries ---------------------------------------------------------------------------
    def _index(self):
        if self._by_family is None:
            idx = {}
            for f in self.faces:
                for name in f.families:
                    idx.setdefault(name.lower(), []).append(f)
            self._by_family = idx
        return self._by_family

    def family_faces(self, family: str) -> list:
        """Faces of a family name; a generic name resolves through its mapping, unless it is
        quoted (then it is a family's name, CSS Fonts 4 §3.1)."""
        family = family.strip()
        if len(family) > 1 and family[0] == family[-1] and family[0] in "'\"":
            return self._index().get(family[1:-1].strip().lower(), [])
        key = family.lower()
        if key in GENERIC_FAMILIES:
            for name in self.generics.get(key, []):
                faces = self._index().get(name.lower())
                if faces:
                    return faces
            return []
        return self._index().get(key, [])

    def query(self, families, weight=400, style="normal", stretch=100.0):
        """The best FaceInfo for a CSS family list, or None when no family exists."""
        if isinstance(families, str):
            families = parse_family_list(families)
        # (answers are kept until faces or generics change: a document's texts ask the same
        # few questions, each a sort of a family's faces)
        key = (tuple(families), weight, style, stretch)
        if key in self._queries:
            return self._queries[key]
        found = None
        for family in families:
            found = best_match(self.family_faces(family), weight, style, stretch)
            if found is not None:
                break
        self._queries[key] = found
        return found

    def query_or_default(self, families, weight=400, style="normal", stretch=100.0):
        """Like :meth:`query`, falling back to the default family and then to any face."""
        match = self.query(families, weight, style, stretch)
        if match is None:
            match = self.query([self.default_family], weight, style, stretch)
        if match is None and self.faces:
            match = best_match(self.faces, weight, style, stretch)
        return match

    def fallback_for_char(self, char: str, families=(), weight=400, style="normal",
                          stretch=100.0, exclude=()):
        """A face that has ``char``: the list's families first (CSS Fonts 4 §5.2), then the
        first face in database order that shares its style, weight or stretch with the face
        the text asked for (``exclude[0]``, else the given ones), else any face that has it.
        That is fontdb's order as resvg's fallback walks it; which face covers a character
        no listed family has is the renderer's choice (CSS Fonts 4 §5.2 step 7)."""
        try:
            return self._fallback(ord(char), families, weight, style, stretch, exclude)
        finally:
            self.save_caches()        # the coverage read on the way, when any was

    def save_caches(self):
        """Write the folder caches that learnt something since they were written."""
        for cache in set(self._caches.values()):
            cache.save()

    def _fallback(self, cp, families, weight, style, stretch, exclude):
        tried = set(exclude)
        for family in families:
            info = best_match(self.family_faces(family), weight, style, stretch)
            if info is not None and info not in tried:
                tried.add(info)
                if self.has_char(info, cp):
                    return info
        base = exclude[0] if exclude else None
        if base is not None:
            style, weight, stretch = base.style, base.weight, base.stretch
        # the first face that has it and is alike, else the first that has it: faces are
        # loaded only when their coverage holds the character, alike ones first
        unlike = []
        for f in self.faces:
            if not covers(self.coverage(f), cp) or f in tried:
                continue
            if f.style == style or f.weight == weight or f.stretch == stretch:
                if self.has_char(f, cp):
                    return f
            else:
                unlike.append(f)
        return next((f for f in unlike if self.has_char(f, cp)), None)

    def coverage(self, info: FaceInfo) -> list:
        """The characters of a face's cmap as range boundaries (facecache.read_coverage),
        through its folder's cache."""
        cache = self._caches.get(info.path)
        if cache is not None:
            return cache.coverage(info)
        key = (info.path, info.index)
        bounds = self._coverage.get(key)
        if bounds is None:
            bounds = self._coverage[key] = read_coverage(info.path, info.index)
        return bounds

    def has_char(self, info: FaceInfo, cp: int) -> bool:
        """Whether a face draws a character: its coverage holds it and the face loads (the
        coverage spares loading faces that lack it)."""
        if not covers(self.coverage(info), cp):
            return False
        try:
            return info.load().has_char(cp)
        except FontError:
            return False


def _family_names(name) -> list:
    """The family names a face answers to: its typographic family (name ID 16) when it has
    one, else its family name (ID 1), in every language the table gives. OpenType: ID 16 is
    the family of the whole weight and width range; ID 1 is the legacy family of at most four
    styles (NotoSans-Black.ttf: 16 "Noto Sans", 1 "Noto Sans Blk"), which fontdb, and so resvg,
    does not match either: such faces are chosen by font-weight and font-stretch."""
    for nid in (16, 1):
        families = []
        for rec in name.names:
            if rec.nameID == nid:
                try:
                    s = rec.toUnicode()
                except UnicodeDecodeError:
                    continue
                if s and s not in families:
                    families.append(s)
        if families:
            return families
    return []


def parse_family_list(text: str) -> list:
    """CSS font-family value → list of names (quotes removed, whitespace collapsed). A quoted
    name that spells a generic family keeps its double quotes: it names a family, not the
    generic (CSS Fonts 4 §3.1: ``'serif'`` is a font called serif)."""
    out = []
    cur, quote, quoted = [], None, False

    def name():
        n = " ".join("".join(cur).split())
        return f'"{n}"' if quoted and n.lower() in GENERIC_FAMILIES else n

    for ch in text or "":
        if quote:
            if ch == quote:
                quote = None
            else:
                cur.append(ch)
        elif ch in "'\"":
            quote = ch
            quoted = True
        elif ch == ",":
            out.append(name())
            cur, quoted = [], False
        else:
            cur.append(ch)
    out.append(name())
    return [f for f in out if f]


_DB_CACHE = {}


def database_from_options(options: dict) -> FontDatabase:
    """A FontDatabase from a dict of the option names (``use_fonts_dir`` may be one folder or
    a list, ``serif_family`` etc. one family each); cached per distinct options."""
    def as_tuple(v):
        if not v:
            return ()
        return (v,) if isinstance(v, (str, bytes)) or hasattr(v, "__fspath__") else tuple(v)

    files = as_tuple(options.get("use_font_file"))
    dirs = as_tuple(options.get("use_fonts_dir"))
    skip = bool(options.get("skip_system_fonts"))
    generics = tuple((g, options.get(f"{g.replace('-', '_')}_family"))
                     for g in GENERIC_FAMILIES)
    family = options.get("font_family")
    key = (files, dirs, skip, generics, family)
    db = _DB_CACHE.get(key)
    if db is None:
        db = FontDatabase()
        for d in dirs:
            db.load_dir(d)
        for f in files:
            db.load_file(f)
        if not skip:
            db.load_system_fonts()
        for g, name in generics:
            if name:
                db.set_generic(g, name)
        if family:
            db.default_family = family
        _DB_CACHE[key] = db
    return db


def default_database() -> FontDatabase:
    """System fonts with default generic mappings."""
    return database_from_options({})
