"""A design expands into the runs it always did, on any number of workers.

``data/design_run_ids.csv`` holds every run of every shipped design (its run id, point id,
speed and gap) as the expansion made them before it computed each rotor once, in parallel
(``scripts/design_run_ids.py``). The ids hash the whole run description, speeds and gaps
included, so an equal id is an equal run."""

from __future__ import annotations

import csv

import pytest
from scripts_loader import load_script

from rubdiag.dataset import Design

SCRIPT = load_script("design_run_ids")


def reference(name: str) -> list[dict]:
    with open(SCRIPT.OUT, encoding="utf-8", newline="") as f:
        return [row for row in csv.DictReader(f) if row["design"] == name]


def test_the_reference_holds_every_shipped_design():
    names = {p.name for p in SCRIPT.DESIGNS.glob("*.toml")}
    with open(SCRIPT.OUT, encoding="utf-8", newline="") as f:
        assert {row["design"] for row in csv.DictReader(f)} == names


@pytest.mark.parametrize("name", ["faults_small.toml", "rub_classifier_lhs300.toml",
                                  "rub_lhs200.toml", "rub_runup_small.toml"])
def test_a_shipped_design_expands_into_its_reference_runs(name):
    assert SCRIPT.rows(SCRIPT.DESIGNS / name, jobs=2) == reference(name)


@pytest.mark.slow
def test_the_multi_fault_journal_design_expands_into_its_reference_runs():
    """640 runs on 32 rig variants: 8 rotors' critical speed maps, 16 thresholds of
    instability, 320 linear approaches (about 10 s of CPU on a cold cache)."""
    name = "faults_journal.toml"
    assert SCRIPT.rows(SCRIPT.DESIGNS / name, jobs=2) == reference(name)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["faults_bands.toml", "faults_bands_slice.toml"])
def test_the_speed_band_designs_expand_into_their_reference_runs(name):
    """960 and 320 runs on 81 rig variants, half of them rub runs whose gaps come from their
    linear approaches (about 25 s of CPU for the larger one)."""
    assert SCRIPT.rows(SCRIPT.DESIGNS / name, jobs=2) == reference(name)


RIG_FACTORS = """
[base]
rig = "paper"
duration_s = 1.2

[sampling]
method = "lhs"
n = 12
seed = 5

[factors]
case = [1, 2]
speed_ratio = {low = 0.9, high = 1.1}
interference_ratio = {low = 1.2, high = 3.0}
disc_mass_scale = [0.9, 1.1]
casing_stiffness_scale = [0.5, 2.0]
damping_ratio = [0.035, 0.045]
"""


def test_runs_on_two_workers_are_the_runs_of_one_and_of_each_point_alone():
    """Rig variants (their critical speeds) and rub approaches computed on worker
    processes: the same runs, to the bit, as in this process and as each run made alone."""
    design = Design.from_toml(RIG_FACTORS)
    alone = [design.design_run(k) for k in range(design.n)]
    for jobs in (1, 2):
        runs = Design.from_toml(RIG_FACTORS).runs(jobs=jobs)
        assert [item.run_id for item in runs] == [item.run_id for item in alone]
        assert [item.run for item in runs] == [item.run for item in alone]
    assert len({item.run.rig for item in alone}) > 4      # the variants were computed apart
    assert len({item.run.gap_m for item in alone}) == design.n


def test_a_point_that_fails_is_named_as_it_was():
    """A run that cannot be made stops the expansion with its point's index and levels,
    the first such point in the design's order, whatever computed its parts."""
    text = RIG_FACTORS.replace("seed = 5", "seed = 8") + "unbalance_scale = [0.0, 1.0]\n"
    design = Design.from_toml(text)
    first = next(k for k, p in enumerate(design.points()) if p["unbalance_scale"] == 0.0)
    assert first > 0                # a point before it is made, approach and all
    with pytest.raises(ValueError, match=rf"^point {first} \(case = .*unbalance_scale = 0, "
                                         r".*\): factors.interference_ratio = .*approach is 0"):
        design.runs(jobs=2)


def test_a_threshold_read_from_the_disk_cache_is_the_one_searched(tmp_path, monkeypatch):
    from rubdiag import _cache
    from rubdiag._blas import one_thread
    from rubdiag.modal import _stability as stability
    from rubdiag.model import preset_rig
    from rubdiag.simulation._rig_cache import forward_critical_speeds, whirl_threshold_speed

    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    rig = preset_rig("paper-journal")
    with one_thread():
        critical = forward_critical_speeds(rig, 2)
        searched = whirl_threshold_speed(rig, critical)
    assert len(list(tmp_path.glob("whirl-threshold-*.npz"))) == 1

    def search(*args, **kwargs):
        raise AssertionError("a cached threshold was searched again")

    monkeypatch.setattr(stability, "threshold_speed", search)
    assert whirl_threshold_speed(rig, critical) == searched
    assert 0.5 * critical[0] < searched < 2.0 * critical[1]
