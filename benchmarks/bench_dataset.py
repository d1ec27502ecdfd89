"""Benchmark of dataset generation: `rubdiag.dataset.generate` on 1 and 2 workers and on Dask.

Usage::

    .venv/bin/python benchmarks/bench_dataset.py [--runs 100] [--duration-s 2.3] [--repeat 3]
        [--skip-dask] [--reduced] [--out FILE]

A quick run: ``--runs 24 --duration-s 2.3 --reduced --repeat 1 --skip-dask`` (≈ 1.5 min).

The design is fixed here (``design_toml``): ``--runs`` LHS points (seed 1) of
``case = [1, 2]``, ``speed_ratio`` 0.9–1.1, ``gap_mm`` 1.5–4.0, ``mu`` 0.2–0.5 on the
paper rig (``--reduced``: its reduced model, ``[base] reduced = true``), so that some
runs rub and some do not; each run lasts ``--duration-s`` with the
first ``min(0.3, duration/3)`` s discarded. For a duration below 1 s the design is
``case = [2]`` only: case 1 runs at ≈ 1350–1650 rpm and its analysis window would hold
fewer than the 10 revolutions a design requires (≥ 0.45 s of window); case 2, at
≈ 5100–6300 rpm, needs ≈ 0.12 s. The shortest duration is 0.3 s (the discarded start must
cover the 0.1 s gap ramp).

Measured, after a warm-up (one short run through the whole row path in this process, so the
Numba kernels are compiled and cached on disk, and the feature code is imported):

* bare: ``simulate(item.run)`` of every run of the design, one after the other in this
  process (BLAS held to one thread, as the workers do), once; the sum;
* parts: ``make_row`` of every run of the design in this process, once, with the functions
  of :data:`PARTS` timed, each less the timed functions it calls: the set-up before the
  kernel (model and reduced model from the rig caches, start state, step operators, the
  rest of ``simulate_system``'s and ``simulate``'s set-up), the kernel, its records made a
  result, the sensor signals (anti-alias filter and decimation), noise, spectral features,
  pair features, contact statistics, labels, and the rest of the row's wall time; each
  part's median over the runs, and the median of everything but the kernel (wall − kernel:
  the goal: ≤ 0.1 s per run);
* (a) ``generate(design, tmp, jobs=1, progress=False)``;
* (b) ``generate(design, tmp, jobs=2, progress=False)`` (a fresh ProcessPoolExecutor per
  call: starting the workers is part of the cost; on Linux they are forked and inherit this
  process's loaded kernels);
* (c) a fresh ``dask.distributed.LocalCluster(n_workers=2, threads_per_worker=1,
  processes=True, dashboard_address=None)`` + ``Client``, ``generate(..., client=client)``,
  and closing both; all three parts are timed (the spawned workers import rubdiag and load
  the cached kernel: the real cost of using Dask on one machine) and shown separately.

(a), (b) and (c) each write into a fresh temporary folder, ``--repeat`` times, interleaved
(a, b, c, a, b, c, …, so that a change of the machine's load hits all three alike);
medians are reported. The script checks that the three produce the same rows. The load
average (1 min, ``os.getloadavg``) is read before and after every measurement.

Reported: runs per minute; the median time a worker spent on one run (the rows' ``wall_s``;
in (c) the first run of each spawned worker also loads the kernels); speedup a/b and a/c
and parallel efficiency = speedup / 2; the overhead of (a) over the bare simulations,
(a − bare) / bare (labels, noise, features, Parquet writing, the dataset card); and a
projection of 1,000 runs × 2.3 s on 2 cores, (b) × 1000/N × 2.3/D. The projection scales
everything with the simulated duration, fixed costs too (worker start-up, design checks,
writing), so from short runs it overstates; project from runs of D = 2.3 s.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

from _threads import cpu_model, limit_threads  # benchmarks/ is on sys.path as a script

SHORT_S = 1.0     # below this duration the design uses case 2 only (see the docstring)


def design_toml(runs: int, duration_s: float, reduced: bool = False) -> str:
    """The benchmark's design (see the module docstring)."""
    discard_s = round(min(0.3, duration_s / 3), 9)    # 0.3 / 3 is 0.0999…: round
    cases = "[1, 2]" if duration_s >= SHORT_S else "[2]"
    model = "reduced = true\n" if reduced else ""
    return f"""
[base]
rig = "paper"
{model}duration_s = {duration_s!r}
discard_s = {discard_s!r}

[sampling]
method = "lhs"
n = {runs}
seed = 1

[factors]
case = {cases}
speed_ratio = {{low = 0.9, high = 1.1}}
gap_mm = {{low = 1.5, high = 4.0}}
mu = {{low = 0.2, high = 0.5}}
"""


def git_commit() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, check=True, cwd=Path(__file__).resolve().parent)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True,
                               cwd=Path(__file__).resolve().parent).stdout.strip()
        return out.stdout.strip() + (" (modified)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def load1() -> float:
    return os.getloadavg()[0]


@dataclasses.dataclass
class Timing:
    """Wall times of one configuration and the load average around each."""

    times: list = dataclasses.field(default_factory=list)
    loads: list = dataclasses.field(default_factory=list)     # (before, after)
    parts: dict = dataclasses.field(default_factory=dict)     # name -> list of seconds
    run_s: list = dataclasses.field(default_factory=list)     # median row wall_s per call
    # (call wall - summed simulate_s) / summed simulate_s: everything but the simulations
    overhead: list = dataclasses.field(default_factory=list)

    def add(self, seconds: float, before: float, after: float, **parts) -> None:
        self.times.append(seconds)
        self.loads.append((before, after))
        for name, value in parts.items():
            self.parts.setdefault(name, []).append(value)

    @property
    def median(self) -> float:
        return statistics.median(self.times)

    def spread(self) -> str:
        if len(self.times) == 1:
            return "–"
        return f"{min(self.times):.1f}–{max(self.times):.1f}"

    def load_text(self) -> str:
        return ", ".join(f"{b:.2f}→{a:.2f}" for b, a in self.loads)


def warm_up(design) -> float:
    """One short run of the design's fastest point through the whole row path (simulate,
    labels, noise, features): compiles the kernels or loads them from the on-disk cache, and
    imports everything a row needs. Returns its wall time."""
    from rubdiag.dataset._rows import make_row

    item = max(design.runs(), key=lambda it: it.run.speed_rad_s)
    short = dataclasses.replace(item, run=dataclasses.replace(
        item.run, duration_s=0.3, discard_s=0.1, gap_ramp_s=0.1))
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = make_row(short)
    if row["status"] != "ok":
        raise SystemExit(f"warm-up run failed: {row['status']}: {row['message']}")
    return time.perf_counter() - start


def bare_simulations(design) -> tuple[float, list[float]]:
    """``simulate(item.run)`` of every run, one after the other; (sum, per run) in s."""
    from threadpoolctl import threadpool_limits

    from rubdiag.simulation import simulate

    per_run = []
    with threadpool_limits(limits=1):
        for item in design.runs():
            start = time.perf_counter()
            simulate(item.run)
            per_run.append(time.perf_counter() - start)
    return sum(per_run), per_run


#: (module, function, part): what a row's parts are timed by (:func:`part_times`)
PARTS = (
    ("rubdiag.simulation._simulation", "damped_model", "set-up: model (rig cache)"),
    ("rubdiag.reduce", "reduced_model", "set-up: reduced model (cache)"),
    ("rubdiag.simulation._simulation", "rig_system", "set-up: start state"),
    ("rubdiag.simulation._system", "level_operators", "set-up: step operators"),
    ("rubdiag.simulation._simulation", "simulate_system", "set-up: integrator, other"),
    ("rubdiag.simulation", "simulate", "set-up: simulate, other"),
    ("rubdiag.simulation._system", "_integrate", "kernel"),
    ("rubdiag.simulation._system", "_package", "kernel's records to a result"),
    ("rubdiag.simulation._simulation_result", "sensor_signals",
     "sensor signals (filter + decimation)"),
    ("rubdiag.dataset._rows", "add_noise", "noise"),
    ("rubdiag.dataset._rows", "_spectral_features", "spectral features"),
    ("rubdiag.dataset._rows", "_pair_features", "pair features"),
    ("rubdiag.dataset._rows", "_truth", "contact statistics"),
    ("rubdiag.dataset._rows", "_labels", "labels"),
)
KERNEL = "kernel"
REST = "rest (row building, BLAS limits)"
ROW = "the row (`make_row`)"


class PartClock:
    """Seconds per part of one row, on two clocks (wall: ``perf_counter``; CPU of this
    process: ``process_time``, which other jobs on a busy machine stretch less): each
    wrapped function's own time, less that of the wrapped functions it calls (the kernel is
    not counted in the ``simulate_system`` that calls it), so that the parts add up to the
    row's time."""

    def __init__(self):
        self.seconds: dict[str, tuple[float, float]] = {}     # part -> (wall, CPU)
        self._inner: list[list[float]] = []

    def wrap(self, part: str, fn):
        import functools

        @functools.wraps(fn)
        def timed(*args, **kwargs):
            self._inner.append([0.0, 0.0])
            start = (time.perf_counter(), time.process_time())
            try:
                return fn(*args, **kwargs)
            finally:
                elapsed = (time.perf_counter() - start[0], time.process_time() - start[1])
                inner = self._inner.pop()
                wall, cpu = self.seconds.get(part, (0.0, 0.0))
                self.seconds[part] = (wall + elapsed[0] - inner[0],
                                      cpu + elapsed[1] - inner[1])
                if self._inner:
                    self._inner[-1][0] += elapsed[0]
                    self._inner[-1][1] += elapsed[1]
        return timed


def part_times(design) -> dict[str, list[tuple[float, float]]]:
    """``make_row`` of every run of the design in this process, with the functions of
    :data:`PARTS` timed: ``{part: [(wall, CPU) s of each run]}``, with :data:`REST` (the
    rest of the row) and :data:`ROW` (the whole ``make_row``)."""
    import importlib
    from contextlib import ExitStack
    from unittest import mock

    from rubdiag.dataset._rows import make_row

    clock = PartClock()
    per_part: dict[str, list[tuple[float, float]]] = {part: [] for *_, part in PARTS}
    per_part[REST], per_part[ROW] = [], []
    with ExitStack() as stack, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for module, name, part in PARTS:
            owner = importlib.import_module(module)
            stack.enter_context(mock.patch.object(owner, name,
                                                  clock.wrap(part, getattr(owner, name))))
        for item in design.runs():
            clock.seconds = {}
            start = (time.perf_counter(), time.process_time())
            row = make_row(item)
            total = (time.perf_counter() - start[0], time.process_time() - start[1])
            if row["status"] != "ok":
                continue
            for *_, part in PARTS:
                per_part[part].append(clock.seconds.get(part, (0.0, 0.0)))
            per_part[REST].append(tuple(t - sum(v[i] for v in clock.seconds.values())
                                        for i, t in enumerate(total)))
            per_part[ROW].append(total)
    return per_part


def parts_table(per_part: dict[str, list[tuple[float, float]]]) -> list[str]:
    """Markdown: each part's median seconds per run (wall and CPU), the set-up before the
    kernel, and everything but the kernel (the figure)."""
    def median(values, i):
        return statistics.median(v[i] for v in values)

    rows = per_part[ROW]
    runs = range(len(rows))
    sums = {
        "*set-up before the kernel (the set-up rows)*": [
            tuple(sum(v[r][i] for p, v in per_part.items() if p.startswith("set-up"))
                  for i in (0, 1)) for r in runs],
        "**everything but the kernel** (row − kernel)": [
            tuple(rows[r][i] - per_part[KERNEL][r][i] for i in (0, 1)) for r in runs],
    }
    wall = median(rows, 0)
    lines = ["| part of a row (make_row, this process) | wall s per run, median | CPU s "
             "per run, median | share of the wall |", "|---|---:|---:|---:|"]
    for part, values in {**{p: v for p, v in per_part.items() if p != ROW}, **sums,
                         ROW: rows}.items():
        w, c = median(values, 0), median(values, 1)
        bold = "**" if part.startswith("**") else ""
        lines.append(f"| {part} | {bold}{w:.4f}{bold} | {c:.4f} | {w / wall:.1%} |")
    return lines


def comparable(rows):
    """The rows without provenance (wall times, version), by run id, for equality checks."""
    from rubdiag.dataset._rows import PROVENANCE

    keep = [c for c in rows.columns if c not in PROVENANCE]
    return rows[keep].sort_values("run_id").reset_index(drop=True)


def run_local(design, jobs: int, timing: Timing) -> object:
    from rubdiag.dataset import generate, load

    with tempfile.TemporaryDirectory(prefix="bench_dataset_") as tmp:
        before = load1()
        start = time.perf_counter()
        summary = generate(design, Path(tmp) / "ds", jobs=jobs, progress=False)
        seconds = time.perf_counter() - start
        timing.add(seconds, before, load1())
        rows = load(Path(tmp) / "ds")
    timing.run_s.append(float(rows["wall_s"].median()))
    simulated = float(rows["simulate_s"].sum())
    timing.overhead.append((seconds * jobs - simulated) / simulated)
    _check_summary(summary, f"jobs={jobs}")
    return rows


def run_dask(design, timing: Timing) -> object:
    import logging

    from distributed import Client, LocalCluster

    from rubdiag.dataset import generate, load

    with tempfile.TemporaryDirectory(prefix="bench_dataset_") as tmp:
        before = load1()
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
        t1 = time.perf_counter()
        try:
            summary = generate(design, Path(tmp) / "ds", client=client, progress=False)
        finally:
            t2 = time.perf_counter()
            client.close()
            cluster.close()
            t3 = time.perf_counter()
        timing.add(t3 - t0, before, load1(), start=t1 - t0, generate=t2 - t1, close=t3 - t2)
        rows = load(Path(tmp) / "ds")
    timing.run_s.append(float(rows["wall_s"].median()))
    _check_summary(summary, "dask")
    return rows


def _check_summary(summary, what: str) -> None:
    if summary["failed"]:
        print(f"warning: {what}: {summary['failed']} of {summary['total']} runs failed",
              file=sys.stderr)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100, help="runs in the design (N)")
    ap.add_argument("--duration-s", type=float, default=2.3,
                    help="simulated seconds per run (D); discard = min(0.3, D/3); "
                    f"below {SHORT_S:g} s the design is case 2 only")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of (a), (b), (c)")
    ap.add_argument("--skip-dask", action="store_true", help="leave (c) out")
    ap.add_argument("--reduced", action="store_true",
                    help="the reduced model ([base] reduced = true) instead of the full one")
    ap.add_argument("--out", type=Path, default=None, help="also write the Markdown here")
    args = ap.parse_args(argv)
    if args.runs < 1:
        ap.error("--runs must be >= 1")
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    if not args.duration_s > 0:
        ap.error("--duration-s must be > 0")

    import numpy as np

    import rubdiag
    from rubdiag.dataset import Design

    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    n, d = args.runs, args.duration_s
    text = design_toml(n, d, args.reduced)
    try:
        design = Design.from_toml(text)
    except ValueError as exc:
        raise SystemExit(f"the benchmark design is not valid for --duration-s {d:g}: "
                         f"{exc}") from None
    cases = sorted({item.point["case"] for item in design.runs()})
    pools = limit_threads(None)
    print(f"{now}; {os.cpu_count()} CPUs ({cpu_model()}); Python {platform.python_version()}, "
          f"numpy {np.__version__}, rubdiag {rubdiag.__version__} ({git_commit()}); "
          f"BLAS/OpenMP in this process: {pools}", flush=True)
    print(f"design: {n} runs x {d:g} s (discard {design.discard_s:g} s), cases {cases}, "
          f"{'reduced' if args.reduced else 'full'} model", flush=True)

    load_start = load1()
    warm_s = warm_up(design)
    print(f"warm-up (one 0.3 s run through the row path): {warm_s:.1f} s", flush=True)

    before = load1()
    bare_sum, bare_runs = bare_simulations(design)
    bare_load = (before, load1())
    print(f"bare simulate: {bare_sum:.1f} s for {n} runs "
          f"(median {statistics.median(bare_runs):.2f} s per run)", flush=True)

    before = load1()
    per_part = part_times(design)
    parts = (f"{len(per_part[ROW])} runs, load average {before:.2f}→{load1():.2f}",
             parts_table(per_part))
    print("\n".join(["", f"parts of a row, {parts[0]}:", *parts[1], ""]), flush=True)

    a, b, c = Timing(), Timing(), Timing()
    reference, mismatches = None, []
    for i in range(args.repeat):
        configs = [("a", lambda: run_local(design, 1, a)), ("b", lambda: run_local(design, 2, b))]
        if not args.skip_dask:
            configs.append(("c", lambda: run_dask(design, c)))
        for name, fn in configs:
            rows = comparable(fn())
            if reference is None:
                reference = rows
            elif not rows.equals(reference):
                mismatches.append(f"{name}#{i + 1}")
            timing = {"a": a, "b": b, "c": c}[name]
            print(f"  repeat {i + 1}/{args.repeat} ({name}): {timing.times[-1]:.1f} s "
                  f"(load {timing.loads[-1][0]:.2f}→{timing.loads[-1][1]:.2f})", flush=True)

    markdown = report(args, design, cases, now, pools, bare_sum, bare_runs, bare_load, a, b, c,
                      reference, mismatches, load_start, warm_s, parts)
    print()
    print(markdown)
    if args.out is not None:
        args.out.write_text(markdown + "\n", encoding="utf-8")
    return 1 if mismatches else 0


def report(args, design, cases, now, pools, bare_sum, bare_runs, bare_load, a, b, c, rows,
           mismatches, load_start, warm_s, parts) -> str:
    import numpy as np

    import rubdiag

    n, d = args.runs, args.duration_s

    def per_min(seconds):
        return n / seconds * 60.0

    lines = [
        f"Dataset generation — {n} runs × {d:g} s (discard {design.discard_s:g} s; LHS seed 1 "
        f"of case {cases}, speed_ratio 0.9–1.1, gap_mm 1.5–4.0, mu 0.2–0.5, paper rig, "
        f"{'reduced' if args.reduced else 'full'} model), "
        f"median of {args.repeat}. {now}, {os.cpu_count()} CPUs (`nproc`; {cpu_model()}), "
        f"Python {platform.python_version()}, numpy {np.__version__}, rubdiag "
        f"{rubdiag.__version__} ({git_commit()}); BLAS/OpenMP: {pools}.",
        "",
        "| configuration | wall, median (s) | min–max (s) | runs / min | s per run in the "
        "worker | speedup vs (a) | parallel efficiency | load avg (1 min) before→after |",
        "|---|---:|---:|---:|---:|---:|---:|---|",
        f"| bare `simulate`, 1 process, summed (once) | {bare_sum:.1f} | – | "
        f"{per_min(bare_sum):.1f} | {statistics.median(bare_runs):.2f} | – | – | "
        f"{bare_load[0]:.2f}→{bare_load[1]:.2f} |",
    ]
    entries = [("(a) `generate`, `jobs=1`", a, 1), ("(b) `generate`, `jobs=2`", b, 2)]
    if c.times:
        entries.append(("(c) `generate`, Dask `LocalCluster` 2 × 1 thread", c, 2))
    for label, timing, workers in entries:
        speedup = a.median / timing.median
        eff = f"{speedup / workers:.0%}" if workers > 1 else "–"
        sp = f"{speedup:.2f}×" if workers > 1 else "–"
        lines.append(f"| {label} | {timing.median:.1f} | {timing.spread()} | "
                     f"{per_min(timing.median):.1f} | {statistics.median(timing.run_s):.2f} | "
                     f"{sp} | {eff} | {timing.load_text()} |")
    overhead = (a.median - bare_sum) / bare_sum
    inside = statistics.median(a.overhead)
    projected = b.median * 1000 / n * 2.3 / d
    lines += [
        "",
        f"- Overhead per run over a bare `simulate`, in the same calls: **{inside:+.1%}** "
        f"(median over the (a) calls of (wall − Σ simulate) / Σ simulate, the simulations "
        f"timed inside `make_row`: labels, noise, features, Parquet, card; "
        f"{', '.join(f'{x:+.1%}' for x in a.overhead)}). Against the separate bare run "
        f"above: {overhead:+.1%} ({(a.median - bare_sum) / n:+.2f} s per run; the machine's "
        "speed drifts between the two by more than the overhead).",
        f"- Projected 1,000 runs × 2.3 s on 2 cores, (b) × 1000/{n} × 2.3/{d:g}: "
        f"**{projected / 60:.1f} min** ({projected / 3600:.2f} h).",
    ]
    if c.times:
        parts = {k: statistics.median(v) for k, v in c.parts.items()}
        lines.append(f"- (c) split, medians: cluster start-up {parts['start']:.1f} s, "
                     f"`generate` {parts['generate']:.1f} s, close {parts['close']:.1f} s.")
    if rows is not None and len(rows):
        ok = rows
        rub = int(ok["rub"].fillna(False).astype(bool).sum()) if "rub" in ok else 0
        sev = ok["severity"].value_counts() if "severity" in ok else {}
        lines.append(f"- Labels of the design's runs: rub {rub} of {len(ok)}; severity none "
                     f"{int(sev.get('none', 0))}, light {int(sev.get('light', 0))}, serious "
                     f"{int(sev.get('serious', 0))}.")
    lines += ["", "Parts of a row, median over the design's runs (`make_row` of each run in "
              f"this process, after the bare runs; {parts[0]}):", "", *parts[1], ""]
    same = ("(a), (b)" + (", (c)" if c.times else "")) + " wrote the same rows"
    lines.append(f"- {same if not mismatches else 'ROWS DIFFER in ' + ', '.join(mismatches)} "
                 "(provenance columns aside); load average at start "
                 f"{load_start:.2f}; warm-up {warm_s:.1f} s (not timed).")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
