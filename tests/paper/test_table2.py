"""The study's claims, as tests on one shared full-length reproduction of Table 2.

Settings: the paper rig preset (μ = 0.4, pure penalty, distributed casing support), dt = 1e-5 s,
2.3 s with 0.3 s discarded. Claims about spectral lines are checked on start-history
ensembles (rub is chaotic), the others on the table. Where a claim were not reproduced by
these documented settings, its test would be an xfail with the measured reason.
"""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rubdiag.paper import ensemble, paper_values, reproduce, table2

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("table2")


@pytest.fixture(scope="module")
def table(out):
    return table2(out, jobs=2, log=lambda message: None)


def cell(table, case, intensity):
    return table[(table.case == case) & (table.intensity == intensity)].iloc[0]


def feature(table, case, intensity, name):
    feats = table.attrs["features"]
    index = cell(table, case, intensity).name
    return feats.loc[index, name]


def test_files_and_columns(table, out):
    for name in ("table2.csv", "table2.md", "features.csv", "fig5_unbalance.png",
                 "fig6_deflection.png", "fig7_case1_light.png", "fig8_case1_serious.png",
                 "fig9_case2_light.png", "fig10_case2_serious.png"):
        assert (out / name).stat().st_size > 1000, name
    written = pd.read_csv(out / "table2.csv")
    for column in ("case", "intensity", "gap_mm", "speed_rpm", "casing_max_y_um",
                   "contact1_min_force_n", "contact1_max_force_n", "contact1_sliding_entries",
                   "contact1_sticking_entries", "shaft_blade_spectrum_features",
                   "paper_casing_max_y_um", "paper_contact1_max_force_n", "window_s"):
        assert column in written.columns
    assert list(zip(written.case, written.intensity, strict=True)) == [
        (1, "light"), (1, "serious"), (2, "light"), (2, "serious")]
    np.testing.assert_allclose(written.speed_rpm, [1500, 1500, 5700, 5700], rtol=0.005)


def test_paper_values_are_the_studys(table):
    reference = pd.read_csv(DATA / "paper_table2.csv")
    pd.testing.assert_frame_equal(paper_values(), reference)
    assert list(table.paper_contact1_max_force_n) == [189.3, 195.7, 1042.5, 1079.6]


# --- claim 1: both gaps rub in both cases; case 2 the more serious, gap for gap ------------
@pytest.mark.parametrize("intensity", ["light", "serious"])
def test_claim1_case2_is_more_serious(table, intensity):
    one, two = cell(table, 1, intensity), cell(table, 2, intensity)
    for c in (one, two):
        assert c.contact1_max_force_n > 0 and c.contact1_sliding_entries > 0
    assert two.contact1_max_force_n / one.contact1_max_force_n >= 3.0
    assert two.casing_max_y_um / one.casing_max_y_um >= 2.5


# --- claims 2 and 3 are about spectral lines, which rub's chaos makes depend on the start
# history: they are checked on an ensemble of 5 start histories (gap ramp 0.1 s ± 2 %) of
# the two case-1 cells, and stated as "in k of 5".
@pytest.fixture(scope="module")
def case1_ensemble():
    table = ensemble([(1, 2.3), (1, 1.9)], jobs=2)
    table["intensity"] = np.where(table.gap_mm == 2.3, "light", "serious")
    return table


def count(ens, intensity, predicate):
    rows = ens[ens.intensity == intensity]
    return int(sum(predicate(r) for r in rows.to_dict("records"))), len(rows)


# --- claim 2: case 1 — 1× dominant, lines grouped around 4× with sidebands 4× ± Δ ----------
@pytest.mark.parametrize("intensity", ["light", "serious"])
def test_claim2_case1_1x_dominant(table, intensity):
    for prefix in ("shaft", "blade"):
        amps = {k: feature(table, 1, intensity, f"{prefix}_amp_{k}")
                for k in ("2x", "3x", "4x", "5x", "6x", "7x", "8x", "1p5x", "3p5x")}
        assert feature(table, 1, intensity, f"{prefix}_amp_1x") > 10 * max(amps.values())


@pytest.mark.parametrize("intensity", ["light", "serious"])
def test_claim2_case1_4x_sidebands_in_most_start_histories(case1_ensemble, intensity):
    # measured: light 5 of 5 (Δ = 2.1-2.8 Hz), serious 4 of 5 (Δ = 5.7 Hz); study: 4× ± 5 Hz
    found, n = count(case1_ensemble, intensity,
                     lambda r: 0 < r["shaft_sb_4x_delta_hz"] < 10 and r["shaft_sb_4x_lower"] > 0)
    assert found >= 3, f"4× sidebands in {found} of {n}"


# --- claim 3: case 1 serious shows 3×/2 and 7×/2, case 1 light does not ---------------------
def test_claim3_7x2_in_case1_serious_only(case1_ensemble):
    # measured: 7×/2 (14-20 µm) in 5 of 5 serious runs, 0 of 5 light runs
    serious, n = count(case1_ensemble, "serious", lambda r: r["shaft_amp_3p5x"] > 0)
    light, _ = count(case1_ensemble, "light", lambda r: r["shaft_amp_3p5x"] > 0)
    assert serious >= 4 and light <= 1, (serious, light, n)


def test_claim3_3x2_in_some_case1_serious_start_histories(case1_ensemble):
    # measured: 3×/2 (7 µm) in 3 of 5 serious runs, 0 of 5 light runs: it comes and goes
    # with the start history, so the study's single run could show it or not
    serious, n = count(case1_ensemble, "serious", lambda r: r["shaft_amp_1p5x"] > 0)
    light, _ = count(case1_ensemble, "light", lambda r: r["shaft_amp_1p5x"] > 0)
    assert serious >= 1 and light <= 1 and serious > light, (serious, light, n)


# --- claim 4: case 2 — a combination pair f_a + f_b = 2× ---------------------------------------
@pytest.mark.parametrize("intensity", ["light", "serious"])
def test_claim4_case2_combination_pair(table, intensity):
    fa = feature(table, 2, intensity, "shaft_combo_fa_hz")
    fb = feature(table, 2, intensity, "shaft_combo_fb_hz")
    f1 = cell(table, 2, intensity).speed_rpm / 60
    assert feature(table, 2, intensity, "shaft_combo_order") == 2
    assert fa + fb == pytest.approx(2 * f1, abs=0.5)          # within the 0.5 Hz resolution
    assert fa < f1 < fb and fb - fa >= 0.5 * f1
    assert "combination" in cell(table, 2, intensity).shaft_blade_spectrum_features


# --- claim 5: sticking at larger force than sliding; case-1 sticking share grows ------------
def test_claim5_sticking_at_larger_force_and_growing_share(table):
    for row in table.itertuples():
        assert row.contact1_mean_force_sticking_n > row.contact1_mean_force_sliding_n
    assert (cell(table, 1, "serious").contact1_sticking_share
            > cell(table, 1, "light").contact1_sticking_share)


# --- claim 6: numbers ---------------------------------------------------------------------------
def test_claim6_numbers_against_the_study(table):
    ratio_force = table.contact1_max_force_n / table.paper_contact1_max_force_n
    assert ratio_force.between(0.7, 1.3).all(), ratio_force.tolist()
    ratio_casing = table.casing_max_y_um / table.paper_casing_max_y_um
    assert ratio_casing.between(0.5, 2.0).all(), ratio_casing.tolist()
    assert cell(table, 1, "light").rotor_max_y_mm == pytest.approx(2.0, rel=0.3)
    # entry counts come per window and per second, with the window stated
    np.testing.assert_allclose(table.window_s, 2.0, rtol=1e-9)
    np.testing.assert_allclose(table.contact1_sliding_entries_per_s,
                               table.contact1_sliding_entries / table.window_s)


# --- resuming ------------------------------------------------------------------------------------
def test_finished_cases_are_reused_and_a_lost_one_is_rerun(table, out):
    messages = []
    reproduce(out, jobs=1, log=messages.append)
    assert sum("reused" in m for m in messages) == 4
    (out / "runs" / "case1_light.npz").unlink()
    messages.clear()
    again = reproduce(out, jobs=1, log=messages.append)
    assert sum("reused" in m for m in messages) == 3
    assert any(m.startswith("case1_light: done") for m in messages)
    np.testing.assert_array_equal(again["case1_light"].system.q,
                                  table.attrs["results"]["case1_light"].system.q)
