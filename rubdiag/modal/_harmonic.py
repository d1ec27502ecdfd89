"""Steady-state harmonic (unbalance) response of the linear rig.

At spin speed Ω an unbalance load f(t) = Re(F̂ e^{iΩt}) gives q(t) = Re(q̂ e^{iΩt}) with

    (K − Ω² M + iΩ (C + Ω G)) q̂ = F̂.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from rubdiag import _check
from rubdiag.modal._critical import with_rayleigh
from rubdiag.model import Unbalance

__all__ = ["HarmonicResponse", "UnbalanceResponse", "harmonic_response", "unbalance_response"]


def _check_speed(speed: float) -> float:
    return _check.positive("speed", speed, unit="rad/s")


def _solve(model, unbalance: Unbalance, speed: float) -> np.ndarray:
    C = with_rayleigh(model).C
    K = model.K
    if model.journal_bearings:      # the films linearised at this speed
        Kb, Cb = model.bearing_matrices(speed)
        K, C = K + Kb, C + Cb
    Z = (K - speed**2 * model.M + 1j * speed * (C + speed * model.G)).tocsc()
    return spla.splu(Z).solve(model.unbalance_force(unbalance, speed))


@dataclass(frozen=True)
class HarmonicResponse:
    """q(t) = Re(q̂ e^{iΩt}) at one speed; ``amplitudes`` is q̂ (m, rad), one per DOF.

    Parameters
    ----------
    speed : float
        Spin speed Ω (rad/s).
    amplitudes : numpy.ndarray
        (n_dof,) complex amplitudes q̂ (m, rad).
    dofs : DofMap
        The names of the DOFs.
    """

    speed: float
    amplitudes: np.ndarray
    dofs: object

    def displacement(self, t: float) -> np.ndarray:
        return np.real(self.amplitudes * np.exp(1j * self.speed * t))

    def velocity(self, t: float) -> np.ndarray:
        return np.real(1j * self.speed * self.amplitudes * np.exp(1j * self.speed * t))

    def amplitude(self, node: str | int, direction: str) -> complex:
        """Complex amplitude of one DOF, e.g. ``amplitude(11, "y")``."""
        return self.amplitudes[self.dofs.index(node, direction)]

    def orbit_semi_major(self, node: str | int) -> float:
        """Largest lateral displacement (m) over the orbit of a node."""
        return _semi_major(self.amplitude(node, "y"), self.amplitude(node, "z"))

    def shaft_deflection(self):
        """Per shaft node: (``|q̂_y|``, ``|q̂_z|``, orbit semi-major axis), all in m."""
        y = np.array([self.amplitude(lbl, "y") for lbl in self._shaft_labels()])
        z = np.array([self.amplitude(lbl, "z") for lbl in self._shaft_labels()])
        return np.abs(y), np.abs(z), _semi_major(y, z)

    def _shaft_labels(self):
        return [label for label, _ in self.dofs.nodes if label.startswith("shaft ")]


def _semi_major(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return np.sqrt(0.5 * (np.abs(a) ** 2 + np.abs(b) ** 2 + np.abs(a**2 + b**2)))


def harmonic_response(model, speed: float, unbalance: Unbalance) -> HarmonicResponse:
    """Steady unbalance response of the linear model at spin speed ``speed`` (rad/s).

    Parameters
    ----------
    model : Model
        The assembled rig.
    speed : float
        Spin speed Ω (rad/s).
    unbalance : Unbalance
        The unbalance per disc.

    Returns
    -------
    HarmonicResponse
        The complex amplitude of every DOF.
    """
    speed = _check_speed(speed)
    return HarmonicResponse(speed=speed, amplitudes=_solve(model, unbalance, speed),
                            dofs=model.dofs)


@dataclass(frozen=True)
class UnbalanceResponse:
    """Unbalance response against speed at chosen response points.

    ``amplitudes[i, j]`` is the complex amplitude (m) at ``speeds[i]`` (rad/s) of point
    ``points[j]`` (a (node, direction) pair).

    Parameters
    ----------
    speeds : numpy.ndarray
        (n_speeds,) spin speeds (rad/s).
    points : tuple of (str or int, str)
        The response points, (node, direction) pairs.
    amplitudes : numpy.ndarray
        (n_speeds, n_points) complex amplitudes (m).
    """

    speeds: np.ndarray
    points: tuple[tuple[str | int, str], ...]
    amplitudes: np.ndarray

    def peak_speed(self, point: int = 0) -> float:
        """Speed (rad/s) of the largest amplitude of a response point."""
        return float(self.speeds[np.argmax(np.abs(self.amplitudes[:, point]))])

    def to_frame(self):
        import pandas as pd

        data = {"speed_rpm": self.speeds * 30.0 / np.pi}
        for j, (node, direction) in enumerate(self.points):
            name = f"{node}".replace(" ", "") + f"_{direction}"
            data[f"{name}_amplitude_m"] = np.abs(self.amplitudes[:, j])
            data[f"{name}_phase_rad"] = np.angle(self.amplitudes[:, j])
        return pd.DataFrame(data)


def unbalance_response(model, speeds, unbalance: Unbalance,
                       points=((11, "y"),)) -> UnbalanceResponse:
    """Linear unbalance response over ``speeds`` (rad/s) at ``points`` ((node, dir) pairs).

    The paper rig's Fig. 5 is ``points=((11, "y"),)`` for cases 1 and 2.

    Parameters
    ----------
    model : Model
        The assembled rig.
    speeds : array_like of float
        Spin speeds (rad/s).
    unbalance : Unbalance
        The unbalance per disc.
    points : sequence of (str or int, str)
        Response points: a shaft node number or node label, and a direction.

    Returns
    -------
    UnbalanceResponse
        The complex amplitudes at every speed and point.
    """
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size == 0:
        raise ValueError("speeds must be a non-empty 1-D array (rad/s)")
    for s in speeds:
        _check_speed(s)
    points = tuple(points)
    index = [model.dofs.index(node, direction) for node, direction in points]
    out = np.empty((speeds.size, len(points)), dtype=complex)
    for i, speed in enumerate(speeds):
        out[i] = _solve(model, unbalance, speed)[index]
    return UnbalanceResponse(speeds=speeds, points=points, amplitudes=out)
