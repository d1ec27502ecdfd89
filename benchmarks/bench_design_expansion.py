"""Benchmark of a design's expansion into its runs: the dry run, and the expansion alone.

Usage::

    .venv/bin/python benchmarks/bench_design_expansion.py [--repeat 3] [--jobs 2]
        [--designs faults_journal.toml ...] [--pythonpath DIR]

For every shipped design (``data/designs/*.toml``, or ``--designs``):

* the dry run as a subprocess, the whole command (interpreter start-up, imports, the
  calibration run)::

      rubdiag dataset DESIGN --dry-run --jobs JOBS

  with a cold rubdiag cache (``RUBDIAG_CACHE_DIR`` a fresh empty folder each time) and warm
  (a folder the same command filled just before); median of ``--repeat``, min–max beside it;
* the expansion alone, what ``generate`` does before its first run is simulated:
  ``Design.from_toml(DESIGN).runs(jobs=JOBS)`` timed in a fresh interpreter after its
  imports (:func:`expansion_seconds`; the design module, ``scipy.stats`` for the samplers
  and ``rubdiag.runs._features`` for the ramp checks, which the design module loads itself
  only where a design needs them), cold and warm likewise.

The Numba JIT cache is whatever it is (warm after any run of this checkout). ``--pythonpath``
puts another source tree first on the subprocesses' path (e.g. ``git archive`` of an older
commit), to measure it with the same venv; a tree whose ``Design.runs`` takes no ``jobs``
expands in one process.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from _threads import cpu_model  # benchmarks/ is on sys.path as a script

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "data" / "designs"

_EXPAND = """
import inspect, sys, time
import scipy.stats, rubdiag.runs._features   # the samplers, the ramp checks: imports, untimed
import rubdiag.dataset._design as design_module
path, jobs = sys.argv[1], int(sys.argv[2])
start = time.perf_counter()
design = design_module.Design.from_toml(path)
options = {"jobs": jobs} if "jobs" in inspect.signature(design.runs).parameters else {}
runs = design.runs(**options)
print(time.perf_counter() - start, len(runs))
"""


def _environ(cache: Path, pythonpath: str | None) -> dict:
    """The subprocesses' environment; they run in ``cache`` (so that ``-m``/``-c`` do not
    put this checkout before ``pythonpath``)."""
    env = {**os.environ, "RUBDIAG_CACHE_DIR": str(cache)}
    if pythonpath:
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [pythonpath, env.get("PYTHONPATH")]))
    return env


def dry_run_seconds(design_path: str | Path, cold: bool, jobs: int = 2,
                    pythonpath: str | None = None) -> float:
    """Wall time (s) of ``rubdiag dataset DESIGN --dry-run --jobs JOBS`` as a subprocess,
    with a fresh empty rubdiag cache (``cold``) or one the same command filled first."""
    import time

    with tempfile.TemporaryDirectory(prefix="bench-design-cache-") as cache:
        command = [sys.executable, "-m", "rubdiag", "dataset", str(design_path), "--dry-run",
                   "--jobs", str(jobs)]
        env = _environ(Path(cache), pythonpath)
        if not cold:
            subprocess.run(command, env=env, cwd=cache, check=True, capture_output=True)
        start = time.perf_counter()
        subprocess.run(command, env=env, cwd=cache, check=True, capture_output=True)
        return time.perf_counter() - start


def expansion_seconds(design_path: str | Path, cold: bool, jobs: int = 2,
                      pythonpath: str | None = None) -> float:
    """Wall time (s) of ``Design.from_toml(DESIGN).runs(jobs=JOBS)`` in a fresh interpreter,
    its imports done first (not timed: module docstring), with a fresh empty rubdiag cache
    (``cold``) or one the same expansion filled first."""
    with tempfile.TemporaryDirectory(prefix="bench-design-cache-") as cache:
        command = [sys.executable, "-c", _EXPAND, str(design_path), str(jobs)]
        env = _environ(Path(cache), pythonpath)
        if not cold:
            subprocess.run(command, env=env, cwd=cache, check=True, capture_output=True)
        done = subprocess.run(command, env=env, cwd=cache, check=True, capture_output=True,
                              text=True)
        return float(done.stdout.split()[0])


def _median(measure, repeat: int) -> tuple[float, float, float]:
    values = [measure() for _ in range(repeat)]
    return statistics.median(values), min(values), max(values)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--designs", nargs="*", help="file names in data/designs (default: all)")
    parser.add_argument("--pythonpath", help="a source tree to measure instead of this one")
    args = parser.parse_args(argv)
    names = args.designs or sorted(p.name for p in DESIGNS.glob("*.toml"))
    load = os.getloadavg()
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, {os.cpu_count()} CPUs "
          f"({cpu_model()}), Python {platform.python_version()}, jobs {args.jobs}, "
          f"repeat {args.repeat}, load {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}"
          + (f", source {args.pythonpath}" if args.pythonpath else ""))
    print("| design | dry run, cold | dry run, warm | expansion, cold | expansion, warm |")
    print("|---|---:|---:|---:|---:|")
    for name in names:
        path = DESIGNS / name
        cells = []
        for measure in (dry_run_seconds, expansion_seconds):
            for cold in (True, False):
                median, lo, hi = _median(
                    lambda m=measure, c=cold, p=path: m(p, c, args.jobs, args.pythonpath),
                    args.repeat)
                cells.append(f"{median:.2f} s ({lo:.2f}–{hi:.2f})")
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)
    load = os.getloadavg()
    print(f"# load at the end {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
