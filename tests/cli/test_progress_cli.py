"""Progress of the long commands: on a terminal a bar that reaches its total (the runs, the
simulated seconds, the speeds); on a stderr that is not a terminal, or with ``--quiet``, no
bar. ``dataset`` and ``table2``, which store what they finish and resume, keep a line per
stored run or case off a terminal, for logs. (train and evaluate:
tests/learn/test_progress_learn.py.)"""

import numpy as np
from fake_terminal import as_terminal, counts

from rubdiag.cli import main
from rubdiag.simulation import Run, simulate

SIM = ["simulate", "--case", "1", "--gap-mm", "2.3", "--duration-s", "0.1",
       "--discard-s", "0.05"]

DESIGN = """
[base]
rig = "paper"
duration_s = 0.25
discard_s = 0.1
reduced = true

[sampling]
method = "grid"
replicates = 1

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.6, 3.5]
"""


def drawn(text: str) -> bool:
    """Whether a bar was drawn in ``text`` (tqdm redraws with a carriage return)."""
    return "\r" in text or "%|" in text


def test_simulate_draws_the_simulated_seconds_on_a_terminal(monkeypatch):
    terminal = as_terminal(monkeypatch)
    assert main(SIM) == 0
    assert counts(terminal.getvalue())[-1] == "0.10/0.10"
    assert "s simulated" in terminal.getvalue()


def test_simulate_is_silent_with_quiet_and_off_a_terminal(capsys, monkeypatch):
    terminal = as_terminal(monkeypatch)
    assert main([*SIM, "--quiet"]) == 0
    assert terminal.getvalue() == ""
    monkeypatch.undo()                       # stderr: pytest's capture, not a terminal
    assert main(SIM) == 0
    assert capsys.readouterr().err == ""


def test_the_faults_runs_share_one_bar_and_their_results(monkeypatch):
    """``rubdiag faults`` simulates its runs one after the other under one bar: it ends at
    their simulated seconds summed, names the run going on, and the runs are those of a
    simulation without a bar, bit for bit (the bar's callback cuts the integration into
    pieces)."""
    terminal = as_terminal(monkeypatch)
    from rubdiag.cli.faults import _simulated

    a = Run.paper_case(1, 2.3, duration_s=0.05, discard_s=0.03)
    b = Run.paper_case(2, 2.3, duration_s=0.1, discard_s=0.05)
    (first, second) = _simulated([{"a": a}, {"b": b}], progress=True)
    text = terminal.getvalue()
    assert counts(text)[-1] == "0.15/0.15" and text.rstrip().endswith("b]")
    for result, run in ((first["a"], a), (second["b"], b)):
        alone = simulate(run)
        assert np.array_equal(result.system.q, alone.system.q)
    _simulated([{"a": a}], progress=False)
    assert terminal.getvalue() == text                # quiet: nothing more


def test_a_runup_leg_s_bar_and_its_reuse(monkeypatch, tmp_path):
    """Each leg of ``rubdiag runup``: a bar over its simulated seconds; a leg read back from
    its file draws none."""
    terminal = as_terminal(monkeypatch)
    from rubdiag.cli.runup import _simulated
    from rubdiag.reduce import Reduction
    from rubdiag.runs._runup import ramp_run

    run = ramp_run(1, 1000.0, 1100.0, 1000.0, 2.3, reduction=Reduction())
    _simulated(run, tmp_path / "runup.npz", "runup")
    assert counts(terminal.getvalue())[-1] == f"{run.duration_s:.2f}/{run.duration_s:.2f}"
    terminal.seek(0)
    terminal.truncate()
    _simulated(run, tmp_path / "runup.npz", "runup")
    assert not drawn(terminal.getvalue()) and "reusing" in terminal.getvalue()


def test_dataset_bar_on_a_terminal_log_lines_elsewhere(tmp_path, capsys, monkeypatch):
    terminal = as_terminal(monkeypatch)
    design = tmp_path / "design.toml"
    design.write_text(DESIGN)
    assert main(["dataset", str(design), "--out", str(tmp_path / "a"), "--jobs", "1"]) == 0
    assert counts(terminal.getvalue())[-1] == "2/2"
    for quiet in ("--quiet", "--no-progress"):          # the old name still works
        terminal.seek(0)
        terminal.truncate()
        assert main(["dataset", str(design), "--out", str(tmp_path / quiet), "--jobs", "1",
                     quiet]) == 0
        assert terminal.getvalue() == ""
    monkeypatch.undo()
    assert main(["dataset", str(design), "--out", str(tmp_path / "b"), "--jobs", "1"]) == 0
    err = capsys.readouterr().err
    assert not drawn(err)
    assert [line.split(",")[0] for line in err.splitlines()] == ["1/2 done", "2/2 done"]


def test_table2_counts_its_cases_as_they_finish(tmp_path, monkeypatch):
    """The four cases in two processes: a bar over them, counted as they finish, and the
    log lines above it; with --quiet (the cases reused) only the closing line."""
    terminal = as_terminal(monkeypatch)
    from rubdiag.paper._table2 import reproduce
    from rubdiag.reduce import Reduction

    window = {"duration_s": 0.55, "discard_s": 0.1}      # 11 revolutions of case 1
    reproduce(tmp_path, jobs=2, progress=True, reduction=Reduction(), **window)
    text = terminal.getvalue()
    assert counts(text)[-1] == "4/4"
    assert text.count(": done in ") == 4 and text.rindex(": done in ") < text.rindex("4/4")
    terminal.seek(0)
    terminal.truncate()                                 # every case reused:
    assert main(["table2", "--out", str(tmp_path), "--duration-s", "0.55", "--discard-s",
                 "0.1", "--reduced", "--no-figures", "--quiet"]) == 0, terminal.getvalue()
    assert terminal.getvalue().startswith("wrote ") and terminal.getvalue().count("\n") == 1


def test_campbell_counts_its_speeds(tmp_path, monkeypatch):
    terminal = as_terminal(monkeypatch)
    assert main(["campbell", "--n-speeds", "3", "--out", str(tmp_path)]) == 0
    assert counts(terminal.getvalue())[-1] == "3/3"


def test_an_ensemble_counts_its_runs_as_they_finish(monkeypatch):
    from rubdiag.paper._ensemble import ensemble

    terminal = as_terminal(monkeypatch)
    rows = ensemble([(2, 2.3)], gap_ramps_s=(0.099, 0.1), jobs=2, progress=True,
                    duration_s=0.25, discard_s=0.1)
    assert list(rows["gap_ramp_s"]) == [0.099, 0.1]      # in the order asked for
    assert counts(terminal.getvalue())[-1] == "2/2"
