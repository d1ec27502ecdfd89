"""The reduced model against the full model's start-history spread, on the study's four
cells (issue 13): rub is chaotic, so one run of either model is one realisation; the reduced
model must land where the full model's five start histories (gap ramp 0.1 s ± 2 %) do.

Not reproduced at the default 2-kHz cutoff (strict xfails, measured 2026-11-24 on
rocketlake): the sticking share comes out 20-45 % low in every cell, and in three cells the
contact-1 maximum force (+1-3 %) or the casing maximum (-3 %) lands just outside a spread
that is 0.7-2 % wide. The stick-slip dynamics at the tips involve modes far above the
feature band: with a 5-kHz cutoff (70 coordinates) a 0.8-s case-2 serious run's sticking
share is 0.451 against the full model's 0.461 (2 kHz: 0.393), converged at 20 kHz
(README "Reduced model"), but then the reduced model is no longer 3× faster."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.paper import ensemble
from rubdiag.paper.table2 import CASES
from rubdiag.reduce import Reduction

pytestmark = pytest.mark.slow

CELLS = [(c.case, c.gap_mm) for c in CASES]
QUANTITIES = ("contact1_max_force_n", "casing_max_y_m", "contact1_sticking_share")
#: (cell, quantity) -> the measured miss (reduced median; full min-max), 2026-11-24
NOT_REPRODUCED = {
    ("case1_light", "contact1_max_force_n"): "187.4 N; 181.2-182.5",
    ("case1_light", "contact1_sticking_share"): "0.187; 0.245-0.259",
    ("case1_serious", "contact1_max_force_n"): "195.6 N; 191.7-194.0",
    ("case1_serious", "casing_max_y_m"): "62.7 um; 64.8-65.2",
    ("case1_serious", "contact1_sticking_share"): "0.262; 0.318-0.336",
    ("case2_light", "contact1_max_force_n"): "1006 N; 963-984",
    ("case2_light", "contact1_sticking_share"): "0.185; 0.322-0.330",
    ("case2_serious", "contact1_sticking_share"): "0.313; 0.429-0.441",
}


def _params():
    for c in CASES:
        for quantity in QUANTITIES:
            miss = NOT_REPRODUCED.get((c.stem, quantity))
            marks = () if miss is None else pytest.mark.xfail(strict=True, reason=(
                f"reduced at 2 kHz misses the full spread: {miss} (module docstring)"))
            yield pytest.param((c.case, c.gap_mm), quantity, id=f"{c.stem}-{quantity}",
                               marks=marks)


@pytest.fixture(scope="module")
def runs():
    full = ensemble(CELLS, jobs=2)
    reduced = ensemble(CELLS, jobs=2, reduction=Reduction())
    return full, reduced


@pytest.mark.parametrize(("cell", "quantity"), list(_params()))
def test_reduced_median_lies_in_the_full_spread(runs, cell, quantity):
    full, reduced = runs
    pick = [(f[(f.case == cell[0]) & (f.gap_mm == cell[1])][quantity]) for f in (full, reduced)]
    lo, hi = pick[0].min(), pick[0].max()
    median = float(np.median(pick[1]))
    assert lo <= median <= hi, f"{quantity}: reduced median {median:.4g}, full {lo:.4g}-{hi:.4g}"
