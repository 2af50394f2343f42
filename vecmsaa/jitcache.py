"""Keep numba's on-disk kernel cache consistent with the sources, one source file at a time.

numba invalidates a cached kernel only when *its own* file changes; a kernel that calls one
from another module (render_msaa → shade_span), or reads another module's constants (the path
verbs), keeps stale machine code after that module is edited. So every kernel file is stamped
with a hash of its own source and of every package module it imports, directly or through
others, and when that hash changes the file's cache entries (``__pycache__/<stem>.*.nbi`` and
``.nbc``) are dropped — only those: an upgrade or an edit recompiles what it can affect, not
every kernel. The stamps live in one manifest beside the cache; a manifest of file sizes and
modification times makes the usual case (nothing changed) cost one ``stat`` per source file.
"""
from __future__ import annotations

import marshal
import os
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
#: the stamps and the sources' sizes and times, in marshal's format: every process reads it,
#: and json's import took 2 ms
MANIFEST = "kernels.stamps"


def _module_name(path: Path, package: Path) -> str:
    rel = path.relative_to(package.parent).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


#: import statements, at any indentation (lazy imports count too); a regular expression rather
#: than the ast module, which took seconds for the package. Text that only looks like an import
#: (in a docstring) can only make a stamp cover more than it must.
_FROM = re.compile(r"^[ \t]*from[ \t]+(\.*)([\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n#]*)", re.M)
_IMPORT = re.compile(r"^[ \t]*import[ \t]+([\w., \t]+)", re.M)


def _imports(path: Path, package: Path, source: str) -> set[str]:
    """Names of the modules ``path`` imports, absolute (``from m import x`` also gives m.x,
    in case x is a submodule)."""
    own = _module_name(path, package)
    parent = own if path.name == "__init__.py" else own.rpartition(".")[0]
    found = set()
    for m in _IMPORT.finditer(source):
        found.update(n.split()[0] for n in m.group(1).split(",") if n.strip())
    for dots, mod, names in _FROM.findall(source):
        if dots:
            base = parent
            for _ in range(len(dots) - 1):
                base = base.rpartition(".")[0]
            mod = f"{base}.{mod}" if mod else base
        found.add(mod)
        found.update(f"{mod}.{n.split()[0]}" for n in names.strip("()").split(",") if n.strip())
    return found


def kernel_stamps(package: Path = PACKAGE) -> dict[str, str]:
    """Source file (relative path) → hash of it and of every package module it imports
    (transitively), for each file that defines numba kernels."""
    import hashlib      # here: only after an edit (OpenSSL's library is 3.4 MB, 4 ms to load)
    files = {_module_name(p, package): p for p in package.rglob("*.py")}
    sources = {name: p.read_text(encoding="utf-8") for name, p in files.items()}
    graph = {name: {m for m in _imports(files[name], package, src) if m in files}
             for name, src in sources.items()}
    stamps = {}
    for name, src in sources.items():
        if "njit" not in src:
            continue
        seen, todo = {name}, [name]
        while todo:
            for dep in graph[todo.pop()] - seen:
                seen.add(dep)
                todo.append(dep)
        h = hashlib.sha256()
        for dep in sorted(seen):
            h.update(dep.encode() + b"\0" + sources[dep].encode() + b"\0")
        stamps[files[name].relative_to(package).as_posix()] = h.hexdigest()
    return stamps


def _file_times(package: Path) -> dict[str, list[int]]:
    """Relative path → [size, modification time] of every ``.py`` file under ``package``:
    every process asks, so os.scandir (0.7 ms for the package's 93 files, where
    Path.rglob and Path.stat took 3.4 ms)."""
    times = {}
    folders = [("", os.fspath(package))]
    while folders:
        rel, folder = folders.pop()
        with os.scandir(folder) as entries:
            for e in entries:
                if e.is_dir() and e.name != "__pycache__":
                    folders.append((f"{rel}{e.name}/", e.path))
                elif e.name.endswith(".py") and e.is_file():
                    st = e.stat()
                    times[rel + e.name] = [st.st_size, st.st_mtime_ns]
    return times


def drop_entries(source: Path) -> None:
    """Remove numba's cache entries of the kernels defined in ``source``."""
    cache = source.parent / "__pycache__"
    for pattern in (f"{source.stem}.*.nbi", f"{source.stem}.*.nbc"):
        for f in cache.glob(pattern):
            f.unlink(missing_ok=True)


_stamps: dict[str, str] | None = None


def ensure_fresh_cache(package: Path = PACKAGE) -> dict[str, str]:
    """Drop the cache entries that sources changed since; return the current stamps (the
    compiled kernels' module is named after them, see aot.py). Once per process."""
    global _stamps
    if _stamps is not None and package == PACKAGE:
        return _stamps
    manifest = package / "__pycache__" / MANIFEST
    try:
        times = _file_times(package)
        try:
            old = marshal.loads(manifest.read_bytes())
            if not isinstance(old, dict):
                old = {}
        except (OSError, ValueError, EOFError, TypeError):
            old = {}
        if old.get("times") == times and "stamps" in old:
            stamps = old["stamps"]
        else:
            stamps = kernel_stamps(package)
            old_stamps = old.get("stamps", {})
            for rel, digest in stamps.items():
                if old_stamps.get(rel) != digest:
                    drop_entries(package / rel)
            try:
                manifest.parent.mkdir(exist_ok=True)
                tmp = manifest.with_suffix(f".{os.getpid()}.tmp")
                tmp.write_bytes(marshal.dumps({"times": times, "stamps": stamps}, 4))
                os.replace(tmp, manifest)
            except OSError:
                pass  # read-only install: numba keeps its cache elsewhere, nothing stale to drop
    except OSError:
        stamps = kernel_stamps(package)
    if package == PACKAGE:
        _stamps = stamps
    return stamps
