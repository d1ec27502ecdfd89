"""Time integration of a generic linear system with contact elements.

``M q'' + C q' + K q = f(t) + Σ_e B_eᵀ p_e(q)`` integrated by Newmark average acceleration
(beta = 1/4, gamma = 1/2) with Newton on the contact forces, solved in a small Schur
complement, and a variable step. The whole time loop runs in one Numba kernel
(:func:`rubdiag.kernels.newmark.newmark_contact`); this module validates, precomputes the
factorizations per step size, allocates, calls and packages the result.

Units are SI throughout: m, s, N, kg, rad/s.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag import _check
from rubdiag.kernels import ensure_fresh_cache, layout
from rubdiag.kernels.contact import (
    AUGMENT_FAILED,
    KIND_ANNULAR,
    KIND_POINT,
    NEWTON_FAILED,
    OPEN,
    SINGULAR,
    SLIDING,
    STICKING,
    element_law,
)
from rubdiag.kernels.newmark import (
    PROFILE_SECTIONS,
    STATUS_DONE,
    STATUS_LOG_FULL,
    STATUS_NO_CONVERGENCE,
    STATUS_NONFINITE,
    ContactSet,
    Factors,
    Linear,
    Logs,
    Outputs,
    State,
    Work,
    newmark_contact,
)
from rubdiag.kernels.sparse_lu import factorize
from rubdiag.simulate.loads import HarmonicForce, kernel_force, load_vector
from rubdiag.simulate.result import EpisodeLog, SimulationDiverged, StatusLog, SystemResult
from rubdiag.simulate.speed_profile import SpeedProfile

__all__ = [
    "Contacts",
    "HarmonicForce",
    "SimulationDiverged",
    "SystemResult",
    "simulate_system",
]

_MAX_LEVELS = 31


# --------------------------------------------------------------------------------------------
# inputs
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Contacts:
    """Contact elements, as arrays over n_c elements (use :meth:`point` / :meth:`annular`).

    * ``kind`` (n_c,) int: 1 point–point (blade tip / casing node, fixed normal), 2 annular
      shaft–stator clearance (normal along the current radial relative displacement).
    * ``dof_a``, ``dof_b`` (n_c, 2) int: (y, z) DOFs of body a (blade tip / shaft node) and body
      b (casing / stator node); -1 in ``dof_b`` means ground.
    * ``normal``, ``tangent`` (n_c, 2): unit normal from a towards b (radial outward) and
      tangent, kind 1 only (kind 2 ignores them).
    * ``gap`` (n_c,) m: initial gap g0 (kind 1) or radial clearance c (kind 2), >= 0.
    * ``k_n``, ``k_t`` (n_c,) N/m: normal penalty and tangential (stick) stiffness.
    * ``mu`` (n_c,): Coulomb coefficient (>= 0; 0 = frictionless).
    * ``radius`` (n_c,) m: kind 2 shaft surface radius R (slip includes Ω R); 0 for kind 1.
    * ``augmented`` (n_c,) bool and ``eps`` (n_c,) m: augmented Lagrangian on, and its
      penetration tolerance ε (eq. 2 of the paper).
    """

    kind: np.ndarray
    dof_a: np.ndarray
    dof_b: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    gap: np.ndarray
    k_n: np.ndarray
    k_t: np.ndarray
    mu: np.ndarray
    radius: np.ndarray
    augmented: np.ndarray
    eps: np.ndarray

    def __post_init__(self):
        conv = {
            "kind": np.int64, "dof_a": np.int64, "dof_b": np.int64, "normal": np.float64,
            "tangent": np.float64, "gap": np.float64, "k_n": np.float64, "k_t": np.float64,
            "mu": np.float64, "radius": np.float64, "augmented": bool, "eps": np.float64,
        }
        for name, dtype in conv.items():
            if dtype is np.int64:   # refuse float indices rather than truncate them
                _check.indices(f"contacts.{name}", getattr(self, name))
            arr = np.array(getattr(self, name), dtype=dtype)
            if name in ("dof_a", "dof_b", "normal", "tangent"):
                arr = arr.reshape(-1, 2)
            else:
                arr = arr.reshape(-1)
            object.__setattr__(self, name, arr)
        nc = self.kind.size
        for name in conv:
            if getattr(self, name).shape[0] != nc:
                raise ValueError(
                    f"contacts.{name}: {getattr(self, name).shape[0]} rows, expected n_c = {nc}"
                )

    @property
    def n_c(self) -> int:
        return int(self.kind.size)

    def __len__(self) -> int:
        return self.n_c

    @classmethod
    def empty(cls) -> Contacts:
        z, z2 = np.zeros(0), np.zeros((0, 2))
        i, i2 = np.zeros(0, np.int64), np.zeros((0, 2), np.int64)
        return cls(i, i2, i2, z2, z2, z, z, z, z, z, z, z)

    @classmethod
    def _broadcast(cls, kind, dof_a, dof_b, normal, tangent, gap, k_n, k_t, mu, radius,
                   augmented, eps) -> Contacts:
        """Elements of one kind, every per-element argument broadcast over ``dof_a``'s rows."""
        dof_a = _check.indices("dof_a", dof_a).reshape(-1, 2)
        nc = dof_a.shape[0]

        def rows(x, dtype):
            return np.broadcast_to(np.asarray(x, dtype=dtype).reshape(-1, 2), (nc, 2)).copy()

        def each(x, dtype=np.float64):
            return np.broadcast_to(np.asarray(x, dtype=dtype), (nc,)).copy()

        k_n = each(k_n)
        return cls(
            np.full(nc, kind), dof_a, rows(_check.indices("dof_b", dof_b), np.int64),
            rows(normal, np.float64), rows(tangent, np.float64), each(gap), k_n,
            k_n.copy() if k_t is None else each(k_t), each(mu), each(radius),
            each(augmented, bool), each(eps),
        )

    @classmethod
    def point(
        cls, dof_a, dof_b, normal, tangent, gap, k_n, *, k_t=None, mu=0.3,
        augmented=False, eps=20e-6,
    ) -> Contacts:
        """Point–point elements (kind 1). Scalars broadcast over the elements;
        ``k_t`` defaults to ``k_n``."""
        return cls._broadcast(KIND_POINT, dof_a, dof_b, normal, tangent, gap, k_n, k_t, mu,
                              0.0, augmented, eps)

    @classmethod
    def annular(
        cls, dof_a, clearance, radius, k_n, *, dof_b=(-1, -1), k_t=None, mu=0.3,
        augmented=False, eps=20e-6,
    ) -> Contacts:
        """Shaft–stator annular clearances (kind 2) at shaft nodes ``dof_a`` (y, z)."""
        # the basis of kind 2 follows the displacement; the fixed one is a placeholder
        return cls._broadcast(KIND_ANNULAR, dof_a, dof_b, (1.0, 0.0), (0.0, 1.0), clearance,
                              k_n, k_t, mu, radius, augmented, eps)

    def __add__(self, other: Contacts) -> Contacts:
        return Contacts(
            *(np.concatenate([getattr(self, f), getattr(other, f)]) for f in (
                "kind", "dof_a", "dof_b", "normal", "tangent", "gap", "k_n", "k_t", "mu",
                "radius", "augmented", "eps",
            ))
        )

    def basis(self) -> np.ndarray:
        """(n_c, 4) rows of the local 2x2 basis: (n_y, n_z, t_y, t_z) for kind 1, identity
        for kind 2."""
        out = np.zeros((self.n_c, 4))
        out[:, 0:2] = self.normal
        out[:, 2:4] = self.tangent
        ann = self.kind == KIND_ANNULAR
        out[ann] = [1.0, 0.0, 0.0, 1.0]
        return out

    def b_matrix(self, n: int) -> np.ndarray:
        """Dense constraint matrix B (2 n_c, n): local contact displacements ``d = B q``."""
        basis = self.basis()
        B = np.zeros((2 * self.n_c, n))
        for e in range(self.n_c):
            for r in range(2):
                for c in range(2):
                    B[2 * e + r, self.dof_a[e, c]] += basis[e, 2 * r + c]
                    if self.dof_b[e, c] >= 0:
                        B[2 * e + r, self.dof_b[e, c]] -= basis[e, 2 * r + c]
        return B


# --------------------------------------------------------------------------------------------
# validation helpers
# --------------------------------------------------------------------------------------------
def _bad(name: str, value, allowed: str) -> ValueError:
    return _check.out_of_range(name, value, allowed)


def _check_matrix(name: str, A, n: int | None) -> sp.csr_matrix:
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


def _check_scalar(name, value, lo=None, hi=None, lo_open=False, allowed=None) -> float:
    return _check.number(name, value, lo=lo, hi=hi, lo_open=lo_open, allowed=allowed)


def _check_contacts(ct: Contacts, n: int) -> None:
    if ct.n_c == 0:
        return
    bad = ~np.isin(ct.kind, (KIND_POINT, KIND_ANNULAR))
    if bad.any():
        e = int(np.argmax(bad))
        raise _bad(f"contacts.kind[{e}]", int(ct.kind[e]), "1 (point-point) or 2 (annular)")
    for name in ("gap", "k_n", "k_t", "mu", "radius", "eps", "normal", "tangent"):
        arr = getattr(ct, name)
        if not np.all(np.isfinite(arr)):
            e = int(np.argmax(~np.isfinite(arr).reshape(ct.n_c, -1).all(axis=1)))
            raise _bad(f"contacts.{name}[{e}]", arr[e].tolist(), "finite")
    checks = (
        ("gap", ct.gap < 0, ">= 0 m (a negative initial gap is a penetration)"),
        ("k_n", ct.k_n <= 0, "> 0 N/m"),
        ("k_t", ct.k_t <= 0, "> 0 N/m"),
        ("mu", ct.mu < 0, ">= 0"),
        ("radius", ct.radius < 0, ">= 0 m"),
        ("eps", ct.augmented & (ct.eps <= 0), "> 0 m when augmentation is on"),
    )
    for name, mask, allowed in checks:
        if mask.any():
            e = int(np.argmax(mask))
            raise _bad(f"contacts.{name}[{e}]", float(getattr(ct, name)[e]), allowed)
    if np.any(ct.dof_a < 0) or np.any(ct.dof_a >= n):
        e = int(np.argmax(((ct.dof_a < 0) | (ct.dof_a >= n)).any(axis=1)))
        raise _bad(f"contacts.dof_a[{e}]", ct.dof_a[e].tolist(), f"DOF indices in [0, {n})")
    if np.any(ct.dof_b < -1) or np.any(ct.dof_b >= n):
        e = int(np.argmax(((ct.dof_b < -1) | (ct.dof_b >= n)).any(axis=1)))
        raise _bad(
            f"contacts.dof_b[{e}]", ct.dof_b[e].tolist(), f"DOF indices in [0, {n}) or -1 (ground)"
        )
    pt = ct.kind == KIND_POINT
    nn = np.linalg.norm(ct.normal, axis=1)
    tn = np.linalg.norm(ct.tangent, axis=1)
    dot = np.abs(np.sum(ct.normal * ct.tangent, axis=1))
    bad = pt & ((np.abs(nn - 1) > 1e-9) | (np.abs(tn - 1) > 1e-9) | (dot > 1e-9))
    if bad.any():
        e = int(np.argmax(bad))
        raise _bad(
            f"contacts.normal/tangent[{e}]", (ct.normal[e].tolist(), ct.tangent[e].tolist()),
            "orthonormal unit vectors",
        )


def _checked_system(M, C, K, force, contacts, q0, v0):
    """The linear system, load, contacts and initial state, checked and converted (CSR
    float64 matrices, float64 vectors; None load or contacts: none)."""
    M = _check_matrix("M", M, None)
    n = M.shape[0]
    C = _check_matrix("C", C, n)
    K = _check_matrix("K", K, n)
    force = HarmonicForce.zero() if force is None else force
    contacts = Contacts.empty() if contacts is None else contacts
    q0 = np.asarray(q0, dtype=np.float64).reshape(-1)
    v0 = np.asarray(v0, dtype=np.float64).reshape(-1)
    for name, vec in (("q0", q0), ("v0", v0)):
        if vec.shape != (n,):
            raise ValueError(f"{name} has shape {vec.shape}: must be ({n},)")
        if not np.all(np.isfinite(vec)):
            raise _bad(name, f"<array with {int(np.sum(~np.isfinite(vec)))} non-finite>", "finite")
    if force.dofs.size:
        if np.any(force.dofs < 0) or np.any(force.dofs >= n):
            raise _bad("force.dofs", force.dofs.tolist(), f"DOF indices in [0, {n})")
        if not (np.all(np.isfinite(force.amplitudes)) and np.all(np.isfinite(force.omega))):
            raise _bad("force", "amplitudes/omega with NaN or inf", "finite")
    _check_contacts(contacts, n)
    return M, C, K, force, contacts, q0, v0


class _TimeGrid(NamedTuple):
    """A run's checked step sizes and its grid of ticks (a tick is the smallest step)."""

    dt: float  # the largest step (s)
    dt_min: float  # the smallest step asked for (s)
    n_lev: int  # step levels dt / 2^k, k < n_lev
    n_big: int  # the run's length in largest steps
    output_dt: float  # s
    tick_total: np.int64  # the run's length in ticks
    out_ticks: np.int64  # ticks between recorded samples

    @property
    def top(self) -> int:
        """The smallest step's level."""
        return self.n_lev - 1

    @property
    def n_out(self) -> int:
        """Recorded samples, t = 0 included."""
        return int(self.tick_total // self.out_ticks) + 1

    @property
    def sen_ticks(self) -> np.int64:
        """Ticks between sensor samples: every largest step."""
        return np.int64(1) << self.top

    def n_sensor_samples(self, n_sensors: int) -> int:
        return int(self.tick_total // self.sen_ticks) + 1 if n_sensors else 0


def _time_grid(duration, dt, dt_min, fixed_step: bool, output_dt) -> _TimeGrid:
    """The checked step sizes and tick grid of a run (parameters as :func:`simulate_system`)."""
    dt = _check_scalar("dt", dt, 0.0, lo_open=True, allowed="finite and > 0 s")
    duration = _check_scalar("duration", duration, 0.0, lo_open=True, allowed="finite and > 0 s")
    if duration < dt * (1 - 1e-9):
        raise _bad("duration", duration, f">= one step dt = {dt:g} s")
    if fixed_step:
        dt_min_ = dt
    elif dt_min is None:
        dt_min_ = dt / 64
    else:
        dt_min_ = _check_scalar("dt_min", dt_min, 0.0, lo_open=True, allowed="finite and > 0 s")
        if dt_min_ > dt:
            raise _bad("dt_min", dt_min_, f"<= dt = {dt:g} s")
    n_lev = 1 + math.floor(math.log2(dt / dt_min_) + 1e-9)
    if n_lev > _MAX_LEVELS:
        raise _bad("dt_min", dt_min_, f">= dt / 2^{_MAX_LEVELS - 1}")
    top = n_lev - 1
    ratio = duration / dt
    n_big = round(ratio) if abs(ratio - round(ratio)) < 1e-9 * max(1.0, ratio) else int(ratio)
    if output_dt is None:
        m_out = 1
        output_dt = dt
    else:
        output_dt = _check_scalar("output_dt", output_dt, 0.0, lo_open=True)
        r = output_dt / dt
        m_out = round(r)
        if m_out < 1 or abs(r - m_out) > 1e-9 * max(1.0, r):
            raise _bad("output_dt", output_dt, f"a positive integer multiple of dt = {dt:g} s")
    tick_total = np.int64(n_big) << top
    out_ticks = np.int64(m_out) << top
    return _TimeGrid(dt, dt_min_, n_lev, n_big, output_dt, tick_total, out_ticks)


def _checked_records(grid: _TimeGrid, n: int, record_dofs, sensor_dofs, recovery):
    """``recovery`` (None or (n_phys, n) float64), ``record_dofs`` and ``sensor_dofs``
    (int64 indices of the physical DOFs), checked, and the outputs' sizes."""
    n_phys = n
    if recovery is not None:
        recovery = np.asarray(recovery, dtype=np.float64)
        if recovery.ndim != 2 or recovery.shape[1] != n or not np.all(np.isfinite(recovery)):
            raise _bad("recovery", f"array of shape {recovery.shape}",
                       f"finite, shape (n_phys, {n})")
        n_phys = recovery.shape[0]
    if record_dofs is None:     # every physical DOF
        record_dofs = np.arange(n_phys, dtype=np.int64)
    record_dofs = _check.indices("record_dofs", record_dofs, n_phys)
    if grid.n_out * max(record_dofs.size, 1) > 5e8:
        raise ValueError(
            f"output of {grid.n_out} samples x {record_dofs.size} DOFs is too large: "
            "increase output_dt or record fewer DOFs"
        )
    sensor_dofs = _check.indices("sensor_dofs", [] if sensor_dofs is None else sensor_dofs,
                                 n_phys)
    n_sen = grid.n_sensor_samples(sensor_dofs.size)
    if n_sen * sensor_dofs.size > 5e8:
        raise ValueError(f"sensor output of {n_sen} samples x {sensor_dofs.size} DOFs is too "
                         "large: record fewer sensors or shorten the run")
    return recovery, record_dofs, sensor_dofs


@dataclass(frozen=True)
class _Settings:
    """:func:`simulate_system`'s numerical settings, checked (see its parameters)."""

    omega: float
    gamma: float
    max_newton: int
    max_augment: int
    grow_after: int
    newton_tol: float
    augment_boost: float
    augment_strict: bool
    gap_jump: float
    contact_stiffness_ratio: float | None
    episode_capacity: int

    @property
    def beta(self) -> float:
        """Newmark β = (γ + 1/2)² / 4."""
        return 0.25 * (self.gamma + 0.5) ** 2

    @classmethod
    def checked(cls, omega, gamma, max_newton, max_augment, grow_after, newton_tol,
                augment_boost, augment_strict, gap_jump, contact_stiffness_ratio,
                episode_capacity) -> _Settings:
        ratio = contact_stiffness_ratio
        return cls(
            omega=_check_scalar("omega", omega),
            gamma=_check_scalar("gamma", gamma, 0.5, 1.0),
            max_newton=_check.integer("max_newton", max_newton, lo=0),
            max_augment=_check.integer("max_augment", max_augment, lo=0),
            grow_after=_check.integer("grow_after", grow_after, lo=1),
            newton_tol=_check_scalar("newton_tol", newton_tol, 0.0, lo_open=True),
            augment_boost=_check_scalar("augment_boost", augment_boost, 0.0, 1.0),
            augment_strict=bool(augment_strict),
            gap_jump=_check_scalar("gap_jump", gap_jump, 0.0, lo_open=True),
            contact_stiffness_ratio=None if ratio is None else _check_scalar(
                "contact_stiffness_ratio", ratio, 0.0, lo_open=True),
            episode_capacity=_check.integer("episode_capacity", episode_capacity, lo=1),
        )


def _checked_gap_ramp(gap_ramp, contacts: Contacts):
    """``t_ramp`` (s; 0 = no ramp) and every element's gap at t = 0 (m)."""
    if gap_ramp is None:
        return 0.0, contacts.gap.copy()
    t_ramp = _check_scalar("gap_ramp[0] (t_ramp)", gap_ramp[0], 0.0)
    g_start = np.broadcast_to(np.asarray(gap_ramp[1], dtype=np.float64), (contacts.n_c,)).copy()
    if not np.all(np.isfinite(g_start)) or np.any(g_start < contacts.gap):
        raise _bad("gap_ramp[1] (g_start)", gap_ramp[1], ">= every element's gap g0, finite")
    return t_ramp, g_start


# --------------------------------------------------------------------------------------------
# set-up: the state at t = 0, the operators of each step size
# --------------------------------------------------------------------------------------------
def _initial_contact_state(contacts: Contacts, d0: np.ndarray, gap: np.ndarray):
    """Forces ``p0`` (2n_c), the kernel's per-element float and int state ``cf`` (CF_SIZE,
    n_c) and ``ci`` (CI_SIZE, n_c), and the contact elastic energy at t = 0, from the
    contact displacements ``d0`` at gaps ``gap``."""
    nc = contacts.n_c
    p0 = np.zeros(2 * nc)
    cf = np.zeros((layout.CF_SIZE, nc))
    ci = np.zeros((layout.CI_SIZE, nc), dtype=np.int64)
    e_c0 = 0.0
    for e in range(nc):
        p_n, p_t, _, _, _, _, st, fn, ft, e_new, _, g, z = element_law(
            int(contacts.kind[e]), d0[2 * e], d0[2 * e + 1], d0[2 * e], d0[2 * e + 1],
            float(gap[e]), float(contacts.k_n[e]), float(contacts.k_t[e]),
            float(contacts.mu[e]), 0.0, 0.0, 0.0,
        )
        p0[2 * e : 2 * e + 2] = p_n, p_t
        st = int(st)
        ci[layout.CI_STATUS, e] = st
        cf[layout.CF_E, e] = e_new
        cf[layout.CF_SLIP, e] = d0[2 * e + 1] if contacts.kind[e] == KIND_POINT else 0.0
        cf[layout.CF_FN, e] = fn
        cf[layout.CF_FT, e] = ft
        cf[layout.CF_GAP, e] = g
        cf[layout.CF_Z, e] = z
        if st != OPEN:
            ci[layout.CI_EP_SLIDE_ENTRIES, e] = int(st == SLIDING)
            ci[layout.CI_EP_STICK_ENTRIES, e] = int(st == STICKING)
            e_c0 += 0.5 * fn**2 / contacts.k_n[e] + 0.5 * ft**2 / contacts.k_t[e]
    return p0, cf, ci, e_c0


def _initial_acceleration(M, C, K, f0: np.ndarray, B, p0, q0, v0, a0) -> np.ndarray:
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
        raise _bad("a0", "<array>", f"finite, shape ({n},)")
    return a0


def _level_operators(M, C, K, B, contacts: Contacts, dt: float, n_lev: int, gamma: float,
                     beta_nm: float, contact_stiffness_ratio: float | None,
                     augment_boost: float, dense: bool):
    """Per step level k (h = dt / 2^k): the factors of K_eff, ``s_mat`` (n_lev, 2n_c, n) =
    (K_eff^-1 Bᵀ)ᵀ, ``w_mat`` (n_lev, 2n_c, 2n_c) = B K_eff^-1 Bᵀ, the smallest level each
    element may be closed at (``lev_req``; None ratio: no criterion), the multiplier update
    stiffness ``aug_k`` (n_lev, n_c), the factors packed for the kernel (l_ptr, l_idx,
    l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c; first axis the level) and,
    ``dense``, the transposed inverses ``inv_t`` (n_lev, n, n) (else (n_lev, 0, 0))."""
    n = M.shape[0]
    nc = contacts.n_c
    top = n_lev - 1
    factors = []
    s_list = []
    w_list = []
    inv_t = np.zeros((n_lev, n, n) if dense else (n_lev, 0, 0))
    Mc = sp.csc_matrix(M)
    Cc = sp.csc_matrix(C)
    Kc = sp.csc_matrix(K)
    for k in range(n_lev):
        h = dt / 2**k
        keff = Kc + (gamma / (beta_nm * h)) * Cc + (1.0 / (beta_nm * h * h)) * Mc
        try:
            if dense:   # LAPACK on the dense matrix (SuperLU's dense solves take ms each)
                inv_t[k] = np.linalg.inv(keff.toarray()).T
            else:
                fac = factorize(keff)
                factors.append(fac)
        except np.linalg.LinAlgError as exc:
            raise ValueError(f"K_eff at dt = {h:g} s is singular: {exc}") from exc
        if nc:
            S = inv_t[k].T @ B.T if dense else fac.splu.solve(np.ascontiguousarray(B.T))
            s_list.append(np.ascontiguousarray(S.T))
            w_list.append(B @ S)
        else:
            s_list.append(np.zeros((0, n)))
            w_list.append(np.zeros((0, 0)))
    # contact-stiffness criterion: k_N W_ee (= (ω_c h)^2 / 4 for a lumped mass) <= ratio
    lev_req = np.zeros(nc, np.int64)
    if nc and contact_stiffness_ratio is not None:
        for e in range(nc):
            lev_req[e] = top
            for k in range(n_lev):
                wee = w_list[k][2 * e, 2 * e]  # kind 1: the normal row
                if contacts.kind[e] == KIND_ANNULAR:  # the normal turns: both rows
                    wee = max(wee, w_list[k][2 * e + 1, 2 * e + 1])
                if contacts.k_n[e] * wee <= contact_stiffness_ratio:
                    lev_req[e] = k
                    break
    # multiplier update stiffness: eq. (2) uses k_N; with the step's dynamic stiffness at the
    # contact, 1 / W_ee, far above k_N (small steps) that converges by a factor
    # 1 / (1 + k_N W_ee) per update only. We add 0.9 / W_ee (the Newton update of the
    # multiplier for an isolated contact, under-relaxed): same fixed point, a few updates.
    aug_k = np.zeros((n_lev, nc))
    for k in range(n_lev):
        for e in range(nc):
            wee = max(w_list[k][2 * e, 2 * e], w_list[k][2 * e + 1, 2 * e + 1])
            aug_k[k, e] = contacts.k_n[e] + (augment_boost / wee if wee > 0 else 0.0)
    s_mat = np.ascontiguousarray(np.stack(s_list))
    w_mat = np.ascontiguousarray(np.stack(w_list))
    return factors, s_mat, w_mat, lev_req, aug_k, _pack_factors(factors, n), inv_t


def _pack_factors(factors, n: int) -> tuple:
    """The per-level LU factors as the kernel reads them: arrays with the level as first
    axis, index and value rows padded to the largest factor (l_ptr, l_idx, l_val, l_dinv,
    u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c)."""
    n_lev = len(factors)
    nnz_l = max(1, max((f.l_val.size for f in factors), default=0))   # none: dense
    nnz_u = max(1, max((f.u_val.size for f in factors), default=0))
    l_ptr = np.zeros((n_lev, n + 1), np.int64)
    u_ptr = np.zeros((n_lev, n + 1), np.int64)
    l_idx = np.zeros((n_lev, nnz_l), np.int64)
    u_idx = np.zeros((n_lev, nnz_u), np.int64)
    l_val = np.zeros((n_lev, nnz_l))
    u_val = np.zeros((n_lev, nnz_u))
    l_dinv = np.zeros((n_lev, n))
    u_dinv = np.zeros((n_lev, n))
    perm_r = np.zeros((n_lev, n), np.int64)
    perm_c = np.zeros((n_lev, n), np.int64)
    for k, f in enumerate(factors):
        l_ptr[k] = f.l_ptr
        u_ptr[k] = f.u_ptr
        l_idx[k, : f.l_idx.size] = f.l_idx
        u_idx[k, : f.u_idx.size] = f.u_idx
        l_val[k, : f.l_val.size] = f.l_val
        u_val[k, : f.u_val.size] = f.u_val
        l_dinv[k] = f.l_dinv
        u_dinv[k] = f.u_dinv
        perm_r[k] = f.perm_r
        perm_c[k] = f.perm_c
    return l_ptr, l_idx, l_val, l_dinv, u_ptr, u_idx, u_val, u_dinv, perm_r, perm_c


# --------------------------------------------------------------------------------------------
# the kernel's arrays (rubdiag.kernels.newmark's bundles; rubdiag.kernels.layout names rows)
# --------------------------------------------------------------------------------------------
def _linear(M, C, K, dense: bool) -> Linear:
    """M and C in CSR, the union pattern of M and K with both value arrays (one pass
    computes M dq and K dq), and for a dense system M and K as dense arrays."""
    n = M.shape[0]
    pat = sp.csr_matrix(abs(M) + abs(K))
    pat.sort_indices()
    rows = np.repeat(np.arange(n), np.diff(pat.indptr))
    mk_m = np.ascontiguousarray(np.asarray(M[rows, pat.indices]).ravel(), dtype=np.float64)
    mk_k = np.ascontiguousarray(np.asarray(K[rows, pat.indices]).ravel(), dtype=np.float64)
    empty = np.zeros((0, 0))
    return Linear(
        M.indptr.astype(np.int64), M.indices.astype(np.int64), M.data,
        C.indptr.astype(np.int64), C.indices.astype(np.int64), C.data,
        pat.indptr.astype(np.int64), pat.indices.astype(np.int64), mk_m, mk_k,
        M.toarray() if dense else empty, K.toarray() if dense else empty)


def _coupled(M: np.ndarray, K: np.ndarray) -> int:
    """How many leading coordinates of a dense system are coupled in M and K: the others
    form a modal tail, K diagonal in their rows and M diagonal in their block, exactly (a
    Craig–Bampton model's fixed-interface modes), which the kernel's products skip."""
    n = M.shape[0]
    modal = [not (np.any(K[i, :i]) or np.any(K[i, i + 1:]) or np.any(M[i, i + 1:]))
             for i in range(n)]
    tail = 0
    while tail < n and modal[n - 1 - tail]:
        tail += 1
    return n - tail


def _checked_profile(profile, tolerance, G, force: HarmonicForce, n: int, grid: _TimeGrid):
    """``(rot, stretches, G)`` of a speed profile (:func:`simulate_system`); for constant
    speed ``(empty (0, 3), [], None)``. ``tolerance`` 0 gives one stretch per largest step,
    each at Ω at its end (the reference the stretches are tested against)."""
    if profile is None:
        return np.zeros((0, 3)), [], None
    if not isinstance(profile, SpeedProfile):
        raise _check.wrong_type("speed_profile", type(profile).__name__,
                                "a SpeedProfile or None")
    if G is None:
        raise ValueError("speed_profile needs gyroscopic (the unit-speed G; use a zero "
                         "matrix for a system without gyroscopic terms)")
    G = _check_matrix("gyroscopic", G, n)
    if force.dofs.size and not np.allclose(force.omega, profile.start_rad_s, rtol=1e-12,
                                           atol=0):
        raise ValueError(f"force.omega = {force.omega[0]:g} rad/s (allowed: the speed "
                         f"profile's start speed, {profile.start_rad_s:g} rad/s)")
    if tolerance == 0:
        ends = grid.dt * np.arange(1, grid.n_big + 1)
        return profile.knots(), list(zip(ends.tolist(), profile.speed(ends).tolist(),
                                         strict=True)), G
    return profile.knots(), profile.stretches(grid.n_big * grid.dt, tolerance), G


class _Schedule:
    """The stretches of a speed profile in ticks, and the step operators of each: the kernel
    runs stretch by stretch, with Ω_ref G in K_eff (:func:`simulate_system`)."""

    def __init__(self, stretches, grid: _TimeGrid, operators):
        tick_dt = grid.dt / 2**grid.top
        self.ends = [min(grid.tick_total, round(t / tick_dt)) for t, _ in stretches]
        self.ends[-1] = grid.tick_total
        self.speeds = [w for _, w in stretches]
        self.operators = operators
        self.index = 0
        self.used = 1

    def tick_end(self) -> int:
        return self.ends[self.index]

    def advance(self, tick: int):
        """The operators for the stretch holding ``tick`` (None: the current ones hold)."""
        index = self.index
        while index < len(self.ends) - 1 and tick >= self.ends[index]:
            index += 1
        if index == self.index:
            return None
        self.index = index
        self.used += 1
        return self.operators(self.speeds[index])


def _contact_set(contacts: Contacts, g_start, omega: float, lev_req, aug_k) -> ContactSet:
    return ContactSet(
        np.ascontiguousarray(contacts.kind),
        np.ascontiguousarray(np.hstack([contacts.dof_a, contacts.dof_b]).astype(np.int64)),
        np.ascontiguousarray(contacts.basis()), np.ascontiguousarray(contacts.gap), g_start,
        np.ascontiguousarray(contacts.k_n), np.ascontiguousarray(contacts.k_t),
        np.ascontiguousarray(contacts.mu),
        np.ascontiguousarray(contacts.augmented.astype(np.int64)),
        np.ascontiguousarray(contacts.eps), np.ascontiguousarray(omega * contacts.radius),
        lev_req, aug_k)


def _state(M, K, q0, v0, a0, p0, d0, cf, ci, e_c0: float) -> State:
    """The kernel's state at t = 0 (copies: the inputs stay as they are)."""
    istate = np.zeros(layout.I_SIZE, np.int64)
    fstate = np.zeros(layout.F_SIZE)
    fstate[layout.F_E_CONTACT] = e_c0
    fstate[layout.F_FAIL_TIME] = np.nan
    istate[layout.I_FAIL_ELEMENT] = -1
    return State(q0.copy(), v0.copy(), a0.copy(), np.ascontiguousarray(M @ v0),
                 np.ascontiguousarray(K @ q0), p0.copy(), np.ascontiguousarray(d0), cf, ci,
                 istate, fstate)


def _outputs(grid: _TimeGrid, nc: int, record_dofs, sensor_dofs, recovery) -> Outputs:
    """The recorded samples and the sensor stream, zeros, with the recovery maps."""
    n_out, n_sen = grid.n_out, grid.n_sensor_samples(sensor_dofs.size)
    empty = np.zeros((0, 0))
    sensors = np.zeros((n_sen, sensor_dofs.size))
    return Outputs(
        record_dofs, np.zeros((n_out, record_dofs.size)), np.zeros((n_out, nc)),
        np.zeros((n_out, nc)), np.zeros((n_out, nc), np.int64), np.zeros((n_out, nc)),
        np.zeros((n_out, nc)), np.zeros((n_out, layout.EN_SIZE)),
        sensor_dofs, sensors, np.zeros_like(sensors), np.zeros_like(sensors),
        empty if recovery is None else np.ascontiguousarray(recovery[record_dofs].T),
        empty if recovery is None else np.ascontiguousarray(recovery[sensor_dofs].T))


def _logs(nc: int, n_lev: int, episode_capacity: int) -> Logs:
    """Empty logs (the segment log starts at four times the episode capacity)."""
    return Logs(
        np.zeros((episode_capacity, layout.EPF_SIZE)),
        np.zeros((episode_capacity, layout.EPI_SIZE), np.int64),
        np.zeros((4 * episode_capacity, layout.SG_SIZE)),
        np.zeros((4 * episode_capacity, layout.SG_SIZE), np.int64),
        np.zeros(256), np.zeros(256, np.int64),
        np.zeros((nc, layout.TOT_SIZE)), np.zeros((nc, layout.MX_SIZE)),
        np.zeros(n_lev, np.int64))


def _grown(logs: Logs, istate, nc: int) -> Logs:
    """``logs`` with room for another step (:data:`STATUS_LOG_FULL`): each log that could
    overflow doubled (the episode log plus n_c rows)."""
    ep_f, ep_i, sg_f, sg_i, lv_t, lv_l = logs[:6]
    if istate[layout.I_N_EPISODES] + nc > ep_f.shape[0]:
        more = ep_f.shape[0] + nc
        ep_f = np.concatenate([ep_f, np.zeros((more, layout.EPF_SIZE))])
        ep_i = np.concatenate([ep_i, np.zeros((more, layout.EPI_SIZE), np.int64)])
    if istate[layout.I_N_SEGMENTS] + nc > sg_f.shape[0]:
        sg_f = np.concatenate([sg_f, np.zeros_like(sg_f)])
        sg_i = np.concatenate([sg_i, np.zeros_like(sg_i)])
    if istate[layout.I_N_LEVEL_CHANGES] + 2 > lv_t.shape[0]:
        lv_t = np.concatenate([lv_t, np.zeros(lv_t.shape[0])])
        lv_l = np.concatenate([lv_l, np.zeros(lv_l.shape[0], np.int64)])
    return logs._replace(ep_f=ep_f, ep_i=ep_i, sg_f=sg_f, sg_i=sg_i, lv_t=lv_t, lv_l=lv_l)


def _work(n: int, nc: int, profile: bool) -> Work:
    """Work arrays, and the cycle counters when profiling (else empty)."""
    return Work(np.zeros((layout.WN_SIZE, n)), np.zeros((layout.WC_SIZE, 2 * nc)),
                np.zeros((layout.WCN_SIZE, nc)), np.zeros((2 * nc, 2 * nc)), np.zeros((nc, 4)),
                np.zeros(5 * nc, np.int64), np.zeros((layout.CR_SIZE, nc)),
                np.zeros(layout.P_SIZE if profile else 0, np.int64))


def _parameters(grid: _TimeGrid, settings: _Settings, t_ramp: float, fixed_step: bool):
    """The kernel's ``fpar`` and ``ipar`` (the end tick is set per call)."""
    fpar = np.zeros(layout.FP_SIZE)
    fpar[layout.FP_DT] = grid.dt
    fpar[layout.FP_T_RAMP] = t_ramp
    fpar[layout.FP_NEWTON_TOL] = settings.newton_tol
    fpar[layout.FP_GAP_JUMP] = settings.gap_jump
    # the boosted update's landing point in the band (see augment_boost)
    fpar[layout.FP_AUG_SHIFT] = 0.98 if settings.augment_boost > 0 else 0.0
    fpar[layout.FP_BETA] = settings.beta
    fpar[layout.FP_GAMMA] = settings.gamma
    ipar = np.zeros(layout.IP_SIZE, np.int64)
    ipar[layout.IP_N_LEV] = grid.n_lev
    ipar[layout.IP_FIXED] = int(bool(fixed_step))
    ipar[layout.IP_GROW_AFTER] = settings.grow_after
    ipar[layout.IP_MAX_NEWTON] = settings.max_newton
    ipar[layout.IP_MAX_AUG] = settings.max_augment
    ipar[layout.IP_OUT_TICKS] = grid.out_ticks
    ipar[layout.IP_AUG_STRICT] = int(settings.augment_strict)
    ipar[layout.IP_SEN_TICKS] = grid.sen_ticks
    return fpar, ipar


# --------------------------------------------------------------------------------------------
# the public entry point
# --------------------------------------------------------------------------------------------
def simulate_system(
    M,
    C,
    K,
    force: HarmonicForce | None,
    contacts: Contacts | None,
    q0,
    v0,
    *,
    duration: float,
    dt: float,
    dt_min: float | None = None,
    fixed_step: bool = False,
    output_dt: float | None = None,
    record_dofs: Sequence[int] | np.ndarray | None = None,
    sensor_dofs: Sequence[int] | np.ndarray | None = None,
    gap_ramp: tuple[float, float | np.ndarray] | None = None,
    omega: float = 0.0,
    gamma: float = 0.5,
    a0=None,
    max_newton: int = 25,
    newton_tol: float = 1e-12,
    max_augment: int = 10000,
    augment_boost: float = 0.0,
    augment_strict: bool = True,
    gap_jump: float = 1e-5,
    contact_stiffness_ratio: float | None = 0.25,
    grow_after: int = 8,
    episode_capacity: int = 4096,
    progress: Callable[[float, float], None] | None = None,
    raise_on_failure: bool = True,
    profile: bool = False,
    linear_solver: str = "sparse",
    recovery: np.ndarray | None = None,
    gyroscopic=None,
    speed_profile: SpeedProfile | None = None,
    speed_tolerance: float = 0.005,
) -> SystemResult:
    """Integrate ``M q'' + C q' + K q = f(t) + contact forces`` from ``(q0, v0)`` at t = 0.

    Parameters
    ----------
    M, C, K : sparse (n, n)
        Mass (kg), damping (N s/m; damping + Ω G, constant) and stiffness (N/m) matrices.
        M must be nonsingular. The energy ledger assumes M and K symmetric (C may carry a
        skew gyroscopic part, which does no work).
    force : HarmonicForce or None
        External load (N): harmonic terms by shaft order and amplitude law
        (:mod:`rubdiag.simulate.loads`).
    contacts : Contacts or None
        Contact elements.
    q0, v0 : (n,)
        Initial displacement (m) and velocity (m/s).
    duration : float
        Simulated time (s), at least one step ``dt``. The run ends at ``N dt`` with
        ``N = floor(duration / dt)`` (``round`` when within 1e-9 of an integer).
    dt : float
        Largest (and initial) step (s), > 0.
    dt_min : float, optional
        Smallest step (s), in (0, dt]; the step sizes are ``dt / 2^k`` down to the largest
        such value >= dt_min. Default ``dt / 64``. Ignored with ``fixed_step``.
    fixed_step : bool
        Constant step ``dt`` (for convergence studies): no halving, a contact iteration that
        fails stops the run.
    output_dt : float, optional
        Sampling interval of the recorded waveforms (s), a positive integer multiple of
        ``dt`` (default ``dt``). Samples are exact states at ``t = k output_dt`` (sample times
        always fall on step ends; nothing is interpolated).
    record_dofs : sequence of int, optional
        DOFs whose displacements are recorded (default: all).
    sensor_dofs : sequence of int, optional
        DOFs whose displacement, velocity and acceleration (the integrator's state) are
        recorded at every multiple of ``dt`` (``sensor_q``, ``sensor_v``, ``sensor_a``):
        the raw stream sensors are filtered and decimated from (default: none).
    gap_ramp : (t_ramp, g_start), optional
        Ramp every element's gap linearly from ``g_start`` (m; scalar or (n_c,), >= g0) at
        t = 0 down to its g0 at ``t_ramp`` (s), so that a linear orbit larger than the gap
        does not start deep inside the casing. Default: no ramp.
    omega : float
        Shaft speed Ω (rad/s): the surface speed Ω R of kind-2 elements.
    gamma : float
        Newmark γ in [0.5, 1]; β = (γ + 1/2)² / 4. The default 1/2 is average acceleration
        (second order, no numerical damping, exact energy identity). γ > 1/2 adds numerical
        damping of the highest frequencies (first order accurate; costs three more sparse
        products per step); the energy residual then also contains the numerical
        dissipation, and ``dissipated_viscous`` uses the trapezoidal mean velocity. (It does
        not cure the augmented-Lagrangian chatter described under ``augment_boost``: tried
        with γ = 0.55 and 0.6.)
    a0 : (n,), optional
        Initial acceleration (m/s²); default: from equilibrium at t = 0,
        ``M a0 = f(0) + Bᵀp(q0) - C v0 - K q0``.
    max_newton : int
        Newton iterations allowed per contact solve (>= 0).
    newton_tol : float
        Convergence tolerance on the contact displacement residual (m), > 0.
    max_augment : int
        Multiplier updates allowed per step (augmented elements), >= 0.
    augment_boost : float
        0 (default): eq. (2) literally, ``λ <- max(0, λ - k_N g)`` while a closed element has
        ``g <= -ε`` or ``g > 0``. It creeps towards g = 0 by a factor ``1 / (1 + k_N W_ee)``
        per update (``W_ee``: the element's diagonal of ``B K_eff^-1 B^T`` at the current step),
        i.e. hundreds of updates per step at small steps, and stops just inside the band.
        > 0: ``λ <- max(0, λ - (k_N + augment_boost / W_ee) (g + 0.98 ε))``, a few updates,
        landing at about ``g = -0.98 ε`` (close to where eq. (2) stops, but with a somewhat
        larger rebound). In [0, 1].
        **Caveat** (measured, see the tests): enforcing the band within each step is a
        rigid wall at depth ε; with the trapezoidal rule a wall hit inside one step gives an
        impulsive force (tens of times the penalty force) and, in *sustained* contact, force
        chatter orders of magnitude above the penalty force and a broken energy balance.
        Pure penalty (the default; README "Differences from the study, and why") has none
        of this.
    augment_strict : bool
        If True (default) a step whose multipliers do not bring every closed element into the
        band within ``max_augment`` updates is a failed contact iteration (halve the step /
        stop); if False it is accepted as is and counted in ``extra['augment_pending']``.
    gap_jump : float
        A step in which an element closes and ends deeper than this penetration (m) is
        rejected and retried at half the step (unless at dt_min or with ``fixed_step``).
    contact_stiffness_ratio : float or None
        Steps in which an element is closed use at most the step size at which
        ``k_N W_ee <= contact_stiffness_ratio``, where ``W_ee`` is the element's diagonal of
        ``B K_eff^-1 B^T`` (for a lumped mass m, ``k_N W_ee ≈ (ω_c h)^2 / 4`` with
        ``ω_c = sqrt(k_N / m)``): resolves a contact stiffness that the step cannot follow
        (down to dt_min). Kind 1 uses the normal row only (the tangential stick spring k_T
        is not considered: at the blade tips of the 412-DOF rig-like test system ``k_T W_tt``
        is ~14x ``k_N W_nn`` at dt = 1e-5 s, and resolving it would cost 4x steps in rub).
        None disables it. Ignored with ``fixed_step``. The default 0.25 (ω_c h <= 1) brought
        the energy residual of the stiff robustness corners (k_N = 1e9 N/m at dt = 1e-4 s)
        from 110-190 % (no criterion) to below 1 %.
    grow_after : int
        Accepted steps at one level before the step is doubled again (>= 1).
    episode_capacity : int
        Initial capacity of the episode log (it grows as needed).
    progress : callable(t, duration), optional
        Called about 100 times during the run (the kernel runs in chunks).
    raise_on_failure : bool
        If True (default) a failed run raises :class:`SimulationDiverged` carrying the partial
        result; if False the partial result is returned with ``status != 0``.
    profile : bool
        Count the CPU cycles of each section of a step (``extra['profile_cycles']``, by
        section name, :data:`~rubdiag.kernels.newmark.PROFILE_SECTIONS`); the results are
        the same bits (``benchmarks/bench_breakdown.py``).
    linear_solver : {"sparse", "dense"}
        How a step solves with K_eff: sparse LU triangular solves (the default, for large
        sparse systems), or a product with its dense inverse, and dense products with M and
        K (for small dense systems such as a reduced model: no indirection, vectorized).
    recovery : (n_phys, n), optional
        The integrated coordinates are generalised (a reduced model): physical
        displacements are ``recovery @ q``. ``record_dofs`` and ``sensor_dofs`` then index
        the physical DOFs, the kernel records the recovered values, and ``q_final``,
        ``v_final``, ``a_final`` are physical too.
    gyroscopic : (n, n), optional
        The unit-speed gyroscopic matrix G (N s/m per rad/s), with ``speed_profile``: the
        damping is then ``C + Ω(t) G``, C without the gyroscopic part.
    speed_profile : SpeedProfile, optional
        A spin speed that changes in time (:mod:`rubdiag.simulate.speed_profile`). The load
        rotates with the shaft angle φ(t) and includes the angular acceleration (``force``
        holds its amplitudes at the profile's start speed, which its ``omega`` must equal).
        Ω(t) G is held at a reference speed over stretches of the run in which Ω stays
        within ``speed_tolerance`` of it (relative), and the step operators are
        refactorised at each new stretch (``extra['speed_stretches']``); kind-2 elements'
        surface speed follows the same reference. ``omega`` is then ignored.
    speed_tolerance : float
        See ``speed_profile``; in (0, 0.5], or 0: refactorise at every largest step, with
        Ω at its end (slow; the reference of the stretches' accuracy test).

    Returns
    -------
    SystemResult
    """
    ensure_fresh_cache()    # before the first kernel call of this process
    t_start = time.perf_counter()
    M, C, K, force, contacts, q0, v0 = _checked_system(M, C, K, force, contacts, q0, v0)
    n, nc = M.shape[0], contacts.n_c
    grid = _time_grid(duration, dt, dt_min, fixed_step, output_dt)
    rot, stretches, G = _checked_profile(speed_profile, speed_tolerance, gyroscopic, force, n,
                                         grid)
    if stretches:
        omega = stretches[0][1]
        C_base, C = C, (C + omega * G).tocsr()
    dense = _check.choice("linear_solver", linear_solver, ("sparse", "dense")) == "dense"
    recovery, record_dofs, sensor_dofs = _checked_records(grid, n, record_dofs, sensor_dofs,
                                                          recovery)
    settings = _Settings.checked(omega, gamma, max_newton, max_augment, grow_after, newton_tol,
                                 augment_boost, augment_strict, gap_jump,
                                 contact_stiffness_ratio, episode_capacity)
    t_ramp, g_start = _checked_gap_ramp(gap_ramp, contacts)

    # the state at t = 0, the operators of each step size, the kernel's arrays
    B = contacts.b_matrix(n)
    d0 = B @ q0
    p0, cf, ci, e_c0 = _initial_contact_state(contacts, d0,
                                              g_start if t_ramp > 0 else contacts.gap)
    a0 = _initial_acceleration(M, C, K, load_vector(force, speed_profile, 0.0, n), B, p0, q0, v0,
                               a0)
    factors, s_mat, w_mat, lev_req, aug_k, lu, inv_t = _level_operators(
        M, C, K, B, contacts, grid.dt, grid.n_lev, settings.gamma, settings.beta,
        None if fixed_step else settings.contact_stiffness_ratio, settings.augment_boost, dense)
    state = _state(M, K, q0, v0, a0, p0, d0, cf, ci, e_c0)
    outputs = _outputs(grid, nc, record_dofs, sensor_dofs, recovery)
    fpar, ipar = _parameters(grid, settings, t_ramp, fixed_step)
    linear = _linear(M, C, K, dense)
    ipar[layout.IP_COUPLED] = _coupled(linear.m_dense, linear.k_dense)
    arrays = (linear, Factors(*lu, s_mat, w_mat, inv_t), kernel_force(force, rot),
              _contact_set(contacts, g_start, settings.omega, lev_req, aug_k), fpar, ipar,
              state, outputs)
    logs = _logs(nc, grid.n_lev, settings.episode_capacity)
    work = _work(n, nc, profile)
    t_setup = time.perf_counter() - t_start

    schedule = None
    if stretches:
        def operators(omega_ref):    # the step operators with Ω_ref G, for the next stretch
            C_ref = (C_base + omega_ref * G).tocsr()
            ops = _level_operators(
                M, C_ref, K, B, contacts, grid.dt, grid.n_lev, settings.gamma, settings.beta,
                None if fixed_step else settings.contact_stiffness_ratio,
                settings.augment_boost, dense)
            return (_linear(M, C_ref, K, dense), Factors(*ops[5], ops[1], ops[2], ops[6]),
                    _contact_set(contacts, g_start, omega_ref, ops[3], ops[4]))

        schedule = _Schedule(stretches, grid, operators)
    code, logs, t_kernel = _integrate(arrays, logs, work, grid, progress, schedule)
    result = _package(code, grid, state, outputs, logs)
    if recovery is not None:    # the final state in physical DOFs, like the records
        q, v, a = state.q, state.v, state.a
        result = dataclasses.replace(result, q_final=recovery @ q, v_final=recovery @ v,
                                     a_final=recovery @ a)
    if profile:
        result.extra["profile_cycles"] = dict(zip(PROFILE_SECTIONS, work.prof.tolist(),
                                                  strict=True))
    result.extra.update(
        setup_seconds=t_setup, kernel_seconds=t_kernel, contact_level_required=lev_req,
        augment_pending=int(state.istate[layout.I_AUG_PENDING]),
        lu_nnz=[f.nnz for f in factors], lu_ordering=[f.ordering for f in factors],
    )
    if schedule is not None:
        result.extra["speed_stretches"] = schedule.used
    if result.status != 0 and raise_on_failure:
        raise SimulationDiverged(result.message, result)
    return result


# --------------------------------------------------------------------------------------------
# running the kernel, and the result
# --------------------------------------------------------------------------------------------
def _integrate(arrays: tuple, logs: Logs, work: Work, grid: _TimeGrid, progress,
               schedule: _Schedule | None = None):
    """Run the kernel to the end of the run (or a failure): in chunks of about 1 % of the
    run when there is a ``progress`` to call, growing a log whenever one is full, and with a
    speed profile's ``schedule`` stretch by stretch (new step operators at each). Returns
    the kernel's status code, the logs and the kernel's wall time (s)."""
    linear, factors, force, contacts, fpar, ipar, state, outputs = arrays
    istate = state.istate
    n_chunks = 100 if progress is not None else 1
    chunk = max(np.int64(1), grid.tick_total // n_chunks)
    t_kernel = 0.0
    while True:
        end = min(grid.tick_total, istate[layout.I_TICK] + chunk)
        if schedule is not None:
            ops = schedule.advance(int(istate[layout.I_TICK]))
            if ops is not None:
                linear, factors, contacts = ops
            end = min(end, schedule.tick_end())
        ipar[layout.IP_TICK_END] = end
        tk = time.perf_counter()
        code = newmark_contact(linear, factors, force, contacts, fpar, ipar, state, outputs,
                               logs, work)
        t_kernel += time.perf_counter() - tk
        if code == STATUS_LOG_FULL:
            logs = _grown(logs, istate, contacts.kind.shape[0])
            continue
        if code != STATUS_DONE:
            return code, logs, t_kernel
        if progress is not None:
            progress(float(istate[layout.I_TICK]) * grid.dt / 2**grid.top, grid.n_big * grid.dt)
        if istate[layout.I_TICK] >= grid.tick_total:
            return code, logs, t_kernel


def _package(code, grid: _TimeGrid, state: State, outputs: Outputs, logs: Logs) -> SystemResult:
    """The kernel's arrays as a :class:`SystemResult`, cut to what the run reached."""
    istate, fstate = state.istate, state.fstate
    tick = int(istate[layout.I_TICK])
    t_final = tick * grid.dt / 2**grid.top
    n_written = tick // int(grid.out_ticks) + 1
    n_sen = tick // int(grid.sen_ticks) + 1 if outputs.sen_dof.size else 0
    episodes, segments = _episode_logs(state, logs, t_final)
    status, message = _status(code, istate, fstate, t_final, grid.dt_min)
    nl = int(istate[layout.I_N_LEVEL_CHANGES])
    sl = slice(0, n_written)
    en = outputs.en
    tot, mx = logs.tot, logs.mx
    return SystemResult(
        t=np.arange(n_written) * grid.output_dt,
        record_dofs=outputs.rec_dof,
        q=outputs.q[sl],
        contact_fn=outputs.fn[sl],
        contact_ft=outputs.ft[sl],
        contact_status=outputs.st[sl].astype(np.int8),
        contact_gap=outputs.gap[sl],
        contact_slip=outputs.slip[sl],
        work_external=en[sl, layout.EN_W_EXT],
        work_drive=en[sl, layout.EN_W_DRIVE],
        dissipated_viscous=en[sl, layout.EN_D_VISC],
        dissipated_friction=en[sl, layout.EN_D_FRIC],
        contact_algorithmic=en[sl, layout.EN_D_NUM],
        kinetic=en[sl, layout.EN_KINETIC],
        strain=en[sl, layout.EN_STRAIN],
        contact_elastic=en[sl, layout.EN_CONTACT],
        episodes=episodes,
        status_segments=segments,
        time_in_status=tot[:, layout.TOT_TIME:layout.TOT_TIME + 3].copy(),
        normal_impulse=tot[:, layout.TOT_FN_IMPULSE:layout.TOT_FN_IMPULSE + 3].copy(),
        tangential_impulse=tot[:, layout.TOT_FT_IMPULSE:layout.TOT_FT_IMPULSE + 3].copy(),
        max_normal_force=mx[:, layout.MX_FN].copy(),
        max_tangential_force=mx[:, layout.MX_FT].copy(),
        max_penetration=mx[:, layout.MX_PENETRATION].copy(),
        max_cone_excess=float(fstate[layout.F_CONE_EXCESS]),
        dt=grid.dt,
        dt_min=grid.dt / 2**grid.top,
        output_dt=grid.output_dt,
        dt_levels=grid.dt / 2.0 ** np.arange(grid.n_lev),
        steps_per_level=logs.lvl_count.copy(),
        level_change_t=logs.lv_t[:nl].copy(),
        level_change_level=logs.lv_l[:nl].copy(),
        n_steps=int(istate[layout.I_N_ACCEPTED]),
        n_rejected_newton=int(istate[layout.I_N_REJ_NEWTON]),
        n_rejected_abrupt=int(istate[layout.I_N_REJ_ABRUPT]),
        n_abrupt_at_min=int(istate[layout.I_N_ABRUPT_AT_MIN]),
        newton_iterations=int(istate[layout.I_NEWTON_TOTAL]),
        newton_iterations_max=int(istate[layout.I_NEWTON_MAX]),
        augment_iterations=int(istate[layout.I_AUG_TOTAL]),
        augment_iterations_max=int(istate[layout.I_AUG_MAX]),
        t_final=t_final,
        q_final=state.q.copy(),
        v_final=state.v.copy(),
        a_final=state.a.copy(),
        status=status,
        message=message,
        failure_time=float(fstate[layout.F_FAIL_TIME]) if status else float("nan"),
        failure_element=int(istate[layout.I_FAIL_ELEMENT]) + 1 if status else 0,  # 0: none
        sensor_dofs=outputs.sen_dof,
        sensor_dt=float(grid.dt * int(grid.sen_ticks) / 2**grid.top),
        sensor_q=outputs.sq[:n_sen],
        sensor_v=outputs.sv[:n_sen],
        sensor_a=outputs.sa[:n_sen],
    )


def _episode_logs(state: State, logs: Logs, t_final: float):
    """The episode and status-segment logs: the ended ones as logged, then those still
    open at ``t_final`` (from the per-element state)."""
    cf, ci, istate = state.cf, state.ci, state.istate
    ne = int(istate[layout.I_N_EPISODES])
    ns = int(istate[layout.I_N_SEGMENTS])
    ep_f, ep_i, sg_f, sg_i = logs.ep_f[:ne], logs.ep_i[:ne], logs.sg_f[:ns], logs.sg_i[:ns]
    open_el = np.flatnonzero(ci[layout.CI_STATUS] != OPEN)

    def ended_then_open(ended, current):
        return np.concatenate([ended, current[open_el]])

    element = np.arange(ci.shape[1])
    still_open = np.full(open_el.size, t_final)
    episodes = EpisodeLog(
        element=ended_then_open(ep_i[:, layout.EPI_ELEMENT], element) + 1,  # numbered from 1
        t_start=ended_then_open(ep_f[:, layout.EPF_T_START], cf[layout.CF_EP_START]),
        t_end=np.concatenate([ep_f[:, layout.EPF_T_END], still_open]),
        n_steps=ended_then_open(ep_i[:, layout.EPI_STEPS], ci[layout.CI_EP_STEPS]),
        peak_normal_force=ended_then_open(ep_f[:, layout.EPF_PEAK_FN],
                                          cf[layout.CF_EP_PEAK_FN]),
        n_slide_entries=ended_then_open(ep_i[:, layout.EPI_SLIDE_ENTRIES],
                                        ci[layout.CI_EP_SLIDE_ENTRIES]),
        n_stick_entries=ended_then_open(ep_i[:, layout.EPI_STICK_ENTRIES],
                                        ci[layout.CI_EP_STICK_ENTRIES]),
        slide_time=ended_then_open(ep_f[:, layout.EPF_SLIDE_TIME], cf[layout.CF_EP_SLIDE_TIME]),
        stick_time=ended_then_open(ep_f[:, layout.EPF_STICK_TIME], cf[layout.CF_EP_STICK_TIME]),
        slide_impulse=ended_then_open(ep_f[:, layout.EPF_SLIDE_IMPULSE],
                                      cf[layout.CF_EP_SLIDE_IMPULSE]),
        stick_impulse=ended_then_open(ep_f[:, layout.EPF_STICK_IMPULSE],
                                      cf[layout.CF_EP_STICK_IMPULSE]),
        complete=np.concatenate([ep_i[:, layout.EPI_COMPLETE] == 1,
                                 np.zeros(open_el.size, bool)]),
    )
    segments = StatusLog(
        element=ended_then_open(sg_i[:, layout.SGI_ELEMENT], element) + 1,
        status=ended_then_open(sg_i[:, layout.SGI_STATUS], ci[layout.CI_STATUS]).astype(np.int8),
        t_start=ended_then_open(sg_f[:, layout.SGF_T_START], cf[layout.CF_SEG_START]),
        t_end=np.concatenate([sg_f[:, layout.SGF_T_END], still_open]),
    )
    return episodes, segments


def _status(code, istate, fstate, t_final: float, dt_min: float) -> tuple[int, str]:
    """The result's status (0 done, 1 no convergence, 2 non-finite) and its message."""
    status = {STATUS_DONE: 0, STATUS_NO_CONVERGENCE: 1, STATUS_NONFINITE: 2}[code]
    fail_t = float(fstate[layout.F_FAIL_TIME])
    fail_e = int(istate[layout.I_FAIL_ELEMENT]) + 1
    if status == 0:
        return status, f"Reached t = {t_final:.6g} s in {int(istate[layout.I_N_ACCEPTED])} steps."
    if status == 1:
        why = {NEWTON_FAILED: "Newton iterations exhausted",
               AUGMENT_FAILED: "augmentation did not reach eps",
               SINGULAR: "singular contact Jacobian"}.get(int(istate[layout.I_FAIL_CODE]),
                                                          "unknown")
        return status, (
            f"Contact iteration did not converge ({why}) at t = {fail_t:.9g} s, contact element "
            f"{fail_e}, even at the smallest step {dt_min:.3g} s; results kept up to "
            f"t = {t_final:.9g} s."
        )
    where = f"contact element {fail_e}" if fail_e > 0 else "the structure"
    return status, (f"State became non-finite at t = {fail_t:.9g} s ({where}); results kept "
                    f"up to t = {t_final:.9g} s.")
