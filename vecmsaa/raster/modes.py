"""The coverage modes (docs/modes.md), listed once for the raster, the command line and the
tools. Imports nothing, so the command line offers the choices without loading the kernels."""

#: multisample modes: coverage from per-sample windings, curves by the mode's rule
MSAA_MODES = ("none", "alpha", "a2c", "persample", "approx")
#: the alpha mode with the saturating (anti-correlated) blend, fills drawn front to back
#: (seed 002; docs/modes.md): no seam where fills abut, wrong where they overlap
SATURATE_MODES = ("alpha-sat",)
#: exact area (tiny-skia style) and the 256-sample conflation-free ground truth
EXACT_MODES = ("analytic", "reference")
MODES = MSAA_MODES + SATURATE_MODES + EXACT_MODES
DEFAULT_MODE = "approx"
#: sample patterns of the multisample modes (raster/sample_patterns.py, docs/modes.md): the
#: Direct3D 10.1 standard patterns, ordered grid, rotated grid, N-rooks, jittered, Poisson disk,
#: quincunx, FLIPQUAD and interleaved sampling
PATTERN_NAMES = ("d3d", "grid", "rgss", "rooks", "jittered", "poisson", "quincunx", "flipquad",
                 "interleaved")
#: resolve filters (raster/resolve.py): the box and the tent within the pixel, and the tent of
#: radius 1 px, Gaussian and Mitchell–Netravali, which weigh the neighbouring pixels' samples
FILTERS = ("box", "tent", "tent1", "gaussian", "mitchell")
DEFAULT_SAMPLES = 8
#: outputs of at most this many pixels (512 x 512, or any shape of that area) default to
#: SMALL_OUTPUT_SAMPLES: at icon sizes one pixel is a visible part of the image (at 16 px one
#: pixel off fails an icon by the suite's criterion) and 8 samples quantise a pixel's coverage
#: to 1/8, which fails 10% of real icons at 16 px, 16 samples none; at thumbnail and test-suite
#: sizes (300 px) thin features and glyph stems still show the eighths (a 0.7 px band at 45°
#: off by 69/255), and 16 samples leave 855 of the suite's 1282 tests with no pixel off its
#: reference where 8 leave 736 (docs/modes.md). The raster's cost per pixel grows by about a
#: third, a few milliseconds a document at these sizes; larger outputs keep 8.
SMALL_OUTPUT_PIXELS = 512 * 512
SMALL_OUTPUT_SAMPLES = 16


def default_samples(width: int, height: int) -> int:
    """The sample count used when none is asked for, by the output's pixel count."""
    return SMALL_OUTPUT_SAMPLES if width * height <= SMALL_OUTPUT_PIXELS else DEFAULT_SAMPLES


def samples_for(samples: int | None, width: int, height: int) -> int:
    """``samples`` when given, else the default for a width x height output."""
    return default_samples(width, height) if samples is None else samples


def coverage(mode: str | None, samples: int | None, width: int, height: int,
             analytic_exact: bool = False) -> dict:
    """``mode`` and ``samples`` for a width x height output: the given ones, else ``analytic``
    where the caller knows exact area per path is exact (no two shapes overlap, as on most font
    sheets: docs/fonts.md) and DEFAULT_MODE elsewhere, with :func:`samples_for`'s count."""
    if mode is None:
        mode = "analytic" if analytic_exact else DEFAULT_MODE
    return dict(mode=mode, samples=samples_for(samples, width, height))
