"""Blade contacts a run cannot close are left to the reduced model's modes and reported open.

The rig is the preset on journal bearings under gravity, as the multi-fault design runs it
without rub: the casing 50 mm away. The same run with the contacts kept physical
(``Reduction(keep_idle_contacts=True)``) is the reference: the two reductions must agree
within the reduced model's stated response error (:data:`rubdiag.reduce._check.RESPONSE_TOLERANCE`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rubdiag.assembly import assemble
from rubdiag.dataset._ids import noise_id, run_id
from rubdiag.model.presets import preset_rig
from rubdiag.reduce import Reduction, boundary_dofs, contact_dofs
from rubdiag.reduce._check import RESPONSE_TOLERANCE
from rubdiag.simulation import Run, simulate
from rubdiag.simulation import _idle_contacts as idle
from rubdiag.simulation._result import SimulationDiverged
from rubdiag.simulation._static_load import StaticLoad

GRAVITY = StaticLoad(direction="y", gravity_m_s2=-9.81)


def journal_run(gap_m: float, keep: bool = False, **options) -> Run:
    rig = preset_rig("paper-journal")
    return Run(rig=rig, speed_rad_s=2 * np.pi * 1000 / 60, unbalance=rig.unbalance(1),
               gap_m=gap_m, duration_s=0.4, discard_s=0.2, static_load=GRAVITY,
               reduction=Reduction(keep_idle_contacts=keep), **options)


@pytest.fixture(scope="module")
def pair():
    """The run with the casing out of reach, with the contacts left out and kept."""
    return simulate(journal_run(0.05)), simulate(journal_run(0.05, keep=True))


def test_out_of_reach_contacts_leave_the_reduced_model(pair):
    """The reduction without them keeps only the films' and the pedestal's DOFs physical:
    40 boundary DOFs fewer, the blades' own modes below the cutoff added back, fewer
    coordinates in all."""
    left, kept = pair
    rig = left.run.rig
    model = assemble(rig)
    with_tips = boundary_dofs(model, Reduction())
    without = boundary_dofs(model, Reduction(), blade_contacts=False)
    assert set(without) == set(with_tips) - set(contact_dofs(model)) - {
        model.dofs.index(f"blade {b}.{rig.blades.n_elements}", "rx") for b in rig.contact.blades}
    assert left.system.extra["n_reduced"] < kept.system.extra["n_reduced"]
    assert left.system.extra["idle_contacts"] == 8
    assert "idle_contacts" not in kept.system.extra


def test_left_out_contacts_are_reported_open_as_kept_ones_are(pair):
    """Same elements, numbered alike: 8 contacts then the two films; open at every sample,
    no force, no episode, all the run's time open."""
    left, kept = pair
    assert left.n_contacts == kept.n_contacts == 8
    assert left.system.contact_fn.shape == kept.system.contact_fn.shape
    np.testing.assert_array_equal(left.system.contact_status[:, :8], 1)
    np.testing.assert_array_equal(left.system.contact_fn[:, :8], 0.0)
    assert len(left.contact_episodes()) == len(kept.contact_episodes()) == 0
    np.testing.assert_allclose(left.system.time_in_status[:8, 0], left.system.t_final)
    # the films are the same elements in both, after the contacts
    np.testing.assert_allclose(left.system.contact_fn[:, 8:], kept.system.contact_fn[:, 8:],
                               rtol=RESPONSE_TOLERANCE, atol=1e-3 * kept.system.contact_fn.max())


def test_left_out_contacts_keep_their_gaps_and_the_response_its_values(pair):
    """Gap changes (g0 − gap: the tips' approach) and slips, and every recorded response,
    agree with the kept contacts' within the reduced model's stated error."""
    left, kept = pair
    for field in ("contact_gap", "contact_slip"):
        a = getattr(left.system, field)[:, :8]
        b = getattr(kept.system, field)[:, :8]
        if field == "contact_gap":
            a, b = 0.05 - a, 0.05 - b
        scale = np.abs(b).max()
        assert scale > 0
        assert np.abs(a - b).max() <= RESPONSE_TOLERANCE * scale
    q_left, q_kept = left.system.q, kept.system.q
    shaft = [j for j, p in enumerate(left.points) if p.startswith("shaft")]
    error = np.abs(q_left[:, shaft] - q_kept[:, shaft]).max(axis=0)
    assert np.all(error <= RESPONSE_TOLERANCE * np.abs(q_kept[:, shaft]).max(axis=0))


def test_contacts_within_reach_stay_physical():
    """A rub gap (and any gap under a millimetre, or under 100 × the approach) keeps them."""
    assert not idle.is_idle(0.9e-3, 1e-6)
    assert not idle.is_idle(0.05, 0.6e-3)
    assert idle.is_idle(0.05, 0.4e-3)
    result = simulate(dataclasses.replace(journal_run(0.002), duration_s=0.25, discard_s=0.2))
    assert "idle_contacts" not in result.system.extra


def test_a_rig_without_other_nonlinear_elements_keeps_its_contacts():
    """On the paper rig (rolling bearings, no fault) the contacts are its only nonlinear
    elements: a run with the casing out of reach is simulated with them."""
    run = Run.paper_case(1, gap_mm=40.0, duration_s=0.2, discard_s=0.1, reduction=Reduction())
    assert "idle_contacts" not in simulate(run).system.extra


def test_a_contact_that_comes_within_reach_stops_the_run_with_what_it_computed(monkeypatch):
    """If the criterion let through a run whose tips reach half their gap, the run stops
    with SimulationDiverged carrying the result, the contacts reported open."""
    monkeypatch.setattr(idle, "IDLE_GAP_RATIO", 0.0)
    monkeypatch.setattr(idle, "MIN_IDLE_GAP_M", 0.0)
    monkeypatch.setattr("rubdiag.simulation._rig_system.MIN_IDLE_GAP_M", 0.0)
    run = dataclasses.replace(journal_run(1e-6), duration_s=0.25, discard_s=0.2)
    with pytest.raises(SimulationDiverged, match="keep_idle_contacts=True") as failure:
        simulate(run)
    partial = failure.value.result
    assert partial.system.extra["idle_contacts"] == 8
    assert partial.system.contact_gap[:, :8].min() < 0.5e-6


def test_keeping_idle_contacts_is_a_solver_setting_of_the_run():
    """Its own run id (another computation), the same noise draw (the same machine)."""
    left, kept = journal_run(0.05), journal_run(0.05, keep=True)
    assert run_id(left) != run_id(kept)
    assert noise_id(left) == noise_id(kept)
    with pytest.raises(TypeError, match="keep_idle_contacts"):
        Reduction(keep_idle_contacts="yes")
