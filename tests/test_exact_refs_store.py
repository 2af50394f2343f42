"""The exact references in vecmsaa/data/exact-refs (tools/make_exact_refs.py; supersampled, or
with a repeated shape removed):
each belongs to a suite test, has its reference's size, is not for a drawing defined on device
pixels, and differs from resvg's reference only along edges, never inside a flat area (the
artifacts it removes are edge fringes; a different drawing would show inside shapes)."""
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from vecmsaa.tools.compare import FLAT_THRESHOLD, compare_images
from vecmsaa.tools.suite import EXACT_REFS, SUPERSAMPLED_REFS, suite_from_environment
from vecmsaa.tools.suite_truth import TRUTHS

HERE = Path(__file__).resolve().parent
SUITE = Path(suite_from_environment(HERE.parent.parent / "shared" / "resvg-suite"))
RESOLUTION_BOUND = (b"<filter", b"filter=", b"<image", b"<feImage", b"SBIX", b"crispEdges",
                    b"optimizeSpeed", b"<pattern")
STORED = sorted(str(p.relative_to(SUPERSAMPLED_REFS).with_suffix("")).replace(os.sep, "/")
                for p in Path(SUPERSAMPLED_REFS).rglob("*.png"))


def rgba(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


def test_store_is_not_empty_and_overlaps_no_other_exact_reference():
    assert STORED
    assert not set(STORED) & set(TRUTHS)


@pytest.mark.parametrize("name", STORED)
def test_stored_exact_reference_differs_from_the_reference_only_along_edges(name):
    svg = SUITE / "tests" / (name + ".svg")
    if not svg.exists():
        pytest.skip(f"the resvg suite is not present at {SUITE}")
    assert not (SUITE / EXACT_REFS / (name + ".png")).exists()
    assert not name.startswith("filters/")
    source = svg.read_bytes()
    assert not any(token in source for token in RESOLUTION_BOUND)
    exact = rgba(Path(SUPERSAMPLED_REFS) / (name + ".png"))
    ref = rgba(SUITE / "tests" / (name + ".png"))
    plain = compare_images(exact, ref)
    strict = compare_images(exact, ref, flat_threshold=FLAT_THRESHOLD)
    assert plain.same_size
    assert plain.off_pixels > 0     # the reference carries an artifact
    assert strict.off_pixels == plain.off_pixels
