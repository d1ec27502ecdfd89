"""Order tracking: known orders of a known run-up in, their amplitudes and phases out."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.interpolate

from rubdiag.signal import (
    amplitude_spectrum,
    angle_from_rpm,
    order_label,
    order_spectrum,
    order_track,
    resample_to_angle,
    rpm_order_map,
    tacho_angle,
)
from rubdiag.signal._records import RecordTooShort

FS = 5000.0
DURATION = 6.0
F0, F1 = 10.0, 40.0  # 600 -> 2400 rpm, linear in time
#: order: (amplitude, phase in rad of A cos(k φ + θ))
ORDERS = {0.5: (0.7, 0.4), 1.0: (1.0, -1.1), 1.5: (0.3, 2.0), 2.0: (0.5, 0.9), 4.0: (0.2, -2.5)}


def run_up(f0=F0, f1=F1):
    """Times and analytic angle φ = 2π (f0 t + a t²/2) of a linear speed ramp f0 -> f1 (Hz)."""
    t = np.arange(round(DURATION * FS)) / FS
    a = (f1 - f0) / DURATION
    return t, 2 * np.pi * (f0 * t + 0.5 * a * t**2)


def time_at_revolution(rev, f0=F0, f1=F1):
    """Analytic time at which the ramp has turned ``rev`` revolutions."""
    a = (f1 - f0) / DURATION
    return (-f0 + np.sqrt(f0**2 + 2 * a * rev)) / a


def orders_signal(phi, orders=ORDERS):
    return sum(a * np.cos(k * phi + theta) for k, (a, theta) in orders.items())


def phase_error_deg(measured_deg, expected_rad):
    return np.abs(np.angle(np.exp(1j * (np.radians(measured_deg) - expected_rad)), deg=True))


def naive_resample(x, phi, samples_per_rev):
    """Cubic interpolation at equal angle steps without any low-pass (what not to do)."""
    t = np.arange(phi.size) / FS
    dphi = 2 * np.pi / samples_per_rev
    grid = dphi * np.arange(np.ceil(phi[0] / dphi), np.floor(phi[-1] / dphi) + 1)
    xa = scipy.interpolate.CubicSpline(t, x)(np.interp(grid, phi, t))
    return xa[: xa.size // samples_per_rev * samples_per_rev]


def at_order(orders, amplitude, k):
    return amplitude[..., np.argmin(np.abs(orders - k))]


class TestOrderTrack:
    @pytest.mark.parametrize(("f0", "f1"), [(F0, F1), (F1, F0)], ids=["run-up", "run-down"])
    def test_recovers_orders_of_a_ramp_within_1_percent(self, f0, f1):
        _, phi = run_up(f0, f1)
        table = order_track(orders_signal(phi), FS, phi, tuple(ORDERS), revs_per_bin=8)
        assert list(table.columns[:3]) == ["rev_start", "t_s", "rpm"]
        assert len(table) == 18  # revolutions 1 … 145 of 150 (the filter needs ~0.2 at the ends)
        np.testing.assert_array_equal(np.diff(table.rev_start), 8)
        for k, (a, theta) in ORDERS.items():
            label = order_label(k)
            assert np.abs(table[f"amp_{label}"] / a - 1).max() < 0.01
            assert phase_error_deg(table[f"phase_{label}_deg"], theta).max() < 1.0
        t0 = time_at_revolution(table.rev_start, f0, f1)
        t1 = time_at_revolution(table.rev_start + 8, f0, f1)
        np.testing.assert_allclose(table.t_s, 0.5 * (t0 + t1), atol=1e-5)
        np.testing.assert_allclose(table.rpm, 60 * 8 / (t1 - t0), rtol=0.005)
        assert table.rpm.min() < 850 and table.rpm.max() > 2300    # the whole ramp

    def test_third_orders_fall_on_bins_of_a_multiple_of_three_revolutions(self):
        _, phi = run_up()
        thirds = {1 / 3: (0.4, 1.0), 2 / 3: (0.25, -0.5), 1.0: (1.0, 0.2), 4 / 3: (0.15, 3.0),
                  2.5: (0.1, -2.0)}
        x = orders_signal(phi, thirds)
        table = order_track(x, FS, phi, tuple(thirds), revs_per_bin=6)
        for k, (a, theta) in thirds.items():
            label = order_label(k)
            assert np.abs(table[f"amp_{label}"] / a - 1).max() < 0.01
            assert phase_error_deg(table[f"phase_{label}_deg"], theta).max() < 1.0
        with pytest.raises(ValueError, match=r"orders\[0\] = 0\.333333333333 does not fall on "
                                             r"a bin of revs_per_bin = 8"):
            order_track(x, FS, phi, tuple(thirds), revs_per_bin=8)

    def test_follows_an_amplitude_that_changes_with_speed(self):
        # 1x through a resonance at 1500 rpm (damping ratio 0.15): amplitude and phase of
        # H = 1 / (1 - r² + 2iζr), r = speed / 1500 rpm, change along the run-up.
        t, phi = run_up()
        rpm = 60 * (F0 + (F1 - F0) / DURATION * t)

        def response(rpm):
            r = rpm / 1500.0
            return 0.2 / (1 - r**2 + 2j * 0.15 * r)

        h = response(rpm)
        x = np.abs(h) * np.cos(phi + np.angle(h))
        table = order_track(x, FS, phi, (1.0,), revs_per_bin=4)
        expected = response(table.rpm.to_numpy())
        assert np.abs(table.amp_1x / np.abs(expected) - 1).max() < 0.015
        assert phase_error_deg(table.phase_1x_deg, np.angle(expected)).max() < 1.0
        assert table.amp_1x.max() > 2.5 * table.amp_1x.iloc[0]    # the resonance is passed

    def test_with_the_angle_from_a_tacho(self):
        _, phi = run_up()
        ramp, mark = 0.4, 1.0
        psi = np.mod(phi - mark + np.pi, 2 * np.pi) - np.pi
        pulses = np.minimum(np.clip((psi + ramp) / ramp, 0, 1), np.clip((0.7 - psi) / 0.4, 0, 1))
        crossing = mark - ramp / 2                   # tacho_angle is 0 here
        angle = tacho_angle(pulses, FS)
        table = order_track(orders_signal(phi), FS, angle, tuple(ORDERS))
        assert len(table) == 18
        for k, (a, theta) in ORDERS.items():
            label = order_label(k)
            assert np.abs(table[f"amp_{label}"] / a - 1).max() < 0.01
            # A cos(k φ + θ) = A cos(k angle + θ + k·crossing)
            assert phase_error_deg(table[f"phase_{label}_deg"], theta + k * crossing).max() < 1

    def test_overlapping_bins(self):
        _, phi = run_up()
        table = order_track(orders_signal(phi), FS, phi, (1.0, 2.0), revs_per_bin=8,
                            revs_step=2)
        np.testing.assert_array_equal(np.diff(table.rev_start), 2)
        assert np.abs(table.amp_2x / 0.5 - 1).max() < 0.01


class TestResampleToAngle:
    def test_grid_and_values(self):
        _, phi = run_up()
        x = np.vstack([np.cos(3 * phi + 0.5), 2 * np.sin(phi)])
        revs, xa = resample_to_angle(x, FS, phi, samples_per_rev=16, max_order=5)
        assert xa.shape == (2, revs.size)
        np.testing.assert_allclose(np.diff(revs), 1 / 16)
        np.testing.assert_allclose(revs * 16, np.rint(revs * 16), atol=1e-9)
        assert 0 < revs[0] < 1 and 149 < revs[-1] < 150       # the filter's ends only
        np.testing.assert_allclose(xa[0], np.cos(3 * 2 * np.pi * revs + 0.5), atol=2e-4)
        np.testing.assert_allclose(xa[1], 2 * np.sin(2 * np.pi * revs), atol=4e-4)
        _, xa_1d = resample_to_angle(x[0], FS, phi, samples_per_rev=16, max_order=5)
        np.testing.assert_array_equal(xa_1d, xa[0])

    @pytest.mark.parametrize("high", [40, 56])
    def test_high_order_is_suppressed_not_aliased(self, high):
        # Orders 40 and 56 fold onto 8 at 32 samples per revolution (56 onto 8 already on a
        # grid of 64 per revolution: the fine grid must be finer than that).
        _, phi = run_up()
        x = np.cos(phi) + 0.5 * np.cos(3 * phi + 1.0) + np.cos(high * phi + 0.3)
        orders, amp = order_spectrum(x, FS, phi, samples_per_rev=32, max_order=12)
        assert orders[-1] == pytest.approx(12, abs=0.01)
        assert at_order(orders, amp, 1) == pytest.approx(1.0, rel=0.01)
        assert at_order(orders, amp, 3) == pytest.approx(0.5, rel=0.01)
        assert amp[(orders > 4) & (orders <= 12)].max() < 1e-3
        naive_orders, naive = amplitude_spectrum(naive_resample(x, phi, 32), 32.0)
        assert at_order(naive_orders, naive, 8) > 0.5

    def test_fixed_frequency_tone_is_suppressed_not_aliased(self):
        # A 1 kHz tone sweeps through orders 100 -> 25 on the run-up: all above 32 - 12.
        t, phi = run_up()
        x = np.cos(phi) + np.cos(2 * np.pi * 1000.0 * t)
        orders, amp = order_spectrum(x, FS, phi, samples_per_rev=32, max_order=12)
        assert at_order(orders, amp, 1) == pytest.approx(1.0, rel=0.01)
        away = np.abs(orders - 1) > 0.1
        assert amp[away].max() < 1e-3
        naive_orders, naive = amplitude_spectrum(naive_resample(x, phi, 32), 32.0)
        assert naive[(np.abs(naive_orders - 1) > 0.1) & (naive_orders <= 12)].max() > 0.03


class TestOrderSpectrum:
    def test_constant_speed_agrees_with_the_amplitude_spectrum(self):
        f1 = 25.0
        t = np.arange(round(8.0 * FS)) / FS
        lines = {1: (1.0, 0.3), 2: (0.4, -1.0), 3: (0.25, 2.0), 5: (0.1, 0.7), 7.5: (0.05, 0)}
        x = sum(a * np.cos(2 * np.pi * k * f1 * t + th) for k, (a, th) in lines.items())
        f, a_time = amplitude_spectrum(x, FS)
        orders, a_order = order_spectrum(x, FS, angle_from_rpm(np.full(t.size, 60 * f1), FS))
        assert round(1 / orders[1]) == 198      # 200 revolutions less the filter's ends,
                                                # a multiple of 6
        for k in (1, 2, 3, 5):                      # on a bin of both spectra
            time_line = at_order(f, a_time, k * f1)
            assert at_order(orders, a_order, k) == pytest.approx(time_line, rel=0.01)
            assert time_line == pytest.approx(lines[k][0], rel=1e-6)

    def test_half_and_third_orders_of_a_run_up_fall_on_bins(self):
        _, phi = run_up()
        lines = {**ORDERS, 1 / 3: (0.2, 0.0), 2 / 3: (0.1, 0.0)}
        orders, amp = order_spectrum(orders_signal(phi, lines), FS, phi)
        assert round(1 / orders[1]) == 144      # 150 revolutions less the filter's ends
        for k, (a, _) in lines.items():
            assert at_order(orders, amp, k) == pytest.approx(a, rel=0.01)

    def test_rows_and_segments(self):
        _, phi = run_up()
        x = np.vstack([orders_signal(phi), 2 * orders_signal(phi)])
        orders, amp = order_spectrum(x, FS, phi, revs_per_segment=16)
        assert orders[1] == pytest.approx(1 / 16)
        assert amp.shape == (2, orders.size)
        for k, (a, _) in ORDERS.items():
            np.testing.assert_allclose(at_order(orders, amp, k), [a, 2 * a], rtol=0.01)


class TestRpmOrderMap:
    def test_map_of_a_run_up(self):
        _, phi = run_up()
        orders, rpm, amp = rpm_order_map(orders_signal(phi), FS, phi, revs_per_bin=8,
                                         samples_per_rev=32)
        assert amp.shape == (orders.size, rpm.size)
        np.testing.assert_allclose(np.diff(orders), 1 / 8)
        assert orders[-1] <= 32 / 2.56
        assert (np.diff(rpm) > 0).all() and rpm[0] < 800 and rpm[-1] > 2200
        for k, (a, _) in ORDERS.items():
            np.testing.assert_allclose(at_order(orders, amp.T, k), a, rtol=0.01)
        # Hann: a line on a bin shows half its amplitude on either neighbour, nothing beyond.
        near = np.abs(orders[:, np.newaxis] - np.array(list(ORDERS))).min(axis=1)
        assert amp[near > 0.2].max() < 1e-3
        np.testing.assert_allclose(at_order(orders, amp.T, 4.125), 0.1, rtol=0.01)


class TestBadInput:
    @pytest.mark.parametrize(
        ("kwargs", "message"),
        [
            ({"samples_per_rev": 16, "max_order": 8},
             r"max_order = 8 is out of range \(allowed: > 0 and < samples_per_rev / 2 = 8"),
            ({"samples_per_rev": 16, "max_order": 0.0}, r"max_order = 0\.0 is out of range"),
            ({"samples_per_rev": 1}, r"samples_per_rev = 1 is out of range \(allowed: >= 2\)"),
            ({"revs_per_bin": 0}, r"revs_per_bin = 0 is out of range \(allowed: >= 1\)"),
            ({"revs_per_bin": 3}, r"orders\[0\] = 0\.5 does not fall on a bin of "
                                  r"revs_per_bin = 3 revolutions \(allowed: multiples of 1/3"),
            ({"orders": (1, 30)}, r"orders\[1\] = 30\.0 is out of range \(allowed: <= max_order "
                                  r"= 25"),
            ({"orders": (1, 2, 1.0)}, r"repeats an order"),
            ({"orders": (1, -2)}, r"orders\[1\] = -2 is out of range \(allowed: > 0\)"),
            ({"orders": ()}, r"orders is empty"),
            ({"revs_step": 0}, r"revs_step = 0 is out of range \(allowed: >= 1\)"),
            ({"fs": -1.0}, r"fs = -1\.0 is out of range \(allowed: > 0 Hz\)"),
        ],
    )
    def test_parameters(self, kwargs, message):
        _, phi = run_up()
        args = {"x": np.cos(phi), "fs": FS, "angle": phi, **kwargs}
        with pytest.raises(ValueError, match=message):
            order_track(**args)

    def test_angle(self):
        _, phi = run_up()
        x = np.cos(phi)
        with pytest.raises(ValueError, match=r"angle has 29999 samples \(allowed: 30000"):
            resample_to_angle(x, FS, phi[:-1])
        backwards = phi.copy()
        backwards[100] = backwards[99]
        with pytest.raises(ValueError, match=r"angle\[100\] = .* is out of range \(allowed: "
                                             r"> angle\[99\] = .* rad"):
            order_spectrum(x, FS, backwards)
        with pytest.raises(ValueError, match=r"angle\[1\] = .* is out of range"):
            order_track(x, FS, phi[::-1])
        with pytest.raises(ValueError, match="angle contains NaN or inf"):
            rpm_order_map(x, FS, np.where(np.arange(phi.size) == 7, np.nan, phi))
        stalls = phi.copy()
        stalls[1000:] += 1e-6 * np.arange(phi.size - 1000) - (phi[1000:] - phi[1000])
        with pytest.raises(ValueError, match=r"below 1/100 of the mean"):
            resample_to_angle(x, FS, stalls)

    def test_one_signal_and_enough_revolutions(self):
        _, phi = run_up()
        with pytest.raises(ValueError, match=r"x has 2 rows \(allowed: one signal, 1-D\)"):
            order_track(np.zeros((2, phi.size)), FS, phi)
        with pytest.raises(RecordTooShort, match=r"allowed: at least revs_per_bin = 8"):
            order_track(np.cos(phi[:3000]), FS, phi[:3000])
        with pytest.raises(RecordTooShort, match="anti-alias filter"):
            resample_to_angle(np.cos(phi[:20]), FS, phi[:20])
