"""cross_validate(): held-out scores where the answer is known, the shuffled-label control, the
unscored classes, the baselines, the audit and the reports.

Synthetic frames first (rows built here, feature values set by hand), then the small
simulated dataset of ``conftest.py``: every test that uses it is in this file, so that it
is generated once per test process.
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pandas as pd
import pytest
from sklearn.model_selection import KFold
from threadpoolctl import threadpool_limits

from rubdiag.learn import audit_columns, cross_validate, folds, make_pipeline
from rubdiag.learn._controls import allowed_outside
from rubdiag.learn._evaluate import target_values
from rubdiag.learn._metrics import null_interval
from rubdiag.learn._splits import Fold
from rubdiag.signal._orders import HARMONICS
from rubdiag.signal._table import still_features

# the module (rubdiag.learn._evaluate is the function, re-exported by the package)
evaluate_module = sys.modules["rubdiag.learn._evaluate"]
# Small settings: the tests compare scores with intervals far apart, not interval ends.
FAST = {"n_bootstrap": 200, "n_null": 200}
# The part of evaluate under test, without the costly extras.
BARE = {"importances": False, "baselines": False, "audit": False, **FAST}


@pytest.fixture(autouse=True, scope="module")
def one_thread():
    """One BLAS/OpenMP thread: the machine's two cores are shared."""
    with threadpool_limits(1):
        yield


def synthetic_rows(n_points, replicates=2, seed=0, rel_noise=1e-3):
    """Rows of a dataset without a simulator: design points with random factors and
    speeds; two channels (``shaft``, ``casing``) whose spectra hold a 1×, a 2× and a
    1.5× line and broadband around the harmonics, every other line absent (amplitude 0,
    location NaN, as a feature table writes it). Values are drawn per design point; its
    replicates are copies within ``rel_noise`` (near-copies, as simulated replicates are).

    ``d`` (returned, per row) is how far the shaft's 1.5× line sits from 1.5×, in orders:
    its ``dev_1p5x``, and no other column says it (its frequency in Hz is mixed with the
    speed)."""
    rng = np.random.default_rng(seed)
    case = rng.integers(1, 3, n_points)
    points = pd.DataFrame({"point_id": [f"p{i:03d}" for i in range(n_points)],
                           "case": case, "speed_ratio": rng.uniform(0.5, 1.5, n_points),
                           "gap_mm": rng.uniform(0.5, 3.5, n_points)})
    points["speed_rpm"] = points["speed_ratio"] * np.where(case == 1, 1500.0, 5700.0)
    f1 = points["speed_rpm"].to_numpy() / 60.0
    d = rng.uniform(-0.03, 0.03, n_points)
    base = still_features()
    features = {}
    for channel in ("shaft", "casing"):
        rms = rng.uniform(0.5, 2.0, n_points)
        cols = {name: np.full(n_points, value) for name, value in base.items()}
        cols["rms"] = rms
        cols["amp_1x"] = rms * rng.uniform(0.5, 0.9, n_points)
        cols["freq_1x_hz"] = f1 * (1.0 + rng.normal(0.0, 1e-3, n_points))
        cols["amp_2x"] = rms * rng.uniform(0.0, 0.3, n_points)
        cols["freq_2x_hz"] = 2.0 * f1 * (1.0 + rng.normal(0.0, 1e-3, n_points))
        cols["amp_1p5x"] = rms * rng.uniform(0.02, 0.1, n_points)
        cols["freq_1p5x_hz"] = (1.5 + (d if channel == "shaft"
                                       else rng.uniform(-0.03, 0.03, n_points))) * f1
        cols["n_half_orders"] = np.ones(n_points)
        for n in HARMONICS:
            cols[f"bb_{n}x_rms"] = rms * rng.uniform(0.0, 0.05, n_points)
        features.update({f"{channel}__{name}": v for name, v in cols.items()})
    # replicates: copies of their point, jittered (locations NaN stay NaN, counts exact)
    at = np.repeat(np.arange(n_points), replicates)
    values = pd.DataFrame(features).iloc[at].reset_index(drop=True)
    jitter = [c for c in values.columns if not c.endswith("_orders")]
    values[jitter] *= 1.0 + rel_noise * rng.standard_normal((len(values), len(jitter)))
    ids = pd.DataFrame({"run_id": [f"r{i:04d}" for i in range(len(at))],
                        "replicate": np.tile(np.arange(replicates), n_points)})
    rows = pd.concat([ids, points.iloc[at].reset_index(drop=True), values], axis=1)
    order = ["run_id", "point_id", *rows.columns.drop(["run_id", "point_id"])]
    return rows[order].copy(), d[at]          # one block per dtype: no fragmentation


def keep_margin(rows, d, margin=0.006):
    """The rows whose 1.5× line is more than ``margin`` orders from 1.5×."""
    keep = np.abs(d) > margin
    return rows[keep].reset_index(drop=True), d[keep]


def row_level_folds(data, split="group", y=None, *, n_splits=5, bands=5, seed=0):
    """A leaking split: rows, not design points, to the folds (replicates on both sides)."""
    splitter = KFold(n_splits, shuffle=True, random_state=seed)
    return [Fold(f"rows {i}", train, test)
            for i, (train, test) in enumerate(splitter.split(np.arange(len(data))))]


def scored(ev, data):
    """Truth, prediction and design point of the scored rows."""
    s = ev.predictions["scored"].to_numpy()
    p = ev.predictions[s]
    return p["true"].to_numpy(), p["predicted"].to_numpy(), data["point_id"].to_numpy()[s]


@pytest.fixture(scope="module")
def learnable():
    """Rub is the sign of the shaft's dev_1p5x alone: the classes lie 0.012 orders apart,
    eight standard deviations of the shift the replicates' jitter gives the line (1e-3
    relative of 1.5×: 1.5e-3 orders)."""
    rows, d = keep_margin(*synthetic_rows(60, seed=1))
    return rows.assign(rub=d > 0.0)


@pytest.fixture(scope="module")
def learnable_evaluation(learnable):
    return cross_validate(learnable, "rub", estimator="logreg", n_repeats=2, **FAST)


class TestKnownAnswers:
    def test_a_function_of_one_order_feature_scores_one(self, learnable_evaluation):
        ev = learnable_evaluation
        # any threshold inside the margin classifies every row; allow one design point
        # (2 of ~90 rows) on the wrong side: macro-F1 >= 0.95
        assert ev.scores["macro_f1"].value >= 0.95
        assert ev.scores["balanced_accuracy"].value >= 0.95
        assert ev.unscored == {}
        assert int(ev.confusion.to_numpy().sum()) == ev.n_rows
        assert (ev.per_class["recall"] >= 0.9).all()

    def test_importances_name_the_feature(self, learnable_evaluation):
        ev = learnable_evaluation
        assert ev.importances.index[0] == "dev_1p5x"
        assert ev.channel_importances.index[0] == "shaft"
        # what permuting dev_1p5x costs: most of the score (2 classes, chance ≈ 1/2)
        assert ev.importances["importance"].iloc[0] > 0.3

    def test_baselines_do_not_find_it(self, learnable_evaluation):
        ev = learnable_evaluation
        assert list(ev.baselines.index) == ["1x level only", "speed only",
                                            "design factors only"]
        assert ev.baselines.loc["speed only", "columns"] == "speed_rpm"
        assert ev.baselines.loc["1x level only", "columns"] == "shaft__amp_1x"
        for s in ev.baselines["macro_f1"]:
            assert s.hi < ev.scores["macro_f1"].value

    def test_audit_flags_the_feature_only(self, learnable_evaluation):
        audit = learnable_evaluation.audit
        assert "shaft__dev_1p5x" in set(audit["column"])
        # its frequency in Hz is mixed with the speed; the casing's 1.5× is unrelated
        assert "shaft__freq_1p5x_hz" not in set(audit["column"])
        assert not audit["column"].str.startswith("casing__").any()
        assert (audit["kind"] == "feature").all()

    def test_shuffled_labels_score_chance(self, learnable_evaluation):
        s = learnable_evaluation.shuffled
        assert len(s["shuffles"]) == s["n_shuffles"] == 5
        assert s["n_outside"] == sum(not r["inside"] for r in s["shuffles"])
        assert s["inside"] and s["n_outside"] <= s["allowed_outside"] == 1

    def test_casing_with_and_without(self, learnable_evaluation):
        ev = learnable_evaluation
        assert ev.channels == ["shaft"]      # "casing…" is a casing channel by its name
        assert ev.casing["without"] == ev.scores["macro_f1"]
        # the same model with the casing channel too (its features are noise here)
        assert ev.casing["with"] != ev.casing["without"]
        assert ev.casing["with"].value < ev.casing["without"].value

    def test_absolute_frequencies_are_opt_in(self, learnable):
        # the same target from the speed: only the absolute family (speed_rpm) has it
        fast = learnable.assign(rub=learnable["speed_rpm"] > 3000.0)
        default = cross_validate(fast, "rub", estimator="logreg", **BARE)
        absolute = cross_validate(fast, "rub", estimator="logreg", families=("orders", "absolute"),
                            **BARE)
        assert absolute.scores["macro_f1"].value >= 0.95
        assert default.scores["macro_f1"].value < absolute.scores["macro_f1"].lo


@pytest.fixture(scope="module")
def independent():
    """A rub label drawn per design point, independent of every column; replicates are
    near-copies with one label: a model that sees a replicate of a test point in
    training recognises it."""
    rows, _ = synthetic_rows(40, seed=2)
    point_label = np.random.default_rng(3).random(40) < 0.5
    rows["rub"] = np.repeat(point_label, 2)
    return rows


# A random forest remembers near-copies, the sharpest test of a leak; fewer trees than
# make_pipeline's 300, for time.
def forest():
    return make_pipeline("rf", channels=["shaft", "casing"]).set_params(
        model__n_estimators=60)


class TestChance:
    def test_an_independent_target_scores_inside_its_null(self, independent):
        ev = cross_validate(independent, "rub", pipeline=forest(), **BARE)
        y, p, groups = scored(ev, independent)
        lo, hi = null_interval(y, p, ev.classes, n=1000, groups=groups)
        # a 95 % interval: a sound evaluation falls outside for 1 seed in 20; these seeds
        # are fixed, so the test is deterministic
        assert lo <= ev.scores["macro_f1"].value <= hi
        assert ev.shuffled["inside"]

    def test_a_leaking_split_scores_outside(self, independent, monkeypatch):
        # The control of the test above: with replicates on both sides the same model and
        # data score far above chance, and the shuffled-label control sees it.
        monkeypatch.setattr(evaluate_module, "folds", row_level_folds)
        ev = cross_validate(independent, "rub", pipeline=forest(), **BARE)
        y, p, groups = scored(ev, independent)
        hi = null_interval(y, p, ev.classes, n=1000, groups=groups)[1]
        assert ev.scores["macro_f1"].value > hi + 0.1
        assert not ev.shuffled["inside"]
        assert ev.shuffled["n_outside"] == ev.shuffled["n_shuffles"]       # every one
        assert ev.shuffled["macro_f1"] > ev.shuffled["null_hi"]
        # said as a warning, the one the report gives (not a verdict of its own)
        (leak,) = [w for w in ev.warnings if "look for a leak" in w]
        assert leak.startswith(f"the shuffled-label control scored above chance: "
                               f"{ev.shuffled['n_shuffles']} of {ev.shuffled['n_shuffles']} "
                               "shuffles outside their null interval (chance allows 1)")
        report = ev.to_markdown()
        assert report.count("look for a leak") == 1 and f"- {leak}" in report


def test_a_class_absent_from_training_is_not_scored():
    # "serious" exists only in the highest gap band: held out, it has no training rows
    rows, d = keep_margin(*synthetic_rows(50, seed=4))
    gap = rows["gap_mm"].to_numpy()
    top_band = gap > np.quantile(rows.drop_duplicates("point_id")["gap_mm"], 0.8)
    rows["severity"] = np.where(top_band, "serious", np.where(d < 0, "none", "light"))
    ev = cross_validate(rows, "severity", "gap_mm", estimator="logreg", bands=5, **BARE)
    held_out = [f for f in folds(rows, "gap_mm", bands=5) if top_band[f.test].all()]
    assert len(held_out) == 1 and top_band[held_out[0].test].sum() == top_band.sum()
    assert ev.unscored == {"serious": int(top_band.sum())}
    assert not ev.predictions["scored"][top_band].any()
    assert (ev.predictions["predicted"][top_band] == "").all()
    assert int(ev.confusion.to_numpy().sum()) == len(rows) - top_band.sum()
    assert ev.confusion.loc["serious"].sum() == 0
    assert ev.per_class.loc["serious", "support"] == 0
    assert "Not scored" in ev.to_markdown() and "serious" in ev.to_markdown()


def test_families_given_as_one_name(learnable):
    ev = cross_validate(learnable, "rub", estimator="logreg", families="orders", **BARE)
    assert ev.families == ["orders"]
    assert ev.scores["macro_f1"].value >= 0.95


def test_reports_are_json_and_markdown(learnable_evaluation, learnable):
    ev = learnable_evaluation
    d = json.loads(json.dumps(ev.to_dict(), allow_nan=False))
    assert d["scores"]["macro_f1"] == pytest.approx(ev.scores["macro_f1"].to_dict())
    assert d["confusion"]["counts"] == ev.confusion.to_numpy().tolist()
    assert d["baselines"][1]["macro_f1"]["value"] == ev.baselines["macro_f1"].iloc[1].value
    assert d["audit"][0]["column"] == ev.audit["column"].iloc[0]
    text = ev.to_markdown()
    for name, s in ev.scores.items():
        assert f"| {name} | {s} |" in text
    assert "chance, as it must be" in text and "(chance allows 1)" in text
    # without bootstrap draws the interval is unknown: null in JSON, never NaN
    bare = cross_validate(learnable, "rub", estimator="logreg", **{**BARE, "n_bootstrap": 0})
    d = json.loads(json.dumps(bare.to_dict(), allow_nan=False))
    assert d["scores"]["macro_f1"]["lo"] is None
    assert d["scores"]["macro_f1"]["value"] == bare.scores["macro_f1"].value


class TestBadInput:
    def test_target(self, learnable):
        with pytest.raises(ValueError, match="target = 'gap_mm'"):
            cross_validate(learnable, "gap_mm", **BARE)
        with pytest.raises(ValueError, match="'severity'"):
            cross_validate(learnable, "severity", **BARE)   # a label the frame does not have

    def test_one_class(self, learnable):
        with pytest.raises(ValueError, match="one value"):
            cross_validate(learnable.assign(rub=True), "rub", **BARE)

    def test_one_class_is_said_before_the_folds_complain(self, learnable):
        """Few design points and one class: the class is the problem to name, not that
        the points are too few for five folds."""
        few = learnable[learnable.point_id.isin(learnable.point_id.unique()[:3])]
        with pytest.raises(ValueError, match="takes one value in the data"):
            cross_validate(few.assign(rub=False), "rub", **BARE)

    def test_channels(self, learnable):
        with pytest.raises(ValueError, match="'blade'"):
            cross_validate(learnable, "rub", channels=["blade"], **BARE)


# -- the small simulated dataset (conftest.small_rows): 24 runs, 12 points × 2 replicates


@pytest.fixture(scope="module")
def rub_evaluation(small_rows):
    return cross_validate(small_rows, "rub", estimator="logreg", n_repeats=1, audit=False, **FAST)


def test_simulated_rub_shuffled_labels_score_chance(rub_evaluation):
    s = rub_evaluation.shuffled
    assert s["inside"] and s["n_outside"] <= s["allowed_outside"]


@pytest.mark.parametrize("n", [1, 2, 5, 8, 16, 17, 40])
def test_allowed_outside_is_the_binomial_bound(n):
    """The least k with P(more than k of n shuffles outside a 95 % interval) <= 5 %,
    summed here from the binomial terms."""
    def more_than(k):
        return sum(math.comb(n, j) * 0.05**j * 0.95 ** (n - j) for j in range(k + 1, n + 1))

    k = allowed_outside(n)
    assert more_than(k) <= 0.05 + 1e-12
    assert k == 0 or more_than(k - 1) > 0.05


def test_simulated_rub_reports(rub_evaluation, small_rows):
    ev = rub_evaluation
    # the default set: the disc probes (the bearing probes carry their noise floor alone,
    # test_channel_choice.py), never the casing
    assert ev.channels == ["shaft11_y_disp", "shaft11_z_disp"]
    assert ev.casing["without"] == ev.scores["macro_f1"]     # the model has no casing
    assert ev.casing["with"] is not None
    d = json.loads(json.dumps(ev.to_dict(), allow_nan=False))
    assert d["n_rows"] == len(small_rows) == 24
    assert sum(map(sum, d["confusion"]["counts"])) + sum(d["unscored"].values()) == 24
    text = ev.to_markdown()
    for name, s in ev.scores.items():
        assert f"| {name} | {s} |" in text
    assert "Casing channels: macro-F1 with" in text


def test_simulated_rub_audit_flags_the_casing(small_rows):
    # A channel of pure noise beside the simulated ones: the audit must not list it. The
    # casing moves only through contact in this model: one of its features alone gives
    # rub away.
    # (The shaft channels are left out for time: the audit judges every column alone.)
    rng = np.random.default_rng(5)
    noise = {f"noise__{name}": rng.uniform(0.0, 1.0, len(small_rows))
             for name in still_features()}
    data = pd.concat([small_rows, pd.DataFrame(noise, index=small_rows.index)], axis=1)
    data = data[[c for c in data.columns if not c.startswith("shaft")]]
    y = target_values(data, "rub")
    classes = sorted(set(y))
    audit = audit_columns(data, y, folds(data, "group", y), classes)
    flagged = set(audit["column"])
    assert any(c.startswith("casing1_y_acc__") for c in flagged)
    assert not any(c.startswith("noise__") for c in flagged)
    assert (audit["macro_f1"] >= 0.9).all()


def test_rows_and_scores_do_not_depend_on_the_order_runs_were_stored(small_dataset, tmp_path):
    """Workers finish in any order; a dataset whose chunks hold the same rows in reverse
    order reads as the same frame, and so evaluates to the same numbers."""
    import shutil

    import pyarrow as pa
    import pyarrow.parquet as pq

    from rubdiag.learn import read_dataset

    copy = tmp_path / "reversed"
    shutil.copytree(small_dataset, copy)
    chunks = sorted((copy / "features").glob("part-*.parquet"))
    rows = pd.concat([pq.read_table(p).to_pandas() for p in chunks], ignore_index=True)
    for p in chunks:
        p.unlink()
    schema = pq.read_schema(small_dataset / "features" / chunks[0].name)
    pq.write_table(pa.Table.from_pandas(rows.iloc[::-1], schema=schema, preserve_index=False),
                   chunks[0])
    a, b = read_dataset(small_dataset), read_dataset(copy)
    assert list(a["run_id"]) == list(b["run_id"]) != list(rows["run_id"].iloc[::-1])
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    kw = dict(importances=False, baselines=False, audit=False, n_bootstrap=50, n_null=50)
    with threadpool_limits(1):
        ea = cross_validate(a, "rub", "group", "logreg", **kw)
        eb = cross_validate(b, "rub", "group", "logreg", **kw)
    assert ea.scores == eb.scores and ea.shuffled == eb.shuffled
