"""Linear analysis: modes at speed, Campbell diagram, critical speeds, harmonic and
unbalance responses, and calibration of unknown geometry to target critical speeds."""

from rubdiag.modal.calibrate import KNOBS, Calibration, calibrate
from rubdiag.modal.campbell import Campbell, campbell
from rubdiag.modal.critical import (
    CriticalSpeeds,
    critical_speeds,
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

__all__ = [
    "KNOBS",
    "Calibration",
    "Campbell",
    "CriticalSpeeds",
    "HarmonicResponse",
    "Modes",
    "UnbalanceResponse",
    "calibrate",
    "campbell",
    "critical_speeds",
    "harmonic_response",
    "modes",
    "synchronous_modes",
    "unbalance_response",
    "with_rayleigh",
]
