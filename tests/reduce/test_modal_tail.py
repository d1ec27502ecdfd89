"""The dense integrator skips what is exactly zero in a Craig–Bampton model's modal tail.

A Craig–Bampton model's fixed-interface modes do not couple to the boundary in K, nor to each
other in M and K; ``simulate_system`` finds that tail (``coupled``) and the kernel forms M dq
and K dq from the coupled block and the tail's diagonals only (``mk_dense``).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import ortho_group

from rubdiag._kernels.products import mk_dense
from rubdiag.simulation._kernel_args import coupled


def _craig_bampton_like(n_b: int, n_m: int, seed: int = 0):
    """Symmetric positive definite M, K with a modal tail of n_m coordinates."""
    rng = np.random.default_rng(seed)
    n = n_b + n_m
    A = rng.normal(size=(n, n))
    M = A @ A.T + n * np.eye(n)
    M[n_b:, n_b:] = np.eye(n_m)
    M[:n_b, :n_b] += 10.0 * n * np.eye(n_b)       # keeps M positive definite
    K = np.zeros((n, n))
    B = rng.normal(size=(n_b, n_b))
    K[:n_b, :n_b] = B @ B.T + n_b * np.eye(n_b)
    K[n_b:, n_b:] = np.diag(rng.uniform(1.0, 100.0, n_m) ** 2)
    return M, K


@pytest.mark.parametrize(("n_b", "n_m"), [(3, 5), (0, 4), (4, 0), (1, 1)])
def test_the_tail_is_found(n_b, n_m):
    M, K = _craig_bampton_like(n_b, n_m)
    assert coupled(M, K) == n_b


def test_one_coupling_entry_moves_the_tail():
    M, K = _craig_bampton_like(3, 5)
    K[2, 6] = K[6, 2] = 1e-300     # any nonzero couples: coordinate 6 and all before it
    assert coupled(M, K) == 7
    M2, K2 = _craig_bampton_like(3, 5)
    M2[5, 7] = M2[7, 5] = 0.1       # mass coupling between two modes: 5 joins the block,
    assert coupled(M2, K2) == 6    # 6 and 7 stay modal (M may couple block and tail)


@pytest.mark.parametrize("n_b", [0, 3, 8])
def test_products_equal_the_full_products(n_b):
    M, K = _craig_bampton_like(n_b, 8 - n_b, seed=n_b)
    dq = np.random.default_rng(1).normal(size=8)
    mdq, kdq = np.empty(8), np.empty(8)
    mk_dense(coupled(M, K), M, K, dq, mdq, kdq)
    np.testing.assert_allclose(mdq, M @ dq, rtol=1e-13)
    np.testing.assert_allclose(kdq, K @ dq, rtol=1e-13)


def test_a_run_does_not_depend_on_the_coordinates():
    # the same system in coordinates that mix the tail (no exact zeros: the plain dense
    # products) gives the same motion, recovered
    from rubdiag.simulation import HarmonicForce, LinearSystem, Solver, TimeGrid, simulate_system

    M, K = _craig_bampton_like(2, 4, seed=3)
    C = 1e-3 * K + 0.5 * M
    Q = np.eye(6)
    Q[2:, 2:] = ortho_group.rvs(4, random_state=4)
    f = np.array([1.0, 0.3, 0.0, 0.0, 0.0, 0.0])
    force = HarmonicForce(np.arange(6), f, 7.0)
    mixed = [np.ascontiguousarray(Q.T @ X @ Q) for X in (M, C, K)]
    assert coupled(mixed[0], mixed[2]) == 6
    grid = TimeGrid(duration=0.5, dt=1e-3, fixed_step=True)
    dense = Solver(linear_solver="dense")
    tail = simulate_system(LinearSystem(M=M, C=C, K=K, force=force), None, grid, solver=dense)
    plain = simulate_system(LinearSystem(M=mixed[0], C=mixed[1], K=mixed[2], recovery=Q,
                                         force=HarmonicForce(np.arange(6), Q.T @ f, 7.0)),
                            None, grid, solver=dense)
    scale = np.abs(tail.q).max()
    np.testing.assert_allclose(plain.q, tail.q, rtol=0, atol=1e-10 * scale)


def test_the_paper_rig_reduction_has_an_exact_tail_and_lost_only_round_off():
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh
    from rubdiag.model import paper_rig
    from rubdiag.reduce import reduced_model
    from rubdiag.reduce._reduced import _symmetric

    rig = paper_rig()
    reduced = reduced_model(rig)
    n_b = reduced.basis.boundary.size
    assert coupled(reduced.M, reduced.K) == n_b
    model = with_rayleigh(assemble(rig))
    for exact, full in ((reduced.M, model.M), (reduced.K, model.K)):
        projected = _symmetric(reduced.basis.project(full))
        # eigh's round-off in Φᵀ K_ii Φ: 0.6-1.2e-11 of K's largest diagonal entry (it
        # depends on the BLAS kernels); a coupling the theory did not zero would be O(1)
        assert np.abs(exact - projected).max() <= 5e-11 * np.abs(np.diag(projected)).max()
