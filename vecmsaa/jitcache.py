"""Keep numba's on-disk kernel cache consistent with the sources.

numba invalidates a cached kernel only when *its own* file changes; a kernel that calls one
from another module (render_msaa → shade) keeps stale machine code after that module is
edited. The cache is therefore stamped with a hash of every kernel source file, and dropped
as a whole when the hash differs. Costs about a millisecond at import.
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
STAMP = PACKAGE / "__pycache__" / "kernels.stamp"


def kernel_sources():
    return sorted(p for p in PACKAGE.rglob("*.py") if "njit" in p.read_text(encoding="utf-8"))


def sources_hash() -> str:
    h = hashlib.sha256()
    for p in kernel_sources():
        h.update(p.relative_to(PACKAGE).as_posix().encode())
        h.update(p.read_bytes())
    return h.hexdigest()


def ensure_fresh_cache() -> None:
    try:
        digest = sources_hash()
        if STAMP.is_file() and STAMP.read_text() == digest:
            return
        for pattern in ("*.nbi", "*.nbc"):
            for f in PACKAGE.rglob(f"__pycache__/{pattern}"):
                f.unlink(missing_ok=True)
        STAMP.parent.mkdir(exist_ok=True)
        tmp = STAMP.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(digest)
        os.replace(tmp, STAMP)
    except OSError:
        pass  # read-only install: numba keeps its cache elsewhere, nothing stale to drop
