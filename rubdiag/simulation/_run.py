"""A rub-impact run of a rig: a frozen, picklable description (the input of ``simulate``).

A :class:`Run` holds everything that determines the result — the rig, the speed, the
unbalance, the blade-casing gap, the time window, the step sizes, the output rate, the
contact law and the model (full, or reduced by a :class:`~rubdiag.reduce.Reduction`) — so
that a run is a pure function of its description: ``simulate(run)`` twice gives the same
arrays, on any machine or Dask worker.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from rubdiag import _check
from rubdiag._tolerances import BOUND_SLACK, ON_LEVEL
from rubdiag.model import BladeContact, Rig, Unbalance
from rubdiag.reduce import Reduction
from rubdiag.simulation._described import WHEN_SET
from rubdiag.simulation._faults import Faults
from rubdiag.simulation._sensors import Sensor, check_sensors
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._static_load import StaticLoad

__all__ = ["LONG_STEP_FACTOR", "SPEED_TOLERANCE", "GapRampInWindow", "Run",
           "critical_speed_for_case"]

#: How far Ω(t) may move from the speed its gyroscopic term is held at before the step
#: operators are refactorised (relative; ``tests/simulation/test_speed_profile.py`` measures
#: the effect against refactorising at every step).
SPEED_TOLERANCE = 0.005
#: the longest step with a step-error tolerance, in base steps: 40 µs at dt_s = 10 µs. Steps
#: end at every 10-kHz sample (100 µs) and start aligned to their length, so they come as
#: 40, 40, 20 | 20, 40, 40 µs per 200 µs; the 10-kHz
#: stream's anti-alias filter (cut-off 4 kHz) would allow about 50 µs; the average
#: acceleration rule's period error, (ω h)² / 12, is 0.44 % at 40 µs for the features'
#: highest line (8× at 6840 rpm, 912 Hz), and the error estimate keeps the rest in check
LONG_STEP_FACTOR = 4
#: how far 1 / (output_rate_hz dt_s) may lie from its whole number (relative): a rate typed
#: to seven digits (3333.333 Hz at dt_s = 10 µs) still names its divisor of 1/dt_s
_TYPED_RATE = 1e-6


class GapRampInWindow(UserWarning):
    """The analysis window of a run starts before its gap ramp ends."""


@dataclass(frozen=True)
class Run:
    """One simulation of a rig at constant speed, or along a speed profile; SI units.

    Parameters
    ----------
    rig : Rig
        The machine. Blade-casing contacts come from ``contact`` (or ``rig.contact``),
        shaft-stator rubs from ``rig.stator_contacts``.
    speed_rad_s : float
        Spin speed Ω (rad/s); with ``speed_profile``, its start speed.
    unbalance : Unbalance
        Per-disc unbalance magnitude (kg·m) and phase (rad); ``rig.unbalance(case)`` gives the
        study's patterns.
    gap_m : float, optional
        Initial blade-tip/casing gap g0 (m) of every contact element; default the rig's
        nominal gap. The casing geometry is the rig's; g0 enters the contact law only.
    seal_clearance_m : float, optional
        The radial clearance (m) of every stator contact (seal) of the rig; default each
        its own ``StatorContact.clearance_m``. Like ``gap_m`` it enters the contact law
        only, so runs that differ in it share one model (and one reduced model). Part of
        the run's description only when set.
    duration_s : float
        Total simulated time (s), default 2.3.
    discard_s : float
        Start of the analysis window (s), default 0.3: statistics and spectra use
        ``discard_s <= t <= duration_s``.
    dt_s, dt_min_s : float
        Base and smallest time step (s); default 1e-5 and dt/64. The base step is the first,
        the longest while a contact is closed, and the sensor stream's interval.
    step_error : float, optional
        Steps longer than ``dt_s`` where nothing is in contact: the tolerance of the Newmark
        local error estimate on the recorded and sensor DOFs and the contacts' local
        coordinates, relative to the largest recorded displacement (``Solver.step_error``
        of :func:`~rubdiag.simulation.simulate_system`). Default None: every step at most
        ``dt_s``. Part of the run's description only when set.
    dt_max_s : float, optional
        The longest step with ``step_error`` (s): ``dt_s`` times 1, 2, 4 or 8; default
        :data:`LONG_STEP_FACTOR` × ``dt_s``.
    fixed_step : bool
        Constant step ``dt_s`` (convergence studies).
    output_rate_hz : float, optional
        Waveform sampling rate (Hz); ``1/(output_rate_hz·dt_s)`` must be an integer. Default
        10 kHz (or 1/dt_s when the step is longer than 0.1 ms). Contact events are
        gathered at every step whatever the output rate.
    contact : BladeContact, optional
        Contact law and which blades touch (default ``rig.contact``): k_N, k_T, μ,
        augmentation and ε.
    gap_ramp_s : float
        Time (s) over which the gap closes linearly from just above the linear response
        amplitude down to g0, so that the run does not start ~1 mm deep in the casing
        (default 0.1 s, or half the duration for runs shorter than 0.2 s; 0 applies g0 at
        once).
    sensors : tuple of Sensor
        Channels recorded as a plant's sensors would measure them (displacement, velocity,
        acceleration of any DOF, bearing reactions), anti-alias filtered to the output rate
        (:mod:`rubdiag.simulation._sensors`; ``default_sensors(rig)`` is a typical set).
        Default: none.
    label : str
        Free text carried into results and tables.
    reduction : Reduction, optional
        Simulate a reduced-order model instead of the full one (default None: the full
        finite-element model). A :class:`~rubdiag.reduce.Reduction` keeps the blade-tip and
        casing DOFs of the contact elements physical and represents everything linear by
        its fixed-interface (Craig–Bampton) modes below ``cutoff_hz``. The default cutoff,
        2 kHz, is twice the 8× line at 6840 rpm (1824 Hz) rounded up: 6840 rpm tops the
        shipped designs' speed ranges, 8× is the feature layer's highest order
        (``Reduction.for_features`` derives a cutoff for other speeds). The reduction is
        part of the run's identity: a reduced run and the full run of the same cell are
        different simulations, with different results, result files and run ids.
    speed_profile : SpeedProfile, optional
        A speed that changes in time — a run-up, a coast-down, a measured speed curve
        (:class:`~rubdiag.simulation._speed_profile.SpeedProfile`); default None: constant
        ``speed_rad_s``, which must then be the profile's start speed. The run starts from
        the linear steady state at that speed; the unbalance follows the shaft angle
        φ(t) = ∫ Ω dt with its angular-acceleration term, the gyroscopic term follows Ω(t)
        (held within ``SPEED_TOLERANCE`` of it, relative).
    static_load : StaticLoad, optional
        Gravity along y or z on every mass, and/or a side load at one node
        (:class:`~rubdiag.simulation._static_load.StaticLoad`); default None: none, as in the
        study. The run starts from its static deflection ``K⁻¹ f`` added to the linear
        steady state. Like the reduction and the speed profile it is part of the run's
        description only when set, so a run without it keeps its ids.
    faults : Faults, optional
        Faults beside (or instead of) rub: a misaligned coupling, a breathing crack
        (:class:`~rubdiag.simulation._faults.Faults`); default None. Part of the run's
        description only when set. On a reduced model their nodes stay physical.
    """

    rig: Rig
    speed_rad_s: float
    unbalance: Unbalance
    gap_m: float | None = None
    duration_s: float = 2.3
    discard_s: float = 0.3
    dt_s: float = 1e-5
    dt_min_s: float | None = None
    fixed_step: bool = False
    output_rate_hz: float | None = None
    contact: BladeContact | None = None
    gap_ramp_s: float | None = None
    sensors: tuple[Sensor, ...] = ()
    label: str = ""
    # added after the first release: a run without them keeps its description and ids
    reduction: Reduction | None = field(default=None, metadata=WHEN_SET)
    speed_profile: SpeedProfile | None = field(default=None, metadata=WHEN_SET)
    static_load: StaticLoad | None = field(default=None, metadata=WHEN_SET)
    faults: Faults | None = field(default=None, metadata=WHEN_SET)
    step_error: float | None = field(default=None, metadata=WHEN_SET)
    dt_max_s: float | None = field(default=None, metadata=WHEN_SET)
    seal_clearance_m: float | None = field(default=None, metadata=WHEN_SET)

    def __post_init__(self):
        if not isinstance(self.rig, Rig):
            raise _check.wrong_type("rig", type(self.rig).__name__, "a Rig")
        if self.faults is not None:
            if not isinstance(self.faults, Faults):
                raise _check.wrong_type("faults", type(self.faults).__name__,
                                        "a Faults or None")
            self.faults.check(self.rig)
        if self.reduction is not None and not isinstance(self.reduction, Reduction):
            raise _check.wrong_type("reduction", type(self.reduction).__name__,
                                    "a Reduction or None")
        _check.number("speed_rad_s", self.speed_rad_s, lo=0.0, hi=1e5, lo_open=True)
        if self.speed_profile is not None:
            if not isinstance(self.speed_profile, SpeedProfile):
                raise _check.wrong_type("speed_profile", type(self.speed_profile).__name__,
                                        "a SpeedProfile or None")
            start = self.speed_profile.start_rad_s
            if not math.isclose(self.speed_rad_s, start, rel_tol=BOUND_SLACK):
                raise ValueError(f"speed_rad_s = {self.speed_rad_s:g} (allowed: the speed "
                                 f"profile's start speed, {start:g} rad/s)")
        if len(self.unbalance.magnitudes_kg_m) != len(self.rig.discs):
            raise ValueError(f"unbalance has {len(self.unbalance.magnitudes_kg_m)} entries "
                             f"(allowed: one per disc, {len(self.rig.discs)})")
        if self.gap_m is None and self.contact_law is not None:
            object.__setattr__(self, "gap_m", self.rig.nominal_gap_m())
        if self.gap_m is not None:
            _check.number("gap_m", self.gap_m, lo=0.0, hi=0.1)
        if self.seal_clearance_m is not None:
            if not self.rig.stator_contacts:
                raise ValueError("seal_clearance_m is given but the rig has no stator contact "
                                 "(allowed: None, or a rig with stator_contacts)")
            _check.number("seal_clearance_m", self.seal_clearance_m, lo=0.0, hi=0.1,
                          lo_open=True)
        _check.positive("dt_s", self.dt_s)
        if self.dt_min_s is None:
            object.__setattr__(self, "dt_min_s", self.dt_s / 64)
        _check.number("dt_min_s", self.dt_min_s, lo=0.0, hi=self.dt_s, lo_open=True)
        self._check_long_steps()
        _check.number("duration_s", self.duration_s, lo=self.dt_s)
        _check.number("discard_s", self.discard_s, lo=0.0, hi=self.duration_s, hi_open=True)
        if self.output_rate_hz is None:
            object.__setattr__(self, "output_rate_hz",
                               1.0 / (self.dt_s * max(1, round(1e-4 / self.dt_s))))
        _check.number("output_rate_hz", self.output_rate_hz, lo=0.0, hi=(1 + ON_LEVEL) / self.dt_s,
                      lo_open=True)
        ratio = 1.0 / (self.output_rate_hz * self.dt_s)
        if abs(ratio - round(ratio)) > _TYPED_RATE * ratio:
            example = 1.0 / self.dt_s / max(1, round(ratio))
            raise _check.out_of_range("output_rate_hz", self.output_rate_hz,
                                      f"1/dt_s divided by an integer, e.g. {example:g}")
        if self.gap_ramp_s is None:
            object.__setattr__(self, "gap_ramp_s", min(0.1, 0.5 * self.duration_s))
        _check.number("gap_ramp_s", self.gap_ramp_s, lo=0.0, hi=self.duration_s)
        if self.contact_law is not None and self.gap_ramp_s > self.discard_s:
            warnings.warn(
                f"gap_ramp_s = {self.gap_ramp_s:g} s is longer than discard_s = "
                f"{self.discard_s:g} s: the analysis window starts while the gap is still "
                "closing, so its spectra and contact statistics hold the ramp's transient",
                GapRampInWindow, stacklevel=3)
        if self.sensors:
            object.__setattr__(self, "sensors", check_sensors(self.sensors, self.rig))
        elif not isinstance(self.sensors, tuple):
            object.__setattr__(self, "sensors", tuple(self.sensors))
        if self.static_load is None and any(b.journal is not None for b in self.rig.bearings):
            raise ValueError("static_load is None on a rig on journal bearings (allowed: a "
                             "StaticLoad, e.g. gravity: the films carry the rotor's weight)")
        if self.static_load is not None:
            if not isinstance(self.static_load, StaticLoad):
                raise _check.wrong_type("static_load", type(self.static_load).__name__,
                                        "a StaticLoad or None")
            from rubdiag.assembly import dof_map

            self.static_load.check_model(dof_map(self.rig))
        if self.contact is not None and self.rig.contact is None:
            raise ValueError("contact is given but the rig has no blade-casing contact "
                             "geometry (blades and casing)")

    def _check_long_steps(self) -> None:
        if self.step_error is None:
            if self.dt_max_s is not None:
                raise ValueError(f"dt_max_s = {self.dt_max_s!r} without step_error "
                                 "(allowed: None, or a step_error with it)")
            return
        _check.number("step_error", self.step_error, lo=0.0, hi=0.01, lo_open=True)
        if self.fixed_step:
            raise ValueError("step_error with fixed_step = True (allowed: one of them)")
        if self.dt_max_s is None:
            object.__setattr__(self, "dt_max_s", LONG_STEP_FACTOR * self.dt_s)
        factor = self.dt_max_s / self.dt_s
        if not any(math.isclose(factor, k, rel_tol=ON_LEVEL) for k in (1, 2, 4, 8)):
            raise _check.out_of_range("dt_max_s", self.dt_max_s,
                                      f"dt_s = {self.dt_s:g} s times 1, 2, 4 or 8")

    @property
    def contact_law(self) -> BladeContact | None:
        """The blade-casing contact law in force: ``contact`` or the rig's."""
        return self.contact if self.contact is not None else self.rig.contact

    @property
    def model_kind(self) -> str:
        """Which model the run simulates: ``"full"`` or ``"reduced"`` (with ``reduction``)."""
        return "full" if self.reduction is None else "reduced"

    @property
    def output_dt_s(self) -> float:
        return self.dt_s * round(1.0 / (self.output_rate_hz * self.dt_s))

    @property
    def speed_rpm(self) -> float:
        """The (start) speed in rpm."""
        return self.speed_rad_s * 30.0 / math.pi

    def speed_at(self, t) -> np.ndarray:
        """Ω (rad/s) at times ``t`` (s)."""
        if self.speed_profile is None:
            return np.full(np.shape(t), self.speed_rad_s)
        return self.speed_profile.speed(t)

    def angle_at(self, t) -> np.ndarray:
        """The shaft angle φ(t) = ∫₀ᵗ Ω dt (rad) at times ``t`` (s)."""
        if self.speed_profile is None:
            return self.speed_rad_s * np.asarray(t, dtype=float)
        return self.speed_profile.angle(t)

    @classmethod
    def paper_case(cls, case: int, gap_mm: float | None, speed_rpm: float | None = None,
                   rig: Rig | None = None, **options) -> Run:
        """The study's case 1 (unbalances in phase, at the first forward critical speed)
        or case 2 (out of phase, at the second), with gap ``gap_mm`` (mm; None: no rub, the
        rig without its blade-casing contacts, e.g. a run with faults only)."""
        from rubdiag.model import paper_rig

        case = _check.integer("case", case, lo=1, hi=2)
        rig = paper_rig() if rig is None else rig
        unbalance = rig.unbalance(case)
        profile = options.get("speed_profile")
        if profile is not None:
            if speed_rpm is not None:
                raise ValueError("give speed_rpm or speed_profile, not both")
            speed = profile.start_rad_s
        elif speed_rpm is None:
            speed = critical_speed_for_case(rig, case)
        else:
            speed = _check.positive("speed_rpm", speed_rpm) * math.pi / 30.0
        if gap_mm is None:      # no rub: the rig without its blade-casing contacts
            options.setdefault("label", f"case {case}, no rub")
            rig = dataclasses.replace(rig, contact=None)
            return cls(rig=rig, speed_rad_s=speed, unbalance=unbalance, gap_m=None, **options)
        gap = _check.number("gap_mm", gap_mm, lo=0.0, hi=100.0) * 1e-3
        options.setdefault("label", f"case {case}, g0 = {gap_mm:g} mm")
        return cls(rig=rig, speed_rad_s=speed, unbalance=unbalance, gap_m=gap, **options)


def critical_speed_for_case(rig: Rig, case: int) -> float:
    """Forward critical speed (rad/s) that the study's case excites: 1st (case 1), 2nd (2).

    Parameters
    ----------
    rig : Rig
        The rig.
    case : {1, 2}
        The study's case.

    Returns
    -------
    float
        The critical speed (rad/s).
    """
    from rubdiag.simulation._rig_cache import forward_critical_speeds

    case = _check.integer("case", case, lo=1, hi=2)
    speeds = forward_critical_speeds(rig, case)    # cached: per process and on disk
    if len(speeds) < case:
        raise ValueError(f"the rig has no forward critical speed number {case}")
    return float(speeds[case - 1])
