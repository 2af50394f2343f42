"""vecmsaa/jit.py and aot.py: kernels from the compiled module without numba, numba's JIT for
what the module lacks, and cached JIT kernels loaded without numba's registries."""
import gc
import inspect
import os
import subprocess
from pathlib import Path
import sys

import numpy as np
import pytest

SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">'
       '<circle cx="20" cy="15" r="12" fill="teal"/></svg>')

RENDER = f"""
import sys
from vecmsaa.api import render_svg_array
img = render_svg_array({SVG!r}.encode())
assert img[15, 20, 3] == 255 and img[0, 0, 3] == 0
import vecmsaa.jit
print(vecmsaa.jit.AOT, "numba" in sys.modules, "numba.np.linalg" in sys.modules,
      "numba.typed.typeddict" in sys.modules)
"""

# a drawing that reaches most kernels (fills and strokes with curves, dashes, text, a
# gradient, a blur, a mask) in several coverage modes, and the tiger where ../shared is
INLINE = """<svg xmlns="http://www.w3.org/2000/svg" width="64" height="48" viewBox="0 0 64 48">
  <defs><linearGradient id="g"><stop offset="0" stop-color="gold"/><stop offset="1" stop-color="navy"/></linearGradient>
  <filter id="b"><feGaussianBlur stdDeviation="1.5"/></filter>
  <mask id="m"><circle cx="40" cy="24" r="14" fill="white"/></mask></defs>
  <path d="M4 40 C 10 2, 30 2, 36 40 Z" fill="url(#g)" stroke="black" stroke-width="1.5"
        stroke-dasharray="3 1.5" stroke-linejoin="round"/>
  <rect x="30" y="8" width="30" height="30" fill="crimson" opacity="0.6" filter="url(#b)" mask="url(#m)"/>
  <text x="6" y="46" font-size="9" font-family="sans-serif">Aa</text>
</svg>"""

COMPARE = f"""
import sys
import numpy as np
from vecmsaa.api import render_svg_array
svg = {INLINE!r}.encode()
out = [render_svg_array(svg, width=160, mode=m) for m in
       ("approx", "persample", "alpha", "analytic", "none", "a2c")]
tiger = "{os.path.join(os.path.dirname(__file__), '..', '..', 'shared', 'corpus', 'Ghostscript_Tiger.svg')}"
import os.path
if os.path.exists(tiger):
    out.append(render_svg_array(tiger, width=300))
np.save(sys.argv[1], np.concatenate([a.ravel() for a in out]))
import vecmsaa.jit
print(vecmsaa.jit.AOT)
"""


def _run(script, *args, jit):
    env = dict(os.environ)
    env.pop("VECMSAA_JIT", None)
    if jit:
        env["VECMSAA_JIT"] = "1"
    return subprocess.run([sys.executable, "-c", script, *args], check=True,
                          capture_output=True, text=True, env=env, timeout=1200).stdout.split()


def test_a_render_with_the_compiled_kernels_imports_no_numba():
    assert _run(RENDER, jit=False) == ["True", "False", "False", "False"]


def test_a_render_from_numbas_cache_loads_no_numba_registry():
    # the first process may compile (the compiler installs every registry); the second loads
    # its kernels from the cache, and a refresh would import both modules
    _run(RENDER, jit=True)
    assert _run(RENDER, jit=True) == ["False", "True", "False", "False"]


def test_the_compiled_kernels_draw_the_bytes_numbas_jit_draws(tmp_path):
    aot, jit = tmp_path / "aot.npy", tmp_path / "jit.npy"
    assert _run(COMPARE, str(aot), jit=False) == ["True"]
    assert _run(COMPARE, str(jit), jit=True) == ["False"]
    a, b = np.load(aot), np.load(jit)
    assert a.shape == b.shape and a.any()
    assert np.array_equal(a, b)


def test_arguments_the_module_lacks_go_to_numba_and_give_the_same_answer():
    from vecmsaa import jit
    from vecmsaa.scene import transform
    kernel = transform._apply
    if not jit.AOT:
        pytest.skip("numba's JIT for every kernel here")
    pts = np.array([[1.0, 2.0], [3.0, -4.0], [0.5, 0.25]])
    # a strided view: no manifest entry takes it (layout 'A')
    view = np.repeat(pts, 2, axis=0)[::2]
    assert jit.arg_key(view) not in {k[0] for k in kernel.entries}
    a, b, c, d, e, f = 2.0, 0.5, -1.0, 3.0, 10.0, -7.0
    expected = np.stack([a * pts[:, 0] + c * pts[:, 1] + e, b * pts[:, 0] + d * pts[:, 1] + f], 1)
    assert np.allclose(kernel(view, a, b, c, d, e, f), expected)


def test_a_kernel_bound_to_its_last_argument_gives_the_kernels_answer():
    # jit.bind_last computes the last argument's part of the call key once; the call must
    # still pick the entry for all the arguments' types (or numba's JIT where none fits)
    from vecmsaa import jit
    from vecmsaa.scene import transform
    kernel = transform._apply
    pts = np.array([[1.0, 2.0], [3.0, -4.0], [0.5, 0.25]])
    view = np.repeat(pts, 2, axis=0)[::2]
    a, b, c, d, e, f = 2.0, 0.5, -1.0, 3.0, 10.0, -7.0
    expected = np.stack([a * pts[:, 0] + c * pts[:, 1] + e, b * pts[:, 0] + d * pts[:, 1] + f], 1)
    bound = jit.bind_last(kernel, f)
    for p in (pts, view):
        assert np.allclose(bound(p, a, b, c, d, e), expected)
    # an integer where the entries take a float: not the float entry's key
    assert np.allclose(jit.bind_last(kernel, -7)(pts, a, b, c, d, e), expected)
    # a plain function (numba's JIT kernels under VECMSAA_JIT=1) is called as it is
    assert jit.bind_last(lambda *args: args, 3)(1, 2) == (1, 2, 3)
    # several trailing arguments bound (jit.bind_tail), a view among the others
    for p in (pts, view):
        assert np.allclose(jit.bind_tail(kernel, (d, e, f))(p, a, b, c), expected)
    assert np.allclose(jit.bind_tail(kernel, (d, e, -7))(pts, a, b, c), expected)
    assert jit.bind_tail(lambda *args: args, (3, 4))(1, 2) == (1, 2, 3, 4)


def test_every_manifest_line_names_a_kernel_with_that_many_parameters():
    import importlib

    from vecmsaa import aot
    lines = [ln for ln in aot.MANIFEST.read_text().splitlines() if ln and not ln.startswith("#")]
    assert lines
    for line in lines:
        name, args, _ = line.split("|")
        module, qualname = name.split(":")
        kernel = getattr(importlib.import_module(module), qualname)
        depth, count = 0, 1 if args else 0
        for ch in args:
            depth += ch in "(["
            depth -= ch in ")]"
            count += ch == "," and depth == 0
        assert count == len(inspect.signature(kernel.py_func).parameters), line


def test_the_module_name_changes_with_any_kernel_source():
    from vecmsaa import aot
    from vecmsaa.jitcache import ensure_fresh_cache
    stamps = dict(ensure_fresh_cache())
    before = aot.key(stamps)
    assert aot.key(dict(stamps)) == before
    name = sorted(stamps)[0]
    stamps[name] = "0" * 64
    assert aot.key(stamps) != before


CSAA = f"""
from vecmsaa.api import render_svg_array
img = render_svg_array({SVG!r}.encode(), color_samples=2)
assert img[15, 20, 3] == 255 and img[0, 0, 3] == 0
import sys
print("numba" in sys.modules)
"""


def test_the_parts_modules_hold_one_entry_per_manifest_line_between_them():
    from vecmsaa import aot
    from vecmsaa.jitcache import ensure_fresh_cache
    _run(RENDER, jit=False)                 # builds the modules where they are missing
    # the first CSAA render builds the lazy part (not numba's JIT: no numba in the process)
    assert _run(CSAA, jit=False) == ["False"]
    # built, the lazy part is still loaded only by a process that calls one of its kernels
    loaded = "\nprint(sum(m.startswith('vecmsaa_kernels_') for m in sys.modules))"
    assert _run(RENDER + loaded, jit=False)[-1] == str(len(aot.parts()))
    assert _run(CSAA + loaded, jit=False)[-1] == str(len(aot.parts()) + 1)
    k = aot.key(ensure_fresh_cache())
    paths, lazy = aot.find(k), aot.find(k, aot.parts(lazy=True))
    assert paths is not None and len(paths) == len(aot.parts()) == 4
    assert lazy is not None and len(lazy) == 1
    module, index = aot.load(paths + lazy)
    lines = [ln for ln in aot.MANIFEST.read_text().splitlines() if ln and not ln.startswith("#")]
    symbols = [symbol for entries in index.values() for symbol, _ in entries]
    assert len(symbols) == len(set(symbols)) == len(lines)
    assert all(callable(getattr(module, s)) for s in symbols)
    assert sorted(index) == sorted({ln.split("|")[0] for ln in lines})
    assert {aot.part_of(name) for name in aot.load(lazy)[1]} == {aot.LAZY_PART}



def test_the_build_process_imports_this_package_whatever_the_working_folder(tmp_path,
                                                                           monkeypatch):
    # ``python -m vecmsaa.aot`` imports the vecmsaa of its working folder first: started in
    # another checkout's folder, it built that checkout's kernels under this one's key
    import subprocess
    from vecmsaa import aot
    other = tmp_path / "other-checkout"
    (other / "vecmsaa").mkdir(parents=True)
    (other / "vecmsaa" / "__init__.py").write_text("raise ImportError('the wrong vecmsaa')\n")
    monkeypatch.chdir(other)
    seen, real_run = {}, subprocess.run

    def run(cmd, **kw):
        # the real build's import, in the folder it would run in
        seen.update(cmd=cmd)
        found = real_run([sys.executable, "-c", "import vecmsaa.aot"], cwd=kw.get("cwd"),
                         env=kw.get("env"), capture_output=True).returncode == 0
        for i in range(3, len(cmd), 2):
            Path(cmd[i]).write_text("built")
        return subprocess.CompletedProcess(cmd, 0 if found else 1)

    monkeypatch.setattr(subprocess, "run", run)
    path = Path("module.so")        # relative to the caller's folder
    assert aot._build_parts({0: path}) is None
    assert (other / "module.so").read_text() == "built"
    assert Path(seen["cmd"][3]).is_absolute()


def test_the_build_runs_each_part_in_a_process_of_its_own_and_fails_when_one_fails(
        tmp_path, monkeypatch):
    # the build's orchestration (aot.build_parts) with stand-ins for numba's part: one set-up,
    # then a forked process per part, all sharing one folder for the C runtime, removed after
    from vecmsaa import aot
    monkeypatch.setattr(aot, "_prepare", lambda: ([], {}))

    def build(path, part, entries, spent, folder):
        if part == 9:
            raise RuntimeError("this part cannot be built")
        # pycc's C runtime, compiled once for all parts (by a process of its own)
        objects = aot._runtime(folder)
        assert objects and all(os.path.getsize(o) > 0 for o in objects)
        path.write_text(f"{os.getpid()} {folder} {' '.join(objects)}")

    monkeypatch.setattr(aot, "build", build)
    jobs = [(tmp_path / "a", 0), (tmp_path / "b", 1), (tmp_path / "c", 2)]
    thresholds = gc.get_threshold()
    assert aot.build_parts(jobs) == 0
    assert gc.get_threshold() == thresholds and gc.get_freeze_count() == 0
    written = [path.read_text().split(" ", 2) for path, _ in jobs]
    assert len({pid for pid, _, _ in written}) == 3
    assert len({folder for _, folder, _ in written}) == 1
    assert len({objects for _, _, objects in written}) == 1
    assert not os.path.exists(written[0][1])
    for failing in ([(tmp_path / "d", 0), (tmp_path / "e", 9)], [(tmp_path / "f", 9),
                                                                  (tmp_path / "g", 0)]):
        assert aot.build_parts(failing) == 1
        assert all(path.exists() for path, part in failing if part != 9)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the build forks")
@pytest.mark.parametrize("cores", [1, 2, 3])
def test_the_build_runs_no_more_parts_at_once_than_there_are_cores(tmp_path, monkeypatch,
                                                                    cores):
    # each part's process takes about 300 MB: four parts on two cores run two at a time
    import time
    from vecmsaa import aot
    monkeypatch.setattr(aot, "_prepare", lambda: ([], {}))
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(cores)))

    def build(path, part, entries, spent, folder):
        start = time.monotonic()
        time.sleep(0.3)
        path.write_text(f"{os.getpid()} {start} {time.monotonic()}")

    monkeypatch.setattr(aot, "build", build)
    jobs = [(tmp_path / f"part{i}", i) for i in range(5)]
    assert aot.build_parts(jobs) == 0
    spans = [tuple(map(float, path.read_text().split()[1:])) for path, _ in jobs]
    assert len({path.read_text().split()[0] for path, _ in jobs}) == 5
    # the most parts building at any moment (at each part's start)
    busy = max(sum(s <= t < e for s, e in spans) for t, _ in spans)
    assert busy == cores

