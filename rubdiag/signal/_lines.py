"""Significant spectral lines: local noise floor, detection and exact estimates.

A bin holds a *line* when it is a local maximum of the amplitude spectrum that stands above
``threshold`` times the local noise floor and above a numerical floor (``1e-6`` of the
strongest bin, so that round-off and window leakage in noise-free signals are never lines).
The *local noise floor* is the median amplitude over blocks of ``floor_width_hz`` (by default
0.5× of the running speed), interpolated linearly between block centres: the median ignores
the few bins that lines occupy in a block.

A line between two bins leaks beyond its main lobe and lifts the median of the blocks around
it, hiding weak lines near it (a sideband, ½×) at some speeds and not at others. So lines are
found twice: on the spectrum, then — their leakage taken out
(:mod:`rubdiag.signal._linefree`) — floor and lines again; the second finding is the one used.
"""

from __future__ import annotations

import numpy as np

from rubdiag import _check
from rubdiag.signal._linefree import line_free
from rubdiag.signal._options import Options
from rubdiag.signal._records import check_fs, check_signals
from rubdiag.signal._spectrum import _spectra

#: Lines weaker than this fraction of the strongest bin are never significant.
REL_FLOOR = 1e-6
#: Fewest bins in a noise-floor block.
MIN_FLOOR_BINS = 8


def spectral_lines(
    x,
    fs: float,
    window=Options.window,
    nperseg: int | None = Options.nperseg,
    detrend=Options.detrend,
    *,
    threshold: float = Options.threshold,
    floor_width_hz: float | None = None,
):
    """Significant lines of a signal with exact frequency, amplitude and phase.

    Parameters
    ----------
    x : array_like, 1-D
        Signal (any unit).
    fs : float
        Sampling frequency in Hz.
    window, nperseg, detrend
        As for :func:`amplitude_spectrum` (default: whole record, Hann window).
    threshold : float
        A line must exceed ``threshold`` times the local median amplitude.
    floor_width_hz : float, optional
        Width of the noise-floor blocks in Hz; default 1/40 of ``fs / 2`` (at least 8 bins).

    Returns
    -------
    f : ndarray
        Line frequencies in Hz, ascending.
    amplitude : ndarray
        Peak amplitudes (unit of ``x``), corrected for the line's offset from the bin.
    phase : ndarray
        Phases in degrees of ``cos(2π f t + phase)`` with ``t = 0`` at the first sample.
        All three are empty for a still signal (every sample equal): it has no line.
    """
    fs = check_fs(fs)
    X, still = check_signals(x, "x")
    if X.shape[0] != 1:
        raise ValueError("spectral_lines takes one signal (a 1-D array)")
    width = (fs / 80.0 if floor_width_hz is None
             else _check.positive("floor_width_hz", floor_width_hz, "Hz"))
    opts = Options(threshold=threshold, window=window, nperseg=nperseg, detrend=detrend)
    spec = _spectra(X, fs, opts.window, opts.nperseg, None, None, opts.detrend)
    if still[0]:
        return np.empty(0), np.empty(0), np.empty(0)
    blocks = block_bins(np.array([width]), spec.df)
    mask = line_mask(spec.amplitude, noise_floor(spec.amplitude, blocks), opts.threshold,
                     spec.kernel)
    # found again without the lines' leakage, as the features find them
    spec = line_free(X, spec, mask, np.array([np.inf]))
    mask = line_mask(spec.amplitude, noise_floor(spec.amplitude, blocks), opts.threshold,
                     spec.kernel)
    p = np.flatnonzero(mask[0])[np.newaxis, :]
    f, amp, phase = spec.kernel.refine(spec.amplitude, spec.first, p, spec.df)
    return f[0], amp[0], phase[0]


def block_bins(width_hz: np.ndarray, df: float) -> np.ndarray:
    """Noise-floor block widths in bins for block widths in Hz (at least 8 bins)."""
    return np.maximum(np.rint(width_hz / df).astype(np.int64), MIN_FLOOR_BINS)


def noise_floor(amplitude: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    """Local median level of each row of ``amplitude`` (n_rows, n_bins).

    ``blocks`` gives the block width in bins, one per row or one for all.
    """
    n_rows, _n_bins = amplitude.shape
    blocks = np.broadcast_to(blocks, (n_rows,))
    floor = np.empty_like(amplitude)
    for b in np.unique(blocks):
        rows = np.flatnonzero(blocks == b)
        floor[rows] = _block_median(amplitude[rows], int(b))
    return floor


def _block_median(a: np.ndarray, b: int) -> np.ndarray:
    n_rows, n_bins = a.shape
    n_blocks = n_bins // b
    if n_blocks < 2:
        return np.broadcast_to(np.median(a, axis=1, keepdims=True), a.shape).copy()
    med = np.median(a[:, : n_blocks * b].reshape(n_rows, n_blocks, b), axis=-1)
    pos = (np.arange(n_bins) - (b - 1) / 2.0) / b
    i0 = np.clip(np.floor(pos).astype(np.int64), 0, n_blocks - 2)
    frac = np.clip(pos - i0, 0.0, 1.0)
    return med[:, i0] * (1.0 - frac) + med[:, i0 + 1] * frac


def line_mask(
    amplitude: np.ndarray, floor: np.ndarray, threshold: float, kernel=None
) -> np.ndarray:
    """Boolean (n_rows, n_bins): bins that hold a significant line.

    A line is a strict local maximum (ties broken towards the lower bin), ``threshold``
    times above ``floor``, above :data:`REL_FLOOR` of the row's strongest bin and, for
    windows with sidelobes (``kernel``), twice above what a stronger line's sidelobes put
    there. The first two and last two bins never hold a line (exact estimates need both
    neighbours).
    """
    a = amplitude
    mask = np.zeros(a.shape, dtype=bool)
    if a.shape[1] < 5:
        return mask
    mid = a[:, 2:-2]
    peak = (mid >= a[:, 1:-3]) & (mid > a[:, 3:-1])
    strongest = a[:, 1:].max(axis=1, keepdims=True)
    mask[:, 2:-2] = peak & (mid > threshold * floor[:, 2:-2]) & (mid > REL_FLOOR * strongest)
    if kernel is not None:
        rows, cols = np.nonzero(mask)
        leak = kernel.sidelobe_level(a, rows, cols)
        drop = a[rows, cols] <= 2.0 * leak
        mask[rows[drop], cols[drop]] = False
    return mask
