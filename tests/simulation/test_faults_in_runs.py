"""Faults in a run's description: ``Run(faults=...)`` on the
full and the reduced model, and in the run's description and id."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rubdiag.dataset._ids import run_id
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._faults import Crack, Faults
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict
from rubdiag.simulation._static_load import StaticLoad

#: the reduced model answers for responses within 5 % in its band (README, Reduced model)
REDUCED_RTOL = 0.05
GRAVITY = StaticLoad(direction="y", gravity_m_s2=-9.81)


def line(result, point: str, order: float) -> float:
    """The amplitude of the ``order`` line of ``point``'s displacement over the window
    (a whole number of revolutions: a lock-in average)."""
    t = result.t[result.window]
    x = result.displacement(point, windowed=True)
    omega = result.run.speed_rad_s
    revs = math.floor((t[-1] - t[0]) * omega / (2 * math.pi))
    keep = t <= t[0] + revs * 2 * math.pi / omega
    phase = np.exp(-1j * order * omega * t[keep])
    return 2 * abs(np.mean((x[keep] - x[keep].mean()) * phase))


def no_rub(**options) -> Run:
    """Case 1 on the paper rig at half its first critical speed, far from the casing."""
    return Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0, duration_s=0.8, discard_s=0.4,
                          static_load=GRAVITY, **options)


def test_a_run_without_faults_keeps_its_description_and_its_id():
    run = no_rub()
    assert "faults" not in run_to_dict(run)
    faulty = dataclasses.replace(run, faults=Faults(crack=Crack(element=10, depth_ratio=0.3)))
    data = run_to_dict(faulty)
    assert data["faults"]["crack"]["depth_ratio"] == 0.3
    assert run_from_dict(data) == faulty
    assert run_id(faulty) != run_id(run)
    misaligned = Faults(misalignment=Misalignment(node=3, drive_torque_n_m=5.0,
                                                  spacer_length_m=0.05, offset_m=2e-4))
    assert run_from_dict(run_to_dict(dataclasses.replace(run, faults=misaligned))).faults \
        == misaligned


@pytest.mark.parametrize(("faults", "message"), [
    (Faults(crack=Crack(element=99, depth_ratio=0.2)), r"faults\.crack\.element"),
    (Faults(misalignment=Misalignment(node=999, drive_torque_n_m=1.0, spacer_length_m=0.1)),
     r"faults\.misalignment\.node"),
])
def test_a_fault_off_the_rig_is_refused_by_name(faults, message):
    with pytest.raises(ValueError, match=message):
        no_rub(faults=faults)


@pytest.fixture(scope="module")
def healthy_2x():
    return line(simulate(no_rub()), "shaft 11 y", 2)


@pytest.mark.parametrize("faults", [
    Faults(crack=Crack(element=10, depth_ratio=0.4)),
    Faults(misalignment=Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                                     offset_m=5e-4)),
], ids=["crack", "misalignment"])
def test_a_faulty_run_shows_2x_on_the_full_and_the_reduced_model(faults, healthy_2x):
    """A crack next to disc 11 under gravity, or a misaligned coupling, at half the first
    critical speed makes a 2× line the healthy rotor does not have (measured: 31.5 and 235 µm
    against 0.04 µm); the reduced model, which keeps the fault's nodes physical by itself,
    gives the same line within its stated band (measured: to 0.01 %)."""
    full = simulate(no_rub(faults=faults))
    reduced = simulate(no_rub(faults=faults, reduction=Reduction()))
    a_full = line(full, "shaft 11 y", 2)
    assert a_full > 100 * healthy_2x
    assert line(reduced, "shaft 11 y", 2) == pytest.approx(a_full, rel=REDUCED_RTOL)
    assert reduced.system.extra["model"] == "reduced"


@pytest.fixture(scope="module")
def every_fault():
    """Rub, a Gasch crack, a misaligned coupling and a loose pedestal in one run: the
    pedestal rig under gravity at 1450 rpm, g0 1.6 mm (the linear approach is 2.2 mm), full
    and reduced model."""
    from rubdiag.model import preset_rig
    from rubdiag.reduce import Reduction
    from rubdiag.simulation._faults import Looseness

    faults = Faults(crack=Crack(element=10, depth_ratio=0.3, law="gasch"),
                    misalignment=Misalignment(node=3, drive_torque_n_m=20.0,
                                              spacer_length_m=0.05, angle_rad=0.01),
                    looseness=Looseness(bearing=0, preload_n=5.0, direction="z"))
    run = Run.paper_case(1, gap_mm=1.6, speed_rpm=1450.0, duration_s=0.6, discard_s=0.3,
                         rig=preset_rig("paper-pedestal"), static_load=GRAVITY,
                         faults=faults)
    return {"full": simulate(run), "reduced": simulate(dataclasses.replace(
        run, reduction=Reduction()))}


def test_every_fault_with_rub_in_one_run_each_element_acts(every_fault):
    from rubdiag.dataset._faults import fault_labels

    for model, result in every_fault.items():
        labels = fault_labels(result, rub=len(result.window_episodes()) > 0)
        assert labels["faults"] == "rub+misalignment+crack+looseness", model
        assert result.n_contacts == 8 and result.system.contact_fn.shape[1] == 10, model


def test_every_fault_with_rub_closes_the_energy_ledger(every_fault):
    """The ledger of the contacts, the crack's and the pedestal's books, the coupling's and
    gravity's loads leaves only the contacts' algorithmic energy, to round-off (measured
    2.6e-11 full, 1.1e-12 reduced, of the largest work), and that energy is small (1.3e-4 and
    1.8e-4 of it)."""
    for model, result in every_fault.items():
        sys = result.system
        scale = np.abs(sys.work_external).max() + np.abs(sys.work_drive).max()
        np.testing.assert_allclose(sys.energy_balance_residual, sys.contact_algorithmic,
                                   rtol=0, atol=1e-9 * scale, err_msg=model)
        assert np.abs(sys.energy_balance_residual).max() <= 1e-3 * scale, model


def test_every_fault_with_rub_the_reduced_model_answers_within_its_band(every_fault):
    """1x at shaft 11: 1.588 / 1.585 mm in y (measured 0.17 % apart)."""
    full, reduced = every_fault["full"], every_fault["reduced"]
    for point in ("shaft 11 y", "shaft 11 z"):
        a, b = line(full, point, 1.0), line(reduced, point, 1.0)
        assert abs(b - a) <= REDUCED_RTOL * a, (point, a, b)
