"""The how-to "Train a rub detector and predict": its `rubdiag predict` examples run as
written, on a small dataset
(DATA), the models its `rubdiag train` lines make, and measurement files made here as the
lines describe them (columns, units, tacho); the slow test runs every command of the block
and its Python block as written, full evaluations included."""

from __future__ import annotations

import io
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import build_parser, main
from rubdiag.dataset import Design, generate, load_waveforms
from rubdiag.learn import predict, read_dataset
from rubdiag.learn._persist import load_model
from rubdiag.learn._predict import UNITS
from rubdiag.learn._train import train

ROOT = Path(__file__).resolve().parents[2]
CHANNEL_SETS = ("auto", "shaft", "all")


PAGE = ROOT / "docs" / "how-to" / "train-and-predict.md"


def section() -> str:
    return PAGE.read_text(encoding="utf-8")


def console_commands() -> list[list[str]]:
    """The commands of the page's first console block, as argv after ``rubdiag``."""
    block = re.search(r"```console\n(.*?)```", section(), re.DOTALL).group(1)
    out = []
    for line in block.splitlines():
        argv = shlex.split(line, comments=True)
        assert argv[0] == "rubdiag", line
        out.append(argv[1:])
    return out


def python_block() -> str:
    return re.search(r"```python\n(.*?)```", section(), re.DOTALL).group(1)


COMMANDS = console_commands()
PARSER = build_parser()


def parsed(argv):
    return PARSER.parse_args(argv)


def channels_option(text: str):
    return text if text in CHANNEL_SETS else [n.strip() for n in text.split(",")]


def pairs(values) -> dict:
    return dict(v.split("=", 1) for v in values)


def test_the_block_trains_and_predicts_for_one_probe_and_many():
    kinds = [argv[0] for argv in COMMANDS]
    assert kinds.count("predict") >= 3 and "train" in kinds
    # a plant with a single probe is served: a one-channel model and a file with one column
    one = [parsed(a) for a in COMMANDS if a[0] == "train" and "--channels" in a]
    assert any(len(channels_option(a.channels)) == 1 for a in one)


def rubbing_run(data: pd.DataFrame) -> pd.Series:
    """The first rubbing run by its design point (case, speed, gap), not by the order of
    the rows (which follows the run ids, a hash): at 0.9 of the critical speed. At the
    critical speed of case 1 (25 Hz) the 0.5-s window puts 1× between two 2-Hz bins, and
    the one-probe file's speed vote can miss it (the tiny design's case-1 runs at 1.0 with
    long steps: the documentation's 'Steps sized by error')."""
    rubbing = data[data["rub"].astype(bool)]
    return rubbing.sort_values(["case", "speed_ratio", "gap_mm"]).iloc[0]


def write_input(path: Path, args, model, dataset: Path, run: pd.Series) -> None:
    """The file a predict line of the page reads: the run's analysis window of the model's
    channels, in the columns (``--column``) and units (``--unit``) the line gives, with a
    time column (CSV) or ``fs`` (NPZ), and the ``--tacho`` column as a once-per-revolution
    pulse at the run's speed."""
    waves = load_waveforms(dataset, run["run_id"])
    fs = waves.attrs["fs_hz"]
    window = waves[waves.index >= waves.attrs["discard_s"] - 1e-9]
    window = window.iloc[:round(model.meta["window_s"] * fs)]
    column_of = {channel: column for column, channel in pairs(args.column).items()}
    units = pairs(args.unit)
    quantity = {c["name"]: c["quantity"] for c in model.meta["channels"]}
    out = {}
    for c in model.channels:
        scale = 1.0 / UNITS[quantity[c]][units[c]] if c in units else 1.0
        out[column_of.get(c, c)] = window[c].to_numpy(np.float64) * scale
    n = len(window)
    if args.tacho:
        turns = run["speed_rpm"] / 60.0 * np.arange(n) / fs
        out[args.tacho] = np.exp(-(((turns + 0.3) % 1.0 - 0.5) / 0.08) ** 2)
    if path.suffix == ".npz":
        np.savez(path, fs=fs, **out)
    else:
        pd.DataFrame({"t": np.arange(n) / fs, **out}).to_csv(path, index=False)


@pytest.fixture(scope="module")
def workdir(tiny_dataset, tmp_path_factory):
    """DATA, the models the predict lines use — trained as their line of the page says, the
    evaluation kept short (the fitted model does not depend on it) — and their files."""
    root = tmp_path_factory.mktemp("examples")
    (root / "DATA").symlink_to(tiny_dataset, target_is_directory=True)
    trains = {str(parsed(a).out): parsed(a) for a in COMMANDS if a[0] == "train"}
    predicts = [parsed(a) for a in COMMANDS if a[0] == "predict"]
    for name in {str(p.model) for p in predicts}:
        assert name in trains, f"no train line of the page makes {name}"
        a = trains[name]
        train(root / a.dataset, root / a.out, target=a.target, estimator=a.estimator,
              split=a.split, channels=channels_option(a.channels), seed=a.seed,
              importances=False, baselines=False, audit=False, n_shuffles=1, n_bootstrap=0)
    data = read_dataset(tiny_dataset)
    run = rubbing_run(data)
    models = {name: load_model(root / name) for name in {str(p.model) for p in predicts}}
    for p in predicts:
        for path in p.inputs:
            if path != "DATA":
                write_input(root / path, p, models[str(p.model)], tiny_dataset, run)
    return root, data, run, models


@pytest.mark.parametrize("argv", [a for a in COMMANDS if a[0] == "predict"],
                         ids=lambda a: " ".join(a[1:3]))
def test_a_predict_example_runs_as_written(argv, workdir, monkeypatch, capsys):
    root, data, run, models = workdir
    monkeypatch.chdir(root)
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 0, captured.err
    args = parsed(argv)
    model = models[str(args.model)]
    table = (pd.DataFrame(json.loads(captured.out)) if args.json else
             pd.read_csv(io.StringIO(captured.out), sep=r"\s+", dtype={"input": str}))
    if args.inputs == ["DATA"]:
        assert sorted(table["input"].astype(str)) == sorted(data["run_id"])
        return
    # the rubbing run's window: read as that run (the model was fitted on it), with the
    # probabilities of its stored row (features from float32 waveforms: within 0.05)
    stored = predict(model, root / "DATA").set_index("input").loc[run["run_id"]]
    window, majority = table.iloc[0], table.iloc[-1]
    assert str(majority["window"]) == "all" and str(majority["predicted"]) == "True"
    assert float(window["p_True"]) == pytest.approx(stored["p_True"], abs=0.05)
    tolerance = 0.002 if args.tacho else 0.03               # a tacho is exact; a line, 3 %
    assert float(window["speed_rpm"]) == pytest.approx(run["speed_rpm"], rel=tolerance)


def test_a_file_without_a_model_channel_says_how_to_train_without_it(workdir, monkeypatch,
                                                                    capsys):
    """Every file of the page against every model of the page whose channels it lacks: one
    line (exit 2) naming the missing channels and the `--channels` of a model without them —
    for the one-probe file and the default model, the page's own one-probe train line."""
    root, _, _, models = workdir
    monkeypatch.chdir(root)
    trains = {str(parsed(a).out): parsed(a) for a in COMMANDS if a[0] == "train"}
    checked = 0
    for argv in (a for a in COMMANDS if a[0] == "predict"):
        args = parsed(argv)
        given = models[str(args.model)].channels
        for name, model in models.items():
            other = model.channels
            missing = [c for c in other if c not in given]
            if not missing or args.inputs == ["DATA"]:
                continue
            code = main(["predict", name, *argv[2:]])
            (err,) = [ln for ln in capsys.readouterr().err.splitlines()
                      if not ln.startswith("rubdiag predict: warning: model ")]
            assert code == 2 and err.startswith("rubdiag predict: error: "), err
            assert all(repr(c) in err for c in missing)
            kept = [c for c in other if c not in missing]
            assert err.endswith(f"rubdiag train DATASET --channels {','.join(kept)}")
            assert any(channels_option(t.channels) == kept for t in trains.values())
            checked += 1
    assert checked >= 1


# --- everything as written ---------------------------------------------------------------

@pytest.mark.slow
def test_the_whole_block_and_the_python_block_as_written(workdir, tiny_design, tmp_path):
    """Every command in a fresh folder, in order, as a user types them (subprocesses),
    OTHER_DATA a second small dataset (other speeds and gaps: no run in common); then the
    Python block."""
    source = workdir[0]
    (tmp_path / "DATA").symlink_to((source / "DATA").resolve(), target_is_directory=True)
    factors = tiny_design.index("[factors]")
    other = tiny_design[:factors] + ("[factors]\ncase = [1, 2]\nspeed_ratio = [0.95]\n"
                                     "gap_mm = [1.0, 2.5]\n")
    generate(Design.from_toml(other), tmp_path / "OTHER_DATA", jobs=1, progress=False)
    for p in (source).iterdir():
        if p.is_file():                                  # the measurement files
            (tmp_path / p.name).write_bytes(p.read_bytes())
    for argv in COMMANDS:
        result = subprocess.run([sys.executable, "-m", "rubdiag", *argv], cwd=tmp_path,
                                capture_output=True, text=True)
        assert result.returncode == 0, (argv, result.stderr)
        if argv[0] == "evaluate":
            assert "out of sample" in result.stdout.splitlines()[0]
    code = "import matplotlib; matplotlib.use('Agg')\n" + python_block().replace(
        '"model"', '"py_model"')
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                            text=True)
    assert result.returncode == 0, result.stderr


def test_the_documentation_states_the_constants():
    """The explanation's prose takes the constants from the library when it is built."""
    from docs_tables import generate

    from rubdiag.learn._caveats import MIN_RUNS_PER_CLASS
    from rubdiag.learn._channel_choice import NOISE_MARGIN_DB

    values = generate.substitutions()
    assert values["noise_margin_db"] == f"{NOISE_MARGIN_DB:g}"
    assert values["min_runs_per_class"] == str(MIN_RUNS_PER_CLASS)
    page = " ".join((ROOT / "docs" / "explanation" / "classifiers.md").read_text().split())
    assert "lies within {{ noise_margin_db }} dB of its noise floor" in page
    assert "when a class has fewer than {{ min_runs_per_class }} runs" in page
