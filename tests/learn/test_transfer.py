"""The transfer table (scripts/transfer.py): on a small case, every row is what a hand count
of the predictions gives, and a held-out band's model never saw the band; the stored table
(data/transfer.csv) is its stored predictions counted by hand, and shows the goals for
textbook records and another simulator's records (or their strict xfails)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.stats import binomtest
from scripts_loader import load_script
from sklearn.metrics import f1_score

ROOT = Path(__file__).resolve().parents[2]
script = load_script("transfer")
KEYS = ["model", "trained_on", "scored_on"]


def wilson(prefix: str, called) -> dict:
    """``prefix`` and its interval of the share of ``called`` (scipy's Wilson interval)."""
    called = np.asarray(called, dtype=bool)
    if not called.size:
        return {}
    ci = binomtest(int(called.sum()), called.size).proportion_ci(method="wilson")
    return {prefix: called.mean(), f"{prefix}_lo": ci.low, f"{prefix}_hi": ci.high}


def hand_count(predictions: pd.DataFrame) -> pd.DataFrame:
    """The table's counts and rates from the predictions alone: per block and kind (split
    by whether the records rub), then the block's "all" row with its macro-F1."""
    rows = []
    for keys, block in predictions.groupby(KEYS, sort=False):
        block_keys = dict(zip(KEYS, keys, strict=True))
        for kind, of_kind in block.groupby("kind", sort=False):
            for rubs, name in ((False, "false_rub_alarm"), (True, "rub_recall")):
                part = of_kind[of_kind["rubbing"] == rubs]
                if len(part):
                    rows.append({**block_keys, "kind": kind, "n": len(part),
                                 "n_called_rub": int(part["called_rub"].sum()),
                                 **wilson(name, part["called_rub"])})
        truth, called = block["rubbing"].to_numpy(), block["called_rub"].to_numpy()
        rows.append({**block_keys, "kind": "all", "n": len(block),
                     "n_called_rub": int(called.sum()),
                     **wilson("false_rub_alarm", called[~truth]),
                     **wilson("rub_recall", called[truth]),
                     "macro_f1": f1_score(truth, called, labels=np.unique(truth),
                                          average="macro")})
    return pd.DataFrame(rows)


def check_against_predictions(table: pd.DataFrame, predictions: pd.DataFrame) -> None:
    """Every row of ``table`` is the hand count of ``predictions``: the same rows, counts,
    rates and Wilson intervals."""
    counted = hand_count(predictions)
    key = [*KEYS, "kind", "n"]
    merged = table.merge(counted, on=key, how="outer", suffixes=("", "_hand"),
                         indicator=True)
    assert (merged["_merge"] == "both").all(), merged.loc[merged["_merge"] != "both", key]
    assert (merged["n_called_rub"] == merged["n_called_rub_hand"]).all()
    for rate in ("false_rub_alarm", "rub_recall"):
        for column in (rate, f"{rate}_lo", f"{rate}_hi"):
            np.testing.assert_allclose(merged[column], merged[f"{column}_hand"], atol=1e-5,
                                       err_msg=column)
    np.testing.assert_allclose(merged["macro_f1"], merged["macro_f1_hand"], atol=1e-6)
    inside = merged[["macro_f1_lo", "macro_f1", "macro_f1_hi"]].dropna()
    assert (inside["macro_f1_lo"] <= inside["macro_f1"]).all()
    assert (inside["macro_f1"] <= inside["macro_f1_hi"]).all()


@pytest.fixture(scope="module")
def small_case(tiny_dataset, tiny_design, tmp_path_factory):
    """The script on the tiny dataset: case 2 held out, the tiny design on another rig
    preset, two textbook kinds, the stored ROSS records fast enough for its 0.5-s window
    (10 revolutions: 1200 rpm and up)."""
    from rubdiag.dataset import Design, generate

    work = tmp_path_factory.mktemp("transfer")
    pedestal = work / "pedestal"
    generate(Design.from_toml(tiny_design.replace('rig = "paper"', 'rig = "paper-pedestal"')),
             pedestal, jobs=1, progress=False)
    ross = pd.read_csv(ROOT / "data" / "ross_records" / "records.csv")
    ross = ross[ross["speed_rpm"] >= 1200.0].assign(
        file=lambda t: [str(ROOT / "data" / "ross_records" / f) for f in t["file"]])
    ross.to_csv(work / "ross.csv", index=False)
    table, predictions = script.transfer(tiny_dataset, work / "models", name="tiny",
                                         hold_out=[("case", 2, 2)], other=[pedestal],
                                         ross=work / "ross.csv",
                                         kinds=["2x", "0.5x"], n_splits=2)
    return table, predictions, work


def test_small_case_rows_are_the_hand_count_of_its_predictions(small_case):
    table, predictions, _ = small_case
    assert list(table.columns) == script.COLUMNS
    check_against_predictions(table, predictions)
    blocks = table.groupby(KEYS, sort=False).size()
    assert len(blocks) == 5          # held-out band, other rig, two textbook, ROSS
    assert "pedestal" in set(table["scored_on"])
    textbook = predictions[predictions["scored_on"].str.startswith("textbook")]
    assert set(textbook["kind"]) == {"2x (on bins)", "2x (between bins)", "0.5x (on bins)",
                                     "0.5x (between bins)"}
    assert not textbook["rubbing"].any()
    ross = predictions[predictions["scored_on"].str.startswith("ROSS")]
    assert set(ross["kind"]) == {"misalignment", "seal rub"}
    assert ross.loc[ross["kind"] == "seal rub", "rubbing"].all()


def test_small_case_held_out_band_was_not_trained_on(small_case, tiny_dataset):
    """The held-out model's training runs are exactly the runs outside case 2, and its
    band block scores exactly the case-2 runs."""
    from rubdiag.learn import read_dataset

    _, predictions, work = small_case
    rows = read_dataset(tiny_dataset)
    band = rows["case"] == 2
    meta = json.loads((work / "models" / "without_case_2_2" / "model.json").read_text())
    assert sorted(meta["training_runs"]["ids"]) == sorted(rows.loc[~band, "run_id"])
    scored = predictions[predictions["scored_on"] == "tiny: case 2"]
    assert sorted(scored["record"]) == sorted(rows.loc[band, "run_id"])


# ---------------------------------------------------------------- the stored full table

TABLE = pd.read_csv(script.CSV)
PREDICTIONS = pd.read_csv(script.PREDICTIONS)


def test_stored_table_is_the_hand_count_of_the_stored_predictions():
    check_against_predictions(TABLE, PREDICTIONS)


def _rows(scored_on: str, model: str = script.DEFAULT) -> pd.DataFrame:
    rows = TABLE[(TABLE["model"] == model) & (TABLE["scored_on"] == scored_on)
                 & (TABLE["kind"] != "all")]
    assert len(rows), (model, scored_on)
    return rows


TEXTBOOK_ALARM = 0.05
ROSS_ALARM, ROSS_RECALL = 0.10, 0.90

# a goal that is not met: its measured number, interval and what limits it
_THREE = ("9 of 9 called rub, 1.00 [0.70, 1.00] (Wilson), every strength (0.1-0.5 of 1x) "
          "and speed: a 3x of 10 % of 1x reads rel_amp_3x = 0.14 (over the channel's level), "
          "while no faults_journal run without rub reads more than 0.022 (y) and 0.036 (z) "
          "at the disc probes (0.07-0.13 at the bearing probes) and 16-26 % of the rubbing "
          "runs read 0.1 or more at the disc: the model reads a 3x of textbook strength as "
          "rub. Needs confusers whose 3x reaches it in training (a crack near a third of the "
          "critical speed, misalignment)")
_NOT_MET = {
    ("textbook records, probe pairs", "3x (on bins)"): _THREE,
    ("textbook records, probe pairs", "3x (between bins)"): _THREE,
    ("ROSS records, paper shaft", "crack"): (
        "4 of 8 called rub, 0.50 [0.21, 0.79] (Wilson): the four runs at 0.45 and 0.5 of the "
        "critical speed, whose 2x is 5-19 % of 1x at the disc's y probe and stronger along "
        "z, where weight acts (shaft11_z_disp__rel_amp_2x 1.37 at 0.5, beyond its training "
        "range 0-1.27), at 718-798 rpm, below the training speeds "
        "(957-8605 rpm); the paper shaft's stiff bearings leave the bearing probes at their "
        "noise floor, where every faults_journal run moves them on its oil film: another rig "
        "and speeds, which predict warns of"),
    ("ROSS records, paper shaft", "seal rub"): (
        "3 of 8 found, 0.375 [0.14, 0.69] (Wilson): ROSS's shaft-on-stator rub is a "
        "continuous annular contact whose response is almost pure 1x (2x at most 8 % of 1x, "
        "7x under 1 % at the disc's y probe); faults_journal labels only blade-casing rub "
        "(8 of 16 blades touching): no seal rub in training"),
}


def _goal_params(scored_on, column):
    rows = _rows(scored_on)
    return [pytest.param(kind, marks=pytest.mark.xfail(strict=True,
                                                       reason=_NOT_MET[scored_on, kind])
                         if (scored_on, kind) in _NOT_MET else ())
            for kind in rows.loc[rows[column].notna(), "kind"]]


@pytest.mark.parametrize("kind", _goal_params("textbook records, probe pairs",
                                              "false_rub_alarm"))
def test_textbook_records_false_rub_alarm_per_kind(kind):
    row = _rows("textbook records, probe pairs").set_index("kind").loc[kind]
    assert row["false_rub_alarm"] <= TEXTBOOK_ALARM, (row["n_called_rub"], row["n"])


@pytest.mark.parametrize("kind", _goal_params("ROSS records, paper shaft", "false_rub_alarm"))
def test_another_simulators_confusers_false_rub_alarm(kind):
    row = _rows("ROSS records, paper shaft").set_index("kind").loc[kind]
    assert row["false_rub_alarm"] <= ROSS_ALARM, (row["n_called_rub"], row["n"])


@pytest.mark.parametrize("kind", _goal_params("ROSS records, paper shaft", "rub_recall"))
def test_another_simulators_rubs_are_found(kind):
    row = _rows("ROSS records, paper shaft").set_index("kind").loc[kind]
    assert row["rub_recall"] >= ROSS_RECALL, (row["n_called_rub"], row["n"])
