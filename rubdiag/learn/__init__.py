"""Rub classifiers: training, honest evaluation, prediction on measured signals.

* :func:`make_pipeline` — features (order-normalised, :mod:`rubdiag.learn.features`) →
  scaling → estimator, a plain scikit-learn ``Pipeline``;
* :func:`evaluate` — cross-validated scores on splits that do not leak
  (:mod:`rubdiag.learn.splits`), with intervals, baselines, the shuffled-label control
  and the leakage audit;
* :func:`read_dataset` — a dataset folder's finished rows;
* :func:`noise_curve` — scores against noise added to the stored waveforms
  (:mod:`rubdiag.learn.robustness`);
* :func:`confusion_figure`, :func:`importances_figure`, :func:`noise_curve_figure` — PNG
  figures of an evaluation and of a noise curve (:mod:`rubdiag.learn.figures`).

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
from rubdiag.learn.figures import confusion_figure, importances_figure, noise_curve_figure
from rubdiag.learn.metrics import Score
from rubdiag.learn.pipelines import ESTIMATORS, baseline_pipeline, make_estimator, make_pipeline
from rubdiag.learn.robustness import noise_curve
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
    "confusion_figure",
    "cross_predict",
    "evaluate",
    "folds",
    "importances_figure",
    "make_estimator",
    "make_pipeline",
    "noise_curve",
    "noise_curve_figure",
    "read_dataset",
    "shaft_channels",
]
