"""A channel's noise floor from its broadband levels, and its bands over that floor.

The broadband RMS around each harmonic (``bb_<n>x_rms``: n× ± 0.25× without the n× line,
:mod:`rubdiag.signal._sidebands`) holds only measurement noise where nothing else reaches,
so a channel's quietest band is its *noise floor*, and a band over the floor says how far it
stands out of the noise: ≈ 1 for noise alone, however loud the machine or its sensor.

How the lines are left out: every line up to 9.25× is fitted (exact frequency, amplitude and
phase) and subtracted from the record, and only its main lobe put back
(:mod:`rubdiag.signal._linefree`); a band then leaves out its n× line's main lobe. A line
between two FFT bins would otherwise leak over the whole band — a clean 1× and 2× of
0.35 × 1× read ``bb_2x_over_floor`` 16.5 at 1451.84 rpm (1-s window) and 1.0 at 1500 rpm;
both now read 1.0, and a speed swept across two bins moves the bands and the floor by less
than :data:`~rubdiag.signal._linefree.OFF_BIN_BAND_TOLERANCE`.

A record without noise has no such floor — a simulation's raw output, a record of high
resolution: its quietest band holds round-off, window leakage and float32 storage, 1e-8 to
1e-6 of the channel's level, or exactly 0. Every band over that reads 1e4 to 1e8, which a
model trained on sensor noise takes for rub. So the floor is taken no lower than
:data:`MIN_FLOOR_OF_LEVEL` of the channel's *level* (its RMS within the searched orders,
computed by the caller), and a band reads no lower than the floor: a band below it is "at
the floor" (1), as it would be under a sensor's noise.
"""

from __future__ import annotations

import numpy as np

#: The least noise floor of a channel, as a fraction of its level: 1e-4 (-80 dB), in a
#: band 0.5× wide. Why this value (``python benchmarks/bench_noise_free.py``: 60 runs of
#: the paper rig, the mid-span probe): it is about the floor a plant's sensor noise gives —
#: the default 1 µm noise puts the quietest band at 1.5e-4 of the level (median; 10–90 %:
#: 5e-5 to 5.4e-4), so a noise-free record reads about as its noisy twin; rub lifts the
#: loudest band 2× … 8× to 7e-4 of the level or more in 9 of 10 rubbing runs (median
#: 6.8e-3), above it; a noise-free record's quietest band (median 1.5e-6, or exactly 0)
#: lies far below. Models trained on the noisy runs then predict 96–100 % of held-out
#: noise-free runs as their noisy twins (forest; 91–98 % without the rule, 64–82 % while
#: the bands still held the lines' leakage), accuracy within 0.03 of the other least
#: floors; 1e-5 and 1e-3 agree about as well (95–100 %), 1e-2 less (91–98 %).
MIN_FLOOR_OF_LEVEL = 1e-4


def channel_floor(bands, level) -> np.ndarray:
    """The noise floor of each row: its smallest band RMS, but no lower than
    :data:`MIN_FLOOR_OF_LEVEL` × ``level``. A band of exactly 0 (a noise-free record whose
    band holds nothing) counts: the floor is then the rule's.

    Parameters
    ----------
    bands : array_like, (n_rows, n_bands)
        Broadband RMS values of each row (unit of the signal; NaN where not measured).
    level : array_like, (n_rows,)
        The channel's level in the same unit.

    Returns
    -------
    ndarray, (n_rows,)
        The floor (unit of the signal); NaN where the level is not positive (a still
        channel: nothing stands over a floor there).
    """
    v = np.atleast_2d(np.asarray(bands, dtype=np.float64))
    level = np.asarray(level, dtype=np.float64)
    quietest = np.min(np.where(np.isnan(v), np.inf, v), axis=1)     # not measured: no floor
    quietest = np.where(np.isfinite(quietest), quietest, 0.0)
    floor = np.maximum(quietest, MIN_FLOOR_OF_LEVEL * level)
    return np.where(level > 0.0, floor, np.nan)


def over_floor(band, floor) -> np.ndarray:
    """``band`` over ``floor``, no lower than 1 (a band is never below the floor); NaN
    where the band was not measured, 0 where there is no floor (a still channel)."""
    band = np.asarray(band, dtype=np.float64)
    floor = np.asarray(floor, dtype=np.float64)
    none = np.isnan(floor)
    ratio = np.maximum(band, floor) / np.where(none, 1.0, floor)    # NaN band stays NaN
    return np.where(none, 0.0 * band, ratio)
