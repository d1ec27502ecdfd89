"""Sensors as a plant has them: what a run records for a measurement-like dataset.

A :class:`Sensor` reads one quantity of one DOF direction: ``displacement`` (a proximity
probe, m), ``velocity`` (m/s), ``acceleration`` (an accelerometer, m/s²) of any node, or
the ``reaction`` force of a bearing (N, ``k u + c v`` of that bearing's spring and damper:
the force the shaft puts on the support). Velocity and acceleration are the integrator's
own state (Newmark's v and a), not differences of displacements.

**Rate and anti-aliasing.** The integrator records the sensors' DOFs at every multiple of
the largest step dt (100 kHz at dt = 10 µs: the step ends, exact states). An impact lasts
less than 0.1 ms, so sampling that stream at the output rate (10 kHz) would fold its
energy above 5 kHz back into the spectrum. Instead it is low-pass filtered and decimated
to ``Run.output_rate_hz`` by a zero-phase FIR filter (Kaiser window, β = 8, 40·q + 1 taps
for a decimation factor q, cut-off at 0.8 × the output Nyquist frequency: 4 kHz at 10 kHz),
as a data acquisition system's anti-aliasing filter does: the passband below 0.65 × the
output Nyquist frequency (3.25 kHz; the 8th harmonic of case 2 is 760 Hz) is flat to
0.02 %, and everything at or above the output Nyquist frequency is attenuated by ≥ 80 dB
instead of aliasing (``tests/simulation/test_sensors.py`` measures both). The filter's edge
transient (20·q input samples, 2 ms at each end of the record) lies in the discarded start
and in the last 2 ms of the window, where the spectra's Hann window is near zero. The
filter is that of ``scipy.signal.resample_poly(..., padtype="line")``, bit for bit, computed
for all channels at once (:mod:`rubdiag.simulation._decimation`: 4× faster on a run's stream).
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass

import numpy as np

from rubdiag import _check

__all__ = ["QUANTITIES", "Sensor", "default_sensors", "sensor_signals"]

#: quantity -> (short name in channel names, unit)
QUANTITIES = {"displacement": ("disp", "m"), "velocity": ("vel", "m/s"),
              "acceleration": ("acc", "m/s^2"), "reaction": ("force", "N")}
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_-]*$")

CUTOFF_OF_NYQUIST = 0.8
KAISER_BETA = 8.0
TAPS_PER_FACTOR = 40


@dataclass(frozen=True)
class Sensor:
    """One channel: ``point`` (a node label, ``"shaft 4"``, ``"casing 1"``,
    ``"blade 1.4"``), ``direction`` (``"y"`` or ``"z"``), ``quantity`` (a key of
    :data:`QUANTITIES`) and ``name`` (default e.g. ``shaft4_y_disp``; letters, digits,
    ``_`` and ``-``, no ``__``, which separates channel and feature in dataset columns).

    Parameters
    ----------
    point : str
        A node label.
    direction : {"y", "z"}
        The direction measured.
    quantity : str
        A key of :data:`QUANTITIES`.
    name : str
        The channel's name; empty: made from the others.
    """

    point: str
    direction: str
    quantity: str = "displacement"
    name: str = ""

    def __post_init__(self):
        if not isinstance(self.point, str):
            raise _check.wrong_type("sensor.point", self.point, "a node label such as "
                                    "'shaft 4'")
        _check.choice("sensor.direction", self.direction, ("y", "z"))
        _check.choice("sensor.quantity", self.quantity, tuple(QUANTITIES))
        if not self.name:
            short = QUANTITIES[self.quantity][0]
            node = self.point.replace(" ", "").replace(".", "-")
            object.__setattr__(self, "name", f"{node}_{self.direction}_{short}")
        if not isinstance(self.name, str) or not _NAME.match(self.name) or "__" in self.name:
            raise ValueError(f"sensor.name = {self.name!r} is not allowed (letters, digits, "
                             "'_' and '-', starting with a letter, no '__')")

    @property
    def unit(self) -> str:
        return QUANTITIES[self.quantity][1]

    def check(self, rig, dofs) -> None:
        """Refuse a sensor whose DOF the rig does not have (or a reaction off a bearing)."""
        if (self.point, self.direction) not in dofs:
            raise ValueError(f"sensor {self.name!r}: no DOF ({self.point!r}, "
                             f"{self.direction!r}) in rig {rig.name!r}")
        if self.quantity == "reaction" and _bearing(rig, self.point) is None:
            nodes = ", ".join(f"shaft {b.node}" for b in rig.bearings)
            raise ValueError(f"sensor {self.name!r}: a reaction needs a bearing node "
                             f"(allowed: {nodes})")


def _bearing(rig, point: str):
    for b in rig.bearings:
        if point == f"shaft {b.node}":
            return b
    return None


def default_sensors(rig) -> tuple[Sensor, ...]:
    """Two orthogonal displacement probes (y, z) at both bearings and at the bladed disc,
    and one radial (y) accelerometer on the casing at contact element 1 — the casing
    moves only through contact in this model, so the accelerometer is silent without rub.

    Parameters
    ----------
    rig : Rig
        The rig.

    Returns
    -------
    tuple of Sensor
        The probes.
    """
    disc = rig.blades.disc_node if rig.blades is not None else rig.discs[0].node
    nodes = sorted({b.node for b in rig.bearings} | {disc})
    probes = tuple(Sensor(f"shaft {n}", d) for n in nodes for d in ("y", "z"))
    if rig.contact is None or rig.casing is None:
        return probes
    return (*probes, Sensor(f"casing {rig.contact_casing_node(1)}", "y", "acceleration"))


def check_sensors(sensors, rig) -> tuple[Sensor, ...]:
    """``sensors`` as a tuple of checked :class:`Sensor` with unique names."""
    from rubdiag.assembly import dof_map

    if isinstance(sensors, Sensor) or not hasattr(sensors, "__iter__"):
        raise _check.wrong_type("sensors", sensors, "a tuple of Sensor")
    sensors = tuple(sensors)
    dofs = dof_map(rig)
    names = set()
    for s in sensors:
        if not isinstance(s, Sensor):
            raise _check.wrong_type("sensors", s, "Sensor objects")
        s.check(rig, dofs)
        if s.name in names:
            raise ValueError(f"sensor name {s.name!r} is given twice")
        names.add(s.name)
    return sensors


@functools.lru_cache(maxsize=16)
def anti_alias_taps(factor: int) -> np.ndarray:
    """The decimation filter of a factor ``factor`` (module docstring)."""
    from scipy.signal import firwin

    return firwin(TAPS_PER_FACTOR * factor + 1, CUTOFF_OF_NYQUIST / factor,
                  window=("kaiser", KAISER_BETA))


def decimate(x: np.ndarray, factor: int) -> np.ndarray:
    """Low-pass filter and keep every ``factor``-th sample (axis 0 of a 1-D or 2-D ``x``),
    zero phase: output sample k is the filtered input at sample k·factor. The bits of
    ``scipy.signal.resample_poly(x, 1, factor, axis=0, window=anti_alias_taps(factor),
    padtype="line")``, every channel in one call (:mod:`rubdiag.simulation._decimation`)."""
    x = np.asarray(x, dtype=np.float64)
    if factor == 1:
        return x.copy()
    columns = x if x.ndim == 2 else x[:, np.newaxis]
    rows = _decimated([(columns, range(columns.shape[1]))], factor)
    return rows[0] if x.ndim == 1 else rows.T


def _decimated(streams, factor: int) -> np.ndarray:
    """:func:`decimate` of the channels of ``streams`` (``(x, columns)`` pairs: the columns
    of x (n, d) that are channels), as rows (channel, output sample)."""
    from rubdiag.simulation._decimation import fir_decimate

    if factor == 1:
        return np.array([x[:, c] for x, columns in streams for c in columns])
    return fir_decimate(streams, anti_alias_taps(factor), factor)


def sensor_signals(run, system) -> dict[str, np.ndarray]:
    """The sensors of ``run`` (a :class:`~rubdiag.simulation.Run`) from the raw stream of
    ``system`` (its SystemResult), filtered and decimated to the output rate: name -> one
    value per output sample (``system.t``)."""
    if not run.sensors:
        return {}
    from rubdiag.assembly import dof_map

    dofs = dof_map(run.rig)
    column = {int(d): j for j, d in enumerate(system.sensor_dofs)}
    factor = round(run.output_dt_s / run.dt_s)
    sources = {"displacement": system.sensor_q, "velocity": system.sensor_v,
               "acceleration": system.sensor_a}
    picked = {}                 # stream -> (sensor indices, its columns): one pass each
    reactions = []
    for j, s in enumerate(run.sensors):
        c = column[dofs.index(s.point, s.direction)]
        if s.quantity in sources:
            js, cs = picked.setdefault(s.quantity, ([], []))
            js.append(j)
            cs.append(c)
        else:
            b = _bearing(run.rig, s.point)
            k, cv = (b.k_y_n_m, b.c_y_ns_m) if s.direction == "y" else (b.k_z_n_m, b.c_z_ns_m)
            reactions.append((j, k * system.sensor_q[:, c] + cv * system.sensor_v[:, c]))
    streams = [(sources[quantity], cs) for quantity, (_, cs) in picked.items()]
    order = [j for js, _ in picked.values() for j in js]
    if reactions:
        streams.append((np.column_stack([r for _, r in reactions]), range(len(reactions))))
        order += [j for j, _ in reactions]
    rows = _decimated(streams, factor)[:, : system.t.size]
    row_of = {j: i for i, j in enumerate(order)}
    return {s.name: rows[row_of[j]] for j, s in enumerate(run.sensors)}


def sensor_dofs(run) -> list[int]:
    """The DOFs the integrator must stream for ``run``'s sensors (each once)."""
    from rubdiag.assembly import dof_map

    dofs = dof_map(run.rig)
    return sorted({dofs.index(s.point, s.direction) for s in run.sensors})
