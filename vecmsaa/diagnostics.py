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
import warnings


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
        warnings.warn(message, RenderWarning, stacklevel=2)


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
        # stacklevel 4: the caller of the vecmsaa.api function that opened this block
        warnings.warn(message, RenderWarning, stacklevel=4)
