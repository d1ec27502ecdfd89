"""Labelled records: signal files with their labels, to score a saved model on records it
was not trained on (another machine's, another simulator's, textbook ones).

A labelled record list is a CSV table, one row per signal file:

``file``
    The file (any that :func:`rubdiag.predict` reads), its path absolute or relative to the
    list's folder.
the label
    A column named as the model's target (``rub``: True/False, ``severity``, ``rub_state``)
    or ``faults``, the faults that acted (``none``, ``rub``, ``crack``, ``rub+crack`` …: a
    ``fault`` model's label, and ``rub`` follows from it).
``kind`` (optional)
    What the record is, in any words (``2x``, ``seal rub`` …): the scores are given per kind
    (:func:`rubdiag.learn._confusers.kind_table`); without it, per ``faults`` label or class.
``speed_rpm`` (optional)
    The record's running speed (rpm; empty: its tacho or the estimate), as in
    ``rubdiag predict --speeds``.

Other columns are kept and ignored. :func:`read_records` reads and checks a list,
:func:`predict_records` predicts each file as ``rubdiag predict`` does (window by window,
then the majority of its windows).
"""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from rubdiag.learn._columns import TARGET_COLUMNS, TARGETS
from rubdiag.learn._confusers import rubbed

__all__ = ["LABEL_COLUMNS", "is_record_list", "predict_records", "read_records"]

#: The columns that may hold a record's label.
LABEL_COLUMNS = tuple(dict.fromkeys(TARGET_COLUMNS.get(t, t) for t in TARGETS))


def is_record_list(path) -> bool:
    """Whether ``path`` names a labelled record list (a ``.csv`` file, not a folder)."""
    path = Path(path)
    return path.suffix.lower() == ".csv" and not path.is_dir()


def read_records(path) -> pd.DataFrame:
    """The rows of a labelled record list (module docstring), ``file`` made absolute, a
    ``rub`` column added from ``faults`` where only that is given, ``run_id`` the file's
    name (records are their own groups); ``attrs["source"]`` is the list's path.

    Parameters
    ----------
    path : str or Path
        The record list (CSV).

    Returns
    -------
    pandas.DataFrame
        One row per record.

    Raises
    ------
    ValueError
        No ``file`` column, no label column, an empty list, a file listed twice or missing.
    """
    path = Path(path)
    try:
        table = pd.read_csv(path, dtype={"file": str, "kind": str, "faults": str},
                            skipinitialspace=True)
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such file") from None
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a CSV table of labelled records "
                         f"({str(exc).splitlines()[0]})") from None
    if "file" not in table.columns:
        raise ValueError(f"{path}: no column 'file' (a labelled record list has file and a "
                         f"label column: {', '.join(LABEL_COLUMNS)})")
    if not any(c in table.columns for c in LABEL_COLUMNS):
        raise ValueError(f"{path}: no label column (allowed: {', '.join(LABEL_COLUMNS)})")
    if table.empty:
        raise ValueError(f"{path}: the list names no record")
    files = [os.path.normpath(path.parent / f.strip()) for f in table["file"].astype(str)]
    twice = pd.Index(files)[pd.Index(files).duplicated()]
    if len(twice):
        raise ValueError(f"{path}: {twice[0]} is listed twice (allowed: one row per record)")
    missing = [f for f in files if not Path(f).is_file()]
    if missing:
        raise ValueError(f"{path}: {len(missing)} listed files do not exist (the first: "
                         f"{missing[0]})")
    table["file"] = files
    if "rub" not in table.columns and "faults" in table.columns:
        table["rub"] = rubbed(table["faults"])
    table["run_id"] = [Path(f).name for f in files]
    table.attrs["source"] = str(path)
    return table


def predict_records(model, records: pd.DataFrame) -> pd.DataFrame:
    """The prediction of each record of ``records`` (:func:`read_records`): the row of
    :func:`rubdiag.learn._predict.predict` whose ``window`` is ``"all"`` (the majority of its
    windows), in the order of ``records``, with ``warnings`` the warnings of its windows
    (joined; empty if none)."""
    from rubdiag.learn._predict import predict

    files = list(records["file"])
    speeds = (dict(zip(files, (None if pd.isna(v) else float(v) for v in records["speed_rpm"]),
                       strict=True))
              if "speed_rpm" in records.columns else None)
    table = predict(model, files, speed_rpm=speeds)
    windows = table[table["window"] != "all"]
    said = windows.groupby("input", sort=False)["warnings"].agg(
        lambda w: " | ".join(dict.fromkeys(x for x in w if x)))
    whole = table[table["window"] == "all"].set_index("input").loc[files]
    whole["warnings"] = said.reindex(files).fillna("").to_numpy()
    whole.index.name = "input"
    whole["predicted"] = whole["predicted"].astype(str)
    return whole.reset_index()
