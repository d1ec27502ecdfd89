"""A design's model: ``[base] reduced`` / ``reduction_cutoff_hz`` reach every run,
the resolved TOML carries them (and stays as it was for the full model), bad values are one
line naming the key. Nothing here simulates."""

import pytest

from rubdiag.dataset import Design
from rubdiag.reduce import DEFAULT_CUTOFF_HZ, Reduction

BASE = """
[base]
critical_speeds_rad_s = [150.0, 600.0]
{model}
[sampling]
method = "grid"
replicates = 2

[factors]
case = [1, 2]
speed_ratio = [1.0]
gap_mm = [1.9, 2.3]
"""


def design(model: str = "") -> Design:
    return Design.from_toml(BASE.format(model=model))


def test_the_default_is_the_full_model_and_its_resolved_form_is_unchanged():
    full = design()
    assert full.reduction is None
    assert {item.run.reduction for item in full.runs()} == {None}
    assert all(item.run.model_kind == "full" for item in full.runs())
    # no model keys in the resolved form: a folder made before reductions existed holds
    # the same design.toml, so a job can still resume it
    assert "reduc" not in full.to_toml()
    assert design("reduced = false") == full
    assert design("reduced = false").to_toml() == full.to_toml()


@pytest.mark.parametrize(("model", "cutoff_hz"), [
    ("reduced = true", DEFAULT_CUTOFF_HZ),
    ("reduced = true\nreduction_cutoff_hz = 1824.0", 1824.0),
    ("reduction_cutoff_hz = 1824.0", 1824.0),              # the cutoff implies reduced
    ("reduction_cutoff_hz = 3000", 3000.0),
])
def test_reduced_designs_reduce_every_run(model, cutoff_hz):
    reduced, full = design(model), design()
    assert reduced.reduction == Reduction(cutoff_hz)
    runs, full_runs = reduced.runs(), full.runs()
    assert len(runs) == len(full_runs) == 8
    for item, twin in zip(runs, full_runs, strict=True):
        assert item.run.reduction == Reduction(cutoff_hz)
        assert item.run.model_kind == "reduced"
        assert item.point == twin.point and item.replicate == twin.replicate
        # the same cell of the other model is another simulation: both ids differ
        assert item.run_id != twin.run_id and item.point_id != twin.point_id
    # replicates still share their point id
    assert len({i.point_id for i in runs}) == 4 and len({i.run_id for i in runs}) == 8


def test_resolved_form_carries_the_reduction_and_round_trips():
    reduced = design("reduction_cutoff_hz = 1824")
    text = reduced.to_toml()
    assert "\nreduced = true\nreduction_cutoff_hz = 1824.0\n" in text
    assert reduced.to_dict()["base"]["reduced"] is True
    again = Design.from_toml(text)
    assert again == reduced and again.to_toml() == text
    assert [i.run_id for i in again.runs()] == [i.run_id for i in reduced.runs()]
    assert Design.from_dict(reduced.to_dict()) == reduced


def test_the_python_form_takes_a_reduction():
    reduced = design("reduced = true")
    made = Design(rig=reduced.rig, factors=reduced.factors, replicates=2,
                  critical_speeds_rad_s=(150.0, 600.0), reduction=Reduction())
    assert made == reduced
    with pytest.raises(ValueError, match=r"^reduction = 'float' has the wrong type"):
        Design(rig=reduced.rig, factors=reduced.factors, reduction=2000.0)


@pytest.mark.parametrize(("model", "message"), [
    ("reduced = false\nreduction_cutoff_hz = 1824.0",
     r"base.reduction_cutoff_hz = 1824.0 is given with base.reduced = false"),
    ("reduction_cutoff_hz = -5.0", r"base.reduction_cutoff_hz = -5.0 is out of range "
     r"\(allowed: >= 1 and <= 1e\+06\)"),
    ("reduced = true\nreduction_cutoff_hz = 0.0", r"base.reduction_cutoff_hz = 0.0 is out of "
     r"range"),
    ("reduction_cutoff_hz = nan", r"base.reduction_cutoff_hz = nan is out of range"),
    ('reduction_cutoff_hz = "2 kHz"', r"base.reduction_cutoff_hz = '2 kHz' has the wrong type"),
    ('reduced = "yes"', r"base.reduced = 'yes' has the wrong type \(expected true or false\)"),
    ("reduced = 1", r"base.reduced = 1 has the wrong type"),
    ("reduction = 2000.0", r"unknown key 'base.reduction' \(allowed: .*reduced, "
     r"reduction_cutoff_hz"),
])
def test_bad_model_keys_are_one_line_naming_the_key(model, message):
    with pytest.raises(ValueError, match=f"^{message}") as info:
        design(model)
    assert "\n" not in str(info.value)


def test_a_reduction_a_design_file_cannot_say_is_refused():
    # the resolved form has no key for tip_rotations, so a design must not carry False
    import dataclasses

    with pytest.raises(ValueError, match=r"^reduction\.tip_rotations = False is not available"):
        dataclasses.replace(design("reduced = true"), reduction=Reduction(tip_rotations=False))
