"""Labelled rub datasets: designs of runs and their stable identities.

:class:`Design` (frozen, picklable, from TOML) says which runs to make; ``Design.runs()``
builds them, each with the design point, its replicate (start history) and two ids:
``point_id`` (the point, shared by its replicates) and ``run_id`` (the simulation), stable
across processes, machines and Python versions (:mod:`rubdiag.dataset.ids`).

This layer sits above :mod:`rubdiag.runs` (features of simulated runs); nothing below
imports it.
"""

from rubdiag.dataset.design import Design, DesignRun
from rubdiag.dataset.factors import FACTORS, Factor
from rubdiag.dataset.generate import generate, pending_runs
from rubdiag.dataset.ids import SCHEMA_VERSION, canonical_run, point_id, run_id
from rubdiag.dataset.labels import LabelRules, label_run, labels_from_measures
from rubdiag.dataset.noise import NoiseFloors
from rubdiag.dataset.sampling import MAX_REPLICATES, gap_ramps_s
from rubdiag.dataset.store import load, load_waveforms

__all__ = [
    "FACTORS",
    "MAX_REPLICATES",
    "SCHEMA_VERSION",
    "Design",
    "DesignRun",
    "Factor",
    "LabelRules",
    "NoiseFloors",
    "canonical_run",
    "gap_ramps_s",
    "generate",
    "label_run",
    "labels_from_measures",
    "load",
    "load_waveforms",
    "pending_runs",
    "point_id",
    "run_id",
]
