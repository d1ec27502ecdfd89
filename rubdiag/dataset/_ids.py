"""Stable identities of runs: ``run_id`` and ``point_id``.

A run is a pure function of its :class:`~rubdiag.simulation.Run`, so its identity is a hash of
the run description — the one result files hold (``rubdiag.simulation``'s ``meta["run"]``:
every ``Run`` field, the rig as in its TOML file, SI units) — with two normalisations, so
that two descriptions of the same simulation get the same id:

- the contact law in force is written out (``contact=None`` and ``contact=rig.contact``
  are the same run);
- the free-text ``label`` is left out (it changes no number of the result).

A full-model run's description has no ``reduction`` key (``run_to_dict`` writes it only when
set), so its ids are those it had before reduced models existed; a reduced run's ids differ
from the full run's of the same cell, ``point_id`` included (another model is another
simulation, not a replicate).

The hash is SHA-256 of canonical JSON — keys sorted, no spaces, every number as a float
written by ``repr`` (shortest round-trip form, so ``1`` and ``1.0``, ``0.0`` and ``-0.0``,
which a ``Run`` compares equal, hash equal), non-finite numbers refused — together with
:data:`SCHEMA_VERSION`, cut to 16 hex digits (64 bits: a collision among a million runs has
a probability of about 3e-8). No ``hash()``: the ids are the same in every process, on
every machine and Python version, and whatever ``PYTHONHASHSEED`` is.

``point_id`` hashes the same description without ``gap_ramp_s``: the replicates of a design
point differ only in their start history (the gap-ramp length, see
:func:`rubdiag.dataset._sampling.gap_ramps_s`), so they share it.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import numbers
import warnings

import numpy as np

from rubdiag.dataset._schema import SCHEMA_VERSION
from rubdiag.simulation import GapRampInWindow, Run
from rubdiag.simulation._run_dict import run_to_dict

__all__ = ["SCHEMA_VERSION", "canonical_run", "point_id", "run_id", "run_ids"]

# SCHEMA_VERSION (rubdiag.dataset._schema) is hashed with the description: raise it when the
# description's meaning changes while its fields do not (a new Run field changes every id).

#: The Run fields that make one replicate of a design point differ from another.
REPLICATE_FIELDS = ("gap_ramp_s",)


def canonical_run(run: Run) -> dict:
    """The description of ``run`` that its ids hash (see the module docstring): plain
    JSON-ready data, the rig as a dict.

    Parameters
    ----------
    run : Run
        The run.

    Returns
    -------
    dict
        The description.
    """
    if not isinstance(run, Run):
        raise TypeError(f"run has the wrong type {type(run).__name__} (expected a Run)")
    with warnings.catch_warnings():   # the run warned when it was made; replace re-checks
        warnings.simplefilter("ignore", GapRampInWindow)
        run = dataclasses.replace(run, contact=run.contact_law, label="")
    data = run_to_dict(run)
    del data["label"]
    return data


def run_id(run: Run) -> str:
    """16 hex digits identifying the simulation ``run`` describes.

    Parameters
    ----------
    run : Run
        The run.

    Returns
    -------
    str
        The id.
    """
    return _digest("run", canonical_run(run))


#: the fields that say how a run is integrated, not what it simulates
STEP_FIELDS = ("step_error", "dt_max_s")


def noise_id(run: Run) -> str:
    """The id a run's measurement noise is drawn from: its :func:`run_id` without the step
    settings (:data:`STEP_FIELDS`) and without ``Reduction.keep_idle_contacts``, so that a
    run with long steps and the same run at 10 µs, or with its idle contacts kept, carry
    the same noise draw (a run without either: its run id)."""
    data = canonical_run(run)
    for name in STEP_FIELDS:
        data.pop(name, None)
    if isinstance(data.get("reduction"), dict):
        data["reduction"] = {k: v for k, v in data["reduction"].items()
                             if k != "keep_idle_contacts"}
    return _digest("run", data)


def point_id(run: Run) -> str:
    """16 hex digits identifying ``run`` without its replicate (its start history).

    Parameters
    ----------
    run : Run
        The run.

    Returns
    -------
    str
        The id.
    """
    data = canonical_run(run)
    for name in REPLICATE_FIELDS:
        del data[name]
    return _digest("point", data)


def run_ids(run: Run) -> tuple[str, str]:
    """``(run_id(run), point_id(run))`` from one description of the run."""
    data = _plain(canonical_run(run))
    point = {k: v for k, v in data.items() if k not in REPLICATE_FIELDS}
    return _hash("run", data), _hash("point", point)


def _digest(kind: str, data: dict) -> str:
    return _hash(kind, _plain(data))


def _hash(kind: str, plain: dict) -> str:
    text = json.dumps({"schema": SCHEMA_VERSION, kind: plain}, sort_keys=True,
                      separators=(",", ":"), ensure_ascii=True, allow_nan=False)
    return hashlib.sha256(text.encode("ascii")).hexdigest()[:16]


def _plain(value):
    """JSON-ready data with one spelling per value: numbers as floats, sequences as lists."""
    kind = type(value)                  # the common exact types first: a run has thousands
    if kind is float:
        return value + 0.0              # + 0.0 turns -0.0 into 0.0
    if kind is str or value is None:
        return value
    if kind is dict:
        return {str(k): _plain(v) for k, v in value.items()}
    if kind is list or kind is tuple:
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [_plain(v) for v in value]
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, numbers.Real):
        return float(value) + 0.0          # + 0.0 turns -0.0 into 0.0
    if value is None or isinstance(value, str):
        return value
    raise TypeError(f"cannot hash a {type(value).__name__} in a run description")
