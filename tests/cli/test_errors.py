"""Every bad input of the command line: one line on stderr naming the problem, exit status 2.

The catalogue of bad inputs, run in-process through ``rubdiag.cli.main``; new
commands add their inputs here. Output locations are checked before any work: for those
entries the expensive functions are replaced by ones that fail the test if they are called.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main

FS = 2000.0
# a fast simulate: given speed (no critical-speed search), 20 ms, gap ramp inside the discard
SIM = ["simulate", "--case", "1", "--speed-rpm", "1500", "--duration-s", "0.02",
       "--discard-s", "0.01"]


@pytest.fixture(scope="module")
def d(tmp_path_factory):
    """A folder of bad (and a few good) input files."""
    from rubdiag.model import paper_rig, save_rig
    from rubdiag.simulation import Run, simulate

    d = tmp_path_factory.mktemp("inputs")
    t = np.arange(4000) / FS
    x = np.sin(2 * np.pi * 25 * t) + 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    pd.DataFrame({"time": t, "shaft": x}).to_csv(d / "a.csv", index=False)
    pd.DataFrame({"time": t, "other": x}).to_csv(d / "b.csv", index=False)
    (d / "empty.csv").write_text("")
    (d / "header.csv").write_text("time,shaft\n")
    (d / "onerow.csv").write_text("time,shaft\n0,1\n")
    pd.DataFrame({"time": t[:20], "shaft": x[:20]}).to_csv(d / "short.csv", index=False)
    for name, bad in (("nan", np.nan), ("inf", np.inf)):
        y = x.copy()
        y[100] = bad
        pd.DataFrame({"time": t, "shaft": y}).to_csv(d / f"{name}.csv", index=False)
    pd.DataFrame({"time": np.r_[t[:10], t[10:] + 0.01], "shaft": x}).to_csv(
        d / "nonuniform.csv", index=False)
    pd.DataFrame({"time": t, "shaft": "high"}).to_csv(d / "text.csv", index=False)
    np.savez(d / "plain.npz", shaft=x, fs=FS)
    (d / "binary.csv").write_bytes((d / "plain.npz").read_bytes())   # zip bytes, NULs
    (d / "latin1.csv").write_bytes("temp\xe9rature,shaft\n1,2\n".encode("latin-1"))
    (d / "notzip.npz").write_bytes(b"not a zip")
    (d / "folder.csv").mkdir()
    (d / "folder").mkdir()
    (d / "folder.npz").mkdir()
    (d / "file").write_text("a file where a folder belongs\n")

    result = simulate(Run.paper_case(2, 2.3, speed_rpm=5700, duration_s=0.02, discard_s=0.01))
    data = result.save(d / "run.npz").read_bytes()
    (d / "truncated.npz").write_bytes(data[: len(data) // 2])
    flipped = bytearray(data)                 # a member's compressed bytes damaged: bad CRC
    mid = len(flipped) // 2
    flipped[mid:mid + 64] = bytes(b ^ 0xFF for b in flipped[mid:mid + 64])
    (d / "corrupt.npz").write_bytes(bytes(flipped))

    save_rig(paper_rig(), d / "paper.toml")
    toml = (d / "paper.toml").read_text()
    for name, old, new in (
            ("node99", "node = 4\n", "node = 99\n"),
            ("negative_e", "youngs_modulus_pa = 210000000000.0", "youngs_modulus_pa = -2e11"),
            ("string_density", "density_kg_m3 = 7850.0", 'density_kg_m3 = "heavy"'),
            ("negative_length", "    0.027669,\n", "    -0.1,\n")):
        assert old in toml
        (d / f"{name}.toml").write_text(toml.replace(old, new, 1))
    (d / "unknown_key.toml").write_text('[shaft]\ncolour = "red"\n')
    (d / "unknown_table.toml").write_text("[shafts]\nx = 1\n")
    (d / "syntax.toml").write_text("[shaft\n")

    good = DESIGN.format(factors='gap_mm = [1.9, 4.0]')
    (d / "design.toml").write_text(good)
    for name, text in (
            ("design_unknown_factor", DESIGN.format(factors='colour = ["red"]')),
            ("design_unknown_key", good.replace("[sampling]", "[sampling]\nsize = 3")),
            ("design_low_above_high", DESIGN.format(factors="gap_mm = {low = 4.0, high = 0.5}")),
            ("design_n_zero", good.replace('method = "grid"', 'method = "lhs"\nn = 0')),
            ("design_mu_negative", DESIGN.format(factors="mu = {low = -1.0, high = 0.5}")),
            ("design_case_and_phase", DESIGN.format(factors="phase_diff_deg = [90.0]")),
            ("design_short_window", good.replace("case = [2]", "case = [1]")),
            ("design_sensor_no_dof", good + '\n[[sensors]]\npoint = "casing 99"\n'
                                            'direction = "y"\n')):
        (d / f"{name}.toml").write_text(text)
    from rubdiag.dataset import Design
    from rubdiag.dataset._store import DatasetFolder

    other = Design.from_toml(DESIGN.format(factors="gap_mm = [2.3]"))
    DatasetFolder(d / "other_dataset").create(other.to_toml())
    (d / "not_a_dataset").mkdir()
    (d / "not_a_dataset" / "notes.txt").write_text("mine\n")
    _learn_inputs(d, t, x)
    return d


def _learn_inputs(d, t, x):
    """A model folder (logistic regression on rows of synthetic 'shaft' records: 1-s
    windows at 2 kHz, rub = a 2x line) with a damaged and a foreign copy, and signals that
    `rubdiag predict` refuses: too slowly sampled, pure noise."""
    import shutil

    import skops.io as sio
    from sklearn.neighbors import KNeighborsClassifier

    from rubdiag.learn import make_pipeline
    from rubdiag.learn._persist import MODEL_FILE, save_model
    from rubdiag.learn._train import model_meta
    from rubdiag.signal._table import prefixed_features

    window = t < 1.0
    rng = np.random.default_rng(1)
    rows = pd.concat([prefixed_features(
        {"shaft": x[window] + a * np.sin(2 * np.pi * 50 * t[window])
         + 1e-3 * rng.standard_normal(window.sum())}, FS, 1500.0, separator="__")
        for a in (0.0, 0.0, 0.0, 0.3, 0.4, 0.5)], ignore_index=True)
    rows["rub"] = [False] * 3 + [True] * 3
    rows.attrs["acquisition"] = {
        "fs_hz": FS, "window_s": 1.0, "discard_s": 0.0,
        "sensors": [{"name": "shaft", "point": "shaft 4", "direction": "y",
                     "quantity": "displacement", "unit": "m"}]}
    y = rows["rub"].astype(str).to_numpy()
    pipe = make_pipeline("logreg", channels=["shaft"]).fit(rows, y)
    save_model(pipe, d / "model", model_meta(pipe, rows, target="rub", estimator="logreg",
                                             split="group", families=["orders"], seed=0))
    shutil.copytree(d / "model", d / "damaged_model")
    data = (d / "model" / MODEL_FILE).read_bytes()
    (d / "damaged_model" / MODEL_FILE).write_bytes(data[: len(data) // 2])
    shutil.copytree(d / "model", d / "untrusted_model")
    knn = make_pipeline("logreg", channels=["shaft"]).set_params(
        model=KNeighborsClassifier(1)).fit(rows, y)
    sio.dump(knn, d / "untrusted_model" / MODEL_FILE)
    slow_t = np.arange(600) / 300.0
    pd.DataFrame({"time": slow_t, "shaft": np.sin(2 * np.pi * 25 * slow_t)}).to_csv(
        d / "slow.csv", index=False)
    pd.DataFrame({"time": t, "shaft": rng.standard_normal(t.size)}).to_csv(
        d / "noise.csv", index=False)
    for name, text in (("speeds_no_column", "file,rpm\na.csv,1500\n"),
                       ("speeds_negative", "file,speed_rpm\na.csv,-1500\n"),
                       ("speeds_text", "file,speed_rpm\na.csv,fast\n"),
                       ("speeds_twice", "file,speed_rpm\na.csv,1500\na.csv,1510\n"),
                       ("speeds_other", "file,speed_rpm\nz.csv,1500\n")):
        (d / f"{name}.csv").write_text(text)


# a small dataset design: case 2 (0.2 s hold 17 revolutions), speed_ratio 1, one factor more
DESIGN = """[base]
rig = "paper"
duration_s = 0.3
discard_s = 0.1

[sampling]
method = "grid"

[factors]
case = [2]
speed_ratio = [1.0]
{factors}
"""


# (id, argv with {d} for the input folder, message fragment); the fragment names the problem
CATALOGUE = [
    # --- output locations: checked (or created) before any work --------------------------
    ("simulate-out-missing-folder", [*SIM, "--gap-mm", "2.3", "--out", "{d}/new/x.npz"],
     "the folder {d}/new does not exist"),
    ("simulate-out-folder", [*SIM, "--gap-mm", "2.3", "--out", "{d}/folder.npz"],
     "--out {d}/folder.npz: is a folder"),
    ("simulate-out-folder-without-suffix", [*SIM, "--gap-mm", "2.3", "--out", "{d}/folder"],
     "--out {d}/folder: is a folder"),
    ("features-csv-missing-folder", ["features", "{d}/a.csv", "--csv", "{d}/new/f.csv"],
     "--csv {d}/new/f.csv: the folder {d}/new does not exist"),
    ("features-csv-folder", ["features", "{d}/a.csv", "--csv", "{d}/folder"],
     "--csv {d}/folder: is a folder"),
    ("compare-out-missing-folder", ["compare", "{d}/a.csv", "{d}/a.csv", "--out",
                                    "{d}/new/c.png"], "the folder {d}/new does not exist"),
    ("calibrate-out-missing-folder", ["calibrate", "--out", "{d}/new/rig.toml"],
     "the folder {d}/new does not exist"),
    ("campbell-out-file", ["campbell", "--out", "{d}/file"], "--out {d}/file: is a file"),
    ("table2-out-file", ["table2", "--out", "{d}/file"], "--out {d}/file: is a file"),
    ("plot-out-file", ["plot", "{d}/run.npz", "--out", "{d}/file"], "--out {d}/file: is a file"),
    # --- unreadable inputs -----------------------------------------------------------------
    ("plot-truncated-npz", ["plot", "{d}/truncated.npz"], "truncated.npz: not a rubdiag result"),
    ("plot-corrupt-npz", ["plot", "{d}/corrupt.npz"], "corrupt.npz: corrupt result file"),
    ("plot-not-a-zip", ["plot", "{d}/notzip.npz"], "notzip.npz: not a rubdiag result file"),
    ("plot-plain-npz", ["plot", "{d}/plain.npz"], "plain.npz: not a rubdiag result file"),
    ("plot-missing", ["plot", "{d}/none.npz"], "{d}/none.npz: no such file"),
    ("features-truncated-npz", ["features", "{d}/truncated.npz"],
     "truncated.npz: not an NPZ archive"),
    ("features-corrupt-result", ["features", "{d}/corrupt.npz"],
     "corrupt.npz: corrupt result file"),
    ("features-binary-csv", ["features", "{d}/binary.csv"], "binary.csv: a binary file"),
    ("features-latin1-csv", ["features", "{d}/latin1.csv"], "latin1.csv: not UTF-8 text"),
    ("features-folder", ["features", "{d}/folder"], "{d}/folder: is a folder"),
    ("features-folder-with-suffix", ["features", "{d}/folder.csv"],
     "{d}/folder.csv: is a folder"),
    ("rig-folder", ["modal", "--rig", "{d}/folder"], "--rig {d}/folder: is a folder"),
    ("rig-missing", ["modal", "--rig", "{d}/none.toml"], "--rig {d}/none.toml: no such file"),
    ("simulate-rig-folder", [*SIM, "--gap-mm", "2.3", "--rig", "{d}/folder"],
     "--rig {d}/folder: is a folder"),
    # --- values: in the user's units, options that exist, negative numbers parsed ---------
    ("calibrate-descending-rpm", ["calibrate", "--targets-rpm", "1500", "1400"],
     "--targets-rpm 1500 1400 must be strictly ascending (rpm)"),
    ("calibrate-zero-rpm", ["calibrate", "--targets-rpm", "0", "5700"],
     "--targets-rpm 0 is out of range"),
    ("simulate-output-too-large", [*SIM, "--gap-mm", "2.3", "--duration-s", "1e4",
                                   "--discard-s", "0.3"],
     "too large an output (at most 5e+08 values): lower --output-rate-hz or shorten "
     "--duration-s"),
    ("simulate-output-rate-zero", [*SIM, "--gap-mm", "2.3", "--output-rate-hz", "0"],
     "output_rate_hz = 0"),
    ("simulate-negative-dt-e-notation", [*SIM, "--gap-mm", "2.3", "--dt-s", "-1e-5"],
     "dt_s = -1e-05 is out of range"),
    ("simulate-negative-inf-gap", [*SIM, "--gap-mm", "-inf"], "--gap-mm = -inf is out of range"),
    ("features-zero-speed", ["features", "{d}/a.csv", "--speed-rpm", "0"],
     "speed_rpm = 0.0 is out of range"),                  # a plain number, not np.float64(0.0)
    ("features-empty-unit", ["features", "{d}/a.csv", "--unit", " "],
     "--unit ' ' names no unit (allowed: the unit of the file's values, e.g. um)"),
    ("compare-empty-unit", ["compare", "{d}/a.csv", "{d}/a.csv", "--unit", ""],
     "--unit '' names no unit (allowed: the unit of the file's values, e.g. um)"),
    # --- one line from the start: they stay so --------------------------------------
    ("simulate-negative-gap", [*SIM, "--gap-mm", "-1"], "--gap-mm = -1 is out of range"),
    ("simulate-zero-gap", [*SIM, "--gap-mm", "0"], "--gap-mm = 0 is out of range"),
    ("simulate-nan-gap", [*SIM, "--gap-mm", "nan"], "--gap-mm = nan is out of range"),
    ("simulate-text-gap", [*SIM, "--gap-mm", "wide"], "argument --gap-mm: invalid float value"),
    ("features-missing", ["features", "{d}/none.csv"], "{d}/none.csv: no such file"),
    ("features-nan", ["features", "{d}/nan.csv"], "contains NaN or inf (first at sample 100)"),
    ("features-inf", ["features", "{d}/inf.csv"], "contains NaN or inf (first at sample 100)"),
    ("features-fs-zero", ["features", "{d}/a.csv", "--fs", "0"], "fs = 0.0 is out of range"),
    ("features-fs-negative", ["features", "{d}/a.csv", "--fs", "-3"],
     "fs = -3.0 is out of range"),
    ("features-empty-csv", ["features", "{d}/empty.csv"], "empty.csv: the file is empty"),
    ("features-header-only", ["features", "{d}/header.csv"], "header.csv: the file holds no "
     "samples"),
    ("features-one-row", ["features", "{d}/onerow.csv"], "onerow.csv: time column 'time' needs"),
    ("features-too-short", ["features", "{d}/short.csv", "--speed-rpm", "1500"],
     "the record is too short"),
    ("features-non-uniform-time", ["features", "{d}/nonuniform.csv"],
     "nonuniform.csv: time column 'time' is not uniformly increasing"),
    ("features-text-column", ["features", "{d}/text.csv"],
     "text.csv: column 'shaft' is not numeric"),
    ("features-above-nyquist", ["features", "{d}/a.csv", "--speed-rpm", "600000"],
     "is above the Nyquist frequency 1000 Hz"),
    ("features-unknown-column", ["features", "{d}/a.csv", "--column", "blade"],
     "column 'blade' not found"),
    ("features-unknown-tacho", ["features", "{d}/a.csv", "--tacho", "key"],
     "column 'key' not found"),
    ("rig-unknown-key", ["modal", "--rig", "{d}/unknown_key.toml"], "unknown key 'shaft.colour'"),
    ("rig-unknown-table", ["modal", "--rig", "{d}/unknown_table.toml"], "unknown key 'shafts'"),
    ("rig-toml-syntax", ["modal", "--rig", "{d}/syntax.toml"], "syntax.toml: not valid TOML"),
    ("rig-bearing-node-99", ["modal", "--rig", "{d}/node99.toml"],
     "Bearing.node = 99 is not a shaft node"),
    ("rig-negative-e", ["modal", "--rig", "{d}/negative_e.toml"],
     "youngs_modulus_pa = -200000000000.0 is out of range"),
    ("rig-string-density", ["modal", "--rig", "{d}/string_density.toml"],
     "density_kg_m3 = 'heavy' has the wrong type"),
    ("rig-negative-length", ["modal", "--rig", "{d}/negative_length.toml"],
     "element_lengths_m[0] = -0.1 is out of range"),
    ("simulate-duration-huge", [*SIM, "--gap-mm", "2.3", "--duration-s", "1e9",
                                "--discard-s", "0.3"],
     "too large an output"),
    ("simulate-duration-negative", [*SIM, "--gap-mm", "2.3", "--duration-s", "-1"],
     "duration_s = -1.0 is out of range"),
    ("simulate-duration-below-dt", [*SIM, "--gap-mm", "2.3", "--duration-s", "1e-6"],
     "duration_s = 1e-06 is out of range"),
    ("simulate-discard-beyond-duration", [*SIM, "--gap-mm", "2.3", "--discard-s", "0.5"],
     "discard_s = 0.5 is out of range"),
    ("simulate-dt-zero", [*SIM, "--gap-mm", "2.3", "--dt-s", "0"], "dt_s = 0.0 is out of range"),
    ("simulate-negative-step-error", [*SIM, "--gap-mm", "2.3", "--step-error", "-1e-5"],
     "step_error = -1e-05 is out of range"),
    ("simulate-dt-too-long", [*SIM, "--gap-mm", "2.3", "--dt-s", "0.1"],
     "duration_s = 0.02 is out of range"),
    ("simulate-negative-mu", [*SIM, "--gap-mm", "2.3", "--mu", "-0.1"],
     "friction_coefficient = -0.1 is out of range"),
    ("simulate-negative-speed", ["simulate", "--case", "1", "--gap-mm", "2.3", "--speed-rpm",
                                 "-100"], "speed_rpm = -100.0 is out of range"),
    ("table2-jobs-zero", ["table2", "--jobs", "0", "--out", "{d}/t2"],
     "--jobs = 0 is out of range"),
    # --- the reduced model: checked before any work ------------------------------
    ("simulate-cutoff-without-reduced", [*SIM, "--gap-mm", "2.3", "--cutoff-hz", "1500"],
     "--cutoff-hz 1500 needs --reduced"),
    ("simulate-cutoff-negative", [*SIM, "--gap-mm", "2.3", "--reduced", "--cutoff-hz", "-5"],
     "--cutoff-hz: cutoff_hz = -5.0 is out of range (allowed: >= 1 and <= 1e+06)"),
    ("simulate-cutoff-nan", [*SIM, "--gap-mm", "2.3", "--reduced", "--cutoff-hz", "nan"],
     "--cutoff-hz: cutoff_hz = nan is out of range"),
    ("simulate-cutoff-text", [*SIM, "--gap-mm", "2.3", "--reduced", "--cutoff-hz", "2kHz"],
     "argument --cutoff-hz: invalid float value: '2kHz'"),
    ("table2-cutoff-without-reduced", ["table2", "--cutoff-hz", "1500", "--out", "{d}/new"],
     "--cutoff-hz 1500 needs --reduced"),
    ("table2-cutoff-zero", ["table2", "--reduced", "--cutoff-hz", "0", "--out", "{d}/new"],
     "--cutoff-hz: cutoff_hz = 0.0 is out of range"),
    ("table2-discard-beyond-duration", ["table2", "--duration-s", "0.2", "--out", "{d}/t2"],
     "discard_s = 0.3 is out of range"),
    ("campbell-n-speeds-zero", ["campbell", "--n-speeds", "0", "--out", "{d}/c"],
     "--n-speeds = 0 is out of range"),
    ("unbalance-case-3", ["unbalance", "--case", "3"], "argument --case: invalid choice: 3"),
    ("calibrate-unknown-knob", ["calibrate", "--knobs", "banana"], "knob 'banana' is not allowed"),
    ("modal-n-modes-zero", ["modal", "--n-modes", "0"], "--n-modes = 0 is out of range"),
    ("compare-missing", ["compare", "{d}/a.csv", "{d}/none.csv"], "{d}/none.csv: no such file"),
    ("compare-no-common-channel", ["compare", "{d}/a.csv", "{d}/b.csv"],
     "have no channel in common"),
    # --- dataset: nothing simulated, nothing written --------------------
    ("dataset-design-missing", ["dataset", "{d}/none.toml", "--out", "{d}/new"],
     "{d}/none.toml: no such file"),
    ("dataset-unknown-factor", ["dataset", "{d}/design_unknown_factor.toml", "--out",
                                "{d}/new"], "unknown factor 'factors.colour'"),
    ("dataset-unknown-key", ["dataset", "{d}/design_unknown_key.toml", "--out", "{d}/new"],
     "unknown key 'sampling.size'"),
    ("dataset-low-above-high", ["dataset", "{d}/design_low_above_high.toml", "--out",
                                "{d}/new"], "factors.gap_mm.low = 4.0 is out of range"),
    ("dataset-n-zero", ["dataset", "{d}/design_n_zero.toml", "--out", "{d}/new"],
     "sampling.n = 0 is out of range"),
    ("dataset-mu-negative", ["dataset", "{d}/design_mu_negative.toml", "--out", "{d}/new"],
     "factors.mu.low = -1.0 is out of range"),
    ("dataset-case-and-phase", ["dataset", "{d}/design_case_and_phase.toml", "--out",
                                "{d}/new"],
     "factors.case and factors.phase_diff_deg exclude each other"),
    ("dataset-short-window", ["dataset", "{d}/design_short_window.toml", "--out", "{d}/new"],
     "holds 5 revolutions at 1500 rpm, the design's slowest speed (allowed: at least 10"),
    ("dataset-sensor-no-dof", ["dataset", "{d}/design_sensor_no_dof.toml", "--out",
                               "{d}/new"],
     "sensor 'casing99_y_disp': no DOF ('casing 99', 'y') in rig"),
    ("dataset-out-file", ["dataset", "{d}/design.toml", "--out", "{d}/file"],
     "--out {d}/file: is a file"),
    ("dataset-out-other-design", ["dataset", "{d}/design.toml", "--out", "{d}/other_dataset"],
     "--out {d}/other_dataset: holds another design (sampling.n is 1 there, 2 here; "
     "factors.gap_mm is [2.3] there, [1.9, 4.0] here)"),
    ("dataset-out-not-a-dataset", ["dataset", "{d}/design.toml", "--out", "{d}/not_a_dataset"],
     "is not empty and holds no dataset"),
    ("dataset-out-missing", ["dataset", "{d}/design.toml"], "--out is required"),
    ("dataset-jobs-zero", ["dataset", "{d}/design.toml", "--out", "{d}/new", "--jobs", "0"],
     "--jobs = 0 is out of range"),
    ("dataset-jobs-and-scheduler", ["dataset", "{d}/design.toml", "--out", "{d}/new",
                                    "--jobs", "2", "--scheduler", "tcp://127.0.0.1:1"],
     "--jobs and --scheduler exclude each other"),
    ("dataset-run-timeout-negative", ["dataset", "{d}/design.toml", "--out", "{d}/new",
                                      "--run-timeout", "-1"], "--run-timeout = -1 is out of range"),
    # --- train, evaluate, predict: nothing trained, nothing written ----
    ("train-out-file", ["train", "{d}/other_dataset", "--out", "{d}/file"],
     "--out {d}/file: is a file, not a folder"),
    ("train-out-not-a-model", ["train", "{d}/other_dataset", "--out", "{d}/not_a_dataset"],
     "--out {d}/not_a_dataset: is not empty and holds no model"),
    ("train-out-model-exists", ["train", "{d}/other_dataset", "--out", "{d}/model"],
     "--out {d}/model: holds a model already"),
    ("train-out-missing", ["train", "{d}/other_dataset"],
     "the following arguments are required: --out"),
    ("train-dataset-missing", ["train", "{d}/none", "--out", "{d}/new"],
     "{d}/none: not a rubdiag dataset folder (no design.toml)"),
    ("train-not-a-dataset", ["train", "{d}/not_a_dataset", "--out", "{d}/new"],
     "{d}/not_a_dataset: not a rubdiag dataset folder (no design.toml)"),
    ("train-unknown-estimator", ["train", "{d}/other_dataset", "--out", "{d}/new",
                                 "--estimator", "knn"],
     "argument --estimator: invalid choice: 'knn'"),
    ("train-n-splits-one", ["train", "{d}/other_dataset", "--out", "{d}/new", "--n-splits",
                            "1"], "--n-splits = 1 is out of range (allowed: >= 2)"),
    ("evaluate-model-missing", ["evaluate", "{d}/none", "{d}/other_dataset"],
     "{d}/none: no such folder"),
    ("evaluate-not-a-dataset", ["evaluate", "{d}/model", "{d}/not_a_dataset"],
     "{d}/not_a_dataset: not a rubdiag dataset folder"),
    ("predict-model-missing", ["predict", "{d}/none", "{d}/a.csv"], "{d}/none: no such folder"),
    ("predict-model-not-a-model", ["predict", "{d}/folder", "{d}/a.csv"],
     "{d}/folder: not a rubdiag model folder (no model.json)"),
    ("predict-model-damaged", ["predict", "{d}/damaged_model", "{d}/a.csv"],
     "{d}/damaged_model/model.skops: not a skops file"),
    ("predict-model-untrusted", ["predict", "{d}/untrusted_model", "{d}/a.csv"],
     "{d}/untrusted_model/model.skops: refused: it holds the type "
     "'sklearn.neighbors._classification.KNeighborsClassifier'"),
    ("predict-missing-channel", ["predict", "{d}/model", "{d}/b.csv"],
     "b.csv: channel 'shaft' is missing (the model needs shaft; the file has other"),
    ("predict-unknown-unit", ["predict", "{d}/model", "{d}/a.csv", "--unit", "shaft=furlong"],
     "unit 'furlong' is not known for a displacement channel (allowed: m, mm, um, µm, mil)"),
    ("predict-unit-not-a-channel", ["predict", "{d}/model", "{d}/a.csv", "--unit", "blade=mm"],
     "units: 'blade' is not a channel of the model (its channels: shaft)"),
    ("predict-unit-malformed", ["predict", "{d}/model", "{d}/a.csv", "--unit", "mm"],
     "--unit 'mm' is not CHANNEL=UNIT"),
    ("predict-fs-too-low", ["predict", "{d}/model", "{d}/slow.csv"],
     "slow.csv, window 0: fs = 300 Hz is too low for the model: its features reach 8.25x"),
    ("predict-column-not-found", ["predict", "{d}/model", "{d}/b.csv", "--column",
                                  "probe=shaft"], "b.csv: column 'probe' not found"),
    ("predict-column-not-a-channel", ["predict", "{d}/model", "{d}/b.csv", "--column",
                                      "other=blade"],
     "columns: 'other' is mapped to 'blade', not a channel of the model"),
    ("predict-too-short", ["predict", "{d}/model", "{d}/short.csv", "--speed-rpm", "1500"],
     "short.csv: the record lasts 0.01 s, shorter than one window of the model (1 s)"),
    ("predict-speed-not-estimable", ["predict", "{d}/model", "{d}/noise.csv"],
     "noise.csv, window 0: the speed cannot be estimated"),
    ("predict-speed-and-tacho", ["predict", "{d}/model", "{d}/a.csv", "--speed-rpm", "1500",
                                 "--tacho", "key"],
     "argument --tacho: not allowed with argument --speed-rpm"),
    ("predict-negative-speed", ["predict", "{d}/model", "{d}/a.csv", "--speed-rpm", "-1500"],
     "speed_rpm = -1500.0 is out of range"),
    ("predict-unknown-tacho", ["predict", "{d}/model", "{d}/a.csv", "--tacho", "key"],
     "a.csv: tacho column 'key' not found"),
    ("predict-missing-input", ["predict", "{d}/model", "{d}/none.csv"],
     "{d}/none.csv: no such file"),
    ("predict-dataset-with-speed", ["predict", "{d}/model", "{d}/other_dataset",
                                    "--speed-rpm", "1500"],
     "speed_rpm applies to signal files only"),
    ("predict-speeds-no-column", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                  "{d}/speeds_no_column.csv"],
     "{d}/speeds_no_column.csv: no column 'speed_rpm' (a speeds file has the columns file, "
     "speed_rpm; this one has file, rpm)"),
    ("predict-speeds-negative", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                 "{d}/speeds_negative.csv"],
     "{d}/speeds_negative.csv: speed_rpm of 'a.csv' = -1500 is out of range (allowed: > 0 "
     "rpm)"),
    ("predict-speeds-not-a-number", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                     "{d}/speeds_text.csv"],
     "speed_rpm of 'a.csv' = 'fast' has the wrong type (expected a number of rpm, or empty)"),
    ("predict-speeds-twice", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                              "{d}/speeds_twice.csv"], "'a.csv' is listed twice"),
    ("predict-speeds-input-missing", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                      "{d}/speeds_other.csv"],
     "{d}/speeds_other.csv: no speed for {d}/a.csv (every input file needs an entry, by its "
     "path or its file name; entries that name no input: z.csv)"),
    ("predict-speeds-missing", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                "{d}/none.csv"], "{d}/none.csv: no such file"),
    ("predict-speeds-and-speed-rpm", ["predict", "{d}/model", "{d}/a.csv", "--speeds",
                                      "{d}/speeds_negative.csv", "--speed-rpm", "1500"],
     "--speeds and --speed-rpm exclude each other"),
    ("predict-pattern-matches-nothing", ["predict", "{d}/model", "{d}/*.nothing"],
     "{d}/*.nothing: the pattern matches no file"),
    ("predict-folder-without-signals", ["predict", "{d}/model", "{d}/folder"],
     "{d}/folder: no signal file in the folder"),
    ("predict-out-unknown-format", ["predict", "{d}/model", "{d}/a.csv", "--out",
                                    "{d}/table.xlsx"],
     "--out {d}/table.xlsx: unknown table format '.xlsx' (allowed: .csv, .parquet, .pq, "
     ".json)"),
    ("predict-out-and-json", ["predict", "{d}/model", "{d}/a.csv", "--out", "{d}/t.csv",
                              "--json"], "--json prints the table; --out writes it"),
]

# entries whose check must come before any work: these functions must not be called
BEFORE_WORK = {"simulate-out-missing-folder", "simulate-out-folder",
               "simulate-out-folder-without-suffix",
               "features-csv-missing-folder", "features-csv-folder",
               "compare-out-missing-folder", "calibrate-out-missing-folder", "campbell-out-file",
               "table2-out-file", "plot-out-file", "simulate-output-too-large",
               "simulate-duration-huge", *(c[0] for c in CATALOGUE if c[0].startswith("dataset")),
               "train-out-file", "train-out-not-a-model", "train-out-model-exists",
               *(c[0] for c in CATALOGUE if "-cutoff-" in c[0])}
WORK = [("rubdiag.simulation", "simulate"), ("rubdiag.signal", "signal_features"),
        ("rubdiag.runs", "run_features"), ("rubdiag.modal", "calibrate"),
        ("rubdiag.modal", "campbell"), ("rubdiag.paper", "table2"),
        ("rubdiag.plotting._run", "save_run_figures"), ("rubdiag.dataset", "generate"),
        ("rubdiag.dataset._rows", "make_row"), ("rubdiag.learn._train", "train")]


def run_main(argv):
    try:
        return main(argv)
    except SystemExit as exc:      # argparse's usage errors
        return exc.code


@pytest.mark.parametrize(("argv", "fragment"), [c[1:] for c in CATALOGUE],
                         ids=[c[0] for c in CATALOGUE])
def test_bad_input_is_one_line_and_exit_2(request, d, capsys, monkeypatch, argv, fragment):
    if request.node.callspec.id in BEFORE_WORK:
        import functools
        import importlib

        # import them all first: a module imported under the patch would keep the fake
        modules = [importlib.import_module(module) for module, _ in WORK]
        for module, (_, name) in zip(modules, WORK, strict=True):
            # the fake keeps the signature: the command line reads its defaults from it
            @functools.wraps(getattr(module, name))
            def work(*args, _name=name, **kwargs):
                raise AssertionError(f"{_name}() ran before the output location was checked")
            monkeypatch.setattr(module, name, work)
    argv = [a.format(d=d) for a in argv]
    code = run_main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.endswith("\n"), err     # exactly one line
    assert err.startswith(f"rubdiag {argv[0]}: error: "), err
    assert fragment.format(d=d) in err
    assert "Traceback" not in err and "np.float64" not in err and "[Errno" not in err
    assert not (d / "new").exists()                # a failed command leaves no new folder
    assert sorted(p.name for p in (d / "not_a_dataset").iterdir()) == ["notes.txt"]
    assert sorted(p.name for p in (d / "other_dataset").iterdir()) == [
        "dataset.json", "design.toml", "features"]
    assert not any((d / "other_dataset" / "features").iterdir())


def test_catalogue_ids_are_unique():
    ids = [c[0] for c in CATALOGUE]
    assert len(ids) == len(set(ids)) and BEFORE_WORK <= set(ids)


def test_subprocess_smoke():
    result = subprocess.run([sys.executable, "-m", "rubdiag", "simulate", "--case", "1",
                             "--gap-mm", "-1"], capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr == ("rubdiag simulate: error: --gap-mm = -1 is out of range "
                             "(allowed: > 0 and <= 100)\n")
    assert result.stdout == ""
