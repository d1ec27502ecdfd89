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
from rubdiag.modal.eigen import modes

__all__ = ["StabilityThreshold", "stability_threshold", "whirl_threshold"]


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
    lam = modes(model, speed, n_modes=n_modes).eigenvalues
    return complex(lam[np.argmax(lam.real)])


def stability_threshold(model, low_rad_s: float, high_rad_s: float, n_grid: int = 33,
                        n_modes: int = 6) -> StabilityThreshold | None:
    """The lowest speed in [``low_rad_s``, ``high_rad_s``] (rad/s, 0 < low < high) at which
    one of the ``n_modes`` lowest roots turns unstable (module docstring), located to 1e-9
    relative; None when the model is stable over the whole range (or unstable already at
    ``low_rad_s``: then no threshold lies in it)."""
    from scipy.optimize import brentq

    low = _check.positive("low_rad_s", low_rad_s, unit="rad/s")
    high = _check.number("high_rad_s", high_rad_s, lo=low, lo_open=True, unit="rad/s")
    n_grid = _check.integer("n_grid", n_grid, lo=2)
    speeds = np.linspace(low, high, n_grid)
    growth = [_rightmost(model, w, n_modes).real for w in speeds]
    if growth[0] >= 0.0:
        return None
    for k in range(1, n_grid):
        if growth[k] >= 0.0:
            speed = brentq(lambda w: _rightmost(model, w, n_modes).real, speeds[k - 1],
                           speeds[k], xtol=1e-9 * speeds[k], rtol=1e-12)
            return StabilityThreshold(float(speed), abs(_rightmost(model, speed, n_modes).imag))
    return None


def whirl_threshold(model) -> StabilityThreshold | None:
    """The threshold of instability of a rig on journal bearings where whirl and whip are
    sought: :func:`stability_threshold` between half its first and twice its second forward
    critical speed (None when it is stable over that range)."""
    from rubdiag.modal.critical import critical_speeds

    first, last = critical_speeds(model, n=2)[[0, -1]]
    return stability_threshold(model, 0.5 * first, 2.0 * last)
