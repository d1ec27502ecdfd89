"""Make a dataset: run a design's runs in parallel and write their rows as they come.

Workers (local processes, or Dask workers) get run descriptions and return rows; only this
process writes, so Dask workers need no shared disk. Each row is stored the moment it
arrives, before the progress counts it (the folder's journal,
:mod:`rubdiag.dataset._store`), and the journal is moved into a Parquet chunk every
``chunk_rows`` rows or ``flush_s`` seconds and when the job ends: a job killed at any moment
loses only the runs in flight, and the same call then resumes, running only what is not
stored yet. A resume first sets aside the chunks that cannot be read (their runs run again).
"""

from __future__ import annotations

import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from rubdiag import _check, _progress
from rubdiag.dataset._card import write_card
from rubdiag.dataset._chunks import row_schema
from rubdiag.dataset._design import Design
from rubdiag.dataset._rows import make_row_and_waveforms
from rubdiag.dataset._store import DatasetFolder, write_waveforms

__all__ = ["GenerateSummary", "generate", "pending_runs"]


class GenerateSummary(dict):
    """What a :func:`generate` call did: ``total``, ``stored_before``, ``run``, ``ok``,
    ``failed`` (this call), ``wall_s``, ``out``, ``set_aside`` (the unreadable files moved
    into ``out/broken``, as ``(from, to)`` paths)."""


def pending_runs(design: Design, out: str | Path, retry_failed: bool = False,
                 runs: list | None = None) -> list:
    """The runs of ``design`` not stored in ``out`` yet (and, with ``retry_failed``, those
    stored with a status other than ``ok``); the runs of an unreadable chunk count as not
    stored (:func:`generate` sets it aside and runs them again). ``runs``: ``design.runs()``
    when the caller has it.

    Parameters
    ----------
    design : Design
        The design.
    out : str or Path
        The dataset folder.
    retry_failed : bool
        Count the runs stored with a failure as pending.
    runs : list of DesignRun or None
        ``design.runs()``, when the caller has it.

    Returns
    -------
    list of DesignRun
        The runs still to make, in design order.
    """
    stored = DatasetFolder(out).stored_status(skip_unreadable=True)
    return _pending(design.runs() if runs is None else runs, stored, retry_failed)


def _pending(items, stored: dict[str, str], retry_failed: bool) -> list:
    return [item for item in items
            if item.run_id not in stored or (retry_failed and stored[item.run_id] != "ok")]


def generate(design: Design, out: str | Path, *, jobs: int | None = None, client=None,
             progress: bool = True, run_timeout_s: float | None = None,
             retry_failed: bool = False, waveforms: bool = False, chunk_rows: int = 32,
             flush_s: float = 30.0) -> GenerateSummary:
    """Simulate, label and describe every run of ``design`` into the folder ``out``.

    ``jobs``: local worker processes (default: all cores); ``client``: a
    ``dask.distributed.Client`` to send the runs to instead (its workers are first compared
    with this process, :mod:`rubdiag.dataset._workers`: those on other BLAS kernels are
    restarted on this process's; any other difference is a ValueError). ``run_timeout_s``:
    wall-time limit of one run (a run over it becomes a ``timeout`` row). ``retry_failed``:
    run again the runs stored with a failure. ``waveforms``: also store each run's measured
    channels (:func:`rubdiag.dataset.load_waveforms`). Resumes: runs already stored are not
    run again.

    Each row is stored when it arrives, whatever ``chunk_rows`` and ``flush_s``: they say
    how often the stored rows are moved into a Parquet chunk (every ``chunk_rows`` rows or
    ``flush_s`` seconds, and at the end), i.e. how far ``pandas.read_parquet(out /
    "features")`` may lag behind a running job, and how large the chunks are. An unreadable
    chunk or journal row (a disk or a copy failed) is moved into ``out/broken`` with a
    warning naming it, and its runs run again. Returns a :class:`GenerateSummary`;
    :func:`rubdiag.dataset.load` reads the rows.

    Parameters
    ----------
    design : Design
        The runs to make.
    out : str or Path
        The dataset folder (created, or resumed).
    jobs : int or None
        Local worker processes.
    client : dask.distributed.Client or None
        A cluster to run on.
    progress : bool
        Show a progress bar on stderr.
    run_timeout_s : float or None
        Wall-time limit of one run (s).
    retry_failed : bool
        Run again the runs stored with a failure.
    waveforms : bool
        Store each run's measured channels.
    chunk_rows : int
        Rows per Parquet chunk.
    flush_s : float
        Longest time between chunks (s).

    Returns
    -------
    GenerateSummary
        What the call did (its keys above).
    """
    if not isinstance(design, Design):
        raise _check.wrong_type("design", design, "a Design, e.g. Design.from_toml(path)")
    if client is None:
        jobs = (os.cpu_count() or 1) if jobs is None else _check.integer("jobs", jobs, lo=1)
    elif jobs is not None:
        raise ValueError("jobs and client exclude each other (allowed: one of them)")
    if run_timeout_s is not None:
        run_timeout_s = _check.positive("run_timeout_s", run_timeout_s, "s")
    chunk_rows = _check.integer("chunk_rows", chunk_rows, lo=1)
    flush_s = _check.positive("flush_s", flush_s, "s")

    toml = design.to_toml()
    folder = DatasetFolder(out)
    folder.check_writable(toml)
    # every run checked before any is made; what they refer to computed on the local cores
    items = design.runs(jobs=jobs or os.cpu_count() or 1)
    folder.create(toml, _acquisition(design, items))
    set_aside = folder.set_aside_unreadable()
    for source, target, why in set_aside:
        warnings.warn(f"{source}: unreadable ({why}); moved to {target}, its runs run again",
                      stacklevel=2)
    folder.compact(final=True)          # what a killed job left in the journal
    stored = folder.stored_status()
    todo = _pending(items, stored, retry_failed)
    retried = {item.run_id for item in todo if item.run_id in stored}

    start = time.perf_counter()
    writer = _Writer(folder, chunk_rows, flush_s, retried)
    bar = _Progress(len(todo), len(items) - len(todo), enabled=progress)
    args = (design.labels, design.noise, run_timeout_s, waveforms)
    results = _run_local(todo, jobs, args) if client is None else \
        _run_dask(todo, client, args)
    try:
        for row, waves in results:
            if waves is not None:     # before the row: a stored row has its waveforms
                write_waveforms(folder.root, row["run_id"], waves, design)
            writer.add(row)
            bar.update(row["status"] == "ok")
    finally:
        writer.compact(final=True)
        bar.close()
    write_card(folder, design)
    return GenerateSummary(total=len(items), stored_before=len(items) - len(todo),
                           run=len(todo), ok=bar.ok, failed=bar.failed,
                           wall_s=time.perf_counter() - start, out=str(folder.root),
                           set_aside=[(str(a), str(b)) for a, b, _ in set_aside])


# --- executors ----------------------------------------------------------------------------
def _start_worker() -> None:
    from rubdiag.dataset._workers import start_local_worker

    start_local_worker()


def _task(item, labels, noise, timeout, waveforms) -> tuple[dict, dict | None]:
    """What a worker does for one run: its row, and its waveforms when asked for."""
    row, waves = make_row_and_waveforms(item, labels, noise, timeout)
    return row, waves if waveforms else None


def _acquisition(design: Design, items) -> dict:
    meta = {"fs_hz": 1.0 / items[0].run.output_dt_s,
            "window_s": min(item.run.duration_s for item in items) - design.discard_s,
            "discard_s": design.discard_s,
            "sensors": [{"name": s.name, "point": s.point, "direction": s.direction,
                         "quantity": s.quantity, "unit": s.unit} for s in design.sensors]}
    if design.ramp is not None:
        meta["ramp"] = design.ramp.to_dict()
    return meta


def _run_local(todo, jobs, args) -> Iterable[tuple]:
    if not todo:
        return
    if jobs == 1:
        for item in todo:
            yield _task(item, *args)
        return
    with ProcessPoolExecutor(max_workers=min(jobs, len(todo)),
                             initializer=_start_worker) as pool:
        futures = [pool.submit(_task, item, *args) for item in todo]
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:
            for future in futures:
                future.cancel()


def _run_dask(todo, client, args) -> Iterable[tuple]:
    from distributed import as_completed as dask_completed

    from rubdiag.dataset._workers import align_dask_workers

    if not todo:
        return
    align_dask_workers(client)      # their rows are this process's bits, or a ValueError
    futures = [client.submit(_task, item, *args, key=f"rubdiag-run-{item.run_id}",
                             pure=False) for item in todo]
    try:
        for future in dask_completed(futures):
            yield future.result()
            future.release()
    finally:
        client.cancel(futures)


# --- writing --------------------------------------------------------------------------------
class _Writer:
    """Each row into the folder's journal as it arrives (stored before the progress
    counts it), the journal into a chunk every ``chunk_rows`` rows or ``flush_s`` seconds.
    The first successful row fixes the columns (failed rows alone do not know the feature
    columns, so they wait in the journal for it, or for the end)."""

    def __init__(self, folder: DatasetFolder, chunk_rows: int, flush_s: float,
                 retried: set[str]):
        self.folder, self.chunk_rows, self.flush_s = folder, chunk_rows, flush_s
        self.retried = retried            # run ids whose old rows are in older chunks
        self.schema = folder.schema()
        self.waiting = 0                  # rows in the journal
        self.last = time.monotonic()

    def add(self, row: dict) -> None:
        if self.schema is None and row["status"] == "ok":
            self.schema = row_schema(row)
            self.folder.set_schema(self.schema)
        self.folder.journal(row)
        self.waiting += 1
        if self.schema is not None and (self.waiting >= self.chunk_rows
                                        or time.monotonic() - self.last >= self.flush_s):
            self.compact()

    def compact(self, final: bool = False) -> None:
        self.folder.compact(final, stored=self.retried)
        self.waiting, self.last = 0, time.monotonic()


# --- progress -------------------------------------------------------------------------------
class _Progress:
    """Runs done, counted once their rows are stored, on stderr: on a terminal a bar with an
    ETA (:mod:`rubdiag._progress`; the failed runs beside it); elsewhere a line per finished
    run, ``done / failed / remaining, ETA``, so that a log shows what is stored."""

    def __init__(self, total: int, skipped: int, enabled: bool = True,
                 stream=None, clock: Callable[[], float] = time.monotonic):
        self.total, self.skipped, self.enabled = total, skipped, enabled and total > 0
        self.stream = sys.stderr if stream is None else stream
        self.clock, self.start = clock, clock()
        self.ok = self.failed = 0
        self.tty = getattr(self.stream, "isatty", lambda: False)()
        if self.enabled and skipped:
            print(f"{skipped} runs already stored, {total} to run", file=self.stream)
        self.bar = _progress.bar(total, "dataset", "run", self.enabled and self.tty,
                                 self.stream)

    def update(self, ok: bool) -> None:
        self.ok += ok
        self.failed += not ok
        if not self.enabled:
            return
        if self.tty:
            if self.failed:
                _progress.label(self.bar, f"{self.failed} failed")
            self.bar.update(1)
        else:
            print(self.line(), file=self.stream, flush=True)

    def line(self) -> str:
        done = self.ok + self.failed
        elapsed = self.clock() - self.start
        eta = elapsed / done * (self.total - done) if done else math.nan
        return (f"{done}/{self.total} done, {self.failed} failed, {self.total - done} "
                f"remaining, ETA {_clock(eta)}")

    def close(self) -> None:
        self.bar.close()


def _clock(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "--:--"
    seconds = round(seconds)
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"
