"""Sphinx configuration of morphkit's documentation (build: ``bash scripts/docs.sh``).

The stack: autodoc + numpydoc read the numpydoc docstrings (and validate them: a public name
without a docstring fails the build); ``apigen`` (``_ext/apigen.py``) writes the API reference
from every public module's ``__all__``; sphinx-gallery runs ``samples/`` into the gallery
(``_ext/morphkit_gallery.py``); myst-parser includes parts of ``README.md`` and
``docs/RESULTS.md`` by marker, so nothing is copied by hand. Warnings are errors (``-W``) and
``nitpicky`` is on, so a broken cross-reference fails the build too.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(ROOT))
os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")  # the gallery renders headless

import morphkit  # noqa: E402

project = "morphkit"
author = "morphkit contributors"
copyright = "morphkit contributors"
version = release = morphkit.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "apigen",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "bench", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "auto_examples/*.json"]
templates_path: list[str] = []

# --- strictness -----------------------------------------------------------------------------
nitpicky = True
# No intersphinx (the build runs offline): names of other packages (numpy, OpenCV, trimesh, the
# standard library) cannot be linked and are not checked (apigen.external_reference); every
# other reference must resolve.

# --- autodoc / numpydoc ---------------------------------------------------------------------
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
autosummary_generate = False  # apigen writes the pages; autosummary only makes the tables
numpydoc_show_class_members = False  # autodoc lists the members (:members: :undoc-members:)
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# GL08: "The object does not have a docstring" -- every public name documented; PR01/RT01: every
# parameter and the return value documented (numpydoc Parameters/Returns sections), so a public
# function added without them fails the build.
numpydoc_validation_checks = {"GL08", "PR01", "RT01"}

# --- MyST -----------------------------------------------------------------------------------
myst_enable_extensions = ["colon_fence"]
myst_heading_anchors = 3

# --- gallery --------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "samples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # run every sample
    "reset_argv": "morphkit_gallery.reset_argv",
    "image_scrapers": ("morphkit_gallery.written_images",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "show_memory": False,
    "plot_gallery": "True",
    "within_subsection_order": "FileNameSortKey",
}

# --- HTML -----------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = "morphkit"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}
html_static_path: list[str] = []
html_show_sourcelink = False


# --- technique pages whose figures may not be in RESULTS.md yet ------------------------------
_OPTIONAL = re.compile(r"<!-- optional-results: (\w+) -->\n(.*?)<!-- /optional-results -->\n", re.S)


def _optional_results(app: Any, docname: str, source: list[str]) -> None:
    """Keep a page's ``{include}`` of a RESULTS.md section only when the section's markers exist.

    A page wraps the include in ``<!-- optional-results: KEY -->`` ... ``<!-- /optional-results -->``;
    until ``docs/RESULTS.md`` holds ``<!-- results:KEY:start -->`` and ``<!-- results:KEY:end -->``
    the block is replaced by a note, so the page builds before its technique is measured.
    """
    results = (DOCS / "RESULTS.md").read_text(encoding="utf-8")

    def keep_or_note(m: re.Match[str]) -> str:
        key = m.group(1)
        if f"<!-- results:{key}:start -->" in results and f"<!-- results:{key}:end -->" in results:
            return m.group(2)
        return f"No measured figures yet (`docs/RESULTS.md` has no `results:{key}` section).\n"

    source[0] = _OPTIONAL.sub(keep_or_note, source[0])


def setup(app: Any) -> None:
    """Register the optional-results filter."""
    app.connect("source-read", _optional_results)
