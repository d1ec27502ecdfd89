"""The documentation's claims table is rendered from ``data/claims.csv``, and the statuses
follow from the file's own numbers.

No simulation: the measurements are ``tests/paper/test_table2.py``'s. On drift run
``python scripts/claims.py --no-measure`` (statuses from the stored measurements) or
``python scripts/claims.py`` (measure again) and review the diff.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from docs_tables import table as shown
from scripts_loader import load_script

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def claims():
    return load_script("claims")


@pytest.fixture(scope="module")
def table(claims):
    return claims.read()


@pytest.fixture(scope="module")
def prose():
    """The shipped prose: the README and the documentation's pages."""
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("[!_]*/**/*.md")),
             *sorted((ROOT / "docs").glob("*.md"))]
    return "\n".join(p.read_text(encoding="utf-8") for p in pages)


def test_the_documented_table_is_rendered_from_the_claims_file(claims, table):
    rendered = shown("claims")
    assert rendered == claims.render(table)
    for c in table:                  # one row per claim, with its verdict
        verdict = "holds" if c["status"] == claims.HOLDS else "**xfail**"
        assert any(line.startswith(f"| {c['id']} |") and f"| {verdict}" in line
                   for line in rendered.splitlines()), c["id"]


def test_every_claim_is_measured_and_its_status_follows(claims, table):
    ids = [c["id"] for c in table]
    assert len(set(ids)) == len(ids)
    for c in table:
        assert c["measured"] != "", f"{c['id']} not measured"
        assert c["status"] == claims.verdict(c), (c["id"], c["measured"], c["tolerance"])
        if c["status"] == claims.HOLDS:
            assert not c["reason"], f"{c['id']} holds but keeps a reason"
        else:
            assert c["reason"], f"{c['id']} is not reproduced and says not why"


def test_every_claim_has_one_measurement_and_a_tolerance(claims, table):
    table_ids = {c["id"] for c in table if claims.ensemble_intensity(c) is None}
    ensemble_ids = {c["id"] for c in table} - table_ids
    assert set(claims.TABLE) == table_ids
    assert set(claims.RUNS) == ensemble_ids
    for c in table:
        claims.tolerance(c)                      # parses (± forms need a numeric study value)
        assert c["claim"] and c["source"] and c["quantity"] and c["rule"], c["id"]
        if c["id"] in ensemble_ids:
            claims.per_run(c)
            assert claims.tolerance(c).hi <= 5    # k of 5 start histories
        else:
            assert c["per_run"] == "", c["id"]


@pytest.mark.parametrize(("spec", "study", "inside", "outside"), [
    ("±15 %", "5.5 (1042.5 / 189.3)", [4.675, 5.5, 6.325], [4.67, 6.33, float("nan")]),
    ("± 2", "43", [41, 45], [40.9, 45.1]),
    ("(1, 1.15]", "slightly", [1.0001, 1.15], [1.0, 1.151]),
    ("[3, 5]", "present", [3, 5], [2, 6]),
    ("(0.5, 1]", "mainly", [0.51], [0.5]),
    ("(1, inf)", "larger", [1e9, float("inf")], [1.0]),
])
def test_tolerances_mean_what_they_say(claims, spec, study, inside, outside):
    claim = {"tolerance": spec, "study": study, "measured": ""}
    t = claims.tolerance(claim)
    assert all(x in t for x in inside) and not any(x in t for x in outside)


def test_every_claim_holds_only_if_it_does(table, prose):
    everything = all(c["status"] == "holds" for c in table)
    sayings = [r"every\s+claim[^.]*\bholds?\b", r"none\s+is\s+an\s+xfail", r"all\s+claims\s+hold"]
    said = [p for p in sayings if re.search(p, prose, re.IGNORECASE)]
    assert everything or not said, f"the documentation says {said} but not every claim holds"
