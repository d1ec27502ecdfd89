"""A design's points expanded into runs: the design point, its replicate and the Run.

:func:`points` draws the design points; :func:`runs` builds every run of them, each checked
before any is simulated. A point's speed is a ratio of a speed of its own rotor — a forward
critical speed (``speed_ratio``) or the threshold of instability (``whirl_speed_ratio``) —
and a rub run's gap with ``interference_ratio`` is its linear approach over the ratio:
these eigenvalue searches and harmonic solves are made here, when the runs are asked for,
each rotor once (:mod:`rubdiag.dataset._resolve`), never when the design is made.
:func:`rig_critical_speeds` gives the design's own rotor's critical speeds, which
``Design.resolved_critical_speeds_rad_s`` keeps.

The functions take the :class:`~rubdiag.dataset._design.Design` whose methods call them
(``Design.points``, ``Design.runs``, ``Design.run_for``, ``Design.design_run``).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from rubdiag import _check
from rubdiag.dataset._approach import approach_of
from rubdiag.dataset._faults import NO_RUB_GAP_M, faults_in, shown_point
from rubdiag.dataset._ids import run_ids
from rubdiag.dataset._ramp import SpeedRamp
from rubdiag.dataset._resolve import Workers, resolve_rotors, start_approaches
from rubdiag.dataset._resolve import critical_speeds_rad_s as rotor_critical_speeds
from rubdiag.dataset._resolve import whirl_threshold_rad_s as rotor_threshold
from rubdiag.dataset._rig_factors import (
    CRITICAL_FACTORS,
    THRESHOLD_FACTORS,
    varied_rig,
    with_rubbing_blades,
)
from rubdiag.dataset._sampling import gap_ramps_s, unit_samples
from rubdiag.dataset._window import check_revolutions, check_top_speed
from rubdiag.model import Rig, StatorContact, Unbalance
from rubdiag.simulation import Run

__all__ = ["DesignRun", "critical_speed_rad_s", "describe_point", "design_run", "points",
           "rig_critical_speeds", "run_for", "runs", "seal_of", "whirl_threshold_rad_s"]

#: Significant digits a speed found by an eigenvalue search is rounded to when a
#: model-uncertainty factor moves it: the search's last bits may differ between machines,
#: these digits do not, so a run's speed (and id) is the same everywhere.
_SPEED_DIGITS = 10
#: Decimal places (m) of a gap set from an interference ratio: 1 nm, far below any gap's
#: effect, and the same on every machine whatever the approach's last bits.
_GAP_DECIMALS = 9


class _Repeated(ValueError):
    """Two points of a design make the same run (its message is whole: no point prefix)."""


@dataclass(frozen=True)
class DesignRun:
    """One run of a design: the design point (factor name -> value, canonical order), the
    replicate, the :class:`~rubdiag.simulation.Run` they make, and its identities
    (:mod:`rubdiag.dataset._ids`); ``speed_rpm``, the design point's speed (None: the run's
    constant speed; with a ramp, the middle of the sweep), and the design's ``ramp``.

    Parameters
    ----------
    point : dict
        Factor name -> value, canonical order.
    replicate : int
        The replicate (from 0).
    run : Run
        The run.
    point_id, run_id : str
        Its identities.
    speed_rpm : float or None
        The design point's speed (rpm).
    ramp : SpeedRamp or None
        The design's speed ramp.
    """

    point: dict = field(hash=False)
    replicate: int
    run: Run
    point_id: str
    run_id: str
    speed_rpm: float | None = None
    ramp: SpeedRamp | None = None

    def __post_init__(self):
        if self.speed_rpm is None:
            object.__setattr__(self, "speed_rpm", self.run.speed_rpm)


def describe_point(point: Mapping) -> str:
    """``name = value, …`` of a design point, leaving out what its run ignores.

    Parameters
    ----------
    point : mapping
        Factor name -> value.

    Returns
    -------
    str
        The point as text.
    """
    return ", ".join(f"{k} = {v}" if isinstance(v, str) else f"{k} = {v:.6g}"
                     for k, v in point.items()
                     if v is not None and not (isinstance(v, float) and math.isnan(v)))


def rig_critical_speeds(rig: Rig, n_cases: int) -> tuple[float, ...]:
    """The reference speeds (rad/s) of cases 1 … ``n_cases`` on ``rig``: the forward
    critical speed each case excites (an eigenvalue problem each, kept per rig).

    Parameters
    ----------
    rig : Rig
        The rig.
    n_cases : int
        The highest case.

    Returns
    -------
    tuple of float
        Case c's critical speed at [c-1] (rad/s).
    """
    return tuple(_case_critical_speed(rig, c) for c in range(1, n_cases + 1))


def seal_of(design) -> StatorContact | None:
    """The annular seal every run of ``design`` has when its ``rub_kind`` factor has the
    level "seal" (its clearance out of reach, :data:`NO_RUB_GAP_M`, unless the run's
    ``seal_clearance_m`` sets it), or None. It sits at ``base.seal_node`` (default: the shaft
    node midway between the outer discs); its contact law is the rig's blade contact's
    (k_N, μ).

    Parameters
    ----------
    design : Design
        The design.

    Returns
    -------
    StatorContact or None
        The seal.
    """
    kinds = next((f.levels for f in design.factors if f.name == "rub_kind"), ())
    if "seal" not in kinds:
        return None
    rig = design.rig
    node = design.fault_settings.seal_node
    if node is None:
        discs = sorted(d.node for d in rig.discs)
        node = (discs[0] + discs[-1]) // 2
    if node not in rig.shaft.nodes:
        nodes = rig.shaft.nodes
        raise ValueError(f"base.seal_node = {node} is not a shaft node (allowed: "
                         f"{nodes.start}..{nodes.stop - 1})")
    law = rig.contact
    return StatorContact(node=node, clearance_m=NO_RUB_GAP_M,
                         stiffness_n_m=law.normal_stiffness_n_m,
                         friction_coefficient=law.friction_coefficient)


def points(design) -> list[dict]:
    """The design points of ``design``: factor name -> value (canonical order), without
    replicates (``Design.points``)."""
    if design.method == "grid":
        names = [f.name for f in design.factors]
        return [dict(zip(names, values, strict=True))
                for values in itertools.product(*(f.grid_levels() for f in design.factors))]
    axes = [f for f in design.factors if not f.is_constant]
    u = unit_samples(design.method, design.n, len(axes), design.seed)
    out = []
    for row in u:
        coordinate = dict(zip((f.name for f in axes), row.tolist(), strict=True))
        out.append({f.name: f.levels[0] if f.is_constant else f.from_unit(
            coordinate[f.name]) for f in design.factors})
    return out


def runs(design, jobs: int | None = 1) -> list[DesignRun]:
    """Every run of ``design`` (``Design.runs``): the design's own critical speeds first
    (its window checked at them), then what the points refer to, on ``jobs`` workers."""
    design.resolved_critical_speeds_rad_s()      # solved, the window checked: before any point
    todo = points(design)
    whirl = ["whirl" in faults_in(p.get("fault", "none")) for p in todo]
    built: dict[int, list | ValueError] = {}    # index -> [(replicate, run, ratio)]
    with Workers(jobs) as workers:
        thresholds = resolve_rotors(*_rotors(design, todo), workers)
        # the points without whirl while the workers seek the thresholds, then the rest
        _build(design, todo, [k for k, w in enumerate(whirl) if not w], built)
        approaches = [_start_approaches(built, workers)]
        thresholds()
        _build(design, todo, [k for k, w in enumerate(whirl) if w], built)
        approaches.append(_start_approaches(
            {k: built[k] for k, w in enumerate(whirl) if w}, workers))
        # the runs without an approach to wait for are made while the workers work
        made = {(k, replicate): _item(design, todo[k], replicate, run)
                for k, items in built.items() if not isinstance(items, ValueError)
                for replicate, run, ratio in items if ratio is None}
        found = {k: value for wait in approaches for k, value in wait().items()}
    out, seen = [], {}
    for index, point in enumerate(todo):
        try:
            if isinstance(built[index], ValueError):
                raise built[index]
            for replicate, run, ratio in built[index]:
                item = (made[(index, replicate)] if ratio is None else _item(
                    design, point, replicate, _gap_from_interference(run, ratio, found[index])))
                if item.run_id in seen:
                    raise _Repeated(f"the design repeats a run: point {index} is point "
                                    f"{seen[item.run_id]} ({describe_point(point)})")
                seen[item.run_id] = index
                out.append(item)
        except _Repeated as exc:
            raise ValueError(str(exc)) from None
        except ValueError as exc:
            raise ValueError(f"point {index} ({describe_point(point)}): {exc}") from None
    return out


def design_run(design, index: int, replicate: int = 0) -> DesignRun:
    """``runs(design)[index * replicates + replicate]`` alone (``Design.design_run``)."""
    todo = points(design)
    index = _check.integer("index", index, lo=0, hi=len(todo) - 1)
    point = todo[index]
    try:
        run = run_for(design, point, replicate)
    except ValueError as exc:
        raise ValueError(f"point {index} ({describe_point(point)}): {exc}") from None
    return _item(design, point, replicate, run)


def run_for(design, point: Mapping, replicate: int = 0) -> Run:
    """The Run of design point ``point`` and replicate ``replicate`` (``Design.run_for``)."""
    design.resolved_critical_speeds_rad_s()      # solved, the window checked: before the point
    run, ratio = _run(design, point, replicate)
    if ratio is None:
        return run
    from rubdiag.dataset._approach import sweep_linear_approach_m

    return _gap_from_interference(run, ratio,
                                  sweep_linear_approach_m(run, of=approach_of(run)))


def critical_speed_rad_s(design, point: Mapping) -> float:
    """The reference speed (rad/s) of ``point``'s ``speed_ratio``
    (``Design.critical_speed_rad_s``)."""
    if not any(name in point for name in CRITICAL_FACTORS):
        return design.resolved_critical_speeds_rad_s()[point["case"] - 1]
    rig = _rotor_rig(design.rig, point, CRITICAL_FACTORS)
    return float(f"{_case_critical_speed(rig, point['case']):.{_SPEED_DIGITS}g}")


def whirl_threshold_rad_s(design, point: Mapping) -> float:
    """The threshold of instability (rad/s) of ``point``'s rig
    (``Design.whirl_threshold_rad_s``)."""
    threshold = rotor_threshold(_rotor_rig(design.rig, point, THRESHOLD_FACTORS),
                                _rotor_rig(design.rig, point, CRITICAL_FACTORS))
    if not any(name in point for name in THRESHOLD_FACTORS):
        return threshold
    return float(f"{threshold:.{_SPEED_DIGITS}g}")


def _speed_rad_s(design, point: Mapping) -> float:
    """The design point's speed (rad/s): with a ramp, the middle of the sweep; with
    whirl, ``whirl_speed_ratio`` times the threshold of instability of the point's rig;
    else ``speed_ratio`` times its rig's critical speed for the case (the design's
    critical speeds unless a model-uncertainty factor moves it), or ``speed_rpm``."""
    if "whirl" in faults_in(point.get("fault", "none")):
        return point["whirl_speed_ratio"] * whirl_threshold_rad_s(design, point)
    if "speed_ratio" in point:
        return point["speed_ratio"] * critical_speed_rad_s(design, point)
    return point["speed_rpm"] * math.pi / 30.0


def _run(design, point: Mapping, replicate: int) -> tuple[Run, float | None]:
    """The run of :func:`run_for` and its ``interference_ratio``, or None: then it is
    the run; else its gap is still to be set from its linear approach."""
    replicate = _check.integer("replicate", replicate, lo=0, hi=design.replicates - 1)
    ramp_s = gap_ramps_s(design.replicates, design.duration_s)[replicate]
    rig = design.rig
    loading = rig.loading
    scale = point.get("unbalance_scale")
    magnitudes = (loading.unbalance_kg_m if scale is None
                  else tuple(m * scale for m in loading.unbalance_kg_m))
    if "case" in point:
        phases = loading.case(point["case"]).phases_rad
    else:
        step = math.radians(point["phase_diff_deg"])
        phases = tuple(step * (j % 2) for j in range(len(magnitudes)))
    speed = _speed_rad_s(design, point)
    rig = varied_rig(rig, point)
    rub = "rub" in faults_in(point.get("fault", "rub"))
    seal_rub = rub and point.get("rub_kind") == "seal"
    blade_rub = rub and not seal_rub
    if blade_rub and "rubbing_blades" in point:
        rig = with_rubbing_blades(rig, point["rubbing_blades"])
    seal = seal_of(design)
    seal_clearance = None
    if seal is not None:
        rig = dataclasses.replace(rig, stator_contacts=(seal,))
    if seal_rub:    # its clearance, or out of reach until its approach sets it
        seal_clearance = (point["gap_mm"] * 1e-3 if "gap_mm" in point
                          else NO_RUB_GAP_M)
    gap = point.get("gap_mm") if blade_rub else NO_RUB_GAP_M * 1e3  # out of reach
    options = {}
    faults = design.fault_settings.faults(point)
    if faults is not None:
        options["faults"] = faults
    static_load = design.fault_settings.static_load()
    if static_load is not None:
        options["static_load"] = static_load
    check_revolutions(design.duration_s, design.discard_s, design.ramp, speed)
    duration = design.duration_s
    if design.ramp is not None:
        profile = design.ramp.profile(speed * 30.0 / math.pi, hold_s=design.discard_s)
        speed, duration = profile.start_rad_s, profile.end_s
        options["speed_profile"] = profile
    run = Run(rig=rig, speed_rad_s=speed, unbalance=Unbalance(magnitudes, phases),
              gap_m=None if gap is None else gap * 1e-3, duration_s=duration,
              discard_s=design.discard_s,
              contact=_contact(rig, point) if blade_rub else None,
              gap_ramp_s=ramp_s, seal_clearance_m=seal_clearance,
              sensors=design.sensors, reduction=design.reduction,
              step_error=design.step_error or None,
              label=f"{describe_point(shown_point(point))}, replicate {replicate}", **options)
    if design.ramp is not None:
        check_top_speed(run)
    return run, point.get("interference_ratio") if rub else None


def _build(design, todo: list, indices, built: dict) -> None:
    """The runs of the points ``indices`` of ``todo`` into ``built`` (index -> [(replicate,
    run, interference ratio or None)], or the ValueError making one raised)."""
    for k in indices:
        try:
            built[k] = [(r, *_run(design, todo[k], r)) for r in range(design.replicates)]
        except ValueError as exc:
            built[k] = exc


def _start_approaches(built: dict, workers: Workers):
    """Start the linear approaches of the points of ``built`` whose gap is set from
    one (a point's replicates share it); the returned function waits for them: index
    -> approach (m) or the ValueError computing it raised."""
    wanted = {k: items[0][1] for k, items in built.items()
              if not isinstance(items, ValueError) and items[0][2] is not None}
    found = start_approaches(list(wanted.values()), workers,
                             [approach_of(run) for run in wanted.values()])
    return lambda: dict(zip(wanted, found(), strict=True))


def _item(design, point: Mapping, replicate: int, run: Run) -> DesignRun:
    run_id, point_id = run_ids(run)
    return DesignRun(_shown(design, point), replicate, run, point_id, run_id,
                     _speed_rad_s(design, point) * 30.0 / math.pi, design.ramp)


def _rotors(design, todo) -> tuple[list, list]:
    """The rotors the points' speeds refer to: (critical speeds wanted, as (rig, case)
    pairs; thresholds wanted, as (rig, the same rotor with the design's damping))."""
    critical, thresholds = [], []
    for point in todo:
        if "whirl" in faults_in(point.get("fault", "none")):
            thresholds.append((_rotor_rig(design.rig, point, THRESHOLD_FACTORS),
                               _rotor_rig(design.rig, point, CRITICAL_FACTORS)))
        if "speed_ratio" in point and any(name in point for name in CRITICAL_FACTORS):
            critical.append((_rotor_rig(design.rig, point, CRITICAL_FACTORS), point["case"]))
    return critical, thresholds


def _shown(design, point: Mapping) -> dict:
    """The point as its row shows it (:func:`~rubdiag.dataset._faults.shown_point`); a
    run with whirl shows as ``speed_ratio`` the speed it turned at over its case's
    critical speed, so that a split by speed band places it by its speed too."""
    shown = shown_point(point)
    if "whirl" in faults_in(point.get("fault", "none")) and "speed_ratio" in point:
        shown["speed_ratio"] = (_speed_rad_s(design, point)
                                / critical_speed_rad_s(design, point))
    return shown


def _case_critical_speed(rig: Rig, case: int) -> float:
    """The forward critical speed (rad/s) case ``case`` excites on ``rig``, as
    :func:`rubdiag.simulation.critical_speed_for_case` (kept per rig:
    :mod:`rubdiag.dataset._resolve`)."""
    speeds = rotor_critical_speeds(rig, case)
    if len(speeds) < case:
        raise ValueError(f"the rig has no forward critical speed number {case}")
    return float(speeds[case - 1])


def _contact(rig: Rig, point: Mapping):
    """The contact law of a point, or None (the rig's) when no contact factor is given."""
    law = rig.contact
    changes = {}
    if "mu" in point:
        changes["friction_coefficient"] = point["mu"]
    if "normal_stiffness_n_m" in point:
        ratio = law.tangential_stiffness_n_m / law.normal_stiffness_n_m
        changes["normal_stiffness_n_m"] = point["normal_stiffness_n_m"]
        changes["tangential_stiffness_n_m"] = point["normal_stiffness_n_m"] * ratio
    if "contact_stiffness_scale" in point:
        s = point["contact_stiffness_scale"]
        changes["normal_stiffness_n_m"] = law.normal_stiffness_n_m * s
        changes["tangential_stiffness_n_m"] = law.tangential_stiffness_n_m * s
    return dataclasses.replace(law, **changes) if changes else None


def _rotor_rig(rig: Rig, point: Mapping, names) -> Rig:
    """``rig`` with only the rig factors ``names`` of ``point`` applied: the key of the
    cached eigenvalue searches, which the other factors do not change."""
    return varied_rig(rig, {k: point[k] for k in names if k in point})


def _gap_from_interference(run: Run, ratio: float, approach: float | ValueError) -> Run:
    """``run`` with g0 (or, when it rubs on its seal, the seal's clearance) = its linear
    ``approach`` (m, at those contacts: :func:`approach_of`; or the ValueError computing it
    raised) / ``ratio``, rounded to :data:`_GAP_DECIMALS` so that the run's id is the same
    on every machine."""
    if isinstance(approach, ValueError):
        raise approach
    gap = round(approach / ratio, _GAP_DECIMALS)
    if gap <= 0.0:
        raise ValueError(f"factors.interference_ratio = {ratio:g}: the run's linear approach "
                         "is 0 (no unbalance response reaches the blades)")
    if approach_of(run) == "seals":
        return dataclasses.replace(run, seal_clearance_m=gap)
    return dataclasses.replace(run, gap_m=gap)
