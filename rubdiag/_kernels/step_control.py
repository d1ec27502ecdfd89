"""Step control: which level a step is taken at, when it is retried shorter, when the step
doubles (the rules are in :mod:`rubdiag._kernels.newmark`'s docstring).

Step sizes are levels ``h_k = dt / 2^k``; time is an integer tick count. A converged trial
step is retried lower when an element closed abruptly or needs a smaller step
(:func:`level_needed`), or, for a step longer than the base step, when its local error
estimate (:func:`local_error`) is above the tolerance (:func:`error_level`). An accepted
step moves the clock on and may double the next one (:func:`advance`,
:func:`may_lengthen`); every level change is logged (:func:`change_level`).
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels.elements import local_coords
from rubdiag._kernels.records import OPEN, V
from rubdiag._numba import njit

__all__ = ["GAP_MARGIN", "GROW_ERROR", "advance", "change_level", "error_level",
           "error_wanted", "level_needed", "local_error", "may_lengthen", "reject",
           "step_level"]

#: a step may double past the base step when its error estimate is at most this share of
#: the tolerance: the estimate grows as h³, so the doubled step's is about 8 times this one's
GROW_ERROR = 0.7 / 8.0
#: a long step keeps each open impact element's gap above this many times the gap's change
#: over the step (twice that before the step doubles)
GAP_MARGIN = 2.0


@njit
def step_level(level, base_level, finest, tick, out_ticks, tick_stop):
    """The level of the next step: ``level``, or for a long one (``level < base_level``) the
    longest not longer that starts on a multiple of its own length and ends by the next
    recorded sample and by ``tick_stop``, so that samples stay exact step ends (the base
    step and shorter ones are never cut: ``out_ticks`` is a multiple of the base step).

    Parameters
    ----------
    level : int
        The level asked for.
    base_level, finest : int
        The base step's level and the smallest step's (``n_lev - 1``).
    tick : int
        The step's start (ticks of the smallest step).
    out_ticks : int
        Ticks between recorded samples.
    tick_stop : int
        A long step does not cross this tick.

    Returns
    -------
    int
        The step's level.
    """
    while level < base_level:
        n_ticks = np.int64(1) << (finest - level)
        next_sample = (tick // out_ticks + 1) * out_ticks
        if tick % n_ticks == 0 and tick + n_ticks <= next_sample and tick + n_ticks <= tick_stop:
            break
        level += 1
    return level


@njit
def level_needed(run, level, elements, track, trial):
    """The level a converged step must be retried at (``level``: none).

    One down when an element open at the start ends deeper than ``run.gap_jump`` (an abrupt
    closing), and at least the ``lev_req`` of every element engaged at the start or end;
    on a long step, the base level when an open impact element could close within one more
    such step (:data:`GAP_MARGIN`).

    Parameters
    ----------
    run : ndarray (1) records.RUN
        The run's parameters.
    level : int
        The step's level.
    elements : ndarray (n_e) records.ELEMENT
        Each element's step requirement and whether it impacts.
    track, trial : ndarray (n_e) records.TRACK, records.TRIAL
        Each element at the step's start and at its end.

    Returns
    -------
    int
        The level needed.
    """
    gap_jump = run[0].gap_jump
    long_step = level < run[0].base_level
    need = level
    for e in range(elements.shape[0]):
        was_open = track[e].status == OPEN
        now_open = trial[e].status == OPEN
        depth = -trial[e].gap
        lev_req = elements[e].lev_req
        if was_open and not now_open and depth > gap_jump:
            need = max(need, level + 1)
        if (not was_open or not now_open) and lev_req > need:
            need = lev_req
        if long_step and elements[e].impact != 0 and now_open:
            # the gap predictor: one more such step could close it (or it closed and
            # opened again within this one): back to the base step
            g1 = trial[e].gap
            if g1 <= GAP_MARGIN * abs(g1 - track[e].gap):
                need = max(need, run[0].base_level)
    return need


@njit(error_model="numpy")
def local_error(beta, h, dq, v, a, w, record_dofs, record_map, sensor_dofs, sensor_map,
                elements, row_dofs, transforms, local_work):
    """The trial's local error estimate by Zienkiewicz and Xie (1991).

    ``e = (β - 1/6) h² (a_{n+1} - a_n) = (1 - 1/(6β)) (Δq - h v_n - h² a_n / 2)`` (from the
    Newmark relation for ``a_{n+1}``), largest over the recorded DOFs, the sensor DOFs and
    the impact elements' local coordinates. Called only for a long step or one that may
    lengthen (its reference counting is then the controller's, on those steps only).

    Parameters
    ----------
    beta : float
        Newmark's β.
    h : float
        The step (s).
    dq : ndarray (n)
        The trial's increment (m).
    v, a : ndarray (n)
        Velocity (m/s) and acceleration (m/s²) at the step's start.
    w : ndarray (n)
        Work.
    record_dofs, record_map, sensor_dofs, sensor_map : ndarray
        The recorded and the sensor DOFs (:func:`largest`).
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates.
    local_work : ndarray (WC_SIZE, m)
        Its row ``V`` is work.

    Returns
    -------
    float
        The estimate (m).
    """
    c = abs(1.0 - 1.0 / (6.0 * beta))
    half_h2 = 0.5 * h * h
    for i in range(w.shape[0]):
        w[i] = dq[i] - h * v[i] - half_h2 * a[i]
    err = max(largest(record_map, record_dofs, w), largest(sensor_map, sensor_dofs, w))
    local_coords(elements, elements.shape[0], row_dofs, transforms, w, local_work, V)
    for e in range(elements.shape[0]):
        if elements[e].impact != 0:
            for r in range(elements[e].row, elements[e].row + elements[e].n):
                err = max(err, abs(local_work[V, r]))
    return c * err


@njit(error_model="numpy")
def largest(map_t, dofs, x):
    """``max |x[dofs]|``, or ``max |mapᵀ x|`` for a non-empty ``map_t``.

    Parameters
    ----------
    map_t : ndarray (n, n_out)
        The recovery map of a reduced model's physical DOFs, or empty (0, 0).
    dofs : ndarray (n_out) int
        The DOFs read when there is no map.
    x : ndarray (n)
        The vector.

    Returns
    -------
    float
        The largest magnitude, in x's unit.
    """
    big = 0.0
    if map_t.shape[0] == 0:
        for r in range(dofs.shape[0]):
            big = max(big, abs(x[dofs[r]]))
        return big
    for r in range(map_t.shape[1]):
        acc = 0.0
        for j in range(map_t.shape[0]):
            acc += map_t[j, r] * x[j]
        big = max(big, abs(acc))
    return big


@njit
def error_wanted(code, tol, level, base_level, may_grow, elements, track):
    """Whether a trial needs its error estimate.

    A converged long step, or a base step that may grow past the base from a start where
    every impact element is open (else :func:`may_lengthen` refuses whatever the error: a
    rubbing run skips the estimate at every step), with a tolerance.

    Parameters
    ----------
    code : int
        The element solve's code (0: converged).
    tol : float
        ``run.step_error`` (0: no long steps).
    level, base_level : int
        The step's level and the base step's.
    may_grow : bool
        Quiet long enough to grow.
    elements, track : ndarray (n_e)
        The elements' records and their state at the step's start.

    Returns
    -------
    bool
    """
    if code != 0 or tol <= 0.0 or level > base_level:
        return False
    if level < base_level:
        return True
    if not may_grow:
        return False
    for e in range(elements.shape[0]):
        if elements[e].impact != 0 and track[e].status != OPEN:
            return False
    return True


@njit(error_model="numpy")
def error_level(need, level, base_level, err, tol):
    """A long step otherwise accepted (``need == level``) whose error ``err`` is above
    ``tol`` goes down by :func:`levels_down`.

    Parameters
    ----------
    need, level, base_level : int
        The level needed so far, the step's, the base step's.
    err, tol : float
        The error estimate and its tolerance (m; ``err`` < 0: none).

    Returns
    -------
    tuple of (int, bool)
        The level needed, and whether the error asks for it.
    """
    if need == level and level < base_level and err > tol:
        return level + levels_down(err / tol, base_level - level), True
    return need, False


@njit(error_model="numpy")
def levels_down(ratio, room):
    """How many levels a long step rejected at ``ratio`` = error / tolerance goes down, at
    most ``room``: the error grows as h³, so a step ``2^-k`` as long has ``8^-k`` of it,
    with a margin of 0.9 on the step.

    Parameters
    ----------
    ratio : float
        The error over its tolerance (> 1).
    room : int
        Levels down to the base step.

    Returns
    -------
    int
    """
    k = 1
    while k < room and ratio > 0.729 * 8.0 ** k:
        k += 1
    return k


@njit(error_model="numpy")
def may_lengthen(err, tol, elements, track, trial):
    """Whether the step may double past the base step: its error estimate leaves room for a
    step twice as long (:data:`GROW_ERROR`), and every impact element stays open with the
    margin of a step twice as long.

    Parameters
    ----------
    err, tol : float
        The error estimate (m; < 0: none, then False) and its tolerance.
    elements : ndarray (n_e) records.ELEMENT
        The elements' records.
    track, trial : ndarray (n_e) records.TRACK, records.TRIAL
        Each element at the step's start and at its end.

    Returns
    -------
    bool
    """
    ok = 0.0 <= err <= GROW_ERROR * tol
    for e in range(elements.shape[0]):
        if elements[e].impact != 0:
            g1 = trial[e].gap
            opened = track[e].status == OPEN and trial[e].status == OPEN
            ok = ok and opened and g1 > 2.0 * GAP_MARGIN * abs(g1 - track[e].gap)
    return ok


@njit
def reject(progress, change_times, change_levels, t, level, failed, by_error):
    """Retry the step at ``level`` (:func:`change_level`), counting why: the element solve
    ``failed``, the error estimate (``by_error``), or an abrupt closing or too stiff a
    contact.

    Parameters
    ----------
    progress : ndarray (1) records.PROGRESS
        The loop's counters.
    change_times, change_levels : ndarray
        The level-change log (s, int).
    t : float
        The step's start (s).
    level : int
        The level it is retried at.
    failed, by_error : bool
        Why.
    """
    change_level(progress, change_times, change_levels, t, level)
    pr = progress[0]
    pr.n_rej_newton += 1 if failed else 0
    pr.n_rej_error += 1 if by_error and not failed else 0
    pr.n_rej_abrupt += 1 if not (failed or by_error) else 0


@njit
def change_level(progress, change_times, change_levels, t, level):
    """Go on at ``level`` from time ``t``, logged.

    Parameters
    ----------
    progress : ndarray (1) records.PROGRESS
        The loop's counters.
    change_times, change_levels : ndarray
        The level-change log (s, int).
    t : float
        When (s).
    level : int
        The new level.
    """
    pr = progress[0]
    pr.level = level
    pr.quiet = 0
    k = pr.n_level_changes
    change_times[k] = t
    change_levels[k] = level
    pr.n_level_changes = k + 1


@njit(error_model="numpy")
def advance(run, progress, level, n_ticks, elements, track, steps_per_level, lengthen):
    """Count the accepted step and move the clock on.

    The next step may be twice as long after ``grow_after`` quiet steps at this level (the
    level asked for, not one cut short), when the new tick is aligned to it, every engaged
    element allows it (``lev_req``) and, past the base step, ``lengthen``.

    Parameters
    ----------
    run : ndarray (1) records.RUN
        The run's parameters.
    progress : ndarray (1) records.PROGRESS
        The loop's counters and clock.
    level, n_ticks : int
        The step's level and length (ticks).
    elements, track : ndarray (n_e)
        The elements' records and their committed state.
    steps_per_level : ndarray (L) int
        Accepted steps per level.
    lengthen : bool
        :func:`may_lengthen`.

    Returns
    -------
    tuple of (int, bool)
        The new tick, and whether the next step may be twice as long.
    """
    fixed = run[0].fixed != 0
    grow_after = run[0].grow_after
    asked = progress[0].level == level
    past_base = level <= run[0].base_level
    tick = progress[0].tick + n_ticks
    progress[0].tick = tick
    progress[0].n_accepted += 1
    steps_per_level[level] += 1
    quiet = progress[0].quiet + 1
    progress[0].quiet = quiet
    grow = (not fixed and level > 0 and quiet >= grow_after and tick % (2 * n_ticks) == 0
            and asked and (lengthen or not past_base))
    for e in range(elements.shape[0]):
        engaged = track[e].status != OPEN
        lev_req = elements[e].lev_req
        if engaged and lev_req >= level:
            grow = False
    return tick, grow
