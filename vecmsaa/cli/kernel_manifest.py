"""Record which kernels Python calls, with which argument types: the list the ahead-of-time
kernel module is built from (``vecmsaa/kernels.manifest``, see ``vecmsaa/aot.py``).

Run as a pytest plugin over the test suite (every entry the tests reach), or over commands::

    VECMSAA_JIT=1 python -m pytest -q -p vecmsaa.cli.kernel_manifest
    VECMSAA_JIT=1 python -m vecmsaa.cli.kernel_manifest "render drawing.svg -o out.png" ...

Both merge what they saw into the manifest (entries of kernels that no longer exist, or whose
parameter count changed, are dropped). Needs numba's JIT (``VECMSAA_JIT=1``): a kernel is
recorded when numba types a call from Python that it has not seen before in this process.
"""
from __future__ import annotations

import inspect
import os
import shlex
import sys

MANIFEST = os.path.join(os.path.dirname(os.path.dirname(__file__)), "kernels.manifest")

_seen: dict[str, dict[str, str]] = {}


def _concrete(args, py_func):
    """Argument types with omitted defaults replaced by the type of the default: the compiled
    entry takes every argument (the caller fills defaults in, see jit.Kernel)."""
    from numba import typeof
    from numba.core import types
    params = list(inspect.signature(py_func).parameters.values())
    return tuple(typeof(params[i].default) if isinstance(a, types.Omitted) else a
                 for i, a in enumerate(args))


def _line(name, args, ret):
    return f"{name}|{', '.join(map(repr, args))}|{ret!r}"


def install():
    """Patch numba's dispatcher to note each new Python-level specialisation."""
    from numba.core import dispatcher as numba_dispatcher
    original = numba_dispatcher.Dispatcher._compile_for_args
    if getattr(original, "_vecmsaa_recording", False):
        return

    def compile_for_args(self, *args, **kws):
        before = set(self.overloads)
        result = original(self, *args, **kws)
        module = self.py_func.__module__
        if module.startswith("vecmsaa."):
            name = f"{module}:{self.py_func.__qualname__}"
            for key in set(self.overloads) - before:
                sig = self.overloads[key].signature
                concrete = _concrete(key, self.py_func)
                _seen.setdefault(name, {})[_line(name, concrete, sig.return_type)] = ""
        return result

    compile_for_args._vecmsaa_recording = True
    numba_dispatcher.Dispatcher._compile_for_args = compile_for_args


def write():
    """Merge what this process saw into the manifest file."""
    lines = set()
    if os.path.exists(MANIFEST):
        with open(MANIFEST) as f:
            lines = {ln.rstrip("\n") for ln in f if ln.strip() and not ln.startswith("#")}
    for entries in _seen.values():
        lines.update(entries)
    from vecmsaa.aot import manifest_entry
    lines = sorted(ln for ln in lines if manifest_entry(ln) is not None)
    tmp = MANIFEST + ".tmp"
    with open(tmp, "w") as f:
        f.write("# kernel|argument types|return type — written by vecmsaa.cli.kernel_manifest\n")
        f.writelines(ln + "\n" for ln in lines)
    os.replace(tmp, MANIFEST)
    return len(lines)


# pytest plugin hooks
def pytest_configure(config):
    install()


def pytest_sessionfinish(session, exitstatus):
    n = write()
    print(f"\nkernel manifest: {n} entries in {MANIFEST}")


def main(argv=None) -> int:
    commands = sys.argv[1:] if argv is None else argv
    install()
    saved = sys.argv
    try:
        for command in commands:
            sys.argv = ["vecmsaa", *shlex.split(command)]
            from vecmsaa.cli.main import main as cli_main
            try:
                cli_main()
            except SystemExit:
                pass
    finally:
        sys.argv = saved
    print(f"kernel manifest: {write()} entries in {MANIFEST}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
