"""The whole Newmark / Newton / contact time loop in one Numba kernel.

Newmark in incremental form; by default average acceleration (beta = 1/4, gamma = 1/2). With
equilibrium at step n (``M a_n + C v_n + K q_n = f_n + B^T p_n``) the increment ``Δq`` of a
step of size h solves ::

    K_eff Δq = Δf + B^T Δp + M (1/(β h) v_n + 1/(2β) a_n) + C (γ/β v_n - h (1 - γ/(2β)) a_n),
    K_eff = K + γ/(β h) C + 1/(β h^2) M,

then ``a_{n+1} = Δq/(β h^2) - v_n/(β h) - (1/(2β) - 1) a_n``,
``v_{n+1} = v_n + h ((1 - γ) a_n + γ a_{n+1})``. For average acceleration, equilibrium at n
turns the right-hand side into ::

    K_eff Δq = f_{n+1} + f_n + B^T (p_{n+1} + p_n) + 4/h M v_n - 2 K q_n,

and ``M v``, ``K q`` are tracked (``M v_{n+1} = 2/h M Δq - M v_n``, ``K q_{n+1} = K q_n +
K Δq``) from one pass over the union pattern of M and K on Δq; ``C Δq`` follows from
``K_eff Δq = rhs`` and gives the viscous dissipation ``Δqᵀ C Δq / h`` of the step. A step thus
costs one sparse product pass, one LU solve and the contact columns of ``S = K_eff^-1 B^T``;
the kinetic and strain energies at the samples are dot products. (γ ≠ 1/2 uses products with
M and C for the right-hand side and recomputes M v: three more products.) A dense system (a
reduced model) replaces the LU solve by a product with ``K_eff^-1`` and the pass over the
pattern by dense products with M and K, which skip what is zero in a modal tail
(``run.coupled``, :func:`~rubdiag._kernels.products.mk_dense`).

Step sizes are levels ``h_k = dt / 2^k`` (k = 0..n_lev-1). Time is an integer tick count
(tick = dt / 2^(n_lev-1)), so sample times and level changes are exact. A step at level k
starts on a multiple of its own tick length; growing to k-1 requires the tick to be aligned
to the larger step. A trial step is rejected and retried one level down when (i) the contact
iteration fails (Newton or augmentation cap, singular Jacobian), (ii) an element that was
open at the step start ends it deeper than ``gap_jump``, or (it jumps straight to that
level) (iii) an element closed at the start or end of the step needs a smaller step by its
step requirement (``lev_req``; for contacts the contact-stiffness criterion). At the
smallest level (i) stops the run with ``STATUS_NO_CONVERGENCE`` and (ii) is accepted and
counted. After ``grow_after`` accepted steps at a level the step doubles (when aligned, and
not below any closed element's ``lev_req``). In fixed-step mode nothing is rejected: (i)
stops the run.

Long steps. With ``run.base_level`` > 0 the levels above it are longer than the base step
dt (``dt0 = 2^base_level dt``). They are taken only where every element that can close on
impact (``impact``) is open: such an element's ``lev_req`` is at least the base level, so a
closing rejects a long step back to the base step, and so does the gap predictor (an open
element whose gap is within ``GAP_MARGIN`` gap changes of closing). Their size follows
Zienkiewicz and Xie's local error estimate against ``run.step_error`` times the largest
recorded displacement: a long step above it is retried shorter, and the step doubles past
the base step only when the estimate is at most ``GROW_ERROR`` of it and the elements keep
twice the margin (:mod:`rubdiag._kernels.step_control`). A long step starts aligned to its
length and ends by the next recorded sample and ``run.tick_stop``, so recorded samples stay
exact step ends; the sensor stream keeps the base step's samples, filled in within a long
step by cubic Hermite interpolation (:mod:`rubdiag._kernels.recording`).

The kernel, part by part. :func:`newmark_contact` is the step controller: the loop, the
order of the parts, rejections and level changes. The parts are modules of their own:

* a trial step: the load's factors at the step's ends (:mod:`~rubdiag._kernels.load`), the
  right-hand side (:mod:`~rubdiag._kernels.increment`), the linear solve (``lu_solve`` of
  :mod:`~rubdiag._kernels.sparse_lu`, or a product with the dense inverse,
  :mod:`~rubdiag._kernels.products`), :func:`_clock` (the step's times and the shaft's
  angle for the element laws), :func:`_element_inputs` and the elements' Newton solve in the
  Schur complement (:mod:`~rubdiag._kernels.element_solve`, each element's law by its kind:
  the seam of :mod:`~rubdiag._kernels.elements`), and the level check
  (:mod:`~rubdiag._kernels.step_control`);
* the accept: the increment ``dq += S Δp`` and the new state
  (:mod:`~rubdiag._kernels.increment`), M dq, K dq and the viscous dissipation in one pass
  (:mod:`~rubdiag._kernels.products`);
* the books: the energy ledger, episodes and status segments, each element's totals and
  new state (:mod:`~rubdiag._kernels.ledger`);
* the clock and the step's growth (:mod:`~rubdiag._kernels.step_control`), the samples at
  the sample ticks (:mod:`~rubdiag._kernels.recording`).

The parts take the plain arrays they use, not the bundles, and are written so that Numba
can drop the reference counting of their array arguments, which otherwise costs two atomic
operations per array per call (the parts that took whole bundles were 0.3-0.4 µs per step
slower): no array used in one branch of an ``if`` only (the controller picks
``rhs_average`` or ``rhs_general``, dense or sparse products), and no ``ZeroDivisionError``
paths (``error_model="numpy"``; no divisor there can be 0: h, β, γ, k_N, k_T > 0 and the
tick counts are checked by the caller), nor calls that could return one. What is left is
the call itself, about 15 ns with 20 arrays; ``increment`` and ``new_state`` are inlined
into the loop (``inline="always"``: the update section was 0.1-0.2 µs per step slower as
calls). Inlining the others brings reference counts back into the controller
(``add_columns`` is inlined into its callers for the same reason, and ``recover`` into the
records: as a call with a branch over its arrays it brought 12 increfs into
``record_sensors``). ``tests/kernels/test_reference_counts.py`` compiles without the disk
cache and counts the calls to ``NRT_incref`` in each part's IR: none in the per-step parts,
a bounded number in the controller (``record`` and the failure paths have some).

Everything is preallocated by the caller (:mod:`rubdiag.simulation._kernel_args`; the bundles
are :mod:`rubdiag._kernels.interface`); the kernel can be re-entered: all state lives in the
arrays passed in. The run's parameters, the loop's counters and clock, each element's
record and the logs are record arrays whose fields are named in
:mod:`rubdiag._kernels.records` (``run[0].dt``, ``progress[0].tick`` …). Without Numba
(``NUMBA_DISABLE_JIT=1``) the same source runs as Python on the same arrays, to the same
bits (``make test-nojit``).
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels.clock import cycles
from rubdiag._kernels.element_solve import solve_elements
from rubdiag._kernels.elements import AUGMENT_PENDING, NONFINITE, local_coords
from rubdiag._kernels.increment import (
    increment,
    load_increment,
    new_state,
    rhs_average,
    rhs_general,
)
from rubdiag._kernels.interface import (
    DOF_DQ,
    DOF_K_DQ,
    DOF_M_DQ,
    DOF_RHS,
    DOF_X,
    STATUS_DONE,
    STATUS_LOG_FULL,
    STATUS_NO_CONVERGENCE,
    STATUS_NONFINITE,
)
from rubdiag._kernels.ledger import commit_elements, energy_ledger, log_episodes, logs_full
from rubdiag._kernels.load import load_factors, shaft_at
from rubdiag._kernels.products import dissipation, matvec_t, mk_dense, mk_products
from rubdiag._kernels.recording import interpolate_sensors, record, record_sensors
from rubdiag._kernels.records import D_LIN, D_NEW, P_NEW, V2, X_N
from rubdiag._kernels.sparse_lu import csr_matvec, lu_solve
from rubdiag._kernels.step_control import (
    advance,
    change_level,
    error_level,
    error_wanted,
    level_needed,
    local_error,
    may_lengthen,
    reject,
    step_level,
)
from rubdiag._numba import njit

__all__ = ["PROFILE_SECTIONS", "P_SIZE", "newmark_contact"]

# CPU cycles per section of a step, in a profiled run (``Work.prof`` (P_SIZE) int64)
P_RHS = 0  # right-hand side of the increment equation (force, M v, K q, Bᵀp)
P_SOLVE = 1  # the linear solve with K_eff
P_CONTACT = 2  # element predictor, the element Newton solve, the level check
P_UPDATE = 3  # accept: dq += S Δp, M dq and K dq, the new state
P_LEDGER = 4  # energy ledger, episodes and totals, committing the elements' state
P_OUTPUT = 5  # step-size control and the recorded samples
P_SIZE = 6
PROFILE_SECTIONS = ("rhs", "solve", "contact", "update", "ledger", "output")


@njit(error_model="numpy")
def _clock(run, progress, speed_knots, t_n, t_1, h):
    """The trial step's clock in ``progress`` for the element laws: its ends and length, the
    shaft's speed and angle at its end, and the Newmark velocity relation
    ``v_1 = cv Δq + cvv v_n + cva a_n``.

    Parameters
    ----------
    run : ndarray (1) records.RUN
        The run's parameters (β, γ, whether a kind reads the rates).
    progress : ndarray (1) records.PROGRESS
        Its clock is set.
    speed_knots : ndarray (n_knots, 3)
        The shaft's speed profile, rows (t (s), Ω (rad/s), φ (rad)).
    t_n, t_1 : float
        The step's ends (s).
    h : float
        The step (s).
    """
    beta = run[0].beta
    gamma = run[0].gamma
    kinematics = run[0].kinematics != 0
    progress[0].t_n = t_n
    progress[0].t_1 = t_1
    progress[0].h = h
    w, _, phi = shaft_at(speed_knots, t_1)  # (the search is over a few knots, and always done)
    progress[0].omega = w
    progress[0].phi = phi
    if kinematics:      # the divisions only for the kinds that read the rates
        progress[0].cv = gamma / (beta * h)
        progress[0].cvv = 1.0 - gamma / beta
        progress[0].cva = h * (1.0 - gamma / (2.0 * beta))


@njit(error_model="numpy")
def _element_inputs(dq, local_state, elements, row_dofs, transforms, local_work, trial):
    """What the element solve starts from: the predictor's local displacements ``d_lin =
    B (q + dq_lin) = d_n + B dq_lin``, and the multipliers.

    Parameters
    ----------
    dq : ndarray (n)
        The linear predictor's increment (m).
    local_state : ndarray (3, m)
        The local displacements at the step's start (row ``X_N``, m).
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates.
    local_work : ndarray (WC_SIZE, m)
        Its row ``D_LIN`` is set (m).
    trial : ndarray (n_e) records.TRIAL
        Each element's multiplier is set to 0.
    """
    local_coords(elements, elements.shape[0], row_dofs, transforms, dq, local_work, D_LIN)
    for i in range(local_work.shape[1]):
        local_work[D_LIN, i] += local_state[X_N, i]
    for e in range(elements.shape[0]):
        # multipliers are iterated from 0 within each step (no carry-over: a multiplier
        # kept while the penetration shrinks pushes the contact open impulsively)
        trial[e].lam = 0.0


@njit
def _count_iterations(code, newton_iterations, augment_updates, progress):
    """Count an element solve's iterations in ``progress``; its code, with a step accepted
    before the multipliers reached the band (``AUGMENT_PENDING``, counted) as converged
    (0)."""
    pr = progress[0]
    pr.newton_total += newton_iterations
    pr.aug_total += augment_updates
    pending = code == AUGMENT_PENDING
    pr.aug_pending += 1 if pending else 0
    return 0 if pending else code


@njit
def _element_failure(progress, row_dofs, code, worst, t):
    """Note a failed element solve in ``progress``: its code, the element of its worst row
    (``row_dofs[worst, 2]``), the time t (s). Returns the kernel's status."""
    pr = progress[0]
    pr.fail_element = row_dofs[worst, 2] if worst >= 0 else -1
    pr.fail_code = code
    pr.fail_time = t
    return STATUS_NONFINITE if code == NONFINITE else STATUS_NO_CONVERGENCE


@njit
def _nonfinite_increment(progress, elements, local_work, t):
    """Note a non-finite increment in ``progress``: the first element with non-finite local
    displacements (``local_work[D_NEW]``), if any, and the time t (s). Returns the kernel's
    status."""
    pr = progress[0]
    pr.fail_element = -1
    for e in range(elements.shape[0]):
        finite = True
        for r in range(elements[e].row, elements[e].row + elements[e].n):
            finite = finite and np.isfinite(local_work[D_NEW, r])
        if not finite:
            pr.fail_element = e
            break
    pr.fail_time = t
    return STATUS_NONFINITE


@njit
def _lap(profile_cycles, section, c0):
    """Add the cycles since ``c0`` to ``profile_cycles[section]``; the new start. Without
    profiling (``profile_cycles`` empty) nothing is read."""
    if profile_cycles.shape[0] == 0:
        return c0
    c1 = cycles()
    profile_cycles[section] += c1 - c0
    return c1


# Complexity (C901) allowed: the step's parts are calls already; what branches here is the
# order of a step (reject, stop or accept, dense or sparse), and each part split off costs
# its arrays' reference counts per step (module docstring)
@njit
def newmark_contact(linear, factors, force, element_arrays, run, state, outputs, logs,  # noqa: C901
                    work):
    """Run the time loop from ``progress.tick`` to ``run.tick_end``.

    The step controller: each pass tries one step at the current level, then rejects it (a
    level down), stops the run or accepts it (module docstring). The bundles are unpacked
    once.

    Parameters
    ----------
    linear : Linear
        The linear system (:data:`~rubdiag._kernels.interface.Linear`).
    factors : Factors
        The step operators per level (:data:`~rubdiag._kernels.interface.Factors`).
    force : Force
        The external load (:data:`~rubdiag._kernels.interface.Force`).
    element_arrays : Elements
        The nonlinear elements (:data:`~rubdiag._kernels.interface.Elements`).
    run : ndarray (1) records.RUN
        The run's parameters.
    state : State
        The state, carried from call to call (:data:`~rubdiag._kernels.interface.State`).
    outputs : Outputs
        The recorded samples (:data:`~rubdiag._kernels.interface.Outputs`).
    logs : Logs
        The event logs and totals (:data:`~rubdiag._kernels.interface.Logs`).
    work : Work
        Work arrays (:data:`~rubdiag._kernels.interface.Work`).

    Returns
    -------
    int
        A ``STATUS_*`` code; ``STATUS_LOG_FULL``: a log could overflow (the caller grows
        it and calls again).
    """
    m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, mk_ptr, mk_idx, mk_m, mk_k, m_dense, k_dense = linear
    (l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c, responses,
     flexibility, inverse_t) = factors
    (load_dofs, load_re, load_im, load_groups, group_laws, group_tables, speed_knots,
     group_factors) = force
    elements, row_dofs, transforms, parameters, augment_stiffness = element_arrays
    (q, v, a, momentum, elastic_force, local_force, local_state, element_state, track,
     progress) = state
    (record_dofs, recorded_q, recorded_elements, recorded_energy, sensor_dofs, sensor_q,
     sensor_v, sensor_a, record_map, sensor_map) = outputs
    episodes, segments, change_times, change_levels, stats, steps_per_level = logs
    dof_work, local_work, newton_matrix, jacobian, index_work, trial, profile_cycles = work
    rp = run[0]
    pr = progress[0]
    n_elements = elements.shape[0]
    dt0, beta, gamma = rp.dt, rp.beta, rp.gamma
    base_level, tol, grow_after = rp.base_level, rp.step_error, rp.grow_after
    trapezoid = beta == 0.25 and gamma == 0.5
    finest, fixed = rp.n_lev - 1, rp.fixed != 0
    out_ticks, sen_ticks = rp.out_ticks, rp.sen_ticks
    tick_dt = dt0 / (1 << finest)
    dense = inverse_t.shape[1] > 0
    sensing = sensor_dofs.shape[0] > 0
    x, rhs, dq = dof_work[DOF_X], dof_work[DOF_RHS], dof_work[DOF_DQ]
    k_dq, m_dq = dof_work[DOF_K_DQ], dof_work[DOF_M_DQ]
    p_new, dp = local_work[P_NEW], local_work[V2]

    tick = pr.tick
    if pr.sample0_done == 0:
        if tick % out_ticks == 0:
            record(tick // out_ticks, q, v, momentum, elastic_force, record_dofs, record_map,
                   track, progress, recorded_q, recorded_elements, recorded_energy)
        if sensing and tick % sen_ticks == 0:
            record_sensors(tick // sen_ticks, q, v, a, sensor_dofs, sensor_map, sensor_q,
                           sensor_v, sensor_a)
        pr.sample0_done = 1

    while tick < rp.tick_end:
        if logs_full(n_elements, progress, episodes, segments, change_times):
            return STATUS_LOG_FULL
        c0 = cycles() if profile_cycles.shape[0] else 0
        level = step_level(pr.level, base_level, finest, tick, out_ticks, rp.tick_stop)
        n_ticks = np.int64(1) << (finest - level)
        h = dt0 / (1 << level)
        t_n = tick * tick_dt
        t_1 = (tick + n_ticks) * tick_dt
        # the load's factors at both ends
        load_factors(group_laws, group_tables, speed_knots, t_n, t_1, group_factors)

        # ---- a trial step: the linear predictor, then the element solve
        if trapezoid:
            rhs_average(h, momentum, elastic_force, local_force, load_dofs, load_re, load_im,
                        load_groups, group_factors, elements, row_dofs, transforms, rhs)
        else:
            rhs_general(run, h, v, a, m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, x, m_dq, rhs)
            load_increment(load_dofs, load_re, load_im, load_groups, group_factors, rhs)
        c0 = _lap(profile_cycles, P_RHS, c0)
        if dense:
            matvec_t(inverse_t[level], rhs, dq)
        else:
            lu_solve(l_ptr[level], l_idx[level], l_val[level], l_dinv[level], u_ptr[level],
                     u_idx[level], u_val[level], u_dinv[level], perm_r[level], perm_c[level],
                     rhs, dq, k_dq)
        c0 = _lap(profile_cycles, P_SOLVE, c0)
        _clock(run, progress, speed_knots, t_n, t_1, h)
        _element_inputs(dq, local_state, elements, row_dofs, transforms, local_work, trial)
        code, newton_iterations, augment_updates, worst = solve_elements(
            flexibility[level], local_work, local_force, local_state, elements, parameters,
            augment_stiffness[level], element_state, track, trial, run, progress, jacobian,
            index_work, newton_matrix)
        code = _count_iterations(code, newton_iterations, augment_updates, progress)
        if code == NONFINITE or (code != 0 and (fixed or level == finest)):
            return _element_failure(progress, row_dofs, code, worst, t_1)
        # the trial's increment (dq += S Δp) and, where wanted, its local error estimate
        increment(level, responses, local_force, p_new, elements, row_dofs, transforms, dp,
                  dq, rhs)
        tol_m = tol * pr.scale
        err = -1.0
        if error_wanted(code, tol, level, base_level, pr.quiet + 1 >= grow_after, elements,
                        track):
            err = local_error(beta, h, dq, v, a, x, record_dofs, record_map, sensor_dofs,
                              sensor_map, elements, row_dofs, transforms, local_work)
        # rejected: the element solve failed (one level down), converged to an abrupt
        # closing or too stiff a contact for this step, or a long step's error is too large
        # (down to the level needed)
        need = level + 1 if code != 0 else level_needed(run, level, elements, track, trial)
        need, by_error = error_level(need, level, base_level, err, tol_m)
        if need > level and not fixed:
            if level < finest:
                reject(progress, change_times, change_levels, t_n, min(need, finest),
                       code != 0, by_error)
                _lap(profile_cycles, P_CONTACT, c0)
                continue
            pr.n_abrupt_at_min += 1  # abrupt at the smallest step: accepted, counted
        c0 = _lap(profile_cycles, P_CONTACT, c0)

        # ---- accept: the new state, the books
        pr.newton_max = max(pr.newton_max, newton_iterations)
        pr.aug_max = max(pr.aug_max, augment_updates)
        lengthen = may_lengthen(err, tol_m, elements, track, trial)
        if dense:   # M and K are symmetric: row j is column j
            mk_dense(rp.coupled, m_dense, k_dense, dq, m_dq, k_dq)
            dvisc = dissipation(beta, gamma, h, dq, rhs, m_dq, k_dq)
        else:
            dvisc = mk_products(beta, gamma, h, mk_ptr, mk_idx, mk_m, mk_k, dq, rhs, m_dq,
                                k_dq)
        if not np.isfinite(dvisc):  # any non-finite dq shows here; the state is untouched
            return _nonfinite_increment(progress, elements, local_work, t_1)
        new_state(beta, gamma, h, dq, m_dq, k_dq, q, v, a, momentum, elastic_force)
        if not trapezoid:
            # M v_{n+1} also has a term h (1 - γ/(2β)) M a_n that is not tracked: recompute
            csr_matvec(m_ptr, m_idx, m_val, v, momentum)
        c0 = _lap(profile_cycles, P_UPDATE, c0)
        energy_ledger(progress, dvisc, dq, load_dofs, load_re, load_im, load_groups,
                      group_factors, local_force, elements, row_dofs, transforms, local_work,
                      trial)
        log_episodes(progress, trial, track, episodes, segments)
        commit_elements(run, progress, trial, element_state, track, stats, local_work,
                        local_force, elements, row_dofs, transforms, q, v, a, local_state)
        c0 = _lap(profile_cycles, P_LEDGER, c0)

        # ---- the next step's size, the samples
        tick, grow = advance(run, progress, level, n_ticks, elements, track, steps_per_level,
                             lengthen)
        if grow:
            change_level(progress, change_times, change_levels, t_1, level - 1)
        if tick % out_ticks == 0:
            record(tick // out_ticks, q, v, momentum, elastic_force, record_dofs, record_map,
                   track, progress, recorded_q, recorded_elements, recorded_energy)
        if sensing and tick % sen_ticks == 0:
            i1 = tick // sen_ticks
            record_sensors(i1, q, v, a, sensor_dofs, sensor_map, sensor_q, sensor_v, sensor_a)
            # a long step: the base step's samples within it (none for the others)
            interpolate_sensors(i1 - n_ticks // sen_ticks, i1, h, sensor_q, sensor_v,
                                sensor_a)
        _lap(profile_cycles, P_OUTPUT, c0)
    return STATUS_DONE
