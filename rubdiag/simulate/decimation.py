"""Zero-phase FIR decimation of many channels at once, bit for bit as scipy computes it.

``scipy.signal.resample_poly(x, 1, q, window=h, padtype="line")`` sums each output sample
on its own: a chain of ``len(h)`` dependent additions per sample, which on a run's sensor
stream (230,000 samples × 7 channels at 2.3 s) took 0.03 s, a third of a dataset row's time
outside the integrator. :func:`fir_decimate` makes the same sums of the same products in
the same order, so the same bits, but many output samples at a time: the input is split
into its q phases (phase r holds samples r, r + q, r + 2q, …), so that one tap meets
consecutive output samples in consecutive memory, and the sums of a block of outputs advance
together in SIMD registers (:func:`_phase_sums`; no ``fastmath``, so no product is fused
into its addition and no sum is reordered).

What resample_poly computes, for taps ``h`` of odd length ``2·half + 1`` with ``half`` a
multiple of q (the sensors' filter: ``half = 20·q``): output k is
``Σ_j x[k·q − half + j] · h[len(h) − 1 − j]``, j ascending from 0.0, for k < ⌈n / q⌉; the
record is extended beyond its ends by the line through its first and last samples
(``x[0] + i·s`` before, ``x[n−1] + (i − n + 1)·s`` after, ``s = (x[n−1] − x[0]) / (n − 1)``).
Its zero taps (the padding that centres the output) add ±0.0 to a sum that is never −0.0,
which changes nothing; they are left out. ``tests/simulate/test_sensors.py`` compares the
two bit for bit.
"""

from __future__ import annotations

import numpy as np

from rubdiag._numba import njit

__all__ = ["fir_decimate"]

#: output samples whose sums advance together (their partial sums stay in the L1 cache)
_BLOCK = 512


def fir_decimate(channels, taps: np.ndarray, q: int) -> np.ndarray:
    """Every channel of ``channels`` (1-D float64 arrays of one length n, strided views
    too) low-pass filtered by ``taps`` and decimated by ``q`` (module docstring), as rows:
    ``(len(channels), ⌈n / q⌉)``, output k centred on input sample k·q. A view is read in
    place: the columns of a run's (samples × DOFs) stream need no copy first."""
    n = channels[0].shape[0]
    half = (taps.size - 1) // 2
    if taps.size % 2 == 0 or half % q:
        raise ValueError(f"fir_decimate needs an odd number of taps and (taps - 1) / 2 a "
                         f"multiple of q = {q} (got {taps.size} taps)")
    n_out = -(-n // q)
    if n < 2:       # no line through one sample: NaN, as scipy gives (nothing for none)
        return np.full((len(channels), n_out), np.nan)
    length = (n_out - 1) * q + taps.size            # the extended record the sums read
    phases = np.empty((len(channels), q, -(-length // q)))
    for c, x in enumerate(channels):
        if x.shape != (n,) or x.dtype != np.float64:
            raise ValueError(f"channel {c}: shape {x.shape}, {x.dtype} (allowed: ({n},) "
                             "float64, as the first)")
        _split_phases(x, (x[-1] - x[0]) / (n - 1), half, length, phases[c])
    out = np.empty((len(channels), n_out))
    _phase_sums(phases, np.ascontiguousarray(taps[::-1], dtype=np.float64), out)
    return out


@njit
def _split_phases(x, slope, before, length, phases):
    """``phases[r, i]``: sample ``i·q + r − before`` of ``x``, extended beyond the record
    by the line through its first and last samples, with scipy's arithmetic
    (``x[0] + i·s``, ``x[n−1] + (i − n + 1)·s``); zeros from ``length`` on, never read."""
    n = x.shape[0]
    q, per_phase = phases.shape
    for i in range(per_phase):
        for r in range(q):
            e = i * q + r - before
            if e >= length - before:
                phases[r, i] = 0.0
            elif e < 0:
                phases[r, i] = x[0] + e * slope
            elif e >= n:
                phases[r, i] = x[n - 1] + (e - n + 1) * slope
            else:
                phases[r, i] = x[e]


@njit
def _phase_sums(phases, reversed_taps, out):
    """``out[c, k] = Σ_j phases[c, j % q, k + j // q] · reversed_taps[j]``, j ascending,
    from 0.0: a block of k at a time, four taps per pass over the block (each k's sum
    still in its own order, one addition after another)."""
    n_ch, n_out = out.shape
    q = phases.shape[1]
    n_taps = reversed_taps.size
    acc = np.empty(_BLOCK)
    for c in range(n_ch):
        for k0 in range(0, n_out, _BLOCK):
            nb = min(_BLOCK, n_out - k0)
            a = acc[:nb]
            a[:] = 0.0
            j = 0
            while j + 4 <= n_taps:
                h0, h1 = reversed_taps[j], reversed_taps[j + 1]
                h2, h3 = reversed_taps[j + 2], reversed_taps[j + 3]
                x0 = phases[c, j % q, k0 + j // q:]
                x1 = phases[c, (j + 1) % q, k0 + (j + 1) // q:]
                x2 = phases[c, (j + 2) % q, k0 + (j + 2) // q:]
                x3 = phases[c, (j + 3) % q, k0 + (j + 3) // q:]
                for i in range(nb):
                    a[i] = (((a[i] + x0[i] * h0) + x1[i] * h1) + x2[i] * h2) + x3[i] * h3
                j += 4
            while j < n_taps:
                h0 = reversed_taps[j]
                x0 = phases[c, j % q, k0 + j // q:]
                for i in range(nb):
                    a[i] += x0[i] * h0
                j += 1
            out[c, k0:k0 + nb] = a
