"""SVG ``<text>`` (being split by job; see :mod:`.layout`)."""
from .layout import build_text

__all__ = ["build_text"]
