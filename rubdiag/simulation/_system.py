"""Time integration of a linear system with nonlinear elements: the entry point and its result.

``M q'' + C q' + K q = f(t) + Σ_e B_eᵀ p_e(q)`` integrated by Newmark average acceleration
(β = 1/4, γ = 1/2) with Newton on the element forces, solved in a small Schur complement,
and a variable step. The whole time loop runs in one Numba kernel
(:func:`rubdiag._kernels.newmark.newmark_contact`); :func:`simulate_system` checks the
described inputs, fills the kernel's arguments (:mod:`._kernel_args`) with the step
operators of each step size (:mod:`._operators`), calls the kernel (stretch by stretch
along a speed profile: :mod:`._schedule`) and packages its records as a
:class:`~rubdiag.simulation.SystemResult`.

Units are SI throughout: m, s, N, kg, rad/s.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence

import numpy as np

from rubdiag import _check
from rubdiag._kernels import ensure_fresh_cache
from rubdiag._kernels.elements import AUGMENT_FAILED, NEWTON_FAILED, SINGULAR
from rubdiag._kernels.interface import (
    STATUS_DONE,
    STATUS_LOG_FULL,
    STATUS_NO_CONVERGENCE,
    STATUS_NONFINITE,
    Logs,
    Outputs,
    State,
    Work,
)
from rubdiag._kernels.newmark import PROFILE_SECTIONS
from rubdiag._kernels.records import OPEN
from rubdiag.simulation._contacts import Contacts
from rubdiag.simulation._elements import checked_elements, gap_ramps
from rubdiag.simulation._grid import Ticks, TimeGrid, ticks
from rubdiag.simulation._kernel_args import (
    b_matrix,
    coupled,
    element_bundle,
    empty_logs,
    grown_logs,
    kernel_for,
    linear_arrays,
    output_arrays,
    packed_elements,
    run_record,
    start_state,
    with_acceleration,
    work_arrays,
)
from rubdiag.simulation._linear_system import LinearSystem, checked, initial_acceleration
from rubdiag.simulation._loads import kernel_force, load_vector
from rubdiag.simulation._operators import level_operators
from rubdiag.simulation._recording import Recording, checked_records
from rubdiag.simulation._result import EpisodeLog, SimulationDiverged, StatusLog, SystemResult
from rubdiag.simulation._schedule import Schedule, checked_profile
from rubdiag.simulation._solver import Settings, Solver

__all__ = ["simulate_system"]


def simulate_system(system: LinearSystem, elements: Sequence | None, grid: TimeGrid,
                    outputs: Recording | None = None, *, solver: Solver | None = None,
                    gap_ramp: tuple | None = None) -> SystemResult:
    """Integrate a linear system with nonlinear elements from its start state.

    Every value is checked when the run starts (against the system it belongs to); a wrong
    one raises ``ValueError`` naming it and its allowed range.

    Parameters
    ----------
    system : LinearSystem
        ``M q'' + C q' + K q = f(t)``, its start state and the shaft's speed (SI units).
    elements : sequence of element descriptions, or None
        The nonlinear elements, in the order the result numbers them (from 1):
        :class:`~rubdiag.simulation.PointContact`, :class:`~rubdiag.simulation.AnnularContact`
        or another kind (:mod:`rubdiag.simulation._elements` says how to add one). None:
        none, a linear run.
    grid : TimeGrid
        The run's length and steps (s).
    outputs : Recording or None
        What is recorded and reported; None: ``Recording()``, every DOF at every step dt.
    solver : Solver or None
        The numerical settings; None: ``Solver()``.
    gap_ramp : tuple of (float, float or numpy.ndarray), or None
        ``(t_ramp, g_start)``: ramp every element's gap linearly from ``g_start`` (m;
        scalar or one per element, >= its gap) at t = 0 down to its gap at ``t_ramp`` (s),
        so that a linear orbit larger than the gap does not start deep inside the casing
        (elements without a gap ignore it). None: no ramp.

    Returns
    -------
    SystemResult
        The samples, element forces and statistics, event log and outcome of the run.

    Raises
    ------
    SimulationDiverged
        The run could not go on (no convergence at the smallest step, a non-finite state)
        and ``outputs.raise_on_failure`` is set; it carries the partial result.
    """
    ensure_fresh_cache()    # before the first kernel call of this process
    t_start = time.perf_counter()
    outputs = Recording() if outputs is None else outputs
    solver = Solver() if solver is None else solver
    M, C, K, force, q0, v0 = checked(system)
    n = M.shape[0]
    if isinstance(elements, Contacts):      # deprecated: its elements, one by one
        elements = elements.elements()
    elements = checked_elements(elements, n)
    ne = len(elements)
    grid = ticks(grid)
    speed_profile = system.speed_profile
    rot, stretches, G = checked_profile(speed_profile, system.speed_tolerance,
                                        system.gyroscopic, force, n, grid)
    omega = system.omega
    if stretches:
        omega = stretches[0][1]
        C_base, C = C, (C + omega * G).tocsr()
    recovery, record_dofs, sensor_dofs = checked_records(grid, n, outputs, system.recovery)
    settings = Settings.checked(solver, omega)
    if grid.base and not settings.step_error:
        raise _check.out_of_range("dt_max", grid.dt_max,
                                  f"dt = {grid.dt:g} s without a step_error")
    ramps = gap_ramps(gap_ramp, elements)
    kernel = kernel_for(elements)

    # the elements at t = 0, the operators of each step size, the kernel's arrays
    packed = packed_elements(elements, settings.omega, ramps)
    B = b_matrix(packed, n)
    ops = level_operators(M, C, K, B, elements, grid, settings)
    bundle = element_bundle(packed, ops.lev_req, ops.aug_k, elements)
    state, _ = start_state(M, K, q0, v0, B, bundle, packed, kernel.at_rest, settings.omega)
    a0 = initial_acceleration(M, C, K, load_vector(force, speed_profile, 0.0, n), B, state.pc,
                              q0, v0, system.a0)
    with_acceleration(state, a0, B)
    state.prog["level"] = grid.base       # the first step is the base step
    recorded = output_arrays(grid, ne, record_dofs, sensor_dofs, recovery)
    run = run_record(grid, settings)
    linear = linear_arrays(M, C, K, settings.dense)
    run["coupled"] = coupled(linear.m_dense, linear.k_dense)
    run["kinematics"] = any(getattr(type(el).kernel, "KINEMATICS", False) for el in elements)
    k_force = kernel_force(force, rot)
    if not stretches:   # constant speed: the shaft's angle Ω t for the element laws
        k_force.rot[0, 1] = settings.omega
    arrays = (linear, ops.kernel, k_force, bundle, run, state, recorded)
    logs = empty_logs(ne, grid.n_lev, settings.episode_capacity)
    work = work_arrays(n, B.shape[0], ne, outputs.profile)
    t_setup = time.perf_counter() - t_start

    schedule = None
    if stretches:
        def operators(omega_ref):    # the step operators with Ω_ref G, for the next stretch
            C_ref = (C_base + omega_ref * G).tocsr()
            new = level_operators(M, C_ref, K, B, elements, grid, settings)
            return (linear_arrays(M, C_ref, K, settings.dense), new.kernel,
                    element_bundle(packed_elements(elements, omega_ref, ramps), new.lev_req,
                                   new.aug_k, elements))

        schedule = Schedule(stretches, grid, operators)
    code, logs, t_kernel = _integrate(kernel.newmark_contact, arrays, logs, work, grid,
                                      outputs.progress, schedule)
    result = _package(code, grid, state, recorded, logs)
    if recovery is not None:    # the final state in physical DOFs, like the records
        q, v, a = state.q, state.v, state.a
        result = dataclasses.replace(result, q_final=recovery @ q, v_final=recovery @ v,
                                     a_final=recovery @ a)
    if outputs.profile:
        result.extra["profile_cycles"] = dict(zip(PROFILE_SECTIONS, work.prof.tolist(),
                                                  strict=True))
    result.extra.update(
        setup_seconds=t_setup, kernel_seconds=t_kernel, contact_level_required=ops.lev_req,
        augment_pending=int(state.prog[0]["aug_pending"]),
        lu_nnz=[f.nnz for f in ops.lu], lu_ordering=[f.ordering for f in ops.lu],
    )
    if schedule is not None:
        result.extra["speed_stretches"] = schedule.used
    if result.status != 0 and outputs.raise_on_failure:
        raise SimulationDiverged(result.message, result)
    return result


def _integrate(kernel, arrays: tuple, logs: Logs, work: Work, grid: Ticks, progress,
               schedule: Schedule | None = None):
    """Run ``kernel`` (:func:`~rubdiag._kernels.newmark.newmark_contact`) to the end of the run
    (or a failure): in chunks of about 1 % of the run when there is a ``progress`` to call,
    growing a log whenever one is full, and with a speed profile's ``schedule`` stretch by
    stretch (new step operators at each). Returns the kernel's status code, the logs and the
    kernel's wall time (s)."""
    linear, factors, force, elements, run, state, outputs = arrays
    prog = state.prog
    n_chunks = 100 if progress is not None else 1
    chunk = max(np.int64(1), grid.tick_total // n_chunks)
    t_kernel = 0.0
    while True:
        end = min(grid.tick_total, prog[0]["tick"] + chunk)
        if schedule is not None:
            ops = schedule.advance(int(prog[0]["tick"]))
            if ops is not None:
                linear, factors, elements = ops
            end = min(end, schedule.tick_end())
            run["tick_stop"] = schedule.tick_end()
        run["tick_end"] = end
        tk = time.perf_counter()
        code = kernel(linear, factors, force, elements, run, state, outputs, logs, work)
        t_kernel += time.perf_counter() - tk
        if code == STATUS_LOG_FULL:
            logs = grown_logs(logs, prog, elements.el.shape[0])
            continue
        if code != STATUS_DONE:
            return code, logs, t_kernel
        if progress is not None:
            progress(float(prog[0]["tick"]) * grid.tick_dt, grid.duration)
        if prog[0]["tick"] >= grid.tick_total:
            return code, logs, t_kernel


#: the result's arrays from the kernel's records: per sample and element, per sample (the
#: energy ledger), per element (totals and maxima)
_SAMPLE_FIELDS = {"contact_fn": "fn", "contact_ft": "ft", "contact_gap": "gap",
                  "contact_slip": "slip"}
_LEDGER_FIELDS = {"work_external": "w_ext", "work_drive": "w_drive",
                  "dissipated_viscous": "d_visc", "dissipated_friction": "d_fric",
                  "contact_algorithmic": "d_num", "kinetic": "kinetic", "strain": "strain",
                  "contact_elastic": "contact"}
_TOTAL_FIELDS = {"time_in_status": "time", "normal_impulse": "fn_impulse",
                 "tangential_impulse": "ft_impulse", "max_normal_force": "max_fn",
                 "max_tangential_force": "max_ft", "max_penetration": "max_penetration"}


def _package(code, grid: Ticks, state: State, outputs: Outputs, logs: Logs) -> SystemResult:
    """The kernel's arrays as a :class:`SystemResult`, cut to what the run reached."""
    pr = state.prog[0]
    tick = int(pr["tick"])
    t_final = tick * grid.tick_dt
    n_written = tick // int(grid.out_ticks) + 1
    n_sen = tick // int(grid.sen_ticks) + 1 if outputs.sen_dof.size else 0
    episodes, segments = _episode_logs(state, logs, t_final)
    status, message = _status(code, pr, t_final, grid.dt_min)
    nl = int(pr["n_level_changes"])
    sl = slice(0, n_written)
    en = outputs.en[sl]
    el = outputs.el[sl]
    columns = {name: np.ascontiguousarray(records_[field])
               for records_, fields in ((el, _SAMPLE_FIELDS), (en, _LEDGER_FIELDS),
                                        (logs.stats, _TOTAL_FIELDS))
               for name, field in fields.items()}
    return SystemResult(
        t=np.arange(n_written) * grid.output_dt,
        record_dofs=outputs.rec_dof,
        q=outputs.q[sl],
        contact_status=np.ascontiguousarray(el["status"], dtype=np.int8),
        **columns,
        episodes=episodes,
        status_segments=segments,
        max_cone_excess=float(pr["cone_excess"]),
        dt=grid.dt,
        dt_min=grid.tick_dt,
        output_dt=grid.output_dt,
        dt_levels=grid.dt_max / 2.0 ** np.arange(grid.n_lev),
        steps_per_level=logs.lvl_count.copy(),
        level_change_t=logs.lv_t[:nl].copy(),
        level_change_level=logs.lv_l[:nl].copy(),
        n_steps=int(pr["n_accepted"]),
        n_rejected_newton=int(pr["n_rej_newton"]),
        n_rejected_abrupt=int(pr["n_rej_abrupt"]),
        n_abrupt_at_min=int(pr["n_abrupt_at_min"]),
        n_rejected_error=int(pr["n_rej_error"]),
        newton_iterations=int(pr["newton_total"]),
        newton_iterations_max=int(pr["newton_max"]),
        augment_iterations=int(pr["aug_total"]),
        augment_iterations_max=int(pr["aug_max"]),
        t_final=t_final,
        q_final=state.q.copy(),
        v_final=state.v.copy(),
        a_final=state.a.copy(),
        status=status,
        message=message,
        failure_time=float(pr["fail_time"]) if status else float("nan"),
        failure_element=int(pr["fail_element"]) + 1 if status else 0,  # 0: none
        sensor_dofs=outputs.sen_dof,
        sensor_dt=float(grid.tick_dt * int(grid.sen_ticks)),
        sensor_q=outputs.sq[:n_sen],
        sensor_v=outputs.sv[:n_sen],
        sensor_a=outputs.sa[:n_sen],
    )


def _episode_logs(state: State, logs: Logs, t_final: float):
    """The episode and status-segment logs: the ended ones as logged, then those still
    open at ``t_final`` (from each element's track)."""
    pr = state.prog[0]
    track = state.track
    ep = logs.ep[: int(pr["n_episodes"])]
    sg = logs.sg[: int(pr["n_segments"])]
    open_el = np.flatnonzero(track["status"] != OPEN)
    current = track[open_el]

    def ended_then_open(ended, now):
        return np.concatenate([ended, now])

    still_open = np.full(open_el.size, t_final)
    episodes = EpisodeLog(
        element=ended_then_open(ep["element"], open_el) + 1,  # numbered from 1
        t_start=ended_then_open(ep["t_start"], current["ep_start"]),
        t_end=np.concatenate([ep["t_end"], still_open]),
        n_steps=ended_then_open(ep["steps"], current["ep_steps"]),
        peak_normal_force=ended_then_open(ep["peak_fn"], current["ep_peak_fn"]),
        n_slide_entries=ended_then_open(ep["slide_entries"], current["ep_slide_entries"]),
        n_stick_entries=ended_then_open(ep["stick_entries"], current["ep_stick_entries"]),
        slide_time=ended_then_open(ep["slide_time"], current["ep_slide_time"]),
        stick_time=ended_then_open(ep["stick_time"], current["ep_stick_time"]),
        slide_impulse=ended_then_open(ep["slide_impulse"], current["ep_slide_impulse"]),
        stick_impulse=ended_then_open(ep["stick_impulse"], current["ep_stick_impulse"]),
        complete=np.concatenate([np.ones(ep.size, bool), np.zeros(open_el.size, bool)]),
    )
    segments = StatusLog(
        element=ended_then_open(sg["element"], open_el) + 1,
        status=ended_then_open(sg["status"], current["status"]).astype(np.int8),
        t_start=ended_then_open(sg["t_start"], current["seg_start"]),
        t_end=np.concatenate([sg["t_end"], still_open]),
    )
    return episodes, segments


def _status(code, pr, t_final: float, dt_min: float) -> tuple[int, str]:
    """The result's status (0 done, 1 no convergence, 2 non-finite) and its message."""
    status = {STATUS_DONE: 0, STATUS_NO_CONVERGENCE: 1, STATUS_NONFINITE: 2}[code]
    fail_t = float(pr["fail_time"])
    fail_e = int(pr["fail_element"]) + 1
    if status == 0:
        return status, f"Reached t = {t_final:.6g} s in {int(pr['n_accepted'])} steps."
    if status == 1:
        why = {NEWTON_FAILED: "Newton iterations exhausted",
               AUGMENT_FAILED: "augmentation did not reach eps",
               SINGULAR: "singular contact Jacobian"}.get(int(pr["fail_code"]), "unknown")
        return status, (
            f"Contact iteration did not converge ({why}) at t = {fail_t:.9g} s, contact element "
            f"{fail_e}, even at the smallest step {dt_min:.3g} s; results kept up to "
            f"t = {t_final:.9g} s."
        )
    where = f"contact element {fail_e}" if fail_e > 0 else "the structure"
    return status, (f"State became non-finite at t = {fail_t:.9g} s ({where}); results kept "
                    f"up to t = {t_final:.9g} s.")
