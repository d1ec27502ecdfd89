"""What the columns of a dataset are, and the one reader of a dataset folder learn uses.

A dataset row (:mod:`rubdiag.dataset._rows`) holds ids, design factors, the run's speed,
label measures, labels, ``CHANNEL__FEATURE`` spectral features, simulator truth
(``contact<k>__…``, ``contacts__…``, ``truth__…``) and provenance. Only the channels' spectral
features (and, opt-in, the speed) describe what a sensor on a machine could see; everything
else is a label, a leak or bookkeeping. Nothing here imports the simulator.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pandas as pd

from rubdiag.dataset import FACTORS, NoiseFloors, acquisition, load
from rubdiag.dataset._labels import LABELS
from rubdiag.dataset._schema import SEPARATOR
from rubdiag.signal._table import FEATURE_NAMES, SPEED_NAMES

__all__ = ["LINE_FEATURES", "TARGETS", "TARGET_COLUMNS", "casing_channels", "channels_of",
           "factor_columns", "read_dataset", "shaft_channels"]

#: The features of one channel (the speed columns are the record's, not a channel's).
LINE_FEATURES = tuple(n for n in FEATURE_NAMES if n not in SPEED_NAMES)
#: What a classifier can be trained to predict: the labels of :mod:`rubdiag.dataset._labels`
#: and ``fault``, the faults that acted (the ``faults`` label: ``none``, ``rub``,
#: ``crack``, ``rub+crack`` …), of a dataset whose design has a ``fault`` factor.
TARGETS = (*LABELS, "fault")
#: The column a target is read from, where it is not the target's own name.
TARGET_COLUMNS = {"fault": "faults"}


def read_dataset(root: str | Path) -> pd.DataFrame:
    """The rows of a dataset folder that finished (``status == "ok"``), with what learn
    needs to know of it in ``attrs``: ``acquisition`` (``fs_hz``, ``window_s``, sensors
    with their units and points), ``noise_floors`` (channel -> standard deviation of the
    white noise the design added to it, in the channel's SI unit), ``failed`` (rows left
    out) and ``source`` (the folder).

    Parameters
    ----------
    root : str or Path
        The dataset folder.

    Returns
    -------
    pandas.DataFrame
        The finished rows.
    """
    rows = load(root)           # first: it says when the folder is not a dataset at all
    meta = acquisition(root)
    if rows.empty:
        raise ValueError(f"{root}: the dataset holds no rows yet")
    ok = rows["status"] == "ok"
    # in design order, not in the order the workers finished: folds, bootstrap and
    # shuffles follow row positions, so the same dataset must give the same rows
    data = rows[ok].sort_values(["point_id", "replicate"], kind="stable").reset_index(drop=True)
    if data.empty:
        raise ValueError(f"{root}: no run of the dataset finished (status ok)")
    design = tomllib.loads((Path(root) / "design.toml").read_text(encoding="utf-8"))
    floors = NoiseFloors(**design.get("noise", {}))
    data.attrs.update(acquisition=meta, factors=list(design.get("factors", {})),
                      noise_floors={s["name"]: floors.floor(s["quantity"])
                                    for s in meta["sensors"]},
                      failed=int((~ok).sum()), source=str(root))
    return data


def channels_of(data: pd.DataFrame) -> list[str]:
    """The sensor channels of a dataset frame, in column order: every ``C`` with the full
    set of ``C__<feature>`` columns (truth columns such as ``contact1__…`` have not).

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).

    Returns
    -------
    list of str
        The channels.
    """
    present = set(data.columns)
    seen = []
    for name in data.columns:
        channel = str(name).split(SEPARATOR, 1)[0] if SEPARATOR in str(name) else None
        if channel is None or channel in seen:
            continue
        if all(f"{channel}{SEPARATOR}{f}" in present for f in LINE_FEATURES):
            seen.append(channel)
    return seen


def casing_channels(data: pd.DataFrame) -> list[str]:
    """Channels measured on the casing: from the sensors' points (``casing …``) when the
    frame came from :func:`read_dataset`, else from the name (``casing…``).

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).

    Returns
    -------
    list of str
        The channels.
    """
    sensors = data.attrs.get("acquisition", {}).get("sensors")
    if sensors:
        on_casing = {s["name"] for s in sensors if str(s["point"]).startswith("casing")}
        return [c for c in channels_of(data) if c in on_casing]
    return [c for c in channels_of(data) if c.lower().startswith("casing")]


def shaft_channels(data: pd.DataFrame) -> list[str]:
    """The channels not on the casing: the default input of a classifier (in this model
    the casing moves only through contact, so a casing channel gives rub away by itself;
    a real casing also sees the rotor through its supports).

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).

    Returns
    -------
    list of str
        The channels.
    """
    casing = set(casing_channels(data))
    return [c for c in channels_of(data) if c not in casing]


def factor_columns(data: pd.DataFrame) -> list[str]:
    """The design's factors among the columns (``case``, ``speed_ratio``, ``gap_mm`` …): those
    of its ``design.toml`` when the frame came from :func:`read_dataset`, else every
    column named as a factor. ``speed_rpm`` is one only when the design set it (every
    row has the run's speed)."""
    named = data.attrs.get("factors")
    if named is None:
        named = [c for c in FACTORS if c != "speed_rpm"]
    return [c for c in data.columns if c in named]
