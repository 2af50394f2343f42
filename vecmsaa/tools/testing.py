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
import shlex
from pathlib import Path, PurePosixPath

import pytest

from .compare import FLAT_THRESHOLD, MAX_FRACTION, THRESHOLD

UPDATE_ENV = "VECMSAA_UPDATE_GOLDENS"
DIFF_DIR_ENV = "VECMSAA_GOLDEN_DIFF_DIR"
REPORT_DIR = "golden-report"     # default of --golden-report, under pytest's rootdir

# Set while a pytest session runs with --update-goldens (see pytest_configure below).
_update_requested_by_option = False
# The plugin's record of the session's golden assertions (None when the plugin is not loaded).
_session: "GoldenSession | None" = None


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
    if _session is not None:
        _session.used.add(golden.resolve())
    if updating_goldens() if update is None else update:
        write_png_if_changed(actual, golden)
        diff_path.unlink(missing_ok=True)
        return
    how_to_update = _how_to_accept()
    if not golden.exists():
        write_triptych(diff_path, None, actual, tolerance.threshold, tolerance.strict)
        if _session is not None:
            _session.failed(svg, golden, "missing", "no golden", None, actual, tolerance)
        raise AssertionError(
            f"golden {golden} does not exist (render of {_describe_source(svg)} in {diff_path});"
            f" {how_to_update}")
    expected = read_png_rgba(golden)
    matches, detail = compare_to_golden(actual, expected, tolerance)
    if matches:
        diff_path.unlink(missing_ok=True)  # a triptych from an earlier failure is stale now
        return
    write_triptych(diff_path, expected, actual, tolerance.threshold, tolerance.strict)
    if _session is not None:
        _session.failed(svg, golden, "differs", detail, expected, actual, tolerance)
    raise AssertionError(
        f"render of {_describe_source(svg)} does not match golden {golden}: {detail}\n"
        f"  expected | difference | actual: {diff_path}\n  {how_to_update}")


def _how_to_accept() -> str:
    test = _session.current if _session is not None else None
    if test:
        return (f"to accept the new render as the golden, run: pytest --update-goldens "
                f"{shlex.quote(test)} (or set {UPDATE_ENV}=1)")
    return (f"to accept the new render as the golden, run again with {UPDATE_ENV}=1 "
            "(or pytest --update-goldens)")


# --- pytest plugin -------------------------------------------------------------------------------

class GoldenSession:
    """What the golden assertions of one pytest run did: the goldens they used, and their
    failures, written as they come into one HTML summary (vecmsaa.tools.golden.ReportWriter)."""

    def __init__(self, config, previous):
        self.previous = previous   # an outer run's (pytester runs pytest inside pytest)
        self.update_option = bool(config.getoption("update_goldens", False))
        self.pytest_session = None
        self.rootdir = Path(str(config.rootpath)).resolve()
        self.report_dir = Path(config.getoption("golden_report") or self.rootdir / REPORT_DIR)
        self.used: set[Path] = set()
        self.current: str | None = None        # node id of the running test
        self.report = None
        self.failures = 0
        self.deselected = 0
        self.pending: list = []   # the running test's golden failures: reported if it fails
        self.report_error: str | None = None

    def failed(self, svg, golden: Path, status, detail, expected, actual, tolerance) -> None:
        from .golden import Outcome

        golden = golden.resolve()
        try:
            name = golden.relative_to(self.rootdir)
        except ValueError:   # a golden outside the rootdir: its triptych by name only
            name = Path(golden.name)
        label = f"{self.current or 'golden assertion'}: {_describe_source(svg)}"
        self.pending.append((Outcome(label, PurePosixPath(name.as_posix()), status, detail,
                                     expected, actual), tolerance))

    def test_finished(self, failed: bool) -> None:
        """A test whose golden assertion failed and was caught (pytest.raises) passes, and
        its failure is not one to summarise; one that failed gets its golden failures in."""
        from .golden import GoldenError, ReportWriter

        try:
            for outcome, tolerance in self.pending if failed else ():
                if self.report is None:
                    self.report = ReportWriter(self.report_dir, tolerance,
                                               title="vecmsaa golden images in pytest")
                self.report.tolerance = tolerance
                self.report.add(outcome)
                self.failures += 1
        except (GoldenError, OSError) as exc:   # the summary is an extra: never break the run
            self.report_error = str(exc)
        finally:
            self.pending.clear()

    def unused_goldens(self) -> list[Path]:
        """Golden PNGs no assertion used, in the folders (within the rootdir) of the goldens
        this run used."""
        from .golden import DIFF_SUFFIX

        folders = {g.parent for g in self.used if g.is_relative_to(self.rootdir)}
        unused = []
        for folder in sorted(folders):
            for png in sorted(folder.glob("*.png")):
                if not png.name.endswith(DIFF_SUFFIX) and png.resolve() not in self.used:
                    unused.append(png)
        return unused


def pytest_addoption(parser) -> None:
    group = parser.getgroup("vecmsaa", "vecmsaa golden images")
    group.addoption("--update-goldens", action="store_true", default=False,
                    help=f"rewrite golden PNGs instead of comparing (same as {UPDATE_ENV}=1)")
    group.addoption("--golden-report", metavar="DIR", default=None,
                    help=f"folder of the HTML summary of golden failures (DIR/index.html and "
                         f"a triptych per failure; default: {REPORT_DIR} in the rootdir), "
                         "written at the end of a run with failures")


def pytest_configure(config) -> None:
    global _update_requested_by_option, _session
    _session = GoldenSession(config, _session)
    _update_requested_by_option = _session.update_option


def pytest_sessionstart(session) -> None:
    if _session is not None:
        _session.pytest_session = session


def pytest_runtest_setup(item) -> None:
    if _session is not None:
        _session.current = item.nodeid


def pytest_runtest_teardown(item) -> None:
    if _session is not None:
        _session.current = None


def pytest_runtest_logreport(report) -> None:
    if _session is not None and report.when == "call":
        _session.test_finished(report.failed)


def pytest_deselected(items) -> None:
    if _session is not None:
        _session.deselected += len(items)


def _whole_run(session) -> bool:
    """Whether every collected test ran, so a golden no assertion used is really unused."""
    config = session.config
    option = config.option
    return not (_session.deselected or getattr(option, "keyword", "") or
                getattr(option, "markexpr", "") or getattr(option, "lf", False) or
                any("::" in str(arg) for arg in config.args) or session.shouldstop or
                session.shouldfail)


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    if _session is None or (not _session.used and _session.report is None):
        return
    lines = []
    index = _session.report_dir / "index.html"
    if _session.report is not None and _session.report_error is None:
        try:
            _session.report.finish(None, accept=f"pytest --update-goldens (or {UPDATE_ENV}=1)")
            lines.append(f"{_session.failures} golden assertion(s) failed; summary: {index}")
        except OSError as exc:
            _session.report_error = str(exc)
    if _session.report_error is not None:
        lines.append(f"warning: no summary of the golden failures: {_session.report_error}")
    whole = _session.pytest_session is not None and _whole_run(_session.pytest_session)
    if _session.report is None and index.is_file() and whole:
        index.unlink()   # a summary of failures that are gone would mislead
    if whole and not updating_goldens():
        skipped = len(terminalreporter.stats.get("skipped", ()))
        for png in _session.unused_goldens():
            lines.append(f"warning: golden {png} was used by no test"
                         + (" (skipped tests may use it)" if skipped else ""))
    if lines:
        terminalreporter.write_sep("=", "vecmsaa golden images")
        for line in lines:
            terminalreporter.write_line(line)


def pytest_report_header(config):
    # Regenerating is easy to leave switched on by accident (an exported variable): say so.
    if updating_goldens():
        return (f"vecmsaa: updating golden images instead of comparing "
                f"(--update-goldens or {UPDATE_ENV})")
    return None


def pytest_unconfigure(config) -> None:
    global _update_requested_by_option, _session
    if _session is not None:
        _session = _session.previous
    _update_requested_by_option = _session.update_option if _session is not None else False


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
