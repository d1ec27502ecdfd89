"""Benchmark of the main job: `rubdiag table2` (four full-length cases, features, figures).

Usage::

    .venv/bin/python benchmarks/bench_table2.py [--repeat 3] [--jobs 2]

Warms the Numba cache with a short run, then reproduces Table 2 from scratch (fresh output
folder, nothing reused) ``--repeat`` times and prints the median wall time of the whole
reproduction and of its stages, plus the kernel's µs per step on the real 412-DOF paper rig
in each case (from the runs' own timers).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=None)
    args = ap.parse_args()

    from rubdiag.paper import table2
    from rubdiag.simulate import Run, simulate

    simulate(Run.paper_case(1, 2.3, duration_s=0.01, discard_s=0.0))   # warm the cache
    totals, per_step = [], {}
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as out:
            start = time.perf_counter()
            table = table2(out, jobs=args.jobs, log=lambda message: None)
            totals.append(time.perf_counter() - start)
        for stem, result in table.attrs["results"].items():
            extra = result.system.extra
            per_step.setdefault(stem, []).append(
                1e6 * extra["kernel_seconds"] / result.system.n_steps)
    print(f"rubdiag table2 (4 cases x 2.3 s, features, figures): median "
          f"{statistics.median(totals):.1f} s over {args.repeat} runs "
          f"(min {min(totals):.1f}, max {max(totals):.1f})")
    for stem, values in per_step.items():
        print(f"  {stem:14s} kernel {statistics.median(values):5.1f} µs/step (412 DOF)")


if __name__ == "__main__":
    main()
