"""rubdiag features: a summary in words first, the table of every feature after it; the
--csv and --json outputs stay machine-readable (bad inputs: test_errors.py)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import rubdiag
from rubdiag.cli import main

FS = 2000.0


@pytest.fixture(scope="module")
def signals(tmp_path_factory):
    """Shaft: 1× (1.0) at 1500 rpm, 4× with sidebands ± 5 Hz, 3×/2 and 7×; casing: 1× only."""
    t = np.arange(int(2 * FS)) / FS
    noise = np.random.default_rng(1).standard_normal((2, t.size)) * 1e-4
    shaft = sum(a * np.cos(2 * np.pi * f * t) for f, a in (
        (25.0, 1.0), (37.5, 0.05), (100.0, 0.02), (95.0, 0.01), (105.0, 0.01), (175.0, 0.03)))
    path = tmp_path_factory.mktemp("signals") / "run.csv"
    pd.DataFrame({"time": t, "shaft": shaft + noise[0],
                  "casing": 0.2 * np.cos(2 * np.pi * 25.0 * t) + noise[1]}).to_csv(path,
                                                                                   index=False)
    return path


def test_summary_first_then_every_feature(signals, capsys):
    assert main(["features", str(signals), "--speed-rpm", "1500"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[:4] == [
        "shaft: 1500 rpm, RMS 0.7085, 1× 1 at 25.00 Hz",
        "  1× dominant; 4×, 7×; broadband peak around 4×; 4× ± 5.0 Hz sidebands; 3×/2",
        "casing: 1500 rpm, RMS 0.1414, 1× 0.2 at 25.00 Hz",
        "  1× dominant",
    ]
    n = len(rubdiag.features(str(signals), speed_rpm=1500).columns) - 1     # but 'channel'
    assert lines[4] == ""
    assert lines[5].startswith(f"all {n} features per channel (amplitudes in the signal's unit")
    table = {ln.split()[0]: ln.split()[1:] for ln in lines[6:]}
    assert table["channel"] == ["shaft", "casing"]
    assert len(lines) == 6 + 1 + n and len(table) == 1 + n
    assert float(table["amp_1p5x"][0]) == pytest.approx(0.05, rel=0.01)


def test_summary_only(signals, capsys):
    assert main(["features", str(signals), "--speed-rpm", "1500", "--summary",
                 "--column", "casing"]) == 0
    assert capsys.readouterr().out == ("casing: 1500 rpm, RMS 0.1414, 1× 0.2 at 25.00 Hz\n"
                                       "  1× dominant\n")
    # at 1100 rpm no line of the 25-Hz signal is a harmonic: 1× absent, nothing significant
    assert main(["features", str(signals), "--speed-rpm", "1100", "--summary",
                 "--column", "casing"]) == 0
    assert capsys.readouterr().out == ("casing: 1100 rpm, RMS 0.1414, 1× absent\n"
                                       "  no significant line\n")


def test_csv_and_json_are_the_feature_table_only(signals, tmp_path, capsys):
    expected = rubdiag.features(str(signals), speed_rpm=1500)
    out = tmp_path / "f.csv"
    assert main(["features", str(signals), "--speed-rpm", "1500", "--csv", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote 2 row(s) to {out}\n"
    pd.testing.assert_frame_equal(pd.read_csv(out), expected, check_dtype=False)
    assert main(["features", str(signals), "--speed-rpm", "1500", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)        # nothing but the JSON on stdout
    assert [r["channel"] for r in rows] == ["shaft", "casing"]
    assert list(rows[0]) == list(expected.columns)


def test_summary_of_a_simulation_result(tmp_path, capsys):
    from rubdiag.simulate import Run, simulate

    result = simulate(Run.paper_case(2, 1.9, speed_rpm=5700, duration_s=0.5, discard_s=0.2))
    path = result.save(tmp_path / "c2.npz")
    row = rubdiag.features(result).iloc[0]
    summary = result.summary()
    assert main(["features", str(path), "--summary"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == (f"{path}: case 2, g0 = 1.9 mm, 5700 rpm, 0.3 s analysed, "
                        "dt = 1e-05 s")
    assert [ln.split(":")[0] for ln in lines[1:]] == [
        "  1× (RMS)", "  shaft and blade tip", "  casing", "  contact 1", "  all contacts"]
    from rubdiag.paper.describe import describe_spectrum

    assert lines[1].startswith(f"  1× (RMS): shaft {row.shaft_amp_1x * 1e6:.4g} um "
                               f"({row.shaft_rms * 1e6:.4g} um), blade tip ")
    assert lines[2] == "  shaft and blade tip: " + describe_spectrum(row)   # as in Table 2
    assert lines[3] == "  casing: " + describe_spectrum(row, prefixes=("casing",))
    assert lines[4].startswith(
        f"  contact 1: max force {summary['contact1_max_force_n']:.1f} N, min ")
    assert (f"entries sliding {summary['contact1_sliding_entries']} / sticking "
            f"{summary['contact1_sticking_entries']}") in lines[4]
    assert lines[5] == (f"  all contacts: max force {summary['max_contact_force_n']:.1f} N, "
                        f"{summary['n_episodes']} episodes")
