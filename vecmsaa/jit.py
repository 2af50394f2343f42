"""``njit`` for every kernel module: the kernel compiled ahead of time when there is one
(``vecmsaa/aot.py``; no numba in the process), numba's JIT function otherwise.

``AOT`` says which: with the compiled module, ``njit`` makes a :class:`Kernel` that calls the
module's entry for its arguments' types, and numba's JIT (imported then) for types the module
lacks. A kernel of the part built on first use (aot.LAZY_PART) loads that part, building
it if need be, on its first call. ``VECMSAA_JIT=1`` chooses numba's JIT for every kernel, as the module's own build does.

In JIT mode, loading a kernel from numba's on-disk cache begins with
``target_context.refresh()``, which imports and installs every typing and lowering registry
numba has (linalg, random, typed containers, jitclass… ≈ 0.2 s, and scipy where it is
installed) although the cached machine code needs none of them: it needs the runtime (NRT)
initialised, and the C math symbols, which the context installs when it is created. So the
cache is read after initialising the runtime alone; a kernel that is not in the cache is
compiled as usual, and numba's compiler refreshes the registries itself before it compiles
(``compiler.compile_extra``). If numba's caching internals are not what this expects, nothing
is changed.
"""
from __future__ import annotations

import os
import threading

__all__ = ["njit", "AOT", "REGISTRIES_DEFERRED"]


def _load_aot():
    if os.environ.get("VECMSAA_JIT", "") not in ("", "0"):
        return None
    from . import aot
    from .jitcache import ensure_fresh_cache
    try:
        return aot.ensure(ensure_fresh_cache())
    except (OSError, ValueError, ImportError):
        return None


_loaded = _load_aot()
#: whether kernels come from the compiled module (False: numba's JIT for all)
AOT = _loaded is not None
_module, _index = _loaded if AOT else (None, {})


def _keys():
    import numpy as np
    scalars = {bool: "bool", int: "int64", float: "float64", complex: "complex128",
               type(None): "none"}
    for t in (np.bool_, np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32,
              np.uint64, np.float32, np.float64, np.complex64, np.complex128):
        scalars[t] = np.dtype(t).name
    # numpy's flag bits → numba's layout, "r" for read-only; None when unaligned
    c, f, aligned, writeable = 0x1, 0x2, 0x100, 0x400
    layouts = [None] * (c | f | aligned | writeable) + [None]
    for bits in range(len(layouts)):
        if bits & aligned and not bits & ~(c | f | aligned | writeable):
            layouts[bits] = ("C" if bits & c else "F" if bits & f else "A") + \
                ("" if bits & writeable else "r")
    return scalars, np.ndarray, layouts, c | f | aligned | writeable


_SCALARS, _NDARRAY, _LAYOUTS, _FLAG_MASK = _keys() if AOT else ({}, None, [], 0)


def arg_key(value):
    """What numba's typeof would say of ``value``, as far as the compiled entries need it:
    arrays by dtype (its type number: byte order is not checked, the package makes only
    native arrays), dimensions, layout and write access (layout None when unaligned), tuples
    by their items; None for anything else (an object): such a call goes to numba's JIT."""
    return _call_key((value,))[0]


def _call_key(args, scalar=_SCALARS.get, ndarray=_NDARRAY, layouts=_LAYOUTS, mask=_FLAG_MASK):
    """arg_key of every argument, written out in one expression: this runs on every call
    (≈ 0.3 µs an array argument, where a function call per argument costs as much)."""
    return tuple([k if (k := scalar(type(a))) is not None else
                  (a.dtype.num, a.ndim, layouts[a.flags.num & mask]) if type(a) is ndarray else
                  ("T", *_call_key(a)) if type(a) is tuple else None for a in args])


def bind_last(kernel, last):
    """``lambda *args: kernel(*args, last)`` with ``last``'s part of the call key computed
    here, once: a raster's scratch buffers are a tuple of fifteen arrays, whose key took 5 µs
    of every fill (documents of many small layers make tens of thousands). ``last`` must keep
    its types (the arrays their dtypes, dimensions, layouts and write access)."""
    return bind_tail(kernel, (last,))


def bind_tail(kernel, tail: tuple):
    """``lambda *args: kernel(*args, *tail)`` with the tail's part of the call key computed
    here, once (as bind_last: a fill's sample positions, weights and flags are the render's,
    seven more arguments to key on every call). The tail must keep its types."""
    if not isinstance(kernel, Kernel):
        return lambda *args: kernel(*args, *tail)
    tail_key = _call_key(tail)
    nargs = kernel.nargs - len(tail)

    def call(*args):
        if len(args) == nargs:
            entry = kernel.entries.get(_call_key(args) + tail_key)
            if entry is not None:
                return entry(*args, *tail)
        return kernel(*args, *tail)
    return call


def _hashable(k):
    return tuple(_hashable(x) for x in k) if isinstance(k, list) else k


class Kernel:
    """A kernel of the compiled module: one entry per argument types in the manifest; other
    argument types (or keyword arguments) go to numba's JIT, compiled from the same function.

    The key is computed in Python: ≈ 3.4 µs of a 4.5 µs call with 7 arguments, where numba's
    dispatcher, which does the same in C, takes 2.1 µs in all (docs/bench.md, session 9)."""

    def __init__(self, func, options):
        self.py_func = func
        self.options = options
        self.__name__ = func.__name__
        self.__qualname__ = func.__qualname__
        self.__module__ = func.__module__
        self.__doc__ = func.__doc__
        self.__wrapped__ = func
        self.name = f"{func.__module__}:{func.__qualname__}"
        self.entries = _entries_of(self.name)
        # its entries are in the lazy part's module, which is loaded on the first call
        self.lazy = not self.entries and _is_lazy(self.name)
        self.nargs = func.__code__.co_argcount
        self._dispatcher = None

    def __call__(self, *args, **kws):
        if kws or len(args) != self.nargs:
            args = self._bind(args, kws)
        entry = self.entries.get(_call_key(args))
        if entry is None:
            return self._call_missing(args)
        return entry(*args)

    def _call_missing(self, args):
        """A call the entries lack: the lazy part is loaded (built if need be) on the first
        such call; other argument types go to numba's JIT."""
        if self.lazy:
            _load_lazy_part()       # another thread's call waits for it here
            self.entries = _entries_of(self.name)
            self.lazy = False
            entry = self.entries.get(_call_key(args))
            if entry is not None:
                return entry(*args)
        return self.dispatcher(*args)

    def _bind(self, args, kws):
        import inspect
        bound = inspect.signature(self.py_func).bind(*args, **kws)
        bound.apply_defaults()
        return bound.args

    @property
    def dispatcher(self):
        """numba's JIT function for this kernel (imports numba on first use)."""
        if self._dispatcher is None:
            from numba import njit as numba_njit
            _defer_registries()
            self._dispatcher = numba_njit(**self.options)(self.py_func)
        return self._dispatcher

    @property
    def _numba_type_(self):
        # numba's typeof for a Kernel named inside a JIT-compiled function: its dispatcher
        from numba.core import types
        return types.Dispatcher(self.dispatcher)

    def __repr__(self):
        return f"<vecmsaa kernel {self.__module__}.{self.__qualname__}>"


def _entries_of(name):
    return {tuple(_hashable(k) for k in keys): getattr(_module, symbol)
            for symbol, keys in _index.get(name, ())}


def _is_lazy(name):
    from . import aot
    return aot.part_of(name) == aot.LAZY_PART


_lazy_lock = threading.Lock() if AOT else None


def _load_lazy_part():
    """Add the lazy part's entries to the module's (once; bands call kernels on threads)."""
    from . import aot
    with _lazy_lock:
        if any(aot.part_of(name) == aot.LAZY_PART for name in _index):
            return
        try:
            loaded = aot.ensure_lazy()
        except (OSError, ValueError, ImportError):
            loaded = None
        if loaded is not None:
            module, index = loaded
            vars(_module).update(vars(module))
            for name, entries in index.items():
                _index.setdefault(name, []).extend(entries)


def _aot_njit(*args, **options):
    if args and callable(args[0]):
        return Kernel(args[0], options)
    return lambda func: Kernel(func, options)


def _load_overload(self, sig, target_context):
    from numba.core.runtime import rtsys
    rtsys.initialize(target_context)
    with self._guard_against_spurious_io_errors():
        return self._load_overload(sig, target_context)


def _defer_registries() -> bool:
    from numba.core import caching
    cache = caching.Cache
    if not (hasattr(cache, "_load_overload") and hasattr(cache, "_guard_against_spurious_io_errors")):
        return False
    cache.load_overload = _load_overload
    return True


if AOT:
    njit = _aot_njit
    #: whether cached kernels load without numba's registries (False: numba's internals changed)
    REGISTRIES_DEFERRED = True
else:
    from numba import njit  # noqa: F401  (re-exported: kernel modules import njit from here)
    REGISTRIES_DEFERRED = _defer_registries()
