"""What importing and using the signal layer loads: no numerical library on ``import rubdiag``,
and neither the simulator nor Numba for the features of a measured signal."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path


def _run(code: str) -> str:
    """Standard output of ``python -c code`` in a fresh interpreter (fails on an error)."""
    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_import_rubdiag_stays_light():
    lazy = ("import sys, rubdiag; "
            "print('numpy' in sys.modules, 'signal_features' in rubdiag.__all__)")
    assert _run(lazy).split() == ["False", "True"]
    code = (
        "import sys, rubdiag; assert callable(rubdiag.signal_features.__call__); "
        "print('numpy' in sys.modules)"
    )
    assert _run(code).strip() == "True"


def test_features_of_an_array_load_no_simulator():
    _run(
        "import sys, numpy, rubdiag; "
        "rubdiag.signal_features(numpy.random.rand(2, 5000), fs=5000, speed_rpm=1500); "
        "assert 'numba' not in sys.modules and 'rubdiag.simulation' not in sys.modules, "
        "sorted(m for m in sys.modules if m.startswith(('numba', 'rubdiag.')))"
    )
