"""``rubdiag compare A B --pair Y,Z``: the probe pair's full spectrum and orbit in two
signal files, from synthetic orbits of known content (y + iz with the shaft turning from y
towards z: a circle turning with the shaft is forward, against it reverse)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main

FS, SPEED = 5000.0, 25.0                # Hz; 1500 rpm
T = np.arange(int(2.0 * FS)) / FS        # 50 whole revolutions
W = 2 * np.pi * SPEED


def _write(path, y, z):
    pd.DataFrame({"time": T, "y": y, "z": z}).to_csv(path, index=False)
    return str(path)


@pytest.fixture
def files(tmp_path):
    """A: a forward circle of radius 3 at 1x. B: a reverse circle of radius 2 at 1x and a
    forward one of radius 1 at 2x."""
    a = _write(tmp_path / "a.csv", 3.0 * np.cos(W * T + 0.4), 3.0 * np.sin(W * T + 0.4))
    b = _write(tmp_path / "b.csv", 2.0 * np.cos(W * T) + np.cos(2 * W * T + 1.0),
               -2.0 * np.sin(W * T) + np.sin(2 * W * T + 1.0))
    return a, b


def _pair_table(out: str, name: str = "y+iz") -> pd.DataFrame:
    """The printed A, B, B - A table of the pair's section."""
    section = out.split(f"channel {name!r}:", 1)[1].splitlines()[2:]
    rows = {}
    for line in section:
        parts = line.split()
        if len(parts) != 4:
            break
        rows[parts[0]] = [float(v) for v in parts[1:]]
    return pd.DataFrame.from_dict(rows, orient="index", columns=["A", "B", "B - A"])


def test_a_forward_circle_against_a_reverse_one(files, capsys):
    a, b = files
    assert main(["compare", a, b, "--pair", "y,z"]) == 0
    table = _pair_table(capsys.readouterr().out)
    assert table.loc["speed_rpm", "A"] == pytest.approx(1500.0)   # each file's own vote
    assert table.loc["speed_rpm", "B"] == pytest.approx(1500.0)
    np.testing.assert_allclose(table.loc["fwd_1x"], [3.0, 0.0, -3.0], atol=1e-5)
    np.testing.assert_allclose(table.loc["rev_1x"], [0.0, 2.0, 2.0], atol=1e-5)
    np.testing.assert_allclose(table.loc["fwd_2x"], [0.0, 1.0, 1.0], atol=1e-5)
    np.testing.assert_allclose(table.loc["precession_1x"], [1, -1, -2])
    # B's orbit: radius |2 + e^{i(3wt + 1)}|, 2 - 1 to 2 + 1, so flattening 1 - 1/3; the
    # samples (200 a revolution) miss its least radius by up to 1 + (3 pi / 200)^2 / 2
    assert table.loc["flattening", "B"] == pytest.approx(2.0 / 3.0, abs=1e-3)
    assert table.loc["flattening", "A"] == pytest.approx(0.0, abs=1e-9)


def test_the_other_rotation_swaps_forward_and_reverse(files, capsys):
    a, b = files
    assert main(["compare", a, b, "--pair", "y,z", "--rotation", "-1",
                 "--speed-rpm", "1500"]) == 0
    table = _pair_table(capsys.readouterr().out)
    np.testing.assert_allclose(table.loc["rev_1x"], [3.0, 0.0, -3.0], atol=1e-5)
    np.testing.assert_allclose(table.loc["fwd_1x"], [0.0, 2.0, 2.0], atol=1e-5)
    np.testing.assert_allclose(table.loc["rev_2x"], [0.0, 1.0, 1.0], atol=1e-5)


@pytest.mark.parametrize(("extra", "message"), [
    (["--pair", "y,q"], "no channel 'q'"),
    (["--pair", "y"], "allowed: two channel names"),
    (["--pair", "y,z", "--revs-per-bin", "10", "--tacho", "y"], "not with --revs-per-bin"),
])
def test_bad_pairs_are_one_line_and_exit_2(files, capsys, extra, message):
    a, b = files
    assert main(["compare", a, b, *extra]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and "Traceback" not in captured.err
    assert captured.out == ""                                  # refused before any output
