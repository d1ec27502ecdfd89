"""Order lines: the strongest significant line near k× of the running speed.

Orders are multiples of the running frequency 1× (``speed_rpm / 60`` Hz). Two families are
searched: the half orders k = 0.5, 1, 1.5, …, 8 (the harmonics and the (2k+1)/2 fractional
lines 3×/2, 7×/2, …) and the third orders k/3 (1/3, 2/3, 4/3, …, 23/3; multiples of 1 are
harmonics and left to the first family).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag._tolerances import ON_LEVEL
from rubdiag.signal._spectrum import _Spectra

#: k = 0.5, 1, 1.5, …, 8.
HALF_ORDERS = tuple(float(k) / 2.0 for k in range(1, 17))
#: k/3 for k = 1 … 24, multiples of 3 left out.
THIRD_ORDERS = tuple(k / 3.0 for k in range(1, 25) if k % 3)
#: The harmonics 1× … 8× (centres of the sideband and broadband features).
HARMONICS = tuple(range(1, 9))


def order_label(k: float) -> str:
    """Column label of order ``k``: ``1x``, ``1p5x``, ``0p33x`` (``p`` is the decimal point).

    Half orders are written exactly, other orders with two decimals (``0p33x`` is 1/3×).

    Parameters
    ----------
    k : float
        The order (multiple of the running speed).

    Returns
    -------
    str
        The label.

    Examples
    --------
    >>> [order_label(k) for k in (1, 1.5, 1 / 3, 7)]
    ['1x', '1p5x', '0p33x', '7x']
    """
    if abs(2.0 * k - round(2.0 * k)) < ON_LEVEL:
        text = f"{k:g}"
    else:
        text = f"{k:.2f}"
    return text.replace(".", "p") + "x"


@dataclass(frozen=True)
class OrderLines:
    """Lines found near a set of orders, arrays of shape (n_rows, n_orders).

    ``valid`` is False where the search band does not lie below the Nyquist frequency;
    ``present`` where a significant line lies in the band. ``freq`` (Hz) and ``phase`` (deg)
    are NaN where absent; ``amp`` is 0 where absent and NaN where not valid.
    """

    orders: np.ndarray
    bins: np.ndarray
    valid: np.ndarray
    present: np.ndarray
    freq: np.ndarray
    amp: np.ndarray
    phase: np.ndarray


def order_lines(
    spec: _Spectra, mask: np.ndarray, orders, f1_hz: np.ndarray, band: float
) -> OrderLines:
    """Strongest significant line within ``k× ± band·1×`` for every row and order ``k``."""
    a = spec.amplitude
    n_rows, n_bins = a.shape
    k = np.asarray(orders, dtype=np.float64)
    centre = k[np.newaxis, :] * (f1_hz / spec.df)[:, np.newaxis]
    half = np.maximum(band * f1_hz / spec.df, 1.0)[:, np.newaxis]
    last = max(n_bins - 3, 2)
    lo = np.maximum(np.ceil(centre - half), 2).astype(np.int64)
    hi = np.minimum(np.floor(centre + half), last).astype(np.int64)
    valid = centre + half <= n_bins - 3
    width = max(int((hi - lo).max(initial=0)) + 1, 1)
    idx = np.minimum(lo[..., np.newaxis] + np.arange(width), last)
    inside = idx <= hi[..., np.newaxis]
    rows = np.arange(n_rows)[:, np.newaxis, np.newaxis]
    cand = np.where(inside & mask[rows, idx], a[rows, idx], -1.0)
    j = np.argmax(cand, axis=-1)[..., np.newaxis]
    p = np.clip(np.take_along_axis(idx, j, axis=-1)[..., 0], 1, n_bins - 2)
    present = valid & (np.take_along_axis(cand, j, axis=-1)[..., 0] > 0.0)
    freq, amp, phase = spec.kernel.refine(a, spec.first, p, spec.df)
    return OrderLines(
        orders=k,
        bins=p,
        valid=valid,
        present=present,
        freq=np.where(present, freq, np.nan),
        amp=np.where(valid, np.where(present, amp, 0.0), np.nan),
        phase=np.where(present, phase, np.nan),
    )
