"""vecmsaa: SVG and font rendering with Loop-Blinn curves and multisample antialiasing."""
from __future__ import annotations

__version__ = "0.1.0"

MODES = ("none", "alpha", "a2c", "persample", "approx", "analytic", "reference")
DEFAULT_MODE = "approx"
DEFAULT_SAMPLES = 8
