#!/usr/bin/env python3
"""Mutation fuzzer for the SVG parser (and renderer), the path-data parser and font loading.

    python tools/fuzz.py --seconds 300 [--targets svg,svgtree,pathdata,font] [--seed N]
                         [--save tests/fuzz_regressions] [--memory-mb 2048]

Seeds are the resvg suite's SVGs and fonts (../shared, when present) and the project's fixture
fonts. ``svg``, ``pathdata`` and ``font`` mutate bytes (flips, deletions, duplications, splices
between seeds and insertion of hostile tokens: huge numbers, NaN, deep nesting, references,
entities). ``svgtree`` mutates the seeds' element trees: extreme numbers in attribute values,
attributes swapped between elements, elements duplicated many times, and elements nested in
copies of themselves or of other elements (fan-out of references, filters, masks, markers).
``--memory-mb`` caps the address space above the warmed-up process, so that an input needing
that much more memory is a crash (MemoryError) instead of a swap storm.

A *crash* is any exception other than the documented errors: :class:`vecmsaa.svg.SvgError` or
another ``ValueError`` with a message for documents and path data (path data never raises: a
bad path renders up to its last good segment), :class:`vecmsaa.fonts.FontError` for fonts; an
input that runs for more than ``--timeout`` seconds is a crash too. Each new crash (by exception
type and place) is saved to the ``--save`` folder as a regression input; tests/test_fuzz.py
loads every file there.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import random
import signal
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SHARED = os.path.join(os.path.dirname(REPO), "shared")
REGRESSIONS = os.path.join(REPO, "tests", "fuzz_regressions")
EXTENSIONS = {"svg": ".svg", "svgtree": ".svg", "pathdata": ".d.txt", "font": ".font"}
#: finds of a target are saved (and replayed by tests/test_fuzz.py) as this kind of input
SAVED_AS = {"svgtree": "svg"}

#: fragments that stress the parser: numbers at the limits, references, nesting, entities
SVG_TOKENS = [
    b"1e308", b"-1e308", b"1e999", b"NaN", b"inf", b"-0", b"0", b"1e-320", b"99999999999",
    b' transform="scale(1e300)"', b' transform="matrix(0 0 0 0 0 0)"',
    b' transform="rotate(45) skewX(90)"', b' stroke-width="1e300"', b' stroke-width="-5"',
    b' stroke-dasharray="0 0"', b' stroke-dasharray="1e-300"', b' opacity="NaN"',
    # custom properties: cycles, self-reference, nested fallbacks, doubling chains, var() in
    # shorthands and in presentation attributes
    b' style="--a: var(--a); fill: var(--a, red)"', b' style="--b: var(--a) var(--a)"',
    b' style="stroke-width: var(--w, var(--v, 1e308))"', b' fill="var(--b)"',
    b' style="marker: var(--m); font: var(--f, bold 1e300px serif)"', b' style="--m: url(#a)"',
    b' style="white-space: var(--a, pre); --a: pre-wrap"', b' stroke-dasharray="1e-9 1e9"',
    b' d="M0 0 A 1e308 1e308 0 1 1 1 1"', b' d="M0 0 L 1e308 1e308 Z"',
    b' d="M 0 0 C 0 0 0 0 0 0 Z"', b' d="M1 1 a0 0 0 0 0 5 5"', b' viewBox="0 0 0 0"',
    b' viewBox="0 0 1e-300 1e-300"', b' width="-1"', b' height="1e9"', b' href="#a"',
    b' xlink:href="#a"', b' id="a"', b' clip-path="url(#a)"', b' mask="url(#a)"',
    b' fill="url(#a)"', b' filter="url(#a)"', b' marker-start="url(#a)"',
    b' font-size="1e300"', b' font-size="0"', b' x="1e308"', b' r="-1"', b' rx="1e308"',
    b"<use href='#a'/>", b"<g id='a'><use href='#a'/></g>", b"<g>" * 50, b"</g>" * 50,
    b"<text>abc</text>", b"<textPath href='#a'>x</textPath>", b"<tspan dx='1e308'>y</tspan>",
    b"<linearGradient id='a'><stop offset='NaN'/></linearGradient>",
    b"<pattern id='a' width='0' height='1e-300'/>", b"<clipPath id='a'><use href='#a'/></clipPath>",
    b"<marker id='a' markerWidth='1e300'/>", b"<image href='data:image/png;base64,iVBORw0K'/>",
    b"<!ENTITY e 'x'>", b"&e;", b"&#0;", b"&#x110000;", b"<![CDATA[", b"]]>", b"\x00", b"\xff\xfe",
    b"<style>* { fill: url(#a) }</style>", b"style='fill:#zzz;stroke:rgb(1e999,0,0)'",
]
PATH_TOKENS = ["M", "m", "L", "l", "H", "h", "V", "v", "C", "c", "S", "s", "Q", "q", "T", "t",
               "A", "a", "Z", "z", " ", ",", "-", ".", "e", "E", "+", "0", "1", "9", "1e308",
               "1e-308", "1e999", "NaN", "inf", "-.5.5", "0 0 0 0 0 0 0", "1 1 0 11 1 1",
               "00", "\t", "\n", "\x00", "\u00a0", "٣"]


# -- seeds ------------------------------------------------------------------------------------
def svg_seeds(limit=400, rng=None):
    seeds = []
    suite = os.path.join(SHARED, "resvg-suite", "tests")
    if os.path.isdir(suite):
        for root, _dirs, files in os.walk(suite):
            for name in files:
                if name.endswith(".svg"):
                    seeds.append(os.path.join(root, name))
    seeds.sort()
    if rng is not None and len(seeds) > limit:
        seeds = rng.sample(seeds, limit)
    data = []
    for path in seeds:
        try:
            with open(path, "rb") as f:
                data.append((f.read(), os.path.dirname(path)))
        except OSError:
            pass
    data.append((b'<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64">'
                 b'<path d="M10 10 C 20 60 50 0 60 60 Z" fill="red" stroke="blue"/>'
                 b'<circle cx="30" cy="30" r="20" opacity="0.5"/></svg>', None))
    return data


def font_seeds():
    out = []
    for folder in (os.path.join(REPO, "fixtures", "fonts"),
                   os.path.join(SHARED, "resvg-suite", "fonts")):
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            path = os.path.join(folder, name)
            if name.lower().endswith((".ttf", ".otf", ".ttc")) and os.path.getsize(path) < 400_000:
                with open(path, "rb") as f:
                    out.append(f.read())
    return out


def path_seeds(svgs):
    import re
    out = set()
    for data, _ in svgs:
        for m in re.finditer(rb'\sd="([^"]{1,2000})"', data):
            out.add(m.group(1).decode("utf-8", "replace"))
    out.update(["M0 0L10 10", "M1,2c3,4 5,6 7,8s9,10 11,12z", "m0 0a5 5 0 1 0 10 0",
                "M0 0Q5 5 10 0T20 0", "M-1-2-3-4", "M.5.5.5.5", "M0 0h10v10H0Z"])
    return sorted(out)


# -- mutation ---------------------------------------------------------------------------------
def mutate_bytes(data: bytes, rng: random.Random, tokens, others) -> bytes:
    buf = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        op = rng.randrange(7)
        n = len(buf)
        if op == 0 and n:                       # flip bits of a byte
            i = rng.randrange(n)
            buf[i] ^= 1 << rng.randrange(8)
        elif op == 1 and n:                     # delete a range
            i = rng.randrange(n)
            del buf[i:i + rng.randint(1, 64)]
        elif op == 2 and n:                     # duplicate a range
            i = rng.randrange(n)
            chunk = buf[i:i + rng.randint(1, 256)]
            j = rng.randrange(len(buf) + 1)
            buf[j:j] = chunk
        elif op == 3 and tokens:                # insert a hostile token
            j = rng.randrange(len(buf) + 1)
            buf[j:j] = rng.choice(tokens)
        elif op == 4 and others:                # splice with another seed
            other = rng.choice(others)
            if other:
                i = rng.randrange(len(other))
                j = rng.randrange(len(buf) + 1)
                buf[j:j] = other[i:i + rng.randint(1, 512)]
        elif op == 5 and n:                     # overwrite with random bytes
            i = rng.randrange(n)
            for k in range(i, min(n, i + rng.randint(1, 8))):
                buf[k] = rng.randrange(256)
        elif op == 6 and n:                     # replace a number-like byte run
            i = rng.randrange(n)
            if chr(buf[i]).isdigit():
                buf[i:i + 1] = rng.choice([b"1e308", b"-1e308", b"NaN", b"0", b"1e-300",
                                           b"999999999"])
    return bytes(buf)


def mutate_text(text: str, rng: random.Random) -> str:
    chars = list(text)
    for _ in range(rng.randint(1, 8)):
        op = rng.randrange(4)
        if op == 0 and chars:
            del chars[rng.randrange(len(chars))]
        elif op == 1:
            chars.insert(rng.randrange(len(chars) + 1), rng.choice(PATH_TOKENS))
        elif op == 2 and chars:
            chars[rng.randrange(len(chars))] = rng.choice(PATH_TOKENS)
        else:
            i = rng.randrange(len(chars) + 1)
            chars[i:i] = list(rng.choice(PATH_TOKENS) + " " + rng.choice(PATH_TOKENS))
    return "".join(chars)


# -- structure-aware SVG mutation (target svgtree) ---------------------------------------------
SVG_NS = "http://www.w3.org/2000/svg"
XLINK_NS = "http://www.w3.org/1999/xlink"
EXTREME_NUMBERS = ["1e308", "-1e308", "1e-308", "1e400", "-1e400", "0", "-0", "1e9", "-1e9",
                   "65536", "2147483648", "4294967297", "1e-9", "0.000001", "NaN", "inf", "-1"]
_NUMBER = None


def parse_tree(data: bytes):
    """A seed's element tree, or None (seeds with entities or bad XML stay byte-mutated)."""
    import xml.etree.ElementTree as ET

    if b"<!ENTITY" in data or b"<!DOCTYPE" in data:
        return None
    try:
        return ET.fromstring(data)
    except (ET.ParseError, ValueError):
        return None


def serialize_tree(root) -> bytes:
    import xml.etree.ElementTree as ET

    ET.register_namespace("", SVG_NS)
    ET.register_namespace("xlink", XLINK_NS)
    return ET.tostring(root)


def mutate_tree(root, rng: random.Random, donors):
    """Mutate an element tree in place (1 to 4 operations); ``donors`` are other seeds' trees
    to take elements and attribute values from."""
    import copy
    import re

    global _NUMBER
    if _NUMBER is None:
        _NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
    elements = list(root.iter())
    parents = {child: parent for parent in elements for child in parent}
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(5)
        el = rng.choice(elements)
        if op == 0 and el.attrib:                   # an extreme number in an attribute
            name = rng.choice(list(el.attrib))
            numbers = list(_NUMBER.finditer(el.attrib[name]))
            value = el.attrib[name]
            if numbers:
                m = rng.choice(numbers)
                value = value[:m.start()] + rng.choice(EXTREME_NUMBERS) + value[m.end():]
            else:
                value = rng.choice(EXTREME_NUMBERS)
            el.set(name, value)
        elif op == 1:                               # attribute swap between elements
            donor_tree = rng.choice(donors) if donors and rng.random() < 0.5 else root
            donor = rng.choice(list(donor_tree.iter()))
            if donor.attrib:
                name = rng.choice(list(donor.attrib))
                if el.attrib and rng.random() < 0.5:    # swap values of two attributes
                    other = rng.choice(list(el.attrib))
                    el.set(other, donor.attrib[name])
                else:
                    el.set(name, donor.attrib[name])
        elif op == 2 and el in parents:             # duplicate an element many times
            parent = parents[el]
            n = min(rng.choice([2, 10, 100, 1000]), _room(elements, el))
            at = list(parent).index(el)
            for i in range(n):
                parent.insert(at + 1, copy.deepcopy(el))
            elements = list(root.iter())
            parents = {c: p for p in elements for c in p}
        elif op == 3 and el in parents:             # nest an element in copies of itself
            parent = parents[el]
            depth = min(rng.choice([2, 8, 50, 300]), _room(elements, el) - 1)
            if depth < 0:
                continue
            inner = copy.deepcopy(el)
            for _ in range(depth):
                outer = copy.deepcopy(el)
                outer.append(inner)
                inner = outer
            parent.insert(list(parent).index(el) + 1, inner)
            elements = list(root.iter())
            parents = {c: p for p in elements for c in p}
        elif op == 4:                               # graft an element of another seed
            donor_tree = rng.choice(donors) if donors else root
            graft = rng.choice(list(donor_tree.iter()))
            if _room(elements, graft) < 1:
                continue
            graft = copy.deepcopy(graft)
            target = rng.choice(elements)
            target.append(graft)
            elements = list(root.iter())
            if rng.random() < 0.5 and _room(elements, target) >= 1:
                graft.append(copy.deepcopy(target))     # and make it a wrapper of its parent
                elements = list(root.iter())
            parents = {c: p for p in elements for c in p}
    return root


#: characters a mutated tree may grow to when serialised (about): each copying operation is
#: cut to fit. Counted in characters, not elements: a thousand copies of an element holding a
#: 300-deep nest took the fuzzer's own memory, and so did 200,000 elements (the budget when it
#: counted elements) carrying a donor's long `d` or `style` (seed 2801 under --memory-mb 2048)
MAX_TREE_CHARS = 20_000_000


def _chars(el) -> int:
    """About how many characters ``el``'s subtree serialises to."""
    return sum(2 * len(e.tag) + 5 + len(e.text or "") + len(e.tail or "")
               + sum(len(k) + len(v) + 4 for k, v in e.attrib.items()) for e in el.iter())


def _room(elements, el):
    """How many more copies of ``el``'s subtree fit in a tree of ``elements`` (the root's
    ``iter()``, the root first)."""
    return max(0, MAX_TREE_CHARS - _chars(elements[0])) // max(1, _chars(el))


# -- targets: each returns normally or raises; documented errors are filtered by the caller ---
def run_svg(data: bytes, folder=None):
    from vecmsaa.api import load_svg
    from vecmsaa.raster.render import render_scene

    scene = load_svg(data, width=48)
    # render small: the renderer must cope with whatever the front end resolved
    if scene.width * scene.height <= 256 * 256:
        render_scene(scene, mode="approx", samples=4)


def run_pathdata(text: str):
    import numpy as np

    from vecmsaa.scene.path import VERB_POINTS, Path
    from vecmsaa.raster.render import render_scene
    from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
    from vecmsaa.svg.pathdata import parse_path_data

    path = parse_path_data(text)
    assert isinstance(path, Path)
    v, p = path.verbs, path.points
    assert len(p) == sum(VERB_POINTS[x] for x in v), "verbs and points disagree"
    if len(v) and np.isfinite(p).all():
        render_scene(Scene(16, 16, Group([Fill(path.transformed((0.1, 0, 0, 0.1, 0, 0)),
                                               Solid())])), mode="approx", samples=4)


def run_font(data: bytes):
    from vecmsaa.fonts import load_face
    from vecmsaa.fonts.shape import shape_text

    with tempfile.NamedTemporaryFile(suffix=".ttf", delete=False) as f:
        f.write(data)
        name = f.name
    try:
        face = load_face(name)
        for gid in range(min(face.num_glyphs, 12)):
            face.outline(gid)
            face.advance(gid)
        shape_text(face, "Hamburgefonstiv 123")
    finally:
        os.unlink(name)


def documented(target, exc) -> bool:
    """Is this exception one the target documents (with a message)?"""
    from vecmsaa.fonts import FontError

    if target == "pathdata":
        return False   # path data never raises
    if target == "font":
        return isinstance(exc, FontError) and bool(str(exc).strip())
    return isinstance(exc, ValueError) and bool(str(exc).strip())


class Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise Timeout("input took too long")


def crash_key(target, exc):
    tb = traceback.extract_tb(exc.__traceback__)
    frames = [f for f in tb if "vecmsaa" in f.filename] or tb
    last = frames[-1] if frames else None
    where = f"{os.path.basename(last.filename)}:{last.lineno}" if last else "?"
    return f"{target}:{type(exc).__name__}:{where}"


def run_one(target, item, timeout):
    """→ None, or (key, message) for a crash."""
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(timeout)
    try:
        if target in ("svg", "svgtree"):
            run_svg(item)
        elif target == "pathdata":
            run_pathdata(item)
        else:
            run_font(item)
    except Timeout as exc:
        return f"{target}:Timeout", str(exc)
    except RecursionError as exc:
        return crash_key(target, exc), f"RecursionError: {exc}"
    except Exception as exc:
        if documented(target, exc):
            return None
        return crash_key(target, exc), f"{type(exc).__name__}: {exc}"
    finally:
        signal.alarm(0)
    return None


def save_crash(folder, target, item, key, message):
    os.makedirs(folder, exist_ok=True)
    raw = item.encode("utf-8", "surrogatepass") if isinstance(item, str) else item
    digest = hashlib.sha1(raw).hexdigest()[:12]
    kind = SAVED_AS.get(target, target)
    path = os.path.join(folder, f"{kind}-{digest}{EXTENSIONS[kind]}")
    with open(path, "wb") as f:
        f.write(raw)
    with open(path + ".why", "w") as f:
        f.write(f"{key}\n{message[:500]}\n")
    return path


def warm_up():
    """Compile or load every kernel (fills, curves, line and curve strokes, dashes, text) before
    any alarm is armed: an alarm that fires inside numba's compiler or cache loader leaves it
    broken, which is not a bug of the input."""
    run_svg(b'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><path d="M0 0 C 8 0 '
            b'0 8 8 8 Q 4 0 0 0Z" stroke="red"/><path d="M0 0 L8 8 L0 8" stroke="blue" '
            b'stroke-dasharray="2 1" stroke-linejoin="round" stroke-linecap="round"/>'
            b'<path d="M1 1 H7 V7 Z" stroke="green" stroke-width="0.3"/>'
            b'<text y="6" font-size="4">x</text></svg>')
    run_pathdata("M0 0 C 50 0 0 50 50 50 Q 0 50 0 0 Z")


def fuzz(seconds=60.0, targets=("svg", "svgtree", "pathdata", "font"), seed=0, save=None,
         timeout=20, log=print, max_inputs=None, last_input=None, memory_mb=None):
    """Fuzz each target for an equal share of ``seconds``. Returns a report dict."""
    import logging
    import warnings
    logging.getLogger("fontTools").setLevel(logging.CRITICAL)
    warnings.simplefilter("ignore")      # broken glyphs warn; only exceptions are crashes
    rng = random.Random(seed)
    warm_up()
    if memory_mb:
        import resource
        with open("/proc/self/statm") as f:
            used = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        limit = used + memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    svgs = svg_seeds(rng=rng) if {"svg", "svgtree", "pathdata"} & set(targets) else []
    svg_bytes = [d for d, _ in svgs]
    trees = [t for t in (parse_tree(d) for d in svg_bytes) if t is not None] \
        if "svgtree" in targets else []
    paths = path_seeds(svgs) if "pathdata" in targets else []
    fonts = font_seeds() if "font" in targets else []
    report = {"seed": seed, "targets": {}}
    share = seconds / max(1, len(targets))
    for target in targets:
        if target == "font" and not fonts:
            log("font: no seed fonts, skipped")
            continue
        tried = 0
        crashes = {}
        end = time.monotonic() + share
        while time.monotonic() < end and (max_inputs is None or tried < max_inputs):
            if target == "svg":
                item = mutate_bytes(rng.choice(svg_bytes), rng, SVG_TOKENS, svg_bytes)
            elif target == "svgtree":
                import copy
                item = serialize_tree(mutate_tree(copy.deepcopy(rng.choice(trees)), rng, trees))
            elif target == "pathdata":
                item = mutate_text(rng.choice(paths), rng)
            else:
                item = mutate_bytes(rng.choice(fonts), rng, [], fonts)
            tried += 1
            if last_input:
                # written before the run: a segfault kills the process, the input survives
                with open(last_input, "wb") as f:
                    f.write(item.encode("utf-8", "surrogatepass") if isinstance(item, str)
                            else item)
            res = run_one(target, item, timeout)
            if res is None:
                continue
            key, message = res
            if key not in crashes:
                where = save_crash(save, target, item, key, message) if save else None
                crashes[key] = {"message": message, "input": where}
                log(f"CRASH {key}: {message[:200]}" + (f" -> {where}" if where else ""))
        report["targets"][target] = {"inputs": tried, "crashes": crashes}
        log(f"{target}: {tried} inputs, {len(crashes)} distinct crashes")
    return report


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="total fuzzing time")
    ap.add_argument("--targets", default="svg,svgtree,pathdata,font")
    ap.add_argument("--memory-mb", type=int, default=None,
                    help="address space allowed above the warmed-up process (MB)")
    ap.add_argument("--seed", type=int, default=None, help="random seed (default: time)")
    ap.add_argument("--save", default=REGRESSIONS, help="folder for crash inputs")
    ap.add_argument("--no-save", action="store_true", help="only report crashes")
    ap.add_argument("--timeout", type=int, default=20, help="seconds before an input is a hang")
    ap.add_argument("--last-input", help="write each input here before running it (to keep "
                    "the input of a hard crash such as a segfault)")
    args = ap.parse_args(argv)
    sys.path.insert(0, REPO)
    seed = args.seed if args.seed is not None else int(time.time())
    targets = tuple(t for t in args.targets.split(",") if t)
    for t in targets:
        if t not in EXTENSIONS:
            ap.error(f"unknown target {t!r}")
    report = fuzz(args.seconds, targets, seed, None if args.no_save else args.save,
                  args.timeout, log=lambda s: print(s, flush=True), last_input=args.last_input,
                  memory_mb=args.memory_mb)
    total = sum(len(t["crashes"]) for t in report["targets"].values())
    print(f"seed {seed}: " + ", ".join(f"{k} {v['inputs']} inputs / {len(v['crashes'])} crashes"
                                       for k, v in report["targets"].items()))
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main())
