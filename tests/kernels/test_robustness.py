"""Robustness corners: contact stiffness x step x friction on a small tip/casing system."""

import itertools

import numpy as np
import pytest
from testsystems import linear_response, tip_casing_system

from rubdiag.simulation import LinearSystem, TimeGrid, simulate_system

# stated tolerance of the energy balance: |W_ext + W_drive - ΔE - D_visc - D_fric| over the
# run, relative to the largest mechanical energy of the run
ENERGY_TOL = 0.03  # measured worst: 1.8 % (k_N = 1e6 N/m, dt = 1e-4 s, mu = 0.5)


@pytest.mark.parametrize(
    ("k_n", "dt", "mu"), list(itertools.product([1e6, 1e9], [1e-6, 1e-4], [0.0, 0.5]))
)
def test_corner_runs_without_divergence(k_n, dt, mu):
    s = tip_casing_system(k_n=k_n, mu=mu, gap=50e-6)
    u = linear_response(s.M, s.C, s.K, s.force)
    amp = float(np.abs(u[s.tip_dofs[:, 0]]).max())  # ~120 µm linear orbit vs 50 µm gap
    duration = 0.02 if dt == 1e-4 else 0.012
    res = simulate_system(
        LinearSystem(M=s.M, C=s.C, K=s.K, force=s.force, q0=u.real,
                     v0=(1j * s.speed * u).real, omega=s.speed),
        s.contacts, TimeGrid(duration=duration, dt=dt, output_dt=1e-4 if dt == 1e-4 else 1e-5),
        gap_ramp=(0.005, 1.5 * amp),
    )
    assert res.success
    assert np.all(np.isfinite(res.q_final))
    # it really rubs, and the contact holds the tips: penetration bounded by the penalty
    # force it takes and far below the 70 µm the linear orbit would overshoot the gap
    assert res.time_in_status[:, 1:].sum() > 0
    assert res.max_penetration.max() < 0.6 * (amp - 50e-6)
    np.testing.assert_allclose(res.max_penetration, res.max_normal_force / k_n, rtol=1e-9)
    # closed energy balance (the residual is the contact-algorithmic energy)
    scale = res.mechanical_energy.max()
    resid = np.abs(res.energy_balance_residual).max()
    assert resid < ENERGY_TOL * scale, resid / scale
    assert res.max_cone_excess <= 1e-9 * res.max_normal_force.max()
    # stiff contact at a coarse step is resolved by the step control
    if k_n == 1e9 and dt == 1e-4:
        assert res.steps_per_level[1:].sum() > 0
