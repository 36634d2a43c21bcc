"""Sphinx configuration: the markdown pages of docs/ (MyST) and the API reference from the docstrings.

    make docs        (regenerates the generated pages, then sphinx-build -W: warnings are errors)
"""
import sys
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the package of this checkout, installed or not

project = "fenics_contact"
author = "fenics_contact contributors"
copyright = "fenics_contact contributors, MIT license"
try:
    release = version = _version("fenics_contact")
except PackageNotFoundError:  # run from a checkout that is not installed
    release = version = ""

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]

myst_heading_anchors = 3  # [text](page.md#a-heading) links to a heading of a page

autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True  # a default as written in the source (``ops=NUMPY``), not its repr
napoleon_google_docstring = True
napoleon_numpy_docstring = False

html_theme = "alabaster"
html_title = "fenics_contact"


def _no_builtin_type_docstring(app, what, name, obj, options, lines):
    """A constant of a built-in type (a dict, a tuple) has no docstring of its own: drop its type's (``dict``'s
    constructor), so that the page says what api.md says about it."""
    if what == "data" and type(obj).__module__ == "builtins":
        lines.clear()


def setup(app):
    app.connect("autodoc-process-docstring", _no_builtin_type_docstring)
