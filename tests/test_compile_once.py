"""Each scan kernel is compiled once, whatever mode, pattern or option a render uses: numba
compiles a kernel again for every distinct set of argument types (a writable against a
read-only array, a literal against an int64), and each extra compile is seconds of a user's
first run (docs/bench.md, "First run"). Checked in a fresh process, where only renders have
called the kernels; cached loads count as compiles here too."""
import os
import subprocess
import sys

SCRIPT = r"""
import numpy as np
from vecmsaa.raster import scan
from vecmsaa.raster.render import render_scene
from vecmsaa.svg.pathdata import parse_path_data
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid

path = parse_path_data("M 2 2 C 20 0 30 30 2 30 Z M 10 10 L 28 12 L 20 28 Z")
scene = Scene(32, 32, Group([Fill(path, Solid((1, 0, 0, 1))), Fill(path, Solid((0, 0, 1, 0.5)))]))
for opts in (dict(mode="none"), dict(mode="alpha"), dict(mode="a2c"), dict(mode="persample"),
             dict(mode="approx"), dict(mode="approx", samples=16), dict(mode="alpha-sat"),
             dict(mode="approx", samples=16, color_samples=4), dict(mode="persample", pattern="grid")):
    render_scene(scene, **opts)
for name in ("render_msaa", "scan_lenses", "scan_edges", "sweep_rows", "sweep_rows_behind"):
    print(name, len(getattr(scan, name).signatures))
"""


def test_scan_kernels_compile_once_for_every_mode():
    # numba's JIT (the compiled kernels of aot.py have one entry per manifest line)
    env = dict(os.environ, VECMSAA_JIT="1")
    run = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                         timeout=900, env=env)
    assert run.returncode == 0, run.stderr[-2000:]
    counts = dict(line.split() for line in run.stdout.split("\n") if line.strip())
    assert counts and all(n in ("0", "1") for n in counts.values()), counts
    assert counts["render_msaa"] == "1"
