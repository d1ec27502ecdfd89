"""Reproduce the study's Table 2: four rub cases, their features, beside the study's values.

Case 1 runs at the first forward critical speed with the unbalances in phase, case 2 at the
second with them out of phase; each with g0 = 2.3 mm (light) and 1.9 mm (serious). The runs
go to parallel processes; each finished run is saved as ``DIR/runs/case{c}_{intensity}.npz``
before the next is waited for, so an interrupted reproduction resumes where it stopped (a
saved run is reused when its description equals the one asked for).

With ``reduction=Reduction(...)`` the four runs simulate the reduced-order model; their
files are ``DIR/runs/case{c}_{intensity}_reduced_{cutoff}hz.npz``, so a reduced and a full
reproduction into the same folder never take or overwrite each other's runs. The table's
``model`` column says which model made it ("full" or "reduced"), and a last line of the
Markdown table names the reduction (the full model's Markdown is as it always was).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import pandas as pd

from rubdiag import _progress
from rubdiag.paper._describe import describe_spectrum

__all__ = ["CASES", "PaperCase", "paper_values", "reproduce", "table2"]


@dataclass(frozen=True)
class PaperCase:
    """One of the study's four rub cases (:data:`CASES`).

    Parameters
    ----------
    case : {1, 2}
        The unbalance case: 1 in phase, at the first critical speed; 2 out of phase, at the
        second.
    intensity : {"light", "serious"}
        The rub's name in the study.
    gap_mm : float
        Blade-tip/casing gap (mm).
    """

    case: int
    intensity: str
    gap_mm: float

    @property
    def stem(self) -> str:
        return f"case{self.case}_{self.intensity}"


CASES = (PaperCase(1, "light", 2.3), PaperCase(1, "serious", 1.9),
         PaperCase(2, "light", 2.3), PaperCase(2, "serious", 1.9))

# our column -> the study's column in paper_table2.csv
_PAPER_COLUMNS = {
    "casing_max_y_um": "casing_max_y_um",
    "contact1_min_force_n": "contact1_min_force_n",
    "contact1_max_force_n": "contact1_max_force_n",
    "contact1_sliding_entries": "contact1_sliding_entries",
    "contact1_sticking_entries": "contact1_sticking_entries",
    "shaft_blade_spectrum_features": "shaft_blade_spectrum_features",
}


def paper_values() -> pd.DataFrame:
    """The study's Table 2 (package data, identical to ``data/paper_table2.csv``).

    Returns
    -------
    pandas.DataFrame
        One row per case: its gap and speed, and the study's casing displacement, spectrum
        features and contact forces and status entries.
    """
    with resources.files("rubdiag.paper").joinpath("paper_table2.csv").open("r") as fh:
        return pd.read_csv(fh)


def _runs(rig, duration_s: float, discard_s: float, **options):
    from rubdiag.simulation import Run

    return {c.stem: Run.paper_case(c.case, c.gap_mm, rig=rig, duration_s=duration_s,
                                   discard_s=discard_s,
                                   label=f"case {c.case} {c.intensity} (g0 = {c.gap_mm} mm)",
                                   **options) for c in CASES}


def _simulate_to(run, path: str) -> tuple[str, float]:
    """Worker: simulate and save (atomically); returns the path and the wall time."""
    from rubdiag.simulation import simulate

    start = time.perf_counter()
    simulate(run).save(path)
    return path, time.perf_counter() - start


def run_file(stem: str, run) -> str:
    """The file name of a case's saved run: ``case1_light.npz`` for the full model,
    ``case1_light_reduced_2000hz.npz`` for a reduction with a 2-kHz cutoff."""
    if run.reduction is None:
        return f"{stem}.npz"
    return f"{stem}_reduced_{run.reduction.cutoff_hz:g}hz.npz"


def _cached(path: Path, run):
    from rubdiag.simulation import load_result

    if not path.is_file():
        return None
    try:
        result = load_result(path)
    except (ValueError, KeyError, OSError):
        return None
    return result if result.success and result.run == run else None


def reproduce(out_dir: str | Path = "out", jobs: int | None = None, duration_s: float = 2.3,
              discard_s: float = 0.3, rig=None, log: Callable[[str], None] | None = None,
              progress=False, **options) -> dict:
    """Run (or reuse) the four cases; returns ``{stem: SimulationResult}``.

    ``options`` go to :class:`~rubdiag.simulation.Run` (``dt_s``, ``contact``,
    ``reduction`` …); the saved runs are named by :func:`run_file`. ``log`` gets a line
    per case reused or finished (default: stderr, above the bar); ``progress``: a bar over
    the cases to simulate, counted as they finish, on stderr when it is a terminal (or an
    open bar of :mod:`rubdiag._progress` to count them on).

    Parameters
    ----------
    out_dir : str or Path
        Folder of the saved runs (``runs/``) and tables.
    jobs : int or None
        Parallel processes; None: every core.
    duration_s : float
        Simulated time of each case (s).
    discard_s : float
        Start of each run left out of the statistics (s).
    rig : Rig or None
        The rig; None: the study's.
    log : callable or None
        Called with one line per case reused or finished.
    progress : bool or bar
        Show a bar on stderr, or count on an open bar.
    **options
        :class:`~rubdiag.simulation.Run` fields.

    Returns
    -------
    dict of str to SimulationResult
        The four runs by stem (``case1_light`` …).
    """
    from rubdiag.model import paper_rig

    log = log or _progress.write
    rig = paper_rig() if rig is None else rig
    runs = _runs(rig, duration_s, discard_s, **options)
    run_dir = Path(out_dir) / "runs"
    run_dir.mkdir(parents=True, exist_ok=True)
    results, todo = {}, {}
    for stem, run in runs.items():
        cached = _cached(run_dir / run_file(stem, run), run)
        if cached is not None:
            results[stem] = cached
            log(f"{stem}: reused {run_dir / run_file(stem, run)}")
        else:
            todo[stem] = run
    if todo:
        jobs = min(len(todo), jobs or os.cpu_count() or 1)
        log(f"simulating {len(todo)} case(s), {duration_s:g} s simulated each, on {jobs} "
            "process(es)")
        start = time.perf_counter()
        with ProcessPoolExecutor(max_workers=jobs) as pool, \
                _progress.shared(progress, len(todo), "table2", "case") as bar:
            futures = {pool.submit(_simulate_to, run, str(run_dir / run_file(stem, run))): stem
                       for stem, run in todo.items()}
            try:
                for done, future in enumerate(as_completed(futures), start=1):
                    stem = futures[future]
                    path, wall = future.result()
                    results[stem] = _cached(Path(path), runs[stem])
                    bar.update()
                    log(f"{stem}: done in {wall:.1f} s ({done}/{len(todo)}, "
                        f"{time.perf_counter() - start:.0f} s elapsed)")
            except BaseException:
                pool.shutdown(wait=False, cancel_futures=True)
                raise
    return {c.stem: results[c.stem] for c in CASES}


def table2(out_dir: str | Path | None = "out", jobs: int | None = None,
           duration_s: float = 2.3, discard_s: float = 0.3, figures: bool = True,
           log=None, progress=False, **options) -> pd.DataFrame:
    """Reproduce the study's Table 2: run (or reuse) the four cases and tabulate them beside
    the study's values.

    Writes ``table2.csv``, ``table2.md`` and ``features.csv`` to ``out_dir`` and, with
    ``figures``, the figures (Figs. 5-10 of the study); the runs are saved in (and reused
    from) ``out_dir/runs`` (:func:`reproduce`).

    Parameters
    ----------
    out_dir : str or Path or None
        Folder of the tables, figures and ``runs/``; None: ``"out"``.
    jobs : int or None
        Parallel processes for the runs and the figures; None: every core.
    duration_s : float
        Simulated time of each case (s).
    discard_s : float
        Start of each run left out of the statistics (s).
    figures : bool
        Also draw and write the figures.
    log : callable or None
        Called with one line per case reused or finished; None: stderr.
    progress : bool or bar
        A bar on stderr over the cases, then over the figures, when stderr is a terminal;
        or an open bar of :mod:`rubdiag._progress` to count on.
    **options
        Passed on to :func:`reproduce`: its ``rig``, and :class:`~rubdiag.simulation.Run`
        fields (``dt_s``, ``contact``, ``reduction=Reduction()`` for the reduced-order
        model: module docstring).

    Returns
    -------
    pandas.DataFrame
        One row per case, ours beside the study's. Columns: ``case``, ``intensity``,
        ``gap_mm``, ``speed_rpm``, ``discard_s``, ``window_s``, ``dt_s``, ``model``
        ("full" or "reduced"), ``rotor_max_y_mm`` (shaft node 11), ``casing_max_y_um``,
        ``contact1_min_force_n`` (smallest per-episode peak, episodes of >= 2 steps),
        ``contact1_p05_force_n``, ``contact1_max_force_n``, ``contact1_sliding_entries`` /
        ``…_sticking_entries`` (in the window) and their ``…_per_s``,
        ``contact1_sticking_share`` (sticking / closed time),
        ``contact1_mean_force_sliding_n`` / ``…_sticking_n``,
        ``shaft_blade_spectrum_features`` (written from the detected features), then the
        study's ``paper_…``. ``attrs["features"]`` holds the runs' feature rows,
        ``attrs["results"]`` the runs by stem.

    See Also
    --------
    reproduce : The four runs alone.
    paper_values : The study's Table 2.
    """
    from rubdiag.runs import run_features

    out = Path(out_dir if out_dir is not None else "out")
    results = reproduce(out, jobs=jobs, duration_s=duration_s, discard_s=discard_s, log=log,
                        progress=progress, **options)
    feats = run_features([results[c.stem] for c in CASES])
    feats.insert(0, "case", [c.case for c in CASES])
    feats.insert(1, "intensity", [c.intensity for c in CASES])
    table = pd.DataFrame({
        "case": feats["case"],
        "intensity": feats["intensity"],
        "gap_mm": [c.gap_mm for c in CASES],
        "speed_rpm": feats["speed_rpm"].round(1),
        "discard_s": discard_s,
        "window_s": feats["window_s"],
        "dt_s": feats["dt_s"],
        "model": [results[c.stem].run.model_kind for c in CASES],
        "rotor_max_y_mm": [results[c.stem].displacement("shaft 11 y", True).max() * 1e3
                           for c in CASES],
        "casing_max_y_um": feats["casing_max_y_m"] * 1e6,
    })
    for key in ("min_force_n", "p05_force_n", "max_force_n", "sliding_entries",
                "sticking_entries", "sliding_entries_per_s", "sticking_entries_per_s",
                "sticking_share", "mean_force_sliding_n", "mean_force_sticking_n"):
        table[f"contact1_{key}"] = feats[f"contact1_{key}"]
    table["shaft_blade_spectrum_features"] = [describe_spectrum(r) for r in
                                              feats.to_dict("records")]
    paper = paper_values().set_index(["case", "intensity"])
    for ours, theirs in _PAPER_COLUMNS.items():
        table[f"paper_{ours}"] = [paper.loc[(c.case, c.intensity), theirs] for c in CASES]
    _write(table, feats, out, results[CASES[0].stem].run.reduction)
    if figures:
        from rubdiag.paper._figures import write_figures

        write_figures(results, feats, out, jobs=jobs, progress=progress)
    # attached last: pandas deep-copies attrs in every operation (0.9 s in _write with them)
    table.attrs["features"] = feats
    table.attrs["results"] = results
    return table


#: Significant digits of the floats in ``table2.csv`` and ``features.csv``: more than any
#: quantity here is meaningful to (the study gives 2-4; a line's frequency is known to far
#: less than 1e-6 of itself), and far fewer than float noise needs (0.5000000000000001).
DIGITS = 6


def write_csv(frame: pd.DataFrame, path: Path, digits: int = DIGITS) -> None:
    """Write ``frame`` with floats to ``digits`` significant digits, so that no float noise
    reaches the file: a 2-s window is ``2``, not ``2.0000000000000004``, and 38 entries in
    it are ``19`` per second, not ``18.999999999999996``."""
    frame.to_csv(path, index=False, float_format=f"%.{digits}g")


def _write(table: pd.DataFrame, feats: pd.DataFrame, out: Path, reduction=None) -> None:
    out.mkdir(parents=True, exist_ok=True)
    write_csv(table, out / "table2.csv", DIGITS)
    write_csv(feats, out / "features.csv", DIGITS)
    (out / "table2.md").write_text(to_markdown(table, reduction), encoding="utf-8")


def to_markdown(table: pd.DataFrame, reduction=None) -> str:
    """Table 2 as Markdown: ours | the study's, cell by cell; with ``reduction`` (the runs'
    :class:`~rubdiag.reduce.Reduction`) a last line says the reduced model made it."""
    header = ("| case | g0 (mm) | speed (rpm) | casing max y (µm) | contact-1 min / max force "
              "(N) | contact-1 sliding / sticking entries | sticking share | spectrum "
              "features (shaft 11, blade tip) |\n|---|---|---|---|---|---|---|---|\n")
    lines = []
    for r in table.itertuples():
        lines.append(
            f"| {r.case} {r.intensity} | {r.gap_mm} | {r.speed_rpm:.0f} | "
            f"**{r.casing_max_y_um:.0f}** / {r.paper_casing_max_y_um:g} | "
            f"**{r.contact1_min_force_n:.1f} / {r.contact1_max_force_n:.1f}** / "
            f"{r.paper_contact1_min_force_n:g} / {r.paper_contact1_max_force_n:g} | "
            f"**{r.contact1_sliding_entries} / {r.contact1_sticking_entries}** / "
            f"{r.paper_contact1_sliding_entries} / {r.paper_contact1_sticking_entries} | "
            f"{r.contact1_sticking_share:.2f} | **{r.shaft_blade_spectrum_features}** / "
            f"{r.paper_shaft_blade_spectrum_features} |")
    first = table.iloc[0]
    note = (f"\nOurs in **bold**, then the study's. Statistics over {first.window_s:g} s after "
            f"discarding the first {first.discard_s:g} s; dt = {first.dt_s:g} s (the variable "
            "step may halve it; on the paper rig it never does). Minimum force: smallest "
            "per-episode peak over episodes of at least 2 steps (not converged in dt: see "
            "the documentation, Time-step convergence).\n")
    if reduction is not None:
        note += (f"\nModel: reduced (Craig-Bampton, fixed-interface modes below "
                 f"{reduction.cutoff_hz:g} Hz); the study's values are from its full model.\n")
    return header + "\n".join(lines) + "\n" + note
