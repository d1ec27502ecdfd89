"""The step operators of every step level: K_eff's factors and the elements' view of them.

A step of size h solves ``K_eff Δq = r`` with ``K_eff = K + γ/(β h) C + 1/(β h²) M``, and
the elements' Newton solve works in the small Schur complement ``W = B K_eff⁻¹ Bᵀ`` of
their local coordinates ``x = B q``. Both are made once per step level ``h = dt_max / 2^k``
(and again per stretch of a speed profile), never inside the time loop.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from rubdiag._kernels.interface import Factors
from rubdiag._kernels.sparse_lu import factorize
from rubdiag.simulation._elements import impacts
from rubdiag.simulation._grid import Ticks
from rubdiag.simulation._solver import Settings

__all__ = ["Operators", "level_operators"]


class Operators(NamedTuple):
    """The step operators of every step level (:func:`level_operators`)."""

    lu: list            # K_eff's SuperLU factors per level (sparse; empty for dense)
    kernel: Factors     # as the kernel reads them
    lev_req: np.ndarray  # (n_e,) the smallest level each element may be engaged at
    aug_k: np.ndarray   # (n_lev, n_e) the multiplier update stiffness (N/m)


def level_operators(M, C, K, B, elements, grid: Ticks, settings: Settings) -> Operators:
    """Per step level k (h = dt_max / 2^k): the factors of K_eff, ``s_mat`` (n_lev, m, n) =
    (K_eff^-1 Bᵀ)ᵀ, ``w_mat`` (n_lev, m, m) = B K_eff^-1 Bᵀ, the smallest level each
    element may be engaged at (``lev_req``, by its step requirement; no criterion with a
    fixed step or without a ``contact_stiffness_ratio``), the multiplier update stiffness
    ``aug_k`` (n_lev, n_e), the factors packed for the kernel (first axis the level) and,
    for a dense solver, the transposed inverses ``inv_t`` (n_lev, n, n) (else (n_lev, 0,
    0))."""
    dt, n_lev, dense = grid.dt_max, grid.n_lev, settings.dense
    gamma, beta_nm, augment_boost = settings.gamma, settings.beta, settings.augment_boost
    ratio = None if grid.fixed_step else settings.contact_stiffness_ratio
    n = M.shape[0]
    m = B.shape[0]
    top = n_lev - 1
    factors = []
    s_list = []
    w_list = []
    inv_t = np.zeros((n_lev, n, n) if dense else (n_lev, 0, 0))
    Mc = sp.csc_matrix(M)
    Cc = sp.csc_matrix(C)
    Kc = sp.csc_matrix(K)
    for k in range(n_lev):
        h = dt / 2**k
        keff = Kc + (gamma / (beta_nm * h)) * Cc + (1.0 / (beta_nm * h * h)) * Mc
        try:
            if dense:   # LAPACK on the dense matrix (SuperLU's dense solves take ms each)
                inv_t[k] = np.linalg.inv(keff.toarray()).T
            else:
                fac = factorize(keff)
                factors.append(fac)
        except np.linalg.LinAlgError as exc:
            raise ValueError(f"K_eff at dt = {h:g} s is singular: {exc}") from exc
        if m:
            S = inv_t[k].T @ B.T if dense else fac.splu.solve(np.ascontiguousarray(B.T))
            s_list.append(np.ascontiguousarray(S.T))
            w_list.append(B @ S)
        else:
            s_list.append(np.zeros((0, n)))
            w_list.append(np.zeros((0, 0)))
    ne = len(elements)
    starts = np.cumsum([0] + [el.kernel.N_LOCAL for el in elements])

    def block(k, e):
        return w_list[k][starts[e]:starts[e + 1], starts[e]:starts[e + 1]]

    # the step requirement: for contacts k_N W_ee (= (ω_c h)^2 / 4 for a lumped mass) <= ratio
    lev_req = np.zeros(ne, np.int64)
    if ne and ratio is not None:
        for e, element in enumerate(elements):
            lev_req[e] = top
            for k in range(n_lev):
                if element.stiffness_ratio(block(k, e)) <= ratio:
                    lev_req[e] = k
                    break
    # an impact element is engaged at the base step or shorter ones: long steps are for
    # open stretches only
    for e, element in enumerate(elements):
        if impacts(element):
            lev_req[e] = max(lev_req[e], grid.base)
    # multiplier update stiffness: eq. (2) uses k_N; with the step's dynamic stiffness at the
    # contact, 1 / W_ee, far above k_N (small steps) that converges by a factor
    # 1 / (1 + k_N W_ee) per update only. We add 0.9 / W_ee (the Newton update of the
    # multiplier for an isolated contact, under-relaxed): same fixed point, a few updates.
    aug_k = np.zeros((n_lev, ne))
    for k in range(n_lev):
        for e, element in enumerate(elements):
            aug_k[k, e] = element.multiplier_stiffness(block(k, e), augment_boost)
    s_mat = np.ascontiguousarray(np.stack(s_list))
    w_mat = np.ascontiguousarray(np.stack(w_list))
    return Operators(factors, Factors(*_pack_factors(factors, n), s_mat, w_mat, inv_t),
                     lev_req, aug_k)


def _pack_factors(factors, n: int) -> tuple:
    """The per-level LU factors as the kernel reads them: arrays with the level as first
    axis, index and value rows padded to the largest factor (l_ptr, l_idx, l_val, l_dinv,
    u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c)."""
    n_lev = len(factors)
    nnz_l = max(1, max((f.l_val.size for f in factors), default=0))   # none: dense
    nnz_u = max(1, max((f.u_val.size for f in factors), default=0))
    l_ptr = np.zeros((n_lev, n + 1), np.int64)
    u_ptr = np.zeros((n_lev, n + 1), np.int64)
    l_idx = np.zeros((n_lev, nnz_l), np.int64)
    u_idx = np.zeros((n_lev, nnz_u), np.int64)
    l_val = np.zeros((n_lev, nnz_l))
    u_val = np.zeros((n_lev, nnz_u))
    l_dinv = np.zeros((n_lev, n))
    u_dinv = np.zeros((n_lev, n))
    perm_r = np.zeros((n_lev, n), np.int64)
    perm_c = np.zeros((n_lev, n), np.int64)
    for k, f in enumerate(factors):
        l_ptr[k] = f.l_ptr
        u_ptr[k] = f.u_ptr
        l_idx[k, : f.l_idx.size] = f.l_idx
        u_idx[k, : f.u_idx.size] = f.u_idx
        l_val[k, : f.l_val.size] = f.l_val
        u_val[k, : f.u_val.size] = f.u_val
        l_dinv[k] = f.l_dinv
        u_dinv[k] = f.u_dinv
        perm_r[k] = f.perm_r
        perm_c[k] = f.perm_c
    return l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c
