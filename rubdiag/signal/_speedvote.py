"""The running speed of a record of several channels: their dominant lines vote.

Each moving channel's strongest line is a guess of 1×, weighed by its confidence (its
amplitude over the local noise floor, :func:`rubdiag.signal._speed.speed_confidence`). The
guesses that agree within the order search band (``band``) with the best-supported one are
kept, and the speed is their confidence-weighted median. A channel alone, or the first
channel, is not enough: probes at stiff bearings see mostly noise, and their strongest
"lines" fall anywhere. The kept confidences must add up to
:data:`~rubdiag.signal._speed.MIN_SPEED_CONFIDENCE` (one clear line, or several weaker ones
at the same frequency), else the speed must be given.

The vote says which line stands out, not that it is 1×: a line at 1/2 or 1/3 of the voted
frequency on any moving channel makes the speed ambiguous (``SpeedVote.ambiguous``, the
rule and why the strongest line is kept: :mod:`rubdiag.signal._speed`, "Which line is 1×").

One estimator for every door that guesses a speed: :func:`rubdiag.signal.signal_features` (and
``rubdiag features`` / ``compare``) and :func:`rubdiag.learn._predict`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag.signal._analysis import FLOOR_WIDTH_ORDERS
from rubdiag.signal._lines import block_bins, noise_floor
from rubdiag.signal._options import Options
from rubdiag.signal._records import check_fs, check_signals
from rubdiag.signal._spectrum import _spectra
from rubdiag.signal._speed import (
    MIN_SPEED_CONFIDENCE,
    SUBMULTIPLES,
    ambiguity,
    dominant_line,
    speed_confidence,
    submultiple_lines,
)


class SpeedNotFound(ValueError):
    """No line of a record stands out of the noise as 1×: the speed must be given."""


@dataclass(frozen=True)
class SpeedVote:
    """A speed guessed from the dominant lines of a record's channels."""

    rpm: float
    confidence: float        # summed confidence of the channels that agree with ``rpm``
    voters: tuple[int, ...]  # rows whose strongest line agreed with it
    #: Per k of :data:`~rubdiag.signal._speed.SUBMULTIPLES`: the strongest line at rpm / k
    #: over its noise floor on any moving channel (0: none counts as a line).
    submultiples: tuple[float, ...] = (0.0,) * len(SUBMULTIPLES)

    @property
    def ambiguous(self) -> bool:
        """Whether 1× may be a weaker line at rpm / k rather than ``rpm`` itself."""
        return any(c > 0 for c in self.submultiples)

    @property
    def alternatives_rpm(self) -> tuple[float, ...]:
        """The other speeds 1× may be (rpm / k of every line found there), highest first."""
        return tuple(self.rpm / k for k, c in zip(SUBMULTIPLES, self.submultiples,
                                                  strict=True) if c > 0)

    def ambiguity(self, where: str = "") -> str:
        """Why the speed is ambiguous, one sentence ("" when it is not); ``where`` names the
        record (" of run.csv")."""
        return ambiguity(self.rpm, self.submultiples, where)


def voted_speed(X, fs: float, options: Options | None = None, labels=None,
                record: str | None = None) -> SpeedVote:
    """The running speed of the channels ``X`` (rows; time along the last axis) by their vote.

    Parameters
    ----------
    X : array_like, (n_channels, n_samples) or 1-D
        The channels of one record (one machine, one speed).
    fs : float
        Sampling frequency in Hz.
    options : Options, optional
        Spectrum settings (``window``, ``nperseg``, ``detrend``) and ``band``, the relative
        speed difference within which two channels' lines agree.
    labels : sequence of str, optional
        Names of the rows for messages (default ``row i``).
    record : str, optional
        Name of the record (a file) that messages start with.

    Returns
    -------
    SpeedVote
        ``rpm``, the kept guesses' summed ``confidence``, the ``voters`` (row indices) and
        the lines at rpm / 2 and rpm / 3 (``submultiples``: ``ambiguous`` when any).

    Raises
    ------
    SpeedNotFound
        A ValueError, when no channel moves (a constant record: no line at all), or no
        line stands out of the noise as 1× (the message names the best-supported line and
        its confidence).
    """
    opts = Options() if options is None else options
    fs = check_fs(fs)
    X, still = check_signals(X, "signal", labels)
    names = labels if labels is not None else [f"row {i}" for i in range(X.shape[0])]
    moving = np.flatnonzero(~still)
    head = "" if record is None else f"{record}: "
    if moving.size == 0:
        raise SpeedNotFound(f"{head}speed_rpm was not given and cannot be guessed: every "
                            "channel is still (a constant signal: no line to take as 1x). "
                            "Give speed_rpm or a tacho signal")
    spec = _spectra(X[moving], fs, opts.window, opts.nperseg, None, None, opts.detrend,
                    phase=False)
    f1, p = dominant_line(spec)
    floor = noise_floor(spec.amplitude, block_bins(FLOOR_WIDTH_ORDERS * f1, spec.df))
    confidence = np.nan_to_num(speed_confidence(spec.amplitude, floor, p))
    agree = np.abs(f1[:, np.newaxis] / f1[np.newaxis, :] - 1.0) <= opts.band
    support = agree @ confidence
    best = int(np.argmax(support))
    if not support[best] >= MIN_SPEED_CONFIDENCE:
        with_others = " with the channels that agree" if agree[best].sum() > 1 else ""
        raise SpeedNotFound(
            f"{head}speed_rpm was not given and cannot be guessed: the strongest line of "
            f"{names[moving[best]]} ({f1[best]:.4g} Hz, {60 * f1[best]:.5g} rpm){with_others} "
            f"stands only speed_confidence = {support[best]:.3g} times above the noise floor "
            f"(allowed: >= {MIN_SPEED_CONFIDENCE:g}); it looks like noise. Give speed_rpm or "
            "a tacho signal")
    kept = np.flatnonzero(agree[best])
    kept = kept[np.argsort(f1[kept], kind="stable")]
    weight = np.cumsum(confidence[kept])
    median = kept[np.searchsorted(weight, 0.5 * weight[-1])]
    f = np.full(moving.size, f1[median])
    lines = submultiple_lines(spec, floor, f, opts.threshold, opts.band).max(axis=0)
    return SpeedVote(rpm=float(60.0 * f1[median]), confidence=float(support[best]),
                     voters=tuple(int(i) for i in moving[np.sort(kept)]),
                     submultiples=tuple(float(c) for c in lines))
