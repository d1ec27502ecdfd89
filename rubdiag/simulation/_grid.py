"""A run's length and steps: the :class:`TimeGrid` a user gives, the :class:`Ticks` it runs on.

Every step of a run is ``dt_max / 2^k`` for a level k; a *tick* is the smallest of them, and
every time the integrator stops at (a step's end, a recorded sample, a sensor sample, a
speed stretch's end) is a whole number of ticks, so the grid is exact in integers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rubdiag import _check
from rubdiag._tolerances import ON_LEVEL

__all__ = ["Ticks", "TimeGrid", "ticks"]

_MAX_LEVELS = 31      # step levels dt / 2^k at most (the tick count stays an int64)
_MAX_LONG = 3         # long steps: dt_max <= 8 dt


@dataclass(frozen=True, kw_only=True)
class TimeGrid:
    """The run's length and steps (s).

    The run ends at ``N dt`` with ``N = floor(duration / dt)`` (``round`` when within 1e-9
    of an integer). The steps are ``dt / 2^k``, halved where an element solve fails or a
    gap closes too fast, down to the largest such value >= ``dt_min``. Samples are exact
    states at step ends.

    Parameters
    ----------
    duration : float
        Simulated time (s), at least one step ``dt``.
    dt : float
        The base step (s, > 0): the first, the longest an impact element (a contact, a
        pedestal's seat) may be engaged at, and the sensor stream's interval.
    dt_min : float or None
        The smallest step (s), in (0, dt]; None: ``dt / 64``.
    fixed_step : bool
        A constant step ``dt`` (for convergence studies): nothing is halved, and an element
        solve that fails stops the run.
    output_dt : float or None
        The interval of the recorded samples (s), a positive integer multiple of ``dt``;
        None: ``dt``.
    dt_max : float or None
        Steps longer than ``dt``, up to ``dt_max = 2^k dt`` (s, k <= 3; None: none), taken
        where the local error estimate stays within ``Solver.step_error`` and every impact
        element is open and not about to close. The sensor stream keeps its interval
        ``dt`` (filled in within a long step by cubic Hermite interpolation), and a long
        step ends at every recorded sample.
    """

    duration: float
    dt: float
    dt_min: float | None = None
    fixed_step: bool = False
    output_dt: float | None = None
    dt_max: float | None = None


class Ticks(NamedTuple):
    """A run's checked step sizes and its grid of ticks (a tick is the smallest step).

    The levels are ``dt_max / 2^k``: the first ``base`` are the long steps (``dt_max =
    2^base dt``, taken where the local error allows and no impact element is near), level
    ``base`` is dt, the base step (the first, the longest an impact element may be engaged
    at, and the sensor stream's interval)."""

    dt: float  # the base step (s)
    dt_min: float  # the smallest step asked for (s)
    n_lev: int  # step levels dt_max / 2^k, k < n_lev
    n_big: int  # the run's length in base steps
    output_dt: float  # s
    tick_total: np.int64  # the run's length in ticks
    out_ticks: np.int64  # ticks between recorded samples
    base: int = 0  # the base step's level
    fixed_step: bool = False  # a constant step dt

    @property
    def top(self) -> int:
        """The smallest step's level."""
        return self.n_lev - 1

    @property
    def dt_max(self) -> float:
        """The longest step (s)."""
        return self.dt * 2**self.base

    @property
    def tick_dt(self) -> float:
        """A tick (s)."""
        return self.dt / 2 ** (self.top - self.base)

    @property
    def duration(self) -> float:
        """The run's length (s): whole base steps."""
        return self.n_big * self.dt

    @property
    def n_out(self) -> int:
        """Recorded samples, t = 0 included."""
        return int(self.tick_total // self.out_ticks) + 1

    @property
    def sen_ticks(self) -> np.int64:
        """Ticks between sensor samples: every base step."""
        return np.int64(1) << (self.top - self.base)

    def n_sensor_samples(self, n_sensors: int) -> int:
        """Sensor samples of a run recording ``n_sensors`` DOFs, t = 0 included."""
        return int(self.tick_total // self.sen_ticks) + 1 if n_sensors else 0


def ticks(grid: TimeGrid) -> Ticks:
    """The checked step sizes and tick grid of ``grid``; a bad value raises ``ValueError``
    naming the field and its allowed range."""
    if not isinstance(grid, TimeGrid):
        raise _check.wrong_type("grid", type(grid).__name__, "a TimeGrid")
    dt = _check.number("dt", grid.dt, lo=0.0, lo_open=True, allowed="finite and > 0 s")
    fixed_step, dt_max = bool(grid.fixed_step), grid.dt_max
    base = 0
    if dt_max is not None:
        dt_max = _check.number("dt_max", dt_max, lo=dt, allowed=f">= dt = {dt:g} s")
        base = round(math.log2(dt_max / dt))
        if abs(dt_max - dt * 2**base) > ON_LEVEL * dt_max or base > _MAX_LONG:
            raise _check.out_of_range("dt_max", dt_max,
                                      f"dt = {dt:g} s times 1, 2, 4 … {2**_MAX_LONG}")
        if fixed_step and base:
            raise _check.out_of_range("dt_max", dt_max, f"dt = {dt:g} s with fixed_step")
    duration = _check.number("duration", grid.duration, lo=0.0, lo_open=True,
                             allowed="finite and > 0 s")
    if duration < dt * (1 - ON_LEVEL):
        raise _check.out_of_range("duration", duration, f">= one step dt = {dt:g} s")
    if fixed_step:
        dt_min = dt
    elif grid.dt_min is None:
        dt_min = dt / 64
    else:
        dt_min = _check.number("dt_min", grid.dt_min, lo=0.0, lo_open=True,
                               allowed="finite and > 0 s")
        if dt_min > dt:
            raise _check.out_of_range("dt_min", dt_min, f"<= dt = {dt:g} s")
    n_lev = 1 + math.floor(math.log2(dt / dt_min) + ON_LEVEL)
    if n_lev > _MAX_LEVELS:
        raise _check.out_of_range("dt_min", dt_min, f">= dt / 2^{_MAX_LEVELS - 1}")
    top = n_lev - 1     # ticks per base step: 2^top
    n_lev += base
    ratio = duration / dt
    n_big = round(ratio) if abs(ratio - round(ratio)) < ON_LEVEL * max(1.0, ratio) else int(ratio)
    if grid.output_dt is None:
        m_out = 1
        output_dt = dt
    else:
        output_dt = _check.number("output_dt", grid.output_dt, lo=0.0, lo_open=True)
        r = output_dt / dt
        m_out = round(r)
        if m_out < 1 or abs(r - m_out) > ON_LEVEL * max(1.0, r):
            raise _check.out_of_range("output_dt", output_dt,
                                      f"a positive integer multiple of dt = {dt:g} s")
    tick_total = np.int64(n_big) << top
    out_ticks = np.int64(m_out) << top
    return Ticks(dt, dt_min, n_lev, n_big, output_dt, tick_total, out_ticks, base, fixed_step)
