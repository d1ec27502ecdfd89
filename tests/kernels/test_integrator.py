"""The Newmark integrator without contact, and a mass striking a spring stop."""

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse as sp

from rubdiag.simulation import (
    HarmonicForce,
    LinearSystem,
    PointContact,
    Recording,
    Solver,
    TimeGrid,
    simulate_system,
)


def _chain(n=6, m=0.5, k=2e5, c_alpha=0.0, c_beta=0.0):
    """Spring-mass chain fixed at one end (SPD K, diagonal M), Rayleigh damping."""
    K = sp.diags([-k * np.ones(n - 1), 2 * k * np.ones(n), -k * np.ones(n - 1)], [-1, 0, 1])
    K = K.tolil()
    K[n - 1, n - 1] = k
    K = sp.csr_matrix(K)
    M = sp.diags(m * (1 + 0.3 * np.arange(n))).tocsr()
    C = sp.csr_matrix(c_alpha * M + c_beta * K)
    return M, C, K


def test_undamped_free_vibration_conserves_energy_to_roundoff():
    M, C, K = _chain()
    rng = np.random.default_rng(0)
    q0 = rng.standard_normal(6) * 1e-3
    v0 = rng.standard_normal(6) * 0.1
    res = simulate_system(LinearSystem(M=M, C=C, K=K, q0=q0, v0=v0), None,
                          TimeGrid(duration=0.2, dt=1e-4, output_dt=1e-3))
    e = res.kinetic + res.strain
    assert np.ptp(e) / e[0] < 1e-12
    # the step never changed (nothing to resolve)
    assert res.steps_per_level[0] == res.n_steps == 2000


def test_steady_harmonic_response_matches_analytic():
    M, C, K = _chain(c_alpha=30.0, c_beta=2e-5)
    # add a gyroscopic-like skew part: it must not spoil the response
    G = sp.csr_matrix(([3.0, -3.0], ([1, 2], [2, 1])), shape=(6, 6))
    C = sp.csr_matrix(C + G)
    w = 250.0
    force = HarmonicForce([2, 5], [40.0, -15j], [w, w])
    F = np.zeros(6, complex)
    F[2], F[5] = 40.0, -15j
    U = np.linalg.solve((K - w**2 * M + 1j * w * C).toarray(), F)
    # start at rest; the transient (slowest decay ~ 1/(alpha/2) = 0.07 s) dies out
    period = 2 * np.pi / w
    dt = period / 200
    res = simulate_system(LinearSystem(M=M, C=C, K=K, force=force), None,
                          TimeGrid(duration=60 * period, dt=dt, output_dt=dt))
    last = res.t >= res.t[-1] - 10 * period
    t = res.t[last]
    basis = np.c_[np.cos(w * t), -np.sin(w * t)]
    coef, *_ = np.linalg.lstsq(basis, res.q[last], rcond=None)
    U_num = coef[0] + 1j * coef[1]
    err = np.abs(U_num - U) / np.abs(U).max()
    assert err.max() < 5e-3, err.max()


def _exact_forced(M, C, K, F, w, q0, v0, T):
    """Exact state at T of M q'' + C q' + K q = Re(F e^{iwt}) by the matrix exponential of the
    first-order system augmented with the (cos, sin) oscillator."""
    n = M.shape[0]
    Mi = np.linalg.inv(M)
    A = np.zeros((2 * n + 2, 2 * n + 2))
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -Mi @ K
    A[n : 2 * n, n : 2 * n] = -Mi @ C
    A[n : 2 * n, 2 * n] = Mi @ F.real  # f = Re(F) cos - Im(F) sin
    A[n : 2 * n, 2 * n + 1] = -Mi @ F.imag
    A[2 * n, 2 * n + 1] = -w  # c' = -w s, s' = w c
    A[2 * n + 1, 2 * n] = w
    x0 = np.r_[q0, v0, 1.0, 0.0]
    return (sl.expm(A * T) @ x0)[:n]


def test_fixed_step_convergence_is_second_order():
    M, C, K = _chain(c_alpha=5.0, c_beta=1e-5)
    w = 400.0
    F = np.zeros(6, complex)
    F[3] = 25.0 + 10j
    force = HarmonicForce([3], [25.0 + 10j], [w])
    q0 = np.linspace(0, 1e-4, 6)
    v0 = np.full(6, 0.01)
    T = 0.05
    exact = _exact_forced(M.toarray(), C.toarray(), K.toarray(), F, w, q0, v0, T)
    errs = []
    dts = [2e-4, 1e-4, 5e-5, 2.5e-5]
    for dt in dts:
        res = simulate_system(LinearSystem(M=M, C=C, K=K, force=force, q0=q0, v0=v0), None,
                              TimeGrid(duration=T, dt=dt, fixed_step=True, output_dt=T))
        errs.append(np.abs(res.q_final - exact).max())
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.15), orders


@pytest.mark.parametrize("mode", ["fixed", "variable"])
def test_mass_striking_spring_stop_contact_duration(mode):
    """A free mass (K = 0 in the contact direction) at v0 hits a penalty stop: the contact
    lasts π/ω_c, ω_c = sqrt(k_N/m), and it rebounds with -v0 (no damping)."""
    m, kn, v_in, g0 = 0.2, 5e6, 0.8, 1e-3
    wc = np.sqrt(kn / m)
    T_c = np.pi / wc
    M = sp.diags([m, m]).tocsr()
    K = sp.diags([0.0, 1e3]).tocsr()  # only the z DOF has a spring: y is free
    C = sp.csr_matrix((2, 2))
    ct = [PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=g0, k_n=kn,
                       mu=0.0)]
    duration = g0 / v_in + 3 * T_c
    if mode == "fixed":
        grid, solver = TimeGrid(duration=duration, dt=T_c / 100, fixed_step=True), Solver()
    else:
        # the largest step spans half the contact: the step control must refine
        grid = TimeGrid(duration=duration, dt=T_c / 2, dt_min=T_c / 2**10)
        solver = Solver(gap_jump=1e-6)
    res = simulate_system(LinearSystem(M=M, C=C, K=K, v0=np.array([v_in, 0.0])), ct, grid,
                          solver=solver)
    ep = res.episodes
    assert len(ep) == 1 and ep.complete[0]
    assert abs(ep.duration[0] - T_c) / T_c < 0.01, ep.duration[0] / T_c
    assert res.v_final[0] == pytest.approx(-v_in, rel=0.01)
    assert res.max_normal_force[0] == pytest.approx(kn * v_in / wc, rel=0.01)
    if mode == "variable":
        assert res.n_rejected_abrupt + res.n_rejected_newton > 0
        assert res.steps_per_level[1:].sum() > 0


def test_numerical_damping_gamma_dissipates_and_is_first_order():
    """γ > 1/2 (β = (γ + 1/2)²/4): the undamped free vibration loses energy monotonically,
    and the fixed-step error falls as dt (first order) instead of dt²."""
    M, C, K = _chain()
    rng = np.random.default_rng(1)
    q0 = rng.standard_normal(6) * 1e-3
    v0 = np.zeros(6)
    system = LinearSystem(M=M, C=C, K=K, q0=q0, v0=v0)
    res = simulate_system(system, None, TimeGrid(duration=0.05, dt=1e-4, output_dt=1e-4),
                          solver=Solver(gamma=0.6))
    e = res.kinetic + res.strain
    assert np.all(np.diff(e) <= 1e-15 * e[0]) and e[-1] < 0.9 * e[0]
    assert np.abs(res.dissipated_viscous).max() < 1e-9 * e[0]  # C = 0: round-off only
    exact = _exact_forced(M.toarray(), C.toarray(), K.toarray(), np.zeros(6, complex), 0.0,
                          q0, v0, 0.05)
    errs = [
        np.abs(simulate_system(system, None, TimeGrid(duration=0.05, dt=dt, fixed_step=True,
                                                      output_dt=0.05),
                               solver=Solver(gamma=0.6)).q_final - exact).max()
        for dt in (5e-5, 2.5e-5, 1.25e-5)
    ]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 1.0) < 0.25), orders


def test_result_frame_and_final_state():
    M, C, K = _chain(c_alpha=5.0)
    res = simulate_system(LinearSystem(M=M, C=C, K=K, force=HarmonicForce([0], [1.0], [100.0])),
                          None, TimeGrid(duration=0.01, dt=1e-4, output_dt=1e-3),
                          Recording(record_dofs=[1, 4]))
    df = res.to_frame()
    assert list(df.columns[:2]) == ["q_1", "q_4"] and len(df) == 11
    np.testing.assert_allclose(df.index.to_numpy(), np.arange(11) * 1e-3, rtol=1e-12)
    np.testing.assert_array_equal(res.q[-1], res.q_final[[1, 4]])
    assert res.t_final == pytest.approx(0.01)
    assert res.success and res.status == 0 and np.isnan(res.failure_time)
