"""Records of samples: what the signal layer accepts, checked up front.

A record is a 2-D float64 array whose rows are signals (channels) and whose last axis is
time. Bad input raises one line in the style of :mod:`rubdiag._check` (``fs = 0.0 is out of
range (allowed: > 0 Hz)``), naming the row where one is at fault. Two rules are signal rules,
not parameter checks, and live here:

* A *still* row (a dead sensor, a casing never touched: every sample equal, up to round-off)
  is valid input. It has no spectrum, so every line of it is absent; :func:`check_signals`
  reports which rows are still and the feature table fills them in without analysing them.
* A record must hold enough revolutions to resolve the orders (:func:`check_resolution`);
  a record that is too short raises :class:`RecordTooShort`, which callers that know the
  layout of their input turn into a hint when the array was probably passed transposed.
"""

from __future__ import annotations

import numpy as np

from rubdiag import _check

#: Fewest samples a record may have (records shorter than a few revolutions are refused
#: by :func:`check_resolution`; this only keeps the arithmetic meaningful).
MIN_SAMPLES = 2

#: Rows whose peak-to-peak range is at most this fraction of their largest magnitude are
#: still (constant up to round-off).
STILL_RANGE = 1e-12


class RecordTooShort(ValueError):
    """A record with too few samples (or revolutions) for the analysis asked of it."""


def check_fs(fs) -> float:
    """``fs`` (sampling frequency, Hz) as a float; a positive finite number."""
    return _check.positive("fs", fs, "Hz")


def check_signals(x, what: str = "signal", labels=None) -> tuple[np.ndarray, np.ndarray]:
    """``x`` as a 2-D float64 array (rows are signals) and the boolean mask of still rows.

    Raises when ``x`` is not numeric, not 1-D or 2-D, empty, shorter than
    :data:`MIN_SAMPLES` (:class:`RecordTooShort`) or not finite. ``what`` names ``x`` in
    messages, ``labels`` its rows (default ``row i``).
    """
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise _check.wrong_type(what, _brief(x), "numeric samples") from None
    if arr.ndim == 0:
        raise _check.wrong_type(what, _brief(x), "an array of samples, not a scalar")
    if arr.ndim == 1:
        arr = arr[np.newaxis, :]
    if arr.ndim != 2:
        raise ValueError(f"{what} has {arr.ndim} dimensions (allowed: 1 or 2, rows are "
                         "signals)")
    if arr.size == 0:
        raise ValueError(f"{what} is empty (allowed: at least {MIN_SAMPLES} samples)")
    n = arr.shape[1]
    if n < MIN_SAMPLES:
        raise RecordTooShort(f"{what} has {_samples(n)} per signal (allowed: at least "
                             f"{MIN_SAMPLES})")
    low, high = arr.min(axis=1), arr.max(axis=1)  # NaN and inf propagate: no big temporaries
    bad_rows = ~(np.isfinite(low) & np.isfinite(high))
    if bad_rows.any():
        row = int(np.flatnonzero(bad_rows)[0])
        col = int(np.flatnonzero(~np.isfinite(arr[row]))[0])
        where = f"sample {col}"
        if arr.shape[0] > 1:
            where = f"{_label(labels, row)}, {where}"
        raise ValueError(f"{what} contains NaN or inf (first at {where})")
    scale = np.maximum(np.maximum(np.abs(low), np.abs(high)), np.finfo(float).tiny)
    return arr, high - low <= STILL_RANGE * scale


def _label(labels, row: int) -> str:
    return f"row {row}" if labels is None else str(labels[row])


def _brief(x):
    """``x`` for a message: itself when short, else its type."""
    text = repr(x)
    return x if len(text) <= 40 else type(x).__name__


def check_speed(speed_rpm, n_rows: int) -> np.ndarray:
    """The running speed (a number, or one per signal, in rpm) as ``n_rows`` 1× frequencies
    in Hz."""
    if np.ndim(speed_rpm) == 0:
        return np.full(n_rows, _check.positive("speed_rpm", speed_rpm, "rpm") / 60.0)
    values = np.asarray(speed_rpm)
    if values.dtype.kind not in "iuf":
        raise _check.wrong_type("speed_rpm", _brief(speed_rpm),
                                "a number or one number per signal")
    if values.shape != (n_rows,):
        raise ValueError(f"speed_rpm has shape {values.shape} (allowed: one number, or one "
                         f"per signal: ({n_rows},))")
    rpm = values.astype(np.float64)
    bad = ~(np.isfinite(rpm) & (rpm > 0.0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise _check.out_of_range(f"speed_rpm[{i}]", rpm[i], "> 0 rpm")
    return rpm / 60.0


def check_resolution(f1_hz: np.ndarray, fs: float, n_seg: int, min_revolutions: float) -> None:
    """Raise when 1× lies above Nyquist or a segment of ``n_seg`` samples holds fewer than
    ``min_revolutions`` revolutions (:class:`RecordTooShort`)."""
    nyquist = fs / 2.0
    high = f1_hz >= nyquist
    if high.any():
        f1 = float(f1_hz[np.flatnonzero(high)[0]])
        raise _check.out_of_range(
            "speed_rpm", 60.0 * f1,
            f"< {60.0 * nyquist:g} rpm: 1x = {f1:g} Hz is above the Nyquist frequency "
            f"{nyquist:g} Hz of fs = {fs:g} Hz")
    revolutions = f1_hz * n_seg / fs
    short = revolutions < min_revolutions
    if short.any():
        i = int(np.flatnonzero(short)[0])
        raise RecordTooShort(
            f"the record is too short: {n_seg} samples ({n_seg / fs:g} s) hold "
            f"{revolutions[i]:.3g} revolutions at {60 * f1_hz[i]:g} rpm; "
            f"at least min_revolutions = {_check.plain(min_revolutions)} are needed"
        )


def transposed_hint(shape: tuple[int, int], what: str, noun: str) -> str | None:
    """The message for a too-short record of ``shape`` that was probably passed transposed
    (more rows than samples), or None. ``what`` names the array, ``noun`` its rows."""
    n_rows, n_samples = shape
    if n_rows <= n_samples:
        return None
    return (f"{what} has {_samples(n_samples)} per {noun} and {n_rows} {noun}s: rows are "
            f"{noun}s (time along the last axis); did you mean {what}.T?")


def _samples(n: int) -> str:
    return f"{n} sample" if n == 1 else f"{n} samples"
