"""The confuser tables of data/designs/rub_kinds.toml against the goals: rub in its kinds —
blade rubs with 8, 12, 16 and 20 blades and three rubbing blade sets, and the shaft on a
seal — against a crack, a misaligned coupling, a loose pedestal and the healthy rotor, every
level in the same two speed bands. Held out by design point, by speed band and by blade
count: a model trained without one blade count must find rub with it. A goal not met is a
strict xfail with its measured number, interval and what limits it.

The stored CSVs (data/rub_kinds_confuser_cells.csv, rub_kinds_confuser_rates.csv,
rub_kinds_one_vs_one.csv) come from ``rubdiag dataset data/designs/rub_kinds.toml --out
rub-kinds --jobs 2`` then ``python scripts/confuser_tables.py rub-kinds --design
rub_kinds``.
"""

import pandas as pd
import pytest
from scripts_loader import load_script

script = load_script("confuser_tables")
CELLS_CSV, RATES_CSV, ONE_CSV, SPLITS = script.OUTPUTS["rub_kinds"]
CELLS = pd.read_csv(CELLS_CSV)
RATES = pd.read_csv(RATES_CSV)
ONE = pd.read_csv(ONE_CSV)
GOALS = {**script.GOALS, "fault_macro_f1_band": 0.85, "kind_recall": 0.90}
SPLIT_NAMES = {"group": "design point", "speed_ratio": "speed band",
               "blade_count": "blade count"}
CONFUSERS = ("misalignment", "crack", "looseness")
KINDS = ("blade", "seal")


def _cell(target, split):
    return script.cell(CELLS, target, split)


def _rates(split, measure):
    r = RATES[(RATES.target == "rub") & (RATES.split == split) & (RATES.measure == measure)]
    return r.set_index("faults")


def test_every_cell_is_stored_and_every_run_counted():
    cells = script.CELLS + script.EXTRA_CELLS["rub_kinds"]
    assert list(zip(CELLS.target, CELLS.split, strict=True)) == cells
    assert (CELLS.n_rows == 800).all()                 # no run lost to a failure
    for split in ("group", "speed_ratio", "blade_count"):
        recall = _rates(split, "rub recall")
        # every rub (alone or with whirl) is a blade or a seal rub, and each kind is scored
        rubs = recall.loc[["rub", *(f"rub+{k}" for k in script.CONFUSER_KINDS)], "n"].sum()
        assert recall.loc["rub (blade)", "n"] + recall.loc["rub (seal)", "n"] == rubs == 160


def test_rates_and_intervals_are_consistent():
    rated = RATES[RATES.n > 0]
    assert ((rated.rate - rated.n_called_rub / rated.n).abs() < 1e-5).all()   # %.6g
    assert ((rated.lo <= rated.rate + 1e-6) & (rated.rate <= rated.hi + 1e-6)).all()


def test_the_classifier_beats_its_shuffled_labels():
    assert (CELLS.macro_f1 > CELLS.shuffled + 0.2).all()


# --- the goals -----------------------------------------------------------------------------
_SEAL = ("{found} of 67 seal rubs found, {rate} [{lo}, {hi}]: the misses are full annular "
         "rubs in case 2 at half its critical speed (4 of 15 found by design point), where "
         "the seal, midway between the discs, sits near the node of case 2's mode: "
         "sub-micrometre clearances and almost nothing at the shaft probes. Every blade rub "
         "is found ({blade})")
_FAULT = ("10 classes: the 5 that carry whirl (which comes from each run's response, 1-24 "
          "runs each) are told apart poorly (by design point crack+whirl F1 0.49, whirl "
          "0.48, rub+whirl 0 of 1); the healthy rotor is called crack 11 times and loose 8 "
          "times of 142, and 15 seal rubs are called healthy")
XFAIL: dict[str, str] = {
    "rub recall, seal, design point": _SEAL.format(found=54, rate="0.806", lo="0.704",
                                                   hi="0.902", blade="91 of 93"),
    "rub recall, seal, speed band": _SEAL.format(found=45, rate="0.672", lo="0.554",
                                                 hi="0.791", blade="91 of 93") +
    "; held out by speed band, a model trained on the other bands also misses case 2's "
    "seal rubs near the critical speed",
    "rub recall, seal, blade count": _SEAL.format(found=52, rate="0.776", lo="0.667",
                                                  hi="0.875", blade="90 of 93"),
    "fault macro-F1, design point": "0.782 [0.736, 0.825] < 0.90: " + _FAULT,
    "fault macro-F1, speed band": "0.654 [0.607, 0.698] < 0.85: " + _FAULT +
    "; each speed band held out is a speed the model never saw for whirl",
}


def _goal(name, *args):
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[name])] if name in XFAIL else []
    return pytest.param(*args, id=name, marks=marks)


@pytest.mark.parametrize("split", [_goal(f"rub macro-F1, {SPLIT_NAMES[s]}", s)
                                   for s in ("group", "speed_ratio", "blade_count")])
def test_goal_rub_against_everything(split):
    assert _cell("rub", split).macro_f1 >= GOALS["rub_macro_f1"]


@pytest.mark.parametrize("split, kind", [
    _goal(f"false rub alarm, {kind}, {SPLIT_NAMES[split]}", split, kind)
    for split in ("group", "speed_ratio", "blade_count") for kind in ("none", *CONFUSERS)])
def test_goal_false_rub_alarm_per_confuser(split, kind):
    alarm = _rates(split, "false rub alarm").loc[kind]
    assert alarm.n >= GOALS["min_runs"]
    assert alarm.rate <= GOALS["false_alarm"]


@pytest.mark.parametrize("split, kind", [
    _goal(f"rub recall, {kind}, {SPLIT_NAMES[split]}", split, kind)
    for split in ("group", "speed_ratio", "blade_count") for kind in KINDS])
def test_goal_each_kind_of_rub_is_found(split, kind):
    """Held out by blade count, each count's runs are predicted by a model trained on the
    other counts: the recall is over the blade rubs of all four counts so predicted."""
    recall = _rates(split, "rub recall").loc[f"rub ({kind})"]
    assert recall.rate >= GOALS["kind_recall"], (recall.n_called_rub, recall.n)


@pytest.mark.parametrize("split, goal", [
    _goal("fault macro-F1, design point", "group", GOALS["fault_macro_f1"]),
    _goal("fault macro-F1, speed band", "speed_ratio", GOALS["fault_macro_f1_band"])])
def test_goal_fault_classes(split, goal):
    assert _cell("fault", split).macro_f1 >= goal


@pytest.mark.parametrize("factor", [_goal(f"band of {f}", f) for f in script.UNCERTAINTY])
def test_goal_model_uncertainty_band(factor):
    drop = _cell("rub", "group").macro_f1 - _cell("rub", factor).macro_f1
    assert drop <= GOALS["band_drop"]
