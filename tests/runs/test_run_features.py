"""Features of simulated runs: contact statistics against the sampled status and forces
(with every step sampled they must agree exactly), and the one-row-per-run table."""

import numpy as np
import pytest

import rubdiag
from rubdiag.runs import contact_statistics
from rubdiag.simulation import Run, simulate


@pytest.fixture(scope="module")
def every_step_run():
    # fixed step, every step recorded: the samples see everything the event log sees
    # (5 µs steps: fine enough for every step of case 2 to converge without relaxation)
    run = Run.paper_case(2, 1.9, duration_s=0.25, discard_s=0.12, dt_s=5e-6, fixed_step=True,
                         output_rate_hz=2e5, gap_ramp_s=0.05)
    return simulate(run)


def _sampled_episodes(status, force):
    """(peaks, steps, slide entries, stick entries) per episode, from a sampled sequence."""
    out, current = [], None
    previous = 1
    for s, f in zip(status, force, strict=True):
        if s != 1:
            if current is None:
                current = [0.0, 0, 0, 0]
            current[0] = max(current[0], f)
            current[1] += 1
            current[2] += s == 2 and previous != 2
            current[3] += s == 3 and previous != 3
        elif current is not None:
            out.append(current)
            current = None
        previous = s
    if current is not None:
        out.append(current)
    return out


def test_statistics_match_the_sampled_status_and_forces(every_step_run):
    r = every_step_run
    stats = contact_statistics(r)
    sys = r.system
    start = np.searchsorted(r.t, r.run.discard_s - 1e-12)
    for e in range(sys.contact_fn.shape[1]):
        status = sys.contact_status[:, e]
        # episodes that start in the window: begin at a sample >= start that follows an open one
        episodes = _sampled_episodes(status[start - 1:], sys.contact_fn[start - 1:, e])
        if status[start - 1] != 1 and episodes:
            episodes = episodes[1:]      # that one started before the window
        k = f"contact{e + 1}_"
        assert stats[k + "n_episodes"] == len(episodes)
        if not episodes:
            continue
        peaks = np.array([p[0] for p in episodes])
        assert stats[k + "max_force_n"] == pytest.approx(peaks.max(), rel=1e-12)
        lasting = peaks[np.array([p[1] for p in episodes]) >= 2]
        if lasting.size:
            assert stats[k + "min_force_n"] == pytest.approx(lasting.min(), rel=1e-12)
        assert stats[k + "sliding_entries"] == sum(p[2] for p in episodes)
        assert stats[k + "sticking_entries"] == sum(p[3] for p in episodes)
    # shares and mean forces from the samples of contact element 1 (every step is a sample)
    window = r.window
    st, fn = sys.contact_status[window, 0], sys.contact_fn[window, 0]
    closed = st != 1
    if closed.any():
        share = np.sum(st == 3) / np.sum(closed)
        assert stats["contact1_sticking_share"] == pytest.approx(share, abs=0.02)
        if np.any(st == 3):
            assert stats["contact1_mean_force_sticking_n"] == pytest.approx(
                fn[st == 3].mean(), rel=0.05)
    # the paper's finding: sticking happens at larger normal force than sliding
    assert stats["contacts_mean_force_sticking_n"] > stats["contacts_mean_force_sliding_n"]
    assert stats["casing_max_y_m"] == pytest.approx(
        r.displacement("casing 1 y", windowed=True).max())


def test_per_second_and_per_revolution_rates(every_step_run):
    stats = contact_statistics(every_step_run)
    window = stats["window_s"]
    assert window == pytest.approx(0.25 - 0.12)
    revs = window * every_step_run.run.speed_rad_s / (2 * np.pi)
    n = stats["contact1_sliding_entries"]
    assert stats["contact1_sliding_entries_per_s"] == pytest.approx(n / window)
    assert stats["contact1_sliding_entries_per_rev"] == pytest.approx(n / revs)


def test_one_row_per_run_with_prefixed_spectra(every_step_run, tmp_path):
    table = rubdiag.run_features(every_step_run, min_revolutions=5)
    assert len(table) == 1
    row = table.iloc[0]
    for column in ("shaft_amp_1x", "blade_amp_1x", "casing_amp_1x", "contact1_max_force_n",
                   "contact8_sticking_share", "contacts_max_force_n", "speed_rpm", "gap_m"):
        assert column in table.columns
    # the shaft columns are the features of the windowed shaft signal itself
    shaft = every_step_run.displacement("shaft 11 y", windowed=True)
    alone = rubdiag.signal_features(shaft, every_step_run.fs, every_step_run.run.speed_rpm,
                                    min_revolutions=5).iloc[0]
    assert row["shaft_amp_1x"] == pytest.approx(alone["amp_1x"], rel=1e-12)
    # a saved result gives the same row
    path = every_step_run.save(tmp_path / "r.npz")
    again = rubdiag.run_features(str(path), min_revolutions=5)
    assert again.iloc[0]["contact1_max_force_n"] == row["contact1_max_force_n"]
    assert again.iloc[0]["shaft_amp_1x"] == pytest.approx(row["shaft_amp_1x"], rel=1e-12)


def test_cli_reads_simulation_results(every_step_run, tmp_path, capsys):
    import json

    from rubdiag.cli import main

    a = every_step_run.save(tmp_path / "a.npz")
    assert main(["features", str(a), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == 1                       # one row for the run, as the Python API
    api = rubdiag.run_features(every_step_run).iloc[0]
    assert rows[0]["shaft_amp_1x"] == pytest.approx(api["shaft_amp_1x"], rel=1e-12)
    assert rows[0]["contact1_max_force_n"] == pytest.approx(api["contact1_max_force_n"])
    assert rows[0]["speed_rpm"] == pytest.approx(every_step_run.run.speed_rpm)
    assert main(["compare", str(a), str(a), "--out", str(tmp_path / "c.png")]) == 0
    out = capsys.readouterr().out
    assert "channel 'shaft'" in out
    assert (tmp_path / "c.png").stat().st_size > 10_000


def test_compare_a_healthy_and_a_rubbing_run(tmp_path, capsys):
    from rubdiag.cli import main

    healthy = simulate(Run.paper_case(1, 5.0, duration_s=0.8, discard_s=0.3))   # never touches
    rubbing = simulate(Run.paper_case(1, 1.9, duration_s=0.8, discard_s=0.3))
    assert healthy.summary()["n_episodes"] == 0 and rubbing.summary()["n_episodes"] > 0
    # a healthy run is a row like any other (datasets mix them): same columns, the casing's
    # lines absent (amplitude 0, location NaN) and no contact statistics
    rows = rubdiag.run_features([healthy, rubbing])
    assert len(rows) == 2 and rows.columns.is_unique
    quiet = rows.iloc[0]
    assert quiet["casing_amp_1x"] == 0.0 and np.isnan(quiet["casing_freq_1x_hz"])
    assert quiet["casing_rms"] == 0.0 and quiet["contact1_n_episodes"] == 0
    assert quiet["contact1_max_force_n"] == 0.0 and np.isnan(quiet["contact1_min_force_n"])
    assert np.isnan(quiet["contact1_sticking_share"]) and quiet["shaft_amp_1x"] > 2e-3
    assert rows.iloc[1]["casing_amp_1x"] > 0
    a, b = healthy.save(tmp_path / "a.npz"), rubbing.save(tmp_path / "b.npz")
    assert main(["compare", str(a), str(b), "--out", str(tmp_path / "c.png")]) == 0
    out = capsys.readouterr().out
    assert "channel 'shaft'" in out and "amp_1x" in out
    assert (tmp_path / "c.png").stat().st_size > 10_000
