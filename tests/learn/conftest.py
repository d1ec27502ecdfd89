"""A small simulated dataset shared by the classifier tests: 12 design points × 2
replicates of both cases, speeds at and below the critical, gaps from serious rub to none,
with waveforms. Made once per test process (about half a minute on one core)."""

from __future__ import annotations

import pytest

SMALL_DESIGN = """
[base]
rig = "paper"
duration_s = 0.75
discard_s = 0.25

[sampling]
method = "grid"
replicates = 2

[factors]
case = [1, 2]
speed_ratio = [0.9, 1.0]
gap_mm = [0.7, 1.6, 3.5]
"""


@pytest.fixture(scope="session")
def small_dataset(tmp_path_factory):
    """The folder of the small dataset (rows and waveforms)."""
    from rubdiag.dataset import Design, generate

    out = tmp_path_factory.mktemp("learn") / "small"
    generate(Design.from_toml(SMALL_DESIGN), out, jobs=1, progress=False, waveforms=True)
    return out


@pytest.fixture(scope="session")
def small_rows(small_dataset):
    """Its finished rows (rubdiag.learn.read_dataset)."""
    from rubdiag.learn import read_dataset

    return read_dataset(small_dataset)


#: A smaller, quicker dataset of the reduced model (one replicate, 0.5-s windows): the
#: documentation's commands run on it (test_predict_examples.py). About 6 s on one core.
TINY_DESIGN = """
[base]
rig = "paper"
duration_s = 0.6
discard_s = 0.1
reduced = true

[sampling]
method = "grid"
replicates = 1

[factors]
case = [1, 2]
speed_ratio = [0.9, 1.0]
gap_mm = [0.7, 1.6, 3.5]
"""


@pytest.fixture(scope="session")
def tiny_design():
    """The tiny dataset's design (TOML text)."""
    return TINY_DESIGN


@pytest.fixture(scope="session")
def tiny_dataset(tmp_path_factory):
    """The folder of the tiny dataset (rows and waveforms)."""
    from rubdiag.dataset import Design, generate

    out = tmp_path_factory.mktemp("learn") / "tiny"
    generate(Design.from_toml(TINY_DESIGN), out, jobs=1, progress=False, waveforms=True)
    return out


def _power_over_floor_db(dataset) -> dict:
    """Channel -> median over the rubbing runs of the power of its stored waveform over
    the analysis window, over the power of the design's noise floor (dB): read from the
    waveforms and design.toml, not through rubdiag.learn (what the default channel set
    is checked against)."""
    import json
    import tomllib

    import numpy as np

    from rubdiag.dataset import load, load_waveforms

    design = tomllib.loads((dataset / "design.toml").read_text())
    acquisition = json.loads((dataset / "dataset.json").read_text())["acquisition"]
    floor = {"displacement": design["noise"]["displacement_m"],
             "acceleration": design["noise"]["acceleration_m_s2"]}
    rows = load(dataset)
    powers: dict = {}
    for run_id in rows.loc[rows["rub"].astype(bool), "run_id"]:
        waves = load_waveforms(dataset, run_id)
        n = round(acquisition["window_s"] * acquisition["fs_hz"])
        window = waves[waves.index >= acquisition["discard_s"] - 1e-9].iloc[:n]
        for s in acquisition["sensors"]:
            x = window[s["name"]].to_numpy(np.float64)
            powers.setdefault(s["name"], []).append(np.var(x))
    return {s["name"]: 10 * np.log10(np.median(powers[s["name"]]) / floor[s["quantity"]] ** 2)
            for s in acquisition["sensors"]}


@pytest.fixture(scope="session")
def power_over_floor_db():
    """The function that measures a dataset's channels against their noise floor from its
    stored waveforms (``_power_over_floor_db``)."""
    return _power_over_floor_db
