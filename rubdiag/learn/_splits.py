"""Train/test splits that do not leak: no design point, and optionally no factor band, on
both sides.

``split="group"``: stratified K-fold over design points (``point_id``): the replicates of a
point (near-copies) always fall on the same side. ``split=<factor>`` (``case``,
``speed_ratio``, ``gap_mm``, ``mu`` … any design factor of the data): leave one band out —
the factor's values over the design points cut into ``bands`` quantile bands (or, with
``bands`` levels or fewer, one fold per level, as for ``case``): the model is scored on a
range of the factor it never saw. Bands are cut on design points, so replicates share a
band too.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd
from sklearn.model_selection import StratifiedGroupKFold

from rubdiag import _check
from rubdiag.learn._columns import factor_columns

__all__ = ["Fold", "folds", "in_band", "split_names"]


@dataclass(frozen=True)
class Fold:
    """One split: row positions of the training and the test side, and what was held out.

    Parameters
    ----------
    name : str
        What was held out.
    train, test : numpy.ndarray
        Row positions of the two sides (int).
    """

    name: str
    train: np.ndarray
    test: np.ndarray


def in_band(data: pd.DataFrame, factor: str, lo: float, hi: float) -> np.ndarray:
    """Which rows of ``data`` have the design factor ``factor`` within ``lo`` … ``hi``
    (both included): a band to hold out of training and score a model on (a level of a
    model-uncertainty factor, a speed band, a case). A row whose factor is blank is not
    in any band."""
    if factor not in factor_columns(data):
        raise ValueError(f"band: {factor!r} is not a design factor of the data (allowed: "
                         f"{', '.join(factor_columns(data)) or 'none'})")
    lo = _check.number("band lo", lo)
    hi = _check.number("band hi", hi, lo=lo)
    values = pd.to_numeric(data[factor], errors="coerce").to_numpy(dtype=np.float64)
    inside = (values >= lo) & (values <= hi)
    if not inside.any():
        raise ValueError(f"band: no row has {factor} within {lo:g} … {hi:g} (its values: "
                         f"{np.nanmin(values):g} … {np.nanmax(values):g})")
    return inside


def split_names(data: pd.DataFrame) -> list[str]:
    """The splits ``data`` allows: ``group`` and one per design factor among its columns."""
    return ["group", *factor_columns(data)]


def folds(data: pd.DataFrame, split: str = "group", y=None, *, n_splits: int = 5,
          bands: int = 5, seed: int = 0) -> list[Fold]:
    """The folds of ``split`` over the rows of ``data`` (module docstring); ``y`` (the
    target) stratifies the ``group`` split.

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).
    split : str
        ``"group"`` or a design factor.
    y : numpy.ndarray or None
        The target, which stratifies the group split.
    n_splits : int
        Folds of the group split.
    bands : int
        Bands of a factor split.
    seed : int
        Seed of the group split.

    Returns
    -------
    list of Fold
        The folds.
    """
    allowed = split_names(data)
    if split not in allowed:
        raise ValueError(f"split = {split!r} is not available (allowed: {', '.join(allowed)})")
    if "point_id" not in data.columns:
        raise ValueError("the data has no point_id column: a dataset's rows are needed")
    if split == "group":
        return _group_folds(data, y, _check.integer("n_splits", n_splits, lo=2), seed)
    return _band_folds(data, split, _check.integer("bands", bands, lo=2))


def _group_folds(data, y, n_splits, seed) -> list[Fold]:
    groups = data["point_id"].to_numpy()
    n_groups = len(np.unique(groups))
    if n_groups < n_splits:
        raise ValueError(f"n_splits = {n_splits} is out of range (allowed: <= {n_groups}, "
                         "the number of design points)")
    labels = np.zeros(len(data)) if y is None else np.asarray(y)
    splitter = StratifiedGroupKFold(n_splits=n_splits, shuffle=True, random_state=seed)
    with warnings.catch_warnings():
        # "the least populated class has fewer members than n_splits": some folds then lack
        # the class, which evaluate() reports per class as unscored rows
        warnings.filterwarnings("ignore", "The least populated class", UserWarning)
        pairs = list(splitter.split(data, labels, groups))
    return [Fold(f"group fold {i + 1}/{n_splits}", train, test)
            for i, (train, test) in enumerate(pairs)]


def _band_folds(data, factor, bands) -> list[Fold]:
    points = data.drop_duplicates("point_id").set_index("point_id")[factor]
    values = points.to_numpy()
    levels = np.unique(values)
    if levels.size < 2:
        raise ValueError(f"split = {factor!r}: the factor takes one value in the data; "
                         "nothing to hold out")
    if levels.size <= bands:
        codes = np.searchsorted(levels, values)
    else:
        codes = pd.qcut(values, bands, labels=False, duplicates="drop")
    band_of = pd.Series(codes, index=points.index)
    row_band = data["point_id"].map(band_of).to_numpy()
    out = []
    for b in np.unique(codes):
        held = values[codes == b]
        # named by the values held out: qcut's bands are (lo, hi], and the lower edge
        # itself belongs to the band below, on the training side
        lo, hi = held.min(), held.max()
        name = f"{factor} = {lo:g}" if lo == hi else f"{factor} in [{lo:g}, {hi:g}]"
        out.append(Fold(f"held out: {name}", np.flatnonzero(row_band != b),
                        np.flatnonzero(row_band == b)))
    return out
