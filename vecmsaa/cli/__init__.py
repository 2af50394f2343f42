"""vecmsaa's command-line layer (installed as ``vecmsaa.cli``)."""
