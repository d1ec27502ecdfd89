"""The command line's entry: --debug shows an error's traceback; every --rig help names the
presets that --rig accepts."""

from __future__ import annotations

import argparse

from rubdiag.cli import build_parser, main
from rubdiag.model import PRESETS

BAD = ["simulate", "--case", "1", "--gap-mm", "-1"]


def test_debug_prints_the_traceback_of_an_error(capsys):
    assert main(["--debug", *BAD]) == 2
    err = capsys.readouterr().err
    assert err.startswith("Traceback (most recent call last):")
    assert err.rstrip().splitlines()[-1] == (
        "ValueError: --gap-mm = -1 is out of range (allowed: > 0 and <= 100)")


def test_without_debug_an_error_is_one_line(capsys):
    assert main(BAD) == 2
    assert capsys.readouterr().err == ("rubdiag simulate: error: --gap-mm = -1 is out of "
                                       "range (allowed: > 0 and <= 100)\n")


def _rig_helps() -> dict[str, str]:
    [commands] = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    return {name: action.help for name, sub in commands.choices.items()
            for action in sub._actions if "--rig" in action.option_strings}


def test_every_rig_help_names_every_preset():
    helps = _rig_helps()
    assert {"simulate", "modal", "table2", "runup"} <= set(helps)
    for command, text in helps.items():
        assert all(name in text for name in PRESETS), (command, text)
