"""The books of an accepted step: the energy ledger, the episode and segment logs, each
element's totals, and the elements' new state.

The ledger adds the step's external work, viscous dissipation and the elements' energy
terms, and what remains of the work the element forces did on the structure (the
algorithmic remainder, ``d_num``) into the loop's record (:func:`energy_ledger`). An
episode is a maximal run of engaged steps of one element, a segment a maximal run of one
engaged status (for contacts: sliding, sticking); both are logged when they end, with
their start and end interpolated where the engagement function crosses 0
(:func:`log_episodes`). Each element's totals by status and its maxima (:func:`commit_elements`)
are what a run reports of its contacts.
"""

from __future__ import annotations

from rubdiag._kernels.elements import local_coords
from rubdiag._kernels.records import OPEN, P_NEW, SLIDING, STICKING, X_N, XA_N, XV_N, V
from rubdiag._numba import njit

__all__ = ["commit_elements", "energy_ledger", "force_work", "log_episodes", "logs_full"]


@njit(error_model="numpy")
def force_work(load_dofs, load_re, load_im, load_groups, group_factors, dq):
    """The work of the load over a step, by the trapezoid rule:
    ``Σ dq[load_dofs] (f(t_n) + f(t_1)) / 2``
    (:func:`~rubdiag._kernels.increment.add_force`).

    Parameters
    ----------
    load_dofs, load_re, load_im, load_groups, group_factors : ndarray
        The load (:func:`~rubdiag._kernels.increment.add_force`).
    dq : ndarray (n)
        The step's displacement increment (m).

    Returns
    -------
    float
        The work (J).
    """
    w = 0.0
    for k in range(load_dofs.shape[0]):
        g = load_groups[k]
        fa = ((load_re[k] * group_factors[g, 0] - load_im[k] * group_factors[g, 1])
              + (load_re[k] * group_factors[g, 2] - load_im[k] * group_factors[g, 3]))
        w += dq[load_dofs[k]] * 0.5 * fa
    return w


@njit(error_model="numpy")
def energy_ledger(progress, dvisc, dq, load_dofs, load_re, load_im, load_groups,
                  group_factors, local_force, elements, row_dofs, transforms, local_work,
                  trial):
    """The energy ledger of the accepted step.

    The external work, the viscous dissipation (``dvisc / h``), and the elements' terms
    (each law's trial record): the drive work (the prescribed gap motion, the surface
    travel), the friction dissipation, the elastic energy stored, and the algorithmic
    remainder of the work the element forces did on the structure, ``B dq · (p_n +
    p_{n+1}) / 2``. Reads the committed state.

    Parameters
    ----------
    progress : ndarray (1) records.PROGRESS
        The ledger (J) and the step's length, added to.
    dvisc : float
        ``dqᵀ C dq`` (J s).
    dq : ndarray (n)
        The step's displacement increment (m).
    load_dofs, load_re, load_im, load_groups, group_factors : ndarray
        The load (:func:`force_work`).
    local_force : ndarray (m)
        The elements' local forces at the step's start (N).
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates.
    local_work : ndarray (WC_SIZE, m)
        Its row ``P_NEW`` holds the forces at the step's end (N); row ``V`` is work.
    trial : ndarray (n_e) records.TRIAL
        Each element's law at the step's end, with its energy terms (J).
    """
    h = progress[0].h
    progress[0].d_visc += dvisc / h
    progress[0].w_ext += force_work(load_dofs, load_re, load_im, load_groups, group_factors,
                                    dq)
    local_coords(elements, elements.shape[0], row_dofs, transforms, dq, local_work, V)
    w_struct = 0.0
    for i in range(local_work.shape[1]):
        w_struct += local_work[V, i] * 0.5 * (local_work[P_NEW, i] + local_force[i])
    wdrive = 0.0
    dfric = 0.0
    ec = 0.0
    for e in range(elements.shape[0]):
        engaged = trial[e].status != OPEN
        w_ramp = trial[e].w_ramp
        elastic = trial[e].elastic
        w_surface = trial[e].w_surface
        dissipated = trial[e].dissipated
        wdrive -= w_ramp
        if engaged:
            ec += elastic
            wdrive -= w_surface
            dfric += dissipated
    progress[0].w_drive += wdrive
    progress[0].d_fric += dfric
    progress[0].d_num += -w_struct + wdrive - (ec - progress[0].e_contact) - dfric
    progress[0].e_contact = ec


@njit
def _log_segment(segments, progress, e, status, t_start, t_end):
    """Log element ``e``'s segment of one engaged ``status`` from ``t_start`` to ``t_end``
    (s)."""
    pr = progress[0]
    k = pr.n_segments
    segments[k].t_start = t_start
    segments[k].t_end = t_end
    segments[k].element = e
    segments[k].status = status
    pr.n_segments = k + 1


@njit(error_model="numpy")
def log_episodes(progress, trial, track, episodes, segments):
    """Each element's current episode and status segment over the accepted step: opened,
    counted, or ended and logged.

    A step counts with its end-of-step status; the episode's start and end are where the
    trial engagement function z crosses 0 within the step.

    Parameters
    ----------
    progress : ndarray (1) records.PROGRESS
        The step's clock; the logs' counts, added to.
    trial : ndarray (n_e) records.TRIAL
        Each element's law at the step's end.
    track : ndarray (n_e) records.TRACK
        Each element's committed status and current episode, updated (its status is left
        for :func:`commit_elements`).
    episodes : ndarray (cap) records.EPISODE
        The log of ended episodes.
    segments : ndarray (cap) records.SEGMENT
        The log of status segments.
    """
    pr = progress[0]
    h = pr.h
    t_n = pr.t_n
    for e in range(track.shape[0]):
        k = track[e]
        so = k.status
        sn = trial[e].status
        fn = trial[e].fn
        zo = k.z
        zn = trial[e].z
        if so == OPEN and sn != OPEN:
            frac = zo / (zo - zn) if zo < 0.0 else 0.0
            k.ep_start = t_n + frac * h
            k.ep_peak_fn = 0.0
            k.ep_slide_time = 0.0
            k.ep_stick_time = 0.0
            k.ep_slide_impulse = 0.0
            k.ep_stick_impulse = 0.0
            k.ep_steps = 0
            k.ep_slide_entries = 0
            k.ep_stick_entries = 0
            k.seg_start = k.ep_start
        elif so != OPEN and sn != OPEN and sn != so:
            # sliding <-> sticking: the step counts with its new status
            _log_segment(segments, progress, e, so, k.seg_start, t_n)
            k.seg_start = t_n
        if sn != OPEN:
            k.ep_steps += 1
            if fn > k.ep_peak_fn:
                k.ep_peak_fn = fn
            if sn == SLIDING and so != SLIDING:
                k.ep_slide_entries += 1
            if sn == STICKING and so != STICKING:
                k.ep_stick_entries += 1
            if sn == SLIDING:
                k.ep_slide_time += h
                k.ep_slide_impulse += fn * h
            else:
                k.ep_stick_time += h
                k.ep_stick_impulse += fn * h
        elif so != OPEN:
            # episode ends inside this step: interpolate the trial normal force to zero
            frac = zo / (zo - zn) if zn < 0.0 and zo > 0.0 else 1.0
            j = pr.n_episodes
            episodes[j].t_start = k.ep_start
            episodes[j].t_end = t_n + frac * h
            episodes[j].peak_fn = k.ep_peak_fn
            episodes[j].slide_time = k.ep_slide_time
            episodes[j].stick_time = k.ep_stick_time
            episodes[j].slide_impulse = k.ep_slide_impulse
            episodes[j].stick_impulse = k.ep_stick_impulse
            episodes[j].element = e
            episodes[j].steps = k.ep_steps
            episodes[j].slide_entries = k.ep_slide_entries
            episodes[j].stick_entries = k.ep_stick_entries
            pr.n_episodes = j + 1
            _log_segment(segments, progress, e, so, k.seg_start, episodes[j].t_end)


@njit
def commit_elements(run, progress, trial, element_state, track, stats, local_work,
                    local_force, elements, row_dofs, transforms, q, v, a, local_state):
    """The accepted step's totals and maxima per element, then its trial state becomes the
    current one.

    Parameters
    ----------
    run : ndarray (1) records.RUN
        The run's parameters (whether a kind reads the local rates).
    progress : ndarray (1) records.PROGRESS
        The step's length; the largest cone excess (N), updated.
    trial : ndarray (n_e) records.TRIAL
        Each element's law at the step's end.
    element_state : ndarray (2, n_e, n_s)
        Each element's own state: the trial one (``[1]``) is committed (``[0]``).
    track : ndarray (n_e) records.TRACK
        Each element's committed record, updated.
    stats : ndarray (n_e) records.STATS
        Each element's totals (s, N s) and maxima (N, m), added to.
    local_work : ndarray (WC_SIZE, m)
        Its row ``P_NEW``: the local forces at the step's end (N).
    local_force : ndarray (m)
        The local forces (N), set to those.
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates.
    q, v, a : ndarray (n)
        The new state (m, m/s, m/s²).
    local_state : ndarray (3, m)
        The local displacement, velocity and acceleration, set from q, v, a (``d_new`` is
        only the Newton solve's, to its tolerance).
    """
    h = progress[0].h
    for e in range(elements.shape[0]):
        sn = trial[e].status
        fn = trial[e].fn
        ft = trial[e].ft
        depth = -trial[e].gap
        cone = trial[e].cone
        stats[e].time[sn - 1] += h
        stats[e].fn_impulse[sn - 1] += fn * h
        stats[e].ft_impulse[sn - 1] += abs(ft) * h
        if fn > stats[e].max_fn:
            stats[e].max_fn = fn
        if abs(ft) > stats[e].max_ft:
            stats[e].max_ft = abs(ft)
        if depth > stats[e].max_penetration:
            stats[e].max_penetration = depth
        if cone > progress[0].cone_excess:
            progress[0].cone_excess = cone
        track[e].status = sn
        track[e].fn = fn
        track[e].ft = ft
        track[e].gap = trial[e].gap
        track[e].z = trial[e].z
        track[e].slip = trial[e].slip
        for j in range(element_state.shape[2]):
            element_state[0, e, j] = element_state[1, e, j]
    for i in range(local_force.shape[0]):
        local_force[i] = local_work[P_NEW, i]
    ne = elements.shape[0]
    local_coords(elements, ne, row_dofs, transforms, q, local_state, X_N)
    # the local velocity and acceleration for the kinds that read them (none of today's:
    # then no element; a count, not a branch, keeps the arrays free of reference counting)
    n_kin = ne if run[0].kinematics != 0 else 0
    local_coords(elements, n_kin, row_dofs, transforms, v, local_state, XV_N)
    local_coords(elements, n_kin, row_dofs, transforms, a, local_state, XA_N)


@njit
def logs_full(n_elements, progress, episodes, segments, change_times):
    """Whether a step could overflow the episode, segment or level-change log (a step logs
    at most one episode and one segment per element, and one level change).

    Parameters
    ----------
    n_elements : int
        n_e.
    progress : ndarray (1) records.PROGRESS
        The logs' counts.
    episodes, segments, change_times : ndarray
        The logs.

    Returns
    -------
    bool
    """
    pr = progress[0]
    full_episodes = pr.n_episodes + n_elements > episodes.shape[0]
    full_segments = pr.n_segments + n_elements > segments.shape[0]
    full_levels = pr.n_level_changes + 2 > change_times.shape[0]
    return full_episodes or full_segments or full_levels
