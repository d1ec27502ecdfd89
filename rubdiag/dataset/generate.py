"""Make a dataset: run a design's runs in parallel and write their rows as they come.

Workers (local processes, or Dask workers) get run descriptions and return rows; only this
process writes, so Dask workers need no shared disk. Rows are written in chunks
(:mod:`rubdiag.dataset.store`) at least every ``chunk_rows`` rows or ``flush_s`` seconds,
so a killed job loses at most the runs in flight and the last unwritten rows; the same
call then resumes, running only what is not stored yet.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import pyarrow as pa

from rubdiag import _check
from rubdiag.dataset.card import write_card
from rubdiag.dataset.design import Design
from rubdiag.dataset.rows import make_row_and_waveforms
from rubdiag.dataset.store import DatasetFolder, write_waveforms

__all__ = ["GenerateSummary", "generate", "pending_runs"]


class GenerateSummary(dict):
    """What a :func:`generate` call did: ``total``, ``stored_before``, ``run``, ``ok``,
    ``failed`` (this call), ``wall_s``, ``out``."""


def pending_runs(design: Design, out: str | Path, retry_failed: bool = False) -> list:
    """The runs of ``design`` not stored in ``out`` yet (and, with ``retry_failed``, those
    stored with a status other than ``ok``)."""
    return _pending(design.runs(), DatasetFolder(out).stored_status(), retry_failed)


def _pending(items, stored: dict[str, str], retry_failed: bool) -> list:
    return [item for item in items
            if item.run_id not in stored or (retry_failed and stored[item.run_id] != "ok")]


def generate(design: Design, out: str | Path, *, jobs: int | None = None, client=None,
             progress: bool = True, run_timeout_s: float | None = None,
             retry_failed: bool = False, waveforms: bool = False, chunk_rows: int = 32,
             flush_s: float = 30.0) -> GenerateSummary:
    """Simulate, label and describe every run of ``design`` into the folder ``out``.

    ``jobs``: local worker processes (default: all cores); ``client``: a
    ``dask.distributed.Client`` to send the runs to instead. ``run_timeout_s``: wall-time
    limit of one run (a run over it becomes a ``timeout`` row). ``retry_failed``: run again
    the runs stored with a failure. ``waveforms``: also store each run's measured channels
    (:func:`rubdiag.dataset.load_waveforms`). Resumes: runs already stored are not run again.
    Returns
    a :class:`GenerateSummary`; :func:`rubdiag.dataset.load` reads the rows.
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

    items = design.runs()                       # every run checked before any is made
    toml = design.to_toml()
    folder = DatasetFolder(out)
    folder.check_writable(toml)
    folder.create(toml, _acquisition(design, items))
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
        writer.flush(final=True)
        bar.close()
    write_card(folder, design)
    return GenerateSummary(total=len(items), stored_before=len(items) - len(todo),
                           run=len(todo), ok=bar.ok, failed=bar.failed,
                           wall_s=time.perf_counter() - start, out=str(folder.root))


# --- executors ----------------------------------------------------------------------------
def _start_worker() -> None:
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1)


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

    if not todo:
        return
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
    """Rows into chunks; failed rows wait for the first success, which fixes the columns
    (a chunk of failures alone would not know the feature columns)."""

    def __init__(self, folder: DatasetFolder, chunk_rows: int, flush_s: float,
                 retried: set[str]):
        self.folder, self.chunk_rows, self.flush_s = folder, chunk_rows, flush_s
        self.retried = retried
        self.schema = folder.schema()
        self.buffer: list[dict] = []
        self.last = time.monotonic()

    def add(self, row: dict) -> None:
        if self.schema is None and row["status"] == "ok":
            self.schema = _schema_of(row)
            self.folder.set_schema(self.schema)
        self.buffer.append(row)
        if len(self.buffer) >= self.chunk_rows or time.monotonic() - self.last >= self.flush_s:
            self.flush()

    def flush(self, final: bool = False) -> None:
        if not self.buffer or (self.schema is None and not final):
            return
        schema = self.schema or _schema_of(self.buffer[0])
        path = self.folder.write_chunk(self.buffer, schema)
        done = {r["run_id"] for r in self.buffer} & self.retried
        if done:
            self.folder.drop_superseded(done, path)
        self.buffer, self.last = [], time.monotonic()


def _schema_of(row: dict) -> pa.Schema:
    def kind(value):
        if isinstance(value, bool):
            return pa.bool_()
        if isinstance(value, int):
            return pa.int64()
        if isinstance(value, float):
            return pa.float64()
        return pa.string()

    return pa.schema([(name, kind(value)) for name, value in row.items()])


# --- progress -------------------------------------------------------------------------------
class _Progress:
    """``done / failed / remaining, ETA`` on stderr: one updating line on a terminal, a
    line per 10 % otherwise."""

    def __init__(self, total: int, skipped: int, enabled: bool = True,
                 stream=None, clock: Callable[[], float] = time.monotonic):
        self.total, self.skipped, self.enabled = total, skipped, enabled and total > 0
        self.stream = sys.stderr if stream is None else stream
        self.clock, self.start = clock, clock()
        self.ok = self.failed = 0
        self.tty = getattr(self.stream, "isatty", lambda: False)()
        self.next_line = 0.1
        if self.enabled and skipped:
            print(f"{skipped} runs already stored, {total} to run", file=self.stream)

    def update(self, ok: bool) -> None:
        self.ok += ok
        self.failed += not ok
        if not self.enabled:
            return
        done = self.ok + self.failed
        if self.tty:
            print(f"\r{self.line()}", end="", file=self.stream, flush=True)
        elif done / self.total >= self.next_line or done == self.total:
            print(self.line(), file=self.stream, flush=True)
            self.next_line = math.floor(done / self.total * 10 + 1) / 10

    def line(self) -> str:
        done = self.ok + self.failed
        elapsed = self.clock() - self.start
        eta = elapsed / done * (self.total - done) if done else math.nan
        return (f"{done}/{self.total} done, {self.failed} failed, {self.total - done} "
                f"remaining, ETA {_clock(eta)}")

    def close(self) -> None:
        if self.enabled and self.tty:
            print(file=self.stream)


def _clock(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "--:--"
    seconds = round(seconds)
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"
