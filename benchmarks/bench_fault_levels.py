"""Worker time per run of every level of the multi-fault design, beside a rub design's.

Usage::

    .venv/bin/python benchmarks/bench_fault_levels.py [--per-level 4] [--jobs 2]

Takes the first ``--per-level`` design points of each fault level of
``data/designs/faults_journal.toml`` (journal bearings, the reduced model, 2.5-s runs, the
dataset's default long steps) and as many points again of ``data/designs/rub_lhs200.toml``
(the paper rig's rub design) made as long (its ``[base]`` given the fault design's
``duration_s``, ``discard_s`` and ``reduced``), so both simulate the same time. Every run is
made into a dataset row (:func:`rubdiag.dataset._rows.make_row`: simulate, features, labels)
on ``--jobs`` worker processes, all runs in one interleaved queue so that a change of the
machine's load hits every level alike; the worker time of a run is its row's ``wall_s``.

Prints per level the runs, the median worker time per run, its ratio to the rub design's
median, and the median steps per run; the goal is every level within 1.5x the rub design.
:func:`level_seconds` gives the same numbers to another script.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import tomllib
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
from rubdiag.dataset import Design
from rubdiag.dataset._design import DesignRun
from rubdiag.dataset._ids import point_id, run_id
from rubdiag.dataset._rows import make_row

DESIGNS = Path(__file__).resolve().parent.parent / "data" / "designs"
FAULTS = DESIGNS / "faults_journal.toml"
RUB = DESIGNS / "rub_lhs200.toml"
#: the rub design's name in the printed table
RUB_LEVEL = "rub design (paper rig)"


def _items(design: Design, points: list[dict]) -> list[DesignRun]:
    out = []
    for point in points:
        run = design.run_for(point)
        out.append(DesignRun(point, 0, run, point_id(run), run_id(run)))
    return out


def chosen_runs(per_level: int) -> dict[str, list[DesignRun]]:
    """Level -> its first ``per_level`` runs of the fault design, and the rub design's first
    ``2 * per_level`` runs as long as the fault design's (under :data:`RUB_LEVEL`)."""
    faults = Design.from_toml(FAULTS)
    by_level: dict[str, list[dict]] = {}
    for point in faults.points():
        by_level.setdefault(point["fault"], [])
        if len(by_level[point["fault"]]) < per_level:
            by_level[point["fault"]].append(point)
    data = tomllib.loads(RUB.read_text(encoding="utf-8"))
    data["base"].update(duration_s=faults.duration_s, discard_s=faults.discard_s,
                        reduced=faults.reduction is not None)
    rub = Design.from_dict(data, root=DESIGNS)
    out = {RUB_LEVEL: _items(rub, rub.points()[:2 * per_level])}
    out.update({level: _items(faults, points) for level, points in by_level.items()})
    return out


def _row(item: DesignRun) -> tuple[float, int]:
    row = make_row(item)
    return row["wall_s"], int(row.get("n_steps", -1))


def level_seconds(per_level: int = 4, jobs: int = 2) -> dict[str, dict]:
    """Level -> ``{"runs", "median_s", "ratio", "median_steps"}``: the median worker time per
    run (s) and its ratio to the rub design's (module docstring)."""
    runs = chosen_runs(per_level)
    make_row(runs[RUB_LEVEL][0])          # compile or load the kernels before forking
    queue = [(level, item) for k in range(2 * per_level) for level, items in runs.items()
             if k < len(items) for item in [items[k]]]
    with ProcessPoolExecutor(jobs, mp_context=get_context("fork")) as pool:
        results = list(pool.map(_row, [item for _, item in queue]))
    times: dict[str, list] = {}
    for (level, _), result in zip(queue, results, strict=True):
        times.setdefault(level, []).append(result)
    reference = statistics.median(t for t, _ in times[RUB_LEVEL])
    return {level: {"runs": len(values),
                    "median_s": statistics.median(t for t, _ in values),
                    "ratio": statistics.median(t for t, _ in values) / reference,
                    "median_steps": statistics.median(s for _, s in values)}
            for level, values in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-level", type=int, default=4, help="runs per fault level")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes")
    args = ap.parse_args()
    start, load = time.perf_counter(), os.getloadavg()[0]
    table = level_seconds(args.per_level, args.jobs)
    print(f"bench_fault_levels: {args.per_level} runs per level on {args.jobs} workers, "
          f"{time.perf_counter() - start:.0f} s wall, load {load:.1f} -> "
          f"{os.getloadavg()[0]:.1f}\n")
    print("| level | runs | median worker s per run | x rub design | median steps |")
    print("|---|---|---|---|---|")
    for level, m in table.items():
        print(f"| {level} | {m['runs']} | {m['median_s']:.2f} | {m['ratio']:.2f} | "
              f"{m['median_steps']:.0f} |")


if __name__ == "__main__":
    main()
