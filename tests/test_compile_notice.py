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


def test_an_in_process_command_leaves_no_listener(monkeypatch, tmp_path, capsys):
    # a command run in-process on a "terminal" (tests do this) announces on that stderr only
    # while it runs: a later compile must not write to the stream it no longer owns
    import sys

    from vecmsaa.cli.main import main

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"/>')
    before = list(event._registered["numba:compile"])
    assert main(["render", str(svg), "-o", str(tmp_path / "a.png")]) == 0
    assert list(event._registered["numba:compile"]) == before
