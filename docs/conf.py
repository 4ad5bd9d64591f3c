"""Sphinx configuration of the debench documentation site.

Build: ``sphinx-build -W --keep-going -n -b html docs docs/_build/html`` (warnings are
errors, nitpicky cross-references). Pages under ``generated/`` are written at build time
by the local extension ``_ext/debench_pages.py`` from the repository itself (the report,
the reference problems, the datasets, the errata, the API module list, the CLI); the
gallery under ``auto_examples/`` is made by sphinx-gallery, which runs every script of
``examples/``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))

# one BLAS/OpenMP and NGSolve thread, as every debench command (set before numpy loads)
os.environ.setdefault("DEBENCH_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

import debench  # noqa: E402  (after the thread settings)

project = "debench"
author = "debench developers"
copyright = "debench developers; code MIT, datasets CC-BY-4.0"  # noqa: A001 - Sphinx's name
release = debench.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
    "debench_pages",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "auto_examples/*.ipynb",
                    "auto_examples/*.py", "auto_examples/*.zip", "**/*.codeobj.json"]

# --- MyST
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3

# --- autodoc / numpydoc
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented"
autodoc_default_options = {"members": True}
# The docs extra has no pytest: autodoc imports the pytest plugin (debench.pytest_plugin)
# with pytest mocked, which documents the fixture as the function it decorates. The page
# generation (_ext/debench_pages.py) never imports that module itself.
autodoc_mock_imports = ["pytest"]
# numpydoc's per-class member tables would list every member a second time
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = False

# Nitpicky mode checks every cross-reference. Inside debench every reference must resolve.
# The site is built offline (no intersphinx inventories can be fetched), so names of other
# packages and of builtin types in signatures and parameter types cannot resolve here:
# only those, by package prefix, are exempt.
EXTERNAL = ("numpy", "np", "scipy", "xarray", "xr", "ngsolve", "ngs", "matplotlib",
            "pathlib", "collections", "typing", "dataclasses", "argparse", "os", "enum",
            "concurrent", "functools", "types", "sympy", "distributed", "dask", "pytest",
            "_pytest", "numpy.typing", "cf_units", "netCDF4")
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", rf"({'|'.join(EXTERNAL)})(\..*)?"),
    # builtin types and typing words as numpydoc and autodoc print them
    (r"py:.*", r"(int|float|complex|str|bool|bytes|dict|list|tuple|set|frozenset|object|"
               r"None|callable|Callable|Any|Iterable|Iterator|Sequence|Mapping|"
               r"ArrayLike|NDArray|optional|array_like|array-like|ndarray|default|"
               r"type|Path|Exception|ValueError|RuntimeError|TypeError|KeyError|"
               r"ArithmeticError|LookupError|AssertionError|Generator|Literal|Self|"
               r"ClassVar|Union|Optional)"),
]

# --- sphinx-gallery: every script in examples/ runs at build time
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": str(DOCS / "auto_examples"),
    "filename_pattern": r".*\.py$",   # execute every example, not only plot_*
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "reset_modules": ("matplotlib",),
    "remove_config_comments": True,
    "min_reported_time": 0,
    "show_memory": False,
    "image_scrapers": ("matplotlib",),
    "backreferences_dir": None,
}

# --- HTML
html_theme = "pydata_sphinx_theme"
html_title = f"debench {release}"
# _static/custom.css: wide tables wrap inside the article column instead of overflowing
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_show_sourcelink = True
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
# The pages of wide tables have no section navigation (top-level pages): without the empty
# primary sidebar their article gets the width their tables need (see _static/custom.css)
html_sidebars = {page: [] for page in ("generated/verdict", "generated/errata",
                                       "generated/peers")}


# --- docstrings: plain-text maths and re-exported names
def _plain_math(app, what, name, obj, options, lines):
    """The docstrings write maths as plain text, where ``|x|`` is an absolute value and
    ``||r||`` a norm; reST would read ``|x|`` as a substitution reference. Escape ``|``
    outside inline literals, roles, literal blocks and table borders, so it shows as
    written."""
    import re

    literal_indent = None
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if literal_indent is not None:
            if stripped and indent <= literal_indent:
                literal_indent = None
            else:
                continue
        if "|" not in line or re.match(r"^\s*(\+[-=+]+\+|\|.*\|)\s*$", line):
            pass  # no bar, or a grid-table border or row
        else:
            parts = re.split(r"(``.*?``|:[a-z:]+:`[^`]*`|`[^`]*`_?)", line)
            lines[i] = "".join(p if k % 2 else p.replace("|", r"\|")
                               for k, p in enumerate(parts))
        if stripped.endswith("::"):
            literal_indent = indent


def _lookup(name: str):
    """The object of debench called ``name`` (module, then attributes), or None."""
    import importlib

    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        try:
            for attr in parts[k:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        return obj
    return None


def _resolve_reexport(app, env, node, contnode):
    """Two rules for references to objects of debench that have no entry of their own.

    * A name an object is re-exported or imported under (``debench.models.materials.
      GentMembrane``, or ``Annulus`` inside a module that imports it) resolves to where the
      object is documented: the module that defines it.
    * A private object (a name part starting with ``_``: ``_newton``, ``_generated``) has
      no page; a reference to one that exists renders as code, without a link.

    A name that is no object of debench, or whose defining place is not documented, stays
    unresolved, and nitpicky mode reports it.
    """
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    here, cls = node.get("py:module"), node.get("py:class")
    cands = []
    if here and cls:
        cands.append(f"{here}.{cls}.{target}")
    if here:
        cands.append(f"{here}.{target}")
    cands.append(target)
    domain = env.get_domain("py")
    for cand in cands:
        if not cand.startswith("debench."):
            continue
        obj = _lookup(cand)
        if obj is None:
            continue
        mod = getattr(obj, "__name__", None) if hasattr(obj, "__path__") or \
            type(obj).__name__ == "module" else getattr(obj, "__module__", None)
        qual = None if type(obj).__name__ == "module" else getattr(obj, "__qualname__", None)
        canonical = mod if type(obj).__name__ == "module" else (
            f"{mod}.{qual}" if mod and qual else None)
        if canonical and canonical != cand and canonical in domain.objects:
            return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                       canonical, node, contnode)
        if canonical is None:  # data: the documented name bound to this very object
            last = cand.rsplit(".", 1)[-1]
            for name, entry in domain.objects.items():
                if name.endswith("." + last) and entry.objtype == "data" and \
                        name != cand and _lookup(name) is obj:
                    return domain.resolve_xref(env, node["refdoc"], app.builder,
                                               node["reftype"], name, node, contnode)
        names = (canonical or cand).split(".")
        if any(n.startswith("_") and not n.startswith("__") for n in names):
            return contnode
    return None


def _numpy_scalars_as_numbers() -> None:
    """Module data documented by autodoc shows its value (``RTOL = ...``) as the repr Sphinx
    makes of it; a numpy scalar's repr is ``np.float64(8.88e-16)``, never a number for
    reading. Show numpy scalars (also inside containers) as the Python number they hold."""
    from sphinx.util import inspect as sphinx_inspect

    original = sphinx_inspect.object_description
    if getattr(original, "_debench", False):
        return

    def described(obj, *args, **kwargs):
        if type(obj).__module__ == "numpy" and getattr(obj, "ndim", None) == 0 and \
                hasattr(obj, "item"):
            obj = obj.item()
        return original(obj, *args, **kwargs)

    described._debench = True
    sphinx_inspect.object_description = described


def setup(app):
    _numpy_scalars_as_numbers()
    app.connect("autodoc-process-docstring", _plain_math, priority=400)
    app.connect("missing-reference", _resolve_reexport)
