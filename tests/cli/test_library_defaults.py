"""Options that stand for a library parameter take its default, and its choices, from the
library: each is compared with the library's own value, and follows it when the library's
value changes; every option named after a Run field is one of them or leaves the field to
the run."""

from __future__ import annotations

import argparse
import dataclasses
import inspect

import pytest

from rubdiag.cli import build_parser

# (command, option) -> (module, owner, parameter): where the library defines its default
RUN = ("rubdiag.simulation._run", "Run")
CRACK = ("rubdiag.simulation._faults", "Crack")
LOOSENESS = ("rubdiag.simulation._faults", "Looseness")
SETTINGS = ("rubdiag.dataset._faults", "FaultSettings")
FAULT_RUNS = ("rubdiag.runs._faults", "fault_runs")
TRAIN = ("rubdiag.learn._train", "train")
MIRRORS = {
    ("simulate", "--duration-s"): (*RUN, "duration_s"),
    ("simulate", "--discard-s"): (*RUN, "discard_s"),
    ("simulate", "--dt-s"): (*RUN, "dt_s"),
    ("runup", "--dt-s"): (*RUN, "dt_s"),
    ("table2", "--duration-s"): ("rubdiag.paper._table2", "table2", "duration_s"),
    ("table2", "--discard-s"): ("rubdiag.paper._table2", "table2", "discard_s"),
    ("runup", "--hold-s"): ("rubdiag.runs._runup", "ramp_run", "hold_s"),
    ("runup", "--point"): ("rubdiag.runs._runup", "runup_orders", "point"),
    ("runup", "--revs-per-bin"): ("rubdiag.runs._runup", "runup_orders", "revs_per_bin"),
    ("faults", "--interference"): (*FAULT_RUNS, "interference"),
    ("faults", "--crack-depth"): (*FAULT_RUNS, "crack_depth"),
    ("faults", "--misalignment-angle-mrad"): (*FAULT_RUNS, "misalignment_angle_mrad"),
    ("faults", "--loose-preload-n"): (*FAULT_RUNS, "loose_preload_n"),
    ("faults", "--duration-s"): (*FAULT_RUNS, "duration_s"),
    ("campbell", "--n-modes"): ("rubdiag.modal._campbell", "campbell", "n_modes"),
    ("calibrate", "--knobs"): ("rubdiag.modal._calibrate", "calibrate", "knobs"),
    ("train", "--target"): (*TRAIN, "target"),
    ("train", "--estimator"): (*TRAIN, "estimator"),
    ("train", "--split"): (*TRAIN, "split"),
    ("train", "--channels"): (*TRAIN, "channels"),
    ("train", "--seed"): (*TRAIN, "seed"),
    ("train", "--n-splits"): ("rubdiag.learn._splits", "folds", "n_splits"),
    **{(command, "--rotation"): ("rubdiag.signal._fullspectrum", "orbit_features", "rotation")
       for command in ("features", "compare")},
    **{(command, option): source for command in ("simulate", "runup")
       for option, source in {
           "--crack-law": (*CRACK, "law"),
           "--loose-direction": (*LOOSENESS, "direction"),
           "--loose-stiffness-n-m": (*LOOSENESS, "loose_stiffness_n_m"),
           "--coupling-node": (*SETTINGS, "coupling_node"),
           "--drive-torque-nm": (*SETTINGS, "drive_torque_n_m"),
           "--spacer-length-mm": (*SETTINGS, "spacer_length_m"),
       }.items()},
}
#: options whose unit differs from the library's: the factor from its unit to theirs
SCALES = {"--spacer-length-mm": 1e3}
# (command, option) -> (module, tuple of the allowed values)
CHOICES = {
    **{(command, "--crack-law"): ("rubdiag.simulation._crack", "LAWS")
       for command in ("simulate", "runup")},
    **{(command, "--loose-direction"): ("rubdiag.simulation._faults", "DIRECTIONS")
       for command in ("simulate", "runup")},
    ("train", "--target"): ("rubdiag.learn", "TARGETS"),
    ("train", "--estimator"): ("rubdiag.learn", "ESTIMATORS"),
    ("features", "--rotation"): ("rubdiag.signal._fullspectrum", "ROTATIONS"),
}


def options() -> dict[tuple[str, str], argparse.Action]:
    """(command, option) -> the option's action, for every option of every command."""
    [commands] = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    return {(name, option): action for name, sub in commands.choices.items()
            for action in sub._actions for option in action.option_strings}


def owner_of(module: str, owner: str):
    import importlib

    return getattr(importlib.import_module(module), owner)


def library_default(module: str, owner: str, name: str):
    found = owner_of(module, owner)
    if dataclasses.is_dataclass(found):
        return {f.name: f.default for f in dataclasses.fields(found)}[name]
    return inspect.signature(found).parameters[name].default


def shown(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


@pytest.mark.parametrize("key", list(MIRRORS), ids=" ".join)
def test_the_default_is_the_librarys(key):
    action = options()[key]
    expected = library_default(*MIRRORS[key]) * SCALES.get(key[1], 1)
    assert action.default == expected
    # the help states it (a default of several values as they are typed: space-separated)
    words = expected if isinstance(expected, tuple) else (expected,)
    assert all(shown(word) in action.help for word in words), action.help


@pytest.mark.parametrize("key", list(MIRRORS), ids=" ".join)
def test_the_default_follows_the_library(key, monkeypatch):
    """The library's value changed, a parser built afterwards has the new one: the option
    reads it, it does not repeat it."""
    module, owner, name = MIRRORS[key]
    value = library_default(module, owner, name)
    other = {int: lambda: value + 1, float: lambda: value + 0.125, str: lambda: value + "x",
             tuple: lambda: (*value, "x")}[type(value)]()
    found = owner_of(module, owner)
    if dataclasses.is_dataclass(found):
        monkeypatch.setattr(found.__dataclass_fields__[name], "default", other)
    else:
        parameters = inspect.signature(found).parameters
        if parameters[name].kind is inspect.Parameter.KEYWORD_ONLY:
            monkeypatch.setattr(found, "__kwdefaults__", {**found.__kwdefaults__, name: other})
        else:
            positional = [p for p in parameters.values() if p.default is not p.empty
                          and p.kind is not inspect.Parameter.KEYWORD_ONLY]
            monkeypatch.setattr(found, "__defaults__", tuple(
                other if p.name == name else p.default for p in positional))
    assert options()[key].default == other * SCALES.get(key[1], 1)


@pytest.mark.parametrize("key", list(CHOICES), ids=" ".join)
def test_the_choices_are_the_librarys(key):
    action = options()[key]
    allowed = tuple(owner_of(*CHOICES[key]))
    assert tuple(action.choices) == allowed
    assert all(str(choice) in action.help for choice in allowed), action.help
    command, option = key
    required = {"simulate": ["--case", "1", "--gap-mm", "2"],
                "runup": ["--case", "1", "--from-rpm", "1000", "--to-rpm", "2000",
                          "--rate-rpm-s", "300", "--out", "x"],
                "train": ["data", "--out", "x"],
                "features": ["x.csv", "--pair", "y,z"]}[command]
    for choice in allowed:
        args = build_parser().parse_args([command, *required, f"{option}={choice}"])
        assert getattr(args, action.dest) == choice


def test_an_option_named_after_a_run_field_reads_it_or_leaves_it_to_the_run():
    """Every option whose value is a Run field of the same name (duration_s, dt_s …) is
    one of MIRRORS (the Run's default, or the default of the function the command calls)
    or has no default of its own (None: the run's)."""
    from rubdiag.simulation import Run

    fields = {f.name for f in dataclasses.fields(Run)}
    for key, action in options().items():
        if action.dest in fields and action.default is not None:
            assert key in MIRRORS, key


def test_the_help_names_every_feature_family_and_knob():
    from rubdiag.learn._features import DEFAULT_FAMILIES, FAMILIES
    from rubdiag.modal import KNOBS

    found = options()
    families = found[("train", "--families")].help
    assert all(name in families for name in FAMILIES), families
    assert ", ".join(DEFAULT_FAMILIES) in families
    knobs = found[("calibrate", "--knobs")].help
    assert all(name in knobs for name in KNOBS), knobs
