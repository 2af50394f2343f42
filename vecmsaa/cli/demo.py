"""vecmsaa demo: the paper's Figure 1 in every coverage mode, with error images."""
from __future__ import annotations

import sys


def add_parser(sub):
    p = sub.add_parser("demo", help="render Figure 1 (shared curved boundary) in every mode",
                       description="Render the Figure 1 situation of Schwarz & Stamminger — two "
                       "regions sharing one curved boundary and a third overlapping both — in "
                       "every coverage mode side by side, with a magnified inset of the shared "
                       "boundary, error images against the 1024-samples-per-pixel reference, and "
                       "each mode's error on the shared boundary and on the whole picture.")
    p.add_argument("-o", "--output", default="demo.png", help="output PNG (default demo.png; - for stdout)")
    p.add_argument("--samples", type=int, default=8, choices=(2, 4, 8, 16),
                   help="samples per pixel for the MSAA modes (default 8)")
    p.add_argument("--size", type=int, default=36, help="scene size in pixels (default 36)")
    p.add_argument("--zoom", type=int, default=3,
                   help="pixel magnification (default 3: a sheet about 900 px wide)")
    return p


def run(args) -> int:
    from vecmsaa.tools.demo import demo_image
    from vecmsaa.output.png import write_png

    if not (8 <= args.size <= 512 and 1 <= args.zoom <= 32):
        print("vecmsaa demo: --size must be 8..512 and --zoom 1..32", file=sys.stderr)
        return 2
    write_png(demo_image(args.size, args.zoom, args.samples), args.output)
    if args.output != "-":
        print(f"wrote {args.output}", file=sys.stderr)
    return 0
