"""The ``dataset`` command: a labelled dataset from a design file."""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

from rubdiag.cli._quiet import add_quiet_option


def register(sub) -> None:
    p = sub.add_parser(
        "dataset", help="simulate a design of runs into a labelled feature dataset",
        description="Simulate every run of a design (TOML: [base], [sampling], [factors], "
        "[labels]), label it from what it did (rub, rub_state, severity) and write one row "
        "of features per run into DIR/features/ (parquet chunks, each written atomically). "
        "A run is stored as soon as it finishes, before the progress counts it: killed "
        "at any moment, the same command resumes. It also moves unreadable chunks into "
        "DIR/broken/ and runs their runs again. See README, 'Labelled datasets'.")
    p.add_argument("design", type=Path, help="design TOML file")
    p.add_argument("--out", type=Path,
                   help="dataset folder (new, empty, or this design's to resume)")
    p.add_argument("--dry-run", action="store_true",
                   help="print the run count, an example run and an ETA from one calibration "
                   "run; write nothing")
    p.add_argument("--jobs", type=int, help="local worker processes (default: all cores)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="send the runs to this dask.distributed scheduler (rubdiag[dask])")
    p.add_argument("--dask-workers", type=int, metavar="N",
                   help="start a local Dask cluster of N worker processes (rubdiag[dask])")
    p.add_argument("--run-timeout", type=float, metavar="S",
                   help="wall-time limit of one run (s): a run over it becomes a 'timeout' row")
    p.add_argument("--retry-failed", action="store_true",
                   help="run again the runs stored with a failure (diverged, timeout, error)")
    p.add_argument("--waveforms", action="store_true",
                   help="also store each run's measured channels (float32, compressed; "
                   "rubdiag.dataset.load_waveforms reads them)")
    add_quiet_option(p, "--no-progress", help="no progress on stderr (on a terminal a bar "
                     "with an ETA; elsewhere, for logs, a line per stored run)")
    p.set_defaults(func=_dataset)


def _dataset(args) -> int:
    from rubdiag.cli._paths import input_file
    from rubdiag.dataset import Design, generate
    from rubdiag.dataset.store import DatasetFolder

    _check_options(args)
    design = Design.from_toml(input_file(args.design, None, "a design TOML file"))
    if args.out is not None:
        DatasetFolder(args.out).check_writable(design.to_toml())
    if args.dry_run:
        return _dry_run(design, args)
    jobs, client, cluster = _executor(args)
    try:
        summary = generate(design, args.out, jobs=jobs, client=client,
                           progress=not args.quiet, run_timeout_s=args.run_timeout,
                           retry_failed=args.retry_failed, waveforms=args.waveforms)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    print(f"{args.out}: {summary['total']} runs, {summary['stored_before']} already stored, "
          f"{summary['ok']} ok and {summary['failed']} failed now "
          f"({summary['wall_s']:.1f} s); rubdiag.dataset.load({str(args.out)!r}) reads them")
    return 0


def _check_options(args) -> None:
    if args.out is None and not args.dry_run:
        raise ValueError("--out is required (the dataset folder), except with --dry-run")
    given = [name for name, value in (("--jobs", args.jobs), ("--scheduler", args.scheduler),
                                      ("--dask-workers", args.dask_workers))
             if value is not None]
    if len(given) > 1:
        raise ValueError(f"{given[0]} and {given[1]} exclude each other (allowed: one of "
                         "them)")
    for name, value in (("--jobs", args.jobs), ("--dask-workers", args.dask_workers)):
        if value is not None and value < 1:
            raise ValueError(f"{name} = {value} is out of range (allowed: >= 1)")
    if args.run_timeout is not None and not (args.run_timeout > 0
                                             and math.isfinite(args.run_timeout)):
        raise ValueError(f"--run-timeout = {args.run_timeout:g} is out of range (allowed: "
                         "> 0 s)")
    if args.scheduler is not None or args.dask_workers is not None:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise ValueError("--scheduler and --dask-workers need dask.distributed: pip "
                             "install 'rubdiag[dask]'") from None


def _executor(args):
    """(jobs, client, cluster) for generate()."""
    if args.scheduler is None and args.dask_workers is None:
        return args.jobs, None, None
    from distributed import Client, LocalCluster

    if args.scheduler is not None:
        try:
            return None, Client(args.scheduler, timeout="10s"), None
        except OSError as exc:
            raise ValueError(f"--scheduler {args.scheduler}: cannot connect ({exc})") from None
    cluster = LocalCluster(n_workers=args.dask_workers, threads_per_worker=1,
                           processes=True, dashboard_address=None)
    return None, Client(cluster), cluster


def _dry_run(design, args) -> int:
    from collections import Counter

    from rubdiag.dataset import pending_runs
    from rubdiag.dataset.rows import make_row
    from rubdiag.dataset.store import DatasetFolder

    runs = design.runs()
    todo = pending_runs(design, args.out, args.retry_failed) if args.out is not None else runs
    print(f"{design.method}: {design.n} design points x {design.replicates} replicate(s) = "
          f"{len(runs)} runs; {len(todo)} to run"
          + (f" ({len(runs) - len(todo)} stored in {args.out})" if args.out else ""))
    unreadable = DatasetFolder(args.out).unreadable() if args.out is not None else []
    if unreadable:
        print(f"unreadable, to be moved into {args.out / 'broken'} (their runs are counted to "
              f"run): {', '.join(str(exc.path) for exc in unreadable)}")
    if runs and "fault" in runs[0].point:
        from rubdiag.dataset.fault_levels import FAULT_LEVELS

        counts = Counter(item.point["fault"] for item in runs)
        print("runs per fault level: " + ", ".join(f"{k} {counts[k]}" for k in FAULT_LEVELS
                                                   if k in counts))
    example = runs[0]
    point = ", ".join(f"{k} = {v}" if isinstance(v, str) else f"{k} = {v:.6g}"
                      for k, v in example.point.items())
    run = example.run
    law = run.contact_law
    contact = ("no contact" if law is None else f"g0 = {run.gap_m * 1e3:.4g} mm, mu = "
               f"{law.friction_coefficient:.4g}")
    print(f"example: point 0 ({point}), replicate 0 -> {run.speed_rpm:.1f} rpm, {contact}, "
          f"{run.duration_s:g} s simulated ({run.discard_s:g} s discarded), dt = "
          f"{run.dt_s:g} s, {run.model_kind} model; run_id {example.run_id}")
    if not todo:
        print("nothing to run")
        return 0
    row = make_row(example, design.labels, design.noise, args.run_timeout)
    workers = args.dask_workers or args.jobs or (os.cpu_count() or 1)
    workers = min(workers, len(todo))
    eta = row["wall_s"] * len(todo) / workers
    where = f"{workers} workers" if args.scheduler is None else "the cluster (1 worker each)"
    print(f"calibration run (the example): {row['wall_s']:.1f} s wall, status {row['status']}, "
          f"rub {row.get('rub')}; ETA for {len(todo)} runs on {where}: {_duration(eta)} "
          "(runs that rub take longer than runs that do not)", file=sys.stdout)
    return 0


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
