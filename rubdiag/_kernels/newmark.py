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
(``run.coupled``, :func:`_mk_dense`).

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

Long steps. With ``run.base`` > 0 the levels above it (``lev < base``) are longer than the
base step dt (level ``base``; ``dt0 = 2^base dt``). They are taken only where every element
that can close on impact (``impact``) is open: such an element's ``lev_req`` is at least
``base``, so a closing rejects a long step back to the base step, and so does the gap
predictor of :func:`_level_needed` (an open element whose gap is within
:data:`GAP_MARGIN` gap changes of closing). Their size follows Zienkiewicz and Xie's local
error estimate (:func:`_local_error`) against ``run.step_error`` times the largest recorded
displacement: a long step above it is retried shorter (:func:`_levels_down`), and the step
doubles past the base step only when the estimate is at most :data:`GROW_ERROR` of it and
the elements keep twice the margin (:func:`_may_lengthen`). A long step starts aligned to
its length and ends by the next recorded sample and ``run.tick_stop`` (:func:`_step_level`),
so recorded samples stay exact step ends; the sensor stream keeps the base step's samples,
filled in within a long step by cubic Hermite interpolation (:func:`_interpolate_sensors`).

The kernel, part by part. :func:`newmark_contact` is the step controller: the loop, the
order of the parts, rejections and level changes. A trial step:
:func:`~rubdiag._kernels.load.load_factors` (the load's factors at the step's ends, once per
group of terms by order and law), :func:`_rhs_average` (or
:func:`_rhs_general` and :func:`_load_increment`, γ != 1/2), the linear solve
(``lu_solve``, or a product with the dense inverse), :func:`_clock` (the step's times and the
shaft's angle for the element laws), :func:`_element_inputs` and
:func:`~rubdiag._kernels.elements.solve_elements` (the nonlinear elements' Newton solve in the
Schur complement, each element's law by its kind: the seam of
:mod:`rubdiag._kernels.elements`), :func:`_level_needed` (abrupt closing, each element's step
requirement). The accept: :func:`_increment` (``dq += S Δp``), :func:`_mk_products` (M dq, K
dq and the viscous dissipation in one pass; dense: :func:`_dissipation`),
:func:`_new_state`. The books: :func:`_energy_ledger`, :func:`_log_episodes` (episodes and
status segments), :func:`_commit_elements` (totals, maxima, the elements' new state). Then
:func:`_advance` (the clock, step growth) and :func:`_record` / :func:`_record_sensors` at
the sample ticks.

The parts take the plain arrays they use, not the bundles, and are written so that Numba
can drop the reference counting of their array arguments, which otherwise costs two atomic
operations per array per call (the parts that took whole bundles were 0.3-0.4 µs per step
slower): no array used in one branch of an ``if`` only (the controller picks
``_rhs_average`` or ``_rhs_general``, dense or sparse products), and no ``ZeroDivisionError``
paths (``error_model="numpy"``; no divisor there can be 0: h, β, γ, k_N, k_T > 0 and the
tick counts are checked by the caller), nor calls that could return one (``_gaps_at`` is
inlined). What is left is the call itself, about 15 ns with 20 arrays; ``_increment`` and
``_new_state`` are inlined into the loop (``inline="always"``: the update section was 0.1-0.2
µs per step slower as calls). Inlining the others brings reference counts back into the
controller (``_add_columns`` is inlined into its callers for the same reason, and
``_recover`` into the records: as a call with a branch over its arrays it brought 12
increfs into ``_record_sensors``).
``tests/kernels/test_reference_counts.py`` compiles without the disk cache and counts the
calls to ``NRT_incref`` in each part's IR: none in the per-step parts, a bounded number in
the controller (``_record`` and the failure paths have some).

Everything is preallocated by the caller (:mod:`rubdiag.simulation._system`); the kernel can be
re-entered: all state lives in the arrays passed in. The run's parameters, the loop's
counters and clock, each element's record and the logs are structured arrays whose fields
are named in :mod:`rubdiag._kernels.records` (``run[0].dt``, ``prog[0].tick`` …).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rubdiag._kernels.clock import cycles
from rubdiag._kernels.elements import (
    AUGMENT_PENDING,
    NONFINITE,
    add_bt_p,
    local_coords,
    solve_elements,
)
from rubdiag._kernels.load import _shaft, load_factors
from rubdiag._kernels.records import (
    D_LIN,
    D_NEW,
    OPEN,
    P_NEW,
    SLIDING,
    STICKING,
    V2,
    X_N,
    XA_N,
    XV_N,
    V,
)
from rubdiag._kernels.sparse_lu import csr_matvec, lu_solve
from rubdiag._numba import njit

__all__ = [
    "PROFILE_SECTIONS",
    "P_SIZE",
    "STATUS_DONE",
    "STATUS_LOG_FULL",
    "STATUS_NONFINITE",
    "STATUS_NO_CONVERGENCE",
    "WC_SIZE",
    "WN_SIZE",
    "Elements",
    "Factors",
    "Force",
    "Linear",
    "Logs",
    "Outputs",
    "State",
    "Work",
    "newmark_contact",
]

# kernel return codes
STATUS_DONE = 0  # reached tick_end
STATUS_NO_CONVERGENCE = 1  # element solve failed at the smallest step
STATUS_NONFINITE = 2  # non-finite state
STATUS_LOG_FULL = 3  # a log (episodes, segments, level changes) is full: caller grows it

# rows of the work ``wn`` (WN_SIZE, n); ``wc`` (WC_SIZE, m) rows are the seam's
WN_X = 0  # operand of the gamma != 1/2 products
WN_RHS = 1  # right-hand side; at the accept, plus Bᵀ Δp: the system dq solves
WN_DQ = 2  # displacement increment
WN_KDQ = 3  # work of the LU solve, then K dq
WN_MDQ = 4  # C x (gamma != 1/2), then M dq
WN_SIZE = 5
WC_SIZE = 5

#: a step may double past the base step when its error estimate is at most this share of
#: the tolerance: the estimate grows as h³, so the doubled step's is about 8 times this one's
GROW_ERROR = 0.7 / 8.0
#: a long step keeps each open impact element's gap above this many times the gap's change
#: over the step (twice that before the step doubles)
GAP_MARGIN = 2.0

# CPU cycles per section of a step, in a profiled run (``prof`` (P_SIZE) int64)
P_RHS = 0  # right-hand side of the increment equation (force, M v, K q, Bᵀp)
P_SOLVE = 1  # the linear solve with K_eff
P_CONTACT = 2  # element predictor, the element Newton solve, the level check
P_UPDATE = 3  # accept: dq += S Δp, M dq and K dq, the new state
P_LEDGER = 4  # energy ledger, episodes and totals, committing the elements' state
P_OUTPUT = 5  # step-size control and the recorded samples
P_SIZE = 6
PROFILE_SECTIONS = ("rhs", "solve", "contact", "update", "ledger", "output")


# The kernel's arrays in named bundles (Numba compiles namedtuples of arrays as records: a
# swapped pair of same-typed arrays is a wrong name here, not a silent wrong result). n DOF,
# n_e nonlinear elements with m local coordinates, L step levels; float64 unless int64.
#: The linear system: CSR of M and C (``m_ptr, m_idx, m_val``, ``c_*``; used by γ != 1/2
#: only), the union pattern of M and K in CSR with both value arrays (``mk_ptr``,
#: ``mk_idx``, ``mk_m``, ``mk_k``). A dense system (a reduced model) also gives M and K as
#: dense (n, n) arrays ``m_dense``, ``k_dense``; a sparse one gives them empty, (0, 0).
Linear = namedtuple("Linear", "m_ptr m_idx m_val c_ptr c_idx c_val mk_ptr mk_idx mk_m mk_k "
                    "m_dense k_dense")
#: Per step level (first axis L): K_eff's SuperLU factors as CSR without diagonals
#: (``l_ptr`` (L, n+1), ``l_idx``/``l_val`` (L, nnz_max), ``l_dinv`` (L, n) the inverse
#: diagonal, the same for U, ``perm_r``/``perm_c`` (L, n)), ``s_mat`` (L, m, n) =
#: (K_eff^-1 Bᵀ)ᵀ and ``w_mat`` (L, m, m) = B S. A dense system gives ``inv_t`` =
#: (K_eff^-1)ᵀ (L, n, n) instead of the LU factors (a sparse one an empty (L, 0, 0)).
Factors = namedtuple("Factors", "l_ptr l_idx l_val l_dinv u_ptr u_idx u_val u_dinv "
                     "perm_r perm_c s_mat w_mat inv_t")
#: The external load: term j is f_j(t) = Re((re + i im) z_g(t)) (N) at DOF ``dof`` (int),
#: with the factor z_g of its group g = ``group[j]`` (int). A group's ``law`` row (G, 3) is
#: (ω, order k, code) and ``table`` (G, n_knots, 2) its (Ω, factor) knots
#: (:mod:`rubdiag._kernels.load`); ``rot`` (n_knots, 3) the knots (t, Ω, φ) of the shaft's
#: speed, one knot (1, 3) for constant speed; ``zt`` (G, 4) work: each group's factor at
#: both ends of the step (:func:`~rubdiag._kernels.load.load_factors`).
Force = namedtuple("Force", "dof re im group law table rot zt")
#: The nonlinear elements (:mod:`rubdiag._kernels.elements`): ``el`` (n_e) records.ELEMENT,
#: ``rmap`` (m, 3) int and ``tmat`` (m, N_LOCAL_MAX) their local coordinates, ``par``
#: (n_e, n_par) their parameters, ``aug_k`` (L, n_e) the multiplier update stiffness of each
#: (N/m) at each step level.
Elements = namedtuple("Elements", "el rmap tmat par aug_k")
#: The state carried from step to step (and from call to call): ``q, v, a`` (n), ``mv = M v``
#: and ``kq = K q`` (n, tracked incrementally), ``pc`` (m) the elements' local forces,
#: ``xs`` (3, m) their local displacement, velocity and acceleration, ``es`` (2, n_e, n_s)
#: each element's own state (committed, trial), ``track`` (n_e) records.TRACK each
#: element's record and current episode, ``prog`` (1) records.PROGRESS the loop's counters,
#: ledger and clock.
State = namedtuple("State", "q v a mv kq pc xs es track prog")
#: The recorded samples (every ``run.out_ticks`` ticks): ``q`` (n_out, n_rec) at ``rec_dof``
#: (int); ``el`` (n_out, n_e) records.SAMPLE each element's record; ``en`` (n_out)
#: records.ENERGY the energy ledger; and the sensor stream (every ``run.sen_ticks`` ticks, a
#: multiple of the largest step, so samples are step ends): ``sq``, ``sv``, ``sa`` (n_sen_out,
#: n_s) displacement, velocity, acceleration at ``sen_dof`` — the integrator's own state,
#: not differences. Recorded values are ``q[rec_dof]`` (``q[sen_dof]``), or, when
#: ``rec_map`` (n, n_rec) and ``sen_map`` (n, n_s) are not empty, the recovered ``rec_mapᵀ
#: q`` (``sen_mapᵀ q``): the physical DOFs of a reduced model.
Outputs = namedtuple("Outputs", "rec_dof q el en sen_dof sq sv sa rec_map sen_map")
#: Event logs and totals (the caller grows the logs on STATUS_LOG_FULL): the ended episodes
#: ``ep`` (cap) records.EPISODE; every status segment (a maximal run of one engaged status:
#: steps count with their end-of-step status, an episode's interpolated start and end bound
#: its first and last segment) ``sg`` (cap) records.SEGMENT; the level changes ``lv_t``,
#: ``lv_l`` (int); ``stats`` (n_e) records.STATS totals and maxima per element; ``lvl_count``
#: (L) int accepted steps per level.
Logs = namedtuple("Logs", "ep sg lv_t lv_l stats lvl_count")
#: Work arrays (nothing is allocated in the loop): ``wn`` (WN_SIZE, n), ``wc`` (WC_SIZE, m),
#: ``wm`` (m, m), ``jac`` (m, N_LOCAL_MAX), ``iwork`` (4 m) int, ``trial`` (n_e)
#: records.TRIAL each element's law at the trial state; and ``prof`` (P_SIZE) int64,
#: the CPU cycles per section of a step (``P_*``), counted when not empty (an empty array
#: costs one branch per section).
Work = namedtuple("Work", "wn wc wm jac iwork trial prof")


@njit(error_model="numpy", inline="always")
def _add_force(f_dof, f_re, f_im, f_group, zt, end, scale, out):
    """``out[f_dof] += scale f(t)`` at the step's start (``end`` 0) or end (2): f_k(t) =
    f_re Re z - f_im Im z with its group's factor z from ``zt`` (:data:`Force`)."""
    for k in range(f_dof.shape[0]):
        g = f_group[k]
        out[f_dof[k]] += scale * (f_re[k] * zt[g, end] - f_im[k] * zt[g, end + 1])


@njit(error_model="numpy")
def _force_work(f_dof, f_re, f_im, f_group, zt, dq):
    """Work of the load over a step, trapezoid: ``Σ dq[f_dof] (f(t_n) + f(t_1)) / 2``
    (:func:`_add_force`)."""
    w = 0.0
    for k in range(f_dof.shape[0]):
        g = f_group[k]
        fa = ((f_re[k] * zt[g, 0] - f_im[k] * zt[g, 1])
              + (f_re[k] * zt[g, 2] - f_im[k] * zt[g, 3]))
        w += dq[f_dof[k]] * 0.5 * fa
    return w


@njit
def _matvec_t(at, x, out):
    """``out = A x`` for ``at = Aᵀ`` dense (see :func:`_add_columns`)."""
    for i in range(out.shape[0]):
        out[i] = 0.0
    _add_columns(at, x, 0, x.shape[0], 0, out.shape[0], out)


@njit(inline="always")
def _add_columns(at, x, j0, j1, i0, i1, out):
    """``out[i0:i1] += A[i0:i1, j0:j1] x[j0:j1]`` for ``at = Aᵀ`` dense: column by column
    (rows of ``at``), so the inner loop is an independent update of contiguous memory, which
    vectorizes (a row dot product would be a serial sum: no fastmath, no reordering). Eight
    columns per pass over ``out``, added as two groups of four, ``(out + ((c0 x0 + c1 x1) +
    (c2 x2 + c3 x3))) + (...)``: the same sums, in the same order, as two passes of four
    (the bits of the four-column version), with half the passes' loads, stores and set-up;
    then four, then one at a time."""
    j = j0
    while j + 8 <= j1:
        x0 = x[j]
        x1 = x[j + 1]
        x2 = x[j + 2]
        x3 = x[j + 3]
        x4 = x[j + 4]
        x5 = x[j + 5]
        x6 = x[j + 6]
        x7 = x[j + 7]
        c0 = at[j]
        c1 = at[j + 1]
        c2 = at[j + 2]
        c3 = at[j + 3]
        c4 = at[j + 4]
        c5 = at[j + 5]
        c6 = at[j + 6]
        c7 = at[j + 7]
        for i in range(i0, i1):
            out[i] = ((out[i] + ((c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3)))
                      + ((c4[i] * x4 + c5[i] * x5) + (c6[i] * x6 + c7[i] * x7)))
        j += 8
    while j + 4 <= j1:
        x0 = x[j]
        x1 = x[j + 1]
        x2 = x[j + 2]
        x3 = x[j + 3]
        c0 = at[j]
        c1 = at[j + 1]
        c2 = at[j + 2]
        c3 = at[j + 3]
        for i in range(i0, i1):
            out[i] += (c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3)
        j += 4
    while j < j1:
        xj = x[j]
        c0 = at[j]
        for i in range(i0, i1):
            out[i] += c0[i] * xj
        j += 1


@njit
def _mk_dense(nb, m_dense, k_dense, dq, mdq, kdq):
    """``mdq = M dq``, ``kdq = K dq`` for symmetric dense M, K whose coordinates from ``nb``
    on are modal: there K is diagonal and uncoupled, M diagonal in that block (a
    Craig–Bampton model: contact DOFs, then fixed-interface modes). ``2 nb n`` products
    instead of ``2 n²``; ``nb = n`` is the plain dense product."""
    n = dq.shape[0]
    for i in range(n):
        modal = i >= nb
        mdq[i] = m_dense[i, i] * dq[i] if modal else 0.0
        kdq[i] = k_dense[i, i] * dq[i] if modal else 0.0
    _add_columns(k_dense, dq, 0, nb, 0, nb, kdq)    # K_bb dq_b
    _add_columns(m_dense, dq, 0, n, 0, nb, mdq)     # M_bb dq_b + M_bm dq_m
    _add_columns(m_dense, dq, 0, nb, nb, n, mdq)    # M_mb dq_b


@njit(inline="always")
def _recover(mapt, dofs, x, out):
    """Recorded values of the state ``x``: ``x[dofs]``, or ``mapᵀ x`` for a non-empty
    ``mapt`` (n, n_out) (the physical DOFs of a reduced model). Inlined, and both paths run,
    each over a count that is 0 when it does not apply: as a call with an ``if`` over the
    arrays it made Numba count references in the records (12 increfs in the sensors' record,
    which runs at every step of a sensor stream, and of a run without sensors: 0.15-0.25 µs
    per step, 2026-11-27)."""
    mapped = mapt.shape[0] > 0
    n_gather = 0 if mapped else dofs.shape[0]
    for r in range(n_gather):
        out[r] = x[dofs[r]]
    n_out = out.shape[0] if mapped else 0
    for i in range(n_out):
        out[i] = 0.0
    _add_columns(mapt, x, 0, mapt.shape[0] if n_out > 0 else 0, 0, n_out, out)


# ---- a trial step: the linear predictor, the elements' inputs, the level check


@njit(error_model="numpy")
def _rhs_average(h, mv, kq, pc, f_dof, f_re, f_im, f_group, zt, el, rmap, tmat, rhs):
    """``rhs`` of the increment equation for average acceleration (module docstring):
    ``f_{n+1} + f_n + 2 Bᵀ p_n + 4/h M v_n - 2 K q_n``, no product."""
    # r_n = M (4/h v + 2 a) + 2 C v = 4/h M v + 2 (f_n + B^T p_n - K q)
    c4 = 4.0 / h
    for i in range(rhs.shape[0]):
        rhs[i] = c4 * mv[i] - 2.0 * kq[i]
    # + Δf + 2 f_n = f_{n+1} + f_n
    _add_force(f_dof, f_re, f_im, f_group, zt, 0, 1.0, rhs)
    add_bt_p(el, rmap, tmat, pc, 2.0, rhs)
    _add_force(f_dof, f_re, f_im, f_group, zt, 2, 1.0, rhs)


@njit(error_model="numpy")
def _rhs_general(run, h, v, a, m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, x, cx, rhs):
    """``rhs`` of the increment equation for Newmark β, γ (``run``) without the load:
    ``M (v_n / (β h) + a_n / (2β)) + C (γ/β v_n - h (1 - γ/(2β)) a_n)``; ``x``, ``cx`` (n)
    work. :func:`_load_increment` adds Δf."""
    nb = run[0].beta
    ng = run[0].gamma
    ca2 = 1.0 / (nb * h)
    ca3 = 1.0 / (2.0 * nb)
    for i in range(rhs.shape[0]):
        x[i] = ca2 * v[i] + ca3 * a[i]
    csr_matvec(m_ptr, m_idx, m_val, x, rhs)
    cy1 = ng / nb
    cy2 = -h * (1.0 - ng / (2.0 * nb))
    for i in range(rhs.shape[0]):
        x[i] = cy1 * v[i] + cy2 * a[i]
    csr_matvec(c_ptr, c_idx, c_val, x, cx)
    for i in range(rhs.shape[0]):
        rhs[i] += cx[i]


@njit(error_model="numpy")
def _load_increment(f_dof, f_re, f_im, f_group, zt, rhs):
    """``rhs += f(t_1) - f(t_n)``."""
    _add_force(f_dof, f_re, f_im, f_group, zt, 0, -1.0, rhs)
    _add_force(f_dof, f_re, f_im, f_group, zt, 2, 1.0, rhs)


@njit(error_model="numpy")
def _clock(run, prog, rot, t_n, t_1, h):
    """The trial step's clock in ``prog`` for the element laws: its ends and length, the
    shaft's speed and angle at its end (``rot``: :data:`Force`), and the Newmark velocity
    relation ``v_1 = cv Δq + cvv v_n + cva a_n``."""
    nb = run[0].beta
    ng = run[0].gamma
    kinematics = run[0].kinematics != 0
    prog[0].t_n = t_n
    prog[0].t_1 = t_1
    prog[0].h = h
    w, _, phi = _shaft(rot, t_1)    # (the search is over a few knots, and always done)
    prog[0].omega = w
    prog[0].phi = phi
    if kinematics:      # the divisions only for the kinds that read the rates
        prog[0].cv = ng / (nb * h)
        prog[0].cvv = 1.0 - ng / nb
        prog[0].cva = h * (1.0 - ng / (2.0 * nb))


@njit(error_model="numpy")
def _element_inputs(dq, xs, el, rmap, tmat, wc, trial):
    """What the element solve starts from: the predictor's local displacements ``d_lin =
    B (q + dq_lin) = d_n + B dq_lin``, and the multipliers."""
    local_coords(el, el.shape[0], rmap, tmat, dq, wc, D_LIN)
    for i in range(wc.shape[1]):
        wc[D_LIN, i] += xs[X_N, i]
    for e in range(el.shape[0]):
        # multipliers are iterated from 0 within each step (no carry-over: a multiplier
        # kept while the penetration shrinks pushes the contact open impulsively)
        trial[e].lam = 0.0


@njit
def _level_needed(run, lev, el, track, trial):
    """The level a converged step at ``lev`` must be retried at (``lev``: none): one down
    when an element open at the start ends deeper than ``run.gap_jump`` (an abrupt
    closing), and at least the ``lev_req`` of every element engaged at the start or end."""
    gap_jump = run[0].gap_jump
    long_step = lev < run[0].base
    need = lev
    for e in range(el.shape[0]):
        was_open = track[e].status == OPEN
        now_open = trial[e].status == OPEN
        depth = -trial[e].gap
        lev_req = el[e].lev_req
        if was_open and not now_open and depth > gap_jump:
            need = max(need, lev + 1)
        if (not was_open or not now_open) and lev_req > need:
            need = lev_req
        if long_step and el[e].impact != 0 and now_open:
            # the gap predictor: one more such step could close it (or it closed and
            # opened again within this one): back to the base step
            g1 = trial[e].gap
            if g1 <= GAP_MARGIN * abs(g1 - track[e].gap):
                need = max(need, run[0].base)
    return need


# ---- steps longer than the base step: where they may go, their error, the sensor stream


@njit
def _step_level(lev, base, top, tick, out_ticks, tick_stop):
    """The level of the next step: ``lev``, or for a long one (``lev < base``) the longest
    not longer that starts on a multiple of its own length and ends by the next recorded
    sample and by ``tick_stop``, so that samples stay exact step ends (the base step and
    shorter ones are never cut: ``out_ticks`` is a multiple of the base step)."""
    while lev < base:
        nt = np.int64(1) << (top - lev)
        next_sample = (tick // out_ticks + 1) * out_ticks
        if tick % nt == 0 and tick + nt <= next_sample and tick + nt <= tick_stop:
            break
        lev += 1
    return lev


@njit(error_model="numpy")
def _local_error(nb, h, dq, v, a, w, rec_dof, rec_map, sen_dof, sen_map, el, rmap, tmat, wc):
    """The trial's local error estimate (m) by Zienkiewicz and Xie (1991): ``e = (β - 1/6)
    h² (a_{n+1} - a_n) = (1 - 1/(6β)) (Δq - h v_n - h² a_n / 2)`` (from the Newmark
    relation for ``a_{n+1}``), largest over the recorded DOFs, the sensor DOFs and the
    impact elements' local coordinates. Reads the state at the step's start; ``w`` (n) and
    ``wc[V]`` work. Called only for a long step or one that may lengthen (its reference
    counting is then the controller's, on those steps only)."""
    c = abs(1.0 - 1.0 / (6.0 * nb))
    half_h2 = 0.5 * h * h
    for i in range(w.shape[0]):
        w[i] = dq[i] - h * v[i] - half_h2 * a[i]
    err = max(_largest(rec_map, rec_dof, w), _largest(sen_map, sen_dof, w))
    local_coords(el, el.shape[0], rmap, tmat, w, wc, V)
    for e in range(el.shape[0]):
        if el[e].impact != 0:
            for r in range(el[e].row, el[e].row + el[e].n):
                err = max(err, abs(wc[V, r]))
    return c * err


@njit(error_model="numpy")
def _largest(mapt, dofs, x):
    """``max |x[dofs]|``, or ``max |mapᵀ x|`` for a non-empty ``mapt`` (n, n_out)
    (:func:`_recover`)."""
    big = 0.0
    if mapt.shape[0] == 0:
        for r in range(dofs.shape[0]):
            big = max(big, abs(x[dofs[r]]))
        return big
    for r in range(mapt.shape[1]):
        acc = 0.0
        for j in range(mapt.shape[0]):
            acc += mapt[j, r] * x[j]
        big = max(big, abs(acc))
    return big


@njit
def _error_wanted(code, tol, lev, base, may_grow, el, track):
    """Whether a converged trial needs its error estimate: a long step, or a base step
    that may grow past the base (``may_grow``: quiet long enough) from a start where every
    impact element is open (else :func:`_may_lengthen` refuses whatever the error: a
    rubbing run skips the estimate at every step), with a tolerance."""
    if code != 0 or tol <= 0.0 or lev > base:
        return False
    if lev < base:
        return True
    if not may_grow:
        return False
    for e in range(el.shape[0]):
        if el[e].impact != 0 and track[e].status != OPEN:
            return False
    return True


@njit(error_model="numpy")
def _error_level(need, lev, base, err, tol):
    """``(level, by_error)``: a long step otherwise accepted (``need == lev``) whose error
    ``err`` is above ``tol`` goes down by :func:`_levels_down`; else ``need``."""
    if need == lev and lev < base and err > tol:
        return lev + _levels_down(err / tol, base - lev), True
    return need, False


@njit(error_model="numpy")
def _levels_down(ratio, room):
    """How many levels a long step rejected at ``ratio`` = error / tolerance goes down, at
    most ``room``: the error grows as h³, so a step ``2^-k`` as long has ``8^-k`` of it,
    with a margin of 0.9 on the step."""
    k = 1
    while k < room and ratio > 0.729 * 8.0 ** k:
        k += 1
    return k


@njit(error_model="numpy")
def _may_lengthen(err, tol, el, track, trial):
    """Whether the step may double past the base step: its error estimate ``err`` leaves
    room for a step twice as long (:data:`GROW_ERROR`), and every impact element stays open
    with the margin of a step twice as long (committed state in ``track``, the step's end in
    ``trial``). False without an estimate (``err`` < 0)."""
    ok = 0.0 <= err <= GROW_ERROR * tol
    for e in range(el.shape[0]):
        if el[e].impact != 0:
            g1 = trial[e].gap
            opened = track[e].status == OPEN and trial[e].status == OPEN
            ok = ok and opened and g1 > 2.0 * GAP_MARGIN * abs(g1 - track[e].gap)
    return ok


@njit(error_model="numpy")
def _interpolate_sensors(i0, i1, h, sq, sv, sa):
    """The sensor samples strictly between ``i0`` and ``i1``, the ends of a long step of
    length ``h`` (both recorded): cubic Hermite in displacement (from q and v at the ends)
    and in velocity (from v and a), linear in acceleration — the base step's stream, whose
    anti-alias filter then sees the same rate wherever the step is."""
    n = i1 - i0
    for k in range(1, n):
        s = k / n
        s2 = s * s
        s3 = s2 * s
        h00 = 2.0 * s3 - 3.0 * s2 + 1.0
        h10 = (s3 - 2.0 * s2 + s) * h
        h01 = 3.0 * s2 - 2.0 * s3
        h11 = (s3 - s2) * h
        for c in range(sq.shape[1]):
            sq[i0 + k, c] = (h00 * sq[i0, c] + h10 * sv[i0, c] + h01 * sq[i1, c]
                             + h11 * sv[i1, c])
            sv[i0 + k, c] = (h00 * sv[i0, c] + h10 * sa[i0, c] + h01 * sv[i1, c]
                             + h11 * sa[i1, c])
            sa[i0 + k, c] = (1.0 - s) * sa[i0, c] + s * sa[i1, c]


# ---- the accept: the increment, its products, the new state


@njit(inline="always")
def _increment(lev, s_mat, pc, p_new, el, rmap, tmat, dp, dq, rhs):
    """The accepted step's increment ``dq += S Δp`` (Δp = ``p_new - pc``, into ``dp``) and
    ``rhs += Bᵀ Δp``: the right-hand side ``K_eff dq = rhs`` actually solved."""
    for j in range(dp.shape[0]):
        dpj = p_new[j] - pc[j]
        dp[j] = dpj
        if dpj != 0.0:
            for i in range(dq.shape[0]):
                dq[i] += dpj * s_mat[lev, j, i]
    add_bt_p(el, rmap, tmat, dp, 1.0, rhs)


@njit(error_model="numpy")
def _mk_products(nb, ng, h, mk_ptr, mk_idx, mk_m, mk_k, dq, rhs, mdq, kdq):
    """``mdq = M dq`` and ``kdq = K dq`` in one pass over the union pattern of M and K.
    Returns ``dqᵀ C dq`` (h times the step's viscous dissipation h v̄ᵀ C v̄, v̄ = dq / h),
    with ``C dq = (rhs - K dq - M dq / (β h²)) β h / γ`` from ``K_eff dq = rhs``; not
    finite when dq is not."""
    ca0 = 1.0 / (nb * h * h)
    cc = nb * h / ng
    dvisc = 0.0
    for i in range(dq.shape[0]):
        am = 0.0
        ak = 0.0
        for k in range(mk_ptr[i], mk_ptr[i + 1]):
            dj = dq[mk_idx[k]]
            am += mk_m[k] * dj
            ak += mk_k[k] * dj
        dvisc += dq[i] * cc * (rhs[i] - ak - ca0 * am)
        mdq[i] = am
        kdq[i] = ak
    return dvisc


@njit(error_model="numpy")
def _dissipation(nb, ng, h, dq, rhs, mdq, kdq):
    """``dqᵀ C dq`` from ``M dq``, ``K dq`` and ``K_eff dq = rhs`` (see :func:`_mk_products`),
    for dense M and K, whose products come first."""
    ca0 = 1.0 / (nb * h * h)
    cc = nb * h / ng
    dvisc = 0.0
    for i in range(dq.shape[0]):
        dvisc += dq[i] * cc * (rhs[i] - kdq[i] - ca0 * mdq[i])
    return dvisc


#: The smallest normal float64: below it, numbers are subnormal.
_TINY = 2.2250738585072014e-308


@njit(error_model="numpy", inline="always")
def _normal(x):
    return x if abs(x) >= _TINY else 0.0


@njit(error_model="numpy", inline="always")
def _new_state(nb, ng, h, dq, mdq, kdq, q, v, a, mv, kq):
    """The state at the end of the accepted step from ``dq`` and its products (``mv`` is
    right for average acceleration only: the caller recomputes it otherwise)."""
    ca0 = 1.0 / (nb * h * h)
    ca2 = 1.0 / (nb * h)
    ca3 = 1.0 / (2.0 * nb) - 1.0
    cmv = ng / (nb * h)
    for i in range(q.shape[0]):
        # a free, damped DOF (the casing after the last contact) decays into subnormal
        # numbers, which cost ~100 cycles per operation on x86: _normal flushes them to 0
        an = ca0 * dq[i] - ca2 * v[i] - ca3 * a[i]
        v[i] = _normal(v[i] + h * ((1.0 - ng) * a[i] + ng * an))
        a[i] = _normal(an)
        q[i] = _normal(q[i] + dq[i])
        kq[i] = _normal(kq[i] + kdq[i])
        mv[i] = _normal(cmv * mdq[i] - mv[i])  # M v_{n+1} = 2/h M dq - M v_n (trapezoid)


# ---- the books: energy, episodes and segments, totals, the elements' state


@njit(error_model="numpy")
def _energy_ledger(prog, dvisc, dq, f_dof, f_re, f_im, f_group, zt, pc, el, rmap, tmat, wc,
                   trial):
    """The energy ledger of the accepted step (``prog``): the external work, the viscous
    dissipation (``dvisc / h``), and the elements' terms (each law's trial record): the
    drive work (the prescribed gap motion, the surface travel), the friction dissipation,
    the elastic energy stored, and the algorithmic remainder of the work the element forces
    did on the structure, ``B dq · (p_n + p_{n+1}) / 2``. Reads the committed state."""
    h = prog[0].h
    prog[0].d_visc += dvisc / h
    prog[0].w_ext += _force_work(f_dof, f_re, f_im, f_group, zt, dq)
    local_coords(el, el.shape[0], rmap, tmat, dq, wc, V)
    w_struct = 0.0
    for i in range(wc.shape[1]):
        w_struct += wc[V, i] * 0.5 * (wc[P_NEW, i] + pc[i])
    wdrive = 0.0
    dfric = 0.0
    ec = 0.0
    for e in range(el.shape[0]):
        engaged = trial[e].status != OPEN
        w_ramp = trial[e].w_ramp
        elastic = trial[e].elastic
        w_surface = trial[e].w_surface
        dissipated = trial[e].dissipated
        wdrive -= w_ramp
        if engaged:
            ec += elastic
            wdrive -= w_surface
            dfric += dissipated
    prog[0].w_drive += wdrive
    prog[0].d_fric += dfric
    prog[0].d_num += -w_struct + wdrive - (ec - prog[0].e_contact) - dfric
    prog[0].e_contact = ec


@njit
def _log_segment(sg, prog, e, status, t_start, t_end):
    """Log element ``e``'s segment of one engaged ``status`` from ``t_start`` to ``t_end``."""
    pr = prog[0]
    k = pr.n_segments
    sg[k].t_start = t_start
    sg[k].t_end = t_end
    sg[k].element = e
    sg[k].status = status
    pr.n_segments = k + 1


@njit(error_model="numpy")
def _log_episodes(prog, trial, track, ep, sg):
    """Each element's current episode (a maximal run of engaged steps) and status segment
    over the accepted step: opened, counted, or ended and logged (``ep``, ``sg``). A step
    counts with its end-of-step status; the episode's start and end are where the trial
    engagement function z crosses 0 within the step. Reads the old status in ``track``."""
    pr = prog[0]
    h = pr.h
    t_n = pr.t_n
    for e in range(track.shape[0]):
        k = track[e]
        so = k.status
        sn = trial[e].status
        fn = trial[e].fn
        zo = k.z
        zn = trial[e].z
        if so == OPEN and sn != OPEN:
            frac = zo / (zo - zn) if zo < 0.0 else 0.0
            k.ep_start = t_n + frac * h
            k.ep_peak_fn = 0.0
            k.ep_slide_time = 0.0
            k.ep_stick_time = 0.0
            k.ep_slide_impulse = 0.0
            k.ep_stick_impulse = 0.0
            k.ep_steps = 0
            k.ep_slide_entries = 0
            k.ep_stick_entries = 0
            k.seg_start = k.ep_start
        elif so != OPEN and sn != OPEN and sn != so:
            # sliding <-> sticking: the step counts with its new status
            _log_segment(sg, prog, e, so, k.seg_start, t_n)
            k.seg_start = t_n
        if sn != OPEN:
            k.ep_steps += 1
            if fn > k.ep_peak_fn:
                k.ep_peak_fn = fn
            if sn == SLIDING and so != SLIDING:
                k.ep_slide_entries += 1
            if sn == STICKING and so != STICKING:
                k.ep_stick_entries += 1
            if sn == SLIDING:
                k.ep_slide_time += h
                k.ep_slide_impulse += fn * h
            else:
                k.ep_stick_time += h
                k.ep_stick_impulse += fn * h
        elif so != OPEN:
            # episode ends inside this step: interpolate the trial normal force to zero
            frac = zo / (zo - zn) if zn < 0.0 and zo > 0.0 else 1.0
            j = pr.n_episodes
            ep[j].t_start = k.ep_start
            ep[j].t_end = t_n + frac * h
            ep[j].peak_fn = k.ep_peak_fn
            ep[j].slide_time = k.ep_slide_time
            ep[j].stick_time = k.ep_stick_time
            ep[j].slide_impulse = k.ep_slide_impulse
            ep[j].stick_impulse = k.ep_stick_impulse
            ep[j].element = e
            ep[j].steps = k.ep_steps
            ep[j].slide_entries = k.ep_slide_entries
            ep[j].stick_entries = k.ep_stick_entries
            pr.n_episodes = j + 1
            _log_segment(sg, prog, e, so, k.seg_start, ep[j].t_end)


@njit
def _commit_elements(run, prog, trial, es, track, stats, wc, pc, el, rmap, tmat, q, v, a, xs):
    """The accepted step's totals and maxima per element (``stats``, the cone excess), then
    its trial state becomes the current one (``track``, ``es``, ``pc``, and the local
    displacement, velocity and acceleration ``xs`` from the new q, v, a: ``d_new`` only up
    to the Newton tolerance)."""
    h = prog[0].h
    for e in range(el.shape[0]):
        sn = trial[e].status
        fn = trial[e].fn
        ft = trial[e].ft
        depth = -trial[e].gap
        cone = trial[e].cone
        stats[e].time[sn - 1] += h
        stats[e].fn_impulse[sn - 1] += fn * h
        stats[e].ft_impulse[sn - 1] += abs(ft) * h
        if fn > stats[e].max_fn:
            stats[e].max_fn = fn
        if abs(ft) > stats[e].max_ft:
            stats[e].max_ft = abs(ft)
        if depth > stats[e].max_penetration:
            stats[e].max_penetration = depth
        if cone > prog[0].cone_excess:
            prog[0].cone_excess = cone
        track[e].status = sn
        track[e].fn = fn
        track[e].ft = ft
        track[e].gap = trial[e].gap
        track[e].z = trial[e].z
        track[e].slip = trial[e].slip
        for j in range(es.shape[2]):
            es[0, e, j] = es[1, e, j]
    for i in range(pc.shape[0]):
        pc[i] = wc[P_NEW, i]
    ne = el.shape[0]
    local_coords(el, ne, rmap, tmat, q, xs, X_N)
    # the local velocity and acceleration for the kinds that read them (none of today's:
    # then no element; a count, not a branch, keeps the arrays free of reference counting)
    n_kin = ne if run[0].kinematics != 0 else 0
    local_coords(el, n_kin, rmap, tmat, v, xs, XV_N)
    local_coords(el, n_kin, rmap, tmat, a, xs, XA_N)


# ---- step control, failures and the records


@njit
def _count_iterations(code, nit, naug, prog):
    """Count an element solve's iterations; its code, with a step accepted before the
    multipliers reached the band (``AUGMENT_PENDING``, counted) as converged."""
    pr = prog[0]
    pr.newton_total += nit
    pr.aug_total += naug
    pending = code == AUGMENT_PENDING
    pr.aug_pending += 1 if pending else 0
    return 0 if pending else code


@njit
def _element_failure(prog, rmap, code, worst, t):
    """Note a failed element solve (its code, the element of its worst row, the time); the
    kernel's status."""
    pr = prog[0]
    pr.fail_element = rmap[worst, 2] if worst >= 0 else -1
    pr.fail_code = code
    pr.fail_time = t
    return STATUS_NONFINITE if code == NONFINITE else STATUS_NO_CONVERGENCE


@njit
def _nonfinite_increment(prog, el, wc, t):
    """Note a non-finite increment (the first element with non-finite local displacements,
    if any, and the time); the kernel's status."""
    pr = prog[0]
    pr.fail_element = -1
    for e in range(el.shape[0]):
        finite = True
        for r in range(el[e].row, el[e].row + el[e].n):
            finite = finite and np.isfinite(wc[D_NEW, r])
        if not finite:
            pr.fail_element = e
            break
    pr.fail_time = t
    return STATUS_NONFINITE


@njit
def _reject(prog, lv_t, lv_l, t, level, failed, by_error):
    """Retry the step at ``level`` (:func:`_change_level`), counting why: the element
    solve ``failed``, the error estimate (``by_error``), or an abrupt closing or too stiff
    a contact."""
    _change_level(prog, lv_t, lv_l, t, level)
    pr = prog[0]
    pr.n_rej_newton += 1 if failed else 0
    pr.n_rej_error += 1 if by_error and not failed else 0
    pr.n_rej_abrupt += 1 if not (failed or by_error) else 0


@njit
def _change_level(prog, lv_t, lv_l, t, level):
    """Go on at ``level`` from time ``t`` (logged)."""
    pr = prog[0]
    pr.level = level
    pr.quiet = 0
    k = pr.n_level_changes
    lv_t[k] = t
    lv_l[k] = level
    pr.n_level_changes = k + 1


@njit(error_model="numpy")
def _advance(run, prog, lev, nt, el, track, lvl_count, lengthen):
    """Count the accepted step of ``nt`` ticks at ``lev`` and move the clock on. Returns the
    new tick and whether the next step may be twice as long: after ``grow_after`` quiet
    steps at this level (the level asked for, not one cut short), when the new tick is
    aligned to it, every engaged element allows it (``lev_req``) and, past the base step,
    ``lengthen`` (:func:`_may_lengthen`)."""
    fixed = run[0].fixed != 0
    grow_after = run[0].grow_after
    asked = prog[0].level == lev
    past_base = lev <= run[0].base
    tick = prog[0].tick + nt
    prog[0].tick = tick
    prog[0].n_accepted += 1
    lvl_count[lev] += 1
    quiet = prog[0].quiet + 1
    prog[0].quiet = quiet
    grow = (not fixed and lev > 0 and quiet >= grow_after and tick % (2 * nt) == 0
            and asked and (lengthen or not past_base))
    for e in range(el.shape[0]):
        engaged = track[e].status != OPEN
        lev_req = el[e].lev_req
        if engaged and lev_req >= lev:
            grow = False
    return tick, grow


@njit
def _logs_full(ne, prog, ep, sg, lv_t):
    """Whether a step could overflow the episode, segment or level-change log (a step logs
    at most one episode and one segment per element, and one level change)."""
    pr = prog[0]
    episodes = pr.n_episodes + ne > ep.shape[0]
    segments = pr.n_segments + ne > sg.shape[0]
    levels = pr.n_level_changes + 2 > lv_t.shape[0]
    return episodes or segments or levels


@njit
def _record(idx, q, v, mv, kq, rec_dof, rec_map, track, prog, out_q, out_el, out_en):
    """Record sample ``idx``: the recorded DOFs (their largest magnitude is the scale of the
    long steps' error tolerance until the next sample), each element's record, and the
    energy ledger with the kinetic and strain energies ``vᵀ M v / 2``, ``qᵀ K q / 2``."""
    _recover(rec_map, rec_dof, q, out_q[idx])
    scale = 0.0
    for r in range(out_q.shape[1]):
        scale = max(scale, abs(out_q[idx, r]))
    prog[0].scale = scale
    for e in range(track.shape[0]):
        k = track[e]
        o = out_el[idx, e]
        o.fn = k.fn
        o.ft = k.ft
        o.status = k.status
        o.gap = k.gap
        o.slip = k.slip
    ek = 0.0
    es = 0.0
    for i in range(q.shape[0]):
        ek += v[i] * mv[i]
        es += q[i] * kq[i]
    pr = prog[0]
    en = out_en[idx]
    en.w_ext = pr.w_ext
    en.w_drive = pr.w_drive
    en.d_visc = pr.d_visc
    en.d_fric = pr.d_fric
    en.d_num = pr.d_num
    en.kinetic = 0.5 * ek
    en.strain = 0.5 * es
    en.contact = pr.e_contact


@njit
def _record_sensors(idx, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa):
    """Record sensor sample ``idx``: displacement, velocity and acceleration."""
    _recover(sen_map, sen_dof, q, out_sq[idx])
    _recover(sen_map, sen_dof, v, out_sv[idx])
    _recover(sen_map, sen_dof, a, out_sa[idx])


@njit
def _lap(prof, section, c0):
    """Add the cycles since ``c0`` to ``prof[section]``; the new start. Without profiling
    (``prof`` empty) nothing is read."""
    if prof.shape[0] == 0:
        return c0
    c1 = cycles()
    prof[section] += c1 - c0
    return c1


@njit
def newmark_contact(linear, factors, force, elements, run, state, outputs, logs, work):
    """Run the time loop from ``prog.tick`` to ``run.tick_end``; a ``STATUS_*``.

    The step controller: each pass tries one step at the current level, then rejects it (a
    level down), stops the run or accepts it (module docstring). The arrays come in the
    bundles (:data:`Linear` … :data:`Work`), unpacked once; ``run`` (1) records.RUN holds
    the run's parameters. ``STATUS_LOG_FULL``: a log could overflow (the caller grows it).
    """
    m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, mk_ptr, mk_idx, mk_m, mk_k, m_dense, k_dense = linear
    (l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c, s_mat,
     w_mat, inv_t) = factors
    f_dof, f_re, f_im, f_group, f_law, f_table, f_rot, zt = force
    el, rmap, tmat, par, aug_k = elements
    q, v, a, mv, kq, pc, xs, es, track, prog = state
    rec_dof, out_q, out_el, out_en, sen_dof, out_sq, out_sv, out_sa, rec_map, sen_map = outputs
    ep, sg, lv_t, lv_l, stats, lvl_count = logs
    wn, wc, wm, jac, iwork, trial, prof = work
    rp = run[0]
    pr = prog[0]
    ne = el.shape[0]
    dt0, nb, ng = rp.dt, rp.beta, rp.gamma
    base, tol, grow_after = rp.base, rp.step_error, rp.grow_after
    trapezoid = nb == 0.25 and ng == 0.5
    top, fixed = rp.n_lev - 1, rp.fixed != 0
    out_ticks, sen_ticks = rp.out_ticks, rp.sen_ticks
    tick_dt = dt0 / (1 << top)
    dense = inv_t.shape[1] > 0
    x, rhs, dq, kdq, mdq = wn[WN_X], wn[WN_RHS], wn[WN_DQ], wn[WN_KDQ], wn[WN_MDQ]
    p_new, dp = wc[P_NEW], wc[V2]

    tick = pr.tick
    if pr.sample0_done == 0:
        if tick % out_ticks == 0:
            _record(tick // out_ticks, q, v, mv, kq, rec_dof, rec_map, track, prog, out_q,
                    out_el, out_en)
        if tick % sen_ticks == 0:
            _record_sensors(tick // sen_ticks, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa)
        pr.sample0_done = 1

    while tick < rp.tick_end:
        if _logs_full(ne, prog, ep, sg, lv_t):
            return STATUS_LOG_FULL
        c0 = cycles() if prof.shape[0] else 0
        lev = _step_level(pr.level, base, top, tick, out_ticks, rp.tick_stop)
        nt = np.int64(1) << (top - lev)
        h = dt0 / (1 << lev)
        t_n = tick * tick_dt
        t_1 = (tick + nt) * tick_dt
        load_factors(f_law, f_table, f_rot, t_n, t_1, zt)   # the load's factors at both ends

        # ---- a trial step: the linear predictor, then the element solve
        if trapezoid:
            _rhs_average(h, mv, kq, pc, f_dof, f_re, f_im, f_group, zt, el, rmap, tmat, rhs)
        else:
            _rhs_general(run, h, v, a, m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, x, mdq, rhs)
            _load_increment(f_dof, f_re, f_im, f_group, zt, rhs)
        c0 = _lap(prof, P_RHS, c0)
        if dense:
            _matvec_t(inv_t[lev], rhs, dq)
        else:
            lu_solve(l_ptr[lev], l_idx[lev], l_val[lev], l_dinv[lev], u_ptr[lev], u_idx[lev],
                     u_val[lev], u_dinv[lev], perm_r[lev], perm_c[lev], rhs, dq, kdq)
        c0 = _lap(prof, P_SOLVE, c0)
        _clock(run, prog, f_rot, t_n, t_1, h)
        _element_inputs(dq, xs, el, rmap, tmat, wc, trial)
        code, nit, naug, worst = solve_elements(
            w_mat[lev], wc, pc, xs, el, par, aug_k[lev], es, track, trial, run, prog, jac, iwork,
            wm)
        code = _count_iterations(code, nit, naug, prog)
        if code == NONFINITE or (code != 0 and (fixed or lev == top)):
            return _element_failure(prog, rmap, code, worst, t_1)
        # the trial's increment (dq += S Δp) and, where wanted, its local error estimate
        _increment(lev, s_mat, pc, p_new, el, rmap, tmat, dp, dq, rhs)
        tol_m = tol * pr.scale
        err = -1.0
        if _error_wanted(code, tol, lev, base, pr.quiet + 1 >= grow_after, el, track):
            err = _local_error(nb, h, dq, v, a, x, rec_dof, rec_map, sen_dof, sen_map, el,
                               rmap, tmat, wc)
        # rejected: the element solve failed (one level down), converged to an abrupt
        # closing or too stiff a contact for this step, or a long step's error is too large
        # (down to the level needed)
        need = lev + 1 if code != 0 else _level_needed(run, lev, el, track, trial)
        need, by_error = _error_level(need, lev, base, err, tol_m)
        if need > lev and not fixed:
            if lev < top:
                _reject(prog, lv_t, lv_l, t_n, min(need, top), code != 0, by_error)
                _lap(prof, P_CONTACT, c0)
                continue
            pr.n_abrupt_at_min += 1  # abrupt at the smallest step: accepted, counted
        c0 = _lap(prof, P_CONTACT, c0)

        # ---- accept: the new state, the books
        pr.newton_max = max(pr.newton_max, nit)
        pr.aug_max = max(pr.aug_max, naug)
        lengthen = _may_lengthen(err, tol_m, el, track, trial)
        if dense:   # M and K are symmetric: row j is column j
            _mk_dense(rp.coupled, m_dense, k_dense, dq, mdq, kdq)
            dvisc = _dissipation(nb, ng, h, dq, rhs, mdq, kdq)
        else:
            dvisc = _mk_products(nb, ng, h, mk_ptr, mk_idx, mk_m, mk_k, dq, rhs, mdq, kdq)
        if not np.isfinite(dvisc):  # any non-finite dq shows here; the state is untouched
            return _nonfinite_increment(prog, el, wc, t_1)
        _new_state(nb, ng, h, dq, mdq, kdq, q, v, a, mv, kq)
        if not trapezoid:
            # M v_{n+1} also has a term h (1 - γ/(2β)) M a_n that is not tracked: recompute
            csr_matvec(m_ptr, m_idx, m_val, v, mv)
        c0 = _lap(prof, P_UPDATE, c0)
        _energy_ledger(prog, dvisc, dq, f_dof, f_re, f_im, f_group, zt, pc, el, rmap, tmat, wc,
                       trial)
        _log_episodes(prog, trial, track, ep, sg)
        _commit_elements(run, prog, trial, es, track, stats, wc, pc, el, rmap, tmat, q, v, a,
                         xs)
        c0 = _lap(prof, P_LEDGER, c0)

        # ---- the next step's size, the samples
        tick, grow = _advance(run, prog, lev, nt, el, track, lvl_count, lengthen)
        if grow:
            _change_level(prog, lv_t, lv_l, t_1, lev - 1)
        if tick % out_ticks == 0:
            _record(tick // out_ticks, q, v, mv, kq, rec_dof, rec_map, track, prog, out_q,
                    out_el, out_en)
        if tick % sen_ticks == 0:
            i1 = tick // sen_ticks
            _record_sensors(i1, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa)
            # a long step: the base step's samples within it (none for the others)
            _interpolate_sensors(i1 - nt // sen_ticks, i1, h, out_sq, out_sv, out_sa)
        _lap(prof, P_OUTPUT, c0)
    return STATUS_DONE
