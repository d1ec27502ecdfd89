"""Small synthetic systems for the tests and benchmarks of the contact time integrator (a test
fixture: not part of the package; scripts and benchmarks put tests/ on their path).

They *resemble* the blade–rotor–casing rig (a rotor carrying blades inside a flexible casing,
point contacts between blade tips and casing nodes, a rotating unbalance), but are not the rig
model (that lives in :mod:`rubdiag.model` / :mod:`rubdiag.assembly`). All units SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rubdiag.simulation import HarmonicForce, PointContact

__all__ = ["TestSystem", "bladed_rotor_casing", "linear_response", "point_contacts",
           "tip_casing_system"]


@dataclass(frozen=True)
class TestSystem:
    """M, C, K (CSR), a rotating unbalance force, contacts and bookkeeping indices."""

    M: sp.csr_matrix
    C: sp.csr_matrix
    K: sp.csr_matrix
    force: HarmonicForce
    contacts: tuple[PointContact, ...]
    speed: float  # rad/s
    disc_dofs: tuple[int, int]
    tip_dofs: np.ndarray  # (n_c, 2) y, z of the contact blade tips
    casing_dofs: np.ndarray  # (n_c, 2)

    @property
    def n(self) -> int:
        return self.M.shape[0]


def point_contacts(dof_a, dof_b, normal, tangent, gap, k_n, **law) -> tuple[PointContact, ...]:
    """Point contacts between the DOF pairs (y, z) of the rows of ``dof_a`` and ``dof_b``
    (-1: ground), each row's normal and tangent; ``gap``, ``k_n`` and the keywords ``law``
    (PointContact's) a scalar or one value per contact."""
    dof_a = np.asarray(dof_a).reshape(-1, 2)
    n = dof_a.shape[0]
    columns = {"dof_a": dof_a, "dof_b": dof_b, "normal": normal, "tangent": tangent,
               "gap": gap, "k_n": k_n, **law}
    for name, value in columns.items():
        value = np.asarray(value)
        pair = name in ("dof_a", "dof_b", "normal", "tangent")
        columns[name] = np.broadcast_to(value.reshape(-1, 2) if pair else value,
                                        (n, 2) if pair else (n,))
    return tuple(PointContact(**{name: tuple(v[i].tolist()) if v.ndim == 2 else v[i].item()
                                 for name, v in columns.items()}) for i in range(n))


def linear_response(M, C, K, force: HarmonicForce) -> np.ndarray:
    """Complex steady harmonic response (all force terms must share one frequency kΩ)."""
    om = np.unique(force.frequencies)
    if om.size != 1:
        raise ValueError("linear_response needs a single frequency")
    w = float(om[0])
    F = np.zeros(M.shape[0], complex)
    np.add.at(F, force.dofs, force.steady_amplitudes())
    A = (K - w**2 * M + 1j * w * C).toarray()
    return np.linalg.solve(A, F)


def _spring(rows, cols, vals, i, j, e, k):
    """2-D spring k along unit vector e between node DOF pairs i=(iy,iz), j (None = ground)."""
    ee = np.outer(e, e) * k
    for a in range(2):
        for b in range(2):
            rows.append(i[a])
            cols.append(i[b])
            vals.append(ee[a, b])
            if j is not None:
                rows += [j[a], i[a], j[a]]
                cols += [j[b], j[b], i[b]]
                vals += [ee[a, b], -ee[a, b], -ee[a, b]]


def tip_casing_system(
    *, n_blades=4, n_contacts=2, gap=50e-6, k_n=1e7, mu=0.3, speed=300.0, unbalance=2e-5,
    damping=0.02,
):
    """A ~20-DOF lumped system: a disc (y, z) on an isotropic shaft spring, ``n_blades`` tip
    masses tied to it by radial (stiff) and tangential (softer) springs, the same number of
    casing masses tied to ground and to their neighbours; point contacts between the first
    ``n_contacts`` blade tips and their casing masses. Driven by a rotating unbalance."""
    m_disc, k_shaft = 2.0, 2e5
    m_tip, k_rad, k_tan = 0.02, 5e6, 2e5
    m_cas, k_cas, k_ring = 0.2, 1e6, 2e5
    nb = n_blades
    n = 2 + 4 * nb
    disc = (0, 1)
    tips = [(2 + 2 * b, 3 + 2 * b) for b in range(nb)]
    cas = [(2 + 2 * nb + 2 * b, 3 + 2 * nb + 2 * b) for b in range(nb)]
    rows, cols, vals = [], [], []
    _spring(rows, cols, vals, disc, None, np.array([1.0, 0.0]), k_shaft)
    _spring(rows, cols, vals, disc, None, np.array([0.0, 1.0]), k_shaft)
    masses = np.zeros(n)
    masses[list(disc)] = m_disc
    for b in range(nb):
        th = 2 * np.pi * b / nb
        er = np.array([np.cos(th), np.sin(th)])
        et = np.array([-np.sin(th), np.cos(th)])
        _spring(rows, cols, vals, tips[b], disc, er, k_rad)
        _spring(rows, cols, vals, tips[b], disc, et, k_tan)
        _spring(rows, cols, vals, cas[b], None, er, k_cas)
        _spring(rows, cols, vals, cas[b], None, et, k_cas)
        nxt = cas[(b + 1) % nb]
        th2 = 2 * np.pi * ((b + 1) % nb) / nb
        chord = np.array([np.cos(th2) - np.cos(th), np.sin(th2) - np.sin(th)])
        _spring(rows, cols, vals, cas[b], nxt, chord / np.linalg.norm(chord), k_ring)
        masses[list(tips[b])] = m_tip
        masses[list(cas[b])] = m_cas
    K = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    M = sp.diags(masses).tocsr()
    # damping ratio ~ `damping` near the shaft mode, stiffness-proportional part small
    w1 = np.sqrt(k_shaft / m_disc)
    C = (2 * damping * w1 * M + 1e-6 * K).tocsr()
    ths = 2 * np.pi * np.arange(n_contacts) / nb
    normal = np.c_[np.cos(ths), np.sin(ths)]
    tangent = np.c_[-np.sin(ths), np.cos(ths)]
    tip_d = np.array(tips[:n_contacts])
    cas_d = np.array(cas[:n_contacts])
    contacts = point_contacts(tip_d, cas_d, normal, tangent, gap=gap, k_n=k_n, mu=mu)
    force = HarmonicForce.unbalance(disc[0], disc[1], unbalance, speed)
    return TestSystem(M, C, K, force, contacts, speed, disc, tip_d, cas_d)


def _frame(L, E, A, I, rho):
    """Planar Euler–Bernoulli frame element (u1, v1, phi1, u2, v2, phi2): local K and M."""
    k = np.zeros((6, 6))
    ea = E * A / L
    k[np.ix_([0, 3], [0, 3])] = ea * np.array([[1, -1], [-1, 1]])
    b = E * I / L**3 * np.array(
        [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
         [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]]
    )
    idx = [1, 2, 4, 5]
    k[np.ix_(idx, idx)] = b
    m = np.zeros((6, 6))
    ma = rho * A * L
    m[np.ix_([0, 3], [0, 3])] = ma / 6 * np.array([[2, 1], [1, 2]])
    mb = ma / 420 * np.array(
        [[156, 22 * L, 54, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
         [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]]
    )
    m[np.ix_(idx, idx)] = mb
    return k, m


def _rot(c, s):
    r = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1.0]])
    T = np.zeros((6, 6))
    T[:3, :3] = r
    T[3:, 3:] = r
    return T


def bladed_rotor_casing(
    *, speed=200.0, unbalance=2e-4, gap=None, k_n=8e7, mu=0.3, gap_fraction=0.6,
):
    """A 412-DOF system shaped like the paper rig.

    Shaft: 25 nodes x (y, z, θy, θz) Euler–Bernoulli beam, bearings at nodes 1 and 23, disc
    at node 8 (100 DOF). Blades: 16 blades x 4 planar frame elements (u_y, u_z, φ) in the disc
    plane, root translations tied to the disc centre (192 DOF). Casing: a ring of 40 planar
    frame nodes (120 DOF), supported on every node. Rayleigh damping α = 9.948 1/s,
    β = 1.061e-4 s, a small gyroscopic coupling at the disc. 8 contacts: every other blade tip
    against the casing node at the same angle, normal radial outward. If ``gap`` is None, it is
    ``gap_fraction`` times the smallest linear radial tip-to-casing amplitude, so all 8 rub.
    """
    E, rho = 2.1e11, 7850.0
    # shaft
    ns = 25
    Ls = 0.6 / (ns - 1)
    d = 0.010
    As, Is = np.pi * d**2 / 4, np.pi * d**4 / 64
    nb, nbe = 16, 4
    nr = 40
    n_shaft = 4 * ns
    n_blade = nb * nbe * 3
    n = n_shaft + n_blade + 3 * nr
    Kd = np.zeros((n, n))
    Md = np.zeros((n, n))
    k_s, m_s = _frame(Ls, E, As, Is, rho)
    for plane in (0, 1):  # y-θz plane (v, φ) and z-θy plane
        for e in range(ns - 1):
            dofs = [4 * e + plane, 4 * e + 2 + plane, 4 * (e + 1) + plane, 4 * (e + 1) + 2 + plane]
            sel = [1, 2, 4, 5]
            Kd[np.ix_(dofs, dofs)] += k_s[np.ix_(sel, sel)]
            Md[np.ix_(dofs, dofs)] += m_s[np.ix_(sel, sel)]
    kb = 1e6
    for node in (1, 23):
        Kd[4 * node, 4 * node] += kb
        Kd[4 * node + 1, 4 * node + 1] += kb
    disc = 8
    dy, dz = 4 * disc, 4 * disc + 1
    md, Ip = 0.453, 0.5 * 0.453 * 0.035**2
    Md[dy, dy] += md
    Md[dz, dz] += md
    Md[4 * disc + 2, 4 * disc + 2] += Ip / 2
    Md[4 * disc + 3, 4 * disc + 3] += Ip / 2
    # blades: root at r = 35 mm, tip at 75 mm
    Lb = 0.040 / nbe
    Ab, Ib = 0.015 * 0.002, 0.015 * 0.002**3 / 12
    k_b, m_b = _frame(Lb, E, Ab, Ib, rho)
    tips = []
    for b in range(nb):
        th = 2 * np.pi * b / nb
        c, s = np.cos(th), np.sin(th)
        T = _rot(c, s)
        kg = T.T @ k_b @ T
        mg = T.T @ m_b @ T
        base = n_shaft + b * nbe * 3
        for e in range(nbe):
            if e == 0:  # root: translations follow the disc centre, root rotation clamped
                dofs = [dy, dz, None, base, base + 1, base + 2]
            else:
                dofs = [base + 3 * (e - 1) + i for i in range(3)] + [
                    base + 3 * e + i for i in range(3)
                ]
            keep = [i for i, dd in enumerate(dofs) if dd is not None]
            dd_ = [dofs[i] for i in keep]
            Kd[np.ix_(dd_, dd_)] += kg[np.ix_(keep, keep)]
            Md[np.ix_(dd_, dd_)] += mg[np.ix_(keep, keep)]
        tips.append((base + 3 * (nbe - 1), base + 3 * (nbe - 1) + 1))
    # casing ring: radius = 75 mm + 0.5 mm + 2.5 mm, section 15 x 5 mm
    Rc = 0.078
    Ac, Ic = 0.015 * 0.005, 0.015 * 0.005**3 / 12
    base_c = n_shaft + n_blade
    k_sup = 1e6 / nr
    c_sup = 1e3 / nr
    Cd_extra = np.zeros((n, n))
    for e in range(nr):
        th1 = 2 * np.pi * e / nr
        th2 = 2 * np.pi * (e + 1) / nr
        p1 = Rc * np.array([np.cos(th1), np.sin(th1)])
        p2 = Rc * np.array([np.cos(th2), np.sin(th2)])
        L = np.linalg.norm(p2 - p1)
        c, s = (p2 - p1) / L
        kl, ml = _frame(L, E, Ac, Ic, rho)
        T = _rot(c, s)
        dofs = [base_c + 3 * e + i for i in range(3)] + [
            base_c + 3 * ((e + 1) % nr) + i for i in range(3)
        ]
        Kd[np.ix_(dofs, dofs)] += T.T @ kl @ T
        Md[np.ix_(dofs, dofs)] += T.T @ ml @ T
        for a in range(2):
            Kd[base_c + 3 * e + a, base_c + 3 * e + a] += k_sup
            Cd_extra[base_c + 3 * e + a, base_c + 3 * e + a] += c_sup
    K = sp.csr_matrix(Kd)
    M = sp.csr_matrix(Md)
    alpha, beta = 9.948, 1.061e-4
    G = np.zeros((n, n))
    G[4 * disc + 2, 4 * disc + 3] = Ip
    G[4 * disc + 3, 4 * disc + 2] = -Ip
    C = sp.csr_matrix(alpha * Md + beta * Kd + Cd_extra + speed * G)
    force = HarmonicForce.unbalance(dy, dz, unbalance, speed)
    tip_d = np.array(tips[::2])
    cas_nodes = [5 * k for k in range(8)]  # 45° apart on the 40-node ring
    cas_d = np.array([(base_c + 3 * k, base_c + 3 * k + 1) for k in cas_nodes])
    ths = 2 * np.pi * np.arange(8) / 8
    normal = np.c_[np.cos(ths), np.sin(ths)]
    tangent = np.c_[-np.sin(ths), np.cos(ths)]
    if gap is None:
        u = linear_response(M, C, K, force)
        rel = np.abs(
            (u[tip_d[:, 0]] - u[cas_d[:, 0]]) * normal[:, 0]
            + (u[tip_d[:, 1]] - u[cas_d[:, 1]]) * normal[:, 1]
        )
        gap = gap_fraction * float(rel.min())
    contacts = point_contacts(tip_d, cas_d, normal, tangent, gap=gap, k_n=k_n, mu=mu)
    return TestSystem(M, C, K, force, contacts, speed, (dy, dz), tip_d, cas_d)
