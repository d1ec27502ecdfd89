"""The threshold of instability of a rotor on journal bearings.

With the films' cross-coupled stiffness (:meth:`Model.bearing_matrices`), the damped linear
model ``M q'' + (C + C_b(Ω) + Ω G) q' + (K + K_b(Ω)) q = 0`` loses stability where the real
part of one of its roots crosses zero as the speed grows: oil whirl sets in there, at the
root's frequency (near half the speed on lightly loaded bearings; the film's own ratio for
a rigid rotor). :func:`stability_threshold` finds the lowest such speed in a range: the
largest real part of the lowest roots on a grid of speeds, then Brent's method on the first
sign change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag.modal.eigen import lowest_roots

__all__ = ["StabilityThreshold", "stability_threshold", "threshold_speed", "whirl_range",
           "whirl_threshold"]


@dataclass(frozen=True)
class StabilityThreshold:
    """The speed (rad/s) at which the linear model turns unstable, and the frequency of the
    root that crosses (rad/s); ``whirl_ratio`` is their ratio."""

    speed_rad_s: float
    frequency_rad_s: float

    @property
    def whirl_ratio(self) -> float:
        return self.frequency_rad_s / self.speed_rad_s


def _rightmost(model, speed: float, n_modes: int) -> complex:
    lam, _ = lowest_roots(model, speed, n_modes)
    return complex(lam[np.argmax(lam.real)])


def stability_threshold(model, low_rad_s: float, high_rad_s: float, n_grid: int = 33,
                        n_modes: int = 6) -> StabilityThreshold | None:
    """The lowest speed in [``low_rad_s``, ``high_rad_s``] (rad/s, 0 < low < high) at which
    one of the ``n_modes`` lowest roots turns unstable (module docstring), located to 1e-9
    relative; None when the model is stable over the whole range (or unstable already at
    ``low_rad_s``: then no threshold lies in it)."""
    speed = threshold_speed(model, low_rad_s, high_rad_s, n_grid, n_modes)
    if speed is None:
        return None
    return StabilityThreshold(speed, abs(_rightmost(model, speed, n_modes).imag))


def threshold_speed(model, low_rad_s: float, high_rad_s: float, n_grid: int = 33,
                    n_modes: int = 6) -> float | None:
    """The speed (rad/s) of :func:`stability_threshold`, without the crossing root's
    frequency (one eigenvalue problem fewer). The grid is walked up from ``low_rad_s`` to
    its first sign change: the points above it cannot change the answer."""
    from scipy.optimize import brentq

    low = _check.positive("low_rad_s", low_rad_s, unit="rad/s")
    high = _check.number("high_rad_s", high_rad_s, lo=low, lo_open=True, unit="rad/s")
    n_grid = _check.integer("n_grid", n_grid, lo=2)
    speeds = np.linspace(low, high, n_grid)
    if _rightmost(model, speeds[0], n_modes).real >= 0.0:
        return None
    for k in range(1, n_grid):
        if _rightmost(model, speeds[k], n_modes).real >= 0.0:
            return float(brentq(lambda w: _rightmost(model, w, n_modes).real, speeds[k - 1],
                                speeds[k], xtol=1e-9 * speeds[k], rtol=1e-12))
    return None


def whirl_threshold(model) -> StabilityThreshold | None:
    """The threshold of instability of a rig on journal bearings where whirl and whip are
    sought: :func:`stability_threshold` between half its first and twice its second forward
    critical speed (None when it is stable over that range)."""
    from rubdiag.modal.critical import critical_speeds

    return stability_threshold(model, *whirl_range(critical_speeds(model, n=2)))


def whirl_range(critical_rad_s) -> tuple[float, float]:
    """The speeds (rad/s) between which :func:`whirl_threshold` seeks the threshold: half
    the first and twice the last of the forward critical speeds ``critical_rad_s``."""
    return 0.5 * critical_rad_s[0], 2.0 * critical_rad_s[-1]
