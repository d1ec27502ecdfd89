"""Sphinx configuration of rubdiag's documentation (``make docs``).

Pages that follow the code are written at build time into ``docs/_generated`` (git-ignored):
the API reference of each subpackage from its ``__all__``, the command-line reference from
the argparse parsers, the tables of the validation pages from their files in ``data/``, and
the tutorials (the notebooks of ``notebooks/``, executed on small
inputs with ``RUBDIAG_QUICK=1``, their outputs cached between builds; ``make docs`` executes
them, and the pages with code cells, in parallel first: ``docs/execute_pages.py``).
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS))

import execute_pages  # noqa: E402  (docs/execute_pages.py: the executed pages, in parallel)
import generate  # noqa: E402  (docs/generate.py: the pages that follow the code)

for _name, _value in execute_pages.ENVIRONMENT.items():    # the tutorials' small mode
    os.environ.setdefault(_name, _value)

project = "rubdiag"
author = "the rubdiag developers"
copyright = "2026, the rubdiag developers"
release = generate.version()

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
# the generated tables are parts of pages (``{include}``), not pages
exclude_patterns = ["_build", "jupyter_execute", "**.ipynb_checkpoints", "_generated/tables"]

autosummary_generate = True
autodoc_typehints = "none"            # the numpydoc sections give the types
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_xref_param_type = False

myst_enable_extensions = ["dollarmath", "colon_fence", "substitution"]
myst_substitutions = generate.substitutions()     # values of data/ and constants in prose
nb_execution_mode = "cache"
nb_execution_timeout = execute_pages.TIMEOUT_S
nb_execution_raise_on_error = True
nb_execution_cache_path = str(execute_pages.CACHE)

html_theme = "pydata_sphinx_theme"
html_title = f"rubdiag {release}"
html_theme_options = {"navigation_depth": 2, "show_toc_level": 2}


def setup(app):
    generate.write_all(DOCS / "_generated")
    # the tutorials are the repository's notebooks, copied so that Sphinx sees them
    target = DOCS / "_generated" / "tutorials"
    target.mkdir(parents=True, exist_ok=True)
    for notebook in sorted((ROOT / "notebooks").glob("*.ipynb")):
        if not (target / notebook.name).exists() or (
                (target / notebook.name).read_bytes() != notebook.read_bytes()):
            shutil.copyfile(notebook, target / notebook.name)
