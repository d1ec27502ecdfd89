"""Designs with a speed ramp: ``[ramp]`` round-trips and is checked, every
run sweeps through its design point's speed, a constant-speed design's resolved text and
run ids are those of before ramps existed, the rows' features are the order-tracked
record's (and that record gives a chirp's 1× where a time spectrum smears it), and a ramp
design generates alike on one and two processes.

The generated design is 2 runs (case 2, reduced model, 0.49 s each) that rub."""

import dataclasses
import hashlib
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rubdiag.dataset import Design, generate, load, load_waveforms
from rubdiag.dataset._approach import sweep_linear_approach_m
from rubdiag.dataset._ids import noise_id
from rubdiag.dataset._labels import LABELS, MEASURES
from rubdiag.dataset._noise import add_noise, noise_seed
from rubdiag.dataset._ramp import SpeedRamp
from rubdiag.dataset._rows import PROVENANCE, RAMP_COLUMNS
from rubdiag.dataset._store import acquisition
from rubdiag.runs._features import max_tracked_rpm, order_tracked, order_tracked_features
from rubdiag.signal import resample_to_angle
from rubdiag.signal._table import prefixed_features

DATA = Path(__file__).resolve().parents[2] / "data"

CRITICALS = "critical_speeds_rad_s = [157.0, 597.0]"

RAMP_TOML = f"""
[base]
discard_s = 0.2
{CRITICALS}

[ramp]
rate_rpm_s = 300
span = 0.15
{{direction}}

[sampling]
replicates = 3

[factors]
case = [1, 2]
speed_ratio = [0.9, 1.0]
gap_mm = [1.9]
"""

# generated below: both replicates of one point that rubs
RUN_TOML = """
[base]
discard_s = 0.11
reduced = true

[ramp]
rate_rpm_s = 3000
span = 0.1

[sampling]
replicates = 2

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.9]
"""

# a constant-speed design whose resolved text and run ids were taken before [ramp] existed
OLD_TOML = f"""
[base]
duration_s = 0.8
discard_s = 0.2
{CRITICALS}

[sampling]
replicates = 2

[factors]
case = [1, 2]
speed_ratio = [0.95, 1.05]
gap_mm = [2.0]
"""
OLD_TEXT_SHA256 = "5d4e2b55f627b1b85d6b9e1b2cbeeb599fc2d714f7579be347ecb478d2eabeff"
OLD_RUN_IDS = ["c63e3980a6b54c6f", "a38e07d8ed833deb", "d02956df225aa1d8", "ea22d115b50f5a6a",
               "f8d87f9c49feec3f", "5b62b38e49d290e8", "2da01b19470bd576", "837a48c1ea2b7ad7"]


def ramp_design(direction: str = "") -> Design:
    return Design.from_toml(RAMP_TOML.format(direction=direction))


# --- the design -----------------------------------------------------------------------------
@pytest.mark.parametrize("direction", ["", 'direction = "down"'])
def test_a_ramp_design_round_trips_exactly(direction):
    design = ramp_design(direction)
    text = design.to_toml()
    again = Design.from_toml(text)
    assert again == design and again.to_toml() == text
    assert Design.from_dict(design.to_dict()) == design
    assert again.runs() == design.runs()
    # [ramp] right after [base], whose duration is derived (so not written)
    kind = "down" if direction else "up"
    assert (f"\n[ramp]\nrate_rpm_s = 300.0\nspan = 0.15\ndirection = \"{kind}\"\n\n[sampling]"
            in text)
    assert "duration_s" not in text.split("[ramp]")[0]
    assert design.duration_s is None and design.ramp == SpeedRamp(300.0, 0.15, kind)


def test_a_constant_speed_design_is_as_before_ramps():
    """The design text of before ramps, at 10 µs (``step_error = 0``, which came later and
    is the only line its resolved form gains), makes the same runs."""
    design = Design.from_toml(OLD_TOML.replace("discard_s = 0.2\n",
                                               "discard_s = 0.2\nstep_error = 0\n"))
    text = design.to_toml()
    assert "\nstep_error = 0.0\n" in text
    text = text.replace("\nstep_error = 0.0\n", "\n")
    assert hashlib.sha256(text.encode()).hexdigest() == OLD_TEXT_SHA256
    assert [item.run_id for item in design.runs()] == OLD_RUN_IDS
    assert "[ramp]" not in text and design.ramp is None and design.duration_s == 0.8
    for item in design.runs():
        assert item.run.speed_profile is None and item.ramp is None
        assert item.speed_rpm == item.run.speed_rpm


@pytest.mark.parametrize("direction", ["up", "down"])
def test_every_run_sweeps_through_its_design_speed(direction):
    design = ramp_design(f'direction = "{direction}"')
    items = design.runs()
    assert len(items) == 4 * 3
    for item in items:
        speed = item.point["speed_ratio"] * (157.0, 597.0)[item.point["case"] - 1]
        rpm = speed * 30 / math.pi
        assert item.speed_rpm == pytest.approx(rpm, rel=1e-15)
        low, high = rpm * 0.85, rpm * 1.15
        start, end = (low, high) if direction == "up" else (high, low)
        run, profile = item.run, item.run.speed_profile
        # held at the start speed for discard_s, then 300 rpm/s to the end, where it stops
        assert profile.times_s[:2] == (0.0, 0.2)
        rpm_knots = np.array(profile.speeds_rad_s) * 30 / math.pi
        np.testing.assert_allclose(rpm_knots, [start, start, end], rtol=1e-14)
        assert run.speed_rad_s == profile.start_rad_s
        assert run.discard_s == 0.2
        assert run.duration_s == profile.end_s == pytest.approx(0.2 + 0.3 * rpm / 300,
                                                                rel=1e-14)
        assert float(run.speed_at(run.duration_s)) * 30 / math.pi == pytest.approx(end)
    # replicates: the standard gap ramps, and nothing else differs
    for first in items[::3]:
        reps = [i for i in items if i.point_id == first.point_id]
        assert [i.run.gap_ramp_s for i in reps] == [0.1, 0.099, 0.101]
        for other in reps[1:]:
            assert dataclasses.replace(other.run, gap_ramp_s=0.1,
                                       label=first.run.label) == first.run
            assert other.run_id != first.run_id
    # a sweep is another simulation than the constant speed of the same cell
    constant = Design.from_toml(RAMP_TOML.format(direction="").replace(
        "[ramp]\nrate_rpm_s = 300\nspan = 0.15\n", "").replace("[base]",
                                                              "[base]\nduration_s = 2.3"))
    assert not {i.run_id for i in items} & {i.run_id for i in constant.runs()}


def _bad(**changes) -> str:
    """RAMP_TOML with keys set to other values (None: left out)."""
    text = RAMP_TOML.format(direction="")
    for key, value in changes.items():
        line = next(line for line in text.splitlines() if line.startswith(f"{key} ="))
        text = text.replace(line + "\n", "" if value is None else f"{key} = {value}\n")
    return text


BAD = [
    (_bad(rate_rpm_s=0), r"ramp.rate_rpm_s = 0 is out of range \(allowed: > 0 and "
     r"<= 1e\+06 rpm/s\)"),
    (_bad(rate_rpm_s=-300), r"ramp.rate_rpm_s = -300 is out of range"),
    (_bad(rate_rpm_s='"fast"'), r"ramp.rate_rpm_s = 'fast' has the wrong type"),
    (_bad(rate_rpm_s=None), r"ramp.rate_rpm_s is missing"),
    (_bad(span=0.0), r"ramp.span = 0.0 is out of range \(allowed: > 0 and < 1\)"),
    (_bad(span=1.0), r"ramp.span = 1.0 is out of range \(allowed: > 0 and < 1\)"),
    (_bad(span=None), r"ramp.span is missing"),
    (RAMP_TOML.format(direction='direction = "sideways"'),
     r"ramp.direction = 'sideways' is not allowed \(allowed: up, down\)"),
    (RAMP_TOML.format(direction="rate = 5"),
     r"unknown key 'ramp.rate' \(allowed: rate_rpm_s, span, direction\)"),
    (_bad(discard_s="0.2\nduration_s = 2.3"),
     r"base.duration_s = 2.3 is given with \[ramp\] \(allowed: no base.duration_s: a run "
     r"lasts base.discard_s \+ 2·ramp.span·speed / ramp.rate_rpm_s\)"),
    (_bad(rate_rpm_s=3000), r"the ramp \(2·ramp.span·speed / ramp.rate_rpm_s = 0.1349 s\) "
     r"holds 3.03 revolutions at 1349.32 rpm, the design's slowest speed \(allowed: at "
     r"least 13, for the spectral features of its order-tracked record; lower "
     r"ramp.rate_rpm_s or widen ramp.span\)$"),
    (_bad(discard_s=0.05), r"base.discard_s = 0.05 is out of range \(allowed: >= "
     r"0.101 s, the longest gap ramp"),
    (_bad(span=0.9).replace("speed_ratio = [0.9, 1.0]", "speed_ratio = [2.5]"),
     r"point 1 \(case = 2, speed_ratio = 2.5, gap_mm = 1.9\): the ramp reaches 27079.4 rpm "
     r"\(allowed: at most 14545.5 rpm at the output rate 10000 Hz, for the features of the "
     r"order-tracked record; lower ramp.span or the speed\)$"),
]


@pytest.mark.parametrize(("text", "message"), BAD, ids=[m[:40] for _, m in BAD])
def test_bad_ramps_are_one_line_naming_the_key(text, message):
    with pytest.raises(ValueError, match=f"^{message}") as info:
        Design.from_toml(text).runs()
    assert "\n" not in str(info.value)


def test_the_example_design_is_a_small_runup():
    design = Design.from_toml(DATA / "designs" / "rub_runup_small.toml")
    items = design.runs()
    assert len(items) == 4 and design.reduction is not None
    assert design.ramp == SpeedRamp(300.0, 0.15, "up")
    for item in items:   # case 1's critical, 0.85 -> 1.15 of it: 1.5 s of ramp
        assert item.speed_rpm == pytest.approx(1500.0, rel=1e-6)
        assert item.run.duration_s == pytest.approx(0.3 + 1.5, rel=1e-6)


# --- the order-tracked record --------------------------------------------------------------
def _chirp(fs=10_000.0, seconds=1.5, rpm0=1275.0, rate_rpm_s=300.0):
    t = np.arange(round(seconds * fs)) / fs
    phi = 2 * np.pi * (rpm0 / 60 * t + 0.5 * rate_rpm_s / 60 * t**2)
    return t, phi


def test_a_chirps_orders_are_steady_lines_of_the_order_tracked_record():
    """A run-up 1275 -> 1725 rpm at 300 rpm/s (1.5 s, the example design's ramp): read as a
    constant-speed record at its mean speed, the 1×, 1.5× and 2× have their analytic
    amplitudes within 1 % and the 1× its phase against the shaft angle; a time spectrum of
    the same record at the same speed smears the 1× over 7.5 Hz and misses the 1.5×."""
    fs = 10_000.0
    _, phi = _chirp(fs)
    x = 2e-4 * np.cos(phi + 0.3) + 3e-5 * np.cos(2 * phi) + 1e-5 * np.cos(1.5 * phi)
    row = order_tracked_features({"a": x}, fs, phi).iloc[0]
    assert row["a_amp_1x"] == pytest.approx(2e-4, rel=0.01)
    assert row["a_amp_1p5x"] == pytest.approx(1e-5, rel=0.01)
    assert row["a_amp_2x"] == pytest.approx(3e-5, rel=0.01)
    assert row["a_phase_1x_deg"] == pytest.approx(math.degrees(0.3), abs=0.5)
    assert row["speed_rpm"] == pytest.approx(1500.0, rel=0.005)
    assert row["a_freq_1x_hz"] == pytest.approx(row["speed_rpm"] / 60, rel=1e-4)
    smeared = prefixed_features({"a": x}, fs, row["speed_rpm"]).iloc[0]
    assert smeared["a_amp_1x"] < 0.8 * 2e-4
    assert smeared["a_amp_1p5x"] == 0.0


def test_the_record_is_whole_revolutions_at_the_mean_speed():
    fs = 10_000.0
    _, phi = _chirp(fs)
    record, fs_equiv, rpm = order_tracked({"a": np.cos(phi)}, fs, phi)
    n = record["a"].size
    assert n % 32 == 0 and 37.5 - 3 <= n / 32 <= 37.5
    # n/32 revolutions over n/fs_equiv seconds, at the mean speed
    assert fs_equiv == pytest.approx(32 * rpm / 60, rel=1e-15)
    assert 1275 < rpm < 1725 and rpm == pytest.approx(1500.0, rel=0.005)
    # a speed whose 8.25x is above 0.2 fs is refused
    assert max_tracked_rpm(fs) == pytest.approx(0.2 * fs / 8.25 * 60)
    with pytest.raises(ValueError, match=r"^angle: the speed reaches 2\d{4}.* rpm \(allowed: "
                       r"at most 14545.5 rpm at fs = 10000 Hz"):
        order_tracked({"a": np.cos(phi * 14)}, fs, phi * 14)


# --- generated rows --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def run_design():
    return Design.from_toml(RUN_TOML)


@pytest.fixture(scope="module")
def generated(run_design, tmp_path_factory):
    out = tmp_path_factory.mktemp("ramp") / "one"
    summary = generate(run_design, out, jobs=1, progress=False, waveforms=True)
    assert summary["ok"] == 2
    return out


def _by_hand(item, design):
    """The spectral features of a ramp run, assembled here from the signal layer."""
    from rubdiag.simulation import simulate

    result = simulate(item.run)
    measured = add_noise(result.sensor_signals(),
                         {s.name: design.noise.floor(s.quantity) for s in item.run.sensors},
                         noise_seed(noise_id(item.run)))
    window = result.window
    names = list(measured)
    angle = item.run.angle_at(result.t[window])
    revolutions, x = resample_to_angle(np.vstack([measured[k][window] for k in names]),
                                       result.fs, angle, samples_per_rev=32)
    first = int(np.flatnonzero(np.isclose(revolutions % 1, 0) | np.isclose(revolutions % 1,
                                                                         1))[0])
    whole = (revolutions.size - first) // 32
    x = x[:, first:first + whole * 32]
    r0 = round(revolutions[first])
    t = np.arange(angle.size) / result.fs
    seconds = np.interp(2 * np.pi * (r0 + whole), angle, t) - np.interp(2 * np.pi * r0,
                                                                         angle, t)
    rpm = 60 * whole / seconds
    table = prefixed_features(dict(zip(names, x, strict=True)), 32 * rpm / 60, rpm,
                              separator="__")
    return table.iloc[0], result


def test_rows_hold_the_order_tracked_features_and_the_sweeps_labels(run_design, generated):
    rows = load(generated)
    items = run_design.runs()
    assert list(rows["status"]) == ["ok", "ok"]
    assert rows[list(MEASURES + LABELS)].notna().all().all()
    assert set(rows["rub"]) == {True}
    columns = list(rows.columns)
    at = columns.index("speed_rpm")
    assert columns[at:at + 6] == ["speed_rpm", *RAMP_COLUMNS, "model"]
    item = next(i for i in items if i.replicate == 0)
    row = rows.set_index("run_id").loc[item.run_id]
    rpm = item.speed_rpm
    assert row["speed_rpm"] == rpm
    assert (row["ramp_from_rpm"], row["ramp_to_rpm"], row["ramp_rate_rpm_s"]) == (
        rpm * 0.9, rpm * 1.1, 3000.0)
    expected, result = _by_hand(item, run_design)
    assert row["ramp_mean_rpm"] == expected["speed_rpm"]
    features = [c for c in expected.index if c != "speed_rpm"]
    assert len(features) > 700
    pd.testing.assert_series_equal(row[features].astype(float), expected[features],
                                   check_names=False, rtol=1e-12, atol=0)
    # the interference ratio: the peak of the linear approach over the sweep (which
    # passes the critical speed), above the start speed's
    gap = item.run.gap_m
    assert row["interference_ratio"] == sweep_linear_approach_m(item.run) / gap
    assert row["interference_ratio"] > 1.1 * result.linear_approach_m / gap
    # per revolution: over the window's revolutions, from the shaft angle
    revs = (item.run.angle_at(result.t[-1]) - item.run.angle_at(item.run.discard_s)) / (
        2 * np.pi)
    assert row["contact1__sliding_entries_per_rev"] == pytest.approx(
        row["contact1__sliding_entries"] / revs, rel=1e-12)


def test_the_sweeps_approach_is_the_peak_of_a_fine_grid(run_design):
    from rubdiag.assembly import assemble
    from rubdiag.dataset._approach import _approach, window_speed_range
    from rubdiag.modal import with_rayleigh

    run = run_design.runs()[0].run
    lo, hi = window_speed_range(run)
    assert (lo, hi) == pytest.approx((run.speed_profile.speeds_rad_s[0],
                                      run.speed_profile.speeds_rad_s[-1]), rel=1e-15)
    model = with_rayleigh(assemble(run.rig))
    fine = max(_approach(run, model, s) for s in np.linspace(lo, hi, 801))
    found = sweep_linear_approach_m(run)
    assert fine <= found <= fine * (1 + 1e-4)


def test_a_ramp_dataset_says_so_and_two_processes_agree(run_design, generated, tmp_path):
    out = tmp_path / "two"
    assert generate(run_design, out, jobs=2, progress=False)["ok"] == 2
    one, two = load(generated), load(out)
    keep = [c for c in one.columns if c not in PROVENANCE]
    pd.testing.assert_frame_equal(one[keep].sort_values("run_id").reset_index(drop=True),
                                  two[keep].sort_values("run_id").reset_index(drop=True))
    assert acquisition(generated)["ramp"] == {"rate_rpm_s": 3000.0, "span": 0.1,
                                              "direction": "up"}
    waves = load_waveforms(generated, one["run_id"][0])
    assert waves.columns[-1] == "angle_rad" and waves.attrs["units"]["angle_rad"] == "rad"
    item = next(i for i in run_design.runs() if i.run_id == one["run_id"][0])
    np.testing.assert_allclose(waves["angle_rad"], item.run.angle_at(waves.index), rtol=1e-12)
    card = (generated / "README.md").read_text()
    assert "Speed ramp: every run is a run-up at 3000 rpm/s" in card
    columns = pd.read_csv(generated / "columns.csv").set_index("column")
    assert columns.loc["ramp_rate_rpm_s", "unit"] == "rpm/s"
    assert set(columns.loc[list(RAMP_COLUMNS), "group"]) == {"run"}
