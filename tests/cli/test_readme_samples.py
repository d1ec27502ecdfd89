"""README's sample outputs are what the tool prints now (scripts/readme_samples.py --check).

On drift: ``python scripts/readme_samples.py`` rewrites the blocks; review the diff.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from scripts_loader import load_script

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def samples():
    return load_script("readme_samples")


@pytest.fixture(scope="module")
def readme():
    return (ROOT / "README.md").read_text(encoding="utf-8")


def _check(samples, readme, names):
    problems = samples.compare(readme, samples.generate(names))
    assert not problems, ("README.md drifted; run `python scripts/readme_samples.py` and "
                          "review:\n" + "\n\n".join(problems))


def test_readme_samples_are_current(samples, readme):
    _check(samples, readme, samples.selected(skip_slow=True))


@pytest.mark.slow
def test_readme_slow_samples_are_current(samples, readme):
    _check(samples, readme, [n for n, s in samples.SAMPLES.items() if s.slow])


def test_every_block_is_a_sample(samples, readme):
    assert set(samples.blocks(readme)) == set(samples.SAMPLES)
    assert samples.SAMPLES["table2"].slow and not samples.SAMPLES["simulate"].slow


def test_drift_is_found_and_volatile_fields_are_not(samples, readme):
    """Without running anything: a changed number is drift, a changed wall time is not."""
    current = samples.blocks(readme)
    assert "s wall)" in current["simulate"]
    assert samples.compare(readme, current) == []
    other_time = {"simulate": current["simulate"].replace(" s wall)", "1 s wall)", 1)}
    assert other_time["simulate"] != current["simulate"]
    assert samples.compare(readme, other_time) == []
    drifted = {"modal": current["modal"].replace("DOFs: 412", "DOFs: 413")}
    (problem,) = samples.compare(readme, drifted)
    assert "-DOFs: 412" in problem and "+DOFs: 413" in problem
    assert samples.compare(readme, {"nowhere": ""}) == [
        "README.md has no block <!-- sample: nowhere -->"]
    # update() puts a block in place and leaves everything around it alone
    updated = samples.update(readme, drifted)
    assert updated == readme.replace(current["modal"], drifted["modal"], 1)
    assert samples.blocks(updated)["modal"] == drifted["modal"]
