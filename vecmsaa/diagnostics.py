"""One channel for problems that do not stop a render: a font family not found, an image not
found or refused, an unresolved ``url(#id)``, an unsupported element or attribute.

The front end calls :func:`warn` with one line. Who listens decides what happens to it: the
command line collects the lines of each file (:func:`collecting`) and prints them on stderr
with the file's name (``--quiet`` drops them); the Python API turns them into
:mod:`warnings` of class :class:`RenderWarning` (:func:`as_python_warnings`). Each message is
reported once per render. Imports nothing of vecmsaa, so every stage may use it.
"""
from __future__ import annotations

import contextlib
import os
import sys
import warnings

#: frames a warning does not point at: vecmsaa's own and the context managers'
_SKIPPED = (os.path.dirname(os.path.abspath(__file__)) + os.sep, contextlib.__file__)


class RenderWarning(UserWarning):
    """Something in the input was skipped or replaced; the image is still made."""


_sinks: list = []   # the innermost listener last; each is a list of messages


def warn(message: str) -> None:
    """Report one problem (one line, without the file name: the listener adds it)."""
    if _sinks:
        sink = _sinks[-1]
        if message not in sink:
            sink.append(message)
    else:
        warnings.warn(message, RenderWarning, stacklevel=_outside_level())


@contextlib.contextmanager
def collecting(sink: list):
    """Within the block, warnings are appended to ``sink`` (each message once)."""
    _sinks.append(sink)
    try:
        yield sink
    finally:
        _sinks.remove(sink)


@contextlib.contextmanager
def as_python_warnings():
    """Within the block, warnings are gathered and then issued as :class:`RenderWarning`
    through :mod:`warnings` (once each), unless an outer listener collects them."""
    if _sinks:
        yield
        return
    found: list = []
    with collecting(found):
        yield
    for message in found:
        warnings.warn(message, RenderWarning, stacklevel=_outside_level())


def _outside_level() -> int:
    """The stacklevel of the first caller outside vecmsaa, so a warning names the user's line."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_code.co_filename.startswith(_SKIPPED):
        frame, level = frame.f_back, level + 1
    return level
