"""dataset.json says how the channels were measured — what a classifier trained on the
dataset must know of a measurement — and reading a stored dataset needs no simulator."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from rubdiag.dataset import Design, acquisition, generate, load_waveforms

ONE_RUN = """
[base]
rig = "paper"
duration_s = 0.3
discard_s = 0.1

[sampling]
method = "grid"

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [4.0]
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("acq") / "ds"
    generate(Design.from_toml(ONE_RUN), out, jobs=1, progress=False, waveforms=True)
    return out


def test_acquisition_is_what_the_waveforms_hold(folder):
    design = Design.from_toml(ONE_RUN)
    acq = acquisition(folder)
    waves = load_waveforms(folder, design.runs()[0].run_id)
    assert acq["fs_hz"] == waves.attrs["fs_hz"]
    assert acq["discard_s"] == waves.attrs["discard_s"] == 0.1
    assert acq["window_s"] == pytest.approx(0.2, abs=1e-12)
    assert [s["name"] for s in acq["sensors"]] == list(waves.columns)
    assert {s["name"]: s["unit"] for s in acq["sensors"]} == waves.attrs["units"]
    assert [s["point"] for s in acq["sensors"]] == [s.point for s in design.sensors]


def test_a_folder_without_acquisition_gets_it_on_resume(folder, tmp_path):
    import shutil

    old = tmp_path / "old"
    shutil.copytree(folder, old)
    meta = json.loads((old / "dataset.json").read_text(encoding="utf-8"))
    expected = meta.pop("acquisition")
    (old / "dataset.json").write_text(json.dumps(meta), encoding="utf-8")
    with pytest.raises(ValueError, match="older rubdiag"):
        acquisition(old)
    summary = generate(Design.from_toml(ONE_RUN), old, jobs=1, progress=False)
    assert summary["run"] == 0                      # nothing simulated again
    assert acquisition(old) == expected


def test_reading_a_dataset_imports_no_simulator(folder):
    code = ("import sys; from rubdiag.dataset import load, load_waveforms, acquisition; "
            f"load({str(folder)!r}); acquisition({str(folder)!r}); "
            "from rubdiag.dataset.noise import add_noise; "
            "print(sorted(m for m in sys.modules if m.startswith(('rubdiag.simulate', "
            "'rubdiag.kernels', 'rubdiag.model', 'numba'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]"
