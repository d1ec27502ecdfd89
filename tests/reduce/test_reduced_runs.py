"""Runs of the reduced model: the same physics as the full one where it must be the same."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.model import paper_rig
from rubdiag.reduce import Reduction
from rubdiag.reduce._check import RESPONSE_TOLERANCE
from rubdiag.simulation import Run, default_sensors, simulate


def _pair(**options):
    rig = paper_rig()
    full = simulate(Run.paper_case(rig=rig, **options))
    reduced = simulate(Run.paper_case(rig=rig, reduction=Reduction(), **options))
    return full, reduced


@pytest.fixture(scope="module")
def linear_pair():
    """Case 1 at its critical speed with a gap no orbit reaches: a linear run, recorded
    and sensed in both models."""
    rig = paper_rig()
    return _pair(case=1, gap_mm=20.0, duration_s=0.05, discard_s=0.01, gap_ramp_s=0.0,
                 sensors=default_sensors(rig))


def test_linear_run_follows_the_full_model(linear_pair):
    full, reduced = linear_pair
    assert reduced.system.extra["model"] == "reduced" and full.system.extra["model"] == "full"
    assert reduced.system.n_steps == full.system.n_steps
    for point in full.points:            # recovered physical displacements
        a, b = full.displacement(point), reduced.displacement(point)
        scale = np.abs(a).max()
        if scale > 1e-6:                 # the casing does not move without contact
            assert np.abs(b - a).max() <= 2e-3 * scale, point
    # sensors: the bearings move 1e-7 m against the disc's 3 mm; each within the band's
    # response tolerance of its own amplitude (the check's frequency responses)
    sig_f, sig_r = full.sensor_signals(), reduced.sensor_signals()
    assert set(sig_f) == set(sig_r)
    for name, a in sig_f.items():
        scale = np.abs(a).max()
        if scale > 0 and name.startswith("shaft"):
            assert np.abs(sig_r[name] - a).max() <= RESPONSE_TOLERANCE * scale, name


def test_linear_run_balances_energy(linear_pair):
    # trapezoidal rule: work in = kinetic + strain + viscous dissipation, to round-off
    s = linear_pair[1].system
    balance = s.work_external - s.dissipated_viscous - (s.kinetic - s.kinetic[0]) \
        - (s.strain - s.strain[0])
    assert np.abs(balance).max() <= 1e-9 * np.abs(s.work_external).max()


@pytest.fixture(scope="module")
def rubbing():
    return simulate(Run.paper_case(2, 1.9, duration_s=0.3, discard_s=0.1,
                                   reduction=Reduction()))


def test_reduced_contact_obeys_the_contact_law(rubbing):
    s = rubbing.system
    assert len(rubbing.window_episodes()) > 10
    law = rubbing.run.contact_law
    closed = s.contact_status >= 2
    # Coulomb: |F_T| <= μ F_N (to round-off), stick means no slip between samples
    assert s.max_cone_excess <= 1e-9 * s.max_normal_force.max()
    fn, ft = s.contact_fn[closed], s.contact_ft[closed]
    assert np.all(np.abs(ft) <= law.friction_coefficient * fn * (1 + 1e-9) + 1e-9)
    # pure penalty: the penetration is F_N / k_N
    pen = -s.contact_gap[closed]
    np.testing.assert_allclose(pen, fn / law.normal_stiffness_n_m, rtol=1e-6, atol=1e-12)
    # open elements carry no force
    assert np.all(s.contact_fn[~closed] == 0.0)


def test_recovery_records_every_physical_dof_by_default():
    # a 2-DOF system integrated in modal coordinates, recovered to 3 "physical" DOFs
    from rubdiag.simulation import HarmonicForce, LinearSystem, Solver, TimeGrid, simulate_system

    T = np.array([[1.0, 0.0], [0.5, 0.5], [0.0, 1.0]])
    M, K = np.eye(2), np.diag([100.0, 400.0])
    force = HarmonicForce([0], [1.0], 3.0)
    grid = TimeGrid(duration=0.1, dt=1e-3, fixed_step=True)
    result = simulate_system(LinearSystem(M=M, C=0.01 * K, K=K, force=force, recovery=T),
                             None, grid, solver=Solver(linear_solver="dense"))
    assert result.q.shape[1] == 3
    sparse = simulate_system(LinearSystem(M=M, C=0.01 * K, K=K, force=force), None, grid)
    np.testing.assert_allclose(result.q, sparse.q @ T.T, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(result.q_final, T @ sparse.q_final, rtol=1e-10, atol=1e-14)
