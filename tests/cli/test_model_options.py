"""``--reduced [--cutoff-hz HZ]`` of ``simulate`` and ``table2``: the options reach
the runs (the simulator replaced: the run it is given is the point), and one short real run
prints its model (bad values: test_errors.py)."""

import json
import warnings

import pytest

import rubdiag.paper
import rubdiag.simulation
from rubdiag.cli import build_parser, main
from rubdiag.reduce import DEFAULT_CUTOFF_HZ, Reduction

SIM = ["simulate", "--case", "1", "--gap-mm", "1.9", "--speed-rpm", "1500",
       "--duration-s", "0.05", "--discard-s", "0.01"]


class Stop(Exception):
    """Raised by the fake simulator once it has the run (the CLI lets it through)."""


@pytest.fixture
def given_run(monkeypatch):
    runs = []

    def fake(run, progress=None, **_):
        runs.append(run)
        raise Stop

    monkeypatch.setattr(rubdiag.simulation, "simulate", fake)
    return runs


@pytest.mark.parametrize(("options", "reduction"), [
    ([], None),
    (["--reduced"], Reduction()),
    (["--reduced", "--cutoff-hz", "1824"], Reduction(cutoff_hz=1824.0)),
    (["--cutoff-hz", "1824", "--reduced"], Reduction(cutoff_hz=1824.0)),
])
def test_simulate_options_reach_the_run(given_run, options, reduction):
    with warnings.catch_warnings(), pytest.raises(Stop):
        warnings.simplefilter("ignore")
        main([*SIM, *options])
    (run,) = given_run
    assert run.reduction == reduction
    assert run.model_kind == ("full" if reduction is None else "reduced")
    assert run.gap_m == pytest.approx(1.9e-3) and run.speed_rpm == pytest.approx(1500)


@pytest.mark.parametrize(("options", "reduction"), [
    ([], None),
    (["--reduced"], Reduction()),
    (["--reduced", "--cutoff-hz", "3000"], Reduction(cutoff_hz=3000.0)),
])
def test_table2_options_reach_the_reproduction(monkeypatch, tmp_path, options, reduction):
    calls = []

    def fake(out_dir, **kwargs):
        calls.append(kwargs)
        raise Stop

    monkeypatch.setattr(rubdiag.paper, "table2", fake)
    with pytest.raises(Stop):
        main(["table2", "--out", str(tmp_path), "--no-figures", *options])
    (kwargs,) = calls
    assert kwargs["reduction"] == reduction


def test_help_states_the_default_cutoff():
    sub = build_parser()._subparsers._group_actions[0].choices
    for command in ("simulate", "table2"):
        text = " ".join(sub[command].format_help().split())
        assert "--reduced" in text
        assert f"default {DEFAULT_CUTOFF_HZ:g}" in text, command


@pytest.mark.parametrize(("options", "model"), [([], "full"), (["--reduced"], "reduced")])
def test_a_short_run_prints_its_model(capsys, options, model):
    """The command, end to end (the critical speed of case 1 found, 50 ms)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")        # the 25-ms gap ramp outlasts the discard
        code = main(["simulate", "--case", "1", "--gap-mm", "1.9", "--duration-s", "0.05",
                     "--discard-s", "0.01", *options, "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["model"] == model
    assert summary["speed_rpm"] == pytest.approx(1500, rel=0.005)


def test_text_output_names_the_reduction_only_when_reduced(capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main([*SIM, "--reduced", "--cutoff-hz", "1824"]) == 0
        reduced = capsys.readouterr().out.splitlines()
        assert main(SIM) == 0
        full = capsys.readouterr().out.splitlines()
    assert reduced[1] == "model: reduced (Craig-Bampton, modes below 1824 Hz)"
    assert not any(line.startswith("model:") for line in full)
    assert len(reduced) == len(full) + 1
