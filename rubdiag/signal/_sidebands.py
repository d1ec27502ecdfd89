"""Sidebands n× ± Δ and the broadband level around n×.

*Sidebands.* Around each harmonic n× (centred on the measured n× line when it is present,
on n·1× otherwise) every spacing Δ from just outside the window's main lobe up to, not
including, 0.25× is tried; a spacing counts when both n× − Δ and n× + Δ hold a significant
line (within ±1 bin, which allows for off-bin lines). The spacing whose weaker line is the
strongest wins; Δ is then half the distance between the two exact line frequencies.

*Broadband level.* The RMS of the spectrum over n× ± 0.25× without the n× line, from the
amplitude spectrum by Parseval's theorem with the window's equivalent noise bandwidth. Both
read the spectrum without the lines' leakage (:mod:`rubdiag.signal._linefree`: every line up
to 9.25× fitted and subtracted, its main lobe kept), so a line between two bins puts nothing
beside its main lobe; the broadband leaves out the n× line's main lobe (the bins within
``kernel.lobe`` of it: 3 or 4 with the Hann window) and scales the power of the bins kept to
the whole band. It measures the study's "wide continuous peak near 4×" (noise, a smeared
hump, and any sidebands).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag.signal._spectrum import _Spectra

#: Sidebands and the broadband band extend to ± this many orders around n×.
HALF_WIDTH_ORDERS = 0.25


@dataclass(frozen=True)
class Sidebands:
    """Sideband pairs, arrays (n_rows, n_harmonics); see :func:`sidebands`."""

    valid: np.ndarray
    present: np.ndarray
    lower_bins: np.ndarray
    upper_bins: np.ndarray
    delta: np.ndarray  # Hz, NaN where absent
    lower: np.ndarray  # amplitude, 0 where absent
    upper: np.ndarray


def sidebands(spec: _Spectra, mask: np.ndarray, centre_hz: np.ndarray, f1_hz: np.ndarray):
    """Symmetric pairs around ``centre_hz`` (n_rows, n_harmonics) with 0 < Δ < 0.25×."""
    a = spec.amplitude
    n_rows, n_bins = a.shape
    last = max(n_bins - 3, 2)
    c = np.rint(centre_hz / spec.df).astype(np.int64)
    d_min = spec.kernel.lobe + 1
    d_max = np.ceil(HALF_WIDTH_ORDERS * f1_hz / spec.df).astype(np.int64) - 1  # Δ < 0.25×
    n_d = max(int(d_max.max()) - d_min + 1, 1)
    d = d_min + np.arange(n_d)
    valid = (c - d_max[:, np.newaxis] - 1 >= 2) & (c + d_max[:, np.newaxis] + 1 <= last)
    valid &= (d_max >= d_min)[:, np.newaxis]
    t = np.arange(-1, 2)
    off = d[:, np.newaxis] + t  # (n_d, 3)
    lower = np.clip(c[..., np.newaxis, np.newaxis] - off, 2, last)
    upper = np.clip(c[..., np.newaxis, np.newaxis] + off, 2, last)
    rows = np.arange(n_rows)[:, np.newaxis, np.newaxis, np.newaxis]
    lo_amp = np.where(mask[rows, lower], a[rows, lower], 0.0)
    up_amp = np.where(mask[rows, upper], a[rows, upper], 0.0)
    allowed = d[np.newaxis, np.newaxis, :] <= d_max[:, np.newaxis, np.newaxis]
    score = np.where(allowed, np.minimum(lo_amp.max(-1), up_amp.max(-1)), 0.0)
    best = np.argmax(score, axis=-1)[..., np.newaxis]
    present = valid & (np.take_along_axis(score, best, axis=-1)[..., 0] > 0.0)

    def pick(bins, amps):
        b = np.take_along_axis(bins, best[..., np.newaxis], axis=2)[:, :, 0]  # (n, H, 3)
        m = np.take_along_axis(amps, best[..., np.newaxis], axis=2)[:, :, 0]
        return np.take_along_axis(b, np.argmax(m, axis=-1)[..., np.newaxis], axis=-1)[..., 0]

    pl, pu = pick(lower, lo_amp), pick(upper, up_amp)
    fl, al, _ = spec.kernel.refine(a, None, pl, spec.df)
    fu, au, _ = spec.kernel.refine(a, None, pu, spec.df)
    return Sidebands(
        valid=valid,
        present=present,
        lower_bins=pl,
        upper_bins=pu,
        delta=np.where(present, 0.5 * (fu - fl), np.nan),
        lower=np.where(valid, np.where(present, al, 0.0), np.nan),
        upper=np.where(valid, np.where(present, au, 0.0), np.nan),
    )


def broadband_rms(
    spec: _Spectra,
    centre_hz: np.ndarray,
    f1_hz: np.ndarray,
    present: np.ndarray,
) -> np.ndarray:
    """RMS (unit of the signal) over ``centre ± 0.25×`` without the centre line.

    ``spec`` is the spectrum without the lines' leakage
    (:func:`~rubdiag.signal._linefree.line_free`), so only the centre line's main lobe
    (the bins within ``kernel.lobe`` of it) is left out, where the line is ``present``.
    The power of the bins kept is scaled to the whole band, so white noise of density
    ``S`` (unit²/Hz) reads ``sqrt(S · 0.5×)`` wherever the line falls. NaN when nothing is
    left (a present line whose main lobe covers the whole band of a very short record).
    """
    a = spec.amplitude
    n_rows, n_bins = a.shape
    cum = np.zeros((n_rows, n_bins + 1))
    np.cumsum(a * a, axis=1, out=cum[:, 1:])
    c = centre_hz / spec.df
    w = (HALF_WIDTH_ORDERS * f1_hz / spec.df)[:, np.newaxis]
    lo = np.clip(np.ceil(c - w).astype(np.int64), 1, n_bins - 1)
    hi = np.clip(np.floor(c + w).astype(np.int64), 1, n_bins - 1)
    rows = np.arange(n_rows)[:, np.newaxis]
    total = cum[rows, hi + 1] - cum[rows, lo]
    n_band = hi - lo + 1
    # an absent line occupies no bins: on short records its main lobe would be most of
    # the band, and dropping it would leave nothing to measure
    lobe = spec.kernel.lobe
    j = np.rint(c).astype(np.int64)[..., np.newaxis] + np.arange(-lobe, lobe + 1)
    drop = ((j >= lo[..., np.newaxis]) & (j <= hi[..., np.newaxis]) & present[..., np.newaxis]
            & (np.abs(j - c[..., np.newaxis]) < lobe))
    jc = np.clip(j, 0, n_bins - 1)
    total -= np.where(drop, a[rows[..., np.newaxis], jc] ** 2, 0.0).sum(axis=-1)
    kept = n_band - drop.sum(axis=-1)
    power = np.maximum(total, 0.0) * n_band / np.maximum(kept, 1)
    rms = np.sqrt(power / (2.0 * spec.kernel.enbw))
    valid = (np.floor(c + w) <= n_bins - 2) & (kept > 0)
    return np.where(valid, rms, np.nan)
