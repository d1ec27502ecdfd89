"""Benchmark of the main job: `rubdiag table2` (four full-length cases, features, figures).

Usage::

    .venv/bin/python benchmarks/bench_table2.py [--repeat 3] [--stage-repeat 5] [--jobs 2]

Warms the Numba cache with a short run, then reproduces Table 2 from scratch (fresh output
folder, nothing reused) ``--repeat`` times and prints the median wall time of the whole
reproduction, plus the kernel's µs per step on the real 412-DOF paper rig in each case (from
the runs' own timers). Then it times the features-and-figures stage alone — everything
``table2`` does after the four runs are in memory: features, table files, Figs. 5-10 — by
reproducing ``--stage-repeat`` more times in the last folder (the saved runs are reused, so
only the stage is left to do) and prints its median.
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import tempfile
import time
import warnings


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="reproductions from scratch")
    ap.add_argument("--stage-repeat", type=int, default=5,
                    help="extra reproductions reusing the runs, for the stage time")
    ap.add_argument("--jobs", type=int, default=None)
    args = ap.parse_args()

    from rubdiag.simulation import Run, simulate

    module = importlib.import_module("rubdiag.paper._table2")   # the package exports table2()
    with warnings.catch_warnings():      # a 0.01-s run is all gap ramp: said, and known
        warnings.simplefilter("ignore")
        simulate(Run.paper_case(1, 2.3, duration_s=0.01, discard_s=0.0))   # warm the cache
    runs_s = []
    reproduce = module.reproduce

    def timed_reproduce(*a, **k):        # the runs (simulated or reused); the rest is the stage
        start = time.perf_counter()
        try:
            return reproduce(*a, **k)
        finally:
            runs_s.append(time.perf_counter() - start)

    module.reproduce = timed_reproduce
    totals, stages, per_step = [], [], {}
    with tempfile.TemporaryDirectory() as root:
        for i in range(args.repeat):
            start = time.perf_counter()
            table = module.table2(f"{root}/{i}", jobs=args.jobs, log=lambda message: None)
            totals.append(time.perf_counter() - start)
            stages.append(totals[-1] - runs_s[-1])
            for stem, result in table.attrs["results"].items():
                extra = result.system.extra
                per_step.setdefault(stem, []).append(
                    1e6 * extra["kernel_seconds"] / result.system.n_steps)
        reused = []
        for _ in range(args.stage_repeat):
            start = time.perf_counter()
            module.table2(f"{root}/{args.repeat - 1}", jobs=args.jobs, log=lambda message: None)
            reused.append(time.perf_counter() - start - runs_s[-1])
    module.reproduce = reproduce
    print(f"rubdiag table2 (4 cases x 2.3 s, features, figures): median "
          f"{statistics.median(totals):.1f} s over {args.repeat} runs "
          f"(min {min(totals):.1f}, max {max(totals):.1f})")
    for stem, values in per_step.items():
        print(f"  {stem:14s} kernel {statistics.median(values):5.1f} µs/step (412 DOF)")
    print(f"features-and-figures stage: median {statistics.median(reused):.2f} s over "
          f"{len(reused)} runs (min {min(reused):.2f}, max {max(reused):.2f}); in the "
          f"reproductions from scratch: {', '.join(f'{s:.2f}' for s in stages)} s")


if __name__ == "__main__":
    main()
