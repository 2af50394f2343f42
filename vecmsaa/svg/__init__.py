"""SVG front end: XML → resolved :class:`vecmsaa.scene.nodes.Scene` (geometry in device pixels).

Modules: :mod:`.document` (safe XML, CSS cascade, computed style), :mod:`.sizing` (opening a
document: its size and root matrix), :mod:`.builder` (the scene construction), :mod:`.units`
(numbers, lengths, transform lists, viewBox), :mod:`.color`, :mod:`.shapes` and :mod:`.pathdata`
(basic shapes and path data → paths), :mod:`.paint` (gradients, patterns), :mod:`.masking`
(clipPath, mask), :mod:`.filters`, :mod:`.markers`, :mod:`.image`, :mod:`.resources` (data: URLs
and files, confined to allowed folders) and :mod:`.text` (``<text>``, a package by job). Strokes
come from :mod:`vecmsaa.geometry.stroke`, fonts from :mod:`vecmsaa.fonts`.
"""
from __future__ import annotations


class SvgError(ValueError):
    """An SVG document that cannot be rendered; the message is one line."""


__all__ = ["SvgError"]
