"""Combination frequencies: pairs of lines f_a < f_b with f_a + f_b = m× (m = 1, 2, 3).

Only significant lines that are neither orders of 1× (within the order search band of any
multiple of 1/2 or 1/3 of 1×, harmonics above 8× included) nor sidebands found around n×
take part. A pair must sum to m× within ``combo_tol_hz`` (default: the frequency resolution
``fs / nperseg``) and be at least 0.5× wide (f_b − f_a ≥ 0.5×), which keeps it apart from a
sideband pair n× ± Δ with Δ < 0.25×. The study's case 2 is such a pair: 43 Hz + 147 Hz = 2×
at 1× = 95 Hz. The strongest pair is the one whose weaker line is the strongest.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rubdiag.signal._analysis import Analysis, analyse
from rubdiag.signal._options import Options
from rubdiag.signal._records import check_fs, check_signals, check_speed

#: Lines per row that take part in the batch search (the strongest candidates).
MAX_LINES = 24
#: Pairs are at least this many orders wide.
MIN_WIDTH_ORDERS = 0.5
#: Sums m× searched.
SUM_ORDERS = (1, 2, 3)


class CombinationPair(NamedTuple):
    """One combination pair: frequencies in Hz, amplitudes in the signal's unit.

    Parameters
    ----------
    fa_hz, fb_hz : float
        The lower and the upper line's frequency (Hz).
    order : int
        m of f_a + f_b = m×.
    amp_a, amp_b : float
        The two lines' amplitudes (the signal's unit).
    """

    fa_hz: float
    fb_hz: float
    order: int
    amp_a: float
    amp_b: float


def combination_pairs(
    x,
    fs: float,
    speed_rpm: float | None = None,
    *,
    band: float = Options.band,
    threshold: float = Options.threshold,
    window=Options.window,
    nperseg: int | None = Options.nperseg,
    detrend=Options.detrend,
    min_revolutions: float = Options.min_revolutions,
    combo_tol_hz: float | None = Options.combo_tol_hz,
) -> list[CombinationPair]:
    """All combination pairs of a signal, strongest first.

    Parameters
    ----------
    x : array_like
        One signal (1-D), in any unit.
    fs : float
        Sampling frequency (Hz).
    speed_rpm : float or None
        Running speed (rpm); None: the dominant line is 1×.
    band, threshold, window, nperseg, detrend, min_revolutions, combo_tol_hz
        The analysis settings, as for :func:`rubdiag.signal.signal_features`.

    Returns
    -------
    list of CombinationPair
        ``(fa_hz, fb_hz, order, amp_a, amp_b)``, sorted by the weaker amplitude, descending;
        empty when the signal holds no pair (a still signal holds no line at all).

    Examples
    --------
    The study's case 2: lines at 43 and 147 Hz beside 1× = 95 Hz sum to 2×:

    >>> import numpy as np
    >>> fs = 2000.0
    >>> t = np.arange(8000) / fs
    >>> x = (np.cos(2 * np.pi * 95 * t) + 0.2 * np.cos(2 * np.pi * 43 * t)
    ...      + 0.1 * np.cos(2 * np.pi * 147 * t))
    >>> (pair,) = combination_pairs(x, fs, speed_rpm=95 * 60)
    >>> print(f"{pair.fa_hz:g} + {pair.fb_hz:g} Hz = {pair.order}x, "
    ...       f"amplitudes {pair.amp_a:.2f} and {pair.amp_b:.2f}")
    43 + 147 Hz = 2x, amplitudes 0.20 and 0.10
    """
    opts = Options(band=band, threshold=threshold, window=window, nperseg=nperseg,
                   detrend=detrend, min_revolutions=min_revolutions, combo_tol_hz=combo_tol_hz)
    if np.ndim(x) != 1:
        raise ValueError("combination_pairs takes one signal (a 1-D array)")
    X, still = check_signals(x, "x")
    if still[0]:
        check_fs(fs)
        if speed_rpm is not None:
            check_speed(speed_rpm, 1)
        return []
    an = analyse(X, fs, speed_rpm, opts, checked=True)
    f, amp, ok = candidate_lines(an, max_lines=None)
    good, score = pair_matrix(an, f, amp, ok)
    ia, ib = np.nonzero(good[0])
    order = np.argsort(-score[0, ia, ib], kind="stable")
    f1 = an.f1_hz[0]
    return [
        CombinationPair(
            float(f[0, a]), float(f[0, b]), round((f[0, a] + f[0, b]) / f1),
            float(amp[0, a]), float(amp[0, b]),
        )
        for a, b in zip(ia[order], ib[order], strict=True)
    ]


def candidate_lines(an: Analysis, max_lines: int | None = MAX_LINES):
    """Exact frequency (Hz), amplitude and validity of the lines that may form pairs.

    Returns arrays (n_rows, n_lines): the strongest ``max_lines`` significant lines of each
    row (all when None), with ``ok`` False for padding, orders and sidebands.
    """
    spec, a = an.spec, an.spec.amplitude
    n_rows, n_bins = a.shape
    sb = an.sidebands
    rows = np.broadcast_to(np.arange(n_rows)[:, np.newaxis], sb.present.shape)[sb.present]
    sideband = np.zeros_like(an.mask)
    for bins in (sb.lower_bins, sb.upper_bins):
        for t in (-1, 0, 1):
            sideband[rows, np.clip(bins[sb.present] + t, 0, n_bins - 1)] = True
    mask = an.mask & ~sideband
    level = np.where(mask, a, 0.0)
    n_lines = int(mask.sum(axis=1).max(initial=0)) if max_lines is None else max_lines
    n_lines = max(min(n_lines, n_bins), 1)
    if n_lines < n_bins:
        p = np.argpartition(-level, n_lines - 1, axis=1)[:, :n_lines]
    else:
        p = np.broadcast_to(np.arange(n_bins), (n_rows, n_bins))
    ok = np.take_along_axis(level, p, axis=1) > 0.0
    p = np.clip(p, 1, n_bins - 2)
    f, amp, _ = spec.kernel.refine(a, None, p, spec.df)
    x = f / an.f1_hz[:, np.newaxis]
    tol = an.options.band
    near_half = np.abs(x - np.rint(2.0 * x) / 2.0) <= tol
    near_third = np.abs(x - np.rint(3.0 * x) / 3.0) <= tol
    ok &= ~near_half & ~near_third
    return f, amp, ok


def pair_matrix(an: Analysis, f, amp, ok):
    """Pairs among candidate lines: ``good`` (n_rows, L, L) for f_a = f[i] < f_b = f[j],
    and ``score`` = the weaker amplitude of each pair."""
    f1 = an.f1_hz[:, np.newaxis, np.newaxis]
    tol = an.options.combo_tol_hz
    tol = an.spec.resolution if tol is None else tol
    fa, fb = f[:, :, np.newaxis], f[:, np.newaxis, :]
    total = fa + fb
    m = np.rint(total / f1)
    good = ok[:, :, np.newaxis] & ok[:, np.newaxis, :] & (fa < fb)
    good &= (m >= SUM_ORDERS[0]) & (m <= SUM_ORDERS[-1]) & (np.abs(total - m * f1) <= tol)
    good &= fb - fa >= MIN_WIDTH_ORDERS * f1
    score = np.where(good, np.minimum(amp[:, :, np.newaxis], amp[:, np.newaxis, :]), 0.0)
    return good, score


def strongest_pair(an: Analysis):
    """Columns of the strongest pair per row: fa, fb (Hz), order m, amp_a, amp_b.

    Frequencies and order are NaN and amplitudes 0 where a row has no pair.
    """
    f, amp, ok = candidate_lines(an)
    good, score = pair_matrix(an, f, amp, ok)
    n_rows, n_lines = f.shape
    flat = score.reshape(n_rows, -1)
    best = np.argmax(flat, axis=1)
    found = good.reshape(n_rows, -1)[np.arange(n_rows), best]
    ia, ib = np.divmod(best, n_lines)
    rows = np.arange(n_rows)
    fa, fb = f[rows, ia], f[rows, ib]
    order = np.rint((fa + fb) / an.f1_hz)
    return {
        "combo_fa_hz": np.where(found, fa, np.nan),
        "combo_fb_hz": np.where(found, fb, np.nan),
        "combo_order": np.where(found, order, np.nan),
        "combo_amp_a": np.where(found, amp[rows, ia], 0.0),
        "combo_amp_b": np.where(found, amp[rows, ib], 0.0),
    }
