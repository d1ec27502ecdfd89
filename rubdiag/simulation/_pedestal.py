"""Mechanical looseness: a bearing pedestal that lifts off its seat, as a nonlinear element.

:class:`LoosePedestal` describes the element of :mod:`rubdiag._kernels.pedestal` (the law, its
model and reference are there): a pedestal DOF along the support direction, pressed onto a
compression-only seat spring by a preload, optionally held by a soft retaining stiffness when
lifted. The system's coordinates are measured from the seated static equilibrium, so a run
whose seat force never reaches zero is the linear pedestal (the seat spring in K).

:func:`lift_off_fraction` is the raw measure the labels use: the time the pedestal spends off
its seat (status 1, or 3 with a retaining stiffness) over the run time, from the result's
``time_in_status`` (each accepted step counts with its end-of-step status).

The signature: a support that lifts off its seat makes sub-harmonics, ½x first and ⅓x,
with their harmonics, while a seated one adds none (Muszynska & Goldman 1995, "Chaotic
responses of unbalanced rotor/bearing/stator systems with looseness or rubs", Chaos,
Solitons & Fractals 5(9) 1683-1704; Muszynska 2005, "Rotordynamics").
tests/simulation/test_looseness_signature.py checks it on ``paper-journal``: the drive-end
pedestal lifting off at half the first critical speed shows ½x at 0.38 of its 1x, 1½x and
2x at 0.1, along the loose direction alone; the journal on it shows ½x at 0.14, the disc
0.04 — the oil film stands between the pedestal and the shaft.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from rubdiag import _check
from rubdiag._kernels import pedestal
from rubdiag.simulation._elements import Packed

__all__ = ["LoosePedestal", "lift_off_fraction"]


@dataclass(frozen=True, kw_only=True)
class LoosePedestal:
    """A pedestal DOF ``dof`` on a loose support (SI).

    ``lift_sign`` (+1 or -1): the sign of ``dof``'s positive direction along the lift-off
    direction (away from the seat). ``base_dof``: the foundation's DOF in the same direction
    (-1: ground). ``stiffness`` k_s (N/m, > 0): the seat spring, compression only.
    ``preload`` F_0 (N, >= 0): the dead load pressing the pedestal onto its seat (the weight
    it carries, a bolt preload); its static compression ``F_0 / k_s`` is included, so the
    coordinates are measured from the seated equilibrium. ``clearance`` c (m, >= 0): a gap
    between pedestal and seat at q = 0 (only without a preload). ``loose_stiffness`` k_l
    (N/m, in [0, k_s]): a retaining spring acting once lifted (0: free). With the dead load
    given as a static load of the system instead, take ``preload = 0`` and start the run from
    the static deflection (the seat then sits at x = 0; its work is then external work).
    """

    dof: int
    stiffness: float
    preload: float = 0.0
    clearance: float = 0.0
    loose_stiffness: float = 0.0
    lift_sign: int = 1
    base_dof: int = -1

    kernel: ClassVar = pedestal

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "dof", _check.integer("LoosePedestal.dof", self.dof, lo=0))
        set_(self, "base_dof", _check.integer("LoosePedestal.base_dof", self.base_dof, lo=-1))
        if self.base_dof == self.dof:
            raise _check.out_of_range("LoosePedestal.base_dof", self.base_dof,
                                      "-1 (ground) or a DOF other than dof")
        sign = _check.integer("LoosePedestal.lift_sign", self.lift_sign)
        if sign not in (-1, 1):
            raise _check.out_of_range("LoosePedestal.lift_sign", sign, "+1 or -1")
        set_(self, "lift_sign", sign)
        _check.number("LoosePedestal.stiffness", self.stiffness, lo=0.0, lo_open=True,
                      allowed="finite and > 0 N/m")
        _check.number("LoosePedestal.preload", self.preload, lo=0.0, allowed=">= 0 N")
        _check.number("LoosePedestal.clearance", self.clearance, lo=0.0, allowed=">= 0 m")
        if self.clearance > 0.0 and self.preload > 0.0:
            raise _check.out_of_range("LoosePedestal.clearance", self.clearance,
                                      "0 m when a preload is given: a pedestal off its seat "
                                      "carries none")
        _check.number("LoosePedestal.loose_stiffness", self.loose_stiffness, lo=0.0,
                      hi=self.stiffness, allowed=f">= 0 and <= stiffness = "
                      f"{_check.plain(float(self.stiffness))} N/m")

    @property
    def seat_position(self) -> float:
        """x_c (m): where the seat spring is unloaded, on the lift-off axis."""
        return self.preload / self.stiffness - self.clearance

    def pack(self, omega: float, ramp=None) -> Packed:
        par = np.array([self.stiffness, self.loose_stiffness, self.preload,
                        self.seat_position], dtype=np.float64)
        return Packed(pedestal.KIND, np.array([[self.dof, self.base_dof]], dtype=np.int64),
                      np.array([[float(self.lift_sign)]]), par, np.zeros(len(pedestal.STATE)),
                      False, 0.0)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        """``k_s W_ee``, as a contact's: a stiff seat is resolved by the step control."""
        return self.stiffness * w[0, 0]

    def multiplier_stiffness(self, w: np.ndarray, boost: float) -> float:
        return 0.0      # no multiplier

    def dofs(self) -> np.ndarray:
        return np.array([d for d in (self.dof, self.base_dof) if d >= 0], dtype=np.int64)


def lift_off_fraction(result, element: int = 0) -> float:
    """The fraction of the run's time element ``element`` (a :class:`LoosePedestal`) spent
    lifted off its seat: ``1 - time seated / run time`` from ``result.time_in_status``
    (status 2 is seated; 1 and 3 lifted)."""
    times = np.asarray(result.time_in_status)
    element = _check.integer("element", element, lo=0, hi=times.shape[0] - 1)
    total = float(times[element].sum())
    if total <= 0.0:
        raise ValueError("result has no accepted step (allowed: a run of at least one step)")
    return 1.0 - float(times[element, pedestal.SEATED - 1]) / total
