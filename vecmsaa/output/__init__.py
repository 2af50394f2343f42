"""Pixels out: premultiplied float → straight RGBA8 (:mod:`.rgba8`) and the encoders (:mod:`.png`).
Imports nothing of vecmsaa."""
