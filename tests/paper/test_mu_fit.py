"""The μ fit (scripts/fit_mu.py): the stored scan is complete, the summary and the tables of
the documentation's "How μ was chosen" follow from the stored runs by the script's stated
rule, and the preset μ is the one they name.

The fast tests read data/mu_fit.csv only; the slow one re-runs one stored simulation.
"""

import dataclasses
import math
import re

import numpy as np
import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script

from rubdiag.model import paper_rig
from rubdiag.paper import paper_values
from rubdiag.paper._ensemble import GAP_RAMPS_S

script = load_script("fit_mu")

RUNS = script.load_runs(script.DATA)
SUMMARY = pd.read_csv(script.DATA / script.SUMMARY_FILE)
#: what the documentation shows, rendered from the stored files when it is built
SHOWN = table("mu-fit")
VALIDATED = table("mu-validated")


def test_the_scan_is_complete():
    mus = np.round(np.arange(0.10, 0.60 + 1e-9, 0.05), 2)
    np.testing.assert_allclose(sorted(RUNS["mu"].unique()), mus)
    for mu, grp in RUNS.groupby("mu"):
        cells = sorted(zip(grp["case"], grp["gap_mm"], grp["gap_ramp_s"], strict=True))
        assert cells == sorted((c, g, r) for c, _, g in script.CELLS for r in GAP_RAMPS_S), mu
        for key, value in script.RUN_OPTIONS.items():
            np.testing.assert_allclose(grp[key], value)
    assert (RUNS["status"] == "ok").all(), RUNS.loc[RUNS["status"] != "ok", ["mu", "message"]]


def test_summary_is_the_stored_runs_summary():
    pd.testing.assert_frame_equal(script.summary(RUNS), SUMMARY, check_dtype=False, rtol=1e-5)


def test_the_documented_tables_are_what_the_stored_data_say():
    # the table, μ*, the held-out scores and the preset μ, as `fit_mu.py --table` prints them
    assert SHOWN == script.render(RUNS, SUMMARY, script.preset_mu()).rstrip("\n") + "\n"
    assert VALIDATED == script.validated(RUNS, SUMMARY, script.preset_mu()).rstrip("\n") + "\n"


def test_validated_ratios_recomputed_by_hand():
    """The held-out case-2 / case-1 ratios at split A's μ*, from the runs and the claims
    table's tolerance, without the script's helpers."""
    star = script.results(RUNS, SUMMARY, script.preset_mu())["A"]["mu_star"]
    study = paper_values().set_index(["case", "intensity"])
    claims = pd.read_csv(script.DATA / "claims.csv").set_index("id")
    at = RUNS[np.isclose(RUNS["mu"], star)]
    for claim, q, intensity in (("C2i", "contact1_max_force_n", "light"),
                                ("C2b", "casing_max_y_um", "serious")):
        med = {c: np.median(at.loc[(at["case"] == c) & (at["intensity"] == intensity), q])
               for c in (1, 2)}
        ours = med[2] / med[1]
        theirs = study.loc[(2, intensity), q] / study.loc[(1, intensity), q]
        tol = float(claims.loc[claim, "tolerance"].strip("±% ")) / 100
        verdict = "holds" if abs(ours / theirs - 1) <= tol else "does not hold"
        assert f"{ours:.1f} against {theirs:.1f} ± {100 * tol:.0f} % ({claim}: {verdict};" \
            in VALIDATED


def test_split_a_recomputed_by_hand():
    """The main rule, written out again without the script's helpers: medians over the five
    histories, rms log-ratio to the study's case-1 numbers, argmin over μ."""
    study = paper_values().set_index(["case", "intensity"])
    quantities = ("contact1_max_force_n", "casing_max_y_um")

    def r(mu, case):
        logs = []
        for intensity in ("light", "serious"):
            rows = RUNS[(RUNS["mu"] == mu) & (RUNS["case"] == case)
                        & (RUNS["intensity"] == intensity)]
            logs += [math.log(np.median(rows[q]) / study.loc[(case, intensity), q])
                     for q in quantities]
        return math.sqrt(np.mean(np.square(logs)))

    mus = sorted(RUNS["mu"].unique())
    fit = [r(mu, 1) for mu in mus]
    star = mus[int(np.argmin(fit))]
    held = {mu: r(mu, 2) for mu in mus}
    stated = re.search(r"Split A .*?μ\* = (?P<star>[\d.]+) \(r = (?P<fit>\d+) %\); held out "
                       r"r = (?P<held>\d+) % at μ\*, (?P<preset>\d+) % at the preset",
                       SHOWN)
    assert stated is not None
    assert float(stated["star"]) == pytest.approx(star)
    assert int(stated["fit"]) == round(100 * min(fit))
    assert int(stated["held"]) == round(100 * held[star])
    assert int(stated["preset"]) == round(100 * held[script.preset_mu()])


def test_preset_mu_is_the_one_the_documentation_names():
    stated = re.search(r"Preset μ = (?P<mu>[\d.]+)\.", SHOWN)
    assert stated is not None
    assert float(stated["mu"]) == paper_rig().contact.friction_coefficient


@pytest.mark.parametrize(("delta_hz", "holds"), [(5.0, True), (4.0, True), (6.0, True),
                                                 (2.8, False), (6.5, False), (math.nan, False)])
def test_sideband_claim_is_4x_pm_5_hz(delta_hz, holds):
    row = {f"shaft_{k}": math.nan for k in script.SPECTRAL}
    row.update(case=1, intensity="light", contact1_sticking_share=0.3,
               shaft_sb_4x_delta_hz=delta_hz)
    assert script.claim_holds(row, "C1d/l") is holds
    assert script.claim_holds({**row, "case": 2}, "C1d/l") is None


def test_claims_are_those_of_the_claims_table():
    ids = set(pd.read_csv(script.DATA / "claims.csv")["id"])
    for claim in script.CLAIMS:
        first, *others = claim.split("/")
        assert first in ids and all(first[:-1] + o in ids for o in others), claim


@pytest.mark.slow
def test_a_stored_run_is_reproduced():
    """Re-simulate the case-1 light run at μ* (split A), gap ramp 0.1 s."""
    star = script.results(RUNS, SUMMARY, script.preset_mu())["A"]["mu_star"]
    from rubdiag.paper import ensemble

    rig = paper_rig()
    contact = dataclasses.replace(rig.contact, friction_coefficient=star)
    again = script._rows(ensemble([(1, 2.3)], (0.1,), jobs=1, rig=rig, contact=contact,
                                  **script.RUN_OPTIONS), star).iloc[0]
    stored = RUNS[(RUNS["mu"] == star) & (RUNS["case"] == 1) & (RUNS["gap_mm"] == 2.3)
                  & np.isclose(RUNS["gap_ramp_s"], 0.1)].iloc[0]
    for key in ("contact1_max_force_n", "casing_max_y_um", "contact1_sliding_entries"):
        assert again[key] == pytest.approx(stored[key], rel=1e-5), key
