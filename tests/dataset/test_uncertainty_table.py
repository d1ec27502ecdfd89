"""The "Model uncertainty" table (scripts/uncertainty.py): its stored rows are what the rig
gives, and the documentation shows exactly what they say; the factors move the rig the way
their physics says."""

import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script

script = load_script("uncertainty")
ROWS = pd.read_csv(script.CSV)


def test_the_documented_table_is_what_the_stored_rows_say():
    shown = table("uncertainty")
    assert shown == script.table(ROWS) + "\n"
    assert len(shown.strip().splitlines()) == 2 + len(ROWS)         # a row per stored row


def test_every_rig_factor_level_of_the_design_is_stored():
    d = script.design()
    stored = set(zip(ROWS.factor, ROWS.value.fillna(-1.0), strict=True))
    assert stored == {(f, -1.0 if v != v else v) for f, v in script.variants(d)}


@pytest.mark.parametrize("factor", ["nominal", "bearing_clearance_scale"])
def test_stored_rows_are_what_the_rig_gives(factor):
    d = script.design()
    value = next(v for f, v in script.variants(d) if f == factor)
    fresh = script.measure(d, factor, value)
    stored = ROWS[(ROWS.factor == factor) & ((ROWS.value == value) | ROWS.value.isna())].iloc[0]
    for column in script.COLUMNS:
        assert fresh[column] == pytest.approx(stored[column], rel=1e-5), column


def _row(factor, which):
    rows = ROWS[ROWS.factor == factor].sort_values("value")
    return rows.iloc[0 if which == "low" else -1]


def test_the_factors_move_the_rig_as_their_physics_says():
    nominal = ROWS[ROWS.factor == "nominal"].iloc[0]
    # heavier discs lower both critical speeds (ω² ~ k/m)
    assert _row("disc_mass_scale", "high").crit1_rpm < nominal.crit1_rpm < _row(
        "disc_mass_scale", "low").crit1_rpm
    # the casing is coupled to the rotor only through contact: its support moves nothing
    # of the rotor's linear response
    for which in ("low", "high"):
        row = _row("casing_stiffness_scale", which)
        for column in script.COLUMNS:
            assert row[column] == pytest.approx(nominal[column], rel=1e-9), column
    # the critical speed map is undamped: the damping ratio moves the threshold only
    lo, hi = _row("damping_ratio", "low"), _row("damping_ratio", "high")
    assert lo.crit1_rpm == pytest.approx(nominal.crit1_rpm, rel=1e-9)
    assert lo.threshold_rpm < nominal.threshold_rpm < hi.threshold_rpm   # damping stabilises
