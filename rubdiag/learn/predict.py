"""A saved classifier on measured signals: one prediction per window of the training length.

:func:`predict` reads signal files (CSV, NPZ, parquet: :func:`rubdiag.signal.read_signals`)
or dataset folders. A file's columns are mapped to the model's channels (``columns``) and
converted to SI (``units``, per the channel's quantity: :data:`UNITS`); the record is cut
into non-overlapping windows of the model's ``window_s`` at the record's own sampling
rate, and each window's features are computed exactly as a dataset row's
(:func:`rubdiag.signal.table.prefixed_features` with the model's feature options) at the
window's speed: given, from a tacho, or the median over the model's channels of the
dominant line (assumed 1×). Every y/z probe pair among the model's channels (named as a
pair: :func:`rubdiag.dataset.schema.pair_channel`) gets its full-spectrum and orbit
columns too, as a dataset row's (:func:`rubdiag.signal.fullspectrum.pairs_features`), so a
model with the ``full_spectrum`` or ``orbit`` family reads a measured file as it read its
dataset. A dataset folder's stored rows are predicted as they are.

Refused (ValueError): a missing channel (every one named, with the ``rubdiag train
--channels`` that makes a model without them), an unknown unit, a record shorter than one
window, a sampling rate too low for the highest order the model's features reach. Told
(the ``warnings`` column): a speed, or features, outside what the model saw in training —
the prediction is then an extrapolation.

Nothing here imports the simulator.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits  # installed with scikit-learn

from rubdiag import _check
from rubdiag.dataset.schema import PAIR_FEATURES, SEPARATOR, pair_channel
from rubdiag.learn.columns import channels_of, read_dataset
from rubdiag.learn.confusers import calls_rub
from rubdiag.learn.persist import Model, load_model
from rubdiag.learn.train import required_fs
from rubdiag.signal.io import read_signals
from rubdiag.signal.options import Options
from rubdiag.signal.speed import tacho_speed
from rubdiag.signal.speedvote import SpeedNotFound, voted_speed
from rubdiag.signal.table import prefixed_features

__all__ = ["RANGE_TOLERANCE", "RUB_LIKELY", "UNITS", "fault_columns", "missing_channels",
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
            tacho=None) -> pd.DataFrame:
    """Predict the class of every window of every input, and the majority of each input.

    Parameters
    ----------
    model : Model or path
        A model (:func:`~rubdiag.learn.persist.load_model`) or its folder.
    inputs : path or list of paths
        Signal files (CSV, NPZ, parquet; one column per channel) or dataset folders (their
        stored rows are predicted, one per run).
    columns : dict, optional
        File column -> model channel, for columns not named as the channels.
    units : dict, optional
        Model channel -> unit of the file's values (default: the channel's unit in the
        model, SI); allowed units per quantity in :data:`UNITS`.
    fs : float, optional
        Sampling rate (Hz) of files without a time column or ``fs`` entry.
    speed_rpm : float, optional
        Running speed of every window. Default: from ``tacho``, else from a column named
        ``tacho``, else estimated per window (the dominant line, median over channels).
    tacho : str, optional
        Column holding a once-per-revolution pulse.

    Returns
    -------
    pandas.DataFrame
        One row per window: ``input``, ``window`` (0, 1 …), ``start_s``, ``end_s`` (from
        the record's start), ``speed_rpm``, ``predicted``, ``p_<class>`` for every class,
        ``warnings`` (empty, or what lies outside the training ranges); after a file's
        windows a row with ``window`` = ``"all"``: the class most windows have (ties: the
        higher mean probability) and the mean probabilities. A dataset folder gives one
        row per run (``input`` = its ``run_id``, ``window`` 0: the stored analysis
        window, times from the run's start). ``attrs["model_warnings"]``: what the
        model's training warned of (:mod:`rubdiag.learn.caveats`; empty if nothing).
        A ``fault``-target model's table has, before ``warnings``, ``p_predicted``,
        ``p_rubbing`` (the summed probability of the classes with rub), ``confuser`` and
        ``p_confuser`` (the most probable class without rub; :func:`fault_columns`).
    """
    if not isinstance(model, Model):
        model = load_model(model)
    paths = [inputs] if isinstance(inputs, str | os.PathLike) else list(inputs)
    if not paths:
        raise ValueError("inputs is empty (allowed: at least one file or dataset folder)")
    if speed_rpm is not None and tacho is not None:
        raise ValueError("speed_rpm and tacho exclude each other (allowed: one of them)")
    if speed_rpm is not None:
        speed_rpm = _check.positive("speed_rpm", speed_rpm, "rpm")
    columns = _check_columns(model, columns)
    factors = _unit_factors(model, units)
    tables = []
    for path in paths:
        path = Path(path)
        if path.is_dir():
            given = [n for n, v in (("columns", columns), ("units", units), ("fs", fs),
                                    ("speed_rpm", speed_rpm), ("tacho", tacho)) if v]
            if given:
                raise ValueError(f"{path}: a dataset folder brings its channels, units, "
                                 f"sampling rate and speeds; {given[0]} applies to signal "
                                 "files only")
            tables.append(predict_rows(model, read_dataset(path)))   # one row per run
        else:
            table = _predict_file(model, path, columns, factors, fs, speed_rpm, tacho)
            tables += [table, _majority(table, model)]
    out = pd.concat(tables, ignore_index=True)
    out.attrs["model_warnings"] = list(model.meta.get("warnings", []))
    return out


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
                  np.full(len(data), start), np.full(len(data), start + window_s))


def _predict_file(model: Model, path: Path, columns: dict, factors: dict, fs, speed_rpm,
                  tacho) -> pd.DataFrame:
    frame, fs = read_signals(path, fs)
    name = path.name
    pulses = None
    if tacho is not None:
        if tacho not in frame.columns:
            raise ValueError(f"{name}: tacho column {tacho!r} not found (its columns: "
                             f"{', '.join(frame.columns)})")
        pulses = frame[tacho].to_numpy()
    elif speed_rpm is None:
        found = [c for c in frame.columns if c.lower() == "tacho" and c not in columns]
        pulses = frame[found[0]].to_numpy() if found else None
    for column in columns:
        if column not in frame.columns:
            raise ValueError(f"{name}: column {column!r} not found (its columns: "
                             f"{', '.join(frame.columns)})")
    frame = frame.rename(columns=columns)
    missing = [c for c in model.channels if c not in frame.columns]
    if missing:
        raise ValueError(missing_channels(name, missing, model, "the file",
                                          list(frame.columns), mappable=True))
    X = np.vstack([frame[c].to_numpy(dtype=np.float64) * factors[c] for c in model.channels])
    window_s = model.meta["window_s"]
    n = round(window_s * fs)
    n_windows = X.shape[1] // n
    if n_windows == 0:
        raise ValueError(f"{name}: the record lasts {X.shape[1] / fs:.4g} s, shorter than "
                         f"one window of the model ({window_s:g} s)")
    options = _options(model)
    rows = []
    for i in range(n_windows):
        part = slice(i * n, (i + 1) * n)
        where = f"{name}, window {i}"
        if speed_rpm is not None:
            speed = speed_rpm
        elif pulses is not None:
            speed = tacho_speed(pulses[part], fs)
        else:
            speed = _dominant_speed(X[:, part], fs, model.channels, options, where)
        _check_fs(model, fs, speed, where)
        signals = dict(zip(model.channels, X[:, part], strict=True))
        row = prefixed_features(signals, fs, speed, separator=SEPARATOR, **options)
        row = pd.concat([row, pd.DataFrame([pair_columns(signals, fs, speed)])], axis=1)
        _check_measured(model, row, fs, speed, where)
        rows.append(row)
    data = pd.concat(rows, ignore_index=True)
    starts = np.arange(n_windows) * n / fs
    return _table(model, data, [str(path)] * n_windows, np.arange(n_windows), starts,
                  starts + n / fs)


def _table(model: Model, data: pd.DataFrame, inputs, windows, starts, ends) -> pd.DataFrame:
    """Window rows: probabilities of the pipeline, warnings from the training ranges."""
    pipeline = model.pipeline
    proba = pipeline.predict_proba(data)
    classes = [str(c) for c in pipeline.classes_]
    speed = data["speed_rpm"].to_numpy(dtype=np.float64)
    table = pd.DataFrame({"input": inputs, "window": pd.Series(windows, dtype=object),
                          "start_s": starts, "end_s": ends, "speed_rpm": speed,
                          "predicted": np.asarray(classes, dtype=object)[proba.argmax(axis=1)]})
    for j, c in enumerate(classes):
        table[f"p_{c}"] = proba[:, j]
    Z = pipeline.named_steps["features"].transform(data)
    table = fault_columns(table, model)
    table["warnings"] = [_range_warnings(model, s, z) for s, z in zip(speed, Z, strict=True)]
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


def _majority(table: pd.DataFrame, model: Model) -> pd.DataFrame:
    """The input's row ``window = "all"``: most frequent class (ties: higher mean
    probability), mean probabilities."""
    p = [f"p_{c}" for c in model.classes]
    mean = table[p].mean()
    counts = table["predicted"].value_counts()
    tied = [c for c in model.classes if counts.get(c, 0) == counts.max()]
    best = max(tied, key=lambda c: mean[f"p_{c}"])
    warned = int((table["warnings"] != "").sum())
    row = {"input": table["input"].iloc[0], "window": "all",
           "start_s": table["start_s"].min(), "end_s": table["end_s"].max(),
           "speed_rpm": float(table["speed_rpm"].median()), "predicted": best,
           **mean.to_dict(),
           "warnings": f"{warned} of {len(table)} windows with warnings" if warned else ""}
    return fault_columns(pd.DataFrame([row]), model)


def _range_warnings(model: Model, speed: float, z: np.ndarray) -> str:
    """What of a window lies outside the training ranges, in words ("" if nothing)."""
    out = []
    lo, hi = model.meta["speed_range_rpm"]
    if not lo * (1 - RANGE_TOLERANCE) <= speed <= hi * (1 + RANGE_TOLERANCE):
        out.append(f"speed {speed:.0f} rpm is outside the training range {lo:.0f}–{hi:.0f} "
                   "rpm")
    ranges = model.meta["feature_ranges"]
    names = list(ranges)
    bounds = np.array([ranges[n] for n in names], dtype=np.float64).reshape(-1, 2)
    low, high = bounds[:, 0], bounds[:, 1]
    tol = RANGE_TOLERANCE * (high - low)
    excess = np.maximum(low - tol - z, z - high - tol)
    outside = np.flatnonzero(excess > 0)
    if outside.size:
        # the worst: furthest outside in units of its range (a constant feature first)
        scale = np.maximum(high - low, np.finfo(float).tiny)
        j = outside[np.argmax(excess[outside] / scale[outside])]
        out.append(f"{outside.size} of {len(names)} features outside their training range "
                   f"(worst: {names[j]} = {z[j]:.4g}, range {low[j]:.4g} to {high[j]:.4g})")
    return "; ".join(out)


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


def _dominant_speed(X: np.ndarray, fs: float, channels, options: dict, where: str) -> float:
    """The running speed of a window from the dominant lines of its channels: their vote
    (:func:`rubdiag.signal.speedvote.voted_speed`, the estimator of ``rubdiag features``
    too)."""
    try:
        return voted_speed(X, fs, Options(**options), list(channels)).rpm
    except SpeedNotFound:
        raise ValueError(f"{where}: the speed cannot be estimated (no line of "
                         f"{', '.join(channels)} stands out of the noise as 1x); give "
                         "speed_rpm (--speed-rpm) or a tacho (--tacho)") from None


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
    named as a dataset row names them (:func:`rubdiag.dataset.schema.pair_channel`), from
    the same function; empty without a pair."""
    from rubdiag.signal.fullspectrum import pairs_features

    pairs = {name: (signals[y], signals[z]) for y in signals for z in signals
             if (name := pair_channel(y, z)) is not None}
    if not pairs:
        return {}
    rows = pairs_features(pairs, fs, speed_rpm)
    return {f"{name}{SEPARATOR}{n}": row[n] for name, row in rows.items() for n in PAIR_FEATURES}


def _check_measured(model: Model, row: pd.DataFrame, fs: float, speed: float,
                    where: str) -> None:
    """An order line the model uses that came out unmeasurable (NaN amplitude: its band
    reaches the Nyquist frequency) would be read as "absent": refuse instead (the
    sampling-rate check is meant to catch it first). Sideband and broadband levels may be
    NaN for a short record of a slow machine, in training too: they are left alone."""
    for column in model.pipeline.named_steps["features"].required_:
        name = column.split(SEPARATOR, 1)[-1]
        if name.startswith("amp_") and np.isnan(row[column].iloc[0]):
            raise ValueError(f"{where}: {column} cannot be measured at fs = {fs:g} Hz and "
                             f"{speed:.0f} rpm (the record is too coarse for the model)")
