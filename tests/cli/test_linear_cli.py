"""The linear-analysis commands (their bad inputs are in test_errors.py)."""

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.model import load_rig


def run(*args):
    return subprocess.run([sys.executable, "-m", "rubdiag", *args], capture_output=True,
                          text=True)


def test_modal_json(capsys):
    assert main(["modal", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    crit = out["critical_speeds_rpm"]
    assert crit == sorted(crit)
    np.testing.assert_allclose(crit[:2], [1500, 5700], rtol=0.005)
    assert out["rayleigh_alpha"] == pytest.approx(9.948, rel=1e-3)
    assert out["rayleigh_beta"] == pytest.approx(1.061e-4, rel=1e-3)
    assert out["n_dof"] == 412
    # the rotor's first bending pair at rest sits just below the first critical (25 Hz)
    assert out["natural_frequencies_at_rest_hz"][0] == pytest.approx(25.0, rel=0.02)


def test_modal_text(capsys):
    assert main(["modal"]) == 0
    text = capsys.readouterr().out
    assert "1500.0" in text and "5700.0" in text and "alpha = 9.9484 1/s" in text


def test_campbell_and_unbalance_write_figures_and_tables(tmp_path):
    assert main(["campbell", "--out", str(tmp_path), "--n-speeds", "5", "--n-modes", "4"]) == 0
    table = pd.read_csv(tmp_path / "campbell.csv")
    assert len(table) == 5 * 4 and (tmp_path / "campbell.png").stat().st_size > 10_000
    for case, critical in ((1, 1500), (2, 5700)):
        assert main(["unbalance", "--case", str(case), "--out", str(tmp_path),
                     "--n-speeds", "160"]) == 0
        curve = pd.read_csv(tmp_path / f"unbalance_case{case}.csv")
        peak = curve["speed_rpm"][curve["11_y_amplitude_m"].idxmax()]
        assert peak == pytest.approx(critical, rel=0.03)
        assert (tmp_path / f"deflection_case{case}.png").exists()


def test_calibrate_writes_a_rig_that_hits_the_targets(tmp_path):
    out = tmp_path / "cal.toml"
    assert main(["calibrate", "--targets-rpm", "1400", "5500", "--out", str(out)]) == 0
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds

    crit = critical_speeds(assemble(load_rig(out)), n=2) * 30 / np.pi
    np.testing.assert_allclose(crit, [1400, 5500], rtol=1e-3)


def test_every_command_has_help_with_units():
    for command, unit in (("modal", "JSON"), ("campbell", "rpm"), ("unbalance", "rpm"),
                          ("calibrate", "rpm")):
        result = run(command, "--help")
        assert result.returncode == 0 and unit in result.stdout
