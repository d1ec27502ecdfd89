"""Stored waveforms and measurement noise: what a dataset row's features were computed from
is what load_waveforms gives back; the noise has the stated floor in physical units, is the
run's own (seeded by its id) and does not depend on the run's level. dataset.json says how
the channels were measured, and reading a stored dataset needs no simulator."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from rubdiag.dataset import Design, acquisition, generate, load, load_waveforms
from rubdiag.dataset._noise import NoiseFloors, add_noise, noise_seed
from rubdiag.signal._table import prefixed_features

TOML = """
[base]
rig = "paper"
duration_s = 0.3
discard_s = 0.1

[sampling]
method = "grid"

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.9, 4.0]

[noise]
acceleration_m_s2 = 0.5
"""


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    out = tmp_path_factory.mktemp("waves") / "ds"
    design = Design.from_toml(TOML)
    generate(design, out, jobs=1, progress=False, waveforms=True)
    return design, out, load(out).set_index("gap_mm")


def test_features_are_those_of_the_stored_waveforms(dataset):
    """Recompute the row's features from the stored (float32) channels: equal to float32
    precision, so the file is what the row describes."""
    design, out, rows = dataset
    for gap in (1.9, 4.0):
        row = rows.loc[gap]
        waves = load_waveforms(out, row["run_id"])
        assert list(waves.columns) == [s.name for s in design.sensors]
        assert waves.attrs["units"]["casing1_y_acc"] == "m/s^2"
        window = waves.index >= design.discard_s - 1e-12
        again = prefixed_features({c: waves[c].to_numpy(np.float64)[window]
                                   for c in waves.columns},
                                  waves.attrs["fs_hz"], row["speed_rpm"], separator="__")
        for column in ("shaft11_y_disp__amp_1x", "shaft4_z_disp__amp_1x",
                       "casing1_y_acc__rms"):
            assert again[column].iloc[0] == pytest.approx(row[column], rel=1e-5), column


def test_a_silent_casing_reads_the_noise_floor(dataset):
    """Without rub the casing accelerometer measures noise only: its RMS is the floor (0.5
    m/s² here; the estimate of 3001 samples is within ±5 %), not a level scaled to the run."""
    design, out, rows = dataset
    quiet = rows.loc[4.0]
    assert not quiet["rub"]
    waves = load_waveforms(out, quiet["run_id"])["casing1_y_acc"].to_numpy(np.float64)
    assert np.std(waves) == pytest.approx(design.noise.acceleration_m_s2, rel=0.05)
    rubbing = load_waveforms(out, rows.loc[1.9]["run_id"])["casing1_y_acc"].to_numpy()
    assert np.std(rubbing) > 5 * design.noise.acceleration_m_s2


def test_noise_is_seeded_by_the_run_and_independent_of_the_level():
    x = {"a": np.zeros(10_000), "b": np.full(10_000, 1e3)}
    floors = {"a": 2.0, "b": 2.0}
    one = add_noise(x, floors, noise_seed("00000000000000ff"))
    again = add_noise(x, floors, noise_seed("00000000000000ff"))
    other = add_noise(x, floors, noise_seed("0000000000000100"))
    np.testing.assert_array_equal(one["a"], again["a"])
    assert not np.array_equal(one["a"], other["a"])
    for name in x:      # the same floor whatever the signal's level
        assert np.std(one[name] - x[name]) == pytest.approx(2.0, rel=0.05)


def test_a_run_without_waveforms_says_so(dataset, tmp_path):
    out = dataset[1]
    with pytest.raises(ValueError, match="no waveforms stored \\(no such run in it\\)"):
        load_waveforms(out, "0" * 16)
    plain = tmp_path / "plain"
    generate(Design.from_toml(TOML.replace("gap_mm = [1.9, 4.0]", "gap_mm = [4.0]")), plain,
             jobs=1, progress=False)
    with pytest.raises(ValueError, match="made without --waveforms"):
        load_waveforms(plain, load(plain)["run_id"].iloc[0])


def test_negative_noise_floor_is_refused():
    with pytest.raises(ValueError, match=r"noise\.force_n = -1\.0 is out of range"):
        NoiseFloors(force_n=-1.0)


def test_feature_columns_are_sensor_channels_only(dataset):
    """A classifier selecting group == "feature" gets what the sensors measured and nothing
    a plant cannot measure: every feature column's channel is a sensor or a y/z pair of
    displacement sensors, and the contact statistics and the casing maximum are 'truth'."""
    import pandas as pd

    design, out, rows = dataset
    columns = pd.read_csv(out / "columns.csv", keep_default_na=False)
    assert set(columns["column"]) == set(rows.reset_index().columns)
    features = columns[columns["group"] == "feature"]
    pairs = {"shaft4_yz_disp", "shaft11_yz_disp", "shaft26_yz_disp"}
    assert set(features["channel"]) == {s.name for s in design.sensors} | pairs
    truth = set(columns.loc[columns["group"] == "truth", "column"])
    assert {"contact1__max_force_n", "contacts__n_episodes", "truth__casing_max_y_m"} <= truth
    assert not any(c.startswith("window") for c in columns["column"])


def test_acquisition_is_what_the_waveforms_hold(dataset):
    """dataset.json says how the channels were measured: what a classifier trained on the
    dataset must know of a measurement."""
    design, folder, _ = dataset
    acq = acquisition(folder)
    waves = load_waveforms(folder, design.runs()[0].run_id)
    assert acq["fs_hz"] == waves.attrs["fs_hz"]
    assert acq["discard_s"] == waves.attrs["discard_s"] == 0.1
    assert acq["window_s"] == pytest.approx(0.2, abs=1e-12)
    assert [s["name"] for s in acq["sensors"]] == list(waves.columns)
    assert {s["name"]: s["unit"] for s in acq["sensors"]} == waves.attrs["units"]
    assert [s["point"] for s in acq["sensors"]] == [s.point for s in design.sensors]


def test_a_folder_without_acquisition_gets_it_on_resume(dataset, tmp_path):
    import shutil

    design, folder, _ = dataset
    old = tmp_path / "old"
    shutil.copytree(folder, old)
    meta = json.loads((old / "dataset.json").read_text(encoding="utf-8"))
    expected = meta.pop("acquisition")
    (old / "dataset.json").write_text(json.dumps(meta), encoding="utf-8")
    with pytest.raises(ValueError, match="older rubdiag"):
        acquisition(old)
    summary = generate(design, old, jobs=1, progress=False)
    assert summary["run"] == 0                      # nothing simulated again
    assert acquisition(old) == expected


def test_reading_a_dataset_imports_no_simulator(dataset):
    folder = dataset[1]
    code = ("import sys; from rubdiag.dataset import load, load_waveforms, acquisition; "
            f"load({str(folder)!r}); acquisition({str(folder)!r}); "
            "from rubdiag.dataset._noise import add_noise; "
            "print(sorted(m for m in sys.modules if m.startswith(('rubdiag.simulation', "
            "'rubdiag._kernels', 'rubdiag.model', 'numba'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]"


def test_stored_waveforms_are_a_signal_file(dataset, tmp_path):
    """``read_signals`` (and so ``rubdiag features``/``compare``/``predict``) reads a stored
    run as its sensors over the analysis window, each channel with its unit, and the CLI
    labels the amplitudes with it."""
    import subprocess
    import sys

    from rubdiag.signal import read_signals

    design, out, rows = dataset
    row = rows.loc[1.9]
    path = out / "waveforms" / f"{row['run_id']}.npz"
    frame, fs = read_signals(path)
    waves = load_waveforms(out, row["run_id"])
    window = waves.index >= design.discard_s - 1e-12
    assert fs == waves.attrs["fs_hz"]
    assert list(frame.columns) == list(waves.columns)
    np.testing.assert_array_equal(frame.to_numpy(), waves[window].to_numpy(np.float64))
    assert frame.attrs["units"] == waves.attrs["units"]
    done = subprocess.run([sys.executable, "-m", "rubdiag", "features", str(path),
                           "--column", "shaft11_y_disp"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "(amplitudes in m," in done.stdout
    refused = subprocess.run([sys.executable, "-m", "rubdiag", "features", str(path),
                              "--column", "shaft11_y_disp", "--unit", "mm"],
                             capture_output=True, text=True)
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert "dataset's stored waveforms, in m" in refused.stderr


def test_no_unit_names_stored_channels_of_several_units(dataset, capsys):
    """A stored run holds displacements (m) and an acceleration (m/s^2): no ``--unit``
    names them all, so one is refused in one line, and the heading does not claim one."""
    from rubdiag.cli import main

    _, out, rows = dataset
    path = out / "waveforms" / f"{rows.loc[1.9]['run_id']}.npz"
    units = {sensor["unit"] for sensor in acquisition(out)["sensors"]}
    assert units == {"m", "m/s^2"}                              # the premise: mixed units
    for command in (["features", str(path)], ["compare", str(path), str(path)]):
        assert main([*command, "--unit", "um"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--unit um" in err
        assert "m/s^2" in err and "--column" in err


def test_a_damaged_waveform_file_is_named(dataset, tmp_path):
    """A truncated DIR/waveforms/<run_id>.npz is a ValueError naming it (it was zipfile's
    "File is not a zip file", which names nothing)."""
    import shutil

    _, out, rows = dataset
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    run_id = rows.loc[1.9]["run_id"]
    path = copy / "waveforms" / f"{run_id}.npz"
    path.write_bytes(path.read_bytes()[:1000])
    with pytest.raises(ValueError) as info:
        load_waveforms(copy, run_id)
    message = str(info.value)
    assert message.startswith(f"{path}: unreadable (") and "\n" not in message
