"""The levels of a design's ``fault`` factor and the names of the fault labels: data only.

Kept apart from :mod:`rubdiag.dataset._faults` (which builds the runs and reads the labels
from a simulation) so that what reads stored datasets — the classifiers, the store — may
import the names without reaching the simulator (the import contract in pyproject.toml).
"""

from __future__ import annotations

__all__ = ["BLADE_RUB_FACTORS", "BLADE_SETS", "CONTACT_FACTORS", "CRACK_OPEN_THRESHOLD",
           "FAULT_KINDS", "FAULT_LABELS", "FAULT_LEVELS", "FAULT_MEASURES",
           "LIFT_OFF_THRESHOLD", "MISALIGNMENT_2X_THRESHOLD_N", "NO_RUB_GAP_M", "RUB_KINDS",
           "SEVERITY_FACTORS", "WHIRL_SHARE_THRESHOLD", "fault_level", "faults_in"]

#: the faults beside rub a level may name
FAULT_KINDS = ("misalignment", "crack", "looseness", "whirl")
FAULT_LEVELS = ("none", "rub", "misalignment", "crack", "looseness", "whirl",
                "rub+misalignment", "rub+crack", "rub+looseness", "rub+whirl")
#: severity factor -> the fault whose runs it applies to
SEVERITY_FACTORS = {"crack_depth_ratio": "crack", "misalignment_angle_mrad": "misalignment",
                    "looseness_preload_n": "looseness", "whirl_speed_ratio": "whirl"}
#: the raw measures and the labels (their columns, in this order)
FAULT_MEASURES = ("crack_open_fraction", "misalignment_2x_force_n", "lift_off_fraction",
                  "subsync_share", "min_film_ratio")
FAULT_LABELS = ("fault_crack", "fault_misalignment", "fault_looseness", "fault_whirl",
                "faults")
#: the gap of the runs without rub (m): far beyond any orbit of the rig (module docstring)
NO_RUB_GAP_M = 0.05
#: what may rub (the ``rub_kind`` factor): blade tips on the casing, the shaft on a seal
RUB_KINDS = ("blade", "seal")
#: which blades may rub (the ``rubbing_blades`` factor): every other blade from blade 1,
#: every blade, or blade 1 alone (:func:`rubdiag.dataset._rig_factors.blade_set`)
BLADE_SETS = ("alternate", "all", "one")
#: the factors a run without rub ignores
CONTACT_FACTORS = ("gap_mm", "interference_ratio", "mu", "normal_stiffness_n_m",
                   "contact_stiffness_scale", "rub_kind", "rubbing_blades")
#: the factors a run whose shaft rubs on its seal ignores
BLADE_RUB_FACTORS = ("rubbing_blades",)
CRACK_OPEN_THRESHOLD = 0.05
MISALIGNMENT_2X_THRESHOLD_N = 0.5
LIFT_OFF_THRESHOLD = 0.05
WHIRL_SHARE_THRESHOLD = 0.25


def fault_level(name: str, value) -> str:
    """Check one level of the ``fault`` factor."""
    if not isinstance(value, str) or value not in FAULT_LEVELS:
        raise ValueError(f"{name} = {value!r} is not a fault level (allowed: "
                         f"{', '.join(FAULT_LEVELS)})")
    return value


def faults_in(level: str) -> tuple[str, ...]:
    """The faults a level names (``"none"``: none)."""
    return () if level == "none" else tuple(level.split("+"))
