"""The package layout: every import of a vecmsaa module (at module top or lazy, inside a
function) goes from a stage to one allowed by the layering rule of docs/architecture.md."""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "vecmsaa"

#: stage → the stages it may import (besides itself), as docs/architecture.md states them
ALLOWED = {
    "scene": set(),
    "output": set(),
    "geometry": {"scene"},
    "raster": {"geometry", "scene", "output"},
    "fonts": {"geometry", "scene"},
    "svg": {"fonts", "geometry", "scene"},
    "api": {"svg", "fonts", "geometry", "scene", "raster", "output"},
    # CairoSVG-style calls and font previews, beside the api
    "convert": {"api", "svg", "fonts", "geometry", "scene", "raster", "output"},
    "tools": {"api", "svg", "fonts", "geometry", "scene", "raster", "output"},
    "cli": {"tools", "api", "svg", "fonts", "geometry", "scene", "raster", "output"},
    # the package itself: the version, the numba cache check, the public names on demand
    "vecmsaa": {"api", "convert", "svg"},
    "jitcache": set(),
    # the compiled kernels' module (built and loaded for jit, which every kernel module uses)
    "aot": {"jitcache"},
    "jit": {"aot", "jitcache"},
    "diagnostics": set(),
    "files": set(),
}
#: what every module may import: the package's own __init__ (the version), the numba cache
#: check it runs, njit (jit: the compiled kernels' module of aot, or numba's JIT), the
#: warnings channel (diagnostics.warn: imports nothing) and whole-or-nothing file writes
#: (files: imports nothing)
SHARED = {"vecmsaa", "jitcache", "jit", "aot", "diagnostics", "files"}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def is_module(name: str) -> bool:
    rel = Path(*name.split("."))
    return (PACKAGE.parent / rel).with_suffix(".py").is_file() or \
        (PACKAGE.parent / rel / "__init__.py").is_file()


def imported_modules(path: Path, tree: ast.AST):
    """(line, module) for every vecmsaa module ``path`` imports, anywhere in the file."""
    name = module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            # ``from . import text`` imports a module; ``from .. import MODES`` a name
            subs = [f"{module}.{a.name}" for a in node.names if is_module(f"{module}.{a.name}")]
            yield from ((node.lineno, m) for m in (subs or [module]))


def stage(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def violations(path: Path, source: str):
    own = stage(module_name(path))
    allowed = ALLOWED[own] | SHARED | {own}
    for line, module in imported_modules(path, ast.parse(source)):
        if module.split(".")[0] != "vecmsaa":
            continue
        # the root package, but no stage, may be imported from anywhere
        if module == "vecmsaa":
            continue
        if stage(module) not in allowed:
            yield f"{path.relative_to(PACKAGE.parent)}:{line}: {own} imports {module}"


def test_every_stage_imports_only_the_stages_below_it():
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        bad.extend(violations(path, path.read_text(encoding="utf-8")))
    assert not bad, "\n".join(bad)


def test_every_stage_is_known():
    stages = {stage(module_name(p)) for p in PACKAGE.rglob("*.py")}
    assert stages <= set(ALLOWED), stages - set(ALLOWED)


@pytest.mark.parametrize("where, source", [
    ("svg/paint.py", "from ..raster.render import render_scene\n"),
    ("svg/text/draw.py", "def f():\n    from ...raster import scan\n"),
    ("scene/nodes.py", "import vecmsaa.geometry.primitives\n"),
    ("geometry/stroke.py", "from ..svg import units\n"),
    ("raster/render.py", "from .. import api\n"),
    ("output/png.py", "from ..scene.nodes import Scene\n"),
])
def test_a_forbidden_import_is_found(where, source):
    assert list(violations(PACKAGE / where, source))


def test_allowed_imports_pass():
    assert not list(violations(PACKAGE / "svg/paint.py", "from ..scene.nodes import Group\n"))
    assert not list(violations(PACKAGE / "raster/render.py",
                               "def f():\n    from ..output.rgba8 import x\n"))


def test_no_module_names_an_undefined_name():
    """Every name a module reads is defined or imported (pyflakes' static check): a call to a
    function nobody imported raises NameError only when that branch runs, as
    ``kernelUnitLength`` did in svg/filters.py until session 13 (every use of the attribute
    failed the render)."""
    from pyflakes import api, messages, reporter

    class Collect(reporter.Reporter):
        def __init__(self):
            super().__init__(None, None)
            self.found = []

        def flake(self, message):
            if isinstance(message, (messages.UndefinedName, messages.UndefinedLocal,
                                    messages.UndefinedExport)):
                self.found.append(str(message))

        def syntaxError(self, *args):
            self.found.append(f"syntax error: {args}")

        def unexpectedError(self, filename, msg):
            self.found.append(f"{filename}: {msg}")

    found = Collect()
    for path in sorted(PACKAGE.rglob("*.py")):
        api.checkPath(str(path), found)
    assert found.found == []
