"""Computed order tracking: signals of a variable speed resampled at equal angle steps.

At a changing speed an order k× sweeps in frequency, so a spectrum over time smears it. Read
against the shaft angle φ instead of time, ``cos(k φ + phase)`` is a steady line at k cycles
per revolution. :func:`resample_to_angle` resamples a record onto equal angle steps
(``samples_per_rev`` per revolution); the order analyses read that record:

* :func:`order_spectrum` — one peak-amplitude spectrum over orders (MATLAB ``orderspectrum``);
* :func:`order_track` — amplitude and phase of chosen orders, bin by bin of whole revolutions,
  against speed (MATLAB ``ordertrack``);
* :func:`rpm_order_map` — the spectrum of every bin, orders × speed (MATLAB ``rpmordermap``);
* :func:`~rubdiag.signal.revolution_features` — every feature of the feature table, bin by
  bin (:mod:`rubdiag.signal._speedtable`, on :func:`angle_bins`).

Anti-aliasing in the angle domain
---------------------------------
Resampling at ``samples_per_rev`` per revolution is sampling again: any content above
``samples_per_rev / 2`` orders (high orders; fixed-frequency tones, which sweep through the
orders as the speed changes) would fold onto the orders analysed. So the record is first
interpolated (cubic spline in time) onto an angle grid ``up`` times finer, with ``up`` chosen
so that even at the record's lowest speed one angle step is no longer than one time step:
then every frequency below ``fs / 2`` lies below that grid's Nyquist order and nothing folds.
A linear-phase Kaiser FIR low-pass in the angle domain then passes the orders up to
``max_order`` (ripple 1e-4) and stops from ``samples_per_rev - max_order`` on (80 dB), the
orders that would fold onto 0 … ``max_order``, and the record is decimated by ``up``
(:func:`scipy.signal.resample_poly`, which compensates the filter's delay). The revolutions
at each end where the filter would run off the record are dropped.

Orders between ``max_order`` and ``samples_per_rev / 2`` lie in the filter's transition band
and are not to be read; the analyses return orders up to ``max_order`` only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
import scipy.interpolate
import scipy.signal

from rubdiag import _check
from rubdiag._tolerances import BOUND_SLACK, ON_LEVEL
from rubdiag.signal._orders import order_label
from rubdiag.signal._records import RecordTooShort, check_fs, check_signals
from rubdiag.signal._spectrum import _Spectra, _spectra, amplitude_spectrum
from rubdiag.signal._tacho import check_angle

#: Default ``max_order`` is ``samples_per_rev`` over this (the ratio of analyzers' lines to
#: their sampling rate: stopband from 1.56 / 2.56 of the rate, well clear of max_order).
SAMPLES_PER_MAX_ORDER = 2.56
#: Stopband attenuation of the angle-domain anti-alias filter (its passband ripple is the
#: same fraction: 1e-4 of an amplitude).
STOPBAND_DB = 80.0
#: Largest ratio of mean to lowest speed: the fine angle grid grows with it.
MAX_SPEED_RATIO = 100.0
#: The default order spectrum spans a multiple of this many revolutions: half and third
#: orders (the fractional families of rub) then fall on bins.
_WHOLE_FRACTIONS = 6


def resample_to_angle(x, fs: float, angle, samples_per_rev: int = 64,
                      max_order: float | None = None):
    """Resample a record at equal angle steps, with anti-aliasing in the angle domain.

    Parameters
    ----------
    x : array_like
        One signal (1-D) or several (2-D, rows are signals), sampled at ``fs``.
    fs : float
        Sampling frequency in Hz.
    angle : array_like, 1-D
        Shaft angle in rad at every sample, strictly increasing (:func:`tacho_angle`,
        :func:`angle_from_rpm`).
    samples_per_rev : int
        Samples per revolution of the output (its "sampling rate" in orders), at least 2.
    max_order : float, optional
        Highest order kept; ``0 < max_order < samples_per_rev / 2``. Default
        ``samples_per_rev / 2.56``.

    Returns
    -------
    revolutions : ndarray
        Angle of each output sample in revolutions (``angle / 2π``): the multiples of
        ``1 / samples_per_rev`` inside the record, less the ends the filter needs.
    x_angle : ndarray
        The signal(s) at those angles (1-D for 1-D input, else rows as ``x``).

    Notes
    -----
    The caller must make sure that ``x`` itself is not aliased: content above ``fs / 2``
    folds at sampling and no later step can tell it apart. And an order k is only in the
    record while ``k × speed`` stays below ``fs / 2``: at the highest speed the record holds
    orders up to ``fs / 2 / (rpm_max / 60)`` only, and higher orders read low (or show what
    the acquisition's anti-alias filter let through).
    """
    fs = check_fs(fs)
    X, _ = check_signals(x, "x")
    spr, max_order = _check_grid(samples_per_rev, max_order)
    rec = _resample(X, fs, check_angle(angle, X.shape[1]), spr, max_order)
    revolutions = (rec.m0 + np.arange(rec.x.shape[1])) / spr
    return revolutions, (rec.x[0] if np.ndim(x) == 1 else rec.x)


def order_spectrum(x, fs: float, angle, samples_per_rev: int = 64,
                   max_order: float | None = None, window="hann",
                   revs_per_segment: int | None = None, detrend="constant"):
    """Peak-amplitude order spectrum of a record at any speed (like MATLAB ``orderspectrum``).

    The record is resampled at equal angle steps (:func:`resample_to_angle`) and analysed by
    :func:`amplitude_spectrum` with revolutions in place of seconds: an order ``k`` of
    amplitude ``A`` (``A cos(k φ + phase)``) that falls on a bin shows as ``A``.

    Parameters
    ----------
    x, fs, angle, samples_per_rev, max_order
        As for :func:`resample_to_angle`.
    window, detrend
        As for :func:`amplitude_spectrum`.
    revs_per_segment : int, optional
        Revolutions per segment, averaged as in :func:`amplitude_spectrum` (half overlap).
        Default: one segment of the largest multiple of 6 whole revolutions in the record
        (all of them when fewer than 6), so that half and third orders fall on bins.

    Returns
    -------
    orders : ndarray
        Orders ``0 … max_order``, spacing ``1 / revolutions`` of a segment (the resolution):
        order ``k`` falls on a bin when ``k`` times the revolutions is a whole number.
    amplitude : ndarray
        Peak amplitude per order (unit of ``x``); rows as ``x``.
    """
    fs = check_fs(fs)
    X, _ = check_signals(x, "x")
    spr, max_order = _check_grid(samples_per_rev, max_order)
    rec = _resample(X, fs, check_angle(angle, X.shape[1]), spr, max_order)
    n_revs = rec.x.shape[1] // spr
    if n_revs < 1:
        raise RecordTooShort(f"x holds {rec.x.shape[1] / spr:.3g} revolutions after the "
                             "anti-alias filter's ends (allowed: at least 1)")
    if revs_per_segment is None:
        n_revs = n_revs - n_revs % _WHOLE_FRACTIONS if n_revs >= _WHOLE_FRACTIONS else n_revs
        nperseg = None
    else:
        nperseg = spr * _check.integer("revs_per_segment", revs_per_segment, lo=1, hi=n_revs)
    orders, amp = amplitude_spectrum(rec.x[:, : n_revs * spr], spr, window, nperseg,
                                     detrend=detrend)
    keep = orders <= max_order * (1.0 + BOUND_SLACK)
    amp = amp[:, keep]
    return orders[keep], (amp[0] if np.ndim(x) == 1 else amp)


def order_track(x, fs: float, angle, orders=(0.5, 1.0, 1.5, 2.0, 4.0), revs_per_bin: int = 8,
                *, revs_step: int | None = None, samples_per_rev: int = 64,
                max_order: float | None = None, window="hann") -> pd.DataFrame:
    """Amplitude and phase of chosen orders against speed (like MATLAB ``ordertrack``).

    The record, resampled at equal angle steps, is cut into bins of ``revs_per_bin`` whole
    revolutions (starting at whole revolutions of ``angle``); each bin's mean is removed, the
    bin windowed and transformed, and each order read at its bin.

    Parameters
    ----------
    x : array_like, 1-D
        One signal.
    fs, angle, samples_per_rev, max_order
        As for :func:`resample_to_angle`.
    orders : sequence of float
        Orders to track, ``0 < k <= max_order``. Each must fall on a bin: ``k ×
        revs_per_bin`` a whole number (half orders need an even ``revs_per_bin``, third
        orders a multiple of 3).
    revs_per_bin : int
        Revolutions per bin: the order resolution is ``1 / revs_per_bin``. Longer bins
        separate close orders, shorter ones follow a faster run-up.
    revs_step : int, optional
        Revolutions from one bin's start to the next; default ``revs_per_bin`` (no overlap).
    window : str or tuple or array_like
        As for :func:`amplitude_spectrum`. With ``"hann"`` a line on a bin leaks into its two
        neighbours only, so an order is read exactly unless another line lies within
        ``1 / revs_per_bin`` of it.

    Returns
    -------
    pandas.DataFrame
        One row per bin: ``rev_start`` (its first revolution, ``angle / 2π``), ``t_s`` (the
        time midway between its start and end, s), ``rpm`` (the mean speed over it:
        revolutions over duration), and for every order ``k`` (label ``1x``, ``0p5x``,
        ``0p33x`` …, see :func:`order_label`) ``amp_<k>`` (peak amplitude, unit of ``x``)
        and ``phase_<k>_deg``: the phase of ``amp cos(k φ + phase)`` in degrees, within
        ±180, φ being ``angle``. ``attrs`` hold ``revs_per_bin``, ``samples_per_rev`` and
        (a named) ``window``.

    Notes
    -----
    Fractional orders are read exactly by making them fall on a bin rather than by
    interpolating between bins: with whole cycles of every order in a bin, the window
    leaves no leakage from one *steady* order onto another. An amplitude that changes within
    a bin is read as the window-weighted mean over the bin (a resonance passed within a few
    bins is flattened: shorten the bins), and the change leaks onto the orders beside it
    (:func:`~rubdiag.signal._leakage.tracking_leakage` gives how much).
    """
    fs = check_fs(fs)
    spr, max_order = _check_grid(samples_per_rev, max_order)
    n_rev = _check.integer("revs_per_bin", revs_per_bin, lo=1)
    k, j = _order_bins(orders, n_rev, max_order)
    b = _binned(x, fs, angle, n_rev, revs_step, spr, max_order, window)
    line = b.spec.first[:, j]        # A exp(i (k φ_start + phase)), φ_start = 2π rev_start
    phase = np.angle(line * np.exp(-2j * np.pi * np.outer(b.rev_start, k)), deg=True)
    columns = {"rev_start": b.rev_start, "t_s": b.t_s, "rpm": b.rpm}
    for i, label in enumerate(order_label(ki) for ki in k):
        columns[f"amp_{label}"] = np.abs(line[:, i])
        columns[f"phase_{label}_deg"] = phase[:, i]
    table = pd.DataFrame(columns)
    # how it was tracked, for tracking_leakage (a figure's leakage level)
    table.attrs.update(revs_per_bin=n_rev, samples_per_rev=spr)
    if isinstance(window, str):
        table.attrs["window"] = window
    return table


def rpm_order_map(x, fs: float, angle, revs_per_bin: int = 8, *, revs_step: int | None = None,
                  samples_per_rev: int = 64, max_order: float | None = None, window="hann"):
    """Order spectra against speed (like MATLAB ``rpmordermap``).

    Parameters
    ----------
    x, fs, angle, revs_per_bin, revs_step, samples_per_rev, max_order, window
        As for :func:`order_track`.

    Returns
    -------
    orders : ndarray
        Orders ``0 … max_order``, spacing ``1 / revs_per_bin``.
    rpm : ndarray
        Mean speed of each bin in rpm, in the record's order (not sorted: a run-up and
        run-down comes back as it was run).
    amplitude : ndarray
        Peak amplitude, shape ``(orders.size, rpm.size)``.
    """
    fs = check_fs(fs)
    spr, max_order = _check_grid(samples_per_rev, max_order)
    n_rev = _check.integer("revs_per_bin", revs_per_bin, lo=1)
    b = _binned(x, fs, angle, n_rev, revs_step, spr, max_order, window)
    orders = b.spec.f
    keep = orders <= max_order * (1.0 + BOUND_SLACK)
    return orders[keep], b.rpm, b.spec.amplitude[:, keep].T


def _check_grid(samples_per_rev, max_order) -> tuple[int, float]:
    spr = _check.integer("samples_per_rev", samples_per_rev, lo=2)
    if max_order is None:
        return spr, spr / SAMPLES_PER_MAX_ORDER
    return spr, _check.number(
        "max_order", max_order, lo=0.0, hi=spr / 2.0, lo_open=True, hi_open=True,
        allowed=f"> 0 and < samples_per_rev / 2 = {spr / 2.0:g}: samples_per_rev must exceed "
                "2 max_order")


def _order_bins(orders, n_rev: int, max_order: float) -> tuple[np.ndarray, np.ndarray]:
    """The orders as floats and their bins in a spectrum of ``n_rev`` revolutions."""
    k = np.asarray(_check.numbers("orders", orders), dtype=np.float64)
    bins = k * n_rev
    for i, (ki, b) in enumerate(zip(k, bins, strict=True)):
        if ki > max_order:
            raise _check.out_of_range(f"orders[{i}]", ki, f"<= max_order = {max_order:g}")
        if abs(b - round(b)) > ON_LEVEL * max(b, 1.0):
            raise ValueError(
                f"orders[{i}] = {_check.plain(ki)} does not fall on a bin of revs_per_bin = "
                f"{n_rev} revolutions (allowed: multiples of 1/{n_rev}; make revs_per_bin a "
                "multiple of the order's denominator)")
    j = np.rint(bins).astype(np.int64)
    labels = {order_label(ki) for ki in k}
    if len(set(j.tolist())) < j.size or len(labels) < k.size:
        raise ValueError(f"orders = {_check.plain(tuple(k))} repeats an order (allowed: "
                         "distinct orders)")
    return k, j


@dataclass(frozen=True)
class _AngleRecord:
    """Rows resampled at angles ``(m0 + i) · 2π / samples_per_rev``, i = 0, 1, …"""

    x: np.ndarray
    m0: int


def _resample(X: np.ndarray, fs: float, phi: np.ndarray, spr: int,
              max_order: float) -> _AngleRecord:
    """Rows of ``X`` at equal angle steps, low-passed to ``max_order`` (module docstring)."""
    dphi = 2.0 * np.pi / spr
    step = np.diff(phi)
    mean_step = (phi[-1] - phi[0]) / step.size
    if mean_step > MAX_SPEED_RATIO * step.min():
        i = int(np.argmin(step))
        raise ValueError(
            f"angle: the speed falls to {_rpm(step[i], fs):.4g} rpm at sample {i}, below "
            f"1/{MAX_SPEED_RATIO:g} of the mean {_rpm(mean_step, fs):.4g} rpm (allowed: "
            "a shaft that turns throughout; trim the record)")
    # At the lowest speed one time step spans step.min() rad: a fine step no longer than
    # that keeps every frequency below fs/2 below the fine grid's Nyquist order.
    up = max(2, math.ceil(dphi / step.min()))
    h = _antialias_filter(spr, up, max_order)
    j0 = math.ceil(phi[0] / dphi)
    n_fine = (math.floor(phi[-1] / dphi) - j0) * up + 1
    half = (h.size - 1) // 2
    first = math.ceil(half / up)                  # first output the filter sees whole
    last = (n_fine - 1 - half) // up
    if last < first:
        raise RecordTooShort(
            f"x spans {(phi[-1] - phi[0]) / (2 * np.pi):.3g} revolutions (allowed: more than "
            f"{2 * half / (up * spr):.3g}, the anti-alias filter's length; raise "
            "samples_per_rev - 2 max_order to shorten it)")
    phi_fine = (j0 * up + np.arange(n_fine)) * (dphi / up)
    t = np.arange(phi.size) / fs
    t_fine = np.interp(phi_fine, phi, t)          # the angle inverted: it increases strictly
    x_fine = scipy.interpolate.CubicSpline(t, X, axis=-1)(t_fine)
    y = scipy.signal.resample_poly(x_fine, 1, up, axis=-1, window=h)
    return _AngleRecord(x=y[:, first : last + 1], m0=j0 + first)


def _antialias_filter(spr: int, up: int, max_order: float) -> np.ndarray:
    """Kaiser low-pass on a grid of ``up · spr`` per revolution: passes ``max_order``, stops
    from ``spr - max_order``; odd length, so its delay is a whole number of samples."""
    rate = up * spr
    width = (spr - 2.0 * max_order) / (rate / 2.0)      # transition, fraction of Nyquist
    numtaps, beta = scipy.signal.kaiserord(STOPBAND_DB, width)
    return scipy.signal.firwin(numtaps | 1, spr / 2.0, window=("kaiser", beta), fs=rate)


def _rpm(dphi: float, fs: float) -> float:
    return 60.0 * dphi * fs / (2.0 * np.pi)


@dataclass(frozen=True)
class _Bins:
    """Spectra of consecutive bins of whole revolutions of one signal (rows are bins)."""

    rev_start: np.ndarray
    t_s: np.ndarray
    rpm: np.ndarray
    spec: _Spectra      # f in orders


@dataclass(frozen=True)
class AngleBins:
    """Rows resampled at equal angle steps and cut into bins of whole revolutions.

    ``x`` has shape ``(n_rows, n_bins, revs_per_bin · samples_per_rev)``: bin ``i`` of a row
    starts at revolution ``rev_start[i]`` (``angle / 2π``, a whole number). ``t_s`` is the
    time midway between a bin's start and end (s), ``rpm`` its mean speed (revolutions over
    duration) and ``max_rpm`` the highest speed of the samples within it.
    """

    x: np.ndarray
    rev_start: np.ndarray
    t_s: np.ndarray
    rpm: np.ndarray
    max_rpm: np.ndarray


def angle_bins(X: np.ndarray, fs: float, phi: np.ndarray, n_rev: int, revs_step,
               spr: int, max_order: float) -> AngleBins:
    """Checked rows ``X`` (n_rows, n_samples) at angles ``phi`` (rad, checked), resampled
    (:func:`resample_to_angle`) and cut into bins of ``n_rev`` whole revolutions, one every
    ``revs_step`` (default ``n_rev``)."""
    step = n_rev if revs_step is None else _check.integer("revs_step", revs_step, lo=1)
    rec = _resample(X, fs, phi, spr, max_order)
    r0 = -(-rec.m0 // spr)                              # first whole revolution on the grid
    r_end = (rec.m0 + rec.x.shape[1]) // spr            # revolutions [r, r + n_rev) fit
    if r_end - r0 < n_rev:
        raise RecordTooShort(
            f"x holds {max(r_end - r0, 0)} whole revolutions after the anti-alias filter's "
            f"ends (allowed: at least revs_per_bin = {n_rev})")
    rev_start = np.arange(r0, r_end - n_rev + 1, step)
    idx = (rev_start * spr - rec.m0)[:, np.newaxis] + np.arange(n_rev * spr)
    t = np.arange(phi.size) / fs
    t0 = np.interp(2.0 * np.pi * rev_start, phi, t)
    t1 = np.interp(2.0 * np.pi * (rev_start + n_rev), phi, t)
    # the highest speed within a bin: of the sample steps that overlap it
    speed = _rpm(np.diff(phi), fs)
    i0 = np.clip(np.floor(t0 * fs).astype(np.int64), 0, speed.size - 1)
    i1 = np.clip(np.ceil(t1 * fs).astype(np.int64), i0 + 1, speed.size)
    max_rpm = np.array([speed[a:b].max() for a, b in zip(i0, i1, strict=True)])
    return AngleBins(x=rec.x[:, idx], rev_start=rev_start, t_s=0.5 * (t0 + t1),
                     rpm=60.0 * n_rev / (t1 - t0), max_rpm=max_rpm)


def _binned(x, fs, angle, n_rev, revs_step, spr, max_order, window) -> _Bins:
    X, _ = check_signals(x, "x")
    if X.shape[0] != 1:
        raise ValueError(f"x has {X.shape[0]} rows (allowed: one signal, 1-D)")
    b = angle_bins(X, fs, check_angle(angle, X.shape[1]), n_rev, revs_step, spr, max_order)
    spec = _spectra(b.x[0], float(spr), window, None, None, None, "constant")
    return _Bins(rev_start=b.rev_start, t_s=b.t_s, rpm=b.rpm, spec=spec)
