"""Oil whirl as a level of a design's fault factor: its severity is the
speed over the rig's threshold of instability, its label the journal's sub-synchronous
orbit share; it needs a rig on journal bearings (the preset paper-journal)."""

from __future__ import annotations

import math

import pytest

from rubdiag.dataset import Design
from rubdiag.dataset._faults import fault_labels, whirl_threshold_rad_s
from rubdiag.dataset._labels import label_run
from rubdiag.model import preset_rig
from rubdiag.simulation import simulate

TOML = """
[base]
rig = "{rig}"
duration_s = 3.0
discard_s = 1.5
reduced = true
gravity_m_s2 = 9.81
[sampling]
method = "lhs"
n = 4
seed = 2
[factors]
case = [2]
speed_ratio = {{low = 0.9, high = 0.95}}
gap_mm = [0.06]
fault = ["none", "whirl"]
whirl_speed_ratio = {{low = 1.05, high = 1.1}}
"""


def test_whirl_needs_a_rig_on_journal_bearings():
    with pytest.raises(ValueError, match=r"no journal bearing: oil whirl needs one.*paper-jour"):
        Design.from_toml(TOML.format(rig="paper"))


@pytest.fixture(scope="module")
def design():
    return Design.from_toml(TOML.format(rig="paper-journal"))


def test_a_whirl_run_turns_at_its_ratio_of_the_threshold_and_ignores_the_speed_factor(design):
    threshold = whirl_threshold_rad_s(preset_rig("paper-journal"))
    for item in design.runs():
        if item.point["fault"] == "whirl":
            assert item.run.speed_rad_s == pytest.approx(
                item.point["whirl_speed_ratio"] * threshold, rel=1e-12)
            # the row shows the speed it turned at, over its case's critical speed
            critical = design.resolved_critical_speeds_rad_s()[item.point["case"] - 1]
            assert item.point["speed_ratio"] == pytest.approx(
                item.run.speed_rad_s / critical, rel=1e-12)
        else:
            assert item.run.speed_rad_s < 0.96 * design.resolved_critical_speeds_rad_s()[1]
            assert math.isnan(item.point["whirl_speed_ratio"])
        assert item.run.rig == design.rig


def test_a_whirl_run_is_labelled_whirl_and_not_rub(design):
    """The films log episodes of their own (always engaged): not rubs. Above the threshold
    the journal's orbit is mostly sub-synchronous (whip of the first mode)."""
    item = next(r for r in design.runs() if r.point["fault"] == "whirl")
    result = simulate(item.run)
    rub = label_run(result)
    labels = fault_labels(result, rub["rub"])
    assert rub["rub"] is False and rub["n_rub_episodes"] == 0
    assert labels["subsync_share"] > 0.5 and labels["fault_whirl"] is True
    assert labels["faults"] == "whirl"
    assert 0.0 < labels["min_film_ratio"] < 1.0       # whipping, yet inside the clearance


def test_the_shipped_journal_design_has_every_level_on_paper_journal():
    import dataclasses
    from collections import Counter
    from pathlib import Path

    from rubdiag.dataset._fault_levels import FAULT_LEVELS
    from rubdiag.dataset._rig_factors import varied_rig

    path = Path(__file__).parents[2] / "data" / "designs" / "faults_journal.toml"
    design = Design.from_toml(path)
    points = design.points()      # not the runs: each rub run's gap costs a linear solve
    assert Counter(p["fault"] for p in points) == {level: 64 for level in FAULT_LEVELS}
    # every run on a variant of paper-journal: the model-uncertainty factors change only
    # its casing supports, damping, disc masses and films
    journal = preset_rig("paper-journal")
    assert design.rig == journal
    assert {dataclasses.replace(varied_rig(journal, p), casing=journal.casing,
                                damping=journal.damping, discs=journal.discs,
                                bearings=journal.bearings) for p in points} == {journal}
    assert {p["case"] for p in points} == {1, 2}


@pytest.mark.slow
def test_every_run_of_the_shipped_journal_design_keeps_its_journals_inside(tmp_path):
    """The short-bearing force holds only inside the clearance: every run of the shipped
    design (640 runs, about 15 min on 2 cores) keeps every journal inside it, and its
    forces stay finite."""
    from pathlib import Path

    import numpy as np

    from rubdiag.dataset import generate, load

    path = Path(__file__).parents[2] / "data" / "designs" / "faults_journal.toml"
    generate(Design.from_toml(path), tmp_path / "d", jobs=2, progress=False)
    rows = load(tmp_path / "d")
    assert len(rows) == 640 and (rows["status"] == "ok").all()
    assert (rows["min_film_ratio"] > 0.0).all()
    forces = rows[[c for c in rows.columns if c.endswith("_force_n")]].to_numpy(float)
    assert np.isfinite(forces[~np.isnan(forces)]).all()
