"""predict guesses a window's speed as rubdiag features does: the channels' strongest lines
vote (rubdiag.signal._speedvote), so a noise-only probe first in the file spoils nothing."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn import make_pipeline
from rubdiag.learn._persist import load_model, save_model
from rubdiag.learn._predict import predict
from rubdiag.learn._train import model_meta
from rubdiag.signal import SpeedAmbiguous, signal_features
from rubdiag.signal._table import prefixed_features

FS, WINDOW_S, RPM = 2000.0, 2.0, 1500.0
N = round(FS * WINDOW_S)
SENSORS = [{"name": name, "unit": "m", "quantity": "displacement", "point": point,
            "direction": "y"} for name, point in (("probe", "shaft 4"), ("shaft", "shaft 11"))]


def _record(rpm, half_order, seed):
    """probe: 1 µm of noise only; shaft: 1× of 50 µm, a 0.5× of ``half_order`` (m), noise."""
    t = np.arange(N) / FS
    noise = np.random.default_rng(seed).standard_normal((2, N)) * 1e-6
    f1 = rpm / 60.0
    shaft = 50e-6 * np.cos(2 * np.pi * f1 * t) + half_order * np.cos(np.pi * f1 * t + 0.4)
    return {"probe": noise[0], "shaft": shaft + noise[1]}


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    """A forest on 12 synthetic runs at 1400–1600 rpm: rub is a 0.5× line."""
    rows = []
    for i, rpm in enumerate(np.linspace(1400.0, 1600.0, 12)):
        rub = bool(i % 2)
        row = prefixed_features(_record(rpm, 5e-6 if rub else 0.0, i), FS, rpm, separator="__")
        rows.append(row.assign(rub=rub))
    data = pd.concat(rows, ignore_index=True)
    data.attrs["acquisition"] = {"fs_hz": FS, "window_s": WINDOW_S, "sensors": SENSORS}
    pipe = make_pipeline("rf", channels=["probe", "shaft"]).fit(data, data["rub"].astype(str))
    meta = model_meta(pipe, data, target="rub", estimator="rf", split="group",
                      families=["orders", "sidebands", "combinations"], seed=0)
    return load_model(save_model(pipe, tmp_path_factory.mktemp("speed") / "m", meta))


def test_a_noise_only_first_channel_gives_the_right_speed(model, tmp_path):
    record = _record(RPM, 5e-6, 99)
    path = tmp_path / "r.csv"
    pd.DataFrame({"t": np.arange(N) / FS, **record}).to_csv(path, index=False)
    table = predict(model, path)
    speed = table["speed_rpm"].iloc[0]
    assert speed == pytest.approx(RPM, rel=1e-5)
    # the rub's 0.5x line could be 1x below a stronger 2x: said, and the speed not halved
    assert table["speed_ambiguous"].iloc[0]
    assert "1x may be 750 rpm below a stronger 2x" in table["warnings"].iloc[0]
    # the same estimator as rubdiag features on the same file, to the last digit
    with pytest.warns(SpeedAmbiguous, match="1x may be 750 rpm"):
        assert speed == signal_features(str(path))["speed_rpm"].iloc[0]
    assert table["predicted"].iloc[0] == "True"
    # the probe alone holds no line to take as 1x: the speed must be given
    alone = tmp_path / "probe.csv"
    pd.DataFrame({"t": np.arange(N) / FS, "probe": record["probe"],
                  "shaft": np.zeros(N)}).to_csv(alone, index=False)
    with pytest.raises(ValueError, match=r"probe\.csv, window 0: the speed cannot be estimated"):
        predict(model, alone)


def _crack(rpm, two, seed):
    """probe: noise only; shaft: 1x of 20 µm and a stronger 2x, ``two`` times 1x (a crack
    near half the critical speed), noise 0.2 µm."""
    t = np.arange(N) / FS
    noise = np.random.default_rng(seed).standard_normal((2, N))
    f1 = rpm / 60.0
    shaft = 20e-6 * (np.cos(2 * np.pi * f1 * t) + two * np.cos(4 * np.pi * f1 * t + 1.0))
    return {"probe": 1e-6 * noise[0], "shaft": shaft + 2e-7 * noise[1]}


def test_a_2x_stronger_than_1x_is_right_or_flagged(model, tmp_path, capsys):
    """Ten records whose 2x is 1.2 to 4.7 times their 1x, at speeds on and off the 0.5-Hz
    bins of the 2-s window: each estimated speed is right or flagged ambiguous (here all
    read 2x and all are flagged, naming the true speed), on its row and on stderr."""
    from rubdiag.cli import main

    speeds = np.linspace(1400.0, 1600.0, 10) + 1.37 * (np.arange(10) % 2)
    files = []
    for i, (rpm, two) in enumerate(zip(speeds, np.linspace(1.2, 4.7, 10), strict=True)):
        files.append(tmp_path / f"crack{i}.csv")
        pd.DataFrame({"t": np.arange(N) / FS, **_crack(rpm, two, i)}).to_csv(files[-1],
                                                                           index=False)
    table = predict(model, files)
    windows = table[table["window"] != "all"]
    assert len(windows) == 10
    for (_, row), rpm in zip(windows.iterrows(), speeds, strict=True):
        assert row["speed_rpm"] == pytest.approx(rpm, rel=1e-3) or row["speed_ambiguous"]
        assert row["speed_ambiguous"]
        assert f"1x may be {rpm:.5g} rpm below a stronger 2x" in row["warnings"]
    assert table.loc[table["window"] == "all", "speed_ambiguous"].all()
    folder = save_model(model.pipeline, tmp_path / "model", model.meta)
    assert main(["predict", str(folder), *map(str, files), "--json"]) == 0
    said = [ln for ln in capsys.readouterr().err.splitlines() if "is ambiguous" in ln]
    assert len(said) == 10
    assert said[0].startswith(f"rubdiag predict: warning: {files[0]}, window 0: the speed is "
                              "ambiguous")


def test_a_constant_record_is_refused_naming_it(model, tmp_path, capsys):
    from rubdiag.cli import main

    flat = tmp_path / "flat.csv"
    pd.DataFrame({"t": np.arange(N) / FS, "probe": 0.0, "shaft": 3e-5}).to_csv(flat,
                                                                               index=False)
    with pytest.raises(ValueError, match=r"flat\.csv, window 0: the speed cannot be "
                                         r"estimated \(every channel is constant"):
        predict(model, flat)
    assert predict(model, flat, speed_rpm=RPM)["speed_rpm"].iloc[0] == RPM    # given: fine
    folder = save_model(model.pipeline, tmp_path / "model", model.meta)
    assert main(["predict", str(folder), str(flat)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith("rubdiag predict: error: flat.csv, window 0: the speed "
                                   "cannot be estimated")
