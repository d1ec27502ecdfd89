"""The dt-convergence study (scripts/dt_convergence.py): its stored results, the table the
documentation renders from them, and the verdicts the stated rule gives.

The fast tests read ``data/dt_convergence_runs.csv`` and ``data/dt_convergence.csv``; the
``slow`` one simulates a run again and compares it with its stored row.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script


@pytest.fixture(scope="module")
def script():
    return load_script("dt_convergence")


@pytest.fixture(scope="module")
def rows(script):
    return script.read_rows(script.RUNS_CSV)


@pytest.fixture(scope="module")
def summary(script):
    return script.read_summary(script.SUMMARY_CSV)


def test_the_documented_table_is_what_the_script_prints_from_the_stored_summary(script,
                                                                             summary):
    assert table("dt-convergence") == script.to_markdown(summary).rstrip("\n") + "\n"
    for r in summary.itertuples():       # a row per quantity and cell, with its verdict
        assert f"| {r.verdict if r.verdict == 'converged' else '**' + r.verdict + '**'} |" \
            in table("dt-convergence")


def test_every_run_is_stored_finished_and_with_the_table2_settings(script, rows):
    assert list(rows.columns) == script.ROW_COLUMNS
    assert len(rows) == len(script.grid()) == 4 * 5 * 3
    assert {script._key_tuple(r) for r in rows.to_dict("records")} == {
        script._key_tuple(k) for k in script.grid()}
    assert (rows["status"] == 0).all()
    assert (script.DURATION_S, script.DISCARD_S) == (2.3, 0.3)


def test_summary_is_the_stored_rows_summarised(script, rows, summary):
    again = script.summarise(rows)
    assert list(again.columns) == list(summary.columns)
    assert (again["quantity"] == summary["quantity"]).all()
    assert (again["verdict"] == summary["verdict"]).all()
    numeric = [c for c in summary.columns if c.startswith(("n_", "median_", "min_", "max_"))]
    numeric += ["study", "shift", "spread"]
    np.testing.assert_allclose(summary[numeric].to_numpy(float),
                               again[numeric].to_numpy(float), rtol=1e-5, equal_nan=True)


def test_verdicts_follow_from_the_stored_numbers(summary):
    """converged <=> |median 5 µs - median 2.5 µs| < min(range 5 µs, range 2.5 µs) (or equal
    medians); too few when either ensemble has fewer than 2 values; the same for 10 µs
    against 2.5 µs."""
    for r in summary.to_dict("records"):
        for coarse, suffix in (("5us", ""), ("10us", "_10us")):
            shift = abs(r[f"median_{coarse}"] - r["median_2p5us"])
            spread = min(r[f"max_{coarse}"] - r[f"min_{coarse}"],
                         r["max_2p5us"] - r["min_2p5us"])
            if r[f"n_{coarse}"] < 2 or r["n_2p5us"] < 2:
                expected = "too few"
            else:
                scale = 1e-5 * max(abs(r[f"median_{coarse}"]), abs(r["max_2p5us"]), 1e-9)
                assert math.isclose(shift, r[f"shift{suffix}"], abs_tol=scale)
                assert math.isclose(spread, r[f"spread{suffix}"], abs_tol=scale)
                expected = "converged" if shift < spread or shift == 0 else "unconverged"
            assert r[f"verdict{suffix}"] == expected, r


def test_the_variable_step_never_engages_on_the_paper_rig(rows):
    """Every run takes exactly duration/dt steps, none rejected, none shorter."""
    assert (rows["n_rejected"] == 0).all()
    assert (rows["n_steps_below_dt"] == 0).all()
    assert (rows["n_steps"] == np.round(2.3 / rows["dt_s"])).all()


def test_the_10us_ramp_01_run_of_each_cell_is_the_table2_run(rows):
    """The Table 2 runs (gap ramp 0.1 s, dt 10 µs) reappear here: Table 2's numbers."""
    table = rows[(rows["gap_ramp_s"] == 0.1) & (rows["dt_s"] == 1e-5)].set_index(
        ["case", "intensity"])
    assert table.loc[(1, "light"), "contact1_min_force_n"] == pytest.approx(64.7, abs=0.05)
    assert table.loc[(1, "light"), "contact1_sliding_entries"] == 38
    assert table.loc[(1, "light"), "contact1_sticking_entries"] == 21


@pytest.mark.slow
def test_a_stored_row_is_reproduced(script, rows):
    key = {"case": 1, "intensity": "serious", "gap_mm": 1.9, "gap_ramp_s": 0.1, "dt_s": 5e-6}
    again = pd.Series(script._row_worker(key, None))
    stored = rows[[script._key_tuple(r) == script._key_tuple(key)
                   for r in rows.to_dict("records")]].iloc[0]
    for column in script.ROW_COLUMNS:
        if column in ("wall_s", "spectrum_features") or column in key:
            continue
        assert float(again[column]) == pytest.approx(float(stored[column]), rel=1e-5,
                                                     nan_ok=True), column
    assert again["spectrum_features"] == stored["spectrum_features"]
