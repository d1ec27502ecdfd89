"""The documentation's generated pages follow the code: every public name of every
subpackage has its reference entry, every command its help; and the site builds with
warnings as errors (slow: ``make docs`` executes the notebooks too)."""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS))
generate = importlib.import_module("generate")


@pytest.mark.parametrize("name", generate.SUBPACKAGES)
def test_every_public_name_has_a_reference_entry(name):
    page = generate.api_page(f"rubdiag.{name}")
    listed = [line.strip() for line in page.splitlines() if line.startswith("   ")
              and not line.strip().startswith(":")]
    assert listed == list(importlib.import_module(f"rubdiag.{name}").__all__)


def test_every_command_has_its_help_on_the_command_line_page():
    from rubdiag.cli import build_parser

    page = generate.cli_page()
    commands = next(a for a in build_parser()._actions
                    if a.__class__.__name__ == "_SubParsersAction").choices
    assert len(commands) > 10
    for name, parser in commands.items():
        assert f"## `rubdiag {name}`" in page
        assert parser.format_help().rstrip() in page


def test_every_notebook_is_a_tutorial():
    notebooks = sorted(p.stem for p in (DOCS.parent / "notebooks").glob("*.ipynb"))
    page = generate.tutorials_page(notebooks)
    assert all(f"\n{stem}\n" in page for stem in notebooks)


def test_the_tour_runs_and_finds_the_rub(tmp_path, monkeypatch):
    """The getting-started tour's code cells, run in order as the page shows them: the
    simulated rub is found by the model trained in the tour, and the dataset holds runs
    with and without rub."""
    cells = re.findall(r"```\{code-cell\} ipython3\n(.*?)```", (DOCS / "tour.md").read_text(),
                       re.S)
    assert len(cells) >= 5
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for cell in cells:
        exec(cell, namespace)
    data, table = namespace["data"], namespace["table"]
    assert set(data["rub"].astype(bool)) == {True, False}
    assert (table["predicted"].astype(str) == "True").all()


@pytest.mark.slow
def test_the_site_builds_without_a_warning(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_nb")
    done = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going",
                           "-D", "nb_execution_mode=off", str(DOCS), str(tmp_path / "html")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "html" / "_generated" / "cli.html").exists()
