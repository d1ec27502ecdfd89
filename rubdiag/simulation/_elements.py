"""The simulator's nonlinear elements as descriptions: one frozen dataclass per kind.

Each kind of nonlinear element the integrator knows (its law is a kernel module behind the
seam of :mod:`rubdiag._kernels.elements`) has one description here: a frozen dataclass in SI
units, validated when it is made, which packs itself into what the kernel reads
(:meth:`pack`) and states its step requirement. :class:`PointContact` and
:class:`AnnularContact` are the contact elements (public: ``rubdiag.simulation``); the
deprecated :class:`rubdiag.simulation.Contacts` arrays convert to them.

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

from collections.abc import Iterable
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from rubdiag import _check
from rubdiag._kernels import annular_contact, contact_books, point_contact
from rubdiag._tolerances import ON_LEVEL

__all__ = ["AnnularContact", "Packed", "PointContact", "checked_elements", "gap_ramps", "impacts"]


class Packed(NamedTuple):
    """One element as the kernel reads it (:mod:`rubdiag._kernels.elements`)."""

    kind: int
    rows: np.ndarray        # (n, 2) int: plus and minus DOF of each local row (-1: ground)
    tmat: np.ndarray        # (n, n): x = T u
    par: np.ndarray         # its parameter row
    state: np.ndarray       # its state at rest
    augmented: bool
    eps: float              # the multiplier's band (m), augmented only


def impacts(element) -> bool:
    """Whether ``element`` can close on impact (a contact, a pedestal's seat): its
    description's ``impacts`` (True when it does not say: the safe side)."""
    return bool(getattr(element, "impacts", True))


def checked_elements(elements, n: int) -> tuple:
    """``elements`` (a sequence of element descriptions, or None: none) as a tuple, each
    element's DOFs checked against the system's n."""
    if elements is None:
        return ()
    if isinstance(elements, str) or not isinstance(elements, Iterable):
        raise _check.wrong_type("elements", type(elements).__name__,
                                "a sequence of element descriptions, or None")
    elements = tuple(elements)
    for i, element in enumerate(elements):
        if not callable(getattr(element, "pack", None)):
            raise _check.wrong_type(f"elements[{i}]", type(element).__name__,
                                    "an element description (PointContact, AnnularContact …)")
        dofs = np.asarray(element.dofs())
        if dofs.size and (dofs.min() < 0 or dofs.max() >= n):
            raise _check.out_of_range(f"elements[{i}] DOFs", dofs.tolist(),
                                      f"DOF indices in [0, {n})")
    return elements


def gap_ramps(gap_ramp, elements) -> list:
    """Each element's gap ramp ``(t_ramp, gap at t = 0)``, or None (no ramp, or a kind
    without a gap), from ``gap_ramp = (t_ramp, g_start)`` (s; m, scalar or one per
    element, >= its gap) or None."""
    gaps = np.array([getattr(el, "gap", np.nan) for el in elements], dtype=np.float64)
    if gap_ramp is None:
        return [None] * len(elements)
    t_ramp = _check.number("gap_ramp[0] (t_ramp)", gap_ramp[0], lo=0.0)
    g_start = np.broadcast_to(np.asarray(gap_ramp[1], dtype=np.float64),
                              (len(elements),)).copy()
    has_gap = np.isfinite(gaps)
    if not np.all(np.isfinite(g_start[has_gap])) or np.any(g_start[has_gap] < gaps[has_gap]):
        raise _check.out_of_range("gap_ramp[1] (g_start)", gap_ramp[1],
                                  ">= every element's gap g0, finite")
    if t_ramp == 0:     # no ramp: the elements start at their gaps
        return [None] * len(elements)
    return [(t_ramp, float(g)) if ok else None for g, ok in zip(g_start, has_gap, strict=True)]


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
    if v.size != 2 or not np.all(np.isfinite(v)) or abs(np.hypot(*v) - 1.0) > ON_LEVEL:
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
    """A point–point contact (:mod:`rubdiag._kernels.point_contact`): a blade tip against
    a casing node, along a fixed normal; SI units, checked when made.

    Parameters
    ----------
    dof_a : tuple of int
        Body a's DOFs (y, z): the blade tip.
    dof_b : tuple of int
        Body b's DOFs (y, z): the casing node; (-1, -1): ground.
    normal : tuple of float
        The unit normal from a towards b (y, z).
    tangent : tuple of float
        The unit tangent, orthogonal to ``normal``.
    gap : float
        The gap at the coordinates' origin x = 0 (m): negative when the origin lies inside
        the contact (coordinates measured from elsewhere than the contact's rest, such as
        a rig run's gaps set at its static deflection).
    k_n : float
        The normal penalty stiffness k_N (N/m, > 0).
    k_t : float or None
        The tangential (stick) stiffness k_T (N/m, > 0); None: ``k_n``.
    mu : float
        The Coulomb coefficient (>= 0; 0: frictionless).
    augmented : bool
        The augmented Lagrangian on: the penetration is held within ``eps``.
    eps : float
        The augmented Lagrangian's penetration tolerance ε (m, > 0).
    """

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
        if abs(np.dot(self.normal, self.tangent)) > ON_LEVEL:
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
    """A shaft–stator annular clearance (:mod:`rubdiag._kernels.annular_contact`): a seal
    or a stator ring, whose normal follows the radial relative displacement; SI units,
    checked when made.

    Parameters
    ----------
    dof_a : tuple of int
        The shaft node's DOFs (y, z).
    dof_b : tuple of int
        The stator's DOFs (y, z); (-1, -1): ground.
    clearance : float
        The radial clearance (m, >= 0).
    radius : float
        The shaft's surface radius R (m, >= 0): the slip includes the surface speed Ω R.
    centre : tuple of float
        The clearance's centre (m): the (y, z) of the relative displacement there; (0, 0):
        the bearing line.
    k_n : float
        The normal penalty stiffness k_N (N/m, > 0).
    k_t : float or None
        The tangential (stick) stiffness k_T (N/m, > 0); None: ``k_n``.
    mu : float
        The Coulomb coefficient (>= 0; 0: frictionless).
    augmented : bool
        The augmented Lagrangian on: the penetration is held within ``eps``.
    eps : float
        The augmented Lagrangian's penetration tolerance ε (m, > 0).
    """

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
