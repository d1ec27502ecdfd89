"""``rubdiag train --target fault``, ``evaluate`` and ``predict`` end to end on a small
simulated dataset with a confuser (misalignment, alone and with rub), and their bad input."""

from __future__ import annotations

import contextlib
import functools
import importlib
import io
import json
import re
import tomllib
from pathlib import Path

import pytest

from rubdiag.cli import main
from rubdiag.dataset import load

TRAIN = importlib.import_module("rubdiag.learn._train")

#: The repository's small multi-fault design cut down to 24 runs of 0.8 s (about 15 s on
#: one core): healthy, rub, a misaligned coupling and both, near the critical speeds.
FAULT_DESIGN = Path(__file__).parents[2] / "data" / "designs" / "faults_small.toml"


def fault_design():
    design = tomllib.loads(FAULT_DESIGN.read_text(encoding="utf-8"))
    design["base"]["duration_s"] = 0.8
    design["sampling"]["n"] = 24
    design["factors"]["fault"] = ["none", "rub", "misalignment", "rub+misalignment"]
    for other in ("crack_depth_ratio", "looseness_preload_n"):
        del design["factors"][other]
    return design


def run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(scope="module")
def fault_dataset(tmp_path_factory):
    from rubdiag.dataset import Design, generate

    out = tmp_path_factory.mktemp("faults") / "data"
    generate(Design.from_dict(fault_design()), out, jobs=1, progress=False)
    return out


@pytest.fixture(scope="module")
def fault_model(fault_dataset, tmp_path_factory):
    """``rubdiag train DATA --target fault --quick``: (model folder, stdout)."""
    out = tmp_path_factory.mktemp("faultmodel") / "model"
    sink = io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(sink):
        # one shuffled-label control, not five: these tests read the model's files and
        # predictions (the control: tests/learn/test_evaluate.py, test_caveats.py)
        patch.setattr(TRAIN, "train", functools.partial(TRAIN.train, n_shuffles=1))
        code = main(["train", str(fault_dataset), "--target", "fault", "--out", str(out),
                     "--quick"])
    assert code == 0
    return out, sink.getvalue()


def test_train_target_fault(fault_model, fault_dataset):
    out, stdout = fault_model
    rows = load(fault_dataset)
    meta = json.loads((out / "model.json").read_text())
    assert meta["target"] == "fault"
    assert meta["classes"] == sorted(set(rows["faults"].astype(str)))
    assert stdout.startswith(f"{out}: fault classifier")
    # the held-out confuser rates: one line each, over as many runs as the dataset has
    n_misaligned = int((rows["faults"] == "misalignment").sum())
    n_healthy = int((rows["faults"] == "none").sum())
    assert n_misaligned and n_healthy
    alarm = re.search(r"false rub alarm, misalignment: \S+ \[\S+, \S+\] \((\d+) of (\d+) "
                      r"runs called rubbing\)", stdout)
    assert alarm and int(alarm[2]) <= n_misaligned
    assert "false rub alarm, crack: no run" in stdout            # not in this design
    assert [r["faults"] for r in meta["confusers"]][:2] == ["none", "misalignment"]
    report = (out / "report.md").read_text()
    assert "## Rub against the faults that look like it" in report


def test_predict_names_rub_and_the_confuser(fault_model, fault_dataset, capsys):
    out, _ = fault_model
    code, stdout, _ = run(["predict", out, fault_dataset, "--json"], capsys)
    assert code == 0
    records = json.loads(stdout)
    classes = json.loads((out / "model.json").read_text())["classes"]
    with_rub = [c for c in classes if c.startswith("rub")]
    without = [c for c in classes if not c.startswith("rub")]
    for r in records:
        assert r["p_rubbing"] == pytest.approx(sum(r[f"p_{c}"] for c in with_rub))
        assert r["confuser"] == max(without, key=lambda c: r[f"p_{c}"])
        assert r["p_predicted"] == r[f"p_{r['predicted']}"]
    code, stdout, _ = run(["predict", out, fault_dataset], capsys)
    assert code == 0
    verdicts = [ln for ln in stdout.splitlines() if re.match(r"^[0-9a-f]{16}: most likely", ln)]
    assert len(verdicts) == len(records)
    for r, line in zip(records, verdicts, strict=True):
        assert line.startswith(f"{r['input']}: most likely {r['predicted']} "
                               f"(p = {r['p_predicted']:.2f}); P(rub) = {r['p_rubbing']:.2f}")
        named = f"the most likely fault without rub is {r['confuser']}"
        assert (named in line) == (r["p_rubbing"] >= 0.5)


def test_evaluate_prints_the_confusers(fault_model, fault_dataset, capsys):
    out, _ = fault_model
    rows = load(fault_dataset)
    code, stdout, _ = run(["evaluate", out, fault_dataset], capsys)
    assert code == 0
    n = int((rows["faults"] == "rub+misalignment").sum())
    assert re.search(rf"rub recall, rub\+misalignment: \S+ \[\S+, \S+\] \(\d+ of {n} runs",
                     stdout)
    code, stdout, _ = run(["evaluate", out, fault_dataset, "--json"], capsys)
    confusers = json.loads(stdout)["confusers"]
    assert {r["faults"]: r["n"] for r in confusers}["none"] == int(
        (rows["faults"] == "none").sum())


def test_target_fault_on_a_dataset_without_faults(tiny_dataset, tmp_path, capsys):
    code, stdout, err = run(["train", tiny_dataset, "--target", "fault", "--out",
                             tmp_path / "m", "--quick"], capsys)
    assert code == 2 and stdout == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "target = 'fault': the data has no 'faults' column" in err
    assert not (tmp_path / "m").exists()


def test_an_unknown_target(fault_dataset, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["train", str(fault_dataset), "--target", "faults", "--out", str(tmp_path / "m")])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "invalid choice: 'faults'" in err and "'fault'" in err and "Traceback" not in err
