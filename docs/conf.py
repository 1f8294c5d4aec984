"""Sphinx configuration of dentopo's documentation site (built by docs/build.sh).

Markdown pages (MyST) and notebooks are read by myst-nb, which executes every
notebook at build; the gallery (examples/gallery/plot_*.py) is run by
sphinx-gallery, so every picture and output on the site is made by the code
beside it, at build.  The API pages are generated from the numpydoc docstrings
by autosummary.  docs/design.md says why these tools.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))  # the checkout's dentopo, whatever is installed
sys.path.insert(0, str(DOCS / "_ext"))  # the gallery's picture scraper

os.environ.setdefault("MPLBACKEND", "Agg")  # no windows: pictures are rendered off-screen
os.environ.pop("DISPLAY", None)

import dentopo  # noqa: E402

project = "dentopo"
author = "dentopo developers"
copyright = "dentopo developers"
release = dentopo.__version__
version = release

extensions = [
    "myst_nb",  # Markdown pages (myst-parser) and executed notebooks
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "**.ipynb_checkpoints",
    "gallery/*.ipynb",  # sphinx-gallery's downloadable notebooks, not pages
    "gallery/*.py",
    "gallery/*.md5",
    "gallery/*.zip",
    "gallery/*.codeobj.json",
    "gallery/*.json",
]
templates_path = ["_templates"]

# -- MyST and notebooks -------------------------------------------------------
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3  # links such as page.md#a-section work, as on GitHub
nb_execution_mode = "force"  # every notebook runs at every build: outputs cannot go stale
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True

# -- API reference ------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"  # the numpydoc sections say the types
numpydoc_show_class_members = False  # a result's fields are listed in its docstring
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()  # per-item style checks off; parsing errors stay
numpydoc_xref_param_type = False

# -- Gallery ------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples" / "gallery"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",  # every plot_*.py is executed at build
    "image_scrapers": ("gallery_pictures.png_files", "matplotlib"),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "show_memory": False,
    "matplotlib_animations": False,
    "reset_modules": ("matplotlib",),
}

# -- HTML ---------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"dentopo {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_show_sourcelink = False

# -- Sections that appear once they have pages --------------------------------
# A toctree glob that matches nothing is a warning (and warnings are errors
# here), and a glob matches only the pages not listed by name before it.  The
# tutorial, and guide pages beyond those listed, are written by their own
# authors, so a glob line that matches no further page yet is left out.
_GLOB_LINE = re.compile(r"^(?P<pattern>[\w./-]*\*[\w./*-]*)\s*$")
_NAME_LINE = re.compile(r"^(?P<name>[\w./-]+)\s*$")
_SOURCE_SUFFIXES = (".md", ".ipynb", ".rst")


def _further_pages(docname: str, pattern: str, listed: set[str]) -> bool:
    folder = (DOCS / docname).parent
    pages = (p for p in folder.glob(pattern) if p.suffix in _SOURCE_SUFFIXES)
    return any(p.relative_to(folder).with_suffix("").as_posix() not in listed for p in pages)


def _drop_empty_globs(app, docname: str, source: list[str]) -> None:
    text = source[0]
    if ":glob:" not in text:
        return
    lines = text.splitlines(keepends=True)
    listed = {m["name"] for line in lines if (m := _NAME_LINE.match(line))}
    kept = [
        line
        for line in lines
        if (m := _GLOB_LINE.match(line)) is None or _further_pages(docname, m["pattern"], listed)
    ]
    source[0] = "".join(kept)


def setup(app):
    app.connect("source-read", _drop_empty_globs)
