"""A saved classifier on measured signals: one prediction per window of the training length.

:func:`predict` reads signal files (CSV, NPZ, parquet: :func:`rubdiag.signal.read_signals`),
folders of them, glob patterns or dataset folders (:mod:`rubdiag.learn._inputs`). A file's
columns are mapped to the model's channels (``columns``) and converted to SI (``units``,
per the channel's quantity: :data:`UNITS`); the record is cut into non-overlapping windows
of the model's ``window_s`` at the record's own sampling rate, and each window's features
are computed exactly as a dataset row's (:func:`rubdiag.signal._table.prefixed_features`
with the model's feature options) at the window's speed: the file's own (per-file speeds),
from a tacho, one given for every file, or the median over the model's channels of the
dominant line (assumed 1×). Every y/z probe pair among the model's channels (named as a
pair: :func:`rubdiag.dataset._schema.pair_channel`) gets its full-spectrum and orbit
columns too when the model reads them, as a dataset row's
(:func:`rubdiag.signal._fullspectrum.orbit_features_by_pair`), so a model with the
``full_spectrum`` or ``orbit`` family reads a measured file as it read its dataset. A
dataset folder's stored rows are predicted as they are. The windows of every file of a
call go through the model in one batch (a row's probabilities do not depend on the rows
beside it), so many short files cost little more than their features.

Refused (ValueError): a missing channel (every one named, with the ``rubdiag train
--channels`` that makes a model without them), an unknown unit, a record shorter than one
window, a sampling rate too low for the highest order the model's features reach, a
record with no line to estimate its speed from (a constant signal). Told (the ``warnings``
column): a speed, or features, outside what the model saw in training — the prediction is
then an extrapolation; the warning names the features furthest outside, with their values
and training ranges (a feature over the noise floor at its least value, 1, is never
outside) — and an estimated speed that is ambiguous (``speed_ambiguous``: a
line at 1/2 or 1/3 of the strongest may be 1×; :mod:`rubdiag.signal._speed`, "Which line
is 1×").

Nothing here imports the simulator.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits  # installed with scikit-learn

from rubdiag import _check
from rubdiag._progress import steps
from rubdiag.dataset._schema import PAIR_FEATURES, SEPARATOR, pair_channel
from rubdiag.learn._caveats import prediction_warnings
from rubdiag.learn._columns import channels_of, read_dataset
from rubdiag.learn._confusers import calls_rub
from rubdiag.learn._inputs import Speeds, expand_inputs, speeds_per_file
from rubdiag.learn._persist import Model, load_model
from rubdiag.learn._sample_rate import required_fs
from rubdiag.signal import read_signals, tacho_speed
from rubdiag.signal._options import Options
from rubdiag.signal._records import check_signals
from rubdiag.signal._speedvote import SpeedNotFound, SpeedVote, voted_speed
from rubdiag.signal._table import prefixed_feature_row

__all__ = ["FLOOR_SUFFIX", "NAMED_FEATURES", "RANGE_TOLERANCE", "RUB_LIKELY", "UNITS",
           "fault_columns", "missing_channels",
           "predict", "predict_rows", "unit_factor"]

#: Units a channel may be given in, per quantity: factor to SI.
UNITS = {
    "displacement": {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "mil": 25.4e-6},
    "velocity": {"m/s": 1.0, "mm/s": 1e-3, "in/s": 0.0254},
    "acceleration": {"m/s^2": 1.0, "m/s2": 1.0, "mm/s^2": 1e-3, "mm/s2": 1e-3,
                     "g": 9.80665},
    "reaction": {"N": 1.0, "kN": 1e3},
}

#: From this summed probability of the classes with rub on, a ``fault`` model's
#: prediction calls rub likely and names the most likely fault without it.
RUB_LIKELY = 0.5

#: A value within this share of its training range's width (of the bound itself for a
#: speed) beyond the range counts as inside: a speed read from a spectrum line and
#: features of a resampled record are not exact to the last digits.
RANGE_TOLERANCE = 0.01

#: How many of the features outside their training range a warning names (the furthest
#: outside first, in units of their range).
NAMED_FEATURES = 3

#: The name ending of a feature read over the channel's noise floor: 1 at the floor.
FLOOR_SUFFIX = "_over_floor"


def unit_factor(quantity: str, unit: str) -> float:
    """Factor from ``unit`` to SI for a channel measuring ``quantity``."""
    allowed = UNITS.get(quantity)
    if allowed is None:
        raise ValueError(f"quantity {quantity!r} has no known units (allowed: "
                         f"{', '.join(UNITS)})")
    if unit not in allowed:
        raise ValueError(f"unit {unit!r} is not known for a {quantity} channel (allowed: "
                         f"{', '.join(allowed)})")
    return allowed[unit]


# short records: two threads cost more than they give (benchmarks/README, "Classifiers")
@threadpool_limits.wrap(limits=1)
def predict(model, inputs, *, columns=None, units=None, fs=None, speed_rpm=None,
            tacho=None, progress: bool = False) -> pd.DataFrame:
    """Predict the class of every window of every input, and the majority of each input.

    Parameters
    ----------
    model : Model or path
        A model (:func:`~rubdiag.learn._persist.load_model`) or its folder.
    inputs : path, glob pattern, or list of them
        Signal files (CSV, NPZ, parquet; one column per channel), folders of signal files
        (every one in the folder, sorted by name), glob patterns (expanded here, sorted) or
        dataset folders (their stored rows are predicted, one per run); see
        :mod:`rubdiag.learn._inputs`.
    columns : dict, optional
        File column -> model channel, for columns not named as the channels.
    units : dict, optional
        Model channel -> unit of the file's values (default: the channel's unit in the
        model, SI); allowed units per quantity in :data:`UNITS`.
    fs : float, optional
        Sampling rate (Hz) of files without a time column or ``fs`` entry.
    speed_rpm : float, sequence or mapping, optional
        Running speed (rpm): one number for every window of every file; or each file its
        own: a sequence aligned with ``inputs`` (a folder's or a pattern's files share its
        speed) or a mapping file -> rpm, the file named by its path or its file name
        (:func:`~rubdiag.learn._inputs.read_speeds` reads one from a CSV; every input file
        must be named, None leaves a file without a speed).
    tacho : str, optional
        Column holding a once-per-revolution pulse (not with one number ``speed_rpm``).
    progress : bool
        Show a progress bar over the files on stderr (when it is a terminal).

    Returns
    -------
    pandas.DataFrame
        One row per window: ``input``, ``window`` (0, 1 …), ``start_s``, ``end_s`` (from
        the record's start), ``speed_rpm``, ``speed_source``, ``speed_ambiguous`` (True
        where the estimated speed may be 2× or 3×: the strongest line, taken as 1×, has a
        line at 1/2 or 1/3 of its frequency), ``predicted``, ``p_<class>`` for every class,
        ``warnings`` (empty, or what lies outside the training ranges, and why a speed is
        ambiguous); after a file's windows a row with ``window`` = ``"all"``: the class
        most windows have (ties: the higher mean probability), the mean probabilities, and
        ``speed_ambiguous`` if any window's is. A file's
        speed is the first of: its own (a per-file ``speed_rpm``: ``speed_source`` =
        ``"speeds"``), its tacho (``tacho``, else a column named ``tacho`` unless one
        number ``speed_rpm`` is given: ``"tacho"``, per window), the one number
        ``speed_rpm`` (``"speed_rpm"``), the estimate per window (``"estimated"``). A
        dataset folder gives one row per run (``input`` = its ``run_id``, ``window`` 0:
        the stored analysis window, times from the run's start, ``speed_source``
        ``"dataset"``). ``attrs["model_warnings"]``: what the model's training warned of
        that concerns its predictions (:func:`rubdiag.learn._caveats.prediction_warnings`:
        not the small-class counts; empty if nothing). A ``fault``-target model's
        table has, before ``warnings``, ``p_predicted``, ``p_rubbing`` (the summed
        probability of the classes with rub), ``confuser`` and ``p_confuser`` (the most
        probable class without rub; :func:`fault_columns`).
    """
    if not isinstance(model, Model):
        model = load_model(model)
    given = [inputs] if isinstance(inputs, str | os.PathLike) else list(inputs)
    one_speed, own = _speed_kind(speed_rpm)
    if one_speed is not None and tacho is not None:
        raise ValueError("speed_rpm and tacho exclude each other (allowed: one of them, or "
                         "speed_rpm per file with tacho for the files without one)")
    files = expand_inputs(given, exclude=[own.source] if isinstance(own, Speeds) else [])
    speeds = ([None] * len(files) if own is None
              else speeds_per_file(own, len(given), files))
    windows = _Windows(model, _check_columns(model, columns), _unit_factors(model, units),
                       fs, tacho, one_speed)
    rows, stored = [], []
    for k, ((path, _), speed) in enumerate(steps(list(zip(files, speeds, strict=True)),
                                                  "predict", unit="file", enabled=progress)):
        if path.is_dir():
            used = [n for n, v in (("columns", columns), ("units", units), ("fs", fs),
                                   ("speed_rpm", speed_rpm), ("tacho", tacho))
                    if v is not None and not (isinstance(v, dict) and not v)]
            if used:
                raise ValueError(f"{path}: a dataset folder brings its channels, units, "
                                 f"sampling rate and speeds; {used[0]} applies to signal "
                                 "files only")
            stored.append((k, predict_rows(model, read_dataset(path))))   # one row per run
        else:
            rows.append((k, windows.of(path, speed)))
    out = _in_order(model, rows, stored)
    out.attrs["model_warnings"] = prediction_warnings(model.meta)
    return out


def _speed_kind(speed_rpm):
    """``(one speed for every file or None, per-file speeds or None)`` of ``speed_rpm``."""
    if speed_rpm is None:
        return None, None
    if isinstance(speed_rpm, Mapping) or (
            isinstance(speed_rpm, Iterable) and not isinstance(speed_rpm, str | bytes)
            and np.ndim(speed_rpm) == 1):
        return None, speed_rpm
    return _check.positive("speed_rpm", speed_rpm, "rpm"), None


def predict_rows(model: Model, data: pd.DataFrame) -> pd.DataFrame:
    """The window rows of :func:`predict` for a dataset's stored rows (one window per run,
    ``input`` = ``run_id``); the channels' units must be the model's."""
    acq = data.attrs.get("acquisition", {})
    have = channels_of(data)
    units = {s["name"]: s["unit"] for s in acq.get("sensors", [])}
    source = data.attrs.get("source", "the dataset")
    missing = [c for c in model.channels if c not in have]
    if missing:
        raise ValueError(missing_channels(f"{source}", missing, model, "the dataset", have))
    for c in model.meta["channels"]:
        if units.get(c["name"], c["unit"]) != c["unit"]:
            raise ValueError(f"{source}: channel {c['name']!r} is in {units[c['name']]}, "
                             f"the model's in {c['unit']}")
    speed = data["speed_rpm"].to_numpy(dtype=np.float64)
    fs = float(acq.get("fs_hz", model.meta["fs_hz"]))
    for s in np.unique(speed):
        _check_fs(model, fs, s, str(source))
    start = float(acq.get("discard_s", 0.0))
    window_s = float(acq.get("window_s", model.meta["window_s"]))
    ids = data["run_id"] if "run_id" in data.columns else pd.Series(range(len(data)))
    return _table(model, data, [str(i) for i in ids], np.zeros(len(data), dtype=int),
                  np.full(len(data), start), np.full(len(data), start + window_s),
                  np.full(len(data), "dataset", dtype=object), [""] * len(data))


class _Windows:
    """The feature rows of a signal file's windows, with what every file of a call shares:
    the column map, unit factors, feature options, the columns to check (built once)."""

    def __init__(self, model: Model, columns: dict, factors: dict, fs, tacho, speed_rpm):
        self.model, self.columns, self.factors = model, columns, factors
        self.fs, self.tacho, self.speed_rpm = fs, tacho, speed_rpm
        self.options = _options(model)
        self.opts = Options(**self.options)
        self.window_s = model.meta["window_s"]
        step = model.pipeline.named_steps["features"]
        needed = [*step.required_, *getattr(step, "pair_required_", ())]
        # the probe pairs' columns cost more than a window's other features: only for a
        # model that reads them
        self.pairs = any(c.split(SEPARATOR, 1)[0] not in model.channels
                         for c in needed if SEPARATOR in c)
        self.lines = [c for c in step.required_ if c.split(SEPARATOR, 1)[-1].startswith("amp_")]

    def of(self, path: Path, given: float | None) -> dict:
        """The windows of the file at ``path`` (its own speed ``given``, or None):
        ``rows`` (feature dicts), ``input``, ``starts``, ``ends``, ``source``."""
        model, columns = self.model, self.columns
        frame, fs = read_signals(path, self.fs)
        name = path.name
        pulses, source = None, "speeds"
        if given is None:
            pulses = self._pulses(frame, name)
            source = ("tacho" if pulses is not None else
                      "speed_rpm" if self.speed_rpm is not None else "estimated")
        for column in columns:
            if column not in frame.columns:
                raise ValueError(f"{name}: column {column!r} not found (its columns: "
                                 f"{', '.join(frame.columns)})")
        frame = frame.rename(columns=columns)
        missing = [c for c in model.channels if c not in frame.columns]
        if missing:
            raise ValueError(missing_channels(name, missing, model, "the file",
                                              list(frame.columns), mappable=True))
        X = np.vstack([frame[c].to_numpy(dtype=np.float64) * self.factors[c]
                       for c in model.channels])
        n = round(self.window_s * fs)
        n_windows = X.shape[1] // n
        if n_windows == 0:
            raise ValueError(f"{name}: the record lasts {X.shape[1] / fs:.4g} s, shorter "
                             f"than one window of the model ({self.window_s:g} s)")
        rows, ambiguity = [], []
        for i in range(n_windows):
            part = slice(i * n, (i + 1) * n)
            where = f"{name}, window {i}"
            said = ""
            if source == "speeds":
                speed = given
            elif source == "tacho":
                speed = tacho_speed(pulses[part], fs)
            elif source == "speed_rpm":
                speed = self.speed_rpm
            else:
                vote = _dominant_speed(X[:, part], fs, model.channels, self.opts, where)
                speed, said = vote.rpm, vote.ambiguity()
            _check_fs(model, fs, speed, where)
            signals = dict(zip(model.channels, X[:, part], strict=True))
            row = prefixed_feature_row(signals, fs, speed, separator=SEPARATOR,
                                       **self.options)
            if self.pairs:
                row.update(pair_columns(signals, fs, speed))
            self._check_measured(row, fs, speed, where)
            rows.append(row)
            ambiguity.append(said)
        starts = np.arange(n_windows) * n / fs
        return {"rows": rows, "input": str(path), "starts": starts, "ends": starts + n / fs,
                "source": source, "ambiguity": ambiguity}

    def _pulses(self, frame: pd.DataFrame, name: str):
        """The tacho pulses of a file without its own speed: ``tacho``'s column, else a
        column named tacho (unless one speed is given for all); None without."""
        if self.tacho is not None:
            if self.tacho not in frame.columns:
                raise ValueError(f"{name}: tacho column {self.tacho!r} not found (its "
                                 f"columns: {', '.join(frame.columns)})")
            return frame[self.tacho].to_numpy()
        if self.speed_rpm is None:
            found = [c for c in frame.columns
                     if c.lower() == "tacho" and c not in self.columns]
            return frame[found[0]].to_numpy() if found else None
        return None

    def _check_measured(self, row: dict, fs: float, speed: float, where: str) -> None:
        """An order line the model uses that came out unmeasurable (NaN amplitude: its band
        reaches the Nyquist frequency) would be read as "absent": refuse instead (the
        sampling-rate check is meant to catch it first). Sideband and broadband levels may
        be NaN for a short record of a slow machine, in training too: they are left
        alone."""
        for column in self.lines:
            if np.isnan(row[column]):
                raise ValueError(f"{where}: {column} cannot be measured at fs = {fs:g} Hz "
                                 f"and {speed:.0f} rpm (the record is too coarse for the "
                                 "model)")


def _in_order(model: Model, files: list, stored: list) -> pd.DataFrame:
    """The table of :func:`predict`: every file's windows then its majority, and every
    dataset's rows, in the order of the inputs (``files``, ``stored``: (position, what)).
    The windows of all files go through the pipeline in one call: each row's
    probabilities are its own, the same in any batch."""
    pieces, position, after = [], [], []
    if files:
        count = [len(f["rows"]) for _, f in files]
        windows = _table(model, pd.DataFrame([row for _, f in files for row in f["rows"]]),
                         [f["input"] for _, f in files for _ in f["rows"]],
                         np.concatenate([np.arange(c) for c in count]),
                         np.concatenate([f["starts"] for _, f in files]),
                         np.concatenate([f["ends"] for _, f in files]),
                         [f["source"] for _, f in files for _ in f["rows"]],
                         [a for _, f in files for a in f["ambiguity"]])
        majority = _majority(windows, model, np.r_[0, np.cumsum(count)])
        order = np.array([k for k, _ in files])
        pieces += [windows, majority]
        position += [np.repeat(order, count), order]
        after += [np.zeros(len(windows)), np.ones(len(majority))]   # a file's majority last
    for k, table in stored:
        pieces.append(table)
        position.append(np.full(len(table), k))
        after.append(np.zeros(len(table)))
    out = pd.concat(pieces, ignore_index=True)
    rank = np.lexsort((np.arange(len(out)), np.concatenate(after), np.concatenate(position)))
    return out.iloc[rank].reset_index(drop=True)


def _table(model: Model, data: pd.DataFrame, inputs, windows, starts, ends,
           sources, ambiguity) -> pd.DataFrame:
    """Window rows: probabilities of the pipeline, warnings from the training ranges and
    ``ambiguity`` (per row: why its estimated speed is ambiguous, "" if it is not)."""
    pipeline = model.pipeline
    proba = pipeline.predict_proba(data)
    classes = [str(c) for c in pipeline.classes_]
    speed = data["speed_rpm"].to_numpy(dtype=np.float64)
    table = pd.DataFrame({"input": inputs, "window": pd.Series(windows, dtype=object),
                          "start_s": starts, "end_s": ends, "speed_rpm": speed,
                          "speed_source": sources,
                          "speed_ambiguous": np.array([bool(a) for a in ambiguity]),
                          "predicted": np.asarray(classes, dtype=object)[proba.argmax(axis=1)]})
    for j, c in enumerate(classes):
        table[f"p_{c}"] = proba[:, j]
    Z = pipeline.named_steps["features"].transform(data)
    table = fault_columns(table, model)
    table["warnings"] = ["; ".join(w for w in pair if w) for pair
                         in zip(ambiguity, _range_warnings(model, speed, Z), strict=True)]
    return table


def fault_columns(table: pd.DataFrame, model: Model) -> pd.DataFrame:
    """For a ``fault``-target model, what a prediction says of rub, as columns (before
    ``warnings``): ``p_predicted`` (the probability of the predicted class),
    ``p_rubbing`` (the summed probability of the classes with rub: ``rub``,
    ``rub+crack`` …), ``confuser`` and ``p_confuser`` (the most probable class without
    rub, and its probability; "" and NaN if the model has none). Other models' tables
    are returned as they are."""
    if model.meta.get("target") != "fault":
        return table
    classes = list(model.classes)
    p = table[[f"p_{c}" for c in classes]].to_numpy(dtype=np.float64)
    rows = np.arange(len(table))
    index = {c: j for j, c in enumerate(classes)}
    rub = calls_rub(classes)
    others = np.flatnonzero(~rub)
    derived = {"p_predicted": p[rows, [index[c] for c in table["predicted"]]],
               "p_rubbing": p[:, rub].sum(axis=1)}
    if others.size:
        best = others[p[:, others].argmax(axis=1)]
        derived["confuser"] = np.asarray(classes, dtype=object)[best]
        derived["p_confuser"] = p[rows, best]
    else:
        derived["confuser"] = np.full(len(table), "", dtype=object)
        derived["p_confuser"] = np.full(len(table), np.nan)
    out = table.drop(columns=[c for c in derived if c in table.columns])
    at = out.columns.get_loc("warnings") if "warnings" in out.columns else len(out.columns)
    for k, (name, values) in enumerate(derived.items()):
        out.insert(at + k, name, values)
    return out


def missing_channels(where: str, missing, model: Model, what: str, have,
                     mappable: bool = False) -> str:
    """The one-line refusal of an input that lacks channels of the model: names every
    missing channel, what the input has, and how to train a model without them."""
    names = ", ".join(repr(c) for c in missing)
    subject = f"channel {names} is" if len(missing) == 1 else f"channels {names} are"
    them = "it" if len(missing) == 1 else "them"
    rest = [c for c in model.channels if c not in missing]
    train = (f"rubdiag train DATASET --channels {','.join(rest)}" if rest
             else "rubdiag train DATASET --channels NAME,… naming channels you have")
    mapping = (f"map a column to {them} with columns / --column COLUMN=CHANNEL, or "
               if mappable else "")
    return (f"{where}: {subject} missing (the model needs {', '.join(model.channels)}; "
            f"{what} has {', '.join(map(str, have)) or 'none'}); {mapping}train a model "
            f"without {them}: {train}")


def _majority(table: pd.DataFrame, model: Model, bounds) -> pd.DataFrame:
    """Each file's row ``window = "all"`` (its windows: ``table`` rows ``bounds[i]`` to
    ``bounds[i + 1]``): the most frequent class (ties: the higher mean probability), the
    mean probabilities, the median speed."""
    classes = list(model.classes)
    p = table[[f"p_{c}" for c in classes]].to_numpy(dtype=np.float64)
    column = {c: table[c].to_numpy() for c in ("input", "start_s", "end_s", "speed_rpm",
                                               "speed_source", "predicted")}
    warned = (table["warnings"] != "").to_numpy()
    ambiguous = table["speed_ambiguous"].to_numpy()
    rows = []
    for a, b in itertools.pairwise(bounds):
        mean = p[a:b].mean(axis=0)
        counts = np.array([np.count_nonzero(column["predicted"][a:b] == c) for c in classes])
        tied = np.flatnonzero(counts == counts.max())
        n_warned = int(warned[a:b].sum())
        rows.append({"input": column["input"][a], "window": "all",
                     "start_s": column["start_s"][a:b].min(),
                     "end_s": column["end_s"][a:b].max(),
                     "speed_rpm": float(np.median(column["speed_rpm"][a:b])),
                     "speed_source": column["speed_source"][a],
                     "speed_ambiguous": bool(ambiguous[a:b].any()),
                     "predicted": classes[tied[np.argmax(mean[tied])]],
                     **{f"p_{c}": mean[j] for j, c in enumerate(classes)},
                     "warnings": (f"{n_warned} of {b - a} windows with warnings" if n_warned
                                  else "")})
    return fault_columns(pd.DataFrame(rows), model)


def _range_warnings(model: Model, speed: np.ndarray, Z: np.ndarray) -> list[str]:
    """What of each window (its speed, its features ``Z``) lies outside the training
    ranges, in words ("" if nothing): the number of features outside and the
    :data:`NAMED_FEATURES` furthest outside (in units of their range), each with its value
    and training range. A feature read over the noise floor (``…_over_floor``) takes 1 at
    the floor, its least value: 1 is never outside, whatever the training rows read."""
    lo, hi = model.meta["speed_range_rpm"]
    ranges = model.meta["feature_ranges"]
    names = list(ranges)
    bounds = np.array([ranges[n] for n in names], dtype=np.float64).reshape(-1, 2)
    low, high = bounds[:, 0], bounds[:, 1]
    tol = RANGE_TOLERANCE * (high - low)
    floor = np.array([n.endswith(FLOOR_SUFFIX) for n in names], dtype=bool)
    low = np.where(floor, np.minimum(low, 1.0), low)
    scale = np.maximum(high - low, np.finfo(float).tiny)   # a constant feature first
    out = []
    for s, z in zip(speed, Z, strict=True):
        said = []
        if not lo * (1 - RANGE_TOLERANCE) <= s <= hi * (1 + RANGE_TOLERANCE):
            said.append(f"speed {s:.0f} rpm is outside the training range {lo:.0f}–{hi:.0f} "
                        "rpm")
        excess = np.maximum(low - tol - z, z - high - tol)
        outside = np.flatnonzero(excess > 0)
        if outside.size:
            with np.errstate(over="ignore"):     # a constant feature: infinitely far
                far = excess[outside] / scale[outside]
            worst = outside[np.argsort(-far, kind="stable")][:NAMED_FEATURES]
            named = ", ".join(f"{names[j]} = {z[j]:.4g} (range {bounds[j, 0]:.4g} to "
                              f"{high[j]:.4g})" for j in worst)
            more = " …" if outside.size > worst.size else ""
            said.append(f"{outside.size} of {len(names)} features outside their training "
                        f"range: {named}{more}")
        out.append("; ".join(said))
    return out


def _check_columns(model: Model, columns) -> dict:
    columns = dict(columns or {})
    for column, channel in columns.items():
        if channel not in model.channels:
            raise ValueError(f"columns: {column!r} is mapped to {channel!r}, not a channel of "
                             f"the model (its channels: {', '.join(model.channels)})")
    return columns


def _unit_factors(model: Model, units) -> dict[str, float]:
    """Model channel -> factor from the file's unit to the model's."""
    units = dict(units or {})
    info = {c["name"]: c for c in model.meta["channels"]}
    for channel in units:
        if channel not in info:
            raise ValueError(f"units: {channel!r} is not a channel of the model (its "
                             f"channels: {', '.join(model.channels)})")
    out = {}
    for name, c in info.items():
        given = units.get(name, c["unit"])
        try:
            out[name] = unit_factor(c["quantity"], given) / unit_factor(c["quantity"],
                                                                         c["unit"])
        except ValueError as exc:
            raise ValueError(f"units: channel {name!r}: {exc}") from None
    return out


def _options(model: Model) -> dict:
    """The feature options of the model (JSON lists back to tuples, as scipy wants)."""
    return {k: tuple(v) if isinstance(v, list) else v
            for k, v in model.meta["feature_options"].items()}


def _dominant_speed(X: np.ndarray, fs: float, channels, options: Options,
                    where: str) -> SpeedVote:
    """The running speed of a window from the dominant lines of its channels: their vote
    (:func:`rubdiag.signal._speedvote.voted_speed`, the estimator of ``rubdiag features``
    too), with what makes it ambiguous."""
    try:
        return voted_speed(X, fs, options, list(channels))
    except SpeedNotFound:
        why = ("every channel is constant: no line at all" if check_signals(X)[1].all()
               else f"no line of {', '.join(channels)} stands out of the noise as 1x")
        raise ValueError(f"{where}: the speed cannot be estimated ({why}); give speed_rpm "
                         "(--speed-rpm) or a tacho (--tacho)") from None


def _check_fs(model: Model, fs: float, speed: float, where: str) -> None:
    top = model.meta["highest_order"]
    need = required_fs(top["reach"], speed, model.meta["window_s"])
    if fs < need:
        raise ValueError(
            f"{where}: fs = {fs:g} Hz is too low for the model: its features reach "
            f"{top['reach']:g}x ({top['order']:g}x and its band, {top['feature']}) of "
            f"{speed / 60.0:.4g} Hz; fs >= {np.ceil(need):.0f} Hz is needed")


def pair_columns(signals: dict, fs: float, speed_rpm: float) -> dict:
    """``PAIR__FEATURE`` of every y/z probe pair among ``signals`` (channel -> window),
    named as a dataset row names them (:func:`rubdiag.dataset._schema.pair_channel`), from
    the same function; empty without a pair."""
    from rubdiag.signal._fullspectrum import orbit_features_by_pair

    pairs = {name: (signals[y], signals[z]) for y in signals for z in signals
             if (name := pair_channel(y, z)) is not None}
    if not pairs:
        return {}
    rows = orbit_features_by_pair(pairs, fs, speed_rpm)
    return {f"{name}{SEPARATOR}{n}": row[n] for name, row in rows.items() for n in PAIR_FEATURES}
