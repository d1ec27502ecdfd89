"""Dataset throughput side by side: full model, reduced model, and the dataset defaults.

Usage::

    .venv/bin/python benchmarks/bench_throughput.py [--runs 24] [--duration-s 2.3] [--repeat 3]
        [--skip-dask] [--out FILE]

One fixed design (``design_data``): ``--runs`` LHS points (seed 1) of the paper rig,
``case = [1, 2]``, ``speed_ratio`` 0.8–1.2, ``gap_mm`` 0.5–4.0, ``mu`` 0.1–0.5, each run
``--duration-s`` long with ``min(0.3, duration/3)`` s discarded (below 1 s: case 2 only, as
in ``bench_dataset.py``). Three configurations of it differ in ``[base]`` only:

* A: the full model at the 10-µs base step (``step_error = 0``);
* B: the reduced model at the 10-µs base step (``reduced = true``, ``step_error = 0``);
* C: the dataset defaults (``reduced = true`` and no ``step_error``:
  ``rubdiag.dataset._design.DEFAULT_STEP_ERROR``, long steps where nothing is in contact).

After a warm-up (one 0.3-s run of each configuration through the row path in this process,
so the Numba kernels are compiled or loaded from the on-disk cache; the local workers are
forked from this process), each configuration runs ``generate(design, tmp, jobs=2,
progress=False)`` into a fresh temporary folder, and (unless ``--skip-dask``) on a fresh
``dask.distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
dashboard_address=None)``, cluster start-up and close timed separately. The order is
interleaved, A, B, C on 2 local workers then A, B, C on Dask, ``--repeat`` times, so that a
change of the machine's load hits all alike; medians are reported. The load average
(1 min) is read before and after every measurement.

Reported per configuration: wall (median, min–max); runs per minute; seconds per run on a
worker, as wall × 2 / N and as the median of the rows' ``wall_s``; worker time per
simulated time, Σ ``simulate_s`` / (N × D) (s per s, i.e. µs per simulated µs); the
speed-up over A (wall against wall, Dask against Dask); minutes per 1,000 runs × 2.3 s on
2 cores, wall × 1000/N × 2.3/D / 60 (fixed costs are scaled too, so project from
D = 2.3 s); rubbing runs; steps per run when the rows carry a step count (``n_steps``). The
script checks that each configuration writes the same rows every time (local and Dask).
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import os
import platform
import statistics
import sys
from pathlib import Path

# benchmarks/ is on sys.path as a script
from _threads import cpu_model, limit_threads
from bench_dataset import (
    SHORT_S,
    Timing,
    comparable,
    git_commit,
    load1,
    run_dask,
    run_local,
    warm_up,
)

SEED = 1
WORKERS = 2
#: configuration -> (what it is, the keys of ``[base]`` that make it)
CONFIGS = {
    "A": ("full model, 10 µs", {"step_error": 0.0}),
    "B": ("reduced model, 10 µs", {"reduced": True, "step_error": 0.0}),
    "C": ("dataset defaults (reduced, default step_error)", {"reduced": True}),
}
STEP_COLUMNS = ("n_steps", "steps")     # a row's step count, if the rows ever carry one


def design_data(runs: int, duration_s: float, base: dict) -> dict:
    """The benchmark's design, as parsed TOML, with the extra ``[base]`` keys ``base``."""
    return {
        "base": {"rig": "paper", **base, "duration_s": duration_s,
                 "discard_s": round(min(0.3, duration_s / 3), 9)},   # 0.3 / 3 is 0.0999…
        "sampling": {"method": "lhs", "n": runs, "seed": SEED},
        "factors": {"case": [1, 2] if duration_s >= SHORT_S else [2],
                    "speed_ratio": {"low": 0.8, "high": 1.2},
                    "gap_mm": {"low": 0.5, "high": 4.0},
                    "mu": {"low": 0.1, "high": 0.5}},
    }


@dataclasses.dataclass
class Measured:
    """One configuration on one scheduler: the wall times and what its rows say."""

    timing: Timing = dataclasses.field(default_factory=Timing)
    simulate_sum: list = dataclasses.field(default_factory=list)   # Σ simulate_s per call
    steps: list = dataclasses.field(default_factory=list)          # median steps per call
    rows: object = None            # the first call's rows (comparable)
    mismatches: int = 0            # later calls whose rows differ from the first
    failed: int = 0                # most failed rows of a call

    def record(self, rows) -> None:
        ok = rows[rows["status"] == "ok"]
        self.simulate_sum.append(float(ok["simulate_s"].sum()))
        self.failed = max(self.failed, len(rows) - len(ok))
        column = next((c for c in STEP_COLUMNS if c in rows), None)
        if column is not None:
            self.steps.append(float(ok[column].median()))
        same = comparable(rows)
        if self.rows is None:
            self.rows = same
        elif not same.equals(self.rows):
            self.mismatches += 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=24, help="runs in the design (N)")
    ap.add_argument("--duration-s", type=float, default=2.3,
                    help="simulated seconds per run (D); discard = min(0.3, D/3); "
                    f"below {SHORT_S:g} s the design is case 2 only")
    ap.add_argument("--repeat", type=int, default=3, help="timed passes of A, B, C")
    ap.add_argument("--dask", action=argparse.BooleanOptionalAction, default=True,
                    help="also on a 2-worker Dask LocalCluster (default: yes)")
    ap.add_argument("--skip-dask", dest="dask", action="store_false",
                    help="leave Dask out (= --no-dask)")
    ap.add_argument("--out", type=Path, default=None, help="also write the Markdown here")
    args = ap.parse_args(argv)
    if args.runs < 1 or args.repeat < 1 or not args.duration_s > 0:
        ap.error("--runs and --repeat must be >= 1, --duration-s > 0")

    from rubdiag.dataset import Design

    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    designs = {}
    for name, (_, base) in CONFIGS.items():
        try:
            designs[name] = Design.from_dict(design_data(args.runs, args.duration_s, base))
        except ValueError as exc:
            raise SystemExit(f"the design is not valid for --duration-s "
                             f"{args.duration_s:g}: {exc}") from None
    pools = limit_threads(None)
    load_start = load1()
    commit = git_commit()     # at the start: others may commit while this runs
    print(f"{now}; {os.cpu_count()} CPUs ({cpu_model()}); {commit}; load {load_start:.2f}",
          flush=True)
    warm = {name: warm_up(design) for name, design in designs.items()}
    print("warm-up (0.3 s through the row path): "
          + ", ".join(f"{k} {v:.1f} s" for k, v in warm.items()), flush=True)

    schedulers = ["local"] + (["dask"] if args.dask else [])
    measured = {(s, name): Measured() for s in schedulers for name in CONFIGS}
    for i in range(args.repeat):
        for scheduler in schedulers:
            for name, design in designs.items():
                m = measured[scheduler, name]
                rows = (run_local(design, WORKERS, m.timing) if scheduler == "local"
                        else run_dask(design, m.timing))
                m.record(rows)
                before, after = m.timing.loads[-1]
                print(f"  pass {i + 1}/{args.repeat} {scheduler} {name}: "
                      f"{m.timing.times[-1]:.1f} s (load {before:.2f}→{after:.2f})", flush=True)

    markdown = report(args, designs["A"], now, commit, pools, load_start, warm, measured,
                      schedulers)
    print()
    print(markdown)
    if args.out is not None:
        args.out.write_text(markdown + "\n", encoding="utf-8")
    return 1 if any(m.mismatches or m.failed for m in measured.values()) else 0


def report(args, design, now, commit, pools, load_start, warm, measured, schedulers) -> str:
    import numpy as np

    import rubdiag
    from rubdiag.dataset._design import DEFAULT_STEP_ERROR

    n, d = args.runs, args.duration_s
    cases = sorted({item.point["case"] for item in design.runs()})
    steps = any(m.steps for m in measured.values())
    lines = [
        f"Dataset throughput — {n} runs × {d:g} s (discard {design.discard_s:g} s; LHS seed "
        f"{SEED} of case {cases}, speed_ratio 0.8–1.2, gap_mm 0.5–4.0, mu 0.1–0.5, paper rig), "
        f"{WORKERS} workers, median of {args.repeat} interleaved passes; C's step_error = "
        f"{DEFAULT_STEP_ERROR:g} (`DEFAULT_STEP_ERROR`). {now}, {os.cpu_count()} CPUs "
        f"({cpu_model()}), Python {platform.python_version()}, numpy {np.__version__}, "
        f"rubdiag {rubdiag.__version__} ({commit}); BLAS/OpenMP: {pools}.",
        "",
        "| configuration | wall, median (s) | min–max (s) | runs / min | s per run "
        "(wall × 2 / N) | s per run (median `wall_s`) | worker s per simulated s "
        "(Σ `simulate_s` / N·D) | speed-up vs A | min per 1,000 runs × 2.3 s "
        + ("| steps per run (median) " if steps else "")
        + "| rubbing runs | load avg (1 min) before→after |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|" if steps else "") + "---:|---|",
    ]
    for scheduler in schedulers:
        where = (f"`jobs={WORKERS}`" if scheduler == "local"
                 else f"Dask `LocalCluster` {WORKERS} × 1 (start + close included)")
        a = measured[scheduler, "A"].timing.median
        for name, (what, _) in CONFIGS.items():
            m = measured[scheduler, name]
            t = m.timing
            per_sim = statistics.median(m.simulate_sum) / (n * d)
            speedup = "–" if name == "A" else f"**{a / t.median:.2f}×**"
            rub = (int(m.rows["rub"].fillna(False).astype(bool).sum())
                   if m.rows is not None and "rub" in m.rows else "–")
            lines.append(
                f"| {name}: {what}, {where} | {t.median:.1f} | {t.spread()} | "
                f"{n / t.median * 60:.1f} | {t.median * WORKERS / n:.2f} | "
                f"{statistics.median(t.run_s):.2f} | {per_sim:.3f} | {speedup} | "
                f"{t.median * 1000 / n * 2.3 / d / 60:.1f} | "
                + (f"{statistics.median(m.steps):,.0f} | " if steps else "")
                + f"{rub} of {n} | {t.load_text()} |")
    lines.append("")
    if "dask" in schedulers:
        split = []
        for name in CONFIGS:
            parts = {k: statistics.median(v)
                     for k, v in measured["dask", name].timing.parts.items()}
            split.append(f"{name} start-up {parts['start']:.1f} s, `generate` "
                         f"{parts['generate']:.1f} s, close {parts['close']:.1f} s")
        gen = {name: statistics.median(measured["dask", name].timing.parts["generate"])
               for name in CONFIGS}
        lines.append(f"- Dask split, medians: {'; '.join(split)}. Speed-up on `generate` "
                     f"alone: B {gen['A'] / gen['B']:.2f}×, C {gen['A'] / gen['C']:.2f}×.")
    for scheduler in schedulers:
        a = measured[scheduler, "A"].timing.times
        paired = {k: ", ".join(f"{x / y:.2f}" for x, y in
                               zip(a, measured[scheduler, k].timing.times, strict=True))
                  for k in ("B", "C")}
        lines.append(f"- Speed-up over A within each pass ({scheduler}): B {paired['B']}; "
                     f"C {paired['C']}.")
    a, c = measured["local", "A"].timing.median, measured["local", "C"].timing.median
    lines.append(f"- C against A on 2 local workers: **{a / c:.2f}×** — "
                 f"{'meets' if a / c >= 4.5 else 'misses'} the goal of ≥ 4.5×.")
    bad = [f"{s} {k}: {m.mismatches} of {args.repeat - 1} later passes differ"
           for (s, k), m in measured.items() if m.mismatches]
    failed = [f"{s} {k}: {m.failed} failed runs" for (s, k), m in measured.items() if m.failed]
    if "dask" in schedulers:
        bad += [f"local and Dask rows of {k} differ" for k in CONFIGS
                if not measured["local", k].rows.equals(measured["dask", k].rows)]
    same = ("every pass of a configuration" + (", local and Dask," if "dask" in schedulers
                                                else "") + " wrote the same rows (provenance "
            "aside), no run failed")
    lines.append(f"- {'; '.join(bad + failed) if bad or failed else same}; load average at "
                 f"start {load_start:.2f}; warm-up (not timed) "
                 + ", ".join(f"{k} {v:.1f} s" for k, v in warm.items()) + ".")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
