"""The largest linear approach over the speeds a run's analysis window sweeps.

A constant-speed run's ``interference_ratio`` (:mod:`rubdiag.dataset._labels`) is the
largest radial approach of its linear (contact-free) steady-state unbalance response at the
contacts, over g0. A run along a speed profile (a design with ``[ramp]``) has a response
that changes with the speed, so its ratio takes the largest approach over every speed its
window passes: :func:`sweep_linear_approach_m`, the steady-state approach maximised over the
window's speed range — found on a grid of :data:`N_GRID` speeds and refined around the best
one (bounded scalar search), so a sweep through a critical speed gets the peak's value.

The approach comes from the full finite-element model at each speed (the rig's linear
response, as ``SimulationResult.linear_approach_m`` of a full-model run at that speed). For
a reduced run it differs from the reduced model's by about 1e-5 relative, far below any
label threshold, and costs a fiftieth of it (a sparse solve per speed).
"""

from __future__ import annotations

import dataclasses
import functools
import warnings

import numpy as np

__all__ = ["N_GRID", "approach_of", "damped_model", "sweep_linear_approach_m",
           "window_speed_range"]

#: Speeds of the first, coarse search over the window's range (both ends included).
N_GRID = 65
#: The refined speed's tolerance, relative to the window's top speed: the approach is flat
#: at its maximum, so its value there is found far more closely than the speed.
_SPEED_XATOL = 1e-7


def approach_of(run) -> str:
    """The contacts whose linear approach sets a design run's clearance from its
    ``interference_ratio`` and labels it: ``"seals"`` when the run sets its seal's
    clearance (``Run.seal_clearance_m``), else ``"blades"``."""
    return "seals" if run.seal_clearance_m is not None else "blades"


def window_speed_range(run) -> tuple[float, float]:
    """The lowest and highest speed (rad/s) of ``run`` over its analysis window
    ``[discard_s, duration_s]`` (the speed is piecewise linear: its ends and the profile's
    knots inside it bound it)."""
    start, end = run.discard_s, run.duration_s
    times = [start, end]
    if run.speed_profile is not None:
        times += [t for t in run.speed_profile.times_s if start < t < end]
    speeds = run.speed_at(np.array(times))
    return float(speeds.min()), float(speeds.max())


def damped_model(rig):
    """The full model of ``rig`` with its Rayleigh damping, as the approach needs it."""
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh

    return with_rayleigh(assemble(rig))


def sweep_linear_approach_m(run, model=None, of: str | None = None) -> float:
    """The largest linear approach (m) of ``run``'s contacts over the speeds of its analysis
    window (module docstring); at constant speed, the approach at that speed. ``model``:
    :func:`damped_model` of the run's rig, when the caller has it; ``of``: "blades" or
    "seals" for those contacts only (None: all of them)."""
    from scipy.optimize import minimize_scalar

    if model is None:
        model = damped_model(run.rig)
    approach = functools.partial(_approach, run, model, of=of)
    lo, hi = window_speed_range(run)
    if hi == lo:
        return approach(lo)
    grid = np.linspace(lo, hi, N_GRID)
    values = np.array([approach(s) for s in grid])
    k = int(np.argmax(values))
    bounds = (grid[max(k - 1, 0)], grid[min(k + 1, N_GRID - 1)])
    best = minimize_scalar(lambda s: -approach(s), bounds=bounds, method="bounded",
                           options={"xatol": _SPEED_XATOL * hi})
    return max(float(values[k]), -float(best.fun))


def _approach(run, model, speed_rad_s: float, of: str | None = None) -> float:
    """The linear approach of ``run``'s contacts at constant speed (full model)."""
    from rubdiag.simulation import GapRampInWindow
    from rubdiag.simulation._rig_system import linear_approach

    with warnings.catch_warnings():   # the run warned when it was made; replace re-checks
        warnings.simplefilter("ignore", GapRampInWindow)
        steady = dataclasses.replace(run, speed_rad_s=float(speed_rad_s), speed_profile=None,
                                     reduction=None, sensors=())
    return linear_approach(steady, model, of)
