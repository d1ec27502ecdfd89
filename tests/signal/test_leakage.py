"""The order tracking's own leakage: a 1× whose amplitude changes within a bin shows at the
orders beside it. For an amplitude growing linearly, A = A_mid + s·R·(v − 1/2) over a bin of
R revolutions (v its fraction, 0 … 1), the Hann window sin²(πv) reads at bin j

    2·s·R·|c(j − R)·e^{iθ} + c(j + R)·e^{-iθ}|,   c(m) = ∫ sin²(πv)(v − 1/2) e^{-2πimv} dv
                                                       = −i / (4π m (m² − 1)),

the first term from the line's positive frequency (at bin R), the second from its negative
one, θ its phase at the bin's start: s·R/(12π) two bins away (0.5× and 1.5× for R = 4), to
within 3 %.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.signal import order_track
from rubdiag.signal._leakage import tracking_leakage

R = 4
A0, SLOPE = 1.0, 0.02        # 1× grows by 2 % of A0 per revolution


def linear_track(n_bins=40, slope=SLOPE):
    """An order_track-like table whose 1× grows linearly, A0 + slope·rev at bin centres."""
    start = np.arange(n_bins, dtype=float)
    return pd.DataFrame({"rev_start": start, "rpm": 1000.0 + start,
                         "amp_1x": A0 + slope * (start + R / 2), "phase_1x_deg": 0.0})


def ramp_leakage(order, theta=0.0, slope=SLOPE):
    """The module docstring's level at ``order`` for bins of R revolutions."""
    def c(m):
        return -1j / (4 * np.pi * m * (m * m - 1))

    j = round(order * R)
    return 2 * slope * R * abs(c(j - R) * np.exp(1j * theta) + c(j + R) * np.exp(-1j * theta))


def test_a_steady_line_leaks_nothing():
    leak = tracking_leakage(linear_track(slope=0.0), R)
    assert leak[["amp_0p5x", "amp_1p5x", "amp_2x", "amp_3x"]].to_numpy().max() < 1e-14


def test_a_linear_ramp_leaks_its_analytic_level():
    leak = tracking_leakage(linear_track(), R)
    for k in (0.5, 1.5, 2.0, 3.0):
        np.testing.assert_allclose(leak[f"amp_{k:g}x".replace(".", "p")], ramp_leakage(k),
                                   rtol=1e-4)
    assert ramp_leakage(0.5) == pytest.approx(SLOPE * R / (12 * np.pi), rel=0.03)


def test_it_is_what_order_track_reads_off_a_run_up():
    """A run-up 600 -> 1800 rpm whose only line is a 1× growing linearly with the angle:
    order_track's 0.5× and 1.5× are the analytic leakage, and tracking_leakage rebuilds
    them from the 1× track alone."""
    fs, seconds = 2000.0, 6.0
    t = np.arange(round(fs * seconds)) / fs
    phi = 2 * np.pi * (10 * t + 10 * t**2 / (2 * seconds))      # 10 -> 30 Hz
    x = (A0 + SLOPE * phi / (2 * np.pi)) * np.cos(phi + 0.7)
    track = order_track(x, fs, phi, orders=(0.5, 1, 1.5, 2), revs_per_bin=R, revs_step=1)
    assert track.attrs == {"revs_per_bin": R, "samples_per_rev": 64, "window": "hann"}
    leak = tracking_leakage(track, R, (0.5, 1.5))
    for k in ("0p5x", "1p5x"):
        order = float(k[:-1].replace("p", "."))
        np.testing.assert_allclose(track[f"amp_{k}"], ramp_leakage(order, 0.7), rtol=2e-3)
        np.testing.assert_allclose(leak[f"amp_{k}"], track[f"amp_{k}"], rtol=2e-3)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"orders": (0.3,)}, r"orders = \[0\.3\]: each times revs_per_bin = 4 must be a whole"),
    ({"revs_per_bin": 0}, r"revs_per_bin = 0 is out of range"),
])
def test_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        tracking_leakage(linear_track(), **{"revs_per_bin": R, **kwargs})
    with pytest.raises(ValueError, match="track has no column phase_1x_deg"):
        tracking_leakage(linear_track().drop(columns="phase_1x_deg"), R)
