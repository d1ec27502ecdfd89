"""The probe pairs' full-spectrum and orbit columns of a dataset row: named
``<node>_yz_disp__<feature>``, in a fixed order, consistent with the single-channel 1x lines
of their two probes, and computed from the same noisy channels (the noise floor shows in
their fractional lines as it would in a lock-in of white noise)."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.dataset import Design
from rubdiag.dataset._card import column_map
from rubdiag.dataset._noise import NoiseFloors
from rubdiag.dataset._rows import make_row, sensor_pairs
from rubdiag.dataset._schema import PAIR_FEATURES, pair_channel, pair_probes
from rubdiag.simulation._sensors import Sensor

# one linear run (the gap is wider than the orbit): 0.2 s analysed, 19 revolutions
TOML = """
base = {rig = "paper", duration_s = 0.3, discard_s = 0.1}
sampling = {method = "grid"}
factors = {case = [2], speed_ratio = [1.0], gap_mm = [4.0]}
"""
PAIRS = ("shaft4_yz_disp", "shaft11_yz_disp", "shaft26_yz_disp")


@pytest.fixture(scope="module")
def rows():
    design = Design.from_toml(TOML)
    item = design.runs()[0]
    noisy = make_row(item, design.labels, design.noise)
    quiet = make_row(item, design.labels, NoiseFloors(displacement_m=0.0))
    assert noisy["status"] == "ok" and quiet["status"] == "ok" and not noisy["rub"]
    return design, noisy, quiet


def test_pair_columns_come_in_a_fixed_order_after_the_channels(rows):
    design, noisy, _ = rows
    names = list(noisy)
    pair_columns = [n for n in names if n.split("__", 1)[0] in PAIRS]
    assert pair_columns == [f"{p}__{f}" for p in PAIRS for f in PAIR_FEATURES]
    first = names.index(pair_columns[0])
    assert names[first:first + len(pair_columns)] == pair_columns      # one block
    assert names.index("casing1_y_acc__rms") < first
    # after them only the simulator's truth and the provenance
    assert all(n.split("__", 1)[0].startswith(("contact", "truth")) or "__" not in n
               for n in names[first + len(pair_columns):])
    assert PAIR_FEATURES[:4] == ("fwd_0p33x", "rev_0p33x", "fwd_0p5x", "rev_0p5x")
    # the same run again: bitwise the same pair values
    again = make_row(design.runs()[0], design.labels, design.noise)
    assert [again[c] for c in pair_columns] == [noisy[c] for c in pair_columns]


def test_forward_and_reverse_1x_follow_from_the_probes_1x_lines(rows):
    """A line y = A cos(wt + a) is Re(Y e^{iwt}) with Y = A e^{ia}; with z likewise,
    y + iz holds (Y + iZ)/2 at +w and conj(Y - iZ)/2 at -w. The run is linear (no rub), so
    the table's 1x lines (Hann, interpolated) and the pair's lock-in see the same line."""
    _, row, _ = rows

    def line(channel):
        phase = np.radians(row[f"{channel}__phase_1x_deg"])
        return row[f"{channel}__amp_1x"] * np.exp(1j * phase)
    y, z = line("shaft11_y_disp"), line("shaft11_z_disp")
    forward, reverse = abs(y + 1j * z) / 2, abs(y - 1j * z) / 2
    assert row["shaft11_yz_disp__fwd_1x"] == pytest.approx(forward, rel=2e-5)
    assert row["shaft11_yz_disp__rev_1x"] == pytest.approx(reverse, abs=1e-4 * forward)
    assert row["shaft11_yz_disp__forward_1x"] == row["shaft11_yz_disp__fwd_1x"]
    assert row["shaft11_yz_disp__precession_1x"] == 1           # the disc whirls forward
    assert row["shaft11_yz_disp__ellipticity_1x"] == pytest.approx(reverse / forward,
                                                                   abs=1e-4)


def test_the_noise_floor_reaches_the_pair_columns(rows):
    """Without noise the linear run has no fractional line; with white noise of sd s on
    both probes, each fractional forward or reverse lock-in over n samples has mean square
    2 s^2 / n. The bearing pair (shaft 4) is measured over its noise, the disc's is not."""
    design, noisy, quiet = rows
    sigma = design.noise.displacement_m
    speed_hz = noisy["speed_rpm"] / 60.0
    run = design.runs()[0].run
    revs = int(np.floor((run.duration_s - run.discard_s) * speed_hz))   # 19: 18 are used
    n = round((revs - revs % 6) * run.output_rate_hz / speed_hz)
    expected = sigma * np.sqrt(2.0 / n)
    fractional = [f for f in PAIR_FEATURES if f[:4] in ("fwd_", "rev_") and "p" in f[4:]]
    assert len(fractional) == 48
    for pair in ("shaft4_yz_disp", "shaft26_yz_disp"):
        rms_noisy = np.sqrt(np.mean([noisy[f"{pair}__{f}"] ** 2 for f in fractional]))
        rms_quiet = np.sqrt(np.mean([quiet[f"{pair}__{f}"] ** 2 for f in fractional]))
        assert rms_quiet < 0.05 * expected
        assert 0.75 * expected < rms_noisy < 1.3 * expected
    # the other columns of the row saw the same noise: the probes' own noisy 1x lines
    assert noisy["shaft4_y_disp__amp_1x"] != quiet["shaft4_y_disp__amp_1x"]


def test_the_column_map_gives_the_pair_units(rows):
    design, row, _ = rows
    m = column_map(list(row), design.sensors).set_index("column")
    assert m.loc["shaft11_yz_disp__rev_2x", ["group", "channel", "feature", "unit"]].tolist() \
        == ["feature", "shaft11_yz_disp", "rev_2x", "m"]
    assert m.loc["shaft11_yz_disp__limit_radius", "unit"] == "m"
    assert m.loc["shaft11_yz_disp__reverse_share", "unit"] == "1"
    assert m.loc["shaft11_yz_disp__precession_1x", "unit"] == "1"


def test_pair_names_and_which_sensors_pair():
    assert pair_channel("shaft11_y_disp", "shaft11_z_disp") == "shaft11_yz_disp"
    assert pair_probes("shaft11_yz_disp") == ("shaft11_y_disp", "shaft11_z_disp")
    assert pair_channel("probeA", "probeB") is None and pair_probes("shaft11_y_disp") is None
    sensors = (Sensor("shaft 4", "y"), Sensor("shaft 4", "z", "velocity"),
               Sensor("shaft 11", "z"), Sensor("shaft 11", "y"), Sensor("shaft 4", "z"),
               Sensor("casing 1", "y", name="left"), Sensor("casing 1", "z", name="right"))
    assert sensor_pairs(sensors) == [("shaft4_yz_disp", "shaft4_y_disp", "shaft4_z_disp"),
                                     ("shaft11_yz_disp", "shaft11_y_disp", "shaft11_z_disp")]
