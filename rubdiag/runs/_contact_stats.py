"""Contact statistics of a simulated run, from its per-step event log.

Every number is taken over the **analysis window** ``[discard_s, end]`` of the run, from
the contact episodes that *start* in it (an episode is a contiguous run of closed status,
2 sliding or 3 sticking, of one element; the kernel logs each one at every step, so force
peaks shorter than the output interval are not missed).

Per contact element k = 1 … n (columns ``contact{k}_…``):

``n_episodes``
    episodes starting in the window.
``min_force_n``, ``p05_force_n``, ``max_force_n``
    smallest, 5th-percentile and largest per-episode peak normal force (N). The minimum and
    the percentile only count episodes of at least 2 steps (a one-step graze peaks near
    0 N); the study does not define its "minimum contact force", so both are reported.
``sliding_entries``, ``sticking_entries``
    entries into status 2 / 3 (the study's "sliding/sticking contact times"); also
    ``…_per_s`` (per second of window) and ``…_per_rev`` (per revolution).
``contact_fraction``
    closed time / window length.
``sticking_share``
    sticking time / closed time (with a fixed step, sticking steps / closed steps).
``mean_force_sliding_n``, ``mean_force_sticking_n``
    time-averaged normal force while sliding / while sticking (N).

Over all elements (columns ``contacts_…``): ``n_episodes``, ``max_force_n``, ``min_force_n``,
``sliding_entries``, ``sticking_entries``, ``contact_fraction`` (mean over elements),
``sticking_share``, ``mean_force_sliding_n``, ``mean_force_sticking_n``.

Without any episode the maximum force is 0 N and the counts and fractions are 0 (measured:
nothing touched); quantities that need an episode (minimum and percentile force, sticking
share, mean forces) are NaN (undefined).
"""

from __future__ import annotations

import numpy as np

from rubdiag._episodes import MIN_EPISODE_S, closed_time

__all__ = ["CONTACT_STAT_NAMES", "contact_statistics"]

CONTACT_STAT_NAMES = (
    "n_episodes", "min_force_n", "p05_force_n", "max_force_n", "sliding_entries",
    "sticking_entries", "sliding_entries_per_s", "sticking_entries_per_s",
    "sliding_entries_per_rev", "sticking_entries_per_rev", "contact_fraction",
    "sticking_share", "mean_force_sliding_n", "mean_force_sticking_n",
)


def _ratio(num: float, den: float) -> float:
    return float(num / den) if den > 0 else float("nan")


def _stats(ep, mask, window_s: float, revolutions: float) -> dict[str, float]:
    peaks = ep.peak_normal_force[mask]
    lasting = peaks[closed_time(ep)[mask] >= MIN_EPISODE_S]
    slide_t, stick_t = ep.slide_time[mask].sum(), ep.stick_time[mask].sum()
    n_slide, n_stick = int(ep.n_slide_entries[mask].sum()), int(ep.n_stick_entries[mask].sum())
    return {
        "n_episodes": int(mask.sum()),
        "min_force_n": float(lasting.min()) if lasting.size else float("nan"),
        "p05_force_n": float(np.percentile(lasting, 5)) if lasting.size else float("nan"),
        "max_force_n": float(peaks.max()) if peaks.size else 0.0,   # no contact: 0 N
        "sliding_entries": n_slide,
        "sticking_entries": n_stick,
        "sliding_entries_per_s": _ratio(n_slide, window_s),
        "sticking_entries_per_s": _ratio(n_stick, window_s),
        "sliding_entries_per_rev": _ratio(n_slide, revolutions),
        "sticking_entries_per_rev": _ratio(n_stick, revolutions),
        "contact_fraction": _ratio(slide_t + stick_t, window_s),
        "sticking_share": _ratio(stick_t, slide_t + stick_t),
        "mean_force_sliding_n": _ratio(ep.slide_impulse[mask].sum(), slide_t),
        "mean_force_sticking_n": _ratio(ep.stick_impulse[mask].sum(), stick_t),
    }


def contact_statistics(result) -> dict[str, float]:
    """Contact statistics of a :class:`~rubdiag.simulation.SimulationResult` (see the module
    docstring for every key), plus ``window_s`` (its length) and, when the run records the
    casing, ``casing_max_y_m``.

    Parameters
    ----------
    result : SimulationResult
        A simulated run.

    Returns
    -------
    dict of str to float
        The statistics by name (SI units).
    """
    ep = result.window_episodes()
    end = float(result.t[-1]) if result.t.size else result.run.discard_s
    window_s = max(end - result.run.discard_s, 0.0)
    run = result.run
    if run.speed_profile is None:
        revolutions = window_s * run.speed_rad_s / (2 * np.pi)
    else:       # along a speed profile: the shaft angle turned over the window
        revolutions = float(run.angle_at(run.discard_s + window_s)
                            - run.angle_at(run.discard_s)) / (2 * np.pi)
    n_elements = result.n_contacts        # a fault element (a crack) is not a contact
    row: dict[str, float] = {"window_s": window_s}
    for k in range(1, n_elements + 1):
        for key, value in _stats(ep, ep.element == k, window_s, revolutions).items():
            row[f"contact{k}_{key}"] = value
    if n_elements:
        overall = _stats(ep, np.ones(len(ep), bool), window_s, revolutions)
        overall["contact_fraction"] /= n_elements
        for key in ("n_episodes", "max_force_n", "min_force_n", "sliding_entries",
                    "sticking_entries", "contact_fraction", "sticking_share",
                    "mean_force_sliding_n", "mean_force_sticking_n"):
            row[f"contacts_{key}"] = overall[key]
    casing = [p for p in result.points if p.startswith("casing") and p.endswith(" y")]
    if casing and result.window.any():
        row["casing_max_y_m"] = float(result.displacement(casing[0], windowed=True).max())
    return row
