"""The kernels against their plain NumPy twins (tests/naive.py) on seeded random inputs: the
contact laws, the sparse LU solve and one Newmark step."""

from __future__ import annotations

import naive
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag._kernels import annular_contact, point_contact, records
from rubdiag._kernels.elements import N_LOCAL_MAX
from rubdiag._kernels.increment import load_increment, new_state, rhs_average, rhs_general
from rubdiag._kernels.load import LAW_CONSTANT, load_factors
from rubdiag._kernels.products import mk_products
from rubdiag._kernels.sparse_lu import factorize, lu_solve

EPS = np.finfo(float).eps
#: The laws: a few operations on numbers of one scale, so kernel and twin differ by a few
#: rounding errors, in the order they take them; 1e-12 of the scale is thousands of those,
#: and a wrong term is a difference of order 1.
LAW_RTOL = 1e-12
#: Samples this close (relative) to contact or to the friction cone's edge are left out:
#: there round-off decides the status, in either code.
EDGE = 1e-9
N_SAMPLES = 2000
#: A linear solve's error bound: |δx| <= c n ε κ(A) |x| for a backward-stable LU (the
#: factors' growth is small for these diagonally dominant matrices); c n = 100.
SOLVE_C = 100.0


def _contact_samples(annular, seed):
    """Displacements (m) across open, sticking and sliding contacts, and the law's
    parameters: an annular clearance of 1 mm, a point gap of 0.1 mm."""
    rng = np.random.default_rng(seed)
    n = N_SAMPLES
    if annular:
        angle = rng.uniform(0.0, 2 * np.pi, n)
        radius = 1e-3 + rng.uniform(-3e-5, 6e-5, n)
        x = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
        gap0 = 1e-3
    else:
        x = np.column_stack([1e-4 + rng.uniform(-3e-5, 6e-5, n), rng.uniform(-1e-4, 1e-4, n)])
        gap0 = 1e-4
    return dict(x=x, x_start=x + rng.normal(0.0, 2e-6, (n, 2)), gap0=gap0,
                k_n=rng.uniform(1e6, 1e8), k_t=rng.uniform(1e6, 1e8),
                mu=[0.0, 0.1, 0.5, 2.0][seed % 4], lam=[0.0, 30.0][seed // 4 % 2],
                e_start=rng.normal(0.0, 3e-7, n), travel=rng.uniform(-2e-6, 2e-6))


def _kernel_law(annular, s):
    """The kernel's law at every sample, stacked as the twin's :class:`naive.Law`."""
    rows = []
    for i in range(N_SAMPLES):
        x, xs = s["x"][i], s["x_start"][i]
        args = (x[0], x[1], xs[0], xs[1], s["gap0"], s["k_n"], s["k_t"], s["mu"], s["lam"],
                s["e_start"][i])
        rows.append(annular_contact.force(*args, s["travel"]) if annular
                    else point_contact.force(*args))
    out = np.array(rows)
    return naive.Law(out[:, 0:2], out[:, 6].astype(int), out[:, 7], out[:, 8], out[:, 9],
                     out[:, 10], out[:, 11])


def _twin_law(annular, s):
    args = (s["x"], s["x_start"], s["gap0"], s["k_n"], s["k_t"], s["mu"], s["lam"],
            s["e_start"])
    return naive.annular_contact(*args, s["travel"]) if annular else naive.point_contact(*args)


def _away_from_edges(twin, s):
    """Samples whose status round-off cannot decide: not at contact (λ - k_N g = 0) and not
    on the cone (|k_T e_trial| = μ F_N)."""
    z = s["lam"] - s["k_n"] * twin.gap
    at_contact = np.abs(z) <= EDGE * (s["lam"] + s["k_n"] * np.abs(twin.gap))
    trial, cone = np.abs(s["k_t"] * twin.e_trial), s["mu"] * twin.f_n
    on_cone = np.abs(trial - cone) <= EDGE * np.maximum(trial, cone)
    return ~at_contact & ~on_cone


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("annular", [False, True], ids=["point", "annular"])
def test_contact_law_equals_its_twin(annular, seed):
    """Status, forces, the new and the trial elastic slip and the gap of the kernel's law are
    the twin's, sample by sample, across open, sticking and sliding contacts (four friction
    coefficients, with and without a multiplier)."""
    s = _contact_samples(annular, seed)
    twin = _twin_law(annular, s)
    keep = _away_from_edges(twin, s)
    assert keep.mean() > 0.99
    expected = {records.OPEN, records.SLIDING} | ({records.STICKING} if s["mu"] else set())
    assert set(twin.status[keep].tolist()) == expected
    got = _kernel_law(annular, s)
    np.testing.assert_array_equal(got.status[keep], twin.status[keep])
    engaged = keep & (twin.status != records.OPEN)     # (an open law has no trial slip)
    for name, scale, where in (("p", twin.f_n, keep), ("f_n", twin.f_n, keep),
                               ("f_t", twin.f_n, keep), ("e", twin.e_trial, keep),
                               ("e_trial", twin.e_trial, engaged), ("gap", twin.gap, keep)):
        atol = LAW_RTOL * np.abs(scale[keep]).max()
        np.testing.assert_allclose(getattr(got, name)[where], getattr(twin, name)[where],
                                   rtol=0, atol=atol, err_msg=name)


def _sparse_system(n, seed):
    """A sparse, diagonally dominant, non-symmetric matrix (a stiffness with a gyroscopic
    skew part) and a right-hand side."""
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.05, random_state=rng, format="csr")
    A = A + A.T + sp.diags(np.abs(A).sum(axis=1).A1 * 1.5 + rng.uniform(0.1, 1.0, n))
    S = sp.random(n, n, density=0.02, random_state=rng)
    return sp.csr_matrix(A + 0.3 * (S - S.T)), rng.standard_normal(n)


@pytest.mark.parametrize("symmetric_mode", [False, True])
@pytest.mark.parametrize("seed", range(3))
def test_lu_solve_equals_its_twin_and_scipy(seed, symmetric_mode):
    """The kernel's substitutions with SuperLU's factors solve A x = b as the twin's dense
    triangular solves with the same factors and as SciPy's spsolve do, within the error
    bound of a backward-stable solve, c n ε κ(A)."""
    n = 80
    A, b = _sparse_system(n, seed)
    factors = factorize(A, symmetric_mode=symmetric_mode)
    x = np.zeros(n)
    lu_solve(factors.l_ptr, factors.l_idx, factors.l_val, factors.l_dinv, factors.u_ptr,
             factors.u_idx, factors.u_val, factors.u_dinv, factors.perm_r, factors.perm_c, b,
             x, np.zeros(n))
    bound = SOLVE_C * n * EPS * np.linalg.cond(A.toarray())
    for reference in (naive.lu_solve(factors, b), spla.spsolve(A.tocsc(), b)):
        assert np.abs(x - reference).max() <= bound * np.abs(reference).max()
    # and a wrong solve would be caught: the residual is at round-off
    assert np.abs(A @ x - b).max() <= bound * np.abs(b).max()


def _structure(n, seed):
    """M, C, K of a random structure: M positive diagonal-dominant, K positive definite, C
    Rayleigh damping plus a gyroscopic (skew) part."""
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    K = B @ B.T * 1e4 + np.eye(n) * 1e5
    L = rng.uniform(-0.02, 0.02, (n, n))
    M = np.diag(rng.uniform(0.1, 1.0, n)) + L @ L.T
    G = rng.standard_normal((n, n))
    C = 2.0 * M + 1e-4 * K + 0.5 * (G - G.T)
    return M, C, K, rng


def _load(n, rng, omega):
    """A harmonic load of one group at constant speed ω: f(t) = Re(F e^{iωt}) on some DOFs,
    as the kernel takes it (terms, group law, speed knot) and as the twin evaluates it."""
    dofs = np.sort(rng.choice(n, 4, replace=False)).astype(np.int64)
    amp = rng.normal(0.0, 50.0, 4) + 1j * rng.normal(0.0, 50.0, 4)
    terms = (dofs, amp.real.copy(), amp.imag.copy(), np.zeros(4, np.int64))
    laws = np.array([[omega, 1.0, LAW_CONSTANT]])
    tables = np.zeros((1, 2, 2))
    knots = np.array([[0.0, omega, 0.0]])

    def f(t):
        out = np.zeros(n)
        out[dofs] = (amp * np.exp(1j * omega * t)).real
        return out

    return terms, laws, tables, knots, f


def _csr(A):
    A = sp.csr_matrix(A)
    return A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data


@pytest.mark.parametrize(("beta", "gamma"), [(0.25, 0.5), (0.3025, 0.6)])
@pytest.mark.parametrize("seed", range(3))
def test_newmark_step_equals_its_twin(seed, beta, gamma):
    """One step of the kernel's incremental form — the right-hand side (average
    acceleration's without products, or the general one), the LU solve, M dq and K dq in one
    pass, the new state — lands where the textbook form of the step does, from a state in
    equilibrium, within the solve's error bound (c n ε κ(K_eff) of the state's scale, the
    acceleration's scale being that of its largest term)."""
    n = 12
    M, C, K, rng = _structure(n, seed)
    h, t_n, omega = 2e-4, 0.013, 350.0
    terms, laws, tables, knots, f = _load(n, rng, omega)
    q = rng.normal(0.0, 1e-4, n)
    v = rng.normal(0.0, 1e-2, n)
    a = np.linalg.solve(M, f(t_n) - C @ v - K @ q)      # equilibrium at the step's start
    q1, v1, a1 = naive.newmark_step(M, C, K, f(t_n + h), q, v, a, h, beta, gamma)

    k_eff = K + gamma / (beta * h) * C + M / (beta * h * h)
    factors = factorize(sp.csc_matrix(k_eff))
    run = np.zeros(1, records.RUN)
    run["beta"], run["gamma"] = beta, gamma
    group_factors = np.zeros((1, 4))
    load_factors(laws, tables, knots, t_n, t_n + h, group_factors)
    no_elements = (np.zeros(0, records.ELEMENT), np.zeros((0, 3), np.int64),
                   np.zeros((0, N_LOCAL_MAX)))
    momentum, elastic_force = M @ v, K @ q
    rhs, dq, work = np.zeros(n), np.zeros(n), np.zeros(n)
    if beta == 0.25 and gamma == 0.5:
        rhs_average(h, momentum, elastic_force, np.zeros(0), *terms, group_factors,
                    *no_elements, rhs)
    else:
        rhs_general(run, h, v, a, *_csr(M), *_csr(C), np.zeros(n), np.zeros(n), rhs)
        load_increment(*terms, group_factors, rhs)
    lu_solve(factors.l_ptr, factors.l_idx, factors.l_val, factors.l_dinv, factors.u_ptr,
             factors.u_idx, factors.u_val, factors.u_dinv, factors.perm_r, factors.perm_c,
             rhs, dq, work)
    full = sp.csr_matrix(np.ones((n, n)))       # the union pattern of dense M and K
    m_dq, k_dq = np.zeros(n), np.zeros(n)
    dvisc = mk_products(beta, gamma, h, full.indptr.astype(np.int64),
                        full.indices.astype(np.int64), M.ravel(), K.ravel(), dq, rhs, m_dq,
                        k_dq)
    q_k, v_k, a_k = q.copy(), v.copy(), a.copy()
    new_state(beta, gamma, h, dq, m_dq, k_dq, q_k, v_k, a_k, momentum, elastic_force)

    tol = SOLVE_C * n * EPS * np.linalg.cond(k_eff)
    assert np.abs(q_k - q1).max() <= tol * np.abs(q1).max()
    assert np.abs(v_k - v1).max() <= tol * np.abs(v1).max()
    a_scale = max(np.abs(dq).max() / (beta * h * h), np.abs(v).max() / (beta * h),
                  np.abs(a).max())
    assert np.abs(a_k - a1).max() <= tol * a_scale
    # the tracked K q and, for average acceleration, M v (= 2/h M dq - M v_n) follow the
    # state, to the scale of their terms
    assert np.abs(elastic_force - K @ q_k).max() <= tol * np.abs(K @ q).max()
    if gamma == 0.5:
        mv_scale = max(2.0 / h * np.abs(M @ dq).max(), np.abs(M @ v).max())
        assert np.abs(momentum - M @ v_k).max() <= tol * mv_scale
    # the step's viscous dissipation dqᵀ C dq, from C dq = (rhs - K dq - M dq / (β h²)) β h / γ:
    # to the scale of those terms
    dq1 = q1 - q
    terms_scale = (np.abs(dq) @ (np.abs(rhs) + np.abs(K @ dq) + np.abs(M @ dq) / (beta * h * h))
                   * beta * h / gamma)
    assert abs(dvisc - dq1 @ C @ dq1) <= tol * terms_scale
