"""The spectrum without the lines' leakage: what every feature measured around a line reads.

A line on a bin of the window shows in its main lobe only (three bins with the Hann window);
a line between two bins also spreads over every other bin (Hann: falling as 1/d³ over d
bins). A clean record of 1× plus a 2× of 0.35 × 1× at 1451.84 rpm (1× between two bins of a
1-s window) put 1.2e-3 × 1× of 2×'s leakage into the band 2× ± 0.25× — 16 times the floor
of the channel, read as rub — where the same record at 1500 rpm put nothing there. The
broadband levels, the noise floor, the sidebands and the fractional and combination
searches all read the bins around a line, so all of them read where the speed put the line
on the FFT grid rather than what the machine did.

So each significant line up to :data:`REACH_ORDERS` is fitted and subtracted:

1. its frequency, amplitude and phase are estimated exactly from its two largest bins and
   the window's own transform (:meth:`~rubdiag.signal._spectrum._Kernel.refine`), in every
   segment — twice (:data:`FITS`), the second time on what the first fit left, so that
   its neighbours' leakage does not bias it;
2. the fitted lines are synthesised in the time domain, subtracted from the segments, and the
   residual — noise, humps, lines too weak to be found — is transformed as the record was
   (detrend, window): every bin of every line's leakage goes, at any distance, with its
   negative-frequency image, whatever the window;
3. each line's own main lobe (the bins within ``lobe`` of it, where its window's transform
   exceeds 1 % of its peak) is added back from its fit.

What the features read is then a line as it would show on a bin — its main lobe — over the
record's own noise. Reading a line again on this spectrum corrects it for its neighbours'
leakage and its own image, so line amplitudes come out at least as exact as before.

Why not computed order tracking (resampling to whole revolutions): it puts only the orders
of the assumed speed on bins. A line at any other frequency (a whirl, a sideband, a
combination line, a 1× that a tacho's speed does not quite match) leaks as before; the
record must be cut to a whole number of revolutions (a multiple of 6, for both fractional
families) and the resampling's interpolation adds an error of its own. Subtraction needs no
speed, takes out any line, and keeps the record as it is.

How well: a speed swept across two bins of the window, for records of 1× and one strong line
(2×, ½×, 3× or 1½× at 0.05–1 × 1×) in white noise, moves every broadband level and the
bands over the floor by less than :data:`OFF_BIN_BAND_TOLERANCE` (10 %) of their on-bin
values, and every line amplitude by less than :data:`OFF_BIN_LINE_TOLERANCE` (1 %)
(``tests/signal/test_off_bin_lines.py``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rubdiag.signal._orders import HARMONICS
from rubdiag.signal._sidebands import HALF_WIDTH_ORDERS
from rubdiag.signal._spectrum import _mean_amplitude, _segment_spectra, _segments, _Spectra

#: Lines up to this order are fitted and their leakage taken out: one order beyond the
#: highest band the features read (8× + 0.25×); a line further off puts less than 3e-4 of
#: itself into that band (Hann window, a record of 10 revolutions, the fewest allowed).
REACH_ORDERS = max(HARMONICS) + HALF_WIDTH_ORDERS + 1.0
#: Times each line is fitted: the second fit reads it on the spectrum the first left, free
#: of its neighbours' leakage. With one fit, a 2× of 0.35 × 1× whose 1× lay 12.5 bins away
#: (0.5-s segments) left its band at 3e-5 × 1×, six times the 5e-6 of the record's noise;
#: with two, 5e-6.
FITS = 2
#: The most a broadband level (``bb_<n>x_rms``) or a band over the channel's floor may move
#: when a line moves from a bin to between two bins: 10 % of its on-bin value.
OFF_BIN_BAND_TOLERANCE = 0.10
#: The most a line amplitude may move when it moves from a bin to between two: 1 %.
OFF_BIN_LINE_TOLERANCE = 0.01


def line_free(X: np.ndarray, spec: _Spectra, mask: np.ndarray, max_hz: np.ndarray) -> _Spectra:
    """``spec`` with the leakage of every line of ``mask`` below ``max_hz`` taken out.

    Parameters
    ----------
    X : ndarray, (n_rows, n_samples)
        The signals ``spec`` was computed from (any unit).
    spec : _Spectra
        Their spectra (its window, segments and detrend are used again).
    mask : ndarray of bool, (n_rows, n_bins)
        The bins that hold a significant line (local maxima).
    max_hz : ndarray, (n_rows,)
        Lines above this frequency (Hz) are left as they are.

    Returns
    -------
    _Spectra
        The same bins, amplitudes in the unit of ``X``: the residual of the fitted lines
        plus each line's main lobe (module docstring); ``spec`` itself where no line is
        fitted.
    """
    fit = mask & (spec.f[np.newaxis, :] <= max_hz[:, np.newaxis])
    n_lines = int(fit.sum(axis=1).max(initial=0))
    if n_lines == 0:
        return spec
    seg = _segments(X, spec.nperseg, spec.noverlap)
    if seg.shape[1] == 1 and spec.first is not None:         # one segment: its spectrum
        free = spec.first[:, np.newaxis, :]
    else:
        free = _segment_spectra(seg, spec.window, spec.nfft, spec.detrend)
    # each row's lines in rising frequency, padded (ok False) to the row with the most
    rows, cols = np.nonzero(fit)
    count = fit.sum(axis=1)
    slot = np.arange(rows.size) - np.repeat(np.cumsum(count) - count, count)
    bins = np.zeros((fit.shape[0], n_lines), dtype=np.int64)
    bins[rows, slot] = cols
    ok = (np.arange(n_lines) < count[:, np.newaxis])[:, np.newaxis, :]
    for _ in range(FITS):
        nu, amp, phi = (np.where(ok, v, 0.0) for v in _fit_lines(free, bins, spec.kernel))
        residual = seg - _synthesis(nu, amp, phi, count, spec.nperseg, spec.nfft)
        free = _segment_spectra(residual, spec.window, spec.nfft, spec.detrend)
        _add_main_lobes(free, nu, amp, phi, spec.kernel)
    return dataclasses.replace(spec, amplitude=_mean_amplitude(free), first=free[:, 0].copy())


def _fit_lines(S: np.ndarray, bins: np.ndarray, kernel):
    """Exact offset (bins), amplitude and phase (rad) of the lines near ``bins`` (n_rows,
    n_lines) in every segment of ``S`` (n_rows, n_seg, n_bins), each (n_rows, n_seg,
    n_lines): a segment's line is read at its own largest bin next to ``bins`` (a speed
    that drifts moves it)."""
    n_rows, n_seg, n_bins = S.shape
    mag = np.abs(S)
    near = np.clip(bins[:, np.newaxis, :, np.newaxis] + np.arange(-1, 2), 0, n_bins - 1)
    rows = np.arange(n_rows)[:, np.newaxis, np.newaxis, np.newaxis]
    segs = np.arange(n_seg)[np.newaxis, :, np.newaxis, np.newaxis]
    step = np.argmax(mag[rows, segs, near], axis=-1) - 1
    p = np.clip(bins[:, np.newaxis, :] + step, 1, n_bins - 2)
    flat = (n_rows * n_seg, n_bins)
    nu, amp, phase = kernel.refine(mag.reshape(flat), S.reshape(flat),
                                   p.reshape(n_rows * n_seg, -1), 1.0)
    shape = p.shape
    return nu.reshape(shape), amp.reshape(shape), np.radians(phase).reshape(shape)


def _synthesis(nu, amp, phi, count, nperseg: int, nfft: int) -> np.ndarray:
    """The lines ``amp cos(2π nu n / nfft + phi)``, n = 0 … nperseg − 1, summed per segment
    (n_rows, n_seg, nperseg); the first ``count`` lines of each row.

    The samples are laid out in blocks, ``n = a·B + b``, so that each line costs two
    products of its cosines and sines over ``a`` and ``b`` (the angle-sum identity) instead
    of a cosine per sample. Row by row, over that row's own lines only: a row's sum does not
    depend on the other rows.
    """
    block = int(np.ceil(np.sqrt(nperseg)))
    n_blocks = -(-nperseg // block)
    omega = (2.0 * np.pi / nfft) * nu[..., np.newaxis]                  # rad per sample
    alpha = omega * (block * np.arange(n_blocks)) + phi[..., np.newaxis]
    beta = omega * np.arange(block)
    # cos(α + β) = cos α cos β − sin α sin β, as one sum over 2 × count terms per row
    a = amp[..., np.newaxis]
    left = np.concatenate([a * np.cos(alpha), -a * np.sin(alpha)], axis=2)
    right = np.concatenate([np.cos(beta), np.sin(beta)], axis=2)
    n_lines = nu.shape[-1]
    total = np.zeros((*nu.shape[:2], n_blocks, block))
    for r, k in enumerate(count):
        terms = np.r_[0:k, n_lines : n_lines + k]
        # einsum's own loops (no BLAS): the same bits whatever the threads or other rows
        total[r] = np.einsum("sla,slb->sab", left[r][:, terms], right[r][:, terms])
    return total.reshape((*nu.shape[:2], -1))[..., :nperseg]


def _add_main_lobes(R: np.ndarray, nu, amp, phi, kernel) -> None:
    """Add each line's main lobe (the bins within ``kernel.lobe`` of it) to ``R`` in place;
    never onto the first and last bins, whose scale differs."""
    n_rows, n_seg, n_bins = R.shape
    k = np.rint(nu).astype(np.int64)[..., np.newaxis] + np.arange(-kernel.lobe, kernel.lobe + 1)
    d = k - nu[..., np.newaxis]
    keep = (np.abs(d) < kernel.lobe) & (k >= 1) & (k <= n_bins - 2) & (amp[..., np.newaxis] > 0)
    value = (amp * np.exp(1j * phi))[..., np.newaxis] * kernel.transform(d)
    rows, segs = np.indices((n_rows, n_seg))
    index = (np.broadcast_to(rows[..., np.newaxis, np.newaxis], k.shape)[keep],
             np.broadcast_to(segs[..., np.newaxis, np.newaxis], k.shape)[keep], k[keep])
    np.add.at(R, index, value[keep])
