"""Campbell diagram: natural frequencies and whirl of the lowest modes against speed."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _progress
from rubdiag.modal._critical import critical_speeds
from rubdiag.modal._eigen import modes

__all__ = ["Campbell", "campbell"]


@dataclass(frozen=True)
class Campbell:
    """Frequencies (rad/s) and whirl ratios of ``n_modes`` modes at each speed (rad/s).

    ``frequencies[i, j]`` is the damped natural frequency of mode j (sorted by frequency)
    at ``speeds[i]``; ``whirl_ratio`` has the same shape (+1 forward … −1 backward);
    ``critical_speeds`` are the forward crossings with 1× (rad/s).

    Parameters
    ----------
    speeds : numpy.ndarray
        (n_speeds,) spin speeds (rad/s).
    frequencies : numpy.ndarray
        (n_speeds, n_modes) damped natural frequencies (rad/s).
    damping_ratios : numpy.ndarray
        (n_speeds, n_modes) damping ratios.
    whirl_ratio : numpy.ndarray
        (n_speeds, n_modes) whirl ratios (+1 forward … −1 backward).
    shaft_share : numpy.ndarray
        (n_speeds, n_modes) share of each mode's kinetic energy in the shaft and discs.
    critical_speeds : numpy.ndarray
        Forward crossings with 1× (rad/s).
    """

    speeds: np.ndarray
    frequencies: np.ndarray
    damping_ratios: np.ndarray
    whirl_ratio: np.ndarray
    shaft_share: np.ndarray
    critical_speeds: np.ndarray

    def to_frame(self):
        """Long table: one row per (speed, mode)."""
        import pandas as pd

        n_speeds, n_modes = self.frequencies.shape
        return pd.DataFrame({
            "speed_rpm": np.repeat(self.speeds * 30 / np.pi, n_modes),
            "mode": np.tile(np.arange(1, n_modes + 1), n_speeds),
            "frequency_hz": self.frequencies.ravel() / (2 * np.pi),
            "damping_ratio": self.damping_ratios.ravel(),
            "whirl_ratio": self.whirl_ratio.ravel(),
            "shaft_share": self.shaft_share.ravel(),
        })


def campbell(model, speeds, n_modes: int = 8, damped: bool = True,
             progress: bool = False) -> Campbell:
    """Modes of ``model`` at every speed in ``speeds`` (rad/s); ``progress``: a bar over
    the speeds on stderr when it is a terminal.

    Parameters
    ----------
    model : Model
        The assembled rig.
    speeds : array_like of float
        Spin speeds (rad/s, >= 0).
    n_modes : int
        Modes kept at each speed, the lowest oscillating ones.
    damped : bool
        Include the damping matrix (False: undamped natural frequencies; gyroscopic effects
        stay).
    progress : bool
        Show a progress bar on stderr when it is a terminal.

    Returns
    -------
    Campbell
        The modes' frequencies, damping and whirl at every speed.
    """
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size == 0 or np.any(~np.isfinite(speeds)) or np.any(
            speeds < 0):
        raise ValueError("speeds must be a non-empty 1-D array of speeds >= 0 rad/s")
    rows = [modes(model, s, n_modes=n_modes, damped=damped)
            for s in _progress.steps(speeds, "campbell", "speed", progress)]
    width = min(len(r.eigenvalues) for r in rows)

    def stack(attr):
        return np.array([np.asarray(getattr(r, attr))[:width] for r in rows])

    return Campbell(speeds=speeds, frequencies=stack("damped_frequencies"),
                    damping_ratios=stack("damping_ratios"), whirl_ratio=stack("whirl_ratio"),
                    shaft_share=stack("shaft_share"),
                    critical_speeds=critical_speeds(model, n=4))
