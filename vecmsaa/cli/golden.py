"""``vecmsaa golden update|check``: golden images for CI (docs/golden.md).

Exit status of ``check``: 0 when every render matches its golden, 1 when any differs, has no
golden or fails to render, 2 on usage or input errors (missing directory, unreadable manifest).
"""
from __future__ import annotations

import argparse
import os
import sys


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number: {text!r}")
    return value


def _color(text: str) -> str:
    """A CSS colour, kept as written (the manifest records it; the renderer parses it)."""
    from vecmsaa.svg.color import parse_color

    if not isinstance(parse_color(text), tuple):
        raise argparse.ArgumentTypeError(f"not a CSS colour: {text!r}")
    return text


def _size(text: str):
    """A positive number of pixels; whole numbers stay int so the manifest reads 300, not 300.0."""
    value = _positive_float(text)
    return int(value) if value.is_integer() else value


def _threshold(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if not 0 <= value <= 255:
        raise argparse.ArgumentTypeError(f"must be in 0..255: {text!r}")
    return value


def _fraction(text: str) -> float:
    """A fraction of pixels: ``0.002`` or ``0.2%``."""
    percent = text.endswith("%")
    try:
        value = float(text[:-1] if percent else text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a fraction or percentage: {text!r}") from None
    if percent:
        value /= 100
    if not 0 <= value <= 1:
        raise argparse.ArgumentTypeError(f"must be between 0 and 1 (0%% and 100%%): {text!r}")
    return value


def _tolerance(text: str) -> tuple[int, int | None, float]:
    """Combined ``THRESHOLD[/FLAT]/FRACTION``, e.g. ``48/8/0.2%`` or ``32/0.001``."""
    parts = text.split("/")
    if len(parts) not in (2, 3):
        raise argparse.ArgumentTypeError(
            f"expected THRESHOLD/FRACTION or THRESHOLD/FLAT/FRACTION, e.g. 48/8/0.2%: {text!r}")
    flat = _threshold(parts[1]) if len(parts) == 3 else None
    return _threshold(parts[0]), flat, _fraction(parts[-1])


def _common(parser: argparse.ArgumentParser) -> None:
    # -h is the render height (as in 'vecmsaa render'), so help is --help only.
    parser.add_argument("--help", action="help", help="show this help message and exit")
    parser.add_argument("svg_dir", metavar="SVG_DIR", help="directory searched recursively for *.svg")
    parser.add_argument("--goldens", metavar="GOLDEN_DIR", required=True,
                        help="directory of the golden PNGs and their manifest "
                             "(SVG_DIR/a/b.svg has the golden GOLDEN_DIR/a/b.png)")
    from .options import add_jobs_option
    add_jobs_option(parser)
    from .options import add_scheduler_option
    add_scheduler_option(parser)


def add_parser(subparsers) -> None:
    from vecmsaa.tools.compare import FLAT_THRESHOLD, MAX_FRACTION, THRESHOLD

    golden = subparsers.add_parser(
        "golden", help="render SVGs to golden PNGs and check renders against them",
        description="Golden images for CI: 'update' renders every SVG under a directory to "
                    "PNGs and records the render options; 'check' renders again with those "
                    "options and compares. See docs/golden.md.",
        epilog=f"Default tolerance of 'check': a pixel is off beyond {THRESHOLD} levels on "
               f"edges and {FLAT_THRESHOLD} away from them, at most {100 * MAX_FRACTION:g}% "
               "of pixels off: antialiasing noise passes, a 16-level colour change of one "
               "shape fails. 'check --junit FILE --json FILE' writes results for CI systems; "
               "after a failure, 'vecmsaa golden update SVG_DIR --goldens GOLDEN_DIR' (or "
               "pytest --update-goldens) accepts the new renders. With --scheduler "
               "tcp://HOST:8786 both actions render on a Dask cluster (docs/cluster.md). "
               "'vecmsaa golden ACTION --help' lists the options.")
    actions = golden.add_subparsers(dest="golden_action", metavar="ACTION", required=True)

    update = actions.add_parser(
        "update", add_help=False, help="(re)create the golden PNGs and their manifest",
        description="Render every SVG under SVG_DIR to GOLDEN_DIR/<relative path>.png and record "
                    "the render options in GOLDEN_DIR/vecmsaa-golden.json. Without any render "
                    "option, the options already recorded there are kept (defaults if none).")
    _common(update)
    update.add_argument("-q", "--quiet", action="store_true",
                        help="no progress bar (failures and the summary are still printed)")
    from vecmsaa.cli.render import FONT_FLAGS

    render = update.add_argument_group(
        "render options", "Recorded in the manifest and used by 'check'; folders are recorded "
                          "relative to GOLDEN_DIR.")
    render.add_argument("-w", "--width", type=_size, help="output width in pixels")
    render.add_argument("-h", "--height", type=_size, help="output height in pixels")
    render.add_argument("-z", "--zoom", type=_positive_float, help="scale factor")
    render.add_argument("--dpi", type=_positive_float, help="resolution for mm, in, pt (96)")
    from .options import add_coverage_options, add_sampling_options
    add_coverage_options(render)
    add_sampling_options(render)
    render.add_argument("--background", type=_color, metavar="COLOR",
                        help="CSS background colour (default: transparent)")
    render.add_argument("--resources-dir", metavar="DIR",
                        help="extra folder images and CSS may be loaded from")
    for flag, dest, metavar, text in FONT_FLAGS:
        render.add_argument(flag, dest=dest, metavar=metavar, help=text)
    render.add_argument("--skip-system-fonts", action="store_true", default=None,
                        help="use only fonts from --use-fonts-dir (goldens that do not depend "
                             "on the machine's fonts)")

    check = actions.add_parser(
        "check", add_help=False, help="render again and compare with the goldens",
        description="Render every SVG under SVG_DIR with the options recorded in GOLDEN_DIR and "
                    "compare with its golden. Exit 0 when all match, 1 when any differs, has "
                    "no golden or fails to render, 2 on usage or input errors. After a "
                    "failure, 'vecmsaa golden update SVG_DIR --goldens GOLDEN_DIR' accepts the "
                    "new renders (keeping the recorded options).")
    _common(check)
    check.add_argument("--report", metavar="DIR",
                       help="write DIR/a/b.diff.png (expected | difference | actual) "
                            "for each failing SVG_DIR/a/b.svg and DIR/index.html summarising them")
    from vecmsaa.tools.compare import FLAT_SPREAD, FLAT_THRESHOLD, MAX_FRACTION, THRESHOLD

    tol = check.add_argument_group(
        "tolerance",
        "A pixel is off when a channel (premultiplied, 8 bits) differs by more than the "
        f"threshold ({THRESHOLD}), or, away from edges (its 3x3 neighbourhood varies by at "
        f"most {FLAT_SPREAD} levels in both images), by more than the flat threshold "
        f"({FLAT_THRESHOLD}); a render matches when at most the given fraction of its pixels "
        f"({100 * MAX_FRACTION:g}%) is off. The defaults pass antialiasing noise (another "
        "sample count or coverage mode, a sub-pixel shift) and catch a one-colour change of "
        "16 levels on one shape, a moved or missing shape, aliasing and size changes.")
    tol.add_argument("--threshold", type=_threshold, help="channel difference at edges, 0..255")
    tol.add_argument("--flat-threshold", type=_threshold, metavar="N",
                     help="channel difference away from edges, 0..255 (at or above "
                          "--threshold: no distinction, the suite's criterion)")
    tol.add_argument("--max-fraction", type=_fraction, metavar="FRACTION",
                     help="fraction of pixels allowed off: 0.002 or 0.2%%")
    tol.add_argument("--tolerance", type=_tolerance, metavar="THRESHOLD[/FLAT]/FRACTION",
                     help=f"all at once, e.g. {THRESHOLD}/{FLAT_THRESHOLD}/"
                          f"{100 * MAX_FRACTION:g}%% (the default); without FLAT the flat "
                          "threshold keeps its default")
    check.add_argument("--junit", metavar="FILE",
                       help="write the results as JUnit XML (one test case per SVG) for CI")
    check.add_argument("--json", metavar="FILE",
                       help="write the results as JSON (counts, tolerance, and per SVG the "
                            "status and measured difference; docs/golden.md)")
    check.add_argument("-q", "--quiet", action="store_true",
                       help="print only failures and the summary")


def run(args) -> int:
    from vecmsaa.tools import golden
    from vecmsaa.tools.cluster import ClusterError

    try:
        if args.golden_action == "update":
            return _update(args, golden)
        return _check(args, golden)
    except (golden.GoldenError, ClusterError) as exc:
        print(f"vecmsaa golden: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # writing goldens or the report (renders report their own errors)
        print(f"vecmsaa golden: error: {exc}", file=sys.stderr)
        return 2


def _update(args, golden) -> int:
    given = {name: getattr(args, name) for name in golden.DEFAULT_RENDER_OPTIONS
             if getattr(args, name, None) is not None}
    for name in golden.PATH_OPTIONS:
        if name in given and not os.path.isdir(given[name]):
            raise golden.GoldenError(f"--{name.replace('_', '-')} {given[name]}: "
                                     "not a directory")
    if given:
        options = golden.render_options(**given)
    elif os.path.exists(os.path.join(args.goldens, golden.MANIFEST_NAME)):
        # An unreadable manifest stops here (exit 2) rather than being replaced by defaults.
        options = golden.read_manifest(args.goldens)["render_options"]
        print("using the render options recorded in the manifest", file=sys.stderr)
    else:
        options = golden.render_options()
    from .progress import Progress

    def progress(svg, failure):
        if failure:
            bar.write(f"ERROR {svg}: {failure}", file=sys.stdout)
        bar.advance(svg)
    with Progress(len(golden.find_svgs(args.svg_dir)), "golden update", args.quiet) as bar:
        result = golden.update_goldens(args.svg_dir, args.goldens, options, progress=progress,
                                       jobs=args.jobs, scheduler=args.scheduler)
    print(f"golden update: {len(result.written)} written, {len(result.unchanged)} unchanged, "
          f"{len(result.errors)} failed to render")
    return 1 if result.errors else 0


def _check(args, golden) -> int:
    from vecmsaa import __version__

    if args.tolerance and (args.threshold is not None or args.max_fraction is not None
                           or args.flat_threshold is not None):
        print("vecmsaa golden check: error: --tolerance replaces --threshold, "
              "--flat-threshold and --max-fraction; give one or the others", file=sys.stderr)
        return 2
    threshold, flat, max_fraction = args.tolerance or (args.threshold, args.flat_threshold,
                                                       args.max_fraction)
    tolerance = golden.Tolerance(
        golden.THRESHOLD if threshold is None else threshold,
        golden.MAX_FRACTION if max_fraction is None else max_fraction,
        golden.FLAT_THRESHOLD if flat is None else flat)
    plan = golden.plan_check(args.svg_dir, args.goldens)
    if plan.recorded_version and plan.recorded_version != __version__:
        print(f"note: goldens made with vecmsaa {plan.recorded_version}, checking with "
              f"{__version__}", file=sys.stderr)
    for orphan in plan.orphans:
        print(f"note: golden {orphan} has no SVG any more", file=sys.stderr)
    results = golden.ResultFiles(args.junit, args.json)
    report = golden.ReportWriter(args.report, tolerance) if args.report else None
    from .progress import Progress

    with Progress(len(plan.svgs), "golden check") as bar:
        for outcome in golden.check_goldens(plan, tolerance, jobs=args.jobs,
                                            scheduler=args.scheduler):
            results.add(outcome)
            if outcome.failed or not args.quiet:
                bar.write(outcome.line(args.svg_dir), file=sys.stdout)
            if report:
                report.add(outcome)
            bar.advance()
    counts = results.counts()
    summary = (f"golden check: {counts[golden.PASS]} matched, {counts[golden.DIFFERS]} differ, "
               f"{counts[golden.MISSING]} missing, {counts[golden.ERROR]} "
               f"error{'' if counts[golden.ERROR] == 1 else 's'} "
               f"[{tolerance.describe()}]")
    accept = golden.accept_command(args.svg_dir, args.goldens)
    if report:
        index = report.finish(plan.options, plan.orphans, accept)
        summary += f"; report: {index}"
    results.finish(plan, tolerance, args.report)
    print(summary)
    if counts[golden.DIFFERS] or counts[golden.MISSING]:
        print(f"to accept these renders as the new goldens: {accept}")
    return 0 if counts[golden.PASS] == len(plan.svgs) else 1
