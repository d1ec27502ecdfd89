"""Rub classifiers: training, honest evaluation, prediction on measured signals.

* :func:`make_pipeline` — features (order-normalised, :mod:`rubdiag.learn._features`) →
  scaling → estimator, a plain scikit-learn ``Pipeline``;
* :func:`cross_validate` — cross-validated scores on splits that do not leak
  (:mod:`rubdiag.learn._splits`), with intervals, baselines, the shuffled-label control
  and the leakage audit;
* :func:`read_dataset` — a dataset folder's finished rows;
* :func:`choose_channels` — the input channels: by default the shaft channels that carry
  more than their noise floor (:mod:`rubdiag.learn._channel_choice`);
* :func:`training_warnings` — what says a model learnt little (a class with too few runs
  or never recognised, no margin over the best baseline or chance;
  :mod:`rubdiag.learn._caveats`), printed by ``train`` and kept in ``model.json``;
* :func:`noise_curve` — scores against noise added to the stored waveforms
  (:mod:`rubdiag.learn._robustness`);
* :func:`confusion_figure`, :func:`importances_figure`, :func:`noise_curve_figure` — PNG
  figures of an evaluation and of a noise curve (:mod:`rubdiag.learn._figures`);
* :func:`train` — a model folder: the pipeline fitted on every row, its evaluation and
  what prediction needs (:mod:`rubdiag.learn._train`); :func:`evaluate` — a saved
  model scored on another dataset; :func:`save_model`, :func:`load_model` — skops with an
  explicit allow-list of types (:mod:`rubdiag.learn._persist`);
* :func:`predict` — a saved model on measured signals, window by window
  (:mod:`rubdiag.learn._predict`);
* :func:`read_records` — a labelled record list (signal files with their labels) that
  :func:`evaluate` scores (:mod:`rubdiag.learn._records`); :func:`textbook_records` —
  records of the confusers' textbook signatures made in code, for evaluation only
  (:mod:`rubdiag.learn._textbook`).

This layer sits above :mod:`rubdiag.dataset` and reads stored datasets only: nothing of it
imports the simulator.
"""

from rubdiag.learn._caveats import MIN_RUNS_PER_CLASS, training_warnings
from rubdiag.learn._channel_choice import NOISE_MARGIN_DB, choose_channels
from rubdiag.learn._columns import (
    TARGETS,
    casing_channels,
    channels_of,
    read_dataset,
    shaft_channels,
)
from rubdiag.learn._controls import audit_columns
from rubdiag.learn._cross_predict import cross_predict
from rubdiag.learn._evaluate import Evaluation, cross_validate
from rubdiag.learn._features import DEFAULT_FAMILIES, FAMILIES, OrderFeatures, SelectColumns
from rubdiag.learn._figures import confusion_figure, importances_figure, noise_curve_figure
from rubdiag.learn._metrics import Score
from rubdiag.learn._persist import Model, load_model, save_model
from rubdiag.learn._pipelines import ESTIMATORS, baseline_pipeline, make_estimator, make_pipeline
from rubdiag.learn._predict import predict
from rubdiag.learn._records import read_records
from rubdiag.learn._robustness import noise_curve
from rubdiag.learn._splits import Fold, folds
from rubdiag.learn._textbook import textbook_records
from rubdiag.learn._train import ModelScores, evaluate, train

__all__ = [
    "DEFAULT_FAMILIES",
    "ESTIMATORS",
    "FAMILIES",
    "MIN_RUNS_PER_CLASS",
    "NOISE_MARGIN_DB",
    "TARGETS",
    "Evaluation",
    "Fold",
    "Model",
    "ModelScores",
    "OrderFeatures",
    "Score",
    "SelectColumns",
    "audit_columns",
    "baseline_pipeline",
    "casing_channels",
    "channels_of",
    "choose_channels",
    "confusion_figure",
    "cross_predict",
    "cross_validate",
    "evaluate",
    "folds",
    "importances_figure",
    "load_model",
    "make_estimator",
    "make_pipeline",
    "noise_curve",
    "noise_curve_figure",
    "predict",
    "read_dataset",
    "read_records",
    "save_model",
    "shaft_channels",
    "textbook_records",
    "train",
    "training_warnings",
]
