"""Rig presets: ``paper`` is the study's rig, ``paper-pedestal`` the same rig with its drive-end
bearing on a pedestal, whose rotor modes stay where they were."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from rubdiag.model import PRESETS, paper_rig, preset_rig
from rubdiag.simulation._rig_cache import forward_critical_speeds


def test_paper_is_the_study_rig():
    assert preset_rig("paper") == paper_rig()


def test_an_unknown_preset_is_refused_with_the_list():
    with pytest.raises(ValueError, match=r"rig.*paper, paper-pedestal"):
        preset_rig("papr")


def test_the_pedestal_rig_differs_only_by_its_pedestal():
    base, rig = paper_rig(), preset_rig("paper-pedestal")
    assert rig.bearings[0].pedestal is not None and rig.bearings[1].pedestal is None
    assert rig.shaft == base.shaft and rig.discs == base.discs and rig.casing == base.casing
    assert rig.bearings[0].k_y_n_m == base.bearings[0].k_y_n_m


def test_the_pedestal_leaves_the_rotor_critical_speeds_within_a_tenth_of_a_percent():
    """The preset's docstring promises the rotor's criticals move by under 0.1 %: a pedestal
    of 20 kg on 20 MN/m (its own frequency sqrt(k/m)/2pi = 159 Hz with the shaft held, above
    the rotor's first two modes, 25 and 94.5 Hz at rest)."""
    base = np.asarray(forward_critical_speeds(paper_rig(), 2))
    moved = np.asarray(forward_critical_speeds(preset_rig("paper-pedestal"), 2))
    assert np.all(np.abs(moved / base - 1.0) < 1e-3)
    assert not np.allclose(moved, base, rtol=1e-9, atol=0.0)     # the pedestal is in the model


@pytest.mark.parametrize("name", list(PRESETS))
def test_the_cli_takes_a_preset_name_for_rig(name):
    command = [sys.executable, "-m", "rubdiag", "modal", "--rig", name, "--n-modes", "2"]
    out = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    first = forward_critical_speeds(preset_rig(name), 1)[0] * 30.0 / math.pi
    assert f"{first:.1f}" in out.stdout


def test_the_cli_names_the_presets_for_a_missing_rig():
    out = subprocess.run([sys.executable, "-m", "rubdiag", "modal", "--rig", "nothing-here"],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "paper-pedestal" in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_the_journal_preset_s_loads_are_the_rotor_weight_each_bearing_carries():
    """paper-journal's films carry what the paper rig's rigid bearings carry under gravity
    (the static reactions of the assembled rig, computed here)."""
    import scipy.sparse.linalg as spla

    from rubdiag.assembly import assemble
    from rubdiag.model.presets import JOURNAL_LOADS_N
    from rubdiag.simulation._static_load import StaticLoad

    rig = paper_rig()
    model = assemble(rig)
    x = spla.spsolve(model.K.tocsc(), StaticLoad(gravity_m_s2=-9.81).vector(model.M,
                                                                           model.dofs))
    reactions = [-b.k_y_n_m * x[model.dofs.index(b.node, "y")] for b in rig.bearings]
    np.testing.assert_allclose(JOURNAL_LOADS_N, reactions, atol=1e-3)
    journal = preset_rig("paper-journal")
    assert [b.journal.load_n for b in journal.bearings] == list(JOURNAL_LOADS_N)
    assert journal.bearings[0].pedestal == preset_rig("paper-pedestal").bearings[0].pedestal


@pytest.fixture(scope="module")
def journal_model():
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh

    return with_rayleigh(assemble(preset_rig("paper-journal")))


def test_the_journal_preset_whips_inside_the_second_case_s_speed_range(journal_model):
    """The preset's promise: its threshold of instability lies inside case 2's range of
    the designs, 0.95-1.05 of its second critical speed, far above case 1's."""
    from rubdiag.modal import critical_speeds, stability_threshold

    first, second = critical_speeds(journal_model, n=2)
    threshold = stability_threshold(journal_model, 0.5 * first, 1.5 * second)
    assert 0.95 * second < threshold.speed_rad_s < 1.05 * second
    assert threshold.whirl_ratio == pytest.approx(first / threshold.speed_rad_s, rel=0.1)


@pytest.mark.parametrize("case", [1, 2])
def test_the_journal_preset_s_journals_start_inside_their_clearance(journal_model, case):
    """At the edges of each case's range the linear start keeps both journals inside their
    clearance (rig_system refuses a run otherwise)."""
    from rubdiag.modal import critical_speeds
    from rubdiag.simulation import Run
    from rubdiag.simulation._rig_cache import damped_model
    from rubdiag.simulation._rig_system import rig_system
    from rubdiag.simulation._static_load import StaticLoad

    critical = critical_speeds(journal_model, n=2)[case - 1]
    rig = preset_rig("paper-journal")
    for ratio in (0.95, 1.0, 1.05):
        run = Run.paper_case(case, None, speed_rpm=ratio * critical * 30 / math.pi, rig=rig,
                             duration_s=0.1, discard_s=0.0,
                             static_load=StaticLoad(gravity_m_s2=-9.81))
        rig_system(run, damped_model(rig))        # raises beyond the clearance


@pytest.mark.parametrize(("rpm", "whips"), [(4250.0, False), (4600.0, True)])
def test_the_journal_preset_whips_in_case_2_above_its_threshold(rpm, whips):
    """3 s on the reduced model (measured: sub-synchronous share of the journal's orbit
    0.02 at 4250 rpm, 0.95 at 4600 rpm, the disc at 22.7 Hz, the first mode; journals at
    0.17 c or more from the wall)."""
    from rubdiag.reduce import Reduction
    from rubdiag.runs import subsynchronous_share
    from rubdiag.simulation import Run, simulate
    from rubdiag.simulation._static_load import StaticLoad

    result = simulate(Run.paper_case(2, None, speed_rpm=rpm, duration_s=3.0, discard_s=1.5,
                                     rig=preset_rig("paper-journal"),
                                     static_load=StaticLoad(gravity_m_s2=-9.81),
                                     reduction=Reduction()))
    share = subsynchronous_share(result, 0)
    assert (share > 0.5) if whips else (share < 0.1), share
    assert result.system.contact_gap[:, -2:].min() > 0.1
