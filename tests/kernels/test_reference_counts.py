"""The kernel's per-step parts do no reference counting (rubdiag._kernels.newmark's docstring).

Numba reference-counts an array argument with two atomic operations per call unless it can
prove them unneeded; the parts are written so that it can, and that was worth 0.3-1.0 µs per
step. Nothing else notices if a change brings the counting back, so this compiles the kernel
afresh (a cached kernel has no IR to inspect) in a fresh interpreter and counts the calls to
``NRT_incref`` in each part's LLVM IR.

The count depends on the CPU LLVM compiles for: its inliner decides per target what it
merges, and Numba prunes the counting only where it sees both ends. On AMD znver3 and znver4
targets some parts keep increfs (before the element seam five parts, 2026-11-25: 11.05 µs per
step compiled for the znver4, 11.06 compiled for Haswell, ``benchmarks/bench_kernel.py
--repeat 5``; behind the seam ``_rhs_general`` 11 and ``_energy_ledger`` 15, Numba 0.68.1).
So the guard compiles for one stated target, :data:`TARGET_CPU`: what it catches is a change
of the code, the same on every machine.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numba
import pytest

pytestmark = pytest.mark.skipif(numba.config.DISABLE_JIT, reason="counts compiled code: none "
                                "runs under NUMBA_DISABLE_JIT")

#: called at every step (or every trial step): no reference counting at all (the parts
#: inlined into their callers, such as ``_add_force``, are counted there)
PER_STEP = ("rhs_average", "rhs_general", "load_increment", "_clock", "_element_inputs",
            "level_needed", "mk_products", "mk_dense", "matvec_t", "dissipation",
            "energy_ledger", "log_episodes", "commit_elements", "advance",
            "_count_iterations", "_lap", "logs_full", "change_level", "force_work",
            # a sensor stream records at every step (12 increfs: 0.15-0.25 µs per step)
            "record_sensors",
            "load_factors", "csr_matvec", "lu_solve",
            # the long steps' parts called at every step
            "step_level", "may_lengthen", "interpolate_sensors", "error_wanted",
            "error_level", "reject",
            # the seam: each kind's law and books on its elements, per Newton iteration
            "element_laws", "element_books")
#: the CPU the guard compiles for (NUMBA_CPU_NAME): one whose inliner lets Numba prune
#: every count in the per-step parts, as on the Intel machines the kernel was tuned on
TARGET_CPU = "haswell"
#: the controller unpacks its bundles once per call (2026-11-24: 171 increfs in its IR, one
#: more with the speed profile's knots; 174 since the load's terms come in groups by order
#: and law, three more arrays in the load's bundle; 132 behind the element seam, whose
#: records replace a dozen arrays)
#: 121 once the sensor recording counted nothing (2026-11-27); 134 with the long steps: their
#: error estimate is called in a branch, on long steps and on those that may lengthen only,
#: and its arrays are counted there
CONTROLLER_MAX = 134
#: the element solve counts its arguments once per call (a trial step): 17 on 2026-11-25 (the
#: contact solve before the seam: 28). Each kind's laws run in a loop of their own with the
#: law inlined (``element_laws``, counted above); a branch over kinds per element brought
#: 9 increfs per element and Newton iteration here (0.25-0.3 µs per step in rub)
SOLVE_MAX = 17

COUNT = """
import json
import numpy as np
from rubdiag._kernels import (annular_contact, element_solve, elements, increment, ledger,
                              load, newmark, point_contact, products, recording, sparse_lu,
                              step_control)
from rubdiag.simulation import (AnnularContact, HarmonicForce, LinearSystem, PointContact,
                                Solver, TimeGrid, simulate_system)

M, K = np.eye(2), np.diag([100.0, 400.0])
c = [PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=1e-3, k_n=1e5,
                  mu=0.3),
     AnnularContact(dof_a=(0, 1), clearance=2e-3, radius=0.01, k_n=1e5)]
for solver in ("sparse", "dense"):   # both linear paths compiled
    simulate_system(LinearSystem(M=M, C=0.01 * K, K=K, force=HarmonicForce([0], [10.0], 3.0)),
                    c, TimeGrid(duration=0.05, dt=1e-3), solver=Solver(linear_solver=solver))
counts = {}
parts = (newmark, increment, products, step_control, ledger, recording, load, sparse_lu,
         element_solve, elements)
for prefix, module in ([("", m) for m in parts] + [("point_contact.", point_contact),
                                                   ("annular_contact.", annular_contact)]):
    for name in dir(module):
        f = getattr(module, name)
        if hasattr(f, "inspect_llvm") and f.signatures:
            ir = f.inspect_llvm().values()
            counts[prefix + name] = sum(text.count("call void @NRT_incref") for text in ir)
print(json.dumps(counts))
"""


def test_per_step_parts_do_no_reference_counting(tmp_path):
    env = os.environ | {"NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_CPU_NAME": TARGET_CPU}
    out = subprocess.run([sys.executable, "-c", COUNT], env=env, capture_output=True,
                         text=True, check=True).stdout
    counts = json.loads(out.splitlines()[-1])
    assert set(PER_STEP) <= set(counts), set(PER_STEP) - set(counts)
    counted = {name: counts[name] for name in PER_STEP if counts[name]}
    assert not counted, f"reference counting in per-step parts: {counted}"
    assert 0 < counts["newmark_contact"] <= CONTROLLER_MAX
    assert counts["solve_elements"] <= SOLVE_MAX
    inlined = {"local_coords", "add_bt_p", "point_contact.law", "annular_contact.law",
               "_point_laws", "_annular_laws", "_point_books", "_annular_books",
               "_crack_laws", "_pedestal_laws"}
    assert not inlined & set(counts), "the seam's per-element parts must be inlined"
