"""The feature dictionary answers for every column a feature row can hold, once."""

from __future__ import annotations

import pytest

from rubdiag.dataset._schema import PAIR_FEATURES
from rubdiag.signal import _glossary as glossary
from rubdiag.signal._table import FEATURE_NAMES


@pytest.mark.parametrize("name", [*FEATURE_NAMES, *PAIR_FEATURES])
def test_every_feature_column_has_exactly_one_entry(name):
    matches = [e for e in glossary.GLOSSARY if e.regex.match(name)]
    assert len(matches) == 1, f"{name}: {[e.pattern for e in matches]}"
    assert matches[0].row == ("pair" if name in PAIR_FEATURES else "channel")


def test_every_entry_is_used():
    names = [*FEATURE_NAMES, *PAIR_FEATURES]
    for entry in glossary.GLOSSARY:
        assert any(entry.regex.match(n) for n in names), entry.pattern


def test_units_agree_with_the_dataset_column_map():
    """The dictionary's unit is the one a dataset's columns.csv gives the same column
    (the signal's unit written "signal" here, m there for displacement probes)."""
    from rubdiag.dataset._card import column_map
    from rubdiag.simulation._sensors import Sensor

    sensors = [Sensor("shaft 11", "y"), Sensor("shaft 11", "z")]
    columns = [f"shaft11_y_disp__{n}" for n in FEATURE_NAMES if n not in ("speed_rpm",)]
    columns += [f"shaft11_yz_disp__{n}" for n in PAIR_FEATURES]
    table = column_map(columns, sensors)
    for column, unit in zip(table["column"], table["unit"], strict=True):
        expected = glossary.describe(column).unit
        assert unit == ("m" if expected == "signal" else expected), column


def test_a_name_that_is_no_feature_is_refused_by_name():
    with pytest.raises(ValueError, match="'amp_2y' is not a feature column"):
        glossary.describe("amp_2y")
    assert glossary.describe("casing1_y_acc__bb_4x_rms").pattern == "bb_<n>x_rms"
