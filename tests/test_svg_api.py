"""SVG API and the ``vecmsaa render`` command: sources, sizes, pixels, errors."""
import io
import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from vecmsaa.api import render_svg, render_svg_array
from vecmsaa.svg import SvgError

NS = 'xmlns="http://www.w3.org/2000/svg"'
# a 20 x 10 document: left half opaque green, right half transparent
HALF = f'<svg {NS} width="20" height="10"><rect width="10" height="10" fill="#008000"/></svg>'


def run_cli(*args, stdin=None):
    return subprocess.run([sys.executable, "-m", "vecmsaa.cli", *args], input=stdin,
                          capture_output=True, timeout=300)


def test_sources_are_equivalent(tmp_path):
    path = tmp_path / "half.svg"
    path.write_text(HALF)
    results = [render_svg_array(src, mode="analytic") for src in
               (HALF, HALF.encode(), str(path), path, io.BytesIO(HALF.encode()),
                io.StringIO(HALF))]
    for r in results[1:]:
        assert np.array_equal(r, results[0])


def test_pixels_of_a_half_filled_document():
    arr = render_svg_array(HALF, mode="analytic")
    assert arr.shape == (10, 20, 4) and arr.dtype == np.uint8
    assert (arr[:, :10] == (0, 128, 0, 255)).all()
    assert (arr[:, 10:, 3] == 0).all()


def test_render_svg_returns_rgba_image_with_width_only():
    im = render_svg(HALF, width=40, mode="analytic")
    assert im.mode == "RGBA" and im.size == (40, 20)


def test_background_fills_transparent_pixels():
    arr = render_svg_array(HALF, background="white", mode="analytic")
    assert (arr[:, 15] == 255).all()


def test_reference_png_from_the_suite(shared_dir):
    from vecmsaa.tools.compare import compare_images

    base = shared_dir / "resvg-suite" / "tests" / "masking" / "mask" / "simple-case"
    if not base.with_suffix(".svg").exists():
        pytest.skip("suite test missing")
    ref = Image.open(base.with_suffix(".png")).convert("RGBA")
    im = render_svg(str(base.with_suffix(".svg")), width=ref.width, mode="analytic")
    assert compare_images(im, ref).passed()


@pytest.mark.parametrize("bad", [b"", b"<svg", b"not xml at all", b"<html/>"])
def test_bad_input_is_an_svg_error(bad):
    with pytest.raises(SvgError):
        render_svg_array(bad)


def test_bad_sizes():
    with pytest.raises(SvgError):
        render_svg_array(HALF, width=-5)
    with pytest.raises(SvgError, match="too large"):
        render_svg_array(HALF, zoom=1e6)


def test_missing_file_is_an_svg_error(tmp_path):
    with pytest.raises(SvgError, match="cannot read"):
        render_svg_array(str(tmp_path / "nope.svg"))


# -- command line -------------------------------------------------------------------------------
def test_cli_single_file_with_height_flag(tmp_path):
    src = tmp_path / "half.svg"
    src.write_text(HALF)
    out = tmp_path / "out.png"
    r = run_cli("render", str(src), "-o", str(out), "-h", "30", "--mode", "analytic")
    assert r.returncode == 0, r.stderr
    assert Image.open(out).size == (60, 30)


def test_cli_stdin_to_stdout():
    r = run_cli("render", "-", "-o", "-", "--mode", "analytic", stdin=HALF.encode())
    assert r.returncode == 0, r.stderr
    assert Image.open(io.BytesIO(r.stdout)).size == (20, 10)


def test_cli_batch_with_a_broken_file(tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "good.svg").write_text(HALF)
    (folder / "broken.svg").write_text("<svg")
    out = tmp_path / "out"
    r = run_cli("render", str(folder), "--out-dir", str(out), "--mode", "analytic",
                "--jobs", "2")
    assert r.returncode == 1
    err = r.stderr.decode()
    assert "broken.svg" in err and "malformed XML" in err
    assert sorted(os.listdir(out)) == ["good.png"]


def test_cli_error_leaves_no_file(tmp_path):
    src = tmp_path / "broken.svg"
    src.write_text("<svg")
    out = tmp_path / "out.png"
    r = run_cli("render", str(src), "-o", str(out))
    assert r.returncode != 0
    lines = r.stderr.decode().strip().splitlines()
    assert len(lines) == 1 and "broken.svg" in lines[0]
    assert not out.exists() and os.listdir(tmp_path) == ["broken.svg"]


@pytest.mark.parametrize("attrs, size", [
    ('', (90, 80)), ('width="200"', (90, 80)), ('height="150"', (90, 80)),
    ('width="50%" height="300"', (90, 80)), ('width="abc" height="300"', (90, 80)),
    ('width="300" height="150"', (300, 150)), ('width="200" viewBox="0 0 100 50"', (200, 100)),
])
def test_intrinsic_size_without_a_viewbox_needs_both_lengths(attrs, size):
    # SVG gives a document no size when a width or height is missing or a percentage (of
    # nothing) and no viewBox gives the ratio: the drawing's right and bottom edges are taken
    # instead (as resvg), here a rect to x = 90 and a circle to y = 80
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg xmlns="http://www.w3.org/2000/svg" {attrs}><rect x="10" '
                           'y="10" width="80" height="40"/><circle cx="50" cy="50" r="30"/></svg>')
    assert img.shape[1::-1] == size


@pytest.mark.parametrize("attrs, body, size", [
    # strokes included: the suite's structure/svg/no-size reference scales by 199.5, where
    # its frame's stroke ends (resvg-py 0.5.0 leaves strokes out)
    ('', '<rect width="100" height="50" stroke="black" stroke-width="10"/>', (105, 55)),
    # the output's whole pixels
    ('', '<rect x="20" y="20" width="100.5" height="50.25"/>', (121, 70)),
    # percentages refer to the width and height as far as given: 96% of 150 is 144
    ('width="150"', '<rect x="2" y="2" width="96%" height="96%"/>', (146, 98)),
    ('width="50%" height="400"', '<rect width="96%" height="10%"/>', (48, 40)),
    # nothing drawn: the size given, 100 for what is not
    ('width="150"', '<rect width="100" height="50" transform="scale(0)"/>', (150, 100)),
    # a clip does not shrink the box, a transform moves it (rotated: corners at x = -35.36
    # and 70.71, y up to 106.07)
    ('', '<clipPath id="c"><rect width="10" height="10"/></clipPath>'
         '<rect width="100" height="50" clip-path="url(#c)"/>', (100, 50)),
    ('', '<rect width="100" height="50" transform="rotate(45)"/>', (71, 106)),
    # a shape painted with nothing, or hidden, still takes room, as in resvg (its root
    # group's bounding box has every path's outline): to x = 160 and y = 70
    ('', '<rect x="10" y="10" width="150" height="60" fill="none"/><circle r="20"/>', (160, 70)),
    ('', '<rect x="10" y="10" width="150" height="60" visibility="hidden"/>', (160, 70)),
])
def test_size_from_the_drawing(attrs, body, size):
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg xmlns="http://www.w3.org/2000/svg" {attrs}>{body}</svg>')
    assert img.shape[1::-1] == size


@pytest.mark.parametrize("attrs", [
    # the viewBox's own rectangle, which here is the whole canvas (the user space's origin is
    # at its middle: a rectangle from the origin would cover a quarter)
    'viewBox="-50 -50 100 100"',
    # the root's transform and opacity are the root element's, not the canvas's (CSS
    # Backgrounds 3 §2.11.2: the root's background becomes the canvas background, which
    # covers the canvas; resvg paints it under the root's group)
    'viewBox="0 0 100 100" transform="rotate(45 50 50)"',
    'viewBox="0 0 100 100" opacity="0.5"',
])
def test_the_background_color_of_the_root_covers_the_canvas(attrs):
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" '
                           f'{attrs} style="background-color: #00ff00"/>'.encode())
    assert (img == (0, 255, 0, 255)).all()


@pytest.mark.parametrize("attrs, size", [
    # a missing, `auto` (SVG 2: the replaced element's auto size, from the aspect ratio) or
    # invalid (ignored) dimension follows the other one by the viewBox's ratio, 2:1 here
    ('width="150"', (150, 75)), ('width="150" height="auto"', (150, 75)),
    ('width="150" height="abc"', (150, 75)), ('width="auto" height="60"', (120, 60)),
    ('width="" height="60"', (120, 60)),
])
def test_a_missing_dimension_follows_the_viewbox_ratio(attrs, size):
    from vecmsaa.api import render_svg_array
    img = render_svg_array(f'<svg xmlns="http://www.w3.org/2000/svg" {attrs} '
                           'viewBox="0 0 200 100"/>'.encode())
    assert img.shape[1::-1] == size
