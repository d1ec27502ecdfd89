"""The transfer table (scripts/transfer.py): on a small case, every row is what a hand count
of the predictions gives, and a held-out band's model never saw the band; the stored table
(data/transfer.csv, models trained on data/designs/rub_kinds.toml's dataset) is its stored
predictions counted by hand, and shows the goals for held-out blade counts and speeds,
textbook records and another simulator's records (or their strict xfails). Made by::

    python scripts/transfer.py rub-kinds --name rub_kinds --hold-out blade_count=8:8 \
        --hold-out blade_count=12:12 --hold-out blade_count=16:16 \
        --hold-out blade_count=20:20 --hold-out speed_ratio=0.9:1.1 \
        --ross data/ross_records/records.csv
"""

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
          "and speed: in rub_kinds a 3x of a tenth of 1x or more is rub's (30-34 % of the "
          "rubbing runs at the disc probes; without rub at most 0.15 (y) and 0.18 (z), the "
          "cracks at half the critical speed): the model reads a textbook 3x as rub. Needs "
          "confusers whose 3x reaches 0.5 of 1x in training (a crack near a third of the "
          "critical speed)")
_NOT_MET = {
    ("textbook records, probe pairs", "3x (on bins)"): _THREE,
    ("textbook records, probe pairs", "3x (between bins)"): _THREE,
    ("ROSS records, paper shaft", "seal rub"): (
        "0 of 8 found, 0.00 [0.00, 0.32] (Wilson): ROSS's shaft-on-stator rub runs on the "
        "paper shaft's stiff bearings, whose probes stay at their noise floor, while every "
        "rub_kinds run (seal rubs included) moves its bearing probes on an oil film; "
        "rub_kinds' own seal rubs are found in 0.81 of runs by design point (the misses at "
        "case 2's half critical speed, where the seal sits near the mode's node): another "
        "rig, which predict warns of"),
}
HELD_OUT_RECALL = 0.90
#: a held-out band's rubs that are not found: measured numbers and what limits them
_HELD_OUT_NOT_MET = {
    **{(f"rub_kinds: blade_count {n}", "rub (seal)"): (
        f"{found} of {total} seal rubs found with blade count {n} held out (the seal rubs' "
        "recall is 0.81 by design point too): a full annular rub at case 2's half critical "
        "speed, the seal near the mode's node, leaves the shaft probes almost unchanged "
        "(4 of 15 found)") for n, found, total in ((8, 12, 17), (12, 14, 20), (16, 12, 18),
                                                   (20, 8, 12))},
    ("rub_kinds: speed_ratio 0.9 to 1.1", "rub (blade)"): (
        "21 of 46 found, 0.46 [0.32, 0.60] (Wilson), trained on the band around half the "
        "critical speed only: rub near the critical speed (large 1x, a rub's lines small "
        "beside it) is never seen in training; the design holds both bands so that no "
        "level is told by its speed"),
    ("rub_kinds: speed_ratio 0.9 to 1.1", "rub (seal)"): (
        "5 of 31 found, 0.16 [0.07, 0.33] (Wilson): as the blade rubs, and a seal rub "
        "near the critical speed is almost pure 1x"),
}


def _held_out_params():
    rows = TABLE[TABLE["scored_on"].str.startswith("rub_kinds: ")
                 & TABLE["kind"].isin(["rub (blade)", "rub (seal)"])]
    return [pytest.param(r.scored_on, r.kind, id=f"{r.scored_on}, {r.kind}",
                         marks=pytest.mark.xfail(
                             strict=True, reason=_HELD_OUT_NOT_MET[r.scored_on, r.kind])
                         if (r.scored_on, r.kind) in _HELD_OUT_NOT_MET else ())
            for r in rows.itertuples()]


@pytest.mark.parametrize("scored_on, kind", _held_out_params())
def test_a_model_finds_rub_in_the_band_it_never_saw(scored_on, kind):
    """Trained without one blade count, a model finds the blade rubs of that count; and
    so on for each held-out band and kind of rub."""
    row = TABLE[(TABLE["scored_on"] == scored_on) & (TABLE["kind"] == kind)].iloc[0]
    assert row["rub_recall"] >= HELD_OUT_RECALL, (row["n_called_rub"], row["n"])


def test_every_blade_count_is_held_out_once():
    held = {s for s in TABLE["scored_on"] if s.startswith("rub_kinds: blade_count")}
    assert held == {f"rub_kinds: blade_count {n}" for n in (8, 12, 16, 20)}
    blade = TABLE[TABLE["scored_on"].isin(held) & (TABLE["kind"] == "rub (blade)")]
    assert blade["n"].sum() == 92        # every blade rub of the design but the one with whirl


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
