"""waterfall: a steady tone reads its amplitude in every segment; the speed follows the ramp."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import waterfall

FS = 5000.0
DURATION = 6.0
F0, F1 = 10.0, 40.0  # 600 -> 2400 rpm, linear in time
NPERSEG = 1024
TONE_HZ = 64 * FS / NPERSEG  # 312.5 Hz, on a bin


def run_up():
    t = np.arange(round(DURATION * FS)) / FS
    a = (F1 - F0) / DURATION
    return t, 2 * np.pi * (F0 * t + 0.5 * a * t**2), 60.0 * (F0 + a * t)


def test_tone_reads_its_amplitude_in_every_segment():
    t, phi, rpm = run_up()
    x = 1.3 * np.cos(2 * np.pi * TONE_HZ * t + 0.4) + np.cos(phi) + 0.2 * np.cos(4 * phi) + 5.0
    f, t_s, speed, amp = waterfall(x, FS, NPERSEG, angle=phi)
    assert amp.shape == (f.size, t_s.size) == (NPERSEG // 2 + 1, speed.size)
    np.testing.assert_allclose(np.diff(f), FS / NPERSEG)
    k = int(np.argmin(np.abs(f - TONE_HZ)))
    assert f[k] == pytest.approx(TONE_HZ)
    assert np.abs(amp[k] / 1.3 - 1).max() < 0.01
    assert amp[0].max() < 0.2                   # the offset removed (1x leaks a little)
    _, _, _, kept = waterfall(x, FS, NPERSEG, detrend=False, angle=phi)
    np.testing.assert_allclose(kept[0], 5.0, atol=0.2)       # DC is not doubled
    # Segments wholly inside the record, half overlapping, centred at t_s.
    np.testing.assert_allclose(np.diff(t_s), NPERSEG / 2 / FS)
    assert t_s[0] >= NPERSEG / 2 / FS and t_s[-1] + NPERSEG / 2 / FS <= DURATION
    assert t_s.size == (t.size - NPERSEG) // (NPERSEG // 2) + 1
    # Speed: the mean over each segment of the linear ramp, i.e. its value at the centre.
    np.testing.assert_allclose(speed, 60.0 * (F0 + (F1 - F0) / DURATION * t_s), rtol=1e-3)
    _, _, from_rpm, amp_rpm = waterfall(x, FS, NPERSEG, speed_rpm=rpm)
    np.testing.assert_allclose(from_rpm, speed, rtol=1e-4)
    np.testing.assert_array_equal(amp_rpm, amp)


@pytest.mark.parametrize("window", ["hann", "flattop", ("kaiser", 8.0)])
def test_window_correction_and_rows(window):
    t, _, rpm = run_up()
    x = np.vstack([np.cos(2 * np.pi * TONE_HZ * t), 0.25 * np.sin(2 * np.pi * TONE_HZ * t)])
    f, t_s, _, amp = waterfall(x, FS, 2048, noverlap=0, window=window, speed_rpm=rpm)
    assert amp.shape == (2, f.size, t_s.size)
    np.testing.assert_allclose(np.diff(t_s), 2048 / FS)
    k = int(np.argmin(np.abs(f - TONE_HZ)))
    np.testing.assert_allclose(amp[:, k], [[1.0] * t_s.size, [0.25] * t_s.size], rtol=1e-6)


class TestBadInput:
    def test_speed_given_once(self):
        _, phi, rpm = run_up()
        x = np.cos(phi)
        with pytest.raises(ValueError, match=r"speed_rpm or as angle \(allowed: exactly one\)"):
            waterfall(x, FS, NPERSEG)
        with pytest.raises(ValueError, match=r"exactly one"):
            waterfall(x, FS, NPERSEG, speed_rpm=rpm, angle=phi)

    def test_lengths_and_segments(self):
        _, phi, rpm = run_up()
        x = np.cos(phi)
        with pytest.raises(ValueError, match=r"speed_rpm has shape \(29999,\) \(allowed: "
                                             r"\(30000,\)"):
            waterfall(x, FS, NPERSEG, speed_rpm=rpm[1:])
        with pytest.raises(ValueError, match=r"angle has 29999 samples \(allowed: 30000"):
            waterfall(x, FS, NPERSEG, angle=phi[1:])
        with pytest.raises(ValueError, match=r"nperseg = 40000 is out of range \(allowed: "
                                             r"<= 30000"):
            waterfall(x, FS, 40000, angle=phi)
        with pytest.raises(ValueError, match=r"noverlap = 1024 is out of range"):
            waterfall(x, FS, NPERSEG, noverlap=NPERSEG, angle=phi)
