"""Held-out predictions of a pipeline over the folds of a split, and their scores.

:func:`cross_predict` fits a clone of the pipeline on each training side and predicts its
test side; a test row whose class is absent from its training fold cannot be predicted:
it is counted (``unscored``) and left out of every score (:func:`held_out_scores`), never
scored as a miss.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from sklearn.base import clone

from rubdiag import _progress
from rubdiag.learn._metrics import Score, score
from rubdiag.learn._splits import Fold

__all__ = ["CrossPrediction", "cross_predict", "held_out_scores"]


@dataclass
class CrossPrediction:
    """Held-out predictions of one pipeline over the folds of a split."""

    predicted: np.ndarray        # class per row; "" where not scored
    scored: np.ndarray           # bool per row
    unscored: dict               # class -> rows not scored (absent from a training fold)
    fitted: list                 # (fold, fitted pipeline or None)


def cross_predict(pipeline, data: pd.DataFrame, y: np.ndarray, splits: list[Fold],
                  test_data: pd.DataFrame | None = None, on_fold=None):
    """Fit a clone of ``pipeline`` on each training side, predict its test side — of
    ``test_data`` when given (the same rows measured otherwise, e.g. with more noise).
    ``on_fold()``, when given, is called after each fold (e.g. a progress bar's
    ``update``).

    Parameters
    ----------
    pipeline : sklearn estimator
        Unfitted.
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).
    y : numpy.ndarray
        The target of every row.
    splits : list of Fold
        The folds.
    test_data : pandas.DataFrame or None
        The rows predicted; None: ``data``.
    on_fold : callable or None
        Called after each fold.

    Returns
    -------
    CrossPrediction
        The held-out class of every row (``predicted``, "" where not ``scored``), the rows
        not scored per class (``unscored``) and the fitted pipelines.
    """
    test_data = data if test_data is None else test_data
    predicted = np.full(len(data), "", dtype=object)
    scored = np.zeros(len(data), dtype=bool)
    unscored: dict[str, int] = {}
    fitted = []
    for fold in _progress.counted(splits, on_fold):
        train_classes = set(y[fold.train])
        ok = np.array([v in train_classes for v in y[fold.test]], dtype=bool)
        for v in y[fold.test][~ok]:
            unscored[v] = unscored.get(v, 0) + 1
        if len(train_classes) < 2 or not ok.any():
            for v in y[fold.test][ok]:
                unscored[v] = unscored.get(v, 0) + 1
            fitted.append((fold, None))
            continue
        model = clone(pipeline).fit(data.iloc[fold.train], y[fold.train])
        test = fold.test[ok]
        predicted[test] = model.predict(test_data.iloc[test])
        scored[test] = True
        fitted.append((fold, model))
    return CrossPrediction(predicted, scored, unscored, fitted)


def held_out_scores(y, cp: CrossPrediction, groups, classes, n_bootstrap: int,
                    seed: int) -> dict[str, Score]:
    """Macro-F1 and balanced accuracy of the scored rows of ``cp`` with their bootstrap
    intervals over ``groups`` (:func:`~rubdiag.learn._metrics.score`); a ValueError when
    no row could be scored."""
    s = cp.scored
    if not s.any():
        raise ValueError("no test row could be scored: every fold lacks a class in training")
    return score(y[s], cp.predicted[s], groups[s], classes, n_bootstrap, seed)
