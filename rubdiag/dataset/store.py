"""A dataset folder that a crash cannot corrupt.

Layout of ``DIR``:

``design.toml``
    The resolved design (:meth:`Design.to_toml`); written first, atomically. A later job
    into the same folder must bring the same design.
``dataset.json``
    The format: ``schema_version`` (:data:`~rubdiag.dataset.schema.SCHEMA_VERSION`, the one
    the run ids were made with) and, once a run has succeeded, ``columns``: every column
    with its Arrow type, the same in every chunk.
``features/part-NNNNNN.parquet``
    The rows, in chunks. Each chunk is written to a hidden temporary file in the same
    folder and renamed (atomic on POSIX and Windows), so a chunk is either complete or
    absent, whenever the job is killed. Hidden and temporary files are ignored by every
    reader (``pandas.read_parquet(DIR / "features")`` included) and removed by the next
    job.
``waveforms/<run_id>.npz``
    With ``--waveforms``: each run's measured channels (the sensors, anti-aliased, noise
    included) over the whole run, float32, compressed, one file per run, written
    atomically when its row arrives; :func:`load_waveforms` reads one. A run along a speed
    ramp also stores its exact shaft angle (float64), for order tracking.
``columns.csv``, ``README.md``
    The column map (name, group, unit) and the dataset card, rewritten at the end of a job.

A run id appears in at most one chunk, except for a moment while failed runs are retried:
the new row is written first, then the chunks holding the old one are rewritten without it.
:func:`load` keeps the newest row of a run id (the highest chunk number), so a crash in
between still gives every run once.
"""

from __future__ import annotations

import io
import json
import os
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from rubdiag.dataset.schema import MODEL_COLUMN, SCHEMA_VERSION

__all__ = ["DatasetFolder", "acquisition", "load", "load_waveforms", "write_waveforms"]

_FORMAT = "rubdiag.dataset"
_CHUNK_PREFIX, _CHUNK_SUFFIX = "part-", ".parquet"


def _atomic_write_bytes(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def atomic_write_text(path: Path, text: str) -> None:
    _atomic_write_bytes(Path(path), text.encode("utf-8"))


class DatasetFolder:
    """The files of one dataset folder (see the module docstring)."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.chunks_dir = self.root / "features"

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
            atomic_write_text(self.root / "design.toml", design_toml)
        meta = self.meta() or {"format": _FORMAT, "schema_version": SCHEMA_VERSION}
        if acquisition is not None and meta.get("acquisition") != acquisition:
            meta["acquisition"] = acquisition
        if meta != self.meta():
            self.write_meta(meta)
        for leftover in [*self.root.glob(".*.tmp"), *self.chunks_dir.glob(".*.tmp"),
                         *(self.root / "waveforms").glob(".*.tmp")]:
            leftover.unlink(missing_ok=True)

    # --- format ----------------------------------------------------------------------------
    def meta(self) -> dict:
        path = self.root / "dataset.json"
        return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}

    def write_meta(self, meta: dict) -> None:
        atomic_write_text(self.root / "dataset.json", json.dumps(meta, indent=1) + "\n")

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
            if pq.read_schema(path) != schema:
                self._rewrite(path, pq.read_table(path).to_pylist(), schema)

    # --- chunks ----------------------------------------------------------------------------
    def chunk_paths(self) -> list[Path]:
        if not self.chunks_dir.is_dir():
            return []
        return sorted(p for p in self.chunks_dir.iterdir()
                      if p.name.startswith(_CHUNK_PREFIX) and p.name.endswith(_CHUNK_SUFFIX))

    def _next_path(self) -> Path:
        paths = self.chunk_paths()
        last = int(paths[-1].name[len(_CHUNK_PREFIX):-len(_CHUNK_SUFFIX)]) if paths else 0
        return self.chunks_dir / f"{_CHUNK_PREFIX}{last + 1:06d}{_CHUNK_SUFFIX}"

    def write_chunk(self, rows: list[dict], schema: pa.Schema) -> Path:
        path = self._next_path()
        self._rewrite(path, rows, schema)
        return path

    def _rewrite(self, path: Path, rows: list[dict], schema: pa.Schema) -> None:
        table = pa.Table.from_pylist(rows, schema=schema)
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink, compression="zstd")
        _atomic_write_bytes(path, sink.getvalue().to_pybytes())

    def stored_status(self) -> dict[str, str]:
        """run_id -> status of every stored row (the newest per run id)."""
        out = {}
        for path in self.chunk_paths():
            table = pq.read_table(path, columns=["run_id", "status"])
            out.update(zip(table["run_id"].to_pylist(), table["status"].to_pylist(),
                           strict=True))
        return out

    def drop_superseded(self, run_ids: set[str], newest: Path) -> None:
        """Remove the rows of ``run_ids`` from every chunk before ``newest``."""
        for path in self.chunk_paths():
            if path >= newest:
                continue
            table = pq.read_table(path)
            keep = [r for r in table.to_pylist() if r["run_id"] not in run_ids]
            if len(keep) == table.num_rows:
                continue
            if keep:
                self._rewrite(path, keep, table.schema)
            else:
                path.unlink()


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
    _atomic_write_bytes(path, sink.getvalue())
    return path


def load_waveforms(root: str | Path, run_id: str) -> pd.DataFrame:
    """The measured channels of one run of a dataset made with ``--waveforms``: a DataFrame
    indexed by time ``t_s`` (s, from the run's start; the analysis window starts at
    ``attrs["discard_s"]``), one float32 column per sensor, and for a run along a speed ramp
    a last column ``angle_rad`` (float64: the shaft angle at the samples, the input of
    :func:`rubdiag.signal.resample_to_angle`); ``attrs["units"]`` maps each column to its
    unit."""
    path = Path(root) / "waveforms" / f"{run_id}.npz"
    if not path.is_file():
        stored = (Path(root) / "waveforms").is_dir()
        why = "no such run in it" if stored else "made without --waveforms"
        raise ValueError(f"{path}: no waveforms stored ({why})")
    with np.load(path, allow_pickle=False) as archive:
        meta = json.loads(str(archive["meta"]))
        columns = {name: archive[f"channel_{i}"] for i, name in enumerate(meta["channels"])}
        units = dict(zip(meta["channels"], meta["units"], strict=True))
        if "angle_rad" in archive.files:
            columns["angle_rad"], units["angle_rad"] = archive["angle_rad"], "rad"
    n = len(next(iter(columns.values()))) if columns else 0
    frame = pd.DataFrame(columns, index=pd.Index(np.arange(n) / meta["fs_hz"], name="t_s"))
    frame.attrs.update(units=units, fs_hz=meta["fs_hz"], discard_s=meta["discard_s"],
                       run_id=run_id)
    return frame


def acquisition(root: str | Path) -> dict:
    """How a dataset's channels were measured: ``{"fs_hz", "window_s", "discard_s",
    "sensors": [{"name", "point", "direction", "quantity", "unit"}, …]}``; for a design with
    a speed ramp also ``"ramp"`` (its ``rate_rpm_s``, ``span``, ``direction``), and
    ``window_s`` is then the shortest analysis window of its runs."""
    meta = DatasetFolder(root).meta()
    if "acquisition" not in meta:
        raise ValueError(f"{root}: dataset.json does not say how the channels were measured "
                         "(made by an older rubdiag); run `rubdiag dataset` on its design.toml "
                         "with --out on this folder once (nothing is simulated again)")
    return meta["acquisition"]


def load(root: str | Path) -> pd.DataFrame:
    """The rows of a dataset folder, one per run (ordered as written). A folder made before
    rows had a ``model`` column holds runs of the full model: the column is filled with
    ``"full"`` (after ``speed_rpm``)."""
    folder = DatasetFolder(root)
    if not (folder.root / "design.toml").is_file():
        raise ValueError(f"{folder.root}: not a rubdiag dataset folder (no design.toml)")
    frames = [pq.read_table(p).to_pandas() for p in folder.chunk_paths()]
    if not frames:
        return pd.DataFrame()
    rows = pd.concat(frames, ignore_index=True)
    rows = rows.drop_duplicates("run_id", keep="last").reset_index(drop=True)
    if MODEL_COLUMN not in rows:
        at = rows.columns.get_loc("speed_rpm") + 1 if "speed_rpm" in rows else len(rows.columns)
        rows.insert(at, MODEL_COLUMN, "full")
    return rows


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
