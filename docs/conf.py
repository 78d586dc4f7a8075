"""Sphinx configuration of geoimg's documentation site.

Build it with ``python -m sphinx -W --keep-going -b html docs docs/_build/html`` (after
``pip install -e ".[docs]"``); warnings are errors. The API reference is generated from the packages'
``__all__`` at each build (``_ext/api_pages.py``); the gallery runs the scripts of ``samples/``
(sphinx-gallery, pictures picked up by ``_ext/png_scraper.py``).
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import api_pages  # noqa: E402

project = "geoimg"
author = "the geoimg developers"
copyright = "2026, the geoimg developers"
release = version = __import__("geoimg").__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_ext", "gallery", "**/README.md"]
myst_heading_anchors = 3

html_theme = "pydata_sphinx_theme"
html_title = "geoimg"
html_static_path: list[str] = []
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}
html_show_sourcelink = False

templates_path = ["_templates"]
autosummary_generate = True
autodoc_typehints = "none"          # the signatures carry the annotations; numpydoc lists the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# Every public function, class, method and property has a summary, its Parameters and what it Returns
# (or Yields), and an Example: the build fails (warnings are errors) where one is missing.
numpydoc_validation_checks = {"SS01", "PR01", "RT01", "EX01"}
# The surface kinds are made by fit_surface, never by hand: their constructors' arguments are the fit's
# internal state, and their methods are the Surface interface's, documented (and validated) there.
numpydoc_validation_exclude = {r"\.__init__$", r"\.__call__$",
                               r"^geoimg\.surface\.(Planar|Sphere|PlanarCoverage|SphereCoverage|Coverage)Surface"
                               r"(\.\w+)?$"}

sphinx_gallery_conf = {
    "examples_dirs": "../samples",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/(fig|partial_|cut_|balanced_|textured|denoise)",
    "ignore_pattern": r"(_common|make_gallery)\.py",
    "image_scrapers": ("png_scraper.scrape",),
    "reset_argv": "png_scraper.argv",
    "reset_modules": (),            # the samples draw with OpenGL and OpenCV, not matplotlib
    "abort_on_example_error": True,
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
    "show_memory": False,
    "min_reported_time": 1e9,
}


def setup(app):
    """Write the API pages before Sphinx reads the sources."""
    api_pages.write(HERE / "api")
    return {"parallel_read_safe": True}
