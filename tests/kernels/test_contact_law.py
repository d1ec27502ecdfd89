"""Contact-law kernels against their definition and one step against a NumPy reference."""

import numpy as np
import pytest
import scipy.optimize as so
import scipy.sparse as sp

from rubdiag._kernels import annular_contact, point_contact
from rubdiag._kernels.records import OPEN, SLIDING, STICKING
from rubdiag.simulation import (
    AnnularContact,
    HarmonicForce,
    LinearSystem,
    PointContact,
    Solver,
    TimeGrid,
    simulate_system,
)
from rubdiag.simulation._kernel_args import b_matrix

KN, KT = 1e7, 5e6


def element_law(kind, x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n, drive):
    """Kind 1's or kind 2's force law (the surface travel ``drive`` is kind 2's)."""
    if kind == point_contact.KIND:
        return point_contact.force(x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n)
    return annular_contact.force(x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n, drive)


def law1(x0, x1, x0n, x1n, g0, mu, lam=0.0, e_n=0.0):
    return element_law(1, x0, x1, x0n, x1n, g0, KN, KT, mu, lam, e_n, 0.0)


def test_point_open_gives_no_force():
    out = law1(0.5e-4, 3e-4, 0.0, 0.0, 1e-4, 0.3)
    assert out[6] == OPEN
    assert out[0:2] == (0.0, 0.0)
    assert out[7] == 0.0 and out[8] == 0.0
    assert out[11] == pytest.approx(0.5e-4)


def test_point_penalty_normal_force_is_eq1():
    # g = 1e-4 - 1.2e-4 = -2e-5  ->  F_N = -k_N g = 200 N, pushing a back along -n
    out = law1(1.2e-4, 0.0, 1.2e-4, 0.0, 1e-4, 0.3)
    assert out[7] == pytest.approx(200.0)
    assert out[0] == pytest.approx(-200.0)
    assert out[11] == pytest.approx(-2e-5)
    # a multiplier adds to the force (eq. 1 with λ)
    out = law1(1.2e-4, 0.0, 1.2e-4, 0.0, 1e-4, 0.3, lam=50.0)
    assert out[7] == pytest.approx(250.0)


def test_point_stick_then_slip():
    # tangential move 1e-6 m: trial |F_T| = 5 N <= 0.3 * 200 -> stick, F_T = -k_T Δs
    out = law1(1.2e-4, 1e-6, 1.2e-4, 0.0, 1e-4, 0.3)
    assert out[6] == STICKING
    assert out[8] == pytest.approx(-5.0)
    # tangential move 1e-4 m: trial 500 N > 60 N -> slide at -mu F_N sign(Δs)
    out = law1(1.2e-4, 1e-4, 1.2e-4, 0.0, 1e-4, 0.3)
    assert out[6] == SLIDING
    assert out[8] == pytest.approx(-60.0)
    assert out[9] == pytest.approx(60.0 / KT)  # elastic part left after the return
    # frictionless contact always slides with F_T = 0
    out = law1(1.2e-4, 1e-6, 1.2e-4, 0.0, 1e-4, 0.0)
    assert out[6] == SLIDING and out[8] == 0.0


@pytest.mark.parametrize("kind", [1, 2])
@pytest.mark.parametrize("tang", [2e-7, 3e-5])  # stick and slip
def test_jacobian_matches_finite_differences(kind, tang):
    x0n, x1n = 0.8e-3, 0.6e-3  # annular: r_n = 1 mm
    x = np.array([x0n + 2e-5, x1n + tang])
    g0 = 1e-3 if kind == 2 else 0.8e-3
    args = (x0n, x1n, g0, KN, KT, 0.4, 0.0, 1e-7, 0.0)
    out = element_law(kind, x[0], x[1], *args)
    assert out[6] != OPEN
    J = np.array([[out[2], out[3]], [out[4], out[5]]])
    h = 1e-10
    Jfd = np.zeros((2, 2))
    for c in range(2):
        xp = x.copy()
        xm = x.copy()
        xp[c] += h
        xm[c] -= h
        fp = element_law(kind, xp[0], xp[1], *args)
        fm = element_law(kind, xm[0], xm[1], *args)
        Jfd[:, c] = (np.array(fp[0:2]) - np.array(fm[0:2])) / (2 * h)
    np.testing.assert_allclose(J, Jfd, rtol=1e-4, atol=1e-4 * np.abs(Jfd).max())


def test_annular_friction_opposes_surface_speed():
    # shaft at rest radially, clearance closed: surface travel Ω R dt > 0 -> F_T < 0
    out = element_law(2, 1.01e-3, 0.0, 1.01e-3, 0.0, 1e-3, KN, KT, 0.2, 0.0, 0.0, 1e-4)
    assert out[6] == SLIDING
    assert out[7] == pytest.approx(100.0)
    assert out[8] == pytest.approx(-20.0)
    # force on the shaft: -F_N n + F_T t with n = (1, 0), t = (0, 1)
    assert out[0] == pytest.approx(-100.0)
    assert out[1] == pytest.approx(-20.0)


# ------------------------------------------------------------------------------------------
# one Newmark step with contact against a slow NumPy reference (full-size, standard form)
# ------------------------------------------------------------------------------------------
def _py_law(kind, x, xn, g0, kn, kt, mu, e_n, drive):
    """The contact law written again from its definition (pure Python)."""
    if kind == 1:
        gap = g0 - x[0]
        if gap >= 0:
            return np.zeros(2)
        fn = -kn * gap
        e_tr = e_n + (x[1] - xn[1])
        ft = -kt * e_tr
        if not (mu > 0 and abs(ft) <= mu * fn):
            ft = -mu * fn * np.sign(e_tr)
        return np.array([-fn, ft])
    r = np.hypot(*x)
    gap = g0 - r
    if gap >= 0:
        return np.zeros(2)
    fn = -kn * gap
    n = x / r
    t = np.array([-n[1], n[0]])
    e_tr = e_n + t @ (x - xn) + drive
    ft = -kt * e_tr
    if not (mu > 0 and abs(ft) <= mu * fn):
        ft = -mu * fn * np.sign(e_tr)
    return -fn * n + ft * t


def _system(n=7, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    K = A @ A.T * 1e4 + np.eye(n) * 1e5
    M = np.diag(rng.uniform(0.05, 0.5, n))
    G = rng.standard_normal((n, n))
    C = 0.01 * K / 1e3 + 2.0 * M + 0.5 * (G - G.T)
    return M, C, K


@pytest.mark.parametrize("mu", [0.0, 0.2, 5.0])
@pytest.mark.parametrize("kind, centre", [(1, None), (2, None), (2, (3e-5, -8e-5))])
def test_one_step_matches_full_newton_reference(kind, centre, mu):
    M, C, K = _system()
    n = M.shape[0]
    h = 2e-4
    if kind == 1:
        th = 0.4
        contacts = [
            PointContact(dof_a=(0, 1), dof_b=(4, 5), normal=(np.cos(th), np.sin(th)),
                         tangent=(-np.sin(th), np.cos(th)), gap=1e-4, k_n=3e6, k_t=2e6,
                         mu=mu),
            PointContact(dof_a=(2, 3), normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=2e-4,
                         k_n=8e6, k_t=1e6, mu=mu),
        ]
    else:
        # an off-centre clearance (a stator aligned on a displaced rotor) measures the
        # displacement from its centre
        contacts = [AnnularContact(dof_a=dofs, clearance=gap, radius=0.02, k_n=k_n, k_t=k_t,
                                   mu=mu, centre=centre or (0.0, 0.0))
                    for dofs, gap, k_n, k_t in (((0, 1), 1e-4, 3e6, 2e6),
                                                ((2, 3), 2e-4, 8e6, 1e6))]
    c = np.zeros(2) if centre is None else np.array(centre)
    omega = 50.0
    rng = np.random.default_rng(1)
    q0 = rng.uniform(-1e-5, 1e-5, n)
    v0 = np.zeros(n)
    v0[[0, 1, 2, 3]] = [0.9, 0.5, 1.4, -0.6]  # drives both elements deep into contact
    force = HarmonicForce([0, 3], [20.0 + 5j, -7.0], [300.0, 300.0])
    res = simulate_system(
        LinearSystem(M=sp.csr_matrix(M), C=sp.csr_matrix(C), K=sp.csr_matrix(K), force=force,
                     q0=q0, v0=v0, omega=omega),
        contacts, TimeGrid(duration=h, dt=h, fixed_step=True), solver=Solver(newton_tol=1e-16),
    )
    assert np.all(res.contact_status[-1] != OPEN)  # the step really closes both
    # reference: Newmark (β = 1/4, γ = 1/2) in standard form, all n unknowns, scipy root
    B = b_matrix([el.pack(0.0) for el in contacts], n)
    a0 = np.linalg.solve(M, force.evaluate(0.0, n) - C @ v0 - K @ q0)
    keff = K + 2 / h * C + 4 / h**2 * M
    rhs = force.evaluate(h, n) + M @ (4 / h**2 * q0 + 4 / h * v0 + a0) + C @ (2 / h * q0 + v0)
    dn = B @ q0

    def resid(q):
        d = B @ q
        p = np.concatenate([
            _py_law(el.kernel.KIND, d[2 * e : 2 * e + 2] - c, dn[2 * e : 2 * e + 2] - c,
                    el.gap, el.k_n, el.k_t, mu, 0.0, omega * getattr(el, "radius", 0.0) * h)
            for e, el in enumerate(contacts)
        ])
        return (keff @ q - rhs - B.T @ p) / np.abs(np.diag(keff))

    sol = so.root(resid, res.q_final, method="hybr", options={"xtol": 1e-14})
    assert np.abs(resid(sol.x)).max() < 1e-14
    np.testing.assert_allclose(res.q_final, sol.x, rtol=0, atol=1e-10 * np.abs(sol.x).max())
    # and the kernel's own state satisfies the reference equations
    assert np.abs(resid(res.q_final)).max() < 1e-11
