"""The reduced model of a rig: one Craig–Bampton reduction per rig, cached per process.

The boundary is every DOF a contact element of the rig touches (blade tips and casing nodes
of the blade contacts, shaft nodes of stator contacts): what is nonlinear stays physical;
with ``Reduction.tip_rotations`` also the contact blades' tip rotations, which the tips'
stick-slip needs (:func:`boundary_dofs`).
M, K, C (Rayleigh + discrete dampers) and the unit-speed gyroscopic G are projected once;
a run at speed Ω uses ``C + Ω G``, so one reduction serves every speed (and a speed that
changes in time). The cache is per process — a Dask worker or a pool process builds it
once, on its first reduced run of that rig.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import numpy as np

from rubdiag.reduce.craig_bampton import CraigBampton, craig_bampton
from rubdiag.reduce.spec import Reduction

__all__ = ["ReducedModel", "boundary_dofs", "contact_dofs", "reduced_model"]


@dataclass(frozen=True)
class ReducedModel:
    """A rig's reduced matrices (dense, SI units) and the basis that made them.

    ``M``, ``K``, ``C`` (damping without the gyroscopic part) and ``G`` (unit speed:
    multiply by Ω in rad/s) are ``Tᵀ X T`` of the full model's matrices; ``basis.T``
    recovers physical displacements. ``build_seconds`` is the one-time cost of the
    reduction (assembly and modal analysis of the full model included).
    """

    reduction: Reduction
    basis: CraigBampton
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    build_seconds: float

    @property
    def n_reduced(self) -> int:
        return self.basis.n_reduced

    @property
    def n_full(self) -> int:
        return int(self.basis.T.shape[0])

    def project_force(self, force: np.ndarray) -> np.ndarray:
        """Generalised force ``Tᵀ f`` of a physical (complex) load vector."""
        return self.basis.T.T @ force

    def harmonic_response(self, force_hat: np.ndarray, speed: float) -> np.ndarray:
        """Steady response x̂ (reduced coordinates) to the physical load Re(F̂ e^{iΩt}):
        ``(K − Ω² M + iΩ (C + Ω G)) x̂ = Tᵀ F̂``."""
        Z = self.K - speed**2 * self.M + 1j * speed * (self.C + speed * self.G)
        return np.linalg.solve(Z, self.project_force(force_hat))


def contact_dofs(model) -> np.ndarray:
    """Every DOF a contact element of ``model``'s rig acts on (ascending)."""
    dofs = []
    geo = model.blade_contacts
    if geo is not None:
        dofs += [geo.tip_dofs.ravel(), geo.casing_dofs.ravel()]
    for sc in model.rig.stator_contacts:
        dofs.append([model.dofs.index(sc.node, "y"), model.dofs.index(sc.node, "z")])
    if not dofs:
        raise ValueError(f"rig {model.rig.name!r} has no contact element: a reduction keeps "
                         "the contact DOFs physical, and there are none")
    return np.unique(np.concatenate(dofs).astype(np.int64))


def boundary_dofs(model, reduction: Reduction) -> np.ndarray:
    """The DOFs ``reduction`` keeps physical (ascending): :func:`contact_dofs`, and with
    ``tip_rotations`` the in-plane rotation of each contact blade's tip."""
    dofs = [contact_dofs(model)]
    if reduction.tip_rotations and model.rig.contact is not None:
        tip = model.rig.blades.n_elements
        dofs.append([model.dofs.index(f"blade {b}.{tip}", "rx") for b in model.rig.contact.blades])
    return np.unique(np.concatenate(dofs).astype(np.int64))


def reduced_model(rig, reduction: Reduction | None = None) -> ReducedModel:
    """The reduced model of ``rig`` (default :class:`Reduction`); cached: the same rig and
    reduction are reduced once per process."""
    return _reduced_model(rig, Reduction() if reduction is None else reduction)


@functools.lru_cache(maxsize=8)
def _reduced_model(rig, reduction: Reduction) -> ReducedModel:
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh

    if not isinstance(reduction, Reduction):
        raise TypeError(f"reduction has the wrong type {type(reduction).__name__} "
                        "(expected a Reduction)")
    start = time.perf_counter()
    model = with_rayleigh(assemble(rig))
    basis = craig_bampton(model.M, model.K, boundary_dofs(model, reduction), reduction.cutoff_hz)
    M, K = _modal_tail(basis.boundary.size, _symmetric(basis.project(model.M)),
                       _symmetric(basis.project(model.K)))
    return ReducedModel(
        reduction=reduction, basis=basis, M=M, K=K, C=basis.project(model.C),
        G=basis.project(model.G), build_seconds=time.perf_counter() - start)


def _modal_tail(n_b: int, M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """M and K with the zeros Craig–Bampton theory gives them set exactly: the modes do not
    couple to the boundary in K (``K_bm = (K_bi + Ψᵀ K_ii) Φ = 0``), nor to each other in
    M and K (``Φᵀ M_ii Φ = I``, ``Φᵀ K_ii Φ = diag ω²``). The projections leave round-off
    there (≤ 5e-12 of the largest diagonal entry on the paper rig); exact zeros let the
    integrator skip them."""
    M, K = M.copy(), K.copy()
    tail = slice(n_b, None)
    K[:n_b, tail] = 0.0
    K[tail, :n_b] = 0.0
    for A in (M, K):
        A[tail, tail] = np.diag(np.diag(A[tail, tail]))
    return M, K


def _symmetric(A: np.ndarray) -> np.ndarray:
    """A projected symmetric matrix, symmetric to the last bit (the kernel reads its rows
    as columns)."""
    return np.ascontiguousarray(0.5 * (A + A.T))
