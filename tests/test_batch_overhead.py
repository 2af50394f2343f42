"""What a render costs beyond its own drawing, counted: executors and threads made, and that
many small renders in one process give each file's own bytes (docs/bench.md, session 36)."""
import concurrent.futures
import math

import numpy as np
import pytest

from vecmsaa.api import render_svg_array
from vecmsaa.raster import render as render_module

#: a small drawing with few items: a 200 px suite test or icon
SMALL_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">'
             '<rect x="20" y="30" width="120" height="90" fill="teal"/>'
             '<circle cx="120" cy="120" r="60" fill="orange" fill-opacity="0.7" '
             'stroke="navy" stroke-width="5"/></svg>')


@pytest.fixture
def executors(monkeypatch):
    """The ThreadPoolExecutors made while the test runs (a list that grows)."""
    made = []

    class Counted(concurrent.futures.ThreadPoolExecutor):
        def __init__(self, *args, **kwargs):
            made.append(self)
            super().__init__(*args, **kwargs)
    monkeypatch.setattr(concurrent.futures, "ThreadPoolExecutor", Counted)
    return made


def test_a_small_image_whose_rows_left_are_cheap_is_drawn_on_one_thread(executors, monkeypatch):
    """A small image with few items (PACED_PIXELS) asked for two threads: the first band that
    draws something decides; when the rows left would take less than MIN_SHARED_SECONDS, no
    executor is made, no thread started, and the image is the one thread's, byte for byte;
    when they would take more (here: any time), the second thread joins, same bytes."""
    one = render_svg_array(SMALL_SVG, threads=1)
    assert one[..., 3].any()
    monkeypatch.setattr(render_module, "MIN_SHARED_SECONDS", math.inf)
    for _ in range(5):
        assert np.array_equal(render_svg_array(SMALL_SVG, threads=2), one)
    assert executors == []
    monkeypatch.setattr(render_module, "MIN_SHARED_SECONDS", 0.0)
    submitted = []
    submit = render_module._LazyPool.submit
    monkeypatch.setattr(render_module._LazyPool, "submit",
                        lambda pool, fn, *args: submitted.append(fn) or submit(pool, fn, *args))
    assert np.array_equal(render_svg_array(SMALL_SVG, threads=2), one)
    assert submitted


def test_band_pace_decides_by_the_time_the_rows_left_would_take(monkeypatch):
    """BandPace of a small image (its height given): empty bands count as rows drawn and
    decide nothing; the first band that draws decides by its CPU time per row times the rows
    left, against MIN_SHARED_SECONDS. A larger image's (no height) waits only for many
    items."""
    monkeypatch.setattr(render_module, "MIN_SHARED_SECONDS", 4e-3)
    assert not render_module.BandPace([], range(0, 400, 50), 50, 400, None).wait
    outcomes = []

    def pace():
        p = render_module.BandPace([], range(0, 200, 32), 32, 200, 200)
        assert p.wait
        p.decide = (lambda: outcomes.append("join"), lambda: outcomes.append("alone"))
        return p
    p = pace()
    p.band_drawn(1.0, 0, 32, 1.0)           # nothing drawn: no decision however slow
    assert outcomes == [] and p.decide is not None
    # rows left after the second band: 200 - 64 = 136; 136 / 32 * 1 ms = 4.25 ms
    p.band_drawn(0.0, 3, 32, 1e-3)
    assert outcomes == ["join"] and p.decide is None
    # the first band: 168 rows left, 168 / 32 * 0.7 ms = 3.675 ms
    pace().band_drawn(1.0, 3, 32, 0.7e-3)
    assert outcomes == ["join", "alone"]
