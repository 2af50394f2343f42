"""vecmsaa: SVG and font rendering with Loop-Blinn curves and multisample antialiasing.

>>> import vecmsaa
>>> png = vecmsaa.svg2png(url="drawing.svg", output_width=512)        # doctest: +SKIP
>>> vecmsaa.render_svg("drawing.svg", width=512).save("drawing.png")   # doctest: +SKIP
>>> vecmsaa.render_text("NotoSans.ttf", "Hamburgefonstiv", 48)       # doctest: +SKIP

The functions are imported on first use: ``import vecmsaa`` alone stays fast.
"""
from __future__ import annotations

__version__ = "0.1.0"

import sys  # noqa: E402

from .jitcache import ensure_fresh_cache  # noqa: E402

#: Building and drawing recurse once or a few times per element level (filtered groups: about
#: five frames); this leaves room for svg.document.MAX_DEPTH levels. Python 3.11+ keeps Python
#: frames off the C stack (3.10 uses well under the 8 MB main-thread stack for this many).
RECURSION_LIMIT = 10_000
sys.setrecursionlimit(max(sys.getrecursionlimit(), RECURSION_LIMIT))

ensure_fresh_cache()

#: public name → the module that defines it (imported when the name is first used: the SVG
#: front end and the kernels cost start-up time that ``import vecmsaa`` should not)
_LAZY = {
    "render_svg": "api", "render_svg_array": "api", "render_svg_png": "api", "load_svg": "api", "query_bounds": "api",
    "svg2png": "convert", "svg2webp": "convert", "svg2jpeg": "convert", "svg2tiff": "convert",
    "render_text": "convert",
    "SvgError": "svg", "RenderWarning": "diagnostics",
}
__all__ = sorted(_LAZY) + ["__version__"]


def __getattr__(name):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'vecmsaa' has no attribute {name!r}")
    import importlib
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
