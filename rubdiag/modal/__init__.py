"""Linear analysis: modes at speed, Campbell diagram, critical speeds, harmonic and
unbalance responses, the threshold of instability on journal bearings, and calibration of
unknown geometry to target critical speeds."""

from rubdiag.modal.calibrate import KNOBS, Calibration, calibrate
from rubdiag.modal.campbell import Campbell, campbell
from rubdiag.modal.critical import (
    CriticalSpeeds,
    critical_speeds,
    direct_film_stiffness,
    synchronous_modes,
    with_rayleigh,
)
from rubdiag.modal.eigen import Modes, modes
from rubdiag.modal.harmonic import (
    HarmonicResponse,
    UnbalanceResponse,
    harmonic_response,
    unbalance_response,
)
from rubdiag.modal.stability import StabilityThreshold, stability_threshold, whirl_threshold

__all__ = [
    "KNOBS",
    "Calibration",
    "Campbell",
    "CriticalSpeeds",
    "HarmonicResponse",
    "Modes",
    "StabilityThreshold",
    "UnbalanceResponse",
    "calibrate",
    "campbell",
    "critical_speeds",
    "direct_film_stiffness",
    "harmonic_response",
    "modes",
    "stability_threshold",
    "synchronous_modes",
    "unbalance_response",
    "whirl_threshold",
    "with_rayleigh",
]
