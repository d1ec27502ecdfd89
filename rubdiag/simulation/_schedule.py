"""A speed profile's stretches: where the integrator holds Ω(t) G at a reference speed.

Along a :class:`~rubdiag.simulation.SpeedProfile` the damping is ``C + Ω(t) G``; the step
operators (factorised once per step size) hold it at a reference speed Ω_ref over a stretch
in which Ω stays within the system's ``speed_tolerance`` of Ω_ref, and are made again at
each new stretch. The kernel runs stretch by stretch (:class:`Schedule`).
"""

from __future__ import annotations

import numpy as np

from rubdiag import _check
from rubdiag._tolerances import BOUND_SLACK
from rubdiag.simulation._grid import Ticks
from rubdiag.simulation._linear_system import checked_matrix
from rubdiag.simulation._loads import HarmonicForce
from rubdiag.simulation._speed_profile import SpeedProfile

__all__ = ["Schedule", "checked_profile"]


def checked_profile(profile, tolerance, G, force: HarmonicForce, n: int, grid: Ticks):
    """``(rot, stretches, G)`` of a speed profile: its knots as the kernel reads them, its
    stretches ``[(t_end, Ω_ref), …]`` and the checked G; for constant speed ``(empty (0,
    3), [], None)``. ``tolerance`` 0 gives one stretch per largest step, each at Ω at its
    end (the reference the stretches are tested against)."""
    if profile is None:
        return np.zeros((0, 3)), [], None
    if not isinstance(profile, SpeedProfile):
        raise _check.wrong_type("speed_profile", type(profile).__name__,
                                "a SpeedProfile or None")
    if G is None:
        raise ValueError("speed_profile needs gyroscopic (the unit-speed G; use a zero "
                         "matrix for a system without gyroscopic terms)")
    G = checked_matrix("gyroscopic", G, n)
    if force.dofs.size and not np.allclose(force.omega, profile.start_rad_s, rtol=BOUND_SLACK,
                                           atol=0):
        raise ValueError(f"force.omega = {force.omega[0]:g} rad/s (allowed: the speed "
                         f"profile's start speed, {profile.start_rad_s:g} rad/s)")
    if tolerance == 0:
        ends = grid.dt * np.arange(1, grid.n_big + 1)
        return profile.knots(), list(zip(ends.tolist(), profile.speed(ends).tolist(),
                                         strict=True)), G
    return profile.knots(), profile.stretches(grid.n_big * grid.dt, tolerance), G


class Schedule:
    """The stretches of a speed profile in ticks, and the step operators of each.

    ``operators(omega_ref)`` makes the operators of a stretch (the kernel's linear part,
    factors and element bundle at Ω_ref); ``used`` counts the stretches the run reached."""

    def __init__(self, stretches, grid: Ticks, operators):
        tick_dt = grid.tick_dt
        self.ends = [min(grid.tick_total, round(t / tick_dt)) for t, _ in stretches]
        self.ends[-1] = grid.tick_total
        self.speeds = [w for _, w in stretches]
        self.operators = operators
        self.index = 0
        self.used = 1

    def tick_end(self) -> int:
        """The current stretch's last tick."""
        return self.ends[self.index]

    def advance(self, tick: int):
        """The operators for the stretch holding ``tick`` (None: the current ones hold)."""
        index = self.index
        while index < len(self.ends) - 1 and tick >= self.ends[index]:
            index += 1
        if index == self.index:
            return None
        self.index = index
        self.used += 1
        return self.operators(self.speeds[index])
