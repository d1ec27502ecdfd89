"""The multi-fault workflow's three costs in one run: expanding the shipped designs, a fault
design's runs level by level beside a rub design's, and predicting many files.

Usage::

    .venv/bin/python benchmarks/bench_multifault.py [--per-level 4] [--files 120] [--repeat 3]

Prints, in order:

1. the dry run of every shipped design (``rubdiag dataset D --dry-run --jobs 2`` as a fresh
   process, median of ``--repeat``), with an empty rubdiag cache (cold) and with one the
   same command filled (warm): :func:`bench_design_expansion.dry_run_seconds`;
2. the median worker time per run of each level of ``faults_journal.toml`` beside the rub
   design's runs made as long (:func:`bench_fault_levels.level_seconds`, ``--per-level``
   runs a level on 2 workers);
3. ``rubdiag predict MODEL DIR --speeds speeds.csv --out table.csv`` on ``--files``
   one-second records (:func:`bench_predict_files.predict_files_seconds`).

The goals each number is held to are printed beside it. ``benchmarks/README.md`` keeps the
latest figures.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
from pathlib import Path

from bench_design_expansion import DESIGNS, dry_run_seconds
from bench_fault_levels import level_seconds
from bench_predict_files import predict_files_seconds

#: the goals: a dry run (s), a fault level against the rub design, 120 files (s)
DRY_RUN_GOAL_S = 5.0
LEVEL_GOAL = 1.5
PREDICT_GOAL_S = 15.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-level", type=int, default=4, help="runs per fault level")
    ap.add_argument("--files", type=int, default=120, help="one-second records to predict")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each command")
    args = ap.parse_args()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=Path(__file__).parent).stdout.strip()
    print(f"bench_multifault: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, "
          f"commit {commit}, {platform.machine()}, {os.cpu_count()} cores, load "
          f"{os.getloadavg()[0]:.1f}\n")

    print(f"1. dry run of each shipped design (s; goal < {DRY_RUN_GOAL_S:g} s cold)\n")
    print("| design | cold cache | warm cache |")
    print("|---|---|---|")
    for design in sorted(DESIGNS.glob("*.toml")):
        cold = statistics.median(dry_run_seconds(design, cold=True)
                                 for _ in range(args.repeat))
        warm = statistics.median(dry_run_seconds(design, cold=False)
                                 for _ in range(args.repeat))
        print(f"| {design.name} | {cold:.1f} | {warm:.1f} |", flush=True)

    print(f"\n2. median worker time per run, faults_journal levels against the rub design "
          f"(goal: every level <= {LEVEL_GOAL:g}x), load {os.getloadavg()[0]:.1f}\n")
    print("| level | runs | s per run | x rub design |")
    print("|---|---|---|---|")
    for level, m in level_seconds(args.per_level, jobs=2).items():
        print(f"| {level} | {m['runs']} | {m['median_s']:.2f} | {m['ratio']:.2f} |",
              flush=True)

    seconds = predict_files_seconds(args.files, args.repeat)
    print(f"\n3. rubdiag predict on {args.files} one-second files with known speeds: "
          f"{seconds:.1f} s (goal <= {PREDICT_GOAL_S:g} s), load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
