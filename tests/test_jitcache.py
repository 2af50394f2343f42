"""Per-file invalidation of numba's kernel cache (vecmsaa/jitcache.py), on a small package of
real numba kernels in a temporary directory, run in fresh processes."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

from vecmsaa.jitcache import ensure_fresh_cache, kernel_stamps

CALLER = """
from numba import njit
from .callee import value

@njit(cache=True)
def answer():
    return value() + 1
"""
CALLEE = """
from numba import njit
from .consts import BASE

@njit(cache=True)
def value():
    return BASE
"""
OTHER = """
from numba import njit

@njit(cache=True)
def other():
    return 7
"""


def _package(tmp_path, base=40):
    pkg = tmp_path / "kpkg"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "caller.py").write_text(CALLER)
    (pkg / "callee.py").write_text(CALLEE)
    (pkg / "other.py").write_text(OTHER)
    _write(pkg / "consts.py", f"BASE = {base}\n")
    return pkg


def _write(path, text):
    """Write and move the modification time on, as an edit some time later would: seconds
    past the file's own (which an earlier _write put 2 s ahead), as Python's bytecode cache
    compares whole seconds and sizes ("BASE = 41" and "BASE = 50" are one size), and a fresh
    process that ran within a second of the first write read its stale .pyc."""
    before = path.stat().st_mtime_ns if path.exists() else 0
    path.write_text(text)
    later = max(time.time_ns(), before) + 2_000_000_000
    os.utime(path, ns=(later, later))


def _run(pkg):
    """Freshen the cache as vecmsaa's import does, then call the kernels in a new process."""
    code = textwrap.dedent(f"""
        import sys
        from pathlib import Path
        sys.path.insert(0, {str(pkg.parent)!r})
        from vecmsaa.jitcache import ensure_fresh_cache
        ensure_fresh_cache(Path({str(pkg)!r}))
        from kpkg.caller import answer
        from kpkg.other import other
        print(answer(), other())
    """)
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         check=True)
    return out.stdout.split()


def _entries(pkg, stem):
    return sorted(p.name for p in (pkg / "__pycache__").glob(f"{stem}.*.nb[ic]"))


def test_stamps_cover_what_a_kernel_file_imports(tmp_path):
    pkg = _package(tmp_path)
    before = kernel_stamps(pkg)
    assert set(before) == {"caller.py", "callee.py", "other.py"}   # consts.py has no kernel
    _write(pkg / "consts.py", "BASE = 41\n")
    after = kernel_stamps(pkg)
    # caller imports callee, which imports consts: both change; other imports neither
    assert after["caller.py"] != before["caller.py"]
    assert after["callee.py"] != before["callee.py"]
    assert after["other.py"] == before["other.py"]


def test_a_change_drops_only_the_entries_it_can_affect_and_no_stale_code_runs(tmp_path):
    pkg = _package(tmp_path)
    assert _run(pkg) == ["41", "7"]
    caller, callee, other = (_entries(pkg, s) for s in ("caller", "callee", "other"))
    assert caller and callee and other
    other_bytes = {n: (pkg / "__pycache__" / n).read_bytes() for n in other}
    # a constant of the callee's module changes: numba itself would reuse caller's entry
    # (its own file is unchanged) and answer 41
    _write(pkg / "consts.py", "BASE = 50\n")
    ensure_fresh_cache(pkg)
    assert _entries(pkg, "caller") == [] and _entries(pkg, "callee") == []
    assert _entries(pkg, "other") == other
    assert _run(pkg) == ["51", "7"]
    # the untouched kernel's entries were kept as they were, not rewritten
    assert {n: (pkg / "__pycache__" / n).read_bytes() for n in other} == other_bytes


def test_nothing_is_dropped_when_nothing_changed(tmp_path):
    pkg = _package(tmp_path)
    _run(pkg)
    before = {s: _entries(pkg, s) for s in ("caller", "callee", "other")}
    ensure_fresh_cache(pkg)
    assert {s: _entries(pkg, s) for s in ("caller", "callee", "other")} == before

