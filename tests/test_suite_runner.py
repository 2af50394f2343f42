"""`vecmsaa suite` on a miniature suite built here: a test passes against its reference or, where
one exists, its exact reference; both counts are reported; $VECMSAA_RESVG_SUITE names the folder.

Truth is by construction: an opaque green square filling the canvas is green everywhere, and a
reference that is red everywhere differs at every pixel."""
import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from vecmsaa.tools.suite import run_suite, summarize

# the missing image draws nothing and warns, as many suite tests do on purpose
GREEN_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="20">'
             '<rect width="20" height="20" fill="#008000"/><image href="missing.png" width="5" '
             'height="5"/></svg>')


def solid(rgb, size=20):
    a = np.zeros((size, size, 4), np.uint8)
    a[..., :3] = rgb
    a[..., 3] = 255
    return Image.fromarray(a)


@pytest.fixture
def mini_suite(tmp_path):
    """shapes/rect/{good, fringe, wrong}: the render is green in all three; 'good' has a green
    reference; 'fringe' a red reference and a green exact reference; 'wrong' red in both."""
    for name, ref, exact in (("good", (0, 128, 0), None), ("fringe", (255, 0, 0), (0, 128, 0)),
                             ("wrong", (255, 0, 0), (255, 0, 0))):
        folder = tmp_path / "tests" / "shapes" / "rect"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / f"{name}.svg").write_text(GREEN_SVG)
        solid(ref).save(folder / f"{name}.png")
        if exact:
            ex = tmp_path / "exact-refs" / "shapes" / "rect"
            ex.mkdir(parents=True, exist_ok=True)
            solid(exact).save(ex / f"{name}.png")
    (tmp_path / "fonts").mkdir()
    return tmp_path


def test_exact_reference_counts_as_a_pass(mini_suite, tmp_path):
    out = tmp_path / "diffs"
    names = ["shapes/rect/good", "shapes/rect/fringe", "shapes/rect/wrong"]
    results = run_suite(str(mini_suite), names, out_dir=str(out))
    assert (results["shapes/rect/good"].plain, results["shapes/rect/good"].passed) == (True, True)
    fringe = results["shapes/rect/fringe"]
    assert (fringe.plain, fringe.exact, fringe.passed) == (False, True, True)
    assert "exact reference" in fringe.detail
    wrong = results["shapes/rect/wrong"]
    assert not wrong.passed
    # a diff image only for the real failure: a label row over three 20 px panels, enlarged
    assert sorted(p.name for p in out.rglob("*.png")) == ["wrong.png"]
    diff = np.asarray(Image.open(out / "shapes" / "rect" / "wrong.png"))
    assert diff.shape[0] > diff.shape[1] / 3 > 20
    table = summarize(results)
    shapes = next(line for line in table.splitlines() if line.startswith("shapes"))
    assert "1/3" in shapes and "2/3" in shapes
    # a pass against one of vecmsaa's own truths counts in the third column only
    own = dict(results, **{"shapes/rect/fringe": fringe._replace(own_truth=True)})
    shapes = next(line for line in summarize(own).splitlines() if line.startswith("shapes"))
    assert shapes.split()[1:6:2] == ["1/3", "1/3", "2/3"]


def test_cli_reads_the_suite_from_the_environment(mini_suite, tmp_path):
    passing = tmp_path / "passing.txt"
    env = dict(os.environ, VECMSAA_RESVG_SUITE=str(mini_suite))
    run = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "suite", "-j", "1", "--failures",
                          "--write-passing", str(passing)],
                         env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert "EXACT shapes/rect/fringe" in run.stdout
    assert "FAIL shapes/rect/wrong" in run.stdout
    # the renders' warnings are not printed, but a failure's detail ends with them
    assert "missing.png" not in run.stderr
    fail = next(line for line in run.stdout.splitlines() if line.startswith("FAIL"))
    assert "warnings:" in fail and "missing.png" in fail
    assert passing.read_text().split() == ["shapes/rect/fringe", "shapes/rect/good"]


def test_cli_without_a_suite_says_so(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "VECMSAA_RESVG_SUITE"}
    run = subprocess.run([sys.executable, "-m", "vecmsaa.cli", "suite"], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 2
    assert "VECMSAA_RESVG_SUITE" in run.stderr and len(run.stderr.strip().splitlines()) == 1


def test_cli_sampling_options(mini_suite):
    env = dict(os.environ, VECMSAA_RESVG_SUITE=str(mini_suite))
    cmd = [sys.executable, "-m", "vecmsaa.cli", "suite", "-j", "1"]
    # a combination no test can render: one line, exit 2, no test run
    bad = subprocess.run(cmd + ["--mode", "a2c", "--pattern", "quincunx"], env=env,
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and "a2c" in bad.stderr
    # an opaque square filling the canvas is green with any pattern of a pixel's own samples
    run = subprocess.run(cmd + ["--pattern", "rooks", "--samples", "16"], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    shapes = next(line for line in run.stdout.splitlines() if line.startswith("shapes"))
    assert shapes.split()[1:6:2] == ["1/3", "2/3", "2/3"]
    # and a wide filter reaches past the canvas's edge, where nothing is drawn: the border
    # pixels are part transparent, so even 'good' fails against its opaque reference
    wide = subprocess.run(cmd + ["--filter", "tent1"], env=env, capture_output=True, text=True,
                          timeout=600)
    shapes = next(line for line in wide.stdout.splitlines() if line.startswith("shapes"))
    assert shapes.split()[1] == "0/3"
