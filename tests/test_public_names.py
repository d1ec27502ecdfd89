"""Every lazily exported name is what it says, whatever was imported before it.

Where a package's public name is also the name of one of its submodules (``rubdiag.simulate``,
the function and the package), importing the submodule makes the import system bind the
name to the module, and the package's lazy ``__getattr__`` is never asked again. Each check
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
    if got is not expected and not (isinstance(got, types.ModuleType) and callable(got)):
        wrong.append(f"{{name}} is {{got!r}}")
print("; ".join(wrong))
"""


def lazy_names(package: str) -> dict[str, str]:
    import importlib

    module = importlib.import_module(package)
    table = getattr(module, "_LAZY", None) or module._WHERE
    prefix = "" if package == "rubdiag" else f"{package}."
    return {name: where if where.startswith("rubdiag") else prefix + where
            for name, where in table.items()}


@pytest.mark.parametrize("package", ["rubdiag", "rubdiag.dataset"])
def test_lazy_names_survive_their_submodules_being_imported_first(package):
    probe = PROBE.format(package=package, lazy=lazy_names(package))
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "", done.stdout


def test_the_simulate_package_called_runs_simulate(monkeypatch):
    import rubdiag
    import rubdiag.simulate

    seen = []
    monkeypatch.setattr(rubdiag.simulate, "simulate",
                        lambda *args, **kwargs: seen.append((args, kwargs)) or "result")
    assert rubdiag.simulate is sys.modules["rubdiag.simulate"]
    assert rubdiag.simulate("run", raise_on_failure=False) == "result"
    assert seen == [(("run",), {"raise_on_failure": False})]
