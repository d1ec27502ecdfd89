#!/usr/bin/env python
"""The documentation's "Steps sized by error" table: what long steps change in a dataset's rows,
against the scatter between start histories.

Two small ensembles, each made twice — at 10 µs (``step_error = 0``) and with long steps
at a tolerance — with three start histories (replicates: gap ramps of 0.1 s ∓ 1 %) per
design point and the default measurement noise (a run and its twin at 10 µs are measured
with the same noise draw: :func:`rubdiag.dataset._ids.noise_id`):

* ``rub``: the paper rig, reduced model, both cases, 0.8–1.2 of the critical speed, gaps
  0.5–4 mm, μ 0.1–0.5 (LHS, 16 points): runs without rub, light and serious rub;
* ``faults``: ``data/designs/faults_small.toml`` (crack, misalignment, looseness, each
  alone and with rub, healthy; reduced model, gravity), 16 points;
* ``journal``: ``data/designs/faults_journal.toml`` (the rig on plain journal bearings:
  oil whirl and whip beside the other faults and rub, the model-uncertainty factors), 20
  points (two per fault level).

For every stored numeric quantity (features, pair features, contact statistics, measures)
the **change** is the median over runs of |value with long steps − value at 10 µs| and the
**scatter** the median over design points of the standard deviation over the three start
histories at 10 µs; quantities without scatter (runs that never touch: their start
history does not matter) are held to a **floor** of 0.1 % of their median magnitude. The
table gives, per family of quantities, the share of quantities whose change is below a
quarter of max(scatter, floor), the 95th percentile and the largest ratio, and the labels'
agreement.

    python scripts/step_study.py --out step-study         # both ensembles, both settings
    python scripts/step_study.py --out step-study --table # the documentation's table, from the CSV

``data/step_study.csv`` holds the table (one row per ensemble, tolerance and family);
``tests/dataset/test_step_study.py`` checks the goal against it.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "data" / "step_study.csv"
FAULTS = ROOT / "data" / "designs" / "faults_small.toml"
JOURNAL = ROOT / "data" / "designs" / "faults_journal.toml"
REPLICATES = 3
POINTS = 16
JOURNAL_POINTS = 20
#: a quantity's change counts against max(scatter, FLOOR × its median magnitude)
FLOOR = 1e-3
#: the goal: every change below this share of the scatter (or the floor)
GOAL = 0.25
NOT_QUANTITIES = {"run_id", "point_id", "replicate", "speed_rpm", "model", "rubdiag_version",
                  "status", "message", "wall_s", "simulate_s"}
LABELS = ("rub", "rub_state", "severity", "faults")

RUB = f"""
[base]
rig = "paper"
duration_s = 2.3
discard_s = 0.3
reduced = true

[sampling]
method = "lhs"
n = {POINTS}
seed = 29
replicates = {REPLICATES}

[factors]
case = [1, 2]
speed_ratio = {{low = 0.8, high = 1.2}}
gap_mm = {{low = 0.5, high = 4.0}}
mu = {{low = 0.1, high = 0.5}}
"""


ENSEMBLES = ("rub", "faults", "journal")


def designs(step_error: float, names=ENSEMBLES) -> dict:
    """The ensembles' designs (those named), with long steps at ``step_error`` (0: none)."""
    import tomllib

    from rubdiag.dataset import Design

    rub = Design.from_dict(tomllib.loads(RUB))
    faults = Design.from_toml(FAULTS)
    faults = dataclasses.replace(faults, n=POINTS, replicates=REPLICATES)
    journal = Design.from_toml(JOURNAL)
    journal = dataclasses.replace(journal, n=JOURNAL_POINTS, replicates=REPLICATES)
    return {name: dataclasses.replace(d, step_error=step_error)
            for name, d in (("rub", rub), ("faults", faults), ("journal", journal))
            if name in names}


def generate(out: Path, step_error: float, jobs: int,
             names=ENSEMBLES) -> dict[str, pd.DataFrame]:
    """The ensembles named at ``step_error`` into ``out`` (resumed if there), their rows."""
    from rubdiag.dataset import generate as make
    from rubdiag.dataset import load

    rows = {}
    for name, design in designs(step_error, names).items():
        folder = out / f"{name}-{step_error:g}"
        start = time.perf_counter()
        make(design, folder, jobs=jobs, progress=False)
        print(f"{folder}: {time.perf_counter() - start:.1f} s", file=sys.stderr)
        rows[name] = load(folder)
    return rows


def family(column: str) -> str:
    """The family of a stored quantity, by its channel and feature name."""
    channel, _, feature = column.partition("__")
    if not feature or channel == "truth":
        return "measures"
    if channel.startswith("contact"):
        return "contact statistics"
    if "_yz_" in channel:
        return "full spectrum and orbit"
    if feature.startswith("sb_") or feature.startswith("bb_"):
        return "sidebands"
    if feature.startswith("comb"):
        return "combinations"
    if "amp_" in feature or "freq_" in feature or feature.startswith("dev_"):
        return "order lines"
    return "levels and counts"


def keyed(rows: pd.DataFrame) -> pd.DataFrame:
    """``rows`` indexed by design point and replicate: the point by its factors' values
    (its ``point_id`` hashes the run, which the step setting is part of)."""
    factors = sorted(_factors(rows))
    point = rows[factors].apply(lambda c: c.map(repr)).agg("|".join, axis=1)
    return rows.assign(point=point).set_index(["point", "replicate"]).sort_index()


def compare(base: pd.DataFrame, long: pd.DataFrame) -> pd.DataFrame:
    """Per quantity: its family, change, scatter, floor and ratio (see the module
    docstring). Rows are matched by design point and replicate."""
    base = keyed(base[base["status"] == "ok"])
    long = keyed(long[long["status"] == "ok"])
    both = base.index.intersection(long.index)
    base, long = base.loc[both], long.loc[both]
    out = []
    for column in base.columns:
        if column in NOT_QUANTITIES or column in LABELS or column not in long:
            continue
        if not pd.api.types.is_numeric_dtype(base[column]):
            continue
        if column in _factors(base):
            continue
        b = base[column].to_numpy(float)
        x = long[column].to_numpy(float)
        seen = np.isfinite(b) & np.isfinite(x)
        if not seen.any():
            continue
        angle = "phase" in column and column.endswith("_deg")
        change = float(np.median(np.abs(_difference(x[seen], b[seen], angle))))
        spread = _scatter(base[column], angle)
        scatter = float(np.nanmedian(spread.to_numpy(float))) if spread.notna().any() else 0.0
        floor = FLOOR * float(np.median(np.abs(b[seen])))
        bound = max(scatter, floor)
        ratio = change / bound if bound > 0 else (0.0 if change == 0 else np.inf)
        out.append({"quantity": column, "family": family(column), "change": change,
                    "scatter": scatter, "floor": floor, "ratio": ratio,
                    "nan_differs": int(np.sum(np.isfinite(b) != np.isfinite(x)))})
    return pd.DataFrame(out)


def _difference(x, y, angle: bool):
    """``x - y``; for angles in degrees wrapped into [-180, 180)."""
    d = np.asarray(x, float) - np.asarray(y, float)
    return (d + 180.0) % 360.0 - 180.0 if angle else d


def _scatter(values: pd.Series, angle: bool) -> pd.Series:
    """Per design point, the standard deviation over its start histories (for angles, of
    each one's wrapped difference to the first)."""
    if not angle:
        return values.groupby(level="point").std(ddof=1)
    first = values.groupby(level="point").transform("first")
    wrapped = pd.Series(_difference(values, first, True), index=values.index)
    return wrapped.groupby(level="point").std(ddof=1)


def _factors(rows: pd.DataFrame) -> set[str]:
    from rubdiag.dataset._factors import FACTORS

    return set(FACTORS) & set(rows.columns)


def agreement(base: pd.DataFrame, long: pd.DataFrame) -> str:
    """How many runs have the same labels in both settings, of how many."""
    b = keyed(base)
    x = keyed(long).loc[b.index]
    labels = [c for c in LABELS if c in b]
    same = (b[labels].astype(str) == x[labels].astype(str)).all(axis=1)
    return f"{int(same.sum())}/{len(same)}"


def table(base: dict, long: dict, step_error: float) -> pd.DataFrame:
    """The CSV's rows for one tolerance: per ensemble and family."""
    rows = []
    for name in base:
        q = compare(base[name], long[name])
        steps = _steps(base[name], long[name])
        for fam, g in q.groupby("family"):
            rows.append({"ensemble": name, "step_error": step_error, "family": fam,
                         "quantities": len(g),
                         "below_goal": int((g["ratio"] <= GOAL).sum()),
                         "ratio_p95": float(np.percentile(g["ratio"], 95)),
                         "ratio_max": float(g["ratio"].max()),
                         "worst": g.loc[g["ratio"].idxmax(), "quantity"],
                         "labels_same": agreement(base[name], long[name]),
                         "simulate_s_ratio": steps})
    return pd.DataFrame(rows)


def _steps(base: pd.DataFrame, long: pd.DataFrame) -> float:
    """Median over runs of the simulate time with long steps over that at 10 µs."""
    b = keyed(base)["simulate_s"]
    x = keyed(long)["simulate_s"].loc[b.index]
    return float(np.median(x.to_numpy() / b.to_numpy()))


def markdown(frame: pd.DataFrame) -> str:
    """The documentation's table (Markdown)."""
    lines = ["| ensemble | step_error | family | quantities | change < ¼ scatter | "
             "95th pct. change / scatter | largest (quantity) | same labels | simulate time |",
             "|---|---:|---|---:|---:|---:|---|---:|---:|"]
    for r in frame.itertuples():
        lines.append(f"| {r.ensemble} | {r.step_error:g} | {r.family} | {r.quantities} | "
                     f"{r.below_goal} | {r.ratio_p95:.3f} | {r.ratio_max:.2f} "
                     f"(`{r.worst}`) | {r.labels_same} | {r.simulate_s_ratio:.2f}× |")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("step-study"),
                   help="folder of the generated ensembles (resumed)")
    p.add_argument("--step-error", type=float, nargs="+", default=None,
                   help="tolerances to compare with 10 µs (default: the designs' default)")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--ensembles", nargs="+", choices=ENSEMBLES, default=list(ENSEMBLES),
                   help="make these ensembles again and replace their rows of the CSV "
                   "(default: all)")
    p.add_argument("--table", action="store_true",
                   help="print the documentation's table from the CSV")
    args = p.parse_args(argv)
    if args.table:
        print(markdown(pd.read_csv(CSV)))
        return 0
    from rubdiag.dataset._design import DEFAULT_STEP_ERROR

    tolerances = args.step_error or [DEFAULT_STEP_ERROR]
    base = generate(args.out, 0.0, args.jobs, args.ensembles)
    frames = [table(base, generate(args.out, tol, args.jobs, args.ensembles), tol)
              for tol in tolerances]
    if CSV.exists():     # the rows of other ensembles and tolerances stay
        kept = pd.read_csv(CSV)
        frames.insert(0, kept[~(kept["ensemble"].isin(args.ensembles)
                                & kept["step_error"].isin(tolerances))])
    frame = pd.concat(frames, ignore_index=True)
    order = {name: k for k, name in enumerate(ENSEMBLES)}
    frame = frame.sort_values(["step_error", "ensemble"], key=lambda c: c.map(order)
                              if c.name == "ensemble" else c, kind="stable")
    frame.to_csv(CSV, index=False, float_format="%.6g")
    print(markdown(frame))
    return 0


if __name__ == "__main__":
    sys.exit(main())
