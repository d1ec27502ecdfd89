"""Run-ups and coast-downs through the critical speeds: the run, its order tracks and its
headline numbers.

* :func:`ramp_run` — a run of the study's rig along a linear speed ramp, starting from the
  linear steady state at the start speed (with the gap closed gently first when that state
  already reaches the casing).
* :func:`runup_orders` — amplitude and phase of chosen orders of a recorded point against
  speed (computed order tracking on the run's shaft angle, :func:`rubdiag.signal.order_track`).
* :func:`linear_response` — the contact-free steady-state 1× vector of a point at given
  speeds, the reference a Bode plot draws dashed.
* :func:`runup_summary` — peak 1× amplitude and its speed, and where the rub starts and ends.

Phases follow :func:`~rubdiag.signal.order_track`: a point moves as ``amp cos(kφ + phase)``
with φ the shaft angle, so the linear response ``A`` (``x = Re(A e^{iφ})``) has phase ``arg A``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag.signal import order_label, order_track

if TYPE_CHECKING:   # the simulator loads on first use: rubdiag.signal_features must not need it
    from rubdiag.simulation import Run

__all__ = ["DEFAULT_POINT", "RUNUP_ORDERS", "linear_response", "ramp_run", "runup_orders",
           "runup_summary"]

#: The shaft's mid-span station, where the first mode peaks (``SimulationResult.points``).
DEFAULT_POINT = "shaft 11 y"
#: Orders tracked by default: the 1× and its harmonics, and the half orders of rub.
RUNUP_ORDERS = (0.5, 1.0, 1.5, 2.0, 3.0, 4.0)
#: Time over which the gap closes when the start speed's linear response reaches the casing.
GAP_CLOSING_S = 0.1


def ramp_run(case: int, from_rpm: float, to_rpm: float, rate_rpm_s: float, gap_mm: float, *,
             hold_s: float = 0.0, **options) -> Run:
    """The study's ``case`` with gap ``gap_mm`` along a ramp ``from_rpm`` → ``to_rpm`` at
    ``rate_rpm_s`` (a coast-down when ``to_rpm < from_rpm``), after ``hold_s`` seconds at
    ``from_rpm``. The run lasts to the end of the ramp and its whole record is analysed
    (``discard_s = 0``).

    It starts from the linear steady state at ``from_rpm``. When that state already reaches
    the casing, the gap closes from just above it over :data:`GAP_CLOSING_S`, held at the
    start speed (``hold_s`` at least that long), and the analysis window starts after it.
    Other ``options`` are :class:`~rubdiag.simulation.Run` fields (``reduction``, ``dt_s``,
    ``contact``, ``rig`` …).

    Parameters
    ----------
    case : {1, 2}
        The study's case.
    from_rpm, to_rpm : float
        Start and end speed of the ramp (rpm).
    rate_rpm_s : float
        The ramp's rate (rpm/s, > 0).
    gap_mm : float
        Blade-tip/casing gap (mm).
    hold_s : float
        Time held at ``from_rpm`` before the ramp (s).
    **options
        Other :class:`~rubdiag.simulation.Run` fields.

    Returns
    -------
    Run
        The run along its speed profile.
    """
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh
    from rubdiag.simulation import Run, SpeedProfile
    from rubdiag.simulation._rig_system import rig_system
    from rubdiag.simulation._simulation import RAMP_MARGIN

    def make(hold: float, closing: float) -> Run:
        profile = SpeedProfile.ramp(from_rpm, to_rpm, rate_rpm_s, hold_s=hold)
        return Run.paper_case(case, gap_mm, speed_profile=profile, duration_s=profile.end_s,
                              discard_s=closing, gap_ramp_s=closing, **options)

    run = make(hold_s, 0.0)
    if run.contact_law is None:
        return run
    approach = rig_system(run, with_rayleigh(assemble(run.rig))).approach
    if RAMP_MARGIN * approach <= run.gap_m:
        return run
    return make(max(hold_s, GAP_CLOSING_S), GAP_CLOSING_S)


def runup_orders(result, point: str = DEFAULT_POINT, orders=RUNUP_ORDERS,
                 revs_per_bin: int = 4, revs_step: int = 1, **options) -> pd.DataFrame:
    """Order tracks of ``point`` over the whole record of a run along a speed profile:
    :func:`rubdiag.signal.order_track` of its displacement (m) on the run's shaft angle,
    with ``options`` passed on. Bins of ``revs_per_bin`` revolutions (even, for the half
    orders), one starting every ``revs_step``: at 300 rpm/s four revolutions are 48 rpm at
    the first critical, and overlapping bins draw the passage as a curve, not a polygon.

    Parameters
    ----------
    result : SimulationResult
        A run along a speed profile.
    point : str
        A recorded displacement.
    orders : sequence of float
        The orders tracked.
    revs_per_bin : int
        Revolutions per bin (even).
    revs_step : int
        Revolutions between the starts of successive bins.
    **options
        Passed on to :func:`rubdiag.signal.order_track`.

    Returns
    -------
    pandas.DataFrame
        One row per bin (:func:`rubdiag.signal.order_track`): its speed (rpm) and each
        order's amplitude (m) and phase (degrees).
    """
    return order_track(result.displacement(point), result.fs, result.angle_rad,
                       orders=orders, revs_per_bin=revs_per_bin, revs_step=revs_step,
                       **options)


def linear_response(run: Run, point: str = DEFAULT_POINT, speed_rpm=None) -> np.ndarray:
    """The contact-free steady-state unbalance response ``A`` (m, complex) of ``point`` at
    the speeds ``speed_rpm`` (full finite-element model, Rayleigh damping, gyroscopic term
    at each speed): ``x = Re(A e^{iφ})``.

    Parameters
    ----------
    run : Run
        A run (its rig, unbalance and speed are used; contacts are not).
    point : str
        A DOF name, e.g. ``"shaft 11 y"``.
    speed_rpm : float or array_like
        Speeds (rpm).

    Returns
    -------
    numpy.ndarray
        Complex amplitude at each speed (m).
    """
    from rubdiag.assembly import assemble
    from rubdiag.modal import harmonic_response, with_rayleigh

    model = with_rayleigh(assemble(run.rig))
    node, direction = point.rsplit(" ", 1)
    dof = model.dofs.index(node, direction)
    speeds = np.atleast_1d(np.asarray(speed_rpm, dtype=float)) * math.pi / 30
    return np.array([harmonic_response(model, float(s), run.unbalance).amplitudes[dof]
                     for s in speeds])


def runup_summary(result, point: str = DEFAULT_POINT, revs_per_bin: int = 4,
                  orders: pd.DataFrame | None = None) -> dict:
    """Headline numbers of a run along a speed profile (SI, speeds in rpm).

    ``peak_1x_m`` and ``peak_rpm``: the largest 1× amplitude of ``point`` and the mean speed
    of its bin (:func:`runup_orders`, or the given ``orders`` table); ``rate_rpm_s``: the
    profile's fastest change; ``n_episodes``: contact episodes of every element
    (``n_episodes_element_1`` of the first); ``first_contact_rpm`` and ``last_contact_rpm``:
    the speed where the first episode starts and the last one ends (NaN without contact);
    ``max_contact_force_n``.

    Parameters
    ----------
    result : SimulationResult
        A run along a speed profile.
    point : str
        A recorded displacement.
    revs_per_bin : int
        Revolutions per bin of the order tracks.
    orders : pandas.DataFrame or None
        The tracks of :func:`runup_orders`; None: computed here.

    Returns
    -------
    dict
        The numbers above by name.
    """
    run = result.run
    if run.speed_profile is None:
        raise ValueError("runup_summary needs a run along a speed profile (speed_profile set)")
    _check.integer("revs_per_bin", revs_per_bin, lo=1)
    table = runup_orders(result, point, (1.0,), revs_per_bin) if orders is None else orders
    amp = table[f"amp_{order_label(1.0)}"].to_numpy()
    k = int(np.argmax(amp))
    episodes = result.contact_episodes()
    rpm = 30 / math.pi
    contact = len(episodes) > 0
    knots = run.speed_profile.knots()
    start, end = knots[0, 1] * rpm, knots[-1, 1] * rpm
    return {
        "label": run.label, "model": run.model_kind, "point": point,
        "direction": "run-up" if end > start else "coast-down",
        "from_rpm": start, "to_rpm": end,
        "rate_rpm_s": float(np.abs(np.diff(knots[:, 1]) / np.diff(knots[:, 0])).max()) * rpm,
        "gap_m": run.gap_m, "status": result.status, "wall_s": result.wall_s,
        "peak_1x_m": float(amp[k]), "peak_rpm": float(table["rpm"].iloc[k]),
        "n_episodes": len(episodes),
        "n_episodes_element_1": int(np.sum(episodes.element == 1)),
        "first_contact_rpm": float(run.speed_at(episodes.t_start.min())) * rpm
        if contact else math.nan,
        "last_contact_rpm": float(run.speed_at(episodes.t_end.max())) * rpm
        if contact else math.nan,
        "max_contact_force_n": float(episodes.peak_normal_force.max()) if contact else 0.0,
    }
