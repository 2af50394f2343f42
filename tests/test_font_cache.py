"""The font face cache (vecmsaa/fonts/facecache.py): what it gives equals what reading the fonts
gives, whatever happened to the fonts or to the cache file since it was written."""
from __future__ import annotations

import glob
import json
import os
import shutil
import subprocess
import sys
import warnings

import pytest

from vecmsaa.fonts import facecache
from vecmsaa.fonts.db import FontDatabase, read_face_infos
from vecmsaa.fonts.face import FontError, load_face
from vecmsaa.fonts.facecache import CACHE_ENV, FolderCache, covers
from vecmsaa.tools.suite import suite_from_environment

FIXTURES = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts"))
SUITE_FONTS = os.path.abspath(os.path.join(suite_from_environment(os.path.join(
    os.path.dirname(__file__), "..", "..", "shared", "resvg-suite")), "fonts"))
needs_suite = pytest.mark.skipif(not os.path.isdir(SUITE_FONTS),
                                 reason="../shared/resvg-suite/fonts not present")
FONT_FOLDERS = [f for f in (FIXTURES, SUITE_FONTS) if os.path.isdir(f)]


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    """A fresh cache folder, named through XDG_CACHE_HOME as a user's would be."""
    monkeypatch.delenv(CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    return tmp_path / "xdg" / "vecmsaa" / "fonts"


def font_files(folder):
    return sorted(glob.glob(os.path.join(folder, "*.[ot]t[fc]")))


def truth(folder):
    """Every face of a folder's font files, read from the files (no cache)."""
    return [info for path in font_files(folder) for info in read_face_infos(path)]


def database(*folders):
    db = FontDatabase()
    for folder in folders:
        db.load_dir(folder)
    return db


def no_reading(monkeypatch):
    """Make reading a font's tables or cmap fail the test: what follows must come from the
    cache."""
    def fail(*args):
        raise AssertionError(f"read a font: {args}")
    monkeypatch.setattr("vecmsaa.fonts.db.read_face_infos", fail)
    monkeypatch.setattr("vecmsaa.fonts.db.read_coverage", fail)
    monkeypatch.setattr(facecache, "read_coverage", fail)


def cache_file(cache_dir):
    files = [f for f in os.listdir(cache_dir) if f.endswith(".json")]
    assert len(files) == 1, files
    return cache_dir / files[0]


def test_cached_faces_are_the_fonts_own(cache_dir, monkeypatch):
    # truth: fontTools reading each file afresh; a second database takes all from the cache
    folders = FONT_FOLDERS
    expected = [info for folder in folders for info in truth(folder)]
    assert database(*folders).faces == expected                  # cold: read and written
    assert len(os.listdir(cache_dir)) == len(folders)            # one cache per folder
    no_reading(monkeypatch)
    assert database(*folders).faces == expected                  # warm: nothing read


def test_cached_coverage_is_the_faces_cmap(cache_dir, monkeypatch):
    # truth: the characters Face.has_char answers from (the face's best Unicode cmap)
    def cmap_ranges(db):
        return {(f.path, f.index): db.coverage(f) for f in db.faces}

    db = database(*FONT_FOLDERS)
    for info in db.faces:
        bounds = db.coverage(info)
        try:
            cmap = load_face(info.path, info.index).cmap
        except FontError:
            continue
        have = {cp for a, b in zip(bounds[::2], bounds[1::2]) for cp in range(a, b)}
        assert have == set(cmap), info.path
        assert all(covers(bounds, cp) for cp in cmap)
        assert not any(covers(bounds, cp) for cp in range(0x3000) if cp not in cmap)
    cold = cmap_ranges(db)
    db.save_caches()
    no_reading(monkeypatch)
    assert cmap_ranges(database(*FONT_FOLDERS)) == cold


def test_changed_added_and_removed_files_are_read_again(cache_dir, tmp_path):
    folder = tmp_path / "fonts"
    folder.mkdir()
    shutil.copy(os.path.join(FIXTURES, "NotoSans-Subset.ttf"), folder / "a.ttf")
    shutil.copy(os.path.join(FIXTURES, "Collection.ttc"), folder / "b.ttc")
    assert database(folder).faces == truth(folder)
    # rewritten with another font, its modification time set back: size and change time differ
    stamp = os.stat(folder / "a.ttf")
    shutil.copy(os.path.join(FIXTURES, "RobotoFlex-Subset.ttf"), folder / "a.ttf")
    os.utime(folder / "a.ttf", ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    shutil.copy(os.path.join(FIXTURES, "NotoSans-Subset-CFF.otf"), folder / "c.otf")
    faces = database(folder).faces
    assert faces == truth(folder)
    assert [f.family for f in faces] == ["Roboto Flex", "Noto Sans", "Roboto Flex", "Noto Sans"]
    os.remove(folder / "b.ttc")
    faces = database(folder).faces
    assert faces == truth(folder) and len(faces) == 2
    files = json.loads(cache_file(cache_dir).read_text())["files"]
    assert sorted(files) == [str(folder / "a.ttf"), str(folder / "c.otf")]


def test_a_file_changed_after_its_coverage_was_cached(cache_dir, tmp_path):
    folder = tmp_path / "fonts"
    folder.mkdir()
    shutil.copy(os.path.join(FIXTURES, "RobotoFlex-Subset.ttf"), folder / "a.ttf")
    db = database(folder)
    assert db.fallback_for_char("z") is None                      # the subset has no 'z'
    shutil.copy(os.path.join(FIXTURES, "NotoSans-Subset.ttf"), folder / "a.ttf")
    db = database(folder)
    assert db.fallback_for_char("z") == db.faces[0]


def _edit(change, rename=True):
    """A cache file changed by ``change(doc)``, and unless ``rename`` is false every face's
    family renamed: a cache that must not be used would show in the faces it gave."""
    def edit(good):
        doc = json.loads(good)
        for entry in doc["files"].values():
            for record in entry[1]:
                record[1] = ["Wrong"] if rename else record[1]
        change(doc)
        return json.dumps(doc).encode()
    return edit


BAD_CACHES = {
    "garbage": lambda good: os.urandom(3000),
    "empty": lambda good: b"",
    "truncated": lambda good: good[: len(good) // 2],
    "not an object": lambda good: b"[1, 2, 3]",
    "foreign format": _edit(lambda doc: doc.update(format="vecmsaa font cache 0")),
    "foreign version": _edit(lambda doc: doc.update(version="x" + doc["version"])),
    "other folder": _edit(lambda doc: doc.update(folder="/elsewhere" + doc["folder"])),
    "bad entry": _edit(lambda doc: doc["files"].update(
        {k: [v[0], v[1][:1], v[2]] for k, v in doc["files"].items()})),
    "bad stamp": _edit(lambda doc: [v[0].__setitem__(0, 1.5) for v in doc["files"].values()]),
    "bad record": _edit(lambda doc: [v[1][-1].__setitem__(3, "bold")
                                     for v in doc["files"].values()]),
    "bad coverage": _edit(lambda doc: [v[2].__setitem__(0, "!!not base64")
                                       for v in doc["files"].values()], rename=False),
}


@pytest.mark.parametrize("kind", sorted(BAD_CACHES))
def test_a_broken_cache_is_ignored_and_rewritten(cache_dir, kind):
    db = database(FIXTURES)
    db.fallback_for_char("z", ["Roboto Flex"])          # coverage cached too
    path = cache_file(cache_dir)
    good = path.read_bytes()
    path.write_bytes(BAD_CACHES[kind](good))
    db = database(FIXTURES)
    assert db.faces == truth(FIXTURES)
    for info in db.faces:
        assert db.coverage(info) == facecache.read_coverage(info.path, info.index)
    db.save_caches()
    assert FolderCache(FIXTURES)._read() is not None      # whole and usable again


def test_a_cache_folder_that_cannot_be_written_means_no_cache(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    # under a file no folder can be made, whoever runs the tests (root ignores modes)
    monkeypatch.setenv(CACHE_ENV, str(blocker / "cache"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        db = database(FIXTURES)
        assert db.faces == truth(FIXTURES)
        assert db.fallback_for_char("z", ["Roboto Flex"]).family == "Noto Sans"
    # a folder that exists and refuses files
    folder = tmp_path / "read-only"
    folder.mkdir()
    monkeypatch.setenv(CACHE_ENV, str(folder))
    os.chmod(folder, 0o555)

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr("os.open", refuse)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert database(FIXTURES).faces == truth(FIXTURES)
    finally:
        os.chmod(folder, 0o755)
    assert os.listdir(folder) == []


def test_a_temporary_file_a_killed_writer_left_is_removed_by_the_next_write(cache_dir):
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    name = os.path.basename(FolderCache(FIXTURES).file)
    cache_dir.mkdir(parents=True)
    left = cache_dir / f".{name}.{done.stdout.strip()}.vecmsaa-tmp"     # its process is gone
    left.write_text("{half a cache")
    mine = cache_dir / f".{name}.{os.getppid()}.vecmsaa-tmp"             # still running
    mine.write_text("{being written")
    db = database(FIXTURES)
    db.save_caches()
    assert not left.exists() and mine.exists()
    assert FolderCache(FIXTURES)._read() is not None


def test_the_cache_can_be_turned_off(cache_dir, monkeypatch):
    monkeypatch.setenv(CACHE_ENV, "0")
    assert database(FIXTURES).faces == truth(FIXTURES)
    assert not cache_dir.exists()


def test_a_file_name_that_is_not_utf8(cache_dir, tmp_path, monkeypatch):
    folder = tmp_path / "fonts"
    folder.mkdir()
    name = os.fsdecode(b"caf\xe9.ttf")            # Latin-1 bytes: a surrogate escape in str
    shutil.copy(os.path.join(FIXTURES, "NotoSans-Subset.ttf"), os.path.join(folder, name))
    expected = truth(folder)
    assert len(expected) == 1 and database(folder).faces == expected
    no_reading(monkeypatch)
    assert database(folder).faces == expected


# -- fallback: the same face as loading every face and asking it (the rule before the cache) ----
def loaded_fallback(db, char, families=(), weight=400, style="normal", stretch=100.0,
                    exclude=()):
    """FontDatabase.fallback_for_char's rule, by loading each face and asking its cmap."""
    from vecmsaa.fonts.db import best_match

    def has(info):
        try:
            return info.load().has_char(char)
        except FontError:
            return False

    tried = set(exclude)
    for family in families:
        info = best_match(db.family_faces(family), weight, style, stretch)
        if info is not None and info not in tried:
            tried.add(info)
            if has(info):
                return info
    if exclude:
        style, weight, stretch = exclude[0].style, exclude[0].weight, exclude[0].stretch
    candidates = [f for f in db.faces if f not in tried and has(f)]
    alike = [f for f in candidates
             if f.style == style or f.weight == weight or f.stretch == stretch]
    return (alike or candidates or [None])[0]


CHARS = ("A", "z", "é", "ß", "Ω", "Ж", "ع", "ﻻ", "क", "ഴ", "日", "あ", "한", "\u0301", "\u00a0",
         "\u2003", "€", "∑", "→", "♪", "\U0001F600", "\U0001F44D", "\u2764", "\U0001CF50",
         "\ue000", "\U000E0001", "\U0010FFFD", "\x00", "\ufffd")


@needs_suite
@pytest.mark.parametrize("warm", [False, True])
def test_fallback_picks_the_face_loading_every_face_picks(cache_dir, warm):
    folders = [SUITE_FONTS, FIXTURES] + [f for f in ("/usr/share/fonts",) if os.path.isdir(f)]
    db = database(*folders)
    if warm:
        for info in db.faces:
            db.coverage(info)
        db.save_caches()
        db = database(*folders)
    asks = [dict(), dict(families=["Roboto Flex", "Noto Sans"]), dict(weight=700),
            dict(style="italic"), dict(stretch=75.0)]
    for name in ("Noto Sans", "Noto Serif", "Roboto Flex", "Amiri", "Yellowtail"):
        base = db.query([name], 700, "italic")
        if base is not None:
            asks.append(dict(exclude=(base,)))
            asks.append(dict(exclude=(base, db.query(["Noto Sans"]))))
    for ask in asks:
        for ch in CHARS:
            got = db.fallback_for_char(ch, **ask)
            assert got == loaded_fallback(db, ch, **ask), (ch, ask)


@needs_suite
def test_text_renders_the_same_through_a_warm_cache(cache_dir, monkeypatch):
    # the same document through a fresh database twice (cold, then from the cache) and with
    # the cache off: the same pixels
    import numpy as np

    from vecmsaa.api import render_svg_array
    from vecmsaa.fonts import db as dbmod

    svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="300" height="80">'
           '<text x="5" y="30" font-family="Noto Sans" font-size="20">Hé 日本 ع क ഴ 😀</text>'
           '<text x="5" y="60" font-family="Yellowtail" font-size="20" font-weight="bold">'
           'Ωß ♪ &#x1CF50;</text></svg>').encode()
    opts = dict(use_fonts_dir=SUITE_FONTS, skip_system_fonts=True)
    renders = []
    for env in ("cold", "warm", "0"):
        if env == "0":
            monkeypatch.setenv(CACHE_ENV, "0")
        dbmod._DB_CACHE.clear()
        renders.append(render_svg_array(svg, **opts))
    dbmod._DB_CACHE.clear()
    assert np.array_equal(renders[0], renders[1]) and np.array_equal(renders[0], renders[2])


# -- several processes at once ----------------------------------------------------------------
WRITER = """
import sys
from vecmsaa.fonts.db import FontDatabase
db = FontDatabase()
db.load_dir(sys.argv[1])
for ch in sys.argv[2]:
    db.fallback_for_char(ch)
"""


def test_processes_writing_at_once_leave_a_whole_cache(cache_dir, tmp_path):
    folder = tmp_path / "fonts"
    folder.mkdir()
    for i in range(8):
        for path in font_files(FIXTURES):
            shutil.copy(path, folder / f"{i}-{os.path.basename(path)}")
    expected = truth(folder)
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "xdg"))
    env.pop(CACHE_ENV, None)
    for round_ in range(3):
        shutil.rmtree(cache_dir, ignore_errors=True)
        procs = [subprocess.Popen([sys.executable, "-c", WRITER, str(folder), chars], env=env)
                 for chars in ("z", "zA", "A\U0001F600", "")]
        assert [p.wait(timeout=120) for p in procs] == [0] * 4
        files = FolderCache(str(folder))._read()
        assert files is not None, round_
        assert list(files) == font_files(folder)
        assert [i for p in font_files(folder) for i in files[p][1]] == expected
        for path, (stamp, infos, coverage) in files.items():
            for info, text in zip(infos, coverage):
                if text is not None:
                    assert facecache._decode_coverage(text) == facecache.read_coverage(
                        path, info.index)
        assert [f for f in os.listdir(cache_dir) if not f.endswith(".json")] == []
