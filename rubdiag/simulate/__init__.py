"""The one public door to the time-integration kernels.

:func:`simulate` runs a rig described by a :class:`Run` and returns a
:class:`SimulationResult`; :func:`simulate_system` integrates a generic linear system
(sparse M, C, K) with a harmonic load and contact elements, for analytic tests and other
models.
"""

import sys
import types

from rubdiag.simulate.result import EpisodeLog, SimulationDiverged, SystemResult
from rubdiag.simulate.run import GapRampInWindow, Run, critical_speed_for_case
from rubdiag.simulate.sensors import Sensor, default_sensors
from rubdiag.simulate.simulation import SimulationResult, load_result, response_points, simulate
from rubdiag.simulate.speed_profile import SpeedProfile
from rubdiag.simulate.system import Contacts, HarmonicForce, simulate_system

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


class _CallablePackage(types.ModuleType):
    """``rubdiag.simulate`` is two things at the top level: this package, and the function
    :func:`simulate` (``rubdiag.simulate(run)``). Once any of the package is imported (as
    ``rubdiag.Run`` does), the import system binds ``rubdiag.simulate`` to the package, so the
    package runs the function when called."""

    def __call__(self, *args, **kwargs):
        return simulate(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
