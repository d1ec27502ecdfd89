"""The ``fault`` factor of a design: which faults a run carries, their fixed settings, and
the labels each fault's own element gives.

Levels (:data:`FAULT_LEVELS`): ``none``, ``rub``, ``misalignment``, ``crack``,
``looseness``, ``whirl``, and ``rub+`` each of the four. A level names the faults present,
joined by ``+``; adding a fault is one entry in :data:`FAULT_KINDS` and its levels.

* Levels without ``rub`` have no blade–casing contact: their runs keep the rig as it is
  (its contact elements, so the same model, reduced model and sensors as the rub runs: the
  rig never gives the class away) with the gap at :data:`NO_RUB_GAP_M` (50 mm, 25 times
  the study's gaps: the paper rig's linear orbit at its critical speeds reaches about 2 mm)
  and the rig's own contact law, so the gap, friction and contact-stiffness factors do not
  enter them (nor their run ids), and their rows show those factors as NaN. (A rig without
  contact elements, ``Run.paper_case(gap_mm=None)``, is not used: its reduced model would
  keep other boundary DOFs than the rub runs'.) ``rub`` is then False from the episodes, as
  always: no episode closes. The gap is the clearance at the static state under gravity
  (:class:`~rubdiag.simulation._static_load.StaticLoad`, ``clearances = "loaded"``).
* A severity factor applies only to the runs where its fault is present
  (:data:`SEVERITY_FACTORS`: ``crack_depth_ratio`` a/D, ``misalignment_angle_mrad`` α₀,
  ``looseness_preload_n`` F₀);
  in the other runs it is ignored — not in the run, not in its id, NaN in its row.
  The coupling's severity is its angular misalignment α₀: in the kinematic coupling model
  (:mod:`rubdiag.simulation._misalignment`) a parallel offset alone bends both joints alike,
  their 2× forces cancel and only a 2× moment is left (0.08 N·m at 0.4 mm, T = 20 N·m,
  L = 5 cm), while α₀ makes a 2× force ≈ T α₀ / (2 L) (2 N at 10 mrad); a fixed offset
  is a ``[base]`` option.
* The loose pedestal's severity is the force F₀ still pressing it onto its seat (what is
  left of the bolts' clamping: smaller is looser). It lifts off where the bearing's dynamic
  force exceeds F₀. Its direction is z by default, across gravity (along -y): under gravity
  the seat also carries the weight (204 N on ``paper-pedestal``: the pedestal's own 196 N
  and the rotor's share), which no unbalance force of the rig lifts (measured: no time
  lifted at case 1's critical speed, 1500 rpm). Across gravity,
  the paper rig's 1× bearing force at half a critical speed is about 0.5 N (case 1) and
  5 N (case 2): F₀ of a fraction of a newton lifts the pedestal in both cases. The rig must
  have that bearing on a pedestal: the preset ``paper-pedestal``.
* Oil whirl (and whip) needs a rig on plain journal bearings (the preset ``paper-journal``).
  Its severity is the speed: a run with whirl turns at ``whirl_speed_ratio`` times the
  rig's threshold of instability (:func:`whirl_threshold_rad_s`), whatever the design's
  speed factor says; the other runs keep that factor. A run on such a rig whips wherever its
  speed lies above the threshold, whatever its level: its label says so.
* Rub has kinds (``rub_kind``: ``blade`` or ``seal``; ``rubbing_blades``: which blades,
  :func:`rubdiag.dataset._rig_factors.blade_set`; and the rig factor ``blade_count``). A
  design with seal rubs gives every run an annular seal at ``seal_node``
  (:meth:`~rubdiag.dataset.Design.runs`), out of reach (:data:`NO_RUB_GAP_M`) unless the
  run rubs on it, when its blades are out of reach instead and ``Run.seal_clearance_m`` is
  the seal's own linear orbit over ``interference_ratio``. Aligned on the loaded rotor
  (clearances ``"loaded"``), the seal is centred on the rotor's static state. Partial rub
  (a touch per revolution) and full annular rub (continuous contact, which dry friction
  can turn into backward whirl) are the two regimes a seal shows (Muszynska A.,
  "Rotor-to-stationary element rub-related vibration phenomena in rotating machinery —
  literature survey", Shock and Vibration Digest 21(3) 3-11, 1989; Black H.F.,
  "Interaction of a whirling rotor with a vibrating stator across a clearance annulus",
  J. Mech. Eng. Sci. 10(1) 1-12, 1968; Choy F.K. & Padovan J., "Non-linear transient
  analysis of rotor-casing rub events", J. Sound Vib. 113(3) 529-545, 1987); the row's
  ``rub_state`` tells them apart.
* The rest of each fault is fixed by ``[base]`` options (:class:`FaultSettings`).

Labels (:func:`fault_labels`), from what each fault's element or model did, never a
probe's spectrum:

``crack_open_fraction``
    The share of the analysis window during which the crack element is engaged (status
    not OPEN: its breathing function f > 0), from the per-step status log of the element
    that follows the contact elements. NaN without a crack.
``misalignment_2x_force_n``
    The 2× line of the coupling's force on the rotor (N): the larger of the y and z force
    amplitudes of :meth:`~rubdiag.simulation.Misalignment.lines` (the model's
    law is "constant": the same at every speed, so this is its value at the run's speed).
    NaN without a misalignment.
``lift_off_fraction``
    The share of the analysis window during which the loose pedestal is off its seat (its
    element's status not SEATED), from the same status log. NaN without a looseness.
``subsync_share``
    The largest over the rig's journal bearings of the share, by power, of the journal's
    orbit relative to its housing below 0.9× of the speed
    (:func:`rubdiag.runs.subsynchronous_share`). NaN on a rig without journal
    bearings.
``min_film_ratio``
    The thinnest oil film over the window, over the clearance, among the rig's journal
    bearings (each film element's recorded ``gap``; > 0: every journal stayed inside its
    clearance, where the short-bearing force holds). NaN on a rig without journal bearings.
``fault_crack``, ``fault_misalignment``, ``fault_looseness``, ``fault_whirl``
    The measure at or above :data:`CRACK_OPEN_THRESHOLD` / :data:`MISALIGNMENT_2X_THRESHOLD_N`
    / :data:`LIFT_OFF_THRESHOLD` / :data:`WHIRL_SHARE_THRESHOLD`.
``faults``
    The faults that acted, ``rub`` first, joined by ``+`` (``"none"`` when none did).

The thresholds are CALIBRATIONS: a crack engaged during under 5 % of the window hardly
breathes; a 2× coupling force under 0.5 N is small beside the paper rig's unbalance forces at half
its first critical speed; with the default coupling (T = 20 N·m, L = 5 cm) it is α₀ ≈ 2.5
mrad; a pedestal off its seat during under 5 % of the window only taps it; a quarter of the
journal's orbit below 0.9× is a whirl that dominates the bearing's motion (measured on the
test rotor of ``tests/journal_rig.py``: 6e-9 below its threshold, 0.98 above).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag.dataset._fault_levels import (
    BLADE_RUB_FACTORS,
    CONTACT_FACTORS,
    CRACK_OPEN_THRESHOLD,
    FAULT_KINDS,
    FAULT_LABELS,
    FAULT_LEVELS,
    FAULT_MEASURES,
    LIFT_OFF_THRESHOLD,
    MISALIGNMENT_2X_THRESHOLD_N,
    NO_RUB_GAP_M,
    SEVERITY_FACTORS,
    WHIRL_SHARE_THRESHOLD,
    fault_level,
    faults_in,
)

__all__ = ["CRACK_OPEN_THRESHOLD", "FAULT_KINDS", "FAULT_LABELS", "FAULT_LEVELS",
           "FAULT_MEASURES", "LIFT_OFF_THRESHOLD",
           "MISALIGNMENT_2X_THRESHOLD_N", "NO_RUB_GAP_M", "SEVERITY_FACTORS",
           "WHIRL_SHARE_THRESHOLD", "FaultSettings", "fault_labels", "fault_level", "faults_in",
           "whirl_threshold_rad_s"]


@dataclass(frozen=True)
class FaultSettings:
    """The fixed settings of the faults in a design (``[base]`` keys, SI units):

    ``gravity_m_s2``: gravity along -y (m/s², >= 0; 0: no static load, the default, so a
    design without it makes the runs it made before) — every run gets
    ``StaticLoad(direction="y", gravity_m_s2=-gravity_m_s2)``; the crack needs it to breathe
    as a real one does. ``crack_element`` (default 10: next to the paper rig's disc),
    ``crack_law`` ("gasch", default: it breathes with the bending moment, so gravity
    matters; or "mayes", whose f > 0 at every angle but one, so that its open fraction is
    1); ``coupling_node`` (default 3), ``drive_torque_n_m`` (default 20 N·m),
    ``spacer_length_m`` (default 0.05 m) and ``misalignment_offset_m`` (default 0 m) of the
    misaligned coupling; ``loose_bearing`` (default 0: the drive end), ``loose_direction``
    ("z", default: across gravity; or "y") and ``loose_stiffness_n_m`` (default 0 N/m: no
    retaining spring once lifted) of the loose pedestal; ``seal_node``, the shaft node of
    the annular seal that a design with a ``rub_kind`` factor gives every run (default: the
    shaft node midway between the first and the last disc, 15 on the paper rig).
    """

    gravity_m_s2: float = 0.0
    crack_element: int = 10
    crack_law: str = "gasch"
    coupling_node: int = 3
    drive_torque_n_m: float = 20.0
    spacer_length_m: float = 0.05
    misalignment_offset_m: float = 0.0
    loose_bearing: int = 0
    loose_direction: str = "z"
    loose_stiffness_n_m: float = 0.0
    seal_node: int | None = None

    def __post_init__(self):
        object.__setattr__(self, "gravity_m_s2", _check.number(
            "base.gravity_m_s2", self.gravity_m_s2, lo=0.0, hi=1e3, unit="m/s²"))
        object.__setattr__(self, "crack_element", _check.integer(
            "base.crack_element", self.crack_element, lo=0))
        _check.choice("base.crack_law", self.crack_law, ("gasch", "mayes"))
        object.__setattr__(self, "coupling_node", _check.integer(
            "base.coupling_node", self.coupling_node, lo=0))
        object.__setattr__(self, "drive_torque_n_m", _check.number(
            "base.drive_torque_n_m", self.drive_torque_n_m, lo=-1e6, hi=1e6, unit="N·m"))
        object.__setattr__(self, "spacer_length_m", _check.number(
            "base.spacer_length_m", self.spacer_length_m, lo=0.0, hi=10.0, lo_open=True,
            unit="m"))
        object.__setattr__(self, "misalignment_offset_m", _check.number(
            "base.misalignment_offset_m", self.misalignment_offset_m, lo=0.0, hi=0.05,
            unit="m"))
        object.__setattr__(self, "loose_bearing", _check.integer(
            "base.loose_bearing", self.loose_bearing, lo=0))
        _check.choice("base.loose_direction", self.loose_direction, ("y", "z"))
        object.__setattr__(self, "loose_stiffness_n_m", _check.number(
            "base.loose_stiffness_n_m", self.loose_stiffness_n_m, lo=0.0, hi=1e12,
            unit="N/m"))
        if self.seal_node is not None:
            object.__setattr__(self, "seal_node", _check.integer(
                "base.seal_node", self.seal_node, lo=0))

    def to_dict(self) -> dict:
        """The non-default settings (a design that sets none writes none)."""
        default = FaultSettings()
        return {k: getattr(self, k) for k in KEYS if getattr(self, k) != getattr(default, k)}

    def static_load(self):
        from rubdiag.simulation import StaticLoad

        if self.gravity_m_s2 == 0.0:
            return None
        return StaticLoad(direction="y", gravity_m_s2=-self.gravity_m_s2)

    def faults(self, point) -> object:
        """The :class:`~rubdiag.simulation._faults.Faults` of a design point, or None."""
        from rubdiag.simulation import Crack, Faults, Looseness, Misalignment

        present = faults_in(point.get("fault", "none"))
        parts = {}
        if "crack" in present:
            parts["crack"] = Crack(element=self.crack_element,
                                   depth_ratio=point["crack_depth_ratio"], law=self.crack_law)
        if "misalignment" in present:
            parts["misalignment"] = Misalignment(
                node=self.coupling_node, drive_torque_n_m=self.drive_torque_n_m,
                spacer_length_m=self.spacer_length_m, offset_m=self.misalignment_offset_m,
                angle_rad=point["misalignment_angle_mrad"] * 1e-3)
        if "looseness" in present:
            parts["looseness"] = Looseness(
                bearing=self.loose_bearing, preload_n=point["looseness_preload_n"],
                loose_stiffness_n_m=self.loose_stiffness_n_m, direction=self.loose_direction)
        return Faults(**parts) if parts else None


KEYS = ("gravity_m_s2", "crack_element", "crack_law", "coupling_node", "drive_torque_n_m",
        "spacer_length_m", "misalignment_offset_m", "loose_bearing", "loose_direction",
        "loose_stiffness_n_m", "seal_node")


def check_factors(names: set[str], levels: tuple[str, ...] | None) -> None:
    """A severity factor needs the ``fault`` factor, and each fault level its severity."""
    for severity, fault in SEVERITY_FACTORS.items():
        if severity in names and levels is None:
            raise ValueError(f"factors.{severity} needs factors.fault (it applies to the "
                             f"runs with a {fault})")
    for level in levels or ():
        for fault in faults_in(level):
            severity = next((s for s, f in SEVERITY_FACTORS.items() if f == fault), None)
            if severity is not None and severity not in names:
                raise ValueError(f"factors.fault level {level!r} needs factors.{severity} "
                                 f"(the {fault}'s severity)")


#: the factors that set a run's speed, which a run with whirl ignores
SPEED_FACTORS = ("speed_ratio", "speed_rpm")


def shown_point(point: dict) -> dict:
    """The point as its row shows it: what its run ignores blank — NaN, or None for a text
    factor (the severities of absent faults; without rub, the contact factors; with a seal
    rub, the blade factors; with whirl, the speed factors)."""
    if "fault" not in point:
        return dict(point)
    present = faults_in(point["fault"])

    def ignored(name: str) -> bool:
        if name in SEVERITY_FACTORS:
            return SEVERITY_FACTORS[name] not in present
        if name in SPEED_FACTORS:               # whirl's speed is its severity's
            return "whirl" in present
        if name in BLADE_RUB_FACTORS and point.get("rub_kind") == "seal":
            return True
        return name in CONTACT_FACTORS and "rub" not in present

    # a text factor shows as empty (None: a null in the stored column), a number as NaN
    return {k: (None if isinstance(v, str) else math.nan) if ignored(k) else v
            for k, v in point.items()}


def fault_labels(result, rub: bool) -> dict:
    """The fault measures and labels of a simulated run, from what each fault's element or
    model did (never a probe's spectrum; module docstring).

    Parameters
    ----------
    result : SimulationResult
        The run, simulated with its faults (``result.run.faults``).
    rub : bool
        The run's rub label (from its contact episodes), which ``faults`` names first.

    Returns
    -------
    dict
        The measures (NaN where the run lacks what they measure):
        ``crack_open_fraction`` and ``lift_off_fraction``, the shares of the analysis
        window the crack is engaged and the loose pedestal off its seat;
        ``misalignment_2x_force_n``, the coupling's 2× force (N); ``subsync_share``, the
        largest share by power of a journal's orbit below 0.9× of the speed;
        ``min_film_ratio``, the thinnest oil film over the clearance. Then the labels:
        ``fault_crack``, ``fault_misalignment``, ``fault_looseness``, ``fault_whirl``
        (bool: the measure at or above its calibrated threshold) and ``faults``, the
        faults that acted, ``rub`` first, joined by ``+`` (``"none"`` when none did).
    """
    from rubdiag._kernels import pedestal
    from rubdiag._kernels.records import SLIDING, STICKING
    from rubdiag.runs import subsynchronous_share

    faults = result.run.faults
    present = () if faults is None else faults.names
    # the fault elements follow the contacts, in Faults.elements' order: crack, pedestal
    element = result.n_contacts + 1
    open_fraction = misalignment_2x = lifted = math.nan
    if "crack" in present:
        open_fraction = _fraction_in(result, element, (SLIDING, STICKING))   # not OPEN
        element += 1
    if "looseness" in present:
        lifted = 1.0 - _fraction_in(result, element, (pedestal.SEATED,))
    if "misalignment" in present:
        lines = faults.misalignment.lines()
        misalignment_2x = float(np.max(np.abs(lines[2][:2]))) if 2 in lines else 0.0
    journals = [k for k, b in enumerate(result.run.rig.bearings) if b.journal is not None]
    share = (max(subsynchronous_share(result, k) for k in journals) if journals
             else math.nan)
    # the films are the last elements: their recorded gap is the thinnest film / clearance
    films = result.system.contact_gap[result.window, -len(journals):] if journals else None
    min_film = float(films.min()) if journals else math.nan
    acted = {"rub": rub,
             "misalignment": bool(misalignment_2x >= MISALIGNMENT_2X_THRESHOLD_N),
             "crack": bool(open_fraction >= CRACK_OPEN_THRESHOLD),
             "looseness": bool(lifted >= LIFT_OFF_THRESHOLD),
             "whirl": bool(share >= WHIRL_SHARE_THRESHOLD)}
    names = [n for n in ("rub", *FAULT_KINDS) if acted[n]]
    return {"crack_open_fraction": open_fraction, "misalignment_2x_force_n": misalignment_2x,
            "lift_off_fraction": lifted, "subsync_share": share, "min_film_ratio": min_film,
            "fault_crack": acted["crack"], "fault_misalignment": acted["misalignment"],
            "fault_looseness": acted["looseness"], "fault_whirl": acted["whirl"],
            "faults": "+".join(names) if names else "none"}


@functools.cache
def whirl_threshold_rad_s(rig) -> float:
    """The threshold of instability (rad/s) of ``rig`` on its journal bearings
    (:func:`rubdiag.modal.whirl_threshold`; cached per rig). A ValueError when the rig has
    no journal bearing or no threshold there."""
    from rubdiag.simulation._rig_cache import forward_critical_speeds

    check_whirl_rig(rig)
    return threshold_for(rig, forward_critical_speeds(rig, 2))


def check_whirl_rig(rig) -> None:
    """A ValueError unless ``rig`` has a journal bearing (where oil whirl happens)."""
    if not any(b.journal is not None for b in rig.bearings):
        raise ValueError(f"rig {rig.name!r} has no journal bearing: oil whirl needs one "
                         "(allowed: a rig such as the preset 'paper-journal')")


def threshold_for(rig, critical_rad_s) -> float:
    """:func:`whirl_threshold_rad_s` of a rig on journal bearings whose forward critical
    speeds ``critical_rad_s`` (rad/s, its first two) are known: they bound the search
    (:func:`rubdiag.simulation._rig_cache.whirl_threshold_speed`: kept on disk)."""
    from rubdiag.simulation._rig_cache import whirl_threshold_speed

    found = whirl_threshold_speed(rig, critical_rad_s)
    if found is None:
        raise ValueError(f"rig {rig.name!r} is stable from half its first to twice its "
                         "second critical speed: no threshold for whirl_speed_ratio")
    return found


def _fraction_in(result, element: int, statuses: tuple[int, ...]) -> float:
    """The share of the analysis window element ``element`` (from 1) spends in one of the
    closed ``statuses`` (2, 3: the status log keeps closed statuses only), from the per-step
    status log (segments clipped to the window)."""
    start = result.run.discard_s
    end = float(result.t[-1]) if result.t.size else start
    if end <= start:
        return math.nan
    seg = result.system.status_segments
    keep = (seg.element == element) & np.isin(seg.status, statuses)
    lo = np.clip(seg.t_start[keep], start, end)
    hi = np.clip(seg.t_end[keep], start, end)
    return float(np.sum(hi - lo) / (end - start))
