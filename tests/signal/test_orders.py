"""Order lines: amplitudes, frequencies, phases, significance, Nyquist, fractional families."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import amplitude_spectrum, feature_names, order_label, signal_features

HALF = [k / 2 for k in range(1, 17)]


def test_column_names():
    names = feature_names()
    for label in ("1x", "1p5x", "2x", "3p5x", "4x", "7p5x", "8x", "0p5x"):
        assert f"amp_{label}" in names
        assert f"freq_{label}_hz" in names
        assert f"phase_{label}_deg" in names
    for label in ("0p33x", "0p67x", "1p33x", "7p67x"):
        assert f"amp_{label}" in names
    for n in range(1, 9):
        for stem in ("sb_{n}x_delta_hz", "sb_{n}x_lower", "sb_{n}x_upper", "bb_{n}x_rms"):
            assert stem.format(n=n) in names
    for name in ("combo_fa_hz", "combo_fb_hz", "combo_order", "combo_amp_a", "combo_amp_b"):
        assert name in names
    assert "amp_3x" in names and "amp_1p0x" not in names and "amp_1x" in names
    assert len(set(names)) == len(names)
    assert order_label(1.0) == "1x" and order_label(3.5) == "3p5x" and order_label(1 / 3) == "0p33x"


@pytest.mark.parametrize(
    ("fs", "duration", "rpm"),
    [(2000.0, 2.0, 1500.0), (2048.0, 1.37, 1500.0), (5000.0, 1.111, 5700.0), (4000.0, 0.9, 3333.0)],
)
def test_amplitudes_frequencies_and_phases_without_noise(synth, fs, duration, rpm):
    f1 = rpm / 60.0
    comps = [(f1, 1.0, 0.3), (2 * f1, 0.25, -2.0), (1.5 * f1, 0.04, 1.0), (3.5 * f1, 0.02, 2.9),
             (4 * f1, 0.1, -0.5)]
    row = signal_features(synth(comps, fs, duration), fs, rpm).iloc[0]
    for f, a, phi in comps:
        label = order_label(f / f1)
        assert row[f"amp_{label}"] == pytest.approx(a, rel=0.01)
        assert row[f"freq_{label}_hz"] == pytest.approx(f, abs=0.05 / duration)
        assert row[f"phase_{label}_deg"] == pytest.approx(np.degrees(phi), abs=1.0)
    present = {order_label(f / f1) for f, _, _ in comps}
    for k in HALF:
        label = order_label(k)
        if label not in present and k * f1 < fs / 2 - 10:
            assert row[f"amp_{label}"] == 0.0
            assert np.isnan(row[f"freq_{label}_hz"]) and np.isnan(row[f"phase_{label}_deg"])
    assert row["n_half_orders"] == 2  # 1.5x and 3.5x
    assert row["speed_rpm"] == pytest.approx(rpm)


def test_line_off_the_order_is_found_within_the_band_only(synth):
    fs, rpm = 2000.0, 1500.0
    x = synth([(25.0, 1.0), (2.04 * 25.0, 0.2)], fs, 2.0, noise=1e-4)
    assert signal_features(x, fs, rpm).iloc[0]["amp_2x"] == 0.0  # 4 % off, default band 3 %
    wide = signal_features(x, fs, rpm, band=0.05).iloc[0]
    assert wide["amp_2x"] == pytest.approx(0.2, rel=0.01)
    assert wide["freq_2x_hz"] == pytest.approx(51.0, abs=0.05)


def test_strongest_line_in_the_band_wins(synth):
    fs, rpm = 4000.0, 3000.0  # 1x = 50 Hz, band ±1.5 Hz; resolution 0.25 Hz
    x = synth([(50.0, 1.0), (150.0 - 1.2, 0.05), (150.0 + 1.0, 0.08)], fs, 4.0, noise=1e-4)
    row = signal_features(x, fs, rpm).iloc[0]
    assert row["amp_3x"] == pytest.approx(0.08, rel=0.01)
    assert row["freq_3x_hz"] == pytest.approx(151.0, abs=0.05)


def test_orders_above_nyquist_are_nan(synth):
    fs, rpm = 400.0, 1500.0  # 1x = 25 Hz, Nyquist 200 Hz = 8x
    x = synth([(25.0, 1.0), (175.0, 0.1)], fs, 4.0, noise=1e-3)
    row = signal_features(x, fs, rpm).iloc[0]
    assert row["amp_7x"] == pytest.approx(0.1, rel=0.02)
    assert np.isnan(row["amp_8x"]) and np.isnan(row["freq_8x_hz"])
    assert row["amp_7p67x"] == 0.0  # 191.7 Hz ± 0.75 Hz: still below Nyquist
    assert np.isnan(row["sb_8x_delta_hz"]) and np.isnan(row["sb_8x_lower"])
    assert np.isnan(row["bb_8x_rms"])
    assert row["amp_6x"] == 0.0


def test_significance_threshold_against_the_local_median(synth):
    fs, rpm, duration = 2000.0, 1500.0, 2.0
    noise = synth([(25.0, 1.0)], fs, duration, noise=0.01, seed=3)
    f, a = amplitude_spectrum(noise, fs)
    near = (f > 50.0 - 12.5) & (f < 50.0 + 12.5)
    level = float(np.median(a[near]))  # the local median, measured here independently
    weak = signal_features(noise + synth([(50.0, 2.0 * level)], fs, duration), fs, rpm).iloc[0]
    strong = signal_features(noise + synth([(50.0, 20.0 * level)], fs, duration), fs, rpm).iloc[0]
    assert weak["amp_2x"] == 0.0
    assert strong["amp_2x"] == pytest.approx(20.0 * level, rel=0.15)
    strict = signal_features(noise + synth([(50.0, 20.0 * level)], fs, duration), fs, rpm,
                      threshold=40.0).iloc[0]
    assert strict["amp_2x"] == 0.0


def test_third_order_family(synth):
    fs, rpm = 2000.0, 1500.0
    comps = [(25.0, 1.0), (25.0 / 3, 0.05), (5 * 25.0 / 3, 0.03)]
    row = signal_features(synth(comps, fs, 3.0, noise=1e-4), fs, rpm).iloc[0]
    assert row["amp_0p33x"] == pytest.approx(0.05, rel=0.01)
    assert row["amp_1p67x"] == pytest.approx(0.03, rel=0.01)
    assert row["amp_0p67x"] == 0.0
    assert row["n_third_orders"] == 2 and row["n_half_orders"] == 0


@pytest.mark.parametrize("noise", [0.0, 1e-4, 1e-2, 0.1])
@pytest.mark.parametrize("seed", [0, 1])
def test_no_false_fractional_line_or_pair_on_harmonics_only(synth, noise, seed):
    fs, rpm = 2000.0, 1500.0
    comps = [(25.0 * n, 1.0 / n**2, 0.7 * n) for n in range(1, 13)]
    row = signal_features(synth(comps, fs, 2.3, noise=noise, seed=seed), fs, rpm).iloc[0]
    assert row["n_half_orders"] == 0
    assert row["n_third_orders"] == 0
    assert np.isnan(row["combo_fa_hz"]) and row["combo_amp_a"] == 0.0
    assert all(np.isnan(row[f"sb_{n}x_delta_hz"]) for n in range(1, 9))
    assert row["amp_1x"] == pytest.approx(1.0, rel=0.01 + 10 * noise)


def test_segment_averaging_and_linear_detrend(synth):
    fs, rpm = 2000.0, 1500.0
    x = synth([(25.0, 1.0), (37.5, 0.05), (100.3, 0.02)], fs, 8.0, noise=1e-3)
    x += np.linspace(0.0, 3.0, x.size)  # a drift that linear detrending removes
    row = signal_features(x, fs, rpm, nperseg=4000, detrend="linear").iloc[0]
    assert row["amp_1x"] == pytest.approx(1.0, rel=0.01)
    assert row["amp_1p5x"] == pytest.approx(0.05, rel=0.02)
    assert row["amp_4x"] == pytest.approx(0.02, rel=0.02)
    assert row["freq_4x_hz"] == pytest.approx(100.3, abs=0.05)
    with pytest.raises(ValueError, match="too short"):
        signal_features(x, fs, rpm, nperseg=400)  # 0.2 s segments hold 5 revolutions
