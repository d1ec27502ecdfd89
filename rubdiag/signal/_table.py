"""The feature table: one row per signal, one column per feature.

Columns (``<k>`` is an order label such as ``1x``, ``1p5x``, ``0p33x``; ``<n>`` is 1 … 8):

``speed_rpm``
    Running speed used (given, from the tacho, or from the dominant line), rpm.
``speed_confidence``
    How far the line taken as 1× stands above the noise when the speed was guessed from the
    dominant lines: a line's amplitude over the local noise floor at its frequency (the
    local median level lines are judged against; at most 1e6, the round-off level), summed
    over the channels whose strongest lines agree on the speed
    (:mod:`rubdiag.signal._speedvote`; :func:`features` gives every moving channel of a
    record the record's speed and this value; the batch path guesses each row alone). Noise
    alone reaches about 5; a guess below :data:`~rubdiag.signal._speed.MIN_SPEED_CONFIDENCE`
    (10) is refused with a ValueError. NaN when the speed was given (``speed_rpm``, a tacho)
    or the channel is still: nothing was guessed from it.
``rms``
    RMS of the (detrended) signal, unit of the signal.
``amp_<k>``, ``freq_<k>_hz``, ``phase_<k>_deg`` for k = 0.5, 1, 1.5, …, 8
    Peak amplitude (unit of the signal), exact frequency and phase (of ``cos(2πft + φ)``,
    t = 0 at the first sample, of the first segment) of the strongest significant line
    within k× ± ``band``·1×.
``amp_<k>`` for k = 1/3, 2/3, 4/3, …, 23/3 (``amp_0p33x``, ``amp_0p67x``, ``amp_1p33x`` …)
    The 1/3-order family.
``n_half_orders``, ``n_third_orders``
    How many lines of the fractional families are present: (2k+1)/2 × (0.5×, 1.5×, …, 7.5×)
    and k/3 × (k not a multiple of 3).
``sb_<n>x_delta_hz``, ``sb_<n>x_lower``, ``sb_<n>x_upper``, ``bb_<n>x_rms``
    Sideband spacing Δ (Hz) and the amplitudes of n× − Δ and n× + Δ; RMS over n× ± 0.25×
    without the n× line (see :mod:`rubdiag.signal._sidebands`). Both are read with every
    line's leakage taken out (:mod:`rubdiag.signal._linefree`): a line between two bins puts
    nothing beside its main lobe, and the broadband leaves out the n× line's main lobe.
``combo_fa_hz``, ``combo_fb_hz``, ``combo_order``, ``combo_amp_a``, ``combo_amp_b``
    The strongest combination pair f_a + f_b = m× (see :mod:`rubdiag.signal._combinations`).

Absent and unmeasurable features
--------------------------------
* A line is *absent* when no significant line (``threshold`` × the local median level)
  lies where it is searched. Its **amplitude is 0** (``amp_*``, ``sb_*_lower``,
  ``sb_*_upper``, ``combo_amp_*``) and its **location is NaN** (``freq_*``, ``phase_*``,
  ``sb_*_delta_hz``, ``combo_fa_hz``, ``combo_fb_hz``, ``combo_order``): an absent line
  has zero amplitude, but no frequency, phase or spacing.
* A feature is *unmeasurable* when its search band reaches above the Nyquist frequency
  (e.g. 8× of a fast machine sampled slowly), or, for sidebands, when the record is too
  short to resolve any Δ < 0.25× outside the n× line's main lobe (about 13
  revolutions or fewer with the Hann window): **every** column of it is NaN, amplitudes too.
* ``bb_*_rms`` is measured whenever its band lies below Nyquist (NaN above it, or when a
  present line's main lobe covers the whole band of a record of a few revolutions).

Still channels
--------------
A channel whose samples are all equal (a dead sensor, a casing no blade touched) is valid
input with no line at all: every line is absent (:func:`still_features`: amplitudes, ``rms``
and levels 0, locations NaN), ``speed_rpm`` is the record's speed, given or guessed from
the other channels (NaN in the batch path) and ``speed_confidence`` NaN. The rule is the
same for :func:`features`, :func:`prefixed_features`, :func:`feature_matrix` and
:class:`~rubdiag.signal.RubFeatures`; the other rows of a batch are analysed as usual, and an
input whose every channel is still gives every row absent, without an exception — except
a record given to :func:`features` without its speed: with no line to guess it from, it is
refused (ValueError).

Layout
------
Arrays hold one channel per row, time along the last axis; DataFrames and files one channel
per column. An array with more rows than samples that is too short to analyse is most likely
transposed: the error says so.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag.signal._analysis import Analysis, analyse
from rubdiag.signal._combinations import strongest_pair
from rubdiag.signal._io import read_signals
from rubdiag.signal._options import Options
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label
from rubdiag.signal._records import (
    RecordTooShort,
    check_fs,
    check_resolution,
    check_signals,
    check_speed,
    transposed_hint,
)
from rubdiag.signal._speed import SpeedAmbiguous, tacho_speed_range
from rubdiag.signal._speedvote import voted_speed

# Rows analysed together: bounds the memory of the batch path.
_ROWS_PER_CHUNK = 128
#: Records shorter than this hold no measurable line: their features are all NaN.
MIN_LINE_SAMPLES = 16

_HALF = [order_label(k) for k in HALF_ORDERS]
_THIRD = [order_label(k) for k in THIRD_ORDERS]
_FRACTIONAL_HALF = np.array([abs(k - round(k)) > 0.25 for k in HALF_ORDERS])

#: Columns that describe the record's speed rather than its lines.
SPEED_NAMES = ("speed_rpm", "speed_confidence")

FEATURE_NAMES: tuple[str, ...] = (
    *SPEED_NAMES,
    "rms",
    *(f"amp_{k}" for k in _HALF),
    *(f"freq_{k}_hz" for k in _HALF),
    *(f"phase_{k}_deg" for k in _HALF),
    *(f"amp_{k}" for k in _THIRD),
    "n_half_orders",
    "n_third_orders",
    *(
        f"{name.format(n=n)}"
        for n in HARMONICS
        for name in ("sb_{n}x_delta_hz", "sb_{n}x_lower", "sb_{n}x_upper", "bb_{n}x_rms")
    ),
    "combo_fa_hz",
    "combo_fb_hz",
    "combo_order",
    "combo_amp_a",
    "combo_amp_b",
)


_RMS = FEATURE_NAMES.index("rms")


def feature_names() -> list[str]:
    """Names of the feature columns, in table order (without ``channel``).

    Returns
    -------
    list of str
        A copy of :data:`FEATURE_NAMES`.
    """
    return list(FEATURE_NAMES)


def _columns(an: Analysis) -> dict[str, np.ndarray]:
    cols: dict[str, np.ndarray] = {
        "speed_rpm": 60.0 * an.f1_hz, "speed_confidence": an.speed_confidence, "rms": an.rms,
    }
    half, third, sb = an.half, an.third, an.sidebands
    for j, k in enumerate(_HALF):
        cols[f"amp_{k}"] = half.amp[:, j]
    for j, k in enumerate(_HALF):
        cols[f"freq_{k}_hz"] = half.freq[:, j]
    for j, k in enumerate(_HALF):
        cols[f"phase_{k}_deg"] = half.phase[:, j]
    for j, k in enumerate(_THIRD):
        cols[f"amp_{k}"] = third.amp[:, j]
    cols["n_half_orders"] = half.present[:, _FRACTIONAL_HALF].sum(axis=1).astype(float)
    cols["n_third_orders"] = third.present.sum(axis=1).astype(float)
    for j, n in enumerate(HARMONICS):
        cols[f"sb_{n}x_delta_hz"] = sb.delta[:, j]
        cols[f"sb_{n}x_lower"] = sb.lower[:, j]
        cols[f"sb_{n}x_upper"] = sb.upper[:, j]
        cols[f"bb_{n}x_rms"] = an.broadband[:, j]
    cols.update(strongest_pair(an))
    return cols


def feature_matrix(
    X, fs: float, speed_rpm=None, options: Options | None = None, labels=None
) -> np.ndarray:
    """Features of the rows of ``X`` (n_signals, n_samples) as a float array.

    The batch path: rows are analysed together (vectorised), :data:`_ROWS_PER_CHUNK` at a
    time to bound memory. Columns follow :data:`FEATURE_NAMES`. ``speed_rpm`` is one
    number, one per row, or None (dominant line of each row); ``labels`` name the rows in
    error messages. Still rows get :func:`still_features` (module docstring).

    Parameters
    ----------
    X : array_like
        (n_signals, n_samples) signals, one per row, in any unit.
    fs : float
        Sampling frequency (Hz).
    speed_rpm : float, array_like or None
        Running speed (rpm): one for all rows, one per row, or None.
    options : Options or None
        The analysis settings; None: the defaults.
    labels : sequence of str or None
        Names of the rows, for error messages.

    Returns
    -------
    numpy.ndarray
        (n_signals, len(FEATURE_NAMES)) features.
    """
    return _feature_matrix(X, fs, speed_rpm, options, labels, ("X", "signal"))


def _feature_matrix(X, fs, speed_rpm, options, labels, layout) -> np.ndarray:
    """:func:`feature_matrix`; ``layout`` = (name of X, noun of its rows) for the hint that
    an array was passed transposed, or None where rows are not the caller's layout."""
    opts = Options() if options is None else options
    fs = check_fs(fs)
    try:
        X, still = check_signals(X, "signal" if layout is None else layout[0], labels)
        return _fill_rows(X, still, fs, speed_rpm, opts, labels)
    except RecordTooShort as exc:   # X converted: a transposed array reads as a short record
        raise _with_hint(exc, X, layout) from None


def _with_hint(exc: RecordTooShort, X, layout) -> RecordTooShort:
    """``exc``, saying that ``X`` was probably passed transposed where its shape says so."""
    shape = np.shape(X)
    hint = layout is not None and len(shape) == 2 and transposed_hint(shape, *layout)
    return RecordTooShort(f"{hint} (as passed, {exc})") if hint else exc


def _fill_rows(X, still, fs, speed_rpm, opts: Options, labels) -> np.ndarray:
    """The feature matrix of checked rows: still rows absent, moving rows analysed."""
    n_rows, n_samples = X.shape
    out = np.tile(_STILL_ROW, (n_rows, 1))
    if speed_rpm is not None:
        out[:, 0] = 60.0 * check_speed(speed_rpm, n_rows)
    moving = np.flatnonzero(~still)
    if moving.size == 0:
        return out
    if n_samples < MIN_LINE_SAMPLES:
        # too short to hold a line (reachable only with min_revolutions near 0): unmeasurable
        if speed_rpm is None:
            raise RecordTooShort(
                f"the record is too short to guess the speed from: {n_samples} samples "
                f"(allowed: at least {MIN_LINE_SAMPLES}); give speed_rpm")
        check_resolution(out[moving, 0] / 60.0, fs, n_samples, opts.min_revolutions)
        out[moving, _RMS:] = np.nan
        out[moving, _RMS] = X[moving].std(axis=1)
        return out
    if labels is None and n_rows > 1:
        labels = [f"row {i}" for i in range(n_rows)]
    for start in range(0, moving.size, _ROWS_PER_CHUNK):
        rows = moving[start : start + _ROWS_PER_CHUNK]
        part = None if speed_rpm is None else out[rows, 0]
        names = None if labels is None else [labels[i] for i in rows]
        cols = _columns(analyse(X[rows], fs, part, opts, checked=True, labels=names))
        out[rows] = np.column_stack([cols[name] for name in FEATURE_NAMES])
    return out


def signal_features(
    signal,
    fs: float | None = None,
    speed_rpm: float | None = None,
    *,
    tacho=None,
    columns=None,
    band: float = Options.band,
    threshold: float = Options.threshold,
    window=Options.window,
    nperseg: int | None = Options.nperseg,
    detrend=Options.detrend,
    min_revolutions: float = Options.min_revolutions,
    combo_tol_hz: float | None = Options.combo_tol_hz,
) -> pd.DataFrame:
    """Rub-impact spectral features of one or several channels, one row per channel.

    Parameters
    ----------
    signal : path, DataFrame or array_like
        A file (CSV, NPZ, parquet; see :func:`read_signals`), a DataFrame whose columns are
        channels (rows are samples), a 1-D array (one channel) or a 2-D array whose rows are
        channels (time along the last axis). A still channel (all samples equal) has every
        line absent; it raises no error.
    fs : float, optional
        Sampling frequency in Hz; for files it may come from a time column instead.
    speed_rpm : float, optional
        Running speed in rpm. When None: from ``tacho``, else from a channel named
        ``tacho`` if there is one, else the channels' strongest lines vote on 1×
        (:func:`~rubdiag.signal._speedvote.voted_speed`: a noise-only channel does not
        spoil it) and every channel is analysed at that speed: the ``speed_confidence``
        column says how far the agreeing lines stand above the noise, and a speed that
        does not stand out (below ``MIN_SPEED_CONFIDENCE``), or a record whose every
        channel is still (no line at all), raises a ValueError. A guess that may be 2× or
        3× (a line at 1/2 or 1/3 of its frequency) warns :class:`SpeedAmbiguous`
        (:mod:`rubdiag.signal._speed`, "Which line is 1×").
    tacho : str or array_like, optional
        Name of the once-per-revolution channel, or the pulse train itself (same ``fs``).
        The tacho channel (and a channel named ``tacho``) is never analysed. Its mean speed
        is the running speed; a UserWarning says when the speed (over 10 revolutions) strays
        from it by more than ``band``: the lines smear, and
        :func:`~rubdiag.signal.revolution_features` gives the features across speed.
    columns : str or list of str, optional
        Channels to analyse (default: all).
    band : float
        Half-width of the order search band, in orders (0.03: ±3 % of 1×).
    threshold : float
        A line is significant above ``threshold`` × the local median level.
    window, nperseg, detrend
        As for :func:`amplitude_spectrum` (None: the whole record, one segment).
    min_revolutions : float
        Fewest revolutions a record (segment) must hold.
    combo_tol_hz : float, optional
        Tolerance of f_a + f_b = m× in Hz (None: the resolution ``fs / nperseg``). The
        defaults of these settings are those of :class:`~rubdiag.signal._options.Options`.

    Returns
    -------
    pandas.DataFrame
        A ``channel`` column, then the columns of :data:`FEATURE_NAMES` (module docstring:
        units, and 0 / NaN for absent / unmeasurable features).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 2000.0
    >>> t = np.arange(4000) / fs
    >>> x = 1.0 * np.cos(2 * np.pi * 25 * t) + 0.1 * np.cos(2 * np.pi * 37.5 * t)
    >>> row = signal_features(x, fs, speed_rpm=1500).iloc[0]
    >>> round(float(row["amp_1x"]), 4), round(float(row["amp_1p5x"]), 4), float(row["amp_2x"])
    (1.0, 0.1, 0.0)
    """
    opts = Options(band=band, threshold=threshold, window=window, nperseg=nperseg,
                   detrend=detrend, min_revolutions=min_revolutions, combo_tol_hz=combo_tol_hz)
    ch = split_channels(signal, fs, tacho, columns)
    frame, fs = ch.frame, ch.fs
    if speed_rpm is None and ch.pulses is not None:
        speed_rpm, low, high = tacho_speed_range(ch.pulses, fs)
        if max(high / speed_rpm - 1.0, 1.0 - low / speed_rpm) > opts.band:
            warnings.warn(
                f"the tacho speed varies from {low:.5g} to {high:.5g} rpm, by more than band = "
                f"{opts.band:g} of its mean {speed_rpm:.5g} rpm: the order lines smear; for "
                "features across speed give revs_per_bin (revolution_features, "
                "--revs-per-bin)", UserWarning, stacklevel=2)
    X, labels = channel_rows(frame)
    array = not isinstance(signal, str | os.PathLike | pd.DataFrame | pd.Series)
    layout = ("signal", "channel") if array and np.ndim(signal) == 2 else None
    vote = None
    if speed_rpm is None:
        record = os.fspath(signal) if isinstance(signal, str | os.PathLike) else None
        try:
            moving = ~check_signals(X, "signal", labels)[1]
            vote = voted_speed(X, fs, opts, labels, record)   # a constant record: refused
        except RecordTooShort as exc:
            raise _with_hint(exc, X, layout) from None
        speed_rpm = vote.rpm
        if vote.ambiguous:
            warnings.warn(vote.ambiguity("" if record is None else f" of {record}"),
                          SpeedAmbiguous, stacklevel=2)
    values = _feature_matrix(X, fs, speed_rpm, opts, labels, layout)
    if vote is not None:        # the record's guessed speed, on the channels that move
        values[moving, 1] = vote.confidence
    table = pd.DataFrame(values, columns=list(FEATURE_NAMES))
    table.insert(0, "channel", list(frame.columns))
    return table


def prefixed_features(signals: Mapping[str, object], fs: float, speed_rpm: float,
                      separator: str = "_", **options):
    """One row of features of several named 1-D signals of one run, columns prefixed.

    The extension point for simulation results: an adapter for
    ``SimulationResult`` calls it with ``{"shaft": …, "blade": …, "casing": …}`` and adds
    its contact statistics to the row. ``speed_rpm`` is written once, unprefixed (it is
    given, so there is no ``speed_confidence``).

    Parameters
    ----------
    signals : mapping of str to 1-D array_like
        Prefix → signal; all sampled at ``fs``, of equal length.
    fs : float
        Sampling frequency in Hz.
    speed_rpm : float
        Running speed in rpm.
    separator : str
        Between prefix and feature name (``"__"`` for datasets' ``CHANNEL__FEATURE``).
    **options
        Keyword options of :func:`features` (``band``, ``threshold``, ``window`` …).

    Returns
    -------
    pandas.DataFrame
        One row: ``speed_rpm`` then ``<prefix><separator><feature>`` for every prefix and
        feature. A
        signal that never moves (a casing no blade touched) has every line absent
        (:func:`still_features`), even when no signal moves.
    """
    return pd.DataFrame([prefixed_feature_row(signals, fs, speed_rpm, separator, **options)])


def prefixed_feature_row(signals: Mapping[str, object], fs: float, speed_rpm: float,
                         separator: str = "_", **options) -> dict:
    """:func:`prefixed_features`' row as a dict (column -> value): the same values without
    building a one-row DataFrame of thousands of columns, which costs as much as the
    features of a run's few channels."""
    if not signals:
        raise ValueError("signals is empty: give at least one {prefix: signal}")
    lengths = {name: np.shape(x) for name, x in signals.items()}
    if len(set(lengths.values())) != 1 or len(next(iter(lengths.values()))) != 1:
        raise ValueError(f"signals must be 1-D and of equal length, got shapes {lengths}")
    speed_rpm = _check.positive("speed_rpm", speed_rpm, "rpm")
    X = np.vstack([np.asarray(x, dtype=np.float64) for x in signals.values()])
    labels = [f"signal {name!r}" for name in signals]
    values = feature_matrix(X, fs, speed_rpm, Options(**options), labels)
    row = {"speed_rpm": speed_rpm}
    for prefix, v in zip(signals, values, strict=True):
        row.update({f"{prefix}{separator}{n}": v[j] for j, n in enumerate(FEATURE_NAMES)
                    if n not in SPEED_NAMES})
    return row


def still_features() -> dict[str, float]:
    """Feature values of a signal that does not move (e.g. a casing never touched): every
    line absent (amplitudes, ``rms`` and levels 0; locations NaN), as documented above.
    The speed columns (:data:`SPEED_NAMES`) are not line features and not included."""
    located = ("freq_", "phase_", "combo_fa", "combo_fb", "combo_order")
    return {name: (np.nan if name.startswith(located) or name.endswith("_delta_hz") else 0.0)
            for name in FEATURE_NAMES if name not in SPEED_NAMES}


# A still row of the feature matrix: speed and its confidence NaN, then still_features().
_STILL_ROW = np.array([np.nan, np.nan, *still_features().values()])


@dataclass(frozen=True)
class Channels:
    """The channels to analyse (columns of ``frame``), their sampling frequency, and the
    tacho pulses and recorded angle taken out of them (None where not given)."""

    frame: pd.DataFrame
    fs: float
    pulses: np.ndarray | None
    angle: np.ndarray | None


def split_channels(signal, fs, tacho=None, columns=None, angle=None) -> Channels:
    """The channels of ``signal`` (as :func:`features` reads them), less the tacho and angle.

    ``tacho`` and ``angle`` are channel names or arrays (one value per sample); without a
    tacho a channel named ``tacho`` (any case) is taken as one. Neither is analysed.
    """
    frame, fs = _channels(signal, fs)
    if tacho is None:
        tacho = next((c for c in frame.columns if str(c).lower() == "tacho"), None)
    aux = {}
    for name, value in (("tacho", tacho), ("angle", angle)):
        if isinstance(value, str):
            _require(frame, [value])
            aux[name] = frame[value].to_numpy()
            frame = frame.drop(columns=[value])
        else:
            aux[name] = value
    if columns is not None:
        names = [columns] if isinstance(columns, str) else list(columns)
        _require(frame, names)
        frame = frame[names]
    if frame.shape[1] == 0:
        raise ValueError("no channel left to analyse")
    return Channels(frame=frame, fs=fs, pulses=aux["tacho"], angle=aux["angle"])


def channel_rows(frame: pd.DataFrame) -> tuple[np.ndarray, list[str]]:
    """The channels of ``frame`` as float64 rows and their labels for messages."""
    try:
        X = frame.to_numpy(dtype=np.float64).T
    except (TypeError, ValueError):
        raise ValueError("every channel must be numeric") from None
    return X, [f"channel {c!r}" for c in frame.columns]


def _require(frame: pd.DataFrame, names) -> None:
    missing = [n for n in names if n not in frame.columns]
    if missing:
        have = ", ".join(map(str, frame.columns))
        raise ValueError(f"column {missing[0]!r} not found; the channels are: {have}")


def _channels(signal, fs) -> tuple[pd.DataFrame, float]:
    """Channels as a DataFrame (columns) and the sampling frequency."""
    if isinstance(signal, str | os.PathLike):
        return read_signals(signal, fs)
    if fs is None:
        raise ValueError("fs (the sampling frequency in Hz) is required for in-memory signals")
    fs = check_fs(fs)
    if isinstance(signal, pd.DataFrame):
        return signal, fs
    if isinstance(signal, pd.Series):
        return signal.to_frame(), fs
    arr = np.asarray(signal)
    if arr.ndim == 1:
        return pd.DataFrame({0: arr}), fs
    if arr.ndim == 2:
        return pd.DataFrame(arr.T), fs
    raise ValueError(f"signal has {arr.ndim} dimensions (allowed: 1 or 2, rows are channels)")
