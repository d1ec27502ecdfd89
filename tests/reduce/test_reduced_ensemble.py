"""The reduced model against the full model's start-history spread, on the study's four
cells (issue 13): rub is chaotic, so one run of either model is one realisation; the reduced
model must land where the full model's five start histories (gap ramp 0.1 s ± 2 %) do."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.paper import ensemble
from rubdiag.paper.table2 import CASES
from rubdiag.reduce import Reduction

pytestmark = pytest.mark.slow

CELLS = [(c.case, c.gap_mm) for c in CASES]
QUANTITIES = ("contact1_max_force_n", "casing_max_y_m", "contact1_sticking_share")


@pytest.fixture(scope="module")
def runs():
    full = ensemble(CELLS, jobs=2)
    reduced = ensemble(CELLS, jobs=2, reduction=Reduction())
    return full, reduced


@pytest.mark.parametrize("quantity", QUANTITIES)
@pytest.mark.parametrize("cell", CELLS, ids=[c.stem for c in CASES])
def test_reduced_median_lies_in_the_full_spread(runs, cell, quantity):
    full, reduced = runs
    pick = [(f[(f.case == cell[0]) & (f.gap_mm == cell[1])][quantity]) for f in (full, reduced)]
    lo, hi = pick[0].min(), pick[0].max()
    median = float(np.median(pick[1]))
    assert lo <= median <= hi, f"{quantity}: reduced median {median:.4g}, full {lo:.4g}-{hi:.4g}"
