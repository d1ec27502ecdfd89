"""The confuser tables of data/designs/faults_bands.toml (every fault level in the same
speed bands: around half of and around each case's critical speed) against the goals: rub
against everything, false rub alarms per confuser, the fault classes, crack against
misalignment — by design point and by speed band. A goal not met is a strict xfail with its
measured number, interval and what limits it.

The stored CSVs (data/bands_confuser_cells.csv, bands_confuser_rates.csv,
bands_one_vs_one.csv) come from the dataset of data/designs/faults_bands_slice.toml, the
design's 320-run slice with its factors (the 960-run design takes about three times as
long): ``rubdiag dataset data/designs/faults_bands_slice.toml --out bands-slice --jobs 2``
(17 min on 2 busy cores), then ``python scripts/confuser_tables.py bands-slice --design
faults_bands`` (4.5 min).
"""

import pandas as pd
import pytest
from scripts_loader import load_script

script = load_script("confuser_tables")
CELLS_CSV, RATES_CSV, ONE_CSV, SPLITS = script.OUTPUTS["faults_bands"]
CELLS = pd.read_csv(CELLS_CSV)
RATES = pd.read_csv(RATES_CSV)
ONE = pd.read_csv(ONE_CSV)
GOALS = {**script.GOALS, "fault_macro_f1_band": 0.85, "crack_vs_misalignment": 0.90}
SPLIT_NAMES = {"group": "design point", "speed_ratio": "speed band"}


def _cell(target, split):
    return script.cell(CELLS, target, split)


def _alarms(target, split):
    return script.alarms(RATES, target, split)


def test_every_cell_and_pair_is_stored_by_point_and_by_speed_band():
    assert list(zip(CELLS.target, CELLS.split, strict=True)) == script.CELLS
    for target, split in script.CELLS:
        r = RATES[(RATES.target == target) & (RATES.split == split)]
        assert set(r.faults) >= {"none", *script.CONFUSER_KINDS}
    assert SPLITS == ("group", "speed_ratio")
    for split in SPLITS:
        one = ONE[ONE.split == split]
        assert len({(a, b) for a, b in zip(one.a, one.b, strict=True)}) == 4 + 6
        assert set(one.family) == set(script.FAMILY_GROUPS)
    # every run of the slice is in the tables: 320 rows, none lost to a failed run
    assert (CELLS.n_rows == 320).all()


def test_rates_and_intervals_are_consistent():
    rated = RATES[RATES.n > 0]
    assert ((rated.rate - rated.n_called_rub / rated.n).abs() < 1e-5).all()   # %.6g
    scored = ONE.dropna(subset=["macro_f1"])
    for frame, value in ((rated, "rate"), (CELLS, "macro_f1"), (scored, "macro_f1")):
        lo = frame["lo" if "lo" in frame else "macro_f1_lo"]
        hi = frame["hi" if "hi" in frame else "macro_f1_hi"]
        assert (lo <= frame[value] + 1e-6).all() and (frame[value] <= hi + 1e-6).all()


def test_a_pair_without_enough_runs_is_stored_without_a_score():
    few = ONE[(ONE.n_a < script.MIN_PAIR_RUNS) | (ONE.n_b < script.MIN_PAIR_RUNS)]
    assert few.macro_f1.isna().all()
    assert ONE.drop(few.index).macro_f1.notna().all()


def test_the_classifier_beats_its_shuffled_labels():
    assert (CELLS.macro_f1 > CELLS.shuffled + 0.2).all()


# --- the goals -----------------------------------------------------------------------------
_FAULT_LIMITS = (
    "15 classes: the 7 that carry whirl (which comes from the response, only in case 2 "
    "around the second critical speed) hold 18 runs, 0-6 each, too few to learn (F1 "
    "0-0.50); over the 8 classes of the design's levels alone macro-F1 is {eight}: a loose "
    "pedestal is barely seen by shaft probes behind the oil film ({loose}), and rub hides "
    "a crack ({crack})")
XFAIL: dict[str, str] = {
    "fault macro-F1, design point": "0.625 [0.577, 0.696] < 0.90: " + _FAULT_LIMITS.format(
        eight="0.80", loose="looseness called none 9 times of 39, rub+looseness called rub "
        "9 of 40, rub called rub+looseness 8 of 42", crack="rub+crack called rub 9 of 39"),
    "fault macro-F1, speed band": "0.679 [0.583, 0.762] < 0.85: " + _FAULT_LIMITS.format(
        eight="0.78", loose="rub+looseness called rub 15 times of 40, rub called "
        "rub+looseness 13 of 42, looseness called none 6 of 39", crack="rub+crack called "
        "rub 5 of 39"),
}
for _split in SPLIT_NAMES.values():
    XFAIL[f"held-out runs per confuser, {_split}"] = (
        "the generated slice holds 38-40 runs of each confuser without rub and 15 whirl runs "
        "(0 of them called rubbing), fewer than the 60 that make a 5 % rate meaningful; the "
        "960-run design gives about 120 (whirl about 45)")


def _goal(name, *args):
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[name])] if name in XFAIL else []
    return pytest.param(*args, id=name, marks=marks)


@pytest.mark.parametrize("split", [_goal(f"rub macro-F1, {SPLIT_NAMES[s]}", s)
                                   for s in SPLITS])
def test_goal_rub_against_everything(split):
    assert _cell("rub", split).macro_f1 >= GOALS["rub_macro_f1"]


@pytest.mark.parametrize("split, kind", [
    _goal(f"false rub alarm, {kind}, {SPLIT_NAMES[split]}", split, kind)
    for split in SPLITS for kind in script.CONFUSER_KINDS])
def test_goal_false_rub_alarm_per_confuser(split, kind):
    alarm = _alarms("rub", split).loc[kind]
    assert alarm.n > 0
    assert alarm.rate <= GOALS["false_alarm"]


@pytest.mark.parametrize("split", [_goal(f"held-out runs per confuser, {SPLIT_NAMES[s]}", s)
                                   for s in SPLITS])
def test_goal_enough_runs_per_confuser(split):
    assert (_alarms("rub", split).n >= GOALS["min_runs"]).all()


@pytest.mark.parametrize("split, goal", [
    _goal("fault macro-F1, design point", "group", GOALS["fault_macro_f1"]),
    _goal("fault macro-F1, speed band", "speed_ratio", GOALS["fault_macro_f1_band"])])
def test_goal_fault_classes(split, goal):
    assert _cell("fault", split).macro_f1 >= goal


@pytest.mark.parametrize("split", [_goal(f"crack vs misalignment, {SPLIT_NAMES[s]}", s)
                                   for s in SPLITS])
def test_goal_crack_told_from_misalignment(split):
    pair = ONE[(ONE.split == split) & (ONE.a == "misalignment") & (ONE.b == "crack")
               & (ONE.family == "all")].iloc[0]
    assert min(pair.n_a, pair.n_b) >= 30
    assert pair.macro_f1 >= GOALS["crack_vs_misalignment"]


@pytest.mark.parametrize("factor", [_goal(f"band of {f}", f) for f in script.UNCERTAINTY])
def test_goal_model_uncertainty_band(factor):
    drop = _cell("rub", "group").macro_f1 - _cell("rub", factor).macro_f1
    assert drop <= GOALS["band_drop"]
