"""A saved model scored on what it was not trained on: a labelled record list (rubdiag.learn.
records) and a band of a dataset held out of training (``train --leave-out``, ``evaluate
--band``); the per-kind table and its Wilson intervals."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pandas as pd
import pytest
from scipy.stats import binomtest

from rubdiag.cli import main
from rubdiag.learn import read_dataset
from rubdiag.learn._confusers import kind_table
from rubdiag.learn._metrics import wilson_interval
from rubdiag.learn._predict import predict
from rubdiag.learn._records import read_records
from rubdiag.learn._textbook import textbook_records, write_records


def run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize(("hits", "n"), [(0, 10), (3, 10), (10, 10), (1, 300)])
def test_wilson_interval_is_scipys(hits, n):
    ci = binomtest(hits, n).proportion_ci(method="wilson")
    assert wilson_interval(hits, n) == pytest.approx((ci.low, ci.high), abs=1e-12)
    assert all(np.isnan(wilson_interval(0, 0)))


def test_kind_table_counts_each_kind_with_and_without_rub():
    kinds = ["2x", "2x", "2x", "rub", "rub", "mixed", "mixed"]
    rubbing = [False, False, False, True, True, False, True]
    predicted = ["True", "False", "False", "True", "True", "False", "False"]
    table = kind_table(kinds, rubbing, predicted).set_index(["kind", "measure"])
    assert list(table.index) == [("2x", "false rub alarm"), ("rub", "rub recall"),
                                 ("mixed", "false rub alarm"), ("mixed", "rub recall")]
    assert list(table["n"]) == [3, 2, 1, 1]
    assert list(table["n_called_rub"]) == [1, 2, 0, 0]
    assert table.loc[("2x", "false rub alarm"), "rate"] == pytest.approx(1 / 3)
    assert (table.loc[("rub", "rub recall"), ["lo", "hi"]].to_numpy()
            == pytest.approx(wilson_interval(2, 2)))


@pytest.fixture(scope="module")
def model(tiny_dataset, tmp_path_factory):
    """``rubdiag train TINY --quick --n-splits 2 --leave-out case=2:2``: a model that never
    saw case 2."""
    out = tmp_path_factory.mktemp("records") / "model"
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(["train", str(tiny_dataset), "--out", str(out), "--quick",
                     "--n-splits", "2", "--leave-out", "case=2:2"])
    assert code == 0
    return out


@pytest.fixture(scope="module")
def record_list(model, tmp_path_factory):
    """Textbook records of the model's channels, listed with their labels and speeds."""
    meta = json.loads((model / "model.json").read_text())
    records = textbook_records([c["name"] for c in meta["channels"]], meta["fs_hz"],
                               meta["window_s"], [1400.0], kinds=["2x", "rub-like"],
                               bin_offsets=(0.0, 0.5))
    return write_records(records, tmp_path_factory.mktemp("textbook"))


def test_the_left_out_band_is_scored_out_of_sample(model, tiny_dataset, capsys):
    code, out, _ = run(["evaluate", model, tiny_dataset, "--band", "case=2:2", "--json"],
                       capsys)
    assert code == 0
    scores = json.loads(out)
    rows = read_dataset(tiny_dataset)
    assert scores["n_rows"] == int((rows["case"] == 2).sum()) == 6
    assert scores["shared_runs"] == 0 and scores["sample"].startswith("out of sample")
    assert "case within 2 … 2" in scores["dataset"]
    code, out, _ = run(["evaluate", model, tiny_dataset, "--band", "case=1:1"], capsys)
    assert out.splitlines()[0].split("; ")[1].startswith("in-sample: 6 of these 6 runs")
    kinds = {(k["kind"], k["measure"]): k["n"] for k in scores["kinds"]}
    assert kinds == {("rub", "rub recall"): int(rows.loc[rows["case"] == 2, "rub"].sum()),
                     ("none", "false rub alarm"): int((~rows.loc[rows["case"] == 2,
                                                              "rub"]).sum())}


def test_a_record_list_is_scored_as_predict_calls_each_file(model, record_list, capsys):
    """The per-kind counts of ``evaluate MODEL LIST.csv`` are those of ``predict`` on the
    same files at the same speeds (the majority of each file's windows), counted here."""
    code, out, _ = run(["evaluate", model, record_list, "--json"], capsys)
    assert code == 0
    scores = json.loads(out)
    listed = pd.read_csv(record_list)
    files = [str(record_list.parent / f) for f in listed["file"]]
    table = predict(model, files, speed_rpm=dict(zip(files, listed["speed_rpm"], strict=True)))
    called = table.loc[table["window"] == "all"].set_index("input").loc[files, "predicted"]
    listed["called"] = (called == "True").to_numpy()
    by_kind = {k["kind"]: (k["measure"], k["n"], k["n_called_rub"]) for k in scores["kinds"]}
    assert by_kind == {
        kind: ("rub recall" if kind == "rub-like" else "false rub alarm", len(part),
               int(part["called"].sum()))
        for kind, part in listed.groupby("kind")}
    assert scores["n_rows"] == len(listed) and scores["shared_runs"] == 0
    code, out, _ = run(["evaluate", model, record_list], capsys)
    assert "per kind of run or record" in out and "2x: false rub alarm" in out


def test_a_record_list_is_read_with_its_paths_and_labels(record_list, tmp_path):
    records = read_records(record_list)
    assert all(p.startswith(str(record_list.parent)) for p in records["file"])
    assert list(records["rub"]) == list(records["faults"] == "rub")
    assert records.attrs["source"] == str(record_list)


@pytest.mark.parametrize(("text", "message"), [
    ("faults\nrub\n", "no column 'file'"),
    ("file,speed_rpm\na.npz,1000\n", "no label column"),
    ("file,faults\nmissing.npz,rub\n", "do not exist"),
    ("file,faults\n", "names no record"),
])
def test_a_bad_record_list_is_refused(text, message, tmp_path):
    path = tmp_path / "list.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        read_records(path)


@pytest.mark.parametrize(("argv", "message"), [
    (["--band", "case"], "is not FACTOR=LO:HI"),
    (["--band", "nothing=1:2"], "not a design factor"),
    (["--band", "case=5:6"], "no row has case within 5 … 6"),
])
def test_a_bad_band_is_one_line_and_exit_2(argv, message, model, tiny_dataset, capsys):
    code, _, err = run(["evaluate", model, tiny_dataset, *argv], capsys)
    assert code == 2
    assert message in err and len(err.strip().splitlines()) == 1
