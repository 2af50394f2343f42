"""Tools around the renderer, not on its data path: golden images and their pytest plugin,
benchmarks, accuracy measures, the demo, the resvg-suite runner, the FreeType font reference."""
