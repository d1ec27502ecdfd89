"""A plain journal bearing through the element seam: a rigid rotor of
10 kg on its oil film under its weight, the film's force from rubdiag._fluidfilm.

The test rotor: one bearing of radius 20 mm, length 10 mm (L/D = 0.25: a short bearing),
radial clearance 50 um, oil of 0.02 Pa s, carrying m g = 98.1 N along -y. The linearised
film (rubdiag._fluidfilm.linearised_coefficients) puts the threshold of instability of
``m ẍ + C ẋ + K x = 0`` at 1122.4 rad/s (eccentricity ratio 0.434, Sommerfeld number
S = μ N L D / W (R/c)² = 2.33 there, N in rev/s; (L/D)² S = 0.146); the nonlinear element
must agree.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import brentq

from rubdiag import _fluidfilm as ff
from rubdiag.simulation import HarmonicForce, LinearSystem, TimeGrid, simulate_system
from rubdiag.simulation._journal import JournalBearing

MASS, G = 10.0, 9.81
MU, R, L, C = 0.02, 0.02, 0.01, 50e-6
LOAD = MASS * G
DOWN = (-1.0, 0.0)          # the weight along the first DOF's negative direction


def growth_rate(omega: float) -> complex:
    """The linearised rotor's rightmost eigenvalue at ``omega`` (rad/s)."""
    K, Cm, _ = ff.linearised_coefficients(LOAD, omega, MU, R, L, C, direction=DOWN)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K / MASS, -Cm / MASS]])
    lam = np.linalg.eigvals(A)
    return lam[np.argmax(lam.real)]


@pytest.fixture(scope="module")
def threshold() -> float:
    return brentq(lambda w: growth_rate(w).real, 300.0, 3000.0, xtol=1e-9)


def run(omega: float, offset, duration: float = 1.0):
    """The rotor from its static equilibrium moved by ``offset`` (m), at rest."""
    _, _, position = ff.linearised_coefficients(LOAD, omega, MU, R, L, C, direction=DOWN)
    M = sp.identity(2, format="csr") * MASS
    zero = sp.csr_matrix((2, 2))
    weight = HarmonicForce([0], [-LOAD], [omega], order=0.0, law="constant")
    film = JournalBearing(dof_a=(0, 1), mu_pa_s=MU, radius_m=R, length_m=L, clearance_m=C)
    system = LinearSystem(M=M, C=zero, K=zero, force=weight,
                          q0=position + np.asarray(offset), omega=omega)
    result = simulate_system(system, [film], TimeGrid(duration=duration, dt=1e-5))
    return result, position


def excursion(result, position, part: slice) -> float:
    d = result.q[part] - position
    return float(np.hypot(d[:, 0], d[:, 1]).max())


def test_the_test_rotor_s_threshold(threshold):
    eps = ff.eccentricity_for_load(LOAD, threshold, MU, R, L, C)
    sommerfeld = MU * (threshold / (2 * math.pi)) * L * 2 * R / LOAD * (R / C) ** 2
    assert threshold == pytest.approx(1122.45, abs=0.01)      # as the docstring states
    assert eps == pytest.approx(0.434, abs=5e-4)
    assert sommerfeld == pytest.approx(2.33, abs=5e-3)
    assert growth_rate(0.9 * threshold).real < 0.0 < growth_rate(1.1 * threshold).real


def test_below_the_threshold_the_journal_settles_where_the_closed_form_puts_it(threshold):
    """From 10 % of the clearance away, at 0.6 of the threshold: the journal comes to rest at
    ε c along the load turned by the attitude angle (closed forms of rubdiag._fluidfilm)."""
    omega = 0.6 * threshold
    result, position = run(omega, (0.0, 0.1 * C), duration=0.5)
    assert excursion(result, position, slice(-100, None)) < 1e-6 * C
    eps = ff.eccentricity_for_load(LOAD, omega, MU, R, L, C)
    end = result.q[-1]
    assert np.hypot(*end) == pytest.approx(eps * C, rel=1e-5)
    # the journal's angle from the load's direction (-x), counted in the sense of rotation
    # (from +x towards +y: from -x that turns towards -y)
    angle = math.atan2(-end[1], -end[0])
    assert angle == pytest.approx(ff.attitude_angle(eps), abs=1e-5)


@pytest.mark.parametrize(("ratio", "grows"), [(0.95, False), (1.05, True)])
def test_a_small_perturbation_decays_below_the_threshold_and_grows_above(threshold, ratio,
                                                                          grows):
    """2 % of the clearance, 1 s: measured 2e-2 → 1.6e-6 c at 0.95, → 0.53 c at 1.05."""
    result, position = run(ratio * threshold, (0.0, 0.02 * C))
    first = excursion(result, position, slice(0, 10_000))
    last = excursion(result, position, slice(-10_000, None))
    assert (last > 5 * first) if grows else (last < first / 100), (first / C, last / C)
    assert result.contact_gap.min() > 0.0          # inside its clearance throughout


def test_the_energy_ledger_closes_with_the_film_s_work(threshold):
    """The film's work on the journal, booked by its law (the trapezoidal rule over each
    step), closes the ledger with the weight's work and the kinetic energy: what is left is
    the elements' algorithmic energy to round-off, and that is small (measured 1.6e-6 of
    the largest work over a growing whirl of 0.5 s)."""
    result, _ = run(1.05 * threshold, (0.0, 0.02 * C), duration=0.5)
    scale = np.abs(result.work_external).max()
    residual = result.energy_balance_residual
    np.testing.assert_allclose(residual, result.contact_algorithmic, rtol=0,
                               atol=1e-9 * scale)
    assert np.abs(residual).max() < 1e-5 * scale


@pytest.mark.parametrize(("field", "value"), [
    ("mu_pa_s", 0.0), ("radius_m", -1.0), ("length_m", float("nan")),
    ("clearance_m", 0.03)])
def test_bad_values_are_refused_by_name(field, value):
    options = dict(dof_a=(0, 1), mu_pa_s=MU, radius_m=R, length_m=L, clearance_m=C)
    with pytest.raises(ValueError, match=f"JournalBearing.{field}"):
        JournalBearing(**{**options, field: value})
