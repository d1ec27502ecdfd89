"""The linear system a run integrates: the :class:`LinearSystem` a user gives, checked."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag import _check
from rubdiag.simulation._loads import HarmonicForce
from rubdiag.simulation._speed_profile import SpeedProfile

__all__ = ["Checked", "LinearSystem", "checked", "checked_matrix", "initial_acceleration"]


@dataclass(frozen=True, kw_only=True)
class LinearSystem:
    """``M q'' + C q' + K q = f(t) + Σ_e B_eᵀ p_e``, where it starts and how fast it spins.

    ``p_e`` are the forces of the nonlinear elements (contacts, films, cracks), ``B_e``
    their local coordinates. M must be nonsingular; the energy ledger assumes M and K
    symmetric (C may carry a skew gyroscopic part, which does no work).

    Parameters
    ----------
    M, C, K : array_like or scipy.sparse matrix
        (n, n) mass (kg), damping (N s/m; damping + Ω G, constant) and stiffness (N/m).
    force : HarmonicForce or None
        The external load (N); None: none.
    q0, v0 : numpy.ndarray or None
        (n,) the start state (m, m/s); None: zeros.
    a0 : numpy.ndarray or None
        (n,) the start acceleration (m/s²); None: from equilibrium, ``M a0 = f(0) + Bᵀp(q0)
        - C v0 - K q0``.
    omega : float
        The shaft speed Ω (rad/s): the surface speed Ω R of annular clearances, the angle
        Ω t of the element laws.
    gyroscopic : array_like or scipy.sparse matrix or None
        (n, n) the unit-speed gyroscopic matrix G (N s/m per rad/s), needed with
        ``speed_profile``.
    speed_profile : SpeedProfile or None
        A spin speed that changes in time: the damping is then ``C + Ω(t) G`` with C
        without the gyroscopic part, the load rotates with the shaft angle, and ``omega``
        must be the profile's start speed. None: constant speed ``omega``.
    speed_tolerance : float
        Ω(t) G is held at a reference speed over stretches in which Ω stays within this of
        it (relative, in (0, 0.5]; 0: a stretch per largest step).
    recovery : numpy.ndarray or None
        (n_phys, n): the coordinates are generalised (a reduced model) and the physical
        displacements are ``recovery @ q``. None: q is physical.
    """

    M: object
    C: object
    K: object
    force: HarmonicForce | None = None
    q0: np.ndarray | None = None
    v0: np.ndarray | None = None
    a0: np.ndarray | None = None
    omega: float = 0.0
    gyroscopic: object = None
    speed_profile: SpeedProfile | None = None
    speed_tolerance: float = 0.005
    recovery: np.ndarray | None = None


class Checked(NamedTuple):
    """A :class:`LinearSystem`'s matrices (CSR float64), load (never None) and start state
    (float64), checked."""

    M: sp.csr_matrix
    C: sp.csr_matrix
    K: sp.csr_matrix
    force: HarmonicForce
    q0: np.ndarray
    v0: np.ndarray


def checked_matrix(name: str, A, n: int | None) -> sp.csr_matrix:
    """``A`` as a CSR float64 (n, n) matrix with sorted, summed entries; a wrong shape or a
    non-finite entry raises ``ValueError`` naming ``name``."""
    if not sp.issparse(A):
        A = sp.csr_matrix(np.asarray(A, dtype=np.float64))
    A = sp.csr_matrix(A, dtype=np.float64)
    if A.shape[0] != A.shape[1] or (n is not None and A.shape[0] != n):
        raise ValueError(f"{name} has shape {A.shape}: must be square n x n (n = {n})")
    if not np.all(np.isfinite(A.data)):
        raise ValueError(f"{name} contains NaN or inf: all entries must be finite")
    A.sum_duplicates()
    A.sort_indices()
    return A


def checked(system: LinearSystem) -> Checked:
    """``system``'s matrices, load and start state, checked and converted."""
    if not isinstance(system, LinearSystem):
        raise _check.wrong_type("system", type(system).__name__, "a LinearSystem")
    M = checked_matrix("M", system.M, None)
    n = M.shape[0]
    C = checked_matrix("C", system.C, n)
    K = checked_matrix("K", system.K, n)
    force = HarmonicForce.zero() if system.force is None else system.force
    start = []
    for name, vec in (("q0", system.q0), ("v0", system.v0)):
        vec = np.zeros(n) if vec is None else np.asarray(vec, dtype=np.float64).reshape(-1)
        if vec.shape != (n,):
            raise ValueError(f"{name} has shape {vec.shape}: must be ({n},)")
        if not np.all(np.isfinite(vec)):
            raise _check.out_of_range(
                name, f"<array with {int(np.sum(~np.isfinite(vec)))} non-finite>", "finite")
        start.append(vec)
    if force.dofs.size:
        if np.any(force.dofs < 0) or np.any(force.dofs >= n):
            raise _check.out_of_range("force.dofs", force.dofs.tolist(),
                                      f"DOF indices in [0, {n})")
        if not (np.all(np.isfinite(force.amplitudes)) and np.all(np.isfinite(force.omega))):
            raise _check.out_of_range("force", "amplitudes/omega with NaN or inf", "finite")
    return Checked(M, C, K, force, *start)


def initial_acceleration(M, C, K, f0: np.ndarray, B, p0, q0, v0, a0) -> np.ndarray:
    """``a0`` checked, or from equilibrium at t = 0: ``M a0 = f0 + Bᵀp0 - C v0 - K q0``."""
    n = M.shape[0]
    if a0 is None:
        try:
            lu_m = spla.splu(sp.csc_matrix(M))
        except RuntimeError as exc:
            raise ValueError(f"M is singular ({exc}): pass a0 explicitly") from exc
        a0 = lu_m.solve(f0 + B.T @ p0 - C @ v0 - K @ q0)
    a0 = np.asarray(a0, dtype=np.float64).reshape(-1)
    if a0.shape != (n,) or not np.all(np.isfinite(a0)):
        raise _check.out_of_range("a0", "<array>", f"finite, shape ({n},)")
    return a0
