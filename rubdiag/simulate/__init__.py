"""The one public door to the time-integration kernels.

:func:`simulate_system` integrates a generic linear system (sparse M, C, K) with a harmonic load
and contact elements; the rig layer builds the matrices and the contact description on top.
"""

from rubdiag.simulate.result import EpisodeLog, SimulationDiverged, SystemResult
from rubdiag.simulate.system import Contacts, HarmonicForce, simulate_system

__all__ = [
    "Contacts",
    "EpisodeLog",
    "HarmonicForce",
    "SimulationDiverged",
    "SystemResult",
    "simulate_system",
]
