"""The shipped design data/designs/rub_lhs200.toml (200 runs of 2.3 s) runs as
written: one row per run with the labels, the measures and the sensor features (slow:
about 15 min on 2 cores). The fast test checks what can be checked without simulating."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rubdiag.dataset import Design, generate, labels_from_measures, load
from rubdiag.dataset._labels import LABELS, MEASURES

DESIGN = Path(__file__).resolve().parents[2] / "data" / "designs" / "rub_lhs200.toml"


def test_the_rub_lhs200_design_is_valid_and_covers_both_cases():
    design = Design.from_toml(DESIGN)
    runs = design.runs()
    assert len(runs) == 200 == len({r.run_id for r in runs})
    cases = [r.point["case"] for r in runs]
    assert cases.count(1) == cases.count(2) == 100        # lhs: n/k points per level
    gaps = np.array([r.point["gap_mm"] for r in runs])
    assert gaps.min() < 0.6 and gaps.max() > 3.9
    assert all(r.run.sensors == design.sensors for r in runs)


@pytest.mark.slow
def test_the_rub_lhs200_design_runs_as_written(tmp_path):
    design = Design.from_toml(DESIGN)
    generate(design, tmp_path / "ds", jobs=2, progress=False)
    rows = load(tmp_path / "ds")
    assert len(rows) == 200 and rows["run_id"].is_unique
    assert set(rows["run_id"]) == {r.run_id for r in design.runs()}
    assert (rows["status"] == "ok").all(), rows.loc[rows["status"] != "ok", "message"]
    for column in (*LABELS, *MEASURES, "point_id", "replicate", "shaft11_y_disp__amp_1x",
                   "casing1_y_acc__rms", "contact1__max_force_n"):
        assert rows[column].notna().all(), column
    # both labels occur: the gap range reaches runs that do not rub and runs that do
    assert set(rows["rub"]) == {True, False}
    assert {"light", "serious", "none"} <= set(rows["severity"])
    # the stored labels are the rules applied to the stored measures
    for _, row in rows.iterrows():
        again = labels_from_measures(row.to_dict(), design.labels)
        assert tuple(again[k] for k in LABELS) == tuple(row[k] for k in LABELS)
