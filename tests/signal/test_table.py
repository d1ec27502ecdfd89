"""features(): inputs (arrays, DataFrames, files), speed sources, batch path, bad input."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.signal import (
    dominant_speed,
    feature_matrix,
    feature_names,
    features,
    prefixed_features,
    read_signals,
    tacho_speed,
)

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
    table = features(channels, FS, RPM)
    assert list(table.columns) == ["channel", *feature_names()]
    assert list(table["channel"]) == ["shaft", "casing"]  # tacho is not analysed
    shaft, casing = table.iloc[0], table.iloc[1]
    assert shaft["amp_1x"] == pytest.approx(2.0, rel=0.01)
    assert shaft["amp_1p5x"] == pytest.approx(0.1, rel=0.02)
    assert casing["amp_4x"] == pytest.approx(0.05, rel=0.02)
    assert casing["amp_1p5x"] == 0.0


def test_speed_from_the_tacho_channel(channels):
    table = features(channels, FS)  # column "tacho" is found by name
    assert table["speed_rpm"].to_numpy() == pytest.approx(RPM, rel=1e-3)
    named = features(channels.rename(columns={"tacho": "key"}), FS, tacho="key")
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
    row = features(x, FS).iloc[0]
    assert row["speed_rpm"] == pytest.approx(60 * 23.7, rel=1e-4)
    assert row["amp_2x"] == pytest.approx(0.3, rel=0.01)


def test_columns_selection_and_arrays(channels):
    table = features(channels, FS, RPM, columns="casing")
    assert list(table["channel"]) == ["casing"]
    arr = features(channels[["shaft", "casing"]].to_numpy().T, FS, RPM)
    assert list(arr["channel"]) == [0, 1]
    np.testing.assert_allclose(arr.iloc[:, 1:].to_numpy(),
                               features(channels, FS, RPM).iloc[:, 1:].to_numpy(), equal_nan=True)


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
        single = features(X[i], FS, speeds[i]).iloc[0, 1:].to_numpy(dtype=float)
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
    assert len(row.columns) == 1 + 2 * (len(feature_names()) - 1)
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
        table = features(path)
        assert table["speed_rpm"].iloc[0] == pytest.approx(RPM, rel=1e-3)
        assert table["amp_1x"].iloc[0] == pytest.approx(2.0, rel=0.01)

    def test_csv_without_time_needs_fs(self, channels, tmp_path):
        path = tmp_path / "run.csv"
        channels.to_csv(path, index=False)
        with pytest.raises(ValueError, match="no sampling frequency"):
            read_signals(path)
        assert features(path, FS, RPM)["amp_1x"].iloc[0] == pytest.approx(2.0, rel=0.01)

    def test_npz_and_parquet(self, channels, tmp_path):
        np.savez(tmp_path / "run.npz", fs=FS, **{c: channels[c].to_numpy() for c in channels})
        channels.to_parquet(tmp_path / "run.parquet")
        reference = features(channels, FS, RPM)
        for name, fs in (("run.npz", None), ("run.parquet", FS)):
            table = features(tmp_path / name, fs, RPM)
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
            (np.full(4000, 1.5), FS, RPM, "constant"),
            (np.r_[np.ones(100), np.nan, np.zeros(3899)], FS, RPM, "NaN or inf"),
            (np.r_[np.ones(100), np.inf, np.zeros(3899)], FS, RPM, "NaN or inf"),
            (np.sin(np.arange(4000.0)), 0.0, RPM, "fs must be"),
            (np.sin(np.arange(4000.0)), -FS, RPM, "fs must be"),
            (np.sin(np.arange(4000.0)), FS, 61000.0, "above the Nyquist"),
            (np.sin(np.arange(4000.0)), FS, -5.0, "speed_rpm must be positive"),
            (np.sin(np.arange(500.0)), FS, RPM, "too short"),
        ],
    )
    def test_clear_value_errors(self, signal, fs, rpm, message):
        with pytest.raises(ValueError, match=message):
            features(signal, fs, rpm)

    def test_missing_column_is_named(self, channels):
        with pytest.raises(ValueError, match="'blade' not found"):
            features(channels, FS, RPM, columns=["blade"])
        with pytest.raises(ValueError, match="'key' not found"):
            features(channels, FS, tacho="key")

    def test_bad_channel_is_named(self, channels):
        bad = channels.copy()
        bad.loc[10, "casing"] = np.nan
        with pytest.raises(ValueError, match="channel 'casing'"):
            features(bad, FS, RPM)

    def test_in_memory_signal_needs_fs(self):
        with pytest.raises(ValueError, match="fs"):
            features(np.sin(np.arange(100.0)))

    @pytest.mark.parametrize(
        ("kwargs", "message"),
        [({"band": 0.3}, "band"), ({"threshold": 0.5}, "threshold"),
         ({"combo_tol_hz": -1.0}, "combo_tol_hz"), ({"min_revolutions": -1.0}, "min_revolutions")],
    )
    def test_bad_options(self, synth, kwargs, message):
        with pytest.raises(ValueError, match=message):
            features(synth([(F1, 1.0)], FS, 2.0), FS, RPM, **kwargs)
