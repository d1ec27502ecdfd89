"""Which line is 1×: a guessed speed whose strongest line has a line at 1/2 or 1/3 of its
frequency is flagged ambiguous (rubdiag.signal._speed, "Which line is 1×"), never silently
doubled; a record with no line at all is refused, naming it. Synthetic records of stated
lines and noise, at speeds on and off the frequency bins of a 2-s window."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.signal import SpeedAmbiguous, signal_features, voted_speed
from rubdiag.signal._table import feature_matrix

FS, SECONDS = 2000.0, 2.0
#: 25 Hz on a bin of the 2-s window (0.5-Hz bins); 24.197 Hz and 24.388 Hz between bins
SPEEDS = (1500.0, 1451.84, 1463.3)


def record(rpm, lines, noise, seed=0):
    """``sum a cos(2π k f t + 0.3 k)`` over ``(k, a)`` of ``lines`` (k in orders of the
    speed ``rpm``), plus white noise of standard deviation ``noise``."""
    t = np.arange(round(FS * SECONDS)) / FS
    f = rpm / 60.0
    x = sum(a * np.cos(2 * np.pi * k * f * t + 0.3 * k) for k, a in lines)
    return x + noise * np.random.default_rng(seed).standard_normal(t.size)


def right(vote, rpm):
    return vote.rpm == pytest.approx(rpm, rel=1e-3)


@pytest.mark.parametrize("rpm", SPEEDS)
@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.8, 1.25, 2.0, 3.0, 5.0])
def test_1x_and_2x_right_or_flagged(rpm, ratio):
    """1× of 1 and 2× of ``ratio`` (0.2 to 5), noise 1 % of 1×: the speed is right, or the
    vote says it is ambiguous and names the true speed among the others it may be."""
    vote = voted_speed(record(rpm, [(1, 1.0), (2, ratio)], 0.01, seed=int(10 * ratio)), FS)
    if ratio < 1.0:                                   # 1× the strongest: right, unflagged
        assert right(vote, rpm) and not vote.ambiguous
    else:                                             # 2× the strongest: flagged
        assert vote.rpm == pytest.approx(2 * rpm, rel=1e-3)
        assert vote.ambiguous
        assert vote.alternatives_rpm == pytest.approx((rpm,), rel=1e-3)
    assert right(vote, rpm) or vote.ambiguous        # never silently doubled


@pytest.mark.parametrize("rpm", SPEEDS)
@pytest.mark.parametrize("noise", [1e-4, 1e-3, 1e-2])
def test_a_1x_at_1_percent_of_2x_is_flagged(rpm, noise):
    """The fundamental at 1 % of 2×: where it stands out of the noise at all (here 30 to
    3000 times the floor), the speed is flagged, the true one named."""
    vote = voted_speed(record(rpm, [(1, 0.01), (2, 1.0)], noise), FS)
    assert vote.ambiguous and vote.alternatives_rpm == pytest.approx((rpm,), rel=1e-3)
    assert vote.submultiples[0] >= 5.0 and vote.submultiples[1] == 0.0


@pytest.mark.parametrize("rpm", SPEEDS)
def test_1x_and_3x(rpm):
    strong = voted_speed(record(rpm, [(1, 0.5), (3, 1.0)], 0.01), FS)
    assert strong.rpm == pytest.approx(3 * rpm, rel=1e-3)
    assert strong.ambiguous and strong.alternatives_rpm == pytest.approx((rpm,), rel=1e-3)
    assert strong.submultiples[0] == 0.0              # nothing at 1.5x
    weak = voted_speed(record(rpm, [(1, 1.0), (3, 0.5)], 0.01), FS)
    assert right(weak, rpm) and not weak.ambiguous


@pytest.mark.parametrize("rpm", SPEEDS)
@pytest.mark.parametrize("half", [0.1, 0.4, 0.9])
def test_a_sub_harmonic_never_halves_the_speed(rpm, half):
    """1× the larger line with a ½× sub-harmonic (rub, looseness): the speed stays the
    strongest line's — a ½× read as 1× would make a rub look like a crack — and is
    flagged, since a 1× below a stronger 2× gives the same lines."""
    vote = voted_speed(record(rpm, [(1, 1.0), (0.5, half), (1.5, 0.3 * half)], 0.01), FS)
    assert right(vote, rpm)
    assert vote.ambiguous and vote.alternatives_rpm == pytest.approx((rpm / 2,), rel=1e-3)


@pytest.mark.parametrize("rpm", SPEEDS)
@pytest.mark.parametrize("order", [0.42, 0.46])
def test_whirl_is_no_sub_multiple(rpm, order):
    """Oil whirl and whip lie below ½× and do not make the speed ambiguous."""
    vote = voted_speed(record(rpm, [(1, 1.0), (order, 0.6)], 0.01), FS)
    assert right(vote, rpm) and not vote.ambiguous


@pytest.mark.parametrize("seed", range(20))
def test_noise_and_weaker_harmonics_are_not_flagged(seed):
    rpm = SPEEDS[seed % 3]
    lines = [(1, 1.0), (2, 0.4), (3, 0.2), (4, 0.1)] if seed % 2 else [(1, 1.0)]
    vote = voted_speed(record(rpm, lines, 0.05, seed=seed), FS)
    assert right(vote, rpm) and not vote.ambiguous
    assert vote.submultiples == (0.0, 0.0) and vote.ambiguity() == ""


def test_a_sub_multiple_on_another_channel_counts():
    """The channels vote on the strongest line; a line at half of it on any moving
    channel makes the speed ambiguous."""
    rpm = SPEEDS[1]
    X = np.vstack([record(rpm, [(2, 1.0)], 1e-3, seed=1),
                   record(rpm, [(1, 0.3), (2, 1.0)], 1e-3, seed=2)])
    assert not voted_speed(X[:1], FS).ambiguous
    vote = voted_speed(X, FS)
    assert vote.rpm == pytest.approx(2 * rpm, rel=1e-3) and vote.ambiguous


def test_features_warn_naming_the_file(tmp_path):
    rpm = SPEEDS[1]
    path = tmp_path / "crack.csv"
    pd.DataFrame({"t": np.arange(4000) / FS,
                  "shaft": record(rpm, [(1, 0.4), (2, 1.0)], 1e-3)}).to_csv(path, index=False)
    with pytest.warns(SpeedAmbiguous, match=r"the speed of .*crack\.csv is ambiguous: "
                      r"2903\.7 rpm is the strongest line, taken as 1x, but a line at 1/2 of "
                      r"its frequency \(1451\.8 rpm\)"):
        table = signal_features(str(path))
    assert table["speed_rpm"].iloc[0] == pytest.approx(2 * rpm, rel=1e-4)
    with warnings.catch_warnings():                  # the speed given: nothing to say
        warnings.simplefilter("error")
        signal_features(str(path), speed_rpm=rpm)


def test_the_batch_path_warns_once_for_its_rows():
    rpm = SPEEDS[0]
    X = np.vstack([record(rpm, [(1, 1.0)], 1e-3), record(rpm, [(1, 0.4), (2, 1.0)], 1e-3),
                   record(rpm, [(1, 0.3), (3, 1.0)], 1e-3)])
    with pytest.warns(SpeedAmbiguous) as caught:
        Z = feature_matrix(X, FS)
    assert len(caught) == 1
    assert str(caught[0].message).startswith("the speed of row 1 is ambiguous: 3000 rpm")
    assert str(caught[0].message).endswith("(2 of 3 rows so)")
    assert Z[:, 0] == pytest.approx([rpm, 2 * rpm, 3 * rpm], rel=1e-3)


class TestConstantRecords:
    """No line at all: refused in one line naming the record, never "nan rpm"."""

    def test_features_of_a_constant_file(self, tmp_path):
        path = tmp_path / "flat.csv"
        pd.DataFrame({"t": np.arange(4000) / FS, "a": 3.0, "b": 0.0}).to_csv(path, index=False)
        with pytest.raises(ValueError, match=r"flat\.csv: speed_rpm was not given and cannot "
                                             r"be guessed: every channel is still"):
            signal_features(str(path))
        assert (signal_features(str(path), speed_rpm=1500.0)["amp_1x"] == 0.0).all()

    @pytest.mark.parametrize("command", ["features", "compare"])
    def test_the_cli_exits_2_with_one_line(self, tmp_path, command, capsys):
        flat, good = tmp_path / "flat.csv", tmp_path / "good.csv"
        t = np.arange(4000) / FS
        pd.DataFrame({"t": t, "x": np.full(4000, 2.5)}).to_csv(flat, index=False)
        pd.DataFrame({"t": t, "x": record(1500.0, [(1, 1.0)], 1e-3)}).to_csv(good, index=False)
        argv = [command, str(good), str(flat)] if command == "compare" else [command, str(flat)]
        assert main(argv) == 2
        captured = capsys.readouterr()
        assert captured.out == ""
        assert captured.err.count("\n") == 1
        assert captured.err.startswith(f"rubdiag {command}: error: {flat}: speed_rpm was not "
                                       "given and cannot be guessed: every channel is still")

    def test_the_cli_names_the_file_whose_speed_is_ambiguous(self, tmp_path, capsys):
        good, crack = tmp_path / "good.csv", tmp_path / "crack.csv"
        t = np.arange(4000) / FS
        pd.DataFrame({"t": t, "x": record(1500.0, [(1, 1.0)], 1e-3)}).to_csv(good, index=False)
        pd.DataFrame({"t": t, "x": record(1500.0, [(1, 0.4), (2, 1.0)], 1e-3)}).to_csv(
            crack, index=False)
        assert main(["compare", str(good), str(crack)]) == 0
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1
        assert err[0].startswith(f"rubdiag compare: warning: {crack}: the speed is ambiguous")
