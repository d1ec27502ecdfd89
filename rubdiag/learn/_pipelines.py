"""Classifier pipelines: features → scaling → estimator, plain scikit-learn objects.

``make_pipeline("rf")`` returns a :class:`sklearn.pipeline.Pipeline` of three named steps —
``features`` (:class:`~rubdiag.learn._features.OrderFeatures`), ``scale``
(:class:`~sklearn.preprocessing.StandardScaler`) and ``model`` — that prints, clones and
grid-searches as any other (``model__max_depth``, ``features__families`` …). Every
estimator weighs classes by their inverse frequency: rub datasets are rarely balanced,
and an unweighted model buys accuracy by never predicting the rare class.
"""

from __future__ import annotations

from sklearn.calibration import CalibratedClassifierCV
from sklearn.ensemble import HistGradientBoostingClassifier, RandomForestClassifier
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC

from rubdiag.learn._features import DEFAULT_FAMILIES, OrderFeatures, SelectColumns

__all__ = ["ESTIMATORS", "baseline_pipeline", "make_estimator", "make_pipeline"]

#: ``--estimator`` names: random forest (the default: no tuning needed, robust to the
#: many weak, correlated features of a spectrum), histogram gradient boosting, an RBF
#: support-vector machine (probabilities by sigmoid calibration over 3 folds: it needs
#: 3 training rows of every class) and logistic regression.
ESTIMATORS = ("rf", "hgb", "svm", "logreg")


def make_estimator(name: str = "rf", random_state: int = 0):
    """An unfitted classifier by ``--estimator`` name (see :data:`ESTIMATORS`).

    Parameters
    ----------
    name : {"rf", "hgb", "svm", "logreg"}
        The classifier.
    random_state : int
        Its seed.

    Returns
    -------
    sklearn estimator
        Unfitted.
    """
    if name == "rf":
        return RandomForestClassifier(n_estimators=300, min_samples_leaf=1,
                                      class_weight="balanced", n_jobs=1,
                                      random_state=random_state)
    if name == "hgb":
        return HistGradientBoostingClassifier(max_iter=200, learning_rate=0.1,
                                              class_weight="balanced",
                                              random_state=random_state)
    if name == "svm":
        # Platt-scaled probabilities from a 3-fold calibration (scikit-learn's replacement
        # for SVC(probability=True), deprecated in 1.9): every class needs >= 3 training rows
        return CalibratedClassifierCV(SVC(C=10.0, gamma="scale", class_weight="balanced"),
                                      method="sigmoid", cv=3, ensemble=False)
    if name == "logreg":
        return LogisticRegression(C=1.0, max_iter=5000, class_weight="balanced")
    raise ValueError(f"estimator = {name!r} is not known (allowed: {', '.join(ESTIMATORS)})")


def make_pipeline(estimator: str = "rf", *, channels=None, families=DEFAULT_FAMILIES,
                  random_state: int = 0) -> Pipeline:
    """Features of ``channels`` (None: all of the training data's) in ``families`` →
    scaling → the ``estimator``: an unfitted :class:`~sklearn.pipeline.Pipeline`.

    Parameters
    ----------
    estimator : {"rf", "hgb", "svm", "logreg"}
        The classifier.
    channels : sequence of str or None
        The input channels.
    families : sequence of str
        Feature families (:mod:`rubdiag.learn._features`).
    random_state : int
        The classifier's seed.

    Returns
    -------
    sklearn.pipeline.Pipeline
        Unfitted.
    """
    return Pipeline([
        ("features", OrderFeatures(channels=channels, families=families)),
        ("scale", StandardScaler()),
        ("model", make_estimator(estimator, random_state)),
    ])


def baseline_pipeline(columns, estimator: str = "rf", random_state: int = 0) -> Pipeline:
    """The same estimator on the raw ``columns`` only (a baseline: what they alone give).

    Parameters
    ----------
    columns : sequence of str
        The raw columns (design factors, or features).
    estimator : {"rf", "hgb", "svm", "logreg"}
        The classifier.
    random_state : int
        Its seed.

    Returns
    -------
    sklearn.pipeline.Pipeline
        Unfitted.
    """
    return Pipeline([
        ("features", SelectColumns(columns=tuple(columns))),
        ("scale", StandardScaler()),
        ("model", make_estimator(estimator, random_state)),
    ])
