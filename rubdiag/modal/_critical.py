"""Critical speeds: spin speeds at which an undamped natural frequency equals 1×.

A synchronous solution q = q̂ e^{iΩt} of M q'' + Ω G q' + K q = 0 exists where

    K q̂ = Ω² (M − iG) q̂,

a linear (Hermitian-pencil) eigenproblem in Ω², so the crossings of the Campbell diagram
with the 1× line are found directly, without sweeping speeds. Journal bearings make K
depend on Ω: their critical speeds are those of the undamped critical speed map — the films'
direct stiffness (y–y and z–z terms of :meth:`Model.bearing_matrices`, cross-coupling and
damping left out) at the critical speed itself, found as a root (Brent's method). Each
solution is classified by the whirl of q̂ (forward when the orbit turns with the rotor);
only modes whose kinetic energy lies mostly in the shaft and discs count as rotor critical
speeds (a stationary casing ring or a blade's own bending is not one).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from rubdiag._tolerances import REAL_ROOT
from rubdiag.assembly import rayleigh_coefficients
from rubdiag.modal._shapes import energy_shares, whirl_ratio

__all__ = ["CriticalSpeeds", "critical_speeds", "direct_film_stiffness", "synchronous_modes",
           "with_rayleigh"]

_MIN_SHAFT_SHARE = 0.25


@dataclass(frozen=True)
class CriticalSpeeds:
    """All synchronous solutions found: speeds (rad/s, ascending), shapes, whirl, shares.

    Parameters
    ----------
    speeds : numpy.ndarray
        (n,) synchronous speeds (rad/s), ascending.
    shapes : numpy.ndarray
        (n_dof, n) complex shape of each solution.
    whirl_ratio : numpy.ndarray
        (n,) whirl ratio of each shape (+1 forward … −1 backward).
    shaft_share : numpy.ndarray
        (n,) share of each shape's kinetic energy in the shaft and discs.
    """

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


def synchronous_modes(model, n_solutions: int = 12, stiffness=None) -> CriticalSpeeds:
    """The ``n_solutions`` lowest synchronous solutions (forward and backward), of
    ``model.K`` plus ``stiffness`` (sparse n×n, N/m; None: nothing) when given.

    Solved on one BLAS thread: multithreaded BLAS sums in another order, and the critical
    speeds (which define runs through ``speed_ratio`` and the Rayleigh damping) would then
    differ in their last bit with the machine's thread count.

    Parameters
    ----------
    model : Model
        The assembled rig.
    n_solutions : int
        How many solutions to seek.
    stiffness : scipy.sparse matrix or None
        Stiffness added to ``model.K`` (N/m, N·m/rad).

    Returns
    -------
    CriticalSpeeds
        The solutions found, forward and backward, ascending.
    """
    from rubdiag._blas import one_thread

    with one_thread():
        return _synchronous_modes(model, n_solutions, stiffness)


def _synchronous_modes(model, n_solutions: int, stiffness=None) -> CriticalSpeeds:
    K = model.K if stiffness is None else model.K + stiffness
    K, B = K.tocsc(), (model.M - 1j * model.G).tocsc()
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
    ok = np.isfinite(lam) & (lam.real > 0) & (np.abs(lam.imag) < REAL_ROOT * np.abs(lam))
    lam, vec = lam[ok].real, vec[:, ok]
    order = np.argsort(lam)
    speeds, shapes = np.sqrt(lam[order]), vec[:, order]
    return CriticalSpeeds(speeds=speeds, shapes=shapes, whirl_ratio=whirl_ratio(model, shapes),
                          shaft_share=energy_shares(model, shapes)["shaft_share"])


def critical_speeds(model, n: int = 2, whirl: str = "forward") -> np.ndarray:
    """The ``n`` lowest rotor critical speeds (rad/s) of the given whirl direction.

    Fewer are returned when the model has fewer (e.g. a rigid-disc rotor with strong
    gyroscopic stiffening has no forward conical critical speed).

    Parameters
    ----------
    model : Model
        The assembled rig.
    n : int
        How many critical speeds (>= 1).
    whirl : {"forward", "backward"}
        The whirl direction.

    Returns
    -------
    numpy.ndarray
        Up to ``n`` critical speeds (rad/s), ascending.

    Examples
    --------
    A Jeffcott rotor's critical speed against its textbook value: the examples of
    :mod:`rubdiag.modal`.
    """
    if whirl not in ("forward", "backward"):
        raise ValueError(f"whirl = {whirl!r} is not allowed (allowed: forward, backward)")
    if n < 1:
        raise ValueError(f"n = {n!r} is out of range (allowed: >= 1)")
    if model.journal_bearings:
        return _with_films(model, n, whirl)
    return _lowest(model, n, whirl)


def _lowest(model, n: int, whirl: str, stiffness=None) -> np.ndarray:
    k = 4 * n + 8
    while True:
        found = synchronous_modes(model, n_solutions=k, stiffness=stiffness)
        speeds = found.forward if whirl == "forward" else found.backward
        if len(speeds) >= n or k >= model.n_dof - 2:
            return speeds[:n]
        k = min(2 * k, model.n_dof - 2)


#: the critical speed map's search: the lowest speed tried (rad/s), and how far above the
#: rigid-bearing critical speed the bracket reaches
_MAP_LOW_RAD_S = 1.0
_MAP_HIGH_FACTOR = 10.0
#: the search's tolerance on the log of a speed (absolute and relative): near its float
#: resolution, so that a critical speed of the map is its crossing to about 1e-13
_MAP_TOL = 1e-13
#: the rigid bearings the bracket's top is computed with (N/m)
_RIGID_N_M = 1e13


def direct_film_stiffness(model, speed: float):
    """The journal bearings' direct stiffness at Ω (rad/s): the y–y and z–z terms of
    :meth:`Model.bearing_matrices` (N/m), what an undamped critical speed map uses.

    Parameters
    ----------
    model : Model
        The assembled rig, on journal bearings.
    speed : float
        Spin speed Ω (rad/s).

    Returns
    -------
    scipy.sparse.csr_matrix
        (n_dof, n_dof) the films' direct stiffness terms (N/m).
    """
    import scipy.sparse as sp

    Kb, _ = model.bearing_matrices(speed)
    Kb = Kb.tocoo()
    direction = model.dofs.directions
    keep = direction[Kb.row] == direction[Kb.col]
    return sp.csr_matrix((Kb.data[keep], (Kb.row[keep], Kb.col[keep])), shape=Kb.shape)


def _rigid_film_stiffness(model):
    """Stiff springs in place of every film (y and z at the journal, to ground)."""
    import scipy.sparse as sp

    idx = [model.dofs.index(model.rig.bearings[k].node, d)
           for k in model.journal_bearings for d in ("y", "z")]
    return sp.csr_matrix((np.full(len(idx), _RIGID_N_M), (idx, idx)),
                         shape=(model.n_dof, model.n_dof))


def _with_films(model, n: int, whirl: str) -> np.ndarray:
    """Each of the ``n`` lowest critical speeds of the map: the root of ω_j(Ω) = Ω, with
    ω_j(Ω) the j-th synchronous solution with the films' direct stiffness at Ω (module
    docstring), by Brent's method on log Ω between :data:`_MAP_LOW_RAD_S` (where a film is
    nearly rigid: ω_j > Ω) and ten times the rigid-bearing critical speed (ω_j < Ω: no film
    is stiffer than a rigid bearing)."""
    from scipy.optimize import brentq

    rigid = _lowest(model, n, whirl, _rigid_film_stiffness(model))
    out = []
    for j in range(len(rigid)):
        def excess(u, j=j):
            found = _lowest(model, j + 1, whirl, direct_film_stiffness(model, np.exp(u)))
            return (math.log(found[j]) if len(found) > j else math.inf) - u

        low, high = math.log(_MAP_LOW_RAD_S), math.log(_MAP_HIGH_FACTOR * rigid[j])
        if not excess(low) > 0.0 > excess(high):
            raise ValueError(f"the critical speed map has no crossing for mode {j + 1} "
                             f"between {_MAP_LOW_RAD_S:g} and {math.exp(high):.6g} rad/s")
        out.append(math.exp(brentq(excess, low, high, xtol=_MAP_TOL, rtol=_MAP_TOL)))
    return np.array(out)


def with_rayleigh(model):
    """``model`` with its Rayleigh damping known: unchanged when the rig gives reference
    speeds, else a copy whose reference speeds are its first two forward critical speeds
    (the study's choice).

    Parameters
    ----------
    model : Model
        The assembled rig.

    Returns
    -------
    Model
        ``model`` or a copy with ``rayleigh`` set (α in 1/s, β in s).
    """
    if model.rayleigh is not None:
        return model
    found = critical_speeds(model, n=2)
    if len(found) < 2:
        raise ValueError("Damping.reference_speeds_rad_s is not set and the rig has fewer "
                         "than two forward critical speeds: give them")
    damping = model.rig.damping
    alpha_beta = rayleigh_coefficients(found[0], found[1], damping.xi_1, damping.xi_2)
    return dataclasses.replace(model, rayleigh=alpha_beta)
