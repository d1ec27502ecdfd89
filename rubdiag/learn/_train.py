"""Train a classifier on a dataset and save it, with its evaluation, as a model folder.

:func:`train` evaluates the pipeline honestly first (:func:`rubdiag.learn._evaluate`:
cross-validated on the chosen split), then fits it on every row and writes

``model.skops``, ``model.json``
    The fitted pipeline and what prediction needs (:mod:`rubdiag.learn._persist`;
    :func:`model_meta` lists the fields).
``metrics.json``, ``report.md``
    The evaluation (:meth:`Evaluation.to_dict`, :meth:`Evaluation.to_markdown`).
``confusion.png``, ``importances.png``, ``importances.csv``
    Its figures and the permutation importances (these two only when computed).

Everything is written into a hidden sibling folder that is renamed into place at the end:
an interrupted training leaves no half model. :func:`evaluate` scores a saved model
on another dataset.

The default model — target ``rub``, a random forest, split by design point, the shaft
channels that carry more than their noise floor (:mod:`rubdiag.learn._channel_choice`) —
needs no tuning, does not lean on the casing (in this model the casing moves only through
contact, so a casing channel gives rub away by itself), needs no probe that sees only
noise, and is scored on design points it never saw. What says that a model learnt little
(:mod:`rubdiag.learn._caveats`) is written into its report, ``metrics.json`` and
``model.json``; ``model.json`` also lists the training runs, so that a later evaluation
can say whether it is in-sample.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag import _progress
from rubdiag._version import __version__
from rubdiag.dataset._schema import SEPARATOR
from rubdiag.learn._columns import read_dataset
from rubdiag.learn._confusers import (
    confuser_lines,
    kind_lines,
    kind_table,
    rub_confusers,
    rubbed,
)
from rubdiag.learn._evaluate import Evaluation, cross_validate, resolve_channels, target_values
from rubdiag.learn._features import DEFAULT_FAMILIES
from rubdiag.learn._metrics import Score, confusion, score
from rubdiag.learn._persist import Model, is_model_dir, load_meta, load_model, save_model
from rubdiag.learn._pipelines import make_pipeline
from rubdiag.learn._records import is_record_list, predict_records, read_records
from rubdiag.learn._report import confuser_records
from rubdiag.learn._sample_rate import required_fs
from rubdiag.learn._splits import in_band
from rubdiag.signal._combinations import SUM_ORDERS
from rubdiag.signal._options import Options
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label
from rubdiag.signal._sidebands import HALF_WIDTH_ORDERS

__all__ = ["ModelScores", "band_rows", "check_out", "evaluate", "model_meta",
           "order_reach", "record_kinds", "required_fs", "runs_digest", "train",
           "training_runs"]

def train(dataset, out, target: str = "rub", estimator: str = "rf", split: str = "group",
          channels="auto", seed: int = 0, *, families=DEFAULT_FAMILIES,
          overwrite: bool = False, progress: bool = False, leave_out=None,
          **evaluate_options) -> Model:
    """Evaluate, fit on all rows and save a classifier (module docstring).

    Parameters
    ----------
    dataset : path or DataFrame
        A dataset folder, or its rows from :func:`~rubdiag.learn._columns.read_dataset`
        (their ``attrs`` say how the channels were measured).
    out : path
        The model folder to write: new or empty, or a previous model folder with
        ``overwrite=True``.
    target, estimator, split, channels, families, seed
        As for :func:`rubdiag.learn._evaluate`; ``channels`` is ``"auto"`` (default: the
        shaft channels with more than their noise floor), ``"shaft"``, ``"all"`` or a
        list of names.
    overwrite : bool
        Replace the model in ``out``.
    progress : bool
        A bar over the evaluation's fits and the final fit on stderr, when it is a
        terminal.
    leave_out : (str, float, float), optional
        ``(factor, lo, hi)``: train without the rows whose design factor lies in ``lo`` …
        ``hi`` (:func:`band_rows`), to score the model on them afterwards
        (:func:`evaluate` with ``band``): a level of a model-uncertainty factor, a
        speed band, a case.
    **evaluate_options
        Further options of :func:`rubdiag.learn._evaluate` (``n_splits``, ``importances``,
        ``baselines``, ``audit`` …).

    Returns
    -------
    Model
        The fitted pipeline and its description as saved.
    """
    out = check_out(out, overwrite)
    data = read_dataset(dataset) if isinstance(dataset, str | os.PathLike) else dataset
    if "acquisition" not in data.attrs:
        raise ValueError("dataset: the rows carry no acquisition (read them with "
                         "rubdiag.learn.read_dataset, or pass the folder)")
    if leave_out is not None:
        data = band_rows(data, *leave_out, inside=False)
    resolve_channels(data, channels)          # a wrong name fails before the evaluation
    families = list(families)
    with _progress.bar(1, "train", "fit", progress) as bar:    # the evaluation adds its own
        evaluation = cross_validate(data, target, split, estimator, channels=channels,
                              families=families, seed=seed, progress=bar, **evaluate_options)
        channels = evaluation.channels
        pipeline = make_pipeline(estimator, channels=channels, families=families,
                                 random_state=seed)
        pipeline.fit(data, target_values(data, target))
        bar.update()
    meta = model_meta(pipeline, data, target=target, estimator=estimator, split=split,
                      families=families, seed=seed, evaluation=evaluation)
    with _new_folder(out) as tmp:
        save_model(pipeline, tmp, meta)
        _write_evaluation(evaluation, tmp)
    return Model(pipeline=pipeline, meta=load_meta(out))


def check_out(out, overwrite: bool = False, option: str = "out") -> Path:
    """``out`` as a Path if a model may be written there: absent, an empty folder, or a
    model folder with ``overwrite``; else a ValueError naming ``option``."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{option} {out}: is a file, not a folder")
    if out.is_dir() and any(out.iterdir()):
        if not is_model_dir(out):
            raise ValueError(f"{option} {out}: is not empty and holds no model (allowed: a "
                             "new or empty folder, or a model folder to overwrite)")
        if not overwrite:
            raise ValueError(f"{option} {out}: holds a model already (allowed: a new or "
                             "empty folder; overwrite to replace it)")
    return out


class _new_folder:
    """A hidden sibling of ``out`` to write into, renamed to ``out`` on success (an
    existing ``out`` is moved aside first and removed after), removed on failure."""

    def __init__(self, out: Path):
        self.out = out
        stem = f".{out.name}.{os.getpid()}"
        self.tmp = out.parent / f"{stem}.partial"
        self.old = out.parent / f"{stem}.replaced"

    def __enter__(self) -> Path:
        self.out.parent.mkdir(parents=True, exist_ok=True)
        shutil.rmtree(self.tmp, ignore_errors=True)
        self.tmp.mkdir()
        return self.tmp

    def __exit__(self, kind, value, tb) -> None:
        if kind is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            return
        if self.out.exists():
            os.replace(self.out, self.old)
        os.replace(self.tmp, self.out)
        shutil.rmtree(self.old, ignore_errors=True)


def _write_evaluation(ev: Evaluation, folder: Path) -> None:
    from rubdiag.learn._figures import confusion_figure, importances_figure

    (folder / "metrics.json").write_text(
        json.dumps(ev.to_dict(), indent=1, default=_json_default) + "\n", encoding="utf-8")
    (folder / "report.md").write_text(ev.to_markdown(), encoding="utf-8")
    confusion_figure(ev, folder / "confusion.png")
    if ev.importances is not None and not ev.importances.empty:
        ev.importances.to_csv(folder / "importances.csv")
        importances_figure(ev, folder / "importances.png", top=20)


def _json_default(value):
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


# --- what prediction needs ------------------------------------------------------------


def model_meta(pipeline, data: pd.DataFrame, *, target: str, estimator: str, split: str,
               families, seed: int, evaluation: Evaluation | None = None) -> dict:
    """The description of a pipeline fitted on ``data`` (all rows) that prediction needs:
    versions, target and classes, channels with their units, feature options, window and
    sampling rate, the speed and feature ranges seen in training, the highest order the
    kept features reach and the sampling rate it needs, where the model came from and the
    runs it was fitted on (:func:`training_runs`); with ``evaluation``, its scores, its
    warnings (:mod:`rubdiag.learn._caveats`), the channels the default set left out and the
    held-out false rub alarms per confuser (null where they do not apply)."""
    import sklearn

    acq = data.attrs["acquisition"]
    features = pipeline.named_steps["features"]
    sensors = {s["name"]: s for s in acq["sensors"]}
    missing = [c for c in features.channels_ if c not in sensors]
    if missing:
        raise ValueError(f"channel {missing[0]!r} is not among the dataset's sensors")
    options = dataclasses.asdict(Options())
    speed = data["speed_rpm"].to_numpy(dtype=np.float64)
    Z = features.transform(data)
    names = [str(n) for n in features.get_feature_names_out()]
    order, reach, column = max(
        ((*order_reach(c, options["band"]), c) for c in features.required_),
        key=lambda r: r[1])
    y = target_values(data, target)
    meta = {
        "rubdiag_version": __version__,
        "sklearn_version": sklearn.__version__,
        "target": target,
        "classes": [str(c) for c in pipeline.classes_],
        "class_counts": {c: int((y == c).sum()) for c in pipeline.classes_},
        "estimator": estimator,
        "seed": seed,
        "channels": [{k: sensors[c][k] for k in ("name", "unit", "quantity", "point",
                                                 "direction")} for c in features.channels_],
        "families": list(families),
        "feature_options": options,
        "window_s": float(acq["window_s"]),
        "fs_hz": float(acq["fs_hz"]),
        "speed_range_rpm": [float(speed.min()), float(speed.max())],
        "feature_ranges": {n: [float(lo), float(hi)] for n, lo, hi
                           in zip(names, Z.min(axis=0), Z.max(axis=0), strict=True)},
        "highest_order": {"order": order, "reach": reach, "feature": column,
                          "fs_required_hz": required_fs(reach, speed.max(), acq["window_s"])},
        "dataset": {"path": str(Path(data.attrs.get("source", "")).resolve())
                    if data.attrs.get("source") else None,
                    "n_rows": len(data), "failed_rows": int(data.attrs.get("failed", 0))},
        "split": split,
        "training_runs": training_runs(data),
    }
    if evaluation is not None:
        meta["warnings"] = list(evaluation.warnings)
        meta["channels_left_out"] = ({} if evaluation.channel_choice is None
                                     else evaluation.channel_choice.left_out_json())
        # NaN (no bootstrap) as null: strict JSON
        meta["scores"] = {k: {n: None if np.isnan(x) else x for n, x in v.to_dict().items()}
                          for k, v in evaluation.scores.items()}
        meta["confusers"] = confuser_records(evaluation.confusers)
    return meta


def training_runs(data: pd.DataFrame) -> dict | None:
    """The runs a model is fitted on: ``{"n", "sha256", "ids"}`` — the sorted ``run_id``
    values and the SHA-256 of them joined by newlines (None without a ``run_id``
    column). Run ids name a run's content, so the same run in another folder matches."""
    if "run_id" not in data.columns:
        return None
    ids = sorted(map(str, data["run_id"]))
    return {"n": len(ids), "sha256": runs_digest(ids), "ids": ids}


def runs_digest(ids) -> str:
    """SHA-256 (hex) of sorted run ids joined by newlines."""
    return hashlib.sha256("\n".join(sorted(map(str, ids))).encode()).hexdigest()


def _reaches(band: float) -> dict[str, tuple[float, float]]:
    """Raw feature name -> (order, highest order its search reaches)."""
    out = {"speed_rpm": (0.0, 0.0), "rms": (0.0, 0.0)}
    for k in HALF_ORDERS:
        out[f"amp_{order_label(k)}"] = out[f"freq_{order_label(k)}_hz"] = (k, k + band)
    for k in THIRD_ORDERS:
        out[f"amp_{order_label(k)}"] = (k, k + band)
    fractional = max(k for k in HALF_ORDERS if k != round(k))
    out["n_half_orders"] = (fractional, fractional + band)
    out["n_third_orders"] = (max(THIRD_ORDERS), max(THIRD_ORDERS) + band)
    for n in HARMONICS:
        for name in ("sb_{n}x_delta_hz", "sb_{n}x_lower", "sb_{n}x_upper", "bb_{n}x_rms"):
            out[name.format(n=n)] = (float(n), n + HALF_WIDTH_ORDERS)
    top = float(max(SUM_ORDERS))             # both lines of a pair lie below m×
    for name in ("combo_fa_hz", "combo_fb_hz", "combo_order", "combo_amp_a", "combo_amp_b"):
        out[name] = (top, top)
    return out


def order_reach(column: str, band: float = Options.band) -> tuple[float, float]:
    """(order, highest order searched) of a raw feature column ``C__feature``: an order
    line's band ``k ± band``, a sideband's or broadband's ``n ± 0.25``, a combination's
    3×. ``rms`` and ``speed_rpm`` reach 0."""
    name = column.split(SEPARATOR, 1)[-1]
    try:
        return _reaches(band)[name]
    except KeyError:
        raise ValueError(f"{column!r} is not a feature column") from None


# --- a saved model on another dataset ------------------------------------------------


@dataclass
class ModelScores:
    """A saved model scored on a dataset it was not trained on (:func:`evaluate`).

    Parameters
    ----------
    target : str
        What the model predicts.
    dataset : str
        The data scored (its folder or record list).
    classes : list of str
        The model's classes.
    n_rows, n_scored : int
        Rows of the data, and those scored (of a class the model knows).
    unknown : dict of str to int
        Rows per class of the data that the model does not know.
    scores : dict of str to Score
        Macro-F1 and balanced accuracy with their 95 % intervals, by metric.
    per_class, confusion, predictions : pandas.DataFrame
        Per-class precision and recall, the confusion matrix, every row's prediction.
    warnings : list of str
        The prediction warnings of the rows, each "run: warning".
    shared_runs : int or None
        Runs of the data the model was trained on; None: unknown.
    model_warnings : list of str
        The warnings of the model's training.
    confusers, kinds : pandas.DataFrame or None
        False rub alarms per confuser, and per kind of run or record.
    """

    target: str
    dataset: str
    classes: list
    n_rows: int
    n_scored: int
    unknown: dict                   # class of the data the model does not know -> rows
    scores: dict                    # metric -> Score
    per_class: pd.DataFrame
    confusion: pd.DataFrame
    predictions: pd.DataFrame
    warnings: list
    shared_runs: int | None = None  # runs of the data the model was trained on; None: unknown
    model_warnings: list = dataclasses.field(default_factory=list)   # from its training
    confusers: pd.DataFrame | None = None   # rubdiag.learn._confusers.confuser_table
    kinds: pd.DataFrame | None = None       # rubdiag.learn._confusers.kind_table

    def sample_note(self) -> str:
        """Whether the scores are in-sample: "in-sample: …", "out of sample: …" or
        "training runs unknown: …"."""
        if self.shared_runs is None:
            return ("training runs unknown: the model does not record them (trained before "
                    "rubdiag did, or its record does not match its SHA-256) or the data has "
                    "no run ids")
        if self.shared_runs:
            return (f"in-sample: {self.shared_runs} of these {self.n_rows} runs were in the "
                    "model's training set, so these scores flatter it")
        return "out of sample: no run was in the model's training set"

    def to_dict(self) -> dict:
        def plain(v):
            return None if isinstance(v, float) and np.isnan(v) else v

        return {
            "target": self.target, "dataset": self.dataset, "classes": self.classes,
            "n_rows": self.n_rows, "n_scored": self.n_scored, "unknown": self.unknown,
            "scores": {k: v.to_dict() for k, v in self.scores.items()},
            "per_class": [{"class": str(c), **{k: plain(float(v)) for k, v in row.items()}}
                          for c, row in self.per_class.iterrows()],
            "confusion": {"classes": self.classes,
                          "counts": self.confusion.to_numpy().tolist()},
            "warnings": self.warnings,
            "shared_runs": self.shared_runs, "sample": self.sample_note(),
            "model_warnings": self.model_warnings,
            "confusers": confuser_records(self.confusers),
            "kinds": confuser_records(self.kinds),
        }

    def to_text(self) -> str:
        lines = [f"{self.dataset}: {self.n_scored} of {self.n_rows} runs scored, target "
                 f"{self.target}; {self.sample_note()}"]
        if self.unknown:
            lines.append("not scored (class unknown to the model): "
                         + ", ".join(f"{c} {n}" for c, n in self.unknown.items()))
        lines += [f"{k}: {v}" for k, v in self.scores.items()]
        with pd.option_context("display.float_format", "{:.3f}".format):
            lines += ["", self.per_class.to_string(), "",
                      "confusion (rows true, columns predicted):",
                      self.confusion.to_string()]
        if self.confusers is not None:
            lines += ["", "rub against the faults that look like it (rate [95 % interval]):",
                      *confuser_lines(self.confusers)]
        if self.kinds is not None:
            lines += ["", "per kind of run or record (rate [95 % Wilson interval]):",
                      *kind_lines(self.kinds)]
        return "\n".join(lines)


def evaluate(model, dataset, n_bootstrap: int = 1000, seed: int = 0,
             progress=False, band=None) -> ModelScores:
    """Scores of a saved model on data it was not trained on: a dataset (another rig's,
    another design's, a band of one held out of training) or a labelled record list
    (:mod:`rubdiag.learn._records`: signal files with their labels — another machine's,
    another simulator's, textbook records). Macro-F1 and balanced accuracy with 95 %
    bootstrap intervals over design points (records: each its own), per-class precision
    and recall, the confusion matrix and, for a ``rub`` or ``fault`` model, the false rub
    alarms per confuser (``confusers``, on a dataset with faults beside rub:
    :mod:`rubdiag.learn._confusers`) and per kind of run or record (``kinds``: the
    ``kind`` column of a record list, else the ``faults`` label, else rub or none; with
    Wilson intervals, :func:`~rubdiag.learn._confusers.kind_table`). Rows of a class the
    model does not know are counted (``unknown``) and left out of macro-F1 and balanced
    accuracy. ``shared_runs`` counts the dataset's runs the model was trained on
    (``model.json``'s ``training_runs``; None for a model that predates that record): the
    first line of :meth:`ModelScores.to_text` says "in-sample" when any.

    Parameters
    ----------
    model : Model or path
        From :func:`train` or :func:`~rubdiag.learn._persist.load_model` (or its folder).
    dataset : path or DataFrame
        A dataset folder (or its rows) with the model's channels, in the same units; or a
        labelled record list (a ``.csv`` path, or its rows from
        :func:`~rubdiag.learn._records.read_records`).
    n_bootstrap, seed : int
        Bootstrap draws of the intervals and their seed.
    progress : bool or open bar
        A bar over its steps (reading the model and the data, predicting, scoring) on
        stderr when it is a terminal; or an open bar of :mod:`rubdiag._progress` to count
        them on.
    band : (str, float, float), optional
        ``(factor, lo, hi)``: score only the dataset's rows whose design factor lies in
        ``lo`` … ``hi`` (:func:`~rubdiag.learn._splits.in_band`), e.g. a level of a
        model-uncertainty factor the model was trained without (``train(...,
        leave_out=...)``).

    Returns
    -------
    ModelScores
        The scores, tables and warnings above.
    """
    if isinstance(model, pd.DataFrame):
        raise ValueError("evaluate scores a saved model on a dataset: model = a dataset's rows "
                         "(allowed: a Model or a model folder); cross_validate(data, ...) "
                         "cross-validates a dataset")
    from rubdiag.learn._predict import predict_rows

    loaded = isinstance(model, Model)
    with _progress.shared(progress, 3 + (not loaded), "evaluate") as bar:
        if not loaded:
            _progress.label(bar, "reading the model")
            model = load_model(model)
            bar.update()
        _progress.label(bar, "reading the data")
        if isinstance(dataset, str | os.PathLike):
            data = read_records(dataset) if is_record_list(dataset) else read_dataset(dataset)
        else:
            data = dataset
        records = "file" in data.columns and "point_id" not in data.columns
        if band is not None:
            if records:
                raise ValueError("band: a record list has no design factors (allowed: a band "
                                 "of a dataset)")
            data = band_rows(data, *band)
        y = target_values(data, model.meta["target"])
        bar.update()
        _progress.label(bar, "predicting")
        table = predict_records(model, data) if records else predict_rows(model, data)
        bar.update()
        _progress.label(bar, "scoring")
        scores = _scores_of(model, data, y, table, n_bootstrap, seed)
        bar.update()
    return scores


def band_rows(data: pd.DataFrame, factor: str, lo: float, hi: float, *,
              inside: bool = True) -> pd.DataFrame:
    """The rows of ``data`` whose design factor lies in ``lo`` … ``hi`` (``inside=False``:
    the others), with the data's ``attrs`` and ``attrs["band"]`` saying which."""
    keep = in_band(data, factor, lo, hi)
    out = data[keep if inside else ~keep].reset_index(drop=True)
    out.attrs = {**data.attrs, "band": {"factor": factor, "lo": float(lo), "hi": float(hi),
                                        "inside": inside}}
    return out


def _scores_of(model, data, y, table, n_bootstrap: int, seed: int) -> ModelScores:
    """:func:`evaluate`'s scores of ``model``'s predictions ``table`` of ``data``
    (whose classes are ``y``)."""
    source = str(data.attrs.get("source", "dataset"))
    band = data.attrs.get("band")
    if band:
        source += (f" ({band['factor']} {'' if band['inside'] else 'not '}within "
                   f"{band['lo']:g} … {band['hi']:g})")
    classes = model.classes
    known = np.isin(y, classes)
    unknown = {str(c): int((y[~known] == c).sum()) for c in sorted(set(y[~known]))}
    if not known.any():
        raise ValueError(f"{source}: no run has a class the model knows ({', '.join(classes)}"
                         f"; the data's: {', '.join(sorted(set(y)))})")
    predicted = table["predicted"].to_numpy()
    groups = (data["point_id"] if "point_id" in data.columns else data["run_id"]).to_numpy()
    scores: dict[str, Score] = score(y[known], predicted[known], groups[known], classes,
                                     n_bootstrap, seed)
    cm = confusion(y[known], predicted[known], classes)
    tp = np.diag(cm).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        precision, recall = tp / cm.sum(axis=0), tp / cm.sum(axis=1)
    per_class = pd.DataFrame({"precision": precision, "recall": recall,
                              "support": cm.sum(axis=1)}, index=pd.Index(classes, name="class"))
    predictions = pd.DataFrame({"run_id": table["input"].to_numpy(), "true": y,
                                "predicted": predicted, "scored": known})
    kinds = record_kinds(data, model.meta["target"])
    if kinds is not None:
        predictions["kind"], predictions["rubbing"] = kinds
    warnings = [f"{i}: {w}" for i, w in zip(table["input"], table["warnings"], strict=True)
                if w]
    record = model.meta.get("training_runs")
    ids = record.get("ids") if isinstance(record, dict) else None
    shared = None               # unknown: not recorded, or not the ids its digest names
    if isinstance(ids, list) and record.get("sha256") == runs_digest(ids) \
            and "run_id" in data.columns:
        shared = int(np.isin(data["run_id"].astype(str).to_numpy(), ids).sum())
    return ModelScores(
        target=model.meta["target"], dataset=source, classes=classes, n_rows=len(data),
        n_scored=int(known.sum()), unknown=unknown, scores=scores, per_class=per_class,
        confusion=pd.DataFrame(cm, index=pd.Index(classes, name="true"),
                               columns=pd.Index(classes, name="predicted")),
        predictions=predictions, warnings=warnings, shared_runs=shared,
        model_warnings=list(model.meta.get("warnings", [])),
        # every run was predicted, a class unknown to the model too: all count
        confusers=rub_confusers(data, model.meta["target"], predicted, None, n_bootstrap,
                                seed),
        kinds=None if kinds is None else kind_table(*kinds, predicted))


def record_kinds(data: pd.DataFrame, target: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Each row's kind and whether it rubs, for the per-kind scores of a ``rub`` or
    ``fault`` model (None for other targets): the kind is the ``kind`` column (a record
    list's), else the ``faults`` label, else rub / none, with what rubbed where a design
    says (its ``rub_kind`` factor: ``rub (seal)``); rubbing follows ``faults``, else the
    ``rub`` column."""
    if target not in ("rub", "fault"):
        return None
    if "faults" in data.columns:
        rubbing = rubbed(data["faults"])
    else:
        rubbing = data["rub"].astype(str).str.lower().eq("true").to_numpy()
    kinds = (data["kind"] if "kind" in data.columns
             else data["faults"] if "faults" in data.columns
             else pd.Series(np.where(rubbing, "rub", "none"), index=data.index))
    kinds = kinds.astype(str)
    if "kind" not in data.columns and "rub_kind" in data.columns:
        what = data["rub_kind"]
        kinds = kinds.where(~(rubbing & what.notna().to_numpy()),
                            kinds + " (" + what.astype(str) + ")")
    return kinds.to_numpy(), rubbing
