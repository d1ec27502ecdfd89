"""Craig–Bampton reduction: physical boundary DOFs plus fixed-interface normal modes.

The DOFs split into a boundary set b (kept physical: the contact DOFs, where the only
nonlinearity acts) and the interior i. The interior motion is the static response to the
boundary (constraint modes ``Ψ = -K_ii⁻¹ K_ib``) plus the interior's own normal modes with
the boundary held fixed (``K_ii φ = ω² M_ii φ``), kept below a cutoff frequency::

    q = T x,   T = [[I, 0], [Ψ, Φ]],   x = (u_b, η)

with Φ mass-normalised. Every matrix is projected the same way (``T̃ᵀ X T̃`` for M, K, C and
the unit-speed gyroscopic G, whose product with Ω is then formed at run time), so the
reduced model is a congruence of the full one: symmetric M, K stay symmetric, the skew G
stays skew, and the reduced static flexibility at the boundary is exact (the constraint
modes span every static boundary load; only the interior inertia beyond the cutoff is
lost).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

__all__ = ["CraigBampton", "craig_bampton"]


@dataclass(frozen=True)
class CraigBampton:
    """A Craig–Bampton basis.

    Parameters
    ----------
    boundary : (n_b,) int
        The physical DOFs kept, ascending; reduced coordinate k < n_b is DOF ``boundary[k]``.
    T : (n, n_b + n_m)
        Recovery: physical displacements ``q = T x``.
    mode_frequencies_hz : (n_m,)
        Natural frequencies of the fixed-interface modes kept (Hz), ascending.
    first_dropped_hz : float
        The lowest fixed-interface mode left out (Hz; inf when none is).
    """

    boundary: np.ndarray
    T: np.ndarray
    mode_frequencies_hz: np.ndarray
    first_dropped_hz: float

    @property
    def n_reduced(self) -> int:
        return int(self.T.shape[1])

    def project(self, A) -> np.ndarray:
        """``Tᵀ A T`` as a dense array (A sparse or dense, n × n)."""
        return np.ascontiguousarray(self.T.T @ (A @ self.T))

    def boundary_index(self, dofs) -> np.ndarray:
        """Reduced coordinates of physical boundary DOFs (-1 stays -1: ground)."""
        dofs = np.asarray(dofs, dtype=np.int64)
        where = np.searchsorted(self.boundary, dofs)
        where = np.minimum(where, self.boundary.size - 1)
        ok = (dofs < 0) | (self.boundary[where] == dofs)
        if not ok.all():
            raise ValueError(f"DOFs {dofs[~ok].tolist()} are not boundary DOFs of the "
                             "reduction (only the contact DOFs stay physical)")
        return np.where(dofs < 0, -1, where).astype(np.int64)


def craig_bampton(M, K, boundary, cutoff_hz: float) -> CraigBampton:
    """The Craig–Bampton basis of (M, K) keeping ``boundary`` DOFs physical and every
    fixed-interface mode below ``cutoff_hz`` (Hz).

    Parameters
    ----------
    M, K : (n, n) array_like or sparse matrix
        Mass and stiffness matrices (SI), symmetric; the interior block of K must
        be nonsingular (the boundary holds the structure, or the interior is supported on
        its own).
    boundary : sequence of int
        The DOFs kept physical (indices in [0, n), at least one; sorted and made unique).
    cutoff_hz : float
        The fixed-interface modes below this frequency are kept (Hz, > 0).

    Returns
    -------
    CraigBampton
        The basis ``T`` (boundary DOFs first, then the modes, mass-normalised with their
        largest entry positive) and the kept and first dropped mode frequencies (Hz).

    Raises
    ------
    ValueError
        An empty or out-of-range boundary, a cutoff not > 0, or a singular interior
        stiffness.

    See Also
    --------
    reduced_model : The reduction of a rig, with its contact DOFs as the boundary.

    Examples
    --------
    Two unit masses between three unit springs, DOF 0 kept: the constraint mode moves DOF 1
    by half of DOF 0, and DOF 1's mode with DOF 0 held has ω² = 2 (rad/s)²:

    >>> import numpy as np
    >>> M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])
    >>> cb = craig_bampton(M, K, boundary=[0], cutoff_hz=1.0)
    >>> cb.T
    array([[1. , 0. ],
           [0.5, 1. ]])
    >>> print(f"{cb.mode_frequencies_hz[0]:.4f} Hz")       # sqrt(2) / (2 pi)
    0.2251 Hz

    With the mode dropped, the boundary's static stiffness is still exact,
    2 - 1 × 1 / 2 = 1.5 N/m:

    >>> craig_bampton(M, K, boundary=[0], cutoff_hz=0.1).project(K)
    array([[1.5]])
    """
    M = sp.csr_matrix(M)
    K = sp.csr_matrix(K)
    n = M.shape[0]
    boundary = np.unique(np.asarray(boundary, dtype=np.int64))
    if boundary.size == 0 or boundary[0] < 0 or boundary[-1] >= n:
        raise ValueError(f"boundary DOFs must be a non-empty set of indices in [0, {n})")
    if not (np.isfinite(cutoff_hz) and cutoff_hz > 0):
        raise ValueError(f"cutoff_hz = {cutoff_hz!r} is out of range (allowed: > 0 Hz)")
    interior = np.setdiff1d(np.arange(n), boundary)
    K_ii = K[interior][:, interior].toarray()
    K_ib = K[interior][:, boundary].toarray()
    M_ii = M[interior][:, interior].toarray()
    try:
        psi = -sla.solve(K_ii, K_ib, assume_a="sym")
    except (sla.LinAlgError, ValueError) as exc:
        raise ValueError("the interior stiffness K_ii is singular: the boundary does not "
                         f"hold the structure ({exc})") from None
    # the interior's modes with the boundary fixed; eigh normalises Φᵀ M_ii Φ = I
    omega2, phi = sla.eigh(K_ii, M_ii)
    freqs = np.sqrt(np.maximum(omega2, 0.0)) / (2.0 * np.pi)
    keep = freqs < cutoff_hz
    phi = _fix_signs(phi[:, keep])
    n_b, n_m = boundary.size, int(keep.sum())
    T = np.zeros((n, n_b + n_m))
    T[boundary, np.arange(n_b)] = 1.0
    T[np.ix_(interior, np.arange(n_b))] = psi
    T[np.ix_(interior, n_b + np.arange(n_m))] = phi
    dropped = freqs[~keep]
    return CraigBampton(boundary=boundary, T=T, mode_frequencies_hz=freqs[keep],
                        first_dropped_hz=float(dropped.min()) if dropped.size else np.inf)


def _fix_signs(phi: np.ndarray) -> np.ndarray:
    """Each mode with its largest entry positive: the basis does not depend on the sign
    LAPACK happens to return."""
    idx = np.argmax(np.abs(phi), axis=0)
    return phi * np.sign(phi[idx, np.arange(phi.shape[1])])
