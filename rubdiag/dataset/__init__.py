"""Labelled rub datasets: designs of runs and their stable identities.

:class:`Design` (frozen, picklable, from TOML) says which runs to make; ``Design.runs()``
builds them, each with the design point, its replicate (start history) and two ids:
``point_id`` (the point, shared by its replicates) and ``run_id`` (the simulation), stable
across processes, machines and Python versions (:mod:`rubdiag.dataset._ids`).

This layer sits above :mod:`rubdiag.runs` (features of simulated runs); nothing below
imports it. Its names are imported on first use (PEP 562), so that reading a stored
dataset (:func:`load`, :func:`load_waveforms`) or adding noise does not import the
simulator: ``rubdiag predict`` runs on a machine's measurements without it.
"""

import importlib

# public name -> the submodule that defines it
_WHERE = {
    "Design": "design", "DesignRun": "design", "DEFAULT_STEP_ERROR": "design",
    "FACTORS": "factors", "Factor": "factors",
    "generate": "generation", "pending_runs": "generation",
    "canonical_run": "ids", "point_id": "ids", "run_id": "ids",
    "SCHEMA_VERSION": "schema",
    "LabelRules": "labels", "label_run": "labels", "labels_from_measures": "labels",
    "fault_labels": "faults",
    "NoiseFloors": "noise",
    "SpeedRamp": "ramp",
    "MAX_REPLICATES": "sampling", "gap_ramps_s": "sampling",
    "acquisition": "store", "load": "store", "load_waveforms": "store",
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module 'rubdiag.dataset' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"rubdiag.dataset._{_WHERE[name]}"), name)
    globals()[name] = value      # the next access is a plain lookup
    return value


def __dir__():
    return sorted(set(globals()) | set(_WHERE))
