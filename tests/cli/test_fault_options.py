"""``rubdiag simulate`` with the faults that look like rub: a run
without rub needs no --gap-mm; bad fault options get one line and exit 2."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from rubdiag.cli import main
from rubdiag.simulation import load_result

RUN = ["simulate", "--case", "1", "--speed-rpm", "750", "--duration-s", "0.3",
       "--discard-s", "0.1"]


def test_a_cracked_run_without_rub(tmp_path, capsys):
    out = tmp_path / "crack.npz"
    assert main([*RUN, "--gravity-m-s2", "-9.81", "--crack-element", "10", "--crack-depth",
                 "0.4", "--crack-law", "gasch", "--json", "--out", str(out)]) == 0
    summary = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert summary["gap_m"] is None and summary["status"] == 0
    result = load_result(out)
    crack = result.run.faults.crack
    assert (crack.element, crack.depth_ratio, crack.law) == (10, 0.4, "gasch")
    assert result.run.static_load.gravity_m_s2 == -9.81
    # the crack is the run's only nonlinear element, and Gasch's crack opens and closes
    assert result.system.contact_status.shape[1] == 1
    assert set(np.unique(result.system.contact_status)) == {1, 2}


def test_a_misaligned_run_with_rub(tmp_path, capsys):
    assert main([*RUN, "--gap-mm", "50", "--misalignment-offset-mm", "0.5"]) == 0
    text = capsys.readouterr().out
    assert "faults: misalignment" in text and "contact-1 max force" in text


def test_no_gap_and_no_fault_is_one_line_and_exit_2(capsys):
    assert main(RUN) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--gap-mm is missing" in err[0]


def test_a_crack_off_the_shaft_is_one_line_and_exit_2(capsys):
    assert main([*RUN, "--crack-element", "99"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "faults.crack.element = 99" in err[0]


def test_a_cracked_runup_without_rub_counts_no_contact(tmp_path, capsys):
    """The crack is a nonlinear element of the run, not a contact: no contact episodes."""
    assert main(["runup", "--case", "1", "--from-rpm", "700", "--to-rpm", "800",
                 "--rate-rpm-s", "100", "--gravity-m-s2", "-9.81", "--crack-element", "10",
                 "--out", str(tmp_path / "r"), "--json"]) == 0
    (summary,) = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert summary["n_episodes"] == 0 and np.isnan(summary["first_contact_rpm"])


def test_the_faults_figures_show_each_fault_s_lines_beside_rub(tmp_path, capsys):
    """``rubdiag faults``: each fault's predicted lines stand out of the healthy run's at its
    speed (crack 2x and 3x, coupling 2x at 750 rpm; the loose pedestal's 1/3x and 1/2x
    across gravity at 1450 rpm; oil whip at the first natural frequency on paper-journal),
    the rub runs rub at the stated interference and show 4x, and one figure per fault is
    drawn (not blank)."""
    import matplotlib.image as mpimg

    assert main(["faults", "--out", str(tmp_path), "--duration-s", "1.0", "--json"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""                     # no progress bar off a terminal
    lines = json.loads(captured.out.splitlines()[-1])
    slow, fast = lines["none 750"]["y"], lines["none 1450"]["z"]
    assert lines["crack"]["y"]["2x"] > 100 * slow["2x"]
    assert lines["crack"]["y"]["3x"] > 100 * slow["3x"]
    assert lines["misalignment"]["y"]["2x"] > 100 * slow["2x"]
    assert lines["rub 750"]["y"]["4x"] > 100 * slow["4x"]
    loose = lines["looseness"]
    assert max(loose["z"]["0.333x"], loose["z"]["0.5x"]) > 20 * max(fast["0.333x"],
                                                                     fast["0.5x"])
    # across gravity: the subharmonic is in z, the loose direction
    assert loose["z"]["0.333x"] > 10 * loose["y"]["0.333x"]
    # oil whip on paper-journal: the line at the first natural frequency (an order under
    # 0.45 at 1.06 of the threshold) dwarfs 1x, and the rub below the threshold has none
    whip = lines["whirl journal"]["y"]
    (order,) = [k for k in whip if float(k[:-1]) < 0.45]
    assert whip[order] > 5 * whip["1x"]
    assert lines["rub journal"]["y"][order] < 0.01 * whip[order]
    for fault in ("crack", "misalignment", "looseness", "whirl"):
        pixels = mpimg.imread(tmp_path / f"faults_{fault}.png")
        assert min(pixels.shape[:2]) > 400 and pixels[..., :3].std() > 0.02


def test_the_faults_rub_runs_take_their_gap_from_the_interference():
    """The rub run's gap is its linear blade-tip approach over ``interference``; bad
    input: the CLI's one line, exit 2."""
    from rubdiag.dataset._approach import sweep_linear_approach_m
    from rubdiag.runs import fault_runs

    made = fault_runs(interference=2.0, duration_s=1.0)
    for rpm in (750, 1450):
        rub = made[f"rub {rpm}"]
        far = dataclasses.replace(rub, gap_m=0.05)
        assert rub.gap_m == pytest.approx(sweep_linear_approach_m(far) / 2.0, rel=1e-12)
        assert rub.static_load is not None and rub.faults is None
    assert made["crack"].contact_law is None        # the faults' runs do not rub
    with pytest.raises(ValueError, match="interference"):
        fault_runs(interference=0.0)


def test_a_loose_pedestal_from_a_rig_file(tmp_path, capsys):
    """--loose-bearing on a rig file whose bearing stands on a pedestal: the run's seat
    lifts off above the threshold; on the paper rig (no pedestal) one line and exit 2."""
    import dataclasses

    from rubdiag.model import Pedestal, paper_rig, save_rig

    rig = paper_rig()
    pedestal = Pedestal(mass_kg=20.0, k_y_n_m=2e7, k_z_n_m=2e7, c_y_ns_m=500.0,
                        c_z_ns_m=500.0)
    bearings = (dataclasses.replace(rig.bearings[0], pedestal=pedestal), *rig.bearings[1:])
    path = tmp_path / "rig.toml"
    save_rig(dataclasses.replace(rig, bearings=bearings), path)
    out = tmp_path / "loose.npz"
    assert main(["simulate", "--case", "1", "--speed-rpm", "2999", "--duration-s", "0.2",
                 "--discard-s", "0.1", "--rig", str(path), "--loose-bearing", "0",
                 "--loose-preload-n", "2", "--loose-stiffness-n-m", "2e6",
                 "--out", str(out)]) == 0
    result = load_result(out)
    assert result.run.faults.looseness.bearing == 0
    status = result.system.contact_status[:, -1]     # the pedestal: the run's only element
    assert result.system.contact_status.shape[1] == 1 and (status == 3).any()
    capsys.readouterr()
    assert main([*RUN, "--loose-bearing", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "faults.looseness.bearing = 0" in err[0]


def test_a_pedestal_loose_across_gravity_on_the_preset_rig(tmp_path):
    """--rig paper-pedestal --loose-direction z: gravity along y no longer presses the seat,
    so 0.2 N lets it lift at 750 rpm (the 1x bearing force is about 0.5 N); along y the
    pedestal's weight holds it."""
    from rubdiag._kernels import pedestal

    def lifted(direction):
        out = tmp_path / f"loose-{direction}.npz"
        assert main([*RUN, "--rig", "paper-pedestal", "--gravity-m-s2", "-9.81",
                     "--loose-bearing", "0", "--loose-preload-n", "0.2", "--loose-direction",
                     direction, "--out", str(out)]) == 0
        result = load_result(out)
        assert result.run.faults.looseness.direction == direction
        return np.mean(result.system.contact_status[:, -1] != pedestal.SEATED)
    assert lifted("z") > 0.5 and lifted("y") == 0.0


def test_an_angular_misalignment_alone_makes_a_coupling(tmp_path):
    out = tmp_path / "angle.npz"
    assert main([*RUN, "--misalignment-angle-deg", "0.5", "--out", str(out)]) == 0
    coupling = load_result(out).run.faults.misalignment
    assert coupling.offset_m == 0.0 and coupling.angle_rad == pytest.approx(np.radians(0.5))
