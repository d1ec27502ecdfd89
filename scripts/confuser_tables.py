#!/usr/bin/env python
"""The tables of "Telling rub from its confusers", on the dataset of a shipped multi-fault
design (fixed seeds: the same rows on any machine).

    rubdiag dataset data/designs/faults_journal.toml --out faults-data --jobs 2
    python scripts/confuser_tables.py faults-data   # -> data/confuser_*.csv, data/one_vs_one.csv
    python scripts/confuser_tables.py --table       # the documentation's tables, from the CSVs

    rubdiag dataset data/designs/faults_bands_slice.toml --out bands-slice --jobs 2
    python scripts/confuser_tables.py bands-slice --design faults_bands
                                      # -> data/bands_confuser_*.csv, data/bands_one_vs_one.csv

    rubdiag dataset data/designs/rub_kinds.toml --out rub-kinds --jobs 2
    python scripts/confuser_tables.py rub-kinds --design rub_kinds
                                      # -> data/rub_kinds_*.csv

``--design`` names the design whose tables are made (:data:`OUTPUTS`): ``faults_journal``
(the default, whose tables the documentation shows first), ``faults_bands`` (every level in the same
speed bands; ``tests/learn/test_bands_confuser_tables.py`` checks its goals) or
``rub_kinds`` (blade and seal rubs, blade counts 8-20, beside the same confusers; its
extra cell holds out one blade count at a time, :data:`EXTRA_CELLS`, and its rates give
the rub recall of each kind; ``tests/learn/test_rub_kinds_tables.py``).

**Goals** (:data:`CELLS`): :func:`rubdiag.learn._evaluate` with the forest on the shaft
probes only (``channels="shaft"``: every probe but the casing's) and the order families
plus the probe pairs' full spectrum and orbit (:data:`FAMILIES`), held out by design point
(``group``), by speed band (``speed_ratio``, 5 quantile bands of design points) and by each
model-uncertainty factor (one level held out at a time), for the targets ``rub`` (rub
against everything else) and ``fault`` (the ``faults`` label). Per cell: macro-F1 with its
95 % interval over design points, the best baseline, the shuffled-label control, the runs
left unscored (their class absent from a training fold) — into
``data/confuser_cells.csv`` — and the false rub alarm per confuser and the rub recall
beside each — into ``data/confuser_rates.csv``. :data:`GOALS` are what the issue set.

**One against one** (:func:`one_vs_one`): for rub against each confuser and each pair of
confusers (runs whose ``faults`` label is exactly the one fault), the held-out macro-F1
of a forest on one feature family at a time (:data:`FAMILY_GROUPS`), by design point (5
grouped folds) and, for ``faults_bands``, by speed band (5 quantile bands of
``speed_ratio``, each held out once) — into ``data/one_vs_one.csv``
(``data/bands_one_vs_one.csv``). A pair with fewer than 5 runs of either class is stored
with NaN scores.

``tests/learn/test_confuser_tables.py`` checks the documentation's tables against the CSVs and the
goals against the stored numbers (those not met as strict xfails with their numbers).
"""

from __future__ import annotations

import argparse
import itertools
import re
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
CELLS_CSV = ROOT / "data" / "confuser_cells.csv"
RATES_CSV = ROOT / "data" / "confuser_rates.csv"
ONE_CSV = ROOT / "data" / "one_vs_one.csv"
#: design -> (its cells, rates and one-against-one CSVs, the splits of its one-vs-one table)
OUTPUTS = {
    "faults_journal": (CELLS_CSV, RATES_CSV, ONE_CSV, ("group",)),
    "faults_bands": (ROOT / "data" / "bands_confuser_cells.csv",
                     ROOT / "data" / "bands_confuser_rates.csv",
                     ROOT / "data" / "bands_one_vs_one.csv", ("group", "speed_ratio")),
    "rub_kinds": (ROOT / "data" / "rub_kinds_confuser_cells.csv",
                  ROOT / "data" / "rub_kinds_confuser_rates.csv",
                  ROOT / "data" / "rub_kinds_one_vs_one.csv", ("group", "speed_ratio")),
}
FAMILIES = ("orders", "sidebands", "combinations", "full_spectrum", "orbit")
UNCERTAINTY = ("casing_stiffness_scale", "damping_ratio", "disc_mass_scale",
               "oil_viscosity_scale", "bearing_clearance_scale")
#: (target, split) of every goals cell
CELLS = ([("rub", "group"), ("rub", "speed_ratio"), ("fault", "group"),
          ("fault", "speed_ratio")] + [("rub", f) for f in UNCERTAINTY])
#: What the issue sets: rub macro-F1 >= 0.95 and every false rub alarm <= 5 % (with at
#: least 60 held-out runs) under the group and speed splits; fault macro-F1 >= 0.90 under
#: both; rub macro-F1 within 0.05 of the grouped score with a factor's band held out.
GOALS = {"rub_macro_f1": 0.95, "false_alarm": 0.05, "min_runs": 60, "fault_macro_f1": 0.90,
         "band_drop": 0.05}
CONFUSER_KINDS = ("misalignment", "crack", "looseness", "whirl")
#: design -> the cells it adds: rub kinds held out one blade count at a time
EXTRA_CELLS = {"rub_kinds": [("rub", "blade_count")]}


def _channels_and_features(data):
    """The shaft channels and every row's derived features of FAMILIES (a per-row
    transform: fitting it learns nothing from other rows)."""
    from rubdiag.learn._evaluate import resolve_channels
    from rubdiag.learn._features import OrderFeatures

    channels = resolve_channels(data, "shaft")
    features = OrderFeatures(channels=channels, families=FAMILIES).fit(data)
    return channels, pd.DataFrame(features.transform(data),
                                  columns=features.get_feature_names_out())


def goals_cell(data, target: str, split: str) -> tuple[dict, pd.DataFrame]:
    from rubdiag.learn import cross_validate

    start = time.perf_counter()
    full = split == "group"      # the baselines where they speak (each a cross-prediction)
    ev = cross_validate(data, target=target, split=split, estimator="rf", channels="shaft",
                  families=FAMILIES, importances=False, baselines=full, audit=False,
                  n_shuffles=2 if full else 1)
    s = ev.scores["macro_f1"]
    row = {"target": target, "split": split, "n_rows": ev.n_rows, "n_classes": len(ev.classes),
           "unscored": sum(ev.unscored.values()), "macro_f1": s.value, "macro_f1_lo": s.lo,
           "macro_f1_hi": s.hi}
    if ev.baselines is not None:
        best = ev.baselines["macro_f1"].map(lambda b: b.value).idxmax()
        row.update(best_baseline=best, baseline=ev.baselines.loc[best, "macro_f1"].value)
    row.update(shuffled=ev.shuffled["macro_f1"], shuffled_inside=ev.shuffled["inside"],
               wall_s=round(time.perf_counter() - start, 1))
    rates = ev.confusers.assign(target=target, split=split)
    return row, rates


FAMILY_GROUPS = {
    "study": r"rel_amp_4x$|sb_|bb_|combo_|n_half_orders|n_third_orders|"
             r"(rel_amp|dev)_\d+p\d+x$",
    "harmonics": r"rel_amp_\d+x$|dev_\d+x$",
    "full spectrum": r"fwd_rel_|rev_rel_|reverse_share|ellipticity_1x|precession_1x",
    "orbit": r"flattening|near_limit_share|limit_radius_rel",
    "all": r".",
}
FAMILY_NOTES = {
    "study": "the study's features: 4x, sidebands and the broadband around each harmonic, "
             "half and third orders, the combination pair",
    "harmonics": "1x, 2x, 3x ... over the channel's level",
    "full spectrum": "forward and reverse lines of each probe pair, reverse share, 1x "
                     "ellipticity and precession",
    "orbit": "flattening, the clearance-limited radius and the share of time near it",
    "all": "everything above",
}
#: the macro-F1 below which a family is said not to separate a pair
SEPARATES = 0.9


#: the fewest runs of each class a pair needs (one per grouped fold)
MIN_PAIR_RUNS = 5


def one_vs_one(data, features, splits=("group",)) -> pd.DataFrame:
    """Held-out macro-F1 of each family on each pair of pure classes, by each of ``splits``
    (module docstring)."""
    from rubdiag.learn._metrics import score
    from rubdiag.learn._pipelines import make_estimator
    from rubdiag.learn._splits import folds

    faults = data["faults"].astype(str).to_numpy()
    groups = data["point_id"].to_numpy()
    pairs = [("rub", k) for k in CONFUSER_KINDS] + list(itertools.combinations(
        CONFUSER_KINDS, 2))
    rows = []
    for split, (a, b) in itertools.product(splits, pairs):
        keep = np.flatnonzero((faults == a) | (faults == b))
        y, g = faults[keep], groups[keep]
        counts = {"split": split, "a": a, "b": b, "n_a": int((y == a).sum()),
                  "n_b": int((y == b).sum())}
        if min(counts["n_a"], counts["n_b"]) < MIN_PAIR_RUNS:
            rows += [{**counts, "family": f, "n_columns": 0, "macro_f1": np.nan, "lo": np.nan,
                      "hi": np.nan} for f in FAMILY_GROUPS]
            continue
        held_out = folds(data.iloc[keep].reset_index(drop=True), split, y)
        for family, pattern in FAMILY_GROUPS.items():
            cols = [c for c in features.columns if re.search(pattern, c.split("__")[-1])]
            X = features.iloc[keep][cols].to_numpy()
            predicted = np.empty(keep.size, dtype=object)
            for fold in held_out:
                model = make_estimator("rf", random_state=0).fit(X[fold.train], y[fold.train])
                predicted[fold.test] = model.predict(X[fold.test])
            s = score(y, predicted.astype(str), g, sorted({a, b}))["macro_f1"]
            rows.append({**counts, "family": family, "n_columns": len(cols),
                         "macro_f1": s.value, "lo": s.lo, "hi": s.hi})
    return pd.DataFrame(rows)


# --- reading the stored tables -------------------------------------------------------------
def cell(cells: pd.DataFrame, target: str, split: str) -> pd.Series:
    """The goals cell of ``target`` held out by ``split``."""
    return cells[(cells.target == target) & (cells.split == split)].iloc[0]


def alarms(rates: pd.DataFrame, target: str, split: str) -> pd.DataFrame:
    """The false rub alarm of each confuser kind (:data:`CONFUSER_KINDS`), by kind."""
    r = rates[(rates.target == target) & (rates.split == split)
              & (rates.measure == "false rub alarm")]
    return r[r.faults.isin(CONFUSER_KINDS)].set_index("faults")


# --- the documentation's tables -------------------------------------------------------------------
def _f(v, lo=None, hi=None) -> str:
    if v != v:
        return "–"
    text = f"{v:.3f}"
    return text if lo is None or lo != lo else f"{text} [{lo:.3f}, {hi:.3f}]"


def goals_table(cells: pd.DataFrame, rates: pd.DataFrame) -> str:
    """Goals: per cell, macro-F1 and each confuser's false rub alarm (called / runs)."""
    kinds = ["none", *CONFUSER_KINDS]
    lines = ["| target | held out | macro-F1 [95 %] | unscored | "
             + " | ".join(f"false rub alarm: {k}" for k in kinds) + " |",
             "|---|---|---|---:|" + "---|" * len(kinds)]
    for _, c in cells.iterrows():
        r = rates[(rates.target == c.target) & (rates.split == c.split)
                  & (rates.measure == "false rub alarm")].set_index("faults")
        alarms = [f"{_f(r.loc[k, 'rate'])} ({int(r.loc[k, 'n_called_rub'])}/{int(r.loc[k, 'n'])})"
                  for k in kinds]
        split = "design point" if c.split == "group" else f"band of {c.split}"
        lines.append(f"| {c.target} | {split} | {_f(c.macro_f1, c.macro_f1_lo, c.macro_f1_hi)} "
                     f"| {int(c.unscored)} | " + " | ".join(alarms) + " |")
    return "\n".join(lines)


def recall_table(rates: pd.DataFrame) -> str:
    """Rub recall beside each fault (and of each rub kind where the design has them), rub
    target, held out by design point, by speed band and (where stored) by blade count."""
    recall = rates[(rates.target == "rub") & (rates.measure == "rub recall")]
    kinds = ["rub", *[f"rub+{k}" for k in CONFUSER_KINDS]]
    kinds = [k for k in kinds if (recall.faults == k).any() and recall[recall.faults == k].n.sum()]
    kinds += sorted(k for k in set(recall.faults) if k.startswith("rub ("))
    lines = ["| held out | " + " | ".join(f"rub recall: {k}" for k in kinds) + " |",
             "|---|" + "---|" * len(kinds)]
    names = {"group": "design point", "speed_ratio": "band of speed_ratio",
             "blade_count": "blade count"}
    for split, name in names.items():
        r = recall[recall.split == split].set_index("faults")
        if r.empty:
            continue
        cells = [f"{_f(r.loc[k, 'rate'], r.loc[k, 'lo'], r.loc[k, 'hi'])} "
                 f"({int(r.loc[k, 'n_called_rub'])}/{int(r.loc[k, 'n'])})" for k in kinds]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def one_vs_one_table(one: pd.DataFrame) -> str:
    families = list(FAMILY_GROUPS)
    lines = ["| pair | runs | " + " | ".join(families) + " |",
             "|---|---:|" + "---|" * len(families)]
    for (a, b), rows in one.groupby(["a", "b"], sort=False):
        rows = rows.set_index("family")
        best = rows.loc[[f for f in families if f != "all"], "macro_f1"].max()
        cells = []
        for f in families:
            text = _f(rows.loc[f, "macro_f1"], rows.loc[f, "lo"], rows.loc[f, "hi"])
            cells.append(f"**{text}**" if f != "all" and rows.loc[f, "macro_f1"] == best
                         else text)
        n = f"{int(rows.n_a.iloc[0])}/{int(rows.n_b.iloc[0])}"
        lines.append(f"| {a} vs {b} | {n} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def study_failures(one: pd.DataFrame) -> str:
    """The pairs the study's features do not separate (held-out macro-F1 < SEPARATES)."""
    study = one[one.family == "study"]
    weak = study[study.macro_f1 < SEPARATES]
    if weak.empty:
        return (f"The study's features separate every pair (held-out macro-F1 ≥ "
                f"{SEPARATES:g}).")
    parts = [f"{r.a} vs {r.b} ({r.macro_f1:.3f})" for _, r in weak.iterrows()]
    return (f"The study's features alone fall below {SEPARATES:g} held-out macro-F1 on: "
            + "; ".join(parts) + ".")


def blocks() -> dict[str, str]:
    cells, rates, one = (pd.read_csv(p) for p in (CELLS_CSV, RATES_CSV, ONE_CSV))
    return {"confuser-goals": goals_table(cells, rates), "confuser-recall": recall_table(rates),
            "one-vs-one": one_vs_one_table(one) + "\n\n" + study_failures(one)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", nargs="?", help="the dataset folder of the design")
    parser.add_argument("--design", choices=sorted(OUTPUTS), default="faults_journal",
                        help="whose tables to write (default faults_journal)")
    parser.add_argument("--table", action="store_true", help="print the documentation's tables")
    args = parser.parse_args(argv)
    cells_csv, rates_csv, one_csv, splits = OUTPUTS[args.design]
    if not args.table:
        if args.dataset is None:
            parser.error("give the dataset folder, or --table")
        from rubdiag.learn import read_dataset

        data = read_dataset(args.dataset)
        data = data[data["status"] == "ok"].reset_index(drop=True)
        _, features = _channels_and_features(data)
        one = one_vs_one(data, features, splits)
        one.to_csv(one_csv, index=False, float_format="%.6g")
        print(one_vs_one_table(one[one.split == "group"]), flush=True)
        cells, rates = [], []
        for target, split in CELLS + EXTRA_CELLS.get(args.design, []):
            row, r = goals_cell(data, target, split)
            cells.append(row)
            rates.append(r)
            print(row, flush=True)
            pd.DataFrame(cells).to_csv(cells_csv, index=False, float_format="%.6g")
            pd.concat(rates).to_csv(rates_csv, index=False, float_format="%.6g")
        if args.design != "faults_journal":
            return 0
    for name, body in blocks().items():
        print(f"<!-- {name} -->\n{body}\n<!-- /{name} -->\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
