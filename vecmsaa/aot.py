"""The kernels compiled ahead of time into one extension module, loaded without numba.

Importing numba and loading its cached kernels is most of a short render's time: on a 2-core
AMD EPYC, ``import numba`` takes 0.34 s over numpy's 0.15 s and the six or seven cached kernels
a render loads ≈ 0.3 s more (bitcode parsing, symbol tables, the runtime's set-up), where a
whole 10-pixel render takes 0.87 s. So the kernels Python calls — the entries listed in
``kernels.manifest`` with the argument types they are called with — are compiled once by
numba's ahead-of-time compiler (``numba.pycc``) into one extension module, and every later
process imports that (≈ 1 ms) instead of numba.

The module is built on first use (in a child process, ``python -m vecmsaa.aot``, one line on
stderr), into ``__pycache__`` beside the package or the user's cache folder, under a name made
from everything its machine code depends on: the kernel sources and what they import
(jitcache's stamps), the manifest, numba, Python and the CPU. An edit to a kernel file makes a
new name, so a stale module is never loaded. Where it cannot be built (no C compiler, no
setuptools), or ``VECMSAA_JIT=1`` is set (kernel development: numba recompiles one file at a
time), kernels are numba's JIT functions as before, and a call whose argument types the
manifest lacks goes to numba's JIT too (see ``jit.Kernel``).
"""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
MANIFEST = PACKAGE / "kernels.manifest"
SUFFIX = sysconfig.get_config_var("EXT_SUFFIX") or ".so"


def _cpu() -> str:
    """What the machine code may use: the processor's model and features (Linux), or what
    the platform module knows."""
    try:
        with open("/proc/cpuinfo", "rb") as f:
            head = f.read(8192).split(b"\n\n")[0]
        return hashlib.sha256(b"".join(line for line in head.split(b"\n")
                                       if line.startswith((b"model name", b"flags", b"vendor_id",
                                                           b"cpu family", b"model\t")))).hexdigest()
    except OSError:
        import platform
        return f"{platform.machine()} {platform.processor()}"


def _numba_stamp() -> str:
    import importlib.util
    spec = importlib.util.find_spec("numba")
    if spec is None or not spec.origin:
        return "no numba"
    st = os.stat(spec.origin)
    return f"{spec.origin} {st.st_size} {st.st_mtime_ns}"


def key(stamps: dict[str, str]) -> str:
    h = hashlib.sha256()
    # the build itself (this file) and the keys jit.py computes are part of what is compiled
    for part in (json.dumps(stamps, sort_keys=True), MANIFEST.read_text(), _numba_stamp(),
                 sys.version, _cpu(), Path(__file__).read_text(),
                 (PACKAGE / "jit.py").read_text()):
        h.update(part.encode() + b"\0")
    return h.hexdigest()[:20]


def cache_dirs() -> list[Path]:
    """Where the module may live, first choice first: numba's cache folder when one is set
    (``NUMBA_CACHE_DIR``, e.g. a fresh one for a cold-start measurement), the package's
    ``__pycache__``, the user's cache folder."""
    dirs = []
    if os.environ.get("NUMBA_CACHE_DIR"):
        dirs.append(Path(os.environ["NUMBA_CACHE_DIR"]) / "vecmsaa")
    else:
        dirs.append(PACKAGE / "__pycache__")
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        dirs.append(Path(base) / "vecmsaa")
    return dirs


def module_name(k: str) -> str:
    return f"vecmsaa_kernels_{k}"


def find(k: str) -> Path | None:
    for d in cache_dirs():
        p = d / (module_name(k) + SUFFIX)
        if p.exists() and p.with_suffix(".json").exists():
            return p
    return None


def load(path: Path):
    """The extension module at ``path`` and its index: kernel → [(symbol, argument keys)]."""
    import importlib.machinery
    import importlib.util
    name = path.name[: -len(SUFFIX)]
    loader = importlib.machinery.ExtensionFileLoader(name, str(path))
    spec = importlib.util.spec_from_file_location(name, str(path), loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    with open(path.with_suffix(".json")) as f:
        index = json.load(f)
    return module, index


def _failure_marker(k: str) -> Path:
    return cache_dirs()[-1] / f"{module_name(k)}.failed"


def ensure(stamps: dict[str, str]):
    """The module for these sources: found, or built now in a child process; None where it
    cannot be built (the reason is kept beside the cache and said once on stderr)."""
    k = key(stamps)
    path = find(k)
    if path is not None:
        return load(path)
    if _failure_marker(k).exists():
        return None
    for d in cache_dirs():
        try:
            d.mkdir(parents=True, exist_ok=True)
            probe = d / f".probe.{os.getpid()}"
            probe.write_bytes(b"")
            probe.unlink()
        except OSError:
            continue
        path = d / (module_name(k) + SUFFIX)
        break
    else:
        return None
    import fcntl
    with open(path.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)       # one build; others wait for it and load it
        if not (path.exists() and path.with_suffix(".json").exists()):
            _announce()
            env = dict(os.environ, VECMSAA_JIT="1")
            run = subprocess.run([sys.executable, "-m", "vecmsaa.aot", str(path)], env=env,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if run.returncode != 0 or not path.exists():
                reason = (run.stdout.strip().splitlines() or
                          [f"the build process ended with status {run.returncode}"])[-1]
                if run.returncode > 0:      # the build failed (not killed): do not retry it
                    try:
                        marker = _failure_marker(k)
                        marker.parent.mkdir(parents=True, exist_ok=True)
                        marker.write_text(run.stdout)
                    except OSError:
                        pass
                print(f"vecmsaa: could not build the compiled kernels ({reason}); using numba's "
                      f"JIT", file=sys.stderr)
                return None
            if sys.stderr.isatty():
                print(f"vecmsaa: {run.stdout.strip().splitlines()[-1]}", file=sys.stderr)
            _remove_others(path)
    return load(path)


def _remove_others(path: Path) -> None:
    """Delete the modules of earlier sources beside the new one (a process that has one
    loaded keeps it: the file is only unlinked)."""
    for other in path.parent.glob("vecmsaa_kernels_*"):
        if not other.name.startswith(path.name[: -len(SUFFIX)]):
            try:
                other.unlink()
            except OSError:
                pass


#: first-run build of every kernel in the manifest: 102.6 s of CPU on a 2-core AMD EPYC at load
#: 4, 3 Dec 2026 (docs/bench.md, "Session 9: kernels compiled ahead of time")
BUILD_SECONDS = "100"


def _announce():
    if sys.stderr.isatty():
        print(f"vecmsaa: compiling the kernels once (about {BUILD_SECONDS} s of CPU); later runs "
              f"load them in a millisecond", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# the build (in a child process with VECMSAA_JIT=1: kernels are numba dispatchers there)

def manifest_entry(line: str):
    """(kernel name, dispatcher, signature) of one manifest line; None for a stale line (its
    kernel is gone, is no numba kernel any more, or takes another number of parameters):
    that kernel runs on numba's JIT."""
    import importlib

    from numba.core import types, typing
    name, args, ret = line.split("|")
    module, qualname = name.split(":")
    try:
        dispatcher = getattr(importlib.import_module(module), qualname)
    except (ImportError, AttributeError):
        return None
    py_func = getattr(dispatcher, "py_func", None)
    namespace = {**vars(types), "bool": types.boolean}
    argtypes = eval(f"({args},)" if args else "()", namespace)   # noqa: S307 (our own file)
    if py_func is None or len(argtypes) != py_func.__code__.co_argcount:
        return None
    return name, dispatcher, typing.signature(eval(ret, namespace), *argtypes)


def _entries():
    """manifest_entry of each line of the manifest that is not stale."""
    lines = [ln for ln in MANIFEST.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    return [e for e in map(manifest_entry, lines) if e is not None]


def _arg_key(ty):
    """The key jit.arg_key computes from a Python value of numba type ``ty`` (JSON form)."""
    from numba.core import types
    from numba.np.numpy_support import as_dtype
    if isinstance(ty, types.Array):
        return [as_dtype(ty.dtype).num, ty.ndim, ty.layout + ("" if ty.mutable else "r")]
    if isinstance(ty, types.BaseTuple):
        return ["T", *[_arg_key(t) for t in ty.types]]
    return str(ty)


def _memoise_unpickling():
    """Make each unpickled constant of a wrapper a once-per-process load.

    A wrapper returning an array unpickles the array's Python class on every call (numba's
    JIT memoises its unpickler in Python; the ahead-of-time module's C unpickler does not):
    6 µs of a 13 µs call on a short path's transform here. So each call site keeps what it
    unpickled in a module global (one reference held for the process) and loads that after
    the first call; the GIL is held where wrappers unpickle."""
    from llvmlite import ir
    from numba.core import cgutils, pythonapi

    original = pythonapi.PythonAPI.unserialize
    if getattr(original, "_vecmsaa_memoised", False):
        return

    def unserialize(self, structptr):
        module = self.builder.module
        name = f"{structptr.name}.unpickled"
        cache = module.globals.get(name)
        if cache is None:
            cache = ir.GlobalVariable(module, self.pyobj, name)
            cache.linkage = "internal"
            cache.initializer = ir.Constant(self.pyobj, None)
        cached = self.builder.load(cache)
        with self.builder.if_else(cgutils.is_null(self.builder, cached)) as (first, later):
            with first:
                obj = original(self, structptr)
                self.builder.store(obj, cache)
                with self.builder.if_then(cgutils.is_not_null(self.builder, obj)):
                    self.incref(obj)        # the global's reference
            with later:
                self.incref(cached)         # the caller's reference (it decrefs what it gets)
        return self.builder.load(cache)

    unserialize._vecmsaa_memoised = True
    pythonapi.PythonAPI.unserialize = unserialize


def build(path: Path) -> None:
    t0 = time.process_time()
    import numba.pycc.compiler as pycc_compiler
    from numba.pycc import CC

    entries = _entries()
    options = {d.py_func: d.targetoptions for _, d, _ in entries}
    compile_extra = pycc_compiler.compile_extra

    spent = {"entries": 0.0, "module": 0.0}

    def compile_entry(typingctx, targetctx, func, args, return_type, flags, locals, **kws):
        # pycc compiles every export with the same default flags: give each its own error
        # model, and release the GIL in every wrapper (bands run on threads; a kernel holds
        # no Python object)
        flags = flags.copy()
        flags.release_gil = True
        opts = options.get(func, {})
        if "error_model" in opts:
            flags.error_model = opts["error_model"]
        t = time.process_time()
        try:
            return compile_extra(typingctx, targetctx, func, args, return_type, flags, locals,
                                 **kws)
        finally:
            spent["entries"] += time.process_time() - t

    write_object = pycc_compiler.ModuleCompiler.write_native_object

    def timed_write_object(self, *args, **kws):
        t = time.process_time()
        try:
            return write_object(self, *args, **kws)
        finally:
            spent["module"] += time.process_time() - t

    pycc_compiler.compile_extra = compile_entry
    pycc_compiler.ModuleCompiler.write_native_object = timed_write_object
    _memoise_unpickling()
    name = path.name[: -len(SUFFIX)]
    cc = CC(name)
    cc.output_dir = str(path.parent)
    cc.output_file = path.name + f".{os.getpid()}.tmp"
    cc.target_cpu = "host"
    index: dict[str, list] = {}
    for i, (kernel, dispatcher, sig) in enumerate(entries):
        symbol = f"k{i}"
        cc.export(symbol, sig)(dispatcher.py_func)
        index.setdefault(kernel, []).append([symbol, [_arg_key(t) for t in sig.args]])
    cc.compile()
    tmp = path.parent / cc.output_file
    with open(path.with_suffix(f".json.{os.getpid()}.tmp"), "w") as f:
        json.dump(index, f)
    os.replace(path.with_suffix(f".json.{os.getpid()}.tmp"), path.with_suffix(".json"))
    os.replace(tmp, path)
    total = time.process_time() - t0
    print(f"built {len(entries)} kernels in {total:.1f} s CPU (typing, lowering and numba's "
          f"optimisation of the entries and their callees {spent['entries']:.1f} s, the "
          f"module's machine code {spent['module'] - spent['entries']:.1f} s, C runtime and "
          f"link {total - spent['module']:.1f} s): {path}")


if __name__ == "__main__":
    build(Path(sys.argv[1]))
