"""Running speed of a record: from a once-per-revolution tacho or from the dominant line.

A speed guessed from the dominant line comes with its *confidence*: the line's amplitude over
the local noise floor at its frequency (:func:`speed_confidence`). White, pink or brown noise
alone gives at most about 5 (the largest of many noise bins over their median); a real 1×
line stands far higher. Below :data:`MIN_SPEED_CONFIDENCE` the feature table refuses the
guess rather than report the frequency of a noise peak as the running speed.

Which line is 1×
----------------
The strongest line is taken as 1×. The confidence says that it stands out, not that it is
1×: a weaker line at exactly 1/2 or 1/3 of its frequency f (:data:`SUBMULTIPLES`, within
the order search band ``band`` of f/k) makes the guess **ambiguous** whenever it counts as a
line (``threshold`` times above the local noise floor, as the feature table counts lines:
a line the features would report as ½× or ⅓× never passes unremarked). Two machines give
that spectrum:

* one turning at f/k whose k× is stronger than its 1×: a cracked shaft or a misaligned
  coupling near 1/k of a critical speed, where the k× resonance amplifies it (2× up to
  about 5 × 1× in published models);
* one turning at f with a 1/k× sub-harmonic: rub, a loose support (½×, ⅓×) — the faults
  the features are asked to find.

One spectrum cannot tell them apart (1× + 2× with 2× = 2 × 1× has the lines of 1× + ½×
with ½× = 0.5 × 1×), so the estimator does not choose silently: it keeps the strongest
line as 1× and says that the speed is ambiguous, naming the other candidates
(:class:`SpeedAmbiguous`, :attr:`~rubdiag.signal._speedvote.SpeedVote.ambiguous`, the
``speed_ambiguous`` column of :func:`rubdiag.learn._predict`). Why the strongest line and
not f/k: taking f/k would halve the speed of every rubbing record with a clear ½× line —
its sub-harmonic read as 1×, its 1× as 2×: a crack's signature, a rub missed — whereas
keeping f doubles the speed only of records whose k× exceeds their 1×, and those are
flagged. A tacho or a given speed settles both. Sub-synchronous lines that are no exact
sub-multiple (oil whirl and whip, typically 0.40–0.48×) leave the speed unambiguous. A
fundamental too weak to count as a line cannot be seen: such a record reads as its k×
alone.
"""

from __future__ import annotations

import numpy as np

from rubdiag.signal._lines import REL_FLOOR, line_mask
from rubdiag.signal._records import RecordTooShort, check_fs, check_signals
from rubdiag.signal._spectrum import _Spectra, _spectra
from rubdiag.signal._tacho import _pulse_times

#: Least confidence (line amplitude over the local noise floor) of a guessed speed: 10,
#: i.e. 20 dB, twice what the strongest of a million noise bins reaches.
MIN_SPEED_CONFIDENCE = 10.0
#: The k of the lines at f/k (f: the strongest line's frequency) that make a guessed speed
#: ambiguous (module docstring): a 1× below a stronger 2× or 3×, or a ½×, ⅓× sub-harmonic.
SUBMULTIPLES = (2, 3)
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
        :func:`rubdiag.signal.signal_features` reports how far the line stands above the noise
        (``speed_confidence``) and refuses a guess that does not stand out, and
        :func:`~rubdiag.signal.voted_speed` says when 1× may be a weaker line at 1/2 or 1/3
        of it (module docstring).
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


class SpeedAmbiguous(UserWarning):
    """A guessed speed whose 1× may be a weaker line at 1/2 or 1/3 of the strongest line's
    frequency (module docstring, "Which line is 1×"); the speed used is the strongest
    line's. Give the speed or a tacho to settle it."""


def submultiple_lines(spec: _Spectra, floor: np.ndarray, f1: np.ndarray, threshold: float,
                      band: float) -> np.ndarray:
    """How far a line at ``f1 / k`` stands above the noise floor, per row and k of
    :data:`SUBMULTIPLES`.

    Parameters
    ----------
    spec : _Spectra
        Spectra of the rows.
    floor : ndarray, (n_rows, n_bins)
        Their local noise floor (:func:`~rubdiag.signal._lines.noise_floor`).
    f1 : ndarray, (n_rows,)
        The frequency taken as 1× in each row, Hz.
    threshold : float
        A line counts from ``threshold`` times the floor, as in the feature table
        (:func:`~rubdiag.signal._lines.line_mask`: a strict local maximum, clear of a
        stronger line's sidelobes).
    band : float
        Relative half-width of the search around ``f1 / k`` (the order search band of a 1×
        at ``f1 / k``); at least one bin. The line's exact frequency must lie within it.

    Returns
    -------
    ndarray, (n_rows, len(SUBMULTIPLES))
        The strongest counted line's amplitude over the floor at its bin (the floor no
        lower than :data:`REL_FLOOR` of the row's strongest bin, as in
        :func:`speed_confidence`); 0 where no line lies at ``f1 / k``.
    """
    a = spec.amplitude
    n_rows, n_bins = a.shape
    mask = line_mask(a, floor, threshold, spec.kernel)
    rows = np.arange(n_rows)
    low = np.maximum(floor, REL_FLOOR * a[:, 2:-2].max(axis=1, keepdims=True))
    out = np.zeros((n_rows, len(SUBMULTIPLES)))
    for j, k in enumerate(SUBMULTIPLES):
        target = f1 / k
        tol = np.maximum(band * target, spec.df)
        lo = np.ceil((target - tol) / spec.df).astype(np.int64)
        hi = np.floor((target + tol) / spec.df).astype(np.int64)
        bins = lo[:, np.newaxis] + np.arange(int(max((hi - lo).max(), 0)) + 1)
        inside = (bins <= hi[:, np.newaxis]) & (bins >= 2) & (bins < n_bins - 2)
        bins = np.clip(bins, 2, n_bins - 3)
        counted = np.where(inside & mask[rows[:, np.newaxis], bins],
                           a[rows[:, np.newaxis], bins], 0.0)
        best = np.argmax(counted, axis=1)
        p = bins[rows, best]
        f, _, _ = spec.kernel.refine(a, None, p, spec.df)
        there = (counted[rows, best] > 0.0) & (np.abs(f - target) <= tol)
        out[:, j] = np.where(there, a[rows, p] / low[rows, p], 0.0)
    return out


def ambiguity(rpm: float, submultiples, where: str = "") -> str:
    """Why the guessed speed ``rpm`` is ambiguous, in one sentence ("" when it is not).

    Parameters
    ----------
    rpm : float
        The guessed speed (the strongest line's frequency), rpm.
    submultiples : sequence of float
        Per k of :data:`SUBMULTIPLES`, the line at ``rpm / k`` over the noise floor
        (:func:`submultiple_lines`; 0: no line).
    where : str
        What the speed is of (a file, a row), for the message.
    """
    found = [(k, float(c)) for k, c in zip(SUBMULTIPLES, submultiples, strict=True) if c > 0]
    if not found:
        return ""
    one = len(found) == 1
    speeds = [f"{rpm / k:.5g}" for k, _ in found]
    return (f"the speed{where} is ambiguous: {rpm:.5g} rpm is the strongest line, taken as "
            f"1x, but {'a line' if one else 'lines'} at "
            f"{' and '.join(f'1/{k}' for k, _ in found)} of its frequency "
            f"({' and '.join(speeds)} rpm) {'stands' if one else 'stand'} "
            f"{' and '.join(f'{c:.3g}' for _, c in found)} times above the noise floor: 1x "
            f"may be {' or '.join(speeds)} rpm below a stronger "
            f"{' or '.join(f'{k}x' for k, _ in found)}, or "
            f"{'that line a' if one else 'those lines'} "
            f"{' or '.join(f'1/{k}x' for k, _ in found)} sub-harmonic{'' if one else 's'} "
            "(rub, looseness); give speed_rpm or a tacho signal")
