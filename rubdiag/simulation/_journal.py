"""A plain journal bearing as a nonlinear element of the seam (kind 5).

:class:`JournalBearing` describes the element of :mod:`rubdiag._kernels.journal`: the oil film
between a journal (two DOFs, y and z) and its housing (two DOFs, or the ground), with the
short-bearing π-film force of :mod:`rubdiag._fluidfilm` (model, sources and tests there).
The film turns with the shaft: the journal turns from y towards z at the run's speed.

The short-bearing force holds while the journal stays inside its clearance: the element
records the thinnest film over the clearance as its ``gap`` at every sample (``contact_gap``
of the result), positive while it does.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from rubdiag import _check
from rubdiag._kernels import journal
from rubdiag.simulation._elements import Packed, _pair

__all__ = ["JournalBearing"]


@dataclass(frozen=True, kw_only=True)
class JournalBearing:
    """The oil film of a plain journal bearing (SI): the journal's DOFs ``dof_a`` (y, z),
    the housing's ``dof_b`` ((-1, -1): ground), the oil's viscosity ``mu_pa_s`` (Pa s,
    > 0), the journal's radius ``radius_m``, the bearing's length ``length_m`` and its
    radial clearance ``clearance_m`` (m, > 0; clearance below the radius)."""

    dof_a: tuple
    dof_b: tuple = (-1, -1)
    mu_pa_s: float
    radius_m: float
    length_m: float
    clearance_m: float

    kernel: ClassVar = journal
    impacts: ClassVar[bool] = False     # a smooth film: long steps may run through it

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "dof_a", _pair("JournalBearing.dof_a", self.dof_a))
        set_(self, "dof_b", _pair("JournalBearing.dof_b", self.dof_b, ground=True))
        for name, unit in (("mu_pa_s", "Pa s"), ("radius_m", "m"), ("length_m", "m"),
                           ("clearance_m", "m")):
            _check.number(f"JournalBearing.{name}", getattr(self, name), lo=0.0,
                          lo_open=True, allowed=f"finite and > 0 {unit}")
        if not self.clearance_m < self.radius_m:
            raise _check.out_of_range("JournalBearing.clearance_m", self.clearance_m,
                                      f"< radius_m = {_check.plain(self.radius_m)} m")

    def pack(self, omega: float, ramp=None) -> Packed:
        rows = np.array([[self.dof_a[0], self.dof_b[0]], [self.dof_a[1], self.dof_b[1]]],
                        dtype=np.int64)
        par = np.array([self.mu_pa_s, self.radius_m, self.length_m, self.clearance_m])
        return Packed(journal.KIND, rows, np.eye(2), par, np.zeros(len(journal.STATE)),
                      False, 0.0)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        return 0.0      # an implicit, smooth law: no step requirement of its own

    def multiplier_stiffness(self, w: np.ndarray, boost: float) -> float:
        return 0.0      # no multiplier

    def dofs(self) -> np.ndarray:
        return np.array([d for d in (*self.dof_a, *self.dof_b) if d >= 0], dtype=np.int64)
