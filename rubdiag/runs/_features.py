"""Features of simulated runs: one table row per run.

The row holds the run's parameters, the spectral features of its shaft, blade-tip and
casing responses over the analysis window (columns prefixed ``shaft_``, ``blade_``,
``casing_``) and its contact statistics (:mod:`rubdiag.runs._contact_stats`).

:func:`features_of_anything` is what the deprecated ``rubdiag.features`` still does until
its removal: a simulation result goes to :func:`run_features`, anything else (a measured
signal) to :func:`rubdiag.signal.signal_features`.

:func:`order_tracked` and :func:`order_tracked_features` give records along a changing speed
(run-ups, coast-downs) the same columns as constant-speed ones: the record is resampled at
equal shaft-angle steps (:func:`rubdiag.signal.resample_to_angle`, anti-aliased in the angle
domain), cut to whole revolutions, and presented as a constant-speed record at its mean
speed. In that record every order is a steady line, so the features of
:func:`rubdiag.signal._table.prefixed_features` apply unchanged, their frequencies in Hz at the
mean speed (order × mean revolutions per second).
"""

from __future__ import annotations

import math
import sys
import zipfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag.runs._contact_stats import contact_statistics
from rubdiag.signal import resample_to_angle, signal_features
from rubdiag.signal._orders import HARMONICS
from rubdiag.signal._records import RecordTooShort
from rubdiag.signal._sidebands import HALF_WIDTH_ORDERS
from rubdiag.signal._speedtable import MAX_FS_FRACTION, SAMPLES_PER_REV
from rubdiag.signal._table import prefixed_features

__all__ = ["ORDER_TRACK_LOST_REVOLUTIONS", "TOP_FEATURE_ORDER", "is_result",
           "max_tracked_rpm", "order_tracked", "order_tracked_features", "run_features",
           "run_points", "run_signals"]

#: The highest order the features read: 8× and the ±0.25× of its sidebands and broadband.
TOP_FEATURE_ORDER = max(HARMONICS) + HALF_WIDTH_ORDERS
#: The most revolutions :func:`order_tracked` takes off a record: the anti-alias filter's
#: ends (0.36 revolutions each at 32 samples per revolution) and the part revolutions before
#: the first whole one and after the last.
ORDER_TRACK_LOST_REVOLUTIONS = 3.0

_RESULT_MARK = "rubdiag.simulation-result"


def is_result(obj) -> bool:
    """True for a SimulationResult or the path of a saved one (.npz with rubdiag metadata).

    Loads neither the simulator nor Numba: an object can only be a SimulationResult if
    :mod:`rubdiag.simulation` was imported, and a file is recognised by its metadata.

    Parameters
    ----------
    obj : object
        Anything.

    Returns
    -------
    bool
        Whether ``obj`` is a result or a saved result's path.
    """
    simulate = sys.modules.get("rubdiag.simulation")
    if simulate is not None and isinstance(obj, simulate.SimulationResult):
        return True
    if isinstance(obj, str | Path) and Path(obj).suffix == ".npz" and Path(obj).is_file():
        try:
            with np.load(obj, allow_pickle=False) as archive:
                return "meta" in archive.files and _RESULT_MARK in str(archive["meta"])
        except (OSError, ValueError, zipfile.BadZipFile, EOFError):
            return False    # not a readable archive: the reader that opens it says why
    return False


def features_of_anything(signal, fs: float | None = None, speed_rpm: float | None = None,
                         **options):
    """Rub-impact features of measured signals or of simulated runs (deprecated).

    Call :func:`rubdiag.signal_features` for measured signals and
    :func:`rubdiag.run_features` for simulated runs: one function per input kind.

    A :class:`~rubdiag.simulation.SimulationResult`, the path of a saved one, or a list of
    them gives one row per run (:func:`run_features`); anything else is a measured signal
    and gives one row per channel (:func:`rubdiag.signal.signal_features`, whose parameters these
    are).

    Parameters
    ----------
    signal : SimulationResult, path, DataFrame or array_like
        Runs (a result, a saved result's path, or a list of them), or measured signals (as
        for :func:`rubdiag.signal.signal_features`).
    fs : float or None
        Sampling frequency of measured signals (Hz).
    speed_rpm : float or None
        Running speed of measured signals (rpm).
    **options
        The analysis settings of :func:`rubdiag.signal.signal_features`.

    Returns
    -------
    pandas.DataFrame
        One row per run, or one per channel.
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
    casing node of contact element 1), y direction, when recorded.

    Parameters
    ----------
    result : SimulationResult
        A simulated run.

    Returns
    -------
    dict of str to str
        Recorded displacement (``"shaft 11 y"``) by prefix.
    """
    rig = result.run.rig
    disc = rig.blades.disc_node if rig.blades is not None else rig.discs[0].node
    points = {"shaft": f"shaft {disc} y"}
    for prefix in ("blade", "casing"):
        names = [p for p in result.points if p.startswith(prefix) and p.endswith(" y")]
        if names:
            points[prefix] = names[0]
    return points


def run_signals(result) -> dict[str, np.ndarray]:
    """The windowed responses of :func:`run_points` (m), by prefix.

    Parameters
    ----------
    result : SimulationResult
        A simulated run.

    Returns
    -------
    dict of str to numpy.ndarray
        The displacement over the analysis window (m), by prefix.
    """
    return {prefix: result.displacement(point, windowed=True)
            for prefix, point in run_points(result).items()}


def run_features(results, **options) -> pd.DataFrame:
    """One row per simulated run (a SimulationResult, a saved result path, or a list).

    ``options`` are those of :func:`rubdiag.signal.signal_features` (``band``, ``threshold``,
    ``window`` …). Columns: ``label``, ``status``, ``speed_rpm``, ``gap_m``,
    ``friction_coefficient``, ``dt_s``, ``model`` ("full" or "reduced"), ``window_s``, then
    ``shaft_…``, ``blade_…``, ``casing_…`` spectral features, then the contact statistics.
    A run along a speed profile is order-tracked on its shaft angle first
    (:func:`order_tracked_features`): its ``speed_rpm`` is the window's mean speed and its
    frequencies are in Hz at that speed.

    Parameters
    ----------
    results : SimulationResult, str, Path or list of them
        Runs, or paths of saved results.
    **options
        Settings of :func:`rubdiag.signal.signal_features`.

    Returns
    -------
    pandas.DataFrame
        One row per run.
    """
    from rubdiag.simulation import SimulationResult, load_result

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
        if run.speed_profile is None:
            spectra = prefixed_features(run_signals(result), result.fs, run.speed_rpm,
                                        **options)
        else:   # order-tracked on the shaft angle, at the window's mean speed
            spectra = order_tracked_features(run_signals(result), result.fs,
                                             result.angle_rad[result.window], **options)
        stats = pd.DataFrame([contact_statistics(result)])
        rows.append(pd.concat([meta, spectra, stats], axis=1))
    return pd.concat(rows, ignore_index=True)


def max_tracked_rpm(fs: float) -> float:
    """The fastest speed (rpm) at which :func:`order_tracked` reads every feature of a record
    sampled at ``fs`` (Hz): :data:`TOP_FEATURE_ORDER` × speed at most
    :data:`~rubdiag.signal._speedtable.MAX_FS_FRACTION` × ``fs``, where the cubic
    interpolation onto the angle grid reads a line 0.5 % low (2 kHz at 10 kHz: 14545 rpm)."""
    return MAX_FS_FRACTION * _check.positive("fs", fs, "Hz") / TOP_FEATURE_ORDER * 60.0


def order_tracked(signals: Mapping[str, object], fs: float, angle,
                  samples_per_rev: int = SAMPLES_PER_REV) -> tuple[dict, float, float]:
    """Signals recorded along a changing speed, as a constant-speed record at their mean
    speed.

    Parameters
    ----------
    signals : mapping of str to 1-D array_like
        Name → signal, all sampled at ``fs`` over the same samples.
    fs : float
        Sampling frequency in Hz.
    angle : array_like
        The shaft angle (rad) at every sample, strictly increasing (a simulated run's
        exact ``angle_rad``, or :func:`rubdiag.signal.tacho_angle`).
    samples_per_rev : int
        Samples per revolution of the angle record. The default, 32, is
        :func:`rubdiag.signal.revolution_features`'s: the angle-domain anti-alias filter
        passes 12.5 orders, above the features' :data:`TOP_FEATURE_ORDER` (8.25×).

    Returns
    -------
    record : dict of str to ndarray
        The signals at ``samples_per_rev`` equal angle steps per revolution
        (:func:`rubdiag.signal.resample_to_angle` with its default ``max_order``), over the
        whole revolutions inside the record: it starts at a whole revolution (angle a
        multiple of 2π), so phases of integer orders are against the shaft angle.
    fs_equiv : float
        The record's sampling frequency at its mean speed (Hz): ``samples_per_rev`` × the
        revolutions it spans over the time they took.
    speed_rpm : float
        That mean speed (rpm). ``(record, fs_equiv, speed_rpm)`` is a constant-speed record:
        an order k lies at ``k · speed_rpm / 60`` Hz, and the record lasts as long as its
        revolutions did.

    Notes
    -----
    Content above 12.5 orders is removed by the angle-domain low-pass, so ``rms`` of the
    record covers the orders up to there (a constant-speed record's covers its whole
    band). The fastest speed must keep the features below 0.2 ``fs``
    (:func:`max_tracked_rpm`); a faster record raises ``ValueError``. At most
    :data:`ORDER_TRACK_LOST_REVOLUTIONS` revolutions of the input are left out.
    """
    if not signals:
        raise ValueError("signals is empty: give at least one {name: signal}")
    fs = _check.positive("fs", fs, "Hz")
    spr = _check.integer("samples_per_rev", samples_per_rev, lo=2)
    names = list(signals)
    X = np.vstack([np.asarray(signals[n], dtype=np.float64) for n in names])
    phi = np.asarray(angle, dtype=np.float64)
    if phi.ndim == 1 and phi.size == X.shape[1] > 1:
        fastest = 60.0 * float(np.max(np.diff(phi))) * fs / (2.0 * math.pi)
        if fastest > max_tracked_rpm(fs):
            raise ValueError(
                f"angle: the speed reaches {fastest:.6g} rpm (allowed: at most "
                f"{max_tracked_rpm(fs):.6g} rpm at fs = {fs:g} Hz, where "
                f"{TOP_FEATURE_ORDER:g}x stays below {MAX_FS_FRACTION:g} fs)")
    revolutions, Y = resample_to_angle(X, fs, phi, samples_per_rev=spr)
    m0 = round(float(revolutions[0]) * spr)
    i0 = (-m0) % spr                                # the first whole revolution
    n_rev = (Y.shape[1] - i0) // spr
    if n_rev < 1:
        raise RecordTooShort(f"angle: the order-tracked record holds no whole revolution "
                             f"({Y.shape[1]} angle samples at {spr} per revolution)")
    first = (m0 + i0) // spr
    t = np.arange(phi.size) / fs
    t0, t1 = np.interp(2.0 * math.pi * np.array([first, first + n_rev]), phi, t)
    rev_per_s = n_rev / (t1 - t0)
    record = {n: Y[j, i0:i0 + n_rev * spr] for j, n in enumerate(names)}
    return record, spr * rev_per_s, 60.0 * rev_per_s


def order_tracked_features(signals: Mapping[str, object], fs: float, angle,
                           separator: str = "_", samples_per_rev: int = SAMPLES_PER_REV,
                           **options) -> pd.DataFrame:
    """:func:`rubdiag.signal._table.prefixed_features` of signals recorded along a changing speed:
    one row, ``speed_rpm`` (the record's mean speed) then ``<name><separator><feature>``,
    computed on :func:`order_tracked`'s constant-speed record (frequencies in Hz at the mean
    speed). ``options`` are those of :func:`rubdiag.signal.signal_features`."""
    record, fs_equiv, speed_rpm = order_tracked(signals, fs, angle, samples_per_rev)
    return prefixed_features(record, fs_equiv, speed_rpm, separator=separator, **options)
