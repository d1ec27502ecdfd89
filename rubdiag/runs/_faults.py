"""Each fault that looks like rub beside rub: the runs of ``rubdiag faults`` and their lines.

:func:`fault_runs` builds, on the ``paper-pedestal`` rig (the study's rig with its drive-end
bearing on a pedestal) under gravity, case 1 with each fault alone at the speed where its
reference puts its signature (:data:`FIGURE_FAULTS`), and at each of those speeds a rubbing
and a healthy run. A rub run's gap is its linear blade-tip approach over ``interference``, so
that it rubs alike at any speed. :func:`whirl_runs` does the same for oil whip on the
``paper-journal`` rig (the same rig on plain journal bearings): case 2 above the threshold of
instability, and rub below it. :func:`line_amplitudes` measures the lines a figure marks.
"""

from __future__ import annotations

import math

import numpy as np

from rubdiag import _check

__all__ = ["FIGURE_FAULTS", "fault_runs", "line_amplitudes", "whirl_runs"]

#: fault -> (speed in rpm, the shaft direction its figure shows): a crack's 2× resonates at
#: half the first critical speed (1500 rpm), and so does a coupling's 2× force; a loose
#: pedestal lifts most near the critical, where the bearing force peaks. The pedestal is loose
#: across gravity (along z), where its subharmonics show.
FIGURE_FAULTS = {"crack": (750.0, "y"), "misalignment": (750.0, "y"),
                 "looseness": (1450.0, "z")}


def fault_runs(*, speed_rpm: float | None = None, interference: float = 1.3,
               crack_depth: float = 0.4, misalignment_angle_mrad: float = 10.0,
               loose_preload_n: float = 5.0, duration_s: float = 2.0) -> dict:
    """The runs by name: each fault of :data:`FIGURE_FAULTS` (a Gasch crack of depth ratio
    ``crack_depth`` in shaft element 10; a coupling at node 3 with angular misalignment
    ``misalignment_angle_mrad``, 20 N·m through a 5-cm spacer; bearing 0's pedestal loose
    along z with ``loose_preload_n`` N left on its seat), ``"rub <rpm>"`` and
    ``"none <rpm>"`` at each speed they run at (``speed_rpm``: one speed for all). Every run
    lasts ``duration_s`` (s), its last half analysed.

    Parameters
    ----------
    speed_rpm : float or None
        One speed for every run (rpm); None: each fault's own speed in :data:`FIGURE_FAULTS`.
    interference : float
        The rub runs' linear approach over their gap (> 0; above 1: the blades rub).
    crack_depth : float
        The crack's depth over the shaft diameter.
    misalignment_angle_mrad : float
        The coupling's angular misalignment (mrad).
    loose_preload_n : float
        The loose pedestal's preload on its seat (N).
    duration_s : float
        Length of every run (s).

    Returns
    -------
    dict of str to Run
        The runs by name.
    """
    from rubdiag.model import preset_rig
    from rubdiag.simulation import Crack, Faults, Looseness, Misalignment, Run, StaticLoad
    from rubdiag.simulation._rig_cache import damped_model
    from rubdiag.simulation._rig_system import rig_system

    interference = _check.number("interference", interference, lo=0.0, hi=100.0,
                                 lo_open=True)
    rig = preset_rig("paper-pedestal")

    def run(rpm, gap_mm=None, **options):
        return Run.paper_case(1, gap_mm, speed_rpm=rpm, duration_s=duration_s,
                              discard_s=0.5 * duration_s, rig=rig,
                              static_load=StaticLoad(direction="y", gravity_m_s2=-9.81),
                              **options)

    faults = {
        "crack": Crack(element=10, depth_ratio=crack_depth, law="gasch"),
        "misalignment": Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                                     angle_rad=misalignment_angle_mrad * 1e-3),
        "looseness": Looseness(bearing=0, preload_n=loose_preload_n, direction="z"),
    }
    speeds = {name: FIGURE_FAULTS[name][0] if speed_rpm is None else speed_rpm
              for name in FIGURE_FAULTS}
    out = {name: run(speeds[name], faults=Faults(**{name: fault}))
           for name, fault in faults.items()}
    for rpm in sorted(set(speeds.values())):
        probe = run(rpm, 50.0, gap_ramp_s=0.0)      # the casing out of reach: linear
        approach = rig_system(probe, damped_model(rig)).approach
        out[f"rub {rpm:g}"] = run(rpm, 1e3 * approach / interference,
                                  gap_ramp_s=0.25 * duration_s)
        out[f"none {rpm:g}"] = run(rpm)
    return out


def whirl_runs(*, interference: float = 1.3, above: float = 1.06, below: float = 0.95,
               duration_s: float = 3.0) -> tuple[dict, float]:
    """Oil whip beside rub on ``paper-journal`` under gravity, case 2 (its threshold lies in
    case 2's range): ``{"whirl": the rotor at ``above`` times the threshold, "rub": a rubbing
    run at ``below`` times it}`` (the rub gap its linear approach over ``interference``),
    each ``duration_s`` long (s; the last half analysed: the whip needs about a second to
    grow), and the order at which the whip's reference puts its line: the first critical
    speed of the rig's critical speed map over the whip run's speed (whip locks at the first
    natural frequency).

    Parameters
    ----------
    interference : float
        The rub run's linear approach over its gap (> 0).
    above : float
        The whip run's speed over the threshold of instability.
    below : float
        The rub run's speed over the threshold of instability.
    duration_s : float
        Length of each run (s).

    Returns
    -------
    runs : dict of str to Run
        ``"whirl"`` and ``"rub"``.
    order : float
        The order of the whip's line in the whip run.
    """
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds, whirl_threshold, with_rayleigh
    from rubdiag.model import preset_rig
    from rubdiag.simulation import Run, StaticLoad
    from rubdiag.simulation._rig_cache import damped_model
    from rubdiag.simulation._rig_system import rig_system

    interference = _check.number("interference", interference, lo=0.0, hi=100.0,
                                 lo_open=True)
    rig = preset_rig("paper-journal")
    model = with_rayleigh(assemble(rig))
    first = critical_speeds(model, n=1)[0]
    threshold = whirl_threshold(model).speed_rad_s
    gravity = StaticLoad(direction="y", gravity_m_s2=-9.81)

    def run(ratio, gap_mm=None, **options):
        return Run.paper_case(2, gap_mm, speed_rpm=ratio * threshold * 30.0 / math.pi,
                              duration_s=duration_s, discard_s=0.5 * duration_s, rig=rig,
                              static_load=gravity, **options)

    probe = run(below, 50.0, gap_ramp_s=0.0)
    approach = rig_system(probe, damped_model(rig)).approach
    runs = {"whirl": run(above),
            "rub": run(below, 1e3 * approach / interference, gap_ramp_s=0.1 * duration_s)}
    return runs, float(first / runs["whirl"].speed_rad_s)


def line_amplitudes(result, point: str, orders) -> dict[str, float]:
    """The amplitude (m) of each order's line of ``point`` (e.g. ``"shaft 11 y"``) over the
    result's analysis window: a lock-in over the window's whole multiple of 6 revolutions
    (⅓× and ½× fit in it whole; fewer than 6 revolutions: all of them). Keys ``"2x"``,
    ``"0.333x"`` (three significant digits).

    Parameters
    ----------
    result : SimulationResult
        A simulated run.
    point : str
        A recorded displacement, e.g. ``"shaft 11 y"``.
    orders : sequence of float
        The orders (multiples of the running speed).

    Returns
    -------
    dict of str to float
        Amplitude of each order's line (m).
    """
    t = result.t[result.window]
    x = result.displacement(point, True)
    omega = result.run.speed_rad_s
    revs = math.floor((t[-1] - t[0]) * omega / (2 * math.pi))
    revs = revs - revs % 6 if revs >= 6 else revs
    keep = t <= t[0] + revs * 2 * math.pi / omega
    x = x[keep] - x[keep].mean()
    return {f"{k:.3g}x": float(2 * abs(np.mean(x * np.exp(-1j * k * omega * t[keep]))))
            for k in orders}
