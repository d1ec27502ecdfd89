"""signal_features(): inputs (arrays, DataFrames, files), speed sources, batch path, bad input."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.signal import (
    combination_pairs,
    dominant_speed,
    feature_names,
    read_signals,
    signal_features,
    spectral_lines,
    tacho_speed,
)
from rubdiag.signal._options import Options
from rubdiag.signal._speed import MIN_SPEED_CONFIDENCE
from rubdiag.signal._table import feature_matrix, prefixed_features, still_features

FS = 2000.0
RPM = 1500.0
F1 = RPM / 60.0


@pytest.fixture
def channels(synth):
    n = int(2.5 * FS)
    t = np.arange(n) / FS
    tacho = (np.mod(t * F1 + 0.3, 1.0) < 0.1).astype(float) * 5.0  # once per rev, 5 V pulses
    return pd.DataFrame(
        {
            "shaft": synth([(F1, 2.0), (1.5 * F1, 0.1)], FS, 2.5, noise=1e-3, seed=1),
            "casing": synth([(F1, 0.5), (4 * F1, 0.05)], FS, 2.5, noise=1e-3, seed=2),
            "tacho": tacho,
        }
    )


def test_one_row_per_channel_with_channel_column(channels):
    table = signal_features(channels, FS, RPM)
    assert list(table.columns) == ["channel", *feature_names()]
    assert list(table["channel"]) == ["shaft", "casing"]  # tacho is not analysed
    shaft, casing = table.iloc[0], table.iloc[1]
    assert shaft["amp_1x"] == pytest.approx(2.0, rel=0.01)
    assert shaft["amp_1p5x"] == pytest.approx(0.1, rel=0.02)
    assert casing["amp_4x"] == pytest.approx(0.05, rel=0.02)
    assert casing["amp_1p5x"] == 0.0


def test_speed_from_the_tacho_channel(channels):
    table = signal_features(channels, FS)  # column "tacho" is found by name
    assert table["speed_rpm"].to_numpy() == pytest.approx(RPM, rel=1e-3)
    named = signal_features(channels.rename(columns={"tacho": "key"}), FS, tacho="key")
    assert named["speed_rpm"].iloc[0] == pytest.approx(RPM, rel=1e-3)


@pytest.mark.parametrize("rpm", [1497.3, 5700.0])
def test_tacho_speed(rpm):
    t = np.arange(int(3 * FS)) / FS
    pulses = 0.2 + (np.mod(t * rpm / 60.0, 1.0) < 0.15)
    assert tacho_speed(pulses, FS) == pytest.approx(rpm, rel=2e-4)
    with pytest.raises(ValueError, match="pulses"):
        tacho_speed(pulses[:30], FS)


def test_dominant_line_gives_the_speed(synth):
    x = synth([(23.7, 1.0), (47.4, 0.3)], FS, 3.0, noise=1e-3)
    assert dominant_speed(x, FS) == pytest.approx(60 * 23.7, rel=1e-4)
    row = signal_features(x, FS).iloc[0]
    assert row["speed_rpm"] == pytest.approx(60 * 23.7, rel=1e-4)
    assert row["amp_2x"] == pytest.approx(0.3, rel=0.01)


def test_columns_selection_and_arrays(channels):
    table = signal_features(channels, FS, RPM, columns="casing")
    assert list(table["channel"]) == ["casing"]
    arr = signal_features(channels[["shaft", "casing"]].to_numpy().T, FS, RPM)
    assert list(arr["channel"]) == [0, 1]
    np.testing.assert_allclose(arr.iloc[:, 1:].to_numpy(),
                               signal_features(channels, FS, RPM).iloc[:, 1:].to_numpy(),
                               equal_nan=True)


def test_batch_path_matches_one_signal_at_a_time(synth):
    speeds = np.array([1500.0, 1800.0, 2400.0, 5700.0] * 40)
    X = np.vstack([
        synth([(r / 60, 1.0), (1.5 * r / 60, 0.05 * (i % 3)), (4 * r / 60 + 3.0, 0.02),
               (4 * r / 60 - 3.0, 0.02)], FS, 2.0, noise=1e-3, seed=i)
        for i, r in enumerate(speeds)
    ])
    batch = feature_matrix(X, FS, speeds)
    assert batch.shape == (160, len(feature_names()))
    for i in (0, 1, 2, 3, 77, 130, 159):
        single = signal_features(X[i], FS, speeds[i]).iloc[0, 1:].to_numpy(dtype=float)
        np.testing.assert_allclose(batch[i], single, equal_nan=True, rtol=1e-12)
    amp_1p5 = batch[:, feature_names().index("amp_1p5x")]
    np.testing.assert_allclose(amp_1p5, 0.05 * (np.arange(160) % 3), rtol=0.03)
    delta = batch[:, feature_names().index("sb_4x_delta_hz")]
    np.testing.assert_allclose(delta, 3.0, atol=0.5)


def test_prefixed_features_for_simulation_results(synth):
    shaft = synth([(F1, 2e-3), (4 * F1, 1e-5)], FS, 2.0)
    casing = synth([(F1, 5e-5), (4 * F1 - 5, 1e-6), (4 * F1 + 5, 1e-6)], FS, 2.0)
    row = prefixed_features({"shaft": shaft, "casing": casing}, FS, RPM)
    assert row.shape[0] == 1
    assert row["speed_rpm"].iloc[0] == RPM
    assert row["shaft_amp_1x"].iloc[0] == pytest.approx(2e-3, rel=0.01)
    assert row["casing_sb_4x_delta_hz"].iloc[0] == pytest.approx(5.0, abs=0.5)
    assert "shaft_speed_rpm" not in row.columns
    assert "speed_confidence" not in row.columns and "shaft_speed_confidence" not in row.columns
    assert len(row.columns) == 1 + 2 * (len(feature_names()) - 2)
    with pytest.raises(ValueError, match="equal length"):
        prefixed_features({"shaft": shaft, "casing": casing[:-1]}, FS, RPM)
    with pytest.raises(ValueError, match="empty"):
        prefixed_features({}, FS, RPM)


class TestFiles:
    def test_csv_with_time_column(self, channels, tmp_path):
        path = tmp_path / "run.csv"
        channels.assign(time=np.arange(len(channels)) / FS).to_csv(path, index=False)
        frame, fs = read_signals(path)
        assert fs == pytest.approx(FS)
        assert list(frame.columns) == ["shaft", "casing", "tacho"]
        table = signal_features(path)
        assert table["speed_rpm"].iloc[0] == pytest.approx(RPM, rel=1e-3)
        assert table["amp_1x"].iloc[0] == pytest.approx(2.0, rel=0.01)

    def test_csv_without_time_needs_fs(self, channels, tmp_path):
        path = tmp_path / "run.csv"
        channels.to_csv(path, index=False)
        with pytest.raises(ValueError, match="no sampling frequency"):
            read_signals(path)
        assert signal_features(path, FS, RPM)["amp_1x"].iloc[0] == pytest.approx(2.0, rel=0.01)

    def test_npz_and_parquet(self, channels, tmp_path):
        np.savez(tmp_path / "run.npz", fs=FS, **{c: channels[c].to_numpy() for c in channels})
        channels.to_parquet(tmp_path / "run.parquet")
        reference = signal_features(channels, FS, RPM)
        for name, fs in (("run.npz", None), ("run.parquet", FS)):
            table = signal_features(tmp_path / name, fs, RPM)
            pd.testing.assert_frame_equal(table, reference)

    def test_file_errors(self, channels, tmp_path):
        with pytest.raises(FileNotFoundError):
            read_signals(tmp_path / "missing.csv")
        with pytest.raises(ValueError, match="unknown file type"):
            read_signals(tmp_path / "run.wav")
        bad = tmp_path / "bad.csv"
        bad.write_text("a,b\n1,x\n2,y\n")
        with pytest.raises(ValueError, match="not numeric"):
            read_signals(bad, 100.0)
        jitter = tmp_path / "jitter.csv"
        pd.DataFrame({"t": [0.0, 0.1, 0.25, 0.3], "a": [1, 2, 3, 4]}).to_csv(jitter, index=False)
        with pytest.raises(ValueError, match="not uniformly"):
            read_signals(jitter)
        timed = tmp_path / "timed.csv"
        channels.assign(t=np.arange(len(channels)) / FS).to_csv(timed, index=False)
        with pytest.raises(ValueError, match="disagrees"):
            read_signals(timed, 1000.0)


class TestBadInput:
    @pytest.mark.parametrize(
        ("signal", "fs", "rpm", "message"),
        [
            (np.array([]), FS, RPM, "empty"),
            (np.r_[np.ones(100), np.nan, np.zeros(3899)], FS, RPM, "NaN or inf"),
            (np.r_[np.ones(100), np.inf, np.zeros(3899)], FS, RPM, "NaN or inf"),
            (np.sin(np.arange(4000.0)), 0.0, RPM, r"fs = 0\.0 is out of range \(allowed: > 0 Hz\)"),
            (np.sin(np.arange(4000.0)), -FS, RPM, r"fs = -2000\.0 is out of range"),
            (np.sin(np.arange(4000.0)), np.float64(np.nan), RPM, r"fs = nan is out of range"),
            (np.sin(np.arange(4000.0)), "2 kHz", RPM, "fs = '2 kHz' has the wrong type"),
            (np.sin(np.arange(4000.0)), FS, 61000.0, "above the Nyquist"),
            (np.sin(np.arange(4000.0)), FS, -5.0,
             r"speed_rpm = -5\.0 is out of range \(allowed: > 0 rpm\)"),
            (np.sin(np.arange(4000.0)), FS, np.float64(0.0), r"speed_rpm = 0\.0 is out of range"),
            (np.sin(np.arange(4000.0)), FS, "fast", "speed_rpm = 'fast' has the wrong type"),
            (np.sin(np.arange(500.0)), FS, RPM, "too short"),
        ],
    )
    def test_clear_value_errors(self, signal, fs, rpm, message):
        with pytest.raises(ValueError, match=message):
            signal_features(signal, fs, rpm)

    def test_missing_column_is_named(self, channels):
        with pytest.raises(ValueError, match="'blade' not found"):
            signal_features(channels, FS, RPM, columns=["blade"])
        with pytest.raises(ValueError, match="'key' not found"):
            signal_features(channels, FS, tacho="key")

    def test_bad_channel_is_named(self, channels):
        bad = channels.copy()
        bad.loc[10, "casing"] = np.nan
        with pytest.raises(ValueError, match="channel 'casing'"):
            signal_features(bad, FS, RPM)

    def test_in_memory_signal_needs_fs(self):
        with pytest.raises(ValueError, match="fs"):
            signal_features(np.sin(np.arange(100.0)))

    @pytest.mark.parametrize(
        ("kwargs", "message"),
        [({"band": 0.3}, r"band = 0\.3 is out of range \(allowed: > 0 and < 0\.25 orders\)"),
         ({"threshold": 0.5}, r"threshold = 0\.5 is out of range \(allowed: >= 1\)"),
         ({"threshold": "5"}, "threshold = '5' has the wrong type"),
         ({"combo_tol_hz": -1.0}, r"combo_tol_hz = -1\.0 is out of range \(allowed: > 0 Hz\)"),
         ({"min_revolutions": -1.0}, r"min_revolutions = -1\.0 is out of range"),
         ({"nperseg": 1000.0}, r"nperseg = 1000\.0 has the wrong type")],
    )
    def test_bad_options(self, synth, kwargs, message):
        with pytest.raises(ValueError, match=message):
            signal_features(synth([(F1, 1.0)], FS, 2.0), FS, RPM, **kwargs)


class TestStillChannels:
    """A still channel (every sample equal) has every line absent; it never raises."""

    @staticmethod
    def _assert_still(row, speed_rpm=np.nan):
        np.testing.assert_equal(row["speed_rpm"], speed_rpm)
        assert np.isnan(row["speed_confidence"])
        for name, value in still_features().items():
            np.testing.assert_equal(row[name], value, err_msg=name)

    @pytest.mark.parametrize("speed", [RPM, None])
    def test_a_still_channel_among_moving_ones(self, channels, speed):
        frame = channels.assign(dead=0.7)
        table = signal_features(frame, FS, speed)
        assert list(table["channel"]) == ["shaft", "casing", "dead"]
        self._assert_still(table.iloc[2], RPM)       # given or from the tacho channel
        reference = signal_features(channels, FS, speed)
        pd.testing.assert_frame_equal(table.iloc[:2], reference)

    def test_a_still_channel_with_the_speed_to_guess(self, channels):
        frame = channels[["shaft"]].assign(dead=-2.0)
        table = signal_features(frame, FS)
        assert table["speed_rpm"].iloc[0] == pytest.approx(RPM, rel=1e-4)
        # the record's speed, guessed from the shaft: nothing was guessed from the dead one
        self._assert_still(table.iloc[1], table["speed_rpm"].iloc[0])

    def test_every_channel_still(self):
        still = np.vstack([np.zeros(4000), np.full(4000, 1e5)])
        table = signal_features(still, FS, RPM)
        assert len(table) == 2
        for i in range(2):
            self._assert_still(table.iloc[i], RPM)
        # without its speed there is no line to guess it from: refused, not "nan rpm"
        with pytest.raises(ValueError, match="every channel is still"):
            signal_features(still, FS)

    def test_feature_matrix(self, synth):
        X = np.vstack([synth([(F1, 1.0)], FS, 2.0), np.full(4000, 3.0)])
        batch = feature_matrix(X, FS, RPM)
        assert batch[0, feature_names().index("amp_1x")] == pytest.approx(1.0, rel=1e-3)
        self._assert_still(dict(zip(feature_names(), batch[1], strict=True)), RPM)

    def test_prefixed_features(self, synth):
        shaft = synth([(F1, 2e-3)], FS, 2.0)
        row = prefixed_features({"shaft": shaft, "casing": np.zeros_like(shaft)}, FS, RPM)
        assert row["shaft_amp_1x"].iloc[0] == pytest.approx(2e-3, rel=0.01)
        for name, value in still_features().items():
            np.testing.assert_equal(row[f"casing_{name}"].iloc[0], value, err_msg=name)
        row = prefixed_features({"shaft": np.ones(4000), "casing": np.zeros(4000)}, FS, RPM)
        assert row["speed_rpm"].iloc[0] == RPM
        assert row["shaft_amp_1x"].iloc[0] == 0.0 and np.isnan(row["casing_freq_1x_hz"].iloc[0])

    def test_lines_pairs_and_speed_of_a_still_signal(self):
        f, amp, phase = spectral_lines(np.full(1000, 2.0), FS)
        assert f.size == amp.size == phase.size == 0
        assert combination_pairs(np.zeros(4000), FS, RPM) == []
        assert np.isnan(dominant_speed(np.zeros(4000), FS))


class TestGuessedSpeed:
    """speed_rpm=None takes the strongest line as 1×, with its confidence."""

    @pytest.mark.parametrize("n", [2000, 20_000, 200_000])
    @pytest.mark.parametrize("seed", [0, 1, 2])
    def test_pure_noise_is_refused_naming_the_confidence(self, n, seed):
        x = np.random.default_rng(seed).standard_normal(n)
        with pytest.raises(ValueError, match=r"cannot be guessed.*speed_confidence = [0-9.]+ "
                                             r"times above the noise floor \(allowed: >= 10\)"):
            signal_features(x, FS)

    def test_uniform_noise_is_refused(self):
        with pytest.raises(ValueError, match="speed_confidence"):
            signal_features(np.random.default_rng(3).random((2, 5000)), fs=5000)

    def test_a_noise_only_first_channel_takes_the_speed_of_the_others(self, synth):
        """The channels vote (rubdiag.signal._speedvote): a probe that sees only noise,
        first in the file, gets the record's speed from the channel with the 1× line."""
        good = synth([(F1, 1.0), (2 * F1, 0.3)], FS, 2.0, noise=1e-3)
        noise = np.random.default_rng(4).standard_normal(4000)
        table = signal_features(pd.DataFrame({"noise": noise, "shaft": good}), FS)
        alone = signal_features(good, FS).iloc[0]
        assert table["speed_rpm"].tolist() == [alone["speed_rpm"]] * 2
        assert alone["speed_rpm"] == pytest.approx(RPM, rel=1e-4)
        # the vote's confidence: the shaft's line (the noise's strongest line lies elsewhere)
        assert table["speed_confidence"].tolist() == [alone["speed_confidence"]] * 2
        # otherwise the table of that speed given
        given = signal_features(pd.DataFrame({"noise": noise, "shaft": good}), FS,
                                alone["speed_rpm"])
        pd.testing.assert_frame_equal(table.drop(columns="speed_confidence"),
                                      given.drop(columns="speed_confidence"))

    def test_noise_on_every_channel_is_refused_naming_the_best_line(self):
        noise = np.random.default_rng(4).standard_normal((2, 4000))
        frame = pd.DataFrame({"a": noise[0], "b": noise[1]})
        with pytest.raises(ValueError, match=r"strongest line of channel '[ab]' .* "
                                             r"speed_confidence = [0-9.]+ times above"):
            signal_features(frame, FS)

    def test_clean_harmonics_pass_with_high_confidence(self, synth):
        x = synth([(25.0, 1.0), (50.0, 0.4), (75.0, 0.2), (100.0, 0.1)], FS, 2.0, noise=1e-3)
        row = signal_features(x, FS).iloc[0]
        assert row["speed_rpm"] == pytest.approx(1500.0, rel=1e-4)
        assert row["speed_confidence"] > 100 * MIN_SPEED_CONFIDENCE

    def test_confidence_is_the_line_over_the_noise_floor(self, synth):
        # same noise, line twice as strong: twice the confidence (not a ratio of two lines)
        conf = [signal_features(synth([(25.0, a), (50.0, 0.5 * a)], FS, 2.0, noise=0.05, seed=5),
                         FS)["speed_confidence"].iloc[0] for a in (1.0, 2.0)]
        assert conf[0] > MIN_SPEED_CONFIDENCE
        assert conf[1] / conf[0] == pytest.approx(2.0, rel=0.02)

    def test_noise_free_line_has_a_finite_confidence(self, synth):
        conf = signal_features(synth([(25.0, 1.0)], FS, 2.0), FS)["speed_confidence"].iloc[0]
        assert np.isfinite(conf) and conf >= 1e5

    def test_given_speed_has_no_confidence(self, channels):
        assert signal_features(channels, FS, RPM)["speed_confidence"].isna().all()
        assert signal_features(channels, FS)["speed_confidence"].isna().all()      # from the tacho


class TestLayout:
    def test_transposed_array_gets_a_hint(self, channels):
        X = channels[["shaft", "casing"]].to_numpy()          # (5000, 2): time down the rows
        hint = (r"signal has 2 samples per channel and 5000 channels: rows are channels "
                r".*did you mean signal\.T\?")
        for speed in (RPM, None):
            with pytest.raises(ValueError, match=hint):
                signal_features(X, FS, speed)
        with pytest.raises(ValueError, match=hint.replace("2 samples", "1 sample")):
            signal_features(channels[["shaft"]].to_numpy(), FS, RPM)  # (5000, 1)
        assert len(signal_features(X.T, FS, RPM)) == 2

    def test_short_record_with_few_channels_is_too_short(self):
        with pytest.raises(ValueError, match="the record is too short"):
            signal_features(np.random.default_rng(0).standard_normal((2, 300)), FS, RPM)


def test_numpy_scalars_are_numbers(channels):
    reference = signal_features(channels, FS, RPM, threshold=2.3)
    table = signal_features(channels, np.int64(2000), np.int64(1500), threshold=np.float32(2.3),
                     band=np.float64(0.03), nperseg=np.int64(len(channels)),
                     min_revolutions=np.int64(10))
    pd.testing.assert_frame_equal(table, reference, rtol=1e-6)
    assert Options(threshold=np.float32(2.3)).threshold == pytest.approx(2.3)
    assert type(Options(threshold=np.float32(2.3)).threshold) is float
    assert signal_features(channels, FS, np.float32(1500.0))["speed_rpm"].iloc[0] == 1500.0


def test_prefixed_feature_row_is_the_frame_s_row(synth):
    """The dict path that dataset rows use holds the one-row frame's values bit for bit."""
    from rubdiag.signal._table import prefixed_feature_row

    shaft = synth([(F1, 2e-3), (0.5 * F1, 4e-4)], FS, 2.0)
    casing = synth([(F1, 5e-5), (3 * F1, 1e-6)], FS, 2.0)
    frame = prefixed_features({"shaft": shaft, "casing": casing}, FS, RPM)
    row = prefixed_feature_row({"shaft": shaft, "casing": casing}, FS, RPM)
    assert list(row) == list(frame.columns)
    values = frame.iloc[0]
    for key, value in row.items():
        assert np.float64(value).tobytes() == np.float64(values[key]).tobytes(), key
