"""Sphinx configuration of celtstone's documentation site (``make docs``)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

import importlib.util

import celtstone

project = "celtstone"
author = "the celtstone developers"
copyright = "2026, the celtstone developers"
release = celtstone.version()

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "celtstone_docs",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "examples", "_inventories", "_tutorial"]
html_theme = "pydata_sphinx_theme"
html_static_path = ["_static"]
html_context = {"default_mode": "light"}  # the theme logs an error for an unset mode
html_css_files = ["celtstone.css"]
html_theme_options = {
    # the first six pages in the navigation bar, the API and CLI references among them
    "header_links_before_dropdown": 6,
    "navigation_with_keys": False,
}
html_title = f"celtstone {release}"
myst_heading_anchors = 4  # the decisions' record sits one level down
myst_enable_extensions = ["dollarmath", "amsmath"]
# equations typeset at build time as SVG by matplotlib (celtstone_docs.math_svg): offline
html_math_renderer = "mathtext"
autosummary_generate = True
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
nitpicky = False

# Links to Python, NumPy, SciPy, xarray and matplotlib from inventories shipped in
# docs/_inventories (written by its make.py from a declared list of names): the build
# machines have no network, so nothing is fetched (decisions §33).
_spec = importlib.util.spec_from_file_location(
    "inventories", Path(__file__).parent / "_inventories" / "make.py"
)
assert _spec is not None and _spec.loader is not None
_inventories = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_inventories)
intersphinx_mapping = {
    key: (project.base_url, f"_inventories/{key}.inv")
    for key, project in _inventories.PROJECTS.items()
}
# parameter and return types as links (numpy.ndarray, xarray.Dataset, Body, ...); words
# of the type phrases themselves are not names
numpydoc_xref_param_type = True
numpydoc_xref_ignore = {"of", "or", "to", "and", "optional", "default", "shape", "Self"}

# The gallery: docs/examples/plot_*.py run at build time, their figures scraped
# (celtstone's plotting functions return Figure objects outside pyplot: the scraper
# collects those; decisions §33). No thumbnails of other sites, no network.
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "image_scrapers": ("matplotlib", "celtstone_docs.figure_scraper"),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "show_memory": False,
    "write_computation_times": False,
}

# numpydoc validation of every docstring the build renders (celtstone's public API:
# the API page's names and the members on their pages), warnings as errors
# (decisions §33 says why each check below is left out).
numpydoc_validation_checks = {
    "all",
    "ES01",  # extended summary: a one-line docstring is enough for a one-line job
    "SA01",  # See Also: the API page and the guide link related names
    "EX01",  # Examples: the gallery, the guide and the tutorial hold the runnable examples
}
# Data (MODELS, DEFAULT_RTOL, ...) and constructors that are object.__init__ are added to
# the exclusions by celtstone_docs: numpydoc checks a value's docstring as a function's
# (the page shows the docstring written under it).
numpydoc_validation_exclude: set[str] = set()
