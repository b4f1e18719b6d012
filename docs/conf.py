"""Sphinx configuration for wobble's documentation.

Build: ``python -m sphinx -W docs docs/_build`` (warnings are errors). The
build is offline: no intersphinx, no remote images. Every ```python block in
these pages is also executed by ``tests/test_docs_examples.py``.
"""

from __future__ import annotations

import os
import sys
from importlib.metadata import version as _version

os.environ.setdefault("MPLBACKEND", "Agg")
sys.path.insert(0, os.path.abspath(".."))

project = "wobble"
author = "wobble developers"
copyright = "2026, wobble developers"
release = _version("wobble")
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
]
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
# Benchmark reports are generated files, included by the performance page.
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "performance-*.md", "benchmarks"]
root_doc = "index"

autodoc_typehints = "none"  # numpydoc renders the documented types
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "alabaster"
html_static_path = ["_static"]
html_title = f"wobble {release}"
html_theme_options = {"description": "Planetary wobble and rigid-body rotation, with units", "fixed_sidebar": True}
