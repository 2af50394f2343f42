"""``vecmsaa render``: SVG files to PNG, WebP, JPEG or TIFF.

Forms (resvg's, rsvg-convert's and a batch form)::

    vecmsaa render in.svg out.png             # positional output, as resvg
    vecmsaa render in.svg -o out.webp         # format from the name
    vecmsaa render in.svg -c > out.png        # standard output (also without -o when it is
    vecmsaa render - -o out.png < in.svg      # not a terminal); '-' reads standard input
    vecmsaa render a.svg icons/ --out-dir out/ --jobs 0

Nothing is ever written beside the input unasked. Folders are searched recursively and their
tree is mirrored under ``--out-dir``. A broken file is reported with its name and reason, the
others still render (a worker process that dies fails only its file), and the exit status is
1; usage errors exit with 2. Output files are written whole or not at all.
"""
from __future__ import annotations

import os
import sys

from .options import (add_coverage_options, add_jobs_option,  # argparse only
                      add_sampling_options, add_scheduler_option)

DESCRIPTION = ("Render SVG files to PNG, WebP, JPEG or TIFF: 'vecmsaa render in.svg out.png', "
               "'-o OUT', '-c' for standard output, or several files and folders with "
               "--out-dir. Folders are searched recursively and mirrored under --out-dir.")

#: (flag, option name, metavar, help) of the font options, one value each
FAMILY_FLAGS = (("--font-family", "font_family", "NAME", "default font family"),
              ("--serif-family", "serif_family", "NAME", "font for 'serif'"),
              ("--sans-serif-family", "sans_serif_family", "NAME", "font for 'sans-serif'"),
              ("--cursive-family", "cursive_family", "NAME", "font for 'cursive'"),
              ("--fantasy-family", "fantasy_family", "NAME", "font for 'fantasy'"),
              ("--monospace-family", "monospace_family", "NAME", "font for 'monospace'"))
#: the font flags 'vecmsaa golden update' records (one fonts folder: the manifest keeps one)
FONT_FLAGS = (("--use-fonts-dir", "use_fonts_dir", "DIR", "load fonts from DIR"),) + FAMILY_FLAGS
#: repeatable font sources
FONT_SOURCES = (("--use-font-file", "use_font_file", "FILE",
                 "load this font file (repeatable)"),
                ("--use-fonts-dir", "use_fonts_dir", "DIR",
                 "load the fonts in this folder (repeatable)"))
SHAPE_RENDERING = ("optimizeSpeed", "crispEdges", "geometricPrecision")
TEXT_RENDERING = ("optimizeSpeed", "optimizeLegibility", "geometricPrecision")
IMAGE_RENDERING = ("optimizeQuality", "optimizeSpeed")

#: a filled curve and a stroke: what every SVG needs compiled
WARM_UP_SVG = (b'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><path d="M1 1 '
               b'Q7 1 7 7Z" fill="red" stroke="blue"/></svg>')
#: and a text, for a batch with texts: the text modules, the font database, a face
WARM_UP_TEXT_SVG = WARM_UP_SVG.replace(b"</svg>", b'<text x="1" y="7" font-size="6">A</text>'
                                                  b"</svg>")
#: a batch's first files that warm_up_svg reads the beginning of (WARM_UP_PEEK bytes each)
WARM_UP_FILES = 16
WARM_UP_PEEK = 1 << 16


def warm_up_svg(sources) -> bytes:
    """What the parent of a batch's workers renders before forking them: WARM_UP_TEXT_SVG
    when one of the first WARM_UP_FILES files (regular files only) has a ``<text`` in its
    first WARM_UP_PEEK bytes (each worker loaded the text modules, the font database and a face on its first
    text, ≈ 0.25 s of CPU each), else WARM_UP_SVG (a batch of icons would load them for
    nothing)."""
    for src in sources[:WARM_UP_FILES]:
        if not os.path.isfile(src):
            continue        # a FIFO or a device: reading it here could wait forever
        try:
            with open(src, "rb") as f:
                if b"<text" in f.read(WARM_UP_PEEK):
                    return WARM_UP_TEXT_SVG
        except OSError:     # the file reports it when its turn comes
            pass
    return WARM_UP_SVG


def add_parser(subparsers):
    from vecmsaa.output.formats import FORMATS

    # -h is the output height (as in resvg and rsvg-convert), so help is --help alone.
    p = subparsers.add_parser("render", help="render SVG files to PNG, WebP, JPEG or TIFF",
                              add_help=False, description=DESCRIPTION)
    p.add_argument("--help", action="help", help="show this help and exit")
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="SVG files or folders; '-' reads standard input; with one input a "
                        "second argument naming an image (out.png) is the output")
    out = p.add_argument_group("output")
    out.add_argument("-o", "--output", metavar="OUT",
                     help="output file for a single input; '-' is standard output")
    out.add_argument("-c", dest="to_stdout", action="store_true",
                     help="write the image to standard output")
    out.add_argument("--out-dir", metavar="DIR",
                     help="folder for the images of several inputs (tree of folders mirrored)")
    out.add_argument("-f", "--format", choices=FORMATS,
                     help="image format (default: from the output name, else png); JPEG is "
                          "flattened onto --background, white by default")
    size = p.add_argument_group("size")
    size.add_argument("-w", "--width", type=float, help="output width in pixels")
    size.add_argument("-h", "--height", type=float, help="output height in pixels")
    size.add_argument("-z", "--zoom", type=float,
                      help="scale factor on the intrinsic size (ignored with -w or -h, as in "
                           "resvg)")
    size.add_argument("-a", "--keep-aspect-ratio", action="store_true",
                      help="with both -w and -h, fit inside that size instead of stretching")
    size.add_argument("-d", "--dpi", type=float, default=96.0, help="resolution for mm, in, pt (96)")
    size.add_argument("-u", "--no-size-limit", "--unlimited", action="store_true",
                      help="allow images beyond 32768 px per side or 2^28 pixels")
    size.add_argument("-i", "--export-id", metavar="ID",
                      help="render only the element with this id, cropped to its bounds")
    size.add_argument("--export-area-drawing", action="store_true",
                      help="crop the image to the drawing's bounds")
    look = p.add_argument_group("rendering")
    look.add_argument("-b", "--background", "--background-color", metavar="COLOR", help="background colour (any CSS colour)")
    add_coverage_options(look)
    add_sampling_options(look)
    look.add_argument("--shape-rendering", choices=SHAPE_RENDERING,
                      help="default shape-rendering (crispEdges: no antialiasing)")
    look.add_argument("--text-rendering", choices=TEXT_RENDERING,
                      help="default text-rendering")
    look.add_argument("--image-rendering", choices=IMAGE_RENDERING,
                      help="default image-rendering (optimizeSpeed: nearest neighbour)")
    look.add_argument("-s", "--stylesheet", metavar="CSS",
                      help="CSS file applied to the document (before its own style sheets)")
    look.add_argument("--languages", "--accept-language", metavar="LANGS", default="en",
                      help="comma-separated languages for systemLanguage (default: en)")
    look.add_argument("--resources-dir", metavar="DIR",
                      help="extra folder images and CSS may be loaded from")
    fonts = p.add_argument_group("fonts")
    for flag, dest, metavar, text in FONT_SOURCES:
        fonts.add_argument(flag, dest=dest, metavar=metavar, action="append", help=text)
    for flag, dest, metavar, text in FAMILY_FLAGS:
        fonts.add_argument(flag, dest=dest, metavar=metavar, help=text)
    fonts.add_argument("--font-size", type=float, metavar="SIZE",
                       help="font size where the document sets none (default: 12)")
    fonts.add_argument("--skip-system-fonts", action="store_true",
                       help="use only the fonts given by --use-font-file and --use-fonts-dir")
    fonts.add_argument("--list-fonts", action="store_true",
                       help="list the fonts found (with the options above) and exit")
    other = p.add_argument_group("batch and messages")
    add_jobs_option(other)
    other.add_argument("--threads", type=int, metavar="N",
                       help="threads rendering one image (default: every core, or 1 in each "
                            "--jobs worker); the image does not depend on it")
    add_scheduler_option(other)
    other.add_argument("--query-all", action="store_true",
                       help="print id,x,y,width,height of every element with an id (in "
                            "pixels of the output) and exit, as resvg does")
    other.add_argument("-q", "--quiet", action="store_true", help="no warnings, no progress")
    return p


def render_options(args) -> dict:
    """The keyword arguments of :func:`vecmsaa.api.render_svg_array` the flags ask for."""
    opts = dict(width=args.width, height=args.height, zoom=args.zoom, dpi=args.dpi,
                background=args.background, resources_dir=args.resources_dir,
                keep_aspect=args.keep_aspect_ratio, size_limit=not args.no_size_limit)
    if args.mode:
        opts["mode"] = args.mode
    if args.samples:
        opts["samples"] = args.samples
    for dest in ("pattern", "filter", "color_samples"):
        if getattr(args, dest):
            opts[dest] = getattr(args, dest)
    for dest in ("font_size", "shape_rendering", "text_rendering", "image_rendering",
                 "export_id"):
        if getattr(args, dest) is not None:
            opts[dest] = getattr(args, dest)
    if args.export_area_drawing:
        opts["export_area_drawing"] = True
    if args.stylesheet:
        opts["stylesheet"] = read_stylesheet(args.stylesheet)
    langs = [x.strip() for x in args.languages.split(",") if x.strip()]
    if langs != ["en"]:
        opts["languages"] = tuple(langs)
    for _flag, dest, _m, _t in FONT_SOURCES + FAMILY_FLAGS:
        if getattr(args, dest, None):
            opts[dest] = getattr(args, dest)
    if args.skip_system_fonts:
        opts["skip_system_fonts"] = True
    if args.threads is not None:
        opts["threads"] = max(1, args.threads)
    elif args.jobs > 1:
        opts["threads"] = 1     # the workers already use the cores
    return opts


class UsageError(Exception):
    """A flag combination or value that cannot work: exit status 2."""


def read_stylesheet(path) -> str:
    try:
        with open(path, "rb") as f:
            return f.read(1 << 20).decode("utf-8", "replace")
    except OSError as exc:
        raise UsageError(f"cannot read --stylesheet {path}: {exc.strerror}") from None


def svg_files(folder):
    """The *.svg and *.svgz files under ``folder``, recursively, in a stable order."""
    out = []
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        for name in sorted(files):
            if name.lower().endswith((".svg", ".svgz")):
                out.append(os.path.join(root, name))
    return out


def output_name(path, out_dir, relative_to=None, ext=".png"):
    """``out_dir``/(``path`` relative to ``relative_to``, or its base name) with ``ext``."""
    rel = os.path.relpath(path, relative_to) if relative_to else os.path.basename(path)
    stem = rel
    for svg_ext in (".svgz", ".svg"):
        if stem.lower().endswith(svg_ext):
            stem = stem[:-len(svg_ext)]
            break
    return os.path.join(out_dir, stem + ext)


def batch_jobs(inputs, out_dir, ext):
    """[(input, output)] for files and folders given on the command line."""
    pairs = []
    for item in inputs:
        if item == "-":
            raise UsageError("'-' (standard input) works only as the single input")
        if os.path.isdir(item):
            pairs.extend((src, output_name(src, out_dir, item, ext)) for src in svg_files(item))
        else:
            pairs.append((item, output_name(item, out_dir, None, ext)))
    seen = {}
    for src, dst in pairs:
        if dst in seen:
            raise UsageError(f"{seen[dst]} and {src} would both write {dst}")
        seen[dst] = src
    return pairs


def render_one(job):
    """(input, output, format, options) → (error or None, warnings). Never raises."""
    src, dst, fmt, opts = job
    from vecmsaa import diagnostics

    found = []
    try:
        from vecmsaa.api import read_bounded, render_svg_array, render_svg_png
        from vecmsaa.output.formats import encode
        from vecmsaa.files import write_bytes_atomic
        with diagnostics.collecting(found):
            source = read_bounded(sys.stdin.buffer, "standard input") if src == "-" else src
            if fmt == "png":    # encoded band by band as the bands are rendered
                data = render_svg_png(source, **opts)
            else:               # JPEG: flattened onto white (--background is painted already)
                data = encode(render_svg_array(source, **opts), fmt)
    except Exception as exc:   # a bug on one file must not stop the batch
        return failure_text(exc), found
    try:
        write_bytes_atomic(data, dst)
    except OSError as exc:
        return f"cannot write {dst}: {os_reason(exc)}", found
    return None, found


def os_reason(exc: OSError) -> str:
    """An OSError's reason without ``[Errno N]`` or temporary names."""
    reason = (exc.strerror or str(exc)).rstrip(".")
    if isinstance(exc, FileNotFoundError) and exc.filename:
        return f"{reason}: {exc.filename}"
    return reason[:1].lower() + reason[1:]


def one_line(exc) -> str:
    if isinstance(exc, OSError) and exc.strerror:
        return os_reason(exc)
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def print_warnings(src, found, quiet):
    if quiet:
        return
    for message in found:
        print(f"vecmsaa: warning: {src}: {message}", file=sys.stderr)


def failure_text(exc: BaseException) -> str:
    """One line for a file that failed to render."""
    if isinstance(exc, MemoryError):
        return "out of memory"
    if isinstance(exc, (ValueError, OSError, TypeError)):
        return one_line(exc)
    return f"internal error: {type(exc).__name__}: {one_line(exc)}"


def run(args) -> int:
    try:
        return _run(args)
    except UsageError as exc:
        print(f"vecmsaa render: {exc}", file=sys.stderr)
        return 2


def _run(args) -> int:
    from vecmsaa.output.formats import EXTENSION, format_of

    opts = render_options(args)
    if args.list_fonts:
        return list_fonts(opts)
    inputs = list(args.inputs)
    output = args.output
    if (len(inputs) == 2 and output is None and not args.out_dir and not args.to_stdout
            and format_of(inputs[1])):
        inputs, output = inputs[:1], inputs[1]          # resvg's 'in.svg out.png'
    if args.query_all:
        return query_all(inputs, opts)
    single = len(inputs) == 1 and not args.out_dir and (inputs[0] == "-"
                                                        or not os.path.isdir(inputs[0]))
    if single:
        if args.to_stdout and output not in (None, "-"):
            raise UsageError("-c writes to standard output: give -c or an output file, not both")
        dst = "-" if args.to_stdout else output
        if dst is None:
            if sys.stdout.isatty():
                raise UsageError("no output given: name one (in.svg out.png or -o out.png), "
                                 "use -c for standard output, or --out-dir DIR")
            dst = "-"
        if dst != "-" and os.path.isdir(dst):
            print(f"vecmsaa render: cannot write {dst}: it is a folder", file=sys.stderr)
            return 1
        # no ending (stdout, /dev/null, a FIFO 'out'): PNG, as rsvg-convert writes
        fmt = args.format or ("png" if dst == "-" or not os.path.splitext(dst)[1]
                              else format_of(dst))
        if fmt is None:
            raise UsageError(f"cannot tell the image format of {dst}: end it in .png, .webp, "
                             ".jpg, .tif or give --format")
        from .progress import single_render
        with single_render(inputs[0], args.quiet) as report:
            err, found = render_one((inputs[0], dst, fmt, dict(opts, progress=report)))
        print_warnings(inputs[0], found, args.quiet)
        if err:
            print(f"vecmsaa render: {inputs[0]}: {err}", file=sys.stderr)
            return 1
        return 0
    if output or args.to_stdout:
        raise UsageError("several inputs need --out-dir, not -o or -c")
    if not args.out_dir:
        raise UsageError("a folder or several inputs need --out-dir DIR")
    fmt = args.format or "png"
    pairs = batch_jobs(inputs, args.out_dir, EXTENSION[fmt])
    if not pairs:
        raise UsageError("no SVG files found")
    if args.scheduler and fmt != "png":
        raise UsageError("--scheduler batches write PNG only")
    return run_batch(pairs, fmt, opts, args.jobs, args.quiet, args.scheduler)


def run_batch(pairs, fmt, opts, jobs, quiet, scheduler=None) -> int:
    from .progress import Progress

    jobs_list = []
    for src, dst in pairs:
        folder = os.path.dirname(dst)
        try:
            os.makedirs(folder or ".", exist_ok=True)
        except OSError as exc:
            print(f"vecmsaa render: cannot create {folder}: {os_reason(exc)}", file=sys.stderr)
            return 1
        jobs_list.append((src, dst, fmt, opts))
    failed = 0
    total = len(jobs_list)
    with Progress(total, "render", quiet) as bar:
        def report(i, err, found):
            nonlocal failed
            src = jobs_list[i][0]
            for message in () if quiet else found:
                bar.write(f"vecmsaa: warning: {src}: {message}")
            if err:
                failed += 1
                bar.write(f"FAILED {src}: {err}")
            bar.advance(src)
        if scheduler:
            from vecmsaa.tools.cluster import ClusterError, render_files
            try:
                for i, (_src, err) in enumerate(render_files(
                        [(src, dst, opts) for src, dst, _f, opts in jobs_list], scheduler,
                        failure_text)):
                    report(i, err, [])
            except ClusterError as exc:
                print(f"vecmsaa render: {exc}", file=sys.stderr)
                return 2
        elif jobs > 1 and total > 1:
            if sys.platform != "win32":
                # the workers are forked from here: import the renderer and load its compiled
                # kernels once, not once a worker (half a second each); the fonts too where
                # the batch has texts
                from vecmsaa import diagnostics
                from vecmsaa.api import render_svg_png
                try:
                    with diagnostics.collecting([]):
                        render_svg_png(warm_up_svg([src for src, *_ in jobs_list]),
                                       **{**opts, "width": 8, "height": 8, "zoom": None})
                except Exception:   # a bad option: every file reports it
                    pass
            from vecmsaa.tools.workers import imap_unordered
            for i, result in imap_unordered(render_one, jobs_list, jobs):
                if isinstance(result, Exception):
                    report(i, str(result), [])
                else:
                    report(i, *result)
        else:
            for i, job in enumerate(jobs_list):
                report(i, *render_one(job))
    if failed:
        print(f"vecmsaa render: {failed} of {total} files failed", file=sys.stderr)
        return 1
    return 0


def list_fonts(opts) -> int:
    """resvg's --list-fonts: the generic family mapping, then one line per face."""
    from vecmsaa.fonts.db import GENERIC_FAMILIES, database_from_options

    db = database_from_options(opts)
    for generic in GENERIC_FAMILIES:
        info = db.query([generic])
        print(f"{generic}: {info.family if info else '(none)'}")
    for f in db.faces:
        print(f"{f.path}: '{', '.join(f.families)}', {f.index}, {f.style}, {f.weight}, "
              f"{f.stretch:g}%")
    return 0


def query_all(inputs, opts) -> int:
    """resvg's --query-all: ``id,x,y,width,height`` of each element with an id."""
    from vecmsaa.api import query_bounds
    from vecmsaa.svg import SvgError

    if len(inputs) != 1:
        raise UsageError("--query-all takes one input")
    src = inputs[0]
    found = []
    from vecmsaa import diagnostics
    try:
        with diagnostics.collecting(found):
            source = sys.stdin.buffer if src == "-" else src
            boxes = query_bounds(source, **opts)
    except (SvgError, OSError) as exc:
        print(f"vecmsaa render: {src}: {one_line(exc)}", file=sys.stderr)
        return 1
    if not boxes:
        print(f"vecmsaa render: {src}: the file has no element with an id", file=sys.stderr)
        return 1
    for ident, (x, y, w, h) in boxes:
        print(f"{ident},{_round3(x)},{_round3(y)},{_round3(w)},{_round3(h)}")
    return 0


def _round3(v: float) -> str:
    return f"{round(v, 3):g}"
