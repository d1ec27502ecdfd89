"""The simulator's nonlinear elements as descriptions: one frozen dataclass per kind.

Each kind of nonlinear element the integrator knows (its law is a kernel module behind the
seam of :mod:`rubdiag._kernels.elements`) has one description here: a frozen dataclass in SI
units, validated when it is made, which packs itself into what the kernel reads
(:meth:`pack`) and states its step requirement. :class:`PointContact` and
:class:`AnnularContact` are today's contact elements; :class:`rubdiag.simulation.Contacts`
keeps describing many of them as arrays and converts to these.

Adding a kind (the kernel side is in :mod:`rubdiag._kernels.elements`): a frozen dataclass
with

* ``kernel`` (ClassVar): the kernel module (``KIND``, ``N_LOCAL``, ``law``);
* ``pack(omega, ramp)`` → :class:`Packed`: its local rows (the DOF pair whose relative
  displacement each row measures), the square block T of ``x = T u``, its parameter row in
  the order its kernel module names, its state at rest, and whether it carries an
  augmented-Lagrangian multiplier (``omega`` the shaft speed, rad/s; ``ramp`` a gap ramp
  ``(t_ramp, gap_start)`` or None, for kinds with a gap);
* ``stiffness_ratio(w)`` → float: the step requirement. ``w`` is the element's block of
  ``B K_eff⁻¹ Bᵀ`` at a step size; an engaged element allows that step when the ratio is at
  most the run's ``contact_stiffness_ratio`` (0: any step);
* ``multiplier_stiffness(w, boost)`` → the multiplier update stiffness (N/m; 0 without one);
* ``impacts`` (ClassVar, default True): whether it can close on impact; such an element is
  engaged only at the base step dt or shorter ones, and steps longer than dt
  (``TimeGrid.dt_max``) keep it open (False for a smooth law: a film, a crack);
* ``dofs()`` → every DOF it acts on (checked against the system; a reduced model keeps them
  physical: :func:`rubdiag.reduce.boundary_dofs` lists those of the rig's elements).

``tests/simulation/test_element_seam.py`` (with ``tests/ground_spring_kind.py``) adds a linear
spring and dashpot to ground this way, outside the package, and checks them against the same
spring in K and dashpot in C.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from rubdiag import _check
from rubdiag._kernels import annular_contact, contact_books, point_contact

__all__ = ["AnnularContact", "Packed", "PointContact"]


class Packed(NamedTuple):
    """One element as the kernel reads it (:mod:`rubdiag._kernels.elements`)."""

    kind: int
    rows: np.ndarray        # (n, 2) int: plus and minus DOF of each local row (-1: ground)
    tmat: np.ndarray        # (n, n): x = T u
    par: np.ndarray         # its parameter row
    state: np.ndarray       # its state at rest
    augmented: bool
    eps: float              # the multiplier's band (m), augmented only


def _pair(name: str, value, ground: bool = False) -> tuple:
    idx = _check.indices(name, value).reshape(-1)
    if idx.size != 2:
        raise ValueError(f"{name} = {idx.tolist()} (allowed: two DOF indices, y and z)")
    lo = -1 if ground else 0
    if np.any(idx < lo):
        raise _check.out_of_range(name, idx.tolist(),
                                  ">= 0, or -1 (ground)" if ground else ">= 0")
    return tuple(int(i) for i in idx)


def _unit(name: str, value) -> tuple:
    v = np.asarray(value, dtype=np.float64).reshape(-1)
    if v.size != 2 or not np.all(np.isfinite(v)) or abs(np.hypot(*v) - 1.0) > 1e-9:
        raise _check.out_of_range(name, v.tolist(), "a finite unit vector (y, z)")
    return (float(v[0]), float(v[1]))


@dataclass(frozen=True, kw_only=True)
class _Contact:
    """What both contact kinds have (SI): stiffnesses (``k_t`` None: ``k_n``), friction,
    the augmented Lagrangian."""

    k_n: float
    k_t: float | None = None
    mu: float = 0.3
    augmented: bool = False
    eps: float = 20e-6

    def _check_law(self):
        name = type(self).__name__
        if self.k_t is None:
            object.__setattr__(self, "k_t", self.k_n)
        object.__setattr__(self, "augmented", bool(self.augmented))
        for field in ("k_n", "k_t"):
            _check.number(f"{name}.{field}", getattr(self, field), lo=0.0, lo_open=True,
                          allowed="finite and > 0 N/m")
        _check.number(f"{name}.mu", self.mu, lo=0.0, allowed="finite and >= 0")
        if self.augmented:
            _check.number(f"{name}.eps", self.eps, lo=0.0, lo_open=True,
                          allowed="finite and > 0 m when augmentation is on")

    def _parameters(self, gap: float, speed: float, ramp, centre=(0.0, 0.0)) -> np.ndarray:
        t_ramp, gap_start = (0.0, gap) if ramp is None else ramp
        return contact_books.parameters(gap=gap, gap_start=gap_start, t_ramp=t_ramp,
                                        k_n=self.k_n, k_t=self.k_t, mu=self.mu, speed=speed,
                                        centre_y=centre[0], centre_z=centre[1])

    def multiplier_stiffness(self, w: np.ndarray, boost: float) -> float:
        """Eq. (2)'s k_N plus ``boost / W_ee`` (``W_ee`` the larger diagonal of ``w``): the
        Newton update of an isolated contact's multiplier, under-relaxed by ``boost``."""
        wee = max(w[0, 0], w[1, 1])
        return self.k_n + (boost / wee if wee > 0 else 0.0)

    def dofs(self) -> np.ndarray:
        return np.array([d for d in (*self.dof_a, *self.dof_b) if d >= 0], dtype=np.int64)

    def _rows(self) -> np.ndarray:
        return np.array([[self.dof_a[0], self.dof_b[0]], [self.dof_a[1], self.dof_b[1]]],
                        dtype=np.int64)


@dataclass(frozen=True, kw_only=True)
class PointContact(_Contact):
    """A point–point contact (:mod:`rubdiag._kernels.point_contact`): body a's DOFs
    ``dof_a`` (y, z), body b's ``dof_b`` (-1: ground), the unit normal from a towards b and
    the tangent (orthonormal, fixed), the gap at the coordinates' origin x = 0 (m; negative
    when the origin lies inside the contact: coordinates measured from elsewhere than the
    contact's rest, such as a rig run's gaps set at its static deflection), the normal and
    tangential
    stiffness (N/m), the Coulomb coefficient, and the augmented Lagrangian with its band
    ``eps`` (m)."""

    dof_a: tuple
    dof_b: tuple = (-1, -1)
    normal: tuple
    tangent: tuple
    gap: float

    kernel: ClassVar = point_contact

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "dof_a", _pair("PointContact.dof_a", self.dof_a))
        set_(self, "dof_b", _pair("PointContact.dof_b", self.dof_b, ground=True))
        set_(self, "normal", _unit("PointContact.normal", self.normal))
        set_(self, "tangent", _unit("PointContact.tangent", self.tangent))
        if abs(np.dot(self.normal, self.tangent)) > 1e-9:
            raise _check.out_of_range("PointContact.normal/tangent",
                                      (self.normal, self.tangent), "orthonormal unit vectors")
        _check.number("PointContact.gap", self.gap, allowed="a finite gap (m)")
        self._check_law()

    def pack(self, omega: float, ramp=None) -> Packed:
        tmat = np.array([self.normal, self.tangent])
        return Packed(point_contact.KIND, self._rows(), tmat,
                      self._parameters(self.gap, omega * 0.0, ramp),
                      np.zeros(len(contact_books.STATE)), self.augmented, self.eps)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        """``k_N W_nn``: the normal row only (the tangential stick spring is not resolved:
        at the blade tips of the 412-DOF test system ``k_T W_tt`` is ~14x ``k_N W_nn`` at
        dt = 1e-5 s, and resolving it would cost 4x steps in rub)."""
        return self.k_n * w[0, 0]


@dataclass(frozen=True, kw_only=True)
class AnnularContact(_Contact):
    """A shaft–stator annular clearance (:mod:`rubdiag._kernels.annular_contact`): the shaft
    node's DOFs ``dof_a`` (y, z), the stator's ``dof_b`` (-1: ground), the radial clearance
    (m, >= 0) about ``centre`` (m, the (y, z) of the relative displacement at the clearance's
    centre; default the bearing line), the shaft's surface radius R (m, >= 0: the slip
    includes Ω R), the stiffnesses, the Coulomb coefficient and the augmented Lagrangian."""

    dof_a: tuple
    dof_b: tuple = (-1, -1)
    clearance: float
    radius: float = 0.0
    centre: tuple = (0.0, 0.0)

    kernel: ClassVar = annular_contact

    def __post_init__(self):
        object.__setattr__(self, "dof_a", _pair("AnnularContact.dof_a", self.dof_a))
        object.__setattr__(self, "dof_b", _pair("AnnularContact.dof_b", self.dof_b,
                                                ground=True))
        _check.number("AnnularContact.clearance", self.clearance, lo=0.0, allowed=">= 0 m")
        _check.number("AnnularContact.radius", self.radius, lo=0.0, allowed=">= 0 m")
        centre = np.asarray(self.centre, dtype=np.float64).reshape(-1)
        if centre.size != 2 or not np.all(np.isfinite(centre)):
            raise _check.out_of_range("AnnularContact.centre", self.centre,
                                      "two finite numbers (y, z) in m")
        object.__setattr__(self, "centre", (float(centre[0]), float(centre[1])))
        self._check_law()

    @property
    def gap(self) -> float:
        return self.clearance

    def pack(self, omega: float, ramp=None) -> Packed:
        return Packed(annular_contact.KIND, self._rows(), np.eye(2),
                      self._parameters(self.clearance, omega * self.radius, ramp,
                                       self.centre),
                      np.zeros(len(contact_books.STATE)), self.augmented, self.eps)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        """``k_N max(W_yy, W_zz)``: the normal turns, so both rows."""
        return self.k_n * max(w[0, 0], w[1, 1])
