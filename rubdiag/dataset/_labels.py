"""Labels of a simulated run, from what the run did, and the raw measures behind them.

Every measure is taken over the analysis window ``[discard_s, end]`` from the per-step
event logs (not the sampled waveforms, which miss sub-sample impacts), so a user can relabel
with other thresholds:

``interference_ratio``
    The largest radial approach of the linear (contact-free) unbalance response over all
    contact elements, divided by g0 (``SimulationResult.linear_approach_m / gap_m``): how
    deep the rotor would reach into the casing if nothing stopped it. > 1 means the linear
    orbit crosses the casing. A run along a speed profile (a design's ``[ramp]``) takes
    the largest approach over the speeds its window sweeps
    (:func:`rubdiag.dataset._approach.sweep_linear_approach_m`, given to :func:`label_run`):
    how deep the rotor would reach at the sweep's worst speed, e.g. the critical speed it
    passes. A run-up passes a critical faster than the steady response builds up, so this
    is an upper bound of the depth the window reaches; at the worst speed it is that
    speed's constant-speed ratio, so ``severity_threshold`` reads the same way.
``contact_time_fraction``
    The largest, over the contact elements, share of the window during which the element
    is closed (episodes clipped to the window, from their interpolated start and end).
``peak_normal_force_n``
    The largest per-episode peak normal force of the episodes that overlap the window (N).
``peak_penetration_m``
    ``peak_normal_force_n / k_N``: the penalty penetration at that force (m). With
    augmentation the multiplier carries part of the force, so this is an upper bound.
``friction_work_per_rev_j``
    Energy dissipated by friction in the window per revolution (J), from the energy
    ledger's cumulative ``dissipated_friction`` (the window's revolutions from the shaft
    angle along a speed profile).
``sticking_share``
    Sticking time / closed time over all elements and window episodes; NaN without
    contact.
``n_rub_episodes``
    Episodes closed for at least 15 µs (:data:`rubdiag._episodes.MIN_EPISODE_S`)
    that overlap the window.

Labels (rules :class:`LabelRules`, written in the design's ``[labels]`` table):

``rub``
    At least one contact episode closed for at least 15 µs overlaps the window: a one-step
    graze (10 µs) is not a rub, two 10-µs steps are (the rule is stated in time, so that it
    does not depend on the step).
``rub_state``
    ``none`` without rub; ``full`` when some element is closed during at least
    ``full_contact_share`` (default 0.95) of the window (continuous contact); otherwise
    ``partial``.
``severity``
    ``none`` without rub; otherwise ``light`` when ``interference_ratio`` is below
    ``severity_threshold``, ``serious`` from it on. The default threshold, 1.37, is a
    **calibration**: the study calls its 2.3-mm gap light and its 1.9-mm gap serious in
    both cases, and on the paper rig the ratios are 1.30 (case 1, 2.3 mm), 1.57 (case 1,
    1.9 mm), 1.19 (case 2, 2.3 mm) and 1.44 (case 2, 1.9 mm), so any threshold in
    (1.30, 1.44] reproduces the study's words; 1.37 is the middle.
    ``tests/dataset/test_labels.py`` checks the four cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag._episodes import MIN_EPISODE_S, closed_time
from rubdiag._tolerances import BOUND_SLACK

__all__ = ["LABELS", "MEASURES", "RUB_STATES", "SEVERITIES", "LabelRules",
           "label_run", "labels_from_measures"]

RUB_STATES = ("none", "partial", "full")
SEVERITIES = ("none", "light", "serious")
LABELS = ("rub", "rub_state", "severity")
MEASURES = ("interference_ratio", "contact_time_fraction", "peak_normal_force_n",
            "peak_penetration_m", "friction_work_per_rev_j", "sticking_share",
            "n_rub_episodes")


@dataclass(frozen=True)
class LabelRules:
    """Thresholds of the labels (see the module docstring).

    Parameters
    ----------
    severity_threshold : float
        ``interference_ratio`` from which a rub is serious (> 0).
    full_contact_share : float
        Share of the window some element must be closed for a full rub (0-1).
    """

    severity_threshold: float = 1.37
    full_contact_share: float = 0.95

    def __post_init__(self):
        object.__setattr__(self, "severity_threshold", _check.positive(
            "labels.severity_threshold", self.severity_threshold))
        object.__setattr__(self, "full_contact_share", _check.number(
            "labels.full_contact_share", self.full_contact_share, lo=0.0, hi=1.0,
            lo_open=True))

    def to_dict(self) -> dict:
        return {"severity_threshold": self.severity_threshold,
                "full_contact_share": self.full_contact_share}


def label_run(result, rules: LabelRules | None = None,
              linear_approach_m: float | None = None, clearance_m: float | None = None) -> dict:
    """The measures and labels of a :class:`~rubdiag.simulation.SimulationResult`: one dict,
    measures first (:data:`MEASURES`, then :data:`LABELS`).

    ``linear_approach_m``: the approach behind ``interference_ratio``; default the run's
    (``result.linear_approach_m``, at its constant speed). A run along a speed profile needs
    it given: :func:`rubdiag.dataset._approach.sweep_linear_approach_m` of its run.
    ``clearance_m``: the clearance it is over (m; default the run's blade gap g0; a shaft
    rubbing on its seal: the seal's clearance).

    Parameters
    ----------
    result : SimulationResult
        A simulated run.
    rules : LabelRules or None
        Thresholds; None: the defaults.
    linear_approach_m : float or None
        The linear approach (m).
    clearance_m : float or None
        The clearance (m).

    Returns
    -------
    dict
        Measures and labels by name.
    """
    measures = run_measures(result, linear_approach_m, clearance_m)
    return {**measures, **labels_from_measures(measures, rules)}


def labels_from_measures(measures: dict, rules: LabelRules | None = None) -> dict:
    """``rub``, ``rub_state`` and ``severity`` from the measures (relabelling uses this;
    default rules: :class:`LabelRules`).

    Parameters
    ----------
    measures : dict
        The measures of :func:`label_run`.
    rules : LabelRules or None
        Thresholds; None: the defaults.

    Returns
    -------
    dict
        ``rub``, ``rub_state`` and ``severity``.
    """
    rules = LabelRules() if rules is None else rules
    rub = measures["n_rub_episodes"] > 0
    if not rub:
        return {"rub": False, "rub_state": "none", "severity": "none"}
    full = measures["contact_time_fraction"] >= rules.full_contact_share
    serious = measures["interference_ratio"] >= rules.severity_threshold
    return {"rub": True, "rub_state": "full" if full else "partial",
            "severity": "serious" if serious else "light"}


def run_measures(result, linear_approach_m: float | None = None,
                 clearance_m: float | None = None) -> dict:
    """The raw measures of the module docstring (``linear_approach_m``, ``clearance_m``: as
    for :func:`label_run`)."""
    run, system = result.run, result.system
    varying = getattr(run, "speed_profile", None) is not None
    if linear_approach_m is None:
        if varying:
            raise ValueError("a run along a speed profile needs linear_approach_m (the "
                             "largest over its window's speeds: rubdiag.dataset._approach."
                             "sweep_linear_approach_m(run))")
        linear_approach_m = result.linear_approach_m
    start = run.discard_s
    end = float(system.t[-1]) if system.t.size else start
    window = max(end - start, 0.0)
    # the contact elements' episodes only: a fault element (a breathing crack) or a journal
    # bearing's film also logs episodes, which are not rubs (rubdiag.dataset._faults labels
    # them)
    n_elements = getattr(result, "n_contacts", system.contact_fn.shape[1])
    others = n_elements < system.contact_fn.shape[1]
    ep = result.contact_episodes() if others else system.episodes
    overlap = (ep.t_end > start) & (ep.t_start < end)
    lasting = overlap & (closed_time(ep) >= MIN_EPISODE_S)
    closed = np.clip(ep.t_end, start, end) - np.clip(ep.t_start, start, end)
    per_element = np.zeros(max(n_elements, 1))
    np.add.at(per_element, ep.element[overlap] - 1, closed[overlap])
    slide, stick = ep.slide_time[overlap].sum(), ep.stick_time[overlap].sum()
    peak = float(ep.peak_normal_force[overlap].max()) if overlap.any() else 0.0
    law = run.contact_law
    if not varying:
        revolutions = window * run.speed_rad_s / (2 * math.pi)
    else:
        revolutions = float(run.angle_at(end) - run.angle_at(start)) / (2 * math.pi)
    friction = _ledger_in_window(system.t, system.dissipated_friction, start)
    gap = clearance_m if clearance_m else (run.gap_m if run.gap_m else float("nan"))
    return {
        "interference_ratio": linear_approach_m / gap,
        "contact_time_fraction": float(per_element.max() / window) if window > 0 else 0.0,
        "peak_normal_force_n": peak,
        "peak_penetration_m": peak / law.normal_stiffness_n_m if law is not None else 0.0,
        "friction_work_per_rev_j": friction / revolutions if revolutions > 0 else float("nan"),
        "sticking_share": float(stick / (slide + stick)) if slide + stick > 0 else float("nan"),
        "n_rub_episodes": int(lasting.sum()),
    }


def _ledger_in_window(t: np.ndarray, cumulative: np.ndarray, start: float) -> float:
    """Increase of a cumulative ledger from the first sample in the window to the last."""
    inside = np.flatnonzero(t >= start - BOUND_SLACK)
    if inside.size < 2:
        return 0.0
    return float(cumulative[inside[-1]] - cumulative[inside[0]])
