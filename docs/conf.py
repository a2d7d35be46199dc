"""Sphinx configuration for the meschers documentation.

Build (warnings are errors)::

    pip install -e ".[docs]"
    sphinx-build -W -b html docs docs/_build/html

``-D plot_gallery=0`` skips running the examples (the gallery pages then show code only);
``tests/test_examples.py`` runs every example anyway.
"""

from __future__ import annotations

import importlib.util
import os
import re
import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # document the working tree even when it is not installed

# Headless rendering for the gallery: EGL when there is no display (pyvista_views does the
# same on import; setting it here also covers VTK imported before pyvista_views).
if not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

from sphinx.ext import autosummary  # noqa: E402

import meschers_igl  # noqa: E402

# `meschers.__main__` is the `python -m meschers` entry, not API: a placeholder keeps it out of
# autosummary's recursive scan (which skips mocked modules).
_main = types.ModuleType("meschers.__main__")
_main.__sphinx_mock__ = True
sys.modules.setdefault("meschers.__main__", _main)

project = "meschers"
author = "the meschers contributors"
copyright = "2025-2026, the meschers contributors (MIT licence)"
version = release = meschers_igl.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = [
    "_build",
    "CORE_CONTRACT.md",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "**.codeobj.json",
]
source_suffix = {".rst": "restructuredtext"}
root_doc = "index"

# --- API reference (autodoc + autosummary + numpydoc) ------------------------------------
autosummary_generate = True
autosummary_imported_members = False
# Each object is documented once, in the module that defines it (``__all__`` lists re-exports).
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True}
autodoc_typehints = "none"  # the numpy docstrings give types and shapes
autodoc_member_order = "bysource"
# PyTorch is an optional extra: document meschers_igl.inverse without it by mocking it.
autodoc_mock_imports = [m for m in ("torch", "largesteps") if importlib.util.find_spec(m) is None]
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()
nitpicky = False

# The docstrings write absolute values and norms as plain-text math (``|d - d*|``, ``|x|``);
# reStructuredText would read ``|x|`` as a substitution reference and fail the build. Escape
# bars outside inline literals and roles, so they print as written.
_LITERAL = re.compile(r"(``.*?``|:[a-z:]+:`[^`]*`|`[^`]*`)")


def _escape_bars(app, what, name, obj, options, lines) -> None:
    for i, line in enumerate(lines):
        if "|" not in line or line.lstrip().startswith(("|", "+")):  # line blocks, grid tables
            continue
        parts = _LITERAL.split(line)
        lines[i] = "".join(
            p if k % 2 else re.sub(r"(?<!\\)\|", r"\\|", p) for k, p in enumerate(parts)
        )


_OURS = ("meschers_igl", "pyvista_views", "meshlab_filters", "meschers")


def _skip_foreign(app, what, name, obj, skip, options):
    """Never document another library's class imported into a module (e.g. scipy's cKDTree)."""
    module = getattr(obj, "__module__", None)
    if what == "module" and isinstance(module, str) and module.split(".")[0] not in _OURS:
        return True
    return None


def _resolve_reexport(app, env, node, contnode):
    """Link ``meschers_igl.Mescher`` (a re-export) to where it is documented (``meschers_igl.mescher``)."""
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py" or target.split(".")[0] not in _OURS:
        return None
    parts = target.split(".")
    for i in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
            for attr in parts[i:]:
                obj = getattr(obj, attr)
        except (ImportError, AttributeError):
            continue
        module, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
        if not (isinstance(module, str) and isinstance(qualname, str)):
            return None
        real = f"{module}.{qualname}"
        if real == target:
            return None
        return env.get_domain("py").resolve_xref(
            env, node["refdoc"], app.builder, node["reftype"], real, node, contnode
        )
    return None


def setup(app) -> None:
    app.connect("missing-reference", _resolve_reexport)
    app.connect("autodoc-process-docstring", _escape_bars)
    app.connect("autodoc-skip-member", _skip_foreign)


# pyvista_views re-exports functions named like the modules that define them (``render``,
# ``compare``): ``pyvista_views.render`` is then a function to getattr but a module to import.
# Autosummary's recursive scan asks getattr first and would document the function in place of
# the module; let a submodule's own name mean the module.
_import_by_name = autosummary._import_by_name


def _submodules_first(name: str, grouped_exception: bool = True):
    module = sys.modules.get(name)
    parent_name, _, attr = name.rpartition(".")
    parent = sys.modules.get(parent_name)
    if isinstance(module, types.ModuleType) and parent is not None:
        if not isinstance(getattr(parent, attr, None), types.ModuleType):
            return module, parent, parent_name
    return _import_by_name(name, grouped_exception=grouped_exception)


autosummary._import_by_name = _submodules_first


# --- the gallery (sphinx-gallery runs every script in examples/) --------------------------
sphinx_gallery_conf = {
    "examples_dirs": ["../examples"],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r"/plot_",
    "image_scrapers": ("matplotlib",),
    "within_subsection_order": "FileNameSortKey",
    "remove_config_comments": True,
    "download_all_examples": False,
    "show_memory": False,
    "min_reported_time": 1,
    "backreferences_dir": None,
}

# --- HTML: the PyData theme, as PyVista -------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"meschers {release}"
html_static_path = ["_static"]
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "secondary_sidebar_items": ["page-toc", "sourcelink"],
}
html_show_sourcelink = True
