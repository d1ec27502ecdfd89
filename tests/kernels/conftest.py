"""Shared runs for the kernel tests (module-scoped: each is computed once)."""

import numpy as np
import pytest
from testsystems import linear_response, tip_casing_system

from rubdiag._kernels import ensure_fresh_cache
from rubdiag.simulation import LinearSystem, Recording, Solver, TimeGrid, simulate_system


def rub_run(mu=0.5, k_n=1e7, duration=0.04, dt=1e-5, output_dt=None, outputs=None,
            solver=None):
    """The ~18-DOF tip/casing system started on its linear orbit (amplitude ~120 µm) with the
    gap ramped from 1.5x that amplitude down to 50 µm over 10 ms: 2 contacts rub."""
    s = tip_casing_system(k_n=k_n, mu=mu, gap=50e-6)
    u = linear_response(s.M, s.C, s.K, s.force)
    amp = float(np.abs(u[s.tip_dofs[:, 0]]).max())
    res = simulate_system(
        LinearSystem(M=s.M, C=s.C, K=s.K, force=s.force, q0=u.real,
                     v0=(1j * s.speed * u).real, omega=s.speed),
        s.contacts, TimeGrid(duration=duration, dt=dt, output_dt=output_dt),
        outputs or Recording(), solver=solver or Solver(), gap_ramp=(0.01, 1.5 * amp))
    return s, res


@pytest.fixture(scope="session")
def penalty_run():
    return rub_run()


@pytest.fixture(scope="session")
def make_rub_run():
    """The :func:`rub_run` factory, for tests that need their own variant."""
    return rub_run


@pytest.fixture(scope="session", autouse=True)
def fresh_kernel_cache():
    """Kernel tests call kernels directly: drop a stale cache first, as simulate_system does."""
    ensure_fresh_cache()
