"""Run-ups and coast-downs: the ramp run, its order tracks against the linear
response, the summary against the contact record, and rub's hysteresis between run-up and
coast-down — through the ``rubdiag runup`` command on the reduced model."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rubdiag.cli import main
from rubdiag.reduce import Reduction
from rubdiag.runs._runup import (
    GAP_CLOSING_S,
    linear_response,
    ramp_run,
    runup_orders,
    runup_summary,
)
from rubdiag.simulation import load_result, simulate

RPM = math.pi / 30
RATE = 300          # rpm/s
GAP_MM = 2.3        # the study's light rub: contact near the 1st critical both ways


@pytest.fixture(scope="module")
def cli_out(tmp_path_factory):
    """``rubdiag runup --both`` with rub, 1000 <-> 2000 rpm (reduced model, ≈ 5 s)."""
    out = tmp_path_factory.mktemp("runup")
    code = main(["runup", "--case", "1", "--from-rpm", "1000", "--to-rpm", "2000",
                 "--rate-rpm-s", str(RATE), "--gap-mm", str(GAP_MM), "--both", "--reduced",
                 "--out", str(out)])
    assert code == 0
    return out


def test_a_slow_ramps_order_track_is_the_linear_response():
    """The 1× vector tracked on the run's shaft angle and ``linear_response`` share one
    phase convention: within the 2 % and 3° at 50 rpm/s, below the critical."""
    run = ramp_run(1, 1000, 1150, 50, 50.0, reduction=Reduction())
    table = runup_orders(simulate(run), revs_per_bin=4)
    linear = linear_response(run, "shaft 11 y", table["rpm"].to_numpy())
    assert np.abs(np.angle(linear, deg=True)).min() > 5     # a sign error would show
    np.testing.assert_allclose(table["amp_1x"], np.abs(linear), rtol=0.02)
    dphase = (table["phase_1x_deg"] - np.angle(linear, deg=True) + 180) % 360 - 180
    assert np.abs(dphase).max() <= 3.0


def test_a_start_in_contact_closes_the_gap_first():
    """At the critical, the linear state reaches 0.7 mm into a 2.3 mm gap: starting there
    would be an impulse of tens of kN. The ramp run holds the start speed while the gap
    closes, and the force stays that of rubbing."""
    clear = ramp_run(1, 1000, 2000, RATE, GAP_MM)
    assert clear.gap_ramp_s == 0.0 and clear.speed_profile.times_s[0:2] == (0.0, 10 / 3)
    inside = ramp_run(1, 1500, 1600, RATE, GAP_MM, reduction=Reduction())
    assert inside.gap_ramp_s == GAP_CLOSING_S == inside.discard_s
    assert inside.speed_profile.times_s[1] == pytest.approx(GAP_CLOSING_S)
    summary = runup_summary(simulate(inside))
    assert 0 < summary["max_contact_force_n"] < 2000


def test_the_summary_reads_the_contact_record(cli_out):
    for name in ("runup", "coastdown"):
        result = load_result(cli_out / f"{name}.npz")
        s = runup_summary(result)
        assert s["direction"] == {"runup": "run-up", "coastdown": "coast-down"}[name]
        closed = np.flatnonzero((result.system.contact_status > 1).any(axis=1))
        first, last = result.t[closed[0]], result.t[closed[-1]]
        dt = result.run.output_dt_s
        # the event log times the episodes inside a step; the samples see them within one
        for key, t in (("first_contact_rpm", first), ("last_contact_rpm", last)):
            near = result.run.speed_at(np.array([t - dt, t + dt])) / RPM
            assert near.min() - 1e-9 <= s[key] <= near.max() + 1e-9
        table = runup_orders(result)
        assert s["peak_1x_m"] == table["amp_1x"].max()
        assert s["n_episodes"] >= 20            # the issue: >= 20 episodes each way


def test_rub_flattens_the_peak_and_outlasts_on_the_way_up(cli_out):
    """Rub caps the 1× peak of a 300 rpm/s passage (the free rotor's: 2.74 mm up, 2.59 mm
    down), and the two directions differ: the run-up stays on the rubbing branch past the
    speed at which the coast-down first touches (measured: up 1504-1645 rpm, down
    1505-1434 rpm)."""
    rub = {name: runup_summary(load_result(cli_out / f"{name}.npz"))
           for name in ("runup", "coastdown")}
    free = {name: runup_summary(simulate(ramp_run(1, a, b, RATE, 50.0,
                                                  reduction=Reduction())))
            for name, (a, b) in (("runup", (1000, 2000)), ("coastdown", (2000, 1000)))}
    for name in rub:
        assert free[name]["n_episodes"] == 0
        assert rub[name]["peak_1x_m"] < 0.9 * free[name]["peak_1x_m"]
    assert rub["runup"]["last_contact_rpm"] > rub["coastdown"]["first_contact_rpm"] + 50


def test_the_command_writes_what_it_prints(cli_out, capsys):
    pngs = {p.name for p in cli_out.glob("*.png")}
    assert pngs == {f"runup_{name}.png" for name in (
        "bode", "polar", "rub_orders", "waterfall_run_up", "waterfall_coast_down",
        "order_map_run_up", "order_map_coast_down")}
    summaries = json.loads((cli_out / "summary.json").read_text())
    assert [s["direction"] for s in summaries] == ["run-up", "coast-down"]
    for s, name in zip(summaries, ("runup", "coastdown"), strict=True):
        table = np.genfromtxt(cli_out / f"{name}_orders.csv", delimiter=",", names=True)
        assert s["peak_1x_m"] == pytest.approx(table["amp_1x"].max(), rel=1e-12)
    # a second call reuses both results instead of simulating again
    code = main(["runup", "--case", "1", "--from-rpm", "1000", "--to-rpm", "2000",
                 "--rate-rpm-s", str(RATE), "--gap-mm", str(GAP_MM), "--both", "--reduced",
                 "--out", str(cli_out), "--json"])
    assert code == 0
    captured = capsys.readouterr()
    assert captured.err.count("reusing") == 2
    assert json.loads(captured.out) == summaries


@pytest.mark.parametrize(("argv", "match"), [
    (["--rate-rpm-s", "0"], "rate_rpm_s"),
    (["--to-rpm", "1000"], "from_rpm = to_rpm"),
    (["--revs-per-bin", "3"], "--revs-per-bin"),
    (["--gap-mm", "0"], "--gap-mm"),
])
def test_bad_input_is_one_line_and_exit_2(argv, match, tmp_path, capsys):
    base = {"--case": "1", "--from-rpm": "1000", "--to-rpm": "2000", "--rate-rpm-s": "300",
            "--gap-mm": "2.3", "--out": str(tmp_path / "o"), "--revs-per-bin": "4"}
    base.update(dict(zip(argv[::2], argv[1::2], strict=True)))
    args = ["runup"] + [x for kv in base.items() for x in kv]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1


def test_a_ramp_runs_row_is_order_tracked_at_its_mean_speed(cli_out):
    """``rubdiag.run_features`` of a run-up: spectra order-tracked on the shaft angle at the
    window's mean speed, and contact counts per revolution of the angle turned."""
    from rubdiag.runs import run_features

    result = load_result(cli_out / "runup.npz")
    row = run_features(result).iloc[0]
    run, t = result.run, result.t[result.window]
    turned = (run.angle_at(t[-1]) - run.angle_at(t[0])) / (2 * np.pi)
    mean_rpm = 60 * turned / (t[-1] - t[0])
    assert row["speed_rpm"] == pytest.approx(mean_rpm, rel=0.02)     # whole revolutions
    whole = (run.angle_at(result.t[-1]) - run.angle_at(run.discard_s)) / (2 * np.pi)
    assert row["contact1_sliding_entries_per_rev"] == pytest.approx(
        row["contact1_sliding_entries"] / whole, rel=1e-9)
