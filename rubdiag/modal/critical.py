"""Critical speeds: spin speeds at which an undamped natural frequency equals 1×.

A synchronous solution q = q̂ e^{iΩt} of M q'' + Ω G q' + K q = 0 exists where

    K q̂ = Ω² (M − iG) q̂,

a linear (Hermitian-pencil) eigenproblem in Ω², so the crossings of the Campbell diagram
with the 1× line are found directly, without sweeping speeds. Each solution is classified
by the whirl of q̂ (forward when the orbit turns with the rotor); only modes whose kinetic
energy lies mostly in the shaft and discs count as rotor critical speeds (a stationary
casing ring or a blade's own bending is not one).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from rubdiag.assembly import rayleigh_coefficients
from rubdiag.modal.shapes import energy_shares, whirl_ratio

__all__ = ["CriticalSpeeds", "critical_speeds", "synchronous_modes", "with_rayleigh"]

_MIN_SHAFT_SHARE = 0.25


@dataclass(frozen=True)
class CriticalSpeeds:
    """All synchronous solutions found: speeds (rad/s, ascending), shapes, whirl, shares."""

    speeds: np.ndarray
    shapes: np.ndarray
    whirl_ratio: np.ndarray
    shaft_share: np.ndarray

    @property
    def forward(self) -> np.ndarray:
        """Forward-whirl rotor critical speeds (rad/s), ascending."""
        mask = (self.whirl_ratio > 0) & (self.shaft_share >= _MIN_SHAFT_SHARE)
        return self.speeds[mask]

    @property
    def backward(self) -> np.ndarray:
        mask = (self.whirl_ratio < 0) & (self.shaft_share >= _MIN_SHAFT_SHARE)
        return self.speeds[mask]


def synchronous_modes(model, n_solutions: int = 12) -> CriticalSpeeds:
    """The ``n_solutions`` lowest synchronous solutions (forward and backward).

    Solved on one BLAS thread: multithreaded BLAS sums in another order, and the critical
    speeds (which define runs through ``speed_ratio`` and the Rayleigh damping) would then
    differ in their last bit with the machine's thread count."""
    from threadpoolctl import threadpool_limits  # installed with scikit-learn

    with threadpool_limits(limits=1):
        return _synchronous_modes(model, n_solutions)


def _synchronous_modes(model, n_solutions: int) -> CriticalSpeeds:
    K, B = model.K.tocsc(), (model.M - 1j * model.G).tocsc()
    n = model.n_dof
    if n <= 120:
        lam, vec = sla.eig(K.toarray(), B.toarray())
    else:
        sigma = -1.0
        lu = spla.splu((K - sigma * B).tocsc())
        op = spla.LinearOperator((n, n), matvec=lambda x: lu.solve(B @ x), dtype=complex)
        v0 = np.ones(n, dtype=complex)   # a fixed start: the same speeds to the last bit every call
        nu, vec = spla.eigs(op, k=min(n - 2, n_solutions), which="LM", v0=v0)
        lam = sigma + 1.0 / nu
    # Ω² must be real and positive (an indefinite M − iG gives spurious roots)
    ok = np.isfinite(lam) & (lam.real > 0) & (np.abs(lam.imag) < 1e-6 * np.abs(lam))
    lam, vec = lam[ok].real, vec[:, ok]
    order = np.argsort(lam)
    speeds, shapes = np.sqrt(lam[order]), vec[:, order]
    return CriticalSpeeds(speeds=speeds, shapes=shapes, whirl_ratio=whirl_ratio(model, shapes),
                          shaft_share=energy_shares(model, shapes)["shaft_share"])


def critical_speeds(model, n: int = 2, whirl: str = "forward") -> np.ndarray:
    """The ``n`` lowest rotor critical speeds (rad/s) of the given whirl direction.

    Fewer are returned when the model has fewer (e.g. a rigid-disc rotor with strong
    gyroscopic stiffening has no forward conical critical speed).
    """
    if whirl not in ("forward", "backward"):
        raise ValueError(f"whirl = {whirl!r} is not allowed (allowed: forward, backward)")
    if n < 1:
        raise ValueError(f"n = {n!r} is out of range (allowed: >= 1)")
    k = 4 * n + 8
    while True:
        found = synchronous_modes(model, n_solutions=k)
        speeds = found.forward if whirl == "forward" else found.backward
        if len(speeds) >= n or k >= model.n_dof - 2:
            return speeds[:n]
        k = min(2 * k, model.n_dof - 2)


def with_rayleigh(model):
    """``model`` with its Rayleigh damping known: unchanged when the rig gives reference
    speeds, else a copy whose reference speeds are its first two forward critical speeds
    (the study's choice)."""
    if model.rayleigh is not None:
        return model
    found = critical_speeds(model, n=2)
    if len(found) < 2:
        raise ValueError("Damping.reference_speeds_rad_s is not set and the rig has fewer "
                         "than two forward critical speeds: give them")
    damping = model.rig.damping
    alpha_beta = rayleigh_coefficients(found[0], found[1], damping.xi_1, damping.xi_2)
    return dataclasses.replace(model, rayleigh=alpha_beta)
