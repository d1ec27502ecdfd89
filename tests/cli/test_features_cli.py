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
    n = len(rubdiag.signal_features(str(signals), speed_rpm=1500).columns) - 1     # but 'channel'
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
    expected = rubdiag.signal_features(str(signals), speed_rpm=1500)
    out = tmp_path / "f.csv"
    assert main(["features", str(signals), "--speed-rpm", "1500", "--csv", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote 2 row(s) to {out}\n"
    pd.testing.assert_frame_equal(pd.read_csv(out), expected, check_dtype=False)
    assert main(["features", str(signals), "--speed-rpm", "1500", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)        # nothing but the JSON on stdout
    assert [r["channel"] for r in rows] == ["shaft", "casing"]
    assert list(rows[0]) == list(expected.columns)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """A rubbing case-2 run (shaft, blade and casing move) and its saved result file."""
    from rubdiag.simulation import Run, simulate

    result = simulate(Run.paper_case(2, 1.9, speed_rpm=5700, duration_s=0.5, discard_s=0.2))
    return result, result.save(tmp_path_factory.mktemp("simulated") / "c2.npz")


def test_summary_of_a_simulation_result(simulated, capsys):
    result, path = simulated
    row = rubdiag.run_features(result).iloc[0]
    summary = result.summary()
    assert main(["features", str(path), "--summary"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == (f"{path}: case 2, g0 = 1.9 mm, 5700 rpm, 0.3 s analysed, "
                        "dt = 1e-05 s")
    assert [ln.split(":")[0] for ln in lines[1:]] == [
        "  1× (RMS)", "  shaft and blade tip", "  casing", "  contact 1", "  all contacts"]
    from rubdiag.paper._describe import describe_spectrum

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


@pytest.fixture(scope="module")
def run_ups(tmp_path_factory):
    """Two run-ups 600 -> 2400 rpm over 6 s (150 revolutions) with a tacho and the angle:
    A has 1× (1.0), 1.5× (0.3) and 2× (0.5); B has a 0.5× of 0.1 besides."""
    t = np.arange(int(6 * FS)) / FS
    phi = 2 * np.pi * (10 * t + 2.5 * t**2)
    psi = np.mod(phi + np.pi, 2 * np.pi) - np.pi         # pulses rise through 0.5 at φ = 0
    tacho = np.clip(0.5 + psi / 0.4, 0, 1) * (psi < 1.0)
    noise = np.random.default_rng(2).standard_normal((2, t.size)) * 1e-4
    x = np.cos(phi) + 0.3 * np.cos(1.5 * phi + 1.0) + 0.5 * np.cos(2 * phi)
    folder = tmp_path_factory.mktemp("run_ups")
    paths = []
    for name, extra, n in (("a", 0.0, noise[0]), ("b", 0.1 * np.cos(0.5 * phi), noise[1])):
        path = folder / f"{name}.csv"
        pd.DataFrame({"time": t, "shaft": x + extra + n, "tacho": tacho,
                      "phi": phi}).to_csv(path, index=False)
        paths.append(str(path))
    return paths


def test_features_across_speed_csv(run_ups, tmp_path, capsys):
    out = tmp_path / "bins.csv"
    assert main(["features", run_ups[0], "--tacho", "tacho", "--revs-per-bin", "24",
                 "--column", "shaft", "--csv", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote 6 row(s) to {out}\n"
    table = pd.read_csv(out)
    expected = rubdiag.signal.revolution_features(run_ups[0], tacho="tacho",
                                                     revs_per_bin=24, columns="shaft")
    pd.testing.assert_frame_equal(table, expected, check_dtype=False)
    assert table.rpm.is_monotonic_increasing
    assert table.rpm.iloc[0] < 900 and table.rpm.iloc[-1] > 2200     # 600 -> 2400 rpm
    np.testing.assert_allclose(table[["amp_1x", "amp_1p5x", "amp_2x"]], [[1.0, 0.3, 0.5]] * 6,
                               rtol=0.01)
    np.testing.assert_allclose(table.freq_1p5x_order, 1.5, atol=1e-3)
    # the recorded angle instead of the tacho: the same bins (the tacho's angle is 0 at φ = 0)
    assert main(["features", run_ups[0], "--angle", "phi", "--revs-per-bin", "24",
                 "--column", "shaft", "--json"]) == 0
    rows = pd.DataFrame(json.loads(capsys.readouterr().out))
    np.testing.assert_allclose(rows.rpm, table.rpm, rtol=1e-4)
    np.testing.assert_allclose(rows.amp_1p5x, table.amp_1p5x, rtol=1e-3)


def test_features_across_speed_printed(run_ups, capsys):
    assert main(["features", run_ups[0], "--revs-per-bin", "24", "--column", "shaft"]) == 0
    lines = capsys.readouterr().out.splitlines()
    table = rubdiag.signal.revolution_features(run_ups[0], revs_per_bin=24, columns="shaft")
    assert lines[0] == (f"shaft: 6 bins of 24 revolutions, {table.rpm.min():.0f} to "
                        f"{table.rpm.max():.0f} rpm, 1× {table.amp_1x.min():.4g} to "
                        f"{table.amp_1x.max():.4g}")
    assert lines[1].split() == ["bin", "rev_start", "t_s", "rpm", "rms", "amp_0p5x", "amp_1x",
                                "amp_1p5x", "amp_2x", "amp_4x", "n_half_orders",
                                "n_third_orders"]
    assert [float(ln.split()[3]) for ln in lines[2:8]] == pytest.approx(table.rpm, rel=1e-5)
    assert lines[-1].startswith(f"all {len(table.columns) - 5} features per bin with --csv")
    assert main(["features", run_ups[0], "--revs-per-bin", "24", "--column", "shaft",
                 "--summary"]) == 0
    assert capsys.readouterr().out.splitlines() == lines[:1]


def test_compare_across_speed(run_ups, tmp_path, capsys):
    fig = tmp_path / "speed.png"
    assert main(["compare", *run_ups, "--tacho", "tacho", "--column", "shaft",
                 "--revs-per-bin", "24", "--out", str(fig)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("channel 'shaft': A = ")
    assert "B at the speeds of A's bins" in lines[0]
    rows = np.array([[float(v) for v in ln.split()] for ln in lines[3:-1]])
    assert rows.shape == (6, 11)                 # rpm, then A and B - A of five orders
    np.testing.assert_allclose(rows[:, 1:3], [[0.0, 0.1]] * 6, rtol=0.01,     # 0.5×: B only
                               atol=1e-4)          # (the tacho's angle: 3e-5 of 1× at 0.5×)
    np.testing.assert_allclose(rows[:, 3], 1.0, rtol=0.01)                     # 1× of A
    assert np.abs(rows[:, [4, 6, 8, 10]]).max() < 1e-3                         # B - A
    assert lines[-1] == f"wrote {fig}" and fig.stat().st_size > 10_000


@pytest.mark.parametrize(("args", "message"), [
    (["--revs-per-bin", "0"], "revs_per_bin = 0 is out of range (allowed: >= 10"),
    (["--revs-per-bin", "24", "--speed-rpm", "1500"], "--revs-per-bin takes the speed from"),
    (["--revs-per-bin", "24", "--tacho", "tacho", "--angle", "phi"],
     "give --tacho or --angle, not both"),
    (["--angle", "phi"], "--angle gives the shaft angle for --revs-per-bin"),
    (["--revs-per-bin", "24", "--angle", "shaft"], "angle[1] = "),
])
def test_features_across_speed_bad_input(run_ups, capsys, args, message):
    assert main(["features", run_ups[0], *args]) == 2
    out = capsys.readouterr()
    assert out.out == ""
    assert out.err.startswith(f"rubdiag features: error: {message}")
    assert out.err.count("\n") == 1


# --- one speed estimator, units, every channel compared ------------------

RPM = 1500.0


def _probe_then_shaft(path, extra=(), seed=5):
    """A bearing probe that sees only its noise (1 µm), first in the file, then the
    mid-span shaft: 1× of 50 µm at 1500 rpm and 1.5× of 5 µm, plus ``extra`` (order, m)."""
    t = np.arange(int(2 * FS)) / FS
    noise = np.random.default_rng(seed).standard_normal((2, t.size)) * 1e-6
    lines = [(1.0, 50e-6), (1.5, 5e-6), *extra]
    shaft = sum(a * np.cos(2 * np.pi * k * RPM / 60 * t + k) for k, a in lines)
    pd.DataFrame({"time": t, "probe": noise[0], "shaft": shaft + noise[1]}).to_csv(
        path, index=False)
    return str(path)


def test_a_noise_only_first_channel_does_not_stop_features(tmp_path, capsys):
    path = _probe_then_shaft(tmp_path / "a.csv")
    assert main(["features", path, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["channel"] for r in rows] == ["probe", "shaft"]
    for r in rows:                            # the record's speed, the shaft's line
        assert r["speed_rpm"] == pytest.approx(RPM, rel=1e-5)
    assert rows[1]["amp_1p5x"] == pytest.approx(5e-6, rel=0.01)
    assert rows[0]["amp_1x"] == 0.0           # the probe: noise, analysed at that speed


def test_a_noise_only_first_channel_does_not_stop_compare(tmp_path, capsys):
    a = _probe_then_shaft(tmp_path / "a.csv")
    b = _probe_then_shaft(tmp_path / "b.csv", extra=[(0.5, 4e-6)], seed=6)
    assert main(["compare", a, b, "--unit", "m"]) == 0
    blocks = _blocks(capsys.readouterr().out)
    assert list(blocks) == ["probe", "shaft"]
    shaft = blocks["shaft"]
    assert shaft["speed_rpm"][:2] == pytest.approx([RPM, RPM], rel=1e-5)
    assert shaft["amp_0p5x"][2] == pytest.approx(4e-6, rel=0.02)     # B - A


def _blocks(out: str) -> dict[str, dict[str, list[float]]]:
    """compare's printed blocks: channel -> feature -> [A, B, B - A]."""
    blocks, channel = {}, None
    for line in out.splitlines():
        if line.startswith("channel "):
            channel = line.split("'")[1]
            blocks[channel] = {"header": line}
        elif channel and line.strip() and not line.startswith((" ", "wrote ")):
            name, *values = line.split()
            blocks[channel][name] = [float(v) for v in values]
    return blocks


def test_compare_covers_every_channel_of_two_results(simulated, tmp_path, capsys):
    """Simulation results: shaft, blade and casing, as the help says; amplitudes in m."""
    result, path = simulated
    fig = tmp_path / "cmp.png"
    assert main(["compare", str(path), str(path), "--out", str(fig)]) == 0
    out = capsys.readouterr().out
    blocks = _blocks(out)
    assert list(blocks) == ["shaft", "blade", "casing"]
    row = rubdiag.run_features(result).iloc[0]
    for channel, block in blocks.items():
        assert block["header"].endswith("(amplitudes in m, frequencies in Hz)")
        assert block["amp_1x"][0] == pytest.approx(row[f"{channel}_amp_1x"], rel=1e-5)
        assert block["amp_1x"][2] == 0.0                                  # B - A of A itself
    from matplotlib.image import imread

    assert imread(fig).shape[0] == round(3 * 4.2 * 120)                 # a panel each
    assert out.splitlines()[-1] == f"wrote {fig}"


def test_units_are_labelled_from_the_file_or_unit(simulated, tmp_path, capsys):
    _, path = simulated
    assert main(["features", str(path)]) == 0
    assert "features per run (amplitudes in m, frequencies in Hz" in capsys.readouterr().out
    csv = _probe_then_shaft(tmp_path / "a.csv")
    for args, words in (([], "the signal's unit"), (["--unit", "um"], "um")):
        assert main(["features", csv, "--speed-rpm", "1500", *args]) == 0
        assert f"features per channel (amplitudes in {words}, " in capsys.readouterr().out
    assert main(["compare", csv, csv, "--unit", "mm", "--column", "shaft"]) == 0
    assert "(amplitudes in mm, frequencies in Hz)" in capsys.readouterr().out
    # a result is in m: another --unit is refused in one line
    assert main(["compare", str(path), str(path), "--unit", "mm"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a simulation result, in m (allowed: --unit m" in err


def test_a_result_read_as_a_record_of_sensors_says_what_it_is(simulated):
    """``read_signals`` (what ``rubdiag predict`` reads) on a simulation result: it names
    the file as a result and what reads one (it said "KeyError('channels')")."""
    from rubdiag.signal import read_signals

    _, path = simulated
    with pytest.raises(ValueError) as info:
        read_signals(path)
    message = str(info.value)
    assert "\n" not in message and "KeyError" not in message
    assert message.startswith(f"{path.name}: a simulation result (rubdiag simulate --out), "
                              "not a record of sensors")


def test_compare_keeps_a_casing_that_moves_in_one_result_only(simulated, tmp_path, capsys):
    """A run without rub (its casing never moves) against a rubbing one: the casing — the
    largest difference — is compared too (it was left out, unsaid); flat in both, it is not."""
    from rubdiag.simulation import Run, simulate

    _, rubbing = simulated
    quiet = simulate(Run.paper_case(2, 5.0, speed_rpm=5700, duration_s=0.5, discard_s=0.2))
    assert quiet.summary()["casing_max_y_m"] == 0.0            # the premise: untouched
    healthy = quiet.save(tmp_path / "healthy.npz")
    assert main(["compare", str(healthy), str(rubbing)]) == 0
    blocks = _blocks(capsys.readouterr().out)
    assert list(blocks) == ["shaft", "blade", "casing"]
    a, b, diff = blocks["casing"]["rms"]
    assert a == 0.0 and b > 0.0 and diff == b
    assert main(["compare", str(healthy), str(healthy)]) == 0
    assert list(_blocks(capsys.readouterr().out)) == ["shaft", "blade"]
