"""The unbalance a run applies, and the rig's unbalance magnitudes with the study's two
phase patterns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rubdiag import _check
from rubdiag.model._frozen import set_field as _set

__all__ = ["Loading", "Unbalance"]


@dataclass(frozen=True)
class Unbalance:
    """Unbalance per disc, in disc order: magnitude u (kg·m) and phase (rad).

    The force on disc j is u_j Ω² (cos(Ωt + φ_j), sin(Ωt + φ_j)) in (y, z).

    Parameters
    ----------
    magnitudes_kg_m : tuple of float
        Unbalance u of each disc (kg·m, >= 0).
    phases_rad : tuple of float
        Phase φ of each disc's unbalance (rad), one per magnitude.
    """

    magnitudes_kg_m: tuple[float, ...]
    phases_rad: tuple[float, ...]

    def __post_init__(self):
        mags = _check.numbers("Unbalance.magnitudes_kg_m", self.magnitudes_kg_m,
                              check=_check.non_negative)
        phases = _check.numbers("Unbalance.phases_rad", self.phases_rad,
                                check=_check.number, length=len(mags))
        _set(self, "magnitudes_kg_m", mags)
        _set(self, "phases_rad", phases)


@dataclass(frozen=True)
class Loading:
    """The rig's unbalance magnitudes per disc and the study's two phase patterns.

    Case 1 (API 617, first mode) puts the unbalances in phase; case 2 (second mode) puts
    them out of phase.

    Parameters
    ----------
    unbalance_kg_m : tuple of float
        Unbalance magnitude of each disc (kg·m, >= 0).
    case1_phases_rad : tuple of float or None
        Phases of case 1 (rad); None: all 0.
    case2_phases_rad : tuple of float or None
        Phases of case 2 (rad); None: 0, π, 0, ... along the shaft.
    """

    unbalance_kg_m: tuple[float, ...]
    case1_phases_rad: tuple[float, ...] | None = None
    case2_phases_rad: tuple[float, ...] | None = None

    def __post_init__(self):
        mags = _check.numbers("Loading.unbalance_kg_m", self.unbalance_kg_m,
                              check=_check.non_negative)
        n = len(mags)
        _set(self, "unbalance_kg_m", mags)
        case1 = (0.0,) * n if self.case1_phases_rad is None else self.case1_phases_rad
        # out of phase: alternate 0, π along the shaft
        case2 = (tuple(math.pi * (i % 2) for i in range(n))
                 if self.case2_phases_rad is None else self.case2_phases_rad)
        _set(self, "case1_phases_rad",
             _check.numbers("Loading.case1_phases_rad", case1, check=_check.number, length=n))
        _set(self, "case2_phases_rad",
             _check.numbers("Loading.case2_phases_rad", case2, check=_check.number, length=n))

    def case(self, case: int) -> Unbalance:
        """The unbalance of the study's case 1 (in phase) or case 2 (out of phase)."""
        case = _check.integer("case", case, lo=1, hi=2)
        phases = self.case1_phases_rad if case == 1 else self.case2_phases_rad
        return Unbalance(self.unbalance_kg_m, phases)
