"""Documents in the shapes other programs write, for benchmarks against resvg: what a
demanding user feeds a renderer, where the corpus (one drawing each) has large shapes.

    python tools/exporters.py OUT_DIR [--fonts ../shared/resvg-suite/fonts]

writes, seeded (the same bytes every run):

- ``scatter.svg``: a D3 scatter plot, 20,000 ``<circle>``s, fill-opacity and a 0.5 stroke
  (a hairline at 1000 px, a stroke at 3000);
- ``classes.svg``: an Illustrator export, 8,000 curved paths styled by 200 CSS classes;
- ``graph.svg``: a Graphviz layout, 1,500 nodes (ellipse and label) and their edges;
- ``ticks.svg``: D3 axes of 30 small multiples, 3,000 tick ``<g>``s each a line and a
  short ``<text>`` label (half of them the same values in every chart);
- ``xlists.svg``: a PDF converter's text, 90 lines of 110 characters, each line one
  ``<tspan>`` with an x for every character;
- ``glyph_uses.svg`` (with ``--fonts``): cairo's SVG surface (pdftocairo, pdf2svg), every
  glyph a ``<use>`` of a ``<symbol>`` holding its outline, 12,000 on an 800 x 1100 page;
- ``plot_markers.svg`` (its labels with ``--fonts``): matplotlib's SVG backend, a scatter of
  5,000 ``<use>``s of one stroked marker path, each with the style of fill and stroke, and
  200 tick labels whose glyphs are ``<use>``s under a translation and scale each.

Render each with ``/usr/bin/time -f "%e s %U u %M KB" vecmsaa render F -o v.png -w W`` and
``resvg -w W F r.png`` (add ``--use-fonts-dir FONTS --skip-system-fonts`` to both for text).
"""
from __future__ import annotations

import argparse
import os
import random

SVG = '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
CHARS = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.,;:()"


def scatter(rng):
    dots = "".join(f'<circle cx="{rng.uniform(0, 1000):.2f}" cy="{rng.uniform(0, 800):.2f}" '
                   f'r="{rng.uniform(2, 6):.1f}" fill="steelblue" fill-opacity="0.6" '
                   f'stroke="#333" stroke-width="0.5"/>' for _ in range(20000))
    return f'{SVG}width="1000" height="800">{dots}</svg>'


def classes(rng):
    style = "".join(f".st{i}{{fill:#{rng.randrange(1 << 24):06x};stroke:#000;"
                    f"stroke-miterlimit:10;}}" for i in range(200))
    paths = []
    for _ in range(8000):
        x, y = rng.uniform(0, 1000), rng.uniform(0, 800)
        paths.append(f'<path class="st{rng.randrange(200)}" d="M{x:.1f},{y:.1f}c5.2,-3.1 '
                     f'10.4,2.2 12.1,8.3s-4.4,9.1 -9.9,6.6C{x - 3:.1f},{y + 12:.1f} '
                     f'{x - 4:.1f},{y + 5:.1f} {x:.1f},{y:.1f}z"/>')
    return f'{SVG}viewBox="0 0 1000 800"><style type="text/css">{style}</style>' \
        f'{"".join(paths)}</svg>'


def graph(rng):
    out = []
    for i in range(1500):
        x, y = (i % 40) * 100 + 50, (i // 40) * 80 + 40
        out.append(f'<g id="node{i}" class="node"><title>n{i}</title><ellipse fill="none" '
                   f'stroke="black" cx="{x}" cy="{y}" rx="40" ry="18"/><text '
                   f'text-anchor="middle" x="{x}" y="{y + 4}" font-family="Noto Sans" '
                   f'font-size="14.00">node {i}</text></g>')
        if i >= 40:
            px, py = x + rng.choice([-100, 0, 100]), y - 80
            out.append(f'<g class="edge"><title>a</title><path fill="none" stroke="black" '
                       f'd="M{px},{py + 18}C{px},{py + 40} {x},{y - 40} {x},{y - 28}"/>'
                       f'<polygon fill="black" stroke="black" points="{x - 3.5},{y - 28.5} '
                       f'{x},{y - 18.5} {x + 3.5},{y - 28.5} {x - 3.5},{y - 28.5}"/></g>')
    return f'{SVG}width="4050pt" height="3050pt" viewBox="0 0 4050 3050"><g class="graph">' \
        f'<polygon fill="white" stroke="none" points="0,3050 4050,3050 4050,0 0,0"/>' \
        f'{"".join(out)}</g></svg>'


def ticks(rng):
    # D3's axes (d3-axis): a <g> per tick, translated, with its line and a label whose
    # text-anchor, font and fill come from the axis group; 6 x 5 small multiples of two
    # axes of 50 ticks, the same tick values in every chart
    charts = []
    for k in range(30):
        ox, oy = 40 + (k % 6) * 190, 20 + (k // 6) * 160
        axes = []
        for axis, anchor in (("x", "middle"), ("y", "end")):
            tks = []
            for i in range(50):
                v = i * 0.02
                if axis == "x":
                    tks.append(f'<g class="tick" opacity="1" transform="translate({3 * i + 0.5},0)">'
                               f'<line stroke="currentColor" y2="6"></line><text fill="currentColor" '
                               f'y="9" dy="0.71em">{v:.2f}</text></g>')
                else:
                    tks.append(f'<g class="tick" opacity="1" transform="translate(0,{2.4 * i + 0.5})">'
                               f'<line stroke="currentColor" x2="-6"></line><text fill="currentColor" '
                               f'x="-9" dy="0.32em">{rng.randrange(1000)}</text></g>')
            move = f"translate(0,{120})" if axis == "x" else "translate(0,0)"
            axes.append(f'<g transform="{move}" fill="none" font-size="4" font-family="Noto Sans" '
                        f'text-anchor="{anchor}"><path class="domain" stroke="currentColor" '
                        f'd="M0.5,6V0.5H150.5V6"></path>{"".join(tks)}</g>')
        charts.append(f'<g transform="translate({ox},{oy})">{"".join(axes)}</g>')
    return f'{SVG}width="1200" height="1000">{"".join(charts)}</svg>'


def xlists(rng):
    lines = []
    for y in range(20, 1100, 12):
        s = "".join(rng.choice(CHARS[:26] + "    ") for _ in range(110))
        xs = " ".join(f"{20 + 6.8 * i:.2f}" for i in range(len(s)))
        lines.append(f'<tspan x="{xs}" y="{y}">{s.replace(" ", "&#160;")}</tspan>')
    return f'{SVG}width="800" height="1100" viewBox="0 0 800 1100"><text ' \
        f'font-family="Noto Sans" font-size="11" xml:space="preserve">{"".join(lines)}</text></svg>'


def glyph_uses(rng, fonts):
    from fontTools.pens.svgPathPen import SVGPathPen
    from fontTools.ttLib import TTFont
    font = TTFont(os.path.join(fonts, "NotoSans-Regular.ttf"))
    glyphs, cmap = font.getGlyphSet(), font.getBestCmap()
    symbols, advance = [], []
    for i, c in enumerate(CHARS):
        pen = SVGPathPen(glyphs)
        glyphs[cmap[ord(c)]].draw(pen)
        symbols.append(f'<symbol overflow="visible" id="glyph0-{i}"><path style="stroke:none;" '
                       f'd="{pen.getCommands()}" transform="scale(0.01,-0.01)"/></symbol>')
        advance.append(glyphs[cmap[ord(c)]].width * 0.01)
    uses = []
    for y in range(20, 1100, 12):
        x = 20.0
        while x < 780:
            i = rng.randrange(len(CHARS))
            uses.append(f'<use xlink:href="#glyph0-{i}" x="{x:.3f}" y="{y}"/>')
            x += advance[i]
    return f'{SVG}width="800pt" height="1100pt" viewBox="0 0 800 1100"><defs><g>' \
        f'{"".join(symbols)}</g></defs><g style="fill:rgb(0%,0%,0%);fill-opacity:1;">' \
        f'{"".join(uses)}</g></svg>'


def plot_markers(rng, fonts=None):
    r = 1.414214
    k = r * 0.2652            # (matplotlib's circle: four cubics, handles at 0.2652 r)
    marker = (f'<path id="m0" d="M 0 {r} C {k} {r} {r - k} {r - k} {r} 0 C {r} {-k} '
              f'{r - k} {-r + k} 0 {-r} C {-k} {-r} {-r + k} {-r + k} {-r} 0 C {-r} {k} '
              f'{-r + k} {r - k} 0 {r} z" style="stroke: #1f77b4; stroke-opacity: 0.6"/>')
    style = "fill: #1f77b4; fill-opacity: 0.6; stroke: #1f77b4; stroke-opacity: 0.6"
    dots = "".join(f'<use xlink:href="#m0" x="{rng.gauss(360, 70):.6f}" '
                   f'y="{rng.gauss(270, 50):.6f}" style="{style}"/>' for _ in range(5000))
    labels, glyph_defs = [], ""
    if fonts:
        from fontTools.pens.svgPathPen import SVGPathPen
        from fontTools.ttLib import TTFont
        font = TTFont(os.path.join(fonts, "NotoSans-Regular.ttf"))
        glyphs, cmap = font.getGlyphSet(), font.getBestCmap()
        defs, advance = [], {}
        for c in "0123456789.-":
            pen = SVGPathPen(glyphs)
            glyphs[cmap[ord(c)]].draw(pen)
            defs.append(f'<path id="g{ord(c)}" d="{pen.getCommands()}"/>')
            advance[c] = glyphs[cmap[ord(c)]].width
        glyph_defs = "".join(defs)
        for i in range(200):
            text = f"{rng.uniform(-4, 4):.1f}"
            x, uses = 0.0, []
            for c in text:
                move = f' transform="translate({x:.6f} 0)"' if x else ""
                uses.append(f'<use xlink:href="#g{ord(c)}"{move}/>')
                x += advance[c]
            labels.append(f'<g transform="translate({50 + i % 20 * 35:.4f} '
                          f'{30 + i // 20 * 50:.4f}) scale(0.01 -0.01)">{"".join(uses)}</g>')
    return f'{SVG}width="720pt" height="540pt" viewBox="0 0 720 540"><defs>' \
        f'<style type="text/css">*{{stroke-linejoin: round; stroke-linecap: butt}}</style>' \
        f'{marker}{glyph_defs}</defs><g clip-path="url(#p0)">{dots}</g>' \
        f'<g style="fill: #262626">{"".join(labels)}</g><defs><clipPath id="p0"><rect x="40" ' \
        f'y="20" width="640" height="500"/></clipPath></defs></svg>'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--fonts", help="the resvg suite's fonts/ (for glyph_uses.svg)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    docs = {"scatter": scatter, "classes": classes, "graph": graph, "ticks": ticks,
            "xlists": xlists, "plot_markers": lambda rng: plot_markers(rng, args.fonts)}
    if args.fonts:
        docs["glyph_uses"] = lambda rng: glyph_uses(rng, args.fonts)
    for name, make in docs.items():
        with open(os.path.join(args.out, name + ".svg"), "w", encoding="utf-8") as f:
            f.write(make(random.Random(30)))
        print(os.path.join(args.out, name + ".svg"))


if __name__ == "__main__":
    main()
