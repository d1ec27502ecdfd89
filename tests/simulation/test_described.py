"""A run's description as data follows one rule: every field is written, recursively, but a
field declared WHEN_SET is written only when set, so that adding such a field to a
description leaves every existing description (and run id) as it was."""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field

from rubdiag.model._io import rig_to_dict
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run
from rubdiag.simulation._described import WHEN_SET, described
from rubdiag.simulation._faults import Crack, Faults, Looseness
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict


@dataclass(frozen=True)
class Part:
    size: float
    tags: tuple = ()


@dataclass(frozen=True)
class Whole:
    name: str
    part: Part | None = None


@dataclass(frozen=True)
class WholeGrown(Whole):
    """:class:`Whole` with two fields added later, declared as the rule asks."""

    colour: str | None = field(default=None, metadata=WHEN_SET)
    spare: Part | None = field(default=None, metadata=WHEN_SET)


def test_a_field_added_when_set_leaves_the_description_as_it_was():
    for part in (None, Part(1.5, ("a", "b"))):
        assert described(WholeGrown("w", part)) == described(Whole("w", part))
    assert described(Whole("w", Part(1.5, ("a", "b")))) == {
        "name": "w", "part": {"size": 1.5, "tags": ["a", "b"]}}
    grown = described(WholeGrown("w", None, colour="red", spare=Part(2.0)))
    assert grown == {"name": "w", "part": None, "colour": "red",
                     "spare": {"size": 2.0, "tags": []}}


def test_fields_of_the_first_release_are_written_even_when_none():
    """A run without rub has no gap and no contact law: both are written (as null), as
    they always were; the fields added later are left out."""
    run = Run.paper_case(1, None)
    data = run_to_dict(run)
    assert data["gap_m"] is None and data["contact"] is None
    added = {f.name for f in dataclasses.fields(Run) if f.metadata == WHEN_SET}
    assert added == {"reduction", "speed_profile", "static_load", "faults", "step_error",
                     "dt_max_s", "seal_clearance_m"}
    assert not added & set(data)
    assert data["rig"] == rig_to_dict(run.rig)
    assert run_from_dict(json.loads(json.dumps(data))) == run


def test_nested_descriptions_follow_the_same_rule():
    run = Run.paper_case(1, 2.0, faults=Faults(crack=Crack(element=10, depth_ratio=0.3)),
                         reduction=Reduction(shaft_nodes=(4,)))
    data = run_to_dict(run)
    # the crack's fault set: misalignment (first release) written as null, looseness not
    assert data["faults"] == {"misalignment": None,
                              "crack": {"element": 10, "depth_ratio": 0.3, "position": 0.5,
                                        "law": "mayes", "angle": 0.0}}
    # a reduction describes itself
    assert data["reduction"] == Reduction(shaft_nodes=(4,)).description()
    assert run_from_dict(json.loads(json.dumps(data))) == run
    loose = Faults(looseness=Looseness(bearing=0, preload_n=100.0))
    assert set(described(loose)) == {"misalignment", "crack", "looseness"}
