"""The feature table: one row per signal, one column per feature.

Columns (``<k>`` is an order label such as ``1x``, ``1p5x``, ``0p33x``; ``<n>`` is 1 … 8):

``speed_rpm``
    Running speed used (given, from the tacho, or from the dominant line), rpm.
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
    without the n× line (see :mod:`rubdiag.signal.sidebands`).
``combo_fa_hz``, ``combo_fb_hz``, ``combo_order``, ``combo_amp_a``, ``combo_amp_b``
    The strongest combination pair f_a + f_b = m× (see :mod:`rubdiag.signal.combinations`).

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
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np
import pandas as pd

from rubdiag.signal._checks import check_fs, check_resolution, check_signals, check_speed
from rubdiag.signal.analysis import Analysis, Options, analyse
from rubdiag.signal.combinations import strongest_pair
from rubdiag.signal.io import read_signals
from rubdiag.signal.orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label
from rubdiag.signal.speed import tacho_speed

# Rows analysed together: bounds the memory of the batch path.
_ROWS_PER_CHUNK = 128
#: Records shorter than this hold no measurable line: their features are all NaN.
MIN_LINE_SAMPLES = 16

_HALF = [order_label(k) for k in HALF_ORDERS]
_THIRD = [order_label(k) for k in THIRD_ORDERS]
_FRACTIONAL_HALF = np.array([abs(k - round(k)) > 0.25 for k in HALF_ORDERS])

FEATURE_NAMES: tuple[str, ...] = (
    "speed_rpm",
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


def feature_names() -> list[str]:
    """Names of the feature columns, in table order (without ``channel``)."""
    return list(FEATURE_NAMES)


def _columns(an: Analysis) -> dict[str, np.ndarray]:
    cols: dict[str, np.ndarray] = {"speed_rpm": 60.0 * an.f1_hz, "rms": an.rms}
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
    error messages.
    """
    X = check_signals(X, "signal", labels)
    fs = check_fs(fs)
    n_rows = X.shape[0]
    speed = np.full(n_rows, np.nan)
    if speed_rpm is not None:
        speed = 60.0 * check_speed(speed_rpm, n_rows)
    out = np.empty((n_rows, len(FEATURE_NAMES)))
    if X.shape[1] < MIN_LINE_SAMPLES:
        # too short to hold a line (reachable only with min_revolutions near 0): unmeasurable
        check_resolution(speed / 60.0, fs, X.shape[1], (options or Options()).min_revolutions)
        out.fill(np.nan)
        out[:, 0] = speed
        out[:, 1] = X.std(axis=1)
        return out
    for start in range(0, n_rows, _ROWS_PER_CHUNK):
        stop = start + _ROWS_PER_CHUNK
        part = None if speed_rpm is None else speed[start:stop]
        cols = _columns(analyse(X[start:stop], fs, part, options, checked=True))
        out[start:stop] = np.column_stack([cols[name] for name in FEATURE_NAMES])
    return out


def features(
    signal,
    fs: float | None = None,
    speed_rpm: float | None = None,
    *,
    tacho=None,
    columns=None,
    band: float = 0.03,
    threshold: float = 5.0,
    window="hann",
    nperseg: int | None = None,
    detrend="constant",
    min_revolutions: float = 10.0,
    combo_tol_hz: float | None = None,
) -> pd.DataFrame:
    """Rub-impact spectral features of one or several channels, one row per channel.

    Parameters
    ----------
    signal : path, DataFrame or array_like
        A file (CSV, NPZ, parquet; see :func:`read_signals`), a DataFrame whose columns are
        channels (rows are samples), a 1-D array (one channel) or a 2-D array whose rows are
        channels (time along the last axis).
    fs : float, optional
        Sampling frequency in Hz; for files it may come from a time column instead.
    speed_rpm : float, optional
        Running speed in rpm. When None: from ``tacho``, else from a channel named
        ``tacho`` if there is one, else each channel's strongest line is taken as 1×.
    tacho : str or array_like, optional
        Name of the once-per-revolution channel, or the pulse train itself (same ``fs``).
        The tacho channel (and a channel named ``tacho``) is never analysed.
    columns : str or list of str, optional
        Channels to analyse (default: all).
    band : float
        Half-width of the order search band, in orders (default 0.03 = ±3 % of 1×).
    threshold : float
        A line is significant above ``threshold`` × the local median level (default 5).
    window, nperseg, detrend
        As for :func:`amplitude_spectrum` (default: the whole record, Hann window).
    min_revolutions : float
        Fewest revolutions a record (segment) must hold (default 10).
    combo_tol_hz : float, optional
        Tolerance of f_a + f_b = m× in Hz (default: the resolution ``fs / nperseg``).

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
    >>> row = features(x, fs, speed_rpm=1500).iloc[0]
    >>> round(float(row["amp_1x"]), 4), round(float(row["amp_1p5x"]), 4), float(row["amp_2x"])
    (1.0, 0.1, 0.0)
    """
    opts = Options(band, threshold, window, nperseg, detrend, min_revolutions, combo_tol_hz)
    frame, fs = _channels(signal, fs)
    if isinstance(tacho, str):
        _require(frame, [tacho])
    elif tacho is None:
        tacho = next((c for c in frame.columns if str(c).lower() == "tacho"), None)
    if isinstance(tacho, str):
        pulses = frame[tacho].to_numpy()
        frame = frame.drop(columns=[tacho])
    else:
        pulses = tacho
    if columns is not None:
        names = [columns] if isinstance(columns, str) else list(columns)
        _require(frame, names)
        frame = frame[names]
    if frame.shape[1] == 0:
        raise ValueError("no channel left to analyse")
    if speed_rpm is None and pulses is not None:
        speed_rpm = tacho_speed(pulses, fs)
    try:
        X = frame.to_numpy(dtype=np.float64).T
    except (TypeError, ValueError):
        raise ValueError("every channel must be numeric") from None
    labels = [f"channel {c!r}" for c in frame.columns]
    values = feature_matrix(X, fs, speed_rpm, opts, labels)
    table = pd.DataFrame(values, columns=list(FEATURE_NAMES))
    table.insert(0, "channel", list(frame.columns))
    return table


def prefixed_features(signals: Mapping[str, object], fs: float, speed_rpm: float, **options):
    """One row of features of several named 1-D signals of one run, columns prefixed.

    The extension point for simulation results: an adapter for
    ``SimulationResult`` calls it with ``{"shaft": …, "blade": …, "casing": …}`` and adds
    its contact statistics to the row. ``speed_rpm`` is written once, unprefixed.

    Parameters
    ----------
    signals : mapping of str to 1-D array_like
        Prefix → signal; all sampled at ``fs``, of equal length.
    fs : float
        Sampling frequency in Hz.
    speed_rpm : float
        Running speed in rpm.
    **options
        Keyword options of :func:`features` (``band``, ``threshold``, ``window`` …).

    Returns
    -------
    pandas.DataFrame
        One row: ``speed_rpm`` then ``<prefix>_<feature>`` for every prefix and feature. A
        signal that never moves (a casing no blade touched) has every line absent
        (:func:`still_features`); at least one signal must move.
    """
    if not signals:
        raise ValueError("signals is empty: give at least one {prefix: signal}")
    lengths = {name: np.shape(x) for name, x in signals.items()}
    if len(set(lengths.values())) != 1 or len(next(iter(lengths.values()))) != 1:
        raise ValueError(f"signals must be 1-D and of equal length, got shapes {lengths}")
    arrays = {name: np.asarray(x, dtype=np.float64) for name, x in signals.items()}
    moving = {name: x for name, x in arrays.items() if np.ptp(x) > 0 or not np.isfinite(x).all()}
    if not moving:
        raise ValueError("every signal is constant: there is no spectrum to analyse")
    values = feature_matrix(np.vstack(list(moving.values())), fs, speed_rpm, Options(**options))
    computed = dict(zip(moving, values, strict=True))
    row = {"speed_rpm": values[0, 0]}
    for prefix in arrays:
        if prefix in computed:
            v = computed[prefix]
            row.update({f"{prefix}_{n}": v[j] for j, n in enumerate(FEATURE_NAMES) if j > 0})
        else:   # a signal that never moves has no line: all absent
            row.update({f"{prefix}_{n}": v for n, v in still_features().items()})
    return pd.DataFrame([row])


def still_features() -> dict[str, float]:
    """Feature values of a signal that does not move (e.g. a casing never touched): every
    line absent (amplitudes, ``rms`` and levels 0; locations NaN), as documented above."""
    located = ("freq_", "phase_", "combo_fa", "combo_fb", "combo_order")
    return {name: (np.nan if name.startswith(located) or name.endswith("_delta_hz") else 0.0)
            for name in FEATURE_NAMES if name != "speed_rpm"}


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
    raise ValueError(f"signal must be 1-D or 2-D, got {arr.ndim} dimensions")
