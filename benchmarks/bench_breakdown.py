"""Where a step of the full model's kernel spends its time.

Runs the study's rubbing cells (case 1 and case 2, g0 = 1.9 mm: serious) through
``rubdiag.simulation.simulate`` with the kernel's cycle counters on
(``Recording(profile=True)``: the same bits, one counter read per section), and
prints, per case, the kernel's µs per step and each section's share:

rhs      right-hand side of the increment equation (force, M v, K q, Bᵀp)
solve    the sparse triangular solves with K_eff
contact  contact predictor, the contact Newton solve, the abrupt-closing check
update   accept: dq += S Δp, M dq and K dq in one pass, the new state
ledger   energy ledger, episodes and totals, committing the contact state
output   step-size control and the recorded samples

Cycles become seconds through the kernel's own wall time (``perf_counter`` around each
kernel call): a section's µs per step = its share of the counted cycles × the kernel's wall
time per step. Steps are all attempted steps (accepted and rejected). The same cell is also
run without counters: the difference is the counters' cost.

Usage::

    .venv/bin/python benchmarks/bench_breakdown.py [--duration 0.6] [--repeat 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import statistics
import time
from unittest import mock

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np

from rubdiag._kernels.newmark import PROFILE_SECTIONS
from rubdiag.simulation import Run, simulate, simulate_system
from rubdiag.simulation import _simulation as simulation_module


def profiled_system(system, elements, grid, outputs, **options):
    """``simulate_system`` with the kernel's cycle counters on."""
    return simulate_system(system, elements, grid, dataclasses.replace(outputs, profile=True),
                           **options)


def run_once(run: Run, profile: bool):
    """One simulation; the SystemResult. Profiling goes through ``simulate`` by handing it
    :func:`profiled_system` (simulate has no option for it)."""
    if not profile:
        return simulate(run).system
    with mock.patch.object(simulation_module, "simulate_system", profiled_system):
        return simulate(run).system


def breakdown(system) -> dict:
    steps = system.n_steps + system.n_rejected_newton + system.n_rejected_abrupt
    cycles = system.extra["profile_cycles"]
    total = sum(cycles.values())
    us_step = 1e6 * system.extra["kernel_seconds"] / steps
    out = {"us_step": us_step, "steps": steps, "accepted": system.n_steps,
           "newton_per_step": system.newton_iterations / steps,
           "ghz": total / system.extra["kernel_seconds"] / 1e9}
    for name in PROFILE_SECTIONS:
        out[name] = us_step * cycles[name] / total
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.6, help="simulated time (s)")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"bench_breakdown: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
          f"{platform.processor() or platform.machine()}; median of {args.repeat}; "
          f"{args.duration:g} s simulated per run (gap ramp 0.1 s, then rub)\n")
    header = "| case | µs/step | " + " | ".join(PROFILE_SECTIONS) + \
        " | steps | Newton its/step | µs/step unprofiled |"
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    for case in (1, 2):
        run = Run.paper_case(case, 1.9, duration_s=args.duration, discard_s=0.1)
        run_once(run, True)                                    # compile, warm caches
        rows = [breakdown(run_once(run, True)) for _ in range(args.repeat)]
        plain = [run_once(run, False) for _ in range(args.repeat)]
        med = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
        plain_us = statistics.median(
            1e6 * s.extra["kernel_seconds"]
            / (s.n_steps + s.n_rejected_newton + s.n_rejected_abrupt) for s in plain)
        same = all(np.array_equal(s.q, plain[0].q) for s in plain)
        cells = " | ".join(f"{med[k]:.2f} ({100 * med[k] / med['us_step']:.0f} %)"
                           for k in PROFILE_SECTIONS)
        print(f"| {case} serious | {med['us_step']:.2f} | {cells} | {med['steps']:.0f} | "
              f"{med['newton_per_step']:.2f} | {plain_us:.2f} |")
        if not same:
            print("  (unprofiled repeats differ: not deterministic?)")


if __name__ == "__main__":
    main()
