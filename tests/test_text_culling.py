"""Text whose glyphs cannot reach the image is left out of the scene (svg.text.draw,
Ctx.sampled). Truth by brute force: the same RGBA bytes as the scene built with every glyph
(``load_svg(cull=False)``), on documents whose glyphs lie partly and wholly off the canvas
in the contexts where content from far away can still show (a stroke reaching in, a filter's
offset, a pattern's tile, a use, a marker, a textPath) and where the text's bounding box,
which must not shrink with what is drawn, sets a gradient, an anchor or a length."""
from __future__ import annotations

import os

import numpy as np
import pytest

from vecmsaa.api import crop_to_drawing, load_svg, render_svg_array, samples_for
from vecmsaa.raster.render import render_scene_rgba8
from vecmsaa.raster.resolve import RADIUS, apron
from vecmsaa.geometry.primitives import CULL_MARGIN
from vecmsaa.svg.builder import SAMPLED_MARGIN

FIXTURES = os.path.join(os.path.dirname(__file__), "..", "fixtures", "fonts")
FONTS = dict(use_fonts_dir=FIXTURES, skip_system_fonts=True, font_family="Noto Sans")
LONG = "Wavy text, far and wide: MOVW " * 6

DEFS = """<defs>
  <linearGradient id="bbox"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>
  <filter id="offset" x="-10" y="-10" width="20" height="20" filterUnits="objectBoundingBox">
    <feOffset dx="400" dy="0"/></filter>
  <filter id="tile" x="-100" y="0" width="300" height="100" filterUnits="userSpaceOnUse">
    <feOffset dx="0" x="-100" y="0" width="60" height="100"/><feTile/></filter>
  <pattern id="pat" patternUnits="userSpaceOnUse" x="-1000" y="0" width="1000" height="60">
    <text x="5" y="40" font-size="30" stroke="green" stroke-width="3">Tiled text</text></pattern>
  <mask id="mask"><text x="-40" y="70" font-size="60" fill="white" transform="rotate(-10)">{long}</text></mask>
  <clipPath id="clip"><text x="-150" y="60" font-size="50" transform="skewX(-30)">{long}</text></clipPath>
  <marker id="mark" markerWidth="400" markerHeight="100" refX="200" refY="50" overflow="visible"
          markerUnits="userSpaceOnUse"><text x="-300" y="0" font-size="20" stroke="black"
          stroke-width="4">{long}</text></marker>
  <path id="circle" d="M 100 -60 A 110 110 0 1 1 99.9 -60"/>
  <text id="far" x="-500" y="50" font-size="30" stroke="purple" stroke-width="6">Far away text</text>
</defs>""".format(long=LONG)

BODIES = {
    "rotated and skewed": f'<text x="-300" y="40" transform="rotate(25 100 50) skewX(20)" '
                          f'fill="navy">{LONG}</text>',
    # the outline of "V" ends 35 px left of the image; a miter of its 80 px wide stroke
    # reaches in (the ink at column 0 is asserted below)
    "thick mitred stroke": '<text x="-60" y="60" font-size="40" stroke="orange" stroke-width="80" '
                           'stroke-miterlimit="10" fill="none">V</text>'
                           '<text x="230" y="60" font-size="40" stroke="teal" stroke-width="80" '
                           'stroke-linejoin="miter" stroke-miterlimit="20">A</text>',
    "round joins, square caps": f'<text x="-400" y="95" font-size="30" stroke="black" '
                                f'stroke-width="30" stroke-linejoin="round" '
                                f'stroke-linecap="square" fill="none">{LONG}</text>',
    "filter offset brings it in": '<g filter="url(#offset)"><text x="-380" y="50" '
                                  'stroke="red" stroke-width="2">Offset in</text>'
                                  '<rect x="0" y="0" width="1" height="1"/></g>',
    "filter on the text itself": '<text x="-380" y="60" filter="url(#offset)" '
                                 'fill="blue">Filtered text</text>',
    "filter tiles it in": '<g filter="url(#tile)"><text x="-95" y="50" font-size="30" '
                          'fill="maroon">Tiled far</text></g>',
    "pattern tile": '<rect width="200" height="100" fill="url(#pat)"/>',
    "mask": '<rect width="200" height="100" fill="green" mask="url(#mask)"/>',
    "clip path": '<rect width="200" height="100" fill="purple" clip-path="url(#clip)"/>',
    "marker": '<path d="M -100 20 L 100 50 L 300 80" stroke="gray" marker-start="url(#mark)" '
              'marker-mid="url(#mark)" marker-end="url(#mark)"/>',
    "use moves it in": '<use href="#far" x="520"/><use href="#far" x="0" y="30"/>',
    "textPath around the image": f'<text font-size="20" stroke="black" stroke-width="1">'
                                 f'<textPath href="#circle">{LONG}{LONG}</textPath></text>',
    "decorations": f'<text x="-500" y="50" font-size="20" text-decoration="underline" '
                   f'stroke="red" stroke-width="5">{LONG}<tspan text-decoration="overline '
                   f'line-through" fill="yellow" stroke="green" stroke-width="12" '
                   f'stroke-linejoin="miter" stroke-miterlimit="30">{LONG}</tspan>{LONG}</text>',
    "decoration stroke reaching in": '<text x="-300" y="70" font-size="20" '
                                     'text-decoration="underline" stroke="red" '
                                     'stroke-width="600" fill="none">   .  .</text>',
    "objectBoundingBox gradient": f'<text x="-600" y="60" font-size="40" fill="url(#bbox)" '
                                  f'stroke="url(#bbox)">{LONG}</text>',
    "anchor and textLength": f'<text x="100" y="40" text-anchor="middle" '
                             f'textLength="3000">{LONG}</text><text x="200" y="90" '
                             f'text-anchor="end" font-size="25">{LONG}</text>',
    "non-scaling stroke": f'<text x="-3000" y="500" transform="scale(0.1)" font-size="300" '
                          f'stroke="black" stroke-width="30" vector-effect="non-scaling-stroke" '
                          f'stroke-miterlimit="12">{LONG}</text>'
                          f'<text x="-30" y="9" transform="scale(10)" font-size="3" '
                          f'stroke="blue" stroke-width="40" vector-effect="non-scaling-stroke" '
                          f'fill="none">{LONG}</text>',
    "dashed stroke": f'<text x="-500" y="60" font-size="40" stroke="black" stroke-width="4" '
                     f'stroke-dasharray="7 3" stroke-dashoffset="5">{LONG}</text>',
    "hairlines": f'<text x="-800" y="60" font-size="16" stroke="red" stroke-width="0.5" '
                 f'text-decoration="underline">{LONG}{LONG}</text>',
    "vertical": f'<text x="100" y="-600" writing-mode="tb" font-size="20" stroke="black" '
                f'stroke-width="3">{LONG}</text>',
    "nested svg and group transforms": f'<svg x="20" y="10" width="100" height="80" '
                                       f'viewBox="0 0 50 40"><g transform="translate(-200 0) '
                                       f'rotate(5)"><text y="30" font-size="20">{LONG}</text>'
                                       f'</g></svg>',
}


def _doc(body, root=""):
    return (f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
            f'width="200" height="100" font-size="40" font-family="Noto Sans" {root}>{DEFS}{body}</svg>')


def _pair(svg, width=None, threads=1, **kw):
    """The image with culling (as render_svg_array draws it) and without."""
    out = []
    for cull in (True, False):
        scene = load_svg(svg, width=width, cull=cull, **FONTS)
        out.append(render_scene_rgba8(scene, threads=threads, **kw,
                                      samples=samples_for(None, scene.width, scene.height)))
    assert np.array_equal(out[0], render_svg_array(svg, width=width, threads=threads, **FONTS,
                                                   **kw))
    return out


def _glyph_points(svg, cull, width=None):
    """Points of the scene's fills: what the glyphs cost the raster."""
    return sum(len(f.path.points) for f in load_svg(svg, width=width, cull=cull, **FONTS).fills())


@pytest.mark.parametrize("name", sorted(BODIES))
def test_culled_text_draws_the_bytes_of_all_its_glyphs(name):
    svg = _doc(BODIES[name])
    culled, whole = _pair(svg)
    assert whole[..., 3].any(), "the case draws something"
    assert np.array_equal(culled, whole)


@pytest.mark.parametrize("name", ["rotated and skewed", "thick mitred stroke", "decorations",
                                  "textPath around the image", "non-scaling stroke"])
def test_culled_text_at_other_sizes_modes_and_threads(name):
    """The image scaled (root_scale, non-scaling strokes), a resolve filter with an apron
    of samples beyond the pixel (the widest, Mitchell's), two threads."""
    svg = _doc(BODIES[name])
    for width, kw in ((480, {}), (90, {}), (200, dict(filter="mitchell")),
                      (300, dict(threads=2))):
        culled, whole = _pair(svg, width=width, **kw)
        assert np.array_equal(culled, whole), (width, kw)


def test_a_stroke_reaches_in_from_an_outline_outside():
    """The case that fails when a glyph is culled by its outline alone: the "V" lies wholly
    left of the image (and of the culling margin), its stroke's ink is in column 0."""
    svg = _doc('<text x="-60" y="60" font-size="40" stroke="orange" stroke-width="80" '
               'stroke-miterlimit="10" fill="none">V</text>')
    culled, whole = _pair(svg)
    assert whole[:, 0, 3].any()
    assert np.array_equal(culled, whole)


def test_root_filter_and_export_area_drawing_keep_everything():
    """A filter on the root may bring in anything; --export-area-drawing crops to the
    scene's bounds, off-canvas glyphs included."""
    svg = _doc('<text x="-380" y="60" fill="blue">Offset in</text>',
               root='filter="url(#offset)"')
    culled, whole = _pair(svg)
    assert whole[..., 3].any() and np.array_equal(culled, whole)
    svg = _doc('<text x="-300" y="60">Left out</text><rect x="120" y="20" width="10" '
               'height="10"/>')
    cropped = render_svg_array(svg, export_area_drawing=True, **FONTS)
    scene = load_svg(svg, cull=False, **FONTS)
    assert np.array_equal(cropped, crop_to_drawing(_pair(svg)[1], scene))
    assert cropped.shape[1] == 130        # from column 0 (the text reaches past it) to the rect


def test_glyphs_off_the_canvas_cost_nothing():
    """The point of culling: a long line mostly off the image (the fuzzer's document in
    small) leaves only the glyphs near the image, and the anchor and the gradient's box
    stay those of the whole line (the bytes test above)."""
    svg = _doc(f'<text x="100" y="50" text-anchor="middle" font-size="16" stroke="red" '
               f'stroke-width="0.5" text-decoration="underline" fill="url(#bbox)">'
               f'{LONG * 20}</text>')
    kept, every = _glyph_points(svg, True), _glyph_points(svg, False)
    assert kept * 20 < every
    culled, whole = _pair(svg)
    assert np.array_equal(culled, whole)


def test_margin_covers_the_resolve_apron_and_the_raster_margin():
    assert SAMPLED_MARGIN >= max(apron(n) for n in RADIUS) + CULL_MARGIN


def _random_body(rng):
    spans = []
    for _ in range(rng.integers(1, 6)):
        attrs = []
        if rng.random() < 0.6:
            attrs.append(f'stroke="#{rng.integers(0, 1 << 24):06x}" '
                         f'stroke-width="{rng.choice([0.3, 2, 10, 40])}" '
                         f'stroke-linejoin="{rng.choice(["miter", "round", "bevel"])}" '
                         f'stroke-miterlimit="{rng.choice([1, 4, 30])}"')
        if rng.random() < 0.3:
            attrs.append('text-decoration="underline line-through"')
        if rng.random() < 0.3:
            attrs.append(f'dy="{rng.uniform(-60, 60):.1f}"')
        if rng.random() < 0.2:
            attrs.append(f'rotate="{rng.uniform(-90, 90):.0f}"')
        text = "".join(rng.choice(list("AVWMoxlg.,; ")) for _ in range(rng.integers(1, 30)))
        spans.append(f'<tspan {" ".join(attrs)}>{text}</tspan>')
    t = (f'translate({rng.uniform(-300, 300):.1f} {rng.uniform(-100, 150):.1f}) '
         f'rotate({rng.uniform(-60, 60):.0f}) skewX({rng.uniform(-40, 40):.0f}) '
         f'scale({rng.uniform(0.3, 3):.2f})')
    return (f'<text transform="{t}" font-size="{rng.uniform(5, 60):.0f}" '
            f'text-anchor="{rng.choice(["start", "middle", "end"])}">{"".join(spans)}</text>')


@pytest.mark.parametrize("seed", range(12))
def test_random_texts_around_the_image(seed):
    rng = np.random.default_rng(seed)
    svg = _doc("".join(_random_body(rng) for _ in range(4)))
    culled, whole = _pair(svg)
    assert np.array_equal(culled, whole)
