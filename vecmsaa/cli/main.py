"""``vecmsaa`` entry point: one sub-command per module, imported only when it runs.

Each command module exposes ``add_parser(subparsers)`` (cheap: argparse only) and
``run(args) -> int``. Heavy imports (numba kernels, fontTools, PIL) happen inside ``run``, so
``vecmsaa --help`` and start-up stay fast.
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import sys

COMMANDS = ("render", "font", "golden", "bench", "demo", "suite")
#: commands that run numba kernels (they say so on stderr when they compile them)
COMPILING = set(COMMANDS)


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser; with ``only``, a command's name, the parser of that command
    alone (what a run of it needs: the other commands' parsers import what their help texts
    quote, e.g. golden's tolerances from vecmsaa.tools.compare)."""
    from vecmsaa import __version__

    parser = argparse.ArgumentParser(
        prog="vecmsaa", formatter_class=help_formatter,
        description="Render SVG files and font glyphs with Loop-Blinn curves and multisample "
                    "antialiasing.")
    version = f"vecmsaa {__version__}"
    parser.add_argument("-V", "--version", action="version", version=version)
    sub = _WithVersion(parser.add_subparsers(dest="command", metavar="COMMAND"), version)
    for name in COMMANDS if only is None else (only,):
        try:
            module = importlib.import_module(f"vecmsaa.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"vecmsaa.cli.{name}":
                continue  # command not built yet
            raise
        module.add_parser(sub)
    return parser


def help_formatter(prog: str) -> argparse.HelpFormatter:
    """argparse's help formatter as wide as the terminal, told the width: argparse's own
    asks shutil.get_terminal_size, and importing shutil (with bz2, lzma, fnmatch) took 3 ms
    of every command's start, help or not (add_argument makes a formatter to check each
    metavar). The width as shutil computes it: COLUMNS, else standard output's terminal, else
    80 columns; less two, as argparse takes it."""
    try:
        columns = int(os.environ.get("COLUMNS", ""))
    except ValueError:
        columns = 0
    if columns <= 0:
        try:
            columns = os.get_terminal_size(sys.__stdout__.fileno()).columns or 80
        except (AttributeError, ValueError, OSError):
            columns = 80
    return argparse.HelpFormatter(prog, width=columns - 2)


class _WithVersion:
    """The sub-command registry, giving every command -V/--version (as resvg has)."""

    def __init__(self, subparsers, version):
        self.subparsers, self.version = subparsers, version

    def add_parser(self, *args, **kwargs):
        for key in ("help", "description"):   # docstring markup does not belong in --help
            if isinstance(kwargs.get(key), str):
                kwargs[key] = kwargs[key].replace("``", "'")
        kwargs.setdefault("formatter_class", help_formatter)
        parser = self.subparsers.add_parser(*args, **kwargs)
        parser.add_argument("-V", "--version", action="version", version=self.version)
        return parser


def main(argv=None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    # the first word not an option names the command (the top level has no option taking a
    # value); an unknown or missing one gets the whole parser and its message
    first = next((w for w in words if not w.startswith("-")), None)
    parser = build_parser(first if first in COMMANDS else None)
    args = parser.parse_args(argv)
    if not getattr(args, "command", None):
        parser.print_help()
        return 2
    module = importlib.import_module(f"vecmsaa.cli.{args.command}")
    if args.command in COMPILING:
        from .compile_notice import announcing
        notice = announcing()
    else:
        notice = contextlib.nullcontext()
    try:
        with notice:
            return int(module.run(args) or 0)
    except KeyboardInterrupt:
        print("vecmsaa: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 1


def console() -> None:
    """The ``vecmsaa`` command: main(), then the process ends without the interpreter's
    teardown, which frees every object and module one by one (≈ 70 ms of CPU after any
    command: a sixth of a small render's). What an exit must do still happens: the atexit
    handlers run (temporary folders, worker processes, coverage), standard output and error
    are flushed. With another thread alive, an exception or a failing flush, the ordinary exit
    takes over.

    numpy's BLAS (OpenBLAS) starts a thread per core when numpy is imported, ≈ 0.1 s of CPU
    and 30 ms of a small render's 0.17 s on a 2-core machine: the command asks for one
    (unless the environment says otherwise); its one matrix product, feColorMatrix's 4 x 4,
    is memory-bound.

    Python's cyclic garbage collector runs every 50,000 allocations instead of 700: the
    start-up's imports (numpy's most) make tens of thousands of objects that all stay alive,
    and the 60 collections they triggered in a 16 px render freed 494 objects (≈ 6 ms of its
    0.14 s of CPU; a document's build and render pause the collector anyway, see
    api.collector_paused). A long batch still collects its garbage cycles.

    The band threads' executor is kept from render to render (raster.render.band_pool): its
    idle threads end first, so that this thread is alone."""
    import atexit
    import gc
    import os
    import threading

    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    gc.set_threshold(50_000)
    code = main()
    render = sys.modules.get("vecmsaa.raster.render")
    if render is not None:
        render.release_band_pool()      # its idle threads (kept from render to render)
    if threading.active_count() > 1 or not hasattr(atexit, "_run_exitfuncs"):
        sys.exit(code)
    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        sys.exit(code)
    os._exit(code)


if __name__ == "__main__":
    console()
