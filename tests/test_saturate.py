"""alpha-sat: alpha coverage with the saturating (anti-correlated) blend, fills drawn front to
back (seed 002). Truth: exact geometry (abutting opaque fills tile the canvas, so its alpha is 1
everywhere) and the per-sample reference."""
from __future__ import annotations

import numpy as np

from vecmsaa.raster.render import render_scene
from vecmsaa.scene.nodes import Fill, Group, Scene, Solid
from vecmsaa.scene.path import Path
from vecmsaa.tools.accuracy import _split_canvas, figure1_scene, ground_truth
from vecmsaa.tools.demo import shared_boundary_mask

SIZE = 32
CURVE = ((0, 9.0), (10.0, 31.0), (22.0, -3.0), (SIZE, 20.0))


def split_scene(background=(0, 0, 0, 0)):
    """Two opaque regions sharing one curved boundary across the whole canvas."""
    top, bottom = _split_canvas(SIZE, CURVE)
    return Scene(SIZE, SIZE, Group([Fill(top, Solid((0.9, 0.1, 0.1, 1))),
                                    Fill(bottom, Solid((0.1, 0.7, 0.2, 1)))]),
                 background=background)


def test_abutting_fills_leave_no_seam():
    scene = split_scene()
    sat = render_scene(scene, mode="alpha-sat", samples=8)
    plain = render_scene(scene, mode="alpha", samples=8)
    # the two regions tile the canvas: every pixel is fully covered
    assert np.abs(sat[..., 3] - 1.0).max() < 1e-5
    assert plain[..., 3].min() < 0.9          # source-over's seam, which saturation removes
    truth = ground_truth(scene)
    assert np.abs(sat - truth).mean() < np.abs(plain - truth).mean()


def test_seam_gone_in_figure_1():
    """Over Figure 1's black background the seam is darkening: on the shared boundary (mask from
    each region rendered alone, tools.demo) the reference's channel sum minus the render's.
    Source-over darkens it; the saturating blend, drawing green under red, does not."""
    scene = figure1_scene(40)
    truth = ground_truth(scene)
    boundary = shared_boundary_mask(scene)
    assert boundary.sum() > 20

    def darkening(mode):
        img = render_scene(scene, mode=mode, samples=8)
        return float((truth - img)[..., :3].sum(axis=-1)[boundary].mean())
    plain, sat = darkening("alpha"), darkening("alpha-sat")
    assert plain > 0.03
    assert abs(sat) < 0.1 * plain


def _disc():
    """A closed outline of quadratics only: in the alpha modes every edge pixel is a lens
    pixel with fractional coverage (straight edges are per sample, exact for both blends)."""
    p = Path()
    p.moveTo((4.3, 16.0))
    p.qCurveTo((4.0, 4.0), (16.0, 3.7))
    p.qCurveTo((28.0, 4.0), (27.6, 16.0))
    p.qCurveTo((28.0, 28.0), (16.0, 27.3))
    p.qCurveTo((4.0, 28.0), (4.3, 16.0))
    p.closePath()
    return p


def test_overlap_is_the_documented_failure():
    """Saturation assumes the coverages in a pixel are disjoint. A red disc drawn exactly over
    a green one (same outline: fully correlated coverage) hides the green entirely in truth; at
    an edge pixel of coverage a the saturating blend lets min(a, 1 - a) of green through (up to
    1/2), source-over a·(1 - a) (up to 1/4)."""
    disc = _disc()
    scene = Scene(SIZE, SIZE, Group([Fill(disc, Solid((0.0, 1.0, 0.0, 1))),
                                     Fill(disc, Solid((1.0, 0.0, 0.0, 1)))]),
                  background=(0, 0, 0, 0))
    truth = ground_truth(scene)
    assert truth[..., 1].max() < 1e-6
    sat = render_scene(scene, mode="alpha-sat", samples=8)
    plain = render_scene(scene, mode="alpha", samples=8)
    assert plain[..., 1].max() <= 0.25 + 1e-5
    assert sat[..., 1].max() > 0.4
    # per sample the leak is min(a_s, 1 - a_s); the pixel's mean of those is at most
    # min(a, 1 - a) of its mean coverage a (the red channel)
    red = sat[..., 0]
    assert (sat[..., 1] <= np.minimum(red, 1.0 - red) + 1e-5).all()
    assert np.abs(sat - truth).mean() > np.abs(plain - truth).mean()


def test_one_fill_is_plain_alpha():
    """With nothing else in its batch, front to back and back to front are one order: alpha-sat
    draws one fill as alpha does, over an opaque background."""
    top, _ = _split_canvas(SIZE, CURVE)
    scene = Scene(SIZE, SIZE, Group([Fill(top, Solid((0.2, 0.4, 0.9, 0.7)))]),
                  background=(1, 1, 1, 1))
    assert np.abs(render_scene(scene, mode="alpha-sat", samples=8)
                  - render_scene(scene, mode="alpha", samples=8)).max() < 1e-5
