"""``vecmsaa font``: draw text, a waterfall, a glyph grid or a specimen sheet of a font file."""
from __future__ import annotations

import argparse
import sys

DEFAULT_TEXT = "The quick brown fox jumps over the lazy dog"


def add_parser(subparsers):
    p = subparsers.add_parser(
        "font", help="render text or glyph sheets of a font file",
        description="Render one line of text, a waterfall, every glyph, or a specimen sheet of "
                    "a font file (TrueType, CFF, CFF2, variable, collections) to PNG.")
    p.add_argument("font", metavar="FONT", help="font file (.ttf, .otf, .ttc, .otc, .woff2)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.png",
                   help="output PNG ('-' for stdout)")
    what = p.add_mutually_exclusive_group()
    what.add_argument("--waterfall", metavar="SIZES",
                      help="comma-separated pixel sizes, e.g. 8,10,12,16,24,36,48,72")
    what.add_argument("--glyphs", action="store_true",
                      help="grid of every glyph, labelled with glyph name and code point")
    what.add_argument("--specimen", action="store_true",
                      help="family, style and metrics sheet with samples")
    p.add_argument("--text", default=None, help=f"text to draw [default: {DEFAULT_TEXT!r}]")
    p.add_argument("--size", type=float, default=48.0, help="pixels per em [default: 48]")
    p.add_argument("--face-index", type=int, default=0, metavar="N",
                   help="face in a collection (.ttc) [default: 0]")
    p.add_argument("--variations", default=None, metavar="AXES",
                   help="variable font location, e.g. wght=700,wdth=80")
    p.add_argument("--features", default=None, metavar="FEATURES",
                   help="OpenType features, e.g. 'liga=0,ss01,-kern'")
    p.add_argument("--language", default=None, help="BCP 47 language tag for shaping")
    p.add_argument("--script", default=None, help="ISO 15924 script for shaping, e.g. Arab")
    p.add_argument("--direction", choices=("ltr", "rtl", "ttb", "btt"), default=None,
                   help="force one direction (default: from the text, with bidi runs)")
    p.add_argument("--foreground", default="black", metavar="COLOR",
                   help="text colour (CSS) [default: black]")
    p.add_argument("--background", default="white", metavar="COLOR",
                   help="background colour (CSS), 'transparent' allowed [default: white]")
    p.add_argument("--margin", type=float, default=None, metavar="PX",
                   help="margin around a --text line [default: size/8, at least 2]")
    p.add_argument("-q", "--quiet", action="store_true", help="no warnings")
    p.add_argument("--page", type=int, default=1, metavar="N",
                   help="page of --glyphs (1-based) [default: 1]")
    p.add_argument("--per-page", type=int, default=256, metavar="N",
                   help="glyphs per --glyphs page [default: 256]")
    p.add_argument("--columns", type=int, default=16, metavar="N",
                   help="columns of the --glyphs grid [default: 16]")
    from .options import add_coverage_options, add_sampling_options
    add_coverage_options(p, default_mode="analytic on the outlines with their overlaps "
                                          "united, approx for colour fonts (docs/fonts.md)")
    # a pattern or filter asks for samples: the multisample default mode then
    add_sampling_options(p)
    p.set_defaults(func=run)
    return p


#: at most this many --waterfall sizes and this --margin (px): beyond, the sheet could only
#: be refused by its size after laying out all of it
MAX_SIZES = 256
MAX_MARGIN = 10000.0


def _fail(message: str, status: int = 1) -> int:
    print(f"vecmsaa font: error: {message}", file=sys.stderr)
    return status


def _color(text: str, what: str):
    from vecmsaa.svg.color import parse_color

    c = parse_color(text)
    if c is None or isinstance(c, str):
        raise ValueError(f"bad {what} colour {text!r}")
    return tuple(float(v) for v in c)


def _sizes(text: str) -> list:
    try:
        sizes = [float(s) for s in text.replace(" ", "").split(",") if s]
    except ValueError:
        raise ValueError(f"bad --waterfall sizes {text!r}") from None
    if not sizes or any(not 0 < s <= 2000 for s in sizes):
        raise ValueError(f"bad --waterfall sizes {text!r}: need sizes in (0, 2000]")
    if len(sizes) > MAX_SIZES:
        raise ValueError(f"--waterfall has {len(sizes)} sizes, over the limit of {MAX_SIZES}")
    return sizes


def run(args) -> int:
    from vecmsaa.fonts import parse_features, parse_variations

    try:
        foreground = _color(args.foreground, "--foreground")
        background = _color(args.background, "--background")
        location = parse_variations(args.variations)
        features = parse_features(args.features)
        if not 0 < args.size <= 2000:
            raise ValueError("--size must be in (0, 2000]")
        if args.margin is not None and not 0 <= args.margin <= MAX_MARGIN:
            raise ValueError(f"--margin must be in [0, {MAX_MARGIN:g}], over that is beyond the "
                             "image size limit")
        sizes = _sizes(args.waterfall) if args.waterfall else None
    except ValueError as exc:
        return _fail(str(exc), 2)   # option values: a usage error
    from vecmsaa import diagnostics

    found: list = []
    with diagnostics.collecting(found):   # broken glyphs: one line each, after the render
        status = _render(args, location, features, foreground, background, sizes)
    for message in [] if args.quiet else found:
        print(f"vecmsaa font: warning: {message}", file=sys.stderr)
    return status


def _render(args, location, features, foreground, background, sizes) -> int:
    from vecmsaa import diagnostics
    from vecmsaa.fonts import FontError, load_face

    try:
        face = load_face(args.font, args.face_index)
        for tag in location:
            if tag not in face.axes:
                have = ", ".join(face.axes) or "none"
                diagnostics.warn(f"font has no axis {tag!r} (axes: {have})")
        scene = build_scene(face, args, location, features, foreground, background, sizes)
    except (FontError, ValueError) as exc:
        return _fail(str(exc))
    from vecmsaa.api import render_sheet
    from vecmsaa.output.png import write_png

    try:
        image = render_sheet(scene, face, args.mode, args.samples, args.pattern, args.filter)
    except ImportError as exc:    # the raster's compiled dependencies
        return _fail(f"renderer not available: {exc}")
    except ValueError as exc:     # e.g. a sample count the mode has no pattern for
        return _fail(str(exc))
    try:
        write_png(image, args.output)
    except OSError as exc:
        return _fail(f"cannot write {args.output}: {exc.strerror or exc}")
    return 0


def build_scene(face, args, location, features, foreground, background, sizes):
    """The scene the options ask for (no rendering)."""
    from vecmsaa.fonts import sheets

    shaping = dict(location=location, features=features, direction=args.direction,
                   script=args.script, language=args.language)
    colors = dict(foreground=foreground, background=background)
    if args.glyphs:
        return sheets.glyph_grid_scene(face, label_face(face), page=args.page,
                                       columns=max(1, args.columns),
                                       per_page=max(1, args.per_page), location=location,
                                       **colors)
    if args.specimen:
        return sheets.specimen_scene(face, label_face(face), **shaping, **colors)
    text = args.text if args.text is not None else sheets.sample_text(face)
    if sizes:
        return sheets.waterfall_scene(face, text, sizes, label_face(face), **shaping, **colors)
    return sheets.line_scene(face, text, args.size, margin=args.margin, **shaping, **colors)


def label_face(face):
    """A readable face for labels: the system sans-serif, else the font itself."""
    from vecmsaa.fonts import FontError
    from vecmsaa.fonts.db import default_database

    info = default_database().query(["sans-serif"])
    if info is not None:
        try:
            return info.load()
        except FontError:
            pass
    return face


if __name__ == "__main__":   # pragma: no cover
    parser = argparse.ArgumentParser(prog="vecmsaa")
    add_parser(parser.add_subparsers(dest="command"))
    sys.exit(run(parser.parse_args()))
