"""The documentation's generated pages follow the code: every public name of every
subpackage has its reference entry, every command its help; and the site builds with
warnings as errors (slow: ``make docs`` executes the notebooks too)."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from scripts_loader import load_script

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS))
generate = importlib.import_module("generate")


@pytest.mark.parametrize("name", generate.SUBPACKAGES)
def test_every_public_name_has_a_reference_entry(name):
    page = generate.api_page(f"rubdiag.{name}")
    listed = [line.strip() for line in page.splitlines() if line.startswith("   ")
              and not line.strip().startswith(":")]
    assert sorted(listed) == sorted(importlib.import_module(f"rubdiag.{name}").__all__)


def test_every_command_has_its_help_on_the_command_line_page():
    page = generate.cli_page()
    _, commands = generate.commands()
    assert len(commands) > 10
    for name, parser in commands.items():
        assert f"## `rubdiag {name}`" in page
        assert generate._help(parser) in page
    # wrapped to the page's code width: nothing is cut off on the page
    blocks = page.split("```text\n")[1:]
    widest = max(len(line) for block in blocks for line in block.split("```")[0].splitlines())
    assert widest <= generate.HELP_COLUMNS


def test_the_feature_page_lists_every_pattern_with_its_unit():
    from rubdiag.signal._glossary import GLOSSARY

    page = generate.features_page()
    for entry in GLOSSARY:
        assert f"| `{entry.pattern}` | {entry.unit} |" in page


def test_every_notebook_is_a_tutorial():
    notebooks = sorted(p.stem for p in (DOCS.parent / "notebooks").glob("*.ipynb"))
    page = generate.tutorials_page(notebooks)
    assert all(f"\n{stem}\n" in page for stem in notebooks)


def run_page(page: Path, tmp_path, monkeypatch) -> dict:
    """Run a page's code cells in order, as the built page shows them; their namespace."""
    cells = re.findall(r"```\{code-cell\} ipython3\n(.*?)```", page.read_text(), re.S)
    assert cells, f"{page.name} has no code cell"
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for cell in cells:
        exec(cell, namespace)
    return namespace


@pytest.mark.slow      # a minute: make docs executes the page too
def test_the_tour_runs_and_finds_the_rub(tmp_path, monkeypatch):
    """The getting-started tour: the dataset holds runs with and without rub, and the
    simulated rub is found by the model trained in the tour."""
    namespace = run_page(DOCS / "tour.md", tmp_path, monkeypatch)
    data, table = namespace["data"], namespace["table"]
    assert set(data["rub"].astype(bool)) == {True, False}
    assert (table["predicted"].astype(str) == "True").all()


def test_your_own_rig_moves_the_first_critical_speed_down(tmp_path, monkeypatch):
    """A heavier disc lowers the first critical speed, and a misspelt key is refused by
    name."""
    namespace = run_page(DOCS / "how-to" / "own-rig.md", tmp_path, monkeypatch)
    rig, paper = namespace["rig"], namespace["paper_rig"]()
    assert rig.discs[0].thickness_m == pytest.approx(1.5 * paper.discs[0].thickness_m)
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds

    assert critical_speeds(assemble(rig), n=1)[0] < critical_speeds(assemble(paper), n=1)[0]


def test_comparing_records_shows_the_rub_beside_the_healthy_machine(tmp_path, monkeypatch,
                                                                      capsys):
    """compare prints both records' features and writes the figure."""
    namespace = run_page(DOCS / "how-to" / "compare-records.md", tmp_path, monkeypatch)
    printed = capsys.readouterr().out
    assert "healthy.csv" in printed and "rubbing.csv" in printed and "um" in printed
    assert (namespace["folder"] / "spectra.png").stat().st_size > 10_000


@pytest.mark.slow(reason=(
    "make docs executes the page; by default tests/dataset/test_killed_command.py::"
    "test_a_killed_job_keeps_every_run_it_counted kills the same 16-run job and resumes it, "
    "and tests/dataset/test_generate.py's SIGKILL tests kill a job at chosen moments"))
def test_a_killed_dataset_resumes_where_it_stopped(tmp_path, monkeypatch):
    """The job killed after four stored runs: the rerun reuses at least those four and the
    folder ends with every run of the design once."""
    namespace = run_page(DOCS / "how-to" / "dataset-resume.md", tmp_path, monkeypatch)
    assert namespace["job"].returncode == -9
    stored = int(re.search(r"(\d+) already stored", namespace["done"].stdout).group(1))
    assert 4 <= stored < 16
    rows = namespace["rows"]
    assert len(rows) == rows["run_id"].nunique() == 16


@pytest.mark.slow      # a minute: make docs executes the page too
def test_a_plant_record_is_predicted_from_the_probes_it_has(tmp_path, monkeypatch):
    """One probe and an x-y pair: the rubbing run's CSV is called rub, the healthy one not,
    in Python and on the command line (speeds from a CSV)."""
    namespace = run_page(DOCS / "how-to" / "plant-probes.md", tmp_path, monkeypatch)
    assert namespace["one"].channels == ["shaft11_y_disp"]
    done = namespace["done"]
    assert done.returncode == 0, done.stderr
    verdicts = {line.split(".csv")[0]: re.findall(r"\b(True|False)\b", line)[-1]
                for line in done.stdout.splitlines() if ".csv" in line and " all " in line}
    assert verdicts == {"rubbing": "True", "healthy": "False"}
    table = namespace["table"]
    assert (table["predicted"].astype(str) == "True").all()


def test_a_runup_shows_its_rub_in_the_order_tracks(tmp_path, monkeypatch):
    """In contact, 3x stands more than 10 times above its level before the first contact,
    and 1x peaks inside the contact band."""
    namespace = run_page(DOCS / "how-to" / "runup.md", tmp_path, monkeypatch)
    tracks, summary = namespace["tracks"], namespace["summary"]
    first, last = summary["first_contact_rpm"], summary["last_contact_rpm"]
    before = tracks[tracks["rpm"] < first - 20]
    during = tracks[(tracks["rpm"] > first) & (tracks["rpm"] < last)]
    assert during["amp_3x"].max() > 10 * before["amp_3x"].max()
    assert first <= summary["peak_rpm"] <= last


@pytest.mark.slow(reason=(
    "make docs executes the page; by default tests/dataset/test_generate.py::"
    "test_a_dask_cluster_gives_the_same_rows checks a LocalCluster's rows bit for bit "
    "against local processes' and tests/dataset/test_dask_workers.py::"
    "test_dask_workers_with_other_kernels_give_this_process_rows_bit_for_bit"))
def test_a_dataset_on_dask_is_the_local_one_to_the_bit(tmp_path, monkeypatch):
    """Every run made on a LocalCluster, and every feature equal to the local processes'."""
    pytest.importorskip("dask.distributed")
    saved = dict(os.environ)        # the cluster's nannies set thread counts in this process
    try:
        namespace = run_page(DOCS / "how-to" / "dask.md", tmp_path, monkeypatch)
    finally:
        os.environ.clear()
        os.environ.update(saved)
    assert namespace["summary"]["ok"] == 6 and namespace["summary"]["failed"] == 0
    on_dask, local = namespace["on_dask"], namespace["local"]
    assert list(on_dask.index) == list(local.index)
    features = namespace["features"]
    assert len(features) > 100
    assert on_dask[features].equals(local[features])


def test_a_crack_resonates_at_half_the_critical_and_rub_shows_beside_it(tmp_path,
                                                                          monkeypatch):
    """The crack's 2x/1x at half the critical speed is over 100 times its value at the
    critical; with rub there the broadband at 2x and the 7x line rise over 100-fold and
    10-fold, and the blades touch."""
    rows = run_page(DOCS / "how-to" / "fault-beside-rub.md", tmp_path, monkeypatch)["rows"]
    half, alone, rub = (rows[k][0] for k in rows)
    assert half["amp_2x"] / half["amp_1x"] > 100 * alone["amp_2x"] / alone["amp_1x"]
    assert rub["bb_2x_rms"] / rub["amp_1x"] > 100 * alone["bb_2x_rms"] / alone["amp_1x"]
    assert rub["amp_7x"] / rub["amp_1x"] > 10 * alone["amp_7x"] / alone["amp_1x"]
    episodes = [rows[k][1] for k in rows]
    assert episodes[0] == episodes[1] == 0 < episodes[2]


@pytest.mark.slow
def test_the_site_builds_without_a_warning(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_nb")
    done = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going",
                           "-D", "nb_execution_mode=off", str(DOCS), str(tmp_path / "html")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "html" / "_generated" / "cli.html").exists()


def test_every_generated_table_is_shown_by_one_page():
    """Each table rendered from data/ is included by exactly one page."""
    pages = [p for p in DOCS.rglob("*.md") if not p.is_relative_to(DOCS / "_build")
             and not p.is_relative_to(DOCS / "_generated")]
    for name in generate.TABLES:
        including = [p for p in pages
                     if f"{{include}} ../_generated/tables/{name}.md\n" in p.read_text()]
        assert len(including) == 1, (name, including)


def test_the_tables_show_the_values_of_their_data_files():
    """The bands of data/tolerances.toml and a cell of data/learn_table.csv, read here
    without the renderers, appear in the rendered tables and prose."""
    shown = generate.table("runup-bands")
    bands = generate.tolerances()["slow_runup"]
    assert f"| {100 * bands['amplitude']:g} %, {bands['phase_deg']:g}° |" in shown
    assert generate.substitutions()["off_bin_band"] == (
        f"{100 * generate.tolerances()['off_bin_lines']['band']:g} %")
    import pandas as pd

    table = pd.read_csv(generate.DATA / "learn_table.csv")
    first = table.iloc[0]
    assert f"**{first.macro_f1:.2f} [{first.macro_f1_lo:.2f}, {first.macro_f1_hi:.2f}]**" in (
        generate.table("learn-table"))


def test_prose_states_the_library_constants():
    """The reduced model's tolerances, as its page states them, are rubdiag.reduce._check's."""
    check = importlib.import_module("rubdiag.reduce._check")    # the module, not the function
    values = generate.substitutions()
    assert values["reduce_frequency_tolerance"] == f"{100 * check.FREQUENCY_TOLERANCE:g} %"
    assert values["reduce_response_tolerance"] == f"{100 * check.RESPONSE_TOLERANCE:g} %"
    assert float(values["reduce_static_tolerance"]) == check.STATIC_TOLERANCE


check_site = importlib.import_module("check_site")       # docs/check_site.py
needs_chromium = pytest.mark.skipif(not check_site.CHROMIUM.is_file(),
                                    reason=f"no Chromium at {check_site.CHROMIUM} "
                                           "(apt-get install chromium)")


@pytest.mark.slow
@needs_chromium
def test_the_browser_check_finds_a_missing_figure_and_a_dead_link(tmp_path):
    """A page with one good figure, one missing figure, a link to a missing anchor and a
    link to a missing page: exactly the last three are reported."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(2, 1))
    ax.plot([0, 1], [0, 1])
    fig.savefig(tmp_path / "good.png")
    plt.close(fig)
    (tmp_path / "other.html").write_text('<html><body><h1 id="there">x</h1></body></html>')
    (tmp_path / "index.html").write_text(
        '<html><head><title>t</title></head><body><img src="good.png"><img src="gone.png">'
        '<a href="other.html#there">ok</a><a href="other.html#nowhere">anchor</a>'
        '<a href="missing.html">page</a><a href="https://example.org/x">outside</a>'
        '</body></html>')
    (seen,) = check_site.check_site(tmp_path, ["index.html"], tmp_path / "shots")
    assert seen["images"] == 2
    problems = seen["problems"]
    assert len(problems) == 3, problems
    assert "gone.png" in problems[0]
    assert any("#nowhere" in p for p in problems) and any("missing.html" in p for p in problems)
    assert (tmp_path / "shots" / "index.png").stat().st_size > 1000


@pytest.mark.slow       # builds the site first when there is no build (make docs: minutes)
@needs_chromium
def test_the_built_pages_show_their_figures_and_no_link_is_dead():
    """The home page, a tutorial, an API page and the command-line page, opened in headless
    Chromium: every image loaded, every internal link resolves, the tutorial has figures."""
    if not (check_site.BUILD / "index.html").is_file():
        done = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W",
                               "--keep-going", str(DOCS), str(check_site.BUILD)],
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stderr[-3000:]
    seen = {page["page"]: page for page in check_site.check_site()}
    assert list(seen) == list(check_site.PAGES)
    for page in seen.values():
        assert page["problems"] == [], page
        assert page["title"] and page["links"] > 20, page
        assert page["screenshot"].stat().st_size > 20_000, page
    assert seen["_generated/tutorials/02_rub_simulation.html"]["images"] >= 3


# ------------------------------------------------------------------------------------------
# The validation pages state no measured number by hand: their prose takes each one from
# data/ through a substitution ({{ name }}, docs/prose_values.py)
# ------------------------------------------------------------------------------------------
VALIDATION = DOCS / "validation"
#: what a typed number looks like: a decimal, a count "k of n", a percentage
TYPED_NUMBER = re.compile(r"(?<![\w.])\d+\.\d+|(?<![\w.])\d+ of \d+\b|(?<![\w.])\d+(?:\.\d+)? ?%")

#: numbers the pages may type: what a study was given (design ranges, durations, steps, rules
#: and goals), never what it measured
STATED = {
    "checked-against.md": {"1 %"},                              # the closed forms' band
    "claims.md": {"0.1", "15 %", "2 %", "3 of 5", "2 of 5",     # the claims' rules
                  "2.5"},                                       # the script's duration (min)
    "classifier-table.md": {"0.8", "1.2", "0.2", "2.0", "0.1", "0.5", "95 %"},   # the design
    "confusers.md": {"2.5", "0.7", "0.8", "0.45", "0.55", "0.9", "1.1",          # the designs
                     "95 %", "2 %", "5 %", "10 %"},             # intervals, bands and goals
    "dt-convergence.md": {"2.5", "2.3", "0.3"},                 # steps and durations
    "index.md": {"0.3", "0.1", "0.5"},                          # window, ramp, a test's band
    "model-uncertainty.md": {"0.75"},                           # where the approach is taken
    "mu-fit.md": {"2.3", "0.3"},                                # Table 2's durations
    "step-study.md": {"2.3", "95 %"},
    "table2.md": {"2.3", "1.9", "0.1", "0.3", "2.5", "0.4", "0.5", "4.3",    # cases, sweep
                  "0.2",                                        # a setting of the sweep
                  "1.1"},                                       # the study's case-2 force
}
def prose(text: str) -> str:
    """A page's text without code, generated samples, comments, inline code and
    substitutions: what a writer types as sentences."""
    for pattern in (r"```.*?```", r"<!-- sample: .*?<!-- /sample -->", r"<!--.*?-->",
                    r"`[^`\n]*`", r"\{\{.*?\}\}"):
        text = re.sub(pattern, " ", text, flags=re.S)
    return text


def test_the_prose_filter_keeps_sentences_and_drops_code_and_substitutions():
    text = ("Rub 0.970 [0.952, 0.985], 22 of 22, 18 %.\n```python\nx = 0.5\n```\n"
            "`g0 = 1.9` and {{ rub_kinds_rub_point }} <!-- 0.1 -->")
    assert TYPED_NUMBER.findall(prose(text)) == ["0.970", "0.952", "0.985", "22 of 22", "18 %"]


@pytest.mark.parametrize("page", sorted(p.name for p in VALIDATION.glob("*.md")))
def test_a_validation_page_types_no_measured_number(page):
    typed = set(TYPED_NUMBER.findall(prose((VALIDATION / page).read_text(encoding="utf-8"))))
    allowed = STATED.get(page, set())
    assert typed <= allowed, f"typed by hand in {page}: {sorted(typed - allowed)}"


def test_every_substitution_a_page_uses_is_defined():
    values = generate.substitutions()
    pages = [p for p in DOCS.rglob("*.md") if "_build" not in p.parts]
    used = {name for p in pages
            for name in re.findall(r"\{\{\s*(\w+)\s*\}\}", p.read_text(encoding="utf-8"))}
    assert used and used <= set(values), sorted(used - set(values))


def _csv(name: str):
    import pandas as pd

    return pd.read_csv(generate.DATA / name)


def _cell(frame, **where):
    """The one row of ``frame`` with the values ``where``."""
    for column, value in where.items():
        frame = frame[frame[column] == value]
    (row,) = frame.itertuples()
    return row


def test_the_confuser_substitutions_are_the_csv_cells():
    """Scores, alarms and recalls of the three confuser studies, read here from the CSVs."""
    values = generate.substitutions()
    cells = _csv("rub_kinds_confuser_cells.csv")
    r = _cell(cells, target="rub", split="group")
    assert values["rub_kinds_rub_point"] == (
        f"{r.macro_f1:.3f} [{r.macro_f1_lo:.3f}, {r.macro_f1_hi:.3f}]")
    r = _cell(_csv("confuser_cells.csv"), target="fault", split="speed_ratio")
    assert values["journal_fault_band"].startswith(f"{r.macro_f1:.3f} [")
    rates = _csv("rub_kinds_confuser_rates.csv")
    r = _cell(rates, measure="rub recall", faults="rub (seal)", target="rub", split="group")
    assert values["rub_kinds_rub_point_recall_seal"] == f"{r.n_called_rub} of {r.n}"
    r = _cell(_csv("confuser_rates.csv"), measure="false rub alarm", faults="whirl",
              target="rub", split="speed_ratio")
    assert values["journal_rub_band_whirl_alarms"] == f"{r.n_called_rub} of {r.n}"
    one = _csv("one_vs_one.csv")
    r = _cell(one, split="group", a="rub", b="crack", family="study")
    assert values["journal_rub_crack_study"] == f"{r.macro_f1:.3f}"


def test_the_transfer_substitutions_count_the_stored_predictions():
    """The blade rubs found with each blade count held out, counted again from
    data/transfer_predictions.csv."""
    predictions = _csv("transfer_predictions.csv")
    held = predictions[predictions["trained_on"].str.contains("without blade_count")
                       & (predictions["kind"] == "rub (blade)")]
    found = held.groupby("scored_on", sort=False)["called_rub"].agg(["sum", "size"])
    expected = [f"{k} of {n}" for k, n in found.itertuples(index=False)]
    shown = generate.substitutions()["transfer_blade_rubs"]
    assert re.findall(r"\d+ of \d+", shown) == expected
    assert "(8 blades)" in shown


def test_the_learn_and_mu_substitutions_are_the_csv_cells():
    values = generate.substitutions()
    r = _cell(_csv("learn_table.csv"), target="severity", split="group", estimator="rf")
    assert values["learn_severity_point_rf_margin3"] == f"{r.margin:+.3f}"
    assert values["learn_severity_point_short"] == f"{0.10 - r.margin:.3f}"
    summary = _csv("mu_fit_summary.csv")
    for split in ("A", "B"):
        best = summary.loc[summary[f"r_{split}_fit"].idxmin()]
        assert values[f"mu_{split}_star"] == f"{best.mu:g}"
        assert values[f"mu_{split}_held_star"] == f"{100 * best[f'r_{split}_held']:.0f}"


def test_the_step_and_dt_substitutions_are_the_csv_cells():
    values = generate.substitutions()
    r = _cell(_csv("step_study.csv"), ensemble="journal", step_error=1e-5, family="sidebands")
    assert values["step_journal_sidebands_p95"] == f"{r.ratio_p95:.3f}"
    assert values["step_time_default_journal"] == f"{r.simulate_s_ratio:.2f}"
    summary = _csv("dt_convergence.csv")
    entries = [_cell(summary, quantity=f"contact1_{k}_entries", case=2, intensity="light")
               for k in ("sliding", "sticking")]
    assert values["dt_entries_2light"] == " / ".join(f"{e.median_2p5us:.0f}" for e in entries)
    runs = _csv("dt_convergence_runs.csv")
    assert values["dt_runs"] == str(len(runs))


# ------------------------------------------------------------------------------------------
# make docs executes the pages in parallel first (docs/execute_pages.py): Sphinx must then
# find each one in the cache, so the script reads every page exactly as myst-nb does
# ------------------------------------------------------------------------------------------
execute_pages = importlib.import_module("execute_pages")      # docs/execute_pages.py


def _myst_nb_hash(source: Path, tmp_path) -> str:
    """The cache key of ``source`` as myst-nb's own reader in the Sphinx build makes it."""
    from jupyter_cache import get_cache
    from myst_nb.core.config import NbParserConfig
    from myst_nb.core.read import create_nb_reader
    from myst_parser.config.main import MdParserConfig

    text = source.read_text(encoding="utf-8")
    reader = create_nb_reader(str(source), MdParserConfig(), NbParserConfig(), text)
    return get_cache(str(tmp_path / "cache")).create_hashed_notebook(reader.read(text))[1]


def test_the_parallel_executor_runs_every_executed_page_once():
    """Every notebook and every page with code cells, and nothing else."""
    pytest.importorskip("myst_nb")      # the docs extra (make docs)
    found = [source for source, _ in execute_pages.pages()]
    assert len(found) == len(set(found))
    notebooks = sorted((DOCS.parent / "notebooks").glob("*.ipynb"))
    assert found[:len(notebooks)] == notebooks
    pages = set(found[len(notebooks):])
    assert DOCS / "tour.md" in pages and DOCS / "index.md" not in pages
    assert all("```{code-cell}" in p.read_text(encoding="utf-8") for p in pages)


@pytest.mark.parametrize("source", [DOCS / "tour.md", DOCS / "how-to" / "own-rig.md",
                                    DOCS.parent / "notebooks" / "01_rig_and_modes.ipynb"],
                         ids=lambda p: p.name)
def test_the_parallel_executor_caches_a_page_under_myst_nbs_key(source, tmp_path):
    pytest.importorskip("myst_nb")      # the docs extra (make docs)
    from jupyter_cache import get_cache

    cache = get_cache(str(tmp_path / "cache"))
    assert cache.create_hashed_notebook(execute_pages.read(source))[1] == (
        _myst_nb_hash(source, tmp_path))


def test_the_sensitivity_substitutions_are_the_stored_sweep():
    """The sweep in data/ is the whole sweep scripts/sensitivity.py runs, and the prose's
    numbers are its cells, recomputed here from the rows."""
    sweep = load_script("sensitivity")
    rows, found = _csv("sensitivity.csv"), _csv("sensitivity_findings.csv")
    names = [s.name for s in sweep.settings()]
    assert list(dict.fromkeys(rows["setting"])) == list(found["setting"]) == names
    assert len(rows) == len(names) * len(sweep.CASE_NAMES) and (rows["status"] == "ok").all()
    values = generate.substitutions()
    assert values["sweep_pair_settings"] == f"{found['b_combination'].sum()} of {len(names)}"
    case2 = rows[(rows["case"] == 2)].set_index(["setting", "intensity"])["casing_max_y_um"]
    point = case2["casing_support=point"] / case2["casing_support=distributed"]
    assert values["sweep_point_casing"] == f"{point.min():.1f}–{point.max():.1f}"
    late = rows[rows["setting"].isin(["window=4.3", "window=2.3"])].pivot(
        index="cell", columns="setting", values="contact1_max_force_n")
    assert (late["window=4.3"] / late["window=2.3"] - 1).abs().max() <= (
        int(values["sweep_late_window"]) + 0.5) / 100
