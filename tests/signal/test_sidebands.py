"""Sidebands n× ± Δ (Δ found from the data) and the broadband level around n×."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import combination_pairs, signal_features


@pytest.mark.parametrize(
    ("fs", "duration", "delta"),
    [(2000.0, 2.0, 5.0), (2000.0, 2.3, 5.0), (3000.0, 1.7, 4.3), (2048.0, 2.9, 2.5)],
)
def test_paper_sidebands_around_4x(synth, fs, duration, delta):
    f1 = 25.0  # 1500 rpm, case 1
    comps = [(f1, 1.0), (4 * f1, 0.05), (4 * f1 - delta, 0.02, 0.4), (4 * f1 + delta, 0.015, 1.9)]
    row = signal_features(synth(comps, fs, duration), fs, 1500.0).iloc[0]
    resolution = fs / round(duration * fs)
    assert row["sb_4x_delta_hz"] == pytest.approx(delta, abs=resolution)
    assert row["sb_4x_lower"] == pytest.approx(0.02, rel=0.01)
    assert row["sb_4x_upper"] == pytest.approx(0.015, rel=0.01)
    assert row["amp_4x"] == pytest.approx(0.05, rel=0.01)
    for n in (1, 2, 3, 5, 6, 7):
        assert np.isnan(row[f"sb_{n}x_delta_hz"])
        assert row[f"sb_{n}x_lower"] == 0.0 and row[f"sb_{n}x_upper"] == 0.0
    assert np.isnan(row["combo_fa_hz"])  # the sidebands are not a combination pair


def test_sidebands_with_noise_and_without_centre_line(synth):
    fs, rpm = 2000.0, 1500.0
    comps = [(25.0, 1.0), (2 * 25.0 - 3.3, 0.01), (2 * 25.0 + 3.3, 0.01), (6 * 25.0 - 4.0, 0.02),
             (6 * 25.0 + 4.0, 0.03)]
    row = signal_features(synth(comps, fs, 4.0, noise=0.002, seed=5), fs, rpm).iloc[0]
    assert row["sb_2x_delta_hz"] == pytest.approx(3.3, abs=0.25)
    assert row["sb_6x_delta_hz"] == pytest.approx(4.0, abs=0.25)
    assert row["sb_6x_upper"] == pytest.approx(0.03, rel=0.05)
    assert row["amp_6x"] == 0.0  # no centre line needed
    assert np.isnan(row["sb_4x_delta_hz"])


def test_one_sided_line_is_not_a_sideband_pair(synth):
    fs = 2000.0
    x = synth([(25.0, 1.0), (100.0, 0.05), (105.0, 0.02)], fs, 2.0, noise=1e-4)
    row = signal_features(x, fs, 1500.0).iloc[0]
    assert np.isnan(row["sb_4x_delta_hz"]) and row["sb_4x_upper"] == 0.0


@pytest.mark.parametrize("delta_orders", [0.05, 0.1, 0.2, 0.24, 0.26, 0.3, 0.4, 0.45])
def test_small_delta_is_a_sideband_large_delta_a_combination_never_both(synth, delta_orders):
    fs, f1 = 4000.0, 95.0  # case 2 speed, 5700 rpm
    d = delta_orders * f1
    x = synth([(f1, 1.0), (f1 - d, 0.03), (f1 + d, 0.02)], fs, 2.0, noise=1e-4)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    is_sideband = np.isfinite(row["sb_1x_delta_hz"])
    is_combo = np.isfinite(row["combo_fa_hz"])
    assert not (is_sideband and is_combo)
    near_third = min(abs(1 - delta_orders - 2 / 3), abs(1 + delta_orders - 4 / 3)) <= 0.03
    if delta_orders < 0.25:
        assert is_sideband
        assert row["sb_1x_delta_hz"] == pytest.approx(d, abs=0.5)
    elif not near_third:
        assert is_combo
        assert row["combo_order"] == 2
        assert row["combo_fa_hz"] == pytest.approx(f1 - d, abs=0.5)
        assert row["combo_fb_hz"] == pytest.approx(f1 + d, abs=0.5)
        pairs = combination_pairs(x, fs, 60 * f1)
        assert len(pairs) == 1 and pairs[0].order == 2


@pytest.mark.parametrize("sigma", [0.001, 0.01])
def test_broadband_rms_of_white_noise(synth, sigma):
    fs, f1 = 2000.0, 25.0
    x = synth([(f1, 1.0), (4 * f1, 0.1)], fs, 8.0, noise=sigma, seed=11)
    row = signal_features(x, fs, 60 * f1).iloc[0]
    expected = np.sqrt(2 * sigma**2 / fs * 0.5 * f1)  # density 2σ²/fs over 0.5x
    for n in (1, 2, 4, 7):
        assert row[f"bb_{n}x_rms"] == pytest.approx(expected, rel=0.2)


def test_broadband_hump_near_4x(synth):
    fs, f1, duration = 2000.0, 25.0, 4.0
    rng = np.random.default_rng(2)
    n = int(fs * duration)
    spectrum = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / fs)
    spectrum[np.abs(f - 4 * f1) > 4.0] = 0.0  # band-limited noise 96 … 104 Hz
    hump = np.fft.irfft(spectrum, n)
    hump *= 0.05 / hump.std()
    x = synth([(f1, 1.0)], fs, duration, noise=1e-4) + hump
    row = signal_features(x, fs, 60 * f1).iloc[0]
    assert row["bb_4x_rms"] == pytest.approx(0.05, rel=0.1)
    assert row["bb_3x_rms"] < 0.002 and row["bb_5x_rms"] < 0.002


def test_sidebands_need_enough_revolutions(synth):
    fs, f1 = 2000.0, 25.0
    x = synth([(f1, 1.0), (4 * f1, 0.05)], fs, 11 / f1, noise=1e-4)  # 11 revolutions
    row = signal_features(x, fs, 60 * f1).iloc[0]
    assert row["amp_4x"] == pytest.approx(0.05, rel=0.02)  # orders are still measured
    assert np.isnan(row["sb_4x_delta_hz"]) and np.isnan(row["sb_4x_lower"])
    longer = signal_features(synth([(f1, 1.0), (4 * f1, 0.05)], fs, 2.0, noise=1e-4), fs, 60 * f1)
    assert longer["sb_4x_lower"].iloc[0] == 0.0
