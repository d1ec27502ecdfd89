"""A dataset design: which runs to make. Frozen, picklable, checked when it is made.

:class:`Design` holds the design's settings and checks every value on construction, with
one-line ``ValueError`` messages; it solves nothing then. Its TOML form — the tables, the
keys, the sampling and the resolved form — is :mod:`rubdiag.dataset._design_toml` (read and
written there); the expansion of its points into runs, which solves the eigenvalue problems
the points' speeds refer to, is :mod:`rubdiag.dataset._expansion`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from rubdiag import _check
from rubdiag.dataset import _design_toml, _expansion
from rubdiag.dataset._expansion import DesignRun, describe_point
from rubdiag.dataset._factors import EXCLUSIVE, FACTORS, Factor
from rubdiag.dataset._faults import (
    FaultSettings,
    check_factors,
    check_whirl_rig,
    faults_in,
)
from rubdiag.dataset._labels import LabelRules
from rubdiag.dataset._noise import NoiseFloors
from rubdiag.dataset._ramp import SpeedRamp
from rubdiag.dataset._rig_factors import blade_set_of, check_rig_factors
from rubdiag.dataset._sampling import MAX_REPLICATES, METHODS, check_sobol_n, gap_ramps_s
from rubdiag.dataset._window import MIN_REVOLUTIONS, check_revolutions
from rubdiag.model import Rig
from rubdiag.reduce import Reduction
from rubdiag.simulation import Sensor, default_sensors
from rubdiag.simulation._sensors import check_sensors

__all__ = ["DEFAULT_STEP_ERROR", "MIN_REVOLUTIONS", "Design", "DesignRun", "describe_point"]

#: ``base.duration_s`` of a constant-speed design that does not give it (s).
DEFAULT_DURATION_S = 2.3
#: ``base.step_error`` of a design that does not give it: the tolerance of the runs' long
#: steps, relative to the largest recorded displacement (``Run.step_error``)
DEFAULT_STEP_ERROR = 1e-5
#: The field the resolved form fills in from the rig; equality compares its resolved value.
_RESOLVED = "critical_speeds_rad_s"


@dataclass(frozen=True, eq=False)
class Design:
    """Which runs to make (:mod:`rubdiag.dataset._design_toml` has the TOML form and the
    rules).

    ``factors`` may be given as a mapping name -> TOML form (a list of levels or
    ``{"low", "high"[, "n"]}``) or as :class:`~rubdiag.dataset._factors.Factor` objects; it is
    kept as a tuple of factors in canonical order. ``n`` is the number of design points
    (required by the sampling methods; for ``grid`` it is set to the product of the levels).
    ``critical_speeds_rad_s[c-1]`` is case c's reference speed of ``speed_ratio``; when
    ``None`` and needed, it is computed from the rig when the runs are expanded or the
    resolved form written (:meth:`resolved_critical_speeds_rad_s`), never on construction.
    Two designs are equal when they make the same runs: a design given its rig's critical
    speeds equals the same design left to compute them. ``reduction`` (a
    :class:`~rubdiag.reduce.Reduction`, or None for the full model) goes into every run;
    the TOML form is ``[base] reduced`` / ``reduction_cutoff_hz``. ``ramp`` (a
    :class:`~rubdiag.dataset._ramp.SpeedRamp` or its table, or None: constant speed) makes
    every run a sweep; ``duration_s`` is then None (each run's length is derived), else
    2.3 s by default.

    Parameters
    ----------
    rig : Rig
        The rig of every run.
    factors : tuple of Factor or mapping
        The design's factors.
    method : {"grid", "lhs", "sobol", "random"}
        How design points are drawn.
    n : int or None
        Number of design points.
    seed : int
        Seed of the sampling (>= 0).
    replicates : int
        Runs per design point, each with its own start history.
    duration_s : float or None
        Length of each run (s).
    discard_s : float
        Start of each run left out of the analysis (s).
    critical_speeds_rad_s : tuple of float or None
        Reference speed of ``speed_ratio`` per case (rad/s); None: the rig's.
    labels : LabelRules
        Thresholds of the labels.
    noise : NoiseFloors
        The sensors' noise.
    sensors : tuple of Sensor or None
        The measured channels; None: :func:`~rubdiag.simulation.default_sensors`.
    reduction : Reduction or None
        The reduced model of every run; None: the full model.
    ramp : SpeedRamp or None
        The speed sweep of every run; None: constant speed.
    fault_settings : FaultSettings
        Fixed settings of the faults (``[base]`` keys).
    step_error : float
        Tolerance of the runs' long steps, relative to the largest recorded displacement
        (0-0.01; 0: every step at the base step).
    """

    rig: Rig
    factors: tuple[Factor, ...]
    method: str = "grid"
    n: int | None = None
    seed: int = 0
    replicates: int = 1
    duration_s: float | None = None
    discard_s: float = 0.3
    critical_speeds_rad_s: tuple[float, ...] | None = None
    labels: LabelRules = field(default_factory=LabelRules)
    noise: NoiseFloors = field(default_factory=NoiseFloors)
    sensors: tuple[Sensor, ...] | None = None
    reduction: Reduction | None = None
    ramp: SpeedRamp | None = None
    fault_settings: FaultSettings = field(default_factory=FaultSettings)
    step_error: float = DEFAULT_STEP_ERROR

    def __post_init__(self):
        def set_(name, value):
            object.__setattr__(self, name, value)

        if not isinstance(self.rig, Rig):
            raise _check.wrong_type("base.rig", type(self.rig).__name__, "a Rig")
        if self.rig.contact is None:
            raise ValueError(f"base.rig = {self.rig.name!r} has no blade-casing contact "
                             "(a dataset needs blades, a casing and [contact])")
        if self.rig.loading is None:
            raise ValueError(f"base.rig = {self.rig.name!r} has no [loading] (the unbalance "
                             "magnitudes and case patterns)")
        if self.reduction is not None and not isinstance(self.reduction, Reduction):
            raise _check.wrong_type("reduction", type(self.reduction).__name__,
                                    "a Reduction or None")
        if self.reduction is not None and not self.reduction.tip_rotations:
            # a design file has no key for it: its resolved form could not say so
            raise ValueError("reduction.tip_rotations = False is not available in a design "
                             "(allowed: True, the default)")
        _check.number("base.step_error", self.step_error, lo=0.0, hi=0.01)
        set_("step_error", float(self.step_error))
        if isinstance(self.labels, Mapping):
            set_("labels", LabelRules(**self.labels))
        if not isinstance(self.labels, LabelRules):
            raise _check.wrong_type("labels", self.labels, "a LabelRules or a table")
        if isinstance(self.noise, Mapping):
            set_("noise", NoiseFloors(**self.noise))
        if not isinstance(self.noise, NoiseFloors):
            raise _check.wrong_type("noise", self.noise, "a NoiseFloors or a table")
        sensors = default_sensors(self.rig) if self.sensors is None else self.sensors
        if not sensors:
            raise ValueError("sensors is empty (allowed: at least one sensor; leave it out "
                             "for the default set)")
        set_("sensors", check_sensors(
            [Sensor(**s) if isinstance(s, Mapping) else s for s in sensors], self.rig))
        set_("factors", _factors(self.factors))
        names = {f.name for f in self.factors}
        _check_combination(names)
        if isinstance(self.fault_settings, Mapping):
            set_("fault_settings", FaultSettings(**self.fault_settings))
        if not isinstance(self.fault_settings, FaultSettings):
            raise _check.wrong_type("fault_settings", self.fault_settings,
                                    "a FaultSettings or a table")
        levels = next((f.levels for f in self.factors if f.name == "fault"), None)
        check_factors(names, levels)
        check_rig_factors(self.rig, names)
        self._check_rub_kinds(names)
        if any("whirl" in faults_in(level) for level in levels or ()):
            check_whirl_rig(self.rig)   # its variants' thresholds are sought with the runs
        set_("method", _check.choice("sampling.method", self.method, METHODS))
        set_("seed", _check.integer("sampling.seed", self.seed, lo=0))
        set_("replicates", _check.integer("sampling.replicates", self.replicates, lo=1,
                                          hi=MAX_REPLICATES))
        if isinstance(self.ramp, Mapping):
            set_("ramp", SpeedRamp.from_dict(self.ramp))
        if self.ramp is not None and not isinstance(self.ramp, SpeedRamp):
            raise _check.wrong_type("ramp", self.ramp, "a SpeedRamp, a table or None")
        if self.ramp is None:
            given = DEFAULT_DURATION_S if self.duration_s is None else self.duration_s
            duration = _check.positive("base.duration_s", given, "s")
            discard = _check.number("base.discard_s", self.discard_s, lo=0.0, hi=duration,
                                    hi_open=True, unit="s")
        elif self.duration_s is not None:
            raise ValueError(f"base.duration_s = {_check.plain(self.duration_s)} is given "
                             "with [ramp] (allowed: no base.duration_s: a run lasts "
                             "base.discard_s + 2·ramp.span·speed / ramp.rate_rpm_s)")
        else:
            duration = None
            discard = _check.non_negative("base.discard_s", self.discard_s, "s")
        set_("duration_s", duration)
        set_("discard_s", discard)
        longest = max(gap_ramps_s(self.replicates, duration))
        if discard < longest:
            raise _check.out_of_range("base.discard_s", discard,
                                      f">= {longest:g} s, the longest gap ramp of the "
                                      "replicates")
        set_("n", self._n())
        set_("critical_speeds_rad_s", self._given_critical_speeds())
        if self.critical_speeds_rad_s is not None or "speed_ratio" not in names:
            self._check_window(self.critical_speeds_rad_s)    # else when they are computed

    def _check_rub_kinds(self, names: set[str]) -> None:
        """The blade sets need a rig whose contact blades follow one; a seal rub needs a rig
        without stator contacts of its own, and takes the rig's contact law."""
        if names & {"blade_count", "rubbing_blades"}:
            blade_set_of(self.rig)
        if _expansion.seal_of(self) is None:
            return
        if self.rig.stator_contacts:
            raise ValueError(f"factors.rub_kind 'seal' with base.rig = {self.rig.name!r}, which "
                             "has stator contacts (allowed: a rig without: the design adds "
                             "its seal at base.seal_node)")
        law = sorted(names & {"mu", "normal_stiffness_n_m", "contact_stiffness_scale"})
        if law:
            raise ValueError(f"factors.{law[0]} with factors.rub_kind 'seal' (allowed: no "
                             "contact-law factor: the seal takes the rig's contact law)")

    def _check_window(self, critical_speeds_rad_s) -> None:
        """The analysis window must hold MIN_REVOLUTIONS at the slowest speed of the design
        (checked from the factors' bounds and the cases' critical speeds, without building
        the runs)."""
        by_name = {f.name: f for f in self.factors}
        if "speed_rpm" in by_name:
            slowest = _lowest(by_name["speed_rpm"]) * math.pi / 30.0
        else:
            cases = by_name["case"].levels
            slowest = _lowest(by_name["speed_ratio"]) * min(
                critical_speeds_rad_s[c - 1] for c in cases)
        check_revolutions(self.duration_s, self.discard_s, self.ramp, slowest)

    def _n(self) -> int:
        if self.method == "grid":
            return math.prod(len(f.grid_levels()) for f in self.factors)
        if self.n is None:
            raise ValueError(f"sampling.n is missing (method = '{self.method}' needs the "
                             "number of design points)")
        n = _check.integer("sampling.n", self.n, lo=1)
        if not any(f.is_range for f in self.factors):
            raise ValueError(f"sampling.method = '{self.method}' needs a {{low, high}} "
                             "factor (levels alone would repeat points; use 'grid')")
        if self.method == "sobol":
            check_sobol_n(n)
        return n

    def _given_critical_speeds(self) -> tuple[float, ...] | None:
        """``critical_speeds_rad_s`` checked: numbers, one per case at least."""
        speeds = self.critical_speeds_rad_s
        if speeds is None:
            return None
        speeds = _check.numbers("base.critical_speeds_rad_s", speeds)
        n_cases = self._n_cases()
        if n_cases is not None and len(speeds) < n_cases:
            raise ValueError(f"base.critical_speeds_rad_s has {len(speeds)} entries "
                             f"(allowed: one per case, at least {n_cases})")
        return speeds

    def _n_cases(self) -> int | None:
        """The highest case ``speed_ratio`` refers to, or None without ``speed_ratio``."""
        by_name = {f.name: f for f in self.factors}
        if "speed_ratio" not in by_name:
            return None
        return max(by_name["case"].levels)     # speed_ratio needs case (checked)

    def resolved_critical_speeds_rad_s(self) -> tuple[float, ...] | None:
        """The reference speeds of ``speed_ratio`` (rad/s, case c's at [c-1]): the given
        ``critical_speeds_rad_s``, or, on the first call, the forward critical speed each
        case excites on the rig (an eigenvalue problem per case,
        :func:`~rubdiag.dataset._expansion.rig_critical_speeds`), the analysis window then
        checked at them; None when no factor refers to them.

        Returns
        -------
        tuple of float or None
            The speeds (rad/s).
        """
        if "_resolved_speeds" not in self.__dict__:      # kept: the dataclass is frozen
            speeds, n_cases = self.critical_speeds_rad_s, self._n_cases()
            if speeds is None and n_cases is not None:
                speeds = _expansion.rig_critical_speeds(self.rig, n_cases)
                self._check_window(speeds)
            self.__dict__["_resolved_speeds"] = speeds
        return self.__dict__["_resolved_speeds"]

    def __eq__(self, other) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return self._compared() == other._compared() and (
            self.critical_speeds_rad_s == other.critical_speeds_rad_s
            or self.resolved_critical_speeds_rad_s() == other.resolved_critical_speeds_rad_s())

    def __hash__(self) -> int:
        return hash(self._compared())

    def _compared(self) -> tuple:
        """The fields but the critical speeds, which equality compares resolved."""
        return tuple(getattr(self, f.name) for f in dataclasses.fields(self)
                     if f.name != _RESOLVED)

    # --- reading and writing (rubdiag.dataset._design_toml) ---------------------------------
    @classmethod
    def from_toml(cls, source: str | Path) -> Design:
        """A design from a TOML file (a :class:`~pathlib.Path`, or a string without ``=``
        or a line break) or from TOML text (a string with one)."""
        return _design_toml.from_toml(cls, source)

    @classmethod
    def from_dict(cls, data: Mapping, root: str | Path | None = None) -> Design:
        """A design from parsed TOML (tables ``base``, ``sampling``, ``factors``); a rig path
        is relative to ``root`` (default: the working folder)."""
        return _design_toml.from_dict(cls, data, root)

    def to_dict(self) -> dict:
        """The resolved design as plain TOML-ready data
        (:mod:`rubdiag.dataset._design_toml`)."""
        return _design_toml.to_dict(self)

    def to_toml(self) -> str:
        """The resolved design as TOML text: ``[base]``, ``[sampling]`` and ``[factors]`` as
        a person writes them, then the rig as ``[base.rig]``."""
        return _design_toml.to_toml(self)

    # --- the runs (rubdiag.dataset._expansion) -----------------------------------------------
    @property
    def n_runs(self) -> int:
        return self.n * self.replicates

    def points(self) -> list[dict]:
        """The design points: factor name -> value (canonical order), without replicates."""
        return _expansion.points(self)

    def runs(self, jobs: int | None = 1) -> list[DesignRun]:
        """Every run of the design, point by point, each point's replicates together. Every
        run is built (and so checked) here, before any is simulated. What the runs refer
        to — the design's critical speeds, each distinct rotor's critical speeds and
        threshold of instability, the rub runs' linear approaches — is computed here, once,
        on ``jobs`` worker processes (None: every core; :mod:`rubdiag.dataset._resolve`):
        the same runs on any number. A point that cannot be made is named (the first in the
        design's order)."""
        return _expansion.runs(self, jobs)

    def design_run(self, index: int, replicate: int = 0) -> DesignRun:
        """The run ``runs()[index * replicates + replicate]`` alone: design point ``index``,
        with what it refers to computed for it only (a dry run's example)."""
        return _expansion.design_run(self, index, replicate)

    def run_for(self, point: Mapping, replicate: int = 0):
        """The :class:`~rubdiag.simulation.Run` of design point ``point`` (factor name ->
        value, as :meth:`points` gives) and replicate ``replicate``."""
        return _expansion.run_for(self, point, replicate)

    def critical_speed_rad_s(self, point: Mapping) -> float:
        """The reference speed of ``point``'s ``speed_ratio``: its case's critical speed on
        the point's own rig. A factor that moves the critical speeds (disc mass, the films'
        viscosity and clearance) gets it from that rig's critical speed map, rounded to 10
        significant digits so that a run's speed (and id) is the same on every machine;
        otherwise it is the design's (:meth:`resolved_critical_speeds_rad_s`)."""
        return _expansion.critical_speed_rad_s(self, point)

    def whirl_threshold_rad_s(self, point: Mapping) -> float:
        """The threshold of instability (rad/s) of ``point``'s rig, which its
        ``whirl_speed_ratio`` multiplies (rounded to 10 significant digits, as
        :meth:`critical_speed_rad_s`, when a model-uncertainty factor moves it)."""
        return _expansion.whirl_threshold_rad_s(self, point)


def _lowest(factor: Factor) -> float:
    return min(factor.levels) if factor.levels is not None else factor.low


def _factors(factors) -> tuple[Factor, ...]:
    if isinstance(factors, Mapping):
        factors = [Factor.from_spec(k, v) for k, v in factors.items()]
    items = list(factors)
    for f in items:
        if not isinstance(f, Factor):
            raise _check.wrong_type("factors", f, "Factor objects or a table")
    names = [f.name for f in items]
    for name in names:
        if names.count(name) > 1:
            raise ValueError(f"factors.{name} is given twice")
    order = list(FACTORS)
    return tuple(sorted(items, key=lambda f: order.index(f.name)))


def _check_combination(names: set[str]) -> None:
    for a, b in EXCLUSIVE:
        if a in names and b in names:
            raise ValueError(f"factors.{a} and factors.{b} exclude each other "
                             "(allowed: one of them)")
    if not names & {"case", "phase_diff_deg"}:
        raise ValueError("factors needs case or phase_diff_deg (the unbalance pattern; "
                         "a single level such as case = [1] fixes it)")
    if not names & {"speed_ratio", "speed_rpm"}:
        raise ValueError("factors needs speed_ratio or speed_rpm (a single level such as "
                         "speed_ratio = [1.0] fixes it)")
    if "speed_ratio" in names and "case" not in names:
        raise ValueError("factors.speed_ratio needs case (it is relative to the case's "
                         "critical speed); with phase_diff_deg give speed_rpm")
