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
(``ipar[IP_COUPLED]``, :func:`_mk_dense`).

Step sizes are levels ``h_k = dt / 2^k`` (k = 0..n_lev-1). Time is an integer tick count
(tick = dt / 2^(n_lev-1)), so sample times and level changes are exact. A step at level k
starts on a multiple of its own tick length; growing to k-1 requires the tick to be aligned
to the larger step. A trial step is rejected and retried one level down when (i) the contact
iteration fails (Newton or augmentation cap, singular Jacobian), (ii) an element that was
open at the step start ends it deeper than ``gap_jump``, or (it jumps straight to that
level) (iii) an element closed at the start or end of the step needs a smaller step by the
contact-stiffness criterion (``lev_req``). At the smallest level (i) stops the run with
``STATUS_NO_CONVERGENCE`` and (ii) is accepted and counted. After ``grow_after`` accepted
steps at a level the step doubles (when aligned, and not below any closed element's
``lev_req``). In fixed-step mode nothing is rejected: (i) stops the run.

The kernel, part by part. :func:`newmark_contact` is the step controller: the loop, the
order of the parts, rejections and level changes. A trial step:
:func:`~rubdiag.kernels.load.load_factors` (the load's factors at the step's ends, once per
group of terms by order and law), :func:`_rhs_average` (or
:func:`_rhs_general`, γ != 1/2), the linear solve (``lu_solve``, or a product with the dense
inverse), :func:`_contact_inputs` and :func:`~rubdiag.kernels.contact.solve_contact` (the
contact Newton solve in the Schur complement), :func:`_level_needed` (abrupt closing,
contact stiffness). The accept: :func:`_increment` (``dq += S Δp``), :func:`_mk_products`
(M dq, K dq and the viscous dissipation in one pass; dense: :func:`_dissipation`),
:func:`_new_state`. The books: :func:`_energy_ledger`, :func:`_log_episodes` (episodes and
status segments), :func:`_commit_contacts` (totals, maxima, the new contact state). Then
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
controller (``_add_columns`` is inlined into its two callers for the same reason).
``tests/kernels/test_reference_counts.py`` compiles without the disk cache and counts the
calls to ``NRT_incref`` in each part's IR: none in the per-step parts, 170 in the
controller (the records, ``_recover`` and the failure paths have some, as before the
split).

Everything is preallocated by the caller (:mod:`rubdiag.simulate.system`); the kernel can be
re-entered: all state lives in the arrays passed in. The rows of the packed arrays (``cf``,
``ci``, ``ciw``, the work rows, ``fpar``, ``ipar`` …) are named in
:mod:`rubdiag.kernels.layout`.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rubdiag._numba import njit
from rubdiag.kernels.clock import cycles
from rubdiag.kernels.contact import (
    AUGMENT_PENDING,
    KIND_POINT,
    NONFINITE,
    OPEN,
    SLIDING,
    STICKING,
    solve_contact,
)
from rubdiag.kernels.layout import (
    CF_E,
    CF_EP_PEAK_FN,
    CF_EP_SLIDE_IMPULSE,
    CF_EP_SLIDE_TIME,
    CF_EP_START,
    CF_EP_STICK_IMPULSE,
    CF_EP_STICK_TIME,
    CF_FN,
    CF_FT,
    CF_GAP,
    CF_LAM,
    CF_SEG_START,
    CF_SLIP,
    CF_Z,
    CI_EP_SLIDE_ENTRIES,
    CI_EP_STEPS,
    CI_EP_STICK_ENTRIES,
    CI_STATUS,
    CR_E,
    CR_E_TRIAL,
    CR_FN,
    CR_FT,
    CR_GAP,
    CR_Z,
    EN_CONTACT,
    EN_D_FRIC,
    EN_D_NUM,
    EN_D_VISC,
    EN_KINETIC,
    EN_STRAIN,
    EN_W_DRIVE,
    EN_W_EXT,
    EPF_PEAK_FN,
    EPF_SLIDE_IMPULSE,
    EPF_SLIDE_TIME,
    EPF_STICK_IMPULSE,
    EPF_STICK_TIME,
    EPF_T_END,
    EPF_T_START,
    EPI_COMPLETE,
    EPI_ELEMENT,
    EPI_SLIDE_ENTRIES,
    EPI_STEPS,
    EPI_STICK_ENTRIES,
    F_CONE_EXCESS,
    F_D_FRIC,
    F_D_NUM,
    F_D_VISC,
    F_E_CONTACT,
    F_FAIL_TIME,
    F_W_DRIVE,
    F_W_EXT,
    FP_AUG_SHIFT,
    FP_BETA,
    FP_DT,
    FP_GAMMA,
    FP_GAP_JUMP,
    FP_NEWTON_TOL,
    FP_T_RAMP,
    I_AUG_MAX,
    I_AUG_PENDING,
    I_AUG_TOTAL,
    I_FAIL_CODE,
    I_FAIL_ELEMENT,
    I_LEVEL,
    I_N_ABRUPT_AT_MIN,
    I_N_ACCEPTED,
    I_N_EPISODES,
    I_N_LEVEL_CHANGES,
    I_N_REJ_ABRUPT,
    I_N_REJ_NEWTON,
    I_N_SEGMENTS,
    I_NEWTON_MAX,
    I_NEWTON_TOTAL,
    I_QUIET,
    I_SAMPLE0_DONE,
    I_TICK,
    IP_AUG_STRICT,
    IP_COUPLED,
    IP_FIXED,
    IP_GROW_AFTER,
    IP_MAX_AUG,
    IP_MAX_NEWTON,
    IP_N_LEV,
    IP_OUT_TICKS,
    IP_SEN_TICKS,
    IP_TICK_END,
    MX_FN,
    MX_FT,
    MX_PENETRATION,
    P_CONTACT,
    P_LEDGER,
    P_OUTPUT,
    P_RHS,
    P_SIZE,
    P_SOLVE,
    P_UPDATE,
    PROFILE_SECTIONS,
    SGF_T_END,
    SGF_T_START,
    SGI_ELEMENT,
    SGI_STATUS,
    TOT_FN_IMPULSE,
    TOT_FT_IMPULSE,
    TOT_TIME,
    WC_D_LIN,
    WC_D_NEW,
    WC_P_NEW,
    WC_V,
    WC_V2,
    WCN_DRIVE,
    WCN_GAP,
    WCN_GAP_START,
    WCN_LAM,
    WN_DQ,
    WN_KDQ,
    WN_MDQ,
    WN_RHS,
    WN_X,
)
from rubdiag.kernels.load import load_factors
from rubdiag.kernels.sparse_lu import csr_matvec, lu_solve

__all__ = [
    "PROFILE_SECTIONS",
    "P_SIZE",
    "STATUS_DONE",
    "STATUS_LOG_FULL",
    "STATUS_NONFINITE",
    "STATUS_NO_CONVERGENCE",
    "ContactSet",
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
STATUS_NO_CONVERGENCE = 1  # contact iteration failed at the smallest step
STATUS_NONFINITE = 2  # non-finite state
STATUS_LOG_FULL = 3  # a log (episodes, segments, level changes) is full: caller grows it


# The kernel's arrays in named bundles (Numba compiles namedtuples of arrays as records: a
# swapped pair of same-typed arrays is a wrong name here, not a silent wrong result). n DOF,
# n_c contacts, L step levels; float64 unless int64.
#: The linear system: CSR of M and C (``m_ptr, m_idx, m_val``, ``c_*``; used by γ != 1/2
#: only), the union pattern of M and K in CSR with both value arrays (``mk_ptr``,
#: ``mk_idx``, ``mk_m``, ``mk_k``). A dense system (a reduced model) also gives M and K as
#: dense (n, n) arrays ``m_dense``, ``k_dense``; a sparse one gives them empty, (0, 0).
Linear = namedtuple("Linear", "m_ptr m_idx m_val c_ptr c_idx c_val mk_ptr mk_idx mk_m mk_k "
                    "m_dense k_dense")
#: Per step level (first axis L): K_eff's SuperLU factors as CSR without diagonals
#: (``l_ptr`` (L, n+1), ``l_idx``/``l_val`` (L, nnz_max), ``l_dinv`` (L, n) the inverse
#: diagonal, the same for U, ``perm_r``/``perm_c`` (L, n)), ``s_mat`` (L, 2n_c, n) =
#: (K_eff^-1 Bᵀ)ᵀ and ``w_mat`` (L, 2n_c, 2n_c) = B S. A dense system gives ``inv_t`` =
#: (K_eff^-1)ᵀ (L, n, n) instead of the LU factors (a sparse one an empty (L, 0, 0)).
Factors = namedtuple("Factors", "l_ptr l_idx l_val l_dinv u_ptr u_idx u_val u_dinv "
                     "perm_r perm_c s_mat w_mat inv_t")
#: The external load: term j is f_j(t) = Re((re + i im) z_g(t)) (N) at DOF ``dof`` (int),
#: with the factor z_g of its group g = ``group[j]`` (int). A group's ``law`` row (G, 3) is
#: (ω, order k, code) and ``table`` (G, n_knots, 2) its (Ω, factor) knots
#: (:mod:`rubdiag.kernels.load`); ``rot`` (n_knots, 3) the knots (t, Ω, φ) of a speed
#: profile, one knot (1, 3) for constant speed (z = e^{iωt}); ``zt`` (G, 4) work: each
#: group's factor at both ends of the step (:func:`~rubdiag.kernels.load.load_factors`).
Force = namedtuple("Force", "dof re im group law table rot zt")
#: The contact elements (n_c): ``kind`` (int), ``dof`` (n_c, 4) int (a_y, a_z, b_y, b_z,
#: -1 = ground), ``basis`` (n_c, 4) rows of the local 2x2 basis, ``g0``, ``gstart`` (m: the
#: gap, and the gap at t = 0 of a gap ramp), ``kn``, ``kt`` (N/m), ``mu``, ``aug`` (int: 1 =
#: augmented Lagrangian), ``eps`` (m), ``speed`` (Ω R, m/s), ``lev_req`` (int) the smallest
#: level at which a step with the element closed is allowed (contact-stiffness criterion),
#: ``aug_k`` (L, n_c) the multiplier update stiffness per level (N/m).
ContactSet = namedtuple("ContactSet", "kind dof basis g0 gstart kn kt mu aug eps speed "
                        "lev_req aug_k")
#: The state carried from step to step (and from call to call): ``q, v, a`` (n), ``mv = M v``
#: and ``kq = K q`` (n, tracked incrementally), ``pc``, ``dc`` (2n_c) contact forces and
#: displacements, ``cf`` (CF_SIZE, n_c) and ``ci`` (CI_SIZE, n_c) int each element's state
#: and current episode, ``istate`` (I_SIZE) int counters, ``fstate`` (F_SIZE) the energy
#: ledger.
State = namedtuple("State", "q v a mv kq pc dc cf ci istate fstate")
#: The recorded samples (every ``ipar[IP_OUT_TICKS]`` ticks): ``q`` (n_out, n_rec) at
#: ``rec_dof`` (int); per element ``fn``, ``ft``, ``st`` (int), ``gap``, ``slip`` (n_out,
#: n_c); ``en`` (n_out, EN_SIZE) the energy ledger; and the sensor stream (every
#: ``ipar[IP_SEN_TICKS]`` ticks, a multiple of the largest step, so samples are step ends):
#: ``sq``, ``sv``, ``sa`` (n_sen_out, n_s) displacement, velocity, acceleration at
#: ``sen_dof`` — the integrator's own state, not differences. Recorded values are
#: ``q[rec_dof]`` (``q[sen_dof]``), or, when ``rec_map`` (n, n_rec) and ``sen_map`` (n, n_s)
#: are not empty, the recovered ``rec_mapᵀ q`` (``sen_mapᵀ q``): the physical DOFs of a
#: reduced model.
Outputs = namedtuple("Outputs", "rec_dof q fn ft st gap slip en sen_dof sq sv sa rec_map "
                     "sen_map")
#: Event logs and totals (the caller grows the logs on STATUS_LOG_FULL): the ended episodes
#: ``ep_f`` (cap, EPF_SIZE), ``ep_i`` (cap, EPI_SIZE) int; every status segment (a maximal
#: run of one closed status: steps count with their end-of-step status, an episode's
#: interpolated start and end bound its first and last segment) ``sg_f``, ``sg_i`` (cap,
#: SG_SIZE); the level changes ``lv_t``, ``lv_l`` (int); ``tot`` (n_c, TOT_SIZE) time,
#: normal and tangential impulse per status; ``mx`` (n_c, MX_SIZE) largest F_N, |F_T|,
#: penetration; ``lvl_count`` (L) int accepted steps per level.
Logs = namedtuple("Logs", "ep_f ep_i sg_f sg_i lv_t lv_l tot mx lvl_count")
#: Work arrays (nothing is allocated in the loop): ``wn`` (WN_SIZE, n), ``wc`` (WC_SIZE,
#: 2n_c), ``wcn`` (WCN_SIZE, n_c), ``wm`` (2n_c, 2n_c), ``jac`` (n_c, 4), ``iwork`` (5 n_c)
#: int, ``ciw`` (CR_SIZE, n_c) the contact solve's results; and ``prof`` (P_SIZE) int64, the
#: CPU cycles per section of a step (``P_*``), counted when not empty (an empty array costs
#: one branch per section).
Work = namedtuple("Work", "wn wc wcn wm jac iwork ciw prof")


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
    (rows of ``at``), four at a time, so the inner loop is an independent update of
    contiguous memory, which vectorizes (a row dot product would be a serial sum: no
    fastmath, no reordering)."""
    j = j0
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


@njit
def _recover(mapt, dofs, x, out):
    """Recorded values of the state ``x``: ``x[dofs]``, or ``mapᵀ x`` for a non-empty
    ``mapt`` (n, n_out) (the physical DOFs of a reduced model)."""
    if mapt.shape[0] == 0:
        for r in range(dofs.shape[0]):
            out[r] = x[dofs[r]]
    else:
        _matvec_t(mapt, x, out)


@njit(error_model="numpy", inline="always")
def _gaps_at(t, g0, gstart, t_ramp, out):
    """The gaps at time ``t``: ``g0``, or on the gap ramp (``t < t_ramp``) linearly from
    ``gstart`` at t = 0."""
    ramp = t_ramp > 0.0 and t < t_ramp
    frac = 1.0 - t / t_ramp if ramp else 0.0
    for e in range(g0.shape[0]):
        out[e] = g0[e] + (gstart[e] - g0[e]) * frac if ramp else g0[e]


@njit
def _contact_coords(c_dof, c_basis, qv, out):
    """Local contact displacements ``out = B qv`` (2 n_c)."""
    for e in range(c_dof.shape[0]):
        uy = qv[c_dof[e, 0]]
        uz = qv[c_dof[e, 1]]
        if c_dof[e, 2] >= 0:
            uy -= qv[c_dof[e, 2]]
        if c_dof[e, 3] >= 0:
            uz -= qv[c_dof[e, 3]]
        out[2 * e] = c_basis[e, 0] * uy + c_basis[e, 1] * uz
        out[2 * e + 1] = c_basis[e, 2] * uy + c_basis[e, 3] * uz


@njit
def _add_bt_p(c_dof, c_basis, p, scale, out):
    """``out += scale B^T p`` for the local contact forces p (2 n_c)."""
    for e in range(c_dof.shape[0]):
        fy = c_basis[e, 0] * p[2 * e] + c_basis[e, 2] * p[2 * e + 1]
        fz = c_basis[e, 1] * p[2 * e] + c_basis[e, 3] * p[2 * e + 1]
        out[c_dof[e, 0]] += scale * fy
        out[c_dof[e, 1]] += scale * fz
        if c_dof[e, 2] >= 0:
            out[c_dof[e, 2]] -= scale * fy
        if c_dof[e, 3] >= 0:
            out[c_dof[e, 3]] -= scale * fz


# ---- a trial step: the linear predictor, the contact solve's inputs, the level check


@njit(error_model="numpy")
def _rhs_average(h, mv, kq, pc, f_dof, f_re, f_im, f_group, zt, c_dof, c_basis, rhs):
    """``rhs`` of the increment equation for average acceleration (module docstring):
    ``f_{n+1} + f_n + 2 Bᵀ p_n + 4/h M v_n - 2 K q_n``, no product."""
    # r_n = M (4/h v + 2 a) + 2 C v = 4/h M v + 2 (f_n + B^T p_n - K q)
    c4 = 4.0 / h
    for i in range(rhs.shape[0]):
        rhs[i] = c4 * mv[i] - 2.0 * kq[i]
    # + Δf + 2 f_n = f_{n+1} + f_n
    _add_force(f_dof, f_re, f_im, f_group, zt, 0, 1.0, rhs)
    _add_bt_p(c_dof, c_basis, pc, 2.0, rhs)
    _add_force(f_dof, f_re, f_im, f_group, zt, 2, 1.0, rhs)


@njit(error_model="numpy")
def _rhs_general(nb, ng, h, v, a, f_dof, f_re, f_im, f_group, zt, m_ptr, m_idx, m_val,
                 c_ptr, c_idx, c_val, x, cx, rhs):
    """``rhs`` of the increment equation for Newmark β = ``nb``, γ = ``ng``: ``Δf + M (v_n
    / (β h) + a_n / (2β)) + C (γ/β v_n - h (1 - γ/(2β)) a_n)``; ``x``, ``cx`` (n) work."""
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
    _add_force(f_dof, f_re, f_im, f_group, zt, 0, -1.0, rhs)
    _add_force(f_dof, f_re, f_im, f_group, zt, 2, 1.0, rhs)


@njit(error_model="numpy")
def _contact_inputs(h, t_1, t_ramp, dq, dc, c_dof, c_basis, c_g0, c_gstart, c_speed,
                    d_lin, gap, lam, drive):
    """What the contact solve starts from: the predictor's contact displacements ``d_lin =
    B (q + dq_lin) = d_n + B dq_lin``, the gaps at the step end, the multipliers and each
    element's surface travel Ω R h."""
    _contact_coords(c_dof, c_basis, dq, d_lin)
    for i in range(d_lin.shape[0]):
        d_lin[i] += dc[i]
    _gaps_at(t_1, c_g0, c_gstart, t_ramp, gap)
    for e in range(lam.shape[0]):
        # multipliers are iterated from 0 within each step (no carry-over: a multiplier
        # kept while the penetration shrinks pushes the contact open impulsively)
        lam[e] = 0.0
        drive[e] = c_speed[e] * h


@njit
def _level_needed(lev, fpar, ci, st_new, ciw, lev_req):
    """The level a converged step at ``lev`` must be retried at (``lev``: none): one down
    when an element open at the start ends deeper than ``fpar[FP_GAP_JUMP]`` (an abrupt
    closing), and at least the ``lev_req`` of every element closed at the start or end."""
    gap_jump = fpar[FP_GAP_JUMP]
    need = lev
    for e in range(st_new.shape[0]):
        was_open = ci[CI_STATUS, e] == OPEN
        if was_open and st_new[e] != OPEN and -ciw[CR_GAP, e] > gap_jump:
            need = max(need, lev + 1)
        if (not was_open or st_new[e] != OPEN) and lev_req[e] > need:
            need = lev_req[e]
    return need


# ---- the accept: the increment, its products, the new state


@njit(inline="always")
def _increment(lev, s_mat, pc, p_new, c_dof, c_basis, dp, dq, rhs):
    """The accepted step's increment ``dq += S Δp`` (Δp = ``p_new - pc``, into ``dp``) and
    ``rhs += Bᵀ Δp``: the right-hand side ``K_eff dq = rhs`` actually solved."""
    for j in range(dp.shape[0]):
        dpj = p_new[j] - pc[j]
        dp[j] = dpj
        if dpj != 0.0:
            for i in range(dq.shape[0]):
                dq[i] += dpj * s_mat[lev, j, i]
    _add_bt_p(c_dof, c_basis, dp, 1.0, rhs)


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


# ---- the books: energy, episodes and segments, totals, the contact state


@njit(error_model="numpy")
def _energy_ledger(h, t_n, t_1, t_ramp, dvisc, dq, f_dof, f_re, f_im, f_group, zt, pc, p_new,
                   st_new, ciw, cf, c_dof, c_basis, c_g0, c_gstart, c_kn, c_kt, c_speed, gap,
                   gap_start, bdq, fstate):
    """The energy ledger of the accepted step (``fstate``): the external work, the viscous
    dissipation (``dvisc / h``), and the contact terms: the drive work (the prescribed gap
    motion, the surface travel), the friction dissipation, the contact elastic energy, and
    the algorithmic remainder of the work the contact forces did on the structure, ``B dq ·
    (p_n + p_{n+1}) / 2``. Reads ``cf`` before the commit."""
    fstate[F_D_VISC] += dvisc / h
    fstate[F_W_EXT] += _force_work(f_dof, f_re, f_im, f_group, zt, dq)
    _contact_coords(c_dof, c_basis, dq, bdq)
    w_struct = 0.0
    for i in range(bdq.shape[0]):
        w_struct += bdq[i] * 0.5 * (p_new[i] + pc[i])
    wdrive = 0.0
    dfric = 0.0
    ec = 0.0
    ramp = t_ramp > 0.0 and t_n < t_ramp
    _gaps_at(t_n, c_g0, c_gstart, t_ramp, gap_start)
    for e in range(st_new.shape[0]):
        fn = ciw[CR_FN, e]
        ft = ciw[CR_FT, e]
        if ramp:
            # work of the prescribed gap motion on the contact (trapezoid)
            wdrive -= 0.5 * (fn + cf[CF_FN, e]) * (gap[e] - gap_start[e])
        if st_new[e] != OPEN:
            ec += 0.5 * fn * fn / c_kn[e] + 0.5 * ft * ft / c_kt[e]
            wdrive -= ft * c_speed[e] * h
            if st_new[e] == SLIDING:
                dfric += abs(ft) * abs(ciw[CR_E_TRIAL, e] - ciw[CR_E, e])
    fstate[F_W_DRIVE] += wdrive
    fstate[F_D_FRIC] += dfric
    fstate[F_D_NUM] += -w_struct + wdrive - (ec - fstate[F_E_CONTACT]) - dfric
    fstate[F_E_CONTACT] = ec


@njit
def _log_segment(sg_f, sg_i, istate, e, status, t_start, t_end):
    """Log element ``e``'s segment of one closed ``status`` from ``t_start`` to ``t_end``."""
    k = istate[I_N_SEGMENTS]
    sg_f[k, SGF_T_START] = t_start
    sg_f[k, SGF_T_END] = t_end
    sg_i[k, SGI_ELEMENT] = e
    sg_i[k, SGI_STATUS] = status
    istate[I_N_SEGMENTS] = k + 1


@njit(error_model="numpy")
def _log_episodes(h, t_n, st_new, ciw, cf, ci, istate, ep_f, ep_i, sg_f, sg_i):
    """Each element's current episode (a maximal run of closed steps) and status segment
    over the accepted step: opened, counted, or ended and logged (``ep_*``, ``sg_*``). A
    step counts with its end-of-step status; the episode's start and end are where the
    trial normal force z crosses 0 within the step. Reads the old status in ``ci``."""
    for e in range(st_new.shape[0]):
        so = ci[CI_STATUS, e]
        sn = st_new[e]
        fn = ciw[CR_FN, e]
        zo = cf[CF_Z, e]
        zn = ciw[CR_Z, e]
        if so == OPEN and sn != OPEN:
            frac = zo / (zo - zn) if zo < 0.0 else 0.0
            cf[CF_EP_START, e] = t_n + frac * h
            cf[CF_EP_PEAK_FN, e] = 0.0
            cf[CF_EP_SLIDE_TIME, e] = 0.0
            cf[CF_EP_STICK_TIME, e] = 0.0
            cf[CF_EP_SLIDE_IMPULSE, e] = 0.0
            cf[CF_EP_STICK_IMPULSE, e] = 0.0
            ci[CI_EP_STEPS, e] = 0
            ci[CI_EP_SLIDE_ENTRIES, e] = 0
            ci[CI_EP_STICK_ENTRIES, e] = 0
            cf[CF_SEG_START, e] = cf[CF_EP_START, e]
        elif so != OPEN and sn != OPEN and sn != so:
            # sliding <-> sticking: the step counts with its new status
            _log_segment(sg_f, sg_i, istate, e, so, cf[CF_SEG_START, e], t_n)
            cf[CF_SEG_START, e] = t_n
        if sn != OPEN:
            ci[CI_EP_STEPS, e] += 1
            if fn > cf[CF_EP_PEAK_FN, e]:
                cf[CF_EP_PEAK_FN, e] = fn
            if sn == SLIDING and so != SLIDING:
                ci[CI_EP_SLIDE_ENTRIES, e] += 1
            if sn == STICKING and so != STICKING:
                ci[CI_EP_STICK_ENTRIES, e] += 1
            if sn == SLIDING:
                cf[CF_EP_SLIDE_TIME, e] += h
                cf[CF_EP_SLIDE_IMPULSE, e] += fn * h
            else:
                cf[CF_EP_STICK_TIME, e] += h
                cf[CF_EP_STICK_IMPULSE, e] += fn * h
        elif so != OPEN:
            # episode ends inside this step: interpolate the trial normal force to zero
            frac = zo / (zo - zn) if zn < 0.0 and zo > 0.0 else 1.0
            k = istate[I_N_EPISODES]
            ep_f[k, EPF_T_START] = cf[CF_EP_START, e]
            ep_f[k, EPF_T_END] = t_n + frac * h
            ep_f[k, EPF_PEAK_FN] = cf[CF_EP_PEAK_FN, e]
            ep_f[k, EPF_SLIDE_TIME] = cf[CF_EP_SLIDE_TIME, e]
            ep_f[k, EPF_STICK_TIME] = cf[CF_EP_STICK_TIME, e]
            ep_f[k, EPF_SLIDE_IMPULSE] = cf[CF_EP_SLIDE_IMPULSE, e]
            ep_f[k, EPF_STICK_IMPULSE] = cf[CF_EP_STICK_IMPULSE, e]
            ep_i[k, EPI_ELEMENT] = e
            ep_i[k, EPI_STEPS] = ci[CI_EP_STEPS, e]
            ep_i[k, EPI_SLIDE_ENTRIES] = ci[CI_EP_SLIDE_ENTRIES, e]
            ep_i[k, EPI_STICK_ENTRIES] = ci[CI_EP_STICK_ENTRIES, e]
            ep_i[k, EPI_COMPLETE] = 1
            istate[I_N_EPISODES] = k + 1
            _log_segment(sg_f, sg_i, istate, e, so, cf[CF_SEG_START, e], ep_f[k, EPF_T_END])


@njit
def _commit_contacts(h, c_kind, c_mu, c_dof, c_basis, st_new, ciw, d_new, lam, p_new, q, tot,
                     mx, fstate, cf, ci, pc, dc):
    """The accepted step's totals and maxima per element (``tot``, ``mx``, the cone excess),
    then its contact state becomes the current one (``cf``, ``ci``, ``pc``, and ``dc`` from
    the new ``q``: ``d_new`` only up to the Newton tolerance)."""
    for e in range(st_new.shape[0]):
        sn = st_new[e]
        fn = ciw[CR_FN, e]
        ft = ciw[CR_FT, e]
        tot[e, TOT_TIME + sn - 1] += h
        tot[e, TOT_FN_IMPULSE + sn - 1] += fn * h
        tot[e, TOT_FT_IMPULSE + sn - 1] += abs(ft) * h
        if fn > mx[e, MX_FN]:
            mx[e, MX_FN] = fn
        if abs(ft) > mx[e, MX_FT]:
            mx[e, MX_FT] = abs(ft)
        if -ciw[CR_GAP, e] > mx[e, MX_PENETRATION]:
            mx[e, MX_PENETRATION] = -ciw[CR_GAP, e]
        excess = abs(ft) - c_mu[e] * fn
        if excess > fstate[F_CONE_EXCESS]:
            fstate[F_CONE_EXCESS] = excess
        # slip first: it needs the old e
        if c_kind[e] == KIND_POINT:
            cf[CF_SLIP, e] = d_new[2 * e + 1]
        elif sn != OPEN:
            cf[CF_SLIP, e] += ciw[CR_E_TRIAL, e] - cf[CF_E, e]
        ci[CI_STATUS, e] = sn
        cf[CF_E, e] = ciw[CR_E, e] if sn != OPEN else 0.0
        cf[CF_LAM, e] = lam[e] if sn != OPEN else 0.0
        cf[CF_FN, e] = fn
        cf[CF_FT, e] = ft
        cf[CF_GAP, e] = ciw[CR_GAP, e]
        cf[CF_Z, e] = ciw[CR_Z, e]
    for i in range(pc.shape[0]):
        pc[i] = p_new[i]
    _contact_coords(c_dof, c_basis, q, dc)


# ---- step control, failures and the records


@njit
def _count_iterations(code, nit, naug, istate):
    """Count a contact solve's iterations; its code, with a step accepted before the
    multipliers reached the band (``AUGMENT_PENDING``, counted) as converged."""
    istate[I_NEWTON_TOTAL] += nit
    istate[I_AUG_TOTAL] += naug
    pending = code == AUGMENT_PENDING
    istate[I_AUG_PENDING] += 1 if pending else 0
    return 0 if pending else code


@njit
def _contact_failure(istate, fstate, code, worst, t):
    """Note a failed contact solve (its code, the element of its worst row, the time); the
    kernel's status."""
    istate[I_FAIL_ELEMENT] = worst // 2 if worst >= 0 else -1
    istate[I_FAIL_CODE] = code
    fstate[F_FAIL_TIME] = t
    return STATUS_NONFINITE if code == NONFINITE else STATUS_NO_CONVERGENCE


@njit
def _nonfinite_increment(istate, fstate, d_new, t):
    """Note a non-finite increment (the first element with non-finite contact
    displacements, if any, and the time); the kernel's status."""
    istate[I_FAIL_ELEMENT] = -1
    for e in range(d_new.shape[0] // 2):
        if not (np.isfinite(d_new[2 * e]) and np.isfinite(d_new[2 * e + 1])):
            istate[I_FAIL_ELEMENT] = e
            break
    fstate[F_FAIL_TIME] = t
    return STATUS_NONFINITE


@njit
def _change_level(istate, lv_t, lv_l, t, level):
    """Go on at ``level`` from time ``t`` (logged)."""
    istate[I_LEVEL] = level
    istate[I_QUIET] = 0
    k = istate[I_N_LEVEL_CHANGES]
    lv_t[k] = t
    lv_l[k] = level
    istate[I_N_LEVEL_CHANGES] = k + 1


@njit(error_model="numpy")
def _advance(lev, nt, fixed, grow_after, ci, lev_req, istate, lvl_count):
    """Count the accepted step of ``nt`` ticks at ``lev`` and move the clock on. Returns the
    new tick and whether the next step may be twice as long: after ``grow_after`` quiet
    steps at this level, when the new tick is aligned to it and every closed element allows
    it (``lev_req``)."""
    tick = istate[I_TICK] + nt
    istate[I_TICK] = tick
    istate[I_N_ACCEPTED] += 1
    lvl_count[lev] += 1
    quiet = istate[I_QUIET] + 1
    istate[I_QUIET] = quiet
    grow = not fixed and lev > 0 and quiet >= grow_after and tick % (2 * nt) == 0
    for e in range(lev_req.shape[0]):
        if ci[CI_STATUS, e] != OPEN and lev_req[e] >= lev:
            grow = False
    return tick, grow


@njit
def _logs_full(nc, istate, ep_f, sg_f, lv_t):
    """Whether a step could overflow the episode, segment or level-change log (a step logs
    at most one episode and one segment per element, and one level change)."""
    episodes = istate[I_N_EPISODES] + nc > ep_f.shape[0]
    segments = istate[I_N_SEGMENTS] + nc > sg_f.shape[0]
    levels = istate[I_N_LEVEL_CHANGES] + 2 > lv_t.shape[0]
    return episodes or segments or levels


@njit
def _record(
    idx, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate,
    out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en,
):
    """Record sample ``idx``: the recorded DOFs, each element's force, status, gap and slip,
    and the energy ledger with the kinetic and strain energies ``vᵀ M v / 2``, ``qᵀ K q /
    2``."""
    _recover(rec_map, rec_dof, q, out_q[idx])
    for e in range(ci.shape[1]):
        out_fn[idx, e] = cf[CF_FN, e]
        out_ft[idx, e] = cf[CF_FT, e]
        out_st[idx, e] = ci[CI_STATUS, e]
        out_gap[idx, e] = cf[CF_GAP, e]
        out_slip[idx, e] = cf[CF_SLIP, e]
    ek = 0.0
    es = 0.0
    for i in range(q.shape[0]):
        ek += v[i] * mv[i]
        es += q[i] * kq[i]
    out_en[idx, EN_W_EXT] = fstate[F_W_EXT]
    out_en[idx, EN_W_DRIVE] = fstate[F_W_DRIVE]
    out_en[idx, EN_D_VISC] = fstate[F_D_VISC]
    out_en[idx, EN_D_FRIC] = fstate[F_D_FRIC]
    out_en[idx, EN_D_NUM] = fstate[F_D_NUM]
    out_en[idx, EN_KINETIC] = 0.5 * ek
    out_en[idx, EN_STRAIN] = 0.5 * es
    out_en[idx, EN_CONTACT] = fstate[F_E_CONTACT]


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
def newmark_contact(linear, factors, force, contacts, fpar, ipar, state, outputs, logs, work):
    """Run the time loop from ``istate[I_TICK]`` to ``ipar[IP_TICK_END]``; a ``STATUS_*``.

    The step controller: each pass tries one step at the current level, then rejects it (a
    level down), stops the run or accepts it (module docstring). The arrays come in the
    bundles (:data:`Linear` … :data:`Work`), unpacked once; ``fpar``, ``ipar`` hold the
    run's parameters. ``STATUS_LOG_FULL``: a log could overflow (the caller grows it).
    """
    m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, mk_ptr, mk_idx, mk_m, mk_k, m_dense, k_dense = linear
    (l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c, s_mat,
     w_mat, inv_t) = factors
    f_dof, f_re, f_im, f_group, f_law, f_table, f_rot, zt = force
    (c_kind, c_dof, c_basis, c_g0, c_gstart, c_kn, c_kt, c_mu, c_aug, c_eps, c_speed,
     lev_req, aug_k) = contacts
    q, v, a, mv, kq, pc, dc, cf, ci, istate, fstate = state
    (rec_dof, out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en, sen_dof, out_sq,
     out_sv, out_sa, rec_map, sen_map) = outputs
    ep_f, ep_i, sg_f, sg_i, lv_t, lv_l, tot, mx, lvl_count = logs
    wn, wc, wcn, wm, jac, iwork, ciw, prof = work
    nc = c_kind.shape[0]
    dt0, t_ramp, nb, ng = fpar[FP_DT], fpar[FP_T_RAMP], fpar[FP_BETA], fpar[FP_GAMMA]
    trapezoid = nb == 0.25 and ng == 0.5
    top, fixed = ipar[IP_N_LEV] - 1, ipar[IP_FIXED] != 0
    out_ticks, sen_ticks = ipar[IP_OUT_TICKS], ipar[IP_SEN_TICKS]
    tick_dt = dt0 / (1 << top)
    dense = inv_t.shape[1] > 0
    x, rhs, dq, kdq, mdq = wn[WN_X], wn[WN_RHS], wn[WN_DQ], wn[WN_KDQ], wn[WN_MDQ]
    d_lin, d_new, p_new, wv, dp = wc[WC_D_LIN], wc[WC_D_NEW], wc[WC_P_NEW], wc[WC_V], wc[WC_V2]
    gap, lam, drive, gap_start = wcn[WCN_GAP], wcn[WCN_LAM], wcn[WCN_DRIVE], wcn[WCN_GAP_START]
    st_new, iw = iwork[4 * nc : 5 * nc], iwork[: 4 * nc]

    tick = istate[I_TICK]
    if istate[I_SAMPLE0_DONE] == 0:
        if tick % out_ticks == 0:
            _record(tick // out_ticks, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate, out_q,
                    out_fn, out_ft, out_st, out_gap, out_slip, out_en)
        if tick % sen_ticks == 0:
            _record_sensors(tick // sen_ticks, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa)
        istate[I_SAMPLE0_DONE] = 1

    while tick < ipar[IP_TICK_END]:
        if _logs_full(nc, istate, ep_f, sg_f, lv_t):
            return STATUS_LOG_FULL
        c0 = cycles() if prof.shape[0] else 0
        lev = istate[I_LEVEL]
        nt = np.int64(1) << (top - lev)
        h = dt0 / (1 << lev)
        t_n = tick * tick_dt
        t_1 = (tick + nt) * tick_dt
        load_factors(f_law, f_table, f_rot, t_n, t_1, zt)   # the load's factors at both ends

        # ---- a trial step: the linear predictor, then the contact solve
        if trapezoid:
            _rhs_average(h, mv, kq, pc, f_dof, f_re, f_im, f_group, zt, c_dof, c_basis, rhs)
        else:
            _rhs_general(nb, ng, h, v, a, f_dof, f_re, f_im, f_group, zt, m_ptr, m_idx, m_val,
                         c_ptr, c_idx, c_val, x, mdq, rhs)
        c0 = _lap(prof, P_RHS, c0)
        if dense:
            _matvec_t(inv_t[lev], rhs, dq)
        else:
            lu_solve(l_ptr[lev], l_idx[lev], l_val[lev], l_dinv[lev], u_ptr[lev], u_idx[lev],
                     u_val[lev], u_dinv[lev], perm_r[lev], perm_c[lev], rhs, dq, kdq)
        c0 = _lap(prof, P_SOLVE, c0)
        _contact_inputs(h, t_1, t_ramp, dq, dc, c_dof, c_basis, c_g0, c_gstart, c_speed, d_lin,
                        gap, lam, drive)
        code, nit, naug, worst = solve_contact(
            w_mat[lev], d_lin, pc, dc, c_kind, gap, c_kn, c_kt, c_mu, c_aug, c_eps, lam,
            cf[CF_E], drive, aug_k[lev], fpar[FP_AUG_SHIFT], ipar[IP_MAX_NEWTON],
            ipar[IP_MAX_AUG], ipar[IP_AUG_STRICT] != 0, fpar[FP_NEWTON_TOL],
            d_new, p_new, jac, ciw, st_new, iw, wm, wv, dp)
        code = _count_iterations(code, nit, naug, istate)
        if code == NONFINITE or (code != 0 and (fixed or lev == top)):
            return _contact_failure(istate, fstate, code, worst, t_1)
        # rejected: the contact solve failed (one level down), or converged to an abrupt
        # closing or too stiff a contact for this step (down to the level needed)
        need = lev + 1 if code != 0 else _level_needed(lev, fpar, ci, st_new, ciw, lev_req)
        if need > lev and not fixed:
            if lev < top:
                _change_level(istate, lv_t, lv_l, t_n, min(need, top))
                istate[I_N_REJ_NEWTON if code != 0 else I_N_REJ_ABRUPT] += 1
                _lap(prof, P_CONTACT, c0)
                continue
            istate[I_N_ABRUPT_AT_MIN] += 1  # abrupt at the smallest step: accepted, counted
        c0 = _lap(prof, P_CONTACT, c0)

        # ---- accept: dq, the new state, the books
        istate[I_NEWTON_MAX] = max(istate[I_NEWTON_MAX], nit)
        istate[I_AUG_MAX] = max(istate[I_AUG_MAX], naug)
        _increment(lev, s_mat, pc, p_new, c_dof, c_basis, dp, dq, rhs)
        if dense:   # M and K are symmetric: row j is column j
            _mk_dense(ipar[IP_COUPLED], m_dense, k_dense, dq, mdq, kdq)
            dvisc = _dissipation(nb, ng, h, dq, rhs, mdq, kdq)
        else:
            dvisc = _mk_products(nb, ng, h, mk_ptr, mk_idx, mk_m, mk_k, dq, rhs, mdq, kdq)
        if not np.isfinite(dvisc):  # any non-finite dq shows here; the state is untouched
            return _nonfinite_increment(istate, fstate, d_new, t_1)
        _new_state(nb, ng, h, dq, mdq, kdq, q, v, a, mv, kq)
        if not trapezoid:
            # M v_{n+1} also has a term h (1 - γ/(2β)) M a_n that is not tracked: recompute
            csr_matvec(m_ptr, m_idx, m_val, v, mv)
        c0 = _lap(prof, P_UPDATE, c0)
        _energy_ledger(h, t_n, t_1, t_ramp, dvisc, dq, f_dof, f_re, f_im, f_group, zt, pc, p_new,
                       st_new, ciw, cf, c_dof, c_basis, c_g0, c_gstart, c_kn, c_kt, c_speed,
                       gap, gap_start, wv, fstate)
        _log_episodes(h, t_n, st_new, ciw, cf, ci, istate, ep_f, ep_i, sg_f, sg_i)
        _commit_contacts(h, c_kind, c_mu, c_dof, c_basis, st_new, ciw, d_new, lam, p_new, q,
                         tot, mx, fstate, cf, ci, pc, dc)
        c0 = _lap(prof, P_LEDGER, c0)

        # ---- the next step's size, the samples
        tick, grow = _advance(lev, nt, fixed, ipar[IP_GROW_AFTER], ci, lev_req, istate,
                              lvl_count)
        if grow:
            _change_level(istate, lv_t, lv_l, t_1, lev - 1)
        if tick % out_ticks == 0:
            _record(tick // out_ticks, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate, out_q,
                    out_fn, out_ft, out_st, out_gap, out_slip, out_en)
        if tick % sen_ticks == 0:
            _record_sensors(tick // sen_ticks, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa)
        _lap(prof, P_OUTPUT, c0)
    return STATUS_DONE
