"""A run as a process: wall time of ``rubdiag simulate … --reduced`` against the full model.

What a user sees from the command line: the whole process (interpreter start, imports,
loading the Numba kernels, the rig's critical speed, assembly, reduction, the run), timed
from outside with ``time.perf_counter`` around ``subprocess.run``. For each condition, the
median (and min–max) of ``--repeat`` runs of each model, full and reduced runs alternating:

* **quiet** — nothing started beside the runs (the machine's other jobs are not ours to stop:
  the load average before and after is printed);
* **busy** — two CPU-bound processes (``python -c "while True: pass"``; ``--busy N``)
  started before and killed after, as on cores that other jobs share;

each with the disk cache of rig-only results (``rubdiag/_cache.py``)

* **cold** — every run gets a new, empty cache folder (a first run of the rig);
* **warm** — one cache folder, filled by one unmeasured run of each model first.

Besides the wall time, the CPU time of each process (user + system, all its threads; Unix):
it hardly depends on what else runs, and a CPU time above the wall time would mean threads
spinning.

The Numba kernels are compiled once per machine (``cache=True``); one unmeasured run makes
sure they are before anything is timed. ``--breakdown`` adds where the time of one process of
each model goes (fresh interpreters; cold and warm): imports, the run's description (critical
speed), assembly, reduction, the first ``simulate`` call and a second, identical one in the
same process — their difference is the one-time cost of loading the Numba kernels.

Usage::

    .venv/bin/python benchmarks/bench_process.py                     # the run, 5 each
    .venv/bin/python benchmarks/bench_process.py --repeat 2 --duration-s 0.3   # a quick look
    .venv/bin/python benchmarks/bench_process.py --breakdown --conditions quiet

Prints markdown tables. ``--checkout DIR`` times the rubdiag package in DIR instead (with this
venv), e.g. an older commit: ``git archive 4dff11d rubdiag | tar -x -C /tmp/old`` then
``--checkout /tmp/old`` (its first run compiles its Numba kernels, untimed).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _threads import cpu_model

CACHE_ENV = "RUBDIAG_CACHE_DIR"
SPIN = "while True: pass"

BREAKDOWN = r"""
import json, sys, time
t = [time.perf_counter()]
laps = {}
def lap(name):
    now = time.perf_counter(); laps[name] = now - t[0]; t[0] = now
import rubdiag.cli, rubdiag.simulate
lap("imports")
from rubdiag.model import paper_rig
from rubdiag.reduce import Reduction, reduced_model
from rubdiag.simulation import Run, simulate
try:
    from rubdiag.simulation._rig_cache import damped_model
except ImportError:    # a checkout from before the cache
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh
    def damped_model(rig):
        return with_rayleigh(assemble(rig))
reduction = Reduction() if sys.argv[1] == "reduced" else None
duration = float(sys.argv[2])
run = Run.paper_case(2, 1.9, duration_s=duration, discard_s=min(0.3, duration / 2),
                     reduction=reduction)
lap("run description (critical speed)")
damped_model(paper_rig())
lap("assembly")
if reduction is not None:
    reduced_model(paper_rig(), reduction)
    lap("reduction")
first = simulate(run)
lap("first simulate()")
second = simulate(run)
lap("second simulate() (same run)")
extra = second.system.extra
laps["kernel (second run)"] = extra["kernel_seconds"]
laps["step operators, state (second run)"] = extra["setup_seconds"]
print(json.dumps(laps))
"""


def preamble(checkout: Path | None) -> str:
    """Python code run first in each measured process: with ``checkout``, rubdiag is
    imported from there (ahead of the editable install's finder, which PYTHONPATH does
    not override)."""
    if checkout is None:
        return "import sys\n"
    return ("import sys\n"
            "sys.meta_path[:] = [f for f in sys.meta_path\n"
            "                    if not getattr(f, '__module__', '').startswith('__editable__')]\n"
            f"sys.path.insert(0, {str(checkout.resolve())!r})\n")


def simulate_command(model: str, duration_s: float, checkout: Path | None) -> list[str]:
    """``rubdiag simulate`` of the cell (``python -c`` running the CLI's main)."""
    command = [sys.executable, "-c", preamble(checkout)
               + "from rubdiag.cli import main\nsys.exit(main())\n",
               "simulate", "--case", "2", "--gap-mm", "1.9", "--duration-s", f"{duration_s:g}",
               "--json"]
    if duration_s <= 0.3:    # the default window starts at 0.3 s
        command += ["--discard-s", f"{duration_s / 2:g}"]
    return command + (["--reduced"] if model == "reduced" else [])


def environment(cache: Path | None) -> dict:
    env = dict(os.environ)
    if cache is not None:
        env[CACHE_ENV] = str(cache)
    return env


def timed_process(command: list[str], env: dict) -> tuple[float, float, dict]:
    """Wall time and CPU time (user + system, all its threads) of the process (s), and its
    JSON summary."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, json.loads(done.stdout.splitlines()[-1])


class Busy:
    """``n`` CPU-bound processes for the duration of a ``with`` block (killed by pid)."""

    def __init__(self, n: int):
        self.n = n
        self.processes: list[subprocess.Popen] = []

    def __enter__(self):
        self.processes = [subprocess.Popen([sys.executable, "-c", SPIN])
                          for _ in range(self.n)]
        time.sleep(1.0)     # running flat out before anything is timed
        return self

    def __exit__(self, *exc):
        for p in self.processes:
            p.kill()
            p.wait()


def measure(args, scratch: Path, warm: bool) -> dict[str, list[tuple[float, float, float]]]:
    """(process wall, process CPU, simulate() wall) per run, per model, full and reduced
    alternating."""
    times: dict[str, list[tuple[float, float, float]]] = {"full": [], "reduced": []}
    shared = scratch / "warm"
    if warm:
        for model in times:      # fills the cache, not timed
            timed_process(simulate_command(model, args.duration_s, args.checkout),
                          environment(shared))
    for i in range(args.repeat):
        for model in times:
            cache = shared if warm else Path(tempfile.mkdtemp(dir=scratch, prefix=f"cold{i}-"))
            wall, cpu, summary = timed_process(
                simulate_command(model, args.duration_s, args.checkout), environment(cache))
            times[model].append((wall, cpu, summary["wall_s"]))
    return times


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}–{max(values):.2f})"


def load_average() -> str:
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def breakdown(args, scratch: Path) -> None:
    print("\nWhere one process's time goes (s; one fresh interpreter each; 'process' timed "
          "from outside, 'start-up' = process − the laps):\n")
    rows, names = {}, []
    for model in ("full", "reduced"):
        for state in ("cold", "warm"):
            cache = scratch / f"breakdown-{model}"
            if state == "cold":
                shutil.rmtree(cache, ignore_errors=True)
            command = [sys.executable, "-c", preamble(args.checkout) + BREAKDOWN, model,
                       f"{args.duration_s:g}"]
            start = time.perf_counter()
            done = subprocess.run(command, env=environment(cache),
                                  capture_output=True, text=True)
            wall = time.perf_counter() - start
            if done.returncode != 0:
                raise SystemExit(done.stderr)
            laps = json.loads(done.stdout.splitlines()[-1])
            inner = ("kernel (second run)", "step operators, state (second run)")
            laps["interpreter start-up, exit"] = wall - sum(
                v for k, v in laps.items() if k not in inner)
            laps["process"] = wall
            rows[f"{model}, {state}"] = laps
            names += [k for k in laps if k not in names]
    header = list(rows)
    print("| | " + " | ".join(header) + " |")
    print("|---|" + "---:|" * len(header))
    for name in names:
        cells = [f"{rows[h][name]:.3f}" if name in rows[h] else "–" for h in header]
        print(f"| {name} | " + " | ".join(cells) + " |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs of each model (default 5)")
    ap.add_argument("--duration-s", type=float, default=1.3,
                    help="simulated time of each run (s, default 1.3)")
    ap.add_argument("--conditions", nargs="+", choices=("quiet", "busy"),
                    default=["quiet", "busy"])
    ap.add_argument("--cache", nargs="+", choices=("cold", "warm"), default=["cold", "warm"],
                    help="disk-cache states to time (a checkout without the cache: cold)")
    ap.add_argument("--busy", type=int, default=2, help="CPU-bound processes beside the runs "
                    "under 'busy' (default 2)")
    ap.add_argument("--breakdown", action="store_true",
                    help="also time the parts of one process of each model")
    ap.add_argument("--checkout", type=Path, help="time the rubdiag in this folder instead")
    args = ap.parse_args()

    print(f"bench_process: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
          f"{cpu_model()}, {os.cpu_count()} CPUs; Python {platform.python_version()}; "
          f"`rubdiag simulate --case 2 --gap-mm 1.9 --duration-s {args.duration_s:g} "
          f"[--reduced]`, median (min–max) of {args.repeat} processes each; "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}"
          + (f"; checkout {args.checkout}" if args.checkout else ""))
    with tempfile.TemporaryDirectory(prefix="bench-process-") as tmp:
        scratch = Path(tmp)
        timed_process(simulate_command("reduced", 0.01, args.checkout),   # Numba compiled
                      environment(scratch / "first"))
        print(f"load average before: {load_average()}\n")
        print("| beside the runs | disk cache | full: process s | reduced: process s "
              "| full / reduced | full: CPU s | reduced: CPU s | full: simulate() s "
              "| reduced: simulate() s |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
        for condition in args.conditions:
            for warm in [state == "warm" for state in args.cache]:
                busy = Busy(args.busy if condition == "busy" else 0)
                with busy:
                    times = measure(args, scratch, warm)
                full, red = (list(zip(*times[m], strict=True)) for m in ("full", "reduced"))
                label = "nothing" if condition == "quiet" else f"{args.busy} CPU-bound"
                ratio = statistics.median(full[0]) / statistics.median(red[0])
                print(f"| {label} | {'warm' if warm else 'cold'} | {spread(full[0])} | "
                      f"{spread(red[0])} | {ratio:.2f}× | {spread(full[1])} | {spread(red[1])} "
                      f"| {spread(full[2])} | {spread(red[2])} |", flush=True)
        print(f"\nload average after: {load_average()}")
        if args.breakdown:
            breakdown(args, scratch)


if __name__ == "__main__":
    main()
