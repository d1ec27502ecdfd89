"""What differs between a local worker and a Dask worker, and whether it changes a row's bits.

Usage::

    .venv/bin/python benchmarks/probe_dask_workers.py [--repeats 10]

Prints, for this process, a local worker (forked by ``generate``'s pool, with its
initializer) and a task on a 2-worker Dask ``LocalCluster``: the BLAS/OpenMP libraries with
their kernels and threads (threadpoolctl, inside the place a run is computed), whether the
CPU flushes subnormal results (FTZ) or inputs (DAZ) in that thread, the variables Dask's
nanny sets, and the thread. Then the candidates for last-bit differences, each made to vary
on purpose:

* hash seed: 4 runs of ``bench_dask_identity.design_toml`` made in processes with
  ``PYTHONHASHSEED`` 1, 2 and 6640 (Dask's), compared bit for bit;
* memory layout and thread: the path of a row after its simulation (anti-alias decimation,
  noise, features; ``perturbed_rows``) recomputed ``--repeats`` times per run, between
  allocations of random sizes (up to 2 MB, some kept, some freed: every temporary lands
  elsewhere), every other time in a second thread; in this process, and the same on a Dask
  worker, whose result is compared with this process's.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import random
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

HASH_SEEDS = ("1", "2", "6640")


def place() -> dict:
    """Where a run would be computed now: libraries, floating-point flags, variables."""
    import numpy as np
    from threadpoolctl import threadpool_info

    smallest = np.finfo(np.float64).smallest_normal
    subnormal = np.array([smallest / 4.0])
    return {"thread": threading.current_thread().name,
            "blas": sorted(f"{i['internal_api']} {i.get('architecture') or ''} "
                           f"{i['num_threads']} thread(s)".replace("  ", " ")
                           for i in threadpool_info()),
            "FTZ": bool((np.array([smallest]) * np.array([0.25]))[0] == 0.0),
            "DAZ": bool((subnormal * np.array([2.0]))[0] == 0.0),
            "environment": {k: os.environ.get(k) for k in
                            ("OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                             "MKL_NUM_THREADS", "MALLOC_TRIM_THRESHOLD_", "PYTHONHASHSEED")}}


def _local_place() -> dict:
    from concurrent.futures import ProcessPoolExecutor

    from rubdiag.dataset._generation import _start_worker

    with ProcessPoolExecutor(1, initializer=_start_worker) as pool:
        return pool.submit(place).result()


def _digest(values) -> str:
    return hashlib.sha256(b"".join(v.tobytes() for v in values)).hexdigest()[:12]


def perturbed_rows(items, repeats: int, seed: int = 0) -> tuple[list[str], int]:
    """The digest of each run's decimated signals and features, and how many of the
    ``repeats`` recomputations per run (between random allocations, every other one in a
    second thread) gave other bits."""
    import numpy as np
    from threadpoolctl import threadpool_limits

    from rubdiag.dataset._ids import noise_id
    from rubdiag.dataset._noise import NoiseFloors, add_noise, noise_seed
    from rubdiag.signal._table import prefixed_features
    from rubdiag.simulation import simulate

    def after_simulation(item, result) -> str:
        signals = result.sensor_signals()
        floors = {s.name: NoiseFloors().floor(s.quantity) for s in item.run.sensors}
        measured = add_noise(signals, floors, noise_seed(noise_id(item.run)))
        window = {k: v[result.window] for k, v in measured.items()}
        table = prefixed_features(window, result.fs, item.run.speed_rpm, separator="__")
        return _digest([*signals.values(), table.to_numpy(dtype=float)])

    rng, kept, other = random.Random(seed), [], [0]
    with threadpool_limits(limits=1):
        results = [(item, simulate(item.run)) for item in items]
        digests = [after_simulation(*pair) for pair in results]

        def again() -> None:
            for item_result, digest in zip(results, digests, strict=True):
                kept.extend(np.empty(rng.randrange(1, 2_000_000), np.uint8)
                            for _ in range(rng.randrange(30)))
                del kept[:rng.randrange(len(kept) + 1)]
                other[0] += after_simulation(*item_result) != digest

        for k in range(repeats):
            if k % 2:
                thread = threading.Thread(target=again)
                thread.start()
                thread.join()
            else:
                again()
    return digests, other[0]


def hash_seed_rows(items_toml: str) -> set[str]:
    """The digests of a design's rows made in processes with each of :data:`HASH_SEEDS`."""
    code = ("import rubdiag, sys, hashlib, numpy as np\n"
            "from rubdiag.dataset import Design, load, generate\n"
            "generate(Design.from_toml(sys.argv[1]), sys.argv[2], jobs=1, progress=False)\n"
            "rows = load(sys.argv[2]).sort_values('run_id')\n"
            "floats = [c for c in rows if rows[c].dtype.kind == 'f' and "
            "c not in ('wall_s', 'simulate_s')]\n"
            "print(hashlib.sha256(rows[floats].to_numpy().tobytes()).hexdigest()[:12])\n")
    found = set()
    with tempfile.TemporaryDirectory() as tmp:
        for seed in HASH_SEEDS:
            out = subprocess.run([sys.executable, "-c", code, items_toml, str(Path(tmp) / seed)],
                                 env={**os.environ, "PYTHONHASHSEED": seed}, check=True,
                                 capture_output=True, text=True).stdout.split()[-1]
            print(f"  PYTHONHASHSEED={seed}: rows {out}", flush=True)
            found.add(out)
    return found


def main(argv=None) -> int:
    import rubdiag

    rubdiag.pin_blas_kernels()    # first: before numpy loads OpenBLAS

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeats", type=int, default=10)
    args = p.parse_args(argv)

    import dask.distributed as dd
    from bench_dask_identity import design_toml  # benchmarks/ is on sys.path as a script

    from rubdiag.dataset import Design
    from rubdiag.dataset._workers import align_dask_workers, signature

    signature()                     # loads scipy.linalg's BLAS here too
    toml = design_toml(4, 0.6, 1)
    items = Design.from_toml(toml).runs()
    places = {"this process (not a worker)": place(), "local worker": _local_place()}
    environ = dict(os.environ)      # a LocalCluster leaves its workers' variables here
    try:
        with dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                             dashboard_address=None) as cluster, dd.Client(cluster) as client:
            align_dask_workers(client)          # as generate does before the first run
            places["Dask task"] = client.submit(place, pure=False).result()
            for name, where in places.items():
                print(f"{name}: {where}", flush=True)
            print(f"\nrecomputing the path after the simulation of {len(items)} runs "
                  f"{args.repeats} times each, between random allocations:", flush=True)
            here, other_here = perturbed_rows(items, args.repeats)
            there, other_there = client.submit(perturbed_rows, items, args.repeats, 1,
                                               pure=False).result()
    finally:
        os.environ.clear()
        os.environ.update(environ)
    print(f"  this process: {other_here} of {len(items) * args.repeats} differ")
    print(f"  Dask worker: {other_there} of {len(items) * args.repeats} differ; "
          f"{sum(a == b for a, b in zip(here, there, strict=True))} of {len(items)} runs "
          "the same bits as this process's")
    print("\nthe same runs' rows made under other hash seeds:", flush=True)
    seeds = hash_seed_rows(toml)
    print(f"  {len(seeds)} distinct row digest(s) over {len(HASH_SEEDS)} seeds")
    same = other_here == other_there == 0 and here == there and len(seeds) == 1
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
