"""Bearings on pedestals (rubdiag.model._rig.Pedestal): the assembled two-mass support."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.linalg as sla

from rubdiag.assembly import assemble
from rubdiag.model import Pedestal, paper_rig, rig_from_dict, rig_to_dict

PEDESTAL = Pedestal(mass_kg=20.0, k_y_n_m=50e6, k_z_n_m=40e6, c_y_ns_m=1e3, c_z_ns_m=2e3)


def on_pedestals(rig, pedestals):
    """``rig`` with ``pedestals[k]`` under bearing k (None: grounded)."""
    bearings = tuple(dataclasses.replace(b, pedestal=p)
                     for b, p in zip(rig.bearings, pedestals, strict=True))
    return dataclasses.replace(rig, bearings=bearings)


def lowest_hz(model, n):
    """The ``n`` lowest undamped natural frequencies at rest (Hz)."""
    w2 = sla.eigh(model.K.toarray(), model.M.toarray(), eigvals_only=True,
                  subset_by_index=(0, n - 1))
    return np.sqrt(w2) / (2 * np.pi)


def test_a_rig_without_pedestals_keeps_its_matrices_and_dofs():
    rig = paper_rig()
    plain, with_one = assemble(rig), assemble(on_pedestals(rig, (PEDESTAL, None)))
    n = plain.n_dof
    assert with_one.n_dof == n + 2
    assert with_one.dofs.labels[n:] == ["pedestal 0 y", "pedestal 0 z"]
    assert with_one.dofs.labels[:n] == plain.dofs.labels
    # the pedestal only adds rows and columns: the shaft node keeps its bearing spring
    for name in ("M", "K", "G", "K_structural", "C_discrete"):
        a, b = getattr(plain, name), getattr(with_one, name)[:n, :n]
        assert abs(a - b).max() == 0.0, name


def test_the_pedestal_couples_its_shaft_node_and_the_ground():
    rig = on_pedestals(paper_rig(), (PEDESTAL, None))
    model = assemble(rig)
    bearing = rig.bearings[0]
    s, p = model.dofs.index(4, "y"), model.dofs.index("pedestal 0", "y")
    assert model.K[s, p] == -bearing.k_y_n_m
    assert model.K[p, p] == bearing.k_y_n_m + PEDESTAL.k_y_n_m
    assert model.C_discrete[p, p] == bearing.c_y_ns_m + PEDESTAL.c_y_ns_m
    assert model.M[p, p] == PEDESTAL.mass_kg
    assert model.K_structural[p, p] == 0.0      # Rayleigh's beta does not act on it


def test_with_the_shaft_held_the_pedestal_is_a_mass_on_two_springs():
    """Shaft node held: ω = √((k_b + k_s)/m) in each direction."""
    rig = on_pedestals(paper_rig(), (PEDESTAL, None))
    model = assemble(rig)
    ped = model.dofs.component("pedestal")
    K, M = model.K.toarray()[np.ix_(ped, ped)], model.M.toarray()[np.ix_(ped, ped)]
    found = np.sort(np.sqrt(sla.eigh(K, M, eigvals_only=True)))
    b = rig.bearings[0]
    expected = np.sort(np.sqrt([(b.k_y_n_m + PEDESTAL.k_y_n_m) / PEDESTAL.mass_kg,
                                (b.k_z_n_m + PEDESTAL.k_z_n_m) / PEDESTAL.mass_kg]))
    np.testing.assert_allclose(found, expected, rtol=1e-12)


def test_a_light_pedestal_is_a_spring_in_series_with_its_bearing():
    """A 1 g pedestal under both bearings: the rotor's lowest modes are those of the grounded
    rig with bearings of stiffness k_b k_s / (k_b + k_s) (two springs in series)."""
    rig = paper_rig()
    light = Pedestal(mass_kg=1e-3, k_y_n_m=20e6, k_z_n_m=10e6)
    series = tuple(dataclasses.replace(
        b, k_y_n_m=b.k_y_n_m * light.k_y_n_m / (b.k_y_n_m + light.k_y_n_m),
        k_z_n_m=b.k_z_n_m * light.k_z_n_m / (b.k_z_n_m + light.k_z_n_m))
        for b in rig.bearings)
    found = lowest_hz(assemble(on_pedestals(rig, (light, light))), 6)
    expected = lowest_hz(assemble(dataclasses.replace(rig, bearings=series)), 6)
    np.testing.assert_allclose(found, expected, rtol=1e-6)  # measured 6e-8
    grounded = lowest_hz(assemble(rig), 6)
    assert np.abs(found / grounded - 1).max() > 1e-3    # the series spring changes them (0.17 %)


def test_the_pedestal_is_read_and_written_in_rig_files():
    rig = on_pedestals(paper_rig(), (None, PEDESTAL))
    data = rig_to_dict(rig)
    assert "pedestal" not in data["bearings"][0]
    assert data["bearings"][1]["pedestal"]["mass_kg"] == 20.0
    assert rig_from_dict(data) == rig
    assert "pedestal" not in rig_to_dict(paper_rig())["bearings"][0]


@pytest.mark.parametrize(("key", "value", "message"), [
    ("mass_kg", 0.0, "Pedestal.mass_kg"),
    ("k_y_n_m", 0.0, "Pedestal.k_y_n_m"),
    ("c_z_ns_m", -1.0, "Pedestal.c_z_ns_m"),
    ("spring", 1.0, r"unknown key 'bearings\[0\]\.pedestal\.spring'"),
])
def test_a_bad_pedestal_is_refused_by_name(key, value, message):
    data = rig_to_dict(paper_rig())
    data["bearings"][0]["pedestal"] = {"mass_kg": 20.0, "k_y_n_m": 1e7, "k_z_n_m": 1e7,
                                       key: value}
    with pytest.raises(ValueError, match=message):
        rig_from_dict(data)
