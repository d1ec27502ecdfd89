"""The simulator gives what it gave before it was split into small parts.

``data/presplit/`` was made by ``scripts/presplit_reference.py`` with the code before the
split: digests of every array of a short contact run, of a portable run (no LAPACK-computed
input) and of a Table 2 cell, with the library versions and the OpenBLAS kernels. With the
same versions and kernels (``rubdiag.pin_blas_kernels()``, which conftest calls, pins Haswell
on x86-64) the bits must be the same, whatever the CPU. Otherwise only the portable run can
be compared (the short run starts from a LAPACK steady state, and the cell is chaotic): each
of its arrays to 1e-12 of the array's largest magnitude (``portable.npz``; a per-element rtol
would fail at the zero crossings of waveforms that differ by round-off).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from scripts_loader import load_script

reference = load_script("presplit_reference")
REFERENCES = [json.loads(p.read_text()) for p in sorted(reference.OUT.glob("reference-*.json"))]
HERE = reference.versions()
SAME = next((m for m in REFERENCES if m["versions"] == HERE), None)
MADE_WITH = [m["versions"] for m in REFERENCES]
RTOL = 1e-12
same_versions = pytest.mark.skipif(SAME is None, reason=(
    f"references made with {MADE_WITH}, not {HERE}: bits are compared only with the same "
    "libraries and OpenBLAS kernels"))


@pytest.fixture(scope="module")
def short():
    from rubdiag.simulation import simulate

    return reference.arrays(simulate(reference.short_run()).system)


@pytest.fixture(scope="module")
def portable():
    return reference.arrays(reference.portable_run())


def test_short_run_touches_and_records_every_array(short, portable):
    # both references exercise contact (closed elements, friction) and the sensor stream
    for run in (short, portable):
        assert run["max_normal_force"].max() > 0.0
        assert (run["contact_status"] >= 2).any()
        assert run["sensor_q"].size > 0
    assert set(short) == set(REFERENCES[0]["short"])


@same_versions
def test_short_run_equals_the_reference_bit_for_bit(short):
    different = [k for k, v in short.items() if reference.digest(v) != SAME["short"][k]]
    assert not different, different


def test_portable_run_equals_the_reference(portable):
    stored = np.load(reference.OUT / "portable.npz")
    assert set(stored.files) == set(portable)
    if SAME is not None and "portable" in SAME:
        different = [k for k, v in portable.items()
                     if reference.digest(v) != SAME["portable"][k]]
        assert not different, different
    for name, value in portable.items():
        scale = float(np.max(np.abs(stored[name]))) if stored[name].size else 0.0
        np.testing.assert_allclose(value, stored[name], rtol=0.0, atol=RTOL * scale,
                                   err_msg=name)


@same_versions
def test_table2_cell_equals_the_reference_bit_for_bit():
    from rubdiag.simulation import simulate

    cell = reference.arrays(simulate(reference.cell_run()).system)
    assert set(cell) == set(SAME["cell"])
    different = [k for k, v in cell.items() if reference.digest(v) != SAME["cell"][k]]
    assert not different, different


def test_profiled_run_gives_the_same_bits_and_counts_every_section(short):
    """``Recording(profile=True)`` only reads the cycle counter: the same arrays, bit for
    bit, and every section of a step has taken some cycles."""
    from unittest import mock

    from rubdiag._kernels.newmark import PROFILE_SECTIONS
    from rubdiag.simulation import _simulation as simulation_module
    from rubdiag.simulation import simulate, simulate_system

    def profiled_run(system, elements, grid, outputs, **options):
        return simulate_system(system, elements, grid,
                               dataclasses.replace(outputs, profile=True), **options)

    with mock.patch.object(simulation_module, "simulate_system", profiled_run):
        system = simulate(reference.short_run()).system
    profiled = reference.arrays(system)
    for name, value in short.items():
        assert reference.digest(profiled[name]) == reference.digest(value), name
    cycles = system.extra["profile_cycles"]
    assert list(cycles) == list(PROFILE_SECTIONS)
    assert all(c > 0 for c in cycles.values()), cycles
