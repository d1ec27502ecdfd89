"""The faults a run may carry beside rub (or instead of it): what a plant confuses with rub.

``Run(faults=Faults(...))`` places each fault on the run's rig:

* ``misalignment`` — a misaligned flexible coupling at a shaft node
  (:class:`~rubdiag.simulate.misalignment.Misalignment`): loads by order (preload, 2×, …);
* ``crack`` — a breathing transverse crack in a shaft element (:class:`Crack`, placed as a
  :class:`~rubdiag.simulate.crack.BreathingCrack` element of the seam).

Mechanical looseness (:class:`~rubdiag.simulate.pedestal.LoosePedestal`) needs a pedestal
mass in the rig's model, which the rig description does not have yet: it is simulated
through ``simulate_system`` only. A fault's severity is its own parameter (the crack's depth
ratio, the coupling's offset and angle). Faults are part of the run's description only when
set, so a run without them keeps its ids.
"""

from __future__ import annotations

from dataclasses import dataclass

from rubdiag import _check
from rubdiag.simulate.crack import LAWS, BreathingCrack
from rubdiag.simulate.misalignment import Misalignment

__all__ = ["Crack", "Faults"]


@dataclass(frozen=True, kw_only=True)
class Crack:
    """A breathing crack in shaft element ``element`` (0-based, axial order) of the rig:
    depth ratio a/D in (0, 0.5], position along the element (fraction, [0, 1]), breathing
    law ``"mayes"`` or ``"gasch"``, the crack normal's angle at shaft angle 0 (rad)."""

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
class Faults:
    """The faults of a run (module docstring); None: absent."""

    misalignment: Misalignment | None = None
    crack: Crack | None = None

    def __post_init__(self):
        for name, kind in (("misalignment", Misalignment), ("crack", Crack)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, kind):
                raise _check.wrong_type(f"faults.{name}", type(value).__name__,
                                        f"a {kind.__name__} or None")

    @property
    def names(self) -> tuple[str, ...]:
        """The faults present, by name."""
        return tuple(n for n in ("misalignment", "crack") if getattr(self, n) is not None)

    def elements(self, rig) -> tuple:
        """The faults' nonlinear elements on ``rig``'s model (physical DOFs)."""
        return () if self.crack is None else (self.crack.on(rig),)

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
