"""The kernels compiled ahead of time into extension modules, loaded without numba.

Importing numba and loading its cached kernels is most of a short render's time: on a 2-core
AMD EPYC, ``import numba`` takes 0.34 s over numpy's 0.15 s and the six or seven cached kernels
a render loads ≈ 0.3 s more (bitcode parsing, symbol tables, the runtime's set-up), where a
whole 10-pixel render takes 0.87 s. So the kernels Python calls — the entries listed in
``kernels.manifest`` with the argument types they are called with — are compiled once by
numba's ahead-of-time compiler (``numba.pycc``) into one extension module, and every later
process imports that (≈ 1 ms) instead of numba.

The module is built on first use (in child processes, ``python -m vecmsaa.aot``, one line on
stderr), into ``__pycache__`` beside the package or the user's cache folder, under a name made
from everything its machine code depends on: the kernel sources and what they import
(jitcache's stamps), the manifest, numba, Python and the CPU. An edit to a kernel file makes a
new name, so a stale module is never loaded. Where it cannot be built (no C compiler, no
setuptools), or ``VECMSAA_JIT=1`` is set (kernel development: numba recompiles one file at a
time), kernels are numba's JIT functions as before, and a call whose argument types the
manifest lacks goes to numba's JIT too (see ``jit.Kernel``).

The build is in two parts (raster and input; geometry), compiled at once, each into a
module of its own: numba's compiler runs on one core, so ``python -m vecmsaa.aot`` imports
numba and the kernels once and forks a process per part (on two cores the first run waits
about half as long); the parts share three small kernels (scan.py's calls into
geometry/primitives.py, compiled in both) and pycc's C runtime, which gcc compiles once
for both. The kernels no default command calls (the CSAA mode's; some only tests call)
are a third part, built the first time one is called. A build spends its time in numba
(typing, lowering to LLVM IR: about two thirds) and in LLVM (one optimisation of each
module as a whole, and its machine code); ``build`` keeps numba from doing the work twice
(``_lean_callees``, ``_memoise_call_types``).
"""
from __future__ import annotations

import marshal
import os
import sys
import time
from importlib.machinery import EXTENSION_SUFFIXES
from pathlib import Path

# SHA-256 for the key every process computes: CPython's own where it has it, as hashlib
# falls back to; hashlib loads OpenSSL's library first (4 ms of CPU and 3.4 MB of a 16 px
# render's 38 MB)
try:
    from _sha2 import sha256            # CPython 3.12 on
except ImportError:
    try:
        from _sha256 import sha256      # CPython 3.10, 3.11
    except ImportError:
        from hashlib import sha256

PACKAGE = Path(__file__).resolve().parent
MANIFEST = PACKAGE / "kernels.manifest"
#: the ending of this Python's extension modules, sysconfig's EXT_SUFFIX (sysconfig and its
#: configuration data take 1.6 ms to import)
SUFFIX = EXTENSION_SUFFIXES[0]


def _cpu() -> str:
    """What the machine code may use: the processor's model and features (Linux), or what
    the platform module knows."""
    try:
        with open("/proc/cpuinfo", "rb") as f:
            head = f.read(8192).split(b"\n\n")[0]
        return sha256(b"".join(line for line in head.split(b"\n")
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
    h = sha256()
    # the build itself (this file) and the keys jit.py computes are part of what is compiled
    for part in (repr(sorted(stamps.items())), MANIFEST.read_text(), _numba_stamp(),
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


#: The build runs in parts, each a process of its own compiling at the same time (numba's
#: compiler is single-threaded and holds one lock; at most as many at once as there are
#: cores, build_parts), each making a module of its own. A kernel and the kernels it calls
#: should share a part, or the callee is compiled in each. Four parts of about the same CPU
#: (7 Dec 2026, load 7-10: the raster's about 29 s, the batch builder's 20, the strokers' and
#: dasher's 20, the hairlines' with path data, bounds and conics 21): on two cores the first
#: run waits about as long as for two halves, on four or more about half as long. (With two
#: parts, geometry had grown to 73 s of CPU against the raster's 29.) The first prefix list
#: a kernel's ``module:qualname`` starts with names its part; any other kernel is the
#: raster's, part 0. Kernels shared across parts: stroke_kernels' _grow helpers (hairlines),
#: primitives' _conic_weight (strokers), scan.py's calls into primitives.py (raster).
PARTS = (
    # kernels no default command calls, a part built on the first call of one of them,
    # alone: the CSAA mode's (``render``, ``font`` and ``demo`` draw nothing in it; about 10 s
    # of CPU) and the curve function only tests call
    (2, ("vecmsaa.raster.csaa:", "vecmsaa.geometry.primitives:_eval_implicit")),
    (4, ("vecmsaa.geometry.hairline_kernels:", "vecmsaa.scene.conics:",
         "vecmsaa.svg.pathdata:", "vecmsaa.scene.bounds:")),
    (3, ("vecmsaa.geometry.stroke_kernels:", "vecmsaa.geometry.arclength:")),
    # the batch builder, with the transforms and the turbulence filter
    (1, ("vecmsaa.geometry.", "vecmsaa.scene.transform:",
         "vecmsaa.raster.filter_effects:_turbulence_pixels")),
)
LAZY_PART = 2


def part_of(kernel: str) -> int:
    """The build part of a kernel (``module:qualname``)."""
    for part, prefixes in PARTS:
        if kernel.startswith(prefixes):
            return part
    return 0


def _manifest_lines() -> list[str]:
    return [ln for ln in MANIFEST.read_text().splitlines() if ln.strip() and not ln.startswith("#")]


def parts(lazy: bool = False) -> list[int]:
    """The parts the manifest has kernels in: those built at once, or (``lazy``) on first use."""
    every = {part_of(line.split("|")[0]) for line in _manifest_lines()}
    return sorted(p for p in every if (p == LAZY_PART) == lazy)


def module_name(k: str, part: int | None = None) -> str:
    return f"vecmsaa_kernels_{k}" if part is None else f"vecmsaa_kernels_{k}_{part}"


def _module_paths(folder: Path, k: str, which: list[int]) -> dict[int, Path]:
    """Part → where its module for key ``k`` lives in ``folder``."""
    return {p: folder / (module_name(k, p) + SUFFIX) for p in which}


#: the ending of a module's index (kernel → its entries), beside it, in marshal's format:
#: Python reads it without an import (json's, with its regular expressions compiled, took
#: 2 ms of every process's start)
INDEX = ".index"


def find(k: str, which: list[int] | None = None) -> list[Path] | None:
    """The modules for key ``k`` of the parts ``which`` (default: those built at once), in
    one of the cache folders; None if any is missing."""
    which = parts() if which is None else which
    for d in cache_dirs():
        paths = list(_module_paths(d, k, which).values())
        if all(p.exists() and p.with_suffix(INDEX).exists() for p in paths):
            return paths
    return None


def load(paths: list[Path]):
    """The parts' functions as one namespace, and their index: kernel → [(symbol, argument
    keys)] (symbols are unique across the parts)."""
    import importlib.machinery
    import importlib.util
    import types
    functions, index = {}, {}
    for path in paths:
        name = path.name[: -len(SUFFIX)]
        loader = importlib.machinery.ExtensionFileLoader(name, str(path))
        spec = importlib.util.spec_from_file_location(name, str(path), loader=loader)
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
        try:
            part_index = marshal.loads(path.with_suffix(INDEX).read_bytes())
        except EOFError as exc:     # cut short: a broken index, as a malformed one (ValueError)
            raise ValueError(f"{path.with_suffix(INDEX)}: {exc}") from exc
        for kernel, entries in part_index.items():
            index.setdefault(kernel, []).extend(entries)
            functions.update((symbol, getattr(module, symbol)) for symbol, _ in entries)
    return types.SimpleNamespace(**functions), index


def _failure_marker(k: str) -> Path:
    return cache_dirs()[-1] / f"{module_name(k)}.failed"


def _writable_cache_dir() -> Path | None:
    for d in cache_dirs():
        try:
            d.mkdir(parents=True, exist_ok=True)
            probe = d / f".probe.{os.getpid()}"
            probe.write_bytes(b"")
            probe.unlink()
            return d
        except OSError:
            continue
    return None


#: the key of this process's modules, once ensure has computed it (ensure_lazy builds for it)
_current: dict[str, str] = {}


def ensure(stamps: dict[str, str]):
    """The modules for these sources: found, or built now in child processes; None where
    they cannot be built (the reason is kept beside the cache and said once on stderr). The
    lazy part's module, even where it was built before, is loaded on the first call of one
    of its kernels (jit.Kernel): 0.5 ms and 0.3 MB a process that draws nothing with them."""
    k = _current["key"] = key(stamps)
    paths = _ensure_parts(k, parts(), _announce)
    if paths is None:
        return None
    return load(paths)


def ensure_lazy():
    """The lazy part's module for this process's key, built now if missing (as ``ensure``)."""
    k = _current.get("key")
    which = parts(lazy=True)
    if k is None or not which:
        return None
    paths = _ensure_parts(k, which, _announce_lazy)
    return None if paths is None else load(paths)


def _ensure_parts(k: str, which: list[int], announce) -> list[Path] | None:
    paths = find(k, which)
    if paths is not None:
        return paths
    if _failure_marker(k).exists():
        return None
    d = _writable_cache_dir()
    if d is None:
        return None
    builds = _module_paths(d, k, which)
    import fcntl
    with open(d / f"{module_name(k)}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)       # one build; others wait for it and load it
        if find(k, which) is None:
            announce()
            failure = _build_parts(builds)
            if failure is not None:
                status, output = failure
                reason = (output.strip().splitlines() or
                          [f"the build process ended with status {status}"])[-1]
                if status > 0:      # the build failed (not killed): do not retry it
                    try:
                        marker = _failure_marker(k)
                        marker.parent.mkdir(parents=True, exist_ok=True)
                        marker.write_text(output)
                    except OSError:
                        pass
                print(f"vecmsaa: could not build the compiled kernels ({reason}); using numba's "
                      f"JIT", file=sys.stderr)
                return None
            _remove_others(d, module_name(k))
    return list(builds.values())


def _build_parts(builds: dict[int, Path]):
    """Build every part (part → module path): one process (``python -m vecmsaa.aot``) that
    forks into the parts; None when all were built, else (exit status, output)."""
    # here, not at the top: every process imports this module, few build
    import resource
    import subprocess
    import tempfile
    env = dict(os.environ, VECMSAA_JIT="1")
    t0, cpu0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    with tempfile.TemporaryFile(mode="w+") as out:
        args = [str(x) for part, path in builds.items() for x in (path.resolve(), part)]
        # run in the folder holding this package: ``-m`` puts the working directory first on
        # sys.path, and a build started in another checkout's folder compiled that checkout's
        # kernels into this one's modules
        status = subprocess.run([sys.executable, "-m", "vecmsaa.aot", *args], env=env,
                                cwd=PACKAGE.parent, stdout=out, stderr=subprocess.STDOUT,
                                text=True).returncode
        if status != 0 or not all(path.exists() for path in builds.values()):
            out.seek(0)
            return status, out.read()
    if sys.stderr.isatty():
        cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime
        modules = f"{len(builds)} modules at once" if len(builds) > 1 else "1 module"
        print(f"vecmsaa: compiled the kernels in {time.perf_counter() - t0:.0f} s ({cpu:.0f} s "
              f"of CPU, {modules}): {next(iter(builds.values())).parent}", file=sys.stderr)
    return None


def _remove_others(folder: Path, name: str) -> None:
    """Delete the modules of earlier sources beside the new ones (a process that has one
    loaded keeps it: the file is only unlinked)."""
    for other in folder.glob("vecmsaa_kernels_*"):
        if not other.name.startswith(name):
            try:
                other.unlink()
            except OSError:
                pass


#: the build of the four parts (`python -m vecmsaa.aot`, the first run's wait): 54-57 s wall,
#: 93-98 s of CPU, the longest part 28 s, 7 Dec 2026 on a 2-core AMD EPYC at load 1-1.5
#: (docs/bench.md, "Session 34, the first run"); the lazy part alone: 12.6 s of CPU
BUILD_SECONDS = "a minute on two cores, half that on four; 95 s of CPU"
LAZY_BUILD_SECONDS = "13 s"


def _announce():
    if sys.stderr.isatty():
        print(f"vecmsaa: compiling the kernels once (about {BUILD_SECONDS}); later runs load "
              f"them in a millisecond", file=sys.stderr, flush=True)


def _announce_lazy():
    if sys.stderr.isatty():
        print(f"vecmsaa: compiling the CSAA mode's kernels once (about {LAZY_BUILD_SECONDS})",
              file=sys.stderr, flush=True)


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
    return [e for e in map(manifest_entry, _manifest_lines()) if e is not None]


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


def _lean_callees():
    """Compile the kernels the entries call as LLVM IR only: no optimisation, no machine code.

    The module's machine code is made from the entries' LLVM IR, which links in their callees'
    IR and is optimised once as a whole (LLVM's module pipeline simplifies each function
    before it inlines it, as it does for a C compiler's unoptimised output). What numba does
    for each callee besides would be thrown away: its function and module passes (each
    callee's module again with its own callees linked in, so a kernel k call levels down
    was optimised k times), its machine code for numba's JIT engine, and its on-disk cache,
    which saves that code. So in the build (``JITCodeLibrary``: the callees'; the module's
    own is an ``AOTCodeLibrary``) a callee's library is linked IR and never made into
    machine code; its entry point is a placeholder nothing in the build calls, and the
    dispatchers cache nothing (none is then loaded from numba's cache either: a cached callee
    has machine code but no IR to link). On the stroke kernels: 18.9 → 15.4 s of CPU.

    The machine code is about as fast as numba's JIT makes it, kernel by kernel, but not the
    same: LLVM's inliner, weighing the callees as it finds them, keeps some small ones as
    calls the JIT inlines (its callees arrive optimised by their own libraries). Same
    arguments, one process: build_batch 1.04–1.23 of the JIT's time (``_push_line`` and
    ``_push_edge`` stay calls), dash_segments 0.86–0.96, the blurs, render_msaa and the rest
    0.89–1.11 (noise), calls of a few µs 0.5–0.8 (pycc's wrapper costs less).
    Running the callees' function passes, or numba's whole pipeline, before linking gives
    build_batch back its 10–16 % and costs dash_segments 5–14 %, with no change a whole
    render shows (docs/bench.md, session 21): not done."""
    from numba.core import codegen, dispatcher
    dispatcher.Dispatcher.enable_caching = lambda self: None
    library = codegen.JITCodeLibrary

    def no_function_passes(self, ll_module):
        ll_module.data_layout = self._codegen._data_layout

    def ready_for_linking(self):
        self._finalize_dynamic_globals()
        self._verify_declare_only_symbols()
        self._finalized = True

    def placeholder_pointer(self, name):
        self._ensure_finalized()
        return 1

    library._optimize_functions = no_function_passes
    # nor the entries' own function passes: the module pipeline runs them all
    library._optimize_final_module = lambda self: None
    library._finalize_final_module = ready_for_linking
    library.get_pointer_to_function = placeholder_pointer
    # a dispatcher's environment is stored into its JIT machine code, which is never made
    codegen.JITCPUCodegen.set_env = lambda self, env_name, env: None


def _memoise_call_types():
    """Type each call of a numba function (an operator, ``min``, ``np.empty`` …) once per
    argument types, not once per call site.

    numba's typing tries the function's templates in order at every call site, building an
    error for each template that does not match (``BaseFunction.get_call_type``); a
    template's answer depends only on the argument types (the overloads' implementations
    are already cached by them), so the build keeps each answer it got. On the stroke
    kernels type inference took 2.9 → 1.2 s of CPU."""
    from numba.core.types import functions
    original = functions.BaseFunction.get_call_type
    answers = {}

    def get_call_type(self, context, args, kws):
        # by identity: the answer's implementation is recorded on this very function type
        key = (id(self), id(context), tuple(args), tuple(sorted(kws.items())))
        try:
            kept = answers.get(key)
        except TypeError:           # an unhashable argument type: not kept
            return original(self, context, args, kws)
        if kept is not None and kept[0] is self and kept[1] is context:
            return kept[2]
        sig = original(self, context, args, kws)
        if sig is not None:
            answers[key] = (self, context, sig)
        return sig

    functions.BaseFunction.get_call_type = get_call_type


def _prepare():
    """What every part's build needs, done once before the build forks into its parts:
    numba imported with its registries installed, the kernel modules imported, the build's
    changes to numba made (≈ 1.3 s of CPU a process); the manifest's entries and the
    timings (entries: their numba compiles; module: the whole LLVM object)."""
    import numba.pycc.compiler as pycc_compiler
    from numba.core.registry import cpu_target

    _lean_callees()
    _memoise_call_types()
    _memoise_unpickling()
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
    # installed by the first compile otherwise, in each part
    cpu_target.typing_context.refresh()
    cpu_target.target_context.refresh()
    return entries, spent


#: the name pycc's C runtime is compiled for (its init function's), the same in every part:
#: the runtime is compiled once for all of them
RUNTIME_NAME = "vecmsaa_kernels"


def _cc(name: str):
    """numba.pycc's compiler of a module ``name``, with the C runtime it links in made the
    same for every part (compiled once: ``_runtime``)."""
    from numba.pycc import CC

    class SharedRuntimeCC(CC):
        def _get_mixin_defines(self):
            return [(n, RUNTIME_NAME if n == "PYCC_MODULE_NAME" else v)
                    for n, v in super()._get_mixin_defines()]

    cc = SharedRuntimeCC(name)
    cc._init_function = f"pycc_init_{RUNTIME_NAME}"
    cc.target_cpu = "host"
    # the C runtime pycc links into the module: no typed containers' (no kernel uses numba's
    # typed dict, list or set: 1.2 s of gcc a part), no debug information, and gcc's -O1,
    # not Python's -O3 (1.7 → 1.0 s of gcc: it boxes arguments and allocates arrays, once a
    # call, not per pixel)
    if isinstance(getattr(cc, "_mixin_sources", None), list):
        cc._mixin_sources = [s for s in cc._mixin_sources
                             if not s.endswith(("dictobject.c", "listobject.c", "setobject.c"))]
    cc._extra_cflags = {"posix": ["-g0", "-O1"]}
    return cc


def _runtime(shared: Path) -> list[str]:
    """The object files of pycc's C runtime in ``shared``, compiled by the first caller
    (``python -m vecmsaa.aot --runtime``, started with the build, while numba is still being
    imported); a later caller waits for them."""
    import fcntl
    import json
    with open(shared / "runtime.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        done = shared / "runtime.json"
        if not done.exists():
            objects = _cc(RUNTIME_NAME)._compile_mixins(str(shared / "runtime"))
            done.write_text(json.dumps(objects))
        return json.loads(done.read_text())


def build(path: Path, part: int, entries, spent, shared: Path) -> None:
    """Build the module of one part at ``path``, linking in pycc's C runtime from
    ``shared``."""
    t0, cpu0 = time.perf_counter(), time.process_time()
    # (a part forked after this process built one starts from that part's timings)
    spent.update(entries=0.0, module=0.0)
    cc = _cc(path.name[: -len(SUFFIX)])
    cc.output_dir = str(path.parent)
    cc.output_file = path.name + f".{os.getpid()}.tmp"
    index: dict[str, list] = {}
    for i, (kernel, dispatcher, sig) in enumerate(entries):
        if part_of(kernel) != part:
            continue
        symbol = f"k{i}"                # unique across the parts
        cc.export(symbol, sig)(dispatcher.py_func)
        index.setdefault(kernel, []).append([symbol, [_arg_key(t) for t in sig.args]])
    # CC.compile, with the runtime's objects compiled once for all parts
    build_dir = shared / f"part{part}"
    build_dir.mkdir()
    objects, exports = cc._compile_object_files(str(build_dir))
    t1 = time.perf_counter()
    cc._toolchain.link_shared(str(path.parent / cc.output_file), objects + _runtime(shared),
                              cc._toolchain.get_python_libraries(),
                              cc._toolchain.get_python_library_dirs(),
                              export_symbols=exports, extra_ldflags=cc._get_extra_ldflags())
    tmp = path.parent / cc.output_file
    index_tmp = path.with_suffix(f"{INDEX}.{os.getpid()}.tmp")
    index_tmp.write_bytes(marshal.dumps(index, 4))
    os.replace(index_tmp, path.with_suffix(INDEX))
    os.replace(tmp, path)
    print(f"part {part}: {sum(map(len, index.values()))} kernels in "
          f"{time.process_time() - cpu0:.1f} s CPU (numba's typing and lowering of the entries "
          f"and their callees {spent['entries']:.1f} s, LLVM's optimisation and machine code "
          f"{spent['module'] - spent['entries']:.1f} s), link "
          f"{time.perf_counter() - t1:.1f} s wall, {time.perf_counter() - t0:.1f} s wall in "
          f"all: {path}", flush=True)


def build_parts(jobs: list[tuple[Path, int]]) -> int:
    """Build each (module path, part): the set-up once, then one process per part (forked,
    so each starts from it; this one builds the first), as many at once as there are cores
    (each takes about 300 MB). The exit status: 0 when every part was built."""
    import gc
    import shutil
    import signal
    import subprocess
    import tempfile
    import traceback
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        (os.cpu_count() or 1)
    shared = Path(tempfile.mkdtemp(prefix="vecmsaa-build-"))
    # gcc on the runtime, on the other core while this process imports numba
    runtime = subprocess.Popen([sys.executable, "-m", "vecmsaa.aot", "--runtime", str(shared)])
    statuses, thresholds = [], gc.get_threshold()
    try:
        t0 = time.process_time()
        entries, spent = _prepare()
        print(f"set-up {time.process_time() - t0:.1f} s CPU", flush=True)
        # Python's cyclic garbage collector: numba's compiler allocates so much that the
        # default thresholds run a collection every few milliseconds, each traversing numba's
        # registries and typing tables (the set-up's objects; frozen here, which also spares
        # their pages the copies a collection's writes would make in the forked parts). Part
        # 0's build, alternated: 17.1, 17.2 s of CPU as before, 16.1, 16.1 frozen, 14.8, 15.0
        # frozen and with these thresholds (peak memory 257 → 317 MB a part; with no
        # collection at all 13.9, 14.7 s and 425 MB)
        gc.freeze()
        gc.set_threshold(50000, 20, 100)
        running, waiting = [], list(jobs[1:])

        def start(path, part):
            pid = os.fork()
            if pid == 0:
                code = 1
                try:
                    build(path, part, entries, spent, shared)
                    code = 0
                except KeyboardInterrupt:
                    code = -signal.SIGINT
                except BaseException:
                    traceback.print_exc()
                finally:
                    sys.stdout.flush()
                    sys.stderr.flush()
                    if code < 0:        # ended by the signal, as an unforked process would
                        signal.signal(-code, signal.SIG_DFL)
                        os.kill(os.getpid(), -code)
                    os._exit(code)
            running.append(pid)

        def reap_one():
            # (the parts' own processes only: not the runtime's, which Popen waits for)
            while True:
                for pid in running:
                    done, status = os.waitpid(pid, os.WNOHANG)
                    if done:
                        running.remove(pid)
                        statuses.append(status)
                        return
                time.sleep(0.05)

        while waiting and len(running) < cores - 1:
            start(*waiting.pop(0))
        try:
            build(*jobs[0], entries, spent, shared)
        except Exception:
            traceback.print_exc()
            statuses.append(1 << 8)
        while waiting or running:
            if waiting and len(running) < cores:
                start(*waiting.pop(0))
            else:
                reap_one()
    finally:
        runtime.wait()
        shutil.rmtree(shared, ignore_errors=True)
        gc.set_threshold(*thresholds)       # as it was, for a caller in process (tests)
        gc.unfreeze()
    killed = [os.WTERMSIG(s) for s in statuses if os.WIFSIGNALED(s)]
    if killed:      # a part killed is no failure of the build (it is tried again)
        signal.signal(killed[0], signal.SIG_DFL)
        os.kill(os.getpid(), killed[0])
    return 0 if not any(statuses) else 1


if __name__ == "__main__" and sys.argv[1:2] == ["--runtime"]:
    _runtime(Path(sys.argv[2]))
elif __name__ == "__main__":
    sys.exit(build_parts([(Path(sys.argv[i]), int(sys.argv[i + 1]))
                          for i in range(1, len(sys.argv), 2)]))
