"""Textbook records (rubdiag.learn._textbook): the lines they state are the lines rubdiag's
own spectral features read, on the bin grid and between two bins; pairs precess as stated;
the same seed gives the same records; bad input is refused naming the parameter."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn._textbook import (
    AMPLITUDE_TOLERANCE,
    ELLIPTICITY,
    KINDS,
    NOISE_TOLERANCE,
    on_bin_speed_rpm,
    textbook_records,
    write_records,
)
from rubdiag.signal._fullspectrum import full_spectrum_lines
from rubdiag.signal._orders import order_label
from rubdiag.signal._table import prefixed_features

FS, WINDOW_S, NOISE = 10_000.0, 1.3, 1e-6
CHANNELS = ("shaft11_y_disp", "shaft11_z_disp", "probe")


@pytest.fixture(scope="module")
def records():
    return textbook_records(CHANNELS, FS, WINDOW_S, [1000.0, 3300.0],
                            bin_offsets=(0.0, 0.25, 0.5), noise_m=NOISE, seed=3)


def test_speeds_sit_where_stated_on_the_bin_grid(records):
    df = 1.0 / WINDOW_S
    for r in records:
        past = (r.speed_rpm / 60.0 / df - r.bin_offset) % 1.0
        assert min(past, 1.0 - past) < 1e-9, r.name
    assert {r.bin_offset for r in records} == {0.0, 0.25, 0.5}
    assert on_bin_speed_rpm(1451.84, 1.0, 0.5) == pytest.approx(1470.0)


def test_every_kind_strength_direction_speed_and_offset_once(records):
    expected = sum(len(k.strengths) * len(k.directions) for k in KINDS.values()) * 2 * 3
    assert len(records) == expected
    assert len({r.name for r in records}) == expected


def test_rubdiags_features_read_the_stated_lines(records):
    """Each line's amplitude as the feature table reads it (the pair's z probe at the
    ellipticity), within the tolerance the module states."""
    worst = 0.0
    for r in records:
        row = prefixed_features(r.signals, FS, r.speed_rpm, separator="__").iloc[0]
        for channel in CHANNELS:
            scale = ELLIPTICITY if channel.endswith("_z_disp") else 1.0
            for order, amplitude in r.lines:
                stated = scale * amplitude
                read = row[f"{channel}__amp_{order_label(order)}"]
                allowed = max(AMPLITUDE_TOLERANCE * stated, NOISE_TOLERANCE * NOISE)
                assert abs(read - stated) <= allowed, (r.name, channel, order, read, stated)
                worst = max(worst, abs(read - stated) / stated)
    assert worst > 0.0          # noise is there: the reading is not the stated number


def test_a_pair_precesses_as_stated(records):
    """The full spectrum of the y/z pair: an ellipse of axes a and e·a is a forward circle
    of a(1 + e)/2 and a reverse one of a(1 − e)/2; 1× forward, the 2× forward or reverse
    as the record says."""
    twos = [r for r in records if r.kind == "2x" and r.bin_offset == 0.0]
    assert {r.direction for r in twos} == {"forward", "reverse"}
    major, minor = (1 + ELLIPTICITY) / 2, (1 - ELLIPTICITY) / 2
    for r in twos:
        fwd, rev = full_spectrum_lines(r.signals["shaft11_y_disp"], r.signals["shaft11_z_disp"],
                                       FS, r.speed_rpm / 60.0, [1.0, 2.0])
        (_, one), (_, two) = r.lines
        main, other = (fwd[1], rev[1]) if r.direction == "forward" else (rev[1], fwd[1])
        for read, stated in ((fwd[0], major * one), (rev[0], minor * one),
                             (main, major * two), (other, minor * two)):
            assert read == pytest.approx(stated, rel=AMPLITUDE_TOLERANCE,
                                         abs=NOISE_TOLERANCE * NOISE), r.name


def test_the_same_seed_gives_the_same_records_and_another_seed_other_noise():
    a = textbook_records(["p"], 2000.0, 1.0, [1200.0], kinds=["3x"], seed=1)
    b = textbook_records(["p"], 2000.0, 1.0, [1200.0], kinds=["3x"], seed=1)
    c = textbook_records(["p"], 2000.0, 1.0, [1200.0], kinds=["3x"], seed=2)
    for x, y, z in zip(a, b, c, strict=True):
        assert np.array_equal(x.signals["p"], y.signals["p"])
        assert not np.array_equal(x.signals["p"], z.signals["p"])


def test_written_records_are_the_records(tmp_path):
    records = textbook_records(["p_y_disp", "p_z_disp"], 2000.0, 1.0, [1200.0],
                               kinds=["0.5x"], bin_offsets=(0.5,))
    table = pd.read_csv(write_records(records, tmp_path))
    assert list(table["file"]) == [f"{r.name}.npz" for r in records]
    assert set(table["faults"]) == {"looseness"} and set(table["kind"]) == {"0.5x"}
    assert list(table["line_0p5x"]) == list(KINDS["0.5x"].strengths)
    with np.load(tmp_path / table["file"][0]) as saved:
        assert float(saved["fs"]) == 2000.0
        assert np.array_equal(saved["p_z_disp"], records[0].signals["p_z_disp"])


@pytest.mark.parametrize(("options", "name"), [
    ({"kinds": ["4x"]}, "kinds"),
    ({"fs_hz": -1.0}, "fs_hz"),
    ({"noise_m": -1e-6}, "noise_m"),
    ({"bin_offsets": (1.5,)}, "bin_offsets"),
    ({"speeds_rpm": [0.0]}, "speeds_rpm"),
    ({"fs_hz": 100.0}, "fs_hz"),          # too low for 3x at 1200 rpm
])
def test_bad_input_names_the_parameter(options, name):
    given = {"channels": ["p"], "fs_hz": 2000.0, "window_s": 1.0, "speeds_rpm": [1200.0],
             **options}
    with pytest.raises(ValueError, match=name):
        textbook_records(**given)
