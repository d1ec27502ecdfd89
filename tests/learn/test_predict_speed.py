"""predict guesses a window's speed as rubdiag features does: the channels' strongest lines
vote (rubdiag.signal.speedvote), so a noise-only probe first in the file spoils nothing."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn import make_pipeline
from rubdiag.learn.persist import load_model, save_model
from rubdiag.learn.predict import predict
from rubdiag.learn.train import model_meta
from rubdiag.signal import features
from rubdiag.signal.table import prefixed_features

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
    # the same estimator as rubdiag features on the same file, to the last digit
    assert speed == features(str(path))["speed_rpm"].iloc[0]
    assert table["predicted"].iloc[0] == "True"
    # the probe alone holds no line to take as 1x: the speed must be given
    alone = tmp_path / "probe.csv"
    pd.DataFrame({"t": np.arange(N) / FS, "probe": record["probe"],
                  "shaft": np.zeros(N)}).to_csv(alone, index=False)
    with pytest.raises(ValueError, match=r"probe\.csv, window 0: the speed cannot be estimated"):
        predict(model, alone)
