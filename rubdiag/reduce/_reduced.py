"""The reduced model of a rig: one Craig–Bampton reduction per rig, cached per process and
on disk.

The boundary is every DOF a contact element of the rig touches (blade tips and casing nodes
of the blade contacts, shaft nodes of stator contacts): what is nonlinear stays physical;
with ``Reduction.tip_rotations`` also the contact blades' tip rotations, which the tips'
stick-slip needs (:func:`boundary_dofs`).
M, K, C (Rayleigh + discrete dampers) and the unit-speed gyroscopic G are projected once;
a run at speed Ω uses ``C + Ω G``, so one reduction serves every speed (and a speed that
changes in time). A process keeps the reduced models it used (a Dask worker or a pool
process reads or builds one on its first reduced run of that rig), and the disk cache
(:mod:`rubdiag._cache`: keyed by the rig's content, the reduction, the rubdiag and library
versions and the BLAS kernels) keeps them for the next process: a reduced run from the
command line reads its model in a few milliseconds instead of assembling and reducing the
rig. The reduction runs on one BLAS thread, so that its bits (and so a reduced run's) do not
depend on the machine's core count.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import numpy as np

from rubdiag import _cache
from rubdiag.reduce._craig_bampton import CraigBampton, craig_bampton
from rubdiag.reduce._spec import Reduction

__all__ = ["ReducedModel", "boundary_dofs", "contact_dofs", "reduced_model"]


@dataclass(frozen=True)
class ReducedModel:
    """A rig's reduced matrices (dense, SI units) and the basis that made them.

    ``M``, ``K``, ``C`` (damping without the gyroscopic part) and ``G`` (unit speed:
    multiply by Ω in rad/s) are ``Tᵀ X T`` of the full model's matrices; ``basis.T``
    recovers physical displacements. ``build_seconds`` is what getting it cost this
    process (s): the reduction (assembly and modal analysis of the full model included), or
    reading it from the disk cache (``from_disk``).

    Parameters
    ----------
    reduction : Reduction
        What was kept.
    basis : CraigBampton
        The basis.
    M, K, C, G : numpy.ndarray
        (n_b + n_m, n_b + n_m) reduced mass, stiffness, damping and unit-speed gyroscopic
        matrices (SI).
    build_seconds : float
        What getting the model cost this process (s).
    from_disk : bool
        Read from the disk cache.
    """

    reduction: Reduction
    basis: CraigBampton
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    build_seconds: float
    from_disk: bool = False

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


def contact_dofs(model, blade_contacts: bool = True) -> np.ndarray:
    """Every DOF a contact element of ``model``'s rig acts on (ascending; empty without);
    without ``blade_contacts``, those of its stator contacts only.

    Parameters
    ----------
    model : Model
        The assembled rig.
    blade_contacts : bool
        Include the blade contacts' DOFs.

    Returns
    -------
    numpy.ndarray
        The DOF numbers (int).
    """
    dofs = [np.zeros(0, np.int64)]
    geo = model.blade_contacts
    if geo is not None and blade_contacts:
        dofs += [geo.tip_dofs.ravel(), geo.casing_dofs.ravel()]
    for sc in model.rig.stator_contacts:
        dofs.append([model.dofs.index(sc.node, "y"), model.dofs.index(sc.node, "z")])
    return np.unique(np.concatenate(dofs).astype(np.int64))


def boundary_dofs(model, reduction: Reduction, blade_contacts: bool = True) -> np.ndarray:
    """The DOFs ``reduction`` keeps physical (ascending): :func:`contact_dofs`, with
    ``tip_rotations`` the in-plane rotation of each contact blade's tip, every DOF of its
    ``shaft_nodes``, every pedestal DOF of the rig (a pedestal may be loose: a nonlinear
    element there needs the physical DOF; a rig without pedestals has none), and the y and z
    of every journal bearing's node (its film is a nonlinear element). Without
    ``blade_contacts``, the blade contacts' DOFs are left to the modes (a run whose blades
    cannot reach the casing: :mod:`rubdiag.simulation._idle_contacts`). Empty for a rig
    without nonlinear elements (which has no reduced model).

    Parameters
    ----------
    model : Model
        The assembled rig.
    reduction : Reduction
        What to keep.
    blade_contacts : bool
        Keep the blade contacts' DOFs.

    Returns
    -------
    numpy.ndarray
        The DOF numbers (int).
    """
    dofs = [contact_dofs(model, blade_contacts), model.dofs.component("pedestal")]
    for k in model.journal_bearings:
        node = model.rig.bearings[k].node
        dofs.append([model.dofs.index(node, "y"), model.dofs.index(node, "z")])
    for node in reduction.shaft_nodes:
        try:
            dofs.append([model.dofs.index(node, d) for d in ("y", "z", "ry", "rz")])
        except ValueError:
            raise ValueError(f"reduction.shaft_nodes: {node} is not a shaft node of rig "
                             f"{model.rig.name!r} (allowed: its shaft node numbers)") from None
    if blade_contacts and reduction.tip_rotations and model.rig.contact is not None:
        tip = model.rig.blades.n_elements
        dofs.append([model.dofs.index(f"blade {b}.{tip}", "rx") for b in model.rig.contact.blades])
    return np.unique(np.concatenate(dofs).astype(np.int64))


def reduced_model(rig, reduction: Reduction | None = None, *,
                  blade_contacts: bool = True) -> ReducedModel:
    """The reduced model of ``rig`` (default :class:`Reduction`); cached per process and on
    disk (module docstring): the same rig and reduction are reduced once per environment.
    ``blade_contacts=False``: the blade contacts' DOFs left to the modes
    (:func:`boundary_dofs`).

    Parameters
    ----------
    rig : Rig
        The rig, with at least one nonlinear element.
    reduction : Reduction or None
        What to keep; None: ``Reduction()``.
    blade_contacts : bool
        Keep the blade contacts' DOFs physical.

    Returns
    -------
    ReducedModel
        The reduced matrices and their basis.
    """
    return _reduced_model(rig, Reduction() if reduction is None else reduction,
                          bool(blade_contacts))


#: the arrays of a reduced model as the disk cache holds them
_ARRAYS = ("boundary", "T", "mode_frequencies_hz", "first_dropped_hz", "M", "K", "C", "G")


@functools.lru_cache(maxsize=8)
def _reduced_model(rig, reduction: Reduction, blade_contacts: bool) -> ReducedModel:
    from rubdiag.model import rig_to_dict

    if not isinstance(reduction, Reduction):
        raise TypeError(f"reduction has the wrong type {type(reduction).__name__} "
                        "(expected a Reduction)")
    start = time.perf_counter()
    depends_on = {"rig": rig_to_dict(rig), "reduction": reduction.description()}
    if not blade_contacts:      # the key of a model with them is the one it always had
        depends_on["blade_contacts"] = False
    arrays, from_disk = _cache.cached("reduced-model", depends_on, _ARRAYS,
                                      functools.partial(_reduce, rig, reduction, blade_contacts))
    basis = CraigBampton(boundary=arrays["boundary"], T=arrays["T"],
                         mode_frequencies_hz=arrays["mode_frequencies_hz"],
                         first_dropped_hz=float(arrays["first_dropped_hz"]))
    return ReducedModel(reduction=reduction, basis=basis, M=arrays["M"], K=arrays["K"],
                        C=arrays["C"], G=arrays["G"], from_disk=from_disk,
                        build_seconds=time.perf_counter() - start)


def _reduce(rig, reduction: Reduction, blade_contacts: bool) -> dict[str, np.ndarray]:
    """The reduction itself, on one BLAS thread: the arrays of :data:`_ARRAYS`."""
    from rubdiag._blas import one_thread
    from rubdiag.assembly import assemble
    from rubdiag.modal import with_rayleigh

    with one_thread():
        model = with_rayleigh(assemble(rig))
        boundary = boundary_dofs(model, reduction, blade_contacts)
        if not boundary.size:
            raise ValueError(f"rig {rig.name!r} has no nonlinear element: a reduction keeps "
                             "the DOFs of its contacts, pedestals, journal bearings and fault "
                             "nodes physical, and there are none")
        basis = craig_bampton(model.M, model.K, boundary, reduction.cutoff_hz)
        M, K = _modal_tail(basis.boundary.size, _symmetric(basis.project(model.M)),
                           _symmetric(basis.project(model.K)))
        C, G = basis.project(model.C), basis.project(model.G)
    return {"boundary": basis.boundary, "T": basis.T,
            "mode_frequencies_hz": basis.mode_frequencies_hz,
            "first_dropped_hz": np.float64(basis.first_dropped_hz),
            "M": M, "K": K, "C": C, "G": G}


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
