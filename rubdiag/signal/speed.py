"""Running speed of a record: from a once-per-revolution tacho or from the dominant line.

A speed guessed from the dominant line comes with its *confidence*: the line's amplitude over
the local noise floor at its frequency (:func:`speed_confidence`). White, pink or brown noise
alone gives at most about 5 (the largest of many noise bins over their median); a real 1×
line stands far higher. Below :data:`MIN_SPEED_CONFIDENCE` the feature table refuses the
guess rather than report the frequency of a noise peak as the running speed. The confidence
says that a line stands out, not that it is 1×: a signal whose 2× is stronger than its 1×
still needs its speed given.
"""

from __future__ import annotations

import numpy as np

from rubdiag.signal.lines import REL_FLOOR
from rubdiag.signal.records import RecordTooShort, check_fs, check_signals
from rubdiag.signal.spectrum import _Spectra, _spectra
from rubdiag.signal.tacho import _pulse_times

#: Least confidence (line amplitude over the local noise floor) of a guessed speed: 10,
#: i.e. 20 dB, twice what the strongest of a million noise bins reaches.
MIN_SPEED_CONFIDENCE = 10.0
#: Revolutions over which :func:`tacho_speed_range` averages the speed.
SPREAD_REVOLUTIONS = 10


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
    t, _ = _pulse_times(pulses, check_fs(fs))
    return 60.0 * (t.size - 1) / (t[-1] - t[0])


def tacho_speed_range(pulses, fs: float) -> tuple[float, float, float]:
    """Mean, lowest and highest running speed (rpm) of a once-per-revolution pulse train.

    The mean is :func:`tacho_speed`'s. The lowest and highest are those of the mean speeds
    over :data:`SPREAD_REVOLUTIONS` consecutive revolutions (fewer in a short record: a
    quarter of its revolutions, at least one), so that the jitter of single pulses (a
    fraction of a sample each) hardly counts.
    """
    t, _ = _pulse_times(pulses, check_fs(fs))
    n = t.size - 1
    w = min(SPREAD_REVOLUTIONS, max(n // 4, 1))
    rpm = 60.0 * w / (t[w:] - t[:-w])
    return 60.0 * n / (t[-1] - t[0]), float(rpm.min()), float(rpm.max())


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
        Speed in rpm (one per row for 2-D input); NaN for a still signal (no line at all).
        :func:`rubdiag.signal.features` reports how far the line stands above the noise
        (``speed_confidence``) and refuses a guess that does not stand out.
    """
    fs = check_fs(fs)
    X, still = check_signals(x, "x")
    f1, _ = dominant_line(_spectra(X, fs, window, nperseg, None, None, detrend))
    rpm = np.where(still, np.nan, 60.0 * f1)
    return float(rpm[0]) if np.ndim(x) == 1 else rpm


def dominant_line(spec: _Spectra) -> tuple[np.ndarray, np.ndarray]:
    """Exact frequency (Hz) and bin of the strongest bin of each row, DC and edges excluded."""
    a = spec.amplitude
    if a.shape[1] < 5:
        raise RecordTooShort(f"the record is too short to find a dominant line: "
                             f"{a.shape[1]} frequency bins (allowed: at least 5)")
    p = 2 + np.argmax(a[:, 2:-2], axis=1)
    f, _, _ = spec.kernel.refine(a, None, p, spec.df)
    return f, p


def speed_confidence(amplitude: np.ndarray, floor: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Amplitude of bin ``p`` of each row over the noise ``floor`` there.

    The floor is taken no lower than :data:`REL_FLOOR` of the line (round-off level), so a
    noise-free line has confidence ``1 / REL_FLOOR`` = 1e6, not infinity.
    """
    rows = np.arange(amplitude.shape[0])
    line = amplitude[rows, p]
    with np.errstate(invalid="ignore"):     # a row without any line: NaN
        return line / np.maximum(floor[rows, p], REL_FLOOR * line)
