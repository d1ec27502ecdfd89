"""Benchmarks of rubdiag's import and linear (modal) analysis of the paper rig.

(a) ``import rubdiag``: the cumulative time of the ``rubdiag`` line of
    ``python -X importtime -c "import rubdiag"`` (median over fresh interpreters), and the
    heavy numerical modules that ``import rubdiag`` loads (checked in ``sys.modules`` of a
    fresh interpreter; there should be none). Bar: < 0.5 s and none.
    For information, the same for ``import rubdiag.modal`` (which does load NumPy/SciPy).
(b) ``assemble(paper_rig())`` + ``critical_speeds(model, n=2)`` after imports, with
    ``paper_rig.cache_clear()`` before each run so that the TOML preset is parsed and
    validated again. Bar: < 2 s (median).
(c) The Campbell diagram of the paper rig (41 speeds 0-8000 rpm, 8 modes, as
    ``rubdiag campbell``) and the linear unbalance response (400 speeds up to 8000 rpm,
    case 1, disc node 11 y, as ``rubdiag unbalance``), each on a freshly assembled model
    (assembly not timed).

Usage::

    .venv/bin/python benchmarks/bench_modal.py [--repeat N]

``--repeat N`` sets the number of runs of every measurement (default: 5 for (a), 7 for
(b), 3 for (c)); medians are reported. ``--threads N`` limits the BLAS/OpenMP thread pools
(threadpoolctl) for (b) and (c): on a small shared machine the default (one OpenBLAS thread
per CPU) spins against other processes and can make these runs several times slower.
Exit status 1 when a bar is missed.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import time

from _threads import cpu_model, limit_threads  # benchmarks/ is on sys.path as a script

HEAVY = ("numpy", "scipy", "pandas", "numba", "matplotlib", "sklearn", "pyarrow")
IMPORT_BAR_S = 0.5
CRITICAL_BAR_S = 2.0
MAX_RPM, N_CAMPBELL, N_MODES, N_UNBALANCE = 8000.0, 41, 8, 400


def import_time_us(module: str) -> int:
    """Cumulative µs of ``module``'s own line in ``-X importtime``, fresh interpreter."""
    proc = subprocess.run([sys.executable, "-X", "importtime", "-c", f"import {module}"],
                          capture_output=True, text=True, check=True)
    for line in proc.stderr.splitlines():
        if not line.startswith("import time:"):
            continue
        parts = line.split("|")
        if len(parts) == 3 and parts[2].strip() == module and not parts[2][1:].startswith(" "):
            return int(parts[1])
    raise RuntimeError(f"no importtime line for {module!r}:\n{proc.stderr[-2000:]}")


def heavy_modules_loaded(module: str) -> list[str]:
    """Top-level heavy packages in ``sys.modules`` after ``import module`` (fresh)."""
    code = (f"import sys, json; import {module}; "
            f"print(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}} & "
            f"set({list(HEAVY)!r}))))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    return json.loads(proc.stdout)


def timed(fn, repeat: int) -> tuple[float, list[float]]:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=None,
                        help="runs per measurement (default 5 import, 7 critical speeds, "
                        "3 Campbell and unbalance)")
    parser.add_argument("--threads", type=int, default=None,
                        help="limit BLAS/OpenMP threads for (b) and (c) (default: library "
                        "default, usually one per CPU)")
    args = parser.parse_args(argv)
    if args.repeat is not None and args.repeat < 1:
        parser.error("--repeat must be >= 1")
    if args.threads is not None and args.threads < 1:
        parser.error("--threads must be >= 1")
    n_import, n_crit, n_sweep = ((args.repeat,) * 3 if args.repeat else (5, 7, 3))

    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    print(f"{now}; {os.cpu_count()} CPUs ({cpu_model()}); Python "
          f"{platform.python_version()} ({sys.executable})")

    # (a) import ----------------------------------------------------------------------
    imp = [import_time_us("rubdiag") for _ in range(n_import)]
    imp_modal = [import_time_us("rubdiag.modal") for _ in range(n_import)]
    heavy = heavy_modules_loaded("rubdiag")
    heavy_modal = heavy_modules_loaded("rubdiag.modal")

    # (b), (c) after imports -----------------------------------------------------------
    import numpy as np

    from rubdiag.assembly import assemble
    from rubdiag.modal import campbell, critical_speeds, unbalance_response
    from rubdiag.model import paper_rig

    print(f"thread pools for (b), (c): {limit_threads(args.threads)}")

    rpm = np.pi / 30.0
    found = {}

    def critical():
        paper_rig.cache_clear()
        model = assemble(paper_rig())
        found["critical"] = critical_speeds(model, n=2)
        found["n_dof"] = model.n_dof

    t_crit, crit_runs = timed(critical, n_crit)

    def sweep(kind):
        runs = []
        for _ in range(n_sweep):
            model = assemble(paper_rig())
            t0 = time.perf_counter()
            if kind == "campbell":
                result = campbell(model, np.linspace(0.0, MAX_RPM * rpm, N_CAMPBELL),
                                  n_modes=N_MODES)
                found["campbell"] = result.frequencies.shape
            else:
                speeds = np.linspace(MAX_RPM * rpm / N_UNBALANCE, MAX_RPM * rpm, N_UNBALANCE)
                result = unbalance_response(model, speeds, model.rig.unbalance(1),
                                            points=((11, "y"),))
                found["peak_rpm"] = result.peak_speed() / rpm
            runs.append(time.perf_counter() - t0)
        return statistics.median(runs), runs

    t_campbell, campbell_runs = sweep("campbell")
    t_unbalance, unbalance_runs = sweep("unbalance")

    # report ----------------------------------------------------------------------------
    t_imp = statistics.median(imp) * 1e-6
    ok_import = t_imp < IMPORT_BAR_S and not heavy
    ok_crit = t_crit < CRITICAL_BAR_S
    crit_rpm = ", ".join(f"{c / rpm:.1f}" for c in found["critical"])
    rows = [
        ("import rubdiag (-X importtime, cumulative)", f"{t_imp * 1e3:.2f} ms", n_import,
         f"< {IMPORT_BAR_S * 1e3:.0f} ms", "PASS" if t_imp < IMPORT_BAR_S else "FAIL"),
        ("heavy modules loaded by import rubdiag", ", ".join(heavy) or "none", 1, "none",
         "PASS" if not heavy else "FAIL"),
        ("import rubdiag.modal (information)",
         f"{statistics.median(imp_modal) * 1e-3:.0f} ms", n_import, "-", "-"),
        (f"assemble(paper_rig()) + critical_speeds(n=2) [{found['n_dof']} DOF]",
         f"{t_crit * 1e3:.1f} ms", n_crit, f"< {CRITICAL_BAR_S:.0f} s",
         "PASS" if ok_crit else "FAIL"),
        (f"campbell: {N_CAMPBELL} speeds x {N_MODES} modes", f"{t_campbell * 1e3:.0f} ms",
         n_sweep, "-", "-"),
        (f"unbalance_response: {N_UNBALANCE} speeds", f"{t_unbalance * 1e3:.0f} ms", n_sweep,
         "-", "-"),
    ]
    width = max(len(r[0]) for r in rows)
    print()
    print(f"{'measurement':<{width}}  {'median':>12}  {'runs':>4}  {'bar':>8}  status")
    for name, value, runs, bar, status in rows:
        print(f"{name:<{width}}  {value:>12}  {runs:>4}  {bar:>8}  {status}")
    print()
    print(f"import rubdiag.modal loads: {', '.join(heavy_modal) or 'none'}")
    print(f"critical speeds (rpm): {crit_rpm}; Campbell array {found['campbell']}; "
          f"unbalance case 1 peak at {found['peak_rpm']:.0f} rpm")
    print("all runs (ms): critical " + " ".join(f"{t * 1e3:.1f}" for t in crit_runs)
          + "; campbell " + " ".join(f"{t * 1e3:.0f}" for t in campbell_runs)
          + "; unbalance " + " ".join(f"{t * 1e3:.0f}" for t in unbalance_runs)
          + "; import rubdiag (µs) " + " ".join(str(t) for t in imp))
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"load average {load} (1, 5, 15 min): other processes on this machine inflate "
          "the timings")
    return 0 if ok_import and ok_crit else 1


if __name__ == "__main__":
    sys.exit(main())
