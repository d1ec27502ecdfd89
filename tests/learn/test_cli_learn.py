"""``rubdiag train``, ``evaluate`` and ``predict`` end to end on the small dataset: the
default model, its files, the output formats, warnings on stderr, a fresh process, and
``predict`` without the simulator. (Bad input: tests/cli/test_errors.py.)"""

from __future__ import annotations

import contextlib
import functools
import importlib
import io
import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.dataset import load_waveforms

TRAIN = importlib.import_module("rubdiag.learn._train")

SIMULATOR = ("rubdiag.simulation", "rubdiag.runs", "rubdiag._kernels", "rubdiag.model",
             "rubdiag.modal", "rubdiag.assembly", "numba")


def run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(scope="module")
def trained(small_dataset, tmp_path_factory):
    """``rubdiag train DATASET --out MODEL --quick``: every default (target, estimator,
    split, channels); (model folder, stdout)."""
    out = tmp_path_factory.mktemp("cli") / "model"
    sink = io.StringIO()                        # capsys is per test; this fixture is not
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(sink):
        # one shuffled-label control, not five: these tests read the model's files and
        # predictions (the control: tests/learn/test_evaluate.py, test_caveats.py)
        patch.setattr(TRAIN, "train", functools.partial(TRAIN.train, n_shuffles=1))
        code = main(["train", str(small_dataset), "--out", str(out), "--quick"])
    assert code == 0
    return out, sink.getvalue()


@pytest.fixture(scope="module")
def csv(small_dataset, small_rows, tmp_path_factory):
    """One run's analysis window as a CSV at the stored rate, shaft channels, speed unknown."""
    row = small_rows.iloc[0]
    waves = load_waveforms(small_dataset, row["run_id"])
    part = waves[waves.index >= waves.attrs["discard_s"] - 1e-9].iloc[:5000]
    path = tmp_path_factory.mktemp("csv") / "run.csv"
    part.reset_index().to_csv(path, index=False)       # t_s, every channel
    return path


def test_the_default_model(trained, small_dataset, small_rows, power_over_floor_db):
    out, stdout = trained
    meta = json.loads((out / "model.json").read_text())
    sensors = json.loads((small_dataset / "dataset.json").read_text())["acquisition"][
        "sensors"]
    # decided defaults: rub, random forest, split by design point,
    # the channels not on the casing — and not at their noise floor either
    assert (meta["target"], meta["estimator"], meta["split"]) == ("rub", "rf", "group")
    over = power_over_floor_db(small_dataset)             # from the waveforms themselves
    shaft = [s["name"] for s in sensors if not s["point"].startswith("casing")]
    quiet = [c for c in shaft if over[c] < 6.0]
    assert quiet and len(quiet) < len(shaft)
    assert [c["name"] for c in meta["channels"]] == [c for c in shaft if c not in quiet]
    assert list(meta["channels_left_out"]) == quiet
    assert meta["classes"] == ["False", "True"]
    assert sorted(p.name for p in out.iterdir()) == [
        "confusion.png", "metrics.json", "model.json", "model.skops", "report.md"]
    lines = stdout.splitlines()
    assert lines[0].startswith(f"{out}: rub classifier (rf; channels shaft11_y_disp, "
                               "shaft11_z_disp)")
    assert "held-out macro-F1" in lines[0]
    assert lines[1].startswith("left out (median power over the rubbing runs within 6 dB of "
                               "the noise floor): ")
    shown = {c: round(meta["channels_left_out"][c], 1) + 0.0 for c in quiet}   # no -0.0
    assert all(f"{c} {db:+.1f} dB" in lines[1] for c, db in shown.items())
    # 12 runs of each class, well separated: nothing to warn of
    assert not [ln for ln in lines if ln.startswith("warning:")] and meta["warnings"] == []


def test_evaluate_prints_scores(trained, small_dataset, capsys):
    out, _ = trained
    code, text, err = run(["evaluate", out, small_dataset], capsys)
    assert code == 0, err
    assert text.splitlines()[0] == (f"{small_dataset}: 24 of 24 runs scored, target rub; "
                                    "in-sample: 24 of these 24 runs were in the model's "
                                    "training set, so these scores flatter it")
    code, text, _ = run(["evaluate", out, small_dataset, "--json"], capsys)
    scores = json.loads(text)
    assert scores["n_rows"] == 24 and scores["unknown"] == {}
    assert sum(map(sum, scores["confusion"]["counts"])) == 24
    assert set(scores["scores"]) == {"macro_f1", "balanced_accuracy"}


def test_predict_table_and_json_agree(trained, csv, small_dataset, capsys):
    out, _ = trained
    code, text, err = run(["predict", out, csv], capsys)
    assert code == 0 and err == ""
    lines = text.splitlines()
    assert lines[0].split() == ["input", "window", "start_s", "end_s", "speed_rpm",
                                "speed_source", "speed_ambiguous", "predicted", "p_False",
                                "p_True"]
    assert [line.split()[1] for line in lines[1:]] == ["0", "all"]
    code, text, _ = run(["predict", out, csv, "--json"], capsys)
    records = json.loads(text)
    assert [r["window"] for r in records] == [0, "all"]
    assert records[0]["p_False"] + records[0]["p_True"] == pytest.approx(1.0)
    assert records[0]["warnings"] == ""
    shown = lines[1].split()
    assert shown[5] == records[0]["speed_source"] == "estimated"     # no tacho column
    assert shown[6] == str(records[0]["speed_ambiguous"])
    assert shown[7] == records[0]["predicted"]
    assert float(shown[9]) == pytest.approx(records[0]["p_True"], abs=5e-4)
    # a dataset folder: one row per run
    code, text, _ = run(["predict", out, small_dataset, "--json"], capsys)
    assert len(json.loads(text)) == 24


def test_predict_warns_on_stderr_and_exits_0(trained, csv, capsys):
    out, _ = trained
    code, text, err = run(["predict", out, csv, "--speed-rpm", "12000"], capsys)
    assert code == 0
    assert [line.split()[1] for line in text.splitlines()[1:]] == ["0", "all"]
    lines = err.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"rubdiag predict: warning: {csv}, window 0: speed 12000 rpm "
                               "is outside the training range")
    assert "Traceback" not in err


def test_predict_column_map_and_units(trained, csv, tmp_path, capsys):
    # the flags' parsing and plumbing; what a unit does to a model is in test_predict.py
    out, _ = trained
    frame = pd.read_csv(csv)
    channel = "shaft11_y_disp"
    frame[channel] *= 1e3                                    # this probe reads mm
    frame = frame.rename(columns={channel: "probe"})
    frame.to_csv(tmp_path / "mm.csv", index=False)
    _, text, _ = run(["predict", out, csv, "--json"], capsys)
    _, mapped, err = run(["predict", out, tmp_path / "mm.csv", "--column",
                          f"probe={channel}", "--unit", f"{channel}=mm", "--json"], capsys)
    assert err == ""
    a, b = json.loads(text)[0], json.loads(mapped)[0]
    assert a["predicted"] == b["predicted"]
    assert b["p_True"] == pytest.approx(a["p_True"], abs=1e-9)


def test_a_fresh_process_predicts_identically(trained, csv):
    out, _ = trained
    from rubdiag.learn._persist import load_model
    from rubdiag.learn._predict import predict

    here = predict(load_model(out), csv)
    result = subprocess.run([sys.executable, "-m", "rubdiag", "predict", str(out), str(csv),
                             "--json"], capture_output=True, text=True, check=True)
    there = pd.DataFrame(json.loads(result.stdout))
    for column in ("p_False", "p_True", "speed_rpm"):
        assert np.array_equal(there[column].to_numpy(float), here[column].to_numpy(float))


def test_predict_does_not_import_the_simulator(trained, csv):
    out, _ = trained
    code = ("import sys; from rubdiag.cli import main; "
            f"code = main(['predict', {str(out)!r}, {str(csv)!r}]); "
            f"print([m for m in sys.modules if m.startswith({SIMULATOR!r})], code, "
            "file=sys.stderr)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)
    assert result.stderr.strip() == "[] 0"


def test_cli_choices_are_the_library_s():
    import argparse

    from rubdiag.cli import learn as cli
    from rubdiag.learn import ESTIMATORS, TARGETS
    from rubdiag.learn._channel_choice import NOISE_MARGIN_DB

    sub = argparse.ArgumentParser().add_subparsers()
    cli.register(sub)
    options = {a.dest: a for a in sub.choices["train"]._actions}
    assert tuple(options["target"].choices) == tuple(TARGETS)
    assert tuple(options["estimator"].choices) == tuple(ESTIMATORS)
    option = options["channels"]
    assert option.default == "auto" and f"{NOISE_MARGIN_DB:g} dB" in option.help
