"""rubdiag against ROSS (ross-rotordynamics): forward critical speeds (the paper shaft's
first four: the 3rd and 4th were not fitted to anything), undamped natural frequencies and
mode shapes at 0 and 8000 rpm, and the complex unbalance response.

ROSS's values are stored in data/ross_references.json, written by scripts/ross_references.py
in an interpreter that has ROSS (see its docstring for the venv); the file records ROSS's
version, the Python version and the date. Every run compares rubdiag with the stored values;
where ROSS is installed, ``test_stored_references_are_what_ross_computes`` also recomputes
them with ROSS, so that the file cannot silently go stale. The rotors (the paper rig's shaft,
discs and bearings, and a thick hollow 40/20 mm shaft on which shear deformation and rotary
inertia move the critical speeds by per cents) are described in the script and stored in the
file with the values.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from docs_tables import table
from scripts_loader import load_script

from rubdiag.model import paper_rig

ROOT = Path(__file__).resolve().parents[2]
script = load_script("ross_references")
STORED = script.load()

# Relative tolerance of every comparison here (rubdiag vs stored ROSS, stored vs live ROSS).
# Both codes use the same Timoshenko element (interdependent interpolation) with Cowper's κ,
# so they agree to solver precision: measured (ROSS 2.3.0, 2026-11-23) 5e-11 for the first
# two critical speeds, 3.2e-9 for the paper shaft's 3rd and 4th (35877, 45233 rpm), 5e-10 for
# the natural frequencies and 5e-9 for the unbalance response (near the criticals, where it
# is most sensitive); ROSS against itself, run to run, up to 2e-10 (ARPACK's
# start vector, the secant iteration). 1e-6 leaves room for other BLAS/LAPACK builds and still
# tells a changed element apart: Hutchinson's κ instead of Cowper's moves every critical speed
# by at least 6.6e-5, leaving out shear deformation by at least 2.7e-4 (see
# test_the_tolerance_tells_other_physics_apart); κ 0.1 % too large in rubdiag fails too (paper
# shaft 1.2e-6, hollow shaft 2.7e-5, unbalance response 2.5e-2).
RTOL = 1e-6

# Mode shapes (the 4 lowest lateral modes at 0 and 8000 rpm; u_y, u_z at the 25 shaft nodes,
# unit largest modulus). Measured (ROSS 2.3.0): 1 − MAC ≤ 3.4e-12; entry-wise, after the
# best complex scale, ≤ 1.9e-6 at 0 rpm and ≤ 1.2e-8 at 8000 rpm. The 0 rpm figure is the
# first pair: its y and z modes are 2.5e-5 apart in frequency (k_y ≠ k_z barely matters with
# the shaft this flexible), so an eigenvector residual of ~1e-10 (ROSS's ARPACK; its shapes
# carry imaginary parts up to 4e-9 where they should be real) mixes them by ~1e-10 / 2.5e-5.
# A phase is needed: the antisymmetric modes of this symmetric rotor have mirror-node maxima
# of equal modulus, so "largest entry real positive" picks either sign by round-off.
# MAC_TOL is the brief's 1e-6; SHAPE_ATOL = 1e-5 is 5 × the worst measured entry.
MAC_TOL = 1e-6
SHAPE_ATOL = 1e-5


@pytest.fixture(scope="module")
def ours():
    return script.rubdiag_values(STORED["inputs"])


def test_stored_inputs_are_the_scripts():
    """The file holds the rotors, speeds and ROSS settings the script defines now (else
    regenerate it: a change there is not covered until ROSS has been run on it)."""
    assert STORED["inputs"] == json.loads(json.dumps(script.inputs())), (
        "scripts/ross_references.py changed its inputs; rerun it with ROSS")


def test_compared_rotor_is_the_paper_rig():
    paper = paper_rig()
    rig = script.rig(STORED["inputs"]["rotors"]["paper-solid-10mm"])
    assert rig.shaft == paper.shaft
    assert rig.discs == paper.discs
    assert rig.material == paper.material
    assert [(b.node, b.k_y_n_m, b.k_z_n_m) for b in rig.bearings] == [
        (b.node, b.k_y_n_m, b.k_z_n_m) for b in paper.bearings]


def test_disc_inertias_are_those_given_to_ross():
    """ROSS gets the closed-form m, Ip, Id of a solid disc; rubdiag computes its own."""
    spec = STORED["inputs"]["rotors"]["paper-solid-10mm"]
    rig = script.rig(spec)
    for disc, stored in zip(rig.discs, spec["discs"], strict=True):
        np.testing.assert_allclose(
            disc.inertia(rig.material.density_kg_m3),
            [stored["mass_kg"], stored["polar_inertia_kg_m2"],
             stored["diametral_inertia_kg_m2"]], rtol=1e-12)


@pytest.mark.parametrize("quantity", list(script.arrays(STORED["ross"])))
def test_rubdiag_matches_stored_ross(ours, quantity):
    np.testing.assert_allclose(script.arrays(ours)[quantity],
                               script.arrays(STORED["ross"])[quantity], rtol=RTOL,
                               err_msg=f"{quantity}: rubdiag vs ROSS {STORED['generated']}")


def test_paper_shaft_has_four_forward_criticals(ours):
    """The 3rd and 4th forward critical speeds (not fitted: the element lengths were chosen
    for the first two) are compared too, by test_rubdiag_matches_stored_ross."""
    assert len(STORED["ross"]["forward_critical_speeds_rpm"]["paper-solid-10mm"]) == 4
    assert len(ours["forward_critical_speeds_rpm"]["paper-solid-10mm"]) == 4


def test_mode_shapes_match_stored_ross(ours):
    theirs = script.shapes(STORED["ross"])
    shp = STORED["inputs"]["mode_shapes"]
    n_nodes = len(STORED["inputs"]["rotors"][shp["rotor"]]["element_lengths_m"]) + 1
    assert theirs.shape == (len(shp["speeds_rpm"]), shp["n_lateral"],
                            len(shp["directions"]) * n_nodes)
    np.testing.assert_allclose(np.max(np.abs(theirs), axis=-1), 1.0, rtol=1e-12)
    one_minus_mac, entrywise = script.shape_agreement(script.shapes(ours), theirs)
    assert np.max(one_minus_mac) <= MAC_TOL, one_minus_mac
    assert np.max(entrywise) <= SHAPE_ATOL, entrywise


def test_shape_comparison_tells_modes_apart(ours):
    """Neighbouring modes (the other whirl or plane of a pair, the next bending mode) are far
    from MAC = 1, so the comparison pairs each mode with its own."""
    theirs = script.shapes(STORED["ross"])
    swapped = script.shapes(ours)[:, [1, 0, 3, 2]]
    one_minus_mac, _ = script.shape_agreement(swapped, theirs)
    assert np.min(one_minus_mac) > 1e3 * MAC_TOL, one_minus_mac


def test_the_tolerance_tells_other_physics_apart(ours):
    """ROSS with Hutchinson's κ or without shear misses every critical speed by more than
    10 × RTOL; on the thick hollow shaft leaving out shear costs more than 1 % (on the
    slender paper shaft only 0.12 %: that is why the hollow shaft is compared too)."""
    mine = ours["forward_critical_speeds_rpm"]
    for label, rotors in STORED["ross_variants_forward_critical_speeds_rpm"].items():
        for name, speeds in rotors.items():
            miss = np.abs(np.asarray(speeds) / mine[name][: len(speeds)] - 1.0)
            assert np.min(miss) > 10 * RTOL, (label, name, miss)
    no_shear = STORED["ross_variants_forward_critical_speeds_rpm"]["no_shear"]["hollow-40-20mm"]
    assert np.max(np.abs(np.asarray(no_shear) / mine["hollow-40-20mm"][: len(no_shear)]
                         - 1.0)) > 0.01


def test_the_documentation_names_the_stored_ross_version():
    generated = STORED["generated"]
    shown = table("ross-versions")
    for text in (f"ROSS {generated['ross']}", f"Python {generated['python']}"):
        assert text in shown, f"the documentation does not say {text!r}"


def test_stored_references_are_what_ross_computes():
    """Only where ROSS is installed (not in the project venv); about a minute."""
    if importlib.util.find_spec("ross") is None:
        pytest.skip("ROSS is not installed; run this file in a venv with ROSS to check the "
                    "stored references against it (scripts/ross_references.py says how)")
    fresh = script.generate(script.import_ross())
    assert fresh["inputs"] == STORED["inputs"]
    for quantity, theirs in script.arrays(STORED["ross"]).items():
        np.testing.assert_allclose(script.arrays(fresh["ross"])[quantity], theirs,
                                   rtol=RTOL, err_msg=quantity)
    one_minus_mac, entrywise = script.shape_agreement(script.shapes(fresh["ross"]),
                                                      script.shapes(STORED["ross"]))
    assert np.max(one_minus_mac) <= MAC_TOL and np.max(entrywise) <= SHAPE_ATOL, (
        one_minus_mac, entrywise)
    variants = STORED["ross_variants_forward_critical_speeds_rpm"]
    for label, rotors in variants.items():
        for name, speeds in rotors.items():
            np.testing.assert_allclose(
                fresh["ross_variants_forward_critical_speeds_rpm"][label][name], speeds,
                rtol=RTOL, err_msg=f"{label}, {name}")
