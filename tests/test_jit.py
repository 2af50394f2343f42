"""vecmsaa/jit.py: cached kernels load without numba's typing and lowering registries."""
import subprocess
import sys

SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">'
       '<circle cx="20" cy="15" r="12" fill="teal"/></svg>')

RENDER = f"""
import sys
from vecmsaa.api import render_svg_array
img = render_svg_array({SVG!r}.encode())
assert img[15, 20, 3] == 255 and img[0, 0, 3] == 0
print("numba.np.linalg" in sys.modules, "numba.typed.typeddict" in sys.modules)
"""


def test_a_render_from_the_cache_loads_no_numba_registry():
    import vecmsaa.jit
    assert vecmsaa.jit.REGISTRIES_DEFERRED
    # the first process may compile (the compiler installs every registry); the second loads
    # its kernels from the cache, and a refresh would import both modules
    subprocess.run([sys.executable, "-c", RENDER], check=True, capture_output=True)
    out = subprocess.run([sys.executable, "-c", RENDER], check=True, capture_output=True,
                         text=True).stdout.split()
    assert out == ["False", "False"]
