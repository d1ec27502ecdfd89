"""Rub in its kinds as design factors: ``blade_count`` (a property of every run's rig),
``rubbing_blades`` (which blades rub) and ``rub_kind`` (blade tips on the casing, or the
shaft on an annular seal aligned on the loaded rotor).

Checked against closed forms where one exists: the films carry the rotor's weight, which
changes by the blades' own mass; the seal's approach is the semi-major axis of the linear
orbit at its node; and end to end, a seal rub is labelled rub from the seal's own contact
episodes, at the interference ratio the design asked for."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rubdiag.dataset import Design, generate, load
from rubdiag.dataset._fault_levels import NO_RUB_GAP_M
from rubdiag.dataset._rig_factors import (
    bearing_loads_n,
    blade_set,
    blade_set_of,
    varied_rig,
    with_rubbing_blades,
)
from rubdiag.model import preset_rig
from rubdiag.simulation import simulate

JOURNAL = preset_rig("paper-journal")
BASE = {"rig": "paper-journal", "duration_s": 2.5, "discard_s": 1.2, "reduced": True,
        "gravity_m_s2": 9.81}


def design(factors: dict, n: int = 8, seed: int = 1, **base) -> Design:
    return Design.from_dict({"base": {**BASE, **base},
                             "sampling": {"method": "lhs", "n": n, "seed": seed},
                             "factors": {"case": [1, 2], **factors}})


def test_blade_sets_are_every_other_every_or_one():
    assert blade_set(16, "alternate") == (1, 3, 5, 7, 9, 11, 13, 15)
    assert blade_set(12, "all") == tuple(range(1, 13))
    assert blade_set(20, "one") == (1,)
    assert blade_set_of(JOURNAL) == "alternate"          # the study's 8 of 16
    odd = dataclasses.replace(JOURNAL, contact=dataclasses.replace(JOURNAL.contact,
                                                                   blades=(1, 5)))
    with pytest.raises(ValueError, match=r"factors.blade_count: the rig's contact blades "
                                         r"\[1, 5\] are none of the sets"):
        blade_set_of(odd)


@pytest.mark.parametrize("count, elements", [(8, 40), (12, 48), (16, 48), (20, 40)])
def test_a_casing_node_faces_every_blade_whatever_the_count(count, elements):
    rig = varied_rig(JOURNAL, {"blade_count": count})
    assert rig.blades.count == count and rig.casing.n_elements == elements
    assert rig.contact.blades == blade_set(count, "alternate")
    every = with_rubbing_blades(rig, "all")        # a valid rig: each blade has its node
    for k, blade in enumerate(every.contact.blades, start=1):
        node = every.contact_casing_node(k)
        assert math.isclose(every.casing.angle_rad(node), every.blades.angle_rad(blade),
                            abs_tol=1e-12)


def test_a_design_varying_the_rubbing_blades_meshes_every_run_alike():
    """The ring's mesh follows the blade count only: a run that rubs with every blade and one
    that does not rub have the same casing."""
    rubbing = varied_rig(JOURNAL, {"rubbing_blades": "all"})
    quiet = varied_rig(JOURNAL, {"rubbing_blades": "alternate"})
    assert rubbing.casing == quiet.casing and rubbing.casing.n_elements == 48


def test_the_films_carry_the_blades_weight():
    """On journal bearings each film's static load is its share of the rotor's weight:
    four blades fewer take 4 ρ L w t g off the two films together."""
    blades = JOURNAL.blades
    blade_weight = (JOURNAL.material.density_kg_m3 * blades.length_m * blades.width_m
                    * blades.thickness_m * 9.81)
    loads = {n: sum(b.journal.load_n for b in varied_rig(JOURNAL, {"blade_count": n}).bearings)
             for n in (12, 16)}
    assert loads[16] - loads[12] == pytest.approx(4 * blade_weight, rel=1e-6)
    rig = varied_rig(JOURNAL, {"blade_count": 12})
    assert tuple(b.journal.load_n for b in rig.bearings) == bearing_loads_n(rig)


def _semi_major_m(rig, run, node):
    """The semi-major axis of the linear orbit of ``node`` (its static state apart)."""
    from rubdiag.modal import harmonic_response
    from rubdiag.simulation._rig_cache import damped_model

    model = damped_model(rig)
    q = harmonic_response(model, run.speed_rad_s, run.unbalance).amplitudes
    y, z = q[model.dofs.index(node, "y")], q[model.dofs.index(node, "z")]
    return math.sqrt(0.5 * (abs(y) ** 2 + abs(z) ** 2 + abs(y * y + z * z)))


def test_a_seal_rub_sets_the_seal_clearance_from_its_own_orbit():
    d = design({"speed_ratio": [0.5], "interference_ratio": {"low": 1.2, "high": 3.0},
                "fault": ["none", "rub"], "rub_kind": ["blade", "seal"],
                "casing_stiffness_scale": {"low": 0.5, "high": 2.0}}, n=8, seed=2)
    runs = d.runs(jobs=1)
    kinds = {(item.point["fault"], item.point["rub_kind"]) for item in runs}
    assert kinds == {("none", None), ("rub", "blade"), ("rub", "seal")}   # None: blank
    for item in runs:
        run, point = item.run, item.point
        (seal,) = run.rig.stator_contacts              # every run has the seal, at node 15
        assert seal.node == 15 and seal.clearance_m == NO_RUB_GAP_M
        if point["fault"] == "none":
            assert run.gap_m == NO_RUB_GAP_M and run.seal_clearance_m is None
        elif point["rub_kind"] == "blade":
            assert run.seal_clearance_m is None and run.gap_m < 1e-3
        else:                                          # the seal rubs; the blades cannot
            assert run.gap_m == NO_RUB_GAP_M
            orbit = _semi_major_m(run.rig, run, 15)
            assert run.seal_clearance_m == pytest.approx(
                orbit / point["interference_ratio"], abs=1e-9)


@pytest.mark.parametrize("factors, message", [
    ({"mu": {"low": 0.1, "high": 0.5}}, r"factors.mu with factors.rub_kind 'seal'"),
])
def test_a_seal_rub_takes_the_rigs_contact_law(factors, message):
    with pytest.raises(ValueError, match=message):
        design({"speed_ratio": [0.5], "interference_ratio": {"low": 1.2, "high": 3.0},
                "fault": ["none", "rub"], "rub_kind": ["seal"], **factors})


def test_the_seal_node_must_be_a_shaft_node():
    with pytest.raises(ValueError, match=r"base.seal_node = 99 is not a shaft node "
                                         r"\(allowed: 3\.\.27\)"):
        design({"speed_ratio": [0.5], "interference_ratio": {"low": 1.2, "high": 3.0},
                "fault": ["none", "rub"], "rub_kind": ["seal"]}, seal_node=99)


def test_a_seal_rub_is_labelled_from_the_seals_episodes(tmp_path):
    """End to end: the shaft rubs on its seal, the blades never touch the casing, and the
    row's interference ratio is the one the design asked for (the clearance is rounded to
    1 nm)."""
    d = design({"speed_ratio": {"low": 0.5, "high": 0.52}, "interference_ratio": [2.0],
                "fault": ["rub"], "rub_kind": ["seal"], "rubbing_blades": ["all"]}, n=2,
               seed=0)
    generate(d, tmp_path, jobs=1, progress=False)
    rows = load(tmp_path)
    assert len(rows) == 2 and rows["rub"].all()
    assert np.allclose(rows["interference_ratio"], 2.0, rtol=1e-3)
    assert set(rows["rub_kind"]) == {"seal"} and rows["rubbing_blades"].isna().all()
    result = simulate(d.runs(jobs=1)[0].run)
    seal = result.n_contacts                       # the last contact element
    episodes = result.contact_episodes()
    assert episodes.element.size > 0 and set(episodes.element.tolist()) == {seal}
