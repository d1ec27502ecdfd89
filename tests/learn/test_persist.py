"""Saved models: every pipeline we make round-trips through skops, the allow-list holds
exactly what those pipelines contain, and anything else is refused in one line."""

from __future__ import annotations

import io
import json
import shutil
import zipfile

import numpy as np
import pytest
import skops.io as sio
from sklearn.neighbors import KNeighborsClassifier
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from threadpoolctl import threadpool_limits

from rubdiag.learn import ESTIMATORS, OrderFeatures, baseline_pipeline, make_pipeline
from rubdiag.learn._columns import shaft_channels
from rubdiag.learn._persist import (
    META_FILE,
    MODEL_FILE,
    TRUSTED_TYPES,
    load_meta,
    load_model,
    save_model,
)

TARGETS = ("rub", "severity")          # a two-class and a three-class target


@pytest.fixture(autouse=True, scope="module")
def one_thread():
    """hgb's OpenMP threads spin against the other processes of a shared 2-core machine."""
    with threadpool_limits(1):
        yield


def fitted_pipeline(rows, estimator, target):
    pipe = make_pipeline(estimator, channels=shaft_channels(rows))
    if estimator == "hgb":
        pipe.set_params(model__max_iter=10)      # the same types as 200 iterations
    if estimator == "rf":
        pipe.set_params(model__n_estimators=20)
    return pipe.fit(rows, rows[target].astype(str).to_numpy())


@pytest.fixture(scope="module")
def pipelines(small_rows):
    """Each estimator's pipeline fitted on each target: {(estimator, target): pipeline}."""
    return {(e, t): fitted_pipeline(small_rows, e, t) for e in ESTIMATORS for t in TARGETS}


def schema_types(data: bytes) -> set[str]:
    """Every ``module.class`` named in a skops archive's schema (read here, not by the
    code under test)."""
    found = set()

    def walk(node):
        if isinstance(node, dict):
            if "__module__" in node and "__class__" in node:
                found.add(f"{node['__module__']}.{node['__class__']}")
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(json.loads(zipfile.ZipFile(io.BytesIO(data)).read("schema.json")))
    return found


def meta_of(pipeline) -> dict:
    return {"classes": [str(c) for c in pipeline.classes_]}


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_every_pipeline_round_trips(pipelines, small_rows, tmp_path, estimator, target):
    pipe = pipelines[(estimator, target)]
    save_model(pipe, tmp_path / "m", meta_of(pipe))
    model = load_model(tmp_path / "m")
    assert type(model.pipeline.named_steps["model"]) is type(pipe.named_steps["model"])
    np.testing.assert_array_equal(model.pipeline.predict_proba(small_rows),
                                  pipe.predict_proba(small_rows))
    assert model.classes == [str(c) for c in pipe.classes_]
    assert load_meta(tmp_path / "m")["format"] == "rubdiag.model"


def test_the_allow_list_is_exactly_what_our_pipelines_hold(pipelines, small_rows):
    held = set()
    for pipe in pipelines.values():
        held |= schema_types(sio.dumps(pipe))
    baseline = baseline_pipeline(["speed_rpm"], "logreg").fit(
        small_rows, small_rows["rub"].astype(str).to_numpy())
    held |= schema_types(sio.dumps(baseline))
    assert held == set(TRUSTED_TYPES)
    assert len(TRUSTED_TYPES) == len(set(TRUSTED_TYPES))


@pytest.fixture(scope="module")
def knn_pipeline(small_rows):
    return Pipeline([("features", OrderFeatures(channels=shaft_channels(small_rows))),
                     ("scale", StandardScaler()),
                     ("model", KNeighborsClassifier(3))]).fit(
        small_rows, small_rows["rub"].astype(str).to_numpy())


def test_an_unlisted_type_is_refused(pipelines, knn_pipeline, tmp_path):
    knn = "sklearn.neighbors._classification.KNeighborsClassifier"
    data = sio.dumps(knn_pipeline)
    # skops itself trusts every scikit-learn estimator: our own list is what refuses it
    assert knn not in sio.get_untrusted_types(data=data)
    good = pipelines[("logreg", "rub")]
    folder = save_model(good, tmp_path / "m", meta_of(good))
    (folder / MODEL_FILE).write_bytes(data)          # same classes, another estimator
    with pytest.raises(ValueError) as info:
        load_model(folder)
    message = str(info.value)
    assert knn in message and str(folder / MODEL_FILE) in message
    assert "\n" not in message


def test_saving_an_unlisted_type_is_refused_and_writes_nothing(knn_pipeline, tmp_path):
    with pytest.raises(ValueError, match="KNeighborsClassifier"):
        save_model(knn_pipeline, tmp_path / "m", meta_of(knn_pipeline))
    assert not (tmp_path / "m").exists()


@pytest.fixture()
def saved(pipelines, tmp_path):
    pipe = pipelines[("logreg", "severity")]
    return save_model(pipe, tmp_path / "m", meta_of(pipe))


def damage(folder, how):
    skops_file, meta_file = folder / MODEL_FILE, folder / META_FILE
    if how == "no folder":
        shutil.rmtree(folder)
    elif how == "no model.json":
        meta_file.unlink()
    elif how == "model.json not JSON":
        meta_file.write_text("{not json")
    elif how == "foreign model.json":
        meta_file.write_text(json.dumps({"format": "someone.else", "classes": []}))
    elif how == "future format":
        meta = json.loads(meta_file.read_text())
        meta_file.write_text(json.dumps({**meta, "format_version": 99}))
    elif how == "no model.skops":
        skops_file.unlink()
    elif how == "truncated model.skops":
        data = skops_file.read_bytes()
        skops_file.write_bytes(data[: len(data) // 2])
    elif how == "zip without schema":
        sink = io.BytesIO()
        with zipfile.ZipFile(sink, "w") as z:
            z.writestr("notes.txt", "hello")
        skops_file.write_bytes(sink.getvalue())
    elif how == "other classes":
        meta = json.loads(meta_file.read_text())
        meta_file.write_text(json.dumps({**meta, "classes": ["a", "b"]}))
    return folder


@pytest.mark.parametrize(("how", "fragment"), [
    ("no folder", "no such folder"),
    ("no model.json", "not a rubdiag model folder (no model.json)"),
    ("model.json not JSON", "model.json: damaged model description"),
    ("foreign model.json", "model.json: not a rubdiag model description"),
    ("future format", "model format version 99"),
    ("no model.skops", "model.skops: no such file"),
    ("truncated model.skops", "model.skops: not a skops file"),
    ("zip without schema", "model.skops: damaged model file"),
    ("other classes", "differ from those of model.json"),
])
def test_damaged_missing_or_foreign_files_are_one_line(saved, how, fragment):
    folder = damage(saved, how)
    with pytest.raises(ValueError) as info:
        load_model(folder)
    assert fragment in str(info.value)
    assert str(folder) in str(info.value)
    assert "\n" not in str(info.value)


def test_model_json_refuses_nan(pipelines, tmp_path):
    pipe = pipelines[("logreg", "rub")]
    with pytest.raises(ValueError):
        save_model(pipe, tmp_path / "m", {**meta_of(pipe), "range": [float("nan"), 1.0]})
    assert not (tmp_path / "m").exists()
