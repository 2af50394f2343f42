"""Options shared by the commands that rasterise: one definition, one validation."""
from __future__ import annotations

import argparse


#: The reference mode's largest sample count: its memory and time grow with the count (2^20
#: samples took 12 GB within a minute for one line of text), and 256 or 1024 is its use.
MAX_REFERENCE_SAMPLES = 4096


def sample_count(text: str) -> int:
    """A sample count the renderer has a pattern for: 1, 2, 4, 8, 16 — or, for the reference
    mode, a square number from 256 to MAX_REFERENCE_SAMPLES."""
    from vecmsaa.raster.sample_patterns import D3D_PATTERNS

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    side = int(round(value ** 0.5)) if value > 0 else 0
    if value in D3D_PATTERNS or (256 <= value <= MAX_REFERENCE_SAMPLES
                                 and side * side == value):
        return value
    raise argparse.ArgumentTypeError(
        f"must be one of {', '.join(map(str, sorted(D3D_PATTERNS)))} "
        f"(or a square from 256 to {MAX_REFERENCE_SAMPLES} for the reference mode): {text!r}")


def add_coverage_options(parser, default_mode: str | None = None) -> None:
    """--mode and --samples. Both stay None when not given, meaning 'the renderer's default'
    (or, for golden checks, 'what the manifest recorded'); ``default_mode`` is the mode the
    command uses then, for the help text (the renderer's default when None)."""
    from ..raster.modes import (DEFAULT_MODE, DEFAULT_SAMPLES, MODES, SMALL_OUTPUT_PIXELS,
                                SMALL_OUTPUT_SAMPLES)

    side = int(SMALL_OUTPUT_PIXELS ** 0.5)
    parser.add_argument("--mode", choices=MODES,
                        help=f"coverage mode: {', '.join(MODES)} (default "
                             f"{default_mode or DEFAULT_MODE}; see docs/modes.md)")
    parser.add_argument("--samples", type=sample_count,
                        help=f"samples per pixel: 1, 2, 4, 8, 16 (default "
                             f"{SMALL_OUTPUT_SAMPLES} for outputs of at most {side}x{side} "
                             f"pixels, {DEFAULT_SAMPLES} for larger ones); the reference mode "
                             f"takes a square from 256 to {MAX_REFERENCE_SAMPLES}")


def add_sampling_options(parser) -> None:
    """--pattern and --filter: where the samples of a pixel lie and how they are weighed."""
    from ..raster.modes import FILTERS, PATTERN_NAMES

    parser.add_argument("--pattern", choices=PATTERN_NAMES,
                        help="sample pattern of the multisample modes (docs/modes.md): d3d (the "
                             "Direct3D 10.1 standard patterns; default), grid (ordered), rgss "
                             "(rotated grid, 4 samples), rooks (N-rooks), jittered, poisson "
                             "(Poisson disk), quincunx (centre and shared corners, 2 stored "
                             "samples), flipquad (shared edge samples, 2 stored) or interleaved "
                             "(a 4x4 tile of pixels, each with its own pattern); the last three "
                             "render once per stored sample and class (interleaved: once per "
                             "class), so cost more")
    parser.add_argument("--filter", choices=FILTERS,
                        help="resolve filter: box (every sample weighs the same; the default, "
                             "tent for quincunx), tent (samples weigh less towards the pixel's "
                             "edges), or, weighing the neighbouring pixels' samples too, tent1 "
                             "(tent of radius 1 px), gaussian (sigma 0.5 px, radius 1.5) or "
                             "mitchell (Mitchell-Netravali B = C = 1/3, radius 2)")
    parser.add_argument("--color-samples", type=int, metavar="K",
                        help="CSAA: store at most K colours per pixel over the --samples "
                             "coverage samples (e.g. --samples 16 --color-samples 4; default: "
                             "one colour per sample; docs/modes.md)")


def job_count(text: str) -> int:
    """Worker processes; 0 means one per core."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 (one per core) or more: {text!r}")
    if value == 0:
        from vecmsaa.tools.workers import default_jobs
        return default_jobs()
    return value


def add_scheduler_option(parser) -> None:
    """--scheduler (the cluster module is imported only when a batch runs on one)."""
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="render on the Dask cluster of this scheduler, e.g. "
                             "tcp://HOST:8786 (needs vecmsaa[dask]; docs/cluster.md)")


def add_jobs_option(parser, default: int = 1) -> None:
    """``-j/--jobs N``, the same in every batch command: N worker processes, 0 = one per core.
    A worker that dies (killed, out of memory) fails only the file it had."""
    stated = "one per core" if default == 0 else str(default)
    # a string default goes through job_count too (so 0 becomes the core count)
    parser.add_argument("-j", "--jobs", type=job_count, default=str(default), metavar="N",
                        help=f"worker processes, 0 for one per core (default: {stated})")
