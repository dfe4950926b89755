"""Sphinx configuration of the quatnav documentation site.

Build it with ``bash tools/docs.sh`` (output in build/docs/html), or directly::

    PYTHONPATH=python python3 -m sphinx -W --keep-going -b html docs build/docs/html

The API reference documents whichever ``quatnav`` Python imports: the source tree with
``PYTHONPATH=python`` (the compiled ``quatnav/_core*.so`` must be there), else the installed
package. The figures are made at build time by running quatnav's own commands
(``_ext/quatnav_figures.py``) and written next to the HTML output, never into the sources.
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import quatnav  # noqa: E402  (the package whose docstrings are documented)

project = "quatnav"
author = "quatnav developers"
copyright = "quatnav developers"
version = release = quatnav.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.viewcode",
    "quatnav_docstrings",
    "quatnav_figures",
    "quatnav_cli",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
templates_path: list[str] = []

# --- Markdown (the docs/*.md pages and the README) ------------------------------------------
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

# --- API reference from the numpydoc docstrings ---------------------------------------------
# Shape names in the docstrings' types ("(N, n_states) ndarray") are not cross-references:
# the same attribute name on several classes is not an ambiguity worth a warning.
suppress_warnings = ["ref.python"]
autodoc_default_options = {"members": True, "member-order": "bysource", "undoc-members": False}
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented"
autodoc_class_signature = "mixed"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True

# --- HTML --------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"quatnav {release}"
html_static_path: list[str] = []
pygments_style = "sphinx"
pygments_dark_style = "monokai"


def _report_package(app):
    from sphinx.util import logging
    logging.getLogger(__name__).info(f"quatnav {quatnav.__version__} documented from {Path(quatnav.__file__).parent}")


def setup(app):
    app.connect("builder-inited", _report_package)
