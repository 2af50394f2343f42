"""``vecmsaa render``: SVG files to PNG.

One file: ``vecmsaa render in.svg -o out.png`` (``-`` reads stdin / writes stdout; without
``-o`` the PNG goes beside the input). Several files
or folders: ``vecmsaa render a.svg b.svg dir/ --out-dir out/`` renders them in one process (or
``--jobs`` processes); a broken file is reported with its name and reason, the others still
render, and the exit status is 1. Output files are written whole or not at all.
"""
from __future__ import annotations

import os
import sys

FONT_FLAGS = (("--use-fonts-dir", "use_fonts_dir", "DIR", "load fonts from DIR"),
              ("--font-family", "font_family", "NAME", "default font family"),
              ("--serif-family", "serif_family", "NAME", "font for 'serif'"),
              ("--sans-serif-family", "sans_serif_family", "NAME", "font for 'sans-serif'"),
              ("--cursive-family", "cursive_family", "NAME", "font for 'cursive'"),
              ("--fantasy-family", "fantasy_family", "NAME", "font for 'fantasy'"),
              ("--monospace-family", "monospace_family", "NAME", "font for 'monospace'"))


from .options import add_coverage_options  # noqa: E402  (argparse only: cheap)

#: a filled curve and a stroke: what every SVG needs compiled
WARM_UP_SVG = (b'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><path d="M1 1 '
               b'Q7 1 7 7Z" fill="red" stroke="blue"/></svg>')


def add_parser(subparsers):
    # -h is the output height, so argparse's automatic -h/--help is replaced by --help alone.
    p = subparsers.add_parser("render", help="render SVG files to PNG", add_help=False,
                              description=__doc__.split("\n\n")[0])
    p.add_argument("--help", action="help", help="show this help and exit")
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="SVG files or folders of SVG files; '-' reads standard input")
    p.add_argument("-o", "--output", help="output PNG for a single input ('-' = stdout)")
    p.add_argument("--out-dir", help="folder for the PNGs of several inputs")
    p.add_argument("-w", "--width", type=float, help="output width in pixels")
    p.add_argument("-h", "--height", type=float, help="output height in pixels")
    p.add_argument("-z", "--zoom", type=float, help="scale factor on the intrinsic size")
    p.add_argument("--dpi", type=float, default=96.0, help="resolution for mm, in, pt (96)")
    p.add_argument("--background", help="background colour (any CSS colour)")
    add_coverage_options(p)
    p.add_argument("--resources-dir", help="extra folder images and CSS may be loaded from")
    p.add_argument("--jobs", "-j", type=int, default=1, help="worker processes for batches")
    p.add_argument("--threads", type=int, metavar="N",
                   help="threads rendering one image (default: every core, or 1 in each "
                        "--jobs worker); the image does not depend on it")
    from vecmsaa.tools.cluster import add_scheduler_option
    add_scheduler_option(p)
    for flag, dest, metavar, text in FONT_FLAGS:
        p.add_argument(flag, dest=dest, metavar=metavar, help=text)
    p.add_argument("--skip-system-fonts", action="store_true",
                   help="use only fonts given by --use-fonts-dir")
    return p


def render_options(args) -> dict:
    opts = dict(width=args.width, height=args.height, zoom=args.zoom, dpi=args.dpi,
                background=args.background, resources_dir=args.resources_dir)
    if args.mode:
        opts["mode"] = args.mode
    if args.samples:
        opts["samples"] = args.samples
    for _flag, dest, _m, _t in FONT_FLAGS:
        if getattr(args, dest, None) is not None:
            opts[dest] = getattr(args, dest)
    if args.skip_system_fonts:
        opts["skip_system_fonts"] = True
    if args.threads is not None:
        opts["threads"] = max(1, args.threads)
    elif args.jobs > 1:
        opts["threads"] = 1     # the workers already use the cores
    return opts


def expand_inputs(inputs):
    """Files as given; folders → their *.svg/*.svgz files (sorted, not recursive)."""
    out = []
    for item in inputs:
        if item != "-" and os.path.isdir(item):
            for name in sorted(os.listdir(item)):
                if name.lower().endswith((".svg", ".svgz")):
                    out.append(os.path.join(item, name))
        else:
            out.append(item)
    return out


def output_name(path, out_dir):
    stem = os.path.basename(path)
    for ext in (".svgz", ".svg"):
        if stem.lower().endswith(ext):
            stem = stem[:-len(ext)]
            break
    return os.path.join(out_dir, stem + ".png")


def render_one(job):
    """(input, output, options) → (input, error or None). Never raises."""
    src, dst, opts = job
    try:
        from vecmsaa.api import render_svg_png
        from vecmsaa.output.png import write_bytes_atomic
        source = sys.stdin.buffer.read() if src == "-" else src
        write_bytes_atomic(render_svg_png(source, **opts), dst)
        return src, None
    except Exception as exc:   # a bug on one file must not stop the batch
        return src, failure_text(exc)


def failure_text(exc: BaseException) -> str:
    """One line for a file that failed to render."""
    if isinstance(exc, MemoryError):
        return "out of memory"
    if isinstance(exc, (ValueError, OSError, TypeError)):
        text = str(exc).strip().splitlines()
        return text[0] if text else type(exc).__name__
    return f"internal error: {type(exc).__name__}: {exc}"


def run(args) -> int:
    inputs = expand_inputs(args.inputs)
    if not inputs:
        print("vecmsaa render: no SVG files found", file=sys.stderr)
        return 2
    opts = render_options(args)
    if len(inputs) == 1 and not args.out_dir:
        src = inputs[0]
        dst = args.output or ("-" if src == "-" else output_name(src, os.path.dirname(src) or "."))
        _, err = render_one((src, dst, opts))
        if err:
            print(f"vecmsaa render: {src}: {err}", file=sys.stderr)
            return 1
        return 0
    if args.output:
        print("vecmsaa render: several inputs need --out-dir, not -o", file=sys.stderr)
        return 2
    if "-" in inputs:
        print("vecmsaa render: '-' (stdin) works only as the single input", file=sys.stderr)
        return 2
    out_dir = args.out_dir or "."
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as exc:
        print(f"vecmsaa render: cannot create {out_dir}: {exc.strerror}", file=sys.stderr)
        return 1
    jobs = [(src, output_name(src, out_dir), opts) for src in inputs]
    names = [j[1] for j in jobs]
    if len(set(names)) != len(names):
        print("vecmsaa render: two inputs would write the same output name", file=sys.stderr)
        return 2
    failed = 0
    total = len(jobs)

    def report(i, src, err):
        nonlocal failed
        if err:
            failed += 1
            print(f"[{i}/{total}] FAILED {src}: {err}", file=sys.stderr, flush=True)
        else:
            print(f"[{i}/{total}] {src}", file=sys.stderr, flush=True)
    if args.scheduler:
        from vecmsaa.tools.cluster import ClusterError, render_files
        try:
            for i, (src, err) in enumerate(render_files(jobs, args.scheduler, failure_text), 1):
                report(i, src, err)
        except ClusterError as exc:
            print(f"vecmsaa render: {exc}", file=sys.stderr)
            return 2
    elif args.jobs > 1 and total > 1:
        import multiprocessing as mp
        if sys.platform != "win32":
            # the workers are forked from here: import the renderer and load its compiled
            # kernels once, not once a worker (half a second each)
            from vecmsaa.api import render_svg_png
            try:
                render_svg_png(WARM_UP_SVG, **{**opts, "width": 8, "height": 8, "zoom": None})
            except Exception:   # a bad option: every file reports it
                pass
        with mp.get_context("spawn" if sys.platform == "win32" else "fork").Pool(
                min(args.jobs, total)) as pool:
            for i, (src, err) in enumerate(pool.imap(render_one, jobs), 1):
                report(i, src, err)
    else:
        for i, job in enumerate(jobs, 1):
            src, err = render_one(job)
            report(i, src, err)
    if failed:
        print(f"vecmsaa render: {failed} of {total} files failed", file=sys.stderr)
        return 1
    return 0
