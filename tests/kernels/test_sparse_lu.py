"""The sparse kernels against dense NumPy references."""

import numpy as np
import pytest
import scipy.sparse as sp

from rubdiag._kernels.sparse_lu import csr_matvec, factorize, lu_solve


def _random_sparse(n, density, seed, symmetric=False):
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=density, random_state=rng, format="csr")
    if symmetric:
        A = A + A.T
    # diagonally dominant -> nonsingular, plus a non-symmetric skew part (like Ω G)
    A = A + sp.diags(np.abs(A).sum(axis=1).A1 + 1.0)
    S = sp.random(n, n, density=density / 2, random_state=rng)
    return sp.csr_matrix(A + 0.3 * (S - S.T))


@pytest.mark.parametrize("symmetric_mode", [False, True])
@pytest.mark.parametrize("ordering", ["COLAMD", "MMD_AT_PLUS_A", "NATURAL"])
@pytest.mark.parametrize("seed", [0, 1])
def test_lu_solve_matches_dense_solve(ordering, seed, symmetric_mode):
    A = _random_sparse(60, 0.08, seed)
    f = factorize(A, orderings=(ordering,), symmetric_mode=symmetric_mode)
    b = np.random.default_rng(seed + 10).standard_normal(60)
    x = np.zeros(60)
    w = np.zeros(60)
    lu_solve(f.l_ptr, f.l_idx, f.l_val, f.l_dinv, f.u_ptr, f.u_idx, f.u_val, f.u_dinv,
             f.perm_r, f.perm_c, b, x, w)
    ref = np.linalg.solve(A.toarray(), b)
    np.testing.assert_allclose(x, ref, rtol=1e-11, atol=1e-12 * np.abs(ref).max())


def test_factorize_keeps_least_fill():
    A = _random_sparse(80, 0.05, 3, symmetric=True)
    best = factorize(A)
    for spec in ("COLAMD", "MMD_AT_PLUS_A"):
        assert best.nnz <= factorize(A, orderings=(spec,), symmetric_mode=False).nnz


def test_csr_matvec_matches_scipy():
    A = _random_sparse(50, 0.1, 4)
    x = np.random.default_rng(5).standard_normal(50)
    out = np.zeros(50)
    csr_matvec(A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data, x, out)
    np.testing.assert_allclose(out, A @ x, rtol=1e-13, atol=1e-13)


def test_factorize_singular_raises():
    A = sp.csr_matrix(np.array([[1.0, 2.0], [2.0, 4.0]]))
    with pytest.raises(np.linalg.LinAlgError):
        factorize(A)
