"""Scan conversion and compositing: MSAA and exact-area kernels (:mod:`.scan`), sample patterns,
paint shaders, blend modes, filter effects, and the layer and band driver (:mod:`.render`).
Imports :mod:`vecmsaa.geometry`, :mod:`vecmsaa.scene` and :mod:`vecmsaa.output`."""
