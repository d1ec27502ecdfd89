"""train(): the model folder, what model.json says of the training, writing that a crash
cannot leave half done, and a saved model scored on a dataset (evaluate)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import balanced_accuracy_score, f1_score

from rubdiag import __version__
from rubdiag.learn._channel_choice import NOISE_MARGIN_DB
from rubdiag.learn._persist import META_FILE, MODEL_FILE, load_model
from rubdiag.learn._train import evaluate, order_reach, train
from rubdiag.signal._table import signal_features

# logreg: the cheapest estimator with every part of the evaluation (importances,
# baselines, audit), so that every file of a model folder is written
OPTIONS = {"target": "severity", "estimator": "logreg", "n_repeats": 1}


@pytest.fixture(scope="module")
def trained(small_dataset, tmp_path_factory):
    """(model returned by train, its folder, the evaluation train wrote)."""
    out = tmp_path_factory.mktemp("train") / "model"
    model = train(small_dataset, out, **OPTIONS)
    return model, out


@pytest.fixture(scope="module")
def sensors(small_dataset):
    """The dataset's sensors as dataset.json states them (read here, not through learn)."""
    return json.loads((small_dataset / "dataset.json").read_text())["acquisition"]["sensors"]


class TestModelFolder:
    def test_every_file_and_nothing_else(self, trained):
        _, out = trained
        assert sorted(p.name for p in out.iterdir()) == sorted([
            MODEL_FILE, META_FILE, "metrics.json", "report.md", "confusion.png",
            "importances.png", "importances.csv"])
        assert [p.name for p in out.parent.iterdir()] == ["model"]   # no temporary left
        for png in ("confusion.png", "importances.png"):
            assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    def test_metrics_report_and_importances_agree(self, trained):
        model, out = trained
        metrics = json.loads((out / "metrics.json").read_text())
        assert metrics["target"] == "severity" and metrics["estimator"] == "logreg"
        assert metrics["scores"] == model.meta["scores"]
        assert sum(map(sum, metrics["confusion"]["counts"])) == 24
        assert (out / "report.md").read_text().startswith("# severity: logreg, split group")
        imp = pd.read_csv(out / "importances.csv")
        assert list(imp.columns) == ["feature", "importance", "std"]
        assert imp["importance"].is_monotonic_decreasing

    def test_the_model_predicts_its_training_rows(self, trained, small_rows):
        model, _ = trained
        predicted = model.pipeline.predict(small_rows)
        # severity of these runs is learnable: a fit on all rows gets most of them
        assert (predicted == small_rows["severity"].astype(str)).mean() >= 0.8


class TestModelJson:
    def test_what_was_trained(self, trained, small_rows, small_dataset, sensors):
        meta = trained[0].meta
        assert meta["rubdiag_version"] == __version__
        assert (meta["target"], meta["estimator"], meta["split"]) == ("severity", "logreg",
                                                                      "group")
        assert meta["classes"] == ["light", "none", "serious"]
        assert meta["class_counts"] == small_rows["severity"].value_counts().to_dict()
        assert meta["dataset"]["path"] == str(small_dataset.resolve())
        assert meta["dataset"]["n_rows"] == 24
        assert (meta["window_s"], meta["fs_hz"]) == (0.5, 10000.0)
        assert meta["families"] == ["orders", "sidebands", "combinations"]
        assert meta["feature_options"]["band"] == 0.03

    def test_channels_are_the_default_set_with_their_units(self, trained, sensors,
                                                           small_dataset,
                                                           power_over_floor_db):
        over = power_over_floor_db(small_dataset)            # from the waveforms
        shaft = [s for s in sensors if not s["point"].startswith("casing")
                 and over[s["name"]] >= NOISE_MARGIN_DB]
        assert 0 < len(shaft) < len(sensors) - 1             # the casing, the quiet probes
        assert trained[0].meta["channels"] == [
            {k: s[k] for k in ("name", "unit", "quantity", "point", "direction")}
            for s in shaft]

    def test_speed_and_feature_ranges_bound_the_training_rows(self, trained, small_rows):
        model, _ = trained
        meta = model.meta
        speed = small_rows["speed_rpm"]
        assert meta["speed_range_rpm"] == [speed.min(), speed.max()]
        step = model.pipeline.named_steps["features"]
        Z = step.transform(small_rows)
        names = list(step.get_feature_names_out())
        assert list(meta["feature_ranges"]) == names
        bounds = np.array([meta["feature_ranges"][n] for n in names])
        assert (Z >= bounds[:, 0]).all() and (Z <= bounds[:, 1]).all()
        # each bound is reached by a training row (not a looser or a raw-column range)
        assert np.isclose(Z, bounds[:, 0]).any(axis=0).all()
        assert np.isclose(Z, bounds[:, 1]).any(axis=0).all()

    def test_highest_order_and_the_sampling_rate_it_needs(self, trained, small_rows):
        top = trained[0].meta["highest_order"]
        # the default features use the broadband level around 8x: 8x +- 0.25x
        assert (top["order"], top["reach"]) == (8.0, 8.25)
        assert order_reach(top["feature"]) == (8.0, 8.25)
        need = top["fs_required_hz"]
        f1 = small_rows["speed_rpm"].max() / 60.0
        assert 2 * 8.25 * f1 < need < 1.05 * 2 * 8.25 * f1
        # the physics of it: at the fastest training speed, a 0.5-s window sampled just
        # above that rate measures every 8x feature, and 5 % below it does not
        for fs, measured in ((1.005 * need, True), (0.95 * need, False)):
            t = np.arange(round(0.5 * fs)) / fs
            x = np.cos(2 * np.pi * f1 * t) + 1e-3 * np.random.default_rng(0).standard_normal(
                t.size)
            row = signal_features(x, fs, speed_rpm=60 * f1).iloc[0]
            assert np.isfinite(row[["amp_8x", "bb_8x_rms", "sb_8x_lower"]].astype(float)
                               ).all() == measured


def test_a_fresh_process_predicts_identically(trained, small_dataset, small_rows):
    model, out = trained
    here = model.pipeline.predict_proba(small_rows)     # the pipeline train fitted
    code = ("import json, sys; from rubdiag.learn import read_dataset; "
            "from rubdiag.learn._persist import load_model; "
            "m = load_model(sys.argv[1]); "
            "print(json.dumps(m.pipeline.predict_proba(read_dataset(sys.argv[2])).tolist()))")
    result = subprocess.run([sys.executable, "-c", code, str(out), str(small_dataset)],
                            capture_output=True, text=True, check=True)
    there = np.array(json.loads(result.stdout))
    assert there.shape == (24, 3)
    assert np.array_equal(here, there)                   # exactly: JSON floats round-trip


class TestWriting:
    @pytest.fixture()
    def quick(self, monkeypatch, trained):
        """train() with its evaluation taken from the fixture (the writing is tested)."""
        import importlib

        # the module, not the function rubdiag.learn exports under the same name
        module = importlib.import_module("rubdiag.learn._train")

        evaluation = {}

        def cross_validate(data, target, *args, **kwargs):
            from rubdiag.learn._evaluate import cross_validate as real

            if target not in evaluation:
                evaluation[target] = real(data, target, *args, importances=False,
                                          baselines=False, audit=False, n_bootstrap=10,
                                          n_null=10, **{k: v for k, v in kwargs.items()
                                                        if k in ("channels", "families",
                                                                 "seed")})
            return evaluation[target]

        monkeypatch.setattr(module, "cross_validate", cross_validate)
        return lambda dataset, out, **kw: module.train(dataset, out, estimator="logreg", **kw)

    def test_refuses_a_folder_that_is_not_a_model(self, small_dataset, tmp_path):
        (tmp_path / "notes").mkdir()
        (tmp_path / "notes" / "mine.txt").write_text("keep\n")
        (tmp_path / "file").write_text("a file\n")
        with pytest.raises(ValueError, match="is not empty and holds no model"):
            train(small_dataset, tmp_path / "notes")
        with pytest.raises(ValueError, match="is a file"):
            train(small_dataset, tmp_path / "file")
        assert [p.name for p in (tmp_path / "notes").iterdir()] == ["mine.txt"]

    def test_overwrite_replaces_the_whole_model(self, quick, small_dataset, trained,
                                                tmp_path):
        import shutil

        out = shutil.copytree(trained[1], tmp_path / "model")
        with pytest.raises(ValueError, match="holds a model already"):
            quick(small_dataset, out, target="rub")
        model = quick(small_dataset, out, target="rub", overwrite=True)
        assert json.loads((out / META_FILE).read_text())["target"] == "rub"
        assert model.meta["classes"] == ["False", "True"]
        # no file of the old model survives (this evaluation computed no importances)
        assert not (out / "importances.csv").exists()
        assert sorted(p.name for p in tmp_path.iterdir()) == ["model"]

    def test_a_crash_leaves_no_half_model(self, quick, small_dataset, trained, tmp_path,
                                          monkeypatch):
        import shutil

        import rubdiag.learn._figures as figures

        def broken(*args, **kwargs):
            raise RuntimeError("disk full")

        monkeypatch.setattr(figures, "confusion_figure", broken)
        with pytest.raises(RuntimeError, match="disk full"):
            quick(small_dataset, tmp_path / "new")
        assert list(tmp_path.iterdir()) == []
        old = shutil.copytree(trained[1], tmp_path / "old")
        before = {p.name: p.read_bytes() for p in old.iterdir()}
        with pytest.raises(RuntimeError, match="disk full"):
            quick(small_dataset, old, target="rub", overwrite=True)
        assert {p.name: p.read_bytes() for p in old.iterdir()} == before
        assert [p.name for p in tmp_path.iterdir()] == ["old"]
        assert load_model(old).meta["target"] == "severity"


class TestEvaluateModel:
    def test_scores_on_a_dataset(self, trained, small_rows):
        model, out = trained
        result = evaluate(out, small_rows)
        y = small_rows["severity"].astype(str).to_numpy()
        predicted = model.pipeline.predict(small_rows)
        assert result.n_scored == result.n_rows == 24 and result.unknown == {}
        assert result.scores["macro_f1"].value == pytest.approx(
            f1_score(y, predicted, average="macro"))
        assert result.scores["balanced_accuracy"].value == pytest.approx(
            balanced_accuracy_score(y, predicted))
        assert result.confusion.to_numpy().sum() == 24
        assert result.per_class["support"].to_dict() == small_rows[
            "severity"].value_counts().to_dict()
        assert json.loads(json.dumps(result.to_dict()))["n_rows"] == 24

    def test_a_class_the_model_does_not_know_is_reported_not_scored(self, trained,
                                                                      small_rows):
        model, _ = trained
        data = small_rows.copy()
        data.loc[:3, "severity"] = "extreme"
        assert data.attrs == small_rows.attrs
        result = evaluate(model, data)
        assert result.unknown == {"extreme": 4}
        assert result.n_scored == 20
        known = np.arange(24) >= 4
        y = data["severity"].astype(str).to_numpy()[known]
        predicted = model.pipeline.predict(data)[known]
        assert result.scores["macro_f1"].value == pytest.approx(
            f1_score(y, predicted, average="macro", labels=sorted(set(y))))
        assert result.confusion.to_numpy().sum() == 20
        assert not result.predictions["scored"][:4].any()

    def test_refuses_other_units_or_missing_channels(self, trained, small_rows):
        import copy

        model, _ = trained
        data = small_rows.copy()
        data.attrs = copy.deepcopy(small_rows.attrs)
        sensor = next(s for s in data.attrs["acquisition"]["sensors"]
                      if s["name"] == model.channels[0])
        sensor["unit"] = "mm"
        with pytest.raises(ValueError, match=f"'{model.channels[0]}' is in mm, the model's "
                           "in m"):
            evaluate(model, data)
        dropped = small_rows.drop(columns=[c for c in small_rows.columns
                                           if c.startswith("shaft11_y_disp__")])
        with pytest.raises(ValueError, match="channel 'shaft11_y_disp' is missing"):
            evaluate(model, dropped)
