"""``vecmsaa bench``: run time against error for every coverage mode, sample count and pattern.

Renders built-in synthetic scenes plus any SVG files or folders given, in every MSAA mode x
samples (1, 2, 4, 8, 16) x pattern (d3d, grid; every pattern: --patterns), timing at --size and
measuring the error against the reference mode at a small size; writes table.md, results.csv, results.json and pareto.png.
"""
from __future__ import annotations

import sys


def add_parser(subparsers):
    p = subparsers.add_parser("bench", help="time against error for every mode (writes a "
                              "table, CSV, JSON and a plot)", description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="*", metavar="INPUT", help="SVG files or folders to add")
    p.add_argument("-o", "--out-dir", "--output", dest="out_dir", required=True,
                   help="folder for the results")
    p.add_argument("--quick", action="store_true",
                   help="small sizes, samples 1/4/16, one repeat: under a minute")
    p.add_argument("--size", type=int, help="longer side of the timed renders (1024; quick 256)")
    p.add_argument("--repeat", type=int, help="timed runs per render after a warm-up (3; quick 1)")
    p.add_argument("--no-synthetic", action="store_true", help="only the given SVG files")
    p.add_argument("--no-jit", action="store_true", help="skip the JIT/start-up subprocesses")
    p.add_argument("--no-special", action="store_true",
                   help="skip the skip-unneeded-work rows (full-canvas rectangle etc.)")
    p.add_argument("--memory", default=None, metavar="SIZES",
                   help="comma-separated sizes for the peak-memory rows (default 2048,4096,8192; "
                        "quick none; 0 = none)")
    p.add_argument("--versus-resvg", action="store_true",
                   help="only the rows against resvg on the given SVG files: whole process at "
                        "8192 and 2048 px with peak memory, warm in one process at 2048 px, "
                        "the files as a batch with --jobs 1 and 2; vecmsaa's processes with "
                        "Python's bytecode caches, as installed (writes versus.md/json)")
    p.add_argument("--sequence", action="store_true",
                   help="only the temporal-stability study: slow pans, zooms and rotations "
                        "of Figure 1, thin lines and small text in every mode, flicker against "
                        "the reference and a moving edge's crawl (writes sequence.md/json/png "
                        "and an animated WebP per case)")
    p.add_argument("--conics", action="store_true",
                   help="only the exact-conics study: circles and ellipses from 8 to 8192 px "
                        "across, and stroked circles, as conics and as the cubics arcs used to "
                        "be, in the MSAA and exact-area modes, against the exact shape (the "
                        "ring for a stroke), and their time (writes conics.md/json)")
    p.add_argument("--csaa", action="store_true",
                   help="only the CSAA study: 16 coverage samples with 8, 4 and 2 stored "
                        "colours against plain 4x and 16x MSAA on Figure 1, random scenes and "
                        "fans of 8 colours a pixel (the failure case): error, time, bytes per "
                        "split pixel (writes csaa.md/json)")
    p.add_argument("--patterns", action="store_true",
                   help="only the sample-pattern and filter study: every pattern at equal "
                        "stored samples on Figure 1, random scenes and near-horizontal and "
                        "near-vertical edges, and every resolve filter against the reference "
                        "filtered the same way, with time (writes patterns.md/json)")
    p.add_argument("--icons", action="store_true",
                   help="only the small-size study on the given icon folders or files: "
                        "each rendered at 16, 24 and 32 px in the default and every mode "
                        "against 1024-sample ground truth, pass rates by the suite's criterion "
                        "and edge error (writes icons.md/json)")
    return p


def run(args) -> int:
    from vecmsaa.tools.bench import run_bench

    if args.size is not None and args.size < 8:
        print("vecmsaa bench: --size must be at least 8", file=sys.stderr)
        return 2
    memory = None
    if args.memory is not None:
        try:
            memory = tuple(int(v) for v in args.memory.split(",") if int(v) > 0)
        except ValueError:
            print("vecmsaa bench: --memory takes comma-separated sizes", file=sys.stderr)
            return 2

    def log(text):
        print(text, file=sys.stderr, flush=True)
    if args.sequence:
        from vecmsaa.tools.sequence import study
        study(args.out_dir, log=log)
        log(f"bench: results in {args.out_dir}/ (sequence.md, sequence.json, sequence.png, "
            "*.webp)")
        return 0
    if args.conics:
        from vecmsaa.tools.conics import study
        study(args.out_dir, size=args.size or 1024, repeat=args.repeat or 3, log=log)
        log(f"bench: results in {args.out_dir}/ (conics.md, conics.json)")
        return 0
    if args.csaa:
        from vecmsaa.tools.csaa import write_study
        print(write_study(args.out_dir, quick=args.quick, repeat=args.repeat, log=log))
        log(f"bench: results in {args.out_dir}/ (csaa.md, csaa.json)")
        return 0
    if args.patterns:
        from vecmsaa.tools.patterns import write_study
        print(write_study(args.out_dir, quick=args.quick, repeat=args.repeat, size=args.size,
                          log=log))
        log(f"bench: results in {args.out_dir}/ (patterns.md, patterns.json)")
        return 0
    if args.icons:
        from vecmsaa.tools.icons import write_study
        paths = _svg_inputs(args.inputs)
        if not paths:
            print("vecmsaa bench: --icons needs SVG files or folders", file=sys.stderr)
            return 2
        write_study(args.out_dir, paths, log=log)
        log(f"bench: results in {args.out_dir}/ (icons.md, icons.json)")
        return 0
    if args.versus_resvg:
        from vecmsaa.tools.bench import versus_rows, write_versus
        paths = _svg_inputs(args.inputs)
        if not paths:
            print("vecmsaa bench: --versus-resvg needs SVG files or folders", file=sys.stderr)
            return 2
        write_versus(args.out_dir, versus_rows(paths, repeat=args.repeat or 3, log=log))
        log(f"bench: results in {args.out_dir}/ (versus.md, versus.json)")
        return 0
    result = run_bench(args.inputs, args.out_dir, quick=args.quick, size=args.size,
                       repeat=args.repeat, log=log, synthetic=not args.no_synthetic,
                       jit=not args.no_jit, special=not args.no_special, memory=memory)
    log(f"bench: {result['bench_s']:.1f} s; results in {args.out_dir}/ (table.md, results.csv, "
        f"results.json, pareto.png)")
    return 0


def _svg_inputs(inputs) -> list:
    """The SVG files given, folders expanded to the SVG files under them."""
    import os

    from vecmsaa.cli.render import svg_files
    return [p for item in inputs for p in (svg_files(item) if os.path.isdir(item) else [item])]
