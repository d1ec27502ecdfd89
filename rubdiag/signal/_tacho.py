"""Shaft angle and speed at every sample: from a tacho pulse train or from a speed channel.

Order tracking needs the rotation angle φ(t) (rad) of the shaft at each sample. A tacho gives
it at the pulses only: each pulse is ``2π / pulses_per_rev`` more angle, and between pulses a
monotone cubic (PCHIP) through the pulse times interpolates it without overshoot, so the
angle never runs backwards even where the speed changes abruptly. A record that carries a
speed channel instead is integrated (:func:`angle_from_rpm`).

:func:`check_angle` is the one check of an angle record that every angle-domain analysis
(:mod:`rubdiag.signal._ordertrack`, :mod:`rubdiag.signal._waterfall`) runs.
"""

from __future__ import annotations

import numpy as np
import scipy.integrate
import scipy.interpolate

from rubdiag import _check
from rubdiag.signal._records import check_fs, check_signals

#: Fewest pulses an angle or speed is built from (two intervals: a speed and its change).
MIN_PULSES = 3


def tacho_angle(pulses, fs: float, pulses_per_rev: int = 1) -> np.ndarray:
    """Rotation angle of the shaft at every sample, from a tacho pulse train.

    A pulse is a rising crossing of the level halfway between the signal's minimum and
    maximum, located to a fraction of a sample (as in :func:`tacho_speed`). The angle is 0
    at the first pulse and grows by ``2π / pulses_per_rev`` at each following pulse. A
    PCHIP interpolant through (pulse time, angle) gives the angle between pulses; before the
    first and after the last pulse the angle is extrapolated at a constant speed, the
    interpolant's speed at that pulse (so the speed has no step there).

    Parameters
    ----------
    pulses : array_like, 1-D
        Tacho signal: ``pulses_per_rev`` evenly spaced pulses per revolution, pointing up.
    fs : float
        Sampling frequency in Hz.
    pulses_per_rev : int
        Pulses per revolution (teeth of the wheel, marks on the shaft), at least 1.

    Returns
    -------
    ndarray
        Angle φ in rad, one per sample, increasing. Orders are phased against it:
        ``cos(k φ + phase)``.

    Notes
    -----
    The angle between pulses is an interpolation: it is exact for a constant speed and
    follows a smooth run-up to second order in the speed change per pulse interval (about
    1e-3 rad at one pulse per revolution on a 5 %-per-revolution run-up). Pulses are taken as
    evenly spaced; a wheel with uneven teeth needs its spacing measured.
    """
    return _tacho_curve(pulses, check_fs(fs), pulses_per_rev, 0)


def tacho_rpm(pulses, fs: float, pulses_per_rev: int = 1) -> np.ndarray:
    """Running speed at every sample, from a tacho pulse train (like MATLAB ``tachorpm``).

    The derivative of the interpolant of :func:`tacho_angle` (the same angle, so speed and
    angle agree), converted to rpm; constant before the first and after the last pulse.

    Parameters
    ----------
    pulses, fs, pulses_per_rev
        As for :func:`tacho_angle`.

    Returns
    -------
    ndarray
        Speed in rpm, one per sample.
    """
    return (60.0 / (2.0 * np.pi)) * _tacho_curve(pulses, check_fs(fs), pulses_per_rev, 1)


def angle_from_rpm(speed_rpm, fs: float) -> np.ndarray:
    """Rotation angle at every sample from a speed channel, by trapezoidal integration.

    Parameters
    ----------
    speed_rpm : array_like, 1-D
        Running speed in rpm, one per sample, finite and >= 0.
    fs : float
        Sampling frequency in Hz.

    Returns
    -------
    ndarray
        Angle φ in rad, 0 at the first sample. Order analysis needs it to increase strictly:
        trim the record to where the shaft turns.
    """
    fs = check_fs(fs)
    rpm, _ = check_signals(speed_rpm, "speed_rpm")
    if rpm.shape[0] != 1:
        raise ValueError(f"speed_rpm has {rpm.shape[0]} rows (allowed: one speed channel, 1-D)")
    rpm = rpm[0]
    if (rpm < 0.0).any():
        i = int(np.flatnonzero(rpm < 0.0)[0])
        raise _check.out_of_range(f"speed_rpm[{i}]", rpm[i], ">= 0 rpm")
    omega = rpm * (2.0 * np.pi / 60.0)
    return scipy.integrate.cumulative_trapezoid(omega, dx=1.0 / fs, initial=0.0)


def check_angle(angle, n_samples: int) -> np.ndarray:
    """``angle`` (rad, one per sample) as a float64 1-D array of ``n_samples`` values, finite
    and strictly increasing (a shaft turning backwards: pass ``-angle``)."""
    try:
        phi = np.asarray(angle, dtype=np.float64)
    except (TypeError, ValueError):
        raise _check.wrong_type("angle", type(angle).__name__, "numeric angles in rad") from None
    if phi.ndim != 1:
        raise ValueError(f"angle has {phi.ndim} dimensions (allowed: 1, one angle per sample)")
    if phi.size != n_samples:
        raise ValueError(f"angle has {phi.size} samples (allowed: {n_samples}, one per sample "
                         "of x)")
    bad = ~np.isfinite(phi)
    if bad.any():
        raise ValueError(f"angle contains NaN or inf (first at sample {np.flatnonzero(bad)[0]})")
    step = np.diff(phi)
    if (step <= 0.0).any():
        i = int(np.flatnonzero(step <= 0.0)[0]) + 1
        raise _check.out_of_range(
            f"angle[{i}]", phi[i],
            f"> angle[{i - 1}] = {_check.plain(phi[i - 1])} rad: the angle must increase "
            "strictly")
    return phi


def _tacho_curve(pulses, fs: float, pulses_per_rev, nu: int) -> np.ndarray:
    """φ(t) (``nu = 0``, rad) or dφ/dt (``nu = 1``, rad/s) at every sample: PCHIP through
    the pulses, straight lines beyond the first and last at the interpolant's end speeds."""
    ppr = _check.integer("pulses_per_rev", pulses_per_rev, lo=1)
    tp, n = _pulse_times(pulses, fs)
    phi = (2.0 * np.pi / ppr) * np.arange(tp.size)
    # PCHIP's slopes at the pulses; its end slopes are one-sided three-point estimates (the
    # end interval's mean speed is that of its middle). After an abrupt speed change PCHIP
    # sets an end slope to 0, a shaft at rest: take the end interval's speed there instead.
    w = scipy.interpolate.PchipInterpolator(tp, phi)(tp, 1)
    secant = np.diff(phi) / np.diff(tp)
    w[0] = w[0] if w[0] > 0.0 else secant[0]
    w[-1] = w[-1] if w[-1] > 0.0 else secant[-1]
    curve = scipy.interpolate.CubicHermiteSpline(tp, phi, w)
    t = np.arange(n) / fs
    inside = curve(np.clip(t, tp[0], tp[-1]), nu)
    if nu == 1:
        return np.where(t < tp[0], w[0], np.where(t > tp[-1], w[-1], inside))
    return inside + w[0] * np.minimum(t - tp[0], 0.0) + w[-1] * np.maximum(t - tp[-1], 0.0)


def _pulse_times(pulses, fs: float) -> tuple[np.ndarray, int]:
    """Times (s) of the rising crossings of the mid level of a pulse train.

    The level is halfway between the signal's minimum and maximum; each crossing is located
    to a fraction of a sample by linear interpolation between the samples around it (also
    :func:`rubdiag.signal.tacho_speed`'s pulses). Returns the crossing times in s (``t = 0`` at the
    first sample; at least :data:`MIN_PULSES` of them) and the number of samples.
    """
    x, _ = check_signals(pulses, "pulses")
    if x.shape[0] != 1:
        raise ValueError(f"pulses has {x.shape[0]} rows (allowed: one tacho signal, 1-D)")
    x = x[0]
    level = 0.5 * (x.min() + x.max())
    above = x > level
    i = np.flatnonzero(~above[:-1] & above[1:])  # crossing between samples i and i + 1
    if i.size < MIN_PULSES:
        raise ValueError(f"pulses has {i.size} pulses (rising crossings of its mid level) "
                         f"(allowed: at least {MIN_PULSES})")
    return (i + (level - x[i]) / (x[i + 1] - x[i])) / fs, x.size
