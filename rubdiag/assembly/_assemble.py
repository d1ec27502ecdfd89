"""Global matrices of a rig: M, K, C, G as sparse CSR, and the DOF map.

The equations of motion at spin speed Ω are

    M q'' + (C + Ω G) q' + K q = f(t),

with C = α M + β K_s + C_d: Rayleigh damping on the structural stiffness K_s (shaft,
blades, casing ring) plus the discrete dampers C_d of bearings and casing supports (which
carry their own damping, so β does not act on their springs). A bearing on a pedestal
(:class:`~rubdiag.model._rig.Pedestal`) joins its shaft node to the pedestal's mass, whose
support joins it to the ground; the pedestal's springs are discrete too.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rubdiag.assembly._damping import rayleigh_coefficients
from rubdiag.assembly._dofs import DofMap
from rubdiag.assembly._elements import disc_matrices, frame_element, shaft_element
from rubdiag.model import Rig, Unbalance

__all__ = ["BladeContactGeometry", "Model", "assemble"]


class _Triplets:
    """COO triplets collected element by element, converted to CSR once."""

    def __init__(self, n: int):
        self.n = n
        self.rows, self.cols, self.vals = [], [], []

    def add(self, dofs, block) -> None:
        """Add ``block`` on ``dofs``; a DOF of -1 is held fixed (its rows/columns drop)."""
        dofs, block = np.asarray(dofs), np.asarray(block)
        if dofs.min() < 0:
            keep = dofs >= 0
            dofs, block = dofs[keep], block[np.ix_(keep, keep)]
        self.rows.append(np.repeat(dofs, dofs.size))    # row-major, as the block's entries
        self.cols.append(np.tile(dofs, dofs.size))
        self.vals.append(block.ravel())

    def csr(self) -> sp.csr_matrix:
        if not self.vals:
            return sp.csr_matrix((self.n, self.n))
        data = (np.concatenate(self.vals), (np.concatenate(self.rows), np.concatenate(self.cols)))
        return sp.coo_matrix(data, shape=(self.n, self.n)).tocsr()


@dataclass(frozen=True)
class BladeContactGeometry:
    """Blade-tip/casing contact elements as DOF numbers and unit vectors (y, z).

    ``tip_dofs[k]`` and ``casing_dofs[k]`` are the (y, z) DOFs of contact element k+1;
    ``normal`` points radially outwards and ``tangent`` along +θ. The gap is
    g = g0 − (u_tip − u_casing)·normal.

    Parameters
    ----------
    tip_dofs, casing_dofs : numpy.ndarray
        (n_contacts, 2) int: the blade tip's and the casing node's (y, z) DOF numbers.
    normal, tangent : numpy.ndarray
        (n_contacts, 2): unit radial and circumferential vectors in (y, z).
    angle_rad : numpy.ndarray
        (n_contacts,): angle of each contact from +y towards +z (rad).
    """

    tip_dofs: np.ndarray
    casing_dofs: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    angle_rad: np.ndarray


@dataclass(frozen=True)
class Model:
    """The assembled rig: sparse matrices, DOF map and what is needed to load it.

    Parameters
    ----------
    rig : Rig
        The rig assembled.
    dofs : DofMap
        The names of the DOFs, in matrix order.
    M, K, G : scipy.sparse.csr_matrix
        Mass (kg, kg·m²), stiffness (N/m, N·m/rad) and unit-speed gyroscopic matrix
        (multiply by Ω in rad/s).
    K_structural : scipy.sparse.csr_matrix
        The part of K that Rayleigh's β acts on (shaft, blades, casing ring).
    C_discrete : scipy.sparse.csr_matrix
        Bearing and casing-support dampers (N·s/m).
    rayleigh : (float, float) or None
        Rayleigh (α in 1/s, β in s), from the rig's damping ratios and reference speeds.
        None when the rig leaves the reference speeds to its critical speeds, which only
        the modal layer computes: :func:`rubdiag.modal.with_rayleigh` fills it in.
    """

    rig: Rig
    dofs: DofMap
    M: sp.csr_matrix
    K: sp.csr_matrix
    G: sp.csr_matrix
    K_structural: sp.csr_matrix
    C_discrete: sp.csr_matrix
    rayleigh: tuple[float, float] | None = None

    @property
    def n_dof(self) -> int:
        return self.dofs.n_dof

    @functools.cached_property
    def C(self) -> sp.csr_matrix:
        """Damping matrix (N·s/m): α M + β K_structural + discrete dampers."""
        if self.rayleigh is None:
            raise ValueError("Rayleigh damping is not known: the rig has no "
                             "Damping.reference_speeds_rad_s; rubdiag.modal.with_rayleigh(model) "
                             "takes them from its first two forward critical speeds")
        alpha, beta = self.rayleigh
        return (alpha * self.M + beta * self.K_structural + self.C_discrete).tocsr()

    @property
    def journal_bearings(self) -> tuple[int, ...]:
        """The indices (in ``rig.bearings``) of the plain journal bearings."""
        return tuple(k for k, b in enumerate(self.rig.bearings) if b.journal is not None)

    def bearing_matrices(self, speed: float) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """The journal bearings' film linearised at their static load at spin speed Ω
        (rad/s, > 0): stiffness and damping (N/m, N·s/m; n×n, non-symmetric, zeros without
        journal bearings), between the shaft node and the ground or the bearing's pedestal
        (:meth:`rubdiag.model.JournalFilm.coefficients`: the Jacobian of the same film
        force the time integrator uses). The linear analysis adds them to K and C."""
        K, C = _Triplets(self.n_dof), _Triplets(self.n_dof)
        if self.journal_bearings and not (np.isfinite(speed) and speed > 0.0):
            raise ValueError(f"speed = {speed!r} is out of range (allowed: > 0 rad/s: a journal "
                             "bearing's film has no stiffness at rest)")
        for k in self.journal_bearings:
            b = self.rig.bearings[k]
            f = b.journal
            kb, cb = f.coefficients(speed)
            idx = [self.dofs.index(b.node, "y"), self.dofs.index(b.node, "z")]
            if b.pedestal is not None:      # the film between journal and pedestal
                idx += [self.dofs.index(f"pedestal {k}", "y"),
                        self.dofs.index(f"pedestal {k}", "z")]
                kb = np.block([[kb, -kb], [-kb, kb]])
                cb = np.block([[cb, -cb], [-cb, cb]])
            K.add(idx, kb)
            C.add(idx, cb)
        return K.csr(), C.csr()

    @functools.cached_property
    def shaft_x_m(self) -> np.ndarray:
        """Axial position of every shaft node (m)."""
        return np.array(self.rig.shaft.node_positions_m)

    def unbalance_force(self, unbalance: Unbalance, speed: float) -> np.ndarray:
        """Complex force amplitudes F̂ (N) with f(t) = Re(F̂ e^{iΩt}) at speed Ω (rad/s).

        A disc unbalance u at phase φ rotating forwards gives
        (f_y, f_z) = uΩ² (cos(Ωt + φ), sin(Ωt + φ)), i.e. F̂_y = uΩ²e^{iφ}, F̂_z = −i F̂_y.
        """
        discs = self.rig.discs
        if len(unbalance.magnitudes_kg_m) != len(discs):
            raise ValueError(f"unbalance has {len(unbalance.magnitudes_kg_m)} entries "
                             f"(allowed: one per disc, {len(discs)})")
        force = np.zeros(self.n_dof, dtype=complex)
        for disc, u, phase in zip(discs, unbalance.magnitudes_kg_m, unbalance.phases_rad,
                                  strict=True):
            amplitude = u * speed**2 * np.exp(1j * phase)
            force[self.dofs.index(disc.node, "y")] += amplitude
            force[self.dofs.index(disc.node, "z")] += -1j * amplitude
        return force

    @functools.cached_property
    def blade_contacts(self) -> BladeContactGeometry | None:
        """The blade-tip/casing contact elements, or None for a rig without them."""
        rig = self.rig
        if rig.contact is None:
            return None
        tip = rig.blades.n_elements
        blades = rig.contact.blades
        angle = np.array([rig.blades.angle_rad(b) for b in blades])
        tips = [[self.dofs.index(f"blade {b}.{tip}", d) for d in "yz"] for b in blades]
        casing = [[self.dofs.index(f"casing {rig.contact_casing_node(k)}", d) for d in "yz"]
                  for k in range(1, len(blades) + 1)]
        return BladeContactGeometry(
            tip_dofs=np.array(tips, dtype=np.int64),
            casing_dofs=np.array(casing, dtype=np.int64),
            normal=np.column_stack([np.cos(angle), np.sin(angle)]),
            tangent=np.column_stack([-np.sin(angle), np.cos(angle)]),
            angle_rad=angle,
        )


def dof_map(rig: Rig) -> DofMap:
    """The DOF names of ``rig``'s model, without assembling it.

    Parameters
    ----------
    rig : Rig
        The rig.

    Returns
    -------
    DofMap
        The map ``assemble(rig).dofs`` would hold (shared by rigs of the same layout).
    """
    blades, casing = rig.blades, rig.casing
    return _dof_map(tuple(rig.shaft.nodes), blades.count if blades else 0,
                    blades.n_elements if blades else 0, casing.n_elements if casing else 0,
                    tuple(k for k, b in enumerate(rig.bearings) if b.pedestal is not None))


@functools.lru_cache(maxsize=64)
def _dof_map(shaft_nodes, n_blades, n_blade_stations, n_casing, pedestals) -> DofMap:
    """One (immutable) map per layout: the rig variants of a design share it."""
    return DofMap.build(shaft_nodes, n_blades=n_blades, n_blade_stations=n_blade_stations,
                        n_casing=n_casing, pedestals=pedestals)


def assemble(rig: Rig) -> Model:
    """Assemble the global sparse matrices of ``rig``.

    Rayleigh damping is set when the rig gives its reference speeds; otherwise
    ``Model.rayleigh`` is None until :func:`rubdiag.modal.with_rayleigh` computes it.

    Parameters
    ----------
    rig : Rig
        The rig.

    Returns
    -------
    Model
        Its sparse M, K, G, C_discrete and DOF map.
    """
    blades, casing = rig.blades, rig.casing
    dofs = dof_map(rig)
    n = dofs.n_dof
    M, Ks, G, Kd, Cd = (_Triplets(n) for _ in range(5))
    _add_shaft(rig, dofs, M, Ks, G)
    _add_discs(rig, dofs, M, G)
    _add_bearings(rig, dofs, M, Kd, Cd)
    if blades is not None:
        _add_blades(rig, dofs, M, Ks)
    if casing is not None:
        _add_casing(rig, dofs, M, Ks, Kd, Cd)
    K_structural = Ks.csr()
    damping = rig.damping
    rayleigh = None
    if damping.reference_speeds_rad_s is not None:
        rayleigh = rayleigh_coefficients(*damping.reference_speeds_rad_s, damping.xi_1,
                                         damping.xi_2)
    return Model(rig=rig, dofs=dofs, M=M.csr(), K=(K_structural + Kd.csr()).tocsr(),
                 G=G.csr(), K_structural=K_structural, C_discrete=Cd.csr(), rayleigh=rayleigh)


def _add_shaft(rig, dofs, M, K, G) -> None:
    mat, shaft = rig.material, rig.shaft
    nodes = list(shaft.nodes)
    for e, (length, do, di) in enumerate(zip(shaft.element_lengths_m, shaft.outer_diameters_m,
                                             shaft.inner_diameters_m, strict=True)):
        me, ke, ge = shaft_element(length, do, di, mat.youngs_modulus_pa, mat.poisson_ratio,
                                   mat.density_kg_m3)
        idx = [dofs.index(nodes[e], d) for d in ("y", "z", "ry", "rz")]
        idx += [dofs.index(nodes[e + 1], d) for d in ("y", "z", "ry", "rz")]
        M.add(idx, me)
        K.add(idx, ke)
        G.add(idx, ge)


def _add_discs(rig, dofs, M, G) -> None:
    for disc in rig.discs:
        md, gd = disc_matrices(*disc.inertia(rig.material.density_kg_m3))
        idx = [dofs.index(disc.node, d) for d in ("y", "z", "ry", "rz")]
        M.add(idx, md)
        G.add(idx, gd)


def _add_bearings(rig, dofs, M, K, C) -> None:
    for k, b in enumerate(rig.bearings):
        idx = [dofs.index(b.node, "y"), dofs.index(b.node, "z")]
        if b.pedestal is None:
            K.add(idx, np.diag([b.k_y_n_m, b.k_z_n_m]))
            C.add(idx, np.diag([b.c_y_ns_m, b.c_z_ns_m]))
            continue
        # shaft node -- bearing -- pedestal mass -- support -- ground, per direction
        p = b.pedestal
        ped = [dofs.index(f"pedestal {k}", "y"), dofs.index(f"pedestal {k}", "z")]
        for i, (kb, cb) in enumerate(((b.k_y_n_m, b.c_y_ns_m), (b.k_z_n_m, b.c_z_ns_m))):
            pair = [idx[i], ped[i]]
            K.add(pair, kb * np.array([[1.0, -1.0], [-1.0, 1.0]]))
            C.add(pair, cb * np.array([[1.0, -1.0], [-1.0, 1.0]]))
        M.add(ped, p.mass_kg * np.eye(2))
        K.add(ped, np.diag([p.k_y_n_m, p.k_z_n_m]))
        C.add(ped, np.diag([p.c_y_ns_m, p.c_z_ns_m]))


def _add_blades(rig, dofs, M, K) -> None:
    mat, blades = rig.material, rig.blades
    length = blades.length_m / blades.n_elements
    # the root is clamped to the disc centre: its translations are the shaft node's,
    # its in-plane rotation is fixed (-1)
    root = [dofs.index(blades.disc_node, "y"), dofs.index(blades.disc_node, "z"), -1]
    for b in range(1, blades.count + 1):
        me, ke = frame_element(length, blades.angle_rad(b), blades.width_m, blades.thickness_m,
                               mat.youngs_modulus_pa, mat.poisson_ratio, mat.density_kg_m3)
        previous = root
        for s in range(1, blades.n_elements + 1):
            current = [dofs.index(f"blade {b}.{s}", d) for d in ("y", "z", "rx")]
            M.add(previous + current, me)
            K.add(previous + current, ke)
            previous = current


def _add_casing(rig, dofs, M, K, Kd, Cd) -> None:
    mat, casing = rig.material, rig.casing
    n, R = casing.n_elements, casing.radius_m
    chord = 2.0 * R * math.sin(math.pi / n)
    for k in range(1, n + 1):
        # chord from node k to node k+1 is perpendicular to the bisecting radius
        angle = casing.angle_rad(k) + math.pi / n + math.pi / 2
        me, ke = frame_element(chord, angle, casing.axial_width_m, casing.radial_height_m,
                               mat.youngs_modulus_pa, mat.poisson_ratio, mat.density_kg_m3)
        nxt = k % n + 1
        idx = [dofs.index(f"casing {k}", d) for d in ("y", "z", "rx")]
        idx += [dofs.index(f"casing {nxt}", d) for d in ("y", "z", "rx")]
        M.add(idx, me)
        K.add(idx, ke)
    if casing.support == "distributed":
        share = 1.0 / n
        for k in range(1, n + 1):
            _add_support(dofs, f"casing {k}", casing, share, Kd, Cd, k_rx=0.0)
    else:
        k_rx = (casing.support_k_rx_nm_rad if casing.support_k_rx_nm_rad is not None
                else casing.support_k_y_n_m * R**2)
        _add_support(dofs, f"casing {casing.support_node}", casing, 1.0, Kd, Cd, k_rx)


def _add_support(dofs, node, casing, share, K, C, k_rx) -> None:
    idx = [dofs.index(node, d) for d in ("y", "z", "rx")]
    K.add(idx, np.diag([casing.support_k_y_n_m * share, casing.support_k_z_n_m * share, k_rx]))
    C.add(idx, np.diag([casing.support_c_y_ns_m * share, casing.support_c_z_ns_m * share, 0.0]))
