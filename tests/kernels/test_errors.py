"""Bad input is refused with a message naming the parameter; failures keep partial results."""

import numpy as np
import pytest
import scipy.sparse as sp

from rubdiag.simulation import (
    AnnularContact,
    HarmonicForce,
    LinearSystem,
    PointContact,
    Recording,
    SimulationDiverged,
    Solver,
    TimeGrid,
    simulate_system,
)


def _contact(**kw):
    return PointContact(**{"dof_a": (0, 1), "normal": (1.0, 0.0), "tangent": (0.0, 1.0),
                           "gap": 1e-4, "k_n": 1e7, **kw})


def _base():
    M = sp.diags([1.0, 1.0, 0.5]).tocsr()
    K = sp.csr_matrix(np.array([[2e4, -1e4, 0], [-1e4, 2e4, -1e4], [0, -1e4, 1e4]]))
    C = sp.csr_matrix(1e-4 * K)
    return M, C, K, [_contact()]


def _run(system=(), grid=(), outputs=(), solver=(), elements=None, gap_ramp=None):
    """The base system's run with the fields of its described objects changed."""
    M, C, K, ct = _base()
    return simulate_system(LinearSystem(**{"M": M, "C": C, "K": K, **dict(system)}),
                           ct if elements is None else elements,
                           TimeGrid(**{"duration": 1e-3, "dt": 1e-4, **dict(grid)}),
                           Recording(**dict(outputs)), solver=Solver(**dict(solver)),
                           gap_ramp=gap_ramp)


@pytest.mark.parametrize(
    ("over", "pattern"),
    [
        (dict(grid=dict(dt=0.0)), r"dt = 0\.0 .*> 0"),
        (dict(grid=dict(dt=-1e-5)), r"dt = -1e-05"),
        (dict(grid=dict(dt=float("nan"))), r"dt = nan"),
        (dict(grid=dict(dt_min=2e-4)), r"dt_min = 0\.0002 .*<= dt = 0\.0001"),
        (dict(grid=dict(dt_min=0.0)), r"dt_min = 0\.0"),
        (dict(grid=dict(duration=5e-5)), r"duration = 5e-05 .*>= one step dt = 0\.0001"),
        (dict(grid=dict(output_dt=1.5e-4)), r"output_dt = 0\.00015 .*integer multiple of dt"),
        (dict(elements=[_contact(dof_a=(0, 7))]), r"elements\[0\] DOFs = \[0, 7\]"),
        (dict(elements=[_contact(), _contact(dof_b=(3, 1))]),
         r"elements\[1\] DOFs = \[0, 1, 3, 1\] .*\[0, 3\)"),
        (dict(elements=[(0, 1)]), r"elements\[0\] = .*wrong type"),
        (dict(system=dict(q0=np.array([0.0, np.nan, 0.0]))), r"q0 = .*non-finite"),
        (dict(system=dict(v0=np.array([0.0, np.inf, 0.0]))), r"v0 = .*non-finite"),
        (dict(system=dict(q0=np.zeros(4))), r"q0 has shape \(4,\)"),
        (dict(system=dict(K=sp.csr_matrix(np.full((3, 3), np.nan)))), r"K contains NaN or inf"),
        (dict(system=dict(M=sp.diags([1.0, np.inf, 1.0]).tocsr())), r"M contains NaN or inf"),
        (dict(system=dict(C=sp.csr_matrix((4, 4)))), r"C has shape \(4, 4\)"),
        (dict(system=dict(force=HarmonicForce([1], [np.nan], [10.0]))), r"force = .*finite"),
        (dict(system=dict(force=HarmonicForce([5], [1.0], [10.0]))), r"force\.dofs = \[5\]"),
        (dict(gap_ramp=(0.01, 1e-5)), r"gap_ramp\[1\] \(g_start\) = 1e-05 .*>= every"),
        (dict(solver=dict(max_newton=-1)), r"max_newton = -1"),
        (dict(solver=dict(newton_tol=0.0)), r"newton_tol = 0\.0"),
        (dict(solver=dict(gamma=0.4)), r"gamma = 0\.4 .*>= 0\.5 and <= 1"),
        (dict(solver=dict(linear_solver="lu")), r"linear_solver = 'lu' .*sparse, dense"),
        (dict(outputs=dict(record_dofs=[0, 3])), r"record_dofs = \[0, 3\]"),
    ],
)
def test_bad_input_names_parameter_value_and_range(over, pattern):
    with pytest.raises(ValueError, match=pattern):
        _run(**over)


@pytest.mark.parametrize(
    ("fields", "pattern"),
    [
        (dict(gap=np.nan), r"PointContact\.gap = nan .*finite"),
        (dict(gap=np.inf), r"PointContact\.gap = inf .*finite"),
        (dict(mu=-0.1), r"PointContact\.mu = -0\.1 .*>= 0"),
        (dict(k_n=0.0), r"PointContact\.k_n = 0\.0 .*> 0 N/m"),
        (dict(k_n=-5.0), r"PointContact\.k_n = -5\.0"),
        (dict(k_t=0.0), r"PointContact\.k_t = 0\.0 .*> 0 N/m"),
        (dict(normal=(1.0, 1.0)), r"PointContact\.normal = \[1\.0, 1\.0\] .*unit vector"),
        (dict(dof_a=(0, -1)), r"PointContact\.dof_a = \[0, -1\] .*>= 0"),
        (dict(augmented=True, eps=0.0), r"PointContact\.eps = 0\.0"),
    ],
)
def test_bad_contact_is_refused_when_described(fields, pattern):
    with pytest.raises(ValueError, match=pattern):
        _contact(**fields)


def test_singular_mass_is_refused():
    M = sp.diags([1.0, 0.0, 1.0]).tocsr()
    with pytest.raises(ValueError, match="M is singular"):
        _run(system=dict(M=M))


def test_no_convergence_at_dt_min_stops_with_when_where_and_partial_result():
    """A Newton cap of 0 iterations cannot follow a contact force that changes: the first
    closing step fails, at dt_min = dt, and the run stops there."""
    M, C, K, _ = _base()
    ct = [_contact(gap=1e-2), _contact(dof_a=(2, 1), gap=1e-4)]
    v0 = np.array([0.0, 0.0, 0.5])  # DOF 2 (contact element 2) moves to its stop at 0.5 m/s
    system = LinearSystem(M=M, C=C, K=K, v0=v0)
    grid = TimeGrid(duration=1e-2, dt=1e-5, dt_min=1e-5)
    with pytest.raises(SimulationDiverged) as info:
        simulate_system(system, ct, grid, solver=Solver(max_newton=0))
    err = info.value
    res = err.result
    assert res.status == 1 and not res.success
    assert res.failure_element == 2       # numbered from 1, as everywhere public
    # the stop is reached at ~ gap / v = 0.2 ms, far before the 10 ms asked for
    assert 1.5e-4 < res.failure_time < 3e-4
    assert res.t_final == pytest.approx(res.failure_time - 1e-5)
    assert "t = " in str(err) and "contact element 2," in str(err)
    assert "did not converge" in str(err)
    # what was computed is kept: samples up to the failure, consistent final state
    assert res.t[-1] == pytest.approx(res.t_final)
    assert res.q.shape[0] == res.t.size == res.n_steps + 1
    np.testing.assert_allclose(res.q[-1], res.q_final)
    # without raising, the same partial result is returned
    res2 = simulate_system(system, ct, grid, Recording(raise_on_failure=False),
                           solver=Solver(max_newton=0))
    assert res2.status == 1 and res2.failure_time == res.failure_time


def test_variable_step_recovers_where_fixed_step_fails():
    """Annular rub (curved contact: Newton needs 2 updates at dt = 1e-4 s) with a cap of 1
    update: the fixed-step run stops, the variable-step run halves where needed and ends."""
    M = sp.diags([1.0, 1.0]).tocsr()
    K = sp.diags([4e4, 4e4]).tocsr()
    C = sp.diags([4.0, 4.0]).tocsr()
    omega = 220.0
    force = HarmonicForce.unbalance(0, 1, 2e-4, omega)
    ct = [AnnularContact(dof_a=(0, 1), clearance=1e-3, radius=0.05, k_n=2e7, mu=0.2)]
    system = LinearSystem(M=M, C=C, K=K, force=force, omega=omega)
    solver = Solver(max_newton=1)
    ok = simulate_system(system, ct, TimeGrid(duration=0.1, dt=1e-4, dt_min=1e-4 / 64),
                         solver=solver)
    assert ok.success
    assert ok.n_rejected_newton > 0 and ok.steps_per_level[1:].sum() > 0
    assert ok.newton_iterations_max <= 1
    with pytest.raises(SimulationDiverged, match=r"contact element 1,"):
        simulate_system(system, ct, TimeGrid(duration=0.1, dt=1e-4, fixed_step=True),
                        solver=solver)


def test_non_finite_state_stops_with_status_2():
    """A load that overflows the state: the run stops cleanly with status 2 and the time."""
    M, C, K, _ = _base()
    force = HarmonicForce([2], [1e305], [1e3])
    with pytest.raises(SimulationDiverged, match="non-finite") as info:
        simulate_system(LinearSystem(M=M, C=C, K=K, force=force), None,
                        TimeGrid(duration=1e-2, dt=1e-4))
    res = info.value.result
    assert res.status == 2
    assert 0 < res.failure_time <= 1e-2
    assert np.all(np.isfinite(res.q))  # what was kept is the last finite state


def test_a_negative_gap_is_the_gap_at_the_origin_a_shift_of_the_coordinates():
    """A point contact's g0 is its gap at x = 0, not a penetration: g0 = -1e-4 m started at
    q0 = -2e-4 m along the normal (1e-4 m outside the contact) is the base system (g0 =
    +1e-4 m from q0 = 0) moved by -2e-4 m, at every sample (it closes and reopens)."""
    M, C, K, _ = _base()
    K = sp.diags([1e4, 1e4, 1e4]).tocsr()       # grounded DOFs: a shift is a static state
    shift = np.array([-2e-4, 0.0, 0.0])
    force = HarmonicForce([0], [10.0], [150.0])  # drives the DOF through its gap

    def run(gap, q0):
        # the shifted system's static load holds it at its shifted rest: K shift
        f = force + HarmonicForce([0], [K[0, 0] * q0[0]], [150.0], order=0.0,
                                  law="constant")
        return simulate_system(LinearSystem(M=M, C=C, K=K, force=f, q0=q0), [_contact(gap=gap)],
                               TimeGrid(duration=0.05, dt=1e-5))
    base, moved = run(1e-4, np.zeros(3)), run(-1e-4, shift)
    assert base.contact_fn.max() > 0.0                       # the contact closes
    np.testing.assert_allclose(moved.q - shift, base.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(moved.contact_fn, base.contact_fn, rtol=1e-9, atol=1e-9)
