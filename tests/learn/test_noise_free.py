"""A noise-free record is not rub: the broadband bands over the channel's
noise floor (``bb_<n>x_over_floor``) get a defined floor when a record has none, so a model
trained on sensor noise reads a simulation's raw output as it reads the same run measured."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from data_tolerances import TOLERANCES

from rubdiag.dataset._noise import NoiseFloors
from rubdiag.learn._features import OrderFeatures
from rubdiag.signal._bandfloor import MIN_FLOOR_OF_LEVEL
from rubdiag.signal._orders import HARMONICS
from rubdiag.signal._table import prefixed_features

FS, RPM = 2000.0, 1500.0
F1 = RPM / 60.0
BANDS = [f"shaft__bb_{n}x_over_floor" for n in HARMONICS]


def _tone(lines, seconds=2.0):
    """A sum of cosines (order, amplitude) on exact bins, without noise."""
    t = np.arange(round(seconds * FS)) / FS
    return sum(a * np.cos(2 * np.pi * k * F1 * t + 0.3 * k) for k, a in lines)


def _over_floor(x) -> pd.Series:
    row = prefixed_features({"shaft": x}, FS, RPM, separator="__")
    z = OrderFeatures(channels="shaft", families="sidebands").fit(row)
    return pd.Series(z.transform(row)[0], index=z.get_feature_names_out())


def test_a_pure_tone_without_noise_sits_at_its_floor():
    """Nothing but 1×: the quietest band is round-off, the floor the rule's 1e-4 of the
    level, and every band reads 1 (at the floor) — not round-off over round-off."""
    z = _over_floor(_tone([(1.0, 2.0)]))
    assert (z[BANDS] == 1.0).all()


def test_a_band_over_the_rules_floor_reads_its_analytic_value():
    """1× of amplitude A and a pair of lines 1.9× and 2.1× of amplitude s, noise-free: the
    2× band holds the pair, RMS s (Parseval: two lines of power s²/2); the level is
    sqrt(A²/2 + s²); the floor is MIN_FLOOR_OF_LEVEL of it. So bb_2x_over_floor =
    s / (1e-4 · level) ≈ 141 — finite and bounded (a band never exceeds the level: at most
    1 / MIN_FLOOR_OF_LEVEL), where the floor of round-off gave 1e6 and more."""
    a, s = 2.0, 0.02
    z = _over_floor(_tone([(1.0, a), (1.9, s), (2.1, s)]))
    level = np.sqrt(a**2 / 2 + s**2)
    assert z["shaft__bb_2x_over_floor"] == pytest.approx(s / (MIN_FLOOR_OF_LEVEL * level),
                                                         rel=1e-6)
    assert (z[[b for b in BANDS if "_2x_" not in b]] == 1.0).all()
    assert z[BANDS].max() <= 1.0 / MIN_FLOOR_OF_LEVEL


def test_a_noisy_record_keeps_its_own_floor():
    """Noise above the rule's floor: the floor is the quietest band, as before the rule
    (bands of noise alone ≈ 1, the quietest exactly 1)."""
    x = _tone([(1.0, 2.0)]) + 5e-2 * np.random.default_rng(0).standard_normal(round(2 * FS))
    row = prefixed_features({"shaft": x}, FS, RPM, separator="__")
    bands = row[[f"shaft__bb_{n}x_rms" for n in HARMONICS]].to_numpy()[0]
    z = _over_floor(x)
    np.testing.assert_allclose(z[BANDS].to_numpy(), bands / bands.min(), rtol=1e-12)
    assert bands.min() > 10 * MIN_FLOOR_OF_LEVEL * np.sqrt(2.0)   # far above the rule's


# --- the test: a model trained on noise, records without it -----------------------

_DESIGN = """
[base]
rig = "paper"
duration_s = 0.85
discard_s = 0.25
reduced = true

[sampling]
method = "lhs"
n = {n}
seed = {seed}

[factors]
case = [1, 2]
speed_ratio = {{low = 0.8, high = 1.2}}
gap_mm = {{low = 0.3, high = 2.5}}
"""
#: Every noise floor 0 (the sensor records of the same runs without noise).
_NO_NOISE = "\n[noise]\n" + "".join(f"{k} = 0.0\n" for k in NoiseFloors().to_dict())
#: Share of runs whose noise-free records must be predicted as their noisy ones
#: (data/tolerances.toml, which the documentation shows).
AGREEMENT = TOLERANCES["noise_free"]["agreement"]


@pytest.fixture(scope="module")
def datasets(tmp_path_factory):
    """A noisy training set (40 runs) and 24 other runs twice: with the default noise
    floors and with every floor 0, waveforms stored (reduced model, 0.6-s windows)."""
    from rubdiag.dataset import Design, generate

    root = tmp_path_factory.mktemp("noise_free")
    made = {}
    for name, text in (("train", _DESIGN.format(n=40, seed=1)),
                       ("noisy", _DESIGN.format(n=24, seed=2)),
                       ("clean", _DESIGN.format(n=24, seed=2) + _NO_NOISE)):
        made[name] = root / name
        generate(Design.from_toml(text), made[name], jobs=1, progress=False,
                 waveforms=name != "train")
    return made


def _records(folder, out):
    """run_id -> (NPZ of its measured channels over the analysis window, with fs; its
    speed in rpm)."""
    from rubdiag.dataset import load, load_waveforms

    records = {}
    out.mkdir()
    for run_id, rpm in load(folder)[["run_id", "speed_rpm"]].itertuples(index=False):
        waves = load_waveforms(folder, run_id)
        part = waves[waves.index >= waves.attrs["discard_s"] - 1e-9]
        records[run_id] = (out / f"{run_id}.npz", rpm)
        np.savez(records[run_id][0], fs=waves.attrs["fs_hz"],
                 **{c: part[c].to_numpy(np.float64) for c in part.columns})
    return records


@pytest.mark.slow
def test_the_clean_runs_are_the_noisy_runs_without_their_noise(datasets):
    """Same run ids; a stored record less its noise-free twin is white noise of the 1 µm
    displacement floor, on every channel."""
    from rubdiag.dataset import load, load_waveforms

    ids = list(load(datasets["noisy"])["run_id"])
    assert ids == list(load(datasets["clean"])["run_id"])
    noisy, clean = (load_waveforms(datasets[n], ids[0]) for n in ("noisy", "clean"))
    difference = (noisy - clean)[[c for c in noisy.columns if c.endswith("_disp")]]
    np.testing.assert_allclose(difference.std(), 1e-6, rtol=0.05)


@pytest.mark.slow
@pytest.mark.parametrize("channels", [None, ["shaft11_y_disp"]], ids=["default", "mid-span"])
def test_noise_free_records_are_predicted_as_their_noisy_ones(datasets, tmp_path, channels):
    """``rubdiag train`` with its default channels, and the one-probe model."""
    from rubdiag.learn._predict import predict
    from rubdiag.learn._train import train

    chosen = {} if channels is None else {"channels": channels}
    model = train(datasets["train"], tmp_path / "model", importances=False, baselines=False,
                  audit=False, **chosen)
    calls = {}
    for name in ("noisy", "clean"):
        # the speed as a tacho gives it: a serious rub's spectrum may hold no clear 1×
        calls[name] = pd.Series({
            run: predict(model, path, speed_rpm=rpm)["predicted"].iloc[-1]    # "all"
            for run, (path, rpm) in _records(datasets[name], tmp_path / name).items()})
    same = (calls["noisy"] == calls["clean"]).mean()
    print(f"channels {model.channels}: {same:.3f} of {len(calls['noisy'])} runs predicted alike "
          f"(noisy: {calls['noisy'].value_counts().to_dict()})")
    assert same >= AGREEMENT
    assert calls["noisy"].nunique() == 2            # both classes among the records
