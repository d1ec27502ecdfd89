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
M and C for the right-hand side and recomputes M v: three more products.)

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

Everything is preallocated by the caller (:mod:`rubdiag.simulate.system`); the kernel can be
re-entered: all state lives in the arrays passed in.
"""

from __future__ import annotations

import math
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
# swapped pair of same-typed arrays is a wrong name here, not a silent wrong result).
#: The linear system: CSR of M and C (γ != 1/2 only), the union pattern of M and K with
#: both value arrays.
#: A dense system (a reduced model) also gives M and K as dense (n, n) arrays; a sparse one
#: gives them empty, (0, 0).
Linear = namedtuple("Linear", "m_ptr m_idx m_val c_ptr c_idx c_val mk_ptr mk_idx mk_m mk_k "
                    "m_dense k_dense")
#: Per step level (first axis): K_eff's LU factors as CSR without diagonals, S = (K_eff^-1
#: Bᵀ)ᵀ and W = B S; a dense system gives ``inv_t`` = (K_eff^-1)ᵀ (L, n, n) instead of the
#: LU factors (and a sparse one an empty (L, 0, 0)).
Factors = namedtuple("Factors", "l_ptr l_idx l_val l_dinv u_ptr u_idx u_val u_dinv "
                     "perm_r perm_c s_mat w_mat inv_t")
#: The harmonic force f_k(t) = re cos(om t) - im sin(om t) at DOF ``dof``.
Force = namedtuple("Force", "dof re im om")
#: The contact elements and their per-level data.
ContactSet = namedtuple("ContactSet", "kind dof basis g0 gstart kn kt mu aug eps speed "
                        "lev_req aug_k")
#: The state carried from step to step (and from call to call).
State = namedtuple("State", "q v a mv kq pc dc cf ci istate fstate")
#: The recorded samples and sensor stream. Recorded values are ``q[rec_dof]`` (and
#: ``q[sen_dof]``), or, when ``rec_map`` (n, n_rec) and ``sen_map`` (n, n_s) are not empty,
#: the recovered ``rec_mapᵀ q`` (``sen_mapᵀ q``): the physical DOFs of a reduced model.
Outputs = namedtuple("Outputs", "rec_dof q fn ft st gap slip en sen_dof sq sv sa rec_map "
                     "sen_map")
#: Event logs and totals (the caller grows the logs on STATUS_LOG_FULL).
Logs = namedtuple("Logs", "ep_f ep_i sg_f sg_i lv_t lv_l tot mx lvl_count")
#: Work arrays (nothing is allocated in the loop) and the cycle counters.
Work = namedtuple("Work", "wn wc wcn wm jac iwork ciw prof")

@njit
def _add_force(f_dof, f_re, f_im, f_om, t, scale, out):
    """``out[f_dof] += scale f(t)``, f_k(t) = f_re cos(om t) - f_im sin(om t); cos and sin
    are evaluated once per run of equal frequencies (a projected load has one per DOF)."""
    om = math.nan
    c = 0.0
    s = 0.0
    for k in range(f_dof.shape[0]):
        if f_om[k] != om:
            om = f_om[k]
            c = math.cos(om * t)
            s = math.sin(om * t)
        out[f_dof[k]] += scale * (f_re[k] * c - f_im[k] * s)


@njit
def _force_work(f_dof, f_re, f_im, f_om, t_n, t_1, dq):
    """Work of the load over a step, trapezoid: ``Σ dq[f_dof] (f(t_n) + f(t_1)) / 2``."""
    om = math.nan
    c0 = s0 = c1 = s1 = 0.0
    w = 0.0
    for k in range(f_dof.shape[0]):
        if f_om[k] != om:
            om = f_om[k]
            c0 = math.cos(om * t_n)
            s0 = math.sin(om * t_n)
            c1 = math.cos(om * t_1)
            s1 = math.sin(om * t_1)
        fa = (f_re[k] * c0 - f_im[k] * s0) + (f_re[k] * c1 - f_im[k] * s1)
        w += dq[f_dof[k]] * 0.5 * fa
    return w


@njit
def _matvec_t(at, x, out):
    """``out = A x`` for ``at = Aᵀ`` dense: column by column (rows of ``at``), four at a
    time, so the inner loop is an independent update of contiguous memory, which vectorizes
    (a row dot product would be a serial sum: no fastmath, no reordering)."""
    n = out.shape[0]
    m = x.shape[0]
    for i in range(n):
        out[i] = 0.0
    j = 0
    while j + 4 <= m:
        x0 = x[j]
        x1 = x[j + 1]
        x2 = x[j + 2]
        x3 = x[j + 3]
        c0 = at[j]
        c1 = at[j + 1]
        c2 = at[j + 2]
        c3 = at[j + 3]
        for i in range(n):
            out[i] += (c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3)
        j += 4
    while j < m:
        xj = x[j]
        c0 = at[j]
        for i in range(n):
            out[i] += c0[i] * xj
        j += 1


@njit
def _recover(mapt, dofs, x, out):
    """Recorded values of the state ``x``: ``x[dofs]``, or ``mapᵀ x`` for a non-empty
    ``mapt`` (n, n_out) (the physical DOFs of a reduced model)."""
    if mapt.shape[0] == 0:
        for r in range(dofs.shape[0]):
            out[r] = x[dofs[r]]
    else:
        _matvec_t(mapt, x, out)


@njit
def _gaps_at(t, g0, gstart, t_ramp, out):
    if t_ramp > 0.0 and t < t_ramp:
        frac = 1.0 - t / t_ramp
        for e in range(g0.shape[0]):
            out[e] = g0[e] + (gstart[e] - g0[e]) * frac
    else:
        for e in range(g0.shape[0]):
            out[e] = g0[e]


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


@njit
def _record(
    idx, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate,
    out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en,
):
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
    _recover(sen_map, sen_dof, q, out_sq[idx])
    _recover(sen_map, sen_dof, v, out_sv[idx])
    _recover(sen_map, sen_dof, a, out_sa[idx])


@njit
def _log_segment(sg_f, sg_i, istate, e, status, t_start, t_end):
    k = istate[I_N_SEGMENTS]
    sg_f[k, SGF_T_START] = t_start
    sg_f[k, SGF_T_END] = t_end
    sg_i[k, SGI_ELEMENT] = e
    sg_i[k, SGI_STATUS] = status
    istate[I_N_SEGMENTS] = k + 1


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
    """Run the time loop from ``istate[I_TICK]`` to ``ipar[IP_TICK_END]``; a status code.

    The arrays come in the bundles :data:`Linear`, :data:`Factors`, :data:`Force`,
    :data:`ContactSet`, :data:`State`, :data:`Outputs`, :data:`Logs` and :data:`Work`; below,
    by the local names the kernel unpacks them to (n DOF, n_c contacts, L = n_lev levels;
    all float64 unless int64):

    * CSR of M and C (used by the γ != 1/2 path only); the union pattern of M and K in CSR
      with both value arrays (``mk_ptr``, ``mk_idx``, ``mk_m``, ``mk_k``); per level (first
      axis L) the SuperLU factors as CSR without diagonals (``l_ptr`` (L, n+1),
      ``l_idx``/``l_val`` (L, nnz_max), ``l_dinv`` (L, n) inverse diagonal, same for U,
      ``perm_r``/``perm_c`` (L, n)), ``s_mat`` (L, 2n_c, n) = (K_eff^-1 B^T)^T,
      ``w_mat`` (L, 2n_c, 2n_c) = B S.
    * force: ``f_dof`` (int), ``f_re``, ``f_im`` (N), ``f_om`` (rad/s):
      f_k(t) = f_re cos(om t) - f_im sin(om t) at DOF f_dof.
    * contacts (n_c): ``c_kind`` (int), ``c_dof`` (n_c, 4) int (a_y, a_z, b_y, b_z, -1 =
      ground), ``c_basis`` (n_c, 4) rows of the local 2x2 basis, ``c_g0``, ``c_gstart`` (m),
      ``c_kn``, ``c_kt`` (N/m), ``c_mu``, ``c_aug`` (int), ``c_eps`` (m), ``c_speed``
      (Omega R, m/s), ``lev_req`` (int) the smallest level at
      which a step with the element closed is allowed (contact stiffness criterion);
      ``aug_k`` (L, n_c) multiplier update stiffness per level (N/m).
    * state: ``q, v, a`` (n), ``mv = M v``, ``kq = K q`` (n, tracked incrementally);
      ``pc``, ``dc`` (2n_c) contact forces and
      displacements; ``cf`` (CF_SIZE, n_c) float and ``ci`` (CI_SIZE, n_c) int per-element
      state (the current episode's too), rows ``CF_*``, ``CI_*``
      (:mod:`rubdiag.kernels.layout` names every row of the packed arrays).
    * logs: ``ep_f`` (cap, EPF_SIZE), ``ep_i`` (cap, EPI_SIZE) the ended episodes
      (``EPF_*``, ``EPI_*``); ``sg_f``, ``sg_i`` (cap, SG_SIZE) t_start, t_end and
      element, status of every status segment (a maximal run of one closed status:
      steps count with their end-of-step status, the episode's interpolated start and end
      bound its first and last segment); ``lv_t``/``lv_l`` level-change log;
      ``tot`` (n_c, TOT_SIZE) time / normal impulse / tangential impulse per status 1..3;
      ``mx`` (n_c, MX_SIZE) max F_N, max |F_T|, max penetration; ``lvl_count`` (L) accepted
      steps.
    * work: ``wn`` (WN_SIZE, n), ``wc`` (WC_SIZE, 2n_c), ``wcn`` (WCN_SIZE, n_c), ``wm``
      (2n_c, 2n_c), ``jac`` (n_c, 4), ``iwork`` (5 n_c) int, ``ciw`` (CR_SIZE, n_c) —
      nothing is allocated inside the loop.
    * ``prof`` (P_SIZE) int64: CPU cycles per section of the step (``P_*``), added to when
      not empty (a profiled run; an empty array costs one branch per section).
    * sensors: ``sen_dof`` (n_s) int; ``out_sq``, ``out_sv``, ``out_sa`` (n_sen_out, n_s)
      displacement, velocity and acceleration of those DOFs — the integrator's own state,
      not differences — every ``ipar[IP_SEN_TICKS]`` ticks (a multiple of the largest step, so the
      samples are step ends).
    """
    m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, mk_ptr, mk_idx, mk_m, mk_k, m_dense, k_dense = linear
    (l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c, s_mat,
     w_mat, inv_t) = factors
    f_dof, f_re, f_im, f_om = force
    (c_kind, c_dof, c_basis, c_g0, c_gstart, c_kn, c_kt, c_mu, c_aug, c_eps, c_speed,
     lev_req, aug_k) = contacts
    q, v, a, mv, kq, pc, dc, cf, ci, istate, fstate = state
    (rec_dof, out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en, sen_dof, out_sq,
     out_sv, out_sa, rec_map, sen_map) = outputs
    ep_f, ep_i, sg_f, sg_i, lv_t, lv_l, tot, mx, lvl_count = logs
    wn, wc, wcn, wm, jac, iwork, ciw, prof = work
    n = q.shape[0]
    nc = c_kind.shape[0]
    m2 = 2 * nc
    dt0 = fpar[FP_DT]
    t_ramp = fpar[FP_T_RAMP]
    tol = fpar[FP_NEWTON_TOL]
    gap_jump = fpar[FP_GAP_JUMP]
    aug_shift = fpar[FP_AUG_SHIFT]
    nb = fpar[FP_BETA]
    ng = fpar[FP_GAMMA]
    trapezoid = nb == 0.25 and ng == 0.5
    n_lev = ipar[IP_N_LEV]
    fixed = ipar[IP_FIXED] != 0
    grow_after = ipar[IP_GROW_AFTER]
    max_newton = ipar[IP_MAX_NEWTON]
    max_aug = ipar[IP_MAX_AUG]
    aug_strict = ipar[IP_AUG_STRICT] != 0
    tick_end = ipar[IP_TICK_END]
    out_ticks = ipar[IP_OUT_TICKS]
    sen_ticks = ipar[IP_SEN_TICKS]
    top = n_lev - 1
    tick_dt = dt0 / (1 << top)
    ep_cap = ep_f.shape[0]
    sg_cap = sg_f.shape[0]
    lv_cap = lv_t.shape[0]
    dense = inv_t.shape[1] > 0

    x = wn[WN_X]
    rhs = wn[WN_RHS]
    dq = wn[WN_DQ]
    lw = wn[WN_KDQ]
    w5 = wn[WN_MDQ]
    d_lin = wc[WC_D_LIN]
    d_new = wc[WC_D_NEW]
    p_new = wc[WC_P_NEW]
    wv = wc[WC_V]
    wv2 = wc[WC_V2]
    gcur = wcn[WCN_GAP]
    lam_w = wcn[WCN_LAM]
    drive = wcn[WCN_DRIVE]
    gstart_w = wcn[WCN_GAP_START]
    st_new = iwork[4 * nc : 5 * nc]
    iw = iwork[: 4 * nc]

    if istate[I_SAMPLE0_DONE] == 0:
        if istate[I_TICK] % out_ticks == 0:
            _record(
                istate[I_TICK] // out_ticks, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate,
                out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en,
            )
        if istate[I_TICK] % sen_ticks == 0:
            _record_sensors(istate[I_TICK] // sen_ticks, q, v, a, sen_dof, sen_map, out_sq,
                            out_sv, out_sa)
        istate[I_SAMPLE0_DONE] = 1

    while istate[I_TICK] < tick_end:
        if (
            istate[I_N_EPISODES] + nc > ep_cap
            or istate[I_N_SEGMENTS] + nc > sg_cap
            or istate[I_N_LEVEL_CHANGES] + 2 > lv_cap
        ):
            return STATUS_LOG_FULL
        c0 = cycles() if prof.shape[0] else 0
        tick = istate[I_TICK]
        lev = istate[I_LEVEL]
        nt = np.int64(1) << (top - lev)
        h = dt0 / (1 << lev)
        t_n = tick * tick_dt
        t_1 = (tick + nt) * tick_dt

        # right-hand side of the increment equation (see the module docstring)
        if trapezoid:
            # r_n = M (4/h v + 2 a) + 2 C v = 4/h M v + 2 (f_n + B^T p_n - K q): no product
            c4 = 4.0 / h
            for i in range(n):
                rhs[i] = c4 * mv[i] - 2.0 * kq[i]
            # + Δf + 2 f_n = f_{n+1} + f_n (f_{n+1} added below)
            _add_force(f_dof, f_re, f_im, f_om, t_n, 1.0, rhs)
            _add_bt_p(c_dof, c_basis, pc, 2.0, rhs)
        else:
            ca2 = 1.0 / (nb * h)
            ca3 = 1.0 / (2.0 * nb)
            for i in range(n):
                x[i] = ca2 * v[i] + ca3 * a[i]
            csr_matvec(m_ptr, m_idx, m_val, x, rhs)
            cy1 = ng / nb
            cy2 = -h * (1.0 - ng / (2.0 * nb))
            for i in range(n):
                x[i] = cy1 * v[i] + cy2 * a[i]
            csr_matvec(c_ptr, c_idx, c_val, x, w5)
            for i in range(n):
                rhs[i] += w5[i]
            _add_force(f_dof, f_re, f_im, f_om, t_n, -1.0, rhs)
        _add_force(f_dof, f_re, f_im, f_om, t_1, 1.0, rhs)
        c0 = _lap(prof, P_RHS, c0)
        if dense:
            _matvec_t(inv_t[lev], rhs, dq)
        else:
            lu_solve(
                l_ptr[lev], l_idx[lev], l_val[lev], l_dinv[lev],
                u_ptr[lev], u_idx[lev], u_val[lev], u_dinv[lev],
                perm_r[lev], perm_c[lev], rhs, dq, lw,
            )
        c0 = _lap(prof, P_SOLVE, c0)
        # predictor contact displacements d_lin = B (q + dq_lin) = d_n + B dq_lin
        _contact_coords(c_dof, c_basis, dq, d_lin)
        for i in range(m2):
            d_lin[i] += dc[i]
        _gaps_at(t_1, c_g0, c_gstart, t_ramp, gcur)
        for e in range(nc):
            # multipliers are iterated from 0 within each step (no carry-over: a multiplier
            # kept while the penetration shrinks pushes the contact open impulsively)
            lam_w[e] = 0.0
            drive[e] = c_speed[e] * h
        code, nit, naug, worst = solve_contact(
            w_mat[lev], d_lin, pc, dc, c_kind, gcur, c_kn, c_kt, c_mu, c_aug, c_eps,
            lam_w, cf[CF_E], drive, aug_k[lev], aug_shift, max_newton, max_aug, aug_strict, tol,
            d_new, p_new, jac, ciw, st_new, iw, wm, wv, wv2,
        )
        istate[I_NEWTON_TOTAL] += nit
        istate[I_AUG_TOTAL] += naug
        if code == AUGMENT_PENDING:
            istate[I_AUG_PENDING] += 1
            code = 0
        if code == NONFINITE:
            istate[I_FAIL_ELEMENT] = worst // 2 if worst >= 0 else -1
            istate[I_FAIL_CODE] = code
            fstate[F_FAIL_TIME] = t_1
            return STATUS_NONFINITE
        if code != 0:
            if fixed or lev == top:
                istate[I_FAIL_ELEMENT] = worst // 2 if worst >= 0 else -1
                istate[I_FAIL_CODE] = code
                fstate[F_FAIL_TIME] = t_1
                return STATUS_NO_CONVERGENCE
            istate[I_LEVEL] = lev + 1
            istate[I_QUIET] = 0
            istate[I_N_REJ_NEWTON] += 1
            nl = istate[I_N_LEVEL_CHANGES]
            lv_t[nl] = t_n
            lv_l[nl] = lev + 1
            istate[I_N_LEVEL_CHANGES] = nl + 1
            _lap(prof, P_CONTACT, c0)
            continue
        # abrupt closing: open at the start, deeper than gap_jump at the end; or a closed
        # element whose contact stiffness is too stiff for this step (lev_req)
        abrupt = False
        need = lev
        for e in range(nc):
            if ci[CI_STATUS, e] == OPEN and st_new[e] != OPEN and -ciw[CR_GAP, e] > gap_jump:
                abrupt = True
                if need < lev + 1:
                    need = lev + 1
            if (ci[CI_STATUS, e] != OPEN or st_new[e] != OPEN) and lev_req[e] > need:
                abrupt = True
                need = lev_req[e]
        if abrupt and not fixed:
            if lev < top:
                if need > top:
                    need = top
                istate[I_LEVEL] = need
                istate[I_QUIET] = 0
                istate[I_N_REJ_ABRUPT] += 1
                nl = istate[I_N_LEVEL_CHANGES]
                lv_t[nl] = t_n
                lv_l[nl] = need
                istate[I_N_LEVEL_CHANGES] = nl + 1
                _lap(prof, P_CONTACT, c0)
                continue
            istate[I_N_ABRUPT_AT_MIN] += 1

        c0 = _lap(prof, P_CONTACT, c0)
        # ---- accept: displacement increment dq = dq_lin + S (p_new - p_n)
        for j in range(m2):
            dp = p_new[j] - pc[j]
            if dp != 0.0:
                srow = s_mat[lev, j]
                for i in range(n):
                    dq[i] += dp * srow[i]
        if nit > istate[I_NEWTON_MAX]:
            istate[I_NEWTON_MAX] = nit
        if naug > istate[I_AUG_MAX]:
            istate[I_AUG_MAX] = naug

        # external work (trapezoid on the sparse force) before q changes
        wext = _force_work(f_dof, f_re, f_im, f_om, t_n, t_1, dq)
        # B^T Δp completes the right-hand side actually solved: K_eff dq = rhs
        for j in range(m2):
            wv2[j] = p_new[j] - pc[j]
        _add_bt_p(c_dof, c_basis, wv2, 1.0, rhs)
        # M dq and K dq in one pass over the union pattern; C dq from K_eff dq = rhs;
        # viscous dissipation of the step h v̄ᵀ C v̄ = dqᵀ C dq / h (v̄ = dq / h, trapezoid)
        ca0 = 1.0 / (nb * h * h)
        cc = nb * h / ng
        dvisc = 0.0
        if dense:   # M and K are symmetric: row j is column j
            _matvec_t(m_dense, dq, w5)
            _matvec_t(k_dense, dq, lw)
            for i in range(n):
                dvisc += dq[i] * cc * (rhs[i] - lw[i] - ca0 * w5[i])
        else:
            for i in range(n):
                am = 0.0
                ak = 0.0
                for k in range(mk_ptr[i], mk_ptr[i + 1]):
                    dj = dq[mk_idx[k]]
                    am += mk_m[k] * dj
                    ak += mk_k[k] * dj
                dvisc += dq[i] * cc * (rhs[i] - ak - ca0 * am)
                w5[i] = am
                lw[i] = ak
        if not np.isfinite(dvisc):  # any non-finite dq shows here; the state is untouched
            istate[I_FAIL_ELEMENT] = -1
            for e in range(nc):
                if not (np.isfinite(d_new[2 * e]) and np.isfinite(d_new[2 * e + 1])):
                    istate[I_FAIL_ELEMENT] = e
                    break
            fstate[F_FAIL_TIME] = t_1
            return STATUS_NONFINITE
        fstate[F_D_VISC] += dvisc / h
        fstate[F_W_EXT] += wext
        # new state
        ca2 = 1.0 / (nb * h)
        ca3 = 1.0 / (2.0 * nb) - 1.0
        cmv = ng / (nb * h)
        for i in range(n):
            an = ca0 * dq[i] - ca2 * v[i] - ca3 * a[i]
            v[i] = v[i] + h * ((1.0 - ng) * a[i] + ng * an)
            a[i] = an
            q[i] += dq[i]
            kq[i] += lw[i]
            mv[i] = cmv * w5[i] - mv[i]  # M v_{n+1} = 2/h M dq - M v_n (trapezoid)
        if not trapezoid:
            # M v_{n+1} also has a term h (1 - γ/(2β)) M a_n that is not tracked: recompute
            csr_matvec(m_ptr, m_idx, m_val, v, mv)

        c0 = _lap(prof, P_UPDATE, c0)
        # contact energy ledger: work of the contact forces on the structure, B dq . p_avg
        _contact_coords(c_dof, c_basis, dq, wv)
        wc_ = 0.0
        for i in range(m2):
            wc_ += wv[i] * 0.5 * (p_new[i] + pc[i])
        wdrive = 0.0
        dfric = 0.0
        ec = 0.0
        if t_ramp > 0.0 and t_n < t_ramp:
            _gaps_at(t_n, c_g0, c_gstart, t_ramp, gstart_w)
        for e in range(nc):
            fn = ciw[CR_FN, e]
            ft = ciw[CR_FT, e]
            if t_ramp > 0.0 and t_n < t_ramp:
                # work of the prescribed gap motion on the contact (trapezoid)
                wdrive -= 0.5 * (fn + cf[CF_FN, e]) * (gcur[e] - gstart_w[e])
            if st_new[e] != OPEN:
                ec += 0.5 * fn * fn / c_kn[e] + 0.5 * ft * ft / c_kt[e]
                wdrive -= ft * c_speed[e] * h
                if st_new[e] == SLIDING:
                    dfric += abs(ft) * abs(ciw[CR_E_TRIAL, e] - ciw[CR_E, e])
        fstate[F_W_DRIVE] += wdrive
        fstate[F_D_FRIC] += dfric
        fstate[F_D_NUM] += -wc_ + wdrive - (ec - fstate[F_E_CONTACT]) - dfric
        fstate[F_E_CONTACT] = ec

        # per-element bookkeeping: episodes, totals, maxima
        for e in range(nc):
            so = ci[CI_STATUS, e]
            sn = st_new[e]
            fn = ciw[CR_FN, e]
            ft = ciw[CR_FT, e]
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
                # each step counts with its end-of-step status, as in ``tot``
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
                _log_segment(sg_f, sg_i, istate, e, so, cf[CF_SEG_START, e],
                             ep_f[k, EPF_T_END])
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
            # commit the contact state (slip first: it needs the old e)
            if c_kind[e] == KIND_POINT:
                cf[CF_SLIP, e] = d_new[2 * e + 1]
            elif sn != OPEN:
                cf[CF_SLIP, e] += ciw[CR_E_TRIAL, e] - cf[CF_E, e]
            ci[CI_STATUS, e] = sn
            cf[CF_E, e] = ciw[CR_E, e] if sn != OPEN else 0.0
            cf[CF_LAM, e] = lam_w[e] if sn != OPEN else 0.0
            cf[CF_FN, e] = fn
            cf[CF_FT, e] = ft
            cf[CF_GAP, e] = ciw[CR_GAP, e]
            cf[CF_Z, e] = zn
        for i in range(m2):
            pc[i] = p_new[i]
        # contact displacements of the committed state (d_new up to the Newton tolerance)
        _contact_coords(c_dof, c_basis, q, dc)

        c0 = _lap(prof, P_LEDGER, c0)
        tick_new = tick + nt
        istate[I_TICK] = tick_new
        istate[I_N_ACCEPTED] += 1
        lvl_count[lev] += 1
        istate[I_QUIET] += 1
        floor_lev = 0
        for e in range(nc):
            if ci[CI_STATUS, e] != OPEN and lev_req[e] > floor_lev:
                floor_lev = lev_req[e]
        if (
            not fixed
            and lev > floor_lev
            and istate[I_QUIET] >= grow_after
            and tick_new % (2 * nt) == 0
        ):
            istate[I_LEVEL] = lev - 1
            istate[I_QUIET] = 0
            nl = istate[I_N_LEVEL_CHANGES]
            lv_t[nl] = t_1
            lv_l[nl] = lev - 1
            istate[I_N_LEVEL_CHANGES] = nl + 1
        if tick_new % out_ticks == 0:
            _record(
                tick_new // out_ticks, q, v, mv, kq, rec_dof, rec_map, cf, ci, fstate,
                out_q, out_fn, out_ft, out_st, out_gap, out_slip, out_en,
            )
        if tick_new % sen_ticks == 0:
            _record_sensors(tick_new // sen_ticks, q, v, a, sen_dof, sen_map, out_sq, out_sv,
                            out_sa)
        _lap(prof, P_OUTPUT, c0)
    return STATUS_DONE
