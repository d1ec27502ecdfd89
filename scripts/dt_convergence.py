#!/usr/bin/env python
"""Time-step convergence of the Table 2 columns: five start histories per cell at three dt.

Every cell of the study's Table 2 — (case 1, g0 = 2.3 mm light), (1, 1.9 serious),
(2, 2.3), (2, 1.9), :data:`rubdiag.paper._table2.CASES` — runs once per gap-ramp length of the
default start-history ensemble (:data:`rubdiag.paper._ensemble.GAP_RAMPS_S`, 0.1 s ± 2 %) at
each largest step dt = 10, 5 and 2.5 µs (:data:`DTS_S`), with the duration and discard of
:func:`rubdiag.paper._table2.table2` (2.3 s, 0.3 s): 60 runs. The runs are the ones
:func:`rubdiag.paper._ensemble.ensemble` makes (``Run.paper_case(case, gap_mm,
gap_ramp_s=…, dt_s=…)``), so that the 10-µs, 0.1-s one of each cell is the Table 2 run.

**Per-run rows** (``data/dt_convergence_runs.csv``, 6 significant digits): the cell, the gap
ramp and dt; the step statistics (accepted steps, rejected steps, steps shorter than dt);
the Table 2 columns (``casing_max_y_um``, ``contact1_min_force_n``, ``contact1_max_force_n``,
``contact1_sliding_entries``, ``contact1_sticking_entries``, the spectrum features in words and
the numbers behind the study's spectral claims); and the candidate redefinitions of the
columns that move with dt (:data:`QUANTITIES`). Rewritten atomically (temporary file, then
rename) after every run; a rerun skips the runs already stored, so an interrupted study
resumes. Each simulated run is also kept in ``--cache`` (``out/dt_convergence/runs/``, not in
the repository), from which the rows are recomputed without simulating when a row column is
added.

**Summary** (``data/dt_convergence.csv``): per quantity and cell, at each dt, the number of
runs with a value (``n_10us`` …), the median and the range (``min_…``, ``max_…``) over the
five start histories; then ``shift`` = |median(5 µs) − median(2.5 µs)|, ``spread`` = the
smaller of the two ranges (max − min) at 5 and 2.5 µs, and ``verdict`` (:func:`verdict`):
**converged** when shift < spread, or shift = 0 (equal medians); **unconverged** otherwise;
**too few** when either ensemble has fewer than 2 values (a spectral line found in at most
one history). The start-history scatter is the yardstick: a dt effect smaller than the
scatter of either ensemble cannot be told from a different start. ``shift_10us``,
``spread_10us`` and ``verdict_10us`` apply the same rule to 10 µs against 2.5 µs: whether
the number at Table 2's own dt (10 µs) is converged.

Usage::

    python scripts/dt_convergence.py [--jobs 1]   # simulate what data/ lacks, then summarise
    python scripts/dt_convergence.py --table      # print the documentation's table from data/

≈ 10 min on one core (60 runs, ≈ 4, 7 and 17 s each at 10, 5 and 2.5 µs, measured
2026-11-23 with the second core busy); rows recomputed from ``--cache`` in ≈ 2 min.
"""

from __future__ import annotations

import argparse
import inspect
import math
import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np
import pandas as pd

from rubdiag.paper._ensemble import GAP_RAMPS_S
from rubdiag.paper._table2 import CASES, DIGITS, paper_values, table2

ROOT = Path(__file__).resolve().parents[1]
RUNS_CSV = ROOT / "data" / "dt_convergence_runs.csv"
SUMMARY_CSV = ROOT / "data" / "dt_convergence.csv"
CACHE = ROOT / "out" / "dt_convergence" / "runs"

#: Largest time steps (s) compared; the last two decide convergence.
DTS_S = (1e-5, 5e-6, 2.5e-6)
_TABLE2 = inspect.signature(table2).parameters
DURATION_S = _TABLE2["duration_s"].default       # the Table 2 runs' own
DISCARD_S = _TABLE2["discard_s"].default
#: Episode durations (s) of the candidate minimum-force definitions.
MIN_EPISODE_S = (1e-4, 3e-4)

KEY = ["case", "intensity", "gap_mm", "gap_ramp_s", "dt_s"]
CELLS = [(c.case, c.intensity) for c in CASES]


@dataclass(frozen=True)
class Quantity:
    column: str               # per-run column
    text: str                 # what it is, for the table
    group: str                # "table2": a Table 2 column; "spectrum": behind its words;
    #                           "candidate": a redefinition of an unconverged column
    study: str | None = None  # the study's column in paper_table2.csv
    cells: tuple = tuple(CELLS)


_CASE1 = tuple(c for c in CELLS if c[0] == 1)
_CASE2 = tuple(c for c in CELLS if c[0] == 2)

QUANTITIES = (
    Quantity("casing_max_y_um", "casing max y (µm)", "table2", "casing_max_y_um"),
    Quantity("contact1_min_force_n", "contact-1 min force (N), episodes ≥ 2 steps", "table2",
             "contact1_min_force_n"),
    Quantity("contact1_max_force_n", "contact-1 max force (N)", "table2",
             "contact1_max_force_n"),
    Quantity("contact1_sliding_entries", "contact-1 sliding entries (per 2 s)", "table2",
             "contact1_sliding_entries"),
    Quantity("contact1_sticking_entries", "contact-1 sticking entries (per 2 s)", "table2",
             "contact1_sticking_entries"),
    Quantity("contact1_sticking_share", "contact-1 sticking share", "table2"),
    Quantity("shaft_sb_4x_delta_hz", "spectrum: 4× ± Δ sideband spacing Δ (Hz)", "spectrum",
             cells=_CASE1),
    Quantity("shaft_amp_3p5x_um", "spectrum: 7×/2 amplitude (µm, 0 = absent)", "spectrum",
             cells=((1, "serious"),)),
    Quantity("shaft_amp_1p5x_um", "spectrum: 3×/2 amplitude (µm, 0 = absent)", "spectrum",
             cells=((1, "serious"),)),
    Quantity("shaft_combo_fa_hz", "spectrum: combination pair f_a (Hz), f_a + f_b = 2×",
             "spectrum", cells=_CASE2),
    *(Quantity(f"contact1_min_force_{round(d * 1e6)}us_n",
               f"contact-1 min force (N), episodes ≥ {d * 1e6:g} µs", "candidate")
      for d in MIN_EPISODE_S),
    Quantity("contact1_p05_force_n", "contact-1 5th-percentile episode peak (N)", "candidate"),
    Quantity("contact1_sliding_entries_per_contact_s",
             "contact-1 sliding entries per second of contact", "candidate"),
    Quantity("contact1_sticking_entries_per_contact_s",
             "contact-1 sticking entries per second of contact", "candidate"),
)

STEP_COLUMNS = ["status", "n_steps", "n_rejected", "n_steps_below_dt", "wall_s"]
ROW_COLUMNS = [*KEY, *STEP_COLUMNS, *(q.column for q in QUANTITIES), "spectrum_features"]


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- runs

def grid() -> list[dict]:
    """The 60 runs: dt (coarse first), then cell, then gap ramp."""
    return [{"case": c.case, "intensity": c.intensity, "gap_mm": c.gap_mm, "gap_ramp_s": ramp,
             "dt_s": dt} for dt in DTS_S for c in CASES for ramp in GAP_RAMPS_S]


def make_run(key: dict):
    from rubdiag.simulation import Run

    return Run.paper_case(key["case"], key["gap_mm"], gap_ramp_s=key["gap_ramp_s"],
                          dt_s=key["dt_s"], duration_s=DURATION_S, discard_s=DISCARD_S)


def stem(key: dict) -> str:
    return (f"case{key['case']}_{key['intensity']}_ramp{key['gap_ramp_s']:g}"
            f"_dt{key['dt_s'] * 1e6:g}us")


def _entries_rate(entries: float, seconds: float) -> float:
    return entries / seconds if seconds > 0 else math.nan


def row_of(result, key: dict) -> dict:
    """One per-run row (:data:`ROW_COLUMNS`) of a finished run."""
    from rubdiag.paper._describe import describe_spectrum
    from rubdiag.runs import run_features

    feats = run_features(result).iloc[0].to_dict()
    system = result.system
    ep = result.window_episodes()
    one = ep.element == 1
    peaks, durations = ep.peak_normal_force[one], ep.duration[one]
    closed_s = float(ep.slide_time[one].sum() + ep.stick_time[one].sum())
    row = {**key,
           "status": int(system.status),
           "n_steps": int(system.n_steps),
           "n_rejected": int(system.n_rejected_newton + system.n_rejected_abrupt),
           "n_steps_below_dt": int(np.sum(system.steps_per_level[1:])),
           "wall_s": float(result.wall_s),
           "casing_max_y_um": feats["casing_max_y_m"] * 1e6}
    for name in ("min_force_n", "max_force_n", "sliding_entries", "sticking_entries",
                 "sticking_share", "p05_force_n"):
        row[f"contact1_{name}"] = feats[f"contact1_{name}"]
    sb = feats["shaft_sb_4x_delta_hz"]
    row["shaft_sb_4x_delta_hz"] = sb if feats["shaft_sb_4x_lower"] > 0 else math.nan
    row["shaft_amp_3p5x_um"] = feats["shaft_amp_3p5x"] * 1e6
    row["shaft_amp_1p5x_um"] = feats["shaft_amp_1p5x"] * 1e6
    row["shaft_combo_fa_hz"] = (feats["shaft_combo_fa_hz"] if feats["shaft_combo_order"] == 2
                                else math.nan)
    for d in MIN_EPISODE_S:
        lasting = peaks[durations >= d]
        row[f"contact1_min_force_{round(d * 1e6)}us_n"] = (float(lasting.min()) if lasting.size
                                                           else math.nan)
    row["contact1_sliding_entries_per_contact_s"] = _entries_rate(
        feats["contact1_sliding_entries"], closed_s)
    row["contact1_sticking_entries_per_contact_s"] = _entries_rate(
        feats["contact1_sticking_entries"], closed_s)
    row["spectrum_features"] = describe_spectrum(feats)
    return {c: row[c] for c in ROW_COLUMNS}


def _row_worker(key: dict, cache: str | None) -> dict:
    """Worker: the row of one run, from its cached result or a new simulation (then cached)."""
    from rubdiag.simulation import load_result, simulate

    run = make_run(key)
    path = Path(cache) / f"{stem(key)}.npz" if cache else None
    result = None
    if path is not None and path.is_file():
        try:
            result = load_result(path)
        except (ValueError, KeyError, OSError):
            result = None
        if result is not None and (result.run != run or not result.success):
            result = None
    if result is None:
        result = simulate(run)
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            result.save(path)
    return row_of(result, key)


def write_atomic(frame: pd.DataFrame, path: Path) -> None:
    """``frame`` as CSV (floats to :data:`DIGITS` significant digits): a temporary file in
    the same folder, then renamed over ``path``, so that an interrupt never leaves half a
    file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            frame.to_csv(fh, index=False, float_format=f"%.{DIGITS}g", lineterminator="\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _key_tuple(row) -> tuple:
    return (int(row["case"]), str(row["intensity"]), float(row["gap_ramp_s"]),
            float(row["dt_s"]))


def read_rows(path: Path = RUNS_CSV) -> pd.DataFrame:
    return pd.read_csv(path) if path.is_file() else pd.DataFrame(columns=ROW_COLUMNS)


def _sorted(rows: pd.DataFrame) -> pd.DataFrame:
    order = {_key_tuple(k): i for i, k in enumerate(grid())}
    index = sorted(range(len(rows)), key=lambda i: order.get(_key_tuple(rows.iloc[i]), 10**6))
    return rows.iloc[index].reset_index(drop=True)[ROW_COLUMNS]


def collect(jobs: int = 1, path: Path = RUNS_CSV, cache: Path | None = CACHE) -> pd.DataFrame:
    """Run (or reuse) every run of :func:`grid` not stored in ``path``; returns all rows."""
    stored = read_rows(path)
    if any(c not in stored.columns for c in ROW_COLUMNS):
        log(f"{path.name} lacks columns of this script: recomputing every row")
        stored = pd.DataFrame(columns=ROW_COLUMNS)
    done = {_key_tuple(r) for r in stored.to_dict("records")}
    todo = [k for k in grid() if _key_tuple(k) not in done]
    rows = stored.to_dict("records")
    if not todo:
        return _sorted(pd.DataFrame(rows))
    log(f"{len(todo)} run(s) to do on {jobs} process(es), {len(done)} stored in {path}")
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(_row_worker, k, str(cache) if cache else None): k
                   for k in todo}
        try:
            for n, future in enumerate(as_completed(futures), start=1):
                row = future.result()
                rows.append(row)
                write_atomic(_sorted(pd.DataFrame(rows)), path)
                log(f"{stem(futures[future])}: {row['n_steps']} steps, {row['n_rejected']} "
                    f"rejected ({n}/{len(todo)}, {time.perf_counter() - start:.0f} s)")
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
    return _sorted(pd.DataFrame(rows))


# --------------------------------------------------------------------------- summary

def _dt_tag(dt_s: float) -> str:
    """1e-5 -> '10us', 2.5e-6 -> '2p5us'."""
    return f"{dt_s * 1e6:g}".replace(".", "p") + "us"


def verdict(shift: float, spread: float, n_a: int, n_b: int) -> str:
    """The rule for two ensembles a, b (``n_a``, ``n_b`` values): ``converged`` when their
    medians differ (``shift``) by less than the smaller of their two ranges (``spread``) or
    not at all, ``too few`` when either has fewer than 2 values, else ``unconverged``."""
    if n_a < 2 or n_b < 2:
        return "too few"
    return "converged" if shift < spread or shift == 0 else "unconverged"


def _stored(x: float) -> float:
    """``x`` as the CSV stores it (:data:`DIGITS` significant digits)."""
    return float(f"{x:.{DIGITS}g}")


def _study(quantity: Quantity, case: int, intensity: str):
    if quantity.study is None:
        return math.nan
    paper = paper_values().set_index(["case", "intensity"])
    return float(paper.loc[(case, intensity), quantity.study])


def summarise(rows: pd.DataFrame) -> pd.DataFrame:
    """The summary table (one row per quantity and cell) of the per-run rows."""
    out = []
    for q in QUANTITIES:
        for case, intensity in q.cells:
            cell = rows[(rows["case"] == case) & (rows["intensity"] == intensity)]
            rec = {"quantity": q.column, "group": q.group, "case": case,
                   "intensity": intensity, "study": _study(q, case, intensity)}
            for dt in DTS_S:
                values = cell.loc[np.isclose(cell["dt_s"], dt), q.column].astype(float)
                values = values[np.isfinite(values)]
                tag = _dt_tag(dt)
                rec[f"n_{tag}"] = int(values.size)
                # rounded as stored, so that the verdict follows from the stored numbers
                rec[f"median_{tag}"] = _stored(values.median()) if values.size else math.nan
                rec[f"min_{tag}"] = _stored(values.min()) if values.size else math.nan
                rec[f"max_{tag}"] = _stored(values.max()) if values.size else math.nan
            finest = _dt_tag(DTS_S[-1])
            for suffix, tag in (("", _dt_tag(DTS_S[-2])), (f"_{_dt_tag(DTS_S[0])}",
                                                           _dt_tag(DTS_S[0]))):
                rec[f"shift{suffix}"] = abs(rec[f"median_{tag}"] - rec[f"median_{finest}"])
                rec[f"spread{suffix}"] = min(rec[f"max_{tag}"] - rec[f"min_{tag}"],
                                             rec[f"max_{finest}"] - rec[f"min_{finest}"])
                rec[f"verdict{suffix}"] = verdict(rec[f"shift{suffix}"], rec[f"spread{suffix}"],
                                                  rec[f"n_{tag}"], rec[f"n_{finest}"])
            out.append(rec)
    return pd.DataFrame(out)


def read_summary(path: Path = SUMMARY_CSV) -> pd.DataFrame:
    return pd.read_csv(path)


# --------------------------------------------------------------------------- table

def _fmt(x: float) -> str:
    if not math.isfinite(x):
        return "—"
    if x == round(x) and abs(x) < 1e6:
        return f"{x:.0f}"
    if abs(x) >= 100:
        return f"{x:.0f}"
    return f"{x:.3g}"


_TEXT = {q.column: q.text for q in QUANTITIES}
_GROUP_TITLE = {"table2": "Table 2 columns", "spectrum": "Numbers behind the spectrum words",
                "candidate": "Candidate definitions for the columns that move with dt"}


def to_markdown(summary: pd.DataFrame) -> str:
    """The documentation's table, from the stored summary alone."""
    tags = [_dt_tag(dt) for dt in DTS_S]
    coarse = f"{DTS_S[0] * 1e6:g} µs"
    fine, finest = (f"{dt * 1e6:g}" for dt in DTS_S[-2:])
    header = ("| quantity | cell | study | median at " + " / ".join(f"{dt * 1e6:g}"
                                                                for dt in DTS_S)
              + " µs | range (min–max) at " + " ; ".join(f"{dt * 1e6:g}" for dt in DTS_S)
              + f" µs | shift / spread, {fine} vs {finest} µs | verdict | at {coarse} "
              "(Table 2's dt) |\n|---|---|---|---|---|---|---|---|\n")
    marks = {"converged": "converged", "unconverged": "**unconverged**",
             "too few": "too few values"}
    lines = []
    for group in ("table2", "spectrum", "candidate"):
        part = summary[summary["group"] == group]
        if part.empty:
            continue
        lines.append(f"| *{_GROUP_TITLE[group]}* | | | | | | | |")
        previous = None
        for r in part.to_dict("records"):
            name = _TEXT.get(r["quantity"], r["quantity"]) if r["quantity"] != previous else ""
            previous = r["quantity"]
            counts = ""
            if any(r[f"n_{t}"] < 5 for t in tags):
                counts = " (in " + " / ".join(str(int(r[f"n_{t}"])) for t in tags) + " of 5)"
            medians = " / ".join(_fmt(r[f"median_{t}"]) for t in tags) + counts
            ranges = " ; ".join(f"{_fmt(r[f'min_{t}'])}–{_fmt(r[f'max_{t}'])}"
                                if r[f"n_{t}"] else "—" for t in tags)
            lines.append(f"| {name} | {r['case']} {r['intensity']} | {_fmt(r['study'])} | "
                         f"{medians} | {ranges} | {_fmt(r['shift'])} / {_fmt(r['spread'])} | "
                         f"{marks[r['verdict']]} | {marks[r[f'verdict_{tags[0]}']]} |")
    note = (f"\nFive start histories (gap ramp {GAP_RAMPS_S[0]:g} … {GAP_RAMPS_S[-1]:g} s) per "
            f"cell and dt; {DURATION_S:g} s simulated, the first {DISCARD_S:g} s discarded. "
            f"Verdict: converged when |median at {fine} µs − median at {finest} µs| (shift) "
            "< the smaller of the two ranges (spread), or the medians are equal. The last "
            f"column applies the same rule to {coarse} against {finest} µs. Spectral "
            "numbers are over the histories where the line is found (counts given when fewer "
            "than 5).\n")
    return header + "\n".join(lines) + "\n" + note


def step_statistics(rows: pd.DataFrame) -> str:
    """One line: the step counts of the stored runs (does the variable step engage?)."""
    parts = []
    for dt in DTS_S:
        at = rows[np.isclose(rows["dt_s"], dt)]
        parts.append(f"dt = {dt * 1e6:g} µs: {len(at)} runs, {int(at['n_steps'].min())}–"
                     f"{int(at['n_steps'].max())} steps, {int(at['n_rejected'].sum())} "
                     f"rejected, {int(at['n_steps_below_dt'].sum())} shorter than dt, "
                     f"{at['wall_s'].sum() / 60:.1f} min")
    return "; ".join(parts)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=1, help="processes (default 1)")
    parser.add_argument("--table", action="store_true",
                        help="print the documentation's table from the stored summary and stop")
    parser.add_argument("--cache", default=str(CACHE),
                        help="folder of the simulated runs ('' keeps none)")
    args = parser.parse_args(argv)
    if args.table:
        sys.stdout.write(to_markdown(read_summary()))
        return 0
    rows = collect(args.jobs, RUNS_CSV, Path(args.cache) if args.cache else None)
    if rows["status"].ne(0).any():
        log("some runs did not finish: the summary leaves them out")
    summary = summarise(rows[rows["status"] == 0])
    write_atomic(summary, SUMMARY_CSV)
    log(step_statistics(rows))
    sys.stdout.write(to_markdown(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
