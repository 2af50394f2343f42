"""tools/growth.py: every shape it measures is a well-formed SVG document at any size, one that
vecmsaa builds or refuses with its one-line error (the study measures documents, not
crashes), and a larger size makes a larger document."""
import os
import sys
import xml.etree.ElementTree as ET

import pytest

from vecmsaa.api import load_svg
from vecmsaa.svg import SvgError

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tools"))
import growth  # noqa: E402


@pytest.mark.parametrize("shape", sorted(growth.S))
def test_every_shape_is_a_document_that_grows(shape):
    small, large = growth.S[shape](3), growth.S[shape](12)
    assert len(large) > len(small)
    ET.fromstring(small.encode())
    try:
        load_svg(small.encode(), width=20)
    except SvgError:
        pass
