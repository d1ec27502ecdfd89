"""The docstring examples of the signal layer run and give what they print."""

from __future__ import annotations

import doctest
import importlib

import pytest


@pytest.mark.parametrize(
    "module",
    ["rubdiag.signal.spectrum", "rubdiag.signal.table", "rubdiag.signal.transformer"],
)
def test_examples(module):
    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0
    assert result.failed == 0


def test_import_rubdiag_stays_light():
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])}
    code = (
        "import sys, rubdiag; assert callable(rubdiag.features.__call__); "
        "print('numpy' in sys.modules)"
    )
    lazy = "import sys, rubdiag; print('numpy' in sys.modules, 'features' in rubdiag.__all__)"
    run = {"capture_output": True, "text": True, "check": True, "env": env}
    out = subprocess.run([sys.executable, "-c", lazy], **run)
    assert out.stdout.split() == ["False", "True"]
    out = subprocess.run([sys.executable, "-c", code], **run)
    assert out.stdout.strip() == "True"
