"""The documentation pages that follow the code, written before each build (``conf.py``).

* ``api/<subpackage>.rst``: one page per public subpackage, its module docstring and an
  autosummary table of the names of its ``__all__`` (each with a page of its own);
* ``cli.md``: every ``rubdiag`` command's help, as ``rubdiag COMMAND --help`` prints it;
* ``tutorials/index.md``: the notebooks, in order;
* ``features.md``: the dictionary of the feature columns (:mod:`rubdiag.signal._glossary`);
* ``tables/<name>.md``: each table of the validation and explanation pages, rendered from its
  file in ``data/`` by the script that wrote the file (:data:`TABLES`); the numbers that the
  pages' prose states are substitutions (:func:`substitutions`) read from the same files.

A page is rewritten only when its text changes, so that an unchanged page is not rebuilt.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import os
import shutil
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"

#: the public API, grouped by task: every package's ``__all__`` (tests/test_public_api.py)
API = ROOT / "docs" / "api.toml"


def api_groups() -> dict[str, dict[str, list[str]]]:
    """``{package: {group: [names]}}`` from :data:`API`, packages in the order a user meets
    them (the layers, bottom up)."""
    with API.open("rb") as f:
        return tomllib.load(f)


#: the public subpackages, in the order a user meets them
SUBPACKAGES = tuple(name.removeprefix("rubdiag.") for name in api_groups() if "." in name)


def version() -> str:
    from rubdiag import __version__

    return __version__


def write_all(folder: Path) -> None:
    """Every generated page into ``folder``."""
    shutil.rmtree(folder / "api" / "generated", ignore_errors=True)   # stubs of renamed names
    _write(folder / "api" / "rubdiag.rst", top_level_page())
    for name in SUBPACKAGES:
        _write(folder / "api" / f"{name}.rst", api_page(f"rubdiag.{name}"))
    _write(folder / "cli.md", cli_page())
    _write(folder / "features.md", features_page())
    notebooks = sorted(p.stem for p in (ROOT / "notebooks").glob("*.ipynb"))
    _write(folder / "tutorials" / "index.md", tutorials_page(notebooks))
    for name, text in tables().items():
        _write(folder / "tables" / f"{name}.md", text)


def api_page(module: str) -> str:
    """The reference page of ``module``: its docstring, then its public names by task."""
    title = f"``{module}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {module}", "   :no-members:", "",
             f".. currentmodule:: {module}", ""]
    for group, names in api_groups()[module].items():
        lines += [group, "-" * len(group), "", ".. autosummary::", "   :toctree: generated",
                  "   :nosignatures:", "", *(f"   {name}" for name in names), ""]
    return "\n".join(lines)


def top_level_page() -> str:
    """The ``rubdiag`` page: each workflow's entry points, linked to where they are documented
    (the subpackage that defines them), so that no object is documented twice."""
    import rubdiag

    title = "``rubdiag``"
    lines = [title, "=" * len(title), "", ".. automodule:: rubdiag", "   :no-members:", ""]
    for group, names in api_groups()["rubdiag"].items():
        lines += [group, "-" * len(group), ""]
        for name in names:
            where = rubdiag._LAZY.get(name)
            lines.append(f"* ``rubdiag.{name}``" if where is None
                         else f"* :obj:`rubdiag.{name} <{where}.{name}>`")
        lines.append("")
    return "\n".join(lines)


def commands() -> tuple:
    """``(parser, {name: subparser})`` of the ``rubdiag`` command line."""
    from rubdiag.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    commands = {}
    for name, subparser in sub.choices.items():     # an alias maps to its command's parser
        if all(subparser is not seen for seen in commands.values()):
            commands[name] = subparser
    return parser, commands


#: the width (characters) of the help text on the command-line page: the pages' code width
HELP_COLUMNS = 76


def _help(parser) -> str:
    """``parser``'s help wrapped at :data:`HELP_COLUMNS` (argparse reads ``COLUMNS``)."""
    saved = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(HELP_COLUMNS)
    try:
        return parser.format_help().rstrip()
    finally:
        if saved is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = saved


def cli_page() -> str:
    """Every command's ``--help``, from the parsers themselves."""
    parser, subcommands = commands()
    out = ["# Command line", "",
           "Every command of `rubdiag`, with the help it prints (`rubdiag COMMAND --help`).",
           "Invalid input is refused in one line on stderr, with exit status 2.", "",
           "```text", _help(parser), "```", ""]
    for name, sub in subcommands.items():
        out += [f"## `rubdiag {name}`", "", "```text", _help(sub), "```", ""]
    return "\n".join(out)


def features_page() -> str:
    """The feature dictionary: one table row per name pattern."""
    from rubdiag.signal._glossary import glossary_frame

    frame = glossary_frame()
    out = ["# Feature columns", "",
           "What each feature column of a feature table or a dataset row means. A dataset "
           "stores a channel's features as `<channel>__<feature>` (`shaft11_y_disp__amp_2x`) "
           "and a probe pair's as `<node>_yz_disp__<feature>`; its `columns.csv` gives every "
           "column's group, channel and unit. `rubdiag.signal._glossary.describe(name)` looks "
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


def script(name: str):
    """``scripts/<name>.py`` as the module ``name`` (loaded once): the script that wrote a
    data file renders its table."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def tolerances() -> dict:
    """``data/tolerances.toml``: the bands the pages state and the tests apply."""
    return tomllib.loads((DATA / "tolerances.toml").read_text(encoding="utf-8"))


def _percent(fraction: float) -> str:
    return f"{100 * fraction:g} %"


def substitutions() -> dict[str, str]:
    """The values that prose states, as MyST substitutions (``{{ off_bin_band }}`` in a
    page): the bands of ``data/tolerances.toml``, the library's constants, and the measured
    numbers of the validation pages (:func:`prose_values.values`, from ``data/*.csv``)."""
    import prose_values

    from rubdiag.learn import MIN_RUNS_PER_CLASS, NOISE_MARGIN_DB
    check = importlib.import_module("rubdiag.reduce._check")    # the module, not the function
    t = tolerances()
    return {"reduce_frequency_tolerance": _percent(check.FREQUENCY_TOLERANCE),
            "reduce_response_tolerance": _percent(check.RESPONSE_TOLERANCE),
            "reduce_static_tolerance": f"{check.STATIC_TOLERANCE:.0e}".replace("e-0", "e-"),
            "noise_margin_db": f"{NOISE_MARGIN_DB:g}",
            "min_runs_per_class": f"{MIN_RUNS_PER_CLASS}",
            "off_bin_band": _percent(t["off_bin_lines"]["band"]),
            "off_bin_line": _percent(t["off_bin_lines"]["line"]),
            "noise_free_agreement": _percent(t["noise_free"]["agreement"]),
            "noise_free_measured": t["noise_free"]["measured"],
            **prose_values.values()}


def runup_bands_table() -> str:
    """The run-up checks whose bands ``data/tolerances.toml`` holds."""
    t = tolerances()
    stretch, slow = t["speed_stretches"], t["slow_runup"]
    error = f"{stretch['max_error_of_peak']:.0e}".replace("e-0", "e-")
    rows = [(stretch["claim"], f"{error} of each channel's peak",
             stretch["measured"]),
            (slow["claim"], f"{_percent(slow['amplitude'])}, {slow['phase_deg']:g}°",
             slow["measured"])]
    return "\n".join(["| check | band | measured |", "|---|---|---|",
                      *(f"| {a} | {b} | {c} |" for a, b, c in rows)])


def ross_versions() -> str:
    """What computed ``data/ross_references.json``."""
    made = json.loads((DATA / "ross_references.json").read_text(encoding="utf-8"))["generated"]
    return (f"ROSS {made['ross']} (`ross-rotordynamics`), Python {made['python']}, "
            f"NumPy {made['numpy']}, SciPy {made['scipy']}")


def _claims() -> str:
    claims = script("claims")
    return claims.render(claims.read())


def _mu(render: str) -> str:
    fit = script("fit_mu")
    runs = fit.load_runs(fit.DATA)
    import pandas as pd

    summary = pd.read_csv(fit.DATA / fit.SUMMARY_FILE)
    return getattr(fit, render)(runs, summary, fit.preset_mu())


def _dt_convergence() -> str:
    dt = script("dt_convergence")
    return dt.to_markdown(dt.read_summary(dt.SUMMARY_CSV))


def _csv_table(name: str, render: str, csv: str = "CSV") -> str:
    import pandas as pd

    module = script(name)
    return getattr(module, render)(pd.read_csv(getattr(module, csv)))


def _confusers(design: str) -> dict[str, str]:
    """The confuser tables of ``design``'s dataset; one one-against-one table per split."""
    import pandas as pd

    module = script("confuser_tables")
    cells_csv, rates_csv, one_csv, splits = module.OUTPUTS[design]
    cells, rates, one = (pd.read_csv(path) for path in (cells_csv, rates_csv, one_csv))
    prefix = {"faults_journal": "", "faults_bands": "bands-"}.get(
        design, design.replace("_", "-") + "-")
    out = {f"{prefix}confuser-goals": module.goals_table(cells, rates),
           f"{prefix}confuser-recall": module.recall_table(rates)}
    for split in splits:
        part = one[one["split"] == split] if "split" in one else one
        name = f"{prefix}one-vs-one" + ("" if split == "group" else f"-{split}")
        out[name] = module.one_vs_one_table(part) + "\n\n" + module.study_failures(part)
    return out


#: every generated table: name -> what renders it from its files in ``data/``
TABLES = {
    "claims": _claims,
    "mu-fit": lambda: _mu("render"),
    "mu-validated": lambda: _mu("validated"),
    "dt-convergence": _dt_convergence,
    "uncertainty": lambda: _csv_table("uncertainty", "table"),
    "step-study": lambda: _csv_table("step_study", "markdown"),
    "learn-table": lambda: _csv_table("learn_table", "table"),
    "noise-curve": lambda: _csv_table("noise_table", "table"),
    "runup-bands": runup_bands_table,
    "ross-versions": ross_versions,
    **{name: (lambda design=design, name=name: _confusers(design)[name])
       for design, names in (("faults_journal", ("confuser-goals", "confuser-recall",
                                                 "one-vs-one")),
                             ("faults_bands", ("bands-confuser-goals",
                                               "bands-confuser-recall", "bands-one-vs-one",
                                               "bands-one-vs-one-speed_ratio")),
                             ("rub_kinds", ("rub-kinds-confuser-goals",
                                            "rub-kinds-confuser-recall",
                                            "rub-kinds-one-vs-one",
                                            "rub-kinds-one-vs-one-speed_ratio")))
       for name in names},
}


def table(name: str) -> str:
    """The generated table ``name`` (Markdown, one final newline)."""
    return TABLES[name]().rstrip("\n") + "\n"


def tables() -> dict[str, str]:
    """Every generated table, by name."""
    return {name: table(name) for name in TABLES}


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
