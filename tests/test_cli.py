"""Command-line behaviour shared by all commands: errors, output files."""
import json
import os
import stat
import subprocess
import sys

SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10">'
       '<rect x="2" y="2" width="16" height="6" fill="#08f"/></svg>')


def vecmsaa(*args, **kw):
    return subprocess.run([sys.executable, "-m", "vecmsaa.cli", *map(str, args)],
                          capture_output=True, text=True, **kw)


def test_output_into_a_missing_folder_is_a_one_line_error(tmp_path):
    src = tmp_path / "a.svg"
    src.write_text(SVG)
    out = tmp_path / "missing" / "a.png"
    proc = vecmsaa("render", src, "-o", out)
    assert proc.returncode == 1
    assert len(proc.stderr.strip().splitlines()) == 1 and "missing" in proc.stderr
    assert not (tmp_path / "missing").exists()


def test_batch_creates_its_output_folder_and_files_get_normal_permissions(tmp_path):
    a, b = tmp_path / "a.svg", tmp_path / "b.svg"
    a.write_text(SVG)
    b.write_text(SVG)
    out_dir = tmp_path / "out" / "nested"
    old = os.umask(0o022)
    try:
        proc = vecmsaa("render", a, b, "--out-dir", out_dir)
    finally:
        os.umask(old)
    assert proc.returncode == 0, proc.stderr
    mode = stat.S_IMODE((out_dir / "a.png").stat().st_mode)
    assert mode == 0o644


def test_usage_errors_exit_2(tmp_path):
    src = tmp_path / "a.svg"
    src.write_text(SVG)
    for bad in (["--mode", "sharp"], ["--samples", "3"]):
        proc = vecmsaa("render", src, "-o", tmp_path / "x.png", *bad)
        assert proc.returncode == 2
        assert not (tmp_path / "x.png").exists()


def test_help_lists_every_command():
    proc = vecmsaa("--help")
    for command in ("render", "font", "golden", "demo", "suite", "bench"):
        assert command in proc.stdout


def test_bench_versus_resvg_expands_folders_and_needs_svgs(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    proc = vecmsaa("bench", "--versus-resvg", empty, "-o", tmp_path / "out")
    assert proc.returncode == 2 and "needs SVG files" in proc.stderr


def test_bench_times_processes_with_bytecode_caches(tmp_path, monkeypatch):
    """The whole-process rows time what an installed command costs: a child Python started
    with the bench's environment writes the bytecode cache of a module it imports, even where
    PYTHONDONTWRITEBYTECODE is set around the bench."""
    import subprocess
    import sys
    from vecmsaa.tools.bench import user_env
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")
    (tmp_path / "probe_mod.py").write_text("X = 1\n")
    subprocess.run([sys.executable, "-c", "import probe_mod"], cwd=tmp_path, check=True,
                   env=dict(user_env(), PYTHONPATH=str(tmp_path)))
    assert list((tmp_path / "__pycache__").glob("probe_mod.*.pyc"))


def test_bench_icons_writes_the_small_size_table(tmp_path):
    """The small-size rows: a disc icon passes at the default (16 samples up to 128 px) and
    with exact area against 1024-sample ground truth at every size; an empty folder is a
    usage error."""
    icons = tmp_path / "icons"
    icons.mkdir()
    (icons / "disc.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="16" '
                                    'height="16"><circle cx="8.3" cy="7.8" r="5.4"/></svg>')
    proc = vecmsaa("bench", "--icons", icons, "-o", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
    rows = {(r["config"], r["size"]): r
        for r in json.loads((tmp_path / "out" / "icons.json").read_text())}
    assert {size for _, size in rows} == {16, 24, 32}
    assert all(rows[("default", s)]["pass"] == 1.0 for s in (16, 24, 32))
    assert rows[("analytic", 16)]["pass"] == 1.0
    assert "| default |" in (tmp_path / "out" / "icons.md").read_text()
    empty = tmp_path / "empty"
    empty.mkdir()
    assert vecmsaa("bench", "--icons", empty, "-o", tmp_path / "o2").returncode == 2


def test_render_imports_no_other_commands_modules(tmp_path):
    """A render builds its own parser only: the other commands' parsers import what their help
    quotes (golden: vecmsaa.tools.compare), and --scheduler needs no cluster module."""
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
                   '<rect width="2" height="2"/></svg>')
    code = ("import sys; from vecmsaa.cli.main import main; "
            f"rc = main(['render', {str(svg)!r}, '-o', {str(tmp_path / 'a.png')!r}]); "
            "print(rc, sorted(m for m in sys.modules if m.startswith('vecmsaa.tools')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split(None, 1)
    assert out == ["0", "[]\n"]


#: what a render of a document without those features never needs (each costs start-up)
FEATURE_MODULES = ("vecmsaa.scene.effects", "vecmsaa.svg.filters", "vecmsaa.raster.filter_effects",
                   "vecmsaa.svg.text", "vecmsaa.fonts", "vecmsaa.svg.masking", "vecmsaa.svg.paint",
                   "vecmsaa.svg.image", "numba", "tinycss2", "cssselect2", "PIL", "uharfbuzz",
                   "xml.etree", "fontTools")


def _render_imports(tmp_path, body):
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10">'
                   + body + '</svg>')
    code = ("import sys; from vecmsaa.cli.main import main; import vecmsaa.jit; "
            f"rc = main(['render', {str(svg)!r}, '-o', {str(tmp_path / 'a.png')!r}]); "
            f"print(rc, vecmsaa.jit.AOT, "
            f"*sorted(m for m in sys.modules if m.startswith({FEATURE_MODULES!r})))")
    env = {k: v for k, v in os.environ.items() if k != "VECMSAA_JIT"}
    rc, aot, *modules = subprocess.run([sys.executable, "-c", code], capture_output=True,
                                       text=True, check=True, env=env).stdout.split()
    # (numba's JIT stands in where the compiled module could not be built)
    return [rc] + [m for m in modules if aot == "True" or not m.startswith("numba")]


#: what a plain render's start-up does without (measured in docs/bench.md, "Session 20, the
#: start-up floor"): OpenSSL's hashing (the kernels' module key uses CPython's own SHA-256),
#: sysconfig (the extension suffix comes from importlib), the thread pool's
#: concurrent.futures and logging while nothing is submitted to it, shutil (argparse's help
#: formatter is told the terminal's width) and json (the kernels' index and the sources'
#: stamps are in marshal's format)
START_UP_MODULES = ("_hashlib", "sysconfig", "concurrent.futures", "logging", "shutil", "json")


def test_help_is_wrapped_to_the_columns_the_environment_gives():
    """The width argparse's formatter would take (shutil.get_terminal_size: COLUMNS first),
    now computed without shutil: the description's lines fill COLUMNS less two."""
    def lines(columns):
        env = dict(os.environ, COLUMNS=str(columns))
        out = vecmsaa("render", "--help", env=env, check=True).stdout
        return out.split("\n\n")[1].splitlines()      # the description paragraph
    narrow, wide = lines(50), lines(120)
    assert max(map(len, narrow)) <= 48 < max(map(len, wide)) <= 118
    assert " ".join(narrow) == " ".join(wide)


def test_a_small_render_starts_without_modules_it_does_not_use(tmp_path):
    """A 16 px shape on two threads: one band and one path, nothing for the pool's threads;
    only modules the render itself imported count (the interpreter's site may bring some)."""
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16">'
                   '<path d="M2 2 L14 2 L8 14 Z" fill="#c33" stroke="#000"/></svg>')
    code = ("import sys; before = set(sys.modules); from vecmsaa.cli.main import main; "
            "import vecmsaa.jit; "
            f"rc = main(['render', {str(svg)!r}, '-o', {str(tmp_path / 'a.png')!r}, "
            "'--threads', '2']); "
            f"print(rc, vecmsaa.jit.AOT, *sorted(m for m in set(sys.modules) - before "
            f"if m.startswith({START_UP_MODULES!r})))")
    env = {k: v for k, v in os.environ.items() if k != "VECMSAA_JIT"}
    rc, aot, *modules = subprocess.run([sys.executable, "-c", code], capture_output=True,
                                       text=True, check=True, env=env).stdout.split()
    assert rc == "0"
    # (numba's JIT, standing in where the compiled module could not be built, imports them)
    assert modules == [] or aot == "False"
    assert (tmp_path / "a.png").read_bytes().startswith(b"\x89PNG")


def test_render_imports_no_module_of_a_feature_the_document_lacks(tmp_path):
    """A fill, a stroke and a path: no filters, text, fonts, clip paths, masks, gradients,
    images, CSS, numba (the compiled kernels run without it). A filter brings its modules in,
    a mask its own (not the gradients' and patterns')."""
    plain = ('<rect width="5" height="5" fill="red"/><circle cx="5" cy="5" r="3" stroke="blue"'
             ' fill="none"/><path d="M 1 1 Q 9 1 9 9" stroke="#000" stroke-dasharray="1 1"/>')
    assert _render_imports(tmp_path, plain) == ["0"]
    blurred = ('<filter id="f"><feGaussianBlur stdDeviation="1"/></filter>'
               '<rect width="5" height="5" filter="url(#f)"/>')
    assert set(_render_imports(tmp_path, blurred)) == {
        "0", "vecmsaa.scene.effects", "vecmsaa.svg.filters", "vecmsaa.raster.filter_effects"}
    masked = ('<mask id="m"><rect width="5" height="5" fill="white"/></mask>'
              '<rect width="5" height="5" mask="url(#m)"/>')
    assert _render_imports(tmp_path, masked) == ["0", "vecmsaa.svg.masking"]


def test_the_command_ends_without_teardown_but_runs_atexit_and_flushes(tmp_path):
    """console() (the vecmsaa script, python -m vecmsaa.cli) skips the interpreter's teardown:
    atexit handlers still run, standard output is complete, the exit status is main()'s."""
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
                   '<rect width="2" height="2"/></svg>')
    marker = tmp_path / "atexit-ran"
    code = ("import atexit, sys; "
            f"atexit.register(lambda: open({str(marker)!r}, 'w').close()); "
            "sys.argv = ['vecmsaa'] + sys.argv[1:]; "
            "from vecmsaa.cli.main import console; console()")
    png = subprocess.run([sys.executable, "-c", code, "render", str(svg), "-c"],
                         capture_output=True, check=True).stdout
    assert png.startswith(b"\x89PNG") and png.endswith(b"IEND\xaeB`\x82")
    assert marker.exists()
    failed = subprocess.run([sys.executable, "-c", code, "render", str(tmp_path / "none.svg"),
                             "-o", str(tmp_path / "x.png")], capture_output=True, text=True)
    assert failed.returncode == 1 and failed.stderr.count("\n") == 1
