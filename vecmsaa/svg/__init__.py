"""SVG front end: XML → resolved :class:`vecmsaa.scene.nodes.Scene` (geometry in device pixels).

Modules: :mod:`.document` (safe XML, CSS cascade, computed style), :mod:`.color`, :mod:`.units`
(lengths, transforms, viewBox), :mod:`.shapes` (basic shapes → paths), :mod:`.paint` (paint
servers), :mod:`.resources` (data: URLs and files, confined to allowed folders), :mod:`.builder`
(the scene construction). ``pathdata``, ``text`` and :mod:`vecmsaa.geometry.stroke` come from other parts
of the project.
"""
from __future__ import annotations


class SvgError(ValueError):
    """An SVG document that cannot be rendered; the message is one line."""


__all__ = ["SvgError"]
