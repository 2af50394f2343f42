"""``vecmsaa suite DIR``: render the resvg test suite and compare with its reference PNGs.

Each ``tests/<category>/<feature>/<name>.svg`` is rendered at its reference PNG's size with the
suite's fonts (``fonts/``, generic families mapped as resvg does), compared with the project's
criterion (:mod:`vecmsaa.tools.compare`), and counted per category and feature. The suite is the
``crates/resvg/tests`` folder of the resvg repository; DIR defaults to $VECMSAA_RESVG_SUITE. A
test whose reference keeps resvg's antialiasing fringe may have an exact reference in
``exact-refs/`` beside ``tests/``; it passes when it matches either, and counts are printed both
ways (plain, with exact refs). Failures get a labelled diff image (reference | difference |
render) in ``--out``.

``--write-passing FILE`` writes the names of the passing tests: that is how
``tests/resvg_passing.txt``, the ratchet list of ``tests/test_resvg_suite.py``, is regenerated::

    vecmsaa suite ../shared/resvg-suite --jobs 2 --write-passing tests/resvg_passing.txt
"""
from __future__ import annotations

import os
import sys


def add_parser(subparsers):
    p = subparsers.add_parser("suite", help="run the resvg test suite against its reference PNGs",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("dir", nargs="?",
                   help="the resvg suite folder (with tests/ and fonts/); "
                        "default: $VECMSAA_RESVG_SUITE")
    p.add_argument("--out", help="folder for diff images of failing tests")
    from .options import add_coverage_options, add_sampling_options
    add_coverage_options(p)
    add_sampling_options(p)
    from .options import add_jobs_option
    add_jobs_option(p, default=0)
    from .options import add_scheduler_option
    add_scheduler_option(p)
    p.add_argument("--only", action="append", default=[], metavar="TEXT",
                   help="only tests whose name contains TEXT (repeatable)")
    p.add_argument("--category", action="append", default=[],
                   help="only these categories (repeatable)")
    p.add_argument("--features", action="store_true", help="print pass rates per feature too")
    p.add_argument("--failures", action="store_true",
                   help="list failing tests, and those that pass only against an exact reference")
    p.add_argument("--write-passing", metavar="FILE",
                   help="write the names of passing tests, exact references counted "
                        "(the ratchet list)")
    return p


def run(args) -> int:
    from vecmsaa.tools.suite import (SUITE_ENV, collect, run_suite, suite_from_environment,
                                     summarize, tests_root)

    folder = args.dir or suite_from_environment()
    if not folder:
        print(f"vecmsaa suite: give the suite folder or set {SUITE_ENV}", file=sys.stderr)
        return 2
    coverage = dict(mode=args.mode, samples=args.samples, pattern=args.pattern,
                    filter=args.filter, color_samples=args.color_samples)
    from vecmsaa.raster.render import RenderOptions
    try:    # a combination no test can render is one error, not a failure of every test
        RenderOptions(**{k: v for k, v in coverage.items() if v is not None})
    except ValueError as exc:
        print(f"vecmsaa suite: {exc}", file=sys.stderr)
        return 2
    suite_dir, tests_dir = tests_root(folder)
    if not os.path.isdir(tests_dir):
        print(f"vecmsaa suite: no tests folder in {folder}", file=sys.stderr)
        return 2
    names = collect(tests_dir, args.category, args.only)
    if not names:
        print("vecmsaa suite: no tests selected", file=sys.stderr)
        return 2
    from vecmsaa.tools.cluster import ClusterError

    from .progress import Progress

    with Progress(len(names), "suite") as bar:
        def progress(done, total):
            if bar.bar is None and (done % 100 == 0 or done == total):
                print(f"{done}/{total}", file=sys.stderr, flush=True)
            bar.advance()
        try:
            results = run_suite(suite_dir, names, args.jobs, args.out, coverage, progress,
                                args.scheduler)
        except ClusterError as exc:
            print(f"vecmsaa suite: {exc}", file=sys.stderr)
            return 2
    if args.failures:
        for name in sorted(results):
            r = results[name]
            if not r.plain:
                tag = ("TRUTH" if r.own_truth else "EXACT") if r.exact else "FAIL"
                print(f"{tag} {name}: {r.detail}")
    print(summarize(results, args.features))
    if args.write_passing:
        passing = sorted(n for n, r in results.items() if r.passed)
        from vecmsaa.files import write_bytes_atomic
        write_bytes_atomic(("\n".join(passing) + "\n").encode(), args.write_passing)
    return 0
