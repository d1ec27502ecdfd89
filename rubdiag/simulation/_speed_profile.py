"""A run's spin speed in time: a linear ramp or a table of (t, rpm) points.

Ω(t) is piecewise linear through the knots and constant after the last one, so the shaft
angle φ(t) = ∫ Ω dt (φ(0) = 0) is exact, piecewise quadratic. The unbalance load follows φ
and includes the angular-acceleration term (:data:`rubdiag._kernels.interface.Force`); the
gyroscopic term Ω(t) G is held at a reference speed over stretches of the run in which Ω
stays within a relative ``tolerance`` of it, and the step operators are refactorised at each
new stretch (:meth:`SpeedProfile.stretches`). A constant-speed run has no profile.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from rubdiag import _check

__all__ = ["SpeedProfile"]

_RPM = math.pi / 30.0   # rad/s per rpm


@dataclass(frozen=True)
class SpeedProfile:
    """Ω(t), piecewise linear through ``(times_s[k], speeds_rad_s[k])``, constant after the
    last knot. ``times_s`` start at 0 and increase; speeds are positive (rad/s).

    Use :meth:`ramp` for a run-up or coast-down at a constant rate, :meth:`table` for a
    measured or designed speed curve in rpm.

    Parameters
    ----------
    times_s : tuple of float
        Knot times (s), from 0, increasing.
    speeds_rad_s : tuple of float
        Speed at each knot (rad/s, > 0).
    """

    times_s: tuple[float, ...]
    speeds_rad_s: tuple[float, ...]

    def __post_init__(self):
        times = tuple(float(t) for t in np.atleast_1d(self.times_s))
        speeds = tuple(float(w) for w in np.atleast_1d(self.speeds_rad_s))
        if len(times) != len(speeds) or len(times) < 2:
            raise ValueError(f"a speed profile needs matching times_s and speeds_rad_s with at "
                             f"least 2 points (got {len(times)} and {len(speeds)})")
        if times[0] != 0.0:
            raise ValueError(f"times_s[0] = {times[0]:g} s (allowed: 0, the run's start)")
        for k, t in enumerate(times):
            _check.number(f"times_s[{k}]", t, lo=0.0, hi=1e6)
        if any(b <= a for a, b in itertools.pairwise(times)):
            raise ValueError("times_s must increase strictly")
        for k, w in enumerate(speeds):
            _check.number(f"speeds_rad_s[{k}]", w, lo=0.0, hi=1e5, lo_open=True)
        object.__setattr__(self, "times_s", times)
        object.__setattr__(self, "speeds_rad_s", speeds)

    @classmethod
    def ramp(cls, from_rpm: float, to_rpm: float, rate_rpm_s: float,
             hold_s: float = 0.0) -> SpeedProfile:
        """Constant speed ``from_rpm`` for ``hold_s`` seconds, then a linear ramp at
        ``rate_rpm_s`` (rpm/s, > 0) to ``to_rpm``: a run-up, or a coast-down when
        ``to_rpm < from_rpm``."""
        start = _check.number("from_rpm", from_rpm, lo=0.0, hi=1e6, lo_open=True)
        end = _check.number("to_rpm", to_rpm, lo=0.0, hi=1e6, lo_open=True)
        rate = _check.number("rate_rpm_s", rate_rpm_s, lo=0.0, hi=1e6, lo_open=True)
        hold = _check.number("hold_s", hold_s, lo=0.0, hi=1e6)
        if start == end:
            raise ValueError(f"from_rpm = to_rpm = {start:g} (allowed: different speeds; a "
                             "constant-speed run has no profile)")
        times = [0.0, hold] if hold > 0 else [0.0]
        speeds = [start, start] if hold > 0 else [start]
        times.append(hold + abs(end - start) / rate)
        speeds.append(end)
        return cls(tuple(times), tuple(s * _RPM for s in speeds))

    @classmethod
    def table(cls, times_s, speeds_rpm) -> SpeedProfile:
        """Ω through the points ``(times_s[k], speeds_rpm[k])`` (rpm), linear in between."""
        return cls(tuple(np.atleast_1d(times_s)),
                   tuple(float(w) * _RPM for w in np.atleast_1d(speeds_rpm)))

    @property
    def start_rad_s(self) -> float:
        return self.speeds_rad_s[0]

    @property
    def end_s(self) -> float:
        """Time of the last knot (s): the speed is constant after it."""
        return self.times_s[-1]

    def knots(self) -> np.ndarray:
        """(n, 3) rows (t, Ω, φ) at the knots: what the integrator's load evaluates."""
        t, w = np.array(self.times_s), np.array(self.speeds_rad_s)
        phi = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
        return np.ascontiguousarray(np.column_stack([t, w, phi]))

    def speed(self, t) -> np.ndarray:
        """Ω (rad/s) at times ``t`` (s)."""
        return np.interp(t, self.times_s, self.speeds_rad_s)

    def acceleration(self, t) -> np.ndarray:
        """dΩ/dt (rad/s²) at times ``t`` (s); at a knot, the slope of the segment after it."""
        t = np.asarray(t, dtype=float)
        knots = self.knots()
        k = np.clip(np.searchsorted(knots[:, 0], t, side="right") - 1, 0, len(knots) - 1)
        slope = np.append(np.diff(knots[:, 1]) / np.diff(knots[:, 0]), 0.0)
        return slope[k]

    def angle(self, t) -> np.ndarray:
        """φ(t) = ∫₀ᵗ Ω dt (rad), exact."""
        t = np.asarray(t, dtype=float)
        knots = self.knots()
        k = np.clip(np.searchsorted(knots[:, 0], t, side="right") - 1, 0, len(knots) - 1)
        tau = t - knots[k, 0]
        return knots[k, 2] + knots[k, 1] * tau + 0.5 * self.acceleration(t) * tau**2

    def stretches(self, duration_s: float, tolerance: float,
                  resolution_s: float = 1e-4) -> list[tuple[float, float]]:
        """``[(t_end, Ω_ref), …]``: consecutive stretches of ``[0, duration_s]`` over which
        Ω stays within ``tolerance · Ω_ref`` of Ω_ref (the middle of its range there), found
        on a grid of ``resolution_s``. The integrator holds the gyroscopic term at Ω_ref G
        over a stretch and refactorises at the next."""
        tol = _check.number("speed_tolerance", tolerance, lo=0.0, hi=0.5, lo_open=True)
        t = np.linspace(0.0, duration_s, max(2, math.ceil(duration_s / resolution_s) + 1))
        w = self.speed(t)
        out, first = [], 0
        while first < len(t) - 1:
            lo = hi = w[first]
            last = first + 1
            while last < len(t):
                lo2, hi2 = min(lo, w[last]), max(hi, w[last])
                if hi2 - lo2 > tol * (hi2 + lo2):   # |Ω - mid| ≤ tol · mid
                    break
                lo, hi, last = lo2, hi2, last + 1
            end = last if last == len(t) else last - 1    # the last point inside the band
            end = max(min(end, len(t) - 1), first + 1)
            out.append((float(t[end]), 0.5 * (lo + hi)))
            first = end
        return out
