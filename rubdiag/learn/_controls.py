"""What says how far to trust a classifier's held-out score (:mod:`rubdiag.learn._evaluate`).

* the baselines (:func:`baselines`) — the same estimator on the 1× levels only, on the
  speed only, on the design factors only (those every run shows: :func:`baseline_factors`)
  — and the score with and without the casing channels (:func:`casing_scores`);
* the shuffled-label control (:func:`shuffled_control`): the pipeline trained on labels
  shuffled between design points, each shuffle scored against the permutation-null
  interval of its own prediction, no more of them outside than chance allows
  (:func:`allowed_outside`; if more, something leaks through the split);
* the audit (:func:`audit_columns`): every single column (derived feature in any family,
  raw level or frequency, design factor) that alone separates the classes.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.base import clone
from sklearn.tree import DecisionTreeClassifier

from rubdiag import _progress
from rubdiag.dataset._labels import MEASURES
from rubdiag.dataset._schema import SEPARATOR
from rubdiag.learn._columns import casing_channels, factor_columns
from rubdiag.learn._cross_predict import cross_predict, held_out_scores
from rubdiag.learn._features import FAMILIES, OrderFeatures
from rubdiag.learn._metrics import Score, group_permutations, macro_f1, null_interval
from rubdiag.learn._pipelines import baseline_pipeline, make_pipeline

__all__ = ["allowed_outside", "audit_columns", "baseline_factors", "baselines",
           "casing_scores", "condition_factors", "fold_of_rows", "shuffled_control"]


def baselines(data, y, splits, groups, classes, channels, estimator, n_bootstrap, seed,
              on_fold=None) -> pd.DataFrame:
    """The same estimator on what should not be enough: 1× levels, speed, design factors
    (``left_out``: the factors left out of that baseline, :func:`baseline_factors`). A
    baseline without a column is not fitted: NaN scores."""
    rows = []
    factors, left_out = baseline_factors(data)
    candidates = [
        ("1x level only", [f"{c}{SEPARATOR}amp_1x" for c in channels], []),
        ("speed only", ["speed_rpm"], []),
        ("design factors only", factors, left_out),
    ]
    for name, columns, unused in candidates:
        if columns:
            cp = cross_predict(baseline_pipeline(columns, estimator, seed), data, y, splits,
                               on_fold=on_fold)
            s = held_out_scores(y, cp, groups, classes, n_bootstrap, seed)
        else:
            for _ in _progress.counted(splits, on_fold):     # the bar counts its folds
                pass
            s = dict.fromkeys(("macro_f1", "balanced_accuracy"), Score(np.nan, np.nan, np.nan))
        rows.append({"baseline": name, "columns": ", ".join(columns),
                     "left_out": ", ".join(unused),
                     "macro_f1": s["macro_f1"], "balanced_accuracy": s["balanced_accuracy"]})
    return pd.DataFrame(rows).set_index("baseline")


def condition_factors(data: pd.DataFrame) -> list[str]:
    """The numeric design factors: the conditions of a run (speed, gap, a fault's
    severity …). The ``fault`` factor is not one: it names the faults the design meant
    the run to have — the label as designed — and it is text."""
    return [c for c in factor_columns(data) if pd.api.types.is_numeric_dtype(data[c])]


def baseline_factors(data: pd.DataFrame) -> tuple[list[str], list[str]]:
    """The design factors the design-factors baseline reads, and those it leaves out.

    A factor blank (NaN) in some runs is blank by design for some level — a crack's depth
    where no crack acted, the gap where nothing rubs, the speed ratio of a whirling run
    (:func:`rubdiag.dataset._faults.shown_point`): where it is blank tells the level, and a
    baseline reading it is an oracle. So is, in a design with a fault factor, a factor
    whose column holds the run's own measure of that name: ``interference_ratio``, which
    the row shows as measured (the linear approach over the gap: about 0.001 where the
    casing is out of reach, 1.2 and up where the design made the run rub; in a design where
    every run rubs it is the designed condition, and stays). Such factors are left out; the
    audit
    (:func:`audit_columns`) still lists any factor that separates the classes.

    Returns
    -------
    (list of str, list of str)
        The :func:`condition_factors` every run shows, and those blank in some run.
    """
    factors = condition_factors(data)
    faults = "faults" in data.columns          # some level keeps the contacts out of reach
    blank = [c for c in factors if data[c].isna().any() or (faults and c in MEASURES)]
    return [c for c in factors if c not in blank], blank


def casing_scores(data, y, splits, groups, classes, channels, families, estimator, scores,
                  n_bootstrap, seed, on_fold=None) -> dict | None:
    """Macro-F1 with and without the casing channels (one of the two is the model's)."""
    casing = casing_channels(data)
    if not casing:
        return None
    used = [c for c in channels if c in casing]
    other = ([c for c in channels if c not in casing] if used
             else [*channels, *casing])
    if not other:
        return {"with": scores["macro_f1"], "without": None}
    pipe = make_pipeline(estimator, channels=other, families=families, random_state=seed)
    s = held_out_scores(y, cross_predict(pipe, data, y, splits, on_fold=on_fold), groups,
                        classes, n_bootstrap, seed)["macro_f1"]
    return ({"with": scores["macro_f1"], "without": s} if used
            else {"with": s, "without": scores["macro_f1"]})


def shuffled_control(pipeline, data, y, groups, split_rows, classes, n_null, n_shuffles,
                     seed, on_fold=None) -> dict:
    """The pipeline on labels shuffled between design points, scored against them, and
    its chance interval, for ``n_shuffles`` shuffles (``split_rows(labels)``: the folds of
    the evaluation's split for those labels). Whole points' labels move, so
    replicates keep one label between them as in the data: were a point's replicates on
    both sides of a split, a model would recognise them and score above chance (a
    row-by-row shuffle would hide that). The null moves labels within each test fold
    (:func:`null_interval`), or across folds where a point's rows lie in several (a split
    that is not grouped).

    One shuffle lands outside its 95 % interval 1 time in 20 without any leak, so a
    single one cannot tell an unlucky draw from a leak; the verdict is on all of them:
    no more outside than :func:`allowed_outside` (a binomial 95 % bound)."""
    runs = []
    for r in range(n_shuffles):
        rng = np.random.default_rng(np.random.SeedSequence([seed, 1, r]))
        shuffled = y[group_permutations(groups, 1, rng)[0]]
        splits = split_rows(shuffled)
        cp = cross_predict(pipeline, data, shuffled, splits, on_fold=on_fold)
        s = cp.scored
        value = macro_f1(shuffled[s], cp.predicted[s], classes)
        lo, hi = null_interval(shuffled[s], cp.predicted[s], classes, n_null, seed,
                               groups=groups[s], strata=fold_of_rows(splits, groups, s))
        runs.append({"macro_f1": value, "null_lo": lo, "null_hi": hi,
                     "inside": lo <= value <= hi})
    outside = sum(not run["inside"] for run in runs)
    allowed = allowed_outside(n_shuffles)
    return {"macro_f1": float(np.median([run["macro_f1"] for run in runs])),
            "null_lo": float(np.median([run["null_lo"] for run in runs])),
            "null_hi": float(np.median([run["null_hi"] for run in runs])),
            "n_shuffles": n_shuffles, "n_outside": outside, "allowed_outside": allowed,
            "inside": outside <= allowed, "shuffles": runs}


def allowed_outside(n_shuffles: int, level: float = 0.05) -> int:
    """How many of ``n_shuffles`` controls may land outside their 95 % intervals without
    a leak: the least k with P(Binomial(n, 0.05) > k) <= ``level`` (0 for one shuffle,
    1 for 2–7, 2 for 8–16 …)."""
    from scipy.stats import binom

    k = 0
    while binom.sf(k, n_shuffles, 0.05) > level:
        k += 1
    return k


def fold_of_rows(splits, groups, rows) -> np.ndarray | None:
    """The test fold of each of ``rows`` (a mask), or None when a group's rows lie in
    several folds."""
    fold = np.full(len(groups), -1)
    for i, f in enumerate(splits):
        fold[f.test] = i
    fold, groups = fold[rows], np.asarray(groups)[rows]
    per_group = pd.Series(fold).groupby(groups).nunique()
    return fold if (per_group == 1).all() else None


def audit_columns(data, y, splits, classes, threshold: float = 0.9, seed: int = 0,
                  on_fold=None):
    """Every single column that alone separates the classes: a depth-2 tree on it, cross-
    predicted on ``splits``, reaches ``threshold`` macro-F1. Candidates: every derived
    feature of every channel in every family (levels and absolute frequencies included)
    and every design factor; sorted by score. ``on_fold()``, when given, is called after
    each fold's trees.

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).
    y : numpy.ndarray
        The target of every row.
    splits : list of Fold
        The folds.
    classes : list of str
        The classes.
    threshold : float
        Macro-F1 from which a column separates the classes (0-1).
    seed : int
        Seed of the trees.
    on_fold : callable or None
        Called after each fold.

    Returns
    -------
    pandas.DataFrame
        ``column``, ``kind`` and ``macro_f1`` of each such column, best first.
    """
    everything = OrderFeatures(channels=None, families=FAMILIES).fit(data)
    Z = everything.transform(data)
    names = list(everything.get_feature_names_out())
    factors = condition_factors(data)
    Z = np.column_stack([Z, np.nan_to_num(data[factors].to_numpy(dtype=float))])
    kinds = ["feature"] * len(names) + ["factor"] * len(factors)
    names += factors
    yi = np.searchsorted(classes, y)           # classes are sorted
    tree = DecisionTreeClassifier(max_depth=2, class_weight="balanced", random_state=seed)
    varying = [j for j in range(len(names)) if np.ptp(Z[:, j]) != 0.0]
    true, pred = [], {j: [] for j in varying}
    for fold in _progress.counted(splits, on_fold):
        if len(set(yi[fold.train])) < 2:
            continue
        test = fold.test[np.isin(yi[fold.test], yi[fold.train])]
        true.append(yi[test])
        for j in varying:
            x = Z[:, [j]]
            pred[j].append(clone(tree).fit(x[fold.train], yi[fold.train]).predict(x[test]))
    rows = []
    for j in varying:
        f1 = macro_f1(np.concatenate(true), np.concatenate(pred[j]), range(len(classes)))
        if f1 >= threshold:
            rows.append({"column": names[j], "kind": kinds[j], "macro_f1": f1})
    frame = pd.DataFrame(rows, columns=["column", "kind", "macro_f1"])
    return frame.sort_values("macro_f1", ascending=False, kind="stable").reset_index(drop=True)
