"""The reference stands on the docstrings: every public name of rubdiag documents each of its
parameters under its own name and what it returns (numpydoc's PR01, PR02, RT01), and the
Examples the docstrings give run and print what they say.

A class is checked as numpydoc checks it: its docstring's Parameters against ``__init__``
(a dataclass's fields). Names not yet documented are strict xfails listed in ``PENDING``:
document one and remove it from the list.
"""

from __future__ import annotations

import doctest
import importlib
import sys
from pathlib import Path

import pytest

numpydoc_validate = pytest.importorskip("numpydoc.validate")

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "rubdiag"
sys.path.insert(0, str(ROOT / "docs"))
generate = importlib.import_module("generate")       # docs/generate.py: the subpackages

PACKAGES = ("rubdiag", *(f"rubdiag.{name}" for name in generate.SUBPACKAGES))

#: missing parameters, wrong parameter names, missing returns
CHECKED = ("PR01", "PR02", "RT01")

#: public names whose docstrings do not document every parameter and return yet
PENDING: frozenset[str] = frozenset()


def public_names() -> list[str]:
    return [f"{package}.{name}" for package in PACKAGES
            for name in importlib.import_module(package).__all__]


def _param(name: str):
    if name in PENDING:
        return pytest.param(name, marks=pytest.mark.xfail(
            strict=True, reason="parameters or returns not documented yet"))
    return name


def resolve(name: str):
    package, attribute = name.rsplit(".", 1)
    return getattr(importlib.import_module(package), attribute)


@pytest.mark.parametrize("name", [_param(name) for name in public_names()])
def test_every_parameter_and_return_is_documented(name):
    found = numpydoc_validate.validate(name)
    errors = [f"{code}: {message}" for code, message in found["errors"] if code in CHECKED]
    assert errors == [], f"{name} ({found['file']}:{found['file_line']})"


def test_the_pending_list_names_only_public_names():
    assert PENDING <= set(public_names())


def modules_with_examples() -> list[str]:
    """Every module of rubdiag whose source holds a doctest (``>>>``), as
    ``--doctest-modules`` would collect them (``__main__`` modules left out)."""
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name != "__main__.py" and ">>>" in path.read_text(encoding="utf-8"):
            parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


@pytest.mark.parametrize("module", modules_with_examples())
def test_the_examples_print_what_they_say(module):
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = doctest.DocTestFinder().find(importlib.import_module(module))
    assert any(test.examples for test in tests)
    for test in tests:
        runner.run(test)
    assert runner.summarize(verbose=False).failed == 0


def _docstrings(name: str):
    """The docstring of a public name and, for a class, of each of its public members."""
    obj = resolve(name)
    yield name, obj.__doc__
    if isinstance(obj, type):
        for attribute, member in vars(obj).items():
            if not attribute.startswith("_") and (callable(member) or isinstance(
                    member, (property, classmethod, staticmethod))):
                yield f"{name}.{attribute}", member.__doc__


def substitutions(text: str) -> list[str]:
    """The substitution references reStructuredText finds in ``text`` (``|T|``: roles that
    only Sphinx knows, literals and math are not read as ones)."""
    from docutils.frontend import get_default_settings
    from docutils.nodes import substitution_reference
    from docutils.parsers.rst import Parser
    from docutils.utils import new_document

    settings = get_default_settings(Parser)
    settings.report_level = settings.halt_level = 5
    tree = new_document("docstring", settings)
    Parser().parse(text, tree)
    return [n.astext() for n in tree.findall(substitution_reference)]


def test_the_substitution_check_sees_one():
    assert substitutions("Torque |T| <= 1e6; ``|x|`` and :math:`|v|` are fine.") == ["T"]


@pytest.mark.parametrize("name", public_names())
def test_no_docstring_text_reads_as_a_substitution(name):
    """reStructuredText reads ``|T|`` as a substitution the reference does not define (an
    error in the documentation's build): absolute values are written in words or as code."""
    import inspect

    for where, doc in _docstrings(name):
        if doc and "|" in doc:
            assert substitutions(inspect.cleandoc(doc)) == [], where
