"""The simulate command: JSON keys and units, a saved result, one-line errors."""

import json
import subprocess
import sys

import pytest

from rubdiag.cli import main
from rubdiag.simulate import load_result


def test_simulate_json_and_saved_result(capsys, tmp_path):
    out = tmp_path / "c2.npz"
    code = main(["simulate", "--case", "2", "--gap-mm", "2.3", "--duration-s", "0.4",
                 "--discard-s", "0.2", "--out", str(out), "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    for key in ("n_steps", "wall_s", "max_contact_force_n", "contact1_max_force_n",
                "casing_max_y_m", "shaft_max_y_m", "contact1_sliding_entries",
                "contact1_sticking_entries"):
        assert key in summary
    assert summary["speed_rpm"] == pytest.approx(5700, rel=0.005)    # 2nd critical by default
    assert summary["n_steps"] >= 0.4 / 1e-5
    assert summary["max_contact_force_n"] >= summary["contact1_max_force_n"] > 0
    assert 0 < summary["casing_max_y_m"] < 1e-3                       # metres, not µm
    result = load_result(out)
    assert result.run.gap_m == pytest.approx(2.3e-3)
    assert result.summary()["contact1_max_force_n"] == summary["contact1_max_force_n"]


def test_speed_and_friction_options(capsys):
    assert main(["simulate", "--case", "1", "--gap-mm", "2.3", "--speed-rpm", "1400",
                 "--mu", "0.0", "--duration-s", "0.3", "--discard-s", "0.1", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["speed_rpm"] == pytest.approx(1400)
    assert summary["contact1_sticking_entries"] == 0        # no friction: nothing sticks


@pytest.mark.parametrize("args,match", [
    (["--gap-mm", "-1"], "gap_mm = -1.0 is out of range"),
    (["--gap-mm", "2.3", "--dt-s", "0"], "dt_s = 0.0 is out of range"),
    (["--gap-mm", "2.3", "--mu", "-0.1"], "friction_coefficient = -0.1 is out of range"),
    (["--gap-mm", "2.3", "--duration-s", "1e-6"], "duration_s = 1e-06 is out of range"),
    (["--gap-mm", "nan"], "gap_mm = nan is out of range"),
])
def test_bad_input_exits_2_with_one_line(args, match):
    result = subprocess.run([sys.executable, "-m", "rubdiag", "simulate", "--case", "1", *args],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert match in result.stderr and "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
