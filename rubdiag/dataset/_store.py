"""A dataset folder that a crash cannot corrupt, and in which nothing finished is lost.

Layout of ``DIR``:

``design.toml``
    The resolved design (:meth:`Design.to_toml`); written first, atomically. A later job
    into the same folder must bring the same design.
``dataset.json``
    The format: ``schema_version`` (:data:`~rubdiag.dataset._schema.SCHEMA_VERSION`, the one
    the run ids were made with) and, once a run has succeeded, ``columns``: every column
    with its Arrow type, the same in every chunk.
``journal/row-NNNNNN.json``
    Each finished run's row, written the moment it arrives (before the progress line counts
    it): a job killed at any moment loses only the runs in flight. The job moves them into
    a chunk every few rows or seconds, when it ends and when it resumes
    (:meth:`DatasetFolder.compact`).
``features/part-NNNNNN.parquet``
    The rows, in chunks: what ``pandas.read_parquet(DIR / "features")`` reads — every row
    of a finished job; while a job runs, or after it was killed until the next job on the
    folder, all but the rows still in the journal. :func:`load` reads both.
``waveforms/<run_id>.npz``
    With ``--waveforms``: each run's measured channels (the sensors, anti-aliased, noise
    included) over the whole run, float32, compressed, one file per run, written
    atomically when its row arrives; :func:`load_waveforms` reads one. A run along a speed
    ramp also stores its exact shaft angle (float64), for order tracking.
``broken/``
    Chunks and journal rows that could not be read (empty, truncated, garbled: a disk or a
    copy failed), set aside by the next job, which runs their runs again; kept for a look.
``columns.csv``, ``README.md``
    The column map (name, group, unit) and the dataset card, rewritten at the end of a job.

Every file is written to a hidden temporary file in the same folder and renamed
(:mod:`rubdiag.dataset._chunks`), so it is complete or absent whenever the job is killed.
Hidden and temporary files are ignored by every reader (``pandas.read_parquet`` included)
and removed by the next job. Readers never write; a damaged file is a one-line
``ValueError`` naming it and saying how to recover.

Which row of a run id counts: the newest — a journal row over any chunk's, and a chunk of
a higher number over one of a lower. A run id is in one place, except for a moment: a
compaction writes its chunk first and then removes the journal rows it holds; a retried
run's new row is written first and the chunks holding the old one are then rewritten
without it. A crash in between leaves two copies of which :func:`load` keeps the newest,
and the next job removes the older.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa

from rubdiag._atomic import write_bytes, write_text
from rubdiag.dataset._chunks import (
    UnreadableFile,
    read_chunk,
    read_journal_row,
    row_schema,
    write_chunk,
    write_journal_row,
)
from rubdiag.dataset._schema import MODEL_COLUMN, SCHEMA_VERSION

__all__ = ["DatasetFolder", "acquisition", "load", "load_waveforms", "write_waveforms"]

_FORMAT = "rubdiag.dataset"
_CHUNK_PREFIX, _CHUNK_SUFFIX = "part-", ".parquet"
_JOURNAL_PREFIX, _JOURNAL_SUFFIX = "row-", ".json"


class DatasetFolder:
    """The files of one dataset folder (see the module docstring)."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.chunks_dir = self.root / "features"
        self.journal_dir = self.root / "journal"
        self.broken_dir = self.root / "broken"

    # --- opening ---------------------------------------------------------------------------
    def check_writable(self, design_toml: str) -> None:
        """Refuse, before anything is written, a folder that cannot take this design: a
        file in the way, another design, another schema version."""
        if self.root.exists() and not self.root.is_dir():
            raise ValueError(f"--out {self.root}: is a file (allowed: a new or empty folder, "
                             "or the folder of this design)")
        if self.root.is_dir():
            existing = self.root / "design.toml"
            if existing.is_file():
                self._check_same(existing.read_text(encoding="utf-8"), design_toml)
            elif not all(self._left_by_create(p) for p in self.root.iterdir()):
                raise ValueError(f"--out {self.root}: is not empty and holds no dataset "
                                 "(allowed: a new or empty folder, or the folder of this "
                                 "design)")
        parent = self.root if self.root.is_dir() else _existing_parent(self.root)
        if not os.access(parent, os.W_OK):
            raise ValueError(f"--out {self.root}: {parent} is not writable")

    def _left_by_create(self, path: Path) -> bool:
        """What a job killed in :meth:`create` before design.toml leaves: the empty chunk
        folder and the design's temporary file."""
        if path == self.chunks_dir:
            return path.is_dir() and not any(path.iterdir())
        return path.name.startswith(".design.toml.") and path.name.endswith(".tmp")

    def _check_same(self, stored_toml: str, design_toml: str) -> None:
        meta = self.meta()
        stored_schema = meta.get("schema_version")
        if not meta and not self.chunk_paths():
            stored_schema = SCHEMA_VERSION     # killed before dataset.json: nothing stored
        if stored_schema != SCHEMA_VERSION:
            raise ValueError(f"--out {self.root}: made with run-id schema version "
                             f"{stored_schema}, this rubdiag uses {SCHEMA_VERSION} (its run "
                             "ids would differ; use a new folder)")
        if stored_toml != design_toml:
            import tomllib

            found = _differences(tomllib.loads(stored_toml), tomllib.loads(design_toml))
            shown = "; ".join(found[:3]) + (f"; {len(found) - 3} more" if len(found) > 3 else "")
            raise ValueError(f"--out {self.root}: holds another design ({shown}); use a new "
                             "folder or the same design")

    def create(self, design_toml: str, acquisition: dict | None = None) -> None:
        """Make the folder (or reuse it), write the design, the format and how the channels
        are measured (``acquisition``: what a classifier needs to know of its training
        data; a folder made before that key existed gets it on a resume), and remove what
        an interrupted job left half-written."""
        self.chunks_dir.mkdir(parents=True, exist_ok=True)
        if not (self.root / "design.toml").is_file():
            write_text(self.root / "design.toml", design_toml)
        meta = self.meta() or {"format": _FORMAT, "schema_version": SCHEMA_VERSION}
        if acquisition is not None and meta.get("acquisition") != acquisition:
            meta["acquisition"] = acquisition
        if meta != self.meta():
            self.write_meta(meta)
        for leftover in [*self.root.glob(".*.tmp"), *self.chunks_dir.glob(".*.tmp"),
                         *self.journal_dir.glob(".*.tmp"),
                         *(self.root / "waveforms").glob(".*.tmp")]:
            leftover.unlink(missing_ok=True)

    # --- format ----------------------------------------------------------------------------
    def meta(self) -> dict:
        path = self.root / "dataset.json"
        if not path.is_file():
            return {}
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except ValueError as exc:               # JSONDecodeError, UnicodeDecodeError
            raise ValueError(f"{path}: unreadable ({exc})") from None

    def write_meta(self, meta: dict) -> None:
        write_text(self.root / "dataset.json", json.dumps(meta, indent=1) + "\n")

    def schema(self) -> pa.Schema | None:
        columns = self.meta().get("columns")
        if not columns:
            return None
        return pa.schema([(name, pa.type_for_alias(kind)) for name, kind in columns])

    def set_schema(self, schema: pa.Schema) -> None:
        """Fix the columns (from the first successful row) and rewrite the chunks written
        before (failed rows only) with them."""
        meta = self.meta()
        meta["columns"] = [(f.name, str(f.type)) for f in schema]
        self.write_meta(meta)
        for path in self.chunk_paths():
            table = read_chunk(path)
            if table.schema != schema:
                write_chunk(path, table.to_pylist(), schema)

    # --- chunks and journal ------------------------------------------------------------------
    def chunk_paths(self) -> list[Path]:
        return _numbered(self.chunks_dir, _CHUNK_PREFIX, _CHUNK_SUFFIX)

    def journal_paths(self) -> list[Path]:
        return _numbered(self.journal_dir, _JOURNAL_PREFIX, _JOURNAL_SUFFIX)

    def write_chunk(self, rows: list[dict], schema: pa.Schema) -> Path:
        path = _next_path(self.chunks_dir, _CHUNK_PREFIX, _CHUNK_SUFFIX)
        write_chunk(path, rows, schema)
        return path

    def journal(self, row: dict) -> Path:
        """Write one finished row to the journal: stored when this returns."""
        self.journal_dir.mkdir(exist_ok=True)
        path = _next_path(self.journal_dir, _JOURNAL_PREFIX, _JOURNAL_SUFFIX)
        write_journal_row(path, row)
        return path

    def compact(self, final: bool = False, stored: set[str] | None = None) -> Path | None:
        """Move the journal's rows into a new chunk, then remove them from the journal.

        While no row has succeeded the columns are unknown: failed rows wait in the journal,
        unless ``final`` (then they get their own columns, and the first successful row of a
        later job rewrites their chunk). ``stored``: the run ids that older chunks may hold
        (a retried run's old row, removed from them once the new one is in its chunk);
        ``None``: read them from the chunks. Returns the new chunk, if any."""
        chunk = self._compact(final, stored)
        if final and self.journal_dir.is_dir() and not any(self.journal_dir.iterdir()):
            self.journal_dir.rmdir()               # a finished folder has no empty journal
        return chunk

    def _compact(self, final: bool, stored: set[str] | None) -> Path | None:
        schema = self.schema()
        paths = self.journal_paths()
        if not paths or (schema is None and not final):
            return None
        rows: dict[str, dict] = {}
        for path in paths:
            row = read_journal_row(path)
            rows.pop(row["run_id"], None)          # the newest of a run id, last
            rows[row["run_id"]] = row
        older = self.chunk_paths()
        chunk = self.write_chunk(list(rows.values()),
                                 schema or row_schema(next(iter(rows.values()))))
        if stored is None:
            stored = {run_id for path in older
                      for run_id in read_chunk(path, ["run_id"])["run_id"].to_pylist()}
        if superseded := stored & set(rows):
            self.drop_superseded(superseded, chunk)
        for path in paths:
            path.unlink()
        return chunk

    def stored_status(self, skip_unreadable: bool = False) -> dict[str, str]:
        """run_id -> status of every stored row (the newest per run id). An unreadable file
        raises :class:`~rubdiag.dataset._chunks.UnreadableFile`, or with ``skip_unreadable``
        counts as holding no run."""
        out = {}
        for path in [*self.chunk_paths(), *self.journal_paths()]:
            try:
                if path.suffix == _JOURNAL_SUFFIX:
                    row = read_journal_row(path)
                    out[row["run_id"]] = row["status"]
                    continue
                table = read_chunk(path, ["run_id", "status"])
            except UnreadableFile:
                if skip_unreadable:
                    continue
                raise
            out.update(zip(table["run_id"].to_pylist(), table["status"].to_pylist(),
                           strict=True))
        return out

    def drop_superseded(self, run_ids: set[str], newest: Path) -> None:
        """Remove the rows of ``run_ids`` from every chunk before ``newest``."""
        for path in self.chunk_paths():
            if path >= newest:
                continue
            table = read_chunk(path)
            keep = [r for r in table.to_pylist() if r["run_id"] not in run_ids]
            if len(keep) == table.num_rows:
                continue
            if keep:
                write_chunk(path, keep, table.schema)
            else:
                path.unlink()

    # --- damaged files ---------------------------------------------------------------------
    def unreadable(self) -> list[UnreadableFile]:
        """Every chunk and journal row that cannot be read, each read whole."""
        found = []
        for path in self.chunk_paths():
            try:
                read_chunk(path)
            except UnreadableFile as exc:
                found.append(exc)
        for path in self.journal_paths():
            try:
                read_journal_row(path)
            except UnreadableFile as exc:
                found.append(exc)
        return found

    def set_aside_unreadable(self) -> list[tuple[Path, Path, str]]:
        """Move every unreadable chunk and journal row into ``broken/`` (kept, under its
        own name; ``.1``, ``.2`` … after it if that is taken), where no reader looks: their
        runs count as not stored. Returns (from, to, why) of each."""
        moved = []
        for exc in self.unreadable():
            self.broken_dir.mkdir(exist_ok=True)
            target, n = self.broken_dir / exc.path.name, 0
            while target.exists():
                n += 1
                target = self.broken_dir / f"{exc.path.name}.{n}"
            os.replace(exc.path, target)
            moved.append((exc.path, target, exc.reason))
        return moved


def _numbered(folder: Path, prefix: str, suffix: str) -> list[Path]:
    """The files ``<prefix>NNNNNN<suffix>`` of ``folder``, in number order."""
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir()
                  if p.name.startswith(prefix) and p.name.endswith(suffix))


def _next_path(folder: Path, prefix: str, suffix: str) -> Path:
    paths = _numbered(folder, prefix, suffix)
    last = int(paths[-1].name[len(prefix):-len(suffix)]) if paths else 0
    return folder / f"{prefix}{last + 1:06d}{suffix}"


def write_waveforms(root: str | Path, run_id: str, waves: dict, design) -> Path:
    """Store one run's measured channels (see the module docstring)."""
    folder = Path(root) / "waveforms"
    folder.mkdir(exist_ok=True)
    units = {s.name: s.unit for s in design.sensors}
    meta = {"run_id": run_id, "fs_hz": waves["fs"], "discard_s": design.discard_s,
            "channels": list(waves["channels"]),
            "units": [units[name] for name in waves["channels"]]}
    arrays = {f"channel_{i}": v for i, v in enumerate(waves["channels"].values())}
    if "angle_rad" in waves:
        arrays["angle_rad"] = np.asarray(waves["angle_rad"], dtype=np.float64)
    sink = io.BytesIO()
    np.savez_compressed(sink, meta=np.array(json.dumps(meta)), **arrays)
    path = folder / f"{run_id}.npz"
    write_bytes(path, sink.getvalue())
    return path


def load_waveforms(root: str | Path, run_id: str) -> pd.DataFrame:
    """The measured channels of one run of a dataset made with ``--waveforms``: a DataFrame
    indexed by time ``t_s`` (s, from the run's start; the analysis window starts at
    ``attrs["discard_s"]``), one float32 column per sensor, and for a run along a speed ramp
    a last column ``angle_rad`` (float64: the shaft angle at the samples, the input of
    :func:`rubdiag.signal.resample_to_angle`); ``attrs["units"]`` maps each column to its
    unit.

    Parameters
    ----------
    root : str or Path
        The dataset folder.
    run_id : str
        The run's id (its ``run_id`` column).

    Returns
    -------
    pandas.DataFrame
        The channels, indexed by ``t_s``.
    """
    path = Path(root) / "waveforms" / f"{run_id}.npz"
    if not path.is_file():
        stored = (Path(root) / "waveforms").is_dir()
        why = "no such run in it" if stored else "made without --waveforms"
        raise ValueError(f"{path}: no waveforms stored ({why})")
    try:
        with np.load(path, allow_pickle=False) as archive:
            meta = json.loads(str(archive["meta"]))
            columns = {name: archive[f"channel_{i}"]
                       for i, name in enumerate(meta["channels"])}
            units = dict(zip(meta["channels"], meta["units"], strict=True))
            if "angle_rad" in archive.files:
                columns["angle_rad"], units["angle_rad"] = archive["angle_rad"], "rad"
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise ValueError(f"{path}: unreadable ({type(exc).__name__}: {exc})") from None
    n = len(next(iter(columns.values()))) if columns else 0
    frame = pd.DataFrame(columns, index=pd.Index(np.arange(n) / meta["fs_hz"], name="t_s"))
    frame.attrs.update(units=units, fs_hz=meta["fs_hz"], discard_s=meta["discard_s"],
                       run_id=run_id)
    return frame


def acquisition(root: str | Path) -> dict:
    """How a dataset's channels were measured: ``{"fs_hz", "window_s", "discard_s",
    "sensors": [{"name", "point", "direction", "quantity", "unit"}, …]}``; for a design with
    a speed ramp also ``"ramp"`` (its ``rate_rpm_s``, ``span``, ``direction``), and
    ``window_s`` is then the shortest analysis window of its runs.

    Parameters
    ----------
    root : str or Path
        The dataset folder.

    Returns
    -------
    dict
        The keys above.
    """
    meta = DatasetFolder(root).meta()
    if "acquisition" not in meta:
        raise ValueError(f"{root}: dataset.json does not say how the channels were measured "
                         "(made by an older rubdiag); run `rubdiag dataset` on its design.toml "
                         "with --out on this folder once (nothing is simulated again)")
    return meta["acquisition"]


def load(root: str | Path) -> pd.DataFrame:
    """The rows of a dataset folder, one per run (ordered as written): its chunks and its
    journal (the rows a running or killed job has not moved into a chunk yet). A folder
    made before rows had a ``model`` column holds runs of the full model: the column is
    filled with ``"full"`` (after ``speed_rpm``). Writes nothing. An unreadable chunk or
    journal row is a ``ValueError`` naming it, with the command that repairs the folder.

    Parameters
    ----------
    root : str or Path
        The dataset folder.

    Returns
    -------
    pandas.DataFrame
        One row per run: design factors, ids, status, labels, measures and features.
    """
    folder = DatasetFolder(root)
    if not (folder.root / "design.toml").is_file():
        raise ValueError(f"{folder.root}: not a rubdiag dataset folder (no design.toml)")
    try:
        journal, tables = _read_rows(folder)
    except UnreadableFile as exc:
        raise UnreadableFile(exc.path, exc.reason, advice=(
            f"`rubdiag dataset {folder.root / 'design.toml'} --out {folder.root}` moves it "
            f"into {folder.broken_dir} and runs its runs again")) from None
    if journal:
        schema = folder.schema() or (tables[0].schema if tables else row_schema(journal[0]))
        tables.append(pa.Table.from_pylist(journal, schema=schema))
    if not tables:
        return pd.DataFrame()
    rows = pd.concat([t.to_pandas() for t in tables], ignore_index=True)
    rows = rows.drop_duplicates("run_id", keep="last").reset_index(drop=True)
    if MODEL_COLUMN not in rows:
        at = rows.columns.get_loc("speed_rpm") + 1 if "speed_rpm" in rows else len(rows.columns)
        rows.insert(at, MODEL_COLUMN, "full")
    return rows


def _read_rows(folder: DatasetFolder, attempts: int = 5) -> tuple[list[dict], list[pa.Table]]:
    """The journal's rows and the chunks' tables, read beside a job that may be writing:
    the journal first — a compaction writes its chunk before it removes the journal rows,
    so a row that leaves the journal after it was listed is then in a chunk listed later;
    a file removed between listing and reading (moved into a chunk, or rewritten without a
    retried run's old row) means reading again."""
    def once():
        journal = [read_journal_row(p) for p in folder.journal_paths()]
        return journal, [read_chunk(p) for p in folder.chunk_paths()]

    for _ in range(attempts - 1):
        try:
            return once()
        except FileNotFoundError:
            pass
    return once()


def _existing_parent(path: Path) -> Path:
    for parent in path.absolute().parents:
        if parent.exists():
            return parent
    return Path.cwd()


def _differences(a, b, where: str = "") -> list[str]:
    """Every key path at which two parsed designs differ, with both values."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for key in list(a) + [k for k in b if k not in a]:
            if key not in a or key not in b:
                there = "missing" if key not in a else repr(a[key])
                here = "missing" if key not in b else repr(b[key])
                out.append(f"{where}{key} is {there} there, {here} here")
            elif a[key] != b[key]:
                out += _differences(a[key], b[key], f"{where}{key}.")
        return out
    return [f"{where.rstrip('.')} is {a!r} there, {b!r} here"]
