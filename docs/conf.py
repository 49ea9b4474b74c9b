"""Sphinx configuration of the Beltrami user guide (MyST Markdown, furo).
Built by `./beltrami.sh docs` into build/docs/html.  The settings tables
and the benchmarks page are generated here, at every build, from their one
source each: the plugin XML (reference.py) and the JSON files the benchmark
scripts write (benchmarks.py)."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import benchmarks  # noqa: E402
import reference  # noqa: E402

project = "Beltrami"
author = "The Beltrami developers"
copyright = "2026, the Beltrami developers"
extensions = ["myst_parser"]
source_suffix = {".md": "markdown"}
exclude_patterns = ["_build", "_generated/*", "examples/*", "benchmarks/*", "README.md"]
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3
html_theme = "furo"
html_title = "Beltrami user guide"
html_static_path = []
nitpicky = False


def generate(app):
    out = os.path.join(HERE, "_generated")
    reference.write_markdown(os.path.join(out, "settings"))
    benchmarks.write_markdown(os.path.join(HERE, "benchmarks"), os.path.join(out, "benchmarks.md"))


def setup(app):
    app.connect("builder-inited", generate)
