"""Where first-run compile time goes: CPU seconds per numba kernel, compiles of the kernels it
calls subtracted, over ``vecmsaa`` commands run one after another in one process.

    NUMBA_CACHE_DIR=$(mktemp -d) python -m vecmsaa.cli.compile_times \\
        "render drawing.svg -o out.png" "font Font.ttf -o font.png" "demo -o demo.png"

An empty ``NUMBA_CACHE_DIR`` makes every kernel compile without touching the project's cache.
Kernels compiled more than once (one specialisation per distinct argument types, e.g. a
``Literal[int](0)`` counter) are listed with their signatures: each is a whole extra compile.
"""
from __future__ import annotations

import collections
import os
import shlex
import sys
import time

# what this measures is numba's JIT, kernel by kernel (the compiled module of aot.py is built
# from the same compiles: ``python -m vecmsaa.aot`` reports its total)
os.environ["VECMSAA_JIT"] = "1"

from numba.core import event


class CompileTimes(event.Listener):
    """Self CPU time and compile count per dispatcher (``module.function``)."""

    def __init__(self):
        self.stack = []
        self.seconds = collections.Counter()
        self.count = collections.Counter()
        self.dispatchers = {}

    def on_start(self, ev):
        self.stack.append([ev.data["dispatcher"], time.process_time(), 0.0])

    def on_end(self, ev):
        dispatcher, t0, nested = self.stack.pop()
        dt = time.process_time() - t0
        name = f"{dispatcher.py_func.__module__}.{dispatcher.py_func.__qualname__}"
        self.seconds[name] += dt - nested
        self.count[name] += 1
        self.dispatchers[name] = dispatcher
        if self.stack:
            self.stack[-1][2] += dt

    def report(self, top=40):
        lines = [f"compiling: {sum(self.seconds.values()):.1f} s CPU in all"]
        by_module = collections.Counter()
        for name, s in self.seconds.items():
            by_module[name.rpartition(".")[0]] += s
        lines += [f"{s:8.2f} s  {m}" for m, s in by_module.most_common()]
        lines.append("largest kernels (self time, compiles):")
        lines += [f"{s:8.2f} s {self.count[n]:3d}  {n}" for n, s in self.seconds.most_common(top)]
        for name, d in self.dispatchers.items():
            if len(d.signatures) > 1 and not name.startswith("numba."):
                lines.append(f"compiled {len(d.signatures)} times: {name}")
                lines += [f"    {sig}" for sig in d.signatures]
        return "\n".join(lines)


def main(argv=None) -> int:
    commands = sys.argv[1:] if argv is None else argv
    if not commands:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    listener = CompileTimes()
    event.register("numba:compile", listener)
    saved = sys.argv
    try:
        for command in commands:
            # each command as `vecmsaa ...` would run it, in this process (cli.main.main: the
            # console entry point ends the process with os._exit after one command)
            sys.argv = ["vecmsaa", *shlex.split(command)]
            t0 = time.process_time()
            from vecmsaa.cli.main import main as cli_main
            try:
                status = cli_main()
            except SystemExit as exc:
                status = exc.code
            print(f"{time.process_time() - t0:8.1f} s CPU  vecmsaa {command}"
                  + (f"  (exit {status})" if status else ""))
    finally:
        sys.argv = saved
        event.unregister("numba:compile", listener)
    print(listener.report())
    return 0


if __name__ == "__main__":
    sys.exit(main())
