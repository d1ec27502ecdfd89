"""Point and annular contacts give, behind the element seam, the bits they gave before it.

``data/seam/`` was made by ``scripts/seam_reference.py`` with the code before the seam:
digests of every array of runs that reach each path of the contact code (annular clearance,
both kinds in one run, augmented Lagrangian, Newmark γ ≠ 1/2, the dense linear path, a speed
run-up with step rejections, a reduced Table 2 cell). Bits are compared only with the library
versions and OpenBLAS kernels the references were made with (see
``tests/simulation/test_presplit_reference.py``).
"""

from __future__ import annotations

import json

import pytest
from scripts_loader import load_script

seam = load_script("seam_reference")
presplit = load_script("presplit_reference")
REFERENCES = [json.loads(p.read_text()) for p in sorted(seam.OUT.glob("reference-*.json"))]
HERE = presplit.versions()
SAME = next((m for m in REFERENCES if m["versions"] == HERE), None)
pytestmark = pytest.mark.skipif(SAME is None, reason=(
    f"references made with {[m['versions'] for m in REFERENCES]}, not {HERE}: bits are "
    "compared only with the same libraries and OpenBLAS kernels"))


@pytest.fixture(scope="module")
def made():
    return {name: presplit.arrays(result) for name, result in seam.runs().items()}


@pytest.mark.parametrize("name", ["annular", "mixed", "dense", "general", "augmented",
                                  "profile", "reduced"])
def test_run_equals_the_reference_bit_for_bit(made, name):
    got = made[name]
    assert set(got) == set(SAME[name])
    different = [k for k, v in got.items() if presplit.digest(v) != SAME[name][k]]
    assert not different, different


def test_references_reach_every_contact_path(made):
    """What the references are for: a check that reaches nothing proves nothing."""
    assert (made["annular"]["contact_status"] == 2).any()      # annular sliding
    assert (made["mixed"]["contact_status"] == 3).any()        # sticking
    assert int(made["augmented"]["augment_iterations"]) > 0
    assert int(made["profile"]["n_rejected_abrupt"]) > 0       # level changes
    assert int(made["profile"]["steps_per_level"][1:].sum()) > 0
