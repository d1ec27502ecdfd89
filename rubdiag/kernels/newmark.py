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
from rubdiag.kernels.sparse_lu import csr_matvec, lu_solve

__all__ = [
    "FS",
    "IS",
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


class IS:
    """Indices into the int64 state vector ``istate``."""

    TICK = 0
    LEVEL = 1
    QUIET = 2  # accepted steps since the last level change
    N_ACCEPTED = 3
    N_REJ_NEWTON = 4
    N_REJ_ABRUPT = 5
    NEWTON_TOTAL = 6
    NEWTON_MAX = 7
    AUG_TOTAL = 8
    N_EPISODES = 9
    N_LEVEL_CHANGES = 10
    FAIL_ELEMENT = 11
    N_ABRUPT_AT_MIN = 12
    SAMPLE0_DONE = 13
    AUG_MAX = 14
    FAIL_CODE = 15  # contact-solve code of the failure
    AUG_PENDING = 16  # steps accepted with the penetration band not yet reached
    N_SEGMENTS = 17
    SIZE = 18


class FS:
    """Indices into the float64 state vector ``fstate`` (J unless stated)."""

    W_EXT = 0
    W_DRIVE = 1
    D_VISC = 2
    D_FRIC = 3
    D_NUM = 4
    CONE_EXCESS = 5  # max over steps/elements of |F_T| - mu F_N (N)
    FAIL_TIME = 6  # s
    E_CONTACT = 7  # contact elastic energy at the current state
    SIZE = 8


# the same indices as module constants (Numba cannot read class attributes)
I_TICK = 0
I_LEVEL = 1
I_QUIET = 2
I_N_ACCEPTED = 3
I_N_REJ_NEWTON = 4
I_N_REJ_ABRUPT = 5
I_NEWTON_TOTAL = 6
I_NEWTON_MAX = 7
I_AUG_TOTAL = 8
I_N_EPISODES = 9
I_N_LEVEL_CHANGES = 10
I_FAIL_ELEMENT = 11
I_N_ABRUPT_AT_MIN = 12
I_SAMPLE0_DONE = 13
I_AUG_MAX = 14
I_FAIL_CODE = 15
I_AUG_PENDING = 16
I_N_SEGMENTS = 17
I_SIZE = 18
F_W_EXT = 0
F_W_DRIVE = 1
F_D_VISC = 2
F_D_FRIC = 3
F_D_NUM = 4
F_CONE_EXCESS = 5
F_FAIL_TIME = 6
F_E_CONTACT = 7
F_SIZE = 8

# sections of a step whose CPU cycles a profiled run counts (``prof``, length P_SIZE)
P_RHS = 0  # right-hand side of the increment equation (force, M v, K q, Bᵀp)
P_SOLVE = 1  # the sparse triangular solves with K_eff
P_CONTACT = 2  # contact predictor, the contact Newton solve, the abrupt-closing check
P_UPDATE = 3  # accept: dq += S Δp, M dq and K dq, the new state
P_LEDGER = 4  # energy ledger, episodes and totals, committing the contact state
P_OUTPUT = 5  # step-size control and the recorded samples
P_SIZE = 6
PROFILE_SECTIONS = ("rhs", "solve", "contact", "update", "ledger", "output")

# parameter vectors
# fpar: 0 dt, 1 t_ramp, 2 newton_tol, 3 gap_jump, 4 aug_shift, 5 Newmark beta, 6 gamma
# ipar: 0 n_lev, 1 fixed, 2 grow_after, 3 max_newton, 4 max_aug, 5 tick_end, 6 out_ticks,
#       7 aug_strict



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
        out_fn[idx, e] = cf[3, e]
        out_ft[idx, e] = cf[4, e]
        out_st[idx, e] = ci[0, e]
        out_gap[idx, e] = cf[5, e]
        out_slip[idx, e] = cf[2, e]
    ek = 0.0
    es = 0.0
    for i in range(q.shape[0]):
        ek += v[i] * mv[i]
        es += q[i] * kq[i]
    out_en[idx, 0] = fstate[F_W_EXT]
    out_en[idx, 1] = fstate[F_W_DRIVE]
    out_en[idx, 2] = fstate[F_D_VISC]
    out_en[idx, 3] = fstate[F_D_FRIC]
    out_en[idx, 4] = fstate[F_D_NUM]
    out_en[idx, 5] = 0.5 * ek
    out_en[idx, 6] = 0.5 * es
    out_en[idx, 7] = fstate[F_E_CONTACT]


@njit
def _record_sensors(idx, q, v, a, sen_dof, sen_map, out_sq, out_sv, out_sa):
    _recover(sen_map, sen_dof, q, out_sq[idx])
    _recover(sen_map, sen_dof, v, out_sv[idx])
    _recover(sen_map, sen_dof, a, out_sa[idx])


@njit
def _log_segment(sg_f, sg_i, istate, e, status, t_start, t_end):
    k = istate[I_N_SEGMENTS]
    sg_f[k, 0] = t_start
    sg_f[k, 1] = t_end
    sg_i[k, 0] = e
    sg_i[k, 1] = status
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
    """Run the time loop from ``istate[TICK]`` to ``ipar[5]`` (tick_end). Returns a status code.

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
      displacements; ``cf`` (14, n_c) rows e, lam, slip s, F_N, F_T, gap, episode start time,
      episode peak F_N, trial normal force z, then the episode's sliding time, sticking time,
      normal impulse while sliding and while sticking, and the current segment's start time;
      ``ci`` (4, n_c) rows status, episode steps,
      slide entries, stick entries.
    * logs: ``ep_f`` (cap, 7) t_start, t_end, peak F_N, sliding time, sticking time, normal
      impulse while sliding, while sticking; ``ep_i`` (cap, 5) element, steps,
      slide entries, stick entries, complete; ``sg_f`` (cap, 2) t_start, t_end and ``sg_i``
      (cap, 2) element, status of every status segment (a maximal run of one closed status:
      steps count with their end-of-step status, the episode's interpolated start and end
      bound its first and last segment); ``lv_t``/``lv_l`` level-change log;
      ``tot`` (n_c, 9) time / normal impulse / tangential impulse per status 1..3;
      ``mx`` (n_c, 3) max F_N, max |F_T|, max penetration; ``lvl_count`` (L) accepted steps.
    * work: ``wn`` (6, n), ``wc`` (5, 2n_c), ``wcn`` (3, n_c), ``wm`` (2n_c, 2n_c),
      ``jac`` (n_c, 4), ``iwork`` (5 n_c) int, ``ciw`` (7, n_c) — nothing is allocated
      inside the loop.
    * ``prof`` (P_SIZE) int64: CPU cycles per section of the step (``P_*``), added to when
      not empty (a profiled run; an empty array costs one branch per section).
    * sensors: ``sen_dof`` (n_s) int; ``out_sq``, ``out_sv``, ``out_sa`` (n_sen_out, n_s)
      displacement, velocity and acceleration of those DOFs — the integrator's own state,
      not differences — every ``ipar[8]`` ticks (a multiple of the largest step, so the
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
    dt0 = fpar[0]
    t_ramp = fpar[1]
    tol = fpar[2]
    gap_jump = fpar[3]
    aug_shift = fpar[4]
    nb = fpar[5]
    ng = fpar[6]
    trapezoid = nb == 0.25 and ng == 0.5
    n_lev = ipar[0]
    fixed = ipar[1] != 0
    grow_after = ipar[2]
    max_newton = ipar[3]
    max_aug = ipar[4]
    aug_strict = ipar[7] != 0
    tick_end = ipar[5]
    out_ticks = ipar[6]
    sen_ticks = ipar[8]
    top = n_lev - 1
    tick_dt = dt0 / (1 << top)
    ep_cap = ep_f.shape[0]
    sg_cap = sg_f.shape[0]
    lv_cap = lv_t.shape[0]
    dense = inv_t.shape[1] > 0

    x = wn[0]
    rhs = wn[1]
    dq = wn[2]
    lw = wn[3]
    w5 = wn[5]
    d_lin = wc[0]
    d_new = wc[1]
    p_new = wc[2]
    wv = wc[3]
    wv2 = wc[4]
    gcur = wcn[0]
    lam_w = wcn[1]
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
            wcn[2, e] = c_speed[e] * h
        code, nit, naug, worst = solve_contact(
            w_mat[lev], d_lin, pc, dc, c_kind, gcur, c_kn, c_kt, c_mu, c_aug, c_eps,
            lam_w, cf[0], wcn[2], aug_k[lev], aug_shift, max_newton, max_aug, aug_strict, tol,
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
            if ci[0, e] == OPEN and st_new[e] != OPEN and -ciw[4, e] > gap_jump:
                abrupt = True
                if need < lev + 1:
                    need = lev + 1
            if (ci[0, e] != OPEN or st_new[e] != OPEN) and lev_req[e] > need:
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
            _gaps_at(t_n, c_g0, c_gstart, t_ramp, wcn[2])
        for e in range(nc):
            fn = ciw[0, e]
            ft = ciw[1, e]
            if t_ramp > 0.0 and t_n < t_ramp:
                # work of the prescribed gap motion on the contact (trapezoid)
                wdrive -= 0.5 * (fn + cf[3, e]) * (gcur[e] - wcn[2, e])
            if st_new[e] != OPEN:
                ec += 0.5 * fn * fn / c_kn[e] + 0.5 * ft * ft / c_kt[e]
                wdrive -= ft * c_speed[e] * h
                if st_new[e] == SLIDING:
                    dfric += abs(ft) * abs(ciw[3, e] - ciw[2, e])
        fstate[F_W_DRIVE] += wdrive
        fstate[F_D_FRIC] += dfric
        fstate[F_D_NUM] += -wc_ + wdrive - (ec - fstate[F_E_CONTACT]) - dfric
        fstate[F_E_CONTACT] = ec

        # per-element bookkeeping: episodes, totals, maxima
        for e in range(nc):
            so = ci[0, e]
            sn = st_new[e]
            fn = ciw[0, e]
            ft = ciw[1, e]
            zo = cf[8, e]
            zn = ciw[5, e]
            if so == OPEN and sn != OPEN:
                frac = zo / (zo - zn) if zo < 0.0 else 0.0
                cf[6, e] = t_n + frac * h
                cf[7, e] = 0.0
                for r in range(9, 13):
                    cf[r, e] = 0.0
                ci[1, e] = 0
                ci[2, e] = 0
                ci[3, e] = 0
                cf[13, e] = cf[6, e]
            elif so != OPEN and sn != OPEN and sn != so:
                # sliding <-> sticking: the step counts with its new status
                _log_segment(sg_f, sg_i, istate, e, so, cf[13, e], t_n)
                cf[13, e] = t_n
            if sn != OPEN:
                ci[1, e] += 1
                if fn > cf[7, e]:
                    cf[7, e] = fn
                if sn == SLIDING and so != SLIDING:
                    ci[2, e] += 1
                if sn == STICKING and so != STICKING:
                    ci[3, e] += 1
                # each step counts with its end-of-step status, as in ``tot``
                r = 9 if sn == SLIDING else 10
                cf[r, e] += h
                cf[r + 2, e] += fn * h
            elif so != OPEN:
                # episode ends inside this step: interpolate the trial normal force to zero
                frac = zo / (zo - zn) if zn < 0.0 and zo > 0.0 else 1.0
                k = istate[I_N_EPISODES]
                ep_f[k, 0] = cf[6, e]
                ep_f[k, 1] = t_n + frac * h
                ep_f[k, 2] = cf[7, e]
                for r in range(4):
                    ep_f[k, 3 + r] = cf[9 + r, e]
                ep_i[k, 0] = e
                ep_i[k, 1] = ci[1, e]
                ep_i[k, 2] = ci[2, e]
                ep_i[k, 3] = ci[3, e]
                ep_i[k, 4] = 1
                istate[I_N_EPISODES] = k + 1
                _log_segment(sg_f, sg_i, istate, e, so, cf[13, e], ep_f[k, 1])
            tot[e, sn - 1] += h
            tot[e, 3 + sn - 1] += fn * h
            tot[e, 6 + sn - 1] += abs(ft) * h
            if fn > mx[e, 0]:
                mx[e, 0] = fn
            if abs(ft) > mx[e, 1]:
                mx[e, 1] = abs(ft)
            if -ciw[4, e] > mx[e, 2]:
                mx[e, 2] = -ciw[4, e]
            excess = abs(ft) - c_mu[e] * fn
            if excess > fstate[F_CONE_EXCESS]:
                fstate[F_CONE_EXCESS] = excess
            # commit the contact state (slip first: it needs the old e)
            if c_kind[e] == KIND_POINT:
                cf[2, e] = d_new[2 * e + 1]
            elif sn != OPEN:
                cf[2, e] += ciw[3, e] - cf[0, e]
            ci[0, e] = sn
            cf[0, e] = ciw[2, e] if sn != OPEN else 0.0
            cf[1, e] = lam_w[e] if sn != OPEN else 0.0
            cf[3, e] = fn
            cf[4, e] = ft
            cf[5, e] = ciw[4, e]
            cf[8, e] = zn
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
            if ci[0, e] != OPEN and lev_req[e] > floor_lev:
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
