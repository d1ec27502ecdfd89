"""Dask rows against local rows, bit for bit: ``--checks`` designs made both ways.

Usage::

    .venv/bin/python benchmarks/bench_dask_identity.py [--checks 10] [--runs 40]
        [--duration-s 0.6] [--seed 1] [--workers 2] [--out FILE]

A check is one design (``design_toml``: ``--runs`` LHS points of the paper rig's case 2 on
the reduced model, speed 0.95–1.08 × critical, g0 0.8–3 mm, μ 0.2–0.5, so that most runs rub
and some do not; LHS seed ``--seed`` + the check's index) made by
``rubdiag.dataset.generate`` on ``--workers`` local processes and on a fresh Dask
``LocalCluster`` of ``--workers`` processes × 1 thread, each into a fresh folder. The two
datasets are compared run by run on every column but the wall times (``wall_s``,
``simulate_s``): floats by their 64 bits (NaN where NaN, -0.0 apart from 0.0), everything else
by value. A check passes when no bit differs; the script exits with status 1 when a check
fails. It prints one line per check (runs, rubbing runs, the columns compared, what differs,
both wall times) and, first, the machine, versions and the BLAS kernels of this process and
of the first cluster's workers (``rubdiag.dataset._workers.signature``).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

NOT_COMPARED = ("wall_s", "simulate_s")     # wall times: never the same twice


def design_toml(runs: int, duration_s: float, seed: int) -> str:
    """A check's design (module docstring)."""
    return f"""
[base]
rig = "paper"
duration_s = {duration_s!r}
discard_s = 0.1
reduced = true

[sampling]
method = "lhs"
n = {runs}
seed = {seed}

[factors]
case = [2]
speed_ratio = {{low = 0.95, high = 1.08}}
gap_mm = {{low = 0.8, high = 3.0}}
mu = {{low = 0.2, high = 0.5}}
"""


def bit_differences(a, b) -> tuple[list[str], set[str]]:
    """The columns and run ids where two datasets' rows differ (floats by their bits)."""
    import numpy as np

    a, b = (rows.sort_values("run_id").reset_index(drop=True) for rows in (a, b))
    if list(a["run_id"]) != list(b["run_id"]) or list(a.columns) != list(b.columns):
        return ["run_id or the column list"], set(a["run_id"]) ^ set(b["run_id"])
    columns, runs = [], set()
    for name in a.columns:
        if name in NOT_COMPARED:
            continue
        x, y = a[name].to_numpy(), b[name].to_numpy()
        if x.dtype.kind == "f" and y.dtype == x.dtype:
            differ = x.view(f"u{x.itemsize}") != y.view(f"u{y.itemsize}")
        else:
            differ = np.array([u != v and not (u != u and v != v)     # NaN == NaN here
                               for u, v in zip(x, y, strict=True)], dtype=bool)
        if differ.any():
            columns.append(name)
            runs |= set(a["run_id"][differ])
    return columns, runs


def one_check(index: int, args, root: Path) -> dict:
    import dask.distributed as dd

    from rubdiag.dataset import Design, generate, load
    from rubdiag.dataset._workers import signature

    design = Design.from_toml(design_toml(args.runs, args.duration_s, args.seed + index))
    start = time.perf_counter()
    generate(design, root / "local", jobs=args.workers, progress=False)
    local_s = time.perf_counter() - start
    environ = dict(os.environ)      # a LocalCluster leaves its workers' variables here
    try:
        start = time.perf_counter()
        with dd.LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                             dashboard_address=None) as cluster, dd.Client(cluster) as client:
            generate(design, root / "dask", client=client, progress=False)
            workers = client.run(signature)
        dask_s = time.perf_counter() - start
    finally:
        os.environ.clear()
        os.environ.update(environ)
    local, dask = load(root / "local"), load(root / "dask")
    columns, runs = bit_differences(local, dask)
    return {"seed": args.seed + index, "runs": len(local),
            "ok": int((local["status"] == "ok").sum()), "rub": int(local["rub"].sum()),
            "floats": sum(local[c].dtype.kind == "f" for c in local.columns
                          if c not in NOT_COMPARED),
            "columns": columns, "differing_runs": runs, "local_s": local_s, "dask_s": dask_s,
            "workers": workers}


def describe_machine(first: dict, here: dict) -> list[str]:
    from _threads import cpu_model  # benchmarks/ is on sys.path as a script
    from bench_dataset import git_commit

    return [f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, commit {git_commit()}, "
            f"{os.cpu_count()} CPUs ({cpu_model()}), Python {platform.python_version()}, "
            f"load average {os.getloadavg()[0]:.1f}",
            f"this process: {here}",
            *(f"worker {name}: {'the same' if sig == here else sig}"
              for name, sig in sorted(first.items()))]


def main(argv=None) -> int:
    import rubdiag

    rubdiag.pin_blas_kernels()    # first: before numpy loads OpenBLAS

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--checks", type=int, default=10)
    p.add_argument("--runs", type=int, default=40)
    p.add_argument("--duration-s", type=float, default=0.6)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", type=Path, help="also write the report to this file")
    args = p.parse_args(argv)

    from rubdiag.dataset._workers import signature

    lines, failed = [], 0
    header = ["| check (seed) | runs (ok) | rubbing | float columns | differing columns | "
              "differing runs | local (s) | Dask (s) |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for index in range(args.checks):
        with tempfile.TemporaryDirectory(prefix="dask-identity-") as tmp:
            check = one_check(index, args, Path(tmp))
        if index == 0:
            lines = [*describe_machine(check["workers"], signature()), "", *header]
            print("\n".join(lines), flush=True)
        failed += bool(check["columns"])
        row = (f"| {index + 1} ({check['seed']}) | {check['runs']} ({check['ok']}) | "
               f"{check['rub']} | {check['floats']} | {len(check['columns'])} | "
               f"{len(check['differing_runs'])} | {check['local_s']:.0f} | "
               f"{check['dask_s']:.0f} |")
        if check["columns"]:
            row += " " + ", ".join(check["columns"][:5])
        lines.append(row)
        print(row, flush=True)
    summary = (f"\n{args.checks - failed} of {args.checks} checks identical "
               f"({args.runs} runs of {args.duration_s:g} s each, {args.workers} workers)")
    lines.append(summary)
    print(summary)
    if args.out is not None:
        args.out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
