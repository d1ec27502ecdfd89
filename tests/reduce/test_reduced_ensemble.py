"""The reduced model against the full model's start-history spread, on the study's four
cells (issue 13): rub is chaotic, so one run of either model is one realisation; the reduced
model must land where the full model's five start histories (gap ramp 0.1 s ± 2 %) do.

Not reproduced at the default 2-kHz cutoff (strict xfails, measured 2026-11-24 with the
pinned Haswell kernels): 3 of 12 pass. The sticking share comes out 20-45 % low in every
cell; the contact-1 maximum force is 1-3 % high and the casing maximum up to 3 % low, outside
spreads that are only 0.7-2 % wide (case 2 light's casing median lands 0.01 % below its
spread's lower end). The stick-slip dynamics at the tips involve modes far above the feature
band. The same ensembles at higher cutoffs (README "Reduced model"): 5 kHz (70 coordinates,
3.1× faster) passes 5 of 12, its sticking shares 0.3-9 % below the spreads; 10 kHz passes 7
of 12, every miss within 0.2-4.3 % of a spread's end; no cutoff that stays 3× faster passes
all.
Medians that land this close to a spread's end move across it with round-off (the
integrator's summation order moved 5 kHz's case 2 light casing median from inside to 1 %
below), so the xfail list is a measurement of this code, not a property of the cutoff."""

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
    ("case1_light", "contact1_max_force_n"): "187.1 N; 181.2-182.5",
    ("case1_light", "contact1_sticking_share"): "0.187; 0.245-0.258",
    ("case1_serious", "contact1_max_force_n"): "195.6 N; 191.7-194.0",
    ("case1_serious", "casing_max_y_m"): "63.3 um; 64.8-65.2",
    ("case1_serious", "contact1_sticking_share"): "0.252; 0.318-0.336",
    ("case2_light", "contact1_max_force_n"): "1003 N; 970-977",
    ("case2_light", "casing_max_y_m"): "205.4 um; 205.4-207.4 (0.01 % below)",
    ("case2_light", "contact1_sticking_share"): "0.185; 0.323-0.330",
    ("case2_serious", "contact1_sticking_share"): "0.318; 0.428-0.444",
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
