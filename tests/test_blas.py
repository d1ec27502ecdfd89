"""``import rubdiag`` pins OpenBLAS's kernels, so that a run's bits do not depend on the CPU.

Each case runs in a fresh interpreter: OpenBLAS reads its kernel choice once, when loaded.
That the pinned kernels give the same bits on different CPUs is what
``tests/simulate/test_presplit_reference.py`` checks (its reference was made on another CPU).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from rubdiag._blas import KERNELS, _has_avx2

pytestmark = pytest.mark.skipif(not _has_avx2(), reason="the pin applies to x86-64 with AVX2")

REPORT = ("import json, os; from rubdiag._blas import kernels_in_use; "
          "print(json.dumps([kernels_in_use(), os.environ.get('OPENBLAS_CORETYPE')]))")


def _fresh(code: str, **env: str):
    environ = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"} | env
    out = subprocess.run([sys.executable, "-c", code], env=environ,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.splitlines()[-1])


def test_rubdiag_first_runs_the_pinned_kernels_and_children_inherit_them():
    assert _fresh(f"import rubdiag, numpy, scipy.linalg; {REPORT}") == [KERNELS, KERNELS]


def test_numpy_first_keeps_openblas_choice_and_names_it_for_workers():
    chosen, environment = _fresh(f"import numpy, rubdiag; {REPORT}")
    [openblas_choice] = _fresh("import json, numpy, threadpoolctl; print(json.dumps("
                               "[i['architecture'] for i in threadpoolctl.threadpool_info()]))")
    assert chosen == environment == openblas_choice


def test_a_users_choice_is_kept():
    assert _fresh(f"import rubdiag, numpy; {REPORT}", OPENBLAS_CORETYPE="Sandybridge") == \
        ["Sandybridge", "Sandybridge"]


def test_this_test_session_runs_the_pinned_kernels():
    # the bit-for-bit references assume it: conftest imports rubdiag before numpy
    import numpy  # noqa: F401  (loads OpenBLAS)

    from rubdiag._blas import kernels_in_use

    assert kernels_in_use() == KERNELS
