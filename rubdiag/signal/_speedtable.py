"""Features across speed: the feature table on bins of whole revolutions, in the angle domain.

At a changing speed every order sweeps in frequency and a spectrum over time smears it.
:func:`revolution_features` resamples each channel at equal angle steps once
(:func:`~rubdiag.signal.resample_to_angle`, anti-aliased in the angle domain), cuts the record
into bins of ``revs_per_bin`` whole revolutions (as :func:`~rubdiag.signal.order_track` does)
and runs the feature engine of :func:`~rubdiag.signal.signal_features` on every bin. A bin
sampled at
``samples_per_rev`` per revolution *is* a constant-speed record: its "sampling frequency" is
``samples_per_rev`` and its 1× lies at one cycle per revolution, so every feature of the
constant-speed table is measured in orders instead of Hz, whatever the speed.

Columns
-------
``channel``, ``bin``
    The channel, and the bin's index within it (0, 1, … in the record's order).
``rev_start``, ``t_s``, ``rpm``
    The bin's first revolution (``angle / 2π``, a whole number), the time midway between its
    start and end (s, ``t = 0`` at the first sample) and its mean speed (its revolutions over
    its duration, rpm), as in :func:`~rubdiag.signal.order_track`.
Then the columns of :data:`~rubdiag.signal.FEATURE_NAMES` without ``speed_rpm`` and
``speed_confidence``, with every frequency given in orders (a ``_order`` suffix in place of
``_hz``):

``freq_<k>_order``
    Exact order of the line found near k× (1.5 for a 1.5× line), not its frequency in Hz.
``sb_<n>x_delta_order``
    Sideband spacing Δ in orders: the lines at n× ± Δ.
``combo_fa_order``, ``combo_fb_order``
    The orders of the combination pair f_a + f_b = m× (``combo_order`` is m, as before).
``phase_<k>_deg``
    Phase θ of ``amp cos(k φ + θ)`` in degrees within ±180, φ the shaft angle (``angle``, or
    :func:`~rubdiag.signal.tacho_angle`: 0 at the first tacho pulse), with k the nominal
    order of the column: a line locked to the shaft keeps its phase from bin to bin. (The
    constant-speed table phases against the first sample instead.)
``rms``
    RMS of the bin's angle samples, mean removed: content up to ``max_order`` orders only
    (the angle-domain low-pass removes the rest).

Amplitudes (``amp_*``, ``sb_*_lower``/``upper``, ``bb_*_rms``, ``combo_amp_*``) keep the
signal's unit, and 0 / NaN keep their meaning (:mod:`rubdiag.signal._table`): an absent line
has amplitude 0 and NaN location. A feature is unmeasurable (all NaN) in a bin when its
search band reaches above :data:`MAX_FS_FRACTION` × ``fs`` at the bin's highest speed: an
order k is only in a record sampled at ``fs`` while ``k × speed < fs / 2``, and the cubic
interpolation of the time record onto the angle grid reads a line at 0.2 ``fs`` 0.5 % low
(1 % at 0.23 ``fs``, 4 % at 0.3 ``fs``, half at ``fs / 2``). ``n_half_orders`` and
``n_third_orders`` count the measurable lines present.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag.signal._options import Options
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label
from rubdiag.signal._ordertrack import _check_grid, angle_bins
from rubdiag.signal._records import check_signals
from rubdiag.signal._sidebands import HALF_WIDTH_ORDERS
from rubdiag.signal._table import (
    FEATURE_NAMES,
    SPEED_NAMES,
    _feature_matrix,
    channel_rows,
    split_channels,
)
from rubdiag.signal._tacho import check_angle, tacho_angle

#: Default samples per revolution of the angle record: ``max_order`` 12.5 (32 / 2.56).
SAMPLES_PER_REV = 32
#: Lowest ``max_order`` allowed: the features read up to 8× + 0.25× (sidebands, broadband)
#: and the bins around it; beyond ``max_order`` the anti-alias filter attenuates.
MIN_MAX_ORDER = 8.5
#: Highest line frequency, as a fraction of the time record's ``fs``, whose features are
#: read (module docstring): the interpolation onto the angle grid reads it 0.5 % low.
MAX_FS_FRACTION = 0.2
#: Columns that place a bin, before the features.
BIN_NAMES = ("channel", "bin", "rev_start", "t_s", "rpm")

_HZ_TO_ORDER = {
    **{f"freq_{order_label(k)}_hz": f"freq_{order_label(k)}_order" for k in HALF_ORDERS},
    **{f"sb_{n}x_delta_hz": f"sb_{n}x_delta_order" for n in HARMONICS},
    "combo_fa_hz": "combo_fa_order",
    "combo_fb_hz": "combo_fb_order",
}
_KEPT = [i for i, name in enumerate(FEATURE_NAMES) if name not in SPEED_NAMES]

#: The feature columns of :func:`revolution_features`, after :data:`BIN_NAMES`.
REVOLUTION_FEATURE_NAMES: tuple[str, ...] = tuple(
    _HZ_TO_ORDER.get(FEATURE_NAMES[i], FEATURE_NAMES[i]) for i in _KEPT)


def _column_orders() -> tuple[np.ndarray, np.ndarray]:
    """For every feature column: the order it is searched at (NaN: none) and whether its
    band is the order search band (``band``) rather than ±0.25× (sidebands, broadband)."""
    centre = np.full(len(REVOLUTION_FEATURE_NAMES), np.nan)
    banded = np.zeros(centre.size, dtype=bool)
    index = {name: j for j, name in enumerate(REVOLUTION_FEATURE_NAMES)}
    for k in HALF_ORDERS:
        label = order_label(k)
        for name in (f"amp_{label}", f"freq_{label}_order", f"phase_{label}_deg"):
            centre[index[name]], banded[index[name]] = k, True
    for k in THIRD_ORDERS:
        j = index[f"amp_{order_label(k)}"]
        centre[j], banded[j] = k, True
    for n in HARMONICS:
        for name in (f"sb_{n}x_delta_order", f"sb_{n}x_lower", f"sb_{n}x_upper",
                     f"bb_{n}x_rms"):
            centre[index[name]] = n
    return centre, banded


_CENTRE, _BANDED = _column_orders()
_PHASES = np.array([name.startswith("phase_") for name in REVOLUTION_FEATURE_NAMES])
_FRACTIONAL_HALF = [REVOLUTION_FEATURE_NAMES.index(f"amp_{order_label(k)}")
                    for k in HALF_ORDERS if k % 1]
_THIRD = [REVOLUTION_FEATURE_NAMES.index(f"amp_{order_label(k)}") for k in THIRD_ORDERS]


def revolution_features(
    signal,
    fs: float | None = None,
    angle=None,
    *,
    tacho=None,
    revs_per_bin: int = 48,
    revs_step: int | None = None,
    samples_per_rev: int = SAMPLES_PER_REV,
    max_order: float | None = None,
    columns=None,
    band: float = Options.band,
    threshold: float = Options.threshold,
    window=Options.window,
    detrend=Options.detrend,
    min_revolutions: float = Options.min_revolutions,
    combo_tol_order: float | None = None,
) -> pd.DataFrame:
    """Rub-impact features across speed: one row per bin of whole revolutions and channel.

    Each channel is resampled at equal angle steps (:func:`resample_to_angle`) and cut
    into bins of ``revs_per_bin`` revolutions; every bin gets the features of
    :func:`features`, with frequencies in orders (module docstring: the columns).

    Parameters
    ----------
    signal : path, DataFrame or array_like
        As for :func:`features`: a file, a DataFrame of channels, or a 1-D / 2-D array (rows
        are channels).
    fs : float, optional
        Sampling frequency in Hz; for files it may come from a time column instead.
    angle : str or array_like, optional
        The shaft angle in rad at every sample, strictly increasing (a recorded angle,
        :func:`angle_from_rpm`), or the name of the channel that holds it.
    tacho : str or array_like, optional
        Name of the once-per-revolution pulse channel, or the pulse train itself: the angle
        is then :func:`tacho_angle`'s. Give ``angle`` or ``tacho``; with neither, a channel
        named ``tacho`` is used. Tacho and angle channels are never analysed.
    revs_per_bin : int
        Revolutions per bin, at least ``min_revolutions``: the order resolution is
        ``1 / revs_per_bin``. Shorter bins follow a faster run-up; longer ones separate close
        lines. The default 48 is a multiple of 6 (half and third orders fall on bins), well
        above the 14 revolutions sidebands need, and gives the noise floor (a median over
        0.5×) 24 bins, so that a crowded stretch of lines (n×, sidebands, a combination
        line) does not lift it above the lines.
    revs_step : int, optional
        Revolutions from one bin's start to the next; default ``revs_per_bin`` (no overlap).
    samples_per_rev : int
        Samples per revolution of the angle record.
    max_order : float, optional
        Highest order the angle-domain anti-alias filter passes (default
        ``samples_per_rev / 2.56``); at least 8.5, so that every feature lies below it.
    columns : str or list of str, optional
        Channels to analyse (default: all but the tacho and angle).
    band, threshold, window, detrend, min_revolutions
        As for :func:`features` (``band`` in orders).
    combo_tol_order : float, optional
        Tolerance of f_a + f_b = m× in orders (None: the resolution ``1 / revs_per_bin``).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`BIN_NAMES` then :data:`REVOLUTION_FEATURE_NAMES`; the bins of the
        first channel, then those of the next.

    Examples
    --------
    A run-up from 600 to 2400 rpm with a 1× of amplitude 1 and a 1.5× of 0.2:

    >>> import numpy as np
    >>> fs = 2000.0
    >>> t = np.arange(12000) / fs
    >>> phi = 2 * np.pi * (10 * t + 2.5 * t**2)
    >>> x = np.cos(phi) + 0.2 * np.cos(1.5 * phi + 0.5)
    >>> table = revolution_features(x, fs, phi, revs_per_bin=24)
    >>> table[["rev_start", "rpm", "amp_1x", "amp_1p5x", "freq_1p5x_order"]].round(2)
       rev_start      rpm  amp_1x  amp_1p5x  freq_1p5x_order
    0          1   875.89     1.0       0.2              1.5
    1         25  1289.95     1.0       0.2              1.5
    2         49  1592.99     1.0       0.2              1.5
    3         73  1845.62     1.0       0.2              1.5
    4         97  2067.14     1.0       0.2              1.5
    5        121  2266.92     1.0       0.2              1.5
    >>> round(float(table["phase_1p5x_deg"].iloc[3]), 1)   # 0.5 rad against the shaft angle
    28.6
    """
    opts = Options(band=band, threshold=threshold, window=window, detrend=detrend,
                   min_revolutions=min_revolutions, combo_tol_hz=combo_tol_order)
    n_rev = _check.integer("revs_per_bin", revs_per_bin)
    if n_rev < max(opts.min_revolutions, 1.0):
        raise _check.out_of_range(
            "revs_per_bin", n_rev, f">= {max(math.ceil(opts.min_revolutions), 1)}: a bin must "
            f"hold min_revolutions = {_check.plain(opts.min_revolutions)} revolutions")
    spr, max_order = _check_grid(samples_per_rev, max_order)
    if max_order < MIN_MAX_ORDER:
        raise _check.out_of_range(
            "max_order", max_order, f">= {MIN_MAX_ORDER:g}: the features read up to 8.25x; "
            "raise samples_per_rev (max_order defaults to samples_per_rev / 2.56)")
    if angle is not None and tacho is not None:
        raise ValueError("give angle or tacho, not both")
    ch = split_channels(signal, fs, tacho, columns, angle)
    X, labels = channel_rows(ch.frame)
    X, _ = check_signals(X, "signal", labels)
    if ch.angle is not None:
        phi = check_angle(ch.angle, X.shape[1])
    elif ch.pulses is not None:
        phi = tacho_angle(ch.pulses, ch.fs)
    else:
        raise ValueError("the shaft angle is needed: give angle (rad, one per sample) or tacho "
                         "(a once-per-revolution pulse channel); no channel is named 'tacho'")
    b = angle_bins(X, ch.fs, phi, n_rev, revs_step, spr, max_order)
    n_ch, n_bins, n_seg = b.x.shape
    names = [f"{label}, bin {i}" for label in labels for i in range(n_bins)]
    # a bin is a record at "fs" = spr with 1× at one cycle per revolution: 60 "rpm"
    values = _feature_matrix(b.x.reshape(-1, n_seg), float(spr), 60.0, opts, names,
                             None)[:, _KEPT]
    values = values.reshape(n_ch, n_bins, -1)
    _measurable(values, MAX_FS_FRACTION * ch.fs / (b.max_rpm / 60.0), opts.band)
    # phases against the bin's start (revolution rev_start) -> against the shaft angle
    phase = values[..., _PHASES] - 360.0 * np.outer(b.rev_start, _CENTRE[_PHASES])
    values[..., _PHASES] = np.mod(phase + 180.0, 360.0) - 180.0
    table = pd.DataFrame(values.reshape(n_ch * n_bins, -1),
                         columns=list(REVOLUTION_FEATURE_NAMES))
    table.insert(0, "channel", np.repeat(np.asarray(ch.frame.columns, dtype=object), n_bins))
    for j, (name, column) in enumerate((("bin", np.arange(n_bins)), ("rev_start", b.rev_start),
                                        ("t_s", b.t_s), ("rpm", b.rpm)), start=1):
        table.insert(j, name, np.tile(column, n_ch))
    return table


def _measurable(values: np.ndarray, top_order: np.ndarray, band: float) -> None:
    """Set to NaN, in place, the features of each bin (axis 1 of ``values``) whose band
    reaches above ``top_order`` (:data:`MAX_FS_FRACTION` × fs in orders at the bin's highest
    speed), and recount the fractional lines present."""
    top = _CENTRE + np.where(_BANDED, band, HALF_WIDTH_ORDERS)
    above = top[np.newaxis, :] > top_order[:, np.newaxis]      # NaN centre: never
    values[:, above] = np.nan
    count = REVOLUTION_FEATURE_NAMES.index
    values[..., count("n_half_orders")] = (values[..., _FRACTIONAL_HALF] > 0).sum(axis=-1)
    values[..., count("n_third_orders")] = (values[..., _THIRD] > 0).sum(axis=-1)
