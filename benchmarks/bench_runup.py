"""Run-up speed: simulated seconds per wall second of a 6-s run-up with rub.

The issue-14 example — case 1, 600 → 2400 rpm at 300 rpm/s (6 s), g0 = 2.3 mm, which rubs
through the first critical — through ``rubdiag.simulation.simulate``, full (412 DOF) and
reduced (Craig–Bampton, 2 kHz) model, median of ``--repeat`` runs after one warm-up run
each. Also printed: the kernel's µs per step, the speed stretches (refactorisations of the
step operators) and the contact episodes.

Usage::

    .venv/bin/python benchmarks/bench_runup.py [--repeat 3] [--rate-rpm-s 300]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split

from rubdiag.reduce import Reduction
from rubdiag.runs._runup import ramp_run
from rubdiag.simulation import simulate


def timed(run) -> dict:
    start = time.perf_counter()
    result = simulate(run)
    wall = time.perf_counter() - start
    s = result.system
    steps = s.n_steps + s.n_rejected_newton + s.n_rejected_abrupt
    return {"sim_per_wall": run.duration_s / wall, "wall": wall,
            "us_step": 1e6 * s.extra["kernel_seconds"] / steps,
            "stretches": s.extra["speed_stretches"], "episodes": len(s.episodes)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rate-rpm-s", type=float, default=300.0)
    args = ap.parse_args()
    print(f"bench_runup: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
          f"{platform.processor() or platform.machine()}; median of {args.repeat}\n")
    print("| model | simulated s | wall s | simulated s per wall s | µs/step | stretches | "
          "episodes |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, reduction in (("full", None), ("reduced 2 kHz", Reduction())):
        run = ramp_run(1, 600, 2400, args.rate_rpm_s, 2.3, reduction=reduction)
        timed(run)                                  # warm-up: caches, the reduction
        rows = [timed(run) for _ in range(args.repeat)]
        med = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
        print(f"| {name} | {run.duration_s:.2f} | {med['wall']:.2f} | "
              f"{med['sim_per_wall']:.3f} | {med['us_step']:.2f} | {med['stretches']:.0f} | "
              f"{med['episodes']:.0f} |")


if __name__ == "__main__":
    main()
