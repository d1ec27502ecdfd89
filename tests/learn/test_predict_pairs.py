"""predict() on a measured file computes every probe pair's full-spectrum and orbit columns
as a dataset row holds them: a model with the ``full_spectrum`` and ``orbit`` families
reads a CSV of the disc's two probes as it read its dataset's rows."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.dataset import load_waveforms
from rubdiag.dataset._schema import PAIR_FEATURES, SEPARATOR
from rubdiag.learn._persist import load_model
from rubdiag.learn._predict import pair_columns, predict
from rubdiag.learn._train import train

Y, Z, PAIR = "shaft11_y_disp", "shaft11_z_disp", "shaft11_yz_disp"
LENGTHS = {n for n in PAIR_FEATURES if n.startswith(("fwd_", "rev_"))} | {
    "forward_1x", "reverse_1x", "limit_radius"}


@pytest.fixture(scope="module")
def model(small_dataset, tmp_path_factory):
    """The rub classifier on the disc's two probes with the pair families besides the
    default ones (evaluation kept short: the fitted model does not depend on it)."""
    out = tmp_path_factory.mktemp("pairs") / "model"
    train(small_dataset, out, channels=[Y, Z],
          families=("orders", "sidebands", "combinations", "full_spectrum", "orbit"),
          importances=False, baselines=False, audit=False, n_shuffles=1, n_bootstrap=0)
    return load_model(out)


@pytest.fixture(scope="module")
def windows(small_dataset, small_rows):
    """run_id -> (fs, {channel: the run's analysis window}): every stored sample from
    ``discard_s`` on, the samples its row's features were computed from."""
    out = {}
    for run_id in small_rows["run_id"]:
        waves = load_waveforms(small_dataset, run_id)
        part = waves[waves.index >= waves.attrs["discard_s"] - 1e-9]
        out[run_id] = waves.attrs["fs_hz"], {c: part[c].to_numpy(np.float64) for c in (Y, Z)}
    return out


def test_the_pair_columns_are_the_rows(small_rows, windows):
    """From the stored (float32) window, every pair column of every run within 1e-4 of the
    row's: lengths relative to the pair's 1× forward amplitude, the rest absolutely."""
    rows = small_rows.set_index("run_id")
    for run_id, (fs, signals) in windows.items():
        got = pair_columns(signals, fs, rows.loc[run_id, "speed_rpm"])
        assert set(got) == {f"{PAIR}{SEPARATOR}{n}" for n in PAIR_FEATURES}
        scale = rows.loc[run_id, f"{PAIR}{SEPARATOR}forward_1x"]
        for n in PAIR_FEATURES:
            column = f"{PAIR}{SEPARATOR}{n}"
            atol = 1e-4 * (scale if n in LENGTHS else 1.0)
            assert got[column] == pytest.approx(rows.loc[run_id, column], abs=atol,
                                                nan_ok=True), (run_id, n)


def test_no_pair_without_both_probes():
    x = np.zeros(100)
    assert pair_columns({Y: x}, 1e4, 1500.0) == {}
    assert pair_columns({Y: x, "shaft4_z_disp": x}, 1e4, 1500.0) == {}


def test_a_csv_of_the_two_probes_predicts_as_the_stored_rows(model, windows, small_rows,
                                                             small_dataset, tmp_path):
    stored = predict(model, small_dataset).set_index("input")
    speed = small_rows.set_index("run_id")["speed_rpm"]
    paths = []
    for run_id, (fs, signals) in windows.items():
        path = tmp_path / f"{run_id}.csv"
        n = round(model.meta["window_s"] * fs)         # one window of the model
        signals = {c: x[:n] for c, x in signals.items()}
        pd.DataFrame({"t": np.arange(n) / fs, **signals}).to_csv(path, index=False)
        paths.append(path)
    table = predict(model, paths, speed_rpm=None)
    table = table[table["window"] != "all"]
    table.index = [p.stem for p in map(type(paths[0]), table["input"])]
    table = table.loc[stored.index]
    assert stored["predicted"].nunique() == 2
    assert list(table["predicted"]) == list(stored["predicted"])
    p = [c for c in table.columns if c.startswith("p_")]
    assert np.abs(table[p].to_numpy() - stored[p].to_numpy()).max() <= 0.05
    np.testing.assert_allclose(table["speed_rpm"], speed[stored.index], rtol=1e-3)


def test_the_noise_curves_recompute_the_pair_columns(small_dataset, small_rows):
    """The noise curves' features of the stored windows (no noise added) hold every pair
    column, within 1e-4 of the rows' as above; with noise added they move."""
    from rubdiag.learn._robustness import (
        analysis_windows,
        noisy_windows,
        reference_power,
        window_features,
    )

    windows = analysis_windows(small_dataset, small_rows["run_id"], [Y, Z])
    speed = small_rows["speed_rpm"].to_numpy()
    clean = window_features(windows.x, windows.fs, speed, [Y, Z])
    columns = [f"{PAIR}{SEPARATOR}{n}" for n in PAIR_FEATURES]
    assert set(columns) <= set(clean.columns)
    scale = small_rows[f"{PAIR}{SEPARATOR}forward_1x"].to_numpy()
    for n, column in zip(PAIR_FEATURES, columns, strict=True):
        atol = 1e-4 * (scale if n in LENGTHS else 1.0)
        got, want = clean[column].to_numpy(), small_rows[column].to_numpy()
        same = np.isclose(got, want, rtol=0, atol=atol) | (np.isnan(got) & np.isnan(want))
        assert same.all(), n
    p_ref = reference_power(windows, small_rows["rub"].to_numpy(dtype=bool))
    noisy = window_features(noisy_windows(windows, p_ref, 10.0, 0), windows.fs, speed,
                            [Y, Z])
    reverse = f"{PAIR}{SEPARATOR}reverse_share"
    assert np.abs(noisy[reverse] - clean[reverse]).max() > 0.01
