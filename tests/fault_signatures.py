"""Short runs of one fault on the multi-fault rig, and the lines its probes show: shared by
the tests that check each fault model's signature against its source
(tests/simulation/test_*_signature.py).

The rig is the preset ``paper-journal`` under gravity, as in the shipped fault designs;
the runs use the reduced model, last ``DURATION_S`` and discard their first half (the
faults' transients decay with the first mode's damping, 0.04: in about 0.2 s).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from rubdiag.model import preset_rig
from rubdiag.reduce import Reduction
from rubdiag.signal._fullspectrum import full_spectrum_lines
from rubdiag.simulation import Run, Sensor, critical_speed_for_case, simulate
from rubdiag.simulation._faults import Faults
from rubdiag.simulation._static_load import StaticLoad

DURATION_S = 1.6
#: the probes read: the drive-end journal (shaft 4, on the pedestal), the bladed disc
#: (shaft 11) and the drive-end pedestal itself
POINTS = ("shaft 4", "shaft 11", "pedestal 0")


@functools.cache
def rig():
    return preset_rig("paper-journal")


def fault_run(speed_ratio: float, case: int = 1, **faults):
    """The result of a run of case ``case`` at ``speed_ratio`` times the case's critical
    speed on :func:`rig`, carrying ``faults`` (:class:`~rubdiag.simulation._faults.Faults`
    fields)."""
    speed = speed_ratio * critical_speed_for_case(rig(), case)
    sensors = tuple(Sensor(p, d) for p in POINTS for d in ("y", "z"))
    run = Run.paper_case(case, None, speed_rpm=speed * 30.0 / math.pi, rig=rig(),
                         duration_s=DURATION_S, discard_s=DURATION_S / 2,
                         static_load=StaticLoad(direction="y", gravity_m_s2=-9.81),
                         faults=Faults(**faults) if faults else None,
                         reduction=Reduction(), sensors=sensors)
    return simulate(run)


def _pair(result, point):
    signals = result.sensor_signals(windowed=True)
    name = point.replace(" ", "")
    return signals[f"{name}_y_disp"], signals[f"{name}_z_disp"]


def lines(result, point: str, orders) -> dict[str, np.ndarray]:
    """The ``y`` and ``z`` line amplitudes (m) of ``point`` at ``orders`` of the speed, and
    the full spectrum's ``forward`` and ``reverse`` amplitudes of its y-z pair."""
    y, z = _pair(result, point)
    fs, speed_hz = result.run.output_rate_hz, result.run.speed_rad_s / (2 * math.pi)
    out = {}
    for axis, x in (("y", y), ("z", z)):
        # one probe's line = the forward plus the reverse amplitude of (x, 0)
        f, r = full_spectrum_lines(x, np.zeros_like(x), fs, speed_hz, orders)
        out[axis] = f + r
    out["forward"], out["reverse"] = full_spectrum_lines(y, z, fs, speed_hz, orders)
    return out
