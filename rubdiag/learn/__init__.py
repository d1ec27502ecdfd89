"""Rub classifiers: training, honest evaluation, prediction on measured signals.

* :func:`make_pipeline` — features (order-normalised, :mod:`rubdiag.learn.features`) →
  scaling → estimator, a plain scikit-learn ``Pipeline``;
* :func:`evaluate` — cross-validated scores on splits that do not leak
  (:mod:`rubdiag.learn.splits`), with intervals, baselines, the shuffled-label control
  and the leakage audit;
* :func:`read_dataset` — a dataset folder's finished rows.

This layer sits above :mod:`rubdiag.dataset` and reads stored datasets only: nothing of it
imports the simulator.
"""

from rubdiag.learn.columns import (
    TARGETS,
    casing_channels,
    channels_of,
    read_dataset,
    shaft_channels,
)
from rubdiag.learn.evaluate import Evaluation, audit_columns, cross_predict, evaluate
from rubdiag.learn.features import DEFAULT_FAMILIES, FAMILIES, OrderFeatures, SelectColumns
from rubdiag.learn.metrics import Score
from rubdiag.learn.pipelines import ESTIMATORS, baseline_pipeline, make_estimator, make_pipeline
from rubdiag.learn.splits import Fold, folds

__all__ = [
    "DEFAULT_FAMILIES",
    "ESTIMATORS",
    "FAMILIES",
    "TARGETS",
    "Evaluation",
    "Fold",
    "OrderFeatures",
    "Score",
    "SelectColumns",
    "audit_columns",
    "baseline_pipeline",
    "casing_channels",
    "channels_of",
    "cross_predict",
    "evaluate",
    "folds",
    "make_estimator",
    "make_pipeline",
    "read_dataset",
    "shaft_channels",
]
