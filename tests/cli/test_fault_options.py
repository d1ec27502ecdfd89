"""``rubdiag simulate`` with the faults that look like rub (issue 26, part 5 in part): a run
without rub needs no --gap-mm; bad fault options get one line and exit 2."""

from __future__ import annotations

import json

import numpy as np

from rubdiag.cli import main
from rubdiag.simulate import load_result

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


def test_the_faults_figure_shows_each_fault_s_line(tmp_path, capsys):
    """``rubdiag faults``: each fault's predicted line stands out of the healthy run's, and
    the figure is drawn (not blank)."""
    import matplotlib.image as mpimg

    assert main(["faults", "--out", str(tmp_path), "--duration-s", "0.4", "--json"]) == 0
    lines = json.loads(capsys.readouterr().out.splitlines()[-1])
    healthy = lines["none"]
    assert lines["crack"]["2x"] > 100 * healthy["2x"]
    assert lines["crack"]["3x"] > 100 * healthy["3x"]
    assert lines["misalignment"]["2x"] > 100 * healthy["2x"]
    assert lines["rub"]["4x"] > 100 * healthy["4x"]
    pixels = mpimg.imread(tmp_path / "faults.png")
    assert min(pixels.shape[:2]) > 500 and pixels[..., :3].std() > 0.02


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
