"""Measurement noise: one floor per sensor quantity, in physical units, with a per-run seed.

White Gaussian noise of standard deviation ``floor`` is added to every channel of a
quantity. The floor is fixed in physical units (a probe's resolution), **not** scaled to
each run's signal power: scaled noise would make the noise level a copy of the signal level
and leak it (a louder run would carry louder noise). A channel that is exactly zero (the
casing of a run without rub) therefore reads pure noise, as a real sensor would.

The seed of a run is derived from its id (:func:`noise_seed` of
:func:`rubdiag.dataset._ids.noise_id`: the ``run_id`` without the step settings), so the
noise is part of the run's identity: the same run gets the same noise on any worker, two
runs never share a noise draw — except a run with long steps and its twin at 10 µs, which
simulate the same thing and are measured with the same noise. The classifier layer uses
the same function to add noise to signals it did not simulate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check

__all__ = ["NoiseFloors", "add_noise", "noise_seed"]


@dataclass(frozen=True)
class NoiseFloors:
    """Standard deviation of the noise per quantity (SI units; 0 = none): typical values of a
    plant's eddy-current probes (1 µm), velocity pickups (0.1 mm/s), accelerometers
    (0.05 m/s², 5 mg) and load cells (1 N).

    Parameters
    ----------
    displacement_m : float
        Of displacement channels (m).
    velocity_m_s : float
        Of velocity channels (m/s).
    acceleration_m_s2 : float
        Of acceleration channels (m/s²).
    force_n : float
        Of force channels (N).
    """

    displacement_m: float = 1e-6
    velocity_m_s: float = 1e-4
    acceleration_m_s2: float = 0.05
    force_n: float = 1.0

    def __post_init__(self):
        for name in ("displacement_m", "velocity_m_s", "acceleration_m_s2", "force_n"):
            object.__setattr__(self, name, _check.non_negative(f"noise.{name}",
                                                               getattr(self, name)))

    def floor(self, quantity: str) -> float:
        """The floor of a sensor quantity (``displacement``, ``velocity``, ``acceleration``,
        ``reaction``)."""
        return {"displacement": self.displacement_m, "velocity": self.velocity_m_s,
                "acceleration": self.acceleration_m_s2, "reaction": self.force_n}[quantity]

    def to_dict(self) -> dict:
        return {"displacement_m": self.displacement_m, "velocity_m_s": self.velocity_m_s,
                "acceleration_m_s2": self.acceleration_m_s2, "force_n": self.force_n}


def noise_seed(run_id: str) -> int:
    """The noise seed of a run: its 16-hex-digit id as an integer."""
    return int(run_id, 16)


def add_noise(signals: dict[str, np.ndarray], floors: dict[str, float],
              seed: int) -> dict[str, np.ndarray]:
    """``signals`` (name -> 1-D array) plus white Gaussian noise of standard deviation
    ``floors[name]``; the draws follow the order of ``signals``, from ``seed``."""
    rng = np.random.default_rng(seed)
    out = {}
    for name, x in signals.items():
        x = np.asarray(x, dtype=np.float64)
        noise = rng.standard_normal(x.shape)         # drawn even at floor 0: same stream
        out[name] = x + floors[name] * noise
    return out
