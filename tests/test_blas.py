"""``rubdiag.pin_blas_kernels()`` pins OpenBLAS's kernels, so that a run's bits do not depend
on the CPU; the command line and a dataset's local workers call it, ``import rubdiag`` does not.

Each case runs in a fresh interpreter: OpenBLAS reads its kernel choice once, when loaded.
That the pinned kernels give the same bits on different CPUs is what
``tests/simulation/test_presplit_reference.py`` checks (its reference was made on another CPU).
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
OPENBLAS_OWN = ("import json, numpy, threadpoolctl; print(json.dumps("
                "[i['architecture'] for i in threadpoolctl.threadpool_info()]))")


def _run(code: str, **env: str) -> subprocess.CompletedProcess:
    environ = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"} | env
    return subprocess.run([sys.executable, "-c", code], env=environ, capture_output=True,
                          text=True, check=True)


def _fresh(code: str, **env: str):
    return json.loads(_run(code, **env).stdout.splitlines()[-1])


def test_a_library_user_who_calls_it_first_runs_the_pinned_kernels_and_children_inherit_them():
    assert _fresh(f"import rubdiag; rubdiag.pin_blas_kernels(); import numpy, scipy.linalg; "
                  f"{REPORT}") == [KERNELS, KERNELS]


def test_it_answers_the_kernels_it_pinned():
    assert _fresh("import json, rubdiag; print(json.dumps(rubdiag.pin_blas_kernels()))") == \
        KERNELS


def test_importing_rubdiag_alone_leaves_openblas_choice_and_the_environment_alone():
    [openblas_choice] = _fresh(OPENBLAS_OWN)
    assert _fresh(f"import rubdiag, numpy; {REPORT}") == [openblas_choice, None]


def test_the_command_line_pins_them_before_numpy_loads():
    code = f"from rubdiag.cli import main; main(['cache']); import numpy; {REPORT}"
    assert _fresh(code) == [KERNELS, KERNELS]


def test_a_local_worker_started_afresh_pins_them(tmp_path):
    """A worker spawned (not forked) by a parent that pinned nothing loads the kernels."""
    code = ("import json, multiprocessing, concurrent.futures as cf\n"
            "from rubdiag.dataset._workers import start_local_worker\n"
            "from rubdiag._blas import kernels_in_use\n"
            "def report():\n"
            "    import numpy\n"
            "    return kernels_in_use()\n"
            "if __name__ == '__main__':\n"
            "    with cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context('spawn'),"
            " initializer=start_local_worker) as pool:\n"
            "        print(json.dumps(pool.submit(report).result()))\n")
    script = tmp_path / "spawn_a_worker.py"     # a spawned worker imports its parent's main
    script.write_text(code)
    environ = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    out = subprocess.run([sys.executable, str(script)], env=environ, capture_output=True,
                         text=True, check=True).stdout
    assert json.loads(out.splitlines()[-1]) == KERNELS


def test_numpy_first_keeps_openblas_choice_names_it_for_workers_and_says_so():
    done = _run(f"import numpy, rubdiag; rubdiag.pin_blas_kernels(); {REPORT}")
    chosen, environment = json.loads(done.stdout.splitlines()[-1])
    [openblas_choice] = _fresh(OPENBLAS_OWN)
    assert chosen == environment == openblas_choice
    said = "numpy was imported before rubdiag.pin_blas_kernels()" in done.stderr
    assert said == (openblas_choice != KERNELS), done.stderr


def test_a_users_choice_is_kept():
    assert _fresh(f"import rubdiag; rubdiag.pin_blas_kernels(); import numpy; {REPORT}",
                  OPENBLAS_CORETYPE="Sandybridge") == ["Sandybridge", "Sandybridge"]


def test_this_test_session_runs_the_pinned_kernels():
    # the bit-for-bit references assume it: conftest pins them before numpy is imported
    import numpy  # noqa: F401  (loads OpenBLAS)

    from rubdiag._blas import kernels_in_use

    assert kernels_in_use() == KERNELS
