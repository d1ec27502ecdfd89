"""The documentation's sample outputs are what the tool prints now
(scripts/doc_samples.py --check).

On drift: ``python scripts/doc_samples.py`` rewrites the blocks; review the diff.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from scripts_loader import load_script

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def samples():
    return load_script("doc_samples")


def page_of(samples, name) -> str:
    return (ROOT / samples.SAMPLES[name].page).read_text(encoding="utf-8")


def _check(samples, names):
    problems = []
    for name in names:
        problems += samples.compare(page_of(samples, name), samples.generate([name]),
                                    samples.SAMPLES[name].page)
    assert not problems, ("the pages drifted; run `python scripts/doc_samples.py` and "
                          "review:\n" + "\n\n".join(problems))


def test_samples_are_current(samples):
    _check(samples, samples.selected(skip_slow=True))


@pytest.mark.slow
def test_slow_samples_are_current(samples):
    _check(samples, [n for n, s in samples.SAMPLES.items() if s.slow])


def test_every_block_is_a_sample_on_its_page(samples):
    pages = {s.page for s in samples.SAMPLES.values()}
    found = {}
    for page in pages:
        for name in samples.blocks((ROOT / page).read_text(encoding="utf-8")):
            assert name not in found, f"{name} on {page} and {found[name]}"
            found[name] = page
    assert found == {name: s.page for name, s in samples.SAMPLES.items()}
    assert samples.SAMPLES["table2"].slow and not samples.SAMPLES["simulate"].slow


def test_drift_is_found_and_volatile_fields_are_not(samples):
    """Without running anything: a changed number is drift, a changed wall time is not."""
    simulate, modal = page_of(samples, "simulate"), page_of(samples, "modal")
    current = {**samples.blocks(simulate), **samples.blocks(modal)}
    assert "s wall)" in current["simulate"]
    assert samples.compare(simulate, {"simulate": current["simulate"]}) == []
    other_time = {"simulate": current["simulate"].replace(" s wall)", "1 s wall)", 1)}
    assert other_time["simulate"] != current["simulate"]
    assert samples.compare(simulate, other_time) == []
    drifted = {"modal": current["modal"].replace("DOFs: 412", "DOFs: 413")}
    (problem,) = samples.compare(modal, drifted, "model.md")
    assert "-DOFs: 412" in problem and "+DOFs: 413" in problem
    assert samples.compare(modal, {"nowhere": ""}, "model.md") == [
        "model.md has no block <!-- sample: nowhere -->"]
    # update() puts a block in place and leaves everything around it alone
    updated = samples.update(modal, drifted)
    assert updated == modal.replace(current["modal"], drifted["modal"], 1)
    assert samples.blocks(updated)["modal"] == drifted["modal"]
