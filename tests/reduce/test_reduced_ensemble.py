"""The reduced model against the full model's start-history spread, on the study's four
cells; the helpers, the control families and the bias limit are
``scripts/reduced_ensemble.py``'s, which prints the same comparison for any cutoff.

Rub is chaotic, so one run of either model is one realisation. Issue 13 asks that the reduced
model's median over the five default start histories (gap ramp 0.1 s ± 2 %) lies in the full
model's min–max over the same five, for the contact-1 maximum force, the casing maximum and
the sticking share: 12 checks. **That criterion is not met, and it cannot be met reliably
by any model**: the full model itself, run on four other families of five start histories
from the same ±2 % range, passes 2, 8, 9 and 8 of the 12 (README, Reduced model). The
default reduced model (2 kHz, tip rotations kept) passes 5; its misses are strict xfails.

The test that separates a model error from the scatter measures each median's offset from
the pooled full-model median (the reference five and two control families, 15 runs) in
their standard deviations, with the limit the full model's own control families stay within
(``BIAS_LIMIT_SD``). The reduced model exceeds it three times, and these are model errors:
the contact-1 maximum force of case 1 serious and case 2 light is 3 % high (+4.6, +2.9 SD)
and case 2 light's sticking share 10 % low (-9.4 SD). They shrink with the cutoff (10 kHz:
+1.2, +0.4 and -3.0 SD).
Measured 2026-11-24 with the pinned Haswell kernels; the reduced runs again on 2026-11-25,
with the reduction on one BLAS thread: the same checks pass and fail.
"""

from __future__ import annotations

import pandas as pd
import pytest
from scripts_loader import load_script

from rubdiag.paper import ensemble
from rubdiag.paper._ensemble import GAP_RAMPS_S
from rubdiag.reduce import Reduction

pytestmark = pytest.mark.slow

script = load_script("reduced_ensemble")
CONTROLS = (1, 2)
#: (cell, quantity) -> the measured miss (reduced median; full min-max), 2026-11-25
OUTSIDE = {
    ("case1_light", "contact1_max_force_n"): "186.1 N; 181.2-182.5",
    ("case1_serious", "contact1_max_force_n"): "199.7 N; 191.7-194.0",
    ("case1_serious", "casing_max_y_m"): "64.58 um; 64.75-65.16",
    ("case2_light", "contact1_max_force_n"): "1002 N; 970-977",
    ("case2_light", "casing_max_y_m"): "205.2 um; 205.4-207.4",
    ("case2_light", "contact1_sticking_share"): "0.296; 0.323-0.330",
    ("case2_serious", "contact1_sticking_share"): "0.421; 0.428-0.444",
}
#: (cell, quantity) -> the measured offset in pooled SDs, beyond BIAS_LIMIT_SD
BIASED = {
    ("case1_serious", "contact1_max_force_n"): "+4.6 SD (199.7 N, 3 % high)",
    ("case2_light", "contact1_max_force_n"): "+2.9 SD (1002 N, 3 % high)",
    ("case2_light", "contact1_sticking_share"): "-9.4 SD (0.296, 10 % low)",
}


@pytest.fixture(scope="module")
def runs():
    reference = ensemble(script.CELLS, GAP_RAMPS_S, jobs=2)
    controls = [ensemble(script.CELLS, script.control_ramps(k), jobs=2) for k in CONTROLS]
    reduced = ensemble(script.CELLS, GAP_RAMPS_S, jobs=2, reduction=Reduction())
    return reference, controls, reduced


@pytest.fixture(scope="module")
def reduced_checks(runs):
    reference, controls, reduced = runs
    return script.checks(reduced, reference, pd.concat([reference, *controls]))


def _params(misses, what):
    for cell in script.CELLS:
        stem = script.STEMS[cell]
        for quantity in script.QUANTITIES:
            miss = misses.get((stem, quantity))
            marks = () if miss is None else pytest.mark.xfail(strict=True, reason=(
                f"reduced at 2 kHz: {what} {miss} (module docstring)"))
            yield pytest.param(stem, quantity, id=f"{stem}-{quantity}", marks=marks)


def _row(table, stem, quantity):
    return table[(table.cell == stem) & (table.quantity == quantity)].iloc[0]


@pytest.mark.parametrize(("stem", "quantity"), list(_params(OUTSIDE, "outside the spread:")))
def test_reduced_median_lies_in_the_full_spread(reduced_checks, stem, quantity):
    r = _row(reduced_checks, stem, quantity)
    assert r.inside, f"{quantity}: reduced median {r['median']:.4g}, full {r.lo:.4g}-{r.hi:.4g}"


@pytest.mark.parametrize(("stem", "quantity"), list(_params(BIASED, "offset")))
def test_reduced_median_is_as_close_as_another_start(reduced_checks, stem, quantity):
    r = _row(reduced_checks, stem, quantity)
    assert abs(r.bias_sd) <= script.BIAS_LIMIT_SD, (
        f"{quantity}: reduced median {r['median']:.4g} is {r.bias_sd:+.2f} SD from the full "
        f"model's (limit {script.BIAS_LIMIT_SD})")


def test_the_bias_limit_holds_for_the_full_model_itself(runs):
    """The limit is not tighter than the start-history scatter: every control family of the
    full model stays within it, though each fails some of the min-max checks."""
    reference, controls, _ = runs
    pooled = pd.concat([reference, *controls])
    for k, control in zip(CONTROLS, controls, strict=True):
        result = script.checks(control, reference, pooled)
        assert result.bias_sd.abs().max() <= script.BIAS_LIMIT_SD, (k, result)
        assert 0 < result.inside.sum() < len(result)
