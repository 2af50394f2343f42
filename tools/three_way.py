#!/usr/bin/env python3
"""Draw SVG files three ways -- vecmsaa (V), resvg 0.48.1 (R, the resvg suite's renderer) and
Chromium (C) -- and say which agree.

    python tools/three_way.py FILE.svg ... [--save DIR] [--chromium /usr/bin/chromium]
    python tools/three_way.py --suite ../shared/resvg-suite [--save DIR]

Needs ``pip install resvg-py playwright`` and a Chromium binary (Debian: ``apt-get install
chromium``); neither is a dependency of vecmsaa. Every renderer gets the resvg suite's fonts
(``fonts/`` of ``--fonts-suite``, default ``$VECMSAA_RESVG_SUITE`` or ``../shared/resvg-suite``)
with its generic families: vecmsaa and resvg through their options, Chromium through a
fontconfig file holding that folder alone. A file is drawn at resvg's size for it (the suite's
reference size with ``--suite``), Chromium by a device scale factor of that width over the
SVG's own, as a standalone document on a transparent page.

V=R uses the suite's criterion (:mod:`vecmsaa.tools.compare`). Comparisons with Chromium take
one pixel of slack (:func:`loose_off`): its glyphs and image resampling differ from both by
about half a percent of pixels where the layout is the same. Reading a result: V differs and
R = C is the likely vecmsaa bug; V = C is resvg's; R's renders are the suite's references.
"""
from __future__ import annotations

import argparse
import io
import json
import os
import pathlib
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from vecmsaa.tools.compare import MAX_FRACTION, THRESHOLD, premultiplied_u8  # noqa: E402
from vecmsaa.tools.suite import EXACT_REFS, SUITE_FONTS, collect, suite_from_environment  # noqa: E402

#: the generic families as the suite maps them (its ``serif_family`` ... options, which
#: vecmsaa and resvg-py both take by those names)
FAMILIES = {k[:-len("_family")].replace("_", "-"): v for k, v in SUITE_FONTS.items()
            if k != "font_family"}
#: Chromium's own default families on Linux, which standalone SVG text falls back to
BROWSER_DEFAULTS = {"Times New Roman": "Noto Serif", "Arial": "Noto Sans",
                    "Courier New": "Noto Mono"}
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--hide-scrollbars", "--font-render-hinting=none",
                 "--disable-lcd-text", "--force-color-profile=srgb"]
#: a pixel is off when no pixel within this many of it in the other image matches
SLACK_PX = 1


def fontconfig_file(fonts_dir, folder):
    """A fontconfig file that knows only ``fonts_dir``, generic families mapped as the suite's."""
    aliases = "".join(
        f'<alias binding="same"><family>{name}</family><prefer><family>{face}</family>'
        f'</prefer></alias>' for name, face in {**FAMILIES, **BROWSER_DEFAULTS}.items())
    path = os.path.join(folder, "fonts.conf")
    with open(path, "w") as f:
        f.write(f'<?xml version="1.0"?><fontconfig><dir>{fonts_dir}</dir>'
                f'<cachedir>{folder}/cache</cachedir>{aliases}</fontconfig>')
    return path


class Chromium:
    """Headless Chromium through Playwright, one page per device scale factor."""

    def __init__(self, executable, fonts_dir):
        from playwright.sync_api import sync_playwright
        self._folder = tempfile.TemporaryDirectory(prefix="three-way-")
        env = dict(os.environ, FONTCONFIG_FILE=fontconfig_file(fonts_dir, self._folder.name))
        self._playwright = sync_playwright().start()
        self._browser = self._playwright.chromium.launch(
            executable_path=executable, args=CHROMIUM_ARGS, env=env)
        self._pages = {}

    def close(self):
        self._browser.close()
        self._playwright.stop()
        self._folder.cleanup()

    def _page(self, scale):
        key = round(scale, 6)
        if key not in self._pages:
            context = self._browser.new_context(device_scale_factor=key)
            self._pages[key] = context.new_page()
        return self._pages[key]

    def _own_width(self, url):
        page = self._page(1.0)
        page.set_viewport_size({"width": 1000, "height": 1000})
        page.goto(url, wait_until="load")
        return page.evaluate("document.documentElement.getBoundingClientRect().width")

    def render(self, path, width, height):
        """RGBA uint8 array of ``width`` x ``height`` device pixels."""
        import numpy as np
        from PIL import Image

        url = pathlib.Path(os.path.abspath(path)).as_uri()     # a # in a name is no fragment
        own = self._own_width(url)
        scale = width / own if own and abs(own - width) > 0.5 else 1.0
        page = self._page(scale)
        page.set_viewport_size({"width": max(1, round(width / scale)),
                                "height": max(1, round(height / scale))})
        page.goto(url, wait_until="load")
        shot = np.asarray(Image.open(io.BytesIO(page.screenshot(omit_background=True)))
                          .convert("RGBA"))
        out = np.zeros((height, width, 4), np.uint8)
        h, w = min(height, shot.shape[0]), min(width, shot.shape[1])
        out[:h, :w] = shot[:h, :w]
        return out


def render_options(path):
    """The suite's fonts and families, resources beside the file."""
    return dict(SUITE_FONTS, skip_system_fonts=True,
                resources_dir=os.path.dirname(os.path.abspath(path)))


def render_resvg(path, fonts_dir, width=None):
    """resvg 0.48.1's drawing (resvg-py), with the options the suite's references were made
    with (languages, dpi and font size differ from resvg-py's defaults)."""
    import numpy as np
    import resvg_py
    from PIL import Image

    with open(path, "rb") as f:
        text = f.read().decode("utf-8", "replace")
    png = resvg_py.svg_to_bytes(svg_string=text, font_dirs=[fonts_dir], languages=["en"],
                                dpi=96, font_size=12, width=width,
                                **render_options(path))
    return np.asarray(Image.open(io.BytesIO(bytes(png))).convert("RGBA"))


def render_vecmsaa(path, fonts_dir, width, height):
    from vecmsaa.api import render_svg_array

    with open(path, "rb") as f:
        data = f.read()
    return render_svg_array(data, width=width, height=height, use_fonts_dir=fonts_dir,
                            **render_options(path))


def _unmatched(a, b, slack):
    """Pixels of premultiplied ``a`` with no pixel of ``b`` within ``slack`` px inside the
    criterion's threshold."""
    import numpy as np

    h, w = a.shape[:2]
    padded = np.pad(b, ((slack, slack), (slack, slack), (0, 0)), mode="edge")
    best = np.full((h, w), np.iinfo(np.int32).max)
    for dy in range(2 * slack + 1):
        for dx in range(2 * slack + 1):
            diff = np.abs(a - padded[dy:dy + h, dx:dx + w]).max(axis=2)
            best = np.minimum(best, diff)
    return best > THRESHOLD


def loose_off(a, b, slack=SLACK_PX):
    """Fraction of pixels off, either way, when each may match within ``slack`` px."""
    if a is None or b is None or a.shape != b.shape:
        return 1.0
    pa, pb = premultiplied_u8(a).astype(int), premultiplied_u8(b).astype(int)
    return float((_unmatched(pa, pb, slack) | _unmatched(pb, pa, slack)).mean())


def loose_pass(a, b):
    """The suite's criterion on loose_off."""
    return loose_off(a, b) <= MAX_FRACTION


def strict_pass(a, b):
    from vecmsaa.tools.compare import compare_images

    return a is not None and b is not None and a.shape == b.shape and compare_images(a, b).passed()


def _attempt(draw, *args):
    try:
        return draw(*args)
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException:   # a renderer refusing a file, or resvg-py's panic (a BaseException),
        return None         # is a result, not a crash of the run


def _save_strip(images, path):
    """V | R | C side by side on white."""
    import numpy as np
    from PIL import Image

    sizes = [i.shape[:2] for i in images if i is not None]
    if not sizes:                   # every renderer refused the file: nothing to show
        return
    h, w = sizes[0]
    strip = Image.new("RGBA", (3 * w + 8, h), (255, 255, 255, 255))
    for k, image in enumerate(images):
        if image is not None and image.shape[:2] == (h, w):
            strip.alpha_composite(Image.fromarray(np.ascontiguousarray(image)), (k * (w + 4), 0))
    strip.save(path)


def compare_files(paths, fonts_dir, chromium, save=None):
    """One line a file: V=R, V=C, R=C as + or -, and the fractions off."""
    for path in paths:
        r = _attempt(render_resvg, path, fonts_dir)
        h, w = r.shape[:2] if r is not None else (200, 200)
        v = _attempt(render_vecmsaa, path, fonts_dir, w, h)
        c = _attempt(chromium.render, path, w, h)
        vr = strict_pass(v, r)
        vc, rc = loose_off(v, c), loose_off(r, c)
        sign = {True: "+", False: "-"}
        print(f"{os.path.basename(path)}: V=R{sign[vr]} V=C{sign[vc <= MAX_FRACTION]} "
              f"R=C{sign[rc <= MAX_FRACTION]} | V-C {vc:.3%} R-C {rc:.3%}", flush=True)
        if save and not (vr and vc <= MAX_FRACTION):
            os.makedirs(save, exist_ok=True)
            _save_strip((v, r, c), os.path.join(save, os.path.basename(path)[:-4] + ".vrc.png"))


def calibrate(suite_dir, chromium, save=None):
    """Chromium against the suite's references (or exact references), per category."""
    import numpy as np
    from PIL import Image

    tests = os.path.join(suite_dir, "tests")
    counts, results = {}, {}
    for name in collect(tests):
        svg = os.path.join(tests, name + ".svg")
        ref = np.asarray(Image.open(svg[:-4] + ".png").convert("RGBA"))
        drawn = _attempt(chromium.render, svg, ref.shape[1], ref.shape[0])
        exact = os.path.join(suite_dir, EXACT_REFS, name + ".png")
        passed = loose_pass(drawn, ref) or (
            os.path.exists(exact)
            and loose_pass(drawn, np.asarray(Image.open(exact).convert("RGBA"))))
        results[name] = passed
        done, ok = counts.get(name.split("/")[0], (0, 0))
        counts[name.split("/")[0]] = (done + 1, ok + passed)
        if save and drawn is not None:
            out = os.path.join(save, name + ".png")
            os.makedirs(os.path.dirname(out), exist_ok=True)
            Image.fromarray(drawn).save(out)
    for category, (done, ok) in sorted(counts.items()):
        print(f"{category:16} {ok:4}/{done}")
    if save:
        with open(os.path.join(save, "results.json"), "w") as f:
            json.dump(results, f, indent=0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="*", help="SVG files to draw three ways")
    parser.add_argument("--suite", help="calibrate: Chromium against this resvg suite's references")
    parser.add_argument("--fonts-suite", default=None,
                        help="resvg suite whose fonts/ every renderer uses")
    parser.add_argument("--chromium", default="/usr/bin/chromium", help="Chromium binary")
    parser.add_argument("--save", help="folder for V|R|C strips (suite: Chromium's renders)")
    args = parser.parse_args(argv)
    suite = args.fonts_suite or args.suite or suite_from_environment(
        os.path.join(os.path.dirname(os.path.dirname(HERE)), "shared", "resvg-suite"))
    fonts_dir = os.path.join(suite, "fonts")
    if not os.path.isdir(fonts_dir):
        parser.error(f"no fonts folder at {fonts_dir}")
    if not args.files and not args.suite:
        parser.error("give SVG files or --suite")
    chromium = Chromium(args.chromium, fonts_dir)
    try:
        if args.suite:
            calibrate(args.suite, chromium, args.save)
        compare_files(args.files, fonts_dir, chromium, args.save)
    finally:
        chromium.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
