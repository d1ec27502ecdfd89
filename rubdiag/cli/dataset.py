"""The ``dataset`` command: a labelled dataset from a design file."""

from __future__ import annotations

import math
import os
from pathlib import Path

from rubdiag.cli._quiet import add_quiet_option


def register(sub) -> None:
    p = sub.add_parser(
        "dataset", aliases=["generate"],     # the Python word: rubdiag.generate
        help="simulate a design of runs into a labelled feature dataset",
        description="Simulate every run of a design (TOML: [base], [sampling], [factors], "
        "[labels]), label it from what it did (rub, rub_state, severity) and write one row "
        "of features per run into DIR/features/ (parquet chunks, each written atomically). "
        "A run is stored as soon as it finishes, before the progress counts it: killed "
        "at any moment, the same command resumes. It also moves unreadable chunks into "
        "DIR/broken/ and runs their runs again. See the documentation, 'Labelled datasets'.")
    p.add_argument("design", type=Path, help="design TOML file")
    p.add_argument("--out", type=Path,
                   help="dataset folder (new, empty, or this design's to resume)")
    p.add_argument("--dry-run", action="store_true",
                   help="print the run count, an example run and an ETA from simulating the "
                   "first quarter of the example; write nothing")
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

    _check_options(args)
    if args.dry_run:
        return _dry_run(args, input_file(args.design, None, "a design TOML file"))
    from rubdiag.dataset import Design, generate
    from rubdiag.dataset._store import DatasetFolder

    design = Design.from_toml(input_file(args.design, None, "a design TOML file"))
    DatasetFolder(args.out).check_writable(design.to_toml())
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


#: the share of the example run that the dry run simulates for its ETA
CALIBRATION_SHARE = 0.25


def _dry_run(args, path: Path) -> int:
    """The run count, the example and an ETA (module help). The ETA's calibration simulates
    the example's first :data:`CALIBRATION_SHARE` in a process of its own while this one
    expands the design, and scales its CPU time to the whole run."""
    from collections import Counter

    from rubdiag.dataset._design import Design, describe_point

    design = Design.from_toml(path)
    if args.out is not None:
        from rubdiag.dataset._store import DatasetFolder

        DatasetFolder(args.out).check_writable(design.to_toml())
    with _Calibration(design) as calibration:
        runs = design.runs(jobs=args.jobs or (os.cpu_count() or 1))
        example = runs[0]
        if args.out is not None:
            from rubdiag.dataset import pending_runs

            todo = pending_runs(design, args.out, args.retry_failed, runs)
        else:
            todo = runs
        print(f"{design.method}: {design.n} design points x {design.replicates} replicate(s) "
              f"= {len(runs)} runs; {len(todo)} to run"
              + (f" ({len(runs) - len(todo)} stored in {args.out})" if args.out else ""))
        unreadable = DatasetFolder(args.out).unreadable() if args.out is not None else []
        if unreadable:
            print(f"unreadable, to be moved into {args.out / 'broken'} (their runs are counted "
                  f"to run): {', '.join(str(exc.path) for exc in unreadable)}")
        if "fault" in example.point:
            from rubdiag.dataset._fault_levels import FAULT_LEVELS

            counts = Counter(item.point["fault"] for item in runs)
            print("runs per fault level: " + ", ".join(f"{k} {counts[k]}"
                                                       for k in FAULT_LEVELS if k in counts))
        point = describe_point(example.point)
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
        status, simulated_s, per_run_s = calibration.result()
    if status != "ok":
        print(f"calibration: the example's first {simulated_s:.3g} s: {status}; no ETA")
        return 0
    workers = min(args.dask_workers or args.jobs or (os.cpu_count() or 1), len(todo))
    where = f"{workers} workers" if args.scheduler is None else "the cluster (1 worker each)"
    print(f"calibration: the example's first {simulated_s:.3g} s simulated, {per_run_s:.1f} s "
          f"of CPU per run scaled from it; ETA for {len(todo)} runs on {where}: "
          f"{_duration(per_run_s * len(todo) / workers)} (runs that rub take longer than runs "
          "that do not)")
    return 0


class _Calibration:
    """:func:`_calibrate` of ``design``'s first run (made there: :meth:`Design.design_run`)
    in a process of its own, started at once (a context manager): :meth:`result` waits for
    it; leaving the context ends the process if it is still running (an error, or nothing
    to run)."""

    def __init__(self, design):
        import multiprocessing

        self._receive, send = multiprocessing.Pipe(duplex=False)
        self._process = multiprocessing.Process(target=_calibration_process,
                                                args=(design, CALIBRATION_SHARE, send),
                                                daemon=True)
        self._process.start()
        send.close()            # the child's end: recv() sees its exit

    def __enter__(self) -> _Calibration:
        return self

    def __exit__(self, *exc) -> None:
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()

    def result(self) -> tuple[str, float, float]:
        try:
            return self._receive.recv()
        except EOFError:
            return f"error (the process ended with code {self._process.exitcode})", 0.0, 0.0


def _calibration_process(design, share: float, send) -> None:
    from rubdiag.dataset._workers import start_local_worker

    start_local_worker()
    try:
        run = design.design_run(0).run
    except ValueError as exc:       # the expansion names it
        send.send((f"error ({exc})", 0.0, 0.0))
        return
    send.send(_calibrate(run, share))


def _calibrate(run, share: float) -> tuple[str, float, float]:
    """A whole run's CPU time (s) estimated from simulating the first ``share`` of ``run``:
    ``(status, simulated s, estimate)``, the status as a dataset row's (``ok``, ``diverged``
    or ``error …``). The share is simulated twice: the first time loads what a worker loads
    once (the compiled kernels, the rig's models); of the second, the set-up counts once and
    the time integration is scaled to the whole run."""
    import dataclasses
    import time
    import warnings

    from rubdiag.simulation import GapRampInWindow, SimulationDiverged, simulate

    def first(duration: float):
        with warnings.catch_warnings():     # a shorter window: the gap ramp may reach into it
            warnings.simplefilter("ignore", GapRampInWindow)
            return dataclasses.replace(run, duration_s=duration,
                                       discard_s=min(run.discard_s, 0.5 * duration),
                                       gap_ramp_s=min(run.gap_ramp_s, duration))

    duration = share * run.duration_s
    try:
        simulate(first(duration))
        cpu, wall = time.process_time(), time.perf_counter()
        result = simulate(first(duration))
    except SimulationDiverged:
        return "diverged", duration, math.nan
    except Exception as exc:        # a failed run is data, as in a dataset row
        return f"error ({type(exc).__name__}: {exc})".splitlines()[0], duration, math.nan
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    kernel = result.system.extra["kernel_seconds"] * cpu / wall     # its wall time as CPU
    return "ok", duration, cpu + kernel * (1.0 / share - 1.0)


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
