"""Every notebook in notebooks/ runs top to bottom on small inputs (RUBDIAG_QUICK=1) and shows
what it is about: figures that are not blank, and numbers that agree with the API."""

import base64
import io
import math
import re
from pathlib import Path

import numpy as np
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))
#: Slow, as make docs executes them too, and what they run is run by default elsewhere:
#: the classifier notebook (a minute and a half: the default evaluation with its shuffles,
#: baselines and audit, two noise curves) calls on the same small design what tests/learn
#: calls on small_dataset: evaluate (test_evaluate.py), train (test_train.py), noise_curve
#: (test_robustness.py), noise_curve_figure (test_figures.py), predict on a resampled CSV in
#: µm (test_predict.py); the faults notebook simulates the runs of fault_runs(duration_s=1.0)
#: and draws their faults_figure, which `rubdiag faults --duration-s 1.0` does in
#: tests/cli/test_fault_options.py, asserting the lines checked below by wider margins
SLOW = {"06_classifiers", "10_faults"}


def _execute(path, tmp_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    monkeypatch.setenv("RUBDIAG_QUICK", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    return [o for cell in nb.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]


def _text(outputs) -> str:
    parts = []
    for o in outputs:
        if o.get("output_type") == "stream":
            parts.append(o["text"])
        elif "data" in o and "text/plain" in o["data"]:
            parts.append(o["data"]["text/plain"])
    return "\n".join(parts)


@pytest.mark.parametrize("path", [
    pytest.param(p, marks=[pytest.mark.slow] if p.stem in SLOW else []) for p in NOTEBOOKS],
    ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_and_draws(path, tmp_path, monkeypatch):
    import matplotlib.image as mpimg

    outputs = _execute(path, tmp_path, monkeypatch)
    assert not [o for o in outputs if o.get("output_type") == "error"]
    pngs = [o["data"]["image/png"] for o in outputs if "image/png" in o.get("data", {})]
    assert pngs, "the notebook shows no figure"
    for encoded in pngs:
        pixels = mpimg.imread(io.BytesIO(base64.b64decode(encoded)), format="png")
        assert min(pixels.shape[:2]) > 100 and pixels[..., :3].std() > 0.02, "a blank figure"
    if path.stem == "01_rig_and_modes":
        # the critical speeds it prints are the API's (and the study's 1500 / 5700 rpm)
        from rubdiag.assembly import assemble
        from rubdiag.modal import critical_speeds
        from rubdiag.model import paper_rig

        line = re.search(r"forward critical speeds \(rpm\): \[([^\]]+)\]", _text(outputs))
        printed = [float(v) for v in line.group(1).split()]
        expected = critical_speeds(assemble(paper_rig()), n=2) * 30 / math.pi
        np.testing.assert_allclose(printed, expected, atol=0.05)
    if path.stem == "07_runup":
        # the tacho path (a measured record's) gives the exact angle's 1× track
        line = re.search(r"exact angle: largest difference ([\d.]+) %", _text(outputs))
        assert float(line.group(1)) < 0.5
    if path.stem == "10_faults":
        # each fault stands out of the healthy run at its speed by the line its model
        # predicts: the crack and the coupling by 2x, the loose pedestal by a subharmonic
        found = {fault: order for fault, order, _ in re.findall(
            r"(\w+): strongest line over the healthy run's: (\S+) x(\d+)", _text(outputs))}
        assert found.keys() == {"crack", "misalignment", "looseness"}
        assert found["crack"] == "2x" and found["misalignment"] == "2x"
        assert found["looseness"] in ("0.333x", "0.5x")
    if path.stem == "11_fluid_film":
        # the film's Jacobian is the closed forms' stiffness; above the threshold it whirls
        text = _text(outputs)
        difference = re.search(r"largest relative difference: (\S+)", text)
        assert float(difference.group(1)) < 1e-9
        share = re.search(r"whirl: share (\S+) of the journal", text)
        assert float(share.group(1)) > 0.9
