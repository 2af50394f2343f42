"""Golden images: render a directory of SVG files, keep the PNGs, and check later renders
against them with the project's comparison criterion (:mod:`vecmsaa.tools.compare`).

Layout of a golden directory (see docs/golden.md)::

    GOLDEN_DIR/vecmsaa-golden.json     render options, vecmsaa version, list of goldens
    GOLDEN_DIR/icons/a.png             golden for SVG_DIR/icons/a.svg

The golden of ``<rel>.svg`` is ``<rel>.png``: the suffix is replaced, as in the resvg test suite, so
goldens may also live beside their SVG files (GOLDEN_DIR = SVG_DIR).

Rendering goes through :func:`vecmsaa.api.render_svg_array`; every function that renders takes a
``render`` callable with that signature so tests and tools can substitute another renderer.
"""
from __future__ import annotations

import html
import json
import math
import os
import shlex
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Callable, Iterator
from urllib.parse import quote

import numpy as np

from .. import __version__
from ..raster.modes import DEFAULT_MODE, FILTERS, MODES, PATTERN_NAMES
from .compare import (FLAT_THRESHOLD, MAX_FRACTION, NEAR_COLOR, OFF_COLOR, THRESHOLD, Comparison,
                      compare_images, write_triptych)
from ..files import write_bytes_atomic
from ..output.png import encode_png

MANIFEST_NAME = "vecmsaa-golden.json"
MANIFEST_FORMAT = 1
#: render options a manifest records, with the values used when an option is not given
DEFAULT_RENDER_OPTIONS = {
    "width": None, "height": None, "zoom": None, "dpi": 96,
    # samples None: the renderer's default for the output's size (16 up to 512 x 512 pixels,
    # else 8), so goldens made at the default keep being checked at the default
    "mode": DEFAULT_MODE, "samples": None, "background": None,
    # where a pixel's samples lie, how they are weighed (None: the pattern's own), CSAA colours
    # (None: one per sample); manifests written before these existed mean these defaults
    "pattern": "d3d", "filter": None, "color_samples": None,
    "resources_dir": None,
    # fonts (see vecmsaa.fonts.db): what text renders with must not depend on the machine
    "use_fonts_dir": None, "skip_system_fonts": False, "font_family": None,
    "serif_family": None, "sans_serif_family": None, "cursive_family": None,
    "fantasy_family": None, "monospace_family": None,
}
#: options naming folders; the manifest stores them relative to itself, so a checkout can move
PATH_OPTIONS = ("resources_dir", "use_fonts_dir")
DIFF_SUFFIX = ".diff.png"

Renderer = Callable[..., np.ndarray]


class GoldenError(Exception):
    """Bad input to a golden run as a whole (missing directory, unreadable manifest): the run
    cannot start, as opposed to one SVG failing."""


@dataclass(frozen=True)
class Tolerance:
    """When a render matches its golden: at most ``max_fraction`` of pixels may be off. A pixel
    is off when a channel (premultiplied, 8 bits) differs by more than ``threshold``, or, away
    from edges (its 3x3 neighbourhood varies by at most FLAT_SPREAD in both images), by more
    than ``flat_threshold``: antialiasing noise is confined to edges, a colour change is not.
    A flat threshold at or above ``threshold`` switches the distinction off."""
    threshold: int = THRESHOLD
    max_fraction: float = MAX_FRACTION
    flat_threshold: int = FLAT_THRESHOLD

    def __post_init__(self):
        for name in ("threshold", "flat_threshold"):
            if not 0 <= getattr(self, name) <= 255:
                raise ValueError(f"{name} must be in 0..255, not {getattr(self, name)}")
        if not 0 <= self.max_fraction <= 1:
            raise ValueError(f"max fraction must be in 0..1, not {self.max_fraction}")

    @property
    def strict(self) -> int:
        """The threshold that applies away from edges (never looser than at edges)."""
        return min(self.threshold, self.flat_threshold)

    def describe(self) -> str:
        away = f" ({self.strict} away from edges)" if self.strict < self.threshold else ""
        return f"threshold {self.threshold}{away}, allowed {100 * self.max_fraction:.3f}%"

    def compare(self, actual: np.ndarray, expected: np.ndarray) -> Comparison:
        return compare_images(actual, expected, self.threshold, self.strict)


# --- rendering and files -------------------------------------------------------------------------

def default_renderer(source, **options) -> np.ndarray:
    # Imported on use: the SVG front end and the numba kernels are heavy.
    from ..api import render_svg_array
    return render_svg_array(source, **options)


def render_options(**given) -> dict:
    """Complete set of recorded render options: ``given`` over the defaults. Unknown names and
    values of the wrong kind are an error (GoldenError), so a typo or a hand-edited manifest
    cannot silently render with something else."""
    unknown = sorted(set(given) - set(DEFAULT_RENDER_OPTIONS))
    if unknown:
        raise GoldenError(f"unknown render option(s): {', '.join(unknown)}")
    options = {**DEFAULT_RENDER_OPTIONS, **given}

    def positive(value, kinds):
        return isinstance(value, kinds) and not isinstance(value, bool) and value > 0

    def number(v):
        return positive(v, (int, float)) and math.isfinite(v)

    def text_or_none(v):
        return v is None or isinstance(v, str)

    checks = {
        "width": lambda v: v is None or number(v),
        "height": lambda v: v is None or number(v),
        "zoom": lambda v: v is None or number(v),
        "dpi": number,
        "mode": lambda v: v in MODES,
        "samples": lambda v: v is None or positive(v, int),
        "pattern": lambda v: v in PATTERN_NAMES,
        "filter": lambda v: v is None or v in FILTERS,
        "color_samples": lambda v: v is None or positive(v, int),
        "skip_system_fonts": lambda v: isinstance(v, bool),
    }
    bad = [f"{name}={value!r}" for name, value in options.items()
           if not checks.get(name, text_or_none)(value)]
    if bad:
        raise GoldenError(f"invalid render option(s): {', '.join(bad)}")
    from ..raster.render import RenderOptions
    coverage = {k: options[k] for k in ("mode", "samples", "pattern", "filter", "color_samples")
                if options[k] is not None}
    try:    # a combination no SVG can render with (a2c with a shared pattern, say)
        RenderOptions(**coverage)
    except ValueError as exc:
        raise GoldenError(f"invalid render options: {exc}") from None
    return options


def render_rgba(source, options: dict, render: Renderer | None = None) -> np.ndarray:
    """Render ``source`` (whatever :func:`vecmsaa.api.render_svg_array` accepts: a path or SVG
    text) to straight RGBA uint8, checking the renderer's result shape."""
    rgba = np.asarray((render or default_renderer)(source, **options))
    if rgba.dtype != np.uint8 or rgba.ndim != 3 or rgba.shape[2] != 4:
        raise TypeError(f"renderer returned {rgba.dtype} array of shape {rgba.shape}, "
                        "expected (H, W, 4) uint8")
    return rgba


def read_png_rgba(path) -> np.ndarray:
    """A PNG file as straight RGBA uint8 (H, W, 4)."""
    from PIL import Image

    with Image.open(path) as image:
        return np.asarray(image.convert("RGBA"))


def write_png_if_changed(rgba: np.ndarray, path) -> bool:
    """Write the PNG unless the file already holds exactly these bytes (keeps timestamps and
    version control quiet). Returns whether the file was written."""
    return write_if_changed(encode_png(rgba), path)


def write_if_changed(data: bytes, path) -> bool:
    try:
        if Path(path).read_bytes() == data:
            return False
    except OSError:
        pass
    write_bytes_atomic(data, path, make_folders=True)
    return True


def find_svgs(svg_dir) -> list[PurePosixPath]:
    """SVG files under ``svg_dir``, recursively, as sorted relative POSIX paths. Hidden
    directories (.git and the like) are skipped; symbolic links to directories are not followed,
    so a link cycle cannot make the walk endless."""
    root = Path(svg_dir)
    if not root.is_dir():
        raise GoldenError(f"{svg_dir}: not a directory")
    found = []
    for folder, subdirs, files in os.walk(root):
        subdirs[:] = [d for d in subdirs if not d.startswith(".")]
        rel_folder = Path(folder).relative_to(root)
        found.extend(PurePosixPath(rel_folder.as_posix(), name) for name in files
                     if name.lower().endswith(".svg") and not name.startswith("."))
    return sorted(found, key=str)


def golden_name(svg_rel: PurePosixPath) -> PurePosixPath:
    """Relative path of the golden PNG for the SVG at ``svg_rel``."""
    return svg_rel.with_suffix(".png")


def diff_name(golden_rel: PurePosixPath) -> PurePosixPath:
    """Relative path of the triptych written for a failing golden ``<name>.png``."""
    return golden_rel.with_name(golden_rel.stem + DIFF_SUFFIX)


# --- manifest ------------------------------------------------------------------------------------

def manifest_bytes(options: dict, goldens: list[PurePosixPath], golden_dir) -> bytes:
    """The manifest as deterministic JSON (sorted keys, fixed layout). Folder options are
    stored relative to ``golden_dir``, where the manifest lives."""
    recorded = render_options(**options)
    for name in PATH_OPTIONS:
        if recorded[name] is not None:
            recorded[name] = Path(os.path.relpath(os.path.abspath(recorded[name]),
                                                  os.path.abspath(golden_dir))).as_posix()
    doc = {
        "format": MANIFEST_FORMAT,
        "vecmsaa_version": __version__,
        "render_options": recorded,
        "goldens": [str(g) for g in sorted(goldens, key=str)],
    }
    return (json.dumps(doc, indent=2, sort_keys=True) + "\n").encode("utf-8")


def read_manifest(golden_dir) -> dict:
    """The manifest of ``golden_dir`` as a dict with ``render_options`` (complete, folders
    resolved against ``golden_dir``), ``goldens`` (relative POSIX paths) and
    ``vecmsaa_version``; GoldenError when it is missing or malformed."""
    path = Path(golden_dir, MANIFEST_NAME)
    if not Path(golden_dir).is_dir():
        raise GoldenError(f"{golden_dir}: not a directory")
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise GoldenError(f"{path}: no manifest (create the goldens with 'vecmsaa golden update')")
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise GoldenError(f"{path}: unreadable manifest: {exc}") from None
    if not isinstance(doc, dict) or doc.get("format") != MANIFEST_FORMAT:
        raise GoldenError(f"{path}: not a version-{MANIFEST_FORMAT} vecmsaa golden manifest")
    options, goldens = doc.get("render_options"), doc.get("goldens", [])
    if not isinstance(options, dict) or not isinstance(goldens, list) \
            or not all(isinstance(g, str) for g in goldens):
        raise GoldenError(f"{path}: malformed manifest (render_options, goldens)")
    try:
        options = render_options(**options)
    except GoldenError as exc:
        raise GoldenError(f"{path}: {exc}") from None
    for name in PATH_OPTIONS:
        if options[name] is not None:
            folder = os.path.normpath(os.path.join(golden_dir, options[name]))
            if not os.path.isdir(folder):
                raise GoldenError(f"{path}: {name} {options[name]!r} is not a directory "
                                  f"(looked for {folder})")
            options[name] = folder
    return {"render_options": options, "goldens": [PurePosixPath(g) for g in goldens],
            "vecmsaa_version": doc.get("vecmsaa_version")}


# --- update --------------------------------------------------------------------------------------

@dataclass
class UpdateResult:
    written: list = field(default_factory=list)     # golden paths (relative) rewritten
    unchanged: list = field(default_factory=list)   # golden paths already holding these bytes
    errors: list = field(default_factory=list)      # (svg path, message) for SVGs not rendered


def update_goldens(svg_dir, golden_dir, options: dict,
                   render: Renderer | None = None,
                   progress: Callable[[str, str | None], None] | None = None, jobs: int = 1,
                   scheduler: str | None = None) -> UpdateResult:
    """Render every SVG under ``svg_dir`` into ``golden_dir`` and record ``options`` in the
    manifest. SVGs that fail to render get no golden and are listed in ``errors``. ``jobs`` > 1
    renders in that many processes, ``scheduler`` on that Dask cluster (vecmsaa.tools.cluster);
    the files written are the same. ``progress(svg path, failure or None)`` after each SVG."""
    options = render_options(**options)
    svgs = find_svgs(svg_dir)
    if Path(golden_dir).exists() and not Path(golden_dir).is_dir():
        raise GoldenError(f"{golden_dir}: not a directory")
    if not svgs:
        raise GoldenError(f"{svg_dir}: no SVG files")
    result = UpdateResult()
    goldens = []
    results = _updates(svg_dir, golden_dir, svgs, options, render, jobs, scheduler)
    for rel, (changed, failure) in zip(svgs, results):
        if progress:
            progress(Path(svg_dir, rel).as_posix(), failure)
        if failure:
            result.errors.append((rel, failure))
            continue
        goldens.append(golden_name(rel))
        (result.written if changed else result.unchanged).append(golden_name(rel))
    manifest = manifest_bytes(options, goldens, golden_dir)
    manifest_path = Path(golden_dir, MANIFEST_NAME)
    if not manifest_path.exists() or manifest_path.read_bytes() != manifest:
        write_bytes_atomic(manifest, manifest_path, make_folders=True)
    return result


def _updates(svg_dir, golden_dir, svgs, options, render, jobs, scheduler) -> Iterator:
    """(golden rewritten, None) or (False, why the render failed) for each SVG, in order."""
    if scheduler is None:
        tasks = [(Path(svg_dir, rel), Path(golden_dir, golden_name(rel)), options, render)
                 for rel in svgs]
        yield from ordered_map(_update_one, tasks, jobs)
        return
    from .cluster import Cluster

    with Cluster(scheduler) as cluster:
        items = ((str(Path(svg_dir, rel)), options) for rel in svgs)
        for rel, png in zip(svgs, cluster.render_pngs(items, render)):
            if isinstance(png, BaseException):
                yield False, render_failure(png)
            else:
                yield write_if_changed(png, Path(golden_dir, golden_name(rel))), None


def _update_one(svg_path, golden_path, options, render) -> tuple[bool, str | None]:
    """(golden rewritten, None) or (False, why the render failed)."""
    try:
        rgba = render_rgba(str(svg_path), options, render)
    except Exception as exc:  # one bad SVG must not stop the others; it is reported
        return False, render_failure(exc)
    return write_png_if_changed(rgba, golden_path), None


def ordered_map(func, argument_tuples: list, jobs: int = 1) -> Iterator:
    """``func(*arguments)`` for each tuple, results in input order. With ``jobs`` > 1 the calls
    run in that many worker processes (``func`` and its arguments must be picklable)."""
    if jobs <= 1 or len(argument_tuples) <= 1:
        for arguments in argument_tuples:
            yield func(*arguments)
        return
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(max_workers=min(jobs, len(argument_tuples))) as pool:
        yield from pool.map(func, *zip(*argument_tuples))


def render_failure(exc: BaseException) -> str:
    """One line for a render that raised: input errors (SvgError is a ValueError, unreadable
    files OSError) by their message, anything else marked as an internal error."""
    message = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, (ValueError, OSError)):
        return f"render failed: {message}"
    return f"render failed (internal error {type(exc).__name__}): {message}"


# --- check ---------------------------------------------------------------------------------------

PASS, DIFFERS, MISSING, ERROR = "pass", "differs", "missing", "error"


@dataclass
class Outcome:
    """Result of checking one SVG. ``expected``/``actual`` are kept only for failures, so a
    report can show them; ``comparison`` holds the measured numbers (without the pixel map)
    when both images were there; ``seconds`` is the time to render, when rendered here."""
    svg: PurePosixPath
    golden: PurePosixPath
    status: str
    detail: str = ""
    expected: np.ndarray | None = None
    actual: np.ndarray | None = None
    comparison: Comparison | None = None
    seconds: float | None = None

    @property
    def failed(self) -> bool:
        return self.status != PASS

    def line(self, svg_dir="") -> str:
        """One line naming the file and what was measured, for logs."""
        label = {PASS: "ok", DIFFERS: "FAIL", MISSING: "MISSING", ERROR: "ERROR"}[self.status]
        name = Path(svg_dir, self.svg).as_posix() if svg_dir else str(self.svg)
        return f"{label} {name}: {self.detail}" if self.detail else f"{label} {name}"


def difference_detail(comparison: Comparison, expected: np.ndarray, actual: np.ndarray,
                      tolerance: Tolerance) -> str:
    """What was measured, in one line."""
    if not comparison.same_size:
        return (f"size differs: golden {expected.shape[1]}x{expected.shape[0]}, "
                f"rendered {actual.shape[1]}x{actual.shape[0]}")
    return f"{comparison.describe()} [{tolerance.describe()}]"


def compare_to_golden(actual: np.ndarray, expected: np.ndarray,
                      tolerance: Tolerance) -> tuple[bool, str]:
    """(matches, one-line description of the measured difference)."""
    comparison = tolerance.compare(actual, expected)
    return (comparison.passed(tolerance.max_fraction),
            difference_detail(comparison, expected, actual, tolerance))


def check_one(svg_path, golden_path, options: dict, tolerance: Tolerance,
              render: Renderer | None = None, svg_rel=None, golden_rel=None) -> Outcome:
    start = time.perf_counter()
    try:
        actual = render_rgba(str(svg_path), options, render)
    except Exception as exc:  # reported as this SVG's failure; the other SVGs still run
        actual = exc
    outcome = judge(actual, golden_path, tolerance, svg_rel or Path(svg_path).name,
                    golden_rel or Path(golden_path).name)
    outcome.seconds = time.perf_counter() - start
    return outcome


def judge(actual, golden_path, tolerance: Tolerance, svg_rel, golden_rel) -> Outcome:
    """The outcome for a render (an RGBA array, or the exception rendering raised) of the
    SVG whose golden is ``golden_path``."""
    svg_rel, golden_rel = PurePosixPath(svg_rel), PurePosixPath(golden_rel)
    if isinstance(actual, BaseException):
        return Outcome(svg_rel, golden_rel, ERROR, render_failure(actual))
    if not Path(golden_path).exists():
        return Outcome(svg_rel, golden_rel, MISSING, f"no golden {golden_rel}", actual=actual)
    try:
        expected = read_png_rgba(golden_path)
    except Exception as exc:  # PIL raises several types for corrupt files
        return Outcome(svg_rel, golden_rel, ERROR,
                       f"golden {golden_rel} unreadable: {' '.join(str(exc).split())}",
                       actual=actual)
    comparison = tolerance.compare(actual, expected)
    detail = difference_detail(comparison, expected, actual, tolerance)
    comparison.off_map = None   # outcomes travel between processes: keep them small
    if comparison.passed(tolerance.max_fraction):
        return Outcome(svg_rel, golden_rel, PASS, detail, comparison=comparison)
    return Outcome(svg_rel, golden_rel, DIFFERS, detail, expected, actual, comparison)


@dataclass
class CheckPlan:
    """What a check will do: the recorded options, the SVGs, and goldens whose SVG is gone."""
    svg_dir: Path
    golden_dir: Path
    options: dict
    svgs: list
    orphans: list     # golden paths listed in the manifest with no SVG any more
    recorded_version: str | None


def plan_check(svg_dir, golden_dir) -> CheckPlan:
    """Validate the inputs of a check before any rendering (GoldenError on bad input)."""
    svgs = find_svgs(svg_dir)
    manifest = read_manifest(golden_dir)
    if not svgs:
        raise GoldenError(f"{svg_dir}: no SVG files")
    current = {golden_name(s) for s in svgs}
    orphans = [g for g in manifest["goldens"] if g not in current]
    return CheckPlan(Path(svg_dir), Path(golden_dir), manifest["render_options"], svgs,
                     orphans, manifest["vecmsaa_version"])


def check_goldens(plan: CheckPlan, tolerance: Tolerance = Tolerance(),
                  render: Renderer | None = None, jobs: int = 1,
                  scheduler: str | None = None) -> Iterator[Outcome]:
    """Render each SVG of ``plan`` with the recorded options and compare it with its golden,
    yielding outcomes in order, one by one (so callers can report progress and drop images).
    ``jobs`` > 1 renders in that many processes, ``scheduler`` on that Dask cluster (the
    comparison then runs here)."""
    if scheduler is None:
        tasks = [(plan.svg_dir / rel, plan.golden_dir / golden_name(rel), plan.options,
                  tolerance, render, rel, golden_name(rel)) for rel in plan.svgs]
        yield from ordered_map(check_one, tasks, jobs)
        return
    from .cluster import Cluster

    with Cluster(scheduler) as cluster:
        items = ((str(plan.svg_dir / rel), plan.options) for rel in plan.svgs)
        for rel, actual in zip(plan.svgs, cluster.render_arrays(items, render)):
            yield judge(actual, plan.golden_dir / golden_name(rel), tolerance, rel,
                        golden_name(rel))


# --- triptych and report -------------------------------------------------------------------------

_INDEX_STYLE = """
body { font-family: sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; }
td, th { border: 1px solid #bbb; padding: .4em .6em; text-align: left; vertical-align: top; }
td.name { font-family: monospace; }
td.differs, td.missing, td.error { color: #a00; }
img { image-rendering: pixelated; max-width: 90vw; }
.legend span { display: inline-block; width: 1em; height: 1em; vertical-align: middle; }
"""


class ReportWriter:
    """Writes ``<report dir>/<rel>.diff.png`` for each failure as it comes, then an offline
    ``index.html`` (relative links only, no scripts or external resources) listing them."""

    def __init__(self, report_dir, tolerance: Tolerance, title: str = "vecmsaa golden check"):
        self.report_dir = Path(report_dir)
        self.title = title
        try:  # fail before any rendering when the report cannot be written
            self.report_dir.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise GoldenError(f"{report_dir}: cannot create the report directory: "
                              f"{exc.strerror or exc}") from None
        self.tolerance = tolerance
        self.rows: list[tuple[Outcome, PurePosixPath | None]] = []
        self.total = 0

    def add(self, outcome: Outcome) -> None:
        self.total += 1
        if not outcome.failed:
            return
        image = None
        if outcome.expected is not None or outcome.actual is not None:
            image = diff_name(outcome.golden)
            write_triptych(self.report_dir / image, outcome.expected, outcome.actual,
                           self.tolerance.threshold, self.tolerance.strict)
        self.rows.append((outcome, image))

    def finish(self, options: dict | None, orphans=(), accept: str | None = None) -> Path:
        """Write index.html. ``options``: the render options all SVGs used (None when they
        vary, as in pytest); ``accept``: the command that accepts the failing renders."""
        failed = len(self.rows)
        esc = html.escape
        parts = [
            "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
            f"<title>{esc(self.title)}</title>", f"<style>{_INDEX_STYLE}</style>",
            "</head>", "<body>", f"<h1>{esc(self.title)}</h1>",
            f"<p>{self.total} SVG files: {self.total - failed} matched, {failed} failed.</p>"
            if options is not None else f"<p>{failed} failed.</p>",
            "<p>" + (f"Render options: {esc(json.dumps(options, sort_keys=True))}<br>"
                     if options is not None else "")
            + f"Tolerance: {esc(self.tolerance.describe())} of pixels off.</p>",
        ]
        if orphans:
            parts.append("<p>Goldens without an SVG any more: "
                         + ", ".join(f"<code>{esc(str(o))}</code>" for o in orphans) + "</p>")
        if self.rows and accept:
            parts.append(f"<p>To accept these renders as the new goldens: "
                         f"<code>{esc(accept)}</code></p>")
        if self.rows:
            parts += [
                '<p class="legend">Each image: expected | difference | actual. Difference: '
                f'<span style="background:rgb{tuple(OFF_COLOR)}"></span> off, '
                f'<span style="background:rgb{tuple(NEAR_COLOR)}"></span> within it.</p>',
                "<table>", "<tr><th>SVG</th><th>Result</th><th>expected | difference | actual"
                "</th></tr>"]
            for outcome, image in self.rows:
                cell = ""
                if image is not None:
                    href = esc(quote(str(image)))
                    cell = f'<a href="{href}"><img src="{href}" alt="{esc(str(image))}"></a>'
                parts.append(
                    f'<tr><td class="name">{esc(str(outcome.svg))}</td>'
                    f'<td class="{outcome.status}">{esc(outcome.status)}: '
                    f'{esc(outcome.detail)}</td><td>{cell}</td></tr>')
            parts.append("</table>")
        else:
            parts.append("<p>All renders match their goldens.</p>")
        parts += ["</body>", "</html>", ""]
        index = self.report_dir / "index.html"
        write_bytes_atomic("\n".join(parts).encode("utf-8"), index, make_folders=True)
        return index


# --- result files for CI systems -----------------------------------------------------------------

RESULTS_FORMAT = 1


def accept_command(svg_dir, golden_dir) -> str:
    """The command that makes the current renders the goldens (keeping the recorded options)."""
    return (f"vecmsaa golden update {shlex.quote(Path(svg_dir).as_posix())} "
            f"--goldens {shlex.quote(Path(golden_dir).as_posix())}")


class ResultFiles:
    """Collects the outcomes of a check (numbers and lines, no images) and writes them at the
    end as JUnit XML (``junit``) and/or JSON (``json_path``), each written whole."""

    def __init__(self, junit=None, json_path=None):
        self.junit, self.json_path = junit, json_path
        for path in (junit, json_path):
            if path is not None:
                folder = Path(path).resolve().parent
                if not folder.is_dir() or Path(path).is_dir():
                    raise GoldenError(f"{path}: cannot write here (no such folder, or a folder)")
        self.outcomes: list[Outcome] = []
        self.pictured: set = set()   # goldens whose failure a report shows in a triptych

    def add(self, outcome: Outcome) -> None:
        self.outcomes.append(Outcome(outcome.svg, outcome.golden, outcome.status,
                                     outcome.detail, comparison=outcome.comparison,
                                     seconds=outcome.seconds))
        if outcome.failed and (outcome.expected is not None or outcome.actual is not None):
            self.pictured.add(outcome.golden)

    def counts(self) -> dict:
        counts = dict.fromkeys((PASS, DIFFERS, MISSING, ERROR), 0)
        for outcome in self.outcomes:
            counts[outcome.status] += 1
        return counts

    def finish(self, plan: CheckPlan, tolerance: Tolerance, report_dir=None) -> None:
        accept = accept_command(plan.svg_dir, plan.golden_dir)
        if self.json_path is not None:
            write_bytes_atomic(self._json(plan, tolerance, report_dir, accept), self.json_path)
        if self.junit is not None:
            write_bytes_atomic(self._junit(plan, tolerance, report_dir, accept), self.junit)

    def _json(self, plan, tolerance, report_dir, accept) -> bytes:
        def result(o: Outcome) -> dict:
            c = o.comparison
            shown = report_dir is not None and o.golden in self.pictured
            return {
                "svg": str(o.svg), "golden": str(o.golden), "status": o.status,
                "detail": o.detail,
                "off_pixels": c.off_pixels if c and c.same_size else None,
                "total_pixels": c.total_pixels if c and c.same_size else None,
                "max_channel_difference": c.max_diff if c and c.same_size else None,
                "seconds": None if o.seconds is None else round(o.seconds, 4),
                "diff_image": str(diff_name(o.golden)) if shown else None,
            }

        doc = {
            "format": RESULTS_FORMAT, "vecmsaa_version": __version__,
            "svg_dir": plan.svg_dir.as_posix(), "golden_dir": plan.golden_dir.as_posix(),
            "render_options": plan.options,
            "tolerance": {"threshold": tolerance.threshold,
                          "flat_threshold": tolerance.strict,
                          "max_fraction": tolerance.max_fraction},
            "counts": {"total": len(self.outcomes), **self.counts()},
            "passed": all(not o.failed for o in self.outcomes),
            "orphans": [str(o) for o in plan.orphans],
            "report": None if report_dir is None else str(Path(report_dir, "index.html")),
            "accept": accept,
            "results": [result(o) for o in self.outcomes],
        }
        return (json.dumps(doc, indent=2, sort_keys=True) + "\n").encode("utf-8")

    def _junit(self, plan, tolerance, report_dir, accept) -> bytes:
        counts = self.counts()
        failures, errors = counts[DIFFERS] + counts[MISSING], counts[ERROR]
        total_time = sum(o.seconds or 0.0 for o in self.outcomes)
        attrs = {"name": "vecmsaa golden check", "tests": str(len(self.outcomes)),
                 "failures": str(failures), "errors": str(errors), "skipped": "0",
                 "time": f"{total_time:.3f}"}
        root = ET.Element("testsuites", attrs)
        suite = ET.SubElement(root, "testsuite", attrs)
        properties = ET.SubElement(suite, "properties")
        for name, value in (("tolerance", tolerance.describe()),
                            ("render_options", json.dumps(plan.options, sort_keys=True)),
                            ("golden_dir", plan.golden_dir.as_posix()),
                            ("vecmsaa_version", __version__)):
            ET.SubElement(properties, "property", {"name": name, "value": value})
        for o in self.outcomes:
            folder = o.svg.parent.as_posix()
            case = ET.SubElement(suite, "testcase", {
                "classname": "vecmsaa.golden" + ("" if folder == "." else
                                                 "." + folder.replace("/", ".")),
                "name": str(o.svg), "file": (plan.svg_dir / o.svg).as_posix()})
            if o.seconds is not None:
                case.set("time", f"{o.seconds:.3f}")
            if not o.failed:
                continue
            text = [f"{o.line(plan.svg_dir)}"]
            if report_dir is not None and o.golden in self.pictured:
                text.append(f"expected | difference | actual: "
                            f"{Path(report_dir, diff_name(o.golden)).as_posix()}")
            if o.status != ERROR:   # a render that fails is not fixed by accepting
                text.append(f"to accept the new render as the golden: {accept}")
            element = ET.SubElement(case, "error" if o.status == ERROR else "failure",
                                    {"type": o.status, "message": o.detail})
            element.text = "\n".join(text)
        ET.indent(root)
        return ET.tostring(root, encoding="utf-8", xml_declaration=True) + b"\n"
