"""Signal features of rub-impact: amplitude spectra, order lines, sidebands, combinations.

Public API (all frequencies in Hz, speeds in rpm, amplitudes in the signal's unit):

* :func:`amplitude_spectrum` ``(x, fs, …) -> (f, amplitude)`` — peak-amplitude spectrum.
* :func:`spectral_lines` ``(x, fs, …) -> (f, amplitude, phase_deg)`` — exact lines.
* :func:`tacho_speed`, :func:`dominant_speed` — running speed in rpm; :func:`voted_speed` —
  the speed of a record whose channels' strongest lines vote (what :func:`signal_features` and
  ``rubdiag predict`` guess); :class:`SpeedAmbiguous` — the warning of a guess whose 1× may
  be a weaker line at 1/2 or 1/3 of it; :class:`SpeedNotFound` — the error of a record
  whose speed must be given.
* :func:`tacho_angle`, :func:`tacho_rpm`, :func:`angle_from_rpm` — shaft angle (rad) and speed
  (rpm) at every sample, for records at a variable speed.
* :func:`resample_to_angle` ``(x, fs, angle, …) -> (revolutions, x_angle)`` — computed order
  tracking: equal angle steps, anti-aliased in the angle domain.
* :func:`order_spectrum` ``(x, fs, angle, …) -> (orders, amplitude)``, :func:`order_track`
  (amplitude and phase of chosen orders against speed, a DataFrame), :func:`rpm_order_map`
  ``-> (orders, rpm, amplitude)`` — order analysis at a variable speed;
  :func:`tracking_leakage` — what a track's changing 1× leaks onto the orders beside it.
* :func:`waterfall` ``(x, fs, nperseg, …) -> (f, t, rpm, amplitude)`` — short-time spectra.
* :func:`features` — one DataFrame row of features per channel (the table).
* :func:`revolution_features` — the same features across speed: one row per bin of whole
  revolutions in the angle domain (frequencies in orders) and channel, with its ``rpm``.
* :func:`feature_names`, :func:`feature_matrix` — the columns; the batch path on a 2-D array.
* :func:`combination_pairs` — all combination pairs of one signal.
* :func:`prefixed_features` — one row for several named signals of one run.
* :class:`RubFeatures` — the scikit-learn transformer.
* :func:`read_signals` — CSV / NPZ / parquet files.

This layer imports nothing else of rubdiag: measured signals never need the simulator.
Simulated runs are turned into rows by :mod:`rubdiag.runs`.

See :mod:`rubdiag.signal._table` for the column names and the meaning of 0 and NaN.
"""

from __future__ import annotations

from rubdiag._deprecation import moved_names
from rubdiag.signal._combinations import CombinationPair, combination_pairs
from rubdiag.signal._fullspectrum import full_spectrum, orbit_features
from rubdiag.signal._io import read_signals
from rubdiag.signal._leakage import tracking_leakage
from rubdiag.signal._lines import spectral_lines
from rubdiag.signal._orders import order_label
from rubdiag.signal._ordertrack import (
    order_spectrum,
    order_track,
    resample_to_angle,
    rpm_order_map,
)
from rubdiag.signal._spectrum import amplitude_spectrum
from rubdiag.signal._speed import SpeedAmbiguous, dominant_speed, tacho_speed
from rubdiag.signal._speedtable import REVOLUTION_FEATURE_NAMES, revolution_features
from rubdiag.signal._speedvote import SpeedNotFound, voted_speed
from rubdiag.signal._table import FEATURE_NAMES, feature_names, signal_features
from rubdiag.signal._tacho import angle_from_rpm, tacho_angle, tacho_rpm
from rubdiag.signal._transformer import RubFeatures
from rubdiag.signal._waterfall import waterfall

__all__ = [
    "FEATURE_NAMES",
    "REVOLUTION_FEATURE_NAMES",
    "CombinationPair",
    "RubFeatures",
    "SpeedAmbiguous",
    "SpeedNotFound",
    "amplitude_spectrum",
    "angle_from_rpm",
    "combination_pairs",
    "dominant_speed",
    "feature_names",
    "full_spectrum",
    "orbit_features",
    "order_label",
    "order_spectrum",
    "order_track",
    "read_signals",
    "resample_to_angle",
    "revolution_features",
    "rpm_order_map",
    "signal_features",
    "spectral_lines",
    "tacho_angle",
    "tacho_rpm",
    "tacho_speed",
    "tracking_leakage",
    "voted_speed",
    "waterfall",
]

__getattr__ = moved_names(__name__, {
    "features": "rubdiag.signal.signal_features",
    "features_by_revolution": "rubdiag.signal.revolution_features",
    "feature_matrix": ("rubdiag.signal._table.feature_matrix",
                       "use rubdiag.signal.RubFeatures (its transform is the same batch path)"),
    "prefixed_features": ("rubdiag.signal._table.prefixed_features",
                          "use rubdiag.run_features for simulated runs, or "
                          "rubdiag.signal_features for named signals"),
})
