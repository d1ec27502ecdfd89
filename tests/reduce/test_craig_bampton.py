"""Craig–Bampton against closed forms: a spring–mass chain whose modes are known exactly."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from rubdiag.reduce import Reduction, craig_bampton

N, k, m = 12, 1e4, 0.5          # masses, spring (N/m), mass (kg)


def chain():
    """N equal masses between two walls: ω_j = 2 sqrt(k/m) sin(jπ / (2(N+1)))."""
    K = sp.diags([-k * np.ones(N - 1), 2 * k * np.ones(N), -k * np.ones(N - 1)], [-1, 0, 1])
    return sp.identity(N, format="csr") * m, K.tocsr()


def exact_hz():
    j = np.arange(1, N + 1)
    return 2 * np.sqrt(k / m) * np.sin(j * np.pi / (2 * (N + 1))) / (2 * np.pi)


def reduced_hz(basis, M, K):
    w2 = sla.eigh(basis.project(K), basis.project(M), eigvals_only=True)
    return np.sqrt(w2) / (2 * np.pi)


def test_all_modes_kept_reproduces_the_exact_frequencies():
    M, K = chain()
    basis = craig_bampton(M, K, [3, 8], cutoff_hz=1e9)
    assert basis.n_reduced == N
    np.testing.assert_allclose(reduced_hz(basis, M, K), exact_hz(), rtol=1e-10)


def test_truncated_basis_bounds_from_above_and_converges():
    # Rayleigh-Ritz: every reduced frequency is an upper bound of the exact one, and the
    # bound tightens as the cutoff rises
    M, K = chain()
    exact = exact_hz()
    errors = []
    for cutoff in (25.0, 30.0, 40.0):
        basis = craig_bampton(M, K, [5], cutoff)
        f = reduced_hz(basis, M, K)
        assert np.all(f >= exact[: f.size] * (1 - 1e-12))
        errors.append(f[1] / exact[1] - 1)
    assert errors[0] > errors[1] > errors[2] > 0


def test_static_flexibility_at_the_boundary_is_exact_without_any_mode():
    M, K = chain()
    boundary = [2, 9]
    basis = craig_bampton(M, K, boundary, cutoff_hz=1e-3)     # Guyan: no interior mode
    assert basis.n_reduced == 2 and basis.mode_frequencies_hz.size == 0
    flex_full = np.linalg.inv(K.toarray())[np.ix_(boundary, boundary)]
    np.testing.assert_allclose(np.linalg.inv(basis.project(K)), flex_full, rtol=1e-12)


def test_modes_are_mass_normalised_and_decoupled_in_stiffness():
    M, K = chain()
    basis = craig_bampton(M, K, [0, 11], cutoff_hz=60.0)
    nb = 2
    Mr, Kr = basis.project(M), basis.project(K)
    modal = slice(nb, None)
    np.testing.assert_allclose(Mr[modal, modal], np.eye(basis.n_reduced - nb), atol=1e-12)
    w2 = (2 * np.pi * basis.mode_frequencies_hz) ** 2
    np.testing.assert_allclose(Kr[modal, modal], np.diag(w2), rtol=1e-10, atol=1e-8 * w2.max())
    np.testing.assert_allclose(Kr[:nb, modal], 0.0, atol=1e-8 * k)   # constraint ⟂ modes in K
    assert basis.first_dropped_hz >= 60.0 > basis.mode_frequencies_hz.max()


def test_boundary_index_and_errors():
    M, K = chain()
    basis = craig_bampton(M, K, [7, 2], cutoff_hz=10.0)
    np.testing.assert_array_equal(basis.boundary, [2, 7])
    np.testing.assert_array_equal(basis.boundary_index([[7, -1], [2, 7]]), [[1, -1], [0, 1]])
    with pytest.raises(ValueError, match="not boundary DOFs"):
        basis.boundary_index([3])
    with pytest.raises(ValueError, match="boundary DOFs"):
        craig_bampton(M, K, [N], 10.0)
    with pytest.raises(ValueError, match="cutoff_hz"):
        craig_bampton(M, K, [1], 0.0)


@pytest.mark.parametrize("bad", [0.0, -5.0, float("nan"), 1e7])
def test_reduction_refuses_a_cutoff_out_of_range(bad):
    with pytest.raises(ValueError, match="cutoff_hz"):
        Reduction(cutoff_hz=bad)


def test_cutoff_from_the_features():
    r = Reduction.for_features(6840.0, max_order=8, margin=2)
    assert r.cutoff_hz == pytest.approx(2 * 8 * 6840 / 60)
    assert r.band_hz == pytest.approx(8 * 6840 / 60)
    assert Reduction().band_hz >= 8 * 6840 / 60      # the default covers the shipped designs
