"""tacho_angle, tacho_rpm, angle_from_rpm: a known run-up in, its analytic angle and speed out."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import angle_from_rpm, tacho_angle, tacho_rpm

FS = 5000.0
DURATION = 6.0
F0, F1 = 10.0, 40.0  # 600 -> 2400 rpm, linear in time
RAMP, TOP = 0.4, 0.3  # rad: the flank and the flat top of a tacho mark
MARK = 1.0  # rad: the angle at which a mark's flank reaches the top


def run_up(f0=F0, f1=F1):
    """Times, analytic angle φ = 2π (f0 t + a t²/2) and speed (rpm) of a linear ramp."""
    t = np.arange(round(DURATION * FS)) / FS
    a = (f1 - f0) / DURATION
    return t, 2 * np.pi * (f0 * t + 0.5 * a * t**2), 60.0 * (f0 + a * t)


def key_phasor(phi, pulses_per_rev=1):
    """Trapezoidal marks (in angle) every 2π / pulses_per_rev, and the angle at which each
    mark's straight rising flank crosses half its height (where tacho_angle's pulses are).

    The flank spans 8 samples at the top speed, so locating its crossing by linear
    interpolation is exact and the tests see the angle's interpolation error alone.
    """
    pitch = 2 * np.pi / pulses_per_rev
    psi = np.mod(phi - MARK + pitch / 2, pitch) - pitch / 2
    rise = np.clip((psi + RAMP) / RAMP, 0.0, 1.0)
    fall = np.clip((TOP + RAMP - psi) / RAMP, 0.0, 1.0)
    return np.minimum(rise, fall), MARK - RAMP / 2


class TestTachoAngle:
    @pytest.mark.parametrize(("pulses_per_rev", "tol"), [(1, 1e-3), (4, 2e-5)])
    def test_follows_the_analytic_angle_of_a_run_up(self, pulses_per_rev, tol):
        _, phi, _ = run_up()
        pulses, crossing = key_phasor(phi, pulses_per_rev)
        err = tacho_angle(pulses, FS, pulses_per_rev) - (phi - crossing)
        # Between the first and last pulse: interpolation error only. Beyond: extrapolated
        # at the end interval's speed while the speed keeps changing.
        first, last = crossing / (2 * np.pi), (phi[-1] - 2 * np.pi + crossing) / (2 * np.pi)
        inside = (phi >= 2 * np.pi * first) & (phi <= 2 * np.pi * last)
        assert np.abs(err[inside]).max() < tol
        assert np.abs(err).max() < 0.01

    def test_gaussian_marks_shift_the_angle_by_little(self):
        # A curved flank biases the linear interpolation of its crossing a little.
        _, phi, _ = run_up()
        sigma = 0.15
        psi = np.mod(phi - MARK + np.pi, 2 * np.pi) - np.pi
        pulses = np.exp(-0.5 * (psi / sigma) ** 2)
        crossing = MARK - sigma * np.sqrt(2 * np.log(2))
        err = tacho_angle(pulses, FS) - (phi - crossing)
        assert np.abs(err[(phi > 2 * np.pi) & (phi < phi[-1] - 2 * np.pi)]).max() < 2e-3

    def test_never_runs_backwards_through_abrupt_speed_changes(self):
        fs = 10000.0
        times = np.array([0.05, 0.35, 0.40, 0.45, 0.50, 1.50, 1.52, 1.54, 1.56, 1.60])
        pulses = np.zeros(round(1.7 * fs))
        at = np.rint(times * fs).astype(int)
        for i in at:
            pulses[i] = 0.5                     # the mid level: the crossing is sample i
            pulses[i + 1 : i + 5] = 1.0
        angle = tacho_angle(pulses, fs)
        assert (np.diff(angle) > 0).all()
        assert (tacho_rpm(pulses, fs) > 0).all()
        np.testing.assert_allclose(angle[at], 2 * np.pi * np.arange(times.size), atol=1e-9)

    def test_constant_speed_is_exact(self):
        t = np.arange(20000) / FS
        phi = 2 * np.pi * 23.7 * t
        pulses, crossing = key_phasor(phi)
        np.testing.assert_allclose(tacho_angle(pulses, FS), phi - crossing, atol=1e-9)

    def test_pulse_polarity_and_offset_do_not_matter(self):
        _, phi, _ = run_up()
        pulses, _ = key_phasor(phi)
        np.testing.assert_allclose(tacho_angle(3.0 * pulses - 7.0, FS),
                                   tacho_angle(pulses, FS), atol=1e-9)


class TestTachoRpm:
    def test_follows_the_ramp_within_0p1_percent(self):
        t, phi, rpm = run_up()
        pulses, _ = key_phasor(phi)
        measured = tacho_rpm(pulses, FS)
        away = (t > 0.2) & (t < DURATION - 0.2)
        assert np.abs(measured[away] / rpm[away] - 1).max() < 1e-3

    def test_run_down_and_constant_beyond_the_end_pulses(self):
        t, phi, rpm = run_up(F1, F0)
        pulses, crossing = key_phasor(phi)
        measured = tacho_rpm(pulses, FS)
        away = (t > 0.2) & (t < DURATION - 0.2)
        assert np.abs(measured[away] / rpm[away] - 1).max() < 1e-3
        before = phi < crossing                 # no pulse yet: the speed at the first one
        assert before.sum() > 5
        assert np.ptp(measured[before]) == 0.0
        assert measured[0] == pytest.approx(F1 * 60, rel=0.005)

    def test_is_the_derivative_of_the_angle(self):
        _, phi, _ = run_up()
        pulses, _ = key_phasor(phi)
        angle = tacho_angle(pulses, FS)
        rpm = tacho_rpm(pulses, FS)
        mid = 0.5 * (rpm[1:] + rpm[:-1]) * 2 * np.pi / 60 / FS   # trapezoidal rule
        np.testing.assert_allclose(np.diff(angle), mid, rtol=1e-4)


class TestAngleFromRpm:
    def test_integrates_a_ramp_exactly(self):
        _, phi, rpm = run_up()
        np.testing.assert_allclose(angle_from_rpm(rpm, FS), phi, rtol=0, atol=1e-9)

    def test_constant_speed(self):
        phi = angle_from_rpm(np.full(1001, 1500.0), 1000.0)
        assert phi[0] == 0.0
        assert phi[-1] == pytest.approx(2 * np.pi * 25.0)


class TestBadInput:
    def test_too_few_pulses(self):
        _, phi, _ = run_up()
        pulses, _ = key_phasor(phi[:500])      # 0.1 s at 10 Hz: one mark
        with pytest.raises(ValueError, match=r"pulses has 1 pulses .*\(allowed: at least 3\)"):
            tacho_angle(pulses, FS)
        with pytest.raises(ValueError, match=r"pulses has 0 pulses"):
            tacho_rpm(np.ones(100), FS)

    @pytest.mark.parametrize(
        ("kwargs", "message"),
        [
            ({"pulses_per_rev": 0}, r"pulses_per_rev = 0 is out of range \(allowed: >= 1\)"),
            ({"pulses_per_rev": 1.0}, r"pulses_per_rev = 1\.0 has the wrong type"),
            ({"fs": 0.0}, r"fs = 0\.0 is out of range \(allowed: > 0 Hz\)"),
        ],
    )
    def test_parameters(self, kwargs, message):
        _, phi, _ = run_up()
        pulses, _ = key_phasor(phi)
        with pytest.raises(ValueError, match=message):
            tacho_angle(pulses, **{"fs": FS, **kwargs})

    def test_one_tacho_signal(self):
        with pytest.raises(ValueError, match=r"pulses has 2 rows \(allowed: one tacho signal"):
            tacho_angle(np.zeros((2, 100)), FS)

    def test_negative_speed(self):
        with pytest.raises(ValueError,
                           match=r"speed_rpm\[3\] = -1\.0 is out of range \(allowed: >= 0 rpm\)"):
            angle_from_rpm([3.0, 2.0, 0.0, -1.0], FS)
