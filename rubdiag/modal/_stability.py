"""The threshold of instability of a rotor on journal bearings.

With the films' cross-coupled stiffness (:meth:`Model.bearing_matrices`), the damped linear
model ``M q'' + (C + C_b(Ω) + Ω G) q' + (K + K_b(Ω)) q = 0`` loses stability where the real
part of one of its roots crosses zero as the speed grows: oil whirl sets in there, at the
root's frequency (near half the speed on lightly loaded bearings; the film's own ratio for
a rigid rotor). :func:`stability_threshold` finds the lowest such speed in a range: the
largest real part of the lowest roots on a grid of speeds, then Brent's method on the first
sign change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag.modal._critical import with_rayleigh
from rubdiag.modal._eigen import DENSE_BELOW, found_roots, lowest_of, lowest_roots, ritz_count

__all__ = ["StabilityThreshold", "stability_threshold", "threshold_speed", "whirl_range",
           "whirl_threshold"]


@dataclass(frozen=True)
class StabilityThreshold:
    """The speed (rad/s) at which the linear model turns unstable, and the frequency of the
    root that crosses (rad/s); ``whirl_ratio`` is their ratio.

    Parameters
    ----------
    speed_rad_s : float
        The threshold speed (rad/s).
    frequency_rad_s : float
        Frequency of the root that turns unstable there (rad/s).
    """

    speed_rad_s: float
    frequency_rad_s: float

    @property
    def whirl_ratio(self) -> float:
        return self.frequency_rad_s / self.speed_rad_s


def _rightmost(model, speed: float, n_modes: int) -> complex:
    lam, _ = lowest_roots(model, speed, n_modes)
    return complex(lam[np.argmax(lam.real)])


def stability_threshold(model, low_rad_s: float, high_rad_s: float, n_grid: int = 33,
                        n_modes: int = 6) -> StabilityThreshold | None:
    """The lowest speed in [``low_rad_s``, ``high_rad_s``] (rad/s, 0 < low < high) at which
    one of the ``n_modes`` lowest roots turns unstable (module docstring), located to 1e-9
    relative; None when the model is stable over the whole range (or unstable already at
    ``low_rad_s``: then no threshold lies in it).

    Parameters
    ----------
    model : Model
        The assembled rig.
    low_rad_s, high_rad_s : float
        The speed range searched (rad/s).
    n_grid : int
        Grid points over the range before the crossing is located.
    n_modes : int
        The lowest roots watched.

    Returns
    -------
    StabilityThreshold or None
        The threshold, or None.
    """
    speed = threshold_speed(model, low_rad_s, high_rad_s, n_grid, n_modes)
    if speed is None:
        return None
    return StabilityThreshold(speed, abs(_rightmost(model, speed, n_modes).imag))


def threshold_speed(model, low_rad_s: float, high_rad_s: float, n_grid: int = 33,
                    n_modes: int = 6) -> float | None:
    """The speed (rad/s) of :func:`stability_threshold`, without the crossing root's
    frequency (one eigenvalue problem fewer).

    Only the sign of the grid points below the first sign change matters, so the grid is
    walked up to it, each point's sign from the cheapest source that decides it
    (:func:`_first_unstable`); the bracket's two ends and every step of Brent's method are
    the roots to machine precision, as on a full grid: the same threshold to the last bit."""
    from scipy.optimize import brentq

    low = _check.positive("low_rad_s", low_rad_s, unit="rad/s")
    high = _check.number("high_rad_s", high_rad_s, lo=low, lo_open=True, unit="rad/s")
    n_grid = _check.integer("n_grid", n_grid, lo=2)
    n_modes = _check.integer("n_modes", n_modes, lo=1)
    speeds = np.linspace(low, high, n_grid)
    known: dict[float, float] = {}

    def growth(w: float) -> float:
        if w not in known:
            known[w] = _rightmost(model, w, n_modes).real
        return known[w]

    k = _first_unstable(model, speeds, n_modes, reduced=True)
    if k and not growth(speeds[k - 1]) < 0.0 <= growth(speeds[k]):
        k = _first_unstable(model, speeds, n_modes, reduced=False)   # the reduced model erred
    if not k:                     # unstable at low_rad_s (k = 0) or stable throughout
        return None
    return float(brentq(growth, speeds[k - 1], speeds[k], xtol=_THRESHOLD_TOL * speeds[k],
                        rtol=_SEARCH_RTOL))


#: ARPACK's tolerance on a grid point's roots, whose sign alone matters there
GRID_TOL = 1e-8
#: the threshold's location, relative to the speed (the 1e-9 stability_threshold promises)
_THRESHOLD_TOL = 1e-9
#: the search's relative tolerance, near float resolution: the one above decides
_SEARCH_RTOL = 1e-12
#: singular values of the projection basis below this share of the largest are dependent
#: directions (the real and imaginary parts of a real mode): left out of the basis
_RANK_TOL = 1e-10
#: how many of its error bounds a growth rate must lie from 0 for its sign to count
_MARGIN = 1e3


def _first_unstable(model, speeds: np.ndarray, n_modes: int, reduced: bool) -> int | None:
    """The index of the first of ``speeds`` where the rightmost of the ``n_modes`` lowest
    roots has a real part >= 0 (None: nowhere). A point's sign comes from the model
    projected on the first point's roots (:class:`_Reduced`, with ``reduced``) when that
    decides it, else from the roots to :data:`GRID_TOL` when their growth rate lies
    :data:`_MARGIN` error bounds from 0, else from the roots to machine precision."""
    lam, vectors = found_roots(model, speeds[0], n_modes, tol=GRID_TOL)
    if _unstable(model, speeds[0], n_modes, lowest_of(lam, vectors, n_modes)[0]):
        return 0
    projected = (_Reduced(model, vectors, speeds[0], n_modes)
                 if reduced and model.n_dof >= DENSE_BELOW else None)
    for k in range(1, len(speeds)):
        unstable = None if projected is None else projected.unstable(speeds[k])
        if unstable is None:
            lam, _ = lowest_roots(model, speeds[k], n_modes, tol=GRID_TOL)
            unstable = _unstable(model, speeds[k], n_modes, lam)
        if unstable:
            return k
    return None


def _unstable(model, speed: float, n_modes: int, lam: np.ndarray) -> bool:
    """The sign at ``speed`` from its lowest roots ``lam`` found to :data:`GRID_TOL`, when
    their growth rate lies :data:`_MARGIN` error bounds (``GRID_TOL·|λ + 1|``) from 0; else
    from the roots to machine precision."""
    growth = float(lam.real.max())
    if abs(growth) > _MARGIN * GRID_TOL * float(np.abs(lam + 1.0).max()):
        return growth >= 0.0
    return _rightmost(model, speed, n_modes).real >= 0.0


class _Reduced:
    """``model`` projected on the real span of ``vectors`` (its roots' displacement vectors
    at ``speed``) and its journal bearings' DOFs: the lowest roots at another speed from a
    dense problem of that size.

    Each root's error bound is first order in its vector's error: ``|λ| |K⁻¹ r| / |x|``,
    with ``r = Q(λ) x`` the residual in the full model (``Q(λ) = λ² M + λ D + K``) and K
    the stiffness at ``speed``. A Galerkin root's error is second order: on the whirl
    rotors of the dataset designs the bound was 900 to 9000 times the error measured
    against the roots to machine precision."""

    def __init__(self, model, vectors: np.ndarray, speed: float, n_modes: int):
        import scipy.sparse.linalg as spla

        damped = with_rayleigh(model)
        columns = [vectors.real, vectors.imag]
        K = damped.K
        if model.journal_bearings:
            Kb = model.bearing_matrices(speed)[0]
            columns.append(np.eye(model.n_dof)[:, np.unique(Kb.nonzero()[0])])
            K = K + Kb
        u, sigma, _ = np.linalg.svd(np.hstack(columns), full_matrices=False)
        V = u[:, sigma > _RANK_TOL * sigma[0]]
        self.model, self.V, self.n_modes = damped, V, n_modes
        self.stiffness = spla.splu(K.tocsc())
        self.M_inv = np.linalg.inv(V.T @ (damped.M @ V))
        self.K, self.C, self.G = (V.T @ (a @ V) for a in (damped.K, damped.C, damped.G))

    def unstable(self, speed: float) -> bool | None:
        """Whether the rightmost of the lowest roots at ``speed`` is unstable, or None when
        the reduced model cannot tell (its growth rate, or the gap between the last root
        counted and the next, within the error bounds)."""
        model, V, n = self.model, self.V, self.n_modes
        K, D = model.K, model.C + speed * model.G
        k_r, d_r = self.K, self.C + speed * self.G
        if model.journal_bearings:
            Kb, Cb = model.bearing_matrices(speed)
            K, D = K + Kb, D + Cb
            k_r, d_r = k_r + V.T @ (Kb @ V), d_r + V.T @ (Cb @ V)
        m = V.shape[1]
        A = np.block([[np.zeros((m, m)), np.eye(m)],
                      [-self.M_inv @ k_r, -self.M_inv @ d_r]])
        lam, y = np.linalg.eig(A)
        near = np.argsort(np.abs(lam + 1.0))[:ritz_count(n)]    # as the sparse solver: σ = -1
        lam, x = lowest_of(lam[near], V @ y[:m, near], n + 1)
        if len(lam) <= n:
            return None
        r = lam**2 * (model.M @ x) + lam * (D @ x) + K @ x
        dx = self.stiffness.solve(np.ascontiguousarray(r.real)) \
            + 1j * self.stiffness.solve(np.ascontiguousarray(r.imag))
        bound = np.abs(lam) * np.linalg.norm(dx, axis=0) / np.linalg.norm(x, axis=0)
        growth = float(lam[:n].real.max())
        if abs(growth) <= bound[:n].max() or lam[n].imag - lam[n - 1].imag <= bound.max():
            return None
        return growth >= 0.0


def whirl_threshold(model) -> StabilityThreshold | None:
    """The threshold of instability of a rig on journal bearings where whirl and whip are
    sought: :func:`stability_threshold` between half its first and twice its second forward
    critical speed (None when it is stable over that range).

    Parameters
    ----------
    model : Model
        The assembled rig.

    Returns
    -------
    StabilityThreshold or None
        The threshold, or None.
    """
    from rubdiag.modal._critical import critical_speeds

    return stability_threshold(model, *whirl_range(critical_speeds(model, n=2)))


def whirl_range(critical_rad_s) -> tuple[float, float]:
    """The speeds (rad/s) between which :func:`whirl_threshold` seeks the threshold: half
    the first and twice the last of the forward critical speeds ``critical_rad_s``."""
    return 0.5 * critical_rad_s[0], 2.0 * critical_rad_s[-1]
