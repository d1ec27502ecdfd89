"""Features measured around a line read the machine, not where its speed puts the line on
the FFT grid: a speed swept across two bins of the window moves the broadband levels and
the bands over the floor by less than OFF_BIN_BAND_TOLERANCE, line amplitudes by less than
OFF_BIN_LINE_TOLERANCE (the bands of data/tolerances.toml, which the documentation shows),
and a real broadband rise is still measured."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest
import scipy.signal
from data_tolerances import TOLERANCES

import rubdiag.signal._linefree as linefree
from rubdiag.learn._features import OrderFeatures
from rubdiag.signal._orders import HARMONICS
from rubdiag.signal._table import FEATURE_NAMES, feature_matrix

OFF_BIN_BAND_TOLERANCE = TOLERANCES["off_bin_lines"]["band"]
OFF_BIN_LINE_TOLERANCE = TOLERANCES["off_bin_lines"]["line"]
FS, DURATION = 2000.0, 4.0                     # bins of 0.25 Hz
ON_BIN_HZ = 40.0                               # 1× on a bin (2400 rpm)
OFFSETS = np.linspace(0.0, 2.0, 9)             # 1× moved across two bins, in bins
SEEDS = range(16)                              # noise records per speed
BANDS = [f"bb_{n}x_rms" for n in HARMONICS]
OVER_FLOOR = [f"bb_{n}x_over_floor" for n in HARMONICS]
AMPS = [name for name in FEATURE_NAMES if name.startswith(("amp_", "sb_", "combo_amp"))
        and not name.endswith("_delta_hz")]


def _record(f1, lines, sigma, seed, extra=None):
    """1× of amplitude 1 plus ``(order, amplitude)`` lines (fixed phases) and white noise of
    standard deviation ``sigma`` (``seed``: the same noise at every speed)."""
    t = np.arange(round(DURATION * FS)) / FS
    x = np.cos(2 * np.pi * f1 * t + 0.3)
    for j, (order, amp) in enumerate(lines):
        x += amp * np.cos(2 * np.pi * order * f1 * t + 1.1 + j)
    x += sigma * np.random.default_rng(seed).standard_normal(t.size)
    return x if extra is None else x + extra


def _sweep(lines, sigma, extra=None):
    """Features (a DataFrame, one row per speed and noise record) and the bands over the
    floor, as a classifier reads them (OrderFeatures), for every speed of the sweep."""
    speeds = ON_BIN_HZ + OFFSETS / DURATION
    X = np.array([_record(f1, lines, sigma, seed, extra) for f1 in speeds for seed in SEEDS])
    rpm = np.repeat(60.0 * speeds, len(SEEDS))
    table = pd.DataFrame(feature_matrix(X, FS, rpm), columns=list(FEATURE_NAMES))
    frame = table.add_prefix("probe__").assign(speed_rpm=rpm)
    floors = OrderFeatures(families=["sidebands"]).fit(frame)
    over = pd.DataFrame(floors.transform(frame), columns=floors.get_feature_names_out())
    for name in OVER_FLOOR:
        table[name] = over[f"probe__{name}"]
    table["offset"] = np.repeat(OFFSETS, len(SEEDS))
    return table


def _band_deviation(table, names):
    """Largest relative change of the mean over the noise records of each of ``names``,
    from the on-bin speed to any other of the sweep: the mean leaves the line's leakage and
    not which noise bins a band happens to cover."""
    mean = table.groupby("offset")[names].mean()
    return (mean / mean.iloc[0] - 1.0).abs().max().max()


@pytest.mark.parametrize("ratio", [0.05, 0.3, 1.0])
@pytest.mark.parametrize("order", [2.0, 0.5, 3.0, 1.5])
@pytest.mark.parametrize("sigma", [1e-3, 1e-5])
def test_a_strong_line_between_bins_moves_no_band_and_no_line(order, ratio, sigma):
    table = _sweep([(order, ratio)], sigma)
    assert _band_deviation(table, BANDS) < OFF_BIN_BAND_TOLERANCE
    assert _band_deviation(table, OVER_FLOOR) < OFF_BIN_BAND_TOLERANCE
    on_bin = table[AMPS].to_numpy()[: len(SEEDS)]
    for offset, rows in table.groupby("offset"):
        amps = rows[AMPS].to_numpy()
        # absent lines (0) stay absent, present lines move by less than the tolerance
        np.testing.assert_array_equal(amps == 0.0, on_bin == 0.0, err_msg=f"offset {offset}")
        np.testing.assert_allclose(amps, on_bin, rtol=OFF_BIN_LINE_TOLERANCE, atol=0.0,
                                   err_msg=f"offset {offset}")
    counts = ["n_half_orders", "n_third_orders"]                 # no line found or lost
    assert (table.groupby("offset")[counts].nunique() == 1).all().all()
    assert (table.groupby("offset")[counts].first() == table[counts].iloc[0]).all().all()
    assert (table["amp_1x"] - 1.0).abs().max() < OFF_BIN_LINE_TOLERANCE
    strong = "amp_" + f"{order:g}".replace(".", "p") + "x"
    assert (table[strong] / ratio - 1.0).abs().max() < OFF_BIN_LINE_TOLERANCE


@pytest.mark.parametrize("rpm", [1500.0, 1451.84])
def test_a_clean_1x_and_2x_read_no_broadband_on_or_off_the_bins(rpm):
    # 1× and a 2× of 0.35 × 1× and nothing else, 1 s at 10 kHz: at 1451.84 rpm 1× lies
    # between two bins; the bands hold nothing but round-off, at the floor's least (1)
    fs, f1 = 10_000.0, rpm / 60.0
    t = np.arange(10_000) / fs
    x = np.cos(2 * np.pi * f1 * t + 0.3) + 0.35 * np.cos(2 * np.pi * 2 * f1 * t + 1.1)
    table = pd.DataFrame(feature_matrix(x[np.newaxis], fs, rpm), columns=list(FEATURE_NAMES))
    frame = table.add_prefix("probe__").assign(speed_rpm=rpm)
    floors = OrderFeatures(families=["sidebands"]).fit(frame)
    over = dict(zip(floors.get_feature_names_out(), floors.transform(frame)[0], strict=True))
    assert [over[f"probe__{name}"] for name in OVER_FLOOR] == [1.0] * len(OVER_FLOOR)
    assert table["amp_2x"].iloc[0] == pytest.approx(0.35, rel=1e-6)


def _band_limited_noise(rms, lo_hz, hi_hz, seed):
    """White noise kept between ``lo_hz`` and ``hi_hz``, scaled to ``rms``."""
    n = round(DURATION * FS)
    spectrum = np.fft.rfft(np.random.default_rng(seed).standard_normal(n))
    f = np.fft.rfftfreq(n, 1.0 / FS)
    spectrum[(f < lo_hz) | (f > hi_hz)] = 0.0
    hump = np.fft.irfft(spectrum, n)
    return hump * (rms / hump.std())


def test_a_broadband_rise_around_the_line_is_still_measured():
    # a hump of band-limited noise, 2× ± 0.15×, beside a strong 2× at every speed
    rms = 0.01
    hump = _band_limited_noise(rms, 1.85 * ON_BIN_HZ, 2.15 * ON_BIN_HZ, seed=99)
    quiet = _sweep([(2.0, 0.35)], 1e-3)
    loud = _sweep([(2.0, 0.35)], 1e-3, extra=hump)
    assert _band_deviation(loud, ["bb_2x_rms", "bb_2x_over_floor"]) < OFF_BIN_BAND_TOLERANCE
    # the band holds the hump: its RMS under the Hann window (a record's Parseval), less
    # what the 2× line's main lobe covers (3-4 of the hump's 48 bins, the power of the band
    # scaled up from 76-77 bins of 81: up to 4 % low) and the noise (1e-3) adding 2e-8
    w = scipy.signal.get_window("hann", hump.size)
    seen = np.sqrt(np.sum(w**2 * hump**2) / np.sum(w**2))
    assert loud["bb_2x_rms"].to_numpy() == pytest.approx(seen, rel=0.05)
    rise = loud["bb_2x_over_floor"] / quiet["bb_2x_over_floor"]
    assert rise.min() > 30.0
    others = [f"bb_{n}x_rms" for n in HARMONICS if n != 2]
    np.testing.assert_allclose(loud[others], quiet[others], rtol=1e-4)   # not beyond the band


def test_sidebands_beside_a_strong_line_between_bins_read_as_on_a_bin():
    # 4× ± 0.1× sidebands of 0.01 beside a 4× of 0.5: found at every speed, same amplitude
    table = _sweep([(4.0, 0.5), (3.9, 0.01), (4.1, 0.012)], 1e-4)
    assert table["sb_4x_lower"].to_numpy() == pytest.approx(0.01, rel=OFF_BIN_LINE_TOLERANCE)
    assert table["sb_4x_upper"].to_numpy() == pytest.approx(0.012, rel=OFF_BIN_LINE_TOLERANCE)
    delta = table["sb_4x_delta_hz"] / (table["speed_rpm"] / 60.0)
    assert delta.to_numpy() == pytest.approx(0.1, abs=1e-4)


def test_the_library_states_the_tolerances_of_the_data_file():
    """rubdiag.signal._linefree's constants and docstring give the bands tested here."""
    assert linefree.OFF_BIN_BAND_TOLERANCE == OFF_BIN_BAND_TOLERANCE
    assert linefree.OFF_BIN_LINE_TOLERANCE == OFF_BIN_LINE_TOLERANCE
    text = " ".join(linefree.__doc__.split())
    for tolerance in (OFF_BIN_BAND_TOLERANCE, OFF_BIN_LINE_TOLERANCE):
        stated = f"{100 * tolerance:g} %"
        assert re.search(rf"(?<![\d.]){re.escape(stated)}", text), stated


def test_a_combination_pair_beside_strong_lines_between_bins_reads_as_on_a_bin():
    # 0.45× + 1.55× = 2× (0.01 and 0.012) beside a 1× and a 2× of 0.5
    table = _sweep([(2.0, 0.5), (0.45, 0.01), (1.55, 0.012)], 1e-4)
    assert (table["combo_order"] == 2.0).all()
    assert table["combo_amp_a"].to_numpy() == pytest.approx(0.01, rel=OFF_BIN_LINE_TOLERANCE)
    assert table["combo_amp_b"].to_numpy() == pytest.approx(0.012, rel=OFF_BIN_LINE_TOLERANCE)
