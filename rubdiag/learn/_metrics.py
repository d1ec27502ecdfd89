"""Scores with their uncertainty: macro-F1 and balanced accuracy, bootstrap confidence
intervals over design points, and the permutation null of a prediction.

Both scores weigh every class equally, so a model that ignores a rare class cannot hide
behind the common one. Intervals resample *design points* (``point_id``), not rows: the
replicates of a point are near-copies, and resampling them one by one would make the
interval too narrow.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["METRICS", "Score", "bootstrap_weights", "confusion", "group_permutations",
           "group_rate", "macro_f1", "null_interval", "score", "wilson_interval"]

METRICS = ("macro_f1", "balanced_accuracy")


@dataclass(frozen=True)
class Score:
    """A score and its 95 % interval (``lo`` … ``hi``).

    Parameters
    ----------
    value : float
        The score.
    lo, hi : float
        Its 95 % interval.
    """

    value: float
    lo: float
    hi: float

    def __str__(self) -> str:
        return f"{self.value:.3f} [{self.lo:.3f}, {self.hi:.3f}]"

    def to_dict(self) -> dict:
        return {"value": self.value, "lo": self.lo, "hi": self.hi}


def confusion(y_true, y_pred, classes) -> np.ndarray:
    """Counts ``[i, j]`` of rows of class ``classes[i]`` predicted as ``classes[j]``."""
    index = {c: i for i, c in enumerate(classes)}
    t = np.array([index[v] for v in y_true], dtype=np.int64)
    p = np.array([index.get(v, -1) for v in y_pred], dtype=np.int64)
    if (p < 0).any():
        raise ValueError("a prediction is not one of the classes")
    k = len(classes)
    return np.bincount(t * k + p, minlength=k * k).reshape(k, k)


def _from_counts(cm: np.ndarray) -> dict[str, np.ndarray]:
    """Macro-F1 and balanced accuracy of confusion matrices (..., k, k); classes without a
    true row count as absent (left out of both means), as scikit-learn does with
    ``labels=`` the classes present."""
    tp = np.diagonal(cm, axis1=-2, axis2=-1).astype(float)
    support = cm.sum(axis=-1).astype(float)
    predicted = cm.sum(axis=-2).astype(float)
    present = support > 0
    with np.errstate(invalid="ignore", divide="ignore"):
        f1 = np.where(support + predicted > 0, 2 * tp / (support + predicted), 0.0)
        recall = np.where(present, tp / support, 0.0)
    n_present = present.sum(axis=-1)
    return {"macro_f1": (f1 * present).sum(axis=-1) / n_present,
            "balanced_accuracy": recall.sum(axis=-1) / n_present}


def macro_f1(y_true, y_pred, classes) -> float:
    """Macro-F1 of a prediction over the ``classes`` present in ``y_true`` (as
    ``sklearn.metrics.f1_score(average="macro", labels=present, zero_division=0)``)."""
    k = len(classes)
    cm = confusion(y_true, y_pred, classes).reshape(1, k, k)
    return float(_from_counts(cm)["macro_f1"][0])


def score(y_true, y_pred, groups, classes, n_bootstrap: int = 1000,
          seed: int = 0) -> dict[str, Score]:
    """Macro-F1 and balanced accuracy of a prediction with 95 % bootstrap intervals; the
    bootstrap draws ``groups`` (design points) with replacement, all rows of a drawn group
    together."""
    y_true, y_pred, groups = (np.asarray(a) for a in (y_true, y_pred, groups))
    k = len(classes)
    index = {c: i for i, c in enumerate(classes)}
    cell = (np.array([index[v] for v in y_true]) * k
            + np.array([index[v] for v in y_pred]))
    _, g = np.unique(groups, return_inverse=True)
    n_groups = g.max() + 1
    # counts[group, cell]: a bootstrap sample's confusion matrix is a weighted sum of rows
    counts = np.zeros((n_groups, k * k))
    np.add.at(counts, (g, cell), 1.0)
    whole = _from_counts(counts.sum(axis=0).reshape(k, k))
    weights = bootstrap_weights(n_groups, n_bootstrap, seed)
    boot = _from_counts((weights @ counts).reshape(n_bootstrap, k, k))
    out = {}
    for name in METRICS:
        lo, hi = np.nanpercentile(boot[name], [2.5, 97.5]) if n_bootstrap else (np.nan,) * 2
        out[name] = Score(float(whole[name]), float(lo), float(hi))
    return out


def bootstrap_weights(n_groups: int, n_bootstrap: int, seed: int = 0) -> np.ndarray:
    """``(n_bootstrap, n_groups)`` counts of how often each group is drawn when
    ``n_groups`` groups are drawn with replacement: a bootstrap sample's total of any
    per-group count is then ``weights @ counts``."""
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, n_groups, size=(n_bootstrap, n_groups))
    weights = np.zeros((n_bootstrap, n_groups))
    np.add.at(weights, (np.arange(n_bootstrap)[:, None], draws), 1.0)
    return weights


def group_rate(hits, members, groups, n_bootstrap: int = 1000, seed: int = 0) -> Score:
    """The share of ``members`` rows that are ``hits`` (two bool arrays, one value per
    row) with a 95 % bootstrap interval drawing ``groups`` with replacement, as
    :func:`score` does; NaN throughout without members (a draw without members is
    left out of the interval)."""
    hits, members = np.asarray(hits, dtype=bool), np.asarray(members, dtype=bool)
    n = int(members.sum())
    if n == 0:
        return Score(np.nan, np.nan, np.nan)
    _, g = np.unique(np.asarray(groups), return_inverse=True)
    n_groups = g.max() + 1
    per_group = np.zeros((n_groups, 2))            # [members, hits among them]
    np.add.at(per_group, (g, 0), members.astype(float))
    np.add.at(per_group, (g, 1), (hits & members).astype(float))
    value = per_group[:, 1].sum() / n
    if not n_bootstrap:
        return Score(float(value), np.nan, np.nan)
    drawn = bootstrap_weights(n_groups, n_bootstrap, seed) @ per_group
    with np.errstate(invalid="ignore", divide="ignore"):
        rates = drawn[:, 1] / drawn[:, 0]
    lo, hi = np.nanpercentile(rates, [2.5, 97.5])
    return Score(float(value), float(lo), float(hi))


def wilson_interval(hits: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson's score interval of a proportion ``hits`` / ``n`` (95 % by default): unlike
    a bootstrap it is not empty at 0 of n or n of n. (NaN, NaN) when ``n`` is 0."""
    if n == 0:
        return np.nan, np.nan
    p = hits / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return float(max(centre - half, 0.0)), float(min(centre + half, 1.0))


def group_permutations(groups, n: int, rng: np.random.Generator,
                       strata=None) -> np.ndarray:
    """``n`` permutations of the rows (an ``(n, rows)`` array of row positions) that move
    whole groups: the rows of a group take, in order, those of another group of the same
    size — of the same stratum, with ``strata`` (one value per row, constant within a
    group). With every group of one row, plain permutations of the rows."""
    groups = np.asarray(groups)
    _, g, sizes = np.unique(groups, return_inverse=True, return_counts=True)
    rows_of = np.argsort(g, kind="stable")              # the rows, group after group
    starts = np.cumsum(sizes) - sizes
    if strata is None:
        stratum = np.zeros(sizes.size, dtype=np.int64)
    else:
        _, s = np.unique(np.asarray(strata), return_inverse=True)
        if s.shape != g.shape:
            raise ValueError(f"strata: one value per row needed ({g.size}), got {s.size}")
        stratum = s[rows_of[starts]]                    # each group's first row's
        if (s != stratum[g]).any():
            raise ValueError("strata: a group's rows lie in different strata")
    out = np.broadcast_to(np.arange(g.size), (n, g.size)).copy()
    for key in np.unique(np.column_stack([stratum, sizes]), axis=0):
        members = np.flatnonzero((stratum == key[0]) & (sizes == key[1]))
        rows = rows_of[starts[members][:, None] + np.arange(key[1])]        # (m, size)
        perm = rng.permuted(np.broadcast_to(np.arange(members.size), (n, members.size)),
                            axis=1)
        out[:, rows] = rows[perm]                                           # (n, m, size)
    return out


def null_interval(y_true, y_pred, classes, n: int = 1000, seed: int = 0,
                  metric: str = "macro_f1", groups=None, strata=None) -> tuple[float, float]:
    """The 95 % interval of ``metric`` when the truth is shuffled against the predictions:
    what this very prediction scores by chance (same class frequencies, no information).
    With ``groups`` (design points) whole groups' labels move together, as when the labels
    themselves were shuffled between design points: replicates are near-copies, so their
    predictions agree and a row-by-row shuffle would make the interval too narrow.

    With ``strata`` (the test fold of each row) labels move only within a fold. That is
    the exact null of a cross-validated model on labels shuffled between groups: given
    its training side, a fold's predictions are fixed, and the labels of its test groups
    are any arrangement of that fold's labels — but not of another fold's, whose
    composition the training side (and so the predicted class rates) depends on. Across
    folds the interval ignores that dependence and is too narrow for band splits.
    """
    k = len(classes)
    index = {c: i for i, c in enumerate(classes)}
    t = np.array([index[v] for v in y_true])
    p = np.array([index[v] for v in y_pred])
    rng = np.random.default_rng(seed)
    groups = np.arange(t.size) if groups is None else groups
    cells = t[group_permutations(groups, n, rng, strata)] * k + p
    cms = np.zeros((n, k * k))
    np.add.at(cms, (np.arange(n)[:, None], cells), 1.0)
    values = _from_counts(cms.reshape(n, k, k))[metric]
    lo, hi = np.percentile(values, [2.5, 97.5])
    return float(lo), float(hi)
