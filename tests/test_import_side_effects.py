"""Importing rubdiag changes nothing of its process: every module, public or private, imported
in a fresh interpreter leaves ``os.environ`` and matplotlib's backend as they were (the command line
chooses the backend and pins OpenBLAS's kernels where a run starts: ``tests/test_blas.py``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

PROBE = """
import importlib, json, os, pkgutil
import matplotlib, sklearn  # noqa: F401  (scikit-learn sets OpenMP variables of its own)
environ = dict(os.environ)
backend = dict.__getitem__(matplotlib.rcParams, "backend")   # as set, not resolved
import rubdiag
names = [i.name for i in pkgutil.walk_packages(rubdiag.__path__, "rubdiag.")
         if not i.name.endswith("__main__")]
for name in names:
    importlib.import_module(name)
changed = sorted(k for k in set(environ) | set(os.environ) if environ.get(k) != os.environ.get(k))
same_backend = dict.__getitem__(matplotlib.rcParams, "backend") is backend
print(json.dumps({"modules": len(names), "changed": changed, "backend_unchanged": same_backend}))
"""


def test_importing_every_module_leaves_the_environment_and_backend_alone():
    environ = {k: v for k, v in os.environ.items()
               if k not in ("MPLBACKEND", "OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS")}
    done = subprocess.run([sys.executable, "-c", PROBE], env=environ, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout.splitlines()[-1])
    assert report["modules"] > 100          # the walk found the package's modules
    assert report["changed"] == []
    assert report["backend_unchanged"]


def test_importing_the_main_modules_runs_no_command():
    for module in ("rubdiag.__main__", "rubdiag.cli.__main__"):
        done = subprocess.run([sys.executable, "-c", f"import {module}; print('imported')"],
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr[-2000:]
        assert done.stdout == "imported\n" and done.stderr == ""
