"""Simulated runs as tables: what needs both the simulator and the signal layer.

* :func:`run_features` — one row per simulated run: parameters, spectral features of the
  shaft, blade tip and casing, contact statistics.
* :func:`contact_statistics` — contact statistics of one run, from its event logs.
* :func:`ramp_run`, :func:`runup_orders`, :func:`linear_response`, :func:`runup_summary` —
  run-ups and coast-downs (:mod:`rubdiag.runs._runup`).
* :func:`fault_runs`, :func:`whirl_runs`, :func:`line_amplitudes` — each fault that looks
  like rub beside rub (:mod:`rubdiag.runs._faults`).
* :func:`run_orbit_features` — the full spectrum and orbit of every recorded probe pair
  (:mod:`rubdiag.runs._pairs`).
* :func:`subsynchronous_share` — how much of a journal's orbit is oil whirl or whip.
"""

from __future__ import annotations

from rubdiag._deprecation import moved_names
from rubdiag.runs._contact_stats import CONTACT_STAT_NAMES, contact_statistics
from rubdiag.runs._faults import FIGURE_FAULTS, fault_runs, line_amplitudes, whirl_runs
from rubdiag.runs._features import is_result, run_features, run_points, run_signals
from rubdiag.runs._pairs import recorded_pairs, run_orbit_features
from rubdiag.runs._runup import linear_response, ramp_run, runup_orders, runup_summary
from rubdiag.runs._whirl import SUBSYNCHRONOUS_BAND, subsynchronous_share

__all__ = [
    "CONTACT_STAT_NAMES",
    "FIGURE_FAULTS",
    "SUBSYNCHRONOUS_BAND",
    "contact_statistics",
    "fault_runs",
    "is_result",
    "line_amplitudes",
    "linear_response",
    "ramp_run",
    "recorded_pairs",
    "run_features",
    "run_orbit_features",
    "run_points",
    "run_signals",
    "runup_orders",
    "runup_summary",
    "subsynchronous_share",
    "whirl_runs",
]

__getattr__ = moved_names(__name__, {
    "features": ("rubdiag.runs._features.features_of_anything",
                 "use rubdiag.run_features for simulated runs and rubdiag.signal_features "
                 "for measured signals"),
    "pair_rows": "rubdiag.runs.run_orbit_features",
})
