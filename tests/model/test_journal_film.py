"""A journal bearing's film as its description gives it: load capacity, where the journal
sits, and the linearised stiffness and damping, against the short π-film bearing's closed
forms (Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines, 2010, section 5.5)."""

import math

import numpy as np
import pytest

from rubdiag.model import JournalFilm

SPEED = 300.0    # rad/s


def _film(load_n=20.0, direction="-y"):
    return JournalFilm(viscosity_pa_s=0.02, radius_m=0.02, length_m=0.01, clearance_m=50e-6,
                       load_n=load_n, load_direction=direction)


@pytest.mark.parametrize("eps", [0.05, 0.3, 0.6, 0.9])
def test_the_load_capacity_is_the_closed_form_and_the_eccentricity_its_inverse(eps):
    film = _film()
    w = (0.02 * SPEED * 0.02 * 0.01**3 / (4 * (50e-6) ** 2) * eps
         * math.sqrt(16 * eps**2 + math.pi**2 * (1 - eps**2)) / (1 - eps**2) ** 2)
    assert film.load_capacity(eps, SPEED) == pytest.approx(w, rel=1e-12)
    assert _film(load_n=w).eccentricity_ratio(SPEED) == pytest.approx(eps, abs=1e-9)


@pytest.mark.parametrize("eps", [0.1, 0.4, 0.7])
def test_the_direct_stiffnesses_are_the_closed_forms_across_and_along_the_load(eps):
    load = _film().load_capacity(eps, SPEED)
    K, C = _film(load_n=load).coefficients(SPEED)      # load along -y: y along, z across
    h0 = (math.pi**2 * (1 - eps**2) + 16 * eps**2) ** -1.5
    across = 4 * load / 50e-6 * h0 * (math.pi**2 * (2 - eps**2) + 16 * eps**2)
    along = 4 * load / 50e-6 * h0 * (math.pi**2 * (1 + 2 * eps**2)
                                     + 32 * eps**2 * (1 + eps**2) / (1 - eps**2))
    assert K[1, 1] == pytest.approx(across, rel=1e-6)
    assert K[0, 0] == pytest.approx(along, rel=1e-6)
    assert np.all(np.diag(C) > 0)        # a film damps the journal's motion


def test_the_coefficients_turn_with_the_load():
    """The film is isotropic: loaded along -z, its matrices are those loaded along -y turned
    by a quarter turn."""
    K_y, C_y = _film(direction="-y").coefficients(SPEED)
    K_z, C_z = _film(direction="-z").coefficients(SPEED)
    quarter = np.array([[0.0, -1.0], [1.0, 0.0]])       # takes -y to -z
    for turned, loaded in ((K_z, K_y), (C_z, C_y)):
        np.testing.assert_allclose(turned, quarter @ loaded @ quarter.T, rtol=1e-9,
                                   atol=1e-9 * abs(loaded).max())


@pytest.mark.parametrize(("call", "name"), [
    (lambda f: f.load_capacity(1.0, SPEED), "eccentricity_ratio"),
    (lambda f: f.load_capacity(-0.1, SPEED), "eccentricity_ratio"),
    (lambda f: f.load_capacity(0.5, 0.0), "speed_rad_s"),
    (lambda f: f.coefficients(-1.0), "speed_rad_s"),
    (lambda f: f.eccentricity_ratio(float("nan")), "speed_rad_s"),
])
def test_a_value_out_of_range_is_refused_by_name(call, name):
    with pytest.raises(ValueError, match=name):
        call(_film())
