"""Growth of cost with document size: documents of many shapes, each made at n and 4n, loaded
and drawn in a fresh process; a shape whose time grows more than six-fold at 4n is flagged
(docs/svg.md, "Session 29, growth of cost with document size" and "... with text size").

    python tools/growth.py --list                         # the shapes
    python tools/growth.py SHAPE:N ... [--width 200] [--fonts DIR]
    python tools/growth.py --write SHAPE N > doc.svg      # one document

Each line: build and draw seconds at n and 4n (``load_svg`` and ``render_scene_rgba8`` on one
thread) and the process's peak memory (``/usr/bin/time -f "%e %M"``). Text shapes want the
resvg suite's fonts (``--fonts ../shared/resvg-suite/fonts``). The machine's noise moves
single figures by up to 3x: measure a flagged shape again alone.
"""
import argparse
import base64
import os
import struct
import subprocess
import sys
import tempfile
import time
import zlib

HEAD = ('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
        'width="200" height="200" viewBox="0 0 200 200">')
END = "</svg>"

def doc(body, head=HEAD):
    return head + body + END

def png_1x1():
    """A data URI of a 4 x 1 red PNG."""
    def chunk(t, d):
        c = struct.pack('>I', len(d)) + t + d
        return c + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    data = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 4, 1, 8, 6, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(b'\x00' + b'\xff\x00\x00\xff' * 4)) + chunk(b'IEND', b''))
    return 'data:image/png;base64,' + base64.b64encode(data).decode()

def xy(i, n):
    return (i * 37) % 190 + 5, (i * 91) % 190 + 5

S = {}

def shape(f):
    S[f.__name__] = f
    return f

@shape
def siblings(n):
    return doc(''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3" fill="#{i%4096:03x}"/>' for i in range(n)))
@shape
def deep_g(n):
    return doc('<g opacity="1">' * n + '<rect width="50" height="50"/>' + '</g>' * n)
@shape
def deep_g_transform(n):
    return doc('<g transform="translate(0.1 0.1)">' * n + '<rect width="50" height="50"/>' + '</g>' * n)
@shape
def deep_g_opacity(n):
    return doc('<g opacity="0.99">' * n + '<rect width="50" height="50"/>' + '</g>' * n)
@shape
def deep_em(n):
    return doc('<g font-size="1em" stroke-width="1em">' * n + '<rect width="50" height="50" stroke="red"/>' + '</g>' * n)
@shape
def use_chain(n):
    b = '<defs><rect id="u0" width="5" height="5"/></defs>'
    b += ''.join(f'<use id="u{i}" xlink:href="#u{i-1}" x="0.01"/>' for i in range(1, n))
    return doc(b)
@shape
def use_fanout(n):
    b = '<defs><g id="s"><rect width="5" height="5"/><circle r="2"/></g></defs>'
    b += ''.join(f'<use xlink:href="#s" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}"/>' for i in range(n))
    return doc(b)
@shape
def use_glyphs(n):  # pdftocairo's text: 50 glyph symbols, n <use> of them in lines
    d = ''.join(f'<symbol overflow="visible" id="glyph0-{k}"><path style="stroke:none;" '
                f'd="M{k} 0L{300 + 7 * k} 0Q520 {200 + k} {300 + 7 * k} 700L{k} 700Z'
                f'M100 100L200 100L150 {400 + k}Z" transform="scale(0.01,-0.01)"/></symbol>'
                for k in range(50))
    b = ''.join(f'<use xlink:href="#glyph0-{(i * 7) % 50}" x="{(i % 40) * 4.9 + 2:.3f}" '
                f'y="{(i // 40) % 190 + 8}"/>' for i in range(n))
    return doc(f'<defs><g>{d}</g></defs><g style="fill:rgb(0%,0%,0%);fill-opacity:1;">{b}</g>')
@shape
def use_forward(n):
    b = ''.join(f'<use xlink:href="#r{i}"/>' for i in range(n))
    b += '<defs>' + ''.join(f'<rect id="r{i}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="2" height="2"/>' for i in range(n)) + '</defs>'
    return doc(b)
@shape
def css_rules(n):  # n rules, 200 elements
    st = ''.join(f'.c{i}{{fill:#{i%4096:03x}}}' for i in range(n))
    return doc(f'<style>{st}</style>' + ''.join(f'<rect class="c{i*7%n}" x="{xy(i,200)[0]}" y="{xy(i,200)[1]}" width="3" height="3"/>' for i in range(200)))
@shape
def css_elems(n):  # 200 rules, n elements
    st = ''.join(f'.c{i}{{fill:#{i%4096:03x}}}' for i in range(200))
    return doc(f'<style>{st}</style>' + ''.join(f'<rect class="c{i%200}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def css_nth(n):
    st = 'rect:nth-child(3n+1){fill:red} rect:nth-last-child(2n){fill:blue} rect:nth-of-type(5n){fill:green}'
    return doc(f'<style>{st}</style>' + ''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def css_sibling(n):
    st = 'rect ~ rect{fill:red} rect + circle{fill:blue} g rect{stroke:green}'
    return doc(f'<style>{st}</style>' + ''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def css_deep_descendant(n):
    st = 'g rect{fill:red} g g g g rect{stroke:blue} svg > g rect{opacity:0.5}'
    return doc(f'<style>{st}</style>' + '<g>' * n + '<rect width="9" height="9"/>' * 10 + '</g>' * n)
@shape
def css_ids(n):
    st = ''.join(f'#e{i}{{fill:#{i%4096:03x}}}' for i in range(n))
    return doc(f'<style>{st}</style>' + ''.join(f'<rect id="e{i}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def style_attr_long(n):
    st = ';'.join(f'fill:#{i%4096:03x}' for i in range(n))
    return doc(f'<rect width="50" height="50" style="{st}"/>')
@shape
def style_attr_many(n):
    return doc(''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3" style="fill:red;stroke:blue;stroke-width:0.5;opacity:0.9"/>' for i in range(n)))
@shape
def many_classes(n):
    cl = ' '.join(f'k{i}' for i in range(n))
    st = ''.join(f'.k{i}{{stroke-width:{i%5}}}' for i in range(0, n, 10))
    return doc(f'<style>{st}</style><rect width="50" height="50" stroke="red" class="{cl}"/>')
@shape
def css_vars_chain(n):
    st = ':root{--v0:red;' + ''.join(f'--v{i}:var(--v{i-1});' for i in range(1, n)) + '}' + f'rect{{fill:var(--v{n-1})}}'
    return doc(f'<style>{st}</style><rect width="50" height="50"/>')
@shape
def css_vars_many(n):
    st = ':root{' + ''.join(f'--v{i}:#{i%4096:03x};' for i in range(n)) + '}'
    return doc(f'<style>{st}</style>' + ''.join(f'<rect style="fill:var(--v{i})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def gradients(n):
    d = ''.join(f'<linearGradient id="g{i}"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="#{i%4096:03x}"/></linearGradient>' for i in range(n))
    return doc(f'<defs>{d}</defs>' + ''.join(f'<rect fill="url(#g{i})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def gradient_stops(n):
    st = ''.join(f'<stop offset="{i/n:.6f}" stop-color="#{i%4096:03x}"/>' for i in range(n))
    return doc(f'<linearGradient id="g">{st}</linearGradient><rect fill="url(#g)" width="200" height="200"/>')
@shape
def gradient_href_chain(n):
    d = '<linearGradient id="g0"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>'
    d += ''.join(f'<linearGradient id="g{i}" xlink:href="#g{i-1}"/>' for i in range(1, n))
    return doc(f'<defs>{d}</defs>' + ''.join(f'<rect fill="url(#g{i})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(0, n, max(1, n // 100))))
@shape
def gradient_one_many_refs(n):
    d = '<linearGradient id="g"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>'
    return doc(f'<defs>{d}</defs>' + ''.join(f'<rect fill="url(#g)" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def missing_refs(n):
    return doc(''.join(f'<rect fill="url(#nope{i}) red" clip-path="url(#x{i})" mask="url(#m)" filter="url(#f)" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def patterns(n):
    d = ''.join(f'<pattern id="p{i}" width="2" height="2" patternUnits="userSpaceOnUse"><rect width="1" height="1" fill="#{i%4096:03x}"/></pattern>' for i in range(n))
    return doc(f'<defs>{d}</defs>' + ''.join(f'<rect fill="url(#p{i})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def pattern_href_chain(n):
    d = '<pattern id="p0" width="4" height="4" patternUnits="userSpaceOnUse"><rect width="2" height="2"/></pattern>'
    d += ''.join(f'<pattern id="p{i}" xlink:href="#p{i-1}"/>' for i in range(1, n))
    return doc(f'<defs>{d}</defs><rect fill="url(#p{n-1})" width="200" height="200"/>')
@shape
def pattern_many_children(n):
    d = '<pattern id="p" width="200" height="200" patternUnits="userSpaceOnUse">' + ''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="1" height="1"/>' for i in range(n)) + '</pattern>'
    return doc(f'<defs>{d}</defs><rect fill="url(#p)" width="200" height="200"/>')
def reference_shapes(name, tag, attr, key, paint):
    """The shapes of clip paths (name "clip") and masks ("mask"): one for each element
    (NAMEs), a chain of them each referencing the one before (NAME_chain), one referenced by
    every element (NAME_one_many_refs). ``paint``: what the content needs to show."""
    def each(n):
        d = ''.join(f'<{tag} id="{key}{i}"><circle cx="{xy(i,n)[0]}" cy="{xy(i,n)[1]}" r="2"{paint}/></{tag}>' for i in range(n))
        return doc(f'<defs>{d}</defs>' + ''.join(f'<rect {attr}="url(#{key}{i})" x="{xy(i,n)[0]-2}" y="{xy(i,n)[1]-2}" width="4" height="4"/>' for i in range(n)))

    def chain(n):
        d = f'<{tag} id="{key}0"><rect width="150" height="150"{paint}/></{tag}>'
        d += ''.join(f'<{tag} id="{key}{i}" {attr}="url(#{key}{i-1})"><rect x="{i*0.01}" width="190" height="190"{paint}/></{tag}>' for i in range(1, n))
        return doc(f'<defs>{d}</defs><rect {attr}="url(#{key}{n-1})" width="200" height="200"/>')

    def one_many_refs(n):
        d = f'<{tag} id="{key}"><circle cx="100" cy="100" r="90"{paint}/></{tag}>'
        return doc(f'<defs>{d}</defs>' + ''.join(f'<rect {attr}="url(#{key})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))

    S[f"{name}s"], S[f"{name}_chain"], S[f"{name}_one_many_refs"] = each, chain, one_many_refs


reference_shapes("clip", "clipPath", "clip-path", "c", "")
reference_shapes("mask", "mask", "mask", "m", ' fill="white"')
@shape
def clip_many_children(n):
    d = '<clipPath id="c">' + ''.join(f'<rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="2" height="2"/>' for i in range(n)) + '</clipPath>'
    return doc(f'<defs>{d}</defs><rect clip-path="url(#c)" width="200" height="200"/>')
@shape
def markers(n):
    pts = ' '.join(f'{xy(i,n)[0]},{xy(i,n)[1]}' for i in range(n))
    return doc(f'<marker id="m" markerWidth="3" markerHeight="3" refX="1" refY="1" orient="auto"><circle cx="1" cy="1" r="1"/></marker><polyline fill="none" stroke="black" stroke-width="0.1" marker-start="url(#m)" marker-mid="url(#m)" marker-end="url(#m)" points="{pts}"/>')
@shape
def path_lines(n):
    return doc('<path stroke="black" stroke-width="0.3" fill="none" d="M5 5' + ''.join(f' L{xy(i,n)[0]} {xy(i,n)[1]}' for i in range(n)) + '"/>')
@shape
def path_rel_implicit(n):
    return doc('<path fill="red" d="M100 100l' + ''.join(' 1 0 0 1 -1 0 0 -1' for i in range(n // 4)) + 'z"/>')
@shape
def path_arcs(n):
    return doc('<path stroke="black" fill="none" d="M100 100' + ''.join(f' a3 2 {i%90} {i%2} {(i//2)%2} {(-1)**i*2} 1' for i in range(n)) + '"/>')
@shape
def path_curves(n):
    return doc('<path stroke="black" stroke-width="0.5" fill="none" d="M5 5' + ''.join(f' Q{xy(i,n)[0]} {xy(i+1,n)[1]} {xy(i,n)[0]} {xy(i,n)[1]}' for i in range(n)) + '"/>')
@shape
def path_smooth(n):
    return doc('<path fill="blue" d="M100 100' + ''.join(f' s1 {(-1)**i} 1 0 t 1 1' for i in range(n // 2)) + 'z"/>')
@shape
def path_subpaths(n):
    return doc('<path fill="red" d="' + ''.join(f'M{xy(i,n)[0]} {xy(i,n)[1]}h2v2h-2z' for i in range(n)) + '"/>')
@shape
def path_subpaths_stroke(n):
    return doc('<path fill="none" stroke="red" stroke-width="0.5" d="' + ''.join(f'M{xy(i,n)[0]} {xy(i,n)[1]}h2v2h-2z' for i in range(n)) + '"/>')
@shape
def polyline(n):
    pts = ' '.join(f'{xy(i,n)[0]},{xy(i,n)[1]}' for i in range(n))
    return doc(f'<polyline fill="none" stroke="black" stroke-width="0.2" points="{pts}"/>')
@shape
def polygon_fill(n):
    pts = ' '.join(f'{xy(i,n)[0]},{xy(i,n)[1]}' for i in range(n))
    return doc(f'<polygon fill="black" fill-rule="evenodd" points="{pts}"/>')
@shape
def dash_array_long(n):
    da = ' '.join(str(1 + i % 3) for i in range(n))
    return doc(f'<path stroke="black" fill="none" stroke-dasharray="{da}" d="M0 100 H200000"/>')
@shape
def dashes_many(n):  # n dashes (MAX_DASHES 1e5)
    return doc(f'<path stroke="black" fill="none" stroke-width="0.5" stroke-dasharray="1 1" d="M0 0 l{2*n} 0" transform="scale({200/(2*n)*4} 1) translate(0 50)"/>')
@shape
def dashes_many_segments(n):
    return doc('<path stroke="black" fill="none" stroke-width="0.5" stroke-dasharray="3 2" d="M5 5' + ''.join(f' L{xy(i,n)[0]} {xy(i,n)[1]}' for i in range(n)) + '"/>')
@shape
def filter_chain(n):
    prims = ''.join(f'<feOffset dx="0.01" result="r{i}"/>' for i in range(n))
    return doc(f'<filter id="f">{prims}</filter><rect filter="url(#f)" x="50" y="50" width="100" height="100"/>')
@shape
def filter_chain_named(n):
    prims = '<feOffset in="SourceGraphic" result="r0"/>' + ''.join(f'<feComposite in="r{i-1}" in2="SourceAlpha" operator="over" result="r{i}"/>' for i in range(1, n))
    return doc(f'<filter id="f">{prims}</filter><rect filter="url(#f)" x="50" y="50" width="100" height="100"/>')
@shape
def filters_many(n):
    d = ''.join(f'<filter id="f{i}"><feOffset dx="1"/></filter>' for i in range(n))
    return doc(f'<defs>{d}</defs>' + ''.join(f'<rect filter="url(#f{i})" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def filter_merge(n):
    nodes = ''.join('<feMergeNode in="SourceGraphic"/>' for i in range(n))
    return doc(f'<filter id="f"><feMerge>{nodes}</feMerge></filter><rect filter="url(#f)" x="50" y="50" width="100" height="100" fill-opacity="0.01"/>')
@shape
def filter_list(n):
    fl = ' '.join('url(#f)' for i in range(n))
    return doc(f'<filter id="f"><feOffset dx="0.1"/></filter><rect style="filter:{fl}" x="50" y="50" width="100" height="100"/>')
@shape
def filter_func_list(n):
    fl = ' '.join('opacity(0.999)' for i in range(n))
    return doc(f'<rect style="filter:{fl}" x="50" y="50" width="100" height="100"/>')
@shape
def filter_href_chain(n):
    d = '<filter id="f0"><feOffset dx="1"/></filter>' + ''.join(f'<filter id="f{i}" xlink:href="#f{i-1}"/>' for i in range(1, n))
    return doc(f'<defs>{d}</defs><rect filter="url(#f{n-1})" x="50" y="50" width="100" height="100"/>')
@shape
def images_same_uri(n):
    u = png_1x1()
    return doc(''.join(f'<image href="{u}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def images_svg_uri(n):
    inner = base64.b64encode(b'<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><rect width="4" height="2" fill="red"/></svg>').decode()
    return doc(''.join(f'<image href="data:image/svg+xml;base64,{inner}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def ids_many(n):
    return doc(''.join(f'<rect id="id{i}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def ids_duplicate(n):
    return doc(''.join(f'<rect id="same" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)) + '<use href="#same"/>')
@shape
def entities(n):
    head = '<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY r "<rect width=\'3\' height=\'3\'/>"><!ENTITY c "red">]>' + HEAD
    return head + '<g fill="&c;">&r;</g>' * n + END
@shape
def entities_many_decl(n):
    decl = ''.join(f'<!ENTITY e{i} "<rect x=\'{xy(i,n)[0]}\' y=\'{xy(i,n)[1]}\' width=\'3\' height=\'3\'/>">' for i in range(n))
    head = f'<?xml version="1.0"?><!DOCTYPE svg [{decl}]>' + HEAD
    return head + ''.join(f'&e{i};' for i in range(n)) + END
@shape
def switch_lang(n):
    ch = ''.join(f'<rect systemLanguage="x{i}" width="5" height="5"/>' for i in range(n)) + '<rect width="9" height="9"/>'
    return doc(f'<switch>{ch}</switch>')
@shape
def switch_many(n):
    return doc(''.join(f'<switch><rect systemLanguage="zz" width="5" height="5"/><rect requiredFeatures="" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/></switch>' for i in range(n)))
@shape
def nested_svg(n):
    return doc('<svg viewBox="0 0 100 100" width="99%" height="99%" preserveAspectRatio="xMidYMid">' * n + '<rect width="100" height="100"/>' + '</svg>' * n)
@shape
def sibling_svgs(n):
    return doc(''.join(f'<svg x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3" viewBox="0 0 10 10"><rect width="10" height="10"/></svg>' for i in range(n)))
@shape
def transforms_many(n):
    return doc(''.join(f'<rect transform="translate({xy(i,n)[0]} {xy(i,n)[1]}) rotate({i%360}) scale(1.01)" width="3" height="3"/>' for i in range(n)))
@shape
def transform_list_long(n):
    t = ' '.join('translate(0.001 0)' for i in range(n))
    return doc(f'<rect transform="{t}" width="50" height="50"/>')
@shape
def tiny_segments(n):
    return doc('<path fill="red" d="M50 50' + ''.join(f' l{1e-4} {1e-4*((-1)**i)}' for i in range(n)) + ' L150 150 L50 150z"/>')
@shape
def offcanvas_path(n):
    return doc('<path fill="red" stroke="blue" d="M-1000 -1000' + ''.join(f' L{-1000 - (i%50)} {-1000 - i}' for i in range(n)) + ' z"/>')
@shape
def offcanvas_elems(n):
    return doc(''.join(f'<rect x="{-1000-i}" y="-500" width="3" height="3"/>' for i in range(n)))
@shape
def symbols(n):
    d = ''.join(f'<symbol id="s{i}" viewBox="0 0 10 10"><rect width="10" height="10"/></symbol>' for i in range(n))
    return doc(d + ''.join(f'<use href="#s{i}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def anchors(n):
    return doc(''.join(f'<a href="#x"><rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/></a>' for i in range(n)))
@shape
def opacity_groups(n):
    return doc(''.join(f'<g opacity="0.5"><rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/></g>' for i in range(n)))
@shape
def style_elements(n):
    return doc(''.join(f'<style>.c{i}{{fill:red}}</style><rect class="c{i}" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))
@shape
def whitespace_comments(n):
    return doc(''.join(f'<!-- c{i} -->\n   <rect x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>\n' for i in range(n)))
@shape
def markers_many_paths(n):
    return doc('<marker id="m" markerWidth="3" markerHeight="3"><circle cx="1" cy="1" r="1"/></marker>' + ''.join(f'<line marker-end="url(#m)" stroke="black" x1="0" y1="0" x2="{xy(i,n)[0]}" y2="{xy(i,n)[1]}"/>' for i in range(n)))
@shape
def stroke_wide_many(n):
    return doc(''.join(f'<circle stroke="black" stroke-width="2" fill="none" cx="{xy(i,n)[0]}" cy="{xy(i,n)[1]}" r="3"/>' for i in range(n)))
@shape
def attr_many(n):
    attrs = ' '.join(f'data-a{i}="{i}"' for i in range(n))
    return doc(f'<rect {attrs} width="50" height="50"/>')
@shape
def paint_order_many(n):
    return doc(''.join(f'<rect paint-order="stroke markers" stroke="red" stroke-linejoin="round" x="{xy(i,n)[0]}" y="{xy(i,n)[1]}" width="3" height="3"/>' for i in range(n)))

@shape
def pattern_nest(n):
    d = '<pattern id="p0" width="4" height="4" patternUnits="userSpaceOnUse"><rect width="2" height="2"/></pattern>'
    d += ''.join(f'<pattern id="p{i}" width="4" height="4" patternUnits="userSpaceOnUse"><rect width="3" height="3" fill="url(#p{i-1})"/></pattern>' for i in range(1, n))
    return doc(f'<defs>{d}</defs><rect fill="url(#p{n-1})" width="200" height="200"/>')
@shape
def marker_nest(n):
    d = '<marker id="m0" markerWidth="3" markerHeight="3"><circle cx="1" cy="1" r="1"/></marker>'
    d += ''.join(f'<marker id="m{i}" markerWidth="3" markerHeight="3"><path d="M0 0L1 1" stroke="black" marker-end="url(#m{i-1})"/></marker>' for i in range(1, n))
    return doc(d + f'<path d="M10 10L100 100" stroke="black" marker-end="url(#m{n-1})"/>')
@shape
def use_nest_g(n):  # each symbol holds a use of the previous inside 30 groups
    d = '<g id="u0"><rect width="2" height="2"/></g>'
    d += ''.join(f'<g id="u{i}">' + '<g>' * 30 + f'<use href="#u{i-1}" x="0.1"/>' + '</g>' * 30 + '</g>' for i in range(1, n))
    return doc(f'<defs>{d}</defs><use href="#u{n-1}"/>')


# -- text (the suite's fonts: --fonts DIR) ---------------------------------------------------
TEXT_SHAPES = {
    "text_latin": lambda n: f'<text y="20">{"Hamburg " * n}</text>',
    "text_tspans": lambda n: '<text y="20">' + '<tspan fill="red">ab</tspan> ' * n + '</text>',
    "text_x_list": lambda n: '<text y="20" x="' + " ".join(str(i % 200) for i in range(n))
    + '">' + "a" * n + '</text>',
    "text_dx_list": lambda n: '<text y="20" x="0" dx="' + " 0.1" * n + '">' + "a" * n + '</text>',
    "text_rotate_list": lambda n: '<text y="20" x="0" rotate="' + " 5" * n + '">' + "a" * n
    + '</text>',
    "text_chunks": lambda n: '<text y="20">' + "".join(f'<tspan x="{i % 200}">ab</tspan>'
                                                      for i in range(n)) + '</text>',
    "text_length_spans": lambda n: '<text y="20" textLength="150">'
    + '<tspan textLength="10">ab</tspan>' * n + '</text>',
    "text_letter_spacing": lambda n: f'<text y="20" letter-spacing="1">{"ab " * n}</text>',
    "text_decoration_spans": lambda n: '<text y="20" text-decoration="underline">'
    + '<tspan fill="red">ab</tspan> ' * n + '</text>',
    "text_vertical": lambda n: f'<text x="100" y="0" writing-mode="tb">{"Ab日١ " * n}</text>',
    "text_upright": lambda n: '<text x="100" y="0" writing-mode="tb" '
    f'style="text-orientation:upright">{"Ab日١ " * n}</text>',
    "text_bidi_runs": lambda n: f'<text y="20">{"Abc 日本 ١٢٣ " * n}</text>',
    "text_arabic": lambda n: f'<text x="190" y="20" font-family="Amiri">{"مرحبا عالم " * n}</text>',
    "text_fallback": lambda n: f'<text y="20" font-family="Noto Sans">{"a日ж😀ह " * n}</text>',
    "text_zwj_spaced": lambda n: '<text y="20" letter-spacing="1" font-family="Twitter Color '
    'Emoji">' + "\U0001F3F3\uFE0F\u200D\U0001F308 " * n + '</text>',
    "text_on_long_path": lambda n: '<path id="p" d="M0 100 ' + " ".join(
        f"L{(i * 0.01) % 200:.2f} {100 + i % 7}" for i in range(n))
    + '"/><text><textPath href="#p">' + "ab " * n + '</textPath></text>',
    "text_many": lambda n: '<text y="20">ab</text>' * n,
}
for _name, _make in TEXT_SHAPES.items():
    S[_name] = (lambda make: lambda n: doc(make(n)))(_make)


def time_one(path, width, fonts):
    """Print the build and draw seconds of one document (run in its own process)."""
    import warnings
    warnings.simplefilter("ignore")
    from vecmsaa.api import load_svg
    from vecmsaa.raster.modes import samples_for
    from vecmsaa.raster.render import render_scene_rgba8
    options = dict(use_fonts_dir=fonts, skip_system_fonts=True) if fonts else {}
    data = open(path, "rb").read()
    t0 = time.perf_counter()
    try:
        scene = load_svg(data, width=width, **options)
        t1 = time.perf_counter()
        render_scene_rgba8(scene, threads=1, samples=samples_for(None, scene.width,
                                                                  scene.height))
        print(f"{t1 - t0:.3f} {time.perf_counter() - t1:.3f}")
    except Exception as e:
        print(f"{time.perf_counter() - t0:.3f} error {type(e).__name__}")


def measure(shape, n, width, fonts, folder):
    """(build s, draw s or 'error', peak MB) of the shape at n, in a fresh process."""
    path = os.path.join(folder, f"{shape}_{n}.svg")
    with open(path, "w", encoding="utf-8") as f:
        f.write(S[shape](n))
    cmd = [sys.executable, os.path.abspath(__file__), "--time", path, str(width)]
    if fonts:
        cmd += ["--fonts", fonts]
    if os.path.exists("/usr/bin/time"):
        cmd = ["/usr/bin/time", "-f", "%e %M"] + cmd
    r = subprocess.run(cmd, capture_output=True, text=True)
    build, draw = (r.stdout.split() + ["?", "?"])[:2]
    lines = r.stderr.strip().splitlines()
    peak = int(lines[-1].split()[1]) // 1024 if lines and lines[-1].count(" ") == 1 else 0
    return build, draw, peak


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="*", metavar="SHAPE:N")
    ap.add_argument("--width", type=int, default=200)
    ap.add_argument("--fonts", help="font folder (text shapes: the resvg suite's fonts/)")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--write", nargs=2, metavar=("SHAPE", "N"))
    ap.add_argument("--time", nargs=2, metavar=("FILE", "WIDTH"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.time:
        time_one(args.time[0], int(args.time[1]), args.fonts)
    elif args.list:
        print("\n".join(S))
    elif args.write:
        sys.stdout.write(S[args.write[0]](int(args.write[1])))
    else:
        with tempfile.TemporaryDirectory() as folder:
            for run in args.runs:
                shape, n = run.rsplit(":", 1)
                a, b = (measure(shape, k, args.width, args.fonts, folder)
                        for k in (int(n), 4 * int(n)))
                try:
                    grew = max(float(b[i]) / max(float(a[i]), 0.05) for i in (0, 1))
                except ValueError:
                    grew = 0.0
                flag = "  <<<" if grew > 6 else ""
                print(f"{shape:24s} n={n:>7s}  build {a[0]} / {b[0]}  draw {a[1]} / {b[1]}  "
                      f"peak MB {a[2]} / {b[2]}{flag}", flush=True)


if __name__ == "__main__":
    main()
