"""Features of simulated runs: one table row per run.

The row holds the run's parameters, the spectral features of its shaft, blade-tip and
casing responses over the analysis window (columns prefixed ``shaft_``, ``blade_``,
``casing_``) and its contact statistics (:mod:`rubdiag.runs.contact_stats`).

:func:`features` is the public ``rubdiag.features``: a simulation result goes to
:func:`run_features`, anything else (a measured signal) to :func:`rubdiag.signal.features`
without loading the simulator.
"""

from __future__ import annotations

import sys
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag.runs.contact_stats import contact_statistics
from rubdiag.signal import features as signal_features
from rubdiag.signal.table import prefixed_features

__all__ = ["features", "is_result", "run_features", "run_points", "run_signals"]

_RESULT_MARK = "rubdiag.simulation-result"


def is_result(obj) -> bool:
    """True for a SimulationResult or the path of a saved one (.npz with rubdiag metadata).

    Loads neither the simulator nor Numba: an object can only be a SimulationResult if
    :mod:`rubdiag.simulate` was imported, and a file is recognised by its metadata.
    """
    simulate = sys.modules.get("rubdiag.simulate")
    if simulate is not None and isinstance(obj, simulate.SimulationResult):
        return True
    if isinstance(obj, str | Path) and Path(obj).suffix == ".npz" and Path(obj).is_file():
        try:
            with np.load(obj, allow_pickle=False) as archive:
                return "meta" in archive.files and _RESULT_MARK in str(archive["meta"])
        except (OSError, ValueError, zipfile.BadZipFile, EOFError):
            return False    # not a readable archive: the reader that opens it says why
    return False


def features(signal, fs: float | None = None, speed_rpm: float | None = None, **options):
    """Rub-impact features of measured signals or of simulated runs.

    A :class:`~rubdiag.simulate.SimulationResult`, the path of a saved one, or a list of
    them gives one row per run (:func:`run_features`); anything else is a measured signal
    and gives one row per channel (:func:`rubdiag.signal.features`, whose parameters these
    are).
    """
    if is_result(signal) or (isinstance(signal, list) and signal
                             and all(is_result(s) for s in signal)):
        if fs is not None or speed_rpm is not None:
            raise ValueError("fs and speed_rpm come from the simulation result: do not give "
                             "them for a run")
        return run_features(signal, **options)
    return signal_features(signal, fs, speed_rpm, **options)


def run_points(result) -> dict[str, str]:
    """Recorded points analysed for a run, by prefix: ``shaft`` (the bladed disc's node, or
    the first disc), ``blade`` (the tip of contact element 1's blade) and ``casing`` (the
    casing node of contact element 1), y direction, when recorded."""
    rig = result.run.rig
    disc = rig.blades.disc_node if rig.blades is not None else rig.discs[0].node
    points = {"shaft": f"shaft {disc} y"}
    for prefix in ("blade", "casing"):
        names = [p for p in result.points if p.startswith(prefix) and p.endswith(" y")]
        if names:
            points[prefix] = names[0]
    return points


def run_signals(result) -> dict[str, np.ndarray]:
    """The windowed responses of :func:`run_points` (m), by prefix."""
    return {prefix: result.displacement(point, windowed=True)
            for prefix, point in run_points(result).items()}


def run_features(results, **options) -> pd.DataFrame:
    """One row per simulated run (a SimulationResult, a saved result path, or a list).

    ``options`` are those of :func:`rubdiag.signal.features` (``band``, ``threshold``,
    ``window`` …). Columns: ``label``, ``status``, ``speed_rpm``, ``gap_m``,
    ``friction_coefficient``, ``dt_s``, ``model`` ("full" or "reduced"), ``window_s``, then
    ``shaft_…``, ``blade_…``, ``casing_…`` spectral features, then the contact statistics.
    """
    from rubdiag.simulate import SimulationResult, load_result

    if isinstance(results, (SimulationResult, str, Path)):
        results = [results]
    rows = []
    for result in results:
        if not isinstance(result, SimulationResult):
            result = load_result(result)
        if not result.window.any():
            raise ValueError(f"run {result.run.label!r} has no samples in its analysis window")
        run = result.run
        law = run.contact_law
        meta = pd.DataFrame([{
            "label": run.label, "status": result.status,
            "gap_m": run.gap_m if run.gap_m is not None else np.nan,
            "friction_coefficient": law.friction_coefficient if law else np.nan,
            "dt_s": run.dt_s, "model": run.model_kind,
        }])
        spectra = prefixed_features(run_signals(result), result.fs, run.speed_rpm, **options)
        stats = pd.DataFrame([contact_statistics(result)])
        rows.append(pd.concat([meta, spectra, stats], axis=1))
    return pd.concat(rows, ignore_index=True)
