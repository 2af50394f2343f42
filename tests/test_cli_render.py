"""``vecmsaa render`` as resvg, rsvg-convert and CairoSVG users expect it (issue 13), and safe
output and input (issue 16): each test renders real files and checks the effect against
geometry or the other tools' documented behaviour."""
from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from PIL import Image

from vecmsaa.cli.main import main

# a 20 x 10 px drawing: a blue rectangle (2..18, 2..8) and a black disc of radius 2 at (5, 5)
SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10">'
       '<rect id="r" x="2" y="2" width="16" height="6" fill="#0080ff"/>'
       '<circle id="c" cx="5" cy="5" r="2"/></svg>')
SQUARE = ('<svg xmlns="http://www.w3.org/2000/svg" width="50" height="50">'
          '<rect width="50" height="50" fill="red"/></svg>')


@pytest.fixture
def svg(tmp_path):
    path = tmp_path / "in.svg"
    path.write_text(SVG)
    return path


def run(*args):
    return main(["render", *map(str, args)])


def image(path_or_bytes):
    data = path_or_bytes if isinstance(path_or_bytes, bytes) else open(path_or_bytes, "rb").read()
    return Image.open(io.BytesIO(data))


def test_positional_output_as_resvg(svg, tmp_path):
    assert run(svg, tmp_path / "out.png") == 0
    assert image(tmp_path / "out.png").size == (20, 10)
    assert sorted(os.listdir(tmp_path)) == ["in.svg", "out.png"]


def test_without_output_png_goes_to_stdout_never_beside_the_input(svg, tmp_path, capfdbinary):
    assert run(svg) == 0
    out = capfdbinary.readouterr().out
    assert image(out).size == (20, 10)
    assert run(svg, "-c") == 0
    assert image(capfdbinary.readouterr().out).size == (20, 10)
    assert os.listdir(tmp_path) == ["in.svg"]


def test_no_output_on_a_terminal_is_a_usage_error(svg):
    import pty
    leader, follower = pty.openpty()
    proc = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "render", str(svg)],
                          stdout=follower, stderr=subprocess.PIPE, text=True)
    os.close(follower)
    os.close(leader)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and "-o" in proc.stderr
    assert os.listdir(svg.parent) == ["in.svg"]


@pytest.mark.parametrize("name,fmt", [("o.webp", "WEBP"), ("o.tif", "TIFF"), ("o.png", "PNG")])
def test_lossless_formats_from_the_name_keep_the_pixels(svg, tmp_path, name, fmt):
    assert run(svg, "-o", tmp_path / "ref.png") == 0
    assert run(svg, "-o", tmp_path / name) == 0
    img = image(tmp_path / name)
    assert img.format == fmt
    assert np.array_equal(np.asarray(img.convert("RGBA")),
                          np.asarray(image(tmp_path / "ref.png").convert("RGBA")))


def test_jpeg_is_flattened_onto_white_or_the_background(svg, tmp_path):
    assert run(svg, "-o", tmp_path / "o.jpg") == 0
    px = np.asarray(image(tmp_path / "o.jpg").convert("RGB")).astype(int)
    assert (px[0, 0] >= 250).all()                            # transparent corner → white
    assert abs(px[5, 14] - (0, 128, 255)).max() <= 8          # inside the rectangle
    assert run(svg, "-o", tmp_path / "g.jpeg", "--background", "lime") == 0
    px = np.asarray(image(tmp_path / "g.jpeg").convert("RGB")).astype(int)
    assert abs(px[0, 0] - (0, 255, 0)).max() <= 8


def test_format_flag_for_stdout(svg, capfdbinary):
    assert run(svg, "-c", "--format", "webp") == 0
    assert image(capfdbinary.readouterr().out).format == "WEBP"


def test_unknown_extension_is_a_usage_error(svg, tmp_path, capsys):
    assert run(svg, "-o", tmp_path / "o.bmpx") == 2
    assert "format" in capsys.readouterr().err
    assert not (tmp_path / "o.bmpx").exists()


# -- sizes as resvg computes them ----------------------------------------------------------

def size_of(svg_path, tmp_path, *flags):
    out = tmp_path / "size.png"
    assert run(svg_path, "-o", out, *flags) == 0
    return image(out).size


def test_sizes_as_resvg(tmp_path):
    square = tmp_path / "sq.svg"
    square.write_text(SQUARE)
    assert size_of(square, tmp_path, "-w", 300, "-z", 2) == (300, 300)    # zoom ignored
    assert size_of(square, tmp_path, "-z", 2) == (100, 100)
    assert size_of(square, tmp_path, "-w", 300, "-h", 100) == (300, 100)  # stretched
    assert size_of(square, tmp_path, "-w", 300, "-h", 100, "-a") == (100, 100)
    assert size_of(square, tmp_path, "-w", 100, "-h", 300, "-a") == (100, 100)
    mm = tmp_path / "mm.svg"
    mm.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="20mm" height="10mm"/>')
    # 20 mm at 300 dpi = 236.22 px: resvg rounds the intrinsic size (236), never ceils (237)
    assert size_of(mm, tmp_path, "--dpi", 300) == (236, 118)


def test_stretched_and_kept_aspect_geometry(tmp_path):
    square = tmp_path / "sq.svg"
    square.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">'
                      '<rect width="5" height="10"/></svg>')
    out = tmp_path / "o.png"
    assert run(square, "-o", out, "-w", 40, "-h", 20) == 0
    alpha = np.asarray(image(out))[..., 3]
    assert alpha[:, :20].min() == 255 and alpha[:, 20:].max() == 0   # left half of 40 px


def test_size_cap_and_its_opt_out(svg, tmp_path, capsys):
    assert run(svg, "-o", tmp_path / "big.png", "-w", 40000) == 1
    err = capsys.readouterr().err
    assert "too large" in err and "--no-size-limit" in err
    assert not (tmp_path / "big.png").exists()
    # 40000 x 20000 would be 3.2 GB: only check that the limit is lifted before rendering
    from vecmsaa.api import output_size
    assert output_size(20, 10, width=40000, size_limit=False) == (40000, 20000)


# -- output files: whole or not at all, links and devices ----------------------------------

def test_symlink_output_writes_its_target(svg, tmp_path):
    target = tmp_path / "target.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(target)
    assert run(svg, "-o", link) == 0
    assert link.is_symlink()
    assert image(target).size == (20, 10)


def test_fifo_and_device_outputs_are_written_through(svg, tmp_path):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    got = {}

    def reader():
        with open(fifo, "rb") as f:
            got["data"] = f.read()
    thread = threading.Thread(target=reader)
    thread.start()
    assert run(svg, "-o", fifo) == 0
    thread.join(10)
    assert image(got["data"]).size == (20, 10)
    assert fifo.exists() and not fifo.is_file()          # still a FIFO
    assert run(svg, "-o", "/dev/null") == 0
    assert os.path.exists("/dev/null") and not os.path.isfile("/dev/null")


def test_a_temporary_file_left_by_a_killed_run_is_removed_by_the_next(svg, tmp_path):
    """The first write into a folder removes the temporary files of every name there whose
    process is gone (a batch lists the folder once, not at each write); a running process's
    stays."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()                                          # a pid that no longer runs
    for name in ("out.png", "other.png"):
        (tmp_path / f".{name}.{dead.pid}.vecmsaa-tmp").write_bytes(b"half")
    live = f".third.png.{os.getppid()}.vecmsaa-tmp"
    (tmp_path / live).write_bytes(b"being written")
    assert run(svg, "-o", tmp_path / "out.png") == 0
    assert sorted(os.listdir(tmp_path)) == sorted([live, "in.svg", "out.png"])


def test_output_onto_a_folder_is_one_clear_line(svg, tmp_path, capsys):
    assert run(svg, "-o", tmp_path) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "folder" in err and "Errno" not in err


def test_endless_input_stops_at_the_limit(tmp_path, capsys):
    assert run("/dev/zero", "-o", tmp_path / "z.png") == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "limit" in err
    assert not (tmp_path / "z.png").exists()


# -- batches -------------------------------------------------------------------------------

def test_folders_are_recursed_and_mirrored(tmp_path):
    src = tmp_path / "icons"
    (src / "sub").mkdir(parents=True)
    (src / "a.svg").write_text(SVG)
    (src / "sub" / "a.svg").write_text(SQUARE)
    (src / "notes.txt").write_text("not an svg")
    out = tmp_path / "out"
    assert run(src, "--out-dir", out) == 0
    assert image(out / "a.png").size == (20, 10)
    assert image(out / "sub" / "a.png").size == (50, 50)
    assert sorted(os.listdir(out)) == ["a.png", "sub"]


def test_a_folder_without_out_dir_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "a.svg").write_text(SVG)
    assert run(tmp_path) == 2
    assert "--out-dir" in capsys.readouterr().err
    assert os.listdir(tmp_path) == ["a.svg"]


def test_pool_reports_a_killed_worker_and_finishes_the_rest():
    from vecmsaa.tools.workers import WorkerDied, imap_unordered

    results = dict(imap_unordered(_die_on_two, range(6), 2))
    assert sorted(results) == list(range(6))
    assert isinstance(results[2], WorkerDied) and "SIGKILL" in str(results[2])
    assert all(results[i] == i * i for i in (0, 1, 3, 4, 5))


def _die_on_two(i):
    if i == 2:
        os.kill(os.getpid(), signal.SIGKILL)
    return i * i


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(c) for c in f.read().split()]
    except OSError:
        return []


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="needs Linux /proc")
def test_batch_survives_a_worker_killed_with_sigkill(tmp_path):
    """One input is a FIFO held open but never written, so its worker blocks reading it; that
    worker is killed with SIGKILL: the batch reports the file as failed and renders the others."""
    src = tmp_path / "in"
    src.mkdir()
    for name in ("a", "b", "c"):
        (src / f"{name}.svg").write_text(SVG)
    fifo = src / "stuck.svg"
    os.mkfifo(fifo)
    proc = subprocess.Popen([sys.executable, "-m", "vecmsaa.cli", "render", str(src),
                             "--out-dir", str(tmp_path / "out"), "--jobs", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # holding the FIFO open for writing (without writing) keeps its reader blocked in read()
    writer = {}
    opener = threading.Thread(target=lambda: writer.setdefault("f", open(fifo, "wb")))
    opener.start()
    victim = None
    deadline = time.time() + 300
    while victim is None and time.time() < deadline and proc.poll() is None:
        for child in _children(proc.pid):
            try:
                fds = os.listdir(f"/proc/{child}/fd")
                if any(os.readlink(f"/proc/{child}/fd/{fd}") == str(fifo) for fd in fds):
                    victim = child
            except OSError:
                pass
        time.sleep(0.2)
    assert victim is not None, "no worker opened the FIFO"
    os.kill(victim, signal.SIGKILL)
    _out, err = proc.communicate(timeout=300)
    opener.join()
    writer["f"].close()
    assert proc.returncode == 1
    assert "stuck.svg" in err and "SIGKILL" in err
    assert sorted(os.listdir(tmp_path / "out")) == ["a.png", "b.png", "c.png"]


# -- resvg's flags -------------------------------------------------------------------------

def test_version_on_every_command(capsys):
    for command in ([], ["render"], ["font"], ["golden"], ["suite"]):
        with pytest.raises(SystemExit) as exit_:
            main([*command, "-V"])
        assert exit_.value.code == 0
        assert capsys.readouterr().out.startswith("vecmsaa ")


def test_query_all_prints_exact_bounding_boxes(svg, capsys):
    assert run("--query-all", svg) == 0
    assert capsys.readouterr().out.splitlines() == ["r,2,2,16,6", "c,3,3,4,4"]


def test_export_id_renders_only_that_element_at_its_bounds(svg, tmp_path):
    out = tmp_path / "c.png"
    assert run(svg, "-o", out, "--export-id", "c", "-z", 4) == 0
    img = np.asarray(image(out))
    assert img.shape[:2] == (16, 16)
    assert img[..., 2].max() == 0              # no blue: the rectangle is not drawn
    assert img[8, 8, 3] == 255 and img[0, 0, 3] == 0


def test_export_area_drawing_crops_to_the_drawing(tmp_path):
    path = tmp_path / "d.svg"
    path.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40">'
                    '<rect x="10" y="5" width="12" height="20"/></svg>')
    out = tmp_path / "d.png"
    assert run(path, "-o", out, "--export-area-drawing") == 0
    img = np.asarray(image(out))
    assert img.shape[:2] == (20, 12) and img[..., 3].min() == 255


def test_languages_choose_the_switch_branch(tmp_path):
    path = tmp_path / "l.svg"
    path.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><switch>'
                    '<rect systemLanguage="ru-RU" width="4" height="4" fill="red"/>'
                    '<rect width="4" height="4" fill="blue"/></switch></svg>')
    out = tmp_path / "l.png"
    assert run(path, "-o", out) == 0
    assert tuple(np.asarray(image(out))[1, 1]) == (0, 0, 255, 255)
    assert run(path, "-o", out, "--languages", "de, ru") == 0
    assert tuple(np.asarray(image(out))[1, 1]) == (255, 0, 0, 255)


def test_stylesheet_and_shape_rendering(svg, tmp_path):
    css = tmp_path / "s.css"
    css.write_text("rect { fill: lime }")
    out = tmp_path / "s.png"
    assert run(svg, "-o", out, "--stylesheet", css) == 0
    assert tuple(np.asarray(image(out))[5, 14]) == (0, 255, 0, 255)
    # crispEdges: no antialiasing, so the disc's edge has only opaque and empty pixels
    assert run(svg, "-o", out, "--shape-rendering", "crispEdges", "-z", 4) == 0
    alpha = np.asarray(image(out))[..., 3]
    assert set(np.unique(alpha)) <= {0, 255}


def test_font_size_sets_the_default_for_text(tmp_path):
    path = tmp_path / "t.svg"
    path.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">'
                    '<text x="5" y="80">H</text></svg>')
    fonts = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
    heights = []
    for size in (12, 48):
        out = tmp_path / f"t{size}.png"
        assert run(path, "-o", out, "--font-size", size, "--use-fonts-dir", fonts,
                   "--skip-system-fonts") == 0
        rows = np.nonzero(np.asarray(image(out))[..., 3].max(axis=1) > 128)[0]
        heights.append(rows.max() - rows.min() + 1)
    assert 3.5 < heights[1] / heights[0] < 4.5        # cap height scales with the font size


def test_help_has_no_docstring_markup(capsys):
    for command in ("render", "suite", "bench", "golden", "font"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        out = capsys.readouterr().out
        assert "``" not in out and ":func:" not in out, command


def test_jobs_means_the_same_everywhere(capsys):
    from vecmsaa.cli.main import build_parser
    from vecmsaa.tools.workers import default_jobs

    parser = build_parser()
    for argv in (["render", "x.svg"], ["golden", "check", "d", "--goldens", "g"]):
        assert parser.parse_args(argv + ["-j", "0"]).jobs == default_jobs()
        assert parser.parse_args(argv + ["--jobs", "3"]).jobs == 3
    assert parser.parse_args(["suite", "d"]).jobs == default_jobs()
    with pytest.raises(SystemExit) as exit_:
        parser.parse_args(["render", "x.svg", "-j", "-1"])
    assert exit_.value.code == 2


@pytest.mark.parametrize("flags, covered", [
    # a vertical edge 0.3 px into column 10: the samples left of it, by the patterns' tables
    # D3D 16 centred: x offsets -4.5, -3.5, -5.5, -7.5, -6.5 (1/16 px)
    ([], 5 / 16),
    (["--pattern", "grid"], 4 / 16),      # 4 x 4 grid: the first column, at 1/8
])
def test_pattern_flag_picks_where_the_samples_lie(tmp_path, flags, covered):
    svg = tmp_path / "edge.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="4">'
                   '<rect width="10.3" height="4"/></svg>')
    assert run(svg, "-o", tmp_path / "o.png", "--samples", 16, "--mode", "persample",
               *flags) == 0
    alpha = np.asarray(image(tmp_path / "o.png"))[..., 3]
    assert (alpha[:, 10] == round(covered * 255)).all()
    assert (alpha[:, :10] == 255).all() and (alpha[:, 11:] == 0).all()


def test_filter_flag_weighs_samples_by_the_tent(tmp_path):
    # tent weights (1 - |dx|)(1 - |dy|) over the D3D 16 offsets: the covered ones' share
    from vecmsaa.raster.sample_patterns import standard_pattern

    offsets = standard_pattern(16)
    w = (1 - abs(offsets[:, 0])) * (1 - abs(offsets[:, 1]))
    covered = w[offsets[:, 0] + 0.5 < 0.3].sum() / w.sum()
    svg = tmp_path / "edge.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="4">'
                   '<rect width="10.3" height="4"/></svg>')
    assert run(svg, "-o", tmp_path / "o.png", "--samples", 16, "--mode", "persample",
               "--filter", "tent") == 0
    alpha = np.asarray(image(tmp_path / "o.png"))[..., 3].astype(int)
    assert (abs(alpha[:, 10] - covered * 255) <= 0.5 + 1e-9).all()


def test_shared_pattern_and_wide_filter_flags(tmp_path, capsys):
    # a vertical edge 0.3 px into column 10, the rectangle reaching far above and below
    svg = tmp_path / "edge.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="4">'
                   '<rect y="-20" width="10.3" height="40"/></svg>')
    # quincunx: pixel 10's centre (10.5) is out, its left corners (x = 10) in: 2 x 1/8
    assert run(svg, "-o", tmp_path / "q.png", "--mode", "persample", "--pattern",
               "quincunx") == 0
    alpha = np.asarray(image(tmp_path / "q.png"))[..., 3].astype(int)
    assert (alpha[:, 10] == 64).all() and (alpha[:, 9] == 255).all() and (alpha[:, 11] == 0).all()
    # the 2 x 2 grid and the tent of radius 1: samples at x = 9.75, 10.25 (in), 10.75, 11.25
    # weigh 1/4, 3/4, 3/4, 1/4 in pixel 10, so it is half covered (the box: 1/2 too, but
    # from 10.25 alone); pixel 9's reach (8.75 .. 10.25) is all in, pixel 11's all out
    assert run(svg, "-o", tmp_path / "t.png", "--mode", "persample", "--pattern", "grid",
               "--samples", 4, "--filter", "tent1") == 0
    alpha = np.asarray(image(tmp_path / "t.png"))[..., 3].astype(int)
    assert (abs(alpha[:, 10] - 127.5) <= 0.5).all()
    assert (alpha[:, 9] == 255).all() and (alpha[:, 11] == 0).all()
    # Mitchell-Netravali: pixel 10 from the 1-D weights of x = 8.75 .. 12.25 (radius 2)
    xs = np.arange(8.75, 12.3, 0.5)
    d = np.abs(xs - 10.5)
    w = np.where(d < 1, (7 * d ** 3 - 12 * d ** 2 + 16 / 3) / 6,
                 np.where(d < 2, (-7 / 3 * d ** 3 + 12 * d ** 2 - 20 * d + 32 / 3) / 6, 0))
    want = w[xs < 10.3].sum() / w.sum()
    assert run(svg, "-o", tmp_path / "m.png", "--mode", "persample", "--pattern", "grid",
               "--samples", 4, "--filter", "mitchell") == 0
    alpha = np.asarray(image(tmp_path / "m.png"))[..., 3].astype(int)
    assert (abs(alpha[:, 10] - want * 255) <= 0.5 + 1e-9).all(), (alpha[:, 10], want * 255)
    capsys.readouterr()
    assert run(svg, "-o", tmp_path / "x.png", "--mode", "a2c", "--pattern", "flipquad") != 0
    err = capsys.readouterr().err.strip()
    assert "a2c" in err and len(err.splitlines()) == 1
