"""The one public door to the time-integration kernels.

:func:`simulate` runs a rig described by a :class:`Run` and returns a
:class:`SimulationResult`; :func:`simulate_system` integrates a generic linear system
(sparse M, C, K) with a harmonic load and contact elements, for analytic tests and other
models.
"""

from rubdiag.simulation._result import EpisodeLog, SimulationDiverged, SystemResult
from rubdiag.simulation._run import GapRampInWindow, Run, critical_speed_for_case
from rubdiag.simulation._sensors import Sensor, default_sensors
from rubdiag.simulation._simulation import SimulationResult, load_result, response_points, simulate
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._system import Contacts, HarmonicForce, simulate_system

__all__ = [
    "Contacts",
    "EpisodeLog",
    "GapRampInWindow",
    "HarmonicForce",
    "Run",
    "Sensor",
    "SimulationDiverged",
    "SimulationResult",
    "SpeedProfile",
    "SystemResult",
    "critical_speed_for_case",
    "default_sensors",
    "load_result",
    "response_points",
    "simulate",
    "simulate_system",
]

