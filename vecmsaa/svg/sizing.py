"""Opening an SVG document: parsed, with its builder, its size and the matrix from its user
space to that size (:func:`open_svg`, for the API and for SVG images alike)."""
from __future__ import annotations

import math
import re
import urllib.parse

from dataclasses import dataclass

from ..scene.nodes import Group, Scene
from ..scene.transform import compose
from .builder import Builder, Options
from .document import Document, Style, load_document
from .resources import Resources
from ..scene.bounds import path_bounds, union
from .units import parse_aspect, parse_viewbox, split_length, to_px, viewbox_transform


def document_size(doc: Document, dpi: float = 96.0):
    """(width, height, matrix, viewport): intrinsic size in px, user space → (0, 0, w, h), and
    the viewport size percentages of the root's children refer to.

    A zero or negative width or height comes back as is (SVG: rendering is disabled); a
    document without a viewBox whose width or height is missing or a percentage (of nothing:
    SVG leaves the size undefined) gets None for both, and its drawing's extent decides, as
    in resvg; its viewport is then the width and height as far as they are given.
    """
    root = doc.root
    vb = parse_viewbox(root.get("viewBox"))
    style = Style(root.specified)

    def dimension(name, vb_size):
        raw = root.get(name)
        parsed = split_length(raw) if raw is not None else None
        if parsed is None or parsed[1] == "%":
            if vb is not None:
                return vb_size * (parsed[0] / 100 if parsed else 1.0)
            return 100.0 * (parsed[0] / 100 if parsed else 1.0)
        v, unit = parsed
        return to_px(v, unit, style.font_size(), dpi=dpi)

    def absolute(name):
        parsed = split_length(root.get(name)) if root.get(name) is not None else None
        return parsed is not None and parsed[1] != "%"

    if vb is None and not (absolute("width") and absolute("height")):
        # the drawing's extent sizes it; percentages inside refer to the width and height
        # that are given, a percentage of one to that of 100 and a missing one to 100
        # (resvg's default size)
        return None, None, (1.0, 0.0, 0.0, 1.0, 0.0, 0.0), (dimension("width", 100.0),
                                                            dimension("height", 100.0))
    width = dimension("width", vb[2] if vb else 100.0)
    height = dimension("height", vb[3] if vb else 100.0)

    def given(name):
        # `auto` (SVG 2: the replaced element's auto size, which follows the aspect ratio)
        # and an invalid value (ignored) leave the dimension to the other one, as missing
        raw = root.get(name)
        return raw is not None and split_length(raw) is not None

    if vb is not None and not given("width") and given("height"):
        width = height * vb[2] / vb[3]
    elif vb is not None and not given("height") and given("width"):
        height = width * vb[3] / vb[2]
    if not (width > 0 and height > 0):
        return width, height, (1.0, 0.0, 0.0, 1.0, 0.0, 0.0), (100.0, 100.0)
    if vb is not None:
        m = viewbox_transform(vb, parse_aspect(root.get("preserveAspectRatio")), width, height)
        viewport = (vb[2], vb[3])
    else:
        m = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
        viewport = (width, height)
    return width, height, m, viewport


@dataclass
class SizedDocument:
    """A parsed document ready to build: ``width`` x ``height`` px (zero or negative when the
    document disables rendering), ``root_matrix`` from user space to that size, ``viewport``
    the size percentages of the root's children refer to."""
    builder: Builder
    width: float
    height: float
    root_matrix: tuple
    viewport: tuple

    def build(self, to_device, root_scale=1.0, image=None) -> list:
        """The root's nodes under ``to_device`` (the document's px → device): the root's own
        transform in its px, outside the viewBox mapping, and the canvas (the background)
        without it; [] when that transform is singular. As a top-level document and as an
        SVG image alike. ``image``: see Builder.build_root."""
        root_transform = self.builder.root_transform(self.width, self.height)
        if root_transform is None:
            return []
        return self.builder.build_root(
            compose(compose(to_device, root_transform), self.root_matrix), self.viewport,
            root_scale=root_scale, canvas=compose(to_device, self.root_matrix), image=image)


def apply_view(doc: Document, fragment: str) -> None:
    """Link into a view of the document (SVG 2 Linking, "Linking into SVG content"): the id
    of a <view> element, whose viewBox and preserveAspectRatio (each where it has one)
    replace the root <svg>'s; ``svgView(viewBox(x,y,w,h);preserveAspectRatio(...))``, whose
    parameters do the same (its ``transform(...)`` is not applied); a spatial media fragment
    ``xywh=x,y,w,h`` (in pixels), a viewBox. Any other fragment changes nothing."""
    fragment = urllib.parse.unquote(fragment).strip()
    given = {}
    view_spec = _SVG_VIEW.fullmatch(fragment)
    xywh = _XYWH.fullmatch(fragment)
    if view_spec:
        for name, value in _VIEW_PARAM.findall(view_spec.group(1)):
            given[{"viewbox": "viewBox"}.get(name.lower(), name)] = value.replace(",", " ")
    elif xywh:
        given["viewBox"] = xywh.group(1).replace(",", " ")
    else:
        view = doc.lookup("#" + fragment)
        if view is None or view.tag != "view":
            return
        for name in ("viewBox", "preserveAspectRatio"):
            if view.get(name) is not None:
                given[name] = view.get(name)
    if "viewBox" in given and parse_viewbox(given["viewBox"]) is not None:
        doc.root.attrs["viewBox"] = given["viewBox"]
    if "preserveAspectRatio" in given:
        doc.root.attrs["preserveAspectRatio"] = given["preserveAspectRatio"]


_SVG_VIEW = re.compile(r"svgView\((.*)\)", re.S)
_VIEW_PARAM = re.compile(r"\s*(viewBox|preserveAspectRatio|transform)\(([^)]*)\)\s*;?")
_XYWH = re.compile(r"xywh=(?:pixel:)?\s*([-+0-9.eE]+\s*,\s*[-+0-9.eE]+\s*,\s*[-+0-9.eE]+"
                   r"\s*,\s*[-+0-9.eE]+)")


def open_svg(data: bytes, folder, resources: Resources, options: Options,
             whole_pixels: bool = True, view: str | None = None,
             **document_options) -> SizedDocument:
    """Parse SVG bytes and size the document; a document without width, height and viewBox
    takes its drawing's extent. ``document_options`` go to :func:`load_document` (user
    stylesheet, root defaults, languages). Raises SvgError (and RecursionError on absurd
    nesting).

    ``whole_pixels``: a size given by width, height or viewBox is rounded to whole pixels,
    and the drawing keeps its exact size inside (a 100 x 12.5 document is 100 x 13 with an
    empty half row), as resvg sizes a rendering: an output 200 px wide is then scale 2 on
    both axes, where stretching to 26 rows would scale y by 2.08. SVG images and glyphs keep
    the exact size."""
    doc = load_document(data, folder, **document_options)
    if view:
        apply_view(doc, view)
    width, height, root_m, viewport = document_size(doc, options.dpi)
    builder = Builder(doc, resources, options)
    if width is None:
        # not rounded: the suite's references scale by the exact extent (199.5 in no-size)
        width, height = drawing_extent(builder, viewport)
    elif whole_pixels and width > 0 and height > 0:
        width, height = _whole(width), _whole(height)
    return SizedDocument(builder, width, height, root_m, viewport)


def _whole(v: float) -> float:
    """v rounded half up, at least 1 (as the output size is)."""
    return float(max(1, math.floor(v + 0.5))) if math.isfinite(v) else v


def drawing_extent(builder, viewport):
    """Size of a document without width, height and viewBox: its drawing's right and bottom
    edges, strokes included (the suite's `structure/svg/no-size` reference scales by 199.5,
    where its frame's stroke ends; resvg-py 0.5.0 leaves strokes out: 199); the viewport (the
    width and height as far as given, else 100) when it draws nothing."""
    box = None
    # what is drawn, strokes included, and, as resvg sizes a document (its root group's
    # abs_bounding_box), every shape's outline painted or not and text by its object
    # bounding box (its glyphs' em boxes over their advances) rather than its ink
    identity = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    builder.text_fills = {}
    try:
        drawn = Scene(1, 1, Group(children=builder.build_root(identity, viewport))).fills()
        text = builder.text_fills
    finally:
        builder.text_fills = None
    outlines = Scene(1, 1, Group(children=builder.build_root(identity, viewport,
                                                             geometry=True))).fills()
    boxes = [path_bounds(f.path) for f in drawn if id(f) not in text]
    boxes += [path_bounds(f.path) for f in outlines]
    for b in boxes:
        if b is not None and all(math.isfinite(v) for v in b):   # as drawn: others are not
            box = union(box, b)
    if box is None or box[2] <= 0 or box[3] <= 0:
        return viewport
    return box[2], box[3]
