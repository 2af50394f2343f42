"""The resolved tree every input produces (usvg's role): nodes in device pixels, outlines as
:class:`~vecmsaa.scene.path.Path`, affine transforms and bounds. Imports nothing of vecmsaa."""
