"""Blade contacts that a run cannot close: left to the reduced model's modes, reported open.

A fault dataset's runs without rub keep the rig's blade contacts but put the casing out of
reach (a gap of 50 mm against orbits of tens of µm), so that no level is told apart by its
rig. Such contacts are linear for the whole run — open at every step — and a reduced model
need not keep their tips and casing nodes physical: the reduction keeps physical what is
nonlinear. On the journal-bearing rig that is 43 coordinates instead of 66, and a run about
2.5× cheaper.

A blade contact is *idle* in a reduced run when its gap is at least :data:`MIN_IDLE_GAP_M`
and at least :data:`IDLE_GAP_RATIO` times the linear approach (the largest radial approach
of the linear steady state at the contacts, static sag included). The run is then
simulated on the reduction without the blade contacts
(``reduced_model(..., blade_contacts=False)``); their tip and casing displacements are
recovered at every sample, and the result reports each of them as an open contact
element, numbered as always (first): zero forces, status 1, its gap and slip from the
recovered displacements, all its time open. A run in which an idle contact comes within
half its gap of the casing stops with :class:`~rubdiag.simulation._result.SimulationDiverged`
(the criterion was wrong for it; ``Reduction(keep_idle_contacts=True)`` simulates it with
the contacts). The two reductions agree within the reduced model's error: the comparison
is ``scripts/idle_contacts.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rubdiag.simulation._result import EpisodeLog, SimulationDiverged, StatusLog, SystemResult

__all__ = ["IDLE_GAP_RATIO", "MIN_IDLE_GAP_M", "is_idle", "report_open"]

#: An idle contact's gap is at least this many times the run's linear approach. Orbits of a
#: rubbing-free run stay within a few times the linear one (oil whip's limit cycle within
#: the bearing clearance); 100 leaves a margin the post-run check confirms.
IDLE_GAP_RATIO = 100.0
#: An idle contact's gap is at least 1 mm: a gap a real rig's tips can reach is never left out.
MIN_IDLE_GAP_M = 1e-3
#: The post-run check: an idle contact's gap never falls below this share of its gap.
REACH_SHARE = 0.5


def is_idle(gap_m: float, approach_m: float) -> bool:
    """Whether blade contacts with gap ``gap_m`` (m) are out of reach of a run whose linear
    approach is ``approach_m`` (m)."""
    return gap_m >= MIN_IDLE_GAP_M and gap_m >= IDLE_GAP_RATIO * approach_m


def report_open(system: SystemResult, idle: tuple, n_recorded: int,
                check: bool = True) -> SystemResult:
    """``system`` (simulated without the ``idle`` point contacts
    (:class:`~rubdiag.simulation.PointContact`, physical DOFs)) with them
    put back first, open throughout. Its recorded columns past ``n_recorded`` are the idle
    contacts' tip DOFs then casing DOFs (y, z each), which give their gaps and slips and are
    then dropped. With ``check``, raises :class:`SimulationDiverged` (with the result) when
    a contact came within ``REACH_SHARE`` of its gap."""
    n = len(idle)
    gaps = np.array([c.gap for c in idle])
    normal = np.array([c.normal for c in idle]).reshape(n, 2)
    tangent = np.array([c.tangent for c in idle]).reshape(n, 2)
    q = system.q
    tips = q[:, n_recorded:n_recorded + 2 * n].reshape(-1, n, 2)
    casing = q[:, n_recorded + 2 * n:n_recorded + 4 * n].reshape(-1, n, 2)
    rel = tips - casing
    gap = gaps - np.einsum("sej,ej->se", rel, normal)
    slip = np.einsum("sej,ej->se", rel, tangent)
    zeros = np.zeros((q.shape[0], n))
    per_element = np.zeros(n)
    open_time = np.zeros((n, 3))
    open_time[:, 0] = system.t_final
    shifted = {f.name: getattr(system.episodes, f.name) for f in dataclasses.fields(EpisodeLog)}
    shifted["element"] = shifted["element"] + n
    segments = {f.name: getattr(system.status_segments, f.name)
                for f in dataclasses.fields(StatusLog)}
    segments["element"] = segments["element"] + n
    out = dataclasses.replace(
        system,
        q=q[:, :n_recorded], record_dofs=system.record_dofs[:n_recorded],
        contact_fn=np.hstack([zeros, system.contact_fn]),
        contact_ft=np.hstack([zeros, system.contact_ft]),
        contact_status=np.hstack([np.ones((q.shape[0], n), system.contact_status.dtype),
                                  system.contact_status]),
        contact_gap=np.hstack([gap, system.contact_gap]),
        contact_slip=np.hstack([slip, system.contact_slip]),
        episodes=EpisodeLog(**shifted), status_segments=StatusLog(**segments),
        time_in_status=np.vstack([open_time, system.time_in_status]),
        normal_impulse=np.vstack([np.zeros((n, 3)), system.normal_impulse]),
        tangential_impulse=np.vstack([np.zeros((n, 3)), system.tangential_impulse]),
        max_normal_force=np.r_[per_element, system.max_normal_force],
        max_tangential_force=np.r_[per_element, system.max_tangential_force],
        max_penetration=np.r_[per_element, system.max_penetration],
        failure_element=system.failure_element + n if system.failure_element else 0,
        extra={**system.extra, "idle_contacts": n})
    closest = float(np.min(gap / gaps)) if gap.size else 1.0
    if check and closest < REACH_SHARE:
        raise SimulationDiverged(
            f"a blade contact left out as out of reach came within {closest:.0%} of its gap "
            f"({float(np.min(gap)):.3g} m of {float(gaps.min()):.3g} m); simulate the run "
            "with Reduction(keep_idle_contacts=True)", out)
    return out
