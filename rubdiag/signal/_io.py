"""Measured signals from files: CSV, NPZ and parquet.

Every format holds one channel per column (CSV, parquet: a header row names them; NPZ: one
1-D array per key). The sampling frequency is given, or comes from a time column named
``t``, ``time``, ``time_s`` or ``t_s`` (seconds, uniformly spaced), or, in an NPZ, from a
scalar ``fs`` entry (Hz). The time column is removed from the channels.

A run's waveforms stored in a dataset folder (``DIR/waveforms/<run_id>.npz``, made with
``--waveforms``) are NPZ archives of another layout: a JSON ``meta`` entry (``channels``,
``units``, ``fs_hz``, ``discard_s``) and one ``channel_<i>`` array per sensor. They read as
their sensors' channels over the run's analysis window (the first ``discard_s`` seconds, where
the gap closes, are left out, as the dataset's rows leave them out), with ``attrs["units"]``
naming each channel's unit.
"""

from __future__ import annotations

import json
import os
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag.signal._records import check_fs

TIME_COLUMNS = ("t", "time", "time_s", "t_s")
SUFFIXES = (".csv", ".txt", ".npz", ".parquet", ".pq")
#: How far (relative) a file's sample steps may stray from their median, or its time
#: column's rate from the given ``fs``, and still be that rate: time columns written with
#: a few digits carry that much rounding, a wrong rate is off by far more.
_RATE_AGREEMENT = 1e-3


def read_signals(path: str | os.PathLike, fs: float | None = None) -> tuple[pd.DataFrame, float]:
    """Read the channels of a signal file.

    Parameters
    ----------
    path : str or path-like
        A ``.csv``/``.txt`` (comma-separated, header row), ``.npz`` or ``.parquet``/``.pq`` file.
    fs : float, optional
        Sampling frequency in Hz. When None it comes from the time column (or the NPZ ``fs``
        entry); when both are present they must agree within 0.1 %.

    Returns
    -------
    channels : pandas.DataFrame
        One float column per channel, rows are samples.
    fs : float
        Sampling frequency in Hz.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if path.is_dir():
        raise IsADirectoryError(f"{path}: is a folder, not a signal file")
    if suffix not in SUFFIXES:
        raise ValueError(
            f"{path.name}: unknown file type {suffix or '(none)'!r}; use one of "
            + ", ".join(SUFFIXES)
        )
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such file")
    stored_fs = None
    if suffix == ".npz":
        frame, stored_fs = _read_npz(path)
    elif suffix in (".parquet", ".pq"):
        frame = pd.read_parquet(path)
    else:
        frame = _read_csv(path)
    frame.columns = [str(c).strip() for c in frame.columns]
    if len(frame) == 0:
        raise ValueError(f"{path.name}: the file holds no samples")
    for name in frame.columns:
        if not pd.api.types.is_numeric_dtype(frame[name]):
            raise ValueError(f"{path.name}: column {name!r} is not numeric")
    time = next((c for c in frame.columns if c.lower() in TIME_COLUMNS), None)
    time_fs = None
    if time is not None:
        time_fs = _fs_from_time(frame[time].to_numpy(dtype=np.float64), path.name, time)
        frame = frame.drop(columns=[time])
    found = time_fs if time_fs is not None else stored_fs
    if fs is None:
        if found is None:
            raise ValueError(
                f"{path.name}: no sampling frequency; give fs (--fs HZ) or a time column "
                f"named one of {', '.join(TIME_COLUMNS)}"
            )
        fs = found
    fs = check_fs(fs)
    if found is not None and abs(found - fs) > _RATE_AGREEMENT * fs:
        raise ValueError(f"{path.name}: fs = {fs:g} Hz disagrees with the file's {found:g} Hz")
    if frame.shape[1] == 0:
        raise ValueError(f"{path.name}: the file holds no signal column")
    return frame.astype(np.float64), fs


def stored_units(path: str | os.PathLike) -> dict[str, str]:
    """Channel -> unit, where the file says (a dataset's stored waveforms); else empty."""
    path = Path(path)
    if path.suffix.lower() != ".npz" or not zipfile.is_zipfile(path):
        return {}
    try:
        with np.load(path, allow_pickle=False) as data:
            if "meta" not in data.files:
                return {}
            meta = json.loads(str(data["meta"]))
        return dict(zip(meta["channels"], meta["units"], strict=True))
    except (ValueError, KeyError, TypeError, OSError, zipfile.BadZipFile, zlib.error, EOFError):
        return {}


def _read_csv(path: Path) -> pd.DataFrame:
    with path.open("rb") as fh:
        head = fh.read(4096)
    if b"\0" in head:
        raise ValueError(f"{path.name}: a binary file, not a text CSV table")
    try:
        return pd.read_csv(path)
    except pd.errors.EmptyDataError:
        raise ValueError(f"{path.name}: the file is empty") from None
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path.name}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start}); save the CSV as UTF-8") from None
    except pd.errors.ParserError as exc:
        reason = str(exc).splitlines()[0].removeprefix("Error tokenizing data. C error: ")
        raise ValueError(f"{path.name}: not a CSV table ({reason})") from None


def _read_npz(path: Path) -> tuple[pd.DataFrame, float | None]:
    if not zipfile.is_zipfile(path):
        raise ValueError(f"{path.name}: not an NPZ archive (truncated, corrupt or another "
                         "format)")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: np.asarray(data[k]) for k in data.files}
    except (zipfile.BadZipFile, zlib.error, EOFError, OSError) as exc:
        raise ValueError(f"{path.name}: corrupt NPZ archive ({exc})") from None
    except ValueError as exc:   # e.g. an entry holding Python objects (pickles)
        raise ValueError(f"{path.name}: unreadable NPZ entry ({exc})") from None
    if "meta" in arrays and arrays["meta"].ndim == 0:
        return _waveform_archive(arrays, path.name)
    fs = None
    if "fs" in arrays:
        if arrays["fs"].size != 1:
            raise ValueError(f"{path.name}: the 'fs' entry must be a scalar (Hz)")
        fs = float(arrays.pop("fs").reshape(()))
    bad = [k for k, v in arrays.items() if v.ndim != 1]
    if bad:
        raise ValueError(f"{path.name}: entry {bad[0]!r} is not 1-D (one array per channel)")
    if len({v.size for v in arrays.values()}) > 1:
        raise ValueError(f"{path.name}: the channels have different lengths")
    return pd.DataFrame(arrays), fs


#: the format a simulation result's ``meta`` names (rubdiag.simulation writes it; this layer
#: does not import the simulator, so it recognises the result by this text only)
_RESULT_FORMAT = "rubdiag.simulation-result"


def _waveform_archive(arrays: dict, name: str) -> tuple[pd.DataFrame, float]:
    """A dataset's stored waveforms (module docstring): the sensors over the analysis
    window, and the sampling frequency."""
    if _RESULT_FORMAT in str(arrays["meta"]):
        raise ValueError(f"{name}: a simulation result (rubdiag simulate --out), not a record "
                         "of sensors: `rubdiag features` and `compare` read it; a model "
                         "predicts a sensor record or a dataset's stored waveforms")
    try:
        meta = json.loads(str(arrays["meta"]))
        channels, units = list(meta["channels"]), list(meta["units"])
        fs, discard_s = float(meta["fs_hz"]), float(meta["discard_s"])
        columns = {c: arrays[f"channel_{i}"] for i, c in enumerate(channels)}
    except (ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"{name}: the 'meta' entry does not describe a dataset's waveforms "
                         f"({exc!r})") from None
    start = round(discard_s * fs)
    frame = pd.DataFrame({c: np.asarray(v)[start:] for c, v in columns.items()})
    frame.attrs["units"] = dict(zip(channels, units, strict=True))
    return frame, fs


def _fs_from_time(t: np.ndarray, name: str, column: str) -> float:
    if t.size < 2 or not np.isfinite(t).all():
        raise ValueError(f"{name}: time column {column!r} needs at least 2 finite values")
    dt = np.diff(t)
    step = float(np.median(dt))
    if step <= 0.0 or np.abs(dt - step).max() > _RATE_AGREEMENT * step:
        raise ValueError(f"{name}: time column {column!r} is not uniformly increasing")
    return 1.0 / step
