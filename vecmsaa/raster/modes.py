"""The coverage modes (docs/modes.md), listed once for the raster, the command line and the
tools. Imports nothing, so the command line offers the choices without loading the kernels."""

#: multisample modes: coverage from per-sample windings, curves by the mode's rule
MSAA_MODES = ("none", "alpha", "a2c", "persample", "approx")
#: the multisample modes whose curve coverage goes through the half-plane mask table
MASK_TABLE_MODES = MSAA_MODES[1:]
#: exact area (tiny-skia style) and the 256-sample conflation-free ground truth
EXACT_MODES = ("analytic", "reference")
MODES = MSAA_MODES + EXACT_MODES
DEFAULT_MODE = "approx"
DEFAULT_SAMPLES = 8
