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
which changes nothing; they are left out. ``tests/simulation/test_sensors.py`` compares the
two bit for bit.
"""

from __future__ import annotations

import numpy as np

from rubdiag._numba import njit

__all__ = ["fir_decimate"]

#: output samples whose sums advance together (their partial sums stay in the L1 cache)
_BLOCK = 512


def fir_decimate(streams, taps: np.ndarray, q: int) -> np.ndarray:
    """Channels low-pass filtered by ``taps`` and decimated by ``q`` (module docstring), as
    rows ``(channel, ⌈n / q⌉)``, output k centred on input sample k·q. ``streams`` are
    ``(x, columns)`` pairs, ``x`` an (n, d) float64 array whose columns ``columns`` are
    channels; the rows follow the pairs, then the columns. Each stream is read once, row
    after row (a run's stream holds every streamed DOF; a pass per channel would sweep all
    of it for one column)."""
    n = streams[0][0].shape[0]
    half = (taps.size - 1) // 2
    if taps.size % 2 == 0 or half % q:
        raise ValueError(f"fir_decimate needs an odd number of taps and (taps - 1) / 2 a "
                         f"multiple of q = {q} (got {taps.size} taps)")
    n_out = -(-n // q)
    n_ch = sum(len(columns) for _, columns in streams)
    if n < 2:       # no line through one sample: NaN, as scipy gives (nothing for none)
        return np.full((n_ch, n_out), np.nan)
    length = (n_out - 1) * q + taps.size            # the extended record the sums read
    phases = np.empty((n_ch, q, -(-length // q)))
    first = 0
    for x, columns in streams:
        x = np.ascontiguousarray(x, dtype=np.float64)
        columns = np.asarray(columns, dtype=np.int64)
        if x.ndim != 2 or x.shape[0] != n:
            raise ValueError(f"a stream of shape {x.shape} (allowed: ({n}, d), as the first)")
        slopes = (x[-1, columns] - x[0, columns]) / (n - 1)
        _split_phases(x, columns, slopes, half, length, phases[first:first + columns.size])
        first += columns.size
    out = np.empty((n_ch, n_out))
    _phase_sums(phases, np.ascontiguousarray(taps[::-1], dtype=np.float64), out)
    return out


@njit
def _split_phases(x, columns, slopes, before, length, phases):
    """``phases[k, r, i]``: sample ``i·q + r − before`` of column ``columns[k]`` of ``x``,
    extended beyond the record by the line through its first and last samples, with
    scipy's arithmetic (``x[0] + i·s``, ``x[n−1] + (i − n + 1)·s``); zeros from ``length``
    on, never read."""
    n = x.shape[0]
    q, per_phase = phases.shape[1], phases.shape[2]
    for i in range(per_phase):
        for r in range(q):
            e = i * q + r - before
            for k in range(columns.size):
                c = columns[k]
                if e >= length - before:
                    phases[k, r, i] = 0.0
                elif e < 0:
                    phases[k, r, i] = x[0, c] + e * slopes[k]
                elif e >= n:
                    phases[k, r, i] = x[n - 1, c] + (e - n + 1) * slopes[k]
                else:
                    phases[k, r, i] = x[e, c]


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
