"""The files that hold a dataset's rows, written atomically and read so that a damaged one
is a one-line error naming it.

Two kinds (their place in the folder: :mod:`rubdiag.dataset._store`):

* a **journal row** — one finished run's row, JSON (``json`` writes a float's shortest
  repr, which reads back bit for bit; NaN and ±inf included), written the moment the row
  arrives: the encoding takes ≈ 0.5 ms however many columns and the flush to disk most of
  the rest, where a one-row Parquet file of the ≈ 870 columns of a default design costs
  10× more (per-column overhead; ``benchmarks/bench_store.py``);
* a **chunk** — many rows in one Parquet file (zstd, page checksums, so that a flipped
  byte is an error rather than a wrong value), what ``pandas.read_parquet`` reads.

Every file is written to a hidden temporary file beside it, flushed to disk and renamed
(atomic on POSIX and Windows): a file is either complete or absent whenever the process
is killed. A file damaged anyway (a disk or power failure, a copy cut short, a hand edit)
raises :class:`UnreadableFile`, a ``ValueError`` whose one-line message names the file.
"""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from rubdiag._atomic import write_bytes

__all__ = ["UnreadableFile", "read_chunk", "read_journal_row", "row_schema", "write_chunk",
           "write_journal_row"]

#: Columns every row has: a file without them is not a chunk of a dataset.
_NEEDED = ("run_id", "status")


class UnreadableFile(ValueError):
    """A chunk or journal row that cannot be read: ``path``, ``reason`` and what to do
    (``advice``), in one line."""

    def __init__(self, path: Path, reason: str, advice: str = ""):
        super().__init__(f"{path}: unreadable ({reason})" + (f"; {advice}" if advice else ""))
        self.path, self.reason = Path(path), reason


def row_schema(row: dict) -> pa.Schema:
    """The Arrow types of a row's values (a null is a string: a failed row's empty cells)."""
    def kind(value):
        if isinstance(value, bool):
            return pa.bool_()
        if isinstance(value, int):
            return pa.int64()
        if isinstance(value, float):
            return pa.float64()
        return pa.string()

    return pa.schema([(name, kind(value)) for name, value in row.items()])


# --- chunks -------------------------------------------------------------------------------
def write_chunk(path: Path, rows: list[dict], schema: pa.Schema) -> None:
    """``rows`` as one Parquet file (a row's missing columns are nulls)."""
    table = pa.Table.from_pylist(rows, schema=schema)
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression="zstd", write_page_checksum=True)
    write_bytes(path, sink.getvalue().to_pybytes())


def read_chunk(path: Path, columns: list[str] | None = None) -> pa.Table:
    """A chunk's rows (or some of its columns), every page checked; :class:`UnreadableFile`
    for an empty, truncated, garbled or foreign file."""
    try:
        table = pq.read_table(path, columns=columns, page_checksum_verification=True)
    except (FileNotFoundError, PermissionError, IsADirectoryError):
        raise                      # the file system's answer, not the file's content
    except (pa.ArrowException, OSError, ValueError) as exc:
        raise UnreadableFile(path, _reason(exc)) from None
    missing = [name for name in _NEEDED if name not in table.column_names
               and (columns is None or name in columns)]
    if missing:
        raise UnreadableFile(path, f"no {' and '.join(missing)} column: not a dataset chunk")
    return table


def _reason(exc: Exception) -> str:
    """pyarrow's message, first sentence, without the path it repeats."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    if text.startswith("Could not open Parquet input source"):
        text = text.split("': ", 1)[-1]
    return text.split(". ", 1)[0].rstrip(".")


# --- journal rows -----------------------------------------------------------------------------
def write_journal_row(path: Path, row: dict) -> None:
    write_bytes(path, json.dumps(row, allow_nan=True).encode("utf-8"))


def read_journal_row(path: Path) -> dict:
    """One journal row; :class:`UnreadableFile` for an empty, truncated or garbled file."""
    try:
        row = json.loads(path.read_bytes())
    except ValueError as exc:            # JSONDecodeError, UnicodeDecodeError
        raise UnreadableFile(path, f"not a JSON row: {str(exc).splitlines()[0]}") from None
    if not isinstance(row, dict) or any(name not in row for name in _NEEDED):
        raise UnreadableFile(path, "no run_id and status: not a dataset row")
    return row
