"""The simulator gives what it gave before it was split into small parts (issue 13).

``data/presplit/`` was made by ``scripts/presplit_reference.py`` with the code before the
split: the short contact run in full, the Table 2 cell as SHA-256 digests, and the library
versions and CPU they came from. With the same versions the bits must be the same; with
others only the short run can be compared, to rtol 1e-12 (the Table 2 cell is chaotic over
its 230 000 steps: round-off grows to order one).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scripts_loader import load_script

reference = load_script("presplit_reference")
META = json.loads((reference.OUT / "reference.json").read_text())
SAME_VERSIONS = reference.versions() == META["versions"]
RTOL = 1e-12


@pytest.fixture(scope="module")
def short():
    from rubdiag.simulate import simulate

    return reference.arrays(simulate(reference.short_run()).system)


def test_short_run_touches_and_records_every_array(short):
    # the reference exercises contact (closed elements, friction) and the sensor stream
    assert short["max_normal_force"].max() > 0.0
    assert (short["contact_status"] >= 2).any()
    assert short["sensor_q"].size > 0
    assert set(short) == set(META["short"])


def test_short_run_equals_the_reference(short):
    stored = np.load(reference.OUT / "short.npz")
    assert set(stored.files) == set(short)
    for name, value in short.items():
        if SAME_VERSIONS:
            assert reference.digest(value) == META["short"][name], name
        else:
            np.testing.assert_allclose(value, stored[name], rtol=RTOL, atol=0.0,
                                       err_msg=name)


@pytest.mark.skipif(not SAME_VERSIONS, reason=(
    f"made with {META['versions']}: a chaotic 2.3-s run is compared bit for bit only on "
    "the same libraries and CPU"))
def test_table2_cell_equals_the_reference_bit_for_bit():
    from rubdiag.simulate import simulate

    cell = reference.arrays(simulate(reference.cell_run()).system)
    assert set(cell) == set(META["cell"])
    different = [k for k, v in cell.items() if reference.digest(v) != META["cell"][k]]
    assert not different, different


def test_profiled_run_gives_the_same_bits_and_counts_every_section(short):
    """``simulate_system(profile=True)`` only reads the cycle counter: the same arrays, bit
    for bit, and every section of a step has taken some cycles."""
    from functools import partial
    from unittest import mock

    from rubdiag.kernels.newmark import PROFILE_SECTIONS
    from rubdiag.simulate import simulate
    from rubdiag.simulate import simulation as simulation_module
    from rubdiag.simulate.system import simulate_system

    with mock.patch.object(simulation_module, "simulate_system",
                           partial(simulate_system, profile=True)):
        system = simulate(reference.short_run()).system
    profiled = reference.arrays(system)
    for name, value in short.items():
        assert reference.digest(profiled[name]) == reference.digest(value), name
    cycles = system.extra["profile_cycles"]
    assert list(cycles) == list(PROFILE_SECTIONS)
    assert all(c > 0 for c in cycles.values()), cycles
