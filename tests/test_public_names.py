"""Every lazily exported name is what it says, whatever was imported before it.

Were a package's public name also the name of one of its submodules, importing the submodule
would make the import system bind the name to the module, and the package's lazy
``__getattr__`` would never be asked again. Each check
runs in a fresh interpreter, after importing every submodule first: the worst order.
"""

import subprocess
import sys

import pytest

PROBE = """
import importlib, pkgutil, sys, types
import {package} as package
for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
    if not info.name.endswith("__main__"):
        importlib.import_module(info.name)
wrong = []
for name, where in {lazy}.items():
    expected = getattr(importlib.import_module(where), name)
    got = getattr(package, name)
    if got is not expected:
        wrong.append(f"{{name}} is {{got!r}}")
print("; ".join(wrong))
"""


def lazy_names(package: str) -> dict[str, str]:
    import importlib

    module = importlib.import_module(package)
    table = getattr(module, "_LAZY", None) or module._WHERE
    prefix = "" if package == "rubdiag" else f"{package}._"
    return {name: where if where.startswith("rubdiag") else prefix + where
            for name, where in table.items()}


@pytest.mark.parametrize("package", ["rubdiag", "rubdiag.dataset"])
def test_lazy_names_survive_their_submodules_being_imported_first(package):
    probe = PROBE.format(package=package, lazy=lazy_names(package))
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "", done.stdout

