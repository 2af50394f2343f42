"""vecmsaa: SVG and font rendering with Loop-Blinn curves and multisample antialiasing."""
from __future__ import annotations

__version__ = "0.1.0"

from .jitcache import ensure_fresh_cache  # noqa: E402

ensure_fresh_cache()


def __getattr__(name):
    # The convenience API pulls in the SVG front end; import it only when asked for.
    if name in ("render_svg", "render_svg_array", "render_svg_png"):
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'vecmsaa' has no attribute {name!r}")
