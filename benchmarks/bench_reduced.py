"""Full against reduced model: speed of the study's rubbing cells, and the reduction's cost.

For case 1 and case 2 at g0 = 1.9 mm (both rub), the default 2.3-s run through
``rubdiag.simulation.simulate``, full (412 DOF, sparse LU) and reduced (Craig–Bampton, default
cutoff or each of ``--cutoff-hz``, dense), median of ``--repeat`` runs after one warm-up run
each:

* µs per kernel step (the kernel's wall time over its attempted steps);
* simulated seconds per wall second of the whole ``simulate`` call (set-up included, the
  one-time reduction not: it is cached per process);
* the reduced kernel's cycle breakdown (``Recording(profile=True)``), as
  ``bench_breakdown.py`` prints it for the full model;
* the one-time reduction (``reduced_model`` with its cache cleared: assembly, modal
  analysis, constraint modes, projection), median of ``--repeat``.

Usage::

    .venv/bin/python benchmarks/bench_reduced.py [--repeat 3] [--duration 2.3] \
        [--cutoff-hz 2000 5000]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
from unittest import mock

from bench_breakdown import profiled_system  # benchmarks/ is on sys.path as a script

from rubdiag._kernels.newmark import PROFILE_SECTIONS
from rubdiag.model import paper_rig
from rubdiag.reduce import Reduction, _reduced
from rubdiag.reduce._spec import DEFAULT_CUTOFF_HZ
from rubdiag.simulation import Run, simulate
from rubdiag.simulation import _simulation as simulation_module


def timed(run: Run) -> dict:
    start = time.perf_counter()
    result = simulate(run)
    wall = time.perf_counter() - start
    s = result.system
    steps = s.n_steps + s.n_rejected_newton + s.n_rejected_abrupt
    return {"us_step": 1e6 * s.extra["kernel_seconds"] / steps,
            "sim_per_wall": run.duration_s / wall, "steps": steps}


def profiled(run: Run) -> dict:
    with mock.patch.object(simulation_module, "simulate_system", profiled_system):
        s = simulate(run).system
    cycles = s.extra["profile_cycles"]
    total = sum(cycles.values())
    steps = s.n_steps + s.n_rejected_newton + s.n_rejected_abrupt
    us = 1e6 * s.extra["kernel_seconds"] / steps
    return {k: us * v / total for k, v in cycles.items()}


def main() -> None:
    # the one-time reduction is timed as computed, not as read from the disk cache of
    # rig-only results (bench_process.py times both)
    os.environ["RUBDIAG_CACHE_DIR"] = ""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--duration", type=float, default=2.3)
    ap.add_argument("--cutoff-hz", type=float, nargs="+", default=[DEFAULT_CUTOFF_HZ])
    args = ap.parse_args()
    print(f"bench_reduced: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
          f"{platform.processor() or platform.machine()}; median of {args.repeat}; "
          f"{args.duration:g} s simulated per run\n")
    rig = paper_rig()
    reductions = [Reduction(c) for c in args.cutoff_hz]
    for reduction in reductions:
        costs = []
        for _ in range(args.repeat):
            _reduced._reduced_model.cache_clear()
            start = time.perf_counter()
            model = _reduced.reduced_model(rig, reduction)
            costs.append(time.perf_counter() - start)
        print(f"one-time reduction: {statistics.median(costs):.3f} s "
              f"({model.n_full} -> {model.n_reduced} coordinates, cutoff "
              f"{model.reduction.cutoff_hz:g} Hz)")
    print("\n| case | model | µs/step | simulated s / wall s | speed-up |")
    print("|---|---|---|---|---|")
    for case in (1, 2):
        full_rate = None
        for red in (None, *reductions):
            run = Run.paper_case(case, 1.9, rig=rig, duration_s=args.duration,
                                 reduction=red)
            timed(run)                                          # compile, warm caches
            rows = [timed(run) for _ in range(args.repeat)]
            us = statistics.median(r["us_step"] for r in rows)
            rate = statistics.median(r["sim_per_wall"] for r in rows)
            name = "full" if red is None else f"reduced {red.cutoff_hz:g} Hz"
            gain = "" if red is None else f"{rate / full_rate:.2f}×"
            full_rate = rate if red is None else full_rate
            print(f"| {case} serious | {name} | {us:.2f} | {rate:.2f} | {gain} |")
    for red in reductions:
        run = Run.paper_case(2, 1.9, rig=rig, duration_s=args.duration, reduction=red)
        parts = profiled(run)
        print(f"\nreduced kernel at {red.cutoff_hz:g} Hz, µs per step by section (case 2 "
              "serious, one profiled run):")
        print(" | ".join(f"{k} {parts[k]:.2f}" for k in PROFILE_SECTIONS))


if __name__ == "__main__":
    main()
