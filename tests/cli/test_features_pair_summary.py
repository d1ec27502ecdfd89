"""rubdiag features --pair: the summary in words of the probe pair's row names its forward and
reverse lines (it once read the pair's row as a channel's: "RMS nan, 1× absent")."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main

FS, SPEED_HZ = 2048.0, 50.0


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    """y + iz = 1.0 e^(iΩt) + 0.2 e^(-2iΩt): forward 1× of 1.0, reverse 2× of 0.2, with a
    little noise on both probes."""
    t = np.arange(int(4 * FS)) / FS
    w = 2 * np.pi * SPEED_HZ
    orbit = 1.0 * np.exp(1j * w * t) + 0.2 * np.exp(-2j * w * t)
    noise = np.random.default_rng(0).standard_normal((2, t.size)) * 1e-4
    path = tmp_path_factory.mktemp("pair") / "orbit.csv"
    pd.DataFrame({"t": t, "y": orbit.real + noise[0], "z": orbit.imag + noise[1]}).to_csv(
        path, index=False)
    return path


def _pair_lines(path, capsys, *options):
    assert main(["features", str(path), "--pair", "y,z", "--speed-rpm",
                 str(60 * SPEED_HZ), "--summary", *options]) == 0
    lines = capsys.readouterr().out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("y+iz:"))
    return lines[start:start + 2]


def test_the_pair_summary_names_forward_1x_and_reverse_2x(record, capsys):
    head, lines = _pair_lines(record, capsys)
    assert head.startswith("y+iz: 3000 rpm, 1× forward 1, reverse ")
    assert head.endswith("(forward precession)")
    assert lines.startswith("  reverse 2× 0.2;")
    assert "nan" not in head + lines and "absent" not in head + lines


def test_the_other_rotation_swaps_forward_and_reverse(record, capsys):
    head, lines = _pair_lines(record, capsys, "--rotation", "-1")
    assert ", reverse 1 (reverse precession)" in head
    assert lines.startswith("  forward 2× 0.2;")
