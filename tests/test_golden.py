"""Golden images: `vecmsaa golden update|check`, vecmsaa.tools.golden and vecmsaa.tools.testing.

Everything renders with the real renderer (vecmsaa.api). Expected pixel counts come from the
test drawings: rectangles on whole pixels, so a colour change alters exactly their area.
"""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from vecmsaa.tools import compare, golden
from vecmsaa.api import render_svg_array
from vecmsaa.cli.main import main as vecmsaa_main
from vecmsaa.output.png import encode_png
from vecmsaa.tools.testing import assert_matches_golden

pytest_plugins = ["pytester"]

RED = "#c03020"
BLUE = "#2040c0"


def rect_svg(x=5, y=5, w=20, h=10, fill=RED, size=(40, 30)) -> str:
    sw, sh = size
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{sw}" height="{sh}" '
            f'viewBox="0 0 {sw} {sh}"><rect x="{x}" y="{y}" width="{w}" height="{h}" '
            f'fill="{fill}"/></svg>')


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


@pytest.fixture
def tree(tmp_path):
    """An SVG directory with a nested file, and an empty golden directory."""
    svgs = tmp_path / "svgs"
    write(svgs / "plain.svg", rect_svg())
    write(svgs / "icons" / "wide.svg", rect_svg(x=2, y=12, w=36, h=6, fill=BLUE))
    goldens = tmp_path / "goldens"
    goldens.mkdir()
    return svgs, goldens


def cli(capsys, *argv):
    """Run the vecmsaa CLI in-process: (exit status, stdout, stderr)."""
    try:
        status = vecmsaa_main([str(a) for a in argv])
    except SystemExit as exc:  # argparse usage errors
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


# --- update ----------------------------------------------------------------------------------------

def test_update_writes_one_png_per_svg_and_records_the_options(tree, capsys):
    svgs, goldens = tree
    status, out, _ = cli(capsys, "golden", "update", svgs, "--goldens", goldens,
                         "-w", 80, "--samples", 16, "--background", "#ffffff")
    assert status == 0
    pngs = sorted(p.relative_to(goldens).as_posix() for p in goldens.rglob("*.png"))
    assert pngs == ["icons/wide.png", "plain.png"]
    expected = render_svg_array(svgs / "plain.svg", width=80, samples=16, background="#ffffff")
    assert np.array_equal(golden.read_png_rgba(goldens / "plain.png"), expected)
    manifest = json.loads((goldens / golden.MANIFEST_NAME).read_text())
    assert manifest["render_options"] == {
        "width": 80, "height": None, "zoom": None, "dpi": 96, "mode": "approx", "samples": 16,
        "background": "#ffffff", "resources_dir": None, "use_fonts_dir": None,
        "skip_system_fonts": False, "font_family": None, "serif_family": None,
        "sans_serif_family": None, "cursive_family": None, "fantasy_family": None,
        "monospace_family": None, "pattern": "d3d", "filter": None, "color_samples": None}
    assert manifest["goldens"] == ["icons/wide.png", "plain.png"]
    assert manifest["vecmsaa_version"]
    assert "2 written" in out


def test_sampling_options_are_recorded_and_checked_with(tree, capsys):
    svgs, goldens = tree
    status, _, _ = cli(capsys, "golden", "update", svgs, "--goldens", goldens,
                       "--pattern", "grid", "--filter", "tent1")
    assert status == 0
    expected = render_svg_array(svgs / "plain.svg", pattern="grid", filter="tent1")
    assert np.array_equal(golden.read_png_rgba(goldens / "plain.png"), expected)
    recorded = golden.read_manifest(goldens)["render_options"]
    assert (recorded["pattern"], recorded["filter"]) == ("grid", "tent1")
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens)[0] == 0
    # a manifest from before these options existed means the defaults
    path = goldens / golden.MANIFEST_NAME
    doc = json.loads(path.read_text())
    for name in ("pattern", "filter", "color_samples"):
        del doc["render_options"][name]
    path.write_text(json.dumps(doc))
    assert golden.read_manifest(goldens)["render_options"]["pattern"] == "d3d"


def test_update_without_render_options_keeps_the_recorded_ones(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens, "--zoom", 2)
    write(svgs / "plain.svg", rect_svg(fill=BLUE))
    status, _, _ = cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    assert status == 0
    assert golden.read_manifest(goldens)["render_options"]["zoom"] == 2
    assert golden.read_png_rgba(goldens / "plain.png").shape == (60, 80, 4)


def test_update_does_not_replace_an_unreadable_manifest_with_defaults(tree, capsys):
    svgs, goldens = tree
    (goldens / golden.MANIFEST_NAME).write_text("{broken")
    status, _, err = cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    assert status == 2 and "unreadable manifest" in err
    assert (goldens / golden.MANIFEST_NAME).read_text() == "{broken"
    # Options given explicitly replace it.
    assert cli(capsys, "golden", "update", svgs, "--goldens", goldens, "--samples", 4)[0] == 0
    assert golden.read_manifest(goldens)["render_options"]["samples"] == 4


def test_update_output_is_byte_identical_across_runs_and_processes(tree, tmp_path, capsys):
    svgs, first = tree
    assert cli(capsys, "golden", "update", svgs, "--goldens", first)[0] == 0
    second = tmp_path / "second"
    # A separate interpreter, so nothing kept in this process can make the bytes agree.
    done = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "golden", "update", str(svgs),
                           "--goldens", str(second)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    files = sorted(p.relative_to(first) for p in first.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(second) for p in second.rglob("*") if p.is_file())
    for rel in files:
        assert (first / rel).read_bytes() == (second / rel).read_bytes(), rel
    # ...and the bytes are those of the shared encoder, not merely stable.
    expected = encode_png(render_svg_array(svgs / "plain.svg"))
    assert (first / "plain.png").read_bytes() == expected


def test_update_shows_a_progress_bar_on_a_terminal_only(tree, capsys, monkeypatch):
    svgs, goldens = tree
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    status, out, err = cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    assert status == 0 and "2 written" in out
    assert "golden update" in err and "2/2" in err          # one step per SVG
    status, out, err = cli(capsys, "golden", "update", svgs, "--goldens", goldens, "-q")
    assert status == 0 and "golden update" not in err


def test_update_reports_svgs_that_fail_to_render(tree, capsys):
    svgs, goldens = tree
    write(svgs / "broken.svg", "<svg")
    status, out, _ = cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    assert status == 1
    assert f"ERROR {svgs.as_posix()}/broken.svg: render failed: malformed XML" in out
    assert not (goldens / "broken.png").exists()
    assert (goldens / "plain.png").exists()


TEXT_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="60" height="30">'
            '<text x="2" y="22" font-family="Noto Sans" font-size="20">Hi</text></svg>')
FIXTURE_FONTS = Path(__file__).resolve().parents[1] / "fixtures" / "fonts"


def test_font_folder_is_recorded_relative_so_the_tree_can_move(tmp_path, capsys):
    project = tmp_path / "project"
    shutil.copytree(FIXTURE_FONTS, project / "fonts")
    write(project / "svgs" / "hi.svg", TEXT_SVG)
    status, _, _ = cli(capsys, "golden", "update", project / "svgs", "--goldens",
                       project / "goldens", "--use-fonts-dir", project / "fonts",
                       "--skip-system-fonts")
    assert status == 0
    options = json.loads((project / "goldens" / golden.MANIFEST_NAME).read_text())[
        "render_options"]
    assert options["use_fonts_dir"] == "../fonts" and options["skip_system_fonts"] is True
    expected = render_svg_array(TEXT_SVG, use_fonts_dir=str(FIXTURE_FONTS),
                                skip_system_fonts=True)
    assert (expected[..., 3] > 0).any()   # the text was drawn with the given font
    assert np.array_equal(golden.read_png_rgba(project / "goldens" / "hi.png"), expected)

    moved = tmp_path / "elsewhere" / "checkout"
    moved.parent.mkdir()
    project.rename(moved)
    assert cli(capsys, "golden", "check", moved / "svgs", "--goldens", moved / "goldens")[0] == 0
    # Without the folder the text would silently fall back to no font: refuse to run instead.
    shutil.rmtree(moved / "fonts")
    status, _, err = cli(capsys, "golden", "check", moved / "svgs", "--goldens", moved / "goldens")
    assert status == 2 and "use_fonts_dir '../fonts' is not a directory" in err


# --- check -----------------------------------------------------------------------------------------

def test_check_passes_when_nothing_changed(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 0
    assert "2 matched, 0 differ, 0 missing, 0 errors" in out


def test_check_uses_the_recorded_render_options(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens, "-h", 90, "--samples", 4)
    assert golden.read_png_rgba(goldens / "plain.png").shape == (90, 120, 4)
    # Rendered at the default size (40x30) the check would report a size difference.
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens)[0] == 0


def test_a_colour_change_fails_and_is_reported(tree, tmp_path, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "icons" / "wide.svg", rect_svg(x=2, y=12, w=36, h=6, fill=RED))
    report = tmp_path / "report"
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens,
                         "--report", report)
    assert status == 1
    # 36x6 pixels changed from blue to red, of 40x30.
    line = f"FAIL {svgs.as_posix()}/icons/wide.svg: 216 of 1200 pixels off (18.000%), " \
           "max channel difference 160"
    fail_lines = [l for l in out.splitlines() if l.startswith("FAIL")]
    assert len(fail_lines) == 1 and fail_lines[0].startswith(line)
    assert "1 matched, 1 differ" in out

    picture = golden.read_png_rgba(report / "icons" / "wide.diff.png")
    zoom = 4   # small images are enlarged (nearest) to at least 128 px: 40 px x 4
    panel_w = 40 * zoom
    assert picture.shape == (30 * zoom, 3 * panel_w + 2 * compare.PANEL_GAP, 4)
    mid = (15 * zoom, 20 * zoom)   # centre of the changed rectangle, in each panel
    panels = [picture[:, i * (panel_w + compare.PANEL_GAP):][:, :panel_w] for i in range(3)]
    assert tuple(panels[0][mid][:3]) == (0x20, 0x40, 0xc0)      # expected: the golden, blue
    assert tuple(panels[2][mid][:3]) == (0xc0, 0x30, 0x20)      # actual: the new render, red
    assert tuple(panels[1][mid][:3]) == tuple(compare.OFF_COLOR)  # difference: off
    assert tuple(panels[1][2 * zoom, 2 * zoom][:3]) != tuple(compare.OFF_COLOR)  # unchanged

    index = (report / "index.html").read_text()
    links = LinkCollector.collect(index)
    assert links == ["icons/wide.diff.png", "icons/wide.diff.png"]   # <a href> and <img src>
    assert all((report / link).is_file() for link in links)
    assert "icons/wide.svg" in index and "216 of 1200 pixels off" in index
    assert "plain.svg" not in index   # only failures are listed
    legend = re.findall(r'style="([^"]*)"', index)
    assert legend and all(re.fullmatch(r"background:rgb\(\d+, \d+, \d+\)", s) for s in legend)


class LinkCollector(HTMLParser):
    """Every href/src in a page, to check the report is self-contained."""

    def __init__(self):
        super().__init__()
        self.links = []

    def handle_starttag(self, tag, attrs):
        self.links += [value for name, value in attrs if name in ("href", "src")]

    @classmethod
    def collect(cls, page: str) -> list:
        parser = cls()
        parser.feed(page)
        return parser.links


def test_report_lists_missing_goldens_and_render_errors_offline(tree, tmp_path, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "new <one>.svg", rect_svg())
    write(svgs / "broken.svg", "<svg")
    report = tmp_path / "report"
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens,
                         "--report", report)
    assert status == 1
    assert f"MISSING {svgs.as_posix()}/new <one>.svg: no golden new <one>.png" in out
    assert re.search(r"^ERROR .*/broken\.svg: render failed: malformed XML", out, re.M)
    index = (report / "index.html").read_text()
    assert "new &lt;one&gt;.svg" in index and "<one>" not in index
    assert "broken.svg" in index
    links = LinkCollector.collect(index)
    assert links and all(not re.match(r"[a-z]+:|/", link) for link in links)
    assert (report / "new <one>.diff.png").is_file()


def test_a_missing_golden_fails(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    (goldens / "plain.png").unlink()
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 1
    assert f"MISSING {svgs.as_posix()}/plain.svg: no golden plain.png" in out


def test_a_size_change_fails(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "plain.svg", rect_svg(size=(40, 31)))
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 1
    assert "plain.svg: size differs: golden 40x30, rendered 40x31" in out


def test_subpixel_shift_is_within_tolerance_but_a_real_move_is_not(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "plain.svg", rect_svg(x=5.1, y=4.9))
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens)[0] == 0
    write(svgs / "plain.svg", rect_svg(x=7))
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens)[0] == 1


# A disc and a translucent sliver: curved and slanted edges, none on whole pixels.
SHAPES_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30" viewBox="0 0 40 30">'
    '<circle cx="20.3" cy="14.6" r="9.7" fill="#c03020"/>'
    '<path d="M2 28 L38 3 L38 8 Z" fill="#2040c0" fill-opacity="0.7"/></svg>')


@pytest.mark.parametrize("other_setting, passes", [
    (["--samples", "8"], True),       # fewer samples: antialiasing noise only
    (["--samples", "4"], True),
    (["--mode", "analytic"], True),   # exact area coverage instead of samples
    (["--mode", "none"], False),      # aliased: every edge pixel is all or nothing
])
def test_antialiasing_noise_is_within_tolerance_but_aliasing_is_not(
        tmp_path, capsys, other_setting, passes):
    svgs = tmp_path / "svgs"
    write(svgs / "shapes.svg", SHAPES_SVG)
    goldens, other = tmp_path / "goldens", tmp_path / "other"
    cli(capsys, "golden", "update", svgs, "--goldens", goldens, "--zoom", 4, "--samples", 16)
    cli(capsys, "golden", "update", svgs, "--goldens", other, "--zoom", 4, *other_setting)
    assert (goldens / "shapes.png").read_bytes() != (other / "shapes.png").read_bytes()
    # Check with the other setting (its manifest) against the goldens made with 16 samples.
    shutil.copy(other / golden.MANIFEST_NAME, goldens / golden.MANIFEST_NAME)
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == (0 if passes else 1), out


@pytest.mark.parametrize("change, passes", [
    ("#c03020", True),     # the same colour: antialiasing noise only
    ("#c03030", False),    # green +16 on the disc
    ("#b03020", False),    # red -16
    ("#c03029", False),    # blue +9: just beyond the flat threshold of 8
    ("#c03028", True),     # blue +8: within it
])
def test_a_16_level_change_of_one_shape_fails_by_default(tmp_path, capsys, change, passes):
    """The disc's colour changes while the golden and the check differ in antialiasing as
    well (16 samples against analytic coverage): the change must show, the noise must not."""
    svgs = tmp_path / "svgs"
    write(svgs / "shapes.svg", SHAPES_SVG)
    goldens = tmp_path / "goldens"
    cli(capsys, "golden", "update", svgs, "--goldens", goldens, "--zoom", 4, "--samples", 16)
    write(svgs / "shapes.svg", SHAPES_SVG.replace("#c03020", change))
    manifest = goldens / golden.MANIFEST_NAME
    recorded = json.loads(manifest.read_text())
    recorded["render_options"]["mode"] = "analytic"
    manifest.write_text(json.dumps(recorded))
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == (0 if passes else 1), out
    # The suite's criterion (no strict threshold away from edges) lets every one of them pass.
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens,
               "--flat-threshold", 48)[0] == 0


def test_tolerance_options(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "plain.svg", rect_svg(fill="#c03050"))   # blue channel +48 (premultiplied)
    check = ("golden", "check", svgs, "--goldens", goldens)
    status, out, _ = cli(capsys, *check)
    assert status == 1
    # The 20x10 rectangle on whole pixels, every pixel changed by 48: the 18x8 inside it are
    # away from edges, the ring around them sits on the edge and passes at 48.
    assert "144 of 1200 pixels off (12.000%), max channel difference 48 " \
           "[threshold 48 (8 away from edges), allowed 0.200%]" in out
    assert cli(capsys, *check, "--flat-threshold", 48)[0] == 0
    assert cli(capsys, *check, "--flat-threshold", 60)[0] == 0   # capped by --threshold
    assert cli(capsys, *check, "--tolerance", "48/48/0.2%")[0] == 0
    assert cli(capsys, *check, "--flat-threshold", 48, "--threshold", 47)[0] == 1
    assert cli(capsys, *check, "--tolerance", "47/0.2%")[0] == 1
    assert cli(capsys, *check, "--max-fraction", "17%")[0] == 0
    assert cli(capsys, *check, "--tolerance", "47/0.17")[0] == 0
    status, out, _ = cli(capsys, *check, "--threshold", 47, "--max-fraction", "0.16")
    assert status == 1
    assert "200 of 1200 pixels off (16.667%), max channel difference 48 " \
           "[threshold 47 (8 away from edges), allowed 16.000%]" in out


def test_orphaned_golden_is_noted_but_not_a_failure(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    (svgs / "plain.svg").unlink()
    status, _, err = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 0
    assert "note: golden plain.png has no SVG any more" in err


@pytest.mark.parametrize("args, message", [
    (["check", "{svgs}"], "--goldens"),
    (["check", "{tmp}/nothing", "--goldens", "{goldens}"], "not a directory"),
    (["check", "{svgs}", "--goldens", "{tmp}/nothing"], "not a directory"),
    (["check", "{svgs}", "--goldens", "{tmp}"], "no manifest"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--threshold", "256"], "0..255"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--max-fraction", "2"], "between 0 and 1"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--tolerance", "48"], "THRESHOLD/FRACTION"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--tolerance", "48/8/1/1%"], "THRESHOLD/FLAT"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--tolerance", "48/1%", "--flat-threshold",
      "3"], "--tolerance replaces"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--tolerance", "48/1%", "--threshold", "3"],
     "--tolerance replaces"),
    (["check", "{goldens}", "--goldens", "{goldens}"], "no SVG files"),
    (["check", "{svgs}", "--goldens", "{goldens}", "--report", "{svgs}/plain.svg"],
     "cannot create the report directory"),
    (["update", "{svgs}", "--goldens", "{svgs}/plain.svg"], "not a directory"),
    (["update", "{svgs}", "--goldens", "{goldens}", "--mode", "best"], "invalid choice"),
    (["update", "{svgs}", "--goldens", "{goldens}", "-w", "0"], "must be a positive number"),
    (["update", "{svgs}", "--goldens", "{goldens}", "--samples", "32"], "must be one of"),
    (["update", "{svgs}", "--goldens", "{goldens}", "--mode", "a2c", "--pattern", "quincunx"],
     "a2c takes"),
    (["update", "{tmp}/nothing", "--goldens", "{goldens}"], "not a directory"),
    (["update", "{svgs}", "--goldens", "{goldens}", "--use-fonts-dir", "{tmp}/none"],
     "--use-fonts-dir"),
    (["update", "{svgs}", "--goldens", "{goldens}", "--background", "nocolour"], "CSS colour"),
    (["compare", "{svgs}"], "invalid choice"),
    ([], "ACTION"),
])
def test_usage_and_input_errors_exit_2(tree, tmp_path, capsys, args, message):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    argv = [a.format(svgs=svgs, goldens=goldens, tmp=tmp_path) for a in args]
    status, out, err = cli(capsys, "golden", *argv)
    assert status == 2
    assert message in err
    assert "FAIL" not in out


@pytest.mark.parametrize("content", ["{not json", '{"format": 99}', "[1]",
                                     '{"format": 1, "render_options": {"colour": 1}}',
                                     '{"format": 1, "render_options": {"samples": "8"}}',
                                     '{"format": 1, "render_options": {"mode": "fast"}}',
                                     '{"format": 1, "render_options": {"width": -3}}',
                                     '{"format": 1, "render_options": {"dpi": "96"}}',
                                     '{"format": 1, "render_options": {"font_family": 3}}',
                                     '{"format": 1, "render_options": {"pattern": "best"}}',
                                     '{"format": 1, "render_options": {"color_samples": 0}}'])
def test_unreadable_manifest_exits_2(tree, capsys, content):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    (goldens / golden.MANIFEST_NAME).write_text(content)
    status, _, err = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 2
    assert golden.MANIFEST_NAME in err


def test_corrupt_golden_is_a_failure(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    (goldens / "plain.png").write_bytes(b"not a png")
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 1
    assert re.search(r"^ERROR .*plain\.svg: golden plain\.png unreadable", out, re.M)


# --- vecmsaa.tools.testing -------------------------------------------------------------------------------

def test_assert_matches_golden_passes_on_the_same_render(tmp_path):
    svg = write(tmp_path / "a.svg", rect_svg())
    golden_png = tmp_path / "a.png"
    golden_png.write_bytes(encode_png(render_svg_array(svg, samples=16)))
    assert_matches_golden(svg, golden_png, samples=4)   # other samples: within tolerance


def test_assert_matches_golden_failure_message_and_triptych(tmp_path):
    svg = write(tmp_path / "a.svg", rect_svg(fill=BLUE))
    golden_png = tmp_path / "goldens" / "a.png"
    golden_png.parent.mkdir()
    golden_png.write_bytes(encode_png(render_svg_array(write(tmp_path / "b.svg", rect_svg()))))
    with pytest.raises(AssertionError) as failure:
        assert_matches_golden(svg, golden_png, update=False)
    message = str(failure.value)
    assert f"render of {svg} does not match golden {golden_png}: 200 of 1200 pixels off" in message
    diff = tmp_path / "goldens" / "a.diff.png"
    assert str(diff) in message and "VECMSAA_UPDATE_GOLDENS=1" in message
    # expected | difference | actual, each 40x30 enlarged 4 times
    assert golden.read_png_rgba(diff).shape == (120, 3 * 160 + 2 * compare.PANEL_GAP, 4)
    # Once the render matches again, the stale triptych goes away.
    write(svg, rect_svg())
    assert_matches_golden(svg, golden_png, update=False)
    assert not diff.exists()


def test_assert_matches_golden_diff_dir_from_argument_and_environment(tmp_path, monkeypatch):
    svg = write(tmp_path / "a.svg", rect_svg(fill=BLUE))
    golden_png = tmp_path / "a.png"
    golden_png.write_bytes(encode_png(render_svg_array(rect_svg())))
    with pytest.raises(AssertionError):
        assert_matches_golden(svg, golden_png, diff_dir=tmp_path / "given", update=False)
    assert (tmp_path / "given" / "a.diff.png").is_file()
    monkeypatch.setenv("VECMSAA_GOLDEN_DIFF_DIR", str(tmp_path / "env"))
    with pytest.raises(AssertionError):
        assert_matches_golden(svg, golden_png, update=False)
    assert (tmp_path / "env" / "a.diff.png").is_file()
    assert not (tmp_path / "a.diff.png").exists()


def test_assert_matches_golden_missing_golden(tmp_path, monkeypatch):
    monkeypatch.delenv("VECMSAA_UPDATE_GOLDENS", raising=False)
    golden_png = tmp_path / "a.png"
    with pytest.raises(AssertionError, match=r"golden .*a\.png does not exist"):
        assert_matches_golden(rect_svg(), golden_png)
    assert not golden_png.exists()


@pytest.mark.parametrize("value, updates", [("1", True), ("yes", True), ("0", False),
                                            ("", False)])
def test_update_goldens_environment_variable(tmp_path, monkeypatch, value, updates):
    monkeypatch.setenv("VECMSAA_UPDATE_GOLDENS", value)
    golden_png = tmp_path / "a.png"
    golden_png.write_bytes(encode_png(render_svg_array(rect_svg(fill=BLUE))))
    if updates:
        assert_matches_golden(rect_svg(), golden_png)
        assert golden_png.read_bytes() == encode_png(render_svg_array(rect_svg()))
    else:
        with pytest.raises(AssertionError):
            assert_matches_golden(rect_svg(), golden_png)


def test_pytest_plugin_option_and_fixture(pytester, monkeypatch):
    monkeypatch.delenv("VECMSAA_UPDATE_GOLDENS", raising=False)
    monkeypatch.delenv("VECMSAA_GOLDEN_DIFF_DIR", raising=False)

    def write_test(fill):
        pytester.makepyfile(test_picture=f"def test_rect(assert_golden):\n"
                                         f"    assert_golden({rect_svg(fill=fill)!r}, samples=4)\n")

    write_test(RED)
    pytester.runpytest("-p", "vecmsaa.tools.testing").assert_outcomes(failed=1)   # no golden yet
    made = pytester.path / "goldens" / "test_picture" / "test_rect.png"
    assert not made.exists()
    updating = pytester.runpytest("-p", "vecmsaa.tools.testing", "--update-goldens")
    updating.assert_outcomes(passed=1)
    updating.stdout.fnmatch_lines(["vecmsaa: updating golden images instead of comparing*"])
    assert made.read_bytes() == encode_png(render_svg_array(rect_svg(), samples=4))
    checking = pytester.runpytest("-p", "vecmsaa.tools.testing")
    checking.assert_outcomes(passed=1)
    assert "updating golden images" not in checking.stdout.str()
    write_test(BLUE)
    changed = pytester.runpytest("-p", "vecmsaa.tools.testing")
    changed.assert_outcomes(failed=1)
    changed.stdout.fnmatch_lines(["*does not match golden*200 of 1200 pixels off*"])
    assert (made.parent / "test_rect.diff.png").is_file()
    assert made.read_bytes() == encode_png(render_svg_array(rect_svg(), samples=4))


def test_parallel_runs_write_the_same_files_and_lines(tree, tmp_path, capsys):
    svgs, serial = tree
    for i in range(4):
        write(svgs / "more" / f"r{i}.svg", rect_svg(x=3 + i, fill=BLUE))
    parallel = tmp_path / "parallel"
    assert cli(capsys, "golden", "update", svgs, "--goldens", serial)[0] == 0
    assert cli(capsys, "golden", "update", svgs, "--goldens", parallel, "-j", 3)[0] == 0
    files = sorted(p.relative_to(serial) for p in serial.rglob("*") if p.is_file())
    assert len(files) == 7
    for rel in files:
        assert (serial / rel).read_bytes() == (parallel / rel).read_bytes(), rel
    write(svgs / "more" / "r2.svg", rect_svg(x=5, fill=RED))
    one = cli(capsys, "golden", "check", svgs, "--goldens", serial)
    three = cli(capsys, "golden", "check", svgs, "--goldens", parallel, "--jobs", 3)
    assert one[0] == three[0] == 1
    assert one[1].replace(str(serial), "G") == three[1].replace(str(parallel), "G")
    assert "FAIL" in one[1]


def test_goldens_from_another_version_are_noted_and_still_compared(tree, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    manifest_path = goldens / golden.MANIFEST_NAME
    manifest = json.loads(manifest_path.read_text())
    manifest["vecmsaa_version"] = "0.0.1"
    manifest_path.write_text(json.dumps(manifest))
    status, _, err = cli(capsys, "golden", "check", svgs, "--goldens", goldens)
    assert status == 0
    assert "note: goldens made with vecmsaa 0.0.1, checking with " in err
    write(svgs / "plain.svg", rect_svg(fill=BLUE))
    assert cli(capsys, "golden", "check", svgs, "--goldens", goldens)[0] == 1


def test_heat_map_marks_off_pixels_red_and_small_differences_blue():
    expected = np.zeros((1, 3, 4), np.uint8)
    expected[:] = (100, 100, 100, 255)
    actual = expected.copy()
    actual[0, 1, 0] += 20      # within the threshold
    actual[0, 2, 0] += 100     # beyond it
    heat = compare.heat_map(expected, actual, threshold=48)
    unchanged, near, off = (tuple(int(c) for c in heat[0, i]) for i in range(3))
    assert unchanged[0] == unchanged[1] == unchanged[2]          # grey: no difference
    assert near[2] > near[0] and near[2] > near[1]               # blue-ish
    assert off == compare.OFF_COLOR


# --- results for CI systems ------------------------------------------------------------------------

def test_junit_and_json_results_parse_back(tree, tmp_path, capsys):
    import xml.etree.ElementTree as ET

    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    write(svgs / "icons" / "wide.svg", rect_svg(x=2, y=12, w=36, h=6, fill=RED))
    write(svgs / "broken.svg", "<svg")
    write(svgs / "new.svg", rect_svg())
    junit, results, report = tmp_path / "junit.xml", tmp_path / "results.json", tmp_path / "r"
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens,
                         "--junit", junit, "--json", results, "--report", report)
    assert status == 1
    accept = f"vecmsaa golden update {svgs.as_posix()} --goldens {goldens.as_posix()}"
    assert out.splitlines()[-1] == f"to accept these renders as the new goldens: {accept}"

    suite = ET.parse(junit).getroot().find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("4", "2", "1")
    cases = {case.get("name"): case for case in suite.iter("testcase")}
    assert sorted(cases) == ["broken.svg", "icons/wide.svg", "new.svg", "plain.svg"]
    assert list(cases["plain.svg"]) == []                      # passed: no child element
    assert cases["icons/wide.svg"].get("classname") == "vecmsaa.golden.icons"
    failure = cases["icons/wide.svg"].find("failure")
    assert failure.get("type") == "differs"
    assert failure.get("message").startswith("216 of 1200 pixels off (18.000%)")
    assert f"{(report / 'icons' / 'wide.diff.png').as_posix()}" in failure.text
    assert accept in failure.text
    assert cases["new.svg"].find("failure").get("type") == "missing"
    error = cases["broken.svg"].find("error")
    assert error.get("message").startswith("render failed: malformed XML")
    assert accept not in error.text        # accepting does not mend a file that fails
    assert all(float(case.get("time")) >= 0 for case in cases.values())

    doc = json.loads(results.read_text())
    assert doc["format"] == 1 and doc["passed"] is False
    assert doc["counts"] == {"total": 4, "pass": 1, "differs": 1, "missing": 1, "error": 1}
    assert doc["tolerance"] == {"threshold": 48, "flat_threshold": 8, "max_fraction": 0.002}
    assert doc["accept"] == accept and doc["render_options"]["samples"] is None
    by_svg = {r["svg"]: r for r in doc["results"]}
    wide = by_svg["icons/wide.svg"]
    assert (wide["status"], wide["off_pixels"], wide["total_pixels"],
            wide["max_channel_difference"]) == ("differs", 216, 1200, 160)
    assert wide["diff_image"] == "icons/wide.diff.png" and (report / wide["diff_image"]).is_file()
    assert by_svg["plain.svg"]["off_pixels"] == 0 and by_svg["plain.svg"]["diff_image"] is None
    assert by_svg["broken.svg"]["off_pixels"] is None and by_svg["broken.svg"]["diff_image"] is None
    assert by_svg["new.svg"]["status"] == "missing"


def test_result_files_say_all_passed(tree, tmp_path, capsys):
    import xml.etree.ElementTree as ET

    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    junit, results = tmp_path / "junit.xml", tmp_path / "results.json"
    status, out, _ = cli(capsys, "golden", "check", svgs, "--goldens", goldens, "-q",
                         "--junit", junit, "--json", results)
    assert status == 0 and "to accept" not in out
    suite = ET.parse(junit).getroot().find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("2", "0", "0")
    assert json.loads(results.read_text())["passed"] is True


def test_result_file_in_a_missing_folder_exits_2_before_rendering(tree, tmp_path, capsys):
    svgs, goldens = tree
    cli(capsys, "golden", "update", svgs, "--goldens", goldens)
    status, out, err = cli(capsys, "golden", "check", svgs, "--goldens", goldens,
                           "--junit", tmp_path / "nowhere" / "junit.xml")
    assert status == 2 and "cannot write here" in err and "ok " not in out


def test_pytest_summary_of_failures_and_unused_goldens(pytester, monkeypatch):
    monkeypatch.delenv("VECMSAA_UPDATE_GOLDENS", raising=False)
    monkeypatch.delenv("VECMSAA_GOLDEN_DIFF_DIR", raising=False)

    def write_tests(fill):
        pytester.makepyfile(test_pictures=(
            "import pytest\n"
            "from vecmsaa.tools.testing import assert_matches_golden\n"
            f"def test_red(assert_golden):\n    assert_golden({rect_svg(fill=fill)!r})\n"
            f"def test_blue(assert_golden):\n    assert_golden({rect_svg(fill=BLUE)!r})\n"
            "def test_caught(assert_golden, tmp_path):\n"
            "    with pytest.raises(AssertionError):\n"
            f"        assert_matches_golden({rect_svg()!r}, tmp_path / 'none.png', update=False)\n"))

    plugin = ("-p", "vecmsaa.tools.testing")
    write_tests(RED)
    pytester.runpytest(*plugin, "--update-goldens").assert_outcomes(passed=3)
    folder = pytester.path / "goldens" / "test_pictures"
    shutil.copy(folder / "test_red.png", folder / "test_removed.png")   # its test is gone
    write_tests(BLUE)
    result = pytester.runpytest(*plugin)
    result.assert_outcomes(passed=2, failed=1)
    report = pytester.path / "golden-report"
    result.stdout.fnmatch_lines([
        "*to accept the new render as the golden, run: pytest --update-goldens "
        "test_pictures.py::test_red*",
        "*vecmsaa golden images*",
        f"1 golden assertion(s) failed; summary: {report / 'index.html'}",
        f"warning: golden {folder / 'test_removed.png'} was used by no test"])
    index = (report / "index.html").read_text()
    links = LinkCollector.collect(index)
    assert links == ["goldens/test_pictures/test_red.diff.png"] * 2
    assert (report / links[0]).is_file()
    assert "test_pictures.py::test_red" in index and "200 of 1200 pixels off" in index
    assert "test_caught" not in index and "test_blue" not in index   # passed
    assert "pytest --update-goldens" in index
    # A partial run cannot tell unused goldens; a passing whole run drops the stale summary.
    partial = pytester.runpytest(*plugin, "-k", "blue")
    assert "was used by no test" not in partial.stdout.str()
    (folder / "test_removed.png").unlink()
    write_tests(RED)
    passing = pytester.runpytest(*plugin)
    passing.assert_outcomes(passed=3)
    assert "vecmsaa golden images" not in passing.stdout.str()
    assert not (report / "index.html").exists()
