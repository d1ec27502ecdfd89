"""Every dataset row says which model made it (``model``: "full" or "reduced"); a folder made
before the column existed reads as the full model's; the column map and the card say so.
The simulator is replaced where a real run adds nothing (the rows of real runs are checked in
test_generate.py)."""

from unittest import mock

import pandas as pd
import pyarrow as pa
import pytest

import rubdiag.simulation
from rubdiag.dataset import Design, load
from rubdiag.dataset._card import card_text, column_map
from rubdiag.dataset._rows import make_row
from rubdiag.dataset._schema import MODEL_COLUMN, MODEL_KINDS
from rubdiag.dataset._store import DatasetFolder

TOML = """
[base]
critical_speeds_rad_s = [150.0, 600.0]
{model}
[sampling]
method = "grid"

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.9, 2.3]
"""


def design(model: str = "") -> Design:
    return Design.from_toml(TOML.format(model=model))


class Boom(RuntimeError):
    pass


@pytest.mark.parametrize(("model", "kind"), [("", "full"), ("reduced = true", "reduced")])
def test_a_row_says_its_model_also_when_the_run_fails(model, kind):
    item = design(model).runs()[0]
    seen = []

    def fake(run, progress=None):
        seen.append(run)
        raise Boom("no simulation here")

    with mock.patch.object(rubdiag.simulation, "simulate", fake):
        row = make_row(item)
    assert seen == [item.run]                 # the design's run, reduction and all
    assert row["status"] == "error" and "Boom" in row["message"]
    assert row[MODEL_COLUMN] == kind and kind in MODEL_KINDS
    keys = list(row)
    assert keys.index(MODEL_COLUMN) == keys.index("speed_rpm") + 1


def _old_folder(root, with_model: bool | None = None):
    """A dataset folder as rubdiag wrote it before rows had a model column (or, with
    ``with_model``, one whose rows have it)."""
    folder = DatasetFolder(root)
    folder.create(design().to_toml())
    rows = [{"run_id": f"{i:016x}", "point_id": f"{i:016x}", "replicate": 0, "case": 2,
             "speed_ratio": 1.0, "gap_mm": 1.9 + i, "speed_rpm": 5700.0, "rub": bool(i),
             "rubdiag_version": "0.x", "status": "ok", "message": "", "wall_s": 1.0,
             "simulate_s": 0.9} for i in range(2)]
    if with_model:
        for row in rows:
            row[MODEL_COLUMN] = "reduced"
    folder.write_chunk(rows, pa.Table.from_pylist(rows).schema)
    return root


def test_an_old_folder_reads_as_the_full_model(tmp_path):
    rows = load(_old_folder(tmp_path / "old"))
    assert list(rows[MODEL_COLUMN]) == ["full", "full"]
    columns = list(rows.columns)
    assert columns.index(MODEL_COLUMN) == columns.index("speed_rpm") + 1
    assert list(rows["gap_mm"]) == [1.9, 2.9]               # nothing else moved
    # a folder whose rows have the column keeps their values
    kept = load(_old_folder(tmp_path / "new", with_model=True))
    assert list(kept[MODEL_COLUMN]) == ["reduced", "reduced"]
    assert list(kept.columns).count(MODEL_COLUMN) == 1


def test_an_old_folder_takes_the_same_design_again(tmp_path):
    """Its design.toml is the full design's resolved form, unchanged: a job may resume it."""
    root = _old_folder(tmp_path / "old")
    DatasetFolder(root).check_writable(design().to_toml())
    with pytest.raises(ValueError, match=r"holds another design \(base.reduced is missing "
                       r"there, True here"):
        DatasetFolder(root).check_writable(design("reduced = true").to_toml())


def test_column_map_and_card_say_which_model():
    columns = column_map(["run_id", "speed_rpm", MODEL_COLUMN, "shaft11_y_disp__amp_1x"])
    model = columns.set_index("column").loc[MODEL_COLUMN]
    assert (model["group"], model["unit"], model["channel"]) == ("run", "", "")
    rows = pd.DataFrame({"status": ["ok"], "wall_s": [1.0], "simulate_s": [0.5],
                         "rub": [True], "rub_state": ["full"], "severity": ["light"]})
    assert "the full finite-element model" in card_text(rows, design(), columns)
    text = card_text(rows, design("reduction_cutoff_hz = 1824.0"), columns)
    assert "the reduced-order model (Craig–Bampton, fixed-interface modes below 1824 Hz)" in text
