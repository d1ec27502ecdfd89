"""The one public door to the time-integration kernels.

:func:`simulate` runs a rig described by a :class:`Run` and returns a
:class:`SimulationResult`; :func:`simulate_system` integrates a generic linear system
(:class:`LinearSystem`) with nonlinear elements (:class:`PointContact`,
:class:`AnnularContact` …) on a :class:`TimeGrid`, for analytic tests and other models.
"""

from rubdiag.simulation._contacts import Contacts
from rubdiag.simulation._elements import AnnularContact, PointContact
from rubdiag.simulation._faults import Crack, Faults, Looseness
from rubdiag.simulation._grid import TimeGrid
from rubdiag.simulation._linear_system import LinearSystem
from rubdiag.simulation._loads import HarmonicForce
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._recording import Recording
from rubdiag.simulation._result import EpisodeLog, SimulationDiverged, SystemResult
from rubdiag.simulation._run import GapRampInWindow, Run, critical_speed_for_case
from rubdiag.simulation._sensors import Sensor, default_sensors
from rubdiag.simulation._simulation import response_points, simulate
from rubdiag.simulation._simulation_result import SimulationResult, load_result
from rubdiag.simulation._solver import Solver
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._static_load import StaticLoad
from rubdiag.simulation._system import simulate_system

__all__ = [
    "AnnularContact",
    "Contacts",
    "Crack",
    "EpisodeLog",
    "Faults",
    "GapRampInWindow",
    "HarmonicForce",
    "LinearSystem",
    "Looseness",
    "Misalignment",
    "PointContact",
    "Recording",
    "Run",
    "Sensor",
    "SimulationDiverged",
    "SimulationResult",
    "Solver",
    "SpeedProfile",
    "StaticLoad",
    "SystemResult",
    "TimeGrid",
    "critical_speed_for_case",
    "default_sensors",
    "load_result",
    "response_points",
    "simulate",
    "simulate_system",
]

