"""The time-loop kernel's interface: how its caller lays out the arguments.

:func:`rubdiag._kernels.newmark.newmark_contact` takes its arrays in named bundles (Numba
compiles a namedtuple of arrays as a record: a swapped pair of same-typed arrays is a wrong
name here, not a silent wrong result), the run's parameters as a record, and returns one of
the ``STATUS_*`` codes. The bundles' fields keep the short names their caller
(:mod:`rubdiag.simulation._kernel_args`) fills; each is described below, and the kernels take
them under these names:

* ``State``: ``mv``, ``kq`` are ``momentum`` (M v, N s) and ``elastic_force`` (K q, N),
  ``pc`` the ``local_force`` (N) of the elements at the step's start, ``xs`` their
  ``local_state``, ``es`` the ``element_state``, ``prog`` the ``progress``;
* ``Elements``: ``el`` the ``elements`` (kind, local rows, step requirement), ``rmap`` the
  ``row_dofs``, ``tmat`` the ``transforms``, ``par`` the ``parameters``, ``aug_k`` the
  ``augment_stiffness``;
* ``Factors``: ``s_mat`` the ``responses`` S = K_eff^-1 Bᵀ (transposed), ``w_mat`` the
  ``flexibility`` W = B S;
* ``Force``: ``dof``, ``re``, ``im``, ``group`` the ``load_*`` terms, ``zt`` the
  ``group_factors``;
* ``Work``: ``wn`` the ``dof_work`` (rows ``DOF_*``), ``wc`` the ``local_work`` (rows
  ``D_LIN`` … of :mod:`~rubdiag._kernels.records`), ``wm`` the ``newton_matrix``,
  ``jac`` the ``jacobian``, ``iwork`` the ``index_work``, ``prof`` the ``profile_cycles``.

The record types (the run's parameters, the loop's counters, each element's record, the
logs) are :mod:`rubdiag._kernels.records`; the rows of the elements' local vectors are
named there too. n DOF, n_e nonlinear elements with m local coordinates, L step levels;
float64 unless int64; SI units.
"""

from __future__ import annotations

from collections import namedtuple

__all__ = [
    "DOF_DQ",
    "DOF_K_DQ",
    "DOF_M_DQ",
    "DOF_RHS",
    "DOF_X",
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
]

# the kernel's return codes
STATUS_DONE = 0  # reached tick_end
STATUS_NO_CONVERGENCE = 1  # element solve failed at the smallest step
STATUS_NONFINITE = 2  # non-finite state
STATUS_LOG_FULL = 3  # a log (episodes, segments, level changes) is full: caller grows it

# rows of the work over the DOFs, ``Work.wn`` (WN_SIZE, n)
DOF_X = 0  # operand of the gamma != 1/2 products
DOF_RHS = 1  # right-hand side; at the accept, plus Bᵀ Δp: the system dq solves
DOF_DQ = 2  # displacement increment
DOF_K_DQ = 3  # work of the LU solve, then K dq
DOF_M_DQ = 4  # C x (gamma != 1/2), then M dq
WN_SIZE = 5
#: rows of the work over the local coordinates, ``Work.wc`` (WC_SIZE, m): records' D_LIN …
WC_SIZE = 5

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
#: ``wm`` (m, m), ``jac`` (m, N_LOCAL_MAX), ``iwork`` (5 m) int, ``trial`` (n_e)
#: records.TRIAL each element's law at the trial state; and ``prof`` int64, the CPU cycles
#: per section of a step (:data:`rubdiag._kernels.newmark.PROFILE_SECTIONS`), counted when
#: not empty (an empty array costs one branch per section).
Work = namedtuple("Work", "wn wc wm jac iwork trial prof")
