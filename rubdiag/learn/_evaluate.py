"""Honest evaluation of a rub classifier: held-out scores, the baselines, a leakage audit.

:func:`cross_validate` cross-predicts a pipeline over the folds of a split
(:mod:`rubdiag.learn._splits`) and reports, on the same folds:

* macro-F1 and balanced accuracy with 95 % bootstrap intervals over design points,
  per-class precision and recall, the confusion matrix;
* grouped permutation importances on the held-out rows (each derived feature permuted in
  every channel at once, and each channel as a whole);
* the baselines — the same estimator on the 1× levels only, on the speed only, on the
  design factors only (those every run shows:
  :func:`~rubdiag.learn._controls.baseline_factors`) — and the score with and without
  casing channels;
* the pipeline trained on labels shuffled between design points (``n_shuffles`` shuffles),
  each scored against the permutation-null interval of its own prediction: no more of them
  outside than chance allows (if more, something leaks through the split);
* on a dataset with faults beside rub (target ``rub`` or ``fault``): the false rub alarm
  rate per confuser and the rub recall beside each (:mod:`rubdiag.learn._confusers`);
* the audit: every single column (derived feature in any family, raw level or frequency,
  design factor) that alone separates the classes (a depth-2 tree on it reaches
  ``audit_threshold`` macro-F1 on the same folds).

A test row whose class is absent from its training fold cannot be predicted: it is
counted (``unscored``) and left out of every score, never scored as a miss
(:mod:`rubdiag.learn._cross_predict`). The baselines, the shuffled-label control and the
audit are :mod:`rubdiag.learn._controls`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits  # installed with scikit-learn

from rubdiag import _check, _progress
from rubdiag.dataset._schema import SEPARATOR
from rubdiag.learn import _controls
from rubdiag.learn._caveats import training_warnings
from rubdiag.learn._channel_choice import ChannelChoice, choose_channels
from rubdiag.learn._columns import TARGET_COLUMNS, TARGETS, read_dataset
from rubdiag.learn._confusers import rub_confusers
from rubdiag.learn._cross_predict import CrossPrediction, cross_predict, held_out_scores
from rubdiag.learn._features import DEFAULT_FAMILIES, OrderFeatures, _check_families
from rubdiag.learn._metrics import confusion, macro_f1
from rubdiag.learn._pipelines import make_pipeline
from rubdiag.learn._splits import folds

__all__ = ["Evaluation", "cross_validate", "resolve_channels", "target_values"]


def target_values(data: pd.DataFrame, target: str) -> np.ndarray:
    """The target column as class names (strings; ``rub`` gives ``"True"``/``"False"``,
    ``fault`` the ``faults`` label: ``"none"``, ``"rub+crack"`` …). On a dataset with
    other faults ``rub`` is rub against everything else: a crack without rub is
    ``"False"`` like a healthy run."""
    if target not in TARGETS:
        raise ValueError(f"target = {target!r} is not a label (allowed: {', '.join(TARGETS)})")
    column = TARGET_COLUMNS.get(target, target)
    if column not in data.columns:
        need = ("a dataset whose design has a fault factor" if target == "fault"
                else "a dataset's rows")
        raise ValueError(f"target = {target!r}: the data has no {column!r} column ({need} "
                         "is needed)")
    return data[column].astype(str).to_numpy()


def resolve_channels(data: pd.DataFrame, channels) -> list[str]:
    """The channel names of ``channels``: ``"auto"`` (the shaft channels that carry more
    than their noise floor: the default), ``"shaft"`` (every channel not on the casing),
    ``"all"``, or names (:func:`rubdiag.learn._channel_choice.choose_channels`)."""
    return choose_channels(data, channels).channels


@dataclass
class Evaluation:
    """What :func:`cross_validate` measured (``to_dict`` for JSON, ``to_markdown`` for people).

    Parameters
    ----------
    target, split, estimator : str
        What was predicted, how the rows were split, the classifier.
    channels, families : list of str
        The input channels and feature families.
    classes : list of str
        The classes, in the order of the tables.
    class_counts : dict of str to int
        Rows per class.
    n_rows : int
        Rows of the dataset.
    folds : list of dict
        ``name``, ``n_train`` and ``n_test`` of each fold.
    unscored : dict of str to int
        Rows not scored per class (the class was absent from their training fold).
    scores : dict of str to Score
        Macro-F1 and balanced accuracy with their 95 % intervals, by metric.
    per_class, confusion, predictions : pandas.DataFrame
        Per-class precision and recall, the confusion matrix, the held-out prediction of
        every row.
    importances, channel_importances : pandas.DataFrame or None
        Permutation importances of the features and of the channels.
    baselines : pandas.DataFrame or None
        The baselines' scores.
    casing : dict or None
        Macro-F1 with and without the casing channels.
    shuffled : dict or None
        The shuffled-label control.
    audit : pandas.DataFrame or None
        The single columns that separate the classes alone (:func:`audit_columns`).
    confusers : pandas.DataFrame or None
        False rub alarms per confuser (:mod:`rubdiag.learn._confusers`).
    notes : list of str
        Remarks for the report.
    channel_choice : ChannelChoice or None
        What the default channels left out, and why.
    warnings : list of str
        What says the model learnt little (:func:`training_warnings`).
    """

    target: str
    split: str
    estimator: str
    channels: list
    families: list
    classes: list
    class_counts: dict
    n_rows: int
    folds: list                       # [{"name", "n_train", "n_test"}]
    unscored: dict
    scores: dict                      # metric -> Score
    per_class: pd.DataFrame
    confusion: pd.DataFrame
    predictions: pd.DataFrame
    importances: pd.DataFrame | None = None
    channel_importances: pd.DataFrame | None = None
    baselines: pd.DataFrame | None = None
    casing: dict | None = None        # {"with": Score, "without": Score} (macro-F1)
    shuffled: dict | None = None
    audit: pd.DataFrame | None = None
    confusers: pd.DataFrame | None = None    # rubdiag.learn._confusers.confuser_table
    notes: list = field(default_factory=list)
    channel_choice: ChannelChoice | None = None   # what the default channels left out
    warnings: list = field(default_factory=list)  # what says the model learnt little

    def to_dict(self) -> dict:
        from rubdiag.learn._report import evaluation_dict

        return evaluation_dict(self)

    def to_markdown(self) -> str:
        from rubdiag.learn._report import evaluation_markdown

        return evaluation_markdown(self)


@threadpool_limits.wrap(limits=1)
def cross_validate(data, target: str = "rub", split: str = "group", estimator: str = "rf", *,
             channels="auto", families=DEFAULT_FAMILIES, pipeline=None, n_splits: int = 5,
             bands: int = 5, n_bootstrap: int = 1000, n_null: int = 1000,
             importances: bool = True, n_repeats: int = 5, baselines: bool = True,
             audit: bool = True, audit_threshold: float = 0.9, n_shuffles: int = 5,
             seed: int = 0, progress=False) -> Evaluation:
    """Cross-validated scores of a classifier on a dataset, with everything that says how
    far to trust them (module docstring).

    Parameters
    ----------
    data : DataFrame or path
        A dataset's rows (:func:`~rubdiag.learn._columns.read_dataset`) or its folder.
    target : {"rub", "rub_state", "severity", "fault"}
        ``fault``: the faults that acted (the ``faults`` label); ``rub`` on a dataset
        with other faults: rub against everything else, those faults included.
    split : str
        ``"group"`` (by design point) or a design factor to hold out band by band
        (``"speed_ratio"``, ``"gap_mm"``, ``"mu"``, ``"case"`` …).
    estimator : {"rf", "hgb", "svm", "logreg"}
    channels : "auto", "shaft", "all" or list of str
        Input channels. ``"auto"`` (default): the shaft channels whose median power over
        the rubbing runs stands :data:`~rubdiag.learn._channel_choice.NOISE_MARGIN_DB`
        above their noise floor (:mod:`rubdiag.learn._channel_choice`; what it leaves out
        is in ``channel_choice``); ``"shaft"``: every channel not on the casing (see
        :func:`~rubdiag.learn._columns.shaft_channels`).
    families : sequence of str
        Feature families (:mod:`rubdiag.learn._features`).
    pipeline : sklearn estimator, optional
        Replaces the pipeline built from ``estimator``, ``channels`` and ``families``.
    n_splits, bands : int
        Folds of the group split; bands of a factor split.
    n_bootstrap, n_null : int
        Bootstrap draws of the intervals; permutations of the null interval.
    importances, baselines, audit : bool
        Compute these parts (they cost several further cross-predictions).
    n_repeats : int
        Permutations per feature for the importances.
    audit_threshold : float
        Macro-F1 from which one column alone "separates the classes".
    n_shuffles : int
        Label shuffles of the shuffled-label control (each one more cross-prediction).
    seed : int
        Seeds folds, models, bootstrap and permutations: the same call gives the same
        report (fits run on one thread: a multi-threaded histogram sum, as in hgb, may
        round differently from run to run).
    progress : bool or open bar
        A bar over the fits (each fold of each cross-prediction, of the importances and of
        the audit), on stderr when it is a terminal; or an open bar of
        :mod:`rubdiag._progress` to count them on (``train``'s).

    Returns
    -------
    Evaluation
        The scores and everything measured beside them.
    """
    if isinstance(data, str | Path):
        data = read_dataset(data)
    y = target_values(data, target)
    choice = choose_channels(data, channels)
    channels = choice.channels
    families = list(_check_families(families))      # one name as a one-family list
    n_bootstrap = _check.integer("n_bootstrap", n_bootstrap, lo=0)
    n_null = _check.integer("n_null", n_null, lo=10)
    n_shuffles = _check.integer("n_shuffles", n_shuffles, lo=1)
    audit_threshold = _check.number("audit_threshold", audit_threshold, lo=0.0, hi=1.0)
    if pipeline is None:
        pipeline = make_pipeline(estimator, channels=channels, families=families,
                                 random_state=seed)
    classes = sorted(set(y))
    if len(classes) < 2:      # before the folds: their complaints would hide this one
        raise ValueError(f"target {target!r} takes one value in the data ({classes[0]!r}): "
                         "nothing to classify")
    splits = folds(data, split, y, n_splits=n_splits, bands=bands, seed=seed)
    groups = data["point_id"].to_numpy()
    # a bar over the folds of every part: the cross-predictions (the model, each baseline,
    # with or without the casing, each shuffle), the importances and the audit
    parts = 1 + importances + 4 * baselines + n_shuffles + audit
    with _progress.shared(progress, parts * len(splits), "evaluate", "fit") as bar:
        cp = cross_predict(pipeline, data, y, splits, on_fold=bar.update)
        scores = held_out_scores(y, cp, groups, classes, n_bootstrap, seed)
        cm = confusion(y[cp.scored], cp.predicted[cp.scored], classes)
        ev = Evaluation(
            target=target, split=split, estimator=estimator, channels=channels,
            families=families, classes=classes,
            class_counts={c: int((y == c).sum()) for c in classes}, n_rows=len(data),
            folds=[{"name": f.name, "n_train": int(f.train.size),
                    "n_test": int(f.test.size)} for f in splits],
            unscored=cp.unscored, scores=scores, per_class=_per_class(cm, classes),
            confusion=pd.DataFrame(cm, index=pd.Index(classes, name="true"),
                                   columns=pd.Index(classes, name="predicted")),
            predictions=pd.DataFrame({"run_id": data.get("run_id",
                                                         pd.Series(range(len(data)))),
                                      "true": y, "predicted": cp.predicted,
                                      "scored": cp.scored}),
            channel_choice=choice)
        ev.confusers = rub_confusers(data, target, cp.predicted, cp.scored, n_bootstrap,
                                     seed)
        if importances:
            ev.importances, ev.channel_importances = _importances(
                cp, data, y, classes, n_repeats, seed, bar.update)
        if baselines:
            ev.baselines = _controls.baselines(data, y, splits, groups, classes, channels,
                                               estimator, n_bootstrap, seed, bar.update)
            with _progress.part(bar, len(splits)) as tick:    # no fits without a casing
                ev.casing = _controls.casing_scores(data, y, splits, groups, classes, channels,
                                                    families, estimator, scores, n_bootstrap,
                                                    seed, tick)
        ev.shuffled = _controls.shuffled_control(
            pipeline, data, y, groups, lambda labels: folds(
                data, split, labels, n_splits=n_splits, bands=bands, seed=seed),
            classes, n_null, n_shuffles, seed, bar.update)
        if audit:
            ev.audit = _controls.audit_columns(data, y, splits, classes, audit_threshold,
                                               seed, on_fold=bar.update)
    ev.warnings = training_warnings(ev)
    return ev


def _per_class(cm: np.ndarray, classes) -> pd.DataFrame:
    tp = np.diag(cm).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        precision = tp / cm.sum(axis=0)
        recall = tp / cm.sum(axis=1)
        f1 = 2 * precision * recall / (precision + recall)
    return pd.DataFrame({"precision": precision, "recall": recall, "f1": np.nan_to_num(f1),
                         "support": cm.sum(axis=1)}, index=pd.Index(classes, name="class"))


def _importances(cp: CrossPrediction, data, y, classes, n_repeats, seed, on_fold=None):
    """Mean drop of held-out macro-F1 when a feature (in every channel at once) or a
    channel (all its features) is permuted; mean and spread over folds × repeats.

    A fold's permuted copies are predicted together, in one call per
    :data:`_PERMUTED_CELLS` values: a forest's per-call overhead (its 300 trees) would
    otherwise cost more than the predictions themselves."""
    rng = np.random.default_rng(seed)
    by_feature: dict[str, list] = {}
    by_channel: dict[str, list] = {}
    for fold, model in _progress.counted(cp.fitted, on_fold):
        if model is None or not isinstance(model[0], OrderFeatures):
            continue
        test = fold.test[cp.scored[fold.test]]
        Z = model[0].transform(data.iloc[test])
        names = model[0].get_feature_names_out()
        rest = model[1:]
        base = macro_f1(y[test], rest.predict(Z), classes)
        feature_of = np.array([n.split(SEPARATOR, 1)[-1] for n in names])
        channel_of = np.array([n.split(SEPARATOR, 1)[0] if SEPARATOR in n else "(run)"
                               for n in names])
        permuted, owners = [], []
        for key, out in ((feature_of, by_feature), (channel_of, by_channel)):
            for name in dict.fromkeys(key):
                cols = np.flatnonzero(key == name)
                for _ in range(n_repeats):
                    Zp = Z.copy()
                    Zp[:, cols] = Z[rng.permutation(len(Z))][:, cols]
                    permuted.append(Zp)
                    owners.append(out.setdefault(name, []))
        per_call = max(1, _PERMUTED_CELLS // max(Z.size, 1))
        for start in range(0, len(permuted), per_call):
            batch = permuted[start:start + per_call]
            predicted = rest.predict(np.vstack(batch)).reshape(len(batch), len(Z))
            for owner, p in zip(owners[start:start + per_call], predicted, strict=True):
                owner.append(base - macro_f1(y[test], p, classes))

    def table(d, index_name):
        if not d:
            return None
        frame = pd.DataFrame({"importance": {k: np.mean(v) for k, v in d.items()},
                              "std": {k: np.std(v) for k, v in d.items()}})
        frame.index.name = index_name
        return frame.sort_values("importance", ascending=False)
    return table(by_feature, "feature"), table(by_channel, "channel")


#: Feature values per prediction call of the permutation importances (8 MB of float64).
_PERMUTED_CELLS = 1_000_000
