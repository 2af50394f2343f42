"""Outlines → what the raster draws: Loop–Blinn curve primitives and straight edges
(:mod:`.primitives`), stroke outlines and dashes (:mod:`.stroke`). Imports only :mod:`vecmsaa.scene`."""
