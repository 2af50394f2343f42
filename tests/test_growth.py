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


def test_exporters_documents_hold_what_they_say(tmp_path):
    """tools/exporters.py: each document is well-formed, holds the elements its docstring
    counts, and is the same bytes when made again (a benchmark must measure one document)."""
    import exporters
    fonts = os.path.join(REPO, "..", "shared", "resvg-suite", "fonts")
    args = [str(tmp_path)] + (["--fonts", fonts] if os.path.isdir(fonts) else [])
    exporters.main(args)
    ns = "{http://www.w3.org/2000/svg}"
    counts = {"scatter": (f"{ns}circle", 20000), "classes": (f"{ns}path", 8000),
              "graph": (f"{ns}ellipse", 1500), "ticks": (f"{ns}text", 3000),
              "xlists": (f"{ns}tspan", 90)}
    for name, (tag, n) in counts.items():
        root = ET.parse(tmp_path / f"{name}.svg").getroot()
        assert len(root.findall(f".//{tag}")) == n, name
    if os.path.isdir(fonts):
        root = ET.parse(tmp_path / "glyph_uses.svg").getroot()
        assert len(root.findall(f".//{ns}use")) > 10000
    first = (tmp_path / "scatter.svg").read_bytes()
    exporters.main([str(tmp_path)])
    assert (tmp_path / "scatter.svg").read_bytes() == first
