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
