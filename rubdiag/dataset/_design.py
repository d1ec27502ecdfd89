"""A dataset design: which runs to make. Frozen, picklable, read from TOML.

A design file has three tables::

    [base]
    rig = "paper"             # preset ("paper", "paper-pedestal"), a rig TOML path, or a rig
                              # table (the resolved form)
    duration_s = 2.3          # Run.duration_s (default 2.3; not with [ramp])
    discard_s = 0.3           # Run.discard_s (default 0.3)
    reduced = false           # true: every run simulates the reduced-order model
    reduction_cutoff_hz = 2000.0  # optional, implies reduced: the Craig–Bampton cutoff (Hz)
    step_error = 1e-5         # long steps' error tolerance (Run.step_error; 0: every step
                              # at most 10 µs); default DEFAULT_STEP_ERROR
    gravity_m_s2 = 9.81       # optional: gravity along -y in every run (default 0: none);
                              # with the fault settings (rubdiag.dataset._faults.FaultSettings)

    [ramp]                    # optional: every run sweeps its speed (rubdiag.dataset._ramp)
    rate_rpm_s = 300          # > 0
    span = 0.15               # from speed·(1 - span) to speed·(1 + span); 0 < span < 1
    direction = "up"          # "up" (a run-up, default) | "down" (a coast-down)

    [sampling]
    method = "lhs"            # "grid" (default) | "lhs" | "sobol" | "random"
    n = 200                   # design points; ignored by "grid" (the product of the levels)
    seed = 7                  # default 0
    replicates = 1            # start histories per design point (default 1, at most 65)

    [labels]                  # optional: the label thresholds (rubdiag.dataset._labels)
    severity_threshold = 1.37 # interference ratio from which a rub is serious
    full_contact_share = 0.95 # share of the window in contact from which a rub is full

    [noise]                   # optional: noise floors (rubdiag.dataset._noise), SI units
    displacement_m = 1e-6

    [[sensors]]               # optional, repeated: the channels (default: default_sensors)
    point = "shaft 11"
    direction = "y"
    quantity = "displacement" # | "velocity" | "acceleration" | "reaction"

    [factors]
    case = [1, 2]                              # a list: levels
    speed_ratio = {low = 0.8, high = 1.2}      # a table: a continuous range
                                               # ({bands = [[0.45, 0.55], [0.9, 1.1]]}:
                                               # separate bands, an equal share each)
    gap_mm = {low = 0.5, high = 4.0, n = 8}    # n: the grid's levels of a range
    fault = ["none", "rub", "crack"]           # optional: rubdiag.dataset._faults
    crack_depth_ratio = [0.25, 0.45]           # a fault's severity: only its runs

The factors, their physical ranges and the exclusive pairs are listed in
:mod:`rubdiag.dataset._factors`. A design needs an unbalance pattern (``case`` or
``phase_diff_deg``) and a speed (``speed_ratio`` or ``speed_rpm``); a single level
(``case = [1]``) fixes a factor. ``speed_ratio`` is relative to the case's critical speed, so
it needs ``case``. Factors not given keep the rig's values (its nominal gap, contact law,
casing support and unbalance magnitudes). A rig path is relative to the design file's folder.

**Sampling.** ``grid`` makes every combination of the levels (a range gives ``n`` equally
spaced levels, both ends included), the last factor varying fastest. ``lhs``, ``sobol`` and
``random`` draw ``n`` points in the unit hypercube (:func:`rubdiag.dataset._sampling.unit_samples`)
with one axis per factor that varies, in the canonical factor order whatever the order in the
file; single-level factors take no axis. Coordinate u of a range is ``low + u·(high-low)``;
of a factor with k levels it is level ``floor(u·k)``, so each level owns 1/k of the axis (with
``lhs`` and n a multiple of k, exactly n/k points each). Sampling needs at least one range
(levels alone would repeat points: use ``grid``); ``sobol`` needs n a power of 2.

**Replicates** are start histories as in :mod:`rubdiag.paper._ensemble`: replicate r has
gap-ramp length ``gap_ramps_s(replicates, duration_s)[r]`` — the standard 0.1 s, then
-1 %, +1 %, -2 %, +2 % (five replicates are the paper's ensemble), then halving steps inside
±2 % (:func:`rubdiag.dataset._sampling.ramp_offsets`). ``discard_s`` must be at least the
longest ramp, so that no analysis window holds the ramp's transient.

**Speed ramp.** With ``[ramp]`` (:mod:`rubdiag.dataset._ramp`) the design point's speed is
the middle of a sweep: each run holds ``speed·(1 ∓ span)`` for ``discard_s`` (its gap ramp,
the replicate's start history, happens there), then ramps at ``rate_rpm_s`` to
``speed·(1 ± span)`` and ends. Its length is derived — ``discard_s + 2·span·speed /
rate_rpm_s``, so ``base.duration_s`` is not given (an error names both keys) — its analysis
window is the whole ramp, and every replicate has the standard gap ramp (0.1 s, ±2 %,
``gap_ramps_s(replicates)``). The ramp must hold at least ``MIN_REVOLUTIONS`` +
``ORDER_TRACK_LOST_REVOLUTIONS`` (13) revolutions at the design's slowest speed: the
features are measured on the window's order-tracked record
(:func:`rubdiag.runs._features.order_tracked`), which loses up to 3 at its ends; and the
fastest speed must keep the features' 8.25× below 0.2 × the output rate
(:func:`~rubdiag.runs._features.max_tracked_rpm`: 14545 rpm at 10 kHz). Rows of a ramp
design say so (:mod:`rubdiag.dataset._rows`).

**Model.** ``reduced = true`` makes every run ``Run(..., reduction=Reduction())``: the
Craig–Bampton model of :mod:`rubdiag.reduce` with its default cutoff (2 kHz);
``reduction_cutoff_hz`` sets another cutoff and implies ``reduced`` (with ``reduced = false``
it is an error). Every row says which model made it (its ``model`` column).

**Steps.** Every run takes steps longer than its 10-µs base step where nothing is in contact
and the local error estimate allows (``Run.step_error``, relative to the largest recorded
displacement; up to 40 µs): ``step_error`` sets the tolerance, :data:`DEFAULT_STEP_ERROR`
by default, ``0`` keeps every step at 10 µs or shorter. A closed contact is always
integrated at 10 µs or shorter. With the default, against the same runs at 10 µs, the
labels are the same and the spectral features change by less than a quarter of the scatter
between start histories; a rubbing run's contact statistics, which are chaotic, change by
about that scatter (documentation: "Steps sized by error"). The resolved form writes it only when
it is not the default.

**Resolved form.** :meth:`Design.to_dict` / :meth:`Design.to_toml` write everything a run
depends on: the model (``reduced = true`` and the cutoff; nothing for the full model, so
that the resolved form of a design made before reductions existed is unchanged), the
``[ramp]`` table after ``[base]`` (only when set, and then no ``duration_s``), the rig
as a table (a rig file may change; a resolved design does not), the
factors in canonical order with numbers as floats, the grid's point count as ``n``, the
seed, and the critical speeds that ``speed_ratio`` refers to (``critical_speeds_rad_s``,
computed once from the rig, so that the resolved design makes bit-identical runs on any
machine). ``Design.from_toml(d.to_toml()) == d`` and the text round-trips exactly.

Every value is checked when the design is made, before any run, with one-line
``ValueError`` messages; what takes an eigenvalue search per rotor (each whirl rotor's
threshold of instability) when its runs are expanded (:meth:`Design.runs`), before any is
simulated.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from rubdiag import _check
from rubdiag.dataset._approach import approach_of
from rubdiag.dataset._factors import EXCLUSIVE, FACTORS, Factor
from rubdiag.dataset._faults import KEYS as FAULT_KEYS
from rubdiag.dataset._faults import (
    NO_RUB_GAP_M,
    FaultSettings,
    check_factors,
    check_whirl_rig,
    faults_in,
    shown_point,
)
from rubdiag.dataset._ids import run_ids
from rubdiag.dataset._labels import LabelRules
from rubdiag.dataset._noise import NoiseFloors
from rubdiag.dataset._ramp import KEYS as RAMP_KEYS
from rubdiag.dataset._ramp import SpeedRamp
from rubdiag.dataset._resolve import (
    Workers,
    critical_speeds_rad_s,
    resolve_rotors,
    start_approaches,
    whirl_threshold_rad_s,
)
from rubdiag.dataset._rig_factors import (
    CRITICAL_FACTORS,
    THRESHOLD_FACTORS,
    blade_set_of,
    check_rig_factors,
    varied_rig,
    with_rubbing_blades,
)
from rubdiag.dataset._sampling import (
    MAX_REPLICATES,
    METHODS,
    check_sobol_n,
    gap_ramps_s,
    unit_samples,
)
from rubdiag.model._rig import Rig, StatorContact, Unbalance
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, Sensor, default_sensors
from rubdiag.simulation._sensors import check_sensors

__all__ = ["DEFAULT_STEP_ERROR", "MIN_REVOLUTIONS", "Design", "DesignRun", "describe_point"]

#: Revolutions the analysis window must hold (the spectral features' default minimum).
MIN_REVOLUTIONS = 10.0
#: ``base.duration_s`` of a constant-speed design that does not give it (s).
DEFAULT_DURATION_S = 2.3
#: ``base.step_error`` of a design that does not give it: the tolerance of the runs' long
#: steps, relative to the largest recorded displacement (``Run.step_error``)
DEFAULT_STEP_ERROR = 1e-5

_SECTIONS = {
    "base": ("rig", "duration_s", "discard_s", "reduced", "reduction_cutoff_hz",
             "step_error", "critical_speeds_rad_s", *FAULT_KEYS),
    "ramp": RAMP_KEYS,
    "sampling": ("method", "n", "seed", "replicates"),
    "factors": tuple(FACTORS),
    "labels": ("severity_threshold", "full_contact_share"),
    "noise": ("displacement_m", "velocity_m_s", "acceleration_m_s2", "force_n"),
    "sensors": ("point", "direction", "quantity", "name"),
}


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


@dataclass(frozen=True)
class Design:
    """Which runs to make (see the module docstring for the TOML form and the rules).

    ``factors`` may be given as a mapping name -> TOML form (a list of levels or
    ``{"low", "high"[, "n"]}``) or as :class:`~rubdiag.dataset._factors.Factor` objects; it is
    kept as a tuple of factors in canonical order. ``n`` is the number of design points
    (required by the sampling methods; for ``grid`` it is set to the product of the levels).
    ``critical_speeds_rad_s[c-1]`` is case c's reference speed of ``speed_ratio``; computed
    from the rig when ``None`` and needed. ``reduction`` (a
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
        Reference speed of ``speed_ratio`` per case (rad/s).
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
        set_("critical_speeds_rad_s", self._critical_speeds())
        self._check_window()

    def _check_rub_kinds(self, names: set[str]) -> None:
        """The blade sets need a rig whose contact blades follow one; a seal rub needs a rig
        without stator contacts of its own, and takes the rig's contact law."""
        if names & {"blade_count", "rubbing_blades"}:
            blade_set_of(self.rig)
        if self._seal() is None:
            return
        if self.rig.stator_contacts:
            raise ValueError(f"factors.rub_kind 'seal' with base.rig = {self.rig.name!r}, which "
                             "has stator contacts (allowed: a rig without: the design adds "
                             "its seal at base.seal_node)")
        law = sorted(names & {"mu", "normal_stiffness_n_m", "contact_stiffness_scale"})
        if law:
            raise ValueError(f"factors.{law[0]} with factors.rub_kind 'seal' (allowed: no "
                             "contact-law factor: the seal takes the rig's contact law)")

    def _seal(self) -> StatorContact | None:
        """The annular seal every run of a design with seal rubs has (its clearance out of
        reach, :data:`NO_RUB_GAP_M`, unless the run's ``seal_clearance_m`` sets it), or
        None. Its contact law is the rig's blade contact's (k_N, μ)."""
        kinds = next((f.levels for f in self.factors if f.name == "rub_kind"), ())
        if "seal" not in kinds:
            return None
        node = self.fault_settings.seal_node
        if node is None:
            discs = sorted(d.node for d in self.rig.discs)
            node = (discs[0] + discs[-1]) // 2
        if node not in self.rig.shaft.nodes:
            nodes = self.rig.shaft.nodes
            raise ValueError(f"base.seal_node = {node} is not a shaft node (allowed: "
                             f"{nodes.start}..{nodes.stop - 1})")
        law = self.rig.contact
        return StatorContact(node=node, clearance_m=NO_RUB_GAP_M,
                             stiffness_n_m=law.normal_stiffness_n_m,
                             friction_coefficient=law.friction_coefficient)

    def _check_window(self) -> None:
        """The analysis window must hold MIN_REVOLUTIONS at the slowest speed of the design
        (checked from the factors' bounds, without building the runs)."""
        by_name = {f.name: f for f in self.factors}
        if "speed_rpm" in by_name:
            slowest = _lowest(by_name["speed_rpm"]) * math.pi / 30.0
        else:
            cases = by_name["case"].levels
            slowest = _lowest(by_name["speed_ratio"]) * min(
                self.critical_speeds_rad_s[c - 1] for c in cases)
        _check_revolutions(self.duration_s, self.discard_s, self.ramp, slowest)

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

    def _critical_speeds(self) -> tuple[float, ...] | None:
        speeds = self.critical_speeds_rad_s
        if speeds is not None:
            speeds = _check.numbers("base.critical_speeds_rad_s", speeds)
        by_name = {f.name: f for f in self.factors}
        if "speed_ratio" not in by_name:
            return speeds
        n_cases = max(by_name["case"].levels)     # speed_ratio needs case (checked above)
        if speeds is None:
            speeds = _rig_critical_speeds(self.rig, n_cases)
        elif len(speeds) < n_cases:
            raise ValueError(f"base.critical_speeds_rad_s has {len(speeds)} entries "
                             f"(allowed: one per case, at least {n_cases})")
        return speeds

    # --- reading and writing ---------------------------------------------------------------
    @classmethod
    def from_toml(cls, source: str | Path) -> Design:
        """A design from a TOML file (a :class:`~pathlib.Path`, or a string without ``=``
        or a line break) or from TOML text (a string with one)."""
        is_text = isinstance(source, str) and ("\n" in source or "=" in source)
        if is_text:
            text, root, prefix = source, None, ""
        else:
            path = Path(source)
            text, root, prefix = path.read_text(encoding="utf-8"), path.parent, f"{path.name}: "
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"{prefix}not valid TOML ({exc})") from None
        try:
            return cls.from_dict(data, root=root)
        except ValueError as exc:
            raise ValueError(f"{prefix}{exc}") from None

    @classmethod
    def from_dict(cls, data: Mapping, root: str | Path | None = None) -> Design:
        """A design from parsed TOML (tables ``base``, ``sampling``, ``factors``); a rig path
        is relative to ``root`` (default: the working folder)."""
        if not isinstance(data, Mapping):
            raise _check.wrong_type("design", data, "a table")
        for section, value in data.items():
            if section not in _SECTIONS:
                raise ValueError(f"unknown table [{section}] (allowed: "
                                 f"{', '.join(_SECTIONS)})")
            tables = value if section == "sensors" and isinstance(value, list) else [value]
            for table in tables:
                if not isinstance(table, Mapping):
                    raise _check.wrong_type(section, table, "a table")
                for key in table:
                    if key not in _SECTIONS[section]:
                        what = "factor" if section == "factors" else "key"
                        raise ValueError(f"unknown {what} '{section}.{key}' "
                                         f"(allowed: {', '.join(_SECTIONS[section])})")
        base = dict(data.get("base", {}))
        if "ramp" in data:
            base["ramp"] = SpeedRamp.from_dict(data["ramp"])
        base["rig"] = _rig(base.get("rig", "paper"), root)
        base["reduction"] = _reduction(base.pop("reduced", None),
                                       base.pop("reduction_cutoff_hz", None))
        factors = tuple(Factor.from_spec(k, v) for k, v in data.get("factors", {}).items())
        base["fault_settings"] = FaultSettings(**{k: base.pop(k) for k in FAULT_KEYS
                                                  if k in base})
        sensors = data.get("sensors")
        if isinstance(sensors, Mapping):
            sensors = [sensors]
        return cls(factors=factors, **base, **data.get("sampling", {}),
                   labels=LabelRules(**data.get("labels", {})),
                   noise=NoiseFloors(**data.get("noise", {})), sensors=sensors)

    def to_dict(self) -> dict:
        """The resolved design as plain TOML-ready data (see the module docstring)."""
        from rubdiag.model._io import rig_to_dict

        base = {"duration_s": self.duration_s, "discard_s": self.discard_s}
        if self.ramp is not None:
            del base["duration_s"]          # derived, run by run
        if self.reduction is not None:
            base["reduced"] = True
            base["reduction_cutoff_hz"] = float(self.reduction.cutoff_hz)
        if self.step_error != DEFAULT_STEP_ERROR:
            base["step_error"] = self.step_error
        base.update(self.fault_settings.to_dict())     # only what differs from the defaults
        if self.critical_speeds_rad_s is not None:
            base["critical_speeds_rad_s"] = list(self.critical_speeds_rad_s)
        base["rig"] = rig_to_dict(self.rig)
        ramp = {} if self.ramp is None else {"ramp": self.ramp.to_dict()}
        return {"base": base, **ramp,
                "sampling": {"method": self.method, "n": self.n, "seed": self.seed,
                             "replicates": self.replicates},
                "factors": {f.name: f.to_spec() for f in self.factors},
                "labels": self.labels.to_dict(),
                "noise": self.noise.to_dict(),
                "sensors": [dataclasses.asdict(s) for s in self.sensors]}

    def to_toml(self) -> str:
        """The resolved design as TOML text: ``[base]``, ``[sampling]`` and ``[factors]`` as
        a person writes them, then the rig as ``[base.rig]``."""
        import tomli_w

        data = self.to_dict()
        rig = data["base"].pop("rig")
        lines = ["# rubdiag dataset design, resolved: everything its runs depend on is written",
                 "# out (the rig itself, the point count, the seed, speed_ratio's reference",
                 "# speeds), so that the same runs can be made again anywhere."]
        sensors = data.pop("sensors")
        for section, table in data.items():
            lines += ["", f"[{section}]"]
            lines += [f"{key} = {_toml_value(value)}" for key, value in table.items()]
        for sensor in sensors:
            lines += ["", "[[sensors]]"]
            lines += [f"{key} = {_toml_value(value)}" for key, value in sensor.items()]
        return "\n".join(lines) + "\n\n" + tomli_w.dumps({"base": {"rig": rig}})

    # --- the runs ---------------------------------------------------------------------------
    @property
    def n_runs(self) -> int:
        return self.n * self.replicates

    def points(self) -> list[dict]:
        """The design points: factor name -> value (canonical order), without replicates."""
        if self.method == "grid":
            names = [f.name for f in self.factors]
            return [dict(zip(names, values, strict=True))
                    for values in itertools.product(*(f.grid_levels() for f in self.factors))]
        axes = [f for f in self.factors if not f.is_constant]
        u = unit_samples(self.method, self.n, len(axes), self.seed)
        points = []
        for row in u:
            coordinate = dict(zip((f.name for f in axes), row.tolist(), strict=True))
            points.append({f.name: f.levels[0] if f.is_constant else f.from_unit(
                coordinate[f.name]) for f in self.factors})
        return points

    def runs(self, jobs: int | None = 1) -> list[DesignRun]:
        """Every run of the design, point by point, each point's replicates together. Every
        run is built (and so checked) here, before any is simulated. What the runs refer
        to — each distinct rotor's critical speeds and threshold of instability, the rub
        runs' linear approaches — is computed once, on ``jobs`` worker processes (None:
        every core; :mod:`rubdiag.dataset._resolve`): the same runs on any number. A point
        that cannot be made is named (the first in the design's order)."""
        points = self.points()
        whirl = ["whirl" in faults_in(p.get("fault", "none")) for p in points]
        built: dict[int, list | ValueError] = {}    # index -> [(replicate, run, ratio)]
        with Workers(jobs) as workers:
            thresholds = resolve_rotors(*self._rotors(points), workers)
            # the points without whirl while the workers seek the thresholds, then the rest
            self._build(points, [k for k, w in enumerate(whirl) if not w], built)
            approaches = [self._start_approaches(built, workers)]
            thresholds()
            self._build(points, [k for k, w in enumerate(whirl) if w], built)
            approaches.append(self._start_approaches(
                {k: built[k] for k, w in enumerate(whirl) if w}, workers))
            # the runs without an approach to wait for are made while the workers work
            made = {(k, replicate): self._item(points[k], replicate, run)
                    for k, runs in built.items() if not isinstance(runs, ValueError)
                    for replicate, run, ratio in runs if ratio is None}
            found = {k: value for wait in approaches for k, value in wait().items()}
        out, seen = [], {}
        for index, point in enumerate(points):
            try:
                if isinstance(built[index], ValueError):
                    raise built[index]
                for replicate, run, ratio in built[index]:
                    item = (made[(index, replicate)] if ratio is None else self._item(
                        point, replicate, _gap_from_interference(run, ratio, found[index])))
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

    def _build(self, points: list, indices, built: dict) -> None:
        """The runs of the points ``indices`` into ``built`` (index -> [(replicate, run,
        interference ratio or None)], or the ValueError making one raised)."""
        for k in indices:
            try:
                built[k] = [(r, *self._run(points[k], r)) for r in range(self.replicates)]
            except ValueError as exc:
                built[k] = exc

    @staticmethod
    def _start_approaches(built: dict, workers: Workers):
        """Start the linear approaches of the points of ``built`` whose gap is set from
        one (a point's replicates share it); the returned function waits for them: index
        -> approach (m) or the ValueError computing it raised."""
        wanted = {k: runs[0][1] for k, runs in built.items()
                  if not isinstance(runs, ValueError) and runs[0][2] is not None}
        found = start_approaches(list(wanted.values()), workers,
                                 [approach_of(run) for run in wanted.values()])
        return lambda: dict(zip(wanted, found(), strict=True))

    def design_run(self, index: int, replicate: int = 0) -> DesignRun:
        """The run ``runs()[index * replicates + replicate]`` alone: design point ``index``,
        with what it refers to computed for it only (a dry run's example)."""
        points = self.points()
        index = _check.integer("index", index, lo=0, hi=len(points) - 1)
        point = points[index]
        try:
            run = self.run_for(point, replicate)
        except ValueError as exc:
            raise ValueError(f"point {index} ({describe_point(point)}): {exc}") from None
        return self._item(point, replicate, run)

    def _item(self, point: Mapping, replicate: int, run: Run) -> DesignRun:
        run_id, point_id = run_ids(run)
        return DesignRun(self._shown(point), replicate, run, point_id, run_id,
                         self._speed_rad_s(point) * 30.0 / math.pi, self.ramp)

    def _rotors(self, points) -> tuple[list, list]:
        """The rotors the points' speeds refer to: (critical speeds wanted, as (rig, case)
        pairs; thresholds wanted, as (rig, the same rotor with the design's damping))."""
        critical, thresholds = [], []
        for point in points:
            whirl = "whirl" in faults_in(point.get("fault", "none"))
            if whirl:
                thresholds.append((_rotor_rig(self.rig, point, THRESHOLD_FACTORS),
                                   _rotor_rig(self.rig, point, CRITICAL_FACTORS)))
            if "speed_ratio" in point and any(name in point for name in CRITICAL_FACTORS):
                critical.append((_rotor_rig(self.rig, point, CRITICAL_FACTORS), point["case"]))
        return critical, thresholds

    def _shown(self, point: Mapping) -> dict:
        """The point as its row shows it (:func:`~rubdiag.dataset._faults.shown_point`); a
        run with whirl shows as ``speed_ratio`` the speed it turned at over its case's
        critical speed, so that a split by speed band places it by its speed too."""
        shown = shown_point(point)
        if "whirl" in faults_in(point.get("fault", "none")) and "speed_ratio" in point:
            shown["speed_ratio"] = self._speed_rad_s(point) / self.critical_speed_rad_s(point)
        return shown

    def _speed_rad_s(self, point: Mapping) -> float:
        """The design point's speed (rad/s): with a ramp, the middle of the sweep; with
        whirl, ``whirl_speed_ratio`` times the threshold of instability of the point's rig;
        else ``speed_ratio`` times its rig's critical speed for the case (the design's
        ``critical_speeds_rad_s`` unless a model-uncertainty factor moves it), or
        ``speed_rpm``."""
        if "whirl" in faults_in(point.get("fault", "none")):
            return point["whirl_speed_ratio"] * self.whirl_threshold_rad_s(point)
        if "speed_ratio" in point:
            return point["speed_ratio"] * self.critical_speed_rad_s(point)
        return point["speed_rpm"] * math.pi / 30.0

    def whirl_threshold_rad_s(self, point: Mapping) -> float:
        """The threshold of instability (rad/s) of ``point``'s rig, which its
        ``whirl_speed_ratio`` multiplies (rounded to 10 significant digits, as
        :meth:`critical_speed_rad_s`, when a model-uncertainty factor moves it)."""
        threshold = whirl_threshold_rad_s(_rotor_rig(self.rig, point, THRESHOLD_FACTORS),
                                          _rotor_rig(self.rig, point, CRITICAL_FACTORS))
        if not any(name in point for name in THRESHOLD_FACTORS):
            return threshold
        return float(f"{threshold:.10g}")

    def critical_speed_rad_s(self, point: Mapping) -> float:
        """The reference speed of ``point``'s ``speed_ratio``: its case's critical speed on
        the point's own rig. A factor that moves the critical speeds (disc mass, the films'
        viscosity and clearance) gets it from that rig's critical speed map, rounded to 10
        significant digits so that a run's speed (and id) is the same on every machine;
        otherwise it is the design's ``critical_speeds_rad_s``."""
        if not any(name in point for name in CRITICAL_FACTORS):
            return self.critical_speeds_rad_s[point["case"] - 1]
        rig = _rotor_rig(self.rig, point, CRITICAL_FACTORS)
        return float(f"{_case_critical_speed(rig, point['case']):.10g}")

    def run_for(self, point: Mapping, replicate: int = 0) -> Run:
        """The :class:`~rubdiag.simulation.Run` of design point ``point`` (factor name ->
        value, as :meth:`points` gives) and replicate ``replicate``."""
        run, ratio = self._run(point, replicate)
        if ratio is None:
            return run
        from rubdiag.dataset._approach import sweep_linear_approach_m

        return _gap_from_interference(run, ratio,
                                      sweep_linear_approach_m(run, of=approach_of(run)))

    def _run(self, point: Mapping, replicate: int) -> tuple[Run, float | None]:
        """The run of :meth:`run_for` and its ``interference_ratio``, or None: then it is
        the run; else its gap is still to be set from its linear approach."""
        replicate = _check.integer("replicate", replicate, lo=0, hi=self.replicates - 1)
        ramp_s = gap_ramps_s(self.replicates, self.duration_s)[replicate]
        rig = self.rig
        loading = rig.loading
        scale = point.get("unbalance_scale")
        magnitudes = (loading.unbalance_kg_m if scale is None
                      else tuple(m * scale for m in loading.unbalance_kg_m))
        if "case" in point:
            phases = loading.case(point["case"]).phases_rad
        else:
            step = math.radians(point["phase_diff_deg"])
            phases = tuple(step * (j % 2) for j in range(len(magnitudes)))
        speed = self._speed_rad_s(point)
        rig = varied_rig(rig, point)
        rub = "rub" in faults_in(point.get("fault", "rub"))
        seal_rub = rub and point.get("rub_kind") == "seal"
        blade_rub = rub and not seal_rub
        if blade_rub and "rubbing_blades" in point:
            rig = with_rubbing_blades(rig, point["rubbing_blades"])
        seal = self._seal()
        seal_clearance = None
        if seal is not None:
            rig = dataclasses.replace(rig, stator_contacts=(seal,))
        if seal_rub:    # its clearance, or out of reach until its approach sets it
            seal_clearance = (point["gap_mm"] * 1e-3 if "gap_mm" in point
                              else NO_RUB_GAP_M)
        gap = point.get("gap_mm") if blade_rub else NO_RUB_GAP_M * 1e3  # out of reach
        options = {}
        faults = self.fault_settings.faults(point)
        if faults is not None:
            options["faults"] = faults
        static_load = self.fault_settings.static_load()
        if static_load is not None:
            options["static_load"] = static_load
        _check_revolutions(self.duration_s, self.discard_s, self.ramp, speed)
        duration = self.duration_s
        if self.ramp is not None:
            profile = self.ramp.profile(speed * 30.0 / math.pi, hold_s=self.discard_s)
            speed, duration = profile.start_rad_s, profile.end_s
            options["speed_profile"] = profile
        run = Run(rig=rig, speed_rad_s=speed, unbalance=Unbalance(magnitudes, phases),
                  gap_m=None if gap is None else gap * 1e-3, duration_s=duration,
                  discard_s=self.discard_s,
                  contact=_contact(rig, point) if blade_rub else None,
                  gap_ramp_s=ramp_s, seal_clearance_m=seal_clearance,
                  sensors=self.sensors, reduction=self.reduction,
                  step_error=self.step_error or None,
                  label=f"{describe_point(shown_point(point))}, replicate {replicate}", **options)
        if self.ramp is not None:
            _check_top_speed(run)
        return run, point.get("interference_ratio") if rub else None


def _lowest(factor: Factor) -> float:
    return min(factor.levels) if factor.levels is not None else factor.low


def _check_revolutions(duration_s: float | None, discard_s: float, ramp: SpeedRamp | None,
                       speed_rad_s: float) -> None:
    """The analysis window at ``speed_rad_s`` (the design's slowest) must hold
    MIN_REVOLUTIONS; a ramp's, also the revolutions its order tracking takes off."""
    rpm = speed_rad_s * 30.0 / math.pi
    if ramp is None:
        window_s, needed = duration_s - discard_s, MIN_REVOLUTIONS
        what = f"the analysis window (base.duration_s - base.discard_s = {window_s:g} s)"
        why = "for the spectral features"
    else:
        window_s = ramp.sweep_s(rpm)     # a linear sweep's mean speed is its middle
        # the features' module brings the signal layer: imported for ramp designs only
        from rubdiag.runs._features import ORDER_TRACK_LOST_REVOLUTIONS

        needed = MIN_REVOLUTIONS + ORDER_TRACK_LOST_REVOLUTIONS
        what = f"the ramp (2·ramp.span·speed / ramp.rate_rpm_s = {window_s:.4g} s)"
        why = ("for the spectral features of its order-tracked record; lower ramp.rate_rpm_s "
               "or widen ramp.span")
    revolutions = window_s * rpm / 60.0
    if revolutions < needed * (1 - 1e-12):
        digits = 3                  # as few as show it short: never "holds 10 … at least 10"
        while float(f"{revolutions:.{digits}g}") >= needed and digits < 17:
            digits += 1
        raise ValueError(f"{what} holds {revolutions:.{digits}g} revolutions at "
                         f"{rpm:.{max(6, digits + 1)}g} rpm, the design's slowest speed "
                         f"(allowed: at least {needed:g}, {why})")


def _check_top_speed(run: Run) -> None:
    from rubdiag.runs._features import max_tracked_rpm

    top = max(run.speed_profile.speeds_rad_s) * 30.0 / math.pi
    fastest = max_tracked_rpm(run.output_rate_hz)
    if top > fastest:
        raise ValueError(f"the ramp reaches {top:.6g} rpm (allowed: at most {fastest:.6g} rpm "
                         f"at the output rate {run.output_rate_hz:g} Hz, for the features of "
                         "the order-tracked record; lower ramp.span or the speed)")


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


def _rig_critical_speeds(rig: Rig, n_cases: int) -> tuple[float, ...]:
    """The reference speeds of cases 1 … n_cases (an eigenvalue problem each: kept)."""
    return tuple(_case_critical_speed(rig, c) for c in range(1, n_cases + 1))


def _case_critical_speed(rig: Rig, case: int) -> float:
    """The forward critical speed (rad/s) case ``case`` excites on ``rig``, as
    :func:`rubdiag.simulation.critical_speed_for_case` (kept per rig:
    :mod:`rubdiag.dataset._resolve`)."""
    speeds = critical_speeds_rad_s(rig, case)
    if len(speeds) < case:
        raise ValueError(f"the rig has no forward critical speed number {case}")
    return float(speeds[case - 1])


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


def _rig(value, root) -> Rig:
    from rubdiag.model import PRESETS, load_rig, preset_rig, rig_from_dict

    if isinstance(value, Rig):
        return value
    if isinstance(value, Mapping):
        try:
            return rig_from_dict(dict(value))
        except ValueError as exc:
            raise ValueError(f"base.rig: {exc}") from None
    if not isinstance(value, str):
        raise _check.wrong_type("base.rig", value, "a preset name, a rig TOML path or a table")
    if value in PRESETS:
        return preset_rig(value)
    path = Path(value) if root is None else Path(root) / value
    if not path.is_file():
        raise ValueError(f"base.rig = {value!r} is neither a preset nor a file (allowed: "
                         f"{', '.join(map(repr, PRESETS))} or a rig TOML path)")
    try:
        return load_rig(path)
    except ValueError as exc:
        raise ValueError(f"base.rig: {exc}") from None


def _reduction(reduced, cutoff_hz) -> Reduction | None:
    """The reduction of ``[base] reduced`` and ``reduction_cutoff_hz`` (see the module
    docstring), or None: the full model."""
    if reduced is not None and not isinstance(reduced, bool):
        raise _check.wrong_type("base.reduced", reduced, "true or false")
    if cutoff_hz is None:
        return Reduction() if reduced else None
    if reduced is False:
        raise ValueError(f"base.reduction_cutoff_hz = {_check.plain(cutoff_hz)} is given with "
                         "base.reduced = false (allowed: reduced = true, or no "
                         "reduction_cutoff_hz for the full model)")
    try:
        return Reduction(cutoff_hz=cutoff_hz)
    except ValueError as exc:      # "cutoff_hz = … is out of range": name the design's key
        text = str(exc)
        raise type(exc)(f"base.reduction_{text}" if text.startswith("cutoff_hz")
                        else f"base.reduction_cutoff_hz: {text}") from None


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
    raised) / ``ratio``, rounded to 1 nm so that the run's id is the same on every
    machine."""
    if isinstance(approach, ValueError):
        raise approach
    gap = round(approach / ratio, 9)
    if gap <= 0.0:
        raise ValueError(f"factors.interference_ratio = {ratio:g}: the run's linear approach "
                         "is 0 (no unbalance response reaches the blades)")
    if approach_of(run) == "seals":
        return dataclasses.replace(run, seal_clearance_m=gap)
    return dataclasses.replace(run, gap_m=gap)


def describe_point(point: Mapping) -> str:
    """``name = value, …`` of a design point, leaving out what its run ignores."""
    return ", ".join(f"{k} = {v}" if isinstance(v, str) else f"{k} = {v:.6g}"
                     for k, v in point.items()
                     if v is not None and not (isinstance(v, float) and math.isnan(v)))


def _toml_value(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value)   # int, or float in its shortest round-trip form (valid TOML)
