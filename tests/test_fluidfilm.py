"""rubdiag._fluidfilm: the short-bearing π-film force against its closed forms.

The static forces, the load and the attitude angle are those of the short π-film bearing;
the linearised stiffness and damping, which rubdiag takes from the Jacobian of the same
film force the time integrator uses, are checked against the published closed forms
(Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines, 2010, section 5.5.1: x
across the load, y along it, the load towards -y, rotation from x towards y), written out
here independently of the code.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import quad

from rubdiag import _fluidfilm as ff
from rubdiag._numba import njit

MU, R, L, C, OMEGA = 0.02, 0.02, 0.01, 50e-6, 300.0     # Pa s, m, m, m, rad/s
PI2 = math.pi ** 2


def force(x, y, vx=0.0, vy=0.0, omega=OMEGA):
    out = np.zeros((2, 5))
    thinnest = ff.film_force(x, y, vx, vy, omega, MU, R, L, C, out)
    return out, thinnest


def friswell(eps, load, omega=OMEGA):
    """K and C of the short π-film bearing (Friswell et al. 2010, eqs. of section 5.5.1)."""
    e2 = eps * eps
    h0 = 1.0 / (PI2 * (1 - e2) + 16 * e2) ** 1.5
    root = math.sqrt(1 - e2)
    a, b = load / C, load / (C * omega)
    K = a * h0 * np.array([
        [4 * (PI2 * (2 - e2) + 16 * e2),
         math.pi * (PI2 * (1 - e2) ** 2 - 16 * e2 * e2) / (eps * root)],
        [-math.pi * (PI2 * (1 - e2) * (1 + 2 * e2) + 32 * e2 * (1 + e2)) / (eps * root),
         4 * (PI2 * (1 + 2 * e2) + 32 * e2 * (1 + e2) / (1 - e2))]])
    cross = -8 * (PI2 * (1 + 2 * e2) - 16 * e2)
    Cm = b * h0 * np.array([
        [2 * math.pi * root * (PI2 * (1 + 2 * e2) - 16 * e2) / eps, cross],
        [cross, 2 * math.pi * (PI2 * (1 - e2) ** 2 + 48 * e2) / (eps * root)]])
    return K, Cm


@pytest.mark.parametrize("eps", [0.2, 0.5, 0.8])
def test_the_static_film_force_is_the_short_bearing_s_closed_form(eps):
    """Journal at (ε c, 0): a radial force μRL³ωε²/(c²(1−ε²)²) towards the centre and a
    tangential one πμRL³ωε/(4c²(1−ε²)^1.5) in the direction of rotation."""
    out, thinnest = force(eps * C, 0.0)
    radial = MU * R * L ** 3 * OMEGA * eps ** 2 / (C ** 2 * (1 - eps ** 2) ** 2)
    tangential = math.pi * MU * R * L ** 3 * OMEGA * eps / (4 * C ** 2 * (1 - eps ** 2) ** 1.5)
    np.testing.assert_allclose(out[:, 0], [-radial, tangential], rtol=1e-12)
    assert thinnest == pytest.approx(1 - eps, rel=1e-3)     # the thinnest film: c (1 - ε)


@pytest.mark.parametrize("eps", [0.2, 0.5, 0.8])
def test_the_linearised_coefficients_are_the_published_closed_forms(eps):
    load = ff.load_capacity(eps, OMEGA, MU, R, L, C)
    K, Cm, position = ff.linearised_coefficients(load, OMEGA, MU, R, L, C,
                                                 direction=(0.0, -1.0))
    assert np.hypot(*position) == pytest.approx(eps * C, rel=1e-10)
    out, _ = force(*position)
    np.testing.assert_allclose(out[:, 0], [0.0, load], atol=1e-10 * load)   # it balances
    K_ref, C_ref = friswell(eps, load)
    np.testing.assert_allclose(K, K_ref, rtol=1e-9, atol=1e-12 * np.abs(K_ref).max())
    np.testing.assert_allclose(Cm, C_ref, rtol=1e-9, atol=1e-12 * np.abs(C_ref).max())


def test_the_load_and_the_attitude_angle():
    for eps in (0.1, 0.4, 0.7):
        load = ff.load_capacity(eps, OMEGA, MU, R, L, C)
        assert ff.eccentricity_for_load(load, OMEGA, MU, R, L, C) == pytest.approx(eps,
                                                                                  rel=1e-12)
        out, _ = force(eps * C, 0.0)
        assert np.hypot(*out[:, 0]) == pytest.approx(load, rel=1e-12)
        assert math.atan2(out[1, 0], -out[0, 0]) == pytest.approx(ff.attitude_angle(eps),
                                                                  rel=1e-12)
    with pytest.raises(ValueError, match="load"):
        ff.eccentricity_for_load(-1.0, OMEGA, MU, R, L, C)


def quad_force(x, y, vx, vy):
    """The film force by adaptive quadrature over the same half circle of positive pressure
    (its ends, where G = 0, written out here): an independent evaluation of the integral."""
    a, b = OMEGA * x - 2 * vy, OMEGA * y + 2 * vx
    alpha = math.atan2(-a, b)

    def density(theta, k):
        g = a * math.sin(theta) - b * math.cos(theta)
        h = C - x * math.cos(theta) - y * math.sin(theta)
        return 0.5 * MU * R * L ** 3 * g / h ** 3 * (math.cos(theta), math.sin(theta))[k]

    return np.array([quad(density, alpha - math.pi / 2, alpha + math.pi / 2, args=(k,),
                          limit=500, epsabs=0, epsrel=1e-13)[0] for k in (0, 1)])


@pytest.mark.parametrize(("x", "y", "vx", "vy", "rtol"), [
    (10e-6, -20e-6, 1e-3, -2e-3, 1e-12),     # moving: the half circle turns
    (-25e-6, 5e-6, -4e-3, 1e-3, 1e-12),
    (30e-6, 25e-6, 0.0, 0.0, 1e-12),         # ε = 0.78
    (0.0, -45e-6, 2e-3, 0.0, 1e-12),         # ε = 0.9
    (0.0, -47.5e-6, 2e-3, 0.0, 5e-9),        # ε = 0.95: the film's peak sharpens
    (0.0, -49e-6, 2e-3, 0.0, 1e-6),          # ε = 0.98
])
def test_a_moving_journal_s_force_against_adaptive_quadrature(x, y, vx, vy, rtol):
    """Measured on 20 random moving journals at each ε (2026-11-27): 2e-15 at ε <= 0.8,
    4e-14 at 0.9, 5e-10 at 0.95, 4e-7 at 0.98 with the 64 Gauss points."""
    out, _ = force(x, y, vx, vy)
    ref = quad_force(x, y, vx, vy)
    np.testing.assert_allclose(out[:, 0], ref, rtol=rtol, atol=rtol * np.abs(ref).max())


def test_the_jacobian_against_central_differences():
    x, y, vx, vy = 12e-6, -18e-6, 1.5e-3, -0.5e-3
    out, _ = force(x, y, vx, vy)
    steps = (1e-9, 1e-9, 1e-6, 1e-6)
    state = np.array([x, y, vx, vy])
    for j, step in enumerate(steps):
        up, down = state.copy(), state.copy()
        up[j] += step
        down[j] -= step
        numeric = (force(*up)[0][:, 0] - force(*down)[0][:, 0]) / (2 * step)
        np.testing.assert_allclose(out[:, 1 + j], numeric, rtol=1e-6,
                                   atol=1e-6 * np.abs(out[:, 1:]).max())


def test_a_centred_still_journal_feels_nothing_and_squeeze_alone_damps():
    out, _ = force(0.0, 0.0)
    assert np.all(out == 0.0)
    # no rotation, the journal squeezing the film along +x: a force against the motion
    out, _ = force(0.0, 0.0, vx=1e-3, omega=0.0)
    assert out[0, 0] < 0.0 and abs(out[1, 0]) < 1e-12 * abs(out[0, 0])


@functools.cache
def _gauss(n):
    return np.polynomial.legendre.leggauss(n)


def reference_terms(x, y, vx, vy, n=400):
    """Force and Jacobian (as ``film_force``'s columns) by an n-point Gauss rule in NumPy,
    written out here: the reference of the integrator's rules."""
    t, w = _gauss(n)
    a, b = OMEGA * x - 2 * vy, OMEGA * y + 2 * vx
    theta = math.atan2(-a, b) + 0.5 * math.pi * t
    cs, sn = np.cos(theta), np.sin(theta)
    h = C - x * cs - y * sn
    g = a * sn - b * cs
    weight = 0.25 * math.pi * MU * R * L ** 3 * w / h ** 3
    columns = (g, OMEGA * sn + 3 * g * cs / h, -OMEGA * cs + 3 * g * sn / h, -2 * cs, -2 * sn)
    return np.array([[np.sum(weight * col * cs) for col in columns],
                     [np.sum(weight * col * sn) for col in columns]])


@njit
def _step_film_terms(x, y, vx, vy, omega, mu, radius, length, clearance):
    return ff.step_film_terms(x, y, vx, vy, omega, mu, radius, length, clearance)


def step_terms(x, y, vx, vy):
    """step_film_terms' force and Jacobian (as film_force's columns), its thinnest film, and
    film_force's columns."""
    out, _ = force(x, y, vx, vy)
    terms = _step_film_terms(x, y, vx, vy, OMEGA, MU, R, L, C)
    return np.array([terms[0:10:2], terms[1:10:2]]), terms[10], out


def _moving_journals(eps, n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        angle = rng.uniform(0.0, 2 * math.pi)
        speed = 10 ** rng.uniform(-3, 1) * OMEGA * C
        yield (eps * C * math.cos(angle), eps * C * math.sin(angle), *(rng.normal(size=2) * speed))


def _relative_error(terms, ref):
    """Largest error of the force, the stiffness and the damping columns, each relative to
    its own largest entry."""
    return max(np.abs(terms[:, s] - ref[:, s]).max() / np.abs(ref[:, s]).max()
               for s in (slice(0, 1), slice(1, 3), slice(3, 5)))


@pytest.mark.parametrize(("eps", "n_points"), [(eps, n) for eps, n in ff.STEP_RULES[:-1]])
def test_each_step_rule_reaches_round_off_up_to_its_eccentricity_and_no_fewer_points_do(
        eps, n_points):
    """The integrator's rules (STEP_RULES): at the largest eccentricity a rule serves, its
    terms agree with a 400-point rule to 3e-13 on random moving journals; a rule of four
    points fewer does not (the rule is the fewest that does, to within 4 points)."""
    worst = fewer = 0.0
    for x, y, vx, vy in _moving_journals(eps, 40, seed=int(100 * eps)):
        terms, _, _ = step_terms(x, y, vx, vy)
        ref = reference_terms(x, y, vx, vy)
        worst = max(worst, _relative_error(terms, ref))
        fewer = max(fewer, _relative_error(reference_terms(x, y, vx, vy, n_points - 4), ref))
    assert worst < 3e-13
    assert fewer > 3e-13


@pytest.mark.parametrize("eps", [0.1, 0.35, 0.55, 0.65, 0.75, 0.85, 0.9])
def test_the_integrator_s_film_terms_are_the_film_force_s_to_round_off(eps):
    """step_film_terms (turned node angles, fewer points) against film_force (64 points,
    each angle's cosine and sine), and its thinnest film in closed form against the film
    sampled densely over the half circle of pressure."""
    for x, y, vx, vy in _moving_journals(eps, 20, seed=int(1000 * eps)):
        terms, thinnest, out = step_terms(x, y, vx, vy)
        assert _relative_error(terms, out) < 3e-13
        a, b = OMEGA * x - 2 * vy, OMEGA * y + 2 * vx
        theta = math.atan2(-a, b) + np.linspace(-0.5 * math.pi, 0.5 * math.pi, 20001)
        sampled = np.min(C - x * np.cos(theta) - y * np.sin(theta)) / C
        assert thinnest == pytest.approx(sampled, abs=1e-7)
