"""The full spectrum and orbit of every probe pair of a simulated run.

Every recorded node with both a y and a z displacement (the discs' shaft nodes, the casing
node and blade tip of contact 1, pedestals, journals: :func:`rubdiag.simulation.response_points`)
is a pair of orthogonal probes, the shaft turning from y towards z. :func:`run_orbit_features` gives
each pair's :func:`rubdiag.signal._fullspectrum.orbit_features` over the analysis window at
the run's speed, one row per pair.
"""

from __future__ import annotations

import pandas as pd

__all__ = ["recorded_pairs", "run_orbit_features"]


def recorded_pairs(result) -> tuple[str, ...]:
    """The nodes (``"shaft 11"`` …) whose y and z displacements ``result`` records.

    Parameters
    ----------
    result : SimulationResult
        A simulated run.

    Returns
    -------
    tuple of str
        Node labels.
    """
    nodes = [p.rsplit(" ", 1)[0] for p in result.points if p.endswith(" y")]
    return tuple(n for n in nodes if f"{n} z" in result.points)


def run_orbit_features(result) -> pd.DataFrame:
    """One row per recorded pair of ``result`` (a constant-speed SimulationResult): its
    ``pair`` (the node), then :func:`~rubdiag.signal._fullspectrum.orbit_features` (m) over the
    analysis window at the run's speed.

    Parameters
    ----------
    result : SimulationResult
        A run at constant speed.

    Returns
    -------
    pandas.DataFrame
        One row per recorded node.
    """
    from rubdiag.signal import orbit_features

    if result.run.speed_profile is not None:
        raise ValueError("a run along a speed profile has no single speed for its full "
                         "spectrum (allowed: a constant-speed run)")
    rows = []
    for node in recorded_pairs(result):
        y = result.displacement(f"{node} y", windowed=True)
        z = result.displacement(f"{node} z", windowed=True)
        rows.append({"pair": node, **orbit_features(y, z, result.fs, result.run.speed_rpm)})
    return pd.DataFrame(rows)
