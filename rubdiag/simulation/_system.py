"""Time integration of a generic linear system with contact elements.

``M q'' + C q' + K q = f(t) + Σ_e B_eᵀ p_e(q)`` integrated by Newmark average acceleration
(beta = 1/4, gamma = 1/2) with Newton on the contact forces, solved in a small Schur
complement, and a variable step. The whole time loop runs in one Numba kernel
(:func:`rubdiag._kernels.newmark.newmark_contact`); this module validates, precomputes the
factorizations per step size, allocates, calls and packages the result.

Units are SI throughout: m, s, N, kg, rad/s.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag import _check
from rubdiag._kernels import ensure_fresh_cache, records
from rubdiag._kernels.annular_contact import KIND as KIND_ANNULAR
from rubdiag._kernels.elements import AUGMENT_FAILED, KINDS, N_LOCAL_MAX, NEWTON_FAILED, SINGULAR
from rubdiag._kernels.extend import Kernel, kernel_with
from rubdiag._kernels.newmark import (
    PROFILE_SECTIONS,
    STATUS_DONE,
    STATUS_LOG_FULL,
    STATUS_NO_CONVERGENCE,
    STATUS_NONFINITE,
    WC_SIZE,
    WN_SIZE,
    Elements,
    Factors,
    Linear,
    Logs,
    Outputs,
    State,
    Work,
)
from rubdiag._kernels.point_contact import KIND as KIND_POINT
from rubdiag._kernels.records import OPEN
from rubdiag._kernels.sparse_lu import factorize
from rubdiag.simulation._descriptions import LinearSystem, Recording, Solver, TimeGrid, legacy_call
from rubdiag.simulation._elements import AnnularContact, Packed, PointContact
from rubdiag.simulation._loads import HarmonicForce, kernel_force, load_vector
from rubdiag.simulation._result import EpisodeLog, SimulationDiverged, StatusLog, SystemResult
from rubdiag.simulation._speed_profile import SpeedProfile

__all__ = [
    "Contacts",
    "HarmonicForce",
    "SimulationDiverged",
    "SystemResult",
    "simulate_system",
]

_MAX_LEVELS = 31      # step levels dt / 2^k at most (the tick count stays an int64)
_MAX_LONG = 3         # long steps: dt_max <= 8 dt


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
    * ``gap`` (n_c,) m: the gap g0 at the coordinates' origin (kind 1; finite, negative
      when the origin lies inside the contact) or the radial clearance c (kind 2, >= 0).
    * ``k_n``, ``k_t`` (n_c,) N/m: normal penalty and tangential (stick) stiffness.
    * ``mu`` (n_c,): Coulomb coefficient (>= 0; 0 = frictionless).
    * ``radius`` (n_c,) m: kind 2 shaft surface radius R (slip includes Ω R); 0 for kind 1.
    * ``augmented`` (n_c,) bool and ``eps`` (n_c,) m: augmented Lagrangian on, and its
      penetration tolerance ε (eq. 2 of the paper).
    * ``centre`` (n_c, 2) m: kind 2 the clearance's centre (y, z) in the relative
      displacement (default 0: the bearing line); 0 for kind 1.

    Parameters
    ----------
    kind, dof_a, dof_b, normal, tangent, gap, k_n, k_t, mu, radius, augmented, eps : numpy.ndarray
        The arrays above.
    centre : numpy.ndarray or None
        The annular clearances' centres (above); None: 0.
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
    centre: np.ndarray | None = None

    def __post_init__(self):
        if self.centre is None:
            object.__setattr__(self, "centre", np.zeros((np.size(self.kind), 2)))
        conv = {
            "kind": np.int64, "dof_a": np.int64, "dof_b": np.int64, "normal": np.float64,
            "tangent": np.float64, "gap": np.float64, "k_n": np.float64, "k_t": np.float64,
            "mu": np.float64, "radius": np.float64, "augmented": bool, "eps": np.float64,
            "centre": np.float64,
        }
        for name, dtype in conv.items():
            if dtype is np.int64:   # refuse float indices rather than truncate them
                _check.indices(f"contacts.{name}", getattr(self, name))
            arr = np.array(getattr(self, name), dtype=dtype)
            if name in ("dof_a", "dof_b", "normal", "tangent", "centre"):
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
                   augmented, eps, centre=(0.0, 0.0)) -> Contacts:
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
            each(augmented, bool), each(eps), rows(centre, np.float64),
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
        augmented=False, eps=20e-6, centre=(0.0, 0.0),
    ) -> Contacts:
        """Shaft–stator annular clearances (kind 2) at shaft nodes ``dof_a`` (y, z), about
        ``centre`` (m, y and z of the relative displacement; default the bearing line)."""
        # the basis of kind 2 follows the displacement; the fixed one is a placeholder
        return cls._broadcast(KIND_ANNULAR, dof_a, dof_b, (1.0, 0.0), (0.0, 1.0), clearance,
                              k_n, k_t, mu, radius, augmented, eps, centre)

    def __add__(self, other: Contacts) -> Contacts:
        return Contacts(
            *(np.concatenate([getattr(self, f), getattr(other, f)]) for f in (
                "kind", "dof_a", "dof_b", "normal", "tangent", "gap", "k_n", "k_t", "mu",
                "radius", "augmented", "eps", "centre",
            ))
        )

    def elements(self) -> tuple:
        """The elements one by one, as their kinds' descriptions
        (:class:`~rubdiag.simulation._elements.PointContact`,
        :class:`~rubdiag.simulation._elements.AnnularContact`), in order."""
        out = []
        for e in range(self.n_c):
            law = {"dof_a": tuple(self.dof_a[e].tolist()), "dof_b": tuple(self.dof_b[e].tolist()),
                   "k_n": float(self.k_n[e]), "k_t": float(self.k_t[e]),
                   "mu": float(self.mu[e]), "augmented": bool(self.augmented[e]),
                   "eps": float(self.eps[e])}
            if self.kind[e] == KIND_POINT:
                out.append(PointContact(normal=tuple(self.normal[e].tolist()),
                                        tangent=tuple(self.tangent[e].tolist()),
                                        gap=float(self.gap[e]), **law))
            else:
                out.append(AnnularContact(clearance=float(self.gap[e]),
                                          radius=float(self.radius[e]),
                                          centre=tuple(self.centre[e].tolist()), **law))
        return tuple(out)

    def b_matrix(self, n: int) -> np.ndarray:
        """Dense matrix B (2 n_c, n) of the local contact displacements ``d = B q``."""
        return b_matrix([el.pack(0.0) for el in self.elements()], n)


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
        ("gap", (ct.kind == KIND_ANNULAR) & (ct.gap < 0), ">= 0 m for an annular clearance"),
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


def _checked_elements(contacts, n: int) -> tuple:
    """The nonlinear elements: a :class:`Contacts` (checked), a sequence of element
    descriptions (:mod:`rubdiag.simulation._elements`, or a kind defined outside rubdiag), or
    None (none); each element's DOFs checked against the system's n."""
    if contacts is None:
        return ()
    if isinstance(contacts, Contacts):
        _check_contacts(contacts, n)
        return contacts.elements()
    elements = tuple(contacts)
    for i, element in enumerate(elements):
        if not callable(getattr(element, "pack", None)):
            raise _check.wrong_type(f"elements[{i}]", type(element).__name__,
                                    "an element description (rubdiag.simulation._elements)")
        dofs = np.asarray(element.dofs())
        if dofs.size and (dofs.min() < 0 or dofs.max() >= n):
            raise _bad(f"elements[{i}] DOFs", dofs.tolist(), f"DOF indices in [0, {n})")
    return elements


def _checked_system(M, C, K, force, contacts, q0, v0):
    """The linear system, load, elements and initial state, checked and converted (CSR
    float64 matrices, float64 vectors; None load or contacts: none)."""
    M = _check_matrix("M", M, None)
    n = M.shape[0]
    C = _check_matrix("C", C, n)
    K = _check_matrix("K", K, n)
    force = HarmonicForce.zero() if force is None else force
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
    elements = _checked_elements(contacts, n)
    return M, C, K, force, elements, q0, v0


class _TimeGrid(NamedTuple):
    """A run's checked step sizes and its grid of ticks (a tick is the smallest step).

    The levels are ``dt_max / 2^k``: the first ``base`` are the long steps (``dt_max =
    2^base dt``, taken where the local error allows and no impact element is near), level
    ``base`` is dt, the base step (the first, the longest an impact element may be engaged
    at, and the sensor stream's interval)."""

    dt: float  # the base step (s)
    dt_min: float  # the smallest step asked for (s)
    n_lev: int  # step levels dt_max / 2^k, k < n_lev
    n_big: int  # the run's length in base steps
    output_dt: float  # s
    tick_total: np.int64  # the run's length in ticks
    out_ticks: np.int64  # ticks between recorded samples
    base: int = 0  # the base step's level

    @property
    def top(self) -> int:
        """The smallest step's level."""
        return self.n_lev - 1

    @property
    def dt_max(self) -> float:
        """The longest step (s)."""
        return self.dt * 2**self.base

    @property
    def tick_dt(self) -> float:
        """A tick (s)."""
        return self.dt / 2 ** (self.top - self.base)

    @property
    def n_out(self) -> int:
        """Recorded samples, t = 0 included."""
        return int(self.tick_total // self.out_ticks) + 1

    @property
    def sen_ticks(self) -> np.int64:
        """Ticks between sensor samples: every base step."""
        return np.int64(1) << (self.top - self.base)

    def n_sensor_samples(self, n_sensors: int) -> int:
        return int(self.tick_total // self.sen_ticks) + 1 if n_sensors else 0


def _time_grid(duration, dt, dt_min, fixed_step: bool, output_dt,
               dt_max=None) -> _TimeGrid:
    """The checked step sizes and tick grid of a run (parameters as :func:`simulate_system`)."""
    dt = _check_scalar("dt", dt, 0.0, lo_open=True, allowed="finite and > 0 s")
    base = 0
    if dt_max is not None:
        dt_max = _check_scalar("dt_max", dt_max, dt, allowed=f">= dt = {dt:g} s")
        base = round(math.log2(dt_max / dt))
        if abs(dt_max - dt * 2**base) > 1e-9 * dt_max or base > _MAX_LONG:
            raise _bad("dt_max", dt_max, f"dt = {dt:g} s times 1, 2, 4 … {2**_MAX_LONG}")
        if fixed_step and base:
            raise _bad("dt_max", dt_max, f"dt = {dt:g} s with fixed_step")
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
    top = n_lev - 1     # ticks per base step: 2^top
    n_lev += base
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
    return _TimeGrid(dt, dt_min_, n_lev, n_big, output_dt, tick_total, out_ticks, base)


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
    step_error: float

    @property
    def beta(self) -> float:
        """Newmark β = (γ + 1/2)² / 4."""
        return 0.25 * (self.gamma + 0.5) ** 2

    @classmethod
    def checked(cls, solver: Solver, omega) -> _Settings:
        ratio = solver.contact_stiffness_ratio
        return cls(
            omega=_check_scalar("omega", omega),
            gamma=_check_scalar("gamma", solver.gamma, 0.5, 1.0),
            max_newton=_check.integer("max_newton", solver.max_newton, lo=0),
            max_augment=_check.integer("max_augment", solver.max_augment, lo=0),
            grow_after=_check.integer("grow_after", solver.grow_after, lo=1),
            newton_tol=_check_scalar("newton_tol", solver.newton_tol, 0.0, lo_open=True),
            augment_boost=_check_scalar("augment_boost", solver.augment_boost, 0.0, 1.0),
            augment_strict=bool(solver.augment_strict),
            gap_jump=_check_scalar("gap_jump", solver.gap_jump, 0.0, lo_open=True),
            contact_stiffness_ratio=None if ratio is None else _check_scalar(
                "contact_stiffness_ratio", ratio, 0.0, lo_open=True),
            episode_capacity=_check.integer("episode_capacity", solver.episode_capacity,
                                            lo=1),
            step_error=0.0 if solver.step_error is None else _check_scalar(
                "step_error", solver.step_error, 0.0, lo_open=True,
                allowed="finite and > 0 (relative), or None"),
        )


def _checked_gap_ramp(gap_ramp, elements) -> list:
    """Each element's gap ramp ``(t_ramp, gap at t = 0)``, or None (no ramp, or a kind
    without a gap)."""
    gaps = np.array([getattr(el, "gap", np.nan) for el in elements], dtype=np.float64)
    if gap_ramp is None:
        return [None] * len(elements)
    t_ramp = _check_scalar("gap_ramp[0] (t_ramp)", gap_ramp[0], 0.0)
    g_start = np.broadcast_to(np.asarray(gap_ramp[1], dtype=np.float64),
                              (len(elements),)).copy()
    has_gap = np.isfinite(gaps)
    if not np.all(np.isfinite(g_start[has_gap])) or np.any(g_start[has_gap] < gaps[has_gap]):
        raise _bad("gap_ramp[1] (g_start)", gap_ramp[1], ">= every element's gap g0, finite")
    if t_ramp == 0:     # no ramp: the elements start at their gaps
        return [None] * len(elements)
    return [(t_ramp, float(g)) if ok else None for g, ok in zip(g_start, has_gap, strict=True)]


# --------------------------------------------------------------------------------------------
# set-up: the state at t = 0, the operators of each step size
# --------------------------------------------------------------------------------------------
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


def b_matrix(packed: Sequence[Packed], n: int) -> np.ndarray:
    """Dense B (m, n) of the elements' local coordinates ``x = B q``: row r of an element is
    ``Σ_c T[r, c] (q[plus_c] - q[minus_c])``."""
    m = sum(p.rows.shape[0] for p in packed)
    B = np.zeros((m, n))
    r0 = 0
    for p in packed:
        k = p.rows.shape[0]
        for r in range(k):
            for c in range(k):
                B[r0 + r, p.rows[c, 0]] += p.tmat[r, c]
                if p.rows[c, 1] >= 0:
                    B[r0 + r, p.rows[c, 1]] -= p.tmat[r, c]
        r0 += k
    return B


class _Operators(NamedTuple):
    """The step operators of every step level (:func:`_level_operators`)."""

    lu: list            # K_eff's SuperLU factors per level (sparse; empty for dense)
    kernel: Factors     # as the kernel reads them
    lev_req: np.ndarray  # (n_e,) the smallest level each element may be engaged at
    aug_k: np.ndarray   # (n_lev, n_e) the multiplier update stiffness (N/m)


def _level_operators(M, C, K, B, elements, grid: _TimeGrid, settings: _Settings,
                     contact_stiffness_ratio: float | None, dense: bool) -> _Operators:
    """Per step level k (h = dt / 2^k): the factors of K_eff, ``s_mat`` (n_lev, m, n) =
    (K_eff^-1 Bᵀ)ᵀ, ``w_mat`` (n_lev, m, m) = B K_eff^-1 Bᵀ, the smallest level each
    element may be engaged at (``lev_req``, by its step requirement; None ratio: no
    criterion), the multiplier update stiffness ``aug_k`` (n_lev, n_e), the factors packed
    for the kernel (first axis the level) and, ``dense``, the transposed inverses ``inv_t``
    (n_lev, n, n) (else (n_lev, 0, 0))."""
    dt, n_lev = grid.dt_max, grid.n_lev
    gamma, beta_nm, augment_boost = settings.gamma, settings.beta, settings.augment_boost
    n = M.shape[0]
    m = B.shape[0]
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
        if m:
            S = inv_t[k].T @ B.T if dense else fac.splu.solve(np.ascontiguousarray(B.T))
            s_list.append(np.ascontiguousarray(S.T))
            w_list.append(B @ S)
        else:
            s_list.append(np.zeros((0, n)))
            w_list.append(np.zeros((0, 0)))
    ne = len(elements)
    starts = np.cumsum([0] + [el.kernel.N_LOCAL for el in elements])

    def block(k, e):
        return w_list[k][starts[e]:starts[e + 1], starts[e]:starts[e + 1]]

    # the step requirement: for contacts k_N W_ee (= (ω_c h)^2 / 4 for a lumped mass) <= ratio
    lev_req = np.zeros(ne, np.int64)
    if ne and contact_stiffness_ratio is not None:
        for e, element in enumerate(elements):
            lev_req[e] = top
            for k in range(n_lev):
                if element.stiffness_ratio(block(k, e)) <= contact_stiffness_ratio:
                    lev_req[e] = k
                    break
    # an impact element is engaged at the base step or shorter ones: long steps are for
    # open stretches only
    for e, element in enumerate(elements):
        if impacts(element):
            lev_req[e] = max(lev_req[e], grid.base)
    # multiplier update stiffness: eq. (2) uses k_N; with the step's dynamic stiffness at the
    # contact, 1 / W_ee, far above k_N (small steps) that converges by a factor
    # 1 / (1 + k_N W_ee) per update only. We add 0.9 / W_ee (the Newton update of the
    # multiplier for an isolated contact, under-relaxed): same fixed point, a few updates.
    aug_k = np.zeros((n_lev, ne))
    for k in range(n_lev):
        for e, element in enumerate(elements):
            aug_k[k, e] = element.multiplier_stiffness(block(k, e), augment_boost)
    s_mat = np.ascontiguousarray(np.stack(s_list))
    w_mat = np.ascontiguousarray(np.stack(w_list))
    return _Operators(factors, Factors(*_pack_factors(factors, n), s_mat, w_mat, inv_t),
                      lev_req, aug_k)


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
# the kernel's arrays (rubdiag._kernels.newmark's bundles, rubdiag._kernels.records)
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
        tick_dt = grid.tick_dt
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


def impacts(element) -> bool:
    """Whether ``element`` can close on impact (a contact, a pedestal's seat): its
    description's ``impacts`` (True when it does not say: the safe side)."""
    return bool(getattr(element, "impacts", True))


def _element_bundle(packed: Sequence[Packed], lev_req, aug_k, elements) -> Elements:
    """The elements as the kernel reads them (:data:`~rubdiag._kernels.newmark.Elements`)."""
    ne = len(packed)
    el = np.zeros(ne, records.ELEMENT)
    m = sum(p.rows.shape[0] for p in packed)
    rmap = np.zeros((m, 3), np.int64)
    tmat = np.zeros((m, N_LOCAL_MAX))
    par = np.zeros((ne, max((p.par.size for p in packed), default=0)))
    r0 = 0
    for e, p in enumerate(packed):
        k = p.rows.shape[0]
        el[e]["kind"], el[e]["row"], el[e]["n"] = p.kind, r0, k
        el[e]["aug"], el[e]["eps"], el[e]["lev_req"] = int(p.augmented), p.eps, lev_req[e]
        el[e]["impact"] = impacts(elements[e])
        rmap[r0:r0 + k, :2] = p.rows
        rmap[r0:r0 + k, 2] = e
        tmat[r0:r0 + k, :k] = p.tmat
        par[e, : p.par.size] = p.par
        r0 += k
    return Elements(el, rmap, tmat, par, np.ascontiguousarray(aug_k))


def kernel_for(elements) -> Kernel:
    """The kernel whose element dispatch knows every element's kind: the built-in (cached)
    one, or one extended by kinds defined outside rubdiag (:mod:`rubdiag._kernels.extend`)."""
    extra = []
    for element in elements:
        module = type(element).kernel
        if KINDS.get(module.KIND) is module or module in extra:
            continue
        extra.append(module)
    return kernel_with(tuple(sorted(extra, key=lambda m: m.KIND)))


def _packed(elements, omega: float, ramps) -> list[Packed]:
    return [el.pack(omega, ramp) for el, ramp in zip(elements, ramps, strict=True)]


def _state(M, K, q0, v0, B, bundle: Elements, packed, at_rest,
           omega: float = 0.0) -> tuple[State, float]:
    """The kernel's state at t = 0 (copies: the inputs stay as they are) — the elements'
    laws evaluated at q0 and the shaft speed ``omega`` (rad/s), committed — and the
    elements' elastic energy there. The local acceleration is set with a0
    (:func:`_with_acceleration`). ``at_rest``: the kernel's
    (:func:`rubdiag._kernels.elements.at_rest`, or the one of an extended kernel)."""
    ne = len(packed)
    n_state = max((p.state.size for p in packed), default=0)
    es = np.zeros((2, ne, n_state))
    for e, p in enumerate(packed):
        es[0, e, : p.state.size] = p.state
        es[1, e, : p.state.size] = p.state
    xs = np.zeros((3, B.shape[0]))
    xs[records.X_N] = B @ q0
    xs[records.XV_N] = B @ v0
    track = np.zeros(ne, records.TRACK)
    prog = np.zeros(1, records.PROGRESS)       # h = 0: at rest, where ẋ = ẋ_n
    prog["cvv"] = 1.0
    prog["omega"] = omega                      # a journal bearing's film turns at it
    wc = np.zeros((WC_SIZE, B.shape[0]))
    wc[records.D_NEW] = xs[records.X_N]
    e_c0 = at_rest(bundle.el, wc, xs, bundle.par, es, track, np.zeros(ne, records.TRIAL), prog,
                   np.zeros((B.shape[0], N_LOCAL_MAX)))
    pc = wc[records.P_NEW].copy()
    prog["e_contact"] = e_c0
    prog["fail_time"] = np.nan
    prog["fail_element"] = -1
    state = State(q0.copy(), v0.copy(), np.zeros_like(q0), np.ascontiguousarray(M @ v0),
                  np.ascontiguousarray(K @ q0), pc, xs, es, track, prog)
    return state, e_c0


def _with_acceleration(state: State, a0, B) -> None:
    state.a[:] = a0
    state.xs[records.XA_N] = B @ a0


def _outputs(grid: _TimeGrid, ne: int, record_dofs, sensor_dofs, recovery) -> Outputs:
    """The recorded samples and the sensor stream, zeros, with the recovery maps."""
    n_out, n_sen = grid.n_out, grid.n_sensor_samples(sensor_dofs.size)
    empty = np.zeros((0, 0))
    shape = (n_sen, sensor_dofs.size)     # np.zeros, not zeros_like: pages untouched
    return Outputs(
        record_dofs, np.zeros((n_out, record_dofs.size)), np.zeros((n_out, ne), records.SAMPLE),
        np.zeros(n_out, records.ENERGY), sensor_dofs, np.zeros(shape), np.zeros(shape),
        np.zeros(shape),
        empty if recovery is None else np.ascontiguousarray(recovery[record_dofs].T),
        empty if recovery is None else np.ascontiguousarray(recovery[sensor_dofs].T))


def _logs(ne: int, n_lev: int, episode_capacity: int) -> Logs:
    """Empty logs (the segment log starts at four times the episode capacity)."""
    return Logs(np.zeros(episode_capacity, records.EPISODE),
                np.zeros(4 * episode_capacity, records.SEGMENT),
                np.zeros(256), np.zeros(256, np.int64), np.zeros(ne, records.STATS),
                np.zeros(n_lev, np.int64))


def _grown(logs: Logs, prog, ne: int) -> Logs:
    """``logs`` with room for another step (:data:`STATUS_LOG_FULL`): each log that could
    overflow doubled (the episode log plus n_e rows)."""
    ep, sg, lv_t, lv_l = logs.ep, logs.sg, logs.lv_t, logs.lv_l
    pr = prog[0]
    if pr["n_episodes"] + ne > ep.shape[0]:
        ep = np.concatenate([ep, np.zeros(ep.shape[0] + ne, records.EPISODE)])
    if pr["n_segments"] + ne > sg.shape[0]:
        sg = np.concatenate([sg, np.zeros_like(sg)])
    if pr["n_level_changes"] + 2 > lv_t.shape[0]:
        lv_t = np.concatenate([lv_t, np.zeros(lv_t.shape[0])])
        lv_l = np.concatenate([lv_l, np.zeros(lv_l.shape[0], np.int64)])
    return logs._replace(ep=ep, sg=sg, lv_t=lv_t, lv_l=lv_l)


def _work(n: int, m: int, ne: int, profile: bool) -> Work:
    """Work arrays, and the cycle counters when profiling (else empty)."""
    return Work(np.zeros((WN_SIZE, n)), np.zeros((WC_SIZE, m)), np.zeros((m, m)),
                np.zeros((m, N_LOCAL_MAX)), np.zeros(5 * m, np.int64),
                np.zeros(ne, records.TRIAL),
                np.zeros(len(PROFILE_SECTIONS) if profile else 0, np.int64))


def _parameters(grid: _TimeGrid, settings: _Settings, fixed_step: bool) -> np.ndarray:
    """The kernel's ``run`` record (the end tick is set per call)."""
    run = np.zeros(1, records.RUN)
    run["dt"] = grid.dt_max
    run["base"] = grid.base
    run["step_error"] = settings.step_error if grid.base else 0.0
    run["tick_stop"] = grid.tick_total
    run["newton_tol"] = settings.newton_tol
    run["gap_jump"] = settings.gap_jump
    # the boosted update's landing point in the band (see augment_boost)
    run["aug_shift"] = 0.98 if settings.augment_boost > 0 else 0.0
    run["beta"] = settings.beta
    run["gamma"] = settings.gamma
    run["n_lev"] = grid.n_lev
    run["fixed"] = int(bool(fixed_step))
    run["grow_after"] = settings.grow_after
    run["max_newton"] = settings.max_newton
    run["max_aug"] = settings.max_augment
    run["out_ticks"] = grid.out_ticks
    run["aug_strict"] = int(settings.augment_strict)
    run["sen_ticks"] = grid.sen_ticks
    return run


# --------------------------------------------------------------------------------------------
# the public entry point
# --------------------------------------------------------------------------------------------
def simulate_system(system, *args, **options) -> SystemResult:
    """Integrate a linear system with nonlinear elements from its start state.

    ``simulate_system(system, elements, grid, outputs=Recording(), *, solver=Solver(),
    gap_ramp=None)`` (:mod:`rubdiag.simulation._descriptions`).

    The old call keeps working: ``simulate_system(M, C, K, force, contacts, q0, v0, *,
    duration, dt, ...)`` with every field of the four objects as a keyword of the same name
    (:func:`~rubdiag.simulation._descriptions.legacy_call`).

    Parameters
    ----------
    system : LinearSystem
        ``M q'' + C q' + K q = f(t)``, its start state and the shaft's speed.
    *args
        ``elements``, ``grid`` and optionally ``outputs``, in this order:

        * ``elements`` (:class:`Contacts`, a sequence of element descriptions, or None): the
          nonlinear elements (:mod:`rubdiag.simulation._elements`);
        * ``grid`` (``TimeGrid``): the run's length and steps;
        * ``outputs`` (``Recording``): what is recorded and reported.
    **options
        ``solver`` (``Solver``): the numerical settings; ``gap_ramp`` ((t_ramp, g_start),
        optional): ramp every element's gap linearly from ``g_start`` (m; scalar or one per
        element, >= its gap) at t = 0 down to its gap at ``t_ramp`` (s), so that a linear
        orbit larger than the gap does not start deep inside the casing (elements without a
        gap ignore it).

    Returns
    -------
    SystemResult
        The samples, contact statistics, event log and outcome of the run.
    """
    if isinstance(system, LinearSystem):
        return _simulate(system, *args, **options)
    return _simulate(*legacy_call(system, *args, **options))


def _simulate(system: LinearSystem, elements, grid: TimeGrid, outputs: Recording | None = None,
              solver: Solver | None = None, gap_ramp=None) -> SystemResult:
    """:func:`simulate_system` on described objects."""
    ensure_fresh_cache()    # before the first kernel call of this process
    t_start = time.perf_counter()
    outputs = Recording() if outputs is None else outputs
    solver = Solver() if solver is None else solver
    q0, v0 = system.start()
    M, C, K, force, elements, q0, v0 = _checked_system(system.M, system.C, system.K,
                                                       system.force, elements, q0, v0)
    n, ne = M.shape[0], len(elements)
    ticks = _time_grid(grid.duration, grid.dt, grid.dt_min, grid.fixed_step, grid.output_dt,
                       grid.dt_max)
    speed_profile = system.speed_profile
    rot, stretches, G = _checked_profile(speed_profile, system.speed_tolerance,
                                         system.gyroscopic, force, n, ticks)
    omega = system.omega
    if stretches:
        omega = stretches[0][1]
        C_base, C = C, (C + omega * G).tocsr()
    dense = _check.choice("linear_solver", solver.linear_solver, ("sparse", "dense")) == "dense"
    recovery, record_dofs, sensor_dofs = _checked_records(ticks, n, outputs.record_dofs,
                                                          outputs.sensor_dofs, system.recovery)
    settings = _Settings.checked(solver, omega)
    if ticks.base and not settings.step_error:
        raise _bad("dt_max", ticks.dt_max, f"dt = {ticks.dt:g} s without a step_error")
    ramps = _checked_gap_ramp(gap_ramp, elements)
    fixed_step = grid.fixed_step
    kernel = kernel_for(elements)

    # the elements at t = 0, the operators of each step size, the kernel's arrays
    packed = _packed(elements, settings.omega, ramps)
    B = b_matrix(packed, n)
    ratio = None if fixed_step else settings.contact_stiffness_ratio
    ops = _level_operators(M, C, K, B, elements, ticks, settings, ratio, dense)
    bundle = _element_bundle(packed, ops.lev_req, ops.aug_k, elements)
    state, _ = _state(M, K, q0, v0, B, bundle, packed, kernel.at_rest, settings.omega)
    a0 = _initial_acceleration(M, C, K, load_vector(force, speed_profile, 0.0, n), B, state.pc,
                               q0, v0, system.a0)
    _with_acceleration(state, a0, B)
    state.prog["level"] = ticks.base       # the first step is the base step
    recorded = _outputs(ticks, ne, record_dofs, sensor_dofs, recovery)
    run = _parameters(ticks, settings, fixed_step)
    linear = _linear(M, C, K, dense)
    run["coupled"] = _coupled(linear.m_dense, linear.k_dense)
    run["kinematics"] = any(getattr(type(el).kernel, "KINEMATICS", False) for el in elements)
    k_force = kernel_force(force, rot)
    if not stretches:   # constant speed: the shaft's angle Ω t for the element laws
        k_force.rot[0, 1] = settings.omega
    arrays = (linear, ops.kernel, k_force, bundle, run, state, recorded)
    logs = _logs(ne, ticks.n_lev, settings.episode_capacity)
    work = _work(n, B.shape[0], ne, outputs.profile)
    t_setup = time.perf_counter() - t_start

    schedule = None
    if stretches:
        def operators(omega_ref):    # the step operators with Ω_ref G, for the next stretch
            C_ref = (C_base + omega_ref * G).tocsr()
            new = _level_operators(M, C_ref, K, B, elements, ticks, settings, ratio, dense)
            return (_linear(M, C_ref, K, dense), new.kernel,
                    _element_bundle(_packed(elements, omega_ref, ramps), new.lev_req,
                                    new.aug_k, elements))

        schedule = _Schedule(stretches, ticks, operators)
    code, logs, t_kernel = _integrate(kernel.newmark_contact, arrays, logs, work, ticks,
                                      outputs.progress, schedule)
    result = _package(code, ticks, state, recorded, logs)
    if recovery is not None:    # the final state in physical DOFs, like the records
        q, v, a = state.q, state.v, state.a
        result = dataclasses.replace(result, q_final=recovery @ q, v_final=recovery @ v,
                                     a_final=recovery @ a)
    if outputs.profile:
        result.extra["profile_cycles"] = dict(zip(PROFILE_SECTIONS, work.prof.tolist(),
                                                  strict=True))
    result.extra.update(
        setup_seconds=t_setup, kernel_seconds=t_kernel, contact_level_required=ops.lev_req,
        augment_pending=int(state.prog[0]["aug_pending"]),
        lu_nnz=[f.nnz for f in ops.lu], lu_ordering=[f.ordering for f in ops.lu],
    )
    if schedule is not None:
        result.extra["speed_stretches"] = schedule.used
    if result.status != 0 and outputs.raise_on_failure:
        raise SimulationDiverged(result.message, result)
    return result


# --------------------------------------------------------------------------------------------
# running the kernel, and the result
# --------------------------------------------------------------------------------------------
def _integrate(kernel, arrays: tuple, logs: Logs, work: Work, grid: _TimeGrid, progress,
               schedule: _Schedule | None = None):
    """Run ``kernel`` (:func:`~rubdiag._kernels.newmark.newmark_contact`) to the end of the run
    (or a failure): in chunks of about 1 % of the run when there is a ``progress`` to call,
    growing a log whenever one is full, and with a speed profile's ``schedule`` stretch by
    stretch (new step operators at each). Returns the kernel's status code, the logs and the
    kernel's wall time (s)."""
    linear, factors, force, elements, run, state, outputs = arrays
    prog = state.prog
    n_chunks = 100 if progress is not None else 1
    chunk = max(np.int64(1), grid.tick_total // n_chunks)
    t_kernel = 0.0
    while True:
        end = min(grid.tick_total, prog[0]["tick"] + chunk)
        if schedule is not None:
            ops = schedule.advance(int(prog[0]["tick"]))
            if ops is not None:
                linear, factors, elements = ops
            end = min(end, schedule.tick_end())
            run["tick_stop"] = schedule.tick_end()
        run["tick_end"] = end
        tk = time.perf_counter()
        code = kernel(linear, factors, force, elements, run, state, outputs, logs, work)
        t_kernel += time.perf_counter() - tk
        if code == STATUS_LOG_FULL:
            logs = _grown(logs, prog, elements.el.shape[0])
            continue
        if code != STATUS_DONE:
            return code, logs, t_kernel
        if progress is not None:
            progress(float(prog[0]["tick"]) * grid.tick_dt, grid.n_big * grid.dt)
        if prog[0]["tick"] >= grid.tick_total:
            return code, logs, t_kernel


#: the result's arrays from the kernel's records: per sample and element, per sample (the
#: energy ledger), per element (totals and maxima)
_SAMPLE_FIELDS = {"contact_fn": "fn", "contact_ft": "ft", "contact_gap": "gap",
                  "contact_slip": "slip"}
_LEDGER_FIELDS = {"work_external": "w_ext", "work_drive": "w_drive",
                  "dissipated_viscous": "d_visc", "dissipated_friction": "d_fric",
                  "contact_algorithmic": "d_num", "kinetic": "kinetic", "strain": "strain",
                  "contact_elastic": "contact"}
_TOTAL_FIELDS = {"time_in_status": "time", "normal_impulse": "fn_impulse",
                 "tangential_impulse": "ft_impulse", "max_normal_force": "max_fn",
                 "max_tangential_force": "max_ft", "max_penetration": "max_penetration"}


def _package(code, grid: _TimeGrid, state: State, outputs: Outputs, logs: Logs) -> SystemResult:
    """The kernel's arrays as a :class:`SystemResult`, cut to what the run reached."""
    pr = state.prog[0]
    tick = int(pr["tick"])
    t_final = tick * grid.tick_dt
    n_written = tick // int(grid.out_ticks) + 1
    n_sen = tick // int(grid.sen_ticks) + 1 if outputs.sen_dof.size else 0
    episodes, segments = _episode_logs(state, logs, t_final)
    status, message = _status(code, pr, t_final, grid.dt_min)
    nl = int(pr["n_level_changes"])
    sl = slice(0, n_written)
    en = outputs.en[sl]
    el = outputs.el[sl]
    columns = {name: np.ascontiguousarray(records_[field])
               for records_, fields in ((el, _SAMPLE_FIELDS), (en, _LEDGER_FIELDS),
                                        (logs.stats, _TOTAL_FIELDS))
               for name, field in fields.items()}
    return SystemResult(
        t=np.arange(n_written) * grid.output_dt,
        record_dofs=outputs.rec_dof,
        q=outputs.q[sl],
        contact_status=np.ascontiguousarray(el["status"], dtype=np.int8),
        **columns,
        episodes=episodes,
        status_segments=segments,
        max_cone_excess=float(pr["cone_excess"]),
        dt=grid.dt,
        dt_min=grid.tick_dt,
        output_dt=grid.output_dt,
        dt_levels=grid.dt_max / 2.0 ** np.arange(grid.n_lev),
        steps_per_level=logs.lvl_count.copy(),
        level_change_t=logs.lv_t[:nl].copy(),
        level_change_level=logs.lv_l[:nl].copy(),
        n_steps=int(pr["n_accepted"]),
        n_rejected_newton=int(pr["n_rej_newton"]),
        n_rejected_abrupt=int(pr["n_rej_abrupt"]),
        n_abrupt_at_min=int(pr["n_abrupt_at_min"]),
        n_rejected_error=int(pr["n_rej_error"]),
        newton_iterations=int(pr["newton_total"]),
        newton_iterations_max=int(pr["newton_max"]),
        augment_iterations=int(pr["aug_total"]),
        augment_iterations_max=int(pr["aug_max"]),
        t_final=t_final,
        q_final=state.q.copy(),
        v_final=state.v.copy(),
        a_final=state.a.copy(),
        status=status,
        message=message,
        failure_time=float(pr["fail_time"]) if status else float("nan"),
        failure_element=int(pr["fail_element"]) + 1 if status else 0,  # 0: none
        sensor_dofs=outputs.sen_dof,
        sensor_dt=float(grid.tick_dt * int(grid.sen_ticks)),
        sensor_q=outputs.sq[:n_sen],
        sensor_v=outputs.sv[:n_sen],
        sensor_a=outputs.sa[:n_sen],
    )


def _episode_logs(state: State, logs: Logs, t_final: float):
    """The episode and status-segment logs: the ended ones as logged, then those still
    open at ``t_final`` (from each element's track)."""
    pr = state.prog[0]
    track = state.track
    ep = logs.ep[: int(pr["n_episodes"])]
    sg = logs.sg[: int(pr["n_segments"])]
    open_el = np.flatnonzero(track["status"] != OPEN)
    current = track[open_el]

    def ended_then_open(ended, now):
        return np.concatenate([ended, now])

    still_open = np.full(open_el.size, t_final)
    episodes = EpisodeLog(
        element=ended_then_open(ep["element"], open_el) + 1,  # numbered from 1
        t_start=ended_then_open(ep["t_start"], current["ep_start"]),
        t_end=np.concatenate([ep["t_end"], still_open]),
        n_steps=ended_then_open(ep["steps"], current["ep_steps"]),
        peak_normal_force=ended_then_open(ep["peak_fn"], current["ep_peak_fn"]),
        n_slide_entries=ended_then_open(ep["slide_entries"], current["ep_slide_entries"]),
        n_stick_entries=ended_then_open(ep["stick_entries"], current["ep_stick_entries"]),
        slide_time=ended_then_open(ep["slide_time"], current["ep_slide_time"]),
        stick_time=ended_then_open(ep["stick_time"], current["ep_stick_time"]),
        slide_impulse=ended_then_open(ep["slide_impulse"], current["ep_slide_impulse"]),
        stick_impulse=ended_then_open(ep["stick_impulse"], current["ep_stick_impulse"]),
        complete=np.concatenate([np.ones(ep.size, bool), np.zeros(open_el.size, bool)]),
    )
    segments = StatusLog(
        element=ended_then_open(sg["element"], open_el) + 1,
        status=ended_then_open(sg["status"], current["status"]).astype(np.int8),
        t_start=ended_then_open(sg["t_start"], current["seg_start"]),
        t_end=np.concatenate([sg["t_end"], still_open]),
    )
    return episodes, segments


def _status(code, pr, t_final: float, dt_min: float) -> tuple[int, str]:
    """The result's status (0 done, 1 no convergence, 2 non-finite) and its message."""
    status = {STATUS_DONE: 0, STATUS_NO_CONVERGENCE: 1, STATUS_NONFINITE: 2}[code]
    fail_t = float(pr["fail_time"])
    fail_e = int(pr["fail_element"]) + 1
    if status == 0:
        return status, f"Reached t = {t_final:.6g} s in {int(pr['n_accepted'])} steps."
    if status == 1:
        why = {NEWTON_FAILED: "Newton iterations exhausted",
               AUGMENT_FAILED: "augmentation did not reach eps",
               SINGULAR: "singular contact Jacobian"}.get(int(pr["fail_code"]), "unknown")
        return status, (
            f"Contact iteration did not converge ({why}) at t = {fail_t:.9g} s, contact element "
            f"{fail_e}, even at the smallest step {dt_min:.3g} s; results kept up to "
            f"t = {t_final:.9g} s."
        )
    where = f"contact element {fail_e}" if fail_e > 0 else "the structure"
    return status, (f"State became non-finite at t = {fail_t:.9g} s ({where}); results kept "
                    f"up to t = {t_final:.9g} s.")
