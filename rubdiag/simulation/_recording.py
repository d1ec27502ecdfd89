"""What a run records and reports: the :class:`Recording` a user gives, checked."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag.simulation._grid import Ticks

__all__ = ["Recording", "checked_records"]

#: the most values (samples x DOFs) one recorded array may hold
MAX_VALUES = 5e8


@dataclass(frozen=True, kw_only=True)
class Recording:
    """What a run records and reports.

    Parameters
    ----------
    record_dofs : sequence of int or None
        The DOFs whose displacements are sampled every ``TimeGrid.output_dt`` (physical
        DOFs of a reduced model); None: all.
    sensor_dofs : sequence of int or None
        The DOFs whose displacement, velocity and acceleration (the integrator's state) are
        recorded at every multiple of dt: the raw stream sensors are filtered from. None:
        none.
    progress : callable or None
        ``progress(t, duration)`` (s, s), called about 100 times during the run.
    profile : bool
        Count the CPU cycles of each section of a step (``extra['profile_cycles']`` of the
        result; the results are the same bits).
    raise_on_failure : bool
        A failed run raises :class:`~rubdiag.simulation.SimulationDiverged` carrying the
        partial result (False: the partial result is returned with ``status != 0``).
    """

    record_dofs: Sequence[int] | np.ndarray | None = None
    sensor_dofs: Sequence[int] | np.ndarray | None = None
    progress: Callable[[float, float], None] | None = None
    profile: bool = False
    raise_on_failure: bool = True


def checked_records(grid: Ticks, n: int, outputs: Recording, recovery):
    """``(recovery, record_dofs, sensor_dofs)`` of a run of ``n`` coordinates: ``recovery``
    (None, or the (n_phys, n) float64 map to the physical DOFs) and the recorded and sensor
    DOFs (int64 indices of the physical DOFs), checked against the outputs' sizes."""
    if not isinstance(outputs, Recording):
        raise _check.wrong_type("outputs", type(outputs).__name__, "a Recording or None")
    n_phys = n
    if recovery is not None:
        recovery = np.asarray(recovery, dtype=np.float64)
        if recovery.ndim != 2 or recovery.shape[1] != n or not np.all(np.isfinite(recovery)):
            raise _check.out_of_range("recovery", f"array of shape {recovery.shape}",
                                      f"finite, shape (n_phys, {n})")
        n_phys = recovery.shape[0]
    record_dofs = outputs.record_dofs
    if record_dofs is None:     # every physical DOF
        record_dofs = np.arange(n_phys, dtype=np.int64)
    record_dofs = _check.indices("record_dofs", record_dofs, n_phys)
    if grid.n_out * max(record_dofs.size, 1) > MAX_VALUES:
        raise ValueError(
            f"output of {grid.n_out} samples x {record_dofs.size} DOFs is too large: "
            "increase output_dt or record fewer DOFs"
        )
    sensor_dofs = outputs.sensor_dofs
    sensor_dofs = _check.indices("sensor_dofs", [] if sensor_dofs is None else sensor_dofs,
                                 n_phys)
    n_sen = grid.n_sensor_samples(sensor_dofs.size)
    if n_sen * sensor_dofs.size > MAX_VALUES:
        raise ValueError(f"sensor output of {n_sen} samples x {sensor_dofs.size} DOFs is too "
                         "large: record fewer sensors or shorten the run")
    return recovery, record_dofs, sensor_dofs
