"""Running speed of a record: from a once-per-revolution tacho or from the dominant line."""

from __future__ import annotations

import numpy as np

from rubdiag.signal._checks import check_fs, check_signals
from rubdiag.signal.spectrum import _Spectra, _spectra


def tacho_speed(pulses, fs: float) -> float:
    """Mean running speed from a once-per-revolution pulse train.

    Rising crossings of the level halfway between the signal's minimum and maximum are
    located to a fraction of a sample by linear interpolation; the speed is the number of
    whole revolutions between the first and last crossing over the time between them.

    Parameters
    ----------
    pulses : array_like, 1-D
        Tacho (key-phasor) signal: one pulse per revolution, any unit and polarity of the
        baseline, pulses pointing up.
    fs : float
        Sampling frequency in Hz.

    Returns
    -------
    float
        Speed in rpm.
    """
    fs = check_fs(fs)
    x = check_signals(pulses, "tacho signal")
    if x.shape[0] != 1:
        raise ValueError("the tacho signal must be 1-D")
    x = x[0]
    level = 0.5 * (x.min() + x.max())
    above = x > level
    i = np.flatnonzero(~above[:-1] & above[1:])  # crossing between samples i and i + 1
    if i.size < 3:
        raise ValueError(
            f"the tacho signal has {i.size} pulses; at least 3 are needed to measure a speed"
        )
    t = (i + (level - x[i]) / (x[i + 1] - x[i])) / fs
    return 60.0 * (i.size - 1) / (t[-1] - t[0])


def dominant_speed(x, fs: float, window="hann", nperseg: int | None = None, detrend="constant"):
    """Running speed taken as the frequency of the strongest line (assumed to be 1×).

    Parameters
    ----------
    x : array_like
        One signal (1-D) or several (2-D, rows are signals).
    fs : float
        Sampling frequency in Hz.
    window, nperseg, detrend
        As for :func:`amplitude_spectrum`.

    Returns
    -------
    float or ndarray
        Speed in rpm (one per row for 2-D input).
    """
    fs = check_fs(fs)
    X = check_signals(x, "x")
    rpm = 60.0 * _dominant_hz(_spectra(X, fs, window, nperseg, None, None, detrend))
    return float(rpm[0]) if np.ndim(x) == 1 else rpm


def _dominant_hz(spec: _Spectra) -> np.ndarray:
    """Exact frequency (Hz) of the strongest bin of each row, DC and edges excluded."""
    a = spec.amplitude
    if a.shape[1] < 5:
        raise ValueError("the record is too short to find a dominant line")
    p = 2 + np.argmax(a[:, 2:-2], axis=1)
    f, _, _ = spec.kernel.refine(a, None, p, spec.df)
    return f
