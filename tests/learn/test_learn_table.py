"""The classifier table (scripts/learn_table.py): the stored cells are complete, the
documentation shows exactly what they say, and the default model meets its goals.

The fast tests read data/learn_table.csv; the slow one makes the dataset of
data/designs/rub_classifier_lhs300.toml again (about 15 min on 2 cores) and recomputes the
default model's cells, which must come out identical (the evaluation is seeded).
"""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script

ROOT = Path(__file__).resolve().parents[2]
script = load_script("learn_table")
TABLE = pd.read_csv(script.CSV)
DEFAULT = "rf"     # the estimator of `rubdiag train`


def test_every_cell_is_stored():
    cells = set(zip(TABLE["target"], TABLE["split"], TABLE["estimator"], strict=True))
    assert cells == {(t, s, e) for t in script.TARGETS for s in script.SPLITS
                     for e in script.ESTIMATORS}
    assert (TABLE["unscored"] == 0).all()


def test_the_documented_table_is_what_the_stored_cells_say():
    shown = table("learn-table")
    assert shown == script.table(TABLE).rstrip("\n") + "\n"
    assert len(shown.strip().splitlines()) == 2 + len(TABLE)     # a row per stored cell
    for r in TABLE.itertuples():
        assert f"**{r.macro_f1:.2f} [{r.macro_f1_lo:.2f}, {r.macro_f1_hi:.2f}]**" in shown


def test_intervals_hold_their_values():
    for prefix in ("macro_f1", "balanced_accuracy", "b1x", "bspeed", "bfactors"):
        assert (TABLE[f"{prefix}_lo"] <= TABLE[prefix]).all(), prefix
        assert (TABLE[prefix] <= TABLE[f"{prefix}_hi"]).all(), prefix


@pytest.mark.xfail(strict=True, reason=(
    "not met since the band features leave the lines' leakage out: severity by design point "
    "(forest) and severity by speed band (logreg) have 2 of 5 shuffles outside their 95 % "
    "null intervals where chance allows 1; over the table's 80 shuffles 10 fall outside "
    "against 4 expected. Not yet explained (a leak through the grouped split, or null "
    "intervals too narrow for these features)"))
def test_shuffled_labels_score_at_chance_in_every_cell():
    """Five shuffles per cell, at most as many outside their intervals as chance allows."""
    assert (TABLE["shuffled_n"] == 5).all()
    assert TABLE["shuffled_inside"].all(), TABLE.loc[~TABLE["shuffled_inside"],
                                                     ["target", "split", "estimator"]]


_SEVERITY = ("light and serious differ by the interference ratio, a quantity of the design "
             "that the design-factors baseline reads directly")
_NOT_MET = {
    ("severity", "group"): f"0.768 is 0.099 above the design-factors baseline (0.669), "
    f"not 0.10: {_SEVERITY}",
    ("severity", "speed_ratio"): f"0.634 is 0.090 above the design-factors baseline (0.544), "
    f"not 0.10: {_SEVERITY}",
}


@pytest.mark.parametrize(("target", "split"), [
    pytest.param(t, s, marks=pytest.mark.xfail(strict=True, reason=_NOT_MET[t, s])
                 if (t, s) in _NOT_MET else ())
    for t in script.TARGETS for s in script.SPLITS])
def test_default_model_meets_its_goal(target, split):
    """Rub/no-rub macro-F1 >= 0.95; severity >= 0.10 macro-F1 above the best baseline."""
    row = TABLE[(TABLE["target"] == target) & (TABLE["split"] == split)
                & (TABLE["estimator"] == DEFAULT)].iloc[0]
    column, goal = script.GOALS[target]
    assert row[column] >= goal, (target, split, column, row[column])


@pytest.mark.slow
def test_default_cells_recomputed_from_a_fresh_dataset(tmp_path):
    from rubdiag.dataset import Design, generate
    from rubdiag.learn import read_dataset

    design = Design.from_toml(ROOT / "data" / "designs" / "rub_classifier_lhs300.toml")
    generate(design, tmp_path / "data", progress=False)
    data = read_dataset(tmp_path / "data")
    for target in script.TARGETS:
        for split in script.SPLITS:
            fresh = script.cell(data, target, split, DEFAULT)
            stored = TABLE[(TABLE["target"] == target) & (TABLE["split"] == split)
                           & (TABLE["estimator"] == DEFAULT)].iloc[0]
            for key in ("macro_f1", "macro_f1_lo", "macro_f1_hi", "b1x", "bspeed",
                        "bfactors", "margin"):
                np.testing.assert_allclose(fresh[key], stored[key], rtol=1e-5,
                                           err_msg=f"{target} {split} {key}")
