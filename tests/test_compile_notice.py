"""The one line on stderr while numba compiles (first run after installing)."""
from __future__ import annotations

import io

from numba import njit
from numba.core import event

from vecmsaa.cli.compile_notice import install


def test_a_compile_is_announced_once():
    stream = io.StringIO()
    listener = install(stream)
    try:
        # fresh functions (no cache): numba compiles them here
        njit(lambda x: x + 1)(1)
        njit(lambda x: x * 2)(1)
    finally:
        event.unregister("numba:compile", listener)
    lines = stream.getvalue().splitlines()
    assert len(lines) == 1 and "compiling" in lines[0] and "once" in lines[0]


def test_calling_compiled_code_says_nothing():
    f = njit(lambda x: x - 1)
    f(1)
    stream = io.StringIO()
    listener = install(stream)
    try:
        f(2)
    finally:
        event.unregister("numba:compile", listener)
    assert stream.getvalue() == ""
