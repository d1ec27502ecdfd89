"""The ``fault`` factor of dataset designs and the labels each fault's element gives
(rubdiag.dataset._faults)."""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from rubdiag._kernels import pedestal
from rubdiag._kernels.records import OPEN
from rubdiag.cli import main
from rubdiag.dataset import Design
from rubdiag.dataset._factors import Factor
from rubdiag.dataset._faults import (
    FAULT_LEVELS,
    NO_RUB_GAP_M,
    SEVERITY_FACTORS,
    fault_labels,
)
from rubdiag.dataset._labels import label_run
from rubdiag.model import preset_rig
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._faults import Crack, Faults, Looseness
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._static_load import StaticLoad

DESIGNS = Path(__file__).parents[2] / "data" / "designs"
SMALL = DESIGNS / "faults_small.toml"

BASE = """
[base]
rig = "paper-pedestal"
critical_speeds_rad_s = [157.0, 597.0]
duration_s = 1.2
gravity_m_s2 = 9.81
[sampling]
method = "lhs"
n = 16
seed = 1
[factors]
case = [1]
speed_ratio = {low = 0.45, high = 0.55}
gap_mm = [0.3]
"""
#: the levels of a rig without journal bearings (whirl needs them: test_whirl_level.py)
LEVELS = tuple(level for level in FAULT_LEVELS if "whirl" not in level)
FAULT_FACTORS = ("fault = " + str(list(LEVELS)).replace("'", '"') + "\n"
                 "crack_depth_ratio = {low = 0.2, high = 0.45}\n"
                 "misalignment_angle_mrad = {low = 3.0, high = 10.0}\n"
                 "looseness_preload_n = {low = 0.1, high = 1.0}\n")


class TestFactor:
    def test_an_unknown_level_is_refused_with_the_allowed_list(self):
        with pytest.raises(ValueError, match=r"factors\.fault\[1\] = 'whip'.*allowed: none, "
                                             r"rub, misalignment, crack, looseness, whirl, "
                                             r"rub\+misalignment"):
            Factor("fault", levels=("rub", "whip"))

    def test_a_range_of_faults_is_refused(self):
        with pytest.raises(ValueError, match=r"factors\.fault.*a list of levels"):
            Factor.from_spec("fault", {"low": 0, "high": 1})

    def test_a_severity_needs_the_fault_factor(self):
        with pytest.raises(ValueError, match=r"factors\.crack_depth_ratio needs factors\.fault"):
            Design.from_toml(BASE + "crack_depth_ratio = {low = 0.2, high = 0.4}\n")

    def test_a_fault_level_needs_its_severity(self):
        with pytest.raises(ValueError, match=r"level 'rub\+crack' needs "
                                             r"factors\.crack_depth_ratio"):
            Design.from_toml(BASE + 'fault = ["none", "rub+crack"]\n')

    def test_a_depth_beyond_half_the_diameter_is_refused(self):
        with pytest.raises(ValueError, match=r"factors\.crack_depth_ratio\.high"):
            Factor("crack_depth_ratio", low=0.2, high=0.6)

    def test_a_wrong_base_setting_is_refused_by_name(self):
        with pytest.raises(ValueError, match=r"base\.crack_law"):
            Design.from_toml(BASE.replace("[sampling]", 'crack_law = "x"\n[sampling]')
                             + FAULT_FACTORS)


@pytest.fixture(scope="module")
def design():
    return Design.from_toml(BASE + FAULT_FACTORS)


def test_each_level_has_the_same_number_of_runs(design):
    runs = design.runs()
    assert Counter(r.point["fault"] for r in runs) == {level: 2 for level in LEVELS}
    small = Design.from_toml(SMALL)
    assert Counter(r.point["fault"] for r in small.runs()) == {lv: 8 for lv in LEVELS}


def test_the_shipped_design_has_both_cases_and_two_severities_of_each_fault():
    runs = Design.from_toml(SMALL).runs()
    for severity, fault in SEVERITY_FACTORS.items():
        if fault == "whirl":        # the shipped design's rig has no journal bearings
            continue
        for level in (fault, f"rub+{fault}"):
            mine = [r.point for r in runs if r.point["fault"] == level]
            assert len({p[severity] for p in mine}) == 2, (level, severity)
            assert {p["case"] for p in mine} == {1, 2}, level


def test_the_dry_run_counts_the_runs_of_each_level_in_the_levels_order(capsys, tmp_path):
    assert main(["dataset", str(SMALL), "--out", str(tmp_path / "d"), "--dry-run"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("runs per"))
    assert line == "runs per fault level: " + ", ".join(f"{lv} 8" for lv in LEVELS)


def test_runs_carry_only_their_faults_and_every_run_is_on_the_same_rig(design):
    for item in design.runs():
        run, present = item.run, item.point["fault"].split("+")
        assert run.rig == design.rig and run.contact_law == design.rig.contact
        assert run.static_load == StaticLoad(direction="y", gravity_m_s2=-9.81)
        names = () if run.faults is None else run.faults.names
        assert set(names) == set(present) - {"rub", "none"}
        if "rub" in present:
            assert run.gap_m == pytest.approx(0.3e-3)
        else:                               # the casing out of reach, the row says NaN
            assert run.gap_m == NO_RUB_GAP_M and math.isnan(item.point["gap_mm"])
        if "crack" not in present:
            assert math.isnan(item.point["crack_depth_ratio"])
        else:
            assert run.faults.crack.depth_ratio == item.point["crack_depth_ratio"]
        if "looseness" not in present:
            assert math.isnan(item.point["looseness_preload_n"])
        else:           # across gravity, on the drive-end pedestal: FaultSettings' defaults
            loose = run.faults.looseness
            assert loose.preload_n == item.point["looseness_preload_n"]
            assert (loose.bearing, loose.direction, loose.loose_stiffness_n_m) == (0, "z", 0.0)


def test_a_run_ignores_the_severities_of_absent_faults_and_its_ids_too(design):
    point = {"case": 1, "speed_ratio": 0.5, "gap_mm": 0.3, "fault": "misalignment",
             "crack_depth_ratio": 0.2, "misalignment_angle_mrad": 5.0}
    run = design.run_for(point)
    assert run == design.run_for({**point, "crack_depth_ratio": 0.4, "gap_mm": 2.0})
    assert run.faults.misalignment.angle_rad == pytest.approx(5e-3)
    healthy = design.run_for({**point, "fault": "none", "misalignment_angle_mrad": 9.0})
    assert healthy == design.run_for({**point, "fault": "none"}) and healthy.faults is None


def test_a_design_without_fault_settings_writes_none_and_round_trips(design):
    text = (DESIGNS / "rub_lhs200.toml").read_text()
    assert "gravity" not in Design.from_toml(text).to_toml()
    assert Design.from_toml(design.to_toml()) == design
    assert "gravity_m_s2 = 9.81" in design.to_toml()


def quick_run(**options) -> Run:
    """Case 1 at half its first critical speed under gravity, casing out of reach, 0.3 s."""
    return Run.paper_case(1, gap_mm=NO_RUB_GAP_M * 1e3, speed_rpm=750.0, duration_s=0.3,
                          discard_s=0.1, static_load=StaticLoad(gravity_m_s2=-9.81),
                          reduction=Reduction(), **options)


def test_a_healthy_run_far_from_the_casing_does_not_rub():
    result = simulate(quick_run())
    labels = {**label_run(result), **fault_labels(result, rub=False)}
    assert len(result.system.episodes) == 0 and labels["rub"] is False
    assert labels["faults"] == "none" and math.isnan(labels["crack_open_fraction"])


def test_the_crack_label_is_the_share_of_the_window_its_element_is_engaged():
    result = simulate(quick_run(faults=Faults(crack=Crack(element=10, depth_ratio=0.4,
                                                          law="gasch"))))
    labels = {**label_run(result), **fault_labels(result, rub=label_run(result)["rub"])}
    crack = result.n_contacts                 # 0-based column: after the contacts
    status = result.system.contact_status[result.window, crack]
    sampled = np.mean(status != OPEN)         # the element's sampled status
    assert labels["crack_open_fraction"] == pytest.approx(sampled, abs=0.01)
    assert 0.2 < labels["crack_open_fraction"] < 0.8       # it breathes under gravity
    assert labels["fault_crack"] is True and labels["rub"] is False     # not a rub
    assert labels["faults"] == "crack" and labels["n_rub_episodes"] == 0


def test_the_misalignment_label_is_the_coupling_models_2x_force():
    coupling = Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                            angle_rad=0.01)
    result = simulate(quick_run(faults=Faults(misalignment=coupling)))
    labels = fault_labels(result, rub=False)
    # small angles: the 2× force ≈ T α₀ / (2 L) (rubdiag.dataset._faults)
    assert labels["misalignment_2x_force_n"] == pytest.approx(20.0 * 0.01 / 0.1, rel=0.01)
    assert labels["fault_misalignment"] is True and labels["faults"] == "misalignment"
    weak = dataclasses.replace(coupling, angle_rad=1e-3)     # 0.2 N: under the threshold
    labels = fault_labels(simulate(quick_run(faults=Faults(misalignment=weak))), rub=True)
    assert labels["fault_misalignment"] is False and labels["faults"] == "rub"


def loose_run(preload_n: float, **faults) -> Run:
    """``quick_run`` on the pedestal rig with the drive-end pedestal loose across gravity."""
    loose = Looseness(bearing=0, preload_n=preload_n, direction="z")
    return quick_run(rig=preset_rig("paper-pedestal"),
                     faults=Faults(looseness=loose, **faults))


def sampled_share(result, column: int, statuses) -> float:
    """The share of the window's output samples in which element column ``column`` (0-based)
    is in one of ``statuses``: an estimate independent of the status log."""
    status = result.system.contact_status[result.window, column]
    return float(np.mean(np.isin(status, statuses)))


def test_the_looseness_label_is_the_share_of_the_window_the_pedestal_is_lifted():
    """At half the first critical speed the drive-end bearing's 1× force across gravity is
    about 0.5 N: a 0.2 N preload lets the pedestal lift, a 5 N one keeps it seated."""
    loose = simulate(loose_run(0.2))
    labels = fault_labels(loose, rub=False)
    column = loose.n_contacts                   # the only fault element
    lifted = 1.0 - sampled_share(loose, column, [pedestal.SEATED])
    assert labels["lift_off_fraction"] == pytest.approx(lifted, abs=0.01)
    assert labels["lift_off_fraction"] > 0.5 and labels["fault_looseness"] is True
    assert labels["faults"] == "looseness" and label_run(loose)["rub"] is False
    assert math.isnan(labels["crack_open_fraction"])
    tight = fault_labels(simulate(loose_run(5.0)), rub=False)
    assert tight["lift_off_fraction"] == 0.0
    assert tight["fault_looseness"] is False and tight["faults"] == "none"


def test_with_a_crack_and_a_loose_pedestal_each_label_reads_its_own_element():
    """The fault elements follow the contacts in the order crack, pedestal."""
    result = simulate(loose_run(0.2, crack=Crack(element=10, depth_ratio=0.4, law="gasch")))
    labels = fault_labels(result, rub=False)
    crack, foot = result.n_contacts, result.n_contacts + 1
    assert labels["crack_open_fraction"] == pytest.approx(
        1.0 - sampled_share(result, crack, [OPEN]), abs=0.01)
    assert labels["lift_off_fraction"] == pytest.approx(
        1.0 - sampled_share(result, foot, [pedestal.SEATED]), abs=0.01)
    assert labels["faults"] == "crack+looseness"


def test_in_the_shipped_design_each_level_s_faults_act():
    """One run of each level of faults_small.toml: the rub levels rub (their gaps are the
    clearances at the static state, 1.0 or 1.4 mm, against a linear approach of 1.6–3 mm
    near the critical speeds), the no-rub levels do not, the loose pedestal lifts and the
    coupling's 2x force is over its threshold. (The crack may stay closed: near a critical
    the shaft whirls synchronously and a Gasch crack keeps the state the whirl gives it.)"""
    from rubdiag.dataset._rows import make_row

    design = Design.from_toml(SMALL)
    first = {}
    for item in design.runs():
        first.setdefault(item.point["fault"], item)
    for level, item in first.items():
        row = make_row(item, design.labels, design.noise)
        present = set(level.split("+"))
        assert row["rub"] is ("rub" in present), level
        if "looseness" in present:
            assert row["fault_looseness"] is True and row["lift_off_fraction"] > 0.5, level
        if "misalignment" in present:
            assert row["fault_misalignment"] is True, level
        if "crack" in present:
            assert 0.0 <= row["crack_open_fraction"] <= 1.0, level
        assert set(row["faults"].split("+")) <= present | {"none"}, level
