"""Natural frequencies and mode shapes at a spin speed, with gyroscopic effects.

The quadratic eigenproblem (λ²M + λ(C + ΩG) + K) q = 0 is solved in first-order form,
A x = λ B x with x = (q, λq), A = [[0, I], [−K, −D]], B = [[I, 0], [0, M]], by shift-invert
Arnoldi near λ = σ (small, so the lowest modes come first and rigid-body modes do not make
the operator singular). Each mode is classified by its whirl: at every node the lateral
motion (u_y, u_z) = Re((a, b) e^{λt}) traces an ellipse, run forwards (from +y to +z, like
the rotor) when Im(a·conj(b)) > 0. The whirl ratio sums 2·Im(a·conj(b)) over the shaft's
nodes, normalised by Σ(|a|² + |b|²): +1 is a circular forward orbit, −1 backward.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag._tolerances import PLANAR_WHIRL
from rubdiag.modal._critical import with_rayleigh
from rubdiag.modal._shapes import energy_shares, whirl_ratio

__all__ = ["Modes", "modes"]

DENSE_BELOW = 120   # DOFs; below this a dense solver is faster and complete
#: The share of its modulus (at least 1) a root's frequency must exceed to be an oscillating
#: mode: an overdamped (real) root's imaginary part is rounding.
_OSCILLATING = 1e-9


@dataclass(frozen=True)
class Modes:
    """Modes at one spin speed, sorted by natural frequency.

    Parameters
    ----------
    speed : float
        Spin speed Ω (rad/s).
    eigenvalues : ndarray of complex, (n_modes,)
        λ = −ξω_n + iω_d (1/s).
    shapes : ndarray of complex, (n_dof, n_modes)
        Displacement part of each eigenvector, unit max-norm.
    whirl_ratio : ndarray (n_modes,)
        +1 circular forward whirl … −1 circular backward (see module docstring).
    shaft_share, blade_share, casing_share : ndarray (n_modes,)
        Fraction of the mode's kinetic energy in each component.
    """

    speed: float
    eigenvalues: np.ndarray
    shapes: np.ndarray
    whirl_ratio: np.ndarray
    shaft_share: np.ndarray
    blade_share: np.ndarray
    casing_share: np.ndarray

    @property
    def damped_frequencies(self) -> np.ndarray:
        """ω_d (rad/s)."""
        return self.eigenvalues.imag

    @property
    def natural_frequencies(self) -> np.ndarray:
        """``|λ|`` (rad/s): the undamped natural frequency for light damping."""
        return np.abs(self.eigenvalues)

    @property
    def damping_ratios(self) -> np.ndarray:
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def whirl(self) -> np.ndarray:
        """'forward', 'backward' or 'none' (planar, or no shaft motion) per mode."""
        w = self.whirl_ratio
        return np.where(w > PLANAR_WHIRL, "forward",
                        np.where(w < -PLANAR_WHIRL, "backward", "none"))

    def to_frame(self):
        import pandas as pd

        return pd.DataFrame({
            "frequency_hz": self.damped_frequencies / (2 * np.pi),
            "damping_ratio": self.damping_ratios,
            "whirl": self.whirl,
            "whirl_ratio": self.whirl_ratio,
            "shaft_share": self.shaft_share,
            "blade_share": self.blade_share,
            "casing_share": self.casing_share,
        })


def modes(model, speed: float = 0.0, n_modes: int = 10, damped: bool = True) -> Modes:
    """The ``n_modes`` lowest oscillating modes of ``model`` at spin speed Ω (rad/s).

    ``damped=False`` leaves out C (gyroscopic effects stay), giving the undamped natural
    frequencies. Overdamped (non-oscillating) roots are left out. Journal bearings add their
    films' stiffness and (when damped) damping at Ω (:meth:`Model.bearing_matrices`):
    speed-dependent and cross-coupled, so a mode's damping ratio may be negative (unstable)
    above the threshold of instability (:func:`rubdiag.modal.stability_threshold`).

    Parameters
    ----------
    model : Model
        The assembled rig.
    speed : float
        Spin speed Ω (rad/s, >= 0).
    n_modes : int
        How many modes (>= 1).
    damped : bool
        Include the damping matrix.

    Returns
    -------
    Modes
        The modes, sorted by frequency.
    """
    if not np.isfinite(speed) or speed < 0:
        raise ValueError(f"speed = {speed!r} is out of range (allowed: >= 0 rad/s)")
    if n_modes < 1:
        raise ValueError(f"n_modes = {n_modes!r} is out of range (allowed: >= 1)")
    lam, shapes = lowest_roots(model, speed, n_modes, damped)
    shapes = shapes / _max_entry(shapes)
    shares = energy_shares(model, shapes)
    return Modes(speed=float(speed), eigenvalues=lam, shapes=shapes,
                 whirl_ratio=whirl_ratio(model, shapes), **shares)


def lowest_roots(model, speed: float, n_modes: int, damped: bool = True,
                 tol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The roots λ (1/s) of :func:`modes` and their displacement vectors (not normalised),
    without the per-mode quantities: what a search over speeds evaluates. ``tol``: ARPACK's
    relative accuracy of the shift-inverted Ritz values (0: machine precision, as
    :func:`modes`), so that each root is within about ``tol·|λ + 1|`` of its value."""
    return lowest_of(*found_roots(model, speed, n_modes, damped, tol), n_modes)


def found_roots(model, speed: float, n_modes: int, damped: bool = True,
                tol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Every root (and displacement vector) the eigensolver finds when asked for the
    ``n_modes`` lowest: on a large model the ``2·n_modes + 10`` nearest its shift, on a
    small one (below :data:`DENSE_BELOW` DOFs) all of them; :func:`lowest_of` picks."""
    n = model.n_dof
    D = with_rayleigh(model).C + speed * model.G if damped else speed * model.G
    K = model.K
    if model.journal_bearings:      # the films' coefficients at this speed
        Kb, Cb = model.bearing_matrices(speed)
        K, D = K + Kb, (D + Cb if damped else D)
    return _quadratic_eigs(model.M, D, K, min(n_modes, n), tol)


def lowest_of(lam: np.ndarray, vectors: np.ndarray,
              n_modes: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_modes`` lowest oscillating roots (by frequency) among ``lam`` and their
    columns of ``vectors``: overdamped (real) roots and the negative-frequency twins are left
    out."""
    keep = lam.imag > _OSCILLATING * np.maximum(1.0, np.abs(lam))
    lam, vectors = lam[keep], vectors[:, keep]
    order = np.argsort(lam.imag)[:n_modes]
    return lam[order], vectors[:, order]


def ritz_count(n_modes: int) -> int:
    """How many roots nearest its shift the sparse eigensolver computes for ``n_modes``."""
    return 2 * n_modes + 10


def _max_entry(shapes: np.ndarray) -> np.ndarray:
    idx = np.argmax(np.abs(shapes), axis=0)
    return shapes[idx, np.arange(shapes.shape[1])]


def _quadratic_eigs(M, D, K, n_modes: int, tol: float = 0.0):
    n = M.shape[0]
    eye = sp.identity(n, format="csr")
    A = sp.bmat([[None, eye], [-K, -D]], format="csc")
    B = sp.bmat([[eye, None], [None, M]], format="csc")
    # σ: a small negative shift, well below the lowest elastic frequency
    sigma = -1.0
    if n < DENSE_BELOW:
        lam, vec = sla.eig(A.toarray(), B.toarray())
        finite = np.isfinite(lam)
        return lam[finite], vec[:n, finite]
    lu = spla.splu((A - sigma * B).tocsc())
    op = spla.LinearOperator((2 * n, 2 * n), matvec=lambda x: lu.solve(B @ x),
                             dtype=float)
    k = min(2 * n - 2, ritz_count(n_modes))
    nu, vec = spla.eigs(op, k=k, which="LM", v0=np.ones(2 * n),   # fixed start: reproducible
                        tol=tol)
    return sigma + 1.0 / nu, vec[:n]
