"""Invariants of the feature table (hypothesis): scaling, time shift, an unrelated tone."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rubdiag.signal import signal_features

FS = 2000.0
AMPLITUDE_COLUMNS = ["amp_1x", "amp_1p5x", "amp_2x", "amp_3p5x", "amp_4x", "sb_4x_lower",
                     "sb_4x_upper", "combo_amp_a", "combo_amp_b"]


def rub_like(f1, amps, phases, duration, t0=0.0, noise=0.0, seed=0):
    """1×, 2×, 3×/2, 7×/2, 4× ± Δ and a combination pair summing to 2×, at time offset t0."""
    delta = 0.2 * f1
    freqs = [f1, 1.5 * f1, 2 * f1, 3.5 * f1, 4 * f1, 4 * f1 - delta, 4 * f1 + delta,
             0.27 * f1, 1.73 * f1]  # same order as AMPLITUDE_COLUMNS
    n = round(duration * FS)
    t = t0 + np.arange(n) / FS
    x = sum(a * np.cos(2 * np.pi * f * t + p) for f, a, p in zip(freqs, amps, phases, strict=True))
    if noise:
        x = x + noise * np.random.default_rng(seed).standard_normal(n)
    return x


signals = st.fixed_dictionaries(
    {
        "f1": st.floats(20.0, 40.0),
        "amps": st.lists(st.floats(0.1, 1.0), min_size=9, max_size=9),
        "phases": st.lists(st.floats(-np.pi, np.pi), min_size=9, max_size=9),
        "duration": st.floats(3.0, 4.0),
    }
)


@settings(max_examples=15, deadline=None)
@given(s=signals, scale=st.floats(1e-3, 1e4))
def test_scaling_scales_the_amplitudes(s, scale):
    x = rub_like(s["f1"], s["amps"], s["phases"], s["duration"], noise=1e-3)
    rpm = 60 * s["f1"]
    a = signal_features(x, FS, rpm).iloc[0]
    b = signal_features(scale * x, FS, rpm).iloc[0]
    for col in [*AMPLITUDE_COLUMNS, "rms", "bb_4x_rms"]:
        assert b[col] == pytest.approx(scale * a[col], rel=1e-6)
    for col in ("freq_1x_hz", "sb_4x_delta_hz", "combo_fa_hz", "n_half_orders"):
        assert b[col] == pytest.approx(a[col], rel=1e-6, nan_ok=True)


@settings(max_examples=15, deadline=None)
@given(s=signals, t0=st.floats(0.0, 10.0))
def test_time_shift_leaves_the_amplitudes(s, t0):
    rpm = 60 * s["f1"]
    a = signal_features(rub_like(s["f1"], s["amps"], s["phases"], s["duration"]), FS, rpm).iloc[0]
    shifted = rub_like(s["f1"], s["amps"], s["phases"], s["duration"], t0=t0)
    b = signal_features(shifted, FS, rpm).iloc[0]
    for col, amp in zip(AMPLITUDE_COLUMNS, s["amps"], strict=True):
        assert a[col] == pytest.approx(amp, rel=0.01)
        assert b[col] == pytest.approx(amp, rel=0.01)
    assert b["sb_4x_delta_hz"] == pytest.approx(a["sb_4x_delta_hz"], abs=FS / len_(s) / 2)
    assert b["combo_order"] == a["combo_order"] == 2


def len_(s):
    return round(s["duration"] * FS)


@settings(max_examples=15, deadline=None)
@given(s=signals, extra=st.floats(0.01, 2.0))
def test_unrelated_tone_leaves_the_others(s, extra):
    f1, rpm = s["f1"], 60 * s["f1"]
    x = rub_like(f1, s["amps"], s["phases"], s["duration"], noise=1e-4)
    n = x.size
    tone = extra * np.cos(2 * np.pi * 6.4 * f1 * np.arange(n) / FS)  # not an order, no pair
    a = signal_features(x, FS, rpm).iloc[0]
    b = signal_features(x + tone, FS, rpm).iloc[0]
    for col in AMPLITUDE_COLUMNS:
        assert b[col] == pytest.approx(a[col], rel=0.01)
    assert b["combo_fa_hz"] == pytest.approx(a["combo_fa_hz"], abs=0.05)
