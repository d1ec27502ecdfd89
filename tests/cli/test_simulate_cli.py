"""The simulate command: JSON keys and units, a saved result (bad inputs: test_errors.py)."""

import json

import pytest

from rubdiag.cli import main
from rubdiag.simulation import load_result


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


def test_output_rate_and_out_without_suffix(capsys, tmp_path):
    """--output-rate-hz sets the waveform rate; --out without .npz saves (and says) FILE.npz."""
    assert main(["simulate", "--case", "1", "--gap-mm", "2.3", "--speed-rpm", "1500",
                 "--duration-s", "0.12", "--discard-s", "0.1", "--output-rate-hz", "5000",
                 "--out", str(tmp_path / "run")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == f"saved {tmp_path / 'run.npz'}"
    result = load_result(tmp_path / "run.npz")
    assert result.fs == pytest.approx(5000.0)
    assert result.t.size == round(0.12 * 5000) + 1
    assert [p.name for p in tmp_path.iterdir()] == ["run.npz"]   # no temporary file left
