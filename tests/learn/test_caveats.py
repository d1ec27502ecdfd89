"""A model that learnt nothing says so: train's warnings (rules, a real degenerate model,
labels independent of the features against a control), the training runs in model.json
and evaluate's in-sample note."""

from __future__ import annotations

import hashlib
import json
import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.dataset import load_waveforms
from rubdiag.learn import cross_validate
from rubdiag.learn._caveats import MIN_RUNS_PER_CLASS, training_warnings
from rubdiag.learn._columns import LINE_FEATURES
from rubdiag.learn._metrics import Score
from rubdiag.learn._train import evaluate, train

NAN = math.nan


def run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# --- the rules, on evaluations made by hand ----------------------------------------------


def made(counts, recall=None, support=None, f1=0.9, baselines=None, null_hi=None):
    classes = list(counts)
    recall = recall or dict.fromkeys(classes, 0.9)
    support = support or counts
    return SimpleNamespace(
        class_counts=counts,
        per_class=pd.DataFrame({"recall": [recall[c] for c in classes],
                                "support": [support[c] for c in classes]},
                               index=pd.Index(classes, name="class")),
        scores={"macro_f1": Score(f1, NAN, NAN)},
        baselines=None if baselines is None else pd.DataFrame(
            {"macro_f1": [Score(v, NAN, NAN) for v in baselines.values()]},
            index=pd.Index(list(baselines), name="baseline")),
        shuffled=None if null_hi is None else {"null_hi": null_hi})


def test_the_minimum_is_stated():
    assert MIN_RUNS_PER_CLASS == 10


def test_a_sound_evaluation_has_no_warning():
    assert training_warnings(made({"a": 10, "b": 40}, baselines={"x": 0.7, "y": 0.89},
                                  null_hi=0.6)) == []


def test_too_few_runs_of_a_class():
    (w,) = training_warnings(made({"a": 9, "b": 10}))
    assert w.startswith("class a has 9 runs, fewer than the 10")


def test_a_class_never_recognised():
    (w,) = training_warnings(made({"a": 20, "b": 20, "c": 20},
                                  recall={"a": 0.0, "b": 0.5, "c": 0.0},
                                  support={"a": 20, "b": 20, "c": 0}))   # c: none scored
    assert w == "class a: held-out recall 0 (none of its 20 scored runs was recognised)"


def test_no_margin_over_the_best_baseline():
    ev = made({"a": 20, "b": 20}, f1=0.8, baselines={"speed only": 0.5,
                                                     "design factors only": 0.8})
    (w,) = training_warnings(ev)
    assert w.startswith("held-out macro-F1 0.800 is no higher than the best baseline's "
                        "(design factors only: 0.800)")
    ev = made({"a": 20, "b": 20}, f1=0.801, baselines={"design factors only": 0.8})
    assert training_warnings(ev) == []
    # a baseline that could not be scored is not a bar
    assert training_warnings(made({"a": 20, "b": 20}, f1=0.2, baselines={"x": NAN})) == []


def test_a_shuffled_label_control_above_chance():
    ev = made({"a": 20, "b": 20}, f1=0.9, null_hi=0.6)
    ev.shuffled.update(inside=False, n_outside=3, n_shuffles=5, allowed_outside=1)
    (w,) = training_warnings(ev)
    assert w.startswith("the shuffled-label control scored above chance: 3 of 5 shuffles "
                        "outside their null interval (chance allows 1); look for a leak")
    ev.shuffled.update(inside=True, n_outside=1)
    assert training_warnings(ev) == []


def test_within_chance():
    (w,) = training_warnings(made({"a": 20, "b": 20}, f1=0.55, null_hi=0.55))
    assert w.startswith("held-out macro-F1 0.550 is within chance (the shuffled-label "
                        "control's null interval reaches 0.550)")
    assert training_warnings(made({"a": 20, "b": 20}, f1=0.56, null_hi=0.55)) == []


# --- labels the features tell, and labels independent of them ---------------------------

CHANNELS = ["shaft11_y_disp", "shaft11_z_disp"]


def rows(informative: bool, n_points: int = 24, seed: int = 3) -> pd.DataFrame:
    """Two replicates per design point, half the points rubbing; a few lines of every
    channel are noise (the rest absent). ``informative``: the ½× line of one channel grows
    with rub, else it is noise too. The speed, the 1× levels and the design factor carry
    nothing of rub either way."""
    rng = np.random.default_rng(seed)
    rub = np.repeat(np.arange(n_points) % 2 == 1, 2)
    n = rub.size
    cols = {"run_id": [f"{i:016x}" for i in range(n)],
            "point_id": np.repeat(np.arange(n_points), 2), "speed_rpm": np.full(n, 3000.0),
            "gap_mm": np.repeat(rng.uniform(0.5, 2.0, n_points), 2), "rub": rub}
    for c in CHANNELS:
        for f in LINE_FEATURES:
            cols[f"{c}__{f}"] = np.zeros(n)
        for f in ("amp_0p5x", "amp_1p5x", "amp_2x", "sb_2x_upper", "bb_2x_rms"):
            cols[f"{c}__{f}"] = rng.random(n)
        cols[f"{c}__amp_1x"] = np.full(n, 20.0)
        cols[f"{c}__rms"] = np.full(n, 20.0)
    if informative:
        cols["shaft11_y_disp__amp_0p5x"] = 1.0 + 2.0 * rub + rng.normal(0.0, 0.3, n)
    data = pd.DataFrame(cols)
    data.attrs["factors"] = ["gap_mm"]
    return data


def quick_evaluation(data):
    return cross_validate(data, "rub", estimator="logreg", channels=CHANNELS, n_bootstrap=100,
                    n_null=200, importances=False, audit=False)


def test_labels_the_features_tell_give_no_warning():
    ev = quick_evaluation(rows(informative=True))
    assert ev.scores["macro_f1"].value > 0.9            # the ½× line tells rub apart
    assert ev.warnings == []


def test_labels_independent_of_the_features_are_warned_of():
    ev = quick_evaluation(rows(informative=False))
    f1 = ev.scores["macro_f1"].value
    assert f1 <= ev.shuffled["null_hi"]                 # this model learnt nothing
    assert f"held-out macro-F1 {f1:.3f} is within chance" in " ".join(ev.warnings)
    assert ev.to_dict()["warnings"] == ev.warnings
    report = ev.to_markdown()
    assert "## Warnings: the model may have learnt little" in report
    assert report.index("## Warnings") < report.index("## Held-out scores")
    assert all(f"- {w}" in report for w in ev.warnings)


# --- a real degenerate model: 3 rubbing runs of 15 ---------------------------------------


@pytest.fixture(scope="module")
def few(small_rows):
    """The small dataset's 12 runs without rub and its first 3 rubbing ones."""
    rub = small_rows["rub"].astype(bool)
    keep = ~rub | (rub.cumsum() <= 3)
    data = small_rows[keep.to_numpy()].reset_index(drop=True)
    data.attrs = small_rows.attrs
    assert data["rub"].sum() == 3 and len(data) == 15
    return data


@pytest.fixture(scope="module")
def degenerate(few, tmp_path_factory, monkeypatch_module):
    """The default model (rf, importances and baselines; audit off, one shuffle to keep
    it short) trained on ``few``; the importance figure train drew."""
    import rubdiag.learn._figures as figures

    drawn = {}
    real = figures.importances_figure

    def keep(*args, **kwargs):
        drawn["figure"] = real(*args, **kwargs)
        return drawn["figure"]

    monkeypatch_module.setattr(figures, "importances_figure", keep)
    out = tmp_path_factory.mktemp("degenerate") / "model"
    model = train(few, out, audit=False, n_shuffles=1)
    return model, out, drawn["figure"]


@pytest.fixture(scope="module")
def monkeypatch_module():
    with pytest.MonkeyPatch.context() as mp:
        yield mp


def test_the_degenerate_model_is_warned_of_everywhere(degenerate):
    model, out, _ = degenerate
    metrics = json.loads((out / "metrics.json").read_text())
    # it calls every held-out run "no rub": 12 right, 3 rubbing missed
    assert metrics["confusion"]["counts"] == [[12, 0], [3, 0]]
    f1 = (2 * 12 / (12 + 15) + 0.0) / 2                  # F1 of False, F1 of True = 0
    assert metrics["scores"]["macro_f1"]["value"] == pytest.approx(f1)
    assert round(f1, 3) == 0.444
    expected = [f"class True has 3 runs, fewer than the {MIN_RUNS_PER_CLASS}",
                "class True: held-out recall 0 (none of its 3 scored runs was recognised)"]
    for where in (metrics["warnings"], model.meta["warnings"],
                  json.loads((out / "model.json").read_text())["warnings"]):
        assert all(any(w.startswith(e) for w in where) for e in expected)
    report = (out / "report.md").read_text()
    assert all(e in report for e in expected)


def test_its_importances_are_zero_and_the_figure_says_why(degenerate):
    _, out, fig = degenerate
    importances = pd.read_csv(out / "importances.csv")
    assert (importances[["importance", "std"]].to_numpy() == 0).all()
    for ax in fig.axes:                                  # features, channels
        (text,) = [" ".join(t.get_text().split()) for t in ax.texts]     # lines unwrapped
        assert text.startswith("No bars: every importance is 0.")
        assert "the model predicts False for every held-out run" in text
        assert not ax.patches and not ax.get_yticks().size   # no bar, no row of 0


def test_predict_and_evaluate_repeat_the_warnings(degenerate, few, small_dataset, tmp_path,
                                                  capsys):
    model, out, _ = degenerate
    run_id = few.loc[few["rub"].astype(bool), "run_id"].iloc[0]
    waves = load_waveforms(small_dataset, run_id)
    waves[waves.index >= waves.attrs["discard_s"] - 1e-9].iloc[:5000][model.channels] \
        .reset_index().to_csv(tmp_path / "rubbing.csv", index=False)
    code, text, err = run(["predict", out, tmp_path / "rubbing.csv"], capsys)
    assert code == 0
    warned = [ln for ln in err.splitlines() if "(from its training" in ln]
    # each once; the small class's count was told at training, not at every prediction
    assert len(warned) == len(model.meta["warnings"]) - 1 >= 2
    assert any("class True: held-out recall 0" in ln for ln in warned)
    assert not any("class True has 3 runs" in ln for ln in warned)
    assert all(ln.startswith(f"rubdiag predict: warning: model {out}") for ln in warned)
    code, text, err = run(["evaluate", out, small_dataset], capsys)
    assert code == 0
    assert "class True: held-out recall 0" in err and "class True has 3 runs" in err
    first = text.splitlines()[0]
    assert "in-sample: 15 of these 24 runs were in the model's training set" in first


def test_a_bad_input_to_predict_is_one_line_despite_the_warnings(degenerate, tmp_path,
                                                                  capsys):
    """The model's warnings go with a prediction: an input that cannot be predicted is the
    error's line alone (exit 2)."""
    model, out, _ = degenerate
    assert len(model.meta["warnings"]) >= 2                     # the premise: it warns
    for args in ([tmp_path / "missing.csv"], [tmp_path / "x.csv", "--unit", "shaft11_y_disp"]):
        code, text, err = run(["predict", out, *args], capsys)
        assert code == 2 and text == ""
        assert err.count("\n") == 1 and err.startswith("rubdiag predict: error: ")


# --- the training runs and the in-sample note --------------------------------------------


@pytest.fixture(scope="module")
def half(small_rows, tmp_path_factory):
    """A model trained (evaluation kept short) on the first half of the design points."""
    points = sorted(small_rows["point_id"].unique())
    first = small_rows["point_id"].isin(points[:len(points) // 2]).to_numpy()
    data = small_rows[first].reset_index(drop=True)
    data.attrs = small_rows.attrs
    out = tmp_path_factory.mktemp("half") / "model"
    train(data, out, estimator="logreg", importances=False, baselines=False, audit=False,
          n_shuffles=1, n_bootstrap=0)
    rest = small_rows[~first].reset_index(drop=True)
    rest.attrs = small_rows.attrs
    return out, data, rest


def test_model_json_records_the_training_runs(half):
    out, data, _ = half
    record = json.loads((out / "model.json").read_text())["training_runs"]
    ids = sorted(data["run_id"])
    assert record["n"] == len(ids) == 12
    assert record["ids"] == ids
    assert record["sha256"] == hashlib.sha256("\n".join(ids).encode()).hexdigest()


def test_in_sample_out_of_sample_and_unknown(half, small_rows, tmp_path):
    out, _, rest = half
    inside = evaluate(out, small_rows, n_bootstrap=10)
    assert inside.shared_runs == 12
    assert inside.to_text().splitlines()[0].endswith(
        "; in-sample: 12 of these 24 runs were in the model's training set, so these scores "
        "flatter it")
    outside = evaluate(out, rest, n_bootstrap=10)
    assert outside.shared_runs == 0
    assert "out of sample: no run was in the model's training set" in \
        outside.to_text().splitlines()[0]
    assert outside.to_dict()["shared_runs"] == 0
    # a model saved before model.json recorded its training runs
    import shutil

    old = shutil.copytree(out, tmp_path / "old")
    meta = json.loads((old / "model.json").read_text())
    del meta["training_runs"]
    (old / "model.json").write_text(json.dumps(meta))
    unknown = evaluate(old, small_rows, n_bootstrap=10)
    assert unknown.shared_runs is None
    assert "training runs unknown" in unknown.to_text().splitlines()[0]
    assert unknown.to_dict()["sample"].startswith("training runs unknown")


def test_evaluate_s_first_line(half, small_dataset, tiny_dataset, capsys):
    out, _, _ = half
    code, text, _ = run(["evaluate", out, small_dataset], capsys)
    assert code == 0 and "in-sample: 12 of these 24 runs" in text.splitlines()[0]
    code, text, _ = run(["evaluate", out, tiny_dataset], capsys)     # other runs entirely
    assert code == 0 and "out of sample" in text.splitlines()[0]
    code, text, _ = run(["evaluate", out, small_dataset, "--json"], capsys)
    assert json.loads(text)["shared_runs"] == 12


def test_a_training_record_that_does_not_match_its_digest_is_unknown(half, small_rows,
                                                                       tmp_path):
    """model.json edited or damaged (ids no longer those the SHA-256 names): the runs are
    unknown, not "out of sample" (a string of ids was read character by character)."""
    import shutil

    out, _, _ = half
    for damage in ({"ids": "".join(small_rows["run_id"])},          # a string, not a list
                   {"ids": sorted(small_rows["run_id"])[12:]}):     # other ids, old digest
        edited = shutil.copytree(out, tmp_path / f"m{len(list(tmp_path.iterdir()))}")
        meta = json.loads((edited / "model.json").read_text())
        meta["training_runs"].update(damage)
        (edited / "model.json").write_text(json.dumps(meta))
        scores = evaluate(edited, small_rows, n_bootstrap=10)
        assert scores.shared_runs is None
        assert scores.to_text().splitlines()[0].split("; ")[1].startswith(
            "training runs unknown")
