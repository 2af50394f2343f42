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


#: the innermost listener last; each is (its list of messages, {message: warning class})
_sinks: list = []


def warn(message: str, category: type = RenderWarning) -> None:
    """Report one problem (one line, without the file name: the listener adds it).
    ``category``: the :class:`RenderWarning` subclass Python callers see (e.g. FontWarning)."""
    if _sinks:
        sink, categories = _sinks[-1]
        if message not in categories:
            sink.append(message)
            categories[message] = category
    else:
        warnings.warn(message, category, stacklevel=_outside_level())


@contextlib.contextmanager
def collecting(sink: list, categories: dict | None = None):
    """Within the block, warnings are appended to ``sink`` (each message once) and their
    classes recorded in ``categories``."""
    entry = (sink, {} if categories is None else categories)
    _sinks.append(entry)
    try:
        yield sink
    finally:
        _sinks.remove(entry)


@contextlib.contextmanager
def as_python_warnings():
    """Within the block, warnings are gathered and then issued as :class:`RenderWarning`
    through :mod:`warnings` (once each), unless an outer listener collects them."""
    if _sinks:
        yield
        return
    found: list = []
    categories: dict = {}
    with collecting(found, categories):
        yield
    for message in found:
        warnings.warn(message, categories[message], stacklevel=_outside_level())


def _outside_level() -> int:
    """The stacklevel of the first caller outside vecmsaa, so a warning names the user's line."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_code.co_filename.startswith(_SKIPPED):
        frame, level = frame.f_back, level + 1
    return level
