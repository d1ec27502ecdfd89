"""The default channel set: shaft channels whose median power over the rubbing runs is
within NOISE_MARGIN_DB of their noise floor are left out, and said to be."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn._channel_choice import NOISE_MARGIN_DB, choose_channels, decibels
from rubdiag.learn._channel_choice import power_over_floor_db as db_of
from rubdiag.learn._columns import LINE_FEATURES
from rubdiag.learn._evaluate import resolve_channels

FLOOR = 1e-6


def frame(over_floor_db: dict, rub, floors=None, quiet_db=None) -> pd.DataFrame:
    """Rows with every feature of each channel; a channel's ``rms`` is its floor times
    10^(dB/20) on the rubbing rows (``over_floor_db``) and on the others (``quiet_db``,
    default the same)."""
    rub = np.asarray(rub, dtype=bool)
    quiet_db = quiet_db or {}
    cols = {"run_id": [f"{i:016x}" for i in range(rub.size)], "point_id": np.arange(rub.size),
            "speed_rpm": np.full(rub.size, 3000.0), "rub": rub}
    for c, db in over_floor_db.items():
        for f in LINE_FEATURES:
            cols[f"{c}__{f}"] = np.zeros(rub.size)
        loud = FLOOR * 10 ** (db / 20)
        cols[f"{c}__rms"] = np.where(rub, loud, FLOOR * 10 ** (quiet_db.get(c, db) / 20))
    data = pd.DataFrame(cols)
    data.attrs["noise_floors"] = {c: FLOOR for c in over_floor_db} if floors is None \
        else floors
    return data


def test_the_margin_is_6_db():
    assert NOISE_MARGIN_DB == 6.0


def test_the_bearing_probes_at_their_floor_are_left_out(small_dataset, small_rows,
                                                        power_over_floor_db):
    """Against the powers of the stored waveforms themselves (conftest): the bearing probes
    of the paper rig carry their 1 µm floor and nothing else, the disc probes a lot more."""
    expected = power_over_floor_db(small_dataset)
    shaft = [c for c in expected if c.startswith("shaft")]
    choice = choose_channels(small_rows)
    assert set(choice.left_out) == {c for c in shaft if expected[c] < NOISE_MARGIN_DB}
    assert set(choice.left_out) == {"shaft4_y_disp", "shaft4_z_disp", "shaft26_y_disp",
                                    "shaft26_z_disp"}                      # the bearings
    assert choice.channels == ["shaft11_y_disp", "shaft11_z_disp"]         # the disc
    for c, db in choice.left_out.items():
        assert db == pytest.approx(expected[c], abs=0.05)                  # float32 waves
        assert abs(db) < 1.0                                               # noise alone: 0 dB
    assert min(expected["shaft11_y_disp"], expected["shaft11_z_disp"]) > 40.0
    assert choice.n_rubbing == int(small_rows["rub"].sum())
    text = choice.describe()
    assert all(c in text for c in choice.left_out) and "within 6 dB" in text
    assert "--channels" in text
    # the casing is never in the default set, loud as it is
    assert "casing1_y_acc" not in choice.channels and expected["casing1_y_acc"] > 40


def test_only_the_rubbing_runs_set_the_bar():
    rub = [True] * 5 + [False] * 5
    data = frame({"pure_noise": 0.0, "just_below": 5.9, "just_above": 6.1, "quiet_when_ok": 20.0,
                  "loud_when_ok": 3.0, "casing1_y_acc": 0.0},
                 rub, quiet_db={"quiet_when_ok": 0.0, "loud_when_ok": 60.0})
    choice = choose_channels(data)
    assert choice.channels == ["just_above", "quiet_when_ok"]
    assert list(choice.left_out) == ["pure_noise", "just_below", "loud_when_ok"]
    assert [round(v, 6) for v in choice.left_out.values()] == [0.0, 5.9, 3.0]
    assert choice.n_rubbing == 5
    # the median, not the mean: one loud rubbing run does not lift a quiet channel
    data.loc[0, "pure_noise__rms"] = 1e3 * FLOOR
    assert db_of(data, ["pure_noise"])["pure_noise"] == pytest.approx(0.0, abs=1e-9)


def test_a_channel_that_reads_zero_is_left_out_and_stays_strict_json():
    import json

    data = frame({"dead": 0.0, "alive": 20.0}, [True, True])
    data["dead__rms"] = 0.0
    choice = choose_channels(data)
    assert choice.channels == ["alive"] and choice.left_out == {"dead": -np.inf}
    assert json.loads(json.dumps(choice.left_out_json(), allow_nan=False)) == {"dead": None}
    assert "dead (-inf dB)" in choice.describe()
    assert [decibels(v) for v in (-0.04, 0.05, 5.96, -np.inf)] == [
        "+0.0 dB", "+0.1 dB", "+6.0 dB", "-inf dB"]


def test_a_floor_of_zero_or_unknown_keeps_the_channel():
    data = frame({"a": 0.0, "b": 0.0, "c": 0.0}, [True, False],
                 floors={"a": 0.0, "b": FLOOR})            # c: no floor known
    choice = choose_channels(data)
    assert choice.channels == ["a", "c"] and list(choice.left_out) == ["b"]
    assert db_of(data, ["a"]) == {"a": np.inf}


def test_what_cannot_be_judged_is_said():
    no_floors = frame({"a": 0.0, "b": 30.0}, [True, False], floors={})
    choice = choose_channels(no_floors)
    assert choice.channels == ["a", "b"] and choice.left_out == {}
    assert "noise floors of the channels are unknown" in choice.describe()
    no_rub = frame({"a": 0.0, "b": 30.0}, [False, False])
    choice = choose_channels(no_rub)
    assert choice.channels == ["a", "b"] and "No rubbing run" in choice.describe()


def test_every_channel_at_its_floor_is_refused():
    data = frame({"a": 0.5, "b": 1.0}, [True, True])
    with pytest.raises(ValueError, match=r"channels = 'auto': every shaft channel is within "
                       r"6 dB of its noise floor .*a \+0.5 dB, b \+1.0 dB.*--channels shaft"):
        choose_channels(data)
    # named sets and names are taken as they are
    assert choose_channels(data, "shaft").channels == ["a", "b"]
    assert resolve_channels(data, ["b"]) == ["b"]
    with pytest.raises(ValueError, match=r"channels: 'z' is not a channel of the data \(its "
                       r"channels: a, b; or one of auto, shaft, all\)"):
        choose_channels(data, ["z"])


def test_train_and_evaluate_say_what_was_left_out(tiny_dataset, tmp_path,
                                                  power_over_floor_db):
    """The report, metrics.json and model.json of a model trained with the default set."""
    import json

    from rubdiag.learn._train import train

    expected = {c for c, v in power_over_floor_db(tiny_dataset).items()
                if c.startswith("shaft") and v < NOISE_MARGIN_DB}
    model = train(tiny_dataset, tmp_path / "m", estimator="logreg", importances=False,
                  baselines=False, audit=False, n_shuffles=1, n_bootstrap=0)
    assert set(model.channels) == {"shaft11_y_disp", "shaft11_z_disp"}
    assert set(model.meta["channels_left_out"]) == expected
    metrics = json.loads((tmp_path / "m" / "metrics.json").read_text())
    assert set(metrics["channels_left_out"]["channels"]) == expected
    assert metrics["channels_left_out"]["margin_db"] == NOISE_MARGIN_DB
    report = (tmp_path / "m" / "report.md").read_text()
    line = next(ln for ln in report.splitlines() if ln.startswith("Left out of the default"))
    assert all(c in line for c in expected)


def test_a_channel_named_twice_is_refused():
    """``--channels a,a`` made a model whose every feature of ``a`` came twice."""
    data = frame({"a": 30.0, "b": 30.0}, [True, False])
    with pytest.raises(ValueError, match=r"channels: 'a' is named twice \(allowed: each "
                       r"channel once\)"):
        choose_channels(data, ["a", "b", "a"])
    assert choose_channels(data, ["b", "a"]).channels == ["b", "a"]      # order kept
