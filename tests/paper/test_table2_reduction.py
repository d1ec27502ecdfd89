"""Table 2 of the reduced model: the saved runs of a full and a reduced reproduction
never stand in for each other, and the written table says which model made it.

The simulator is replaced by one that returns a single real short run under each requested
description (its numbers are not the point; which description is saved, found and reused is),
and the process pool by threads so that the replacement applies."""

import dataclasses
import importlib
from concurrent.futures import ThreadPoolExecutor

import pandas as pd
import pytest

import rubdiag.simulation
from rubdiag.paper import reproduce, table2
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, simulate

table2_module = importlib.import_module("rubdiag.paper._table2")

WINDOW = {"duration_s": 0.7, "discard_s": 0.2}   # 12.5 revolutions at 1500 rpm


@pytest.fixture(scope="module")
def template():
    return simulate(Run.paper_case(2, 2.3, speed_rpm=5700, **WINDOW))


@pytest.fixture
def simulated(monkeypatch, template):
    """The runs the fake simulator was given, in order."""
    runs = []

    def fake(run, progress=None, **_):
        runs.append(run)
        return dataclasses.replace(template, run=run)

    monkeypatch.setattr(rubdiag.simulation, "simulate", fake)
    monkeypatch.setattr(table2_module, "ProcessPoolExecutor", ThreadPoolExecutor)
    return runs


def test_run_file_names_say_the_model():
    full = Run.paper_case(1, 2.3, speed_rpm=1500, **WINDOW)
    names = {table2_module.run_file("case1_light", dataclasses.replace(full, reduction=r))
             for r in (None, Reduction(), Reduction(1824.0), Reduction(1824.5))}
    assert names == {"case1_light.npz", "case1_light_reduced_2000hz.npz",
                     "case1_light_reduced_1824hz.npz", "case1_light_reduced_1824.5hz.npz"}


def test_the_log_says_the_time_is_simulated_time(tmp_path, simulated):
    messages = []
    reproduce(tmp_path, jobs=2, log=messages.append, **WINDOW)
    assert messages[0] == "simulating 4 case(s), 0.7 s simulated each, on 2 process(es)"


def test_full_and_reduced_runs_are_never_mixed(tmp_path, simulated):
    def run(**options):
        messages = []
        simulated.clear()
        results = reproduce(tmp_path, jobs=2, log=messages.append, **WINDOW, **options)
        return results, sum("reused" in m for m in messages)

    results, reused = run(reduction=Reduction())
    assert reused == 0 and len(simulated) == 4
    assert {r.reduction for r in simulated} == {Reduction()}
    assert {r.run.model_kind for r in results.values()} == {"reduced"}
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == [
        f"case{c}_{i}_reduced_2000hz.npz" for c in (1, 2) for i in ("light", "serious")]

    results, reused = run()                       # the full model: nothing reusable yet
    assert reused == 0 and {r.reduction for r in simulated} == {None}
    assert {r.run.model_kind for r in results.values()} == {"full"}
    assert len(list((tmp_path / "runs").iterdir())) == 8     # the reduced runs are kept

    results, reused = run(reduction=Reduction())   # the reduced runs are still there
    assert reused == 4 and simulated == []
    assert {r.run.reduction for r in results.values()} == {Reduction()}

    results, reused = run(reduction=Reduction(1824.0))     # another cutoff: another model
    assert reused == 0 and {r.reduction for r in simulated} == {Reduction(1824.0)}

    results, reused = run()
    assert reused == 4 and {r.run.reduction for r in results.values()} == {None}


def test_a_reduced_file_under_a_full_name_is_not_taken(tmp_path, template):
    """Even a reduced run saved under the full run's name (by hand, or by an older rubdiag)
    is not reused for the full run: the description must be equal."""
    full = template.run
    path = dataclasses.replace(template, run=dataclasses.replace(
        full, reduction=Reduction())).save(tmp_path / table2_module.run_file("x", full))
    assert table2_module._cached(path, full) is None
    assert table2_module._cached(path, dataclasses.replace(full, reduction=Reduction())) \
        is not None


def test_written_table_says_which_model(tmp_path, simulated):
    full = table2(tmp_path / "full", jobs=1, figures=False, log=lambda m: None, **WINDOW)
    reduced = table2(tmp_path / "reduced", jobs=1, figures=False, log=lambda m: None,
                     reduction=Reduction(1824.0), **WINDOW)
    for folder, table, model in ((tmp_path / "full", full, "full"),
                                 (tmp_path / "reduced", reduced, "reduced")):
        assert list(table["model"]) == [model] * 4
        assert list(pd.read_csv(folder / "table2.csv")["model"]) == [model] * 4
        assert list(pd.read_csv(folder / "features.csv")["model"]) == [model] * 4
    full_md = (tmp_path / "full" / "table2.md").read_text(encoding="utf-8")
    reduced_md = (tmp_path / "reduced" / "table2.md").read_text(encoding="utf-8")
    # the full model's Markdown is as it was (the documentation's sample), the reduced one
    # adds a line
    assert "Model:" not in full_md and "reduced" not in full_md
    assert full_md.endswith("(not converged in dt: see the documentation, Time-step "
                            "convergence).\n")
    last = reduced_md.rstrip("\n").splitlines()[-1]
    assert last == ("Model: reduced (Craig-Bampton, fixed-interface modes below 1824 Hz); "
                    "the study's values are from its full model.")
    assert table2_module.to_markdown(full) == full_md
