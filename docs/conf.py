"""Sphinx configuration of the fretbem documentation.

Build from the repository root with warnings as errors::

    python -m pip install -e ".[docs]"
    python -m sphinx -W -b html docs docs/_build/html

Every tutorial under ``tutorials/`` and every study under ``verification/`` is a Python
script that sphinx-gallery executes at build time, so the pages show what the code does
today; a failing script fails the build (``abort_on_example_error``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import fretbem

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "sphinxext"))  # fretbem_api, fretbem_cli, gallery_resets

# figures are written to files only, whatever the environment says
os.environ["MPLBACKEND"] = "Agg"
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

project = "fretbem"
author = "the fretbem developers"
copyright = "the fretbem developers"
version = release = fretbem.__version__

extensions = [
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "fretbem_cli",
    "fretbem_api",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "Thumbs.db",
    ".DS_Store",
    "sphinxext",
    "tutorials/**/*-out",
    "verification/**/*-out",
    "results/**",  # data and figures of docs/results.md (fretbem convergence writes there)
]
# docs/results.md is written by benchmarks/results_page.py; it joins the verification toctree
# when it exists (see _link_results below) and the site builds without it.
RESULTS_PAGE = DOCS / "results.md"
if not RESULTS_PAGE.exists():
    exclude_patterns.append("results.md")

# -- MyST (theory.md and scene-format.md stay readable on GitHub) -----------------------------
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# -- autodoc -------------------------------------------------------------------------------
autodoc_default_options = {
    "members": True,
    "undoc-members": True,
    "show-inheritance": True,
    "member-order": "bysource",
}
autodoc_typehints = "signature"
autodoc_class_signature = "mixed"
# numpydoc renders the numpy-style sections ("Attributes" of the attrs records included)
numpydoc_show_class_members = False  # autodoc lists the members
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# -- sphinx-gallery ------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": ["tutorials", "verification"],
    "gallery_dirs": ["auto_tutorials", "auto_verification"],
    "filename_pattern": r"\.py$",  # execute every script, not only plot_*.py
    "ignore_pattern": r"__init__\.py",
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    # matplotlib's rcParams and pyvista's global theme are reset before every script
    "reset_modules": ("matplotlib", "gallery_resets.reset_pyvista"),
    "image_scrapers": ("matplotlib",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "min_reported_time": 1,
    "show_signature": False,
    "matplotlib_animations": False,
}

# -- HTML ------------------------------------------------------------------------------------
html_theme = "furo"
html_title = "fretbem"
html_static_path: list[str] = []
html_theme_options = {"navigation_with_keys": True}


def _link_results(app, docname, source) -> None:
    """Add docs/results.md to the verification toctree when benchmarks produced it."""
    if docname == "verification" and RESULTS_PAGE.exists():
        source[0] = source[0].replace(
            "   auto_verification/index\n", "   auto_verification/index\n   results\n"
        )


def setup(app) -> None:
    app.connect("source-read", _link_results)
