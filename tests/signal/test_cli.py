"""rubdiag features / compare: output formats, exit codes, one-line errors."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main

FS, RPM = 2000.0, 1500.0


def _write(path, synth, extra=()):
    t = np.arange(int(2 * FS)) / FS
    pd.DataFrame({
        "time": t,
        "shaft": synth([(25.0, 1.0), (37.5, 0.05), *extra], FS, 2.0, noise=1e-3),
        "casing": synth([(25.0, 0.2)], FS, 2.0, noise=1e-3, seed=4),
    }).to_csv(path, index=False)
    return str(path)


def test_features_json(tmp_path, synth, capsys):
    path = _write(tmp_path / "a.csv", synth)
    assert main(["features", path, "--speed-rpm", str(RPM), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["channel"] for r in rows] == ["shaft", "casing"]
    assert rows[0]["amp_1x"] == pytest.approx(1.0, rel=0.01)
    assert rows[0]["amp_1p5x"] == pytest.approx(0.05, rel=0.02)
    assert rows[0]["freq_2x_hz"] is None and rows[0]["amp_2x"] == 0.0


def test_features_csv_table_and_column(tmp_path, synth, capsys):
    path = _write(tmp_path / "a.csv", synth)
    out = tmp_path / "f.csv"
    assert main(["features", path, "--speed-rpm", "1500", "--column", "casing",
                 "--csv", str(out)]) == 0
    table = pd.read_csv(out)
    assert list(table["channel"]) == ["casing"]
    assert table["amp_1x"].iloc[0] == pytest.approx(0.2, rel=0.01)
    assert main(["features", path, "--speed-rpm", "1500"]) == 0
    printed = capsys.readouterr().out
    assert "amp_1p5x" in printed and "shaft" in printed


def test_compare_prints_differences_and_writes_figure(tmp_path, synth, capsys):
    a = _write(tmp_path / "a.csv", synth)
    b = _write(tmp_path / "b.csv", synth, extra=[(100.0, 0.02), (95.0, 0.01), (105.0, 0.01)])
    fig = tmp_path / "cmp.png"
    assert main(["compare", a, b, "--speed-rpm", "1500", "--out", str(fig)]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("sb_4x_lower"))
    assert float(line.split()[-1]) == pytest.approx(0.01, rel=0.03)  # B - A
    line = next(ln for ln in out.splitlines() if ln.startswith("amp_4x"))
    assert float(line.split()[-1]) == pytest.approx(0.02, rel=0.03)
    assert fig.stat().st_size > 10_000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["features", "{missing}"], "no such file"),
        (["features", "{a}", "--speed-rpm", "1500", "--column", "blade"], "'blade' not found"),
        (["features", "{a}", "--fs", "-3"], "fs = -3.0 is out of range (allowed: > 0 Hz)"),
        (["features", "{a}", "--speed-rpm", "600000"], "Nyquist"),
        (["compare", "{a}", "{missing}"], "no such file"),
    ],
)
def test_errors_exit_2_with_one_line(tmp_path, synth, capsys, args, message):
    a = _write(tmp_path / "a.csv", synth)
    argv = [x.format(a=a, missing=str(tmp_path / "nope.csv")) for x in args]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


def test_help_states_units(capsys):
    with pytest.raises(SystemExit):
        main(["features", "--help"])
    text = capsys.readouterr().out
    assert "rpm" in text and "Hz" in text
