"""Sparse kernels: CSR matrix-vector products and LU triangular solves.

The factorization itself is done once per step size in Python (:func:`factorize`, SuperLU
through :func:`scipy.sparse.linalg.splu` with a fill-reducing column ordering); the kernels
below apply it inside the Numba time loop without allocating.

SuperLU factors ``Pr @ A @ Pc = L @ U`` (``Pr[perm_r[j], j] = 1``, ``Pc[i, perm_c[i]] = 1``),
so ``A x = b`` is solved as ``w = Pr b``; ``w <- L^-1 w``; ``w <- U^-1 w``; ``x = Pc w``.
The factors are handed to the kernel as CSR arrays *without* their diagonals, plus the
inverse diagonals (``l_dinv``, ``u_dinv``): the substitutions are then row dot products
(a register accumulator, no scattered stores), about twice as fast as column sweeps here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag._numba import njit

__all__ = ["LUFactors", "csr_matvec", "factorize", "lu_solve"]

#: the relative residual, max|A x - b| / (max|A| max|x|), a factorisation must solve a
#: random right-hand side to: a sound LU of the rig's operators leaves about 1e-15, a
#: numerically singular one orders of magnitude more
SOLVE_CHECK = 1e-10


@njit
def csr_matvec(indptr, indices, data, x, out):
    """``out = A @ x`` for a CSR matrix A.

    Parameters
    ----------
    indptr, indices : ndarray int
        A's CSR pattern.
    data : ndarray
        A's values.
    x : ndarray (n)
        The operand.
    out : ndarray (n)
        The product, overwritten (must not alias x).
    """
    n = indptr.shape[0] - 1
    for i in range(n):
        acc = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            acc += data[k] * x[indices[k]]
        out[i] = acc


@njit
def lu_solve(l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c, b, x, w):
    """Solve ``A x = b`` with SuperLU factors of A (module docstring).

    Parameters
    ----------
    l_ptr, l_idx, l_val : ndarray
        L without its diagonal, in CSR.
    l_dinv : ndarray (n)
        The inverse of L's diagonal.
    u_ptr, u_idx, u_val, u_dinv : ndarray
        The same for U.
    perm_r, perm_c : ndarray (n) int
        SuperLU's row and column permutations.
    b : ndarray (n)
        The right-hand side.
    x : ndarray (n)
        The solution, written (may alias b).
    w : ndarray (n)
        Work (must not alias x or b).
    """
    n = b.shape[0]
    for j in range(n):
        w[perm_r[j]] = b[j]
    # forward substitution, L lower triangular (CSR, strictly lower part): row dot products
    for i in range(n):
        acc = w[i]
        for k in range(l_ptr[i], l_ptr[i + 1]):
            acc -= l_val[k] * w[l_idx[k]]
        w[i] = acc * l_dinv[i]
    # backward substitution, U upper triangular (CSR, strictly upper part)
    for i in range(n - 1, -1, -1):
        acc = w[i]
        for k in range(u_ptr[i], u_ptr[i + 1]):
            acc -= u_val[k] * w[u_idx[k]]
        w[i] = acc * u_dinv[i]
    for i in range(n):
        x[i] = w[perm_c[i]]


@dataclass(frozen=True)
class LUFactors:
    """Kernel-ready SuperLU factors of one matrix (CSR without diagonals, see module doc)."""

    l_ptr: np.ndarray
    l_idx: np.ndarray
    l_val: np.ndarray
    l_dinv: np.ndarray
    u_ptr: np.ndarray
    u_idx: np.ndarray
    u_val: np.ndarray
    u_dinv: np.ndarray
    perm_r: np.ndarray
    perm_c: np.ndarray
    splu: object  # the scipy SuperLU object (for solves in Python)
    ordering: str

    @property
    def nnz(self) -> int:
        """Nonzeros of L + U (diagonals counted once each)."""
        return int(self.l_val.size + self.u_val.size + 2 * self.l_dinv.size)


def _split_diag(T: sp.csc_matrix) -> tuple[np.ndarray, ...]:
    T = sp.csc_matrix(T)
    T.sort_indices()
    n = T.shape[0]
    diag = T.diagonal()
    if np.any(diag == 0.0):
        raise np.linalg.LinAlgError("singular triangular factor (zero pivot)")
    off = T - sp.diags(diag, format="csc")
    off = sp.csr_matrix(off)
    off.eliminate_zeros()
    off.sort_indices()
    return (
        np.ascontiguousarray(off.indptr, dtype=np.int64),
        np.ascontiguousarray(off.indices, dtype=np.int64),
        np.ascontiguousarray(off.data, dtype=np.float64),
        np.ascontiguousarray(1.0 / diag, dtype=np.float64).reshape(n),
    )


def factorize(
    A, orderings: tuple[str, ...] = ("COLAMD", "MMD_AT_PLUS_A"), symmetric_mode: bool = True
) -> LUFactors:
    """Sparse LU of a square matrix with the least fill among a few SuperLU settings.

    Tries each column ordering with partial pivoting and, if ``symmetric_mode``, also in
    SuperLU's symmetric mode (diagonal pivots, symmetric ordering: about 20 % less fill for
    an effective stiffness ``K + 2/h C + 4/h^2 M``, which is strongly diagonally dominant). A
    candidate is kept only if it solves a random right-hand side to a relative residual
    below :data:`SOLVE_CHECK`. Raises ``numpy.linalg.LinAlgError`` if A is singular.
    """
    A = sp.csc_matrix(A, dtype=np.float64)
    n = A.shape[0]
    rng = np.random.default_rng(0)
    b = rng.standard_normal(n)
    best = None
    settings = [(spec, False) for spec in orderings]
    if symmetric_mode:
        settings += [(spec, True) for spec in orderings]
    error = None
    for spec, sym in settings:
        kw = dict(diag_pivot_thresh=0.0, options=dict(SymmetricMode=True)) if sym else {}
        try:
            lu = spla.splu(A, permc_spec=spec, **kw)
        except RuntimeError as exc:  # singular (or a zero diagonal pivot in symmetric mode)
            error = exc
            continue
        x = lu.solve(b)
        if not np.all(np.isfinite(x)):
            continue
        res = np.abs(A @ x - b).max() / max(np.abs(A).max() * np.abs(x).max(), 1e-300)
        if res > SOLVE_CHECK:
            continue
        nnz = lu.L.nnz + lu.U.nnz
        if best is None or nnz < best[0]:
            best = (nnz, spec + (" symmetric" if sym else ""), lu)
    if best is None:
        raise np.linalg.LinAlgError(f"sparse LU failed: {error}")
    _, spec, lu = best
    lp, li, lv, ld = _split_diag(lu.L)
    up, ui, uv, ud = _split_diag(lu.U)
    return LUFactors(
        lp, li, lv, ld, up, ui, uv, ud,
        np.ascontiguousarray(lu.perm_r, dtype=np.int64),
        np.ascontiguousarray(lu.perm_c, dtype=np.int64),
        lu, spec,
    )
