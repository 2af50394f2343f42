"""One line on stderr when numba's JIT compiles kernels (``VECMSAA_JIT=1``, or where the compiled
kernels of aot.py cannot be built): the first run after installing (or after a change to the
code) compiles what it uses, once, into numba's cache; later runs load it.

Registered as a listener on numba's compile event, which fires only on a cache miss, so a run
with a filled cache prints nothing and pays nothing.
"""
from __future__ import annotations

import contextlib
import sys

#: first-run compile of everything `render`, `font` and `demo` use from an empty cache:
#: 26.5–28.2 s of CPU on a 2-core Intel Xeon machine, 63.9 s on a quiet 2-core AMD EPYC one
#: (73–79 s there at load 3–6.5), 3 Dec 2026 (docs/bench.md, "First run")
COMPILE_SECONDS = "30–65"


def install(stream=None):
    """Announce compiles on ``stream`` (default: stderr when it is a terminal — scripts that
    read stderr, such as a one-line error check, see only what they did before)."""
    if stream is None:
        from .. import jit
        if not sys.stderr.isatty() or jit.AOT:
            # with the compiled kernels (aot.py announces its one build) numba is not imported
            return None
        stream = sys.stderr
    from numba.core import event

    class Notice(event.Listener):
        said = False

        def on_start(self, ev):
            if not self.said:
                self.said = True
                try:
                    print(f"vecmsaa: compiling the numba kernels this command uses, once "
                          f"(about {COMPILE_SECONDS} s of CPU for everything render, font and "
                          f"demo use, more on a busy machine); later runs load them from the "
                          f"cache", file=stream, flush=True)
                except (OSError, ValueError):    # a closed or broken stream: not worth a failure
                    pass

        def on_end(self, ev):
            pass

    listener = Notice()
    event.register("numba:compile", listener)
    return listener


@contextlib.contextmanager
def announcing(stream=None):
    """Within the block, compiles are announced as :func:`install` does; afterwards they are
    not (a command run in-process, as tests do, leaves no listener on a stream it no longer
    owns)."""
    listener = install(stream)
    try:
        yield listener
    finally:
        if listener is not None:
            from numba.core import event
            event.unregister("numba:compile", listener)
