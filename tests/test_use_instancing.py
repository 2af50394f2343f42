"""<use> instances: content prepared once per context and placed per instance (glyphs drawn by
<use> in pdftocairo and matplotlib output), and the expansion count that bounds <use>.

Truth: colours and positions computed by hand from the documents' attributes; counts known
by construction (how many instances, contexts and chain links the document has); the
specification's and resvg's rules (CSS matches the original tree; <use> cut at
MAX_USE_DEPTH levels and at cycles)."""
import pytest

from vecmsaa.api import _Loaded, load_svg
from vecmsaa.scene.bounds import path_bounds
from vecmsaa.scene.nodes import Solid
from vecmsaa.scene.transform import IDENTITY
from vecmsaa.svg import SvgError, builder
from vecmsaa.svg.builder import MAX_USE_DEPTH, Builder, expanded_size

NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'
#: a glyph as pdftocairo writes it (the path (0, 0) (4, 0) (4, 3) in the symbol's space)
GLYPH = ('<symbol id="g" overflow="visible"><path style="stroke:none;" d="M0 0L400 0L400 -300Z" '
         'transform="scale(0.01,-0.01)"/></symbol>')


def scene(body, size=200):
    return load_svg(f'<svg {NS} width="{size}" height="{size}">{body}</svg>')


def colors(s):
    return [tuple(round(c * 255) for c in f.paint.color) for f in s.fills()]


def boxes(s):
    return [tuple(round(v, 9) for v in path_bounds(f.path)) for f in s.fills()]


class Counting:
    """Counts the calls of some Builder methods (monkeypatched for one test)."""

    def __init__(self, monkeypatch, *names):
        self.calls = dict.fromkeys(names, 0)
        for name in names:
            original = getattr(Builder, name)

            def wrapped(*args, _name=name, _original=original, **kw):
                self.calls[_name] += 1
                return _original(*args, **kw)
            monkeypatch.setattr(Builder, name, wrapped)


def test_a_thousand_instances_build_the_glyph_once(monkeypatch):
    """1000 <use> of one symbol in one context: the symbol's path is prepared once, and no
    instance builds it as an element (shape, draw_path: once per instance before) again;
    every instance is in place."""
    count = Counting(monkeypatch, "shape", "draw_path", "_prepare_element")
    uses = "".join(f'<use xlink:href="#g" x="{i % 40 * 5}" y="{i // 40 * 5}"/>'
                   for i in range(1000))
    s = scene(f"<defs>{GLYPH}</defs><g>{uses}</g>")
    assert count.calls == {"shape": 0, "draw_path": 0, "_prepare_element": 1}
    assert boxes(s) == [(i % 40 * 5, i // 40 * 5, i % 40 * 5 + 4, i // 40 * 5 + 3)
                        for i in range(1000)]
    assert set(colors(s)) == {(0, 0, 0, 255)}


def test_instances_in_different_inherited_contexts_are_prepared_per_context(monkeypatch):
    """Fill inherited from the <use>, from a group around it, and the initial black: three
    contexts (three computed styles of the <use>), each prepared once for its 50 uses."""
    count = Counting(monkeypatch, "_prepare_element")
    row = "".join(f'<use xlink:href="#g" x="{5 * i}"/>' for i in range(50))
    red = "".join(f'<use xlink:href="#g" x="{5 * i}" y="10" fill="red"/>' for i in range(50))
    s = scene(f'<defs>{GLYPH}</defs>{row}{red}<g fill="blue" transform="translate(0 20)">'
              f'{row}</g>')
    assert count.calls["_prepare_element"] == 3
    assert colors(s) == [(0, 0, 0, 255)] * 50 + [(255, 0, 0, 255)] * 50 + [(0, 0, 255, 255)] * 50
    assert boxes(s)[50:52] == [(0, 10, 4, 13), (5, 10, 9, 13)]
    assert boxes(s)[100:102] == [(0, 20, 4, 23), (5, 20, 9, 23)]


def test_current_color_takes_each_instances_color():
    s = scene('<defs><symbol id="c" overflow="visible"><rect width="4" height="4" '
              'fill="currentColor"/></symbol></defs>'
              '<use xlink:href="#c" color="red"/><use xlink:href="#c" x="10" color="lime"/>'
              '<g color="blue"><use xlink:href="#c" x="20"/></g><use xlink:href="#c" x="30"/>'
              '<use xlink:href="#c" x="40" style="color:red"/>')
    assert colors(s) == [(255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255),
                         (0, 0, 0, 255), (255, 0, 0, 255)]
    assert [b[0] for b in boxes(s)] == [0, 10, 20, 30, 40]


def test_context_paints_take_each_instances_fill_and_stroke():
    s = scene('<defs><symbol id="k" overflow="visible"><rect width="4" height="4" '
              'fill="context-fill" stroke="context-stroke" stroke-width="2"/></symbol></defs>'
              '<use xlink:href="#k" fill="red" stroke="blue"/>'
              '<use xlink:href="#k" x="10" fill="lime"/>'
              '<g fill="blue"><use xlink:href="#k" x="20"/></g>')
    # fill then stroke for the first; the second and third have stroke none (initial)
    assert colors(s) == [(255, 0, 0, 255), (0, 0, 255, 255), (0, 255, 0, 255), (0, 0, 255, 255)]


def test_css_in_the_content_matches_the_original_tree_not_the_instance():
    """Selectors match where the elements stand in the document (SVG 2 §5.6.2: the instance's
    elements have the original's computed style from their own rules, inheriting from the
    <use>): `g.a use` styles the <use> inside g.a, whose fill the content inherits; `g.a
    path` matches no path (the symbol's path is not in g.a); `.b path` matches the symbol's
    path for every instance."""
    css = ('<style>g.a use { fill: lime } g.a path { fill: red } .b path { stroke: blue; '
           'stroke-width: 2 }</style>')
    s = scene(css + '<defs><symbol id="s" overflow="visible"><path d="M0 0h4v4h-4z"/>'
              '</symbol><symbol id="t" class="b" overflow="visible"><path d="M0 0h4v4h-4z"/>'
              '</symbol></defs>'
              '<g class="a"><use xlink:href="#s"/><use xlink:href="#t" x="10"/></g>'
              '<use xlink:href="#s" x="20"/><use xlink:href="#t" x="30"/>')
    lime, black, blue = (0, 255, 0, 255), (0, 0, 0, 255), (0, 0, 255, 255)
    assert colors(s) == [lime, lime, blue, black, black, blue]
    assert boxes(s) == [(0, 0, 4, 4), (10, 0, 14, 4), (9, -1, 15, 5), (20, 0, 24, 4),
                        (30, 0, 34, 4), (29, -1, 35, 5)]


def test_instances_take_each_use_transform_and_symbol_viewport():
    """A symbol's viewBox scaled to each <use>'s width and height, under the <use>'s own
    transform, with the content's transforms composed inside."""
    s = scene('<defs><symbol id="v" viewBox="0 0 10 10"><g transform="translate(5 0)">'
              '<rect width="5" height="10" transform="scale(1 0.5)"/></g></symbol></defs>'
              '<use xlink:href="#v" width="20" height="20"/>'
              '<use xlink:href="#v" x="10" y="30" width="40" height="40" '
              'transform="scale(2)"/>')
    # first: 2x, the rect at x 5..10, y 0..5 of the viewBox → 10..20, 0..10
    # second: 4x the viewBox at (10, 30), then scale(2): x (10 + 20..40) * 2, y 30*2..(30+20)*2
    assert boxes(s) == [(10, 0, 20, 10), (60, 60, 100, 100)]
    # each clipped to its viewport (a symbol's overflow is hidden), in the use's space
    clips = [path_bounds(g.clip.children[0].path) for g in s.root.children]
    assert clips == [(0, 0, 20, 20), (20, 60, 100, 140)]


def test_instance_content_with_effects_and_strokes():
    """Opacity in the content (built per instance), a stroke (stroked per instance at its
    scale), a hidden and an undisplayed element (nothing drawn)."""
    s = scene('<defs><symbol id="e" overflow="visible"><rect width="4" height="4" '
              'opacity="0.5"/><rect x="10" width="4" height="4" stroke="red" '
              'stroke-width="2" fill="none"/><rect width="9" height="9" display="none"/>'
              '<rect width="9" height="9" visibility="hidden"/></symbol></defs>'
              '<use xlink:href="#e"/><use xlink:href="#e" y="20" transform="scale(2)"/>')
    fills = s.fills()
    assert len(fills) == 4
    # the strokes: 2 wide around 10..14, at scale 1 and at scale 2 (y 20 → 40)
    stroke_boxes = [b for f, b in zip(fills, boxes(s)) if f.paint.color[0] == 1]
    assert stroke_boxes == [(9, -1, 15, 5), (18, 38, 30, 50)]


# -- the expansion count --------------------------------------------------------------------
def expansion(body):
    data = f'<svg {NS} width="100" height="100">{body}</svg>'
    loaded = _Loaded(data, 96, None, {})
    return loaded, expanded_size(loaded.builder.doc)


def chain(n):
    """growth.py's use_chain: u_i uses u_(i-1), u0 a rect in defs."""
    return ('<defs><rect id="u0" width="5" height="5"/></defs>'
            + "".join(f'<use id="u{i}" xlink:href="#u{i - 1}" x="0.01"/>' for i in range(1, n)))


def test_a_long_use_chain_is_counted_as_built():
    """u_i reaches the rect through i <use> levels: instantiated to MAX_USE_DEPTH levels, so
    u_i adds min(i, 32) elements and u_1 .. u_32 draw the rect. Counted fully expanded
    (n^2/2), 2000 links were refused."""
    n = 2000
    loaded, count = expansion(chain(n))
    assert count == (n + 2) + sum(min(i, MAX_USE_DEPTH) for i in range(1, n))
    nodes = loaded.build(IDENTITY)
    assert loaded.builder.nodes_made <= count
    assert len(nodes) == MAX_USE_DEPTH


@pytest.mark.parametrize("body", [
    chain(100),
    # cycles with fan-out: a and b use each other twice; each chain stops at the repeat
    '<defs><g id="a"><use href="#b"/><use href="#b"/><rect width="1" height="1"/></g>'
    '<g id="b"><use href="#a"/><use href="#a"/></g></defs><use href="#a"/><use href="#b"/>',
    # a use inside its own target (drawn nothing), twice over
    '<g id="a"><use href="#a"/><use href="#a"/><rect width="1" height="1"/></g>'
    '<use href="#a"/>',
    # symbols through a symbol, and detached and missing targets
    '<defs><symbol id="s"><rect width="1" height="1"/></symbol><symbol id="t">'
    '<use href="#s"/><use href="#s"/><use href="#nothing"/></symbol></defs>'
    + '<use href="#t"/>' * 20,
])
def test_the_count_bounds_what_the_build_makes(body):
    loaded, count = expansion(body)
    loaded.build(IDENTITY)
    assert loaded.builder.nodes_made <= count < 10_000


def test_use_fan_out_past_the_depth_limit_is_still_refused():
    """Two <use> per level, 40 levels: the depth cut leaves 2^32 instances, refused at once."""
    levels = ['<rect id="l0" width="1" height="1"/>']
    for i in range(1, 41):
        levels.append(f'<g id="l{i}"><use href="#l{i - 1}"/><use href="#l{i - 1}"/></g>')
    with pytest.raises(SvgError, match="too many"):
        scene("<defs>" + "".join(levels) + '</defs><use href="#l40"/>')


def test_the_count_stops_at_the_limit(monkeypatch):
    """The walk stops once past MAX_NODES (3^30 instances here): its steps, a target looked
    up per <use> instance, stay in proportion to the limit, and nothing is built."""
    monkeypatch.setattr(builder, "MAX_NODES", 1000)
    looked_up = []
    original = builder.use_target
    monkeypatch.setattr(builder, "use_target", lambda *a: looked_up.append(1) or original(*a))
    built = Counting(monkeypatch, "shape")
    levels = ['<rect id="l0" width="1" height="1"/>']
    for i in range(1, 31):
        levels.append(f'<g id="l{i}">' + f'<use href="#l{i - 1}"/>' * 3 + '</g>')
    loaded, count = expansion("<defs>" + "".join(levels) + '</defs><use href="#l30"/>')
    assert count == 1001
    assert len(looked_up) <= 1000
    with pytest.raises(SvgError, match="too many"):
        loaded.build(IDENTITY)
    assert built.calls["shape"] == 0


@pytest.mark.parametrize("attrs", ['xlink:href="#a" href="#b"', 'href="#b" xlink:href="#a"',
                                   'xlink:href="#b"'])
def test_a_plain_href_overrides_xlink_href_in_either_order(attrs):
    """SVG 2 §5.6.2 (href over xlink:href), however the attributes are ordered; the parser's
    fast path for elements whose one namespaced attribute is xlink:href reads them so."""
    s = scene('<defs><rect id="a" width="1" height="1" fill="red"/><rect id="b" width="2" '
              f'height="2" fill="lime"/></defs><use {attrs} x="3"/>')
    assert colors(s) == [(0, 255, 0, 255)] and boxes(s) == [(3, 0, 5, 2)]


def test_point_mapper_maps_as_apply_does():
    """point_mapper(pts)(m) is apply(m, pts) to the bit (a·x + c·y + e per point, the same
    kernel), for contiguous and strided points and integer matrix entries."""
    import numpy as np

    from vecmsaa.scene.transform import apply, point_mapper
    rng = np.random.default_rng(7)
    pts = rng.normal(size=(40, 2)) * 1e3
    for p in (pts, pts[::3], pts[:0], pts[:, ::-1]):
        mapper = point_mapper(p)
        for m in [(1, 0, 0, 1, 5, -3), tuple(rng.normal(size=6)), (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)]:
            got, want = mapper(m), apply(m, p)
            assert got.dtype == want.dtype and got.shape == want.shape
            assert got.tobytes() == want.tobytes()


#: <use> of prepared content in the contexts it may meet (the general build is the truth)
CONTEXTS = '''<style>g.a use { fill: green } .b path { fill: blue }</style>
<defs>
<symbol id="s1" overflow="visible"><path style="stroke:none" d="M0 0L1000 0L1000 1000Z"
 transform="scale(0.01,-0.01)"/></symbol>
<symbol id="s2" viewBox="0 0 10 10" width="20" height="20"><circle cx="5" cy="5" r="6"
 fill="currentColor"/></symbol>
<symbol id="s4" class="b"><g transform="rotate(10)"><path d="M0 0L12 0L6 9Z"/>
 <rect x="1" y="1" width="3" height="3" stroke="black" stroke-width="0.5"/></g></symbol>
<symbol id="s5"><path d="M0 0L9 0L9 9Z" stroke="red" stroke-width="0.3"/>
 <path d="M0 0L9 9" stroke="navy" stroke-width="1.5" stroke-linecap="round"/></symbol>
<symbol id="s7" viewBox="0 0 10 10" width="50%" height="10%" overflow="hidden"
 preserveAspectRatio="xMaxYMid slice"><rect x="-5" y="-5" width="20" height="20" fill="teal"/>
 <ellipse cx="5" cy="5" rx="4" ry="2" fill="none" stroke="white"/></symbol>
<g id="gg" class="inner"><rect width="5" height="5" fill-rule="evenodd"/>
 <polygon points="0,0 5,9 9,0" stroke="black" stroke-dasharray="1 1"/></g>
<path id="pp" d="M0 0h6v6z" transform="scale(2)"/>
<symbol id="s9" viewBox="0.3 0.7 9.1 9.3"><g transform="rotate(7) translate(0.13 0.29)">
 <path d="M0.1 0.2L8.7 0.3L4.4 7.9Z" transform="scale(1.13 0.91) rotate(-3)"/></g></symbol>
</defs>
<use xlink:href="#s9" x="150.3" y="60.7" width="33.3" height="27.1"/>
<use xlink:href="#s9" x="150.3" y="90.7" width="33.3" height="27.1" transform="rotate(1.7)"/>
<use xlink:href="#s1" x="5.5" y="5.25"/><use xlink:href="#s1" x="20" y="5" fill="red"/>
<g class="a"><use xlink:href="#s1" x="35" y="5"/><use xlink:href="#s4" x="50" y="5"/>
 <use xlink:href="#gg" x="65" y="5"/></g>
<g fill="yellow" stroke="black" transform="skewX(10)"><use xlink:href="#s1" x="80" y="5"/>
 <use xlink:href="#gg" x="95" y="5"/></g>
<use xlink:href="#s2" x="5" y="30" color="red"/><g color="green"><use xlink:href="#s2" x="55"
 y="30"/></g><use xlink:href="#s2" x="80" y="30" width="10" height="30"/>
<use xlink:href="#s4" x="5" y="80"/><use xlink:href="#s4" x="25" y="80" font-size="30"/>
<use xlink:href="#s5" x="5" y="100"/><use xlink:href="#s5" x="20" y="100"
 transform="scale(0.2)"/><use xlink:href="#s5" x="40" y="100" transform="scale(3)"/>
<use xlink:href="#s7" x="5" y="140"/><use xlink:href="#s7" x="100" y="140" width="20"/>
<use xlink:href="#pp" x="5" y="170"/><use xlink:href="#pp" x="25" y="170" opacity="0.5"/>
<svg x="120" y="20" width="60" height="60" viewBox="0 0 20 20"><use xlink:href="#s1" x="2"
 y="2"/><use xlink:href="#s7"/></svg>
<mask id="m"><use xlink:href="#s1" x="150" y="150" fill="white"/></mask>
<pattern id="p" width="8" height="8" patternUnits="userSpaceOnUse"><use xlink:href="#s5"
 transform="scale(0.5)"/></pattern>
<rect x="140" y="140" width="50" height="50" fill="url(#p)" mask="url(#m)"/>
<use xlink:href="#s1" x="170" y="150" style="fill:purple;stroke:orange;stroke-width:0.5"/>'''


@pytest.mark.parametrize("width", [200, 333])
def test_prepared_instances_draw_what_the_general_build_draws(monkeypatch, width):
    """The same document built with the content prepared once and with every instance built
    as it stands (no target instanceable): the same fills, point for point, the same pixels."""
    import numpy as np

    from vecmsaa.api import render_svg_array
    doc = f'<svg {NS} width="200" height="200" viewBox="0 0 200 200">{CONTEXTS}</svg>'
    prepared = Counting(monkeypatch, "_instance")
    fast = load_svg(doc, width=width)
    fast_pixels = render_svg_array(doc, width=width)
    assert prepared.calls["_instance"] >= 30       # (both builds, most of the <use>)
    monkeypatch.setattr(builder, "_INSTANCEABLE", frozenset())
    slow = load_svg(doc, width=width)
    assert len(fast.fills()) == len(slow.fills()) > 40
    for a, b in zip(fast.fills(), slow.fills()):
        assert a.path.verbs.tobytes() == b.path.verbs.tobytes()
        assert a.path.points.tobytes() == b.path.points.tobytes()
        assert (a.rule, a.opacity, a.antialias) == (b.rule, b.opacity, b.antialias)
        assert type(a.paint) is type(b.paint)
        if isinstance(a.paint, Solid):      # (a pattern's content: by the pixels below)
            assert a.paint == b.paint
    assert np.array_equal(fast_pixels, render_svg_array(doc, width=width))
