"""The broadband level around n× is measured on short records too (no absent line's lobe
is cut out of the band)."""

import numpy as np
import pytest

import rubdiag


@pytest.mark.parametrize("revolutions", [10, 15, 20, 50])
def test_white_noise_level_around_4x(revolutions):
    fs, f1, sigma = 10_000.0, 25.0, 1e-4
    t = np.arange(int(revolutions / f1 * fs)) / fs
    rng = np.random.default_rng(revolutions)
    x = sigma * rng.standard_normal(t.size) + np.cos(2 * np.pi * f1 * t)
    row = rubdiag.signal_features(x, fs, 60 * f1, min_revolutions=5).iloc[0]
    # white noise: one-sided density 2σ²/fs over the band 4× ± 0.25× (12.5 Hz)
    expected = sigma * np.sqrt(2 * 0.5 * f1 / fs)
    assert row["bb_4x_rms"] == pytest.approx(expected, rel=0.35)
    assert row["bb_3x_rms"] == pytest.approx(expected, rel=0.35)
