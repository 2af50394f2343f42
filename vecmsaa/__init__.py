"""vecmsaa: SVG and font rendering with Loop-Blinn curves and multisample antialiasing."""
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


def __getattr__(name):
    # The convenience API pulls in the SVG front end; import it only when asked for.
    if name in ("render_svg", "render_svg_array", "render_svg_png"):
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'vecmsaa' has no attribute {name!r}")
