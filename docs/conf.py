"""Sphinx configuration of the acoustiviz documentation.

Build with ``python -m sphinx -W -b html docs docs/_build/html``. The gallery pages show each
script's code and its committed figure (``docs/images``) without running the scripts; set
``ACOUSTIVIZ_DOCS_RUN_GALLERY=1`` to run them instead (minutes). The API pages and the
command-line reference are generated from the package at build time (``docs/_ext``).
"""

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(ROOT))
os.environ.setdefault("MPLBACKEND", "Agg")

from gallery_source import prepare_gallery  # noqa: E402
from interactive import prepare_interactive  # noqa: E402

import acoustiviz  # noqa: E402

project = "acoustiviz"
author = "acoustiviz developers"
copyright = "acoustiviz developers"
version = release = acoustiviz.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.intersphinx",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "apipages",
    "cliref",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_gallery_src", "_interactive", "**.ipynb_checkpoints", "sg_execution_times.rst"]
templates_path = []
html_static_path = ["_static"]
html_extra_path = [prepare_interactive(HERE)]  # the interactive pages of the user guide, made now
html_css_files = ["acoustiviz.css"]

# -- HTML theme ---------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"acoustiviz {release}"
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "secondary_sidebar_items": {"**": ["page-toc"], "guide/speed_accuracy": []},
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_sidebars = {"index": [], "cli": []}
html_show_sourcelink = False

# -- API pages ----------------------------------------------------------------------------------
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "none"  # the numpydoc Parameters sections say types and units
autosummary_generate = False
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = True
intersphinx_mapping = {}

# -- gallery ------------------------------------------------------------------------------------
RUN_GALLERY = os.environ.get("ACOUSTIVIZ_DOCS_RUN_GALLERY", "") not in ("", "0")
sphinx_gallery_conf = {
    "examples_dirs": str(prepare_gallery(ROOT / "gallery", HERE, run=RUN_GALLERY)),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"plot_",
    "ignore_pattern": r"(__init__|_gallery)\.py",
    "plot_gallery": RUN_GALLERY,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",) if not RUN_GALLERY else ("gallery_source",),
    "show_memory": False,
    "show_signature": False,
    "min_reported_time": 1e9,
    "write_computation_times": False,
}

# -- MyST ---------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
