"""A fitted classifier on disk: the pipeline (skops, never pickle) and what prediction
needs to know (JSON).

A model folder holds

``model.skops``
    The fitted :class:`~sklearn.pipeline.Pipeline` written by :func:`skops.io.dump`.
    Loading it constructs only the types of :data:`TRUSTED_TYPES`: every type named in the
    file, and every type skops itself does not trust
    (:func:`skops.io.get_untrusted_types`), must be listed there, or the file is refused
    before anything in it is built.
``model.json``
    ``format`` / ``format_version`` and the model's description (channels with their
    units, feature options, window length, sampling rate, training ranges …; written by
    :func:`rubdiag.learn._train.train`).

Both files are written atomically; :func:`load_model` refuses a missing, damaged or
foreign file with one ValueError line naming it.
"""

from __future__ import annotations

import io
import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

from rubdiag._atomic import write_bytes, write_text

__all__ = [
    "META_FILE",
    "MODEL_FILE",
    "TRUSTED_TYPES",
    "Model",
    "is_model_dir",
    "load_meta",
    "load_model",
    "save_model",
]

MODEL_FILE = "model.skops"
META_FILE = "model.json"
_FORMAT = "rubdiag.model"
_FORMAT_VERSION = 1

#: Every type a saved pipeline may contain: the rubdiag.learn transformers, and the
#: scikit-learn, numpy and builtin types found by dumping ``make_pipeline(e)`` fitted on a
#: two-class and a three-class target for each of the four estimators
#: (``tests/learn/test_persist.py`` checks that each round-trips). A new estimator means
#: dumping its pipeline and adding what it brings, deliberately.
TRUSTED_TYPES = (
    # rubdiag.learn
    "rubdiag.learn._features.OrderFeatures",
    "rubdiag.learn._features.SelectColumns",
    # the pipeline, its scaler
    "sklearn.pipeline.Pipeline",
    "sklearn.preprocessing._data.StandardScaler",
    # rf
    "sklearn.ensemble._forest.RandomForestClassifier",
    "sklearn.tree._classes.DecisionTreeClassifier",
    "sklearn.tree._tree.Tree",
    # hgb (binary and multinomial losses)
    "sklearn.ensemble._hist_gradient_boosting.gradient_boosting.HistGradientBoostingClassifier",
    "sklearn.ensemble._hist_gradient_boosting.binning._BinMapper",
    "sklearn.ensemble._hist_gradient_boosting.predictor.TreePredictor",
    "sklearn.preprocessing._label.LabelEncoder",
    "sklearn._loss._loss.CyHalfBinomialLoss",
    "sklearn._loss._loss.CyHalfMultinomialLoss",
    "sklearn._loss.link.Interval",
    "sklearn._loss.link.LogitLink",
    "sklearn._loss.link.MultinomialLogit",
    "sklearn._loss.loss.HalfBinomialLoss",
    "sklearn._loss.loss.HalfMultinomialLoss",
    "numpy.random._generator.Generator",
    # svm (calibrated), logreg
    "sklearn.calibration.CalibratedClassifierCV",
    "sklearn.calibration._CalibratedClassifier",
    "sklearn.calibration._SigmoidCalibration",
    "sklearn.svm._classes.SVC",
    "sklearn.linear_model._logistic.LogisticRegression",
    # containers and arrays
    "builtins.dict",
    "builtins.list",
    "builtins.str",
    "builtins.tuple",
    "numpy.ndarray",
    "numpy.float64",
    "numpy.int64",
    "numpy.uint64",
)


@dataclass(frozen=True)
class Model:
    """A loaded model: the fitted ``pipeline`` and its description ``meta`` (model.json).

    Parameters
    ----------
    pipeline : sklearn.pipeline.Pipeline
        The fitted pipeline.
    meta : dict
        Its description.
    """

    pipeline: object
    meta: dict

    @property
    def classes(self) -> list[str]:
        return list(self.meta["classes"])

    @property
    def channels(self) -> list[str]:
        return [c["name"] for c in self.meta["channels"]]


def save_model(pipeline, model_dir: str | Path, meta: dict) -> Path:
    """Write ``pipeline`` to ``model_dir/model.skops`` and ``meta`` to ``model.json``.

    The folder is created if missing. A pipeline holding a type outside
    :data:`TRUSTED_TYPES` is refused here (ValueError), so that no model is saved that
    :func:`load_model` would refuse.

    Parameters
    ----------
    pipeline : sklearn.pipeline.Pipeline
        The fitted pipeline.
    model_dir : str or Path
        The model's folder.
    meta : dict
        Its description (JSON-ready).

    Returns
    -------
    Path
        ``model_dir``.
    """
    import skops.io as sio

    model_dir = Path(model_dir)
    sink = io.BytesIO()
    sio.dump(pipeline, sink)
    data = sink.getvalue()
    untrusted = _untrusted(data=data)
    if untrusted:
        raise ValueError(f"the pipeline holds the type {untrusted[0]!r}, which "
                         "rubdiag.learn._persist.TRUSTED_TYPES does not list: it could not "
                         "be loaded again")
    # strict JSON (no NaN): a model description any reader parses
    text = json.dumps({"format": _FORMAT, "format_version": _FORMAT_VERSION, **meta},
                      indent=1, allow_nan=False)
    model_dir.mkdir(parents=True, exist_ok=True)
    write_bytes(model_dir / MODEL_FILE, data)
    write_text(model_dir / META_FILE, text + "\n")
    return model_dir



def is_model_dir(path: str | Path) -> bool:
    """Whether ``path`` is a folder holding a rubdiag model's ``model.json``."""
    try:
        load_meta(path)
    except ValueError:
        return False
    return True


def load_model(model_dir: str | Path) -> Model:
    """The model saved in ``model_dir`` (see the module docstring).

    Raises
    ------
    ValueError
        One line naming the file: no such folder or file, not a rubdiag model, a damaged
        file, or a type outside :data:`TRUSTED_TYPES` (named).

    Parameters
    ----------
    model_dir : str or Path
        The model's folder.

    Returns
    -------
    Model
        The fitted pipeline and its description.
    """
    import skops.io as sio

    model_dir = Path(model_dir)
    meta = load_meta(model_dir)
    path = model_dir / MODEL_FILE
    if not path.is_file():
        raise ValueError(f"{path}: no such file (the model folder is incomplete)")
    data = path.read_bytes()
    if not zipfile.is_zipfile(io.BytesIO(data)):
        raise ValueError(f"{path}: not a skops file (truncated, damaged or another format)")
    untrusted = _untrusted(data=data, path=path)
    if untrusted:
        raise ValueError(f"{path}: refused: it holds the type {untrusted[0]!r}, which is "
                         "not among the trusted types of a rubdiag model")
    try:
        # every type in the file is in TRUSTED_TYPES (checked above): trust exactly those
        pipeline = sio.load(io.BytesIO(data), trusted=list(TRUSTED_TYPES))
    except Exception as exc:  # a damaged archive can fail anywhere inside skops
        raise ValueError(f"{path}: damaged model file ({type(exc).__name__}: "
                         f"{_first_line(exc)})") from None
    _check_pipeline(pipeline, meta, path)
    return Model(pipeline=pipeline, meta=meta)


def load_meta(model_dir: str | Path) -> dict:
    """The description (``model.json``) of the model in ``model_dir``, checked to be a
    rubdiag model's of this format version (ValueError otherwise)."""
    model_dir = Path(model_dir)
    path = model_dir / META_FILE
    if not model_dir.is_dir():
        what = "is not a folder" if model_dir.exists() else "no such folder"
        raise ValueError(f"{model_dir}: {what} (a model folder written by `rubdiag train` "
                         "is needed)")
    if not path.is_file():
        raise ValueError(f"{model_dir}: not a rubdiag model folder (no {META_FILE})")
    try:
        meta = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: damaged model description ({_first_line(exc)})") from None
    if not isinstance(meta, dict) or meta.get("format") != _FORMAT:
        raise ValueError(f"{path}: not a rubdiag model description")
    if meta.get("format_version") != _FORMAT_VERSION:
        raise ValueError(f"{path}: model format version {meta.get('format_version')!r} "
                         f"(allowed: {_FORMAT_VERSION}); train the model again")
    return meta


def _untrusted(data: bytes, path: Path | None = None) -> list[str]:
    """Types of a skops archive outside :data:`TRUSTED_TYPES`: those skops does not trust
    by default and those named in its schema (skops trusts every scikit-learn estimator;
    a model trusts only its own)."""
    import skops.io as sio

    where = "the pipeline" if path is None else str(path)
    try:
        named = sio.get_untrusted_types(data=data)
        schema = json.loads(zipfile.ZipFile(io.BytesIO(data)).read("schema.json"))
    except Exception as exc:  # damaged archive or schema: skops raises many kinds
        raise ValueError(f"{where}: damaged model file ({type(exc).__name__}: "
                         f"{_first_line(exc)})") from None
    found: dict = {}
    _schema_types(schema, found)            # in the order of the object tree
    found.update(dict.fromkeys(named))
    return [t for t in found if t not in TRUSTED_TYPES]


def _schema_types(node, found: dict) -> None:
    """Collect ``module.class`` of every node of a skops schema into ``found``."""
    if isinstance(node, dict):
        if "__module__" in node and "__class__" in node:
            found.setdefault(f"{node['__module__']}.{node['__class__']}")
        for value in node.values():
            _schema_types(value, found)
    elif isinstance(node, list):
        for value in node:
            _schema_types(value, found)


def _check_pipeline(pipeline, meta: dict, path: Path) -> None:
    """A rubdiag model: features → … → a classifier with the classes model.json names."""
    steps = getattr(pipeline, "named_steps", None)
    if steps is None or "features" not in steps or not hasattr(pipeline, "predict_proba"):
        raise ValueError(f"{path}: not a rubdiag classifier pipeline")
    classes = [str(c) for c in getattr(pipeline, "classes_", [])]
    if classes != [str(c) for c in meta.get("classes", [])]:
        raise ValueError(f"{path}: the pipeline's classes {classes} differ from those of "
                         f"{META_FILE} {meta.get('classes')}")


def _first_line(exc: Exception) -> str:
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__
