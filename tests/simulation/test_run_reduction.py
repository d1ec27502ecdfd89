"""A run's model: ``Run.reduction`` asks for the reduced-order model; it is part of
the run's identity and of its result file, and a run of the full model is described, hashed
and stored exactly as before the field existed."""

import dataclasses
import json
import warnings

import numpy as np
import pytest

import rubdiag
from rubdiag._check import ParameterTypeError
from rubdiag.dataset import point_id, run_id
from rubdiag.reduce import DEFAULT_CUTOFF_HZ, Reduction
from rubdiag.simulation import GapRampInWindow, Run, load_result, simulate
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict


@pytest.fixture(scope="module")
def full():
    rig = rubdiag.paper_rig()
    return Run(rig=rig, speed_rad_s=157.0, unbalance=rig.unbalance(1), gap_m=2.3e-3)


@pytest.fixture(scope="module")
def reduced(full):
    return dataclasses.replace(full, reduction=Reduction())


def test_default_is_the_full_model(full, reduced):
    assert full.reduction is None and full.model_kind == "full"
    assert reduced.reduction.cutoff_hz == DEFAULT_CUTOFF_HZ
    assert reduced.model_kind == "reduced"
    assert full != reduced


@pytest.mark.parametrize("bad", [2000.0, {"cutoff_hz": 2000.0}, "reduced", True])
def test_a_reduction_of_the_wrong_type_is_refused(full, bad):
    with pytest.raises(ParameterTypeError, match=r"^reduction = '\w+' has the wrong type "
                       r"\(expected a Reduction or None\)$"):
        dataclasses.replace(full, reduction=bad)


def test_a_full_run_is_described_as_before(full):
    """No ``reduction`` key: the description (so the result file's meta) has the fields it
    had before, and the ids are those rubdiag gave this run before the field existed."""
    data = run_to_dict(full)
    assert "reduction" not in data
    assert set(data) == {f.name for f in dataclasses.fields(Run)} - {"reduction",
                                                                      "speed_profile",
                                                                      "static_load", "faults",
                                                                      "step_error", "dt_max_s",
                                                                      "seal_clearance_m"}
    # computed with rubdiag at ec17223 (Run without a reduction field), same rig and values
    assert (run_id(full), point_id(full)) == ("c9d0d9212e38d531", "5ad352256e5af7af")


def test_a_reduced_run_is_another_simulation(full, reduced):
    assert run_to_dict(reduced)["reduction"] == {"cutoff_hz": DEFAULT_CUTOFF_HZ,
                                                 "tip_rotations": True}
    # another model is not a replicate: both ids differ
    assert run_id(reduced) != run_id(full)
    assert point_id(reduced) != point_id(full)
    other = dataclasses.replace(full, reduction=Reduction(cutoff_hz=1824.0))
    no_tips = dataclasses.replace(full, reduction=Reduction(tip_rotations=False))
    assert len({run_id(full), run_id(reduced), run_id(other), run_id(no_tips)}) == 4
    # the same cutoff spelt as an int is the same run
    same = dataclasses.replace(full, reduction=Reduction(cutoff_hz=2000))
    assert (run_id(same), point_id(same)) == (run_id(reduced), point_id(reduced))


@pytest.mark.parametrize("reduction", [None, Reduction(1824.0),
                                       Reduction(tip_rotations=False)])
def test_description_round_trips_through_json(full, reduction):
    run = dataclasses.replace(full, reduction=reduction)
    back = run_from_dict(json.loads(json.dumps(run_to_dict(run))))
    assert back == run and back.reduction == run.reduction
    assert run_id(back) == run_id(run)


def test_a_reduction_saved_before_tip_rotations_is_read_as_without_them(full):
    """Result files written before ``tip_rotations`` existed hold ``{"cutoff_hz": …}``: their
    runs kept only the contact DOFs, so they must not pass for today's default model."""
    data = run_to_dict(dataclasses.replace(full, reduction=Reduction()))
    data["reduction"] = {"cutoff_hz": 2000.0}
    assert run_from_dict(data).reduction == Reduction(tip_rotations=False)


@pytest.mark.parametrize("bad", [1, "yes", None])
def test_tip_rotations_must_be_a_bool(bad):
    with pytest.raises(ValueError, match=r"^tip_rotations = .* has the wrong type \(expected "
                       r"True or False\)$"):
        Reduction(tip_rotations=bad)


def test_model_in_the_summary_and_through_a_result_file(tmp_path):
    """A short real run, saved and read back as it is and as the description of a reduced run
    (the file keeps the description; what simulated it is not the point here)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GapRampInWindow)
        run = Run.paper_case(1, 2.3, speed_rpm=1500, duration_s=0.02, discard_s=0.01)
    result = simulate(run)
    assert result.summary()["model"] == "full"
    as_reduced = dataclasses.replace(
        result, run=dataclasses.replace(run, reduction=Reduction(cutoff_hz=1824.0)))
    assert as_reduced.summary()["model"] == "reduced"
    for original in (result, as_reduced):
        back = load_result(original.save(tmp_path / f"{original.run.model_kind}.npz"))
        assert back.run == original.run
        assert back.run.reduction == original.run.reduction
        assert back.summary()["model"] == original.run.model_kind
    with np.load(tmp_path / "full.npz") as archive:
        meta = json.loads(str(archive["meta"]))
    assert "reduction" not in meta["run"]
