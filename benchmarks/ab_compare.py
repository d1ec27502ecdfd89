"""Interleaved A/B benchmark of the simulator kernel between two versions of rubdiag.

A and B are git revisions of this repository (checked out once as a detached worktree
``/tmp/rubdiag-ab-<short sha>``, reused when it exists) or folders holding a checkout; B is
by default this checkout, uncommitted work included. Each side runs its own copies of
``bench_kernel.py``, ``bench_reduced.py`` and ``bench_breakdown.py`` (a side lacking one runs
the other side's copy, said in the output) as separate processes of the same interpreter,
with ``PYTHONPATH`` = that side's folder, one BLAS/OpenMP thread, no disk cache of rig-only
results and no ``NUMBA_CACHE_DIR``: each checkout keeps its Numba cache in its own
``__pycache__``, so the two sides never share compiled kernels.

One warm-up run of each script per side (compiles, fills the caches; not counted), then
``--pairs`` pairs; within a pair each script runs on both sides back to back, A first in
odd pairs and B first in even ones, so a drift of the machine's speed cancels in the ratios.
Printed: per quantity (µs per step) each side's median, the median of the paired ratios B/A
and their range, as a markdown table with the date, the CPU, the load average and the
command; and whether the kernel's criterion (B/A ≤ ``--bar``, default 1.05, on the rubbing
cells' µs per step) is met — as information only when the cores were not quiet or with
``--quick``.

``--clock cpu`` times the processes' CPU time instead of the wall clock: each child starts
with ``time.perf_counter`` replaced by ``time.process_time`` (a ``sitecustomize`` module on
its path), so the kernel's own timer and the scripts' count the CPU seconds the process got.
The kernels run on one thread, so on cores shared with other jobs this is the figure that
does not depend on how much of a core the process was given; the cores need not be quiet.

Usage::

    .venv/bin/python benchmarks/ab_compare.py --a 4dff11d [--b HEAD|FOLDER] [--pairs 5] \
        [--clock wall|cpu] [--bar 1.05] [--quick] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import atexit
import json
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
WORKTREE_PREFIX = "/tmp/rubdiag-ab-"
#: a 1-minute load average above this many runnable processes per CPU: not quiet cores
QUIET_LOAD_PER_CPU = 0.5
#: the default bar: B's µs per step at most 5 % above A's (median of the paired ratios)
BAR = 1.05
#: on a child's path with ``--clock cpu``: every ``time.perf_counter()`` reads CPU time
CPU_CLOCK_SHIM = "import time\ntime.perf_counter = time.process_time\n"
#: variables set alike on both sides: one thread per BLAS/OpenMP pool (the kernels are
#: single-threaded; a spinning pool would time the machine, not the code), and rubdiag's
#: disk cache of rig-only results off (the base revision may predate it)
CHILD_ENV = {
    "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1", "RUBDIAG_CACHE_DIR": "",
}


#: what each ``--clock`` times
CLOCKS = {"wall": "wall clock (time.perf_counter)",
          "cpu": "the process's CPU time (time.perf_counter read as time.process_time)"}


@dataclass(frozen=True)
class Side:
    name: str       # "A" or "B"
    root: Path
    label: str      # what the report calls it


@dataclass(frozen=True)
class Bench:
    script: str
    args: tuple[str, ...]
    quick_args: tuple[str, ...]


# default arguments: those of the figures in benchmarks/README.md
BENCHES = (
    Bench("bench_kernel.py", (), ("--repeat", "1", "--duration", "0.01")),
    # bench_reduced's runs discard their first 0.3 s: a quick run must be longer
    Bench("bench_reduced.py", (), ("--repeat", "1", "--duration", "0.5")),
    Bench("bench_breakdown.py", (), ("--repeat", "1", "--duration", "0.3")),
)


# ---------------------------------------------------------------- sides

def _git(*args: str) -> str:
    return subprocess.run(["git", "-C", str(REPO), *args], capture_output=True, text=True,
                          check=True).stdout.strip()


def _commit_of(folder: Path) -> str | None:
    out = subprocess.run(["git", "-C", str(folder), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True)
    return out.stdout.strip() if out.returncode == 0 else None


def _changed_files(folder: Path) -> int:
    """Files changed or new (untracked) in the code a benchmark runs."""
    out = subprocess.run(["git", "-C", str(folder), "status", "--porcelain", "--",
                          "rubdiag", "benchmarks"], capture_output=True, text=True)
    return len(out.stdout.splitlines()) if out.returncode == 0 else 0


def resolve_side(name: str, spec: str) -> Side:
    """A checkout folder, or a revision of this repository checked out as a worktree."""
    option = f"--{name.lower()}"
    folder = Path(spec).expanduser()
    if folder.is_dir():
        if not (folder / "rubdiag" / "__init__.py").is_file():
            raise ValueError(f"{option} {spec!r}: a folder without rubdiag/__init__.py; "
                             "allowed: a rubdiag checkout or a git revision")
        root = folder.resolve()
        commit = _commit_of(root)
        label = str(root) if commit is None else f"{root} ({commit}"
        if commit is not None:
            changed = _changed_files(root)
            label += (f" + {changed} changed or new files under rubdiag/, benchmarks/)"
                      if changed else ")")
        return Side(name, root, label)
    try:
        sha = _git("rev-parse", "--verify", "--quiet", f"{spec}^{{commit}}")
        short = _git("rev-parse", "--short", sha)
    except subprocess.CalledProcessError:
        raise ValueError(f"{option} {spec!r}: neither a folder nor a git revision of "
                         f"{REPO}; allowed: a rubdiag checkout or a revision") from None
    root = Path(WORKTREE_PREFIX + short)
    if root.exists():
        there = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"],
                               capture_output=True, text=True).stdout.strip()
        if there != sha:
            raise ValueError(f"{option} {spec!r}: {root} exists but holds "
                             f"{there[:7] or 'no checkout'}, not {short}; remove it first")
        if _changed_files(root):
            print(f"note: {root} has uncommitted changes", file=sys.stderr)
    else:
        try:
            _git("worktree", "add", "--detach", str(root), sha)
        except subprocess.CalledProcessError as err:
            raise RuntimeError(f"git worktree add {root} failed: "
                               f"{''.join(err.stderr.strip().splitlines()[-1:])}") from None
        print(f"created worktree {root} at {short}", file=sys.stderr)
    return Side(name, root, f"{short} ({root})")


def child_env(side: Side, shim: Path | None = None) -> dict[str, str]:
    """A child's environment; ``shim``: a folder whose ``sitecustomize`` changes its clock."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env.update(CHILD_ENV)
    env["PYTHONPATH"] = str(side.root) if shim is None else f"{shim}{os.pathsep}{side.root}"
    return env


#: run in a side's environment: imports the modules given as arguments and prints, one a
#: line, every loaded rubdiag module's file
_IMPORT_PROBE = """import importlib, sys
for name in sys.argv[1:]:
    importlib.import_module(name)
for name, module in sorted(sys.modules.items()):
    if name.split(".")[0] == "rubdiag" and getattr(module, "__file__", None):
        print(module.__file__)
"""


def check_imports(side: Side, scripts: list[Path]) -> None:
    """The side's processes must run the side's rubdiag only. The venv's editable install
    of rubdiag comes after PYTHONPATH, but it would still serve a module that the side's
    tree lacks — silently mixing two versions."""
    modules = sorted({m for script in scripts for m in re.findall(
        r"^\s*(?:from|import) (rubdiag[\w.]*)", script.read_text(encoding="utf-8"),
        flags=re.M)} | {"rubdiag"})
    out = subprocess.run([sys.executable, "-c", _IMPORT_PROBE, *modules], cwd=side.root,
                         env=child_env(side), capture_output=True, text=True)
    if out.returncode != 0:
        last = (out.stderr.strip().splitlines() or ["?"])[-1]
        raise ValueError(f"--{side.name.lower()} {side.root}: the benchmarks' rubdiag "
                         f"modules do not import ({last})")
    foreign = [f for f in out.stdout.split() if side.root not in Path(f).resolve().parents]
    if foreign:
        raise ValueError(f"--{side.name.lower()} {side.root}: rubdiag modules come from "
                         f"outside it ({', '.join(foreign[:3])}); allowed: a whole checkout")


# ---------------------------------------------------------------- parsing

def _number(cell: str) -> float | None:
    match = re.match(r"\s*(-?\d+(?:\.\d+)?(?:e-?\d+)?)", cell)
    return float(match.group(1)) if match else None


def _tables(text: str) -> list[list[dict[str, str]]]:
    """The markdown tables in a script's output, as rows of {header: cell}."""
    tables, block = [], []
    for line in [*text.splitlines(), ""]:
        if line.startswith("|"):
            block.append([c.strip() for c in line.strip().strip("|").split("|")])
            continue
        if len(block) >= 2:
            head = block[0]
            tables.append([dict(zip(head, row, strict=True)) for row in block[2:]])
        block = []
    return tables


def parse_kernel(text: str) -> tuple[dict[str, float], dict[str, float]]:
    match = re.search(r"MEDIAN kernel time per step while rubbing: ([\d.]+)", text)
    if match is None:
        raise ValueError("no 'MEDIAN kernel time per step while rubbing' line")
    return {"bench_kernel: test system, rubbing, µs/step": float(match.group(1))}, {}


def parse_reduced(text: str) -> tuple[dict[str, float], dict[str, float]]:
    times: dict[str, float] = {}
    for table in _tables(text):
        for row in table:
            if "model" in row and _number(row.get("µs/step", "")) is not None:
                case = row["case"].split()[0]
                times[f"bench_reduced: case {case}, {row['model']}, µs/step"] = \
                    _number(row["µs/step"])
    # "reduced kernel at 2000 Hz, µs per step by section (case 2 ...):" then "rhs 0.19 | ..."
    for head, line in re.findall(r"reduced kernel at (\S+ Hz), µs per step by section"
                                 r"[^\n]*\n([^\n]+)", text):
        for part in line.split("|"):
            name, _, value = part.strip().rpartition(" ")
            if _number(value) is not None:
                times[f"bench_reduced: case 2, reduced {head}, {name}"] = _number(value)
    if not times:
        raise ValueError("no table of µs per step")
    return times, {}


def parse_breakdown(text: str) -> tuple[dict[str, float], dict[str, float]]:
    times: dict[str, float] = {}
    work: dict[str, float] = {}   # not times: the same work on both sides?
    for table in _tables(text):
        for row in table:
            if "µs/step" not in row:
                continue
            case = row["case"].split()[0]
            for column, cell in row.items():
                value = _number(cell)
                if column == "case" or value is None:
                    continue
                if column in ("steps", "Newton its/step"):
                    work[f"bench_breakdown: case {case}, {column}"] = value
                else:
                    times[f"bench_breakdown: case {case}, {column}"] = value
    if not times:
        raise ValueError("no table of µs per step")
    return times, work


PARSERS = {"bench_kernel.py": parse_kernel, "bench_reduced.py": parse_reduced,
           "bench_breakdown.py": parse_breakdown}
#: the rows the criterion is about: µs per step of whole rubbing runs, full and reduced
CRITERION = re.compile(r"((test system, rubbing|, full|, reduced \S+ Hz), µs/step"
                       r"|case \d, µs/step unprofiled)$")


# ---------------------------------------------------------------- running

def script_for(side: Side, other: Side, bench: Bench) -> Path:
    own = side.root / "benchmarks" / bench.script
    if own.is_file():
        return own
    fallback = other.root / "benchmarks" / bench.script
    print(f"note: {side.name} has no benchmarks/{bench.script}: it runs {fallback}",
          file=sys.stderr)
    return fallback


def run_bench(side: Side, script: Path, bench: Bench, quick: bool, shim: Path | None = None):
    """One process of one script on one side: (µs quantities, work quantities, wall s)."""
    command = [sys.executable, str(script), *(bench.quick_args if quick else bench.args)]
    start = time.perf_counter()
    out = subprocess.run(command, cwd=side.root, env=child_env(side, shim),
                         capture_output=True, text=True)
    wall = time.perf_counter() - start
    if out.returncode != 0:
        last = (out.stderr.strip().splitlines() or ["(no output)"])[-1]
        raise RuntimeError(f"{bench.script} failed on {side.name} ({side.label}), exit "
                           f"{out.returncode}: {last}")
    try:
        times, work = PARSERS[bench.script](out.stdout)
    except ValueError as err:
        raise RuntimeError(f"{bench.script} on {side.name}: output not understood "
                           f"({err})") from None
    return times, work, wall


def cpu_model() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def n_cpus() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") \
        else os.cpu_count() or 1


# ---------------------------------------------------------------- report

def summarise(pairs: list[dict]) -> list[dict]:
    """Per quantity: each side's median, the paired ratios' median, min, max."""
    names: list[str] = []
    for pair in pairs:
        for side in ("A", "B"):
            names += [n for n in pair[side] if n not in names]
    rows = []
    for name in names:
        a = [p["A"][name] for p in pairs if name in p["A"]]
        b = [p["B"][name] for p in pairs if name in p["B"]]
        ratios = [p["B"][name] / p["A"][name] for p in pairs
                  if name in p["A"] and name in p["B"] and p["A"][name] > 0]
        rows.append({
            "quantity": name, "criterion": bool(CRITERION.search(name)),
            "a": statistics.median(a) if a else None,
            "b": statistics.median(b) if b else None,
            "ratio": statistics.median(ratios) if ratios else None,
            "lo": min(ratios, default=None), "hi": max(ratios, default=None),
            "n": len(ratios)})
    return rows


def _fmt(value: float | None, digits: int = 2) -> str:
    return "—" if value is None else f"{value:.{digits}f}"


def report(rows, meta: dict) -> str:
    lines = [f"### A/B: {meta['a']} → {meta['b']}", ""]
    if meta["quick"]:
        lines += ["**QUICK MODE** (`--quick`): short runs, one repeat each — a smoke test "
                  "of the script, not a measurement.", ""]
    if not meta["quiet"] and meta["clock"] == "wall":
        lines += [f"**WARNING: not quiet cores** — 1-minute load average above "
                  f"{QUIET_LOAD_PER_CPU} per CPU (see below): report only.", ""]
    load = meta["load"]
    lines += [
        f"- date: {meta['start']} – {meta['end']} UTC ({meta['minutes']:.1f} min)",
        f"- machine: {meta['cpu']}, {meta['cpus']} CPUs; Python "
        f"{sys.version.split()[0]} ({sys.executable})",
        f"- 1-minute load average: {load[0]:.2f} at start, {load[-1]:.2f} at end "
        f"(after the runs: {min(load):.2f}–{max(load):.2f}; this benchmark itself adds "
        f"about 1)",
        f"- A = {meta['a']}; B = {meta['b']}",
        f"- {meta['pairs']} pair{'s' if meta['pairs'] != 1 else ''} after one warm-up run "
        f"per side, order AB, BA, AB, …; each script a process of its own side, one "
        f"BLAS/OpenMP thread, no disk cache, own Numba cache per checkout",
        f"- clock: {CLOCKS[meta['clock']]}",
        f"- command: `{meta['command']}`",
    ]
    lines += [*(f"- {note}" for note in meta["notes"]), ""]
    lines += ["| quantity (µs per step; bold: the criterion) | A median | B median | "
              "B/A, median of pairs | B/A min–max | pairs |",
              "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        name = f"**{r['quantity']}**" if r["criterion"] else r["quantity"]
        ratio = _fmt(r["ratio"], 3)
        ratio = f"**{ratio}**" if r["criterion"] and r["ratio"] is not None else ratio
        lines.append(f"| {name} | {_fmt(r['a'])} | {_fmt(r['b'])} | {ratio} | "
                     f"{_fmt(r['lo'], 3)}–{_fmt(r['hi'], 3)} | {r['n']} |")
    bar = meta["bar"]
    over = [r["quantity"] for r in rows if r["criterion"] and r["ratio"] is not None
            and r["ratio"] > bar]
    verdict = ("met: every bold row's B/A ≤ " + f"{bar:.2f}" if not over
               else f"NOT met: B/A > {bar:.2f} for " + "; ".join(over))
    noisy = not meta["quiet"] and meta["clock"] == "wall"
    if meta["quick"] or noisy:
        verdict += " — information only (" + ("quick mode" if meta["quick"] else
                                               "not quiet cores") + ")"
    lines += ["", f"Criterion (B's µs per step within +{100 * (bar - 1):.0f} % of A's, "
              f"median of the paired ratios): {verdict}."]
    return "\n".join(lines)


# ---------------------------------------------------------------- main

def parse_args(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a", required=True, help="base: git revision or checkout folder")
    ap.add_argument("--b", default=str(REPO),
                    help="git revision or checkout folder (default: this checkout)")
    ap.add_argument("--pairs", type=int, default=5, help="A/B pairs (default 5)")
    ap.add_argument("--clock", choices=tuple(CLOCKS), default="wall",
                    help="wall: elapsed time (needs quiet cores); cpu: the processes' CPU "
                         "time (default: wall)")
    ap.add_argument("--bar", type=float, default=BAR,
                    help=f"the criterion: B/A at most this (default {BAR})")
    ap.add_argument("--quick", action="store_true", help="short runs: a smoke test")
    ap.add_argument("--json", type=Path, help="also write every run's figures here")
    return ap.parse_args(argv)


def clock_shim(clock: str) -> Path | None:
    """For ``--clock cpu``, a new folder whose ``sitecustomize`` makes the child's
    ``time.perf_counter`` read CPU time (removed when this process ends); None for the wall
    clock."""
    if clock == "wall":
        return None
    shim = Path(tempfile.mkdtemp(prefix="rubdiag-ab-clock-"))
    atexit.register(shutil.rmtree, shim, ignore_errors=True)
    (shim / "sitecustomize.py").write_text(CPU_CLOCK_SHIM, encoding="utf-8")
    return shim


def run(args: argparse.Namespace) -> int:
    if args.pairs < 1:
        raise ValueError(f"--pairs = {args.pairs} is out of range (allowed: >= 1)")
    if not args.bar >= 1.0:
        raise ValueError(f"--bar = {args.bar} is out of range (allowed: >= 1)")
    shim = clock_shim(args.clock)
    start_load = os.getloadavg()[0]
    started = time.time()
    notes = []
    if "NUMBA_CACHE_DIR" in os.environ:
        notes.append(f"NUMBA_CACHE_DIR={os.environ['NUMBA_CACHE_DIR']} is set here; "
                     "dropped for the runs")
    sides = {"A": resolve_side("A", args.a), "B": resolve_side("B", args.b)}
    if sides["A"].root == sides["B"].root:
        notes.append("A and B are the same checkout: an A/A run (the noise)")
    other = {"A": sides["B"], "B": sides["A"]}
    scripts = {(s, b.script): script_for(sides[s], other[s], b)
               for s in sides for b in BENCHES}
    for s, side in sides.items():
        check_imports(side, [scripts[s, b.script] for b in BENCHES])
    notes += [f"{s} runs {path}" for (s, name), path in scripts.items()
              if sides[s].root not in path.parents]

    def log(msg: str) -> None:
        print(f"[{time.strftime('%H:%M:%S', time.gmtime())}] {msg}", file=sys.stderr,
              flush=True)

    # warm-up: compiles into each checkout's __pycache__, and checks the outputs parse
    for s in ("A", "B"):
        for bench in BENCHES:
            _, _, wall = run_bench(sides[s], scripts[s, bench.script], bench, quick=True,
                                   shim=shim)
            log(f"warm-up {s} {bench.script}: {wall:.1f} s")
    loads = [start_load]
    pairs: list[dict] = []
    work = {"A": {}, "B": {}}
    for i in range(args.pairs):
        order = ("A", "B") if i % 2 == 0 else ("B", "A")
        pair = {"order": "".join(order), "A": {}, "B": {}, "wall_s": {}}
        for bench in BENCHES:
            for s in order:
                times, done, wall = run_bench(sides[s], scripts[s, bench.script], bench,
                                              args.quick, shim)
                pair[s].update(times)
                work[s].update(done)
                pair["wall_s"][f"{s} {bench.script}"] = wall
                loads.append(os.getloadavg()[0])
                log(f"pair {i + 1}/{args.pairs} {s} {bench.script}: {wall:.1f} s, load "
                    f"{loads[-1]:.2f}")
        pairs.append(pair)
    # same work on both sides (steps, Newton iterations of the last pair): else say so
    differ = [f"{k}: A {work['A'][k]:g}, B {work['B'].get(k, float('nan')):g}"
              for k in work["A"] if work["B"].get(k) != work["A"][k]]
    if differ:
        notes.append("the sides did different work: " + "; ".join(differ))
    elif work["A"]:
        notes.append("same work on both sides (bench_breakdown's steps and Newton "
                     "iterations per step)")
    cpus = n_cpus()
    # the end load includes this benchmark's own process (≈ 1 runnable)
    quiet = (start_load <= QUIET_LOAD_PER_CPU * cpus
             and loads[-1] - 1 <= QUIET_LOAD_PER_CPU * cpus)
    command = shlex.join([os.path.relpath(sys.executable, REPO)
                          if sys.executable.startswith(str(REPO)) else sys.executable,
                          os.path.relpath(Path(__file__).resolve(), REPO),
                          *sys.argv[1:]])
    meta = {"a": sides["A"].label, "b": sides["B"].label, "quick": args.quick,
            "quiet": quiet, "load": loads, "cpu": cpu_model(), "cpus": cpus,
            "pairs": args.pairs, "command": command, "notes": notes,
            "clock": args.clock, "bar": args.bar,
            "start": time.strftime("%Y-%m-%d %H:%M", time.gmtime(started)),
            "end": time.strftime("%H:%M", time.gmtime()),
            "minutes": (time.time() - started) / 60}
    rows = summarise(pairs)
    print(report(rows, meta))
    if args.json is not None:
        args.json.write_text(json.dumps({"meta": meta, "pairs": pairs, "summary": rows},
                                        indent=1, ensure_ascii=False), encoding="utf-8")
    return 0


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        return run(args)
    except ValueError as err:
        print(f"ab_compare.py: {err}", file=sys.stderr)
        return 2
    except RuntimeError as err:
        print(f"ab_compare.py: {err}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
