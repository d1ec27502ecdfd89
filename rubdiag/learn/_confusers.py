"""Rub against the faults that look like it: how often a model calls a run without rub
rubbing, per fault that did act, and how often it still finds rub beside each fault.

On a dataset whose runs carry the ``faults`` label (the faults that acted, joined by
``+``, rub first; ``none``), a rub detector — or a fault classifier, read as "the class
names rub" — is scored per *confuser*:

* **false rub alarm** of fault k: the share of runs without rub that had k (``none``: the
  healthy runs) which the model calls rubbing — a run with two confusers
  (``looseness+whirl``) counts for both;
* **rub recall** with k: the share of runs that rubbed beside k (``rub+k``; ``rub`` alone
  as the reference) which the model calls rubbing.

Each share comes with the number of runs it is taken over and a 95 % interval from the
bootstrap over design points of :mod:`rubdiag.learn._metrics`. A row without runs is NaN
with ``n`` = 0: a design may leave a fault out, or a split hold none of it out.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from rubdiag.dataset._fault_levels import FAULT_KINDS
from rubdiag.learn._metrics import group_rate, wilson_interval

__all__ = ["CONFUSERS", "CONFUSER_COLUMNS", "KIND_COLUMNS", "calls_rub", "confuser_lines",
           "confuser_table", "has_confusers", "kind_lines", "kind_table", "rub_confusers",
           "rubbed"]

#: The runs a rub alarm can be false on: healthy ones and each fault beside rub.
CONFUSERS = ("none", *FAULT_KINDS)
#: The columns of :func:`confuser_table`.
CONFUSER_COLUMNS = ("measure", "faults", "n", "n_called_rub", "rate", "lo", "hi")
#: The columns of :func:`kind_table`.
KIND_COLUMNS = ("kind", "measure", "n", "n_called_rub", "rate", "lo", "hi")

_ALARM = "false rub alarm"
_RECALL = "rub recall"


def _parts(label) -> set[str]:
    text = str(label)
    return set() if text == "none" else set(text.split("+"))


def calls_rub(predicted) -> np.ndarray:
    """Per predicted class, whether it says the rotor rubs: ``True``/``"True"`` (a ``rub``
    target) or a fault class that names rub (``"rub"``, ``"rub+crack"`` …)."""
    return np.array([str(p) == "True" or "rub" in _parts(p) for p in predicted], dtype=bool)


def has_confusers(faults) -> bool:
    """Whether any run of a ``faults`` column had a fault other than rub."""
    return any(_parts(f) & set(FAULT_KINDS) for f in pd.unique(np.asarray(faults, dtype=str)))


def confuser_table(true_faults, predicted, groups, scored=None, n_bootstrap: int = 1000,
                   seed: int = 0, rub_kinds=None) -> pd.DataFrame:
    """False rub alarms per confuser and rub recall beside each (module docstring).

    Parameters
    ----------
    true_faults : array of str
        The ``faults`` label of each run (``"none"``, ``"crack"``, ``"rub+crack"`` …).
    predicted : array
        The model's class of each run: ``True``/``False`` (or their strings) for a rub
        target, a ``faults`` class for a fault target (:func:`calls_rub`).
    groups : array
        The design point of each run: the bootstrap draws them.
    scored : array of bool, optional
        The runs to count (held out and scored); default all.
    n_bootstrap, seed : int
        Bootstrap draws of the intervals and their seed.
    rub_kinds : array of str, optional
        What rubbed in each run (a design's ``rub_kind`` factor: ``"blade"``, ``"seal"``;
        empty where nothing did): the rub recall of each kind is added.

    Returns
    -------
    pandas.DataFrame
        One row per ``CONFUSERS`` entry (``measure`` "false rub alarm", ``faults`` the
        confuser) then per ``rub`` and ``rub+<fault>`` (``measure`` "rub recall"; with
        ``rub_kinds``, then per ``rub (<kind>)``: every run in which that kind rubbed), with
        :data:`CONFUSER_COLUMNS`: ``n`` runs, ``n_called_rub`` of them called rubbing,
        ``rate`` = n_called_rub / n, ``lo``, ``hi`` its 95 % interval (NaN when n = 0).
    """
    true_faults = np.asarray(true_faults, dtype=str)
    called = calls_rub(predicted)
    groups = np.asarray(groups)
    if not true_faults.shape == called.shape == groups.shape:
        raise ValueError(f"true_faults, predicted and groups: one value per run needed "
                         f"(got {true_faults.size}, {called.size}, {groups.size})")
    scored = (np.ones(true_faults.size, dtype=bool) if scored is None
              else np.asarray(scored, dtype=bool))
    parts = [_parts(f) for f in true_faults]
    rubbed = np.array(["rub" in p for p in parts], dtype=bool)
    rows = []
    for kind in CONFUSERS:
        had = (true_faults == "none" if kind == "none"
               else np.array([kind in p for p in parts], dtype=bool))
        rows.append((_ALARM, kind, had & ~rubbed))
    rows.append((_RECALL, "rub", true_faults == "rub"))
    for kind in FAULT_KINDS:
        rows.append((_RECALL, f"rub+{kind}",
                     rubbed & np.array([kind in p for p in parts], dtype=bool)))
    if rub_kinds is not None:
        rub_kinds = pd.Series(rub_kinds, dtype=object).fillna("").astype(str).to_numpy()
        for kind in sorted(set(rub_kinds[rubbed]) - {""}):
            rows.append((_RECALL, f"rub ({kind})", rubbed & (rub_kinds == kind)))
    out = []
    for measure, faults, members in rows:
        members = members & scored
        rate = group_rate(called, members, groups, n_bootstrap, seed)
        out.append({"measure": measure, "faults": faults, "n": int(members.sum()),
                    "n_called_rub": int((members & called).sum()), "rate": rate.value,
                    "lo": rate.lo, "hi": rate.hi})
    return pd.DataFrame(out, columns=list(CONFUSER_COLUMNS))


def rub_confusers(data: pd.DataFrame, target: str, predicted, scored=None,
                  n_bootstrap: int = 1000, seed: int = 0) -> pd.DataFrame | None:
    """:func:`confuser_table` of a prediction of ``data`` (groups: ``point_id``, else
    ``run_id``) when it applies: a ``rub`` or ``fault`` target, and a ``faults`` column
    with some fault beside rub; else None."""
    if target not in ("rub", "fault") or "faults" not in data.columns \
            or not has_confusers(data["faults"]):
        return None
    key = "point_id" if "point_id" in data.columns else "run_id"
    return confuser_table(data["faults"].astype(str).to_numpy(), predicted,
                          data[key].to_numpy(), scored, n_bootstrap, seed,
                          data["rub_kind"] if "rub_kind" in data.columns else None)


def confuser_lines(table: pd.DataFrame) -> list[str]:
    """The table in words, one line per row with runs (for a terminal)."""
    lines = []
    for r in table.itertuples():
        if r.n:
            lines.append(f"{r.measure}, {r.faults}: {r.rate:.2f} [{r.lo:.2f}, {r.hi:.2f}] "
                         f"({r.n_called_rub} of {r.n} runs called rubbing)")
        else:
            lines.append(f"{r.measure}, {r.faults}: no run")
    return lines


def rubbed(faults) -> np.ndarray:
    """Per ``faults`` label, whether rub acted (``rub``, ``rub+crack`` …)."""
    return np.array(["rub" in _parts(f) for f in np.asarray(faults, dtype=str)], dtype=bool)


def kind_table(kinds, rubbing, predicted) -> pd.DataFrame:
    """Per kind of record, how often a model calls it rubbing: the false rub alarm rate of
    the kind's records without rub and the rub recall of those with, each with its count
    and Wilson's 95 % interval (:func:`~rubdiag.learn._metrics.wilson_interval`: records of
    another origin are independent of each other, and a rate of 0 of n still has an upper
    bound).

    Parameters
    ----------
    kinds : array of str
        The kind of each record (a ``faults`` label, a textbook kind …).
    rubbing : array of bool
        Whether each record rubs.
    predicted : array
        The model's class of each record (:func:`calls_rub`).

    Returns
    -------
    pandas.DataFrame
        :data:`KIND_COLUMNS`, one row per kind (and per measure where a kind holds records
        with and without rub), in the order the kinds first appear.
    """
    kinds = np.asarray(kinds, dtype=str)
    rubbing = np.asarray(rubbing, dtype=bool)
    called = calls_rub(predicted)
    if not kinds.shape == rubbing.shape == called.shape:
        raise ValueError(f"kinds, rubbing and predicted: one value per record needed (got "
                         f"{kinds.size}, {rubbing.size}, {called.size})")
    rows = []
    for kind in dict.fromkeys(kinds):
        for rubs, measure in ((False, _ALARM), (True, _RECALL)):
            members = (kinds == kind) & (rubbing == rubs)
            n, hits = int(members.sum()), int((members & called).sum())
            if n:
                rows.append({"kind": kind, "measure": measure, "n": n, "n_called_rub": hits,
                             "rate": hits / n, **dict(zip(("lo", "hi"),
                                                          wilson_interval(hits, n),
                                                          strict=True))})
    return pd.DataFrame(rows, columns=list(KIND_COLUMNS))


def kind_lines(table: pd.DataFrame) -> list[str]:
    """:func:`kind_table` in words, one line per row (for a terminal)."""
    return [f"{r.kind}: {r.measure} {r.rate:.2f} [{r.lo:.2f}, {r.hi:.2f}] ({r.n_called_rub} "
            f"of {r.n} called rubbing)" for r in table.itertuples()]
