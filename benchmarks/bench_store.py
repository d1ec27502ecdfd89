"""Benchmark of the dataset writer's own time per row (every row is stored the
moment it arrives; that must cost at most 2 % of a 1.3-s reduced run).

Usage::

    .venv/bin/python benchmarks/bench_store.py [--rows 64] [--chunk-rows 32] [--dir DIR]

One real row first: the paper rig, case 1 at its critical speed, g0 = 1.9 mm, the reduced
model, 1.3 s simulated (0.3 s discarded), the default sensors (6 shaft probes and the
casing accelerometer: ≈ 870 columns), made by ``rubdiag.dataset._rows.make_row`` twice in
this process, as a dataset worker makes its runs (the first loads the kernels; the second's
``wall_s`` is the run the writer is measured against, the fixed ≤ 26 ms of the issue the
other). Then
``--rows`` copies of it under distinct run ids go through the writer of
``rubdiag.dataset.generate`` (``chunk_rows`` = ``--chunk-rows``, ``flush_s`` = 30 s) into a
fresh folder under ``--dir`` (default: the current folder — ``/tmp`` may be memory, where
flushing to disk costs nothing), one ``add`` at a time, each timed: a row into the journal
(JSON, written to a temporary file, flushed to disk, renamed), every ``chunk_rows`` rows the
journal moved into a Parquet chunk. Then the final compaction, timed too.

Reported: the median, 90th percentile and maximum of ``add``; the mean per row with every
compaction (the final one included) spread over the rows; both against the run's wall time.
For comparison, the median time of writing the same row as a one-row Parquet chunk (what a
chunk per row would cost) over the same number of rows. The load average (1 min) before
and after.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from _threads import cpu_model  # benchmarks/ is on sys.path as a script
from bench_dataset import git_commit

DESIGN = """
[base]
rig = "paper"
duration_s = 1.3
discard_s = 0.3
reduced = true

[sampling]
method = "grid"
replicates = 1

[factors]
case = [1]
speed_ratio = [1.0]
gap_mm = [1.9]
"""


def one_row() -> dict:
    from rubdiag.dataset import Design
    from rubdiag.dataset._rows import make_row

    design = Design.from_toml(DESIGN)
    item = design.runs()[0]
    make_row(item, design.labels, design.noise)          # warm-up: kernels, imports
    row = make_row(item, design.labels, design.noise)
    if row["status"] != "ok":
        raise SystemExit(f"the run failed: {row['status']}: {row['message']}")
    return row


def time_writer(row: dict, n: int, chunk_rows: int, root: Path) -> tuple[list, float, int]:
    """(seconds of each add, seconds of the final compaction, chunks written)."""
    from rubdiag.dataset._generation import _Writer as writer_class
    from rubdiag.dataset._store import DatasetFolder, load

    folder = DatasetFolder(root)
    folder.create(DESIGN)
    writer = writer_class(folder, chunk_rows, 30.0, retried=set())
    times = []
    for i in range(n):
        copy = dict(row, run_id=f"{i:016x}")
        start = time.perf_counter()
        writer.add(copy)
        times.append(time.perf_counter() - start)
    start = time.perf_counter()
    writer.compact(final=True)
    final = time.perf_counter() - start
    if len(load(root)) != n:
        raise SystemExit("the folder does not hold every row")
    return times, final, len(folder.chunk_paths())


def time_parquet_rows(row: dict, n: int, root: Path) -> list:
    from rubdiag.dataset._chunks import row_schema, write_chunk

    schema = row_schema(row)
    root.mkdir()
    times = []
    for i in range(n):
        start = time.perf_counter()
        write_chunk(root / f"part-{i:06d}.parquet", [dict(row, run_id=f"{i:016x}")], schema)
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", type=int, default=64, help="rows through the writer (>= 20)")
    parser.add_argument("--chunk-rows", type=int, default=32)
    parser.add_argument("--dir", type=Path, default=Path.cwd(),
                        help="where the temporary dataset folder goes")
    args = parser.parse_args()
    if args.rows < 20:
        parser.error("--rows must be >= 20 (a median of at least 20 rows)")

    import numpy as np
    import pyarrow

    row = one_row()
    run_s = row["wall_s"]
    work = Path(tempfile.mkdtemp(prefix="bench-store-", dir=args.dir))
    try:
        load_before = os.getloadavg()[0]
        adds, final, chunks = time_writer(row, args.rows, args.chunk_rows, work / "dataset")
        parquet = time_parquet_rows(row, args.rows, work / "parquet-rows")
        load_after = os.getloadavg()[0]
    finally:
        shutil.rmtree(work, ignore_errors=True)

    ms = 1e3
    median = statistics.median(adds)
    mean = (sum(adds) + final) / len(adds)
    print(f"bench_store {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, "
          f"{os.cpu_count()} CPUs ({cpu_model()}), Python {platform.python_version()}, "
          f"numpy {np.__version__}, pyarrow {pyarrow.__version__}, commit {git_commit()}; "
          f"load average {load_before:.2f} -> {load_after:.2f}; folder under {args.dir}")
    print(f"row: {len(row)} columns; the 1.3-s reduced run took {run_s:.2f} s wall "
          f"(its second in this process); {args.rows} rows, chunk_rows {args.chunk_rows}: "
          f"{chunks} chunks")
    print(f"writer per row: median {median * ms:.1f} ms "
          f"({median / run_s:.2%} of the run), p90 "
          f"{np.percentile(adds, 90) * ms:.1f} ms, max {max(adds) * ms:.1f} ms; "
          f"mean with every compaction {mean * ms:.1f} ms ({mean / run_s:.2%}); "
          f"final compaction {final * ms:.1f} ms")
    print(f"a one-row Parquet chunk instead: median {statistics.median(parquet) * ms:.1f} ms")


if __name__ == "__main__":
    main()
