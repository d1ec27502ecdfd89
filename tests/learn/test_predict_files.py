"""predict over many files, each with its own speed: per-file speeds (a mapping, a sequence,
``--speeds FILE.csv``), where each speed came from, folders and glob patterns, the table
written by ``--out``, and the progress bar. The model: a forest on synthetic records of a
machine with a 1× and a weak 2× line, rubbing with a ½× line, at 1200–1800 rpm."""

from __future__ import annotations

import io
import json
import re
import sys

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.learn import make_pipeline
from rubdiag.learn._inputs import read_speeds
from rubdiag.learn._persist import load_model, save_model
from rubdiag.learn._predict import predict
from rubdiag.learn._train import model_meta
from rubdiag.signal._table import prefixed_features

FS, WINDOW_S = 2000.0, 1.0
CHANNELS = (("probe", "shaft 4", 10e-6), ("shaft", "shaft 11", 50e-6))


def record(rpm, rub=False, seed=0, seconds=WINDOW_S, two=0.2):
    """The channels (m) of the machine at ``rpm``: 1×, a 2× of ``two`` times it, a ½× of a
    tenth of it when rubbing, 1 % noise."""
    t = np.arange(round(FS * seconds)) / FS
    rng = np.random.default_rng(seed)
    f1 = rpm / 60.0
    out = {}
    for name, _, scale in CHANNELS:
        x = scale * (np.cos(2 * np.pi * f1 * t) + two * np.cos(4 * np.pi * f1 * t + 0.3))
        if rub:
            x += 0.1 * scale * np.cos(np.pi * f1 * t + 0.4)
        out[name] = x + 0.01 * scale * rng.standard_normal(t.size)
    return out


def tacho(rpm, n, phase=0.3):
    """A once-per-revolution pulse at ``rpm``."""
    turns = (rpm / 60.0 * np.arange(n) / FS + phase) % 1.0
    return np.exp(-((turns - 0.5) / 0.08) ** 2)


def write(path, signals, pulses=None):
    n = len(next(iter(signals.values())))
    frame = pd.DataFrame({"t": np.arange(n) / FS, **signals})
    if pulses is not None:
        frame["tacho"] = pulses
    frame.to_csv(path, index=False)
    return path


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory):
    rows = []
    for i, rpm in enumerate(np.linspace(1200.0, 1800.0, 16)):
        rub, two = bool(i % 2), 0.15 + 0.1 * (i % 5) / 4       # 2x: 0.15 to 0.25 of 1x
        rows.append(prefixed_features(record(rpm, rub, i, two=two), FS, rpm, separator="__")
                    .assign(rub=rub))
    data = pd.concat(rows, ignore_index=True)
    data.attrs["acquisition"] = {
        "fs_hz": FS, "window_s": WINDOW_S,
        "sensors": [{"name": n, "unit": "m", "quantity": "displacement", "point": p,
                     "direction": "y"} for n, p, _ in CHANNELS]}
    pipe = make_pipeline("rf", channels=[n for n, _, _ in CHANNELS]).fit(
        data, data["rub"].astype(str))
    meta = model_meta(pipe, data, target="rub", estimator="rf", split="group",
                      families=["orders", "sidebands", "combinations"], seed=0)
    return save_model(pipe, tmp_path_factory.mktemp("files") / "model", meta)


@pytest.fixture(scope="module")
def model(model_dir):
    return load_model(model_dir)


@pytest.fixture(scope="module")
def plant(tmp_path_factory):
    """A folder of records, each with a speed of its own: name -> (rpm, rubbing)."""
    folder = tmp_path_factory.mktemp("plant")
    truth = {"a_slow.csv": (1300.0, False), "b_fast.csv": (1700.0, False),
             "c_rub.csv": (1450.0, True), "d_long.csv": (1550.0, True)}
    for k, (name, (rpm, rub)) in enumerate(truth.items()):
        seconds = 2.5 if name == "d_long.csv" else WINDOW_S        # two windows and a half
        write(folder / name, record(rpm, rub, 100 + k, seconds))
    return folder, truth


def run_cli(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return captured


def features_outside(warning: str) -> int:
    found = re.search(r"(\d+) of \d+ features outside", warning)
    return int(found.group(1)) if found else 0


def test_many_files_in_one_call_are_the_files_one_by_one(model, plant):
    folder, truth = plant
    paths = sorted(folder.glob("*.csv"))
    speeds = {name: rpm for name, (rpm, _) in truth.items()}
    together = predict(model, paths, speed_rpm=speeds)
    alone = pd.concat([predict(model, p, speed_rpm={p.name: speeds[p.name]}) for p in paths],
                      ignore_index=True)
    pd.testing.assert_frame_equal(together, alone)          # bit for bit, row for row
    assert list(together["window"]) == [0, "all", 0, "all", 0, "all", 0, 1, "all"]
    assert (together["speed_source"] == "speeds").all()
    majority = together[together["window"] == "all"].set_index("input")
    assert list(majority["speed_rpm"]) == [truth[p.name][0] for p in paths]
    assert list(majority["predicted"]) == [str(truth[p.name][1]) for p in paths]


def test_each_file_read_at_its_own_speed_and_swapping_them_shows(model_dir, plant, tmp_path,
                                                                capsys):
    """Two records of the same machine (no rub) at 1300 and 1700 rpm: at their own speeds
    they read as the machine did in training; swapped, their 1× falls outside the order
    bands and the table says so."""
    folder, _ = plant
    files = [folder / "a_slow.csv", folder / "b_fast.csv"]
    right, swapped = tmp_path / "right.csv", tmp_path / "swapped.csv"
    right.write_text("file,speed_rpm\na_slow.csv,1300\nb_fast.csv,1700\n")
    swapped.write_text("file,speed_rpm\na_slow.csv,1700\nb_fast.csv,1300\n")
    tables = {}
    for name, speeds in (("right", right), ("swapped", swapped)):
        out = tmp_path / f"{name}.json"
        run_cli(["predict", model_dir, *files, "--speeds", speeds, "--out", out], capsys)
        table = pd.DataFrame(json.loads(out.read_text()))
        tables[name] = table[table["window"] != "all"].set_index("input")
    ok, bad = tables["right"], tables["swapped"]
    keys = [str(f) for f in files]
    assert list(ok.loc[keys, "speed_rpm"]) == [1300.0, 1700.0]
    assert list(bad.loc[keys, "speed_rpm"]) == [1700.0, 1300.0]
    assert (ok["speed_source"] == "speeds").all() and (bad["speed_source"] == "speeds").all()
    assert list(ok["predicted"]) == ["False", "False"] and list(ok["warnings"]) == ["", ""]
    assert all(features_outside(w) >= 2 for w in bad["warnings"])


def test_a_range_warning_names_the_features_with_values_and_ranges(model, plant):
    """Swapped speeds: the warning names at most NAMED_FEATURES features, each with the
    value the window read and the model's training range, which it lies outside; a band
    at the noise floor (1) is never among them."""
    from rubdiag.learn._predict import NAMED_FEATURES

    folder, _ = plant
    table = predict(model, [folder / "a_slow.csv"], speed_rpm=[1700.0])
    warning = table["warnings"].iloc[0]
    named = re.findall(r"(\S+__\S+) = (\S+) \(range (\S+) to (\S+)\)", warning)
    assert 1 <= len(named) <= min(NAMED_FEATURES, features_outside(warning))
    ranges = model.meta["feature_ranges"]
    for name, value, lo, hi in named:
        assert [float(lo), float(hi)] == pytest.approx(ranges[name], rel=1e-3)
        assert not float(lo) <= float(value) <= float(hi), name
        assert not (name.endswith("_over_floor") and float(value) == 1.0)


def test_a_tacho_wins_over_the_estimate_when_2x_is_stronger_than_1x(model, tmp_path):
    """With 2× twice as strong as 1×, the dominant line is 2×: the estimate reads twice
    the speed and says it is ambiguous (1× may be the line at half of it); the tacho column
    reads it right, and so does a file's own speed."""
    signals = record(1500.0, two=2.0, seed=7)
    n = len(signals["shaft"])
    plain = write(tmp_path / "plain.csv", signals)
    keyed = write(tmp_path / "keyed.csv", signals, pulses=tacho(1500.0, n))
    guessed = predict(model, plain)
    assert list(guessed["speed_source"]) == ["estimated"] * 2
    assert guessed["speed_rpm"].iloc[0] == pytest.approx(3000.0, rel=1e-3)
    assert list(guessed["speed_ambiguous"]) == [True, True]          # the window, "all"
    assert guessed["warnings"].iloc[0].startswith(
        "the speed is ambiguous: 3000 rpm is the strongest line, taken as 1x, but a line at "
        "1/2 of its frequency (1500 rpm)")
    measured = predict(model, keyed)
    assert measured["speed_source"].iloc[0] == "tacho"
    assert measured["speed_rpm"].iloc[0] == pytest.approx(1500.0, rel=1e-3)
    assert not measured["speed_ambiguous"].any()
    # a file without its own speed (empty in the speeds) falls to its tacho, then to
    # the estimate; a file with one keeps it, tacho or not
    speeds = tmp_path / "speeds.csv"
    speeds.write_text("file,speed_rpm\nplain.csv,\nkeyed.csv,1510\n")
    table = predict(model, [plain, keyed], speed_rpm=read_speeds(speeds))
    table = table[table["window"] == 0].set_index("input")
    assert table.loc[str(plain), "speed_source"] == "estimated"
    assert table.loc[str(keyed), ["speed_source", "speed_rpm"]].tolist() == ["speeds", 1510.0]
    speeds.write_text("file,speed_rpm\nplain.csv,\nkeyed.csv,\n")
    with pytest.raises(ValueError, match=r"plain\.csv: tacho column 'tacho' not found"):
        predict(model, [plain, keyed], speed_rpm=read_speeds(speeds), tacho="tacho")
    speeds.write_text("file,speed_rpm\nplain.csv,1500\nkeyed.csv,\n")
    table = predict(model, [plain, keyed], speed_rpm=read_speeds(speeds), tacho="tacho")
    assert list(table["speed_source"].iloc[[0, 2]]) == ["speeds", "tacho"]


def test_a_folder_and_a_pattern_give_the_rows_of_the_list(model, plant):
    folder, truth = plant
    speeds = {name: rpm for name, (rpm, _) in truth.items()}
    listed = predict(model, [folder / name for name in sorted(truth)], speed_rpm=speeds)
    for given in (folder, str(folder / "*.csv"), str(folder / "[a-d]_*.csv")):
        pd.testing.assert_frame_equal(predict(model, given, speed_rpm=speeds), listed)
    part = predict(model, str(folder / "?_[sf]*.csv"), speed_rpm=speeds)  # the others: unused
    assert sorted(set(part["input"])) == [str(folder / "a_slow.csv"),
                                          str(folder / "b_fast.csv")]


def test_speeds_per_input_as_a_sequence(model, plant):
    """A sequence is aligned with the inputs as given: a folder's files share its speed."""
    folder, _ = plant
    paths = [folder / "a_slow.csv", folder / "b_fast.csv"]
    table = predict(model, paths, speed_rpm=[1300.0, 1700.0])
    assert list(table["speed_rpm"]) == [1300.0, 1300.0, 1700.0, 1700.0]
    table = predict(model, [folder], speed_rpm=[1500.0])
    assert (table["speed_rpm"] == 1500.0).all() and table["input"].nunique() == 4
    with pytest.raises(ValueError, match="speed_rpm has 1 speeds for 2 inputs"):
        predict(model, paths, speed_rpm=[1300.0])


def test_speed_entries_by_path_and_by_name(model, plant, tmp_path):
    folder, _ = plant
    a, b = folder / "a_slow.csv", folder / "b_fast.csv"
    # by its path, before its name
    table = predict(model, [a, b], speed_rpm={str(a): 1300.0, "a_slow.csv": 1.0,
                                              "b_fast.csv": 1700.0})
    assert list(table["speed_rpm"]) == [1300.0, 1300.0, 1700.0, 1700.0]
    twin = tmp_path / "a_slow.csv"
    twin.write_bytes(a.read_bytes())
    with pytest.raises(ValueError, match=r"'a_slow\.csv' names 2 input files; name them "
                       r"by their paths"):
        predict(model, [a, twin], speed_rpm={"a_slow.csv": 1300.0})
    table = predict(model, [a, twin], speed_rpm={str(a): 1300.0, str(twin): 1700.0})
    assert list(table["speed_rpm"]) == [1300.0, 1300.0, 1700.0, 1700.0]
    with pytest.raises(ValueError, match=r"speed_rpm: no speed for .*b_fast\.csv \(every "
                       r"input file needs an entry, by its path or its file name; entries "
                       r"that name no input: b_fst\.csv\)"):
        predict(model, [a, b], speed_rpm={"a_slow.csv": 1300.0, "b_fst.csv": 1700.0})


def test_the_out_table_in_each_format_is_the_printed_one(model_dir, plant, tmp_path, capsys):
    folder, truth = plant
    speeds = tmp_path / "speeds.csv"
    pd.DataFrame({"file": list(truth), "speed_rpm": [r for r, _ in truth.values()]}).to_csv(
        speeds, index=False)
    printed = pd.DataFrame(json.loads(run_cli(
        ["predict", model_dir, folder, "--speeds", speeds, "--json"], capsys).out))
    assert len(printed) == 9
    for suffix in ("csv", "parquet", "json"):
        out = tmp_path / f"table.{suffix}"
        said = run_cli(["predict", model_dir, folder, "--speeds", speeds, "--out", out],
                       capsys).out
        assert said == f"wrote {out}: 9 rows (4 files, their windows and majorities)\n"
        read = {"csv": lambda p: pd.read_csv(p, keep_default_na=False),
                "parquet": pd.read_parquet,
                "json": lambda p: pd.DataFrame(json.loads(p.read_text()))}[suffix](out)
        assert list(read.columns) == list(printed.columns)
        assert list(read["window"].astype(str)) == list(printed["window"].astype(str))
        for column in ("input", "speed_source", "predicted", "warnings"):
            assert list(read[column].astype(str)) == list(printed[column]), column
        for column in ("speed_rpm", "start_s", "end_s", "p_False", "p_True"):
            assert np.array_equal(read[column].to_numpy(float),
                                  printed[column].to_numpy(float)), column


def test_a_folder_leaves_out_the_speeds_file_and_the_table_in_it(model_dir, plant, tmp_path,
                                                                 capsys):
    folder, truth = plant
    mine = tmp_path / "records"
    mine.mkdir()
    for name in truth:
        (mine / name).write_bytes((folder / name).read_bytes())
    speeds = mine / "speeds.csv"
    speeds.write_text("file,speed_rpm\n" + "".join(f"{n},{r}\n" for n, (r, _) in truth.items()))
    for _ in range(2):      # the second run finds the first run's table in the folder
        run_cli(["predict", model_dir, mine, "--speeds", speeds, "--out",
                 mine / "table.csv"], capsys)
        table = pd.read_csv(mine / "table.csv")
        assert sorted(set(table["input"])) == [str(mine / n) for n in sorted(truth)]


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_progress_bar_over_the_files_on_a_terminal_only(model_dir, plant, monkeypatch,
                                                          capsys):
    folder, _ = plant
    speeds = ["--speed-rpm", "1500"]
    for extra, shown in (([], True), (["--quiet"], False)):
        stream = _Terminal()
        monkeypatch.setattr(sys, "stderr", stream)
        run_cli(["predict", model_dir, folder, *speeds, "--json", *extra], capsys)
        assert ("4/4" in stream.getvalue() and "file" in stream.getvalue()) == shown
    monkeypatch.undo()
    code = main(["predict", str(model_dir), str(folder), *speeds, "--json"])
    assert code == 0 and "4/4" not in capsys.readouterr().err     # not a terminal
