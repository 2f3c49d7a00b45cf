"""Sphinx configuration of the tribobem documentation.

Build: ``pip install ".[docs]"`` then ``python -m sphinx -W --keep-going -b html docs docs/_build/html``.
Pages are MyST markdown; the API reference is autodoc/autosummary with numpydoc; the scenario-key
tables of the user guide are generated from the pydantic models at build time (``_ext/scenario_keys.py``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

import tribobem  # noqa: E402

project = "tribobem"
author = "the tribobem authors"
copyright = "tribobem authors, MIT licence"
release = tribobem.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax's files copied into the site: equations render offline
    "sphinx.ext.viewcode",
    "numpydoc",
    "scenario_keys",
    "api_pages",
    "docstring_text",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "data", "figures", "_templates", "api/toplevel.rst", "Thumbs.db", ".DS_Store"]

# Maths: MathJax 3 served from the site itself (_static/mathjax/, copied from the
# sphinx-mathjax-offline package of the docs extra), not from a CDN, so that a site opened
# without a network still typesets its equations.  Set here as well as by that extension, so
# that the built pages' script path can be read from this file.
mathjax_path = "mathjax/tex-chtml.js"

# MyST: the README's markdown moves into pages as is; dollar maths and heading anchors for links.
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
suppress_warnings = []

# API reference (pages written by _ext/api_pages.py into docs/api/, not tracked)
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_typehints = "none"          # numpydoc's Parameters sections carry the types
autodoc_member_order = "bysource"
numpydoc_show_class_members = False  # the autosummary tables list them; no duplicate stubs
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "furo"
html_title = f"tribobem {release}"
html_static_path = ["_static"]
html_css_files = ["tribobem.css"]
html_theme_options = {
    "source_repository": "",
    "navigation_with_keys": True,
}
html_show_sourcelink = True
