"""Oil whirl and whip in a simulated run: how much of a journal's orbit is sub-synchronous."""

from __future__ import annotations

import numpy as np

from rubdiag import _check

__all__ = ["SUBSYNCHRONOUS_BAND", "subsynchronous_share"]

#: the band of orders (× the running speed) whose motion counts as whirl or whip
SUBSYNCHRONOUS_BAND = (0.05, 0.9)


def subsynchronous_share(result, bearing: int) -> float:
    """The share of a journal's orbit in its bearing that is oil whirl or whip.

    The share, by power, of the journal's dynamic orbit relative to its housing over the
    analysis window that lies in :data:`SUBSYNCHRONOUS_BAND` of the running speed: the raw
    measure of whirl, from the element's own coordinates (the journal's recorded y and z less
    its pedestal's), never a probe's. The orbit is the complex ``y + i z`` less its mean
    (forward and backward whirl both count), its power spectrum a Hann-windowed periodogram
    over the window (the window keeps the 1× line's leakage out of the band).

    Parameters
    ----------
    result : SimulationResult
        A run on a rig with plain journal bearings.
    bearing : int
        The journal bearing, by its index in ``result.run.rig.bearings``.

    Returns
    -------
    float
        The share in [0, 1]; 0 for a journal that does not move.

    Raises
    ------
    ValueError
        ``bearing`` out of range, or not a journal bearing.

    See Also
    --------
    rubdiag.modal.stability_threshold : The speed above which the film whirls.
    whirl_runs : Runs of a rig below and above that speed.
    """
    run = result.run
    bearings = run.rig.bearings
    b = bearings[_check.integer("bearing", bearing, lo=0, hi=len(bearings) - 1)]
    if b.journal is None:
        raise ValueError(f"bearing = {bearing} is not a journal bearing of rig "
                         f"{run.rig.name!r}")
    orbit = (result.displacement(f"shaft {b.node} y", True)
             + 1j * result.displacement(f"shaft {b.node} z", True))
    if b.pedestal is not None:
        orbit = orbit - (result.displacement(f"pedestal {bearing} y", True)
                         + 1j * result.displacement(f"pedestal {bearing} z", True))
    orbit = orbit - orbit.mean()
    t = result.t[result.window]
    power = np.abs(np.fft.fft(orbit * np.hanning(t.size))) ** 2
    order = np.abs(np.fft.fftfreq(t.size, t[1] - t[0])) * 2 * np.pi / run.speed_rad_s
    total = power.sum()
    if total == 0.0:
        return 0.0
    low, high = SUBSYNCHRONOUS_BAND
    return float(power[(order >= low) & (order <= high)].sum() / total)
