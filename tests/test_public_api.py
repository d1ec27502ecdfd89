"""The public API is curated: each package's ``__all__`` is the stored list that the
reference is built from (``docs/api.toml``), implementation lives in private modules, no
public name is also a module's name, and every workflow can be done with top-level names
alone (``tests/api_walk.py``)."""

from __future__ import annotations

import ast
import importlib
import json
import pkgutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import rubdiag

ROOT = Path(__file__).resolve().parents[1]
API = tomllib.loads((ROOT / "docs" / "api.toml").read_text())
#: public modules that are not API namespaces: the command line and the rig presets' data
NOT_API = {"rubdiag.cli", "rubdiag.model.presets", "rubdiag.__main__"}


def public_modules() -> list[str]:
    return ["rubdiag", *(info.name for info in pkgutil.walk_packages(rubdiag.__path__, "rubdiag.")
                         if not any(part.startswith("_") for part in info.name.split(".")[1:])
                         and not info.name.startswith("rubdiag.cli."))]


@pytest.mark.parametrize("package", sorted(API))
def test_each_all_is_the_stored_list(package):
    names = [name for group in API[package].values() for name in group]
    assert len(names) == len(set(names)), "a name listed twice"
    assert sorted(names) == sorted(importlib.import_module(package).__all__)


def test_every_public_module_is_a_namespace_of_the_stored_list():
    """Implementation modules are private (``_name.py``): the public modules are exactly the
    packages whose names docs/api.toml lists."""
    assert sorted(set(public_modules()) - NOT_API) == sorted(API)


@pytest.mark.parametrize("package", sorted(API))
def test_no_public_name_is_also_a_module(package):
    module = importlib.import_module(package)
    submodules = {info.name for info in pkgutil.iter_modules(module.__path__)}
    assert not set(module.__all__) & submodules


def test_old_names_warn_and_still_work():
    with pytest.warns(DeprecationWarning, match="use rubdiag.signal.signal_features"):
        old = rubdiag.signal.features
    assert old is rubdiag.signal_features
    with pytest.warns(DeprecationWarning, match="rubdiag.run_features"):
        rubdiag.features
    with pytest.raises(AttributeError):
        rubdiag.no_such_name


def test_the_walk_uses_top_level_names_only():
    tree = ast.parse((ROOT / "tests" / "api_walk.py").read_text())
    used = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            assert not (node.module or "").startswith("rubdiag"), ast.unparse(node)
        if isinstance(node, ast.Import):
            assert all(a.name == "rubdiag" or not a.name.startswith("rubdiag")
                       for a in node.names), ast.unparse(node)
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                and node.value.id == "rubdiag"):
            used.add(node.attr)
    assert used <= set(rubdiag.__all__), used - set(rubdiag.__all__)
    # every workflow: rig, modal, features, dataset, simulation, classifiers
    assert {"paper_rig", "critical_speeds", "signal_features", "orbit_features", "Design",
            "generate", "load", "simulate", "run_features", "train", "evaluate",
            "predict"} <= used


def test_every_workflow_with_top_level_names(tmp_path):
    done = subprocess.run([sys.executable, str(ROOT / "tests" / "api_walk.py"), str(tmp_path)],
                          capture_output=True, text=True, timeout=1500)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.splitlines()[-1])
    # the paper rig is calibrated to a first critical speed of 1500 rpm
    assert report["first_critical_rpm"] == pytest.approx(1500.0, rel=1e-3)
    assert report["signal_1x_um"] == pytest.approx(2.0, rel=1e-6)
    assert report["signal_3x_um"] == pytest.approx(0.7, rel=1e-6)
    assert report["orbit_fwd_1x"] == pytest.approx(1.0, rel=1e-6)
    assert report["orbit_rev_2x"] == pytest.approx(0.2, rel=1e-6)
    assert report["runs"] == 12 and 0 < report["rub_runs"] < 12
    assert report["run_rub_episodes"] > 0      # a 0.7-mm gap at case 2's critical speed rubs
    assert report["in_sample"]                 # scored on its own training runs: it says so
    assert report["predicted"] == ["True"]     # the rubbing record is called rub


def test_the_command_line_and_python_share_their_words():
    """A command that does what a top-level function does has its name: ``rubdiag evaluate``
    and ``rubdiag.evaluate`` both score a saved model, ``rubdiag generate`` (``dataset``)
    and ``rubdiag.generate`` both make a dataset."""
    import argparse

    from rubdiag.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    shared = {"simulate", "table2", "generate", "train", "evaluate", "predict", "calibrate",
              "campbell"}
    assert shared <= set(sub.choices) & set(rubdiag.__all__)
    assert sub.choices["generate"] is sub.choices["dataset"]
