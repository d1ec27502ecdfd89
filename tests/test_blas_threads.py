"""``rubdiag simulate`` tells OpenBLAS, before it loads, to start no worker threads (a single
run's BLAS work is on one thread anyway; started threads spin at load time). Each case runs
in a fresh interpreter: OpenBLAS reads the variable once, when loaded."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.skipif((os.cpu_count() or 1) < 2,
                                reason="OpenBLAS starts one thread per CPU: none to leave out")

THREADS = ("import json, threadpoolctl; print(json.dumps(sorted({i['num_threads'] for i in "
           "threadpoolctl.threadpool_info() if i['internal_api'] == 'openblas'})))")
SIMULATE = ("from rubdiag.cli import main; main(['simulate', '--case', '2', '--gap-mm', '1.9', "
            "'--speed-rpm', '5700', '--duration-s', '0.002', '--discard-s', '0', '--json'])")


#: thread counts a process may have inherited (a Dask LocalCluster sets them in its parent)
_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _fresh(code: str, **env: str):
    environ = {k: v for k, v in os.environ.items() if k not in _THREAD_VARIABLES} | env
    out = subprocess.run([sys.executable, "-c", code], env=environ, capture_output=True,
                         text=True, check=True).stdout
    return json.loads(out.splitlines()[-1])


def test_the_simulate_command_runs_without_openblas_threads():
    [default] = _fresh(f"import numpy, scipy.linalg; {THREADS}")
    assert default > 1                               # one per CPU unless told otherwise
    assert _fresh(f"{SIMULATE}; {THREADS}") == [1]


def test_a_users_setting_and_a_loaded_numpy_are_left_alone():
    assert _fresh(f"{SIMULATE}; {THREADS}", OPENBLAS_NUM_THREADS="2") == [2]
    code = ("import numpy, os; from rubdiag._blas import no_threads_in_this_process; "
            "import json; print(json.dumps([no_threads_in_this_process(), "
            "os.environ.get('OPENBLAS_NUM_THREADS')]))")
    assert _fresh(code) == [False, None]     # too late: nothing changed


def test_one_thread_finds_a_library_loaded_after_its_first_use():
    """rubdiag._blas.one_thread looks the libraries up once, and again after any new import:
    a BLAS loaded later (here scipy's, after a first use with numpy's alone) is held to one
    thread too."""
    code = ("import numpy\n"
            "from rubdiag._blas import one_thread\n"
            "with one_thread():\n"
            "    pass\n"
            "import scipy.linalg, threadpoolctl, json\n"
            "with one_thread(user_api=None):\n"
            "    inside = sorted({i['num_threads'] for i in threadpoolctl.threadpool_info()})\n"
            "blas = [i['filepath'] for i in threadpoolctl.threadpool_info()\n"
            "        if i['user_api'] == 'blas']\n"
            "print(json.dumps([inside, len(blas)]))")
    inside, n_blas = _fresh(code)
    assert inside == [1]
    assert n_blas >= 1
