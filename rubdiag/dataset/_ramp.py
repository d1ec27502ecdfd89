"""A design's speed ramp: every run sweeps its speed through the design point's speed.

The ``[ramp]`` table of a design (:mod:`rubdiag.dataset._design_toml`)::

    [ramp]
    rate_rpm_s = 300          # how fast the speed changes (rpm/s), > 0
    span = 0.15               # the sweep: speed·(1 - span) … speed·(1 + span), 0 < span < 1
    direction = "up"          # "up": a run-up (default); "down": a coast-down

A run of design point speed Ω (rpm) holds ``Ω·(1 ∓ span)`` for ``base.discard_s`` — the
replicates' gap ramps (start histories) happen there, at constant speed, as in a
constant-speed design — then ramps linearly at ``rate_rpm_s`` to ``Ω·(1 ± span)``
(:meth:`SpeedRamp.profile`) and ends there: it lasts ``discard_s + 2·span·Ω / rate_rpm_s``
(:meth:`SpeedRamp.sweep_s` is the second term), and its analysis window is the whole
ramp. The design point's speed is the sweep's middle, so ``speed_ratio = 1`` with
``span = 0.15`` passes the critical speed halfway through the window.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from rubdiag import _check

__all__ = ["DIRECTIONS", "KEYS", "SpeedRamp"]

DIRECTIONS = ("up", "down")
#: The keys of ``[ramp]``: two required, then ``direction`` (default "up").
KEYS = ("rate_rpm_s", "span", "direction")


@dataclass(frozen=True)
class SpeedRamp:
    """The sweep of every run of a design (see the module docstring).

    Parameters
    ----------
    rate_rpm_s : float
        How fast the speed changes (rpm/s, > 0).
    span : float
        Relative half-width of the sweep (0 < span < 1).
    direction : {"up", "down"}
        A run-up or a coast-down.
    """

    rate_rpm_s: float
    span: float
    direction: str = "up"

    def __post_init__(self):
        object.__setattr__(self, "rate_rpm_s", _check.number(
            "ramp.rate_rpm_s", self.rate_rpm_s, lo=0.0, hi=1e6, lo_open=True, unit="rpm/s"))
        object.__setattr__(self, "span", _check.number(
            "ramp.span", self.span, lo=0.0, hi=1.0, lo_open=True, hi_open=True))
        object.__setattr__(self, "direction", _check.choice("ramp.direction", self.direction,
                                                            DIRECTIONS))

    @classmethod
    def from_dict(cls, table) -> SpeedRamp:
        """The ramp of a design's ``[ramp]`` table (keys as :data:`KEYS`)."""
        if not isinstance(table, Mapping):
            raise _check.wrong_type("ramp", table, "a table")
        for key in table:
            if key not in KEYS:
                raise ValueError(f"unknown key 'ramp.{key}' (allowed: {', '.join(KEYS)})")
        for key in KEYS[:2]:
            if key not in table:
                raise ValueError(f"ramp.{key} is missing (a [ramp] needs rate_rpm_s and span)")
        return cls(**table)

    def speeds_rpm(self, speed_rpm: float) -> tuple[float, float]:
        """``(from_rpm, to_rpm)`` of the sweep through ``speed_rpm``."""
        low, high = speed_rpm * (1.0 - self.span), speed_rpm * (1.0 + self.span)
        return (low, high) if self.direction == "up" else (high, low)

    def sweep_s(self, speed_rpm: float) -> float:
        """The ramp's length (s): ``2·span·speed_rpm / rate_rpm_s``."""
        low, high = self.speeds_rpm(speed_rpm)
        return abs(high - low) / self.rate_rpm_s

    def profile(self, speed_rpm: float, hold_s: float):
        """The :class:`~rubdiag.simulation.SpeedProfile` of a run at design speed
        ``speed_rpm``: the start speed for ``hold_s``, then the ramp."""
        from rubdiag.simulation import SpeedProfile

        return SpeedProfile.ramp(*self.speeds_rpm(speed_rpm), self.rate_rpm_s, hold_s=hold_s)

    def to_dict(self) -> dict:
        return {"rate_rpm_s": self.rate_rpm_s, "span": self.span, "direction": self.direction}
