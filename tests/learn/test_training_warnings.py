"""One list of training warnings, everywhere the same, and a design-factors baseline that is
no oracle: ``rubdiag train`` on a small design whose severity factors are blank where their
level is absent (as a fault design's rows show them), then ``rubdiag predict`` on three
files."""

from __future__ import annotations

import importlib
import json
import re

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.learn._caveats import small_class_warnings
from rubdiag.signal._table import prefixed_features

FS, WINDOW_S = 2000.0, 2.0
N = round(FS * WINDOW_S)
CHANNELS = ("probe_y", "probe_z")
SENSORS = [{"name": name, "unit": "m", "quantity": "displacement", "point": "shaft 11",
            "direction": name[-1]} for name in CHANNELS]


def signals(rpm, seed):
    """Both probes: 1× of 30–50 µm and a 2× of 3–8 µm at random, 0.5 µm of noise: nothing
    that tells rub, crack or neither apart."""
    rng = np.random.default_rng(seed)
    t = np.arange(N) / FS
    f1 = rpm / 60.0
    return {c: rng.uniform(30e-6, 50e-6) * np.cos(2 * np.pi * f1 * t + rng.uniform(0, 6))
            + rng.uniform(3e-6, 8e-6) * np.cos(4 * np.pi * f1 * t + rng.uniform(0, 6))
            + 5e-7 * rng.standard_normal(N) for c in CHANNELS}


def design_rows() -> pd.DataFrame:
    """24 design points: 8 rub, 8 crack, 8 healthy, at 1400–1600 rpm. ``gap_mm`` is blank
    where nothing rubs and ``crack_depth_ratio`` where no crack is (rubdiag's fault designs
    show them so): where they are blank tells rub; ``speed_ratio`` every run has."""
    rng = np.random.default_rng(5)
    level = np.array(["rub", "crack", "none"] * 8)
    rows = []
    for i, fault in enumerate(level):
        rpm = 1400.0 + 200.0 * rng.random()
        row = prefixed_features(signals(rpm, i), FS, rpm, separator="__")
        rows.append(row.assign(
            run_id=f"run{i:02d}", point_id=i, replicate=0, rub=fault == "rub",
            speed_ratio=rpm / 1500.0,
            gap_mm=rng.uniform(0.5, 2.0) if fault == "rub" else np.nan,
            crack_depth_ratio=rng.uniform(0.2, 0.5) if fault == "crack" else np.nan))
    data = pd.concat(rows, ignore_index=True)
    data.attrs.update(acquisition={"fs_hz": FS, "window_s": WINDOW_S, "sensors": SENSORS},
                      factors=["speed_ratio", "gap_mm", "crack_depth_ratio"])
    return data


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """``rubdiag train`` (logreg, every part of the evaluation) on :func:`design_rows`:
    (model folder, stdout, stderr)."""
    import contextlib
    import io

    data = design_rows()
    out = tmp_path_factory.mktemp("warnings") / "model"
    stdout, stderr = io.StringIO(), io.StringIO()
    with pytest.MonkeyPatch.context() as mp:     # the rows instead of a dataset folder
        mp.setattr(importlib.import_module("rubdiag.learn._train"), "read_dataset",
                   lambda _: data)
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = main(["train", "rows", "--out", str(out), "--estimator", "logreg",
                         "--channels", ",".join(CHANNELS), "--n-splits", "4", "--quiet"])
    assert code == 0, stderr.getvalue()
    return out, stdout.getvalue(), stderr.getvalue()


def test_the_design_factors_baseline_reads_no_blank_factor(trained):
    out, _, _ = trained
    metrics = json.loads((out / "metrics.json").read_text())
    baseline = {b["baseline"]: b for b in metrics["baselines"]}["design factors only"]
    assert baseline["columns"] == "speed_ratio"
    assert baseline["left_out"] == "gap_mm, crack_depth_ratio"
    # gap_mm's blanks alone would call rub perfectly; speed_ratio knows nothing of it
    assert baseline["macro_f1"]["value"] < 0.9
    assert not any("no higher than the best baseline's (design factors only: 1.000)" in w
                   for w in metrics["warnings"])
    report = (out / "report.md").read_text()
    assert ('Left out of "design factors only": gap_mm, crack_depth_ratio — blank by design'
            in report)


def test_report_metrics_model_and_train_give_the_same_warnings(trained):
    out, stdout, stderr = trained
    metrics = json.loads((out / "metrics.json").read_text())
    model = json.loads((out / "model.json").read_text())
    report = (out / "report.md").read_text()
    section = report.split("## Warnings: the model may have learnt little\n\n", 1)[1]
    in_report = [ln[2:] for ln in section.split("\n\n", 1)[0].splitlines()]
    printed = [ln.removeprefix("rubdiag train: warning: ") for ln in stderr.splitlines()]
    assert in_report == metrics["warnings"] == model["warnings"] == printed
    # 8 rubbing runs of 24: a small class; and a model that learnt nothing says more
    assert printed[:1] == small_class_warnings(metrics["class_counts"])
    assert printed[0].startswith("class True has 8 runs") and len(printed) > 1
    assert not [ln for ln in stdout.splitlines() if "warning:" in ln]     # on stderr only
    # no verdict of the report outside that list
    assert "look for a leak" not in report.replace(section.split("\n\n", 1)[0], "")


def test_predict_on_three_files_gives_each_training_warning_once(trained, tmp_path, capsys):
    out, _, _ = trained
    meta = json.loads((out / "model.json").read_text())
    files = []
    for i, rpm in enumerate((1450.0, 1500.0, 3000.0)):     # the last outside the training
        files.append(tmp_path / f"r{i}.csv")
        pd.DataFrame({"t": np.arange(N) / FS, **signals(rpm, 100 + i)}).to_csv(
            files[-1], index=False)
    assert main(["predict", str(out), *map(str, files), "--speed-rpm", "1500"]) == 0
    main(["predict", str(out), *map(str, files)])
    err = capsys.readouterr().err.splitlines()
    training = [ln for ln in err if "(from its training" in ln]
    small = set(small_class_warnings(meta["class_counts"]))
    expected = [w for w in meta["warnings"] if w not in small]
    assert expected                                  # the premise: some concern predictions
    for run in (training[:len(expected)], training[len(expected):]):    # each call
        assert [ln.split("see its report.md): ", 1)[1] for ln in run] == expected
    assert not any(w in ln for ln in err for w in small)
    # per file only what is about that file, named by it: the last one's speed at least
    about = [ln for ln in err if "(from its training" not in ln]
    named = "|".join(re.escape(str(f)) for f in files)
    assert all(re.match(rf"rubdiag predict: warning: ({named}), window 0: ", ln)
               for ln in about)
    assert (f"rubdiag predict: warning: {files[2]}, window 0: speed 3000 rpm is outside the "
            "training range") in "\n".join(about)
