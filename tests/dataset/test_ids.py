"""Run and point identities: stable across processes (another hash seed), one per
simulation (every Run field counts, the label does not), shared by replicates."""

import dataclasses
import json
import os
import re
import subprocess
import sys

import pytest

from rubdiag.dataset import SCHEMA_VERSION, Design, canonical_run, point_id, run_id
from rubdiag.dataset import _ids as ids_module
from rubdiag.model import Unbalance
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, Sensor
from rubdiag.simulation._faults import Crack, Faults
from rubdiag.simulation._run_dict import run_to_dict
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._static_load import StaticLoad

DESIGN = """
[base]
critical_speeds_rad_s = [157.0, 597.0]
[sampling]
method = "lhs"
n = 6
seed = 3
replicates = 2
[factors]
case = [1, 2]
speed_ratio = {low = 0.9, high = 1.1}
gap_mm = {low = 1.0, high = 3.0}
"""

SCRIPT = f"""
import json
from rubdiag.dataset import Design
runs = Design.from_toml({DESIGN!r}).runs()
print(json.dumps([[r.point_id, r.run_id] for r in runs]))
"""


@pytest.fixture(scope="module")
def run(paper_rig):
    return Run.paper_case(1, 2.3)


def test_ids_are_the_same_in_another_process():
    mine = [[r.point_id, r.run_id] for r in Design.from_toml(DESIGN).runs()]
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                         env=env, check=True)
    assert json.loads(out.stdout) == mine
    assert len(mine) == 12
    assert len({p for p, _ in mine}) == 6 and len({r for _, r in mine}) == 12


def test_ids_are_16_hex_digits(run):
    assert re.fullmatch(r"[0-9a-f]{16}", run_id(run))
    assert re.fullmatch(r"[0-9a-f]{16}", point_id(run))
    assert run_id(run) != point_id(run)


def test_known_value():
    """The canonical form pinned: if this changes, every stored dataset's ids change (raise
    SCHEMA_VERSION when the meaning changed, and update the value here)."""
    data = {"b": [1, 2.5, -0.0], "a": {"y": True, "x": None, "z": "text"}}
    text = '{"run":{"a":{"x":null,"y":true,"z":"text"},"b":[1.0,2.5,0.0]},"schema":1}'
    import hashlib

    assert SCHEMA_VERSION == 1
    assert ids_module._digest("run", data) == hashlib.sha256(text.encode()).hexdigest()[:16]


def _changes(run):
    """One physically different value for every Run field but the label."""
    rig = run.rig
    return {
        "rig": dataclasses.replace(rig, bearings=(dataclasses.replace(rig.bearings[0],
                                                                      k_y_n_m=4e8),
                                                  *rig.bearings[1:])),
        "speed_rad_s": run.speed_rad_s * (1 + 1e-12),
        "unbalance": Unbalance(run.unbalance.magnitudes_kg_m, (0.0, 1e-9)),
        "gap_m": 2.2e-3,
        "duration_s": 2.0,
        "discard_s": 0.25,
        "dt_s": 2e-5,
        "dt_min_s": 1e-7,
        "fixed_step": True,
        "output_rate_hz": 5000.0,
        "contact": dataclasses.replace(rig.contact, friction_coefficient=0.3),
        "gap_ramp_s": 0.099,
        "sensors": (Sensor("shaft 4", "y"),),
        "reduction": Reduction(),
        "speed_profile": SpeedProfile((0.0, 1.0), (run.speed_rad_s, 1.5 * run.speed_rad_s)),
        "static_load": StaticLoad(gravity_m_s2=-9.81),
        "faults": Faults(crack=Crack(element=10, depth_ratio=0.3)),
        "step_error": 1e-5,
    }


def test_changing_any_field_changes_the_run_id(run):
    changes = _changes(run)
    # dt_max_s needs a step_error: test_step_settings_change_the_run_id_not_the_noise
    # seal_clearance_m needs a rig with a seal: test_seal_clearance_changes_the_run_id
    fields = {f.name for f in dataclasses.fields(Run)} - {"label", "dt_max_s",
                                                          "seal_clearance_m"}
    assert set(changes) == fields, "a new Run field: add it here"
    ids = {run_id(run)}
    for name, value in changes.items():
        other = dataclasses.replace(run, **{name: value})
        assert getattr(other, name) != getattr(run, name)
        ids.add(run_id(other))
    assert len(ids) == len(changes) + 1


def test_seal_clearance_changes_the_run_id(run):
    """A run's seal clearance is part of its description when set, and only then: the same
    rig's runs without it keep the ids they had."""
    from rubdiag.model import StatorContact

    sealed = dataclasses.replace(run, rig=dataclasses.replace(run.rig, stator_contacts=(
        StatorContact(node=15, clearance_m=0.05, stiffness_n_m=8e7),)))
    ids = {run_id(sealed)}
    for clearance in (0.05, 1e-4, 1.0001e-4):
        ids.add(run_id(dataclasses.replace(sealed, seal_clearance_m=clearance)))
    assert len(ids) == 4
    assert "seal_clearance_m" not in run_to_dict(sealed)
    with pytest.raises(ValueError, match="seal_clearance_m is given but the rig has no stator"):
        dataclasses.replace(run, seal_clearance_m=1e-4)


def test_step_settings_change_the_run_id_not_the_noise(run):
    """A run with long steps is another run (another id) measured with the noise of its
    twin at 10 µs; a run without long steps draws its noise from its run id."""
    from rubdiag.dataset._ids import noise_id

    long = dataclasses.replace(run, step_error=1e-5)
    longer = dataclasses.replace(long, dt_max_s=8 * run.dt_s)
    assert len({run_id(run), run_id(long), run_id(longer)}) == 3
    assert noise_id(run) == noise_id(long) == noise_id(longer) == run_id(run)
    other = dataclasses.replace(long, gap_ramp_s=0.099)
    assert noise_id(other) != noise_id(long)


def test_point_id_ignores_the_start_history_only(run):
    points = set()
    for name, value in _changes(run).items():
        other = dataclasses.replace(run, **{name: value})
        same = point_id(other) == point_id(run)
        assert same == (name == "gap_ramp_s"), name
        points.add(point_id(other))
    assert len(points) == len(_changes(run))


def test_equal_runs_have_equal_ids(run):
    same = (dataclasses.replace(run, label="another label"),
            dataclasses.replace(run, contact=run.rig.contact))   # the law in force, spelt out
    for other in same:
        assert (run_id(other), point_id(other)) == (run_id(run), point_id(run))
    # an int and a float compare equal in a Run, and hash equal
    assert run_id(dataclasses.replace(run, speed_rad_s=157)) == run_id(
        dataclasses.replace(run, speed_rad_s=157.0))


def test_canonical_run_is_the_result_files_description(run):
    from rubdiag.simulation._run_dict import run_to_dict

    stored = run_to_dict(run)
    canonical = canonical_run(run)
    assert set(stored) - set(canonical) == {"label"}
    assert all(canonical[k] == stored[k] for k in canonical if k != "contact")
    assert canonical["contact"] == run_to_dict(
        dataclasses.replace(run, contact=run.rig.contact))["contact"]


def test_schema_version_is_part_of_the_id(run, monkeypatch):
    before = run_id(run), point_id(run)
    monkeypatch.setattr(ids_module, "SCHEMA_VERSION", SCHEMA_VERSION + 1)
    after = run_id(run), point_id(run)
    assert before[0] != after[0] and before[1] != after[1]


def test_a_run_read_back_from_a_result_file_keeps_its_id(run):
    from rubdiag.simulation._run_dict import run_from_dict, run_to_dict

    for other in (run, dataclasses.replace(run, contact=dataclasses.replace(
            run.rig.contact, friction_coefficient=0.25), gap_ramp_s=0.101)):
        stored = json.loads(json.dumps(run_to_dict(other)))     # as in a result's meta
        assert run_id(run_from_dict(stored)) == run_id(other)
        assert point_id(run_from_dict(stored)) == point_id(other)
