"""The kernels run as plain Python (``NUMBA_DISABLE_JIT=1``) to the bits of the compiled
kernels: the same source on the same arrays. ``make test-nojit`` runs the kernel tests that
way (and their coverage is measured so); this checks that what those tests run is what the
compiled kernels compute."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

HERE = Path(__file__).resolve().parent
#: a short rub of the kernels' test system: both contacts closing, sticking and sliding,
#: a stiff contact (3e8 N/m) halving the step and growing it again (0.012 s: 1296 steps,
#: a few seconds as Python)
RUN = "rub_run(mu=0.3, k_n=3e8, duration=0.012)"
DIGEST = f"""
import dataclasses, hashlib, sys
import numpy as np
sys.path[:0] = [{str(HERE)!r}, {str(HERE.parent)!r}]
from conftest import rub_run
_, result = {RUN}
digest = hashlib.sha256()
def add(name, value):
    if dataclasses.is_dataclass(value):
        for field in dataclasses.fields(value):
            add(name + "." + field.name, getattr(value, field.name))
    elif isinstance(value, np.ndarray):
        digest.update(name.encode() + np.ascontiguousarray(value).tobytes())
    elif isinstance(value, (int, float)):
        digest.update(name.encode() + repr(value).encode())
add("result", result)       # every array and number (not the wall times in ``extra``)
rejected = result.n_rejected_newton + result.n_rejected_abrupt
print(result.n_steps, rejected, sorted(set(result.contact_status.ravel().tolist())))
print(digest.hexdigest())
"""


def _digest(disable_jit: bool) -> list[str]:
    env = os.environ | {"NUMBA_DISABLE_JIT": "1" if disable_jit else "0"}
    out = subprocess.run([sys.executable, "-W", "ignore::RuntimeWarning", "-c", DIGEST],
                         env=env, capture_output=True, text=True, check=True).stdout
    return out.splitlines()[-2:]


@pytest.mark.skipif(numba.config.DISABLE_JIT, reason="compares with the compiled kernels")
def test_kernels_as_python_give_the_compiled_bits():
    compiled = _digest(disable_jit=False)
    _, rejected, statuses = compiled[0].split(" ", 2)
    # the run reaches what the kernel tests need: rejections, both engaged statuses
    assert int(rejected) > 0 and statuses == "[1, 2, 3]", compiled[0]
    assert _digest(disable_jit=True) == compiled
