"""Synthetic signals with known components, built in the tests (never from the code)."""

from __future__ import annotations

import numpy as np
import pytest


def make_signal(components, fs, duration, noise=0.0, seed=0, t0=0.0):
    """Sum of ``a * cos(2π f t + φ)`` for ``(f_hz, a, φ_rad)`` plus white noise of std ``noise``.

    ``t`` starts at ``t0`` seconds; ``duration`` need not hold whole periods.
    """
    n = round(duration * fs)
    t = t0 + np.arange(n) / fs
    x = np.zeros(n)
    for comp in components:
        f, a = comp[0], comp[1]
        phi = comp[2] if len(comp) > 2 else 0.0
        x += a * np.cos(2 * np.pi * f * t + phi)
    if noise:
        x += noise * np.random.default_rng(seed).standard_normal(n)
    return x


@pytest.fixture
def synth():
    return make_signal
