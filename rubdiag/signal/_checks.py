"""Up-front argument checks shared by the signal layer.

Every check raises :class:`ValueError` with a message that names the problem and the offending
value, so that the command line can print it as one line.
"""

from __future__ import annotations

import math

import numpy as np

#: Fewest samples a record may have (records shorter than a few revolutions are refused
#: by :func:`check_resolution`; this only keeps the arithmetic meaningful).
MIN_SAMPLES = 2


def check_fs(fs) -> float:
    """Return ``fs`` as a float, or raise if it is not a positive finite number (Hz)."""
    try:
        value = float(fs)
    except (TypeError, ValueError):
        raise ValueError(f"fs must be a positive number in Hz, got {fs!r}") from None
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"fs must be a positive finite number in Hz, got {fs!r}")
    return value


def check_signals(x, what: str = "signal", labels=None) -> np.ndarray:
    """Return ``x`` as a 2-D float64 array (rows are signals), checking values and length.

    Raises when ``x`` is empty, shorter than :data:`MIN_SAMPLES`, non-numeric, not finite
    or constant (a row whose samples are all equal carries no spectrum). ``labels`` names
    the rows in messages (default ``row i``).
    """
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be numeric") from None
    if arr.ndim == 0:
        raise ValueError(f"{what} must be an array of samples, got a scalar")
    if arr.ndim == 1:
        arr = arr[np.newaxis, :]
    if arr.ndim != 2:
        raise ValueError(f"{what} must be 1-D or 2-D, got {arr.ndim} dimensions")
    if arr.size == 0:
        raise ValueError(f"{what} is empty")
    n = arr.shape[1]
    if n < MIN_SAMPLES:
        raise ValueError(f"{what} has {n} samples; at least {MIN_SAMPLES} are needed")
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
    flat = high - low <= 1e-12 * scale
    if flat.any():
        row = int(np.flatnonzero(flat)[0])
        where = f" ({_label(labels, row)})" if arr.shape[0] > 1 else ""
        raise ValueError(f"{what} is constant{where}: it has no spectrum to analyse")
    return arr


def _label(labels, row: int) -> str:
    return f"row {row}" if labels is None else str(labels[row])


def check_speed(speed_rpm, n_rows: int) -> np.ndarray:
    """Return the running speed as an array of ``n_rows`` 1× frequencies in Hz."""
    try:
        rpm = np.broadcast_to(np.asarray(speed_rpm, dtype=np.float64), (n_rows,)).copy()
    except (TypeError, ValueError):
        raise ValueError(
            f"speed_rpm must be a number or one number per signal, got {speed_rpm!r}"
        ) from None
    bad = ~np.isfinite(rpm) | (rpm <= 0.0)
    if bad.any():
        raise ValueError(
            f"speed_rpm must be positive and finite, got {rpm[np.flatnonzero(bad)[0]]!r}"
        )
    return rpm / 60.0


def check_resolution(f1_hz: np.ndarray, fs: float, n_seg: int, min_revolutions: float) -> None:
    """Raise when 1× lies above Nyquist or a segment holds too few revolutions."""
    nyquist = fs / 2.0
    high = f1_hz >= nyquist
    if high.any():
        f1 = float(f1_hz[np.flatnonzero(high)[0]])
        raise ValueError(
            f"1x = {f1:g} Hz ({60 * f1:g} rpm) is above the Nyquist frequency "
            f"{nyquist:g} Hz of fs = {fs:g} Hz"
        )
    revolutions = f1_hz * n_seg / fs
    short = revolutions < min_revolutions
    if short.any():
        i = int(np.flatnonzero(short)[0])
        raise ValueError(
            f"the record is too short: {n_seg} samples ({n_seg / fs:g} s) hold "
            f"{revolutions[i]:.3g} revolutions at {60 * f1_hz[i]:g} rpm; "
            f"at least {min_revolutions:g} are needed"
        )
