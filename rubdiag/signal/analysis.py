"""The feature engine: one pass over a stack of signals (rows), vectorised over rows.

:func:`analyse` computes the spectra, the local noise floor, the significant lines, the order
lines, the sidebands and the broadband levels of every row at once; the feature table, the
combination search and the scikit-learn transformer all read from its result.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubdiag.signal._checks import check_fs, check_resolution, check_signals, check_speed
from rubdiag.signal.lines import block_bins, line_mask, noise_floor
from rubdiag.signal.orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, OrderLines, order_lines
from rubdiag.signal.sidebands import Sidebands, broadband_rms, sidebands
from rubdiag.signal.spectrum import _Spectra, _spectra
from rubdiag.signal.speed import _dominant_hz

#: Width of a noise-floor block, in orders.
FLOOR_WIDTH_ORDERS = 0.5


@dataclass(frozen=True)
class Options:
    """Settings of the feature engine (see :func:`rubdiag.signal.features`)."""

    band: float = 0.03
    threshold: float = 5.0
    window: object = "hann"
    nperseg: int | None = None
    detrend: object = "constant"
    min_revolutions: float = 10.0
    combo_tol_hz: float | None = None

    def __post_init__(self):
        if not (math.isfinite(self.band) and 0.0 < self.band < 0.25):
            raise ValueError(f"band must lie in (0, 0.25) orders, got {self.band!r}")
        if not (math.isfinite(self.threshold) and self.threshold >= 1.0):
            raise ValueError(f"threshold must be a finite factor >= 1, got {self.threshold!r}")
        if not (math.isfinite(self.min_revolutions) and self.min_revolutions >= 0.0):
            raise ValueError(f"min_revolutions must be >= 0, got {self.min_revolutions!r}")
        tol = self.combo_tol_hz
        if tol is not None and not (math.isfinite(tol) and tol > 0.0):
            raise ValueError(f"combo_tol_hz must be positive, got {tol!r}")


@dataclass(frozen=True)
class Analysis:
    """Everything the features are read from, for ``n_rows`` signals."""

    spec: _Spectra
    f1_hz: np.ndarray  # (n_rows,)
    floor: np.ndarray  # (n_rows, n_bins) local median amplitude
    mask: np.ndarray  # (n_rows, n_bins) significant lines
    half: OrderLines  # k = 0.5 … 8
    third: OrderLines  # k = 1/3 … 23/3
    sidebands: Sidebands  # n = 1 … 8
    broadband: np.ndarray  # (n_rows, 8) RMS around n×
    rms: np.ndarray  # (n_rows,) RMS of the detrended signal
    options: Options


def analyse(
    X, fs: float, speed_rpm=None, options: Options | None = None, *, checked: bool = False
) -> Analysis:
    """Analyse the rows of ``X`` (n_rows, n_samples) sampled at ``fs`` Hz.

    ``speed_rpm`` is a number, one number per row, or None (each row's strongest line is
    taken as 1×). ``checked=True`` skips the checks of ``X`` (the caller made them).
    """
    opts = Options() if options is None else options
    fs = check_fs(fs)
    X = np.asarray(X, dtype=np.float64) if checked else check_signals(X)
    spec = _spectra(X, fs, opts.window, opts.nperseg, None, None, opts.detrend)
    if speed_rpm is None:
        f1 = _dominant_hz(spec)
    else:
        f1 = check_speed(speed_rpm, X.shape[0])
    check_resolution(f1, fs, spec.nperseg, opts.min_revolutions)
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
        floor=floor,
        mask=mask,
        half=half,
        third=third,
        sidebands=sidebands(spec, mask, centre, f1),
        broadband=broadband_rms(spec, centre, f1, half.amp[:, harmonic], floor),
        rms=X.std(axis=1),
        options=opts,
    )
