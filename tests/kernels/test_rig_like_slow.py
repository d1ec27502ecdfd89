"""Longer runs on the 412-DOF rig-like system (``-m slow``)."""

import numpy as np
import pytest
from testsystems import bladed_rotor_casing, linear_response

from rubdiag.simulation import LinearSystem, Recording, TimeGrid, simulate_system


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_rig_like_rub_run_is_sound(mu):
    s = bladed_rotor_casing(mu=mu, gap_fraction=0.3)
    u = linear_response(s.M, s.C, s.K, s.force)
    amp = float(np.abs(u[s.tip_dofs[:, 0]]).max())
    res = simulate_system(
        LinearSystem(M=s.M, C=s.C, K=s.K, force=s.force, q0=u.real,
                     v0=(1j * s.speed * u).real, omega=s.speed),
        s.contacts, TimeGrid(duration=1.0, dt=1e-5, output_dt=1e-4),
        Recording(record_dofs=[s.disc_dofs[0], int(s.tip_dofs[0, 0]),
                               int(s.casing_dofs[0, 0])]),
        gap_ramp=(0.05, 1.2 * amp),
    )
    assert res.success
    assert len(res.episodes) > 20
    assert res.max_cone_excess <= 1e-9 * res.max_normal_force.max()
    scale = res.mechanical_energy.max()
    assert np.abs(res.energy_balance_residual).max() < 0.01 * scale
    # the rub limits the tip orbit well below the linear one
    assert np.abs(res.q[-1000:, 1]).max() < 0.8 * amp
