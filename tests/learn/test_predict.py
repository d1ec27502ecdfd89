"""predict(): a saved model on measured signals — CSVs written from the small dataset's
stored waveforms, resampled as another acquisition system would record them."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.signal import resample_poly

from rubdiag.cli import main
from rubdiag.dataset import load_waveforms
from rubdiag.learn import make_pipeline, shaft_channels
from rubdiag.learn._persist import load_model, save_model
from rubdiag.learn._predict import predict, unit_factor
from rubdiag.learn._train import model_meta, train

FS_STORED = 10_000.0
FS = 5_000.0          # the "measurement": stored waveforms resampled 10 kHz -> 5 kHz


@pytest.fixture(scope="module")
def model_dir(small_dataset, tmp_path_factory):
    """The default model on the three severity classes (evaluation kept short), on all six
    shaft probes: the bearing probes, which see only their noise floor, are what the speed
    vote must ignore."""
    out = tmp_path_factory.mktemp("predict") / "model"
    train(small_dataset, out, target="severity", channels="shaft", importances=False,
          baselines=False, audit=False, n_shuffles=1, n_bootstrap=0)
    return out


@pytest.fixture(scope="module")
def model(model_dir):
    return load_model(model_dir)


@pytest.fixture(scope="module")
def windows(small_dataset, small_rows, model):
    """run_id -> the run's analysis window (t >= discard_s, window_s long) of the model's
    channels, resampled to 5 kHz with scipy.signal.resample_poly."""
    out = {}
    for run_id in small_rows["run_id"]:
        waves = load_waveforms(small_dataset, run_id)
        assert waves.attrs["fs_hz"] == FS_STORED
        part = waves[waves.index >= waves.attrs["discard_s"] - 1e-9]
        part = part.iloc[:round(model.meta["window_s"] * FS_STORED)]
        out[run_id] = {c: resample_poly(part[c].to_numpy(np.float64), 1, 2)
                       for c in model.channels}
    return out


def tacho(rpm, n, fs=FS, phase=0.3):
    """A once-per-revolution key-phasor pulse (smooth, as a probe over a keyway sees it)."""
    turns = (rpm / 60.0 * np.arange(n) / fs + phase) % 1.0
    return np.exp(-((turns - 0.5) / 0.08) ** 2)


def write_csv(path, signals, fs=FS, rpm=None, scale=1.0):
    n = len(next(iter(signals.values())))
    frame = pd.DataFrame({"t": np.arange(n) / fs, **{c: scale * np.asarray(x)
                                                     for c, x in signals.items()}})
    if rpm is not None:
        frame["tacho"] = tacho(rpm, n, fs)
    frame.to_csv(path, index=False)
    return path


def run_cli(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return captured


def probabilities(table):
    return table[[c for c in table.columns if c.startswith("p_")]].to_numpy()


@pytest.fixture(scope="module")
def stored(model, small_dataset):
    """The model on the runs themselves: their stored rows, indexed by run_id."""
    return predict(model, small_dataset).set_index("input")


def test_resampled_csvs_predict_as_the_stored_runs(model_dir, windows, small_rows, stored,
                                                   tmp_path, capsys):
    speed = small_rows.set_index("run_id")["speed_rpm"]
    paths = [write_csv(tmp_path / f"{run_id}.csv", signals, rpm=speed[run_id])
             for run_id, signals in windows.items()]
    out = run_cli(["predict", model_dir, *paths, "--json"], capsys).out
    table = pd.DataFrame(json.loads(out))
    assert len(table) == 2 * len(paths)            # one window each, and its majority row
    per_window = table[table["window"] != "all"].copy()
    per_window["run_id"] = [Path(p).stem for p in per_window["input"]]
    per_window = per_window.set_index("run_id").loc[stored.index]
    # runs of all three classes, predicted as three classes
    assert small_rows["severity"].nunique() == 3 and stored["predicted"].nunique() == 3
    assert list(per_window["predicted"]) == list(stored["predicted"])
    assert np.abs(probabilities(per_window) - probabilities(stored)).max() <= 0.05
    np.testing.assert_allclose(per_window["speed_rpm"], speed[stored.index], rtol=1e-4)


def test_the_speed_is_estimated_when_not_given(model, windows, small_rows, stored,
                                               tmp_path):
    speed = small_rows.set_index("run_id")["speed_rpm"]
    paths = [write_csv(tmp_path / f"{run_id}.csv", signals)
             for run_id, signals in windows.items()]
    table = predict(model, paths)
    table = table[table["window"] == "all"]
    run_ids = [p.name.removesuffix(".csv") for p in paths]
    # the bearing probes see mostly noise: their strongest "lines" fall anywhere, and
    # still the speed comes out of the channels that agree on a line
    np.testing.assert_allclose(table["speed_rpm"], speed[run_ids], rtol=1e-3)
    assert list(table["predicted"]) == list(stored.loc[run_ids, "predicted"])


def test_a_record_of_two_and_a_half_windows(model, windows, small_rows, tmp_path):
    label = small_rows.set_index("run_id")["severity"]
    speed = small_rows.set_index("run_id")["speed_rpm"]
    a = next(r for r in windows if label[r] == "none")
    b = next(r for r in windows if label[r] == "serious")
    alone = {r: predict(model, write_csv(tmp_path / f"{r}.csv", windows[r], rpm=speed[r]))
             for r in (a, b)}
    n = len(windows[a][model.channels[0]])
    half = slice(0, n // 2)
    record = {c: np.concatenate([windows[a][c], windows[b][c], windows[a][c][half]])
              for c in model.channels}
    pulses = np.concatenate([tacho(speed[a], n), tacho(speed[b], n), tacho(speed[a], n)[half]])
    frame = pd.DataFrame({"t": np.arange(len(pulses)) / FS, **record, "tacho": pulses})
    frame.to_csv(tmp_path / "long.csv", index=False)
    table = predict(model, tmp_path / "long.csv")
    assert list(table["window"]) == [0, 1, "all"]            # the last half window is left
    np.testing.assert_allclose(table["start_s"], [0.0, 0.5, 0.0])
    np.testing.assert_allclose(table["end_s"], [0.5, 1.0, 1.0])
    p_a, p_b = probabilities(alone[a])[0], probabilities(alone[b])[0]
    np.testing.assert_allclose(probabilities(table)[:2], [p_a, p_b], atol=1e-12)
    mean = (p_a + p_b) / 2
    np.testing.assert_allclose(probabilities(table)[2], mean, atol=1e-12)
    classes = model.classes
    winners = {classes[np.argmax(p_a)], classes[np.argmax(p_b)]}
    expected = (winners.pop() if len(winners) == 1
                else max(winners, key=lambda c: mean[classes.index(c)]))
    assert table["predicted"].iloc[2] == expected


@pytest.fixture(scope="module")
def levels_model(small_rows, tmp_path_factory):
    """A model that sees absolute levels too: a wrong unit would move its inputs."""
    families = ["orders", "levels"]
    pipe = make_pipeline("logreg", channels=shaft_channels(small_rows),
                         families=families).fit(
        small_rows, small_rows["severity"].astype(str).to_numpy())
    meta = model_meta(pipe, small_rows, target="severity", estimator="logreg",
                      split="group", families=families, seed=0)
    return load_model(save_model(pipe, tmp_path_factory.mktemp("levels") / "m", meta))


class TestUnits:
    def test_a_csv_in_micrometres_predicts_as_in_metres(self, levels_model, windows,
                                                        small_rows, tmp_path):
        run_id = small_rows["run_id"].iloc[0]
        rpm = small_rows["speed_rpm"].iloc[0]
        metres = write_csv(tmp_path / "m.csv", windows[run_id], rpm=rpm)
        micro = write_csv(tmp_path / "um.csv", windows[run_id], rpm=rpm, scale=1e6)
        mils = write_csv(tmp_path / "mil.csv", windows[run_id], rpm=rpm, scale=1 / 25.4e-6)
        reference = predict(levels_model, metres)
        for path, unit in ((micro, "µm"), (micro, "um"), (mils, "mil")):
            table = predict(levels_model, path,
                            units=dict.fromkeys(levels_model.channels, unit))
            np.testing.assert_allclose(probabilities(table), probabilities(reference),
                                       atol=1e-9)
            assert list(table["warnings"]) == list(reference["warnings"])
        # the same file read as metres is a machine a million times larger
        wrong = predict(levels_model, micro)
        assert "features outside their training range" in wrong["warnings"].iloc[0]

    def test_an_unknown_unit_lists_the_allowed_ones(self, model, windows, tmp_path):
        path = write_csv(tmp_path / "x.csv", next(iter(windows.values())), rpm=1500.0)
        channel = model.channels[0]
        with pytest.raises(ValueError, match=r"unit 'inch' is not known for a displacement "
                           r"channel \(allowed: m, mm, um, µm, mil\)"):
            predict(model, path, units={channel: "inch"})
        with pytest.raises(ValueError, match="'blade' is not a channel of the model"):
            predict(model, path, units={"blade": "mm"})

    @pytest.mark.parametrize(("quantity", "unit", "si"), [
        ("displacement", "mm", 1e-3), ("displacement", "mil", 25.4e-6),
        ("velocity", "mm/s", 1e-3), ("velocity", "in/s", 0.0254),
        ("acceleration", "g", 9.80665), ("acceleration", "m/s2", 1.0),
        ("acceleration", "mm/s^2", 1e-3), ("reaction", "kN", 1e3)])
    def test_factors_to_si(self, quantity, unit, si):
        assert unit_factor(quantity, unit) == pytest.approx(si, rel=1e-15)


class TestWarnings:
    def test_a_speed_outside_the_training_range(self, model, windows, small_rows, tmp_path):
        run_id = small_rows["run_id"].iloc[0]
        path = write_csv(tmp_path / "x.csv", windows[run_id])
        table = predict(model, path, speed_rpm=12_000.0)
        lo, hi = small_rows["speed_rpm"].min(), small_rows["speed_rpm"].max()
        assert (f"speed 12000 rpm is outside the training range {lo:.0f}–{hi:.0f} rpm"
                in table["warnings"].iloc[0])
        assert table["warnings"].iloc[1] == "1 of 1 windows with warnings"

    def test_features_outside_the_training_range(self, model, windows, small_rows,
                                                 tmp_path):
        label = small_rows.set_index("run_id")["severity"]
        speed = small_rows.set_index("run_id")["speed_rpm"]
        run_id = next(r for r in windows if label[r] == "none")
        signals = windows[run_id]
        t = np.arange(len(signals[model.channels[0]])) / FS
        f1 = speed[run_id] / 60.0
        # a 2.5x line as strong as 1x on every channel: no training run has one
        odd = {c: x + 1.5 * x.std() * np.cos(2 * np.pi * 2.5 * f1 * t)
               for c, x in signals.items()}
        counts = []
        for name, s in (("plain", signals), ("odd", odd)):
            table = predict(model, write_csv(tmp_path / f"{name}.csv", s, rpm=speed[run_id]))
            found = re.search(r"(\d+) of \d+ features outside", table["warnings"].iloc[0])
            counts.append(int(found.group(1)) if found else 0)
        # at least the 2.5x ratio of every channel (other ratios may come in range: the
        # line raises the level they are divided by)
        assert counts[1] >= len(model.channels) and counts[1] > counts[0]


class TestRefused:
    def test_a_sampling_rate_too_low_for_the_highest_order(self, model, small_dataset,
                                                           small_rows, tmp_path):
        fast = small_rows.loc[small_rows["speed_rpm"].idxmax()]
        slow = small_rows.loc[small_rows["speed_rpm"].idxmin()]
        for row in (fast, slow):
            waves = load_waveforms(small_dataset, row["run_id"])
            part = waves[waves.index >= waves.attrs["discard_s"] - 1e-9].iloc[:5000]
            write_csv(tmp_path / f"{row['run_id']}.csv",
                      {c: resample_poly(part[c].to_numpy(np.float64), 1, 10)
                       for c in model.channels}, fs=1000.0, rpm=row["speed_rpm"])
        with pytest.raises(ValueError) as info:
            predict(model, tmp_path / f"{fast['run_id']}.csv")
        message = str(info.value)
        assert "fs = 1000 Hz is too low for the model" in message and "8.25x" in message
        need = float(re.search(r"fs >= (\d+) Hz is needed", message).group(1))
        nyquist_of_band = 2 * 8.25 * fast["speed_rpm"] / 60.0
        assert nyquist_of_band < need < 1.05 * nyquist_of_band
        # a slow machine needs less: the same sampling rate serves it
        table = predict(model, tmp_path / f"{slow['run_id']}.csv")
        assert table["predicted"].iloc[0] in model.classes

    def test_a_missing_channel_and_a_column_map(self, model, windows, small_rows, stored,
                                                tmp_path):
        run_id = small_rows["run_id"].iloc[0]
        rpm = small_rows["speed_rpm"].iloc[0]
        signals = dict(windows[run_id])
        channel = model.channels[2]
        signals["probe_A"] = signals.pop(channel)
        path = write_csv(tmp_path / "renamed.csv", signals, rpm=rpm)
        with pytest.raises(ValueError, match=f"renamed.csv: channel '{channel}' is missing"):
            predict(model, path)
        mapped = predict(model, path, columns={"probe_A": channel})
        plain = predict(model, write_csv(tmp_path / "plain.csv", windows[run_id], rpm=rpm))
        np.testing.assert_array_equal(probabilities(mapped), probabilities(plain))
        with pytest.raises(ValueError, match="column 'probe_B' not found"):
            predict(model, path, columns={"probe_B": channel})

    def test_a_record_shorter_than_a_window(self, model, windows, tmp_path):
        signals = {c: x[:1000] for c, x in next(iter(windows.values())).items()}
        with pytest.raises(ValueError, match=r"lasts 0.2 s, shorter than one window of the "
                           r"model \(0.5 s\)"):
            predict(model, write_csv(tmp_path / "short.csv", signals, rpm=1500.0))

    def test_no_line_to_take_the_speed_from(self, model, tmp_path):
        noise = np.random.default_rng(0).standard_normal((len(model.channels), 2500))
        path = write_csv(tmp_path / "noise.csv", dict(zip(model.channels, noise, strict=True)))
        with pytest.raises(ValueError, match="the speed cannot be estimated"):
            predict(model, path)

    def test_options_for_files_on_a_dataset_folder(self, model, small_dataset):
        with pytest.raises(ValueError, match="speed_rpm applies to signal files only"):
            predict(model, small_dataset, speed_rpm=1500.0)
