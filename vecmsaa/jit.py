"""numba's ``njit`` for every kernel module, with cached kernels loaded without numba's compiler.

Loading a kernel from numba's on-disk cache begins with ``target_context.refresh()``, which
imports and installs every typing and lowering registry numba has (linalg, random, typed
containers, jitclass… ≈ 0.2 s, and scipy where it is installed) although the cached machine code
needs none of them: it needs the runtime (NRT) initialised, and the C math symbols, which the
context installs when it is created. Every ``vecmsaa`` process that renders pays this once,
which is a third of the single-file start-up. So the cache is read after initialising the
runtime alone; a kernel that is not in the cache is compiled as usual, and numba's compiler
refreshes the registries itself before it compiles (``compiler.compile_extra``).

If numba's caching internals are not what this expects, nothing is changed.
"""
from __future__ import annotations

from numba import njit  # noqa: F401  (re-exported: kernel modules import njit from here)
from numba.core import caching

__all__ = ["njit", "REGISTRIES_DEFERRED"]


def _load_overload(self, sig, target_context):
    from numba.core.runtime import rtsys
    rtsys.initialize(target_context)
    with self._guard_against_spurious_io_errors():
        return self._load_overload(sig, target_context)


def _defer_registries() -> bool:
    cache = caching.Cache
    if not (hasattr(cache, "_load_overload") and hasattr(cache, "_guard_against_spurious_io_errors")):
        return False
    cache.load_overload = _load_overload
    return True


#: whether cached kernels load without numba's registries (False: numba's internals changed)
REGISTRIES_DEFERRED = _defer_registries()
