"""Combination pairs f_a + f_b = m× among the lines that are neither orders nor sidebands."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import combination_pairs, signal_features


@pytest.mark.parametrize(("fa", "fb"), [(43.0, 147.0), (44.0, 146.0), (43.37, 146.63)])
@pytest.mark.parametrize("noise", [0.0, 1e-3])
def test_paper_case_2_pair(synth, fa, fb, noise):
    fs, f1, duration = 2000.0, 95.0, 2.17
    comps = [(f1, 1.0), (2 * f1, 0.1), (fa, 0.03, 0.2), (fb, 0.05, -1.0)]
    x = synth(comps, fs, duration, noise=noise)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    resolution = fs / round(duration * fs)
    assert row["combo_fa_hz"] == pytest.approx(fa, abs=resolution)
    assert row["combo_fb_hz"] == pytest.approx(fb, abs=resolution)
    assert row["combo_order"] == 2
    assert row["combo_amp_a"] == pytest.approx(0.03, rel=0.01 + 2 * noise / 0.03)
    assert row["combo_amp_b"] == pytest.approx(0.05, rel=0.01 + 2 * noise / 0.05)
    pairs = combination_pairs(x, fs, 60 * f1)
    assert len(pairs) == 1
    assert pairs[0].order == 2 and pairs[0].fa_hz == pytest.approx(fa, abs=resolution)


@pytest.mark.parametrize(("fa", "fb", "m"), [(10.0, 85.0, 1), (100.0, 185.0, 3)])
def test_other_sum_orders(synth, fa, fb, m):
    fs, f1 = 2000.0, 95.0
    x = synth([(f1, 1.0), (fa, 0.02), (fb, 0.02)], fs, 2.0, noise=1e-4)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    assert row["combo_order"] == m
    assert row["combo_fa_hz"] == pytest.approx(fa, abs=0.5)


def test_strongest_pair_wins_and_all_pairs_are_listed(synth):
    fs, f1 = 2000.0, 95.0
    comps = [(f1, 1.0), (43.0, 0.01), (147.0, 0.05), (25.0, 0.03), (165.0, 0.04)]
    x = synth(comps, fs, 2.0, noise=1e-4)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    assert row["combo_fa_hz"] == pytest.approx(25.0, abs=0.5)  # weaker line 0.03 > 0.01
    assert row["combo_fb_hz"] == pytest.approx(165.0, abs=0.5)
    pairs = combination_pairs(x, fs, 60 * f1)
    assert [round(p.fa_hz) for p in pairs] == [25, 43]
    assert pairs[1].amp_a == pytest.approx(0.01, rel=0.02)


def test_lines_that_do_not_sum_to_an_order_make_no_pair(synth):
    fs, f1 = 2000.0, 95.0
    x = synth([(f1, 1.0), (43.0, 0.03), (150.0, 0.05)], fs, 2.0, noise=1e-4)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    assert np.isnan(row["combo_fa_hz"]) and np.isnan(row["combo_order"])
    assert row["combo_amp_a"] == 0.0 and row["combo_amp_b"] == 0.0
    assert combination_pairs(x, fs, 60 * f1) == []


def test_narrow_pair_is_not_a_combination(synth):
    fs, f1 = 2000.0, 95.0
    x = synth([(f1, 1.0), (80.0, 0.03), (110.0, 0.03)], fs, 2.0, noise=1e-4)  # 30 Hz < 0.5x
    assert np.isnan(signal_features(x, fs, 60 * f1).iloc[0]["combo_fa_hz"])


def test_tolerance_parameter(synth):
    fs, f1 = 2000.0, 95.0
    x = synth([(f1, 1.0), (43.0, 0.03), (148.2, 0.05)], fs, 2.0, noise=1e-4)  # sum 1.2 Hz off
    assert np.isnan(signal_features(x, fs, 60 * f1).iloc[0]["combo_fa_hz"])
    loose = signal_features(x, fs, 60 * f1, combo_tol_hz=1.5).iloc[0]
    assert loose["combo_fa_hz"] == pytest.approx(43.0, abs=0.1)


def test_harmonics_only_yield_no_pair_over_many_seeds(synth):
    fs, f1 = 2000.0, 95.0
    comps = [(n * f1, 1.0 / n, n) for n in range(1, 11)]
    X = np.vstack([synth(comps, fs, 2.0, noise=0.05, seed=s) for s in range(40)])
    table = signal_features(X, fs, 60 * f1)
    assert table["combo_fa_hz"].isna().all()
    assert (table["n_half_orders"] == 0).all() and (table["n_third_orders"] == 0).all()
