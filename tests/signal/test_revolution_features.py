"""Features across speed: a known run-up in, its order features bin by bin out."""

from __future__ import annotations

import doctest
import warnings

import numpy as np
import pandas as pd
import pytest

import rubdiag.signal._speedtable
from rubdiag.signal import (
    FEATURE_NAMES,
    REVOLUTION_FEATURE_NAMES,
    order_label,
    revolution_features,
    signal_features,
)

FS = 2000.0
DURATION = 10.0
F0, F1 = 10.0, 40.0          # 600 -> 2400 rpm, linear in time: 250 revolutions
N_REV = 48
DELTA = 6 / N_REV            # sideband spacing around 2×, orders (< 0.25×: a sideband)
#: order: (amplitude, phase in rad of A cos(k φ + θ))
LINES = {1.0: (1.0, 0.3), 1.5: (0.3, -1.2), 2.0: (0.5, 0.8), 4.0: (0.2, 2.0)}
SIDEBAND = 0.05              # each of 2× ± Δ: 2× amplitude-modulated by 2 · 0.05 / 0.5
COMBO = {28 / N_REV: 0.1, 68 / N_REV: 0.08}    # 0.583× + 1.417× = 2×
# Every line lies on a bin of N_REV revolutions, at least 4 bins from the next line (Hann:
# no leakage between them) and from any half or third order (outside their search bands);
# the pair is 1× ± 0.417×, too wide for sidebands of 1× (Δ < 0.25×).
NOISE = 1e-3


def ramp(f0=F0, f1=F1, fs=FS):
    """Times and the analytic angle φ = 2π (f0 t + a t²/2) of a linear speed ramp (Hz)."""
    t = np.arange(round(DURATION * fs)) / fs
    return t, 2 * np.pi * (f0 * t + 0.5 * (f1 - f0) / DURATION * t**2)


def time_at_revolution(rev, f0=F0, f1=F1):
    a = (f1 - f0) / DURATION
    return (-f0 + np.sqrt(f0**2 + 2 * a * rev)) / a


def rub_signal(phi, seed=0):
    """The known lines: orders, the modulated 2×, the combination pair, and white noise."""
    x = sum(a * np.cos(k * phi + th) for k, (a, th) in LINES.items())
    a2, th2 = LINES[2.0]
    x += (2 * SIDEBAND / a2) * np.cos(DELTA * phi) * a2 * np.cos(2 * phi + th2)
    x += sum(a * np.cos(k * phi) for k, a in COMBO.items())
    return x + NOISE * np.random.default_rng(seed).standard_normal(phi.size)


def phase_error_deg(measured_deg, expected_rad):
    return np.abs(np.angle(np.exp(1j * (np.radians(measured_deg) - expected_rad)), deg=True))


@pytest.fixture(scope="module")
def run_up():
    _, phi = ramp()
    x = rub_signal(phi)
    return phi, x, revolution_features(x, FS, phi, revs_per_bin=N_REV)


class TestRunUp:
    def test_bins_and_their_speed(self, run_up):
        _, _, table = run_up
        assert list(table.columns) == ["channel", "bin", "rev_start", "t_s", "rpm",
                                       *REVOLUTION_FEATURE_NAMES]
        assert len(table) == 5                     # revolutions 1 … 241 of 250
        np.testing.assert_array_equal(table.bin, np.arange(5))
        np.testing.assert_array_equal(np.diff(table.rev_start), N_REV)
        t0 = time_at_revolution(table.rev_start)
        t1 = time_at_revolution(table.rev_start + N_REV)
        np.testing.assert_allclose(table.rpm, 60 * N_REV / (t1 - t0), rtol=1e-5)
        np.testing.assert_allclose(table.t_s, 0.5 * (t0 + t1), atol=1e-5)
        assert table.rpm.min() < 950 and table.rpm.max() > 2200

    def test_orders_and_their_phase_against_the_shaft_angle(self, run_up):
        _, _, table = run_up
        for k, (a, theta) in LINES.items():
            label = order_label(k)
            np.testing.assert_allclose(table[f"amp_{label}"], a, rtol=0.01)
            np.testing.assert_allclose(table[f"freq_{label}_order"], k, atol=1e-3)
            assert phase_error_deg(table[f"phase_{label}_deg"], theta).max() < 0.5
        for k in (0.5, 2.5, 3.0, 8.0):                            # absent: 0, no location
            assert (table[f"amp_{order_label(k)}"] == 0).all()
            assert table[f"freq_{order_label(k)}_order"].isna().all()
        assert (table.n_half_orders == 1).all()                   # 1.5×
        assert (table.n_third_orders == 0).all()

    def test_sidebands_in_orders(self, run_up):
        _, _, table = run_up
        np.testing.assert_allclose(table.sb_2x_delta_order, DELTA, atol=1e-3)
        np.testing.assert_allclose(table.sb_2x_lower, SIDEBAND, rtol=0.01)
        np.testing.assert_allclose(table.sb_2x_upper, SIDEBAND, rtol=0.01)
        for n in (1, 3, 4, 8):
            assert table[f"sb_{n}x_delta_order"].isna().all()
            assert (table[f"sb_{n}x_lower"] == 0).all()

    def test_combination_pair_in_orders(self, run_up):
        _, _, table = run_up
        (ka, aa), (kb, ab) = COMBO.items()
        np.testing.assert_allclose(table.combo_fa_order, ka, atol=1e-3)
        np.testing.assert_allclose(table.combo_fb_order, kb, atol=1e-3)
        assert (table.combo_order == 2).all()
        np.testing.assert_allclose(table.combo_amp_a, aa, rtol=0.01)
        np.testing.assert_allclose(table.combo_amp_b, ab, rtol=0.01)

    def test_rms_of_the_lines(self, run_up):
        _, _, table = run_up
        power = sum(a**2 for a, _ in LINES.values()) + 2 * SIDEBAND**2
        power += sum(a**2 for a in COMBO.values())
        np.testing.assert_allclose(table.rms, np.sqrt(power / 2), rtol=0.005)

    def test_run_down_is_the_run_up_backwards(self):
        _, phi = ramp(F1, F0)
        table = revolution_features(rub_signal(phi), FS, phi, revs_per_bin=N_REV)
        assert table.rpm.is_monotonic_decreasing
        np.testing.assert_allclose(table.amp_1p5x, LINES[1.5][0], rtol=0.01)
        np.testing.assert_allclose(table.sb_2x_delta_order, DELTA, atol=1e-3)

    def test_overlapping_bins(self, run_up):
        phi, x, table = run_up
        half = revolution_features(x, FS, phi, revs_per_bin=N_REV, revs_step=N_REV // 2)
        np.testing.assert_array_equal(np.diff(half.rev_start), N_REV // 2)
        pd.testing.assert_frame_equal(half.iloc[::2].drop(columns="bin").reset_index(drop=True),
                                      table.drop(columns="bin"))

    def test_orders_above_a_fifth_of_fs_are_unmeasurable(self):
        # At fs = 500 Hz, 3.03× stays below fs / 5 up to 1980 rpm, 3.25× up to 1846 rpm.
        fs = 500.0
        _, phi = ramp(fs=fs)
        x = np.cos(phi) + 0.1 * np.cos(3 * phi) + 0.01 * np.cos(2 * phi)
        table = revolution_features(x, fs, phi, revs_per_bin=16, min_revolutions=16)
        max_rpm = 60 * (F0 + (F1 - F0) / DURATION * time_at_revolution(table.rev_start + 16))
        for k, name, half_width in ((3, "amp_3x", 0.03), (3, "bb_3x_rms", 0.25),
                                    (3, "sb_3x_lower", 0.25)):
            unmeasurable = (k + half_width) * max_rpm / 60 > 0.2 * fs
            assert 0 < unmeasurable.sum() < len(table), name
            np.testing.assert_array_equal(table[name].isna(), unmeasurable, err_msg=name)
        np.testing.assert_allclose(table.amp_3x.dropna(), 0.1, rtol=0.005)
        np.testing.assert_allclose(table.amp_2x, 0.01, rtol=0.005)
        assert table.amp_1x.notna().all()
        assert (table.n_half_orders == 0).all()


class TestAgainstConstantSpeed:
    def test_bins_agree_with_features_of_the_same_samples(self):
        # 1500 rpm at 2000 Hz: 80 samples per revolution, bin r starts at sample 80 r. The
        # bands n× ± 0.25× end between bins of 42 revolutions: with 48 they end on bins, and
        # whether round-off keeps the end bin differs between the two records.
        f1, n_rev = 25.0, 42
        t = np.arange(round(DURATION * FS)) / FS
        phi = 2 * np.pi * f1 * t
        x = rub_signal(phi, seed=3) + 0.05 * np.cos(4 * phi / 3 + 1.0)
        table = revolution_features(x, FS, phi, revs_per_bin=n_rev)
        spr = round(FS / f1)
        for row in table.itertuples():
            seg = x[row.rev_start * spr : (row.rev_start + n_rev) * spr]
            ref = signal_features(seg, FS, 60 * f1).iloc[0]
            assert row.rpm == pytest.approx(60 * f1, rel=1e-9)
            for name in REVOLUTION_FEATURE_NAMES:
                got = getattr(row, name)
                hz = {v: k for k, v in rubdiag.signal._speedtable._HZ_TO_ORDER.items()}
                expected = ref[hz[name]] / f1 if name in hz else ref[name]
                if name.startswith("phase_"):
                    k = float(name.split("_")[1][:-1].replace("p", "."))
                    # features phases against the segment's first sample: φ = 2π rev_start
                    expected = expected - 360 * k * row.rev_start
                    expected = (expected + 180) % 360 - 180
                    assert np.isnan(got) == np.isnan(expected), name
                    if not np.isnan(got):
                        assert abs((got - expected + 180) % 360 - 180) < 0.05, name
                elif name == "rms":         # the angle record holds no noise above 12.5×
                    assert got == pytest.approx(expected, rel=1e-3), name
                else:
                    assert got == pytest.approx(expected, rel=2e-3, abs=1e-9,
                                                nan_ok=True), name


class TestTachoAndAngle:
    @staticmethod
    def pulses(phi, mark=1.0, ramp_rad=0.4):
        """Key-phasor pulses: rising through half height at φ = mark - ramp_rad / 2."""
        psi = np.mod(phi - mark + np.pi, 2 * np.pi) - np.pi
        return np.minimum(np.clip((psi + ramp_rad) / ramp_rad, 0, 1),
                          np.clip((0.7 - psi) / 0.4, 0, 1))

    def test_tacho_path_gives_the_angle_paths_table(self, run_up):
        phi, x, _ = run_up
        crossing = 1.0 - 0.4 / 2                   # tacho_angle is 0 there
        frame = pd.DataFrame({"shaft": x, "tacho": self.pulses(phi),
                              "angle": phi - crossing})
        by_tacho = revolution_features(frame.drop(columns="angle"), FS, revs_per_bin=N_REV)
        by_angle = revolution_features(frame, FS, "angle", revs_per_bin=N_REV)
        assert list(by_tacho.channel.unique()) == ["shaft"]     # tacho and angle not analysed
        pd.testing.assert_frame_equal(by_tacho[["channel", "bin", "rev_start"]],
                                      by_angle[["channel", "bin", "rev_start"]])
        np.testing.assert_allclose(by_tacho.rpm, by_angle.rpm, rtol=1e-5)
        np.testing.assert_allclose(by_tacho.t_s, by_angle.t_s, atol=1e-4)
        phases = [n for n in REVOLUTION_FEATURE_NAMES if n.startswith("phase_")]
        # The broadband level leaves out the bins next to a line where its leakage stands
        # above the noise, and the tacho's interpolated angle (about 1e-3 rad off) changes
        # that leakage: the level of 2× ± 0.25× (the sidebands in it) moves by 2 %.
        broadband = [n for n in REVOLUTION_FEATURE_NAMES if n.startswith("bb_")]
        others = [n for n in REVOLUTION_FEATURE_NAMES if n not in phases + broadband]
        np.testing.assert_allclose(by_tacho[others], by_angle[others], rtol=2e-3, atol=1e-6)
        np.testing.assert_allclose(by_tacho[broadband], by_angle[broadband], rtol=0.05,
                                   atol=5e-5)
        diff = by_tacho[phases].to_numpy() - by_angle[phases].to_numpy()
        assert np.nanmax(np.abs((diff + 180) % 360 - 180)) < 0.2
        np.testing.assert_array_equal(np.isnan(by_tacho[phases]), np.isnan(by_angle[phases]))

    def test_features_warns_when_the_tacho_speed_varies(self, run_up):
        phi, x, _ = run_up
        with pytest.warns(UserWarning, match=r"tacho speed varies from .* give revs_per_bin"):
            signal_features(x, FS, tacho=self.pulses(phi))
        t = np.arange(round(4 * FS)) / FS
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            row = signal_features(np.cos(2 * np.pi * 25 * t), FS,
                           tacho=self.pulses(2 * np.pi * 25 * t)).iloc[0]
        assert row.speed_rpm == pytest.approx(1500, rel=1e-6)


class TestBadInput:
    @pytest.mark.parametrize(("kwargs", "message"), [
        (dict(revs_per_bin=0), r"revs_per_bin = 0 is out of range \(allowed: >= 10: a bin"),
        (dict(revs_per_bin=8), r"revs_per_bin = 8 is out of range \(allowed: >= 10"),
        (dict(revs_per_bin=8, min_revolutions=8), None),
        (dict(revs_per_bin=24.0), r"revs_per_bin = 24.0 has the wrong type"),
        (dict(samples_per_rev=16), r"max_order = 6.25 is out of range \(allowed: >= 8.5"),
        (dict(revs_step=0), r"revs_step = 0 is out of range"),
        (dict(tacho=np.ones(20000)), r"give angle or tacho, not both"),
    ])
    def test_parameters(self, run_up, kwargs, message):
        phi, x, _ = run_up
        if message is None:
            assert len(revolution_features(x, FS, phi, **kwargs)) == 31
        else:
            with pytest.raises(ValueError, match=message):
                revolution_features(x, FS, phi, **kwargs)

    def test_no_angle(self, run_up):
        _, x, _ = run_up
        with pytest.raises(ValueError, match=r"the shaft angle is needed: give angle"):
            revolution_features(x, FS)

    def test_too_few_revolutions(self, run_up):
        phi, x, _ = run_up
        with pytest.raises(ValueError, match=r"x holds 248 whole revolutions .* at least "
                                             r"revs_per_bin = 250"):
            revolution_features(x, FS, phi, revs_per_bin=250)


def test_still_channel_has_every_line_absent(run_up):
    phi, x, _ = run_up
    table = revolution_features(np.vstack([x, np.full(x.size, 2.0)]), FS, phi,
                                   revs_per_bin=N_REV)
    still = table[table.channel == 1]
    assert len(still) == 5 and (still.amp_1x == 0).all() and (still.rms == 0).all()
    assert still.freq_1x_order.isna().all()


def test_columns_are_the_feature_columns_in_orders():
    kept = [n for n in FEATURE_NAMES if n not in ("speed_rpm", "speed_confidence")]
    assert len(REVOLUTION_FEATURE_NAMES) == len(kept)
    assert not any(n.endswith("_hz") for n in REVOLUTION_FEATURE_NAMES)
    renamed = {a: b for a, b in zip(kept, REVOLUTION_FEATURE_NAMES, strict=True) if a != b}
    assert len(renamed) == 16 + 8 + 2
    assert renamed["sb_4x_delta_hz"] == "sb_4x_delta_order"
    assert renamed["freq_1p5x_hz"] == "freq_1p5x_order"


def test_docstring_example():
    result = doctest.testmod(rubdiag.signal._speedtable)
    assert result.attempted > 0 and result.failed == 0
