"""Simulate a rig: from a :class:`~rubdiag.simulation.Run` to a ``SimulationResult``.

``simulate(run)`` assembles the rig (or finds it assembled: :mod:`rubdiag.simulation._rig_cache`),
starts from the linear harmonic steady state at the running speed (so that the transient is
short), ramps the gap down to g0 (a linear orbit larger than the gap must not start deep
inside the casing) and integrates with :func:`~rubdiag.simulation.simulate_system`.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from rubdiag import _check
from rubdiag._blas import one_thread
from rubdiag.simulation._grid import TimeGrid
from rubdiag.simulation._idle_contacts import report_open
from rubdiag.simulation._linear_system import LinearSystem
from rubdiag.simulation._recording import Recording
from rubdiag.simulation._result import SimulationDiverged
from rubdiag.simulation._rig_cache import damped_model
from rubdiag.simulation._rig_system import rig_system
from rubdiag.simulation._run import SPEED_TOLERANCE, Run
from rubdiag.simulation._sensors import sensor_dofs
from rubdiag.simulation._simulation_result import SimulationResult
from rubdiag.simulation._solver import Solver
from rubdiag.simulation._system import simulate_system

__all__ = ["response_points", "simulate"]

RAMP_MARGIN = 1.1    # the ramp starts 10 % above the largest linear approach


def response_points(rig) -> tuple[str, ...]:
    """Recorded DOFs: both directions of every disc node, and with blade contacts the casing
    node of contact element 1 and the tip of its blade (the study's nodes 11, 1844, 39), and
    both directions of every bearing pedestal, then of every journal bearing's node (after
    the others: a rig without pedestals or journal bearings records what it did before they
    existed).

    Parameters
    ----------
    rig : Rig
        The rig.

    Returns
    -------
    tuple of str
        DOF names such as ``"shaft 11 y"``.
    """
    points = [f"shaft {d.node} {x}" for d in rig.discs for x in "yz"]
    if rig.contact is not None:
        casing = rig.contact_casing_node(1)
        tip = f"blade {rig.contact.blades[0]}.{rig.blades.n_elements}"
        points += [f"casing {casing} {x}" for x in "yz"] + [f"{tip} {x}" for x in "yz"]
    points += [f"pedestal {k} {x}" for k, b in enumerate(rig.bearings)
               if b.pedestal is not None for x in "yz"]
    points += [f"shaft {b.node} {x}" for b in rig.bearings if b.journal is not None
               for x in "yz" if f"shaft {b.node} {x}" not in points]
    return tuple(points)


def _dof(model, label: str) -> int:
    node, direction = label.rsplit(" ", 1)
    return model.dofs.index(node, direction)


def simulate(run: Run, progress: Callable[[float, float], None] | None = None,
             raise_on_failure: bool = True) -> SimulationResult:
    """Integrate ``run`` and return its :class:`SimulationResult`.

    ``progress(t, duration)`` is called every few thousand steps. A run that cannot go on
    (no convergence at ``dt_min``, a non-finite state) raises
    :class:`~rubdiag.simulation._result.SimulationDiverged` whose ``result`` is the
    :class:`SimulationResult` up to the failure (or, with ``raise_on_failure=False``, that
    result is returned with ``status != 0``).

    The run's dense linear algebra runs on one BLAS thread (:func:`rubdiag._blas.one_thread`:
    threads spin against other work on busy cores, and their sums would make a reduced
    run's bits depend on the core count); what depends on the rig alone is cached
    (:mod:`rubdiag.simulation._rig_cache`, :func:`rubdiag.reduce.reduced_model`).

    Parameters
    ----------
    run : Run
        What to simulate.
    progress : callable or None
        ``progress(t, duration)`` (s, s), called every few thousand steps.
    raise_on_failure : bool
        Raise :class:`SimulationDiverged` when the run fails (False: return the partial result).

    Returns
    -------
    SimulationResult
        The run's waveforms, contact forces and status, event log and outcome.
    """
    if not isinstance(run, Run):
        raise _check.wrong_type("run", run, "a Run, e.g. Run.paper_case(1, 2.0)")
    with one_thread():
        return _simulate(run, progress, raise_on_failure)


def _simulate(run: Run, progress, raise_on_failure: bool) -> SimulationResult:
    start_time = time.perf_counter()
    model = damped_model(run.rig)
    speed = run.speed_rad_s
    rs = rig_system(run, model)
    gap_ramp = None
    if rs.contacts and run.gap_ramp_s > 0:
        g0 = np.array([c.gap for c in rs.contacts])
        # the approach is over each gap's static shift (zero unless gaps are "loaded")
        g_start = np.maximum(g0, rs.gap_shift + RAMP_MARGIN * rs.approach)
        # the fault elements and films have no gap: their entries are not read
        g_start = np.r_[g_start, np.full(len(rs.fault_elements), np.nan)]
        gap_ramp = (run.gap_ramp_s, g_start if rs.fault_elements else g_start[: len(g0)])
    elements = rs.contacts + rs.fault_elements
    points = response_points(run.rig)
    record = [_dof(model, p) for p in points]
    idle = rs.idle
    if idle:       # their tips and casing nodes too, for their gaps and slips
        record += [d for c in idle for d in c.dof_a] + [d for c in idle for d in c.dof_b]
    info = {"linear_approach_m": rs.approach, "model": rs.model, **rs.extra}
    try:
        profile = run.speed_profile
        varying = {} if profile is None else {
            "gyroscopic": rs.G, "speed_profile": profile, "speed_tolerance": SPEED_TOLERANCE}
        system = simulate_system(
            LinearSystem(M=rs.M, C=rs.C if profile else rs.damping(speed), K=rs.K,
                         force=rs.force, q0=rs.x0, v0=rs.v0, omega=speed,
                         recovery=rs.recovery, **varying),
            elements,
            TimeGrid(duration=run.duration_s, dt=run.dt_s, dt_min=run.dt_min_s,
                     fixed_step=run.fixed_step, output_dt=run.output_dt_s,
                     dt_max=run.dt_max_s),
            Recording(record_dofs=record, sensor_dofs=sensor_dofs(run), progress=progress),
            solver=Solver(linear_solver=rs.linear_solver, step_error=run.step_error),
            gap_ramp=gap_ramp)
        if idle:
            system = report_open(system, idle, len(points))
    except SimulationDiverged as exc:
        failed = exc.result
        if idle and "idle_contacts" not in failed.extra:
            failed = report_open(failed, idle, len(points), check=False)
        failed.extra.update(info)
        partial = SimulationResult(run, points, failed, time.perf_counter() - start_time)
        if raise_on_failure:
            raise SimulationDiverged(str(exc), partial) from None
        return partial
    system.extra.update(info)
    return SimulationResult(run, points, system, time.perf_counter() - start_time)
