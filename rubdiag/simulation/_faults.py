"""The faults a run may carry beside rub (or instead of it): what a plant confuses with rub.

``Run(faults=Faults(...))`` places each fault on the run's rig:

* ``misalignment`` — a misaligned flexible coupling at a shaft node
  (:class:`~rubdiag.simulation.Misalignment`): loads by order (preload, 2×, …);
* ``crack`` — a breathing transverse crack in a shaft element (:class:`Crack`, placed as a
  :class:`~rubdiag.simulation._crack.BreathingCrack` element of the seam).

* ``looseness`` — a bearing pedestal loose on its seat (:class:`Looseness`, placed as a
  :class:`~rubdiag.simulation._pedestal.LoosePedestal` element on the pedestal's DOF): the
  bearing must sit on a pedestal in the rig (:class:`~rubdiag.model._rig.Pedestal`). The
  element takes over the support spring in its direction: the run's linear K loses it
  (:meth:`Faults.removed_stiffness`), while the run starts from the seated (linear) steady
  state, where the element's seat force equals the removed spring's.

A fault's severity is its own parameter (the crack's depth ratio, the coupling's offset and
angle, the pedestal's preload). Faults are part of the run's description only when set, so
a run without them keeps its ids.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rubdiag import _check
from rubdiag.simulation._crack import LAWS, BreathingCrack
from rubdiag.simulation._described import WHEN_SET
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._pedestal import LoosePedestal

__all__ = ["Crack", "Faults", "Looseness"]

#: the directions a pedestal may be loose in
DIRECTIONS = ("y", "z")


@dataclass(frozen=True, kw_only=True)
class Crack:
    """A breathing transverse crack in one shaft element of the rig.

    Placed on a rig it is a :class:`~rubdiag.simulation._crack.BreathingCrack` element
    (:meth:`on`): a stiffness loss that turns with the shaft and opens and closes as it turns.

    Parameters
    ----------
    element : int
        The cracked shaft element (0-based, in axial order; element k joins the rig's k-th
        and (k+1)-th shaft nodes), >= 0.
    depth_ratio : float
        Crack depth over shaft diameter a/D, in (0, 0.5] (linear fracture mechanics).
    position : float
        The crack's distance from the element's first node, as a fraction of the element's
        length, in [0, 1]. Default 0.5: mid-element.
    law : {"mayes", "gasch"}
        The breathing law: Mayes's smooth opening with the shaft angle, or Gasch's hinge,
        open while the bending moment stretches the crack's mouth.
    angle : float
        The crack normal's angle from +y towards +z at shaft angle 0 (rad). Default 0.

    Raises
    ------
    ValueError
        A field out of its range, naming it and the range allowed.

    See Also
    --------
    Faults : The faults of a run, this crack among them.

    Examples
    --------
    A crack a quarter of the diameter deep, mid-way along element 4:

    >>> crack = Crack(element=4, depth_ratio=0.25)
    >>> Faults(crack=crack).names
    ('crack',)

    Deeper than half the diameter is outside the model:

    >>> Crack(element=4, depth_ratio=0.6)
    Traceback (most recent call last):
    ...
    ValueError: crack.depth_ratio = 0.6 is out of range (allowed: in (0, 0.5] ...)
    """

    element: int
    depth_ratio: float
    position: float = 0.5
    law: str = "mayes"
    angle: float = 0.0

    def __post_init__(self):
        _check.integer("crack.element", self.element, lo=0)
        _check.number("crack.depth_ratio", self.depth_ratio, lo=0.0, hi=0.5, lo_open=True,
                      allowed="in (0, 0.5] (linear fracture mechanics: a/D <= 0.5)")
        _check.number("crack.position", self.position, lo=0.0, hi=1.0)
        _check.choice("crack.law", self.law, LAWS)
        _check.number("crack.angle", self.angle, allowed="a finite angle (rad)")

    def on(self, rig) -> BreathingCrack:
        """The crack as an element of ``rig``'s model (its DOFs, geometry and material)."""
        return BreathingCrack.in_rig(rig, self.element, depth_ratio=self.depth_ratio,
                                     position=self.position, law=self.law, angle=self.angle)

    def shaft_nodes(self, rig) -> tuple[int, int]:
        """The shaft nodes at the cracked element's ends."""
        nodes = list(rig.shaft.nodes)
        return nodes[self.element], nodes[self.element + 1]


@dataclass(frozen=True, kw_only=True)
class Looseness:
    """A bearing pedestal loose on its seat: mechanical looseness.

    The seat is on the pedestal's negative side along ``direction``, so the pedestal lifts
    off towards +direction (gravity along -direction presses it on). The seat's stiffness is
    the pedestal's support stiffness in ``direction``; placed on a rig (:meth:`on`), a
    :class:`~rubdiag.simulation._pedestal.LoosePedestal` element takes that spring over.
    The bearing must sit on a pedestal (:class:`~rubdiag.model._rig.Pedestal`).

    Parameters
    ----------
    bearing : int
        The loose bearing, 0-based in ``Rig.bearings``, >= 0.
    preload_n : float
        The dead load pressing the pedestal onto its seat beyond the run's static load
        (N, >= 0; 0 when a :class:`~rubdiag.simulation._static_load.StaticLoad` carries the
        weight). The smaller, the looser.
    clearance_m : float
        A gap between pedestal and seat at rest (m, >= 0); only without a preload.
        Default 0.
    loose_stiffness_n_m : float
        A retaining spring acting once the pedestal has lifted (N/m, >= 0 and at most the
        pedestal's support stiffness, checked when placed on a rig). Default 0: free.
    direction : {"y", "z"}
        The direction the pedestal is loose along.

    Raises
    ------
    ValueError
        A field out of its range, or a clearance together with a preload.

    See Also
    --------
    Faults : The faults of a run, this looseness among them.

    Examples
    --------
    The drive-end pedestal held on its seat by 0.5 N across gravity:

    >>> loose = Looseness(bearing=0, preload_n=0.5, direction="z")
    >>> Faults(looseness=loose).names
    ('looseness',)

    A pedestal is either pressed on (a preload) or clear of its seat, not both:

    >>> Looseness(bearing=0, preload_n=5.0, clearance_m=1e-4)
    Traceback (most recent call last):
    ...
    ValueError: looseness.clearance_m = 0.0001 is out of range (allowed: 0 m when a preload ...)
    """

    bearing: int
    preload_n: float
    clearance_m: float = 0.0
    loose_stiffness_n_m: float = 0.0
    direction: str = "y"

    def __post_init__(self):
        _check.integer("looseness.bearing", self.bearing, lo=0)
        _check.number("looseness.preload_n", self.preload_n, lo=0.0, allowed=">= 0 N")
        _check.number("looseness.clearance_m", self.clearance_m, lo=0.0, allowed=">= 0 m")
        if self.clearance_m > 0.0 and self.preload_n > 0.0:
            raise _check.out_of_range("looseness.clearance_m", self.clearance_m,
                                      "0 m when a preload is given")
        _check.number("looseness.loose_stiffness_n_m", self.loose_stiffness_n_m, lo=0.0,
                      allowed=">= 0 N/m")
        _check.choice("looseness.direction", self.direction, DIRECTIONS)

    def pedestal(self, rig):
        """The loose bearing's :class:`~rubdiag.model._rig.Pedestal` (ValueError without)."""
        if self.bearing >= len(rig.bearings):
            raise _check.out_of_range("faults.looseness.bearing", self.bearing,
                                      f"0 … {len(rig.bearings) - 1} (the rig's bearings)")
        pedestal = rig.bearings[self.bearing].pedestal
        if pedestal is None:
            with_one = [k for k, b in enumerate(rig.bearings) if b.pedestal is not None]
            raise _check.out_of_range("faults.looseness.bearing", self.bearing,
                                      f"a bearing on a pedestal (rig {rig.name!r}: "
                                      f"{with_one or 'none'})")
        return pedestal

    def seat_stiffness(self, rig) -> float:
        """The seat spring (N/m): the pedestal's support stiffness in ``direction``."""
        return getattr(self.pedestal(rig), f"k_{self.direction}_n_m")

    def dof(self, dofs) -> int:
        """The pedestal's DOF along ``direction`` in the DOF map ``dofs``."""
        return dofs.index(f"pedestal {self.bearing}", self.direction)

    def on(self, rig) -> LoosePedestal:
        """The loose pedestal as an element of ``rig``'s model."""
        from rubdiag.assembly import dof_map

        k_s = self.seat_stiffness(rig)
        if self.loose_stiffness_n_m > k_s:
            raise _check.out_of_range("faults.looseness.loose_stiffness_n_m",
                                      self.loose_stiffness_n_m,
                                      f"<= the pedestal's support stiffness {k_s:g} N/m")
        return LoosePedestal(dof=self.dof(dof_map(rig)), stiffness=k_s,
                             preload=self.preload_n, clearance=self.clearance_m,
                             loose_stiffness=self.loose_stiffness_n_m)


@dataclass(frozen=True, kw_only=True)
class Faults:
    """The faults a run carries besides rub (module docstring), each None when absent.

    Parameters
    ----------
    misalignment : Misalignment or None
        A misaligned flexible coupling at a shaft node
        (:class:`~rubdiag.simulation.Misalignment`).
    crack : Crack or None
        A breathing crack in a shaft element.
    looseness : Looseness or None
        A bearing pedestal loose on its seat.

    Raises
    ------
    TypeError
        A field that is neither None nor its fault's class (also a ValueError).

    See Also
    --------
    Run : The run that carries them (``Run(faults=...)``).

    Examples
    --------
    >>> faults = Faults(crack=Crack(element=4, depth_ratio=0.25),
    ...                 looseness=Looseness(bearing=0, preload_n=0.5, direction="z"))
    >>> faults.names
    ('crack', 'looseness')
    """

    misalignment: Misalignment | None = None
    crack: Crack | None = None
    looseness: Looseness | None = field(default=None, metadata=WHEN_SET)   # added later

    def __post_init__(self):
        for name, kind in (("misalignment", Misalignment), ("crack", Crack),
                           ("looseness", Looseness)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, kind):
                raise _check.wrong_type(f"faults.{name}", type(value).__name__,
                                        f"a {kind.__name__} or None")

    @property
    def names(self) -> tuple[str, ...]:
        """The faults present, by name."""
        return tuple(n for n in ("misalignment", "crack", "looseness")
                     if getattr(self, n) is not None)

    def elements(self, rig) -> tuple:
        """The faults' nonlinear elements on ``rig``'s model (physical DOFs)."""
        out = () if self.crack is None else (self.crack.on(rig),)
        if self.looseness is not None:
            out += (self.looseness.on(rig),)
        return out

    def removed_stiffness(self, rig, dofs) -> tuple[tuple[int, float], ...]:
        """``(dof, k)`` pairs: the diagonal springs to ground (N/m) the faults' elements take
        over, to be taken out of the run's linear K (the loose pedestal's support, in its
        direction); DOFs in the DOF map ``dofs``."""
        if self.looseness is None:
            return ()
        return ((self.looseness.dof(dofs), self.looseness.seat_stiffness(rig)),)

    def shaft_nodes(self, rig) -> tuple[int, ...]:
        """The shaft nodes a reduced model must keep physical for these faults."""
        return () if self.crack is None else self.crack.shaft_nodes(rig)

    def check(self, rig) -> None:
        """That every fault fits ``rig`` (a ValueError naming it otherwise)."""
        if self.crack is not None and self.crack.element >= rig.shaft.n_elements:
            raise _check.out_of_range("faults.crack.element", self.crack.element,
                                      f"0 … {rig.shaft.n_elements - 1} (the rig's shaft "
                                      "elements)")
        if self.misalignment is not None and self.misalignment.node not in rig.shaft.nodes:
            raise _check.out_of_range("faults.misalignment.node", self.misalignment.node,
                                      f"a shaft node of the rig ({min(rig.shaft.nodes)} … "
                                      f"{max(rig.shaft.nodes)})")
        if self.looseness is not None:
            self.looseness.on(rig)      # the bearing has a pedestal, the springs fit
