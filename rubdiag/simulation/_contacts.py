"""Contact elements as arrays: the deprecated :class:`Contacts`.

A run's contacts are element descriptions (:class:`~rubdiag.simulation.PointContact`,
:class:`~rubdiag.simulation.AnnularContact`), one per element, which every kind of nonlinear
element shares (films, cracks, a loose pedestal's seat). ``Contacts`` described point and
annular contacts as arrays over the elements, and was converted to those descriptions;
it is kept for one release and warns when made.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag._deprecation import REMOVED_IN
from rubdiag._kernels.annular_contact import KIND as KIND_ANNULAR
from rubdiag._kernels.point_contact import KIND as KIND_POINT
from rubdiag.simulation._elements import AnnularContact, PointContact
from rubdiag.simulation._kernel_args import b_matrix

__all__ = ["Contacts"]
_FIELDS = ("kind", "dof_a", "dof_b", "normal", "tangent", "gap", "k_n", "k_t", "mu", "radius",
           "augmented", "eps", "centre")
_PAIRS = ("dof_a", "dof_b", "normal", "tangent", "centre")


@dataclass(frozen=True)
class Contacts:
    """Contact elements as arrays over n_c elements (deprecated).

    .. deprecated::
        Describe each contact as a :class:`~rubdiag.simulation.PointContact` or
        :class:`~rubdiag.simulation.AnnularContact` and give :func:`simulate_system` a
        sequence of them; ``Contacts(...).elements()`` converts.

    Parameters
    ----------
    kind : numpy.ndarray
        (n_c,) int: 1 point–point (blade tip / casing node, fixed normal), 2 annular
        shaft–stator clearance (normal along the current radial relative displacement).
    dof_a, dof_b : numpy.ndarray
        (n_c, 2) int: (y, z) DOFs of body a (blade tip / shaft node) and body b (casing /
        stator node); -1 in ``dof_b`` means ground.
    normal, tangent : numpy.ndarray
        (n_c, 2): unit normal from a towards b and tangent, kind 1 only.
    gap : numpy.ndarray
        (n_c,) m: the gap at the coordinates' origin (kind 1) or the radial clearance (kind
        2, >= 0).
    k_n, k_t : numpy.ndarray
        (n_c,) N/m: normal penalty and tangential (stick) stiffness.
    mu : numpy.ndarray
        (n_c,): Coulomb coefficient (>= 0).
    radius : numpy.ndarray
        (n_c,) m: kind 2 the shaft's surface radius; 0 for kind 1.
    augmented : numpy.ndarray
        (n_c,) bool: augmented Lagrangian on.
    eps : numpy.ndarray
        (n_c,) m: its penetration tolerance ε.
    centre : numpy.ndarray or None
        (n_c, 2) m: kind 2 the clearance's centre (y, z) in the relative displacement;
        None: 0.
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
        warnings.warn("rubdiag.simulation.Contacts is deprecated and will be removed in "
                      f"rubdiag {REMOVED_IN}: give simulate_system a sequence of PointContact "
                      "and AnnularContact (Contacts(...).elements() converts)",
                      DeprecationWarning, stacklevel=3)
        if self.centre is None:
            object.__setattr__(self, "centre", np.zeros((np.size(self.kind), 2)))
        for name in _FIELDS:
            dtype = (np.int64 if name in ("kind", "dof_a", "dof_b")
                     else bool if name == "augmented" else np.float64)
            if dtype is np.int64:   # refuse float indices rather than truncate them
                _check.indices(f"contacts.{name}", getattr(self, name))
            arr = np.array(getattr(self, name), dtype=dtype)
            object.__setattr__(self, name, arr.reshape(-1, 2) if name in _PAIRS
                               else arr.reshape(-1))
        for name in _FIELDS:
            if getattr(self, name).shape[0] != self.n_c:
                raise ValueError(f"contacts.{name}: {getattr(self, name).shape[0]} rows, "
                                 f"expected n_c = {self.n_c}")

    @property
    def n_c(self) -> int:
        """The number of elements."""
        return int(self.kind.size)

    def __len__(self) -> int:
        return self.n_c

    @classmethod
    def empty(cls) -> Contacts:
        """No elements."""
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
    def point(cls, dof_a, dof_b, normal, tangent, gap, k_n, *, k_t=None, mu=0.3,
              augmented=False, eps=20e-6) -> Contacts:
        """Point–point elements (kind 1). Scalars broadcast over the elements;
        ``k_t`` defaults to ``k_n``."""
        return cls._broadcast(KIND_POINT, dof_a, dof_b, normal, tangent, gap, k_n, k_t, mu,
                              0.0, augmented, eps)

    @classmethod
    def annular(cls, dof_a, clearance, radius, k_n, *, dof_b=(-1, -1), k_t=None, mu=0.3,
                augmented=False, eps=20e-6, centre=(0.0, 0.0)) -> Contacts:
        """Shaft–stator annular clearances (kind 2) at shaft nodes ``dof_a`` (y, z), about
        ``centre`` (m, y and z of the relative displacement; default the bearing line)."""
        # the basis of kind 2 follows the displacement; the fixed one is a placeholder
        return cls._broadcast(KIND_ANNULAR, dof_a, dof_b, (1.0, 0.0), (0.0, 1.0), clearance,
                              k_n, k_t, mu, radius, augmented, eps, centre)

    def __add__(self, other: Contacts) -> Contacts:
        return Contacts(*(np.concatenate([getattr(self, f), getattr(other, f)])
                          for f in _FIELDS))

    def elements(self) -> tuple:
        """The elements one by one, as their kinds' descriptions (:class:`PointContact`,
        :class:`AnnularContact`), in order."""
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
