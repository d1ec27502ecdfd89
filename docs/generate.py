"""The documentation pages that follow the code, written before each build (``conf.py``).

* ``api/<subpackage>.rst``: one page per public subpackage, its module docstring and an
  autosummary table of the names of its ``__all__`` (each with a page of its own);
* ``cli.md``: every ``rubdiag`` command's help, as ``rubdiag COMMAND --help`` prints it;
* ``tutorials/index.md``: the notebooks, in order;
* ``features.md``: the dictionary of the feature columns (:mod:`rubdiag.signal.glossary`).

A page is rewritten only when its text changes, so that an unchanged page is not rebuilt.
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the public subpackages, in the order a user meets them (the layers, bottom up)
SUBPACKAGES = ("model", "assembly", "modal", "simulate", "reduce", "runs", "signal",
               "dataset", "learn", "paper")


def version() -> str:
    from rubdiag import __version__

    return __version__


def write_all(folder: Path) -> None:
    """Every generated page into ``folder``."""
    for name in SUBPACKAGES:
        _write(folder / "api" / f"{name}.rst", api_page(f"rubdiag.{name}"))
    _write(folder / "cli.md", cli_page())
    _write(folder / "features.md", features_page())
    notebooks = sorted(p.stem for p in (ROOT / "notebooks").glob("*.ipynb"))
    _write(folder / "tutorials" / "index.md", tutorials_page(notebooks))


def api_page(module: str) -> str:
    """The reference page of ``module``: its docstring, then its public names."""
    names = list(importlib.import_module(module).__all__)
    title = f"``{module}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {module}", "   :no-members:", "",
             f".. currentmodule:: {module}", "", ".. autosummary::", "   :toctree: generated",
             "   :nosignatures:", ""]
    lines += [f"   {name}" for name in names]
    return "\n".join(lines) + "\n"


def commands() -> tuple:
    """``(parser, {name: subparser})`` of the ``rubdiag`` command line."""
    from rubdiag.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return parser, dict(sub.choices)


def cli_page() -> str:
    """Every command's ``--help``, from the parsers themselves."""
    parser, subcommands = commands()
    out = ["# Command line", "",
           "Every command of `rubdiag`, with the help it prints (`rubdiag COMMAND --help`).",
           "Invalid input is refused in one line on stderr, with exit status 2.", "",
           "```text", parser.format_help().rstrip(), "```", ""]
    for name, sub in subcommands.items():
        out += [f"## `rubdiag {name}`", "", "```text", sub.format_help().rstrip(), "```", ""]
    return "\n".join(out)


def features_page() -> str:
    """The feature dictionary: one table row per name pattern."""
    from rubdiag.signal.glossary import glossary_frame

    frame = glossary_frame()
    out = ["# Feature columns", "",
           "What each feature column of a feature table or a dataset row means. A dataset "
           "stores a channel's features as `<channel>__<feature>` (`shaft11_y_disp__amp_2x`) "
           "and a probe pair's as `<node>_yz_disp__<feature>`; its `columns.csv` gives every "
           "column's group, channel and unit. `rubdiag.signal.glossary.describe(name)` looks "
           "a column up.", "",
           "In a pattern, `<k>` is an order label (`1x`, `2x`, `1p5x` for 1.5×, `0p33x` for "
           "⅓×) and `<n>` a harmonic, 1 to 8. The unit *signal* is the unit of the signal "
           "(m for a simulation's displacements, the probe's unit for a measurement).", ""]
    for row, title in (("channel", "A channel's row"), ("pair", "A probe pair's row")):
        out += [f"## {title}", "", "| column | unit | meaning |", "|---|---|---|"]
        for e in frame[frame["row"] == row].itertuples():
            out.append(f"| `{e.pattern}` | {e.unit} | {e.meaning} |")
        out.append("")
    return "\n".join(out)


def tutorials_page(notebooks: list[str]) -> str:
    return "\n".join([
        "# Tutorials", "",
        "The notebooks of the repository's `notebooks/` folder, executed on small inputs "
        "(`RUBDIAG_QUICK=1`) when the documentation is built; run them yourself with "
        "Jupyter for the full sizes.", "",
        "```{toctree}", ":maxdepth: 1", "", *notebooks, "```", ""])


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
