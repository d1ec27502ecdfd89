"""What a design run's analysis window must hold for its features.

A constant-speed run's window (``duration_s - discard_s``) must hold :data:`MIN_REVOLUTIONS`
at the design's slowest speed (the spectral features' minimum); a speed ramp's window is the
whole sweep, measured on its order-tracked record, which loses up to
``ORDER_TRACK_LOST_REVOLUTIONS`` at its ends, and its fastest speed must keep the features'
highest order inside the output rate (:func:`rubdiag.runs._features.max_tracked_rpm`).
"""

from __future__ import annotations

import math

from rubdiag._tolerances import BOUND_SLACK

__all__ = ["MIN_REVOLUTIONS", "check_revolutions", "check_top_speed"]

#: Revolutions the analysis window must hold (the spectral features' default minimum).
MIN_REVOLUTIONS = 10.0


def check_revolutions(duration_s: float | None, discard_s: float, ramp,
                      speed_rad_s: float) -> None:
    """A ValueError unless the analysis window at ``speed_rad_s`` (the design's slowest)
    holds :data:`MIN_REVOLUTIONS`; a ramp's (``ramp``: a
    :class:`~rubdiag.dataset._ramp.SpeedRamp`, or None), also the revolutions its order
    tracking takes off.

    Parameters
    ----------
    duration_s : float or None
        The runs' length (s); None with a ramp (derived run by run).
    discard_s : float
        The start left out of the window (s).
    ramp : SpeedRamp or None
        The design's speed ramp.
    speed_rad_s : float
        The speed the window is checked at (rad/s).
    """
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
    if revolutions < needed * (1 - BOUND_SLACK):   # exactly enough may compute a few ulps short
        digits = 3                  # as few as show it short: never "holds 10 … at least 10"
        while float(f"{revolutions:.{digits}g}") >= needed and digits < 17:
            digits += 1
        raise ValueError(f"{what} holds {revolutions:.{digits}g} revolutions at "
                         f"{rpm:.{max(6, digits + 1)}g} rpm, the design's slowest speed "
                         f"(allowed: at least {needed:g}, {why})")


def check_top_speed(run) -> None:
    """A ValueError unless the fastest speed of ``run``'s speed profile keeps the features
    of its order-tracked record below its output rate
    (:func:`~rubdiag.runs._features.max_tracked_rpm`).

    Parameters
    ----------
    run : Run
        A run with a speed profile.
    """
    from rubdiag.runs._features import max_tracked_rpm

    top = max(run.speed_profile.speeds_rad_s) * 30.0 / math.pi
    fastest = max_tracked_rpm(run.output_rate_hz)
    if top > fastest:
        raise ValueError(f"the ramp reaches {top:.6g} rpm (allowed: at most {fastest:.6g} rpm "
                         f"at the output rate {run.output_rate_hz:g} Hz, for the features of "
                         "the order-tracked record; lower ramp.span or the speed)")
