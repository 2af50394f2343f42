"""Golden-image assertions for pytest, and a pytest plugin adding ``--update-goldens``.

    from vecmsaa.tools.testing import assert_matches_golden

    def test_logo():
        assert_matches_golden("art/logo.svg", "tests/goldens/logo.png", width=256)

The render is compared with the golden tolerance of :class:`vecmsaa.tools.golden.Tolerance`
(a pixel is off beyond 48 levels at edges or 8 away from them; at most 0.2% of pixels off)
unless ``threshold``/``flat_threshold``/``max_fraction`` say otherwise.
On a mismatch the assertion writes a triptych (expected | difference | actual) to
``<golden name>.diff.png`` beside the golden, or into ``diff_dir`` / $VECMSAA_GOLDEN_DIFF_DIR.

Goldens are (re)written instead of compared when $VECMSAA_UPDATE_GOLDENS is set to 1 (or any
value but 0/false/no), or when pytest runs with ``--update-goldens``; that option exists when
this module is loaded as a plugin (``-p vecmsaa.tools.testing`` or ``pytest_plugins`` in the root
conftest.py). The plugin also provides the ``assert_golden`` fixture. See docs/golden.md.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from .compare import FLAT_THRESHOLD, MAX_FRACTION, THRESHOLD

UPDATE_ENV = "VECMSAA_UPDATE_GOLDENS"
DIFF_DIR_ENV = "VECMSAA_GOLDEN_DIFF_DIR"

# Set while a pytest session runs with --update-goldens (see pytest_configure below).
_update_requested_by_option = False


def updating_goldens() -> bool:
    """Whether goldens are being regenerated rather than checked."""
    if _update_requested_by_option:
        return True
    return os.environ.get(UPDATE_ENV, "").strip().lower() not in ("", "0", "false", "no")


def diff_path_for(golden, diff_dir=None) -> Path:
    """Where the triptych of a failing ``golden`` goes: ``<stem>.diff.png`` in ``diff_dir``,
    else in $VECMSAA_GOLDEN_DIFF_DIR, else beside the golden."""
    from .golden import DIFF_SUFFIX

    golden = Path(golden)
    folder = diff_dir or os.environ.get(DIFF_DIR_ENV) or golden.parent
    return Path(folder, golden.stem + DIFF_SUFFIX)


def _describe_source(svg) -> str:
    if isinstance(svg, (bytes, bytearray)) or (isinstance(svg, str) and "<" in svg):
        return "SVG document"
    return os.fspath(svg)


def assert_matches_golden(svg, golden, *, threshold: int = THRESHOLD,
                          max_fraction: float = MAX_FRACTION,
                          flat_threshold: int = FLAT_THRESHOLD, diff_dir=None,
                          update: bool | None = None, render=None, **render_options) -> None:
    """Render ``svg`` and assert that it matches the PNG ``golden``.

    ``svg`` is anything :func:`vecmsaa.api.render_svg_array` accepts (a path or SVG text);
    ``render_options`` go to it unchanged (width, height, zoom, mode, samples, background, ...).
    ``update`` forces (True) or forbids (False) regeneration; by default it follows
    $VECMSAA_UPDATE_GOLDENS and ``--update-goldens``. ``render`` replaces the renderer (a
    callable with render_svg_array's signature).
    """
    __tracebackhide__ = True  # pytest: show the caller's line, not this helper's internals
    from .compare import write_triptych
    from .golden import Tolerance, compare_to_golden, read_png_rgba, render_rgba, write_png_if_changed

    golden = Path(golden)
    tolerance = Tolerance(threshold, max_fraction, flat_threshold)
    diff_path = diff_path_for(golden, diff_dir)
    actual = render_rgba(svg, render_options, render)
    if updating_goldens() if update is None else update:
        write_png_if_changed(actual, golden)
        diff_path.unlink(missing_ok=True)
        return
    how_to_update = (f"to accept the new render as the golden, run again with {UPDATE_ENV}=1 "
                     "(or pytest --update-goldens)")
    if not golden.exists():
        write_triptych(diff_path, None, actual, tolerance.threshold, tolerance.strict)
        raise AssertionError(
            f"golden {golden} does not exist (render of {_describe_source(svg)} in {diff_path});"
            f" {how_to_update}")
    expected = read_png_rgba(golden)
    matches, detail = compare_to_golden(actual, expected, tolerance)
    if matches:
        diff_path.unlink(missing_ok=True)  # a triptych from an earlier failure is stale now
        return
    write_triptych(diff_path, expected, actual, tolerance.threshold, tolerance.strict)
    raise AssertionError(
        f"render of {_describe_source(svg)} does not match golden {golden}: {detail}\n"
        f"  expected | difference | actual: {diff_path}\n  {how_to_update}")


# --- pytest plugin -------------------------------------------------------------------------------

def pytest_addoption(parser) -> None:
    group = parser.getgroup("vecmsaa", "vecmsaa golden images")
    group.addoption("--update-goldens", action="store_true", default=False,
                    help=f"rewrite golden PNGs instead of comparing (same as {UPDATE_ENV}=1)")


def pytest_configure(config) -> None:
    global _update_requested_by_option
    _update_requested_by_option = bool(config.getoption("update_goldens", False))


def pytest_report_header(config):
    # Regenerating is easy to leave switched on by accident (an exported variable): say so.
    if updating_goldens():
        return (f"vecmsaa: updating golden images instead of comparing "
                f"(--update-goldens or {UPDATE_ENV})")
    return None


def pytest_unconfigure(config) -> None:
    global _update_requested_by_option
    _update_requested_by_option = False


def _safe_file_name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "golden"


@pytest.fixture
def assert_golden(request):
    """``assert_golden(svg, name=None, **options)``: :func:`assert_matches_golden` with the
    golden at ``<test file dir>/goldens/<test file stem>/<test name>[-<name>].png``."""
    test_file = Path(str(request.node.path))
    folder = test_file.parent / "goldens" / test_file.stem

    def check(svg, name: str | None = None, **options):
        __tracebackhide__ = True
        stem = request.node.name + (f"-{name}" if name else "")
        assert_matches_golden(svg, folder / f"{_safe_file_name(stem)}.png", **options)

    return check
