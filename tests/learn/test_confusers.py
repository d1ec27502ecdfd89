"""Rub against the faults that look like it: the confuser table counted by hand, its
intervals over design points, its place in evaluate's report, and what a fault model's
prediction says of rub."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn import cross_validate, make_pipeline
from rubdiag.learn._columns import LINE_FEATURES
from rubdiag.learn._confusers import CONFUSER_COLUMNS, calls_rub, confuser_table, has_confusers
from rubdiag.learn._persist import Model
from rubdiag.learn._predict import fault_columns, predict_rows
from rubdiag.learn._train import model_meta

# --- the table, counted by hand --------------------------------------------------------

#: run: (true faults, predicted by a rub model, design point, scored)
RUNS = [
    ("none", "False", 0, True),
    ("none", "True", 1, True),              # a false alarm on a healthy run
    ("none", "True", 2, False),             # not scored: never counted
    ("crack", "True", 3, True),             # a false alarm on a crack
    ("crack", "False", 3, True),
    ("crack", "False", 4, True),
    ("looseness+whirl", "True", 5, True),   # counts for looseness and for whirl
    ("whirl", "False", 6, True),
    ("misalignment", "True", 7, False),     # the one misalignment run is not scored
    ("rub", "True", 8, True),
    ("rub", "False", 9, True),
    ("rub+crack", "True", 10, True),
    ("rub+crack", "True", 11, True),
    ("rub+looseness", "False", 12, True),
]


def table_of(runs, **kwargs):
    true, pred, groups, scored = (list(c) for c in zip(*runs, strict=True))
    return confuser_table(true, pred, groups, scored, **kwargs).set_index(["measure",
                                                                          "faults"])


def test_rates_counted_by_hand():
    t = table_of(RUNS, n_bootstrap=500)
    assert list(t.reset_index().columns) == list(CONFUSER_COLUMNS)
    expected = {                            # (n, called rub), from the list above
        ("false rub alarm", "none"): (2, 1),
        ("false rub alarm", "misalignment"): (0, 0),
        ("false rub alarm", "crack"): (3, 1),
        ("false rub alarm", "looseness"): (1, 1),
        ("false rub alarm", "whirl"): (2, 1),
        ("rub recall", "rub"): (2, 1),
        ("rub recall", "rub+misalignment"): (0, 0),
        ("rub recall", "rub+crack"): (2, 2),
        ("rub recall", "rub+looseness"): (1, 0),
        ("rub recall", "rub+whirl"): (0, 0),
    }
    assert list(t.index) == list(expected)
    for key, (n, called) in expected.items():
        row = t.loc[key]
        assert (row["n"], row["n_called_rub"]) == (n, called), key
        if n == 0:                          # no held-out run: NaN, not an error
            assert math.isnan(row["rate"]) and math.isnan(row["lo"]) \
                and math.isnan(row["hi"])
        else:
            assert row["rate"] == pytest.approx(called / n)
            assert 0.0 <= row["lo"] <= row["rate"] <= row["hi"] <= 1.0, key
    # a confuser within one design point cannot vary between draws
    assert (t.loc[("false rub alarm", "looseness"), ["lo", "hi"]] == 1.0).all()
    assert (t.loc[("rub recall", "rub+crack"), ["lo", "hi"]] == 1.0).all()


def test_rub_recall_of_each_kind_counted_by_hand():
    """With what rubbed in each run (a design's rub_kind), the recall of each kind follows
    the table's rows: rub and rub+<fault> runs alike, an unscored run never counted."""
    kinds = [None, None, None, None, None, None, None, None, None,
             "seal", "blade", "blade", "seal", "seal"]
    t = table_of(RUNS, n_bootstrap=200, rub_kinds=kinds)
    assert list(t.index[-2:]) == [("rub recall", "rub (blade)"), ("rub recall", "rub (seal)")]
    assert tuple(t.loc[("rub recall", "rub (blade)"), ["n", "n_called_rub"]]) == (2, 1)
    assert tuple(t.loc[("rub recall", "rub (seal)"), ["n", "n_called_rub"]]) == (3, 2)
    assert list(t.index[:-2]) == list(table_of(RUNS, n_bootstrap=200).index)


def test_a_fault_model_s_classes_are_read_for_rub():
    assert calls_rub(["rub", "rub+crack", "crack", "none", "looseness+whirl", "True",
                      "False", True, False]).tolist() == [True, True, False, False, False,
                                                          True, False, True, False]
    fault_model = [("none", "rub+crack", 0, True), ("crack", "rub", 1, True),
                   ("crack", "crack", 2, True), ("rub+crack", "crack", 3, True)]
    t = table_of(fault_model, n_bootstrap=0)
    assert t.loc[("false rub alarm", "none"), "rate"] == 1.0
    assert t.loc[("false rub alarm", "crack"), "rate"] == 0.5
    assert t.loc[("rub recall", "rub+crack"), "rate"] == 0.0
    assert math.isnan(t.loc[("false rub alarm", "crack"), "lo"])     # no draws: no interval


def test_the_interval_draws_design_points_not_runs():
    # 40 healthy runs, 10 called rubbing: as 40 points, and as 20 points of two copies each
    called = np.array([True] * 10 + [False] * 30)
    true = ["none"] * 40
    alone = confuser_table(true, called, np.arange(40)).iloc[0]
    paired = confuser_table(np.repeat(true[:20], 2), np.repeat(called[::2][:20], 2),
                            np.repeat(np.arange(20), 2)).iloc[0]
    assert alone["rate"] == paired["rate"] == 0.25
    # independent runs: about the binomial interval 0.25 +- 1.96 sqrt(0.25 0.75 / 40)
    half = 1.96 * math.sqrt(0.25 * 0.75 / 40)
    assert alone["lo"] == pytest.approx(0.25 - half, abs=0.04)
    assert alone["hi"] == pytest.approx(0.25 + half, abs=0.04)
    # copies are not news: 20 points give a wider interval (about sqrt(2) wider)
    assert (paired["hi"] - paired["lo"]) > 1.2 * (alone["hi"] - alone["lo"])


def test_degenerate_inputs():
    nothing = confuser_table(["none", "rub"], ["True", "True"], [0, 1], [False, False])
    assert (nothing["n"] == 0).all() and nothing["rate"].isna().all()
    with pytest.raises(ValueError, match="one value per run"):
        confuser_table(["none", "rub"], ["True"], [0, 1])
    assert has_confusers(["none", "rub", "looseness+whirl"])
    assert not has_confusers(["none", "rub", "none"])


# --- in evaluate: synthetic runs with faults --------------------------------------------

CHANNELS = ["shaft11_y_disp", "shaft11_z_disp"]
LEVELS = ["none", "rub", "crack", "whirl", "rub+crack", "rub+whirl"]


def fault_rows(n_points: int = 48, seed: int = 5) -> pd.DataFrame:
    """Two replicates per design point, the fault levels in turn; rub raises the ½× line
    of one channel, a crack the 2×, whirl the 0.5× of the other one. A string ``fault``
    factor and a severity factor (NaN where its fault is absent), as a dataset has."""
    rng = np.random.default_rng(seed)
    faults = np.repeat([LEVELS[i % len(LEVELS)] for i in range(n_points)], 2)
    n = faults.size
    parts = [set(f.split("+")) for f in faults]
    has = {k: np.array([k in p for p in parts], dtype=float) for k in ("rub", "crack",
                                                                       "whirl")}
    cols = {"run_id": [f"{i:016x}" for i in range(n)],
            "point_id": np.repeat(np.arange(n_points), 2), "speed_rpm": np.full(n, 3000.0),
            "gap_mm": np.repeat(rng.uniform(0.5, 2.0, n_points), 2),
            "crack_depth_ratio": np.where(has["crack"] > 0, 0.3, np.nan),
            "fault": faults, "faults": faults, "rub": has["rub"] > 0,
            "severity": np.where(has["rub"] > 0, "light", "none")}
    for c in CHANNELS:
        for f in LINE_FEATURES:
            cols[f"{c}__{f}"] = np.zeros(n)
        for f in ("amp_0p5x", "amp_1p5x", "amp_2x"):
            cols[f"{c}__{f}"] = rng.random(n)
        cols[f"{c}__amp_1x"] = np.full(n, 20.0)
        cols[f"{c}__rms"] = np.full(n, 20.0)
    cols["shaft11_y_disp__amp_0p5x"] = 1.0 + 3.0 * has["rub"] + rng.normal(0.0, 0.3, n)
    cols["shaft11_y_disp__amp_2x"] = 1.0 + 3.0 * has["crack"] + rng.normal(0.0, 0.3, n)
    cols["shaft11_z_disp__amp_0p5x"] = 1.0 + 3.0 * has["whirl"] + rng.normal(0.0, 0.3, n)
    data = pd.DataFrame(cols)
    data.attrs["factors"] = ["gap_mm", "crack_depth_ratio", "fault"]
    data.attrs["acquisition"] = {
        "fs_hz": 10_000.0, "window_s": 1.0,
        "sensors": [{"name": c, "unit": "m", "quantity": "displacement",
                     "point": "shaft 11", "direction": c.split("_")[1]} for c in CHANNELS]}
    return data


def quick(data, target):
    return cross_validate(data, target, estimator="logreg", channels=CHANNELS, n_bootstrap=200,
                    n_null=200, n_shuffles=1, importances=False, audit=False)


@pytest.fixture(scope="module")
def data():
    return fault_rows()


@pytest.mark.parametrize("target", ["rub", "fault"])
def test_evaluate_reports_the_confusers(data, target):
    ev = quick(data, target)
    if target == "rub":                 # rub against everything else, confusers included
        assert ev.classes == ["False", "True"]
        assert ev.class_counts == {"False": 48, "True": 48}
    else:
        assert ev.classes == sorted(LEVELS)
    # the crack's severity is blank where no crack is: where it is blank tells the level
    assert ev.baselines.loc["design factors only", "columns"] == "gap_mm"
    assert ev.baselines.loc["design factors only", "left_out"] == "crack_depth_ratio"
    # the table again from the held-out predictions and the faults column, by hand
    p = ev.predictions[ev.predictions["scored"]]
    faults = data.loc[p.index, "faults"]
    called = p["predicted"].isin(["True", "rub", "rub+crack", "rub+whirl"])
    t = ev.confusers.set_index(["measure", "faults"])
    for kind, members in [("none", faults == "none"), ("crack", faults == "crack"),
                          ("whirl", faults == "whirl")]:
        row = t.loc[("false rub alarm", kind)]
        assert row["n"] == members.sum() > 0
        assert row["n_called_rub"] == (called & members).sum()
        assert row["lo"] <= row["rate"] <= row["hi"]
    for combo in ("rub+crack", "rub+whirl"):
        members = faults == combo
        assert t.loc[("rub recall", combo), "n_called_rub"] == (called & members).sum()
    for absent in ("misalignment", "looseness"):
        assert t.loc[("false rub alarm", absent), "n"] == 0
        assert math.isnan(t.loc[("false rub alarm", absent), "rate"])
    # the ½× line tells rub apart: few false alarms, most rub found
    assert t.loc[("false rub alarm", "crack"), "rate"] <= 0.2
    assert t.loc[("rub recall", "rub+crack"), "rate"] >= 0.8
    d = ev.to_dict()["confusers"]
    assert [(r["measure"], r["faults"], r["n"]) for r in d] == \
        list(zip(ev.confusers["measure"], ev.confusers["faults"], ev.confusers["n"],
                 strict=True))
    assert d[1]["rate"] is None                       # misalignment: null in JSON
    report = ev.to_markdown()
    assert "## Rub against the faults that look like it" in report
    row = t.loc[("false rub alarm", "crack")]
    assert (f"| false rub alarm | crack | {row['n']:.0f} | {row['n_called_rub']:.0f} | "
            f"{row['rate']:.3f} [{row['lo']:.3f}, {row['hi']:.3f}] |") in report


def test_no_confuser_table_where_it_does_not_apply(data):
    assert quick(data, "severity").confusers is None            # not a rub target
    only_rub = data[data["faults"].isin(["none", "rub"])].reset_index(drop=True)
    only_rub.attrs = data.attrs
    ev = quick(only_rub, "rub")
    assert ev.confusers is None and ev.to_dict()["confusers"] is None
    assert "Rub against the faults" not in ev.to_markdown()


def test_target_fault_needs_the_faults_label(data):
    with pytest.raises(ValueError, match="target = 'fault': the data has no 'faults' column"):
        quick(data.drop(columns=["faults"]), "fault")


# --- what a fault model's prediction says of rub -----------------------------------------


def test_fault_columns_from_given_probabilities():
    model = SimpleNamespace(meta={"target": "fault"},
                            classes=["crack", "none", "rub", "rub+crack"])
    table = pd.DataFrame({"predicted": ["rub+crack", "none"],
                          "p_crack": [0.3, 0.2], "p_none": [0.1, 0.5],
                          "p_rub": [0.2, 0.25], "p_rub+crack": [0.4, 0.05],
                          "warnings": ["", ""]})
    out = fault_columns(table, model)
    assert list(out.columns[-5:]) == ["p_predicted", "p_rubbing", "confuser", "p_confuser",
                                      "warnings"]
    assert out["p_predicted"].tolist() == [0.4, 0.5]
    assert out["p_rubbing"].tolist() == pytest.approx([0.6, 0.3])
    assert out["confuser"].tolist() == ["crack", "none"]
    assert out["p_confuser"].tolist() == [0.3, 0.5]
    rub_model = SimpleNamespace(meta={"target": "rub"}, classes=["False", "True"])
    assert fault_columns(table, rub_model) is table


def test_a_fault_model_names_rub_and_its_confuser(data):
    pipeline = make_pipeline("logreg", channels=CHANNELS, random_state=0)
    y = data["faults"].astype(str).to_numpy()
    pipeline.fit(data, y)
    model = Model(pipeline, model_meta(pipeline, data, target="fault", estimator="logreg",
                                       split="group", families=["orders"], seed=0))
    rows = data[data["faults"].isin(["rub+crack", "none", "crack"])]
    rows = rows.drop_duplicates("faults").reset_index(drop=True)
    rows.attrs = data.attrs
    table = predict_rows(model, rows).set_index(rows["faults"])
    p = table[[f"p_{c}" for c in model.classes]]
    with_rub = [c for c in model.classes if "rub" in c.split("+")]
    assert table["p_rubbing"].to_numpy() == pytest.approx(
        p[[f"p_{c}" for c in with_rub]].sum(axis=1).to_numpy())
    assert table.loc["rub+crack", "predicted"] == "rub+crack"
    assert table.loc["rub+crack", "p_rubbing"] >= 0.5
    assert table.loc["rub+crack", "confuser"] == "crack"       # its rub taken away
    assert table.loc["none", "p_rubbing"] < 0.5
    assert table.loc["crack", "confuser"] == table.loc["crack", "predicted"] == "crack"
    assert table.loc["crack", "p_confuser"] == table.loc["crack", "p_predicted"]
