"""The feature engine: one pass over a stack of signals (rows), vectorised over rows.

:func:`analyse` computes the spectra, the local noise floor, the significant lines, the order
lines, the sidebands and the broadband levels of every row at once; the feature table, the
combination search and the scikit-learn transformer all read from its result. Everything after
the speed is read from the spectrum without the lines' leakage (:mod:`rubdiag.signal._linefree`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from rubdiag.signal._linefree import REACH_ORDERS, line_free
from rubdiag.signal._lines import block_bins, line_mask, noise_floor
from rubdiag.signal._options import Options
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, OrderLines, order_lines
from rubdiag.signal._records import check_fs, check_resolution, check_signals, check_speed
from rubdiag.signal._sidebands import Sidebands, broadband_rms, sidebands
from rubdiag.signal._spectrum import _Spectra, _spectra
from rubdiag.signal._speed import (
    MIN_SPEED_CONFIDENCE,
    SpeedAmbiguous,
    ambiguity,
    dominant_line,
    speed_confidence,
    submultiple_lines,
)

#: Width of a noise-floor block, in orders.
FLOOR_WIDTH_ORDERS = 0.5


@dataclass(frozen=True)
class Analysis:
    """Everything the features are read from, for ``n_rows`` signals."""

    spec: _Spectra
    f1_hz: np.ndarray  # (n_rows,)
    speed_confidence: np.ndarray  # (n_rows,) of a guessed speed; NaN where it was given
    floor: np.ndarray  # (n_rows, n_bins) local median amplitude
    mask: np.ndarray  # (n_rows, n_bins) significant lines
    half: OrderLines  # k = 0.5 … 8
    third: OrderLines  # k = 1/3 … 23/3
    sidebands: Sidebands  # n = 1 … 8
    broadband: np.ndarray  # (n_rows, 8) RMS around n×
    rms: np.ndarray  # (n_rows,) RMS of the detrended signal
    options: Options


def analyse(
    X, fs: float, speed_rpm=None, options: Options | None = None, *, checked: bool = False,
    labels=None,
) -> Analysis:
    """Analyse the rows of ``X`` (n_rows, n_samples) sampled at ``fs`` Hz.

    ``speed_rpm`` is a number, one number per row, or None: each row's strongest line is
    taken as 1×, a row whose line stands less than :data:`MIN_SPEED_CONFIDENCE` above
    the noise floor raises (``labels`` name the rows), and rows whose 1× may be a line at
    1/2 or 1/3 of it warn :class:`~rubdiag.signal._speed.SpeedAmbiguous` once.
    ``checked=True`` skips the checks of ``X`` (the caller made them); every row must move
    (no still rows: they have no lines).
    """
    opts = Options() if options is None else options
    fs = check_fs(fs)
    X = np.asarray(X, dtype=np.float64) if checked else check_signals(X)[0]
    spec = _spectra(X, fs, opts.window, opts.nperseg, None, None, opts.detrend)
    if speed_rpm is None:
        f1, p = dominant_line(spec)
    else:
        f1 = check_speed(speed_rpm, X.shape[0])
    floor = noise_floor(spec.amplitude, block_bins(FLOOR_WIDTH_ORDERS * f1, spec.df))
    if speed_rpm is None:
        confidence = speed_confidence(spec.amplitude, floor, p)
        _check_guess(f1, confidence, labels)
        _warn_ambiguous(submultiple_lines(spec, floor, f1, opts.threshold, opts.band), f1,
                        labels)
    else:
        confidence = np.full(X.shape[0], np.nan)
    check_resolution(f1, fs, spec.nperseg, opts.min_revolutions)
    # the lines found on the spectrum as computed are fitted and their leakage taken out;
    # the floor and the lines are then found again on what is left (rubdiag.signal._linefree)
    mask = line_mask(spec.amplitude, floor, opts.threshold, spec.kernel)
    spec = line_free(X, spec, mask, REACH_ORDERS * f1)
    floor = noise_floor(spec.amplitude, block_bins(FLOOR_WIDTH_ORDERS * f1, spec.df))
    mask = line_mask(spec.amplitude, floor, opts.threshold, spec.kernel)
    half = order_lines(spec, mask, HALF_ORDERS, f1, opts.band)
    third = order_lines(spec, mask, THIRD_ORDERS, f1, opts.band)
    harmonic = half.orders.searchsorted(np.asarray(HARMONICS, dtype=float))
    nominal = np.asarray(HARMONICS, dtype=float)[np.newaxis, :] * f1[:, np.newaxis]
    centre = np.where(half.present[:, harmonic], half.freq[:, harmonic], nominal)
    return Analysis(
        spec=spec,
        f1_hz=f1,
        speed_confidence=confidence,
        floor=floor,
        mask=mask,
        half=half,
        third=third,
        sidebands=sidebands(spec, mask, centre, f1),
        broadband=broadband_rms(spec, centre, f1, half.present[:, harmonic]),
        rms=X.std(axis=1),
        options=opts,
    )


def _check_guess(f1_hz: np.ndarray, confidence: np.ndarray, labels) -> None:
    """Raise when a guessed speed's line does not stand out of the noise."""
    weak = ~(confidence >= MIN_SPEED_CONFIDENCE)
    if weak.any():
        i = int(np.flatnonzero(weak)[0])
        where = "" if labels is None else f" of {labels[i]}"
        raise ValueError(
            f"speed_rpm was not given and cannot be guessed: the strongest line{where} "
            f"({f1_hz[i]:.4g} Hz, {60 * f1_hz[i]:.5g} rpm) stands only "
            f"speed_confidence = {confidence[i]:.3g} times above the noise floor (allowed: "
            f">= {MIN_SPEED_CONFIDENCE:g}); it looks like noise. Give speed_rpm or a tacho signal"
        )


def _warn_ambiguous(lines: np.ndarray, f1_hz: np.ndarray, labels) -> None:
    """One :class:`SpeedAmbiguous` warning for the rows whose guessed 1× may be a line at
    1/2 or 1/3 of it (``lines``: :func:`~rubdiag.signal._speed.submultiple_lines`)."""
    rows = np.flatnonzero((lines > 0).any(axis=1))
    if rows.size:
        i = int(rows[0])
        where = f" of {'row ' + str(i) if labels is None else labels[i]}"
        more = f" ({rows.size} of {f1_hz.size} rows so)" if rows.size > 1 else ""
        warnings.warn(ambiguity(60.0 * f1_hz[i], lines[i], where) + more, SpeedAmbiguous,
                      stacklevel=3)
