"""The tables of "Telling rub from its confusers" (scripts/confuser_tables.py): the stored
cells are complete, the documentation shows exactly what they say, the numbers are
consistent, and the goals are met — or a strict xfail says by how much not.

The stored CSVs come from the dataset of data/designs/faults_journal.toml (fixed seeds);
remaking them takes the dataset (about 20 min on 2 cores) and the script (about 15 min).
"""

import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script

script = load_script("confuser_tables")
CELLS = pd.read_csv(script.CELLS_CSV)
RATES = pd.read_csv(script.RATES_CSV)
ONE = pd.read_csv(script.ONE_CSV)
GOALS = script.GOALS


def _cell(target, split):
    return script.cell(CELLS, target, split)


def _alarms(target, split):
    return script.alarms(RATES, target, split)


@pytest.mark.parametrize("name", ["confuser-goals", "confuser-recall", "one-vs-one"])
def test_the_documented_tables_are_what_the_stored_numbers_say(name):
    assert table(name) == script.blocks()[name] + "\n"


def test_every_cell_and_pair_is_stored():
    assert list(zip(CELLS.target, CELLS.split, strict=True)) == script.CELLS
    for target, split in script.CELLS:
        r = RATES[(RATES.target == target) & (RATES.split == split)]
        assert set(r.faults) >= {"none", *script.CONFUSER_KINDS}
    pairs = {(a, b) for a, b in zip(ONE.a, ONE.b, strict=True)}
    assert len(pairs) == 4 + 6
    assert set(ONE.family) == set(script.FAMILY_GROUPS)


def test_rates_and_intervals_are_consistent():
    rated = RATES[RATES.n > 0]
    assert ((rated.rate - rated.n_called_rub / rated.n).abs() < 1e-5).all()   # %.6g
    for frame, value in ((rated, "rate"), (CELLS, "macro_f1"), (ONE, "macro_f1")):
        lo = frame["lo" if "lo" in frame else "macro_f1_lo"]
        hi = frame["hi" if "hi" in frame else "macro_f1_hi"]
        assert (lo <= frame[value] + 1e-6).all() and (frame[value] <= hi + 1e-6).all()


def test_the_classifier_beats_its_shuffled_labels():
    """A model that only memorised the design would score about as well on shuffled
    labels: every cell's macro-F1 stands well above its shuffled-label control."""
    assert (CELLS.macro_f1 > CELLS.shuffled + 0.2).all()


# --- the goals -----------------------------------------------------------------------------
# Measured numbers of goals not met go into XFAIL (strict: meeting one fails the test).
_BAND = ("the top speed band holds every whirl run (whip exists only above the threshold, "
         "1.35-1.55 x it, while every other level turns at 0.7-0.8 of its critical speed), "
         "so holding it out trains a model that never saw whip or those speeds")
XFAIL: dict[str, str] = {
    "rub macro-F1, speed band": "0.869 [0.842, 0.892] < 0.95: " + _BAND + "; it calls 55 "
                                "of 62 whip runs rubbing and finds 85 of 108 rub runs",
    "false rub alarm, whirl, speed band": "55 of 62 = 0.887 > 0.05: " + _BAND,
    "fault macro-F1, speed band": "0.839 [0.813, 0.864] < 0.90, 82 runs unscored (whirl "
                                  "classes absent from the training side): " + _BAND,
}


def _goal(name, *args):
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[name])] if name in XFAIL else []
    return pytest.param(*args, id=name, marks=marks)


@pytest.mark.parametrize("split", [_goal("rub macro-F1, group", "group"),
                                   _goal("rub macro-F1, speed band", "speed_ratio")])
def test_goal_rub_macro_f1(split):
    assert _cell("rub", split).macro_f1 >= GOALS["rub_macro_f1"]


@pytest.mark.parametrize("split, kind", [
    _goal(f"false rub alarm, {kind}, {name}", split, kind)
    for split, name in (("group", "group"), ("speed_ratio", "speed band"))
    for kind in script.CONFUSER_KINDS])
def test_goal_false_rub_alarm(split, kind):
    alarm = _alarms("rub", split).loc[kind]
    assert alarm.n >= GOALS["min_runs"]
    assert alarm.rate <= GOALS["false_alarm"]


@pytest.mark.parametrize("split", [_goal("fault macro-F1, group", "group"),
                                   _goal("fault macro-F1, speed band", "speed_ratio")])
def test_goal_fault_macro_f1(split):
    assert _cell("fault", split).macro_f1 >= GOALS["fault_macro_f1"]


@pytest.mark.parametrize("factor", [_goal(f"band of {f}", f) for f in script.UNCERTAINTY])
def test_goal_model_uncertainty_band(factor):
    drop = _cell("rub", "group").macro_f1 - _cell("rub", factor).macro_f1
    assert drop <= GOALS["band_drop"]
