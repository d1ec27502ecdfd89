"""What the two contact kinds share: their parameters, the gap ramp and the books of a step.

A contact element (:mod:`~rubdiag._kernels.point_contact`,
:mod:`~rubdiag._kernels.annular_contact`) has the parameters :data:`PARAMS` — its gap (or
radial clearance) g0 (m), the gap at t = 0 of a gap ramp and the ramp's end (s; 0: no ramp),
the normal and tangential stiffness (N/m), the Coulomb coefficient and the surface speed Ω R
(m/s; 0 for a point contact), and the centre of an annular clearance (m, y and z; 0 for a
point contact) — and one state variable, the elastic tangential displacement
``e`` (m). Its law (the kind's module) gives the forces and :func:`record` keeps them as the
trial record (status, forces, gap, z, slip) and state; when the step is accepted,
:func:`books` gives the step's energy terms, which the ledger adds:

* elastic energy stored ``F_N² / (2 k_N) + F_T² / (2 k_T)`` (engaged only);
* friction dissipation ``|F_T| |e_tr - e|`` (sliding only: the slip of the return mapping);
* work of the prescribed gap motion on the ramp, ``(F_N,n + F_N,n+1) / 2 (g0(t_1) - g0(t_n))``
  (trapezoid), and of the surface drive, ``F_T Ω R h`` — both as the ledger subtracts them;
* the cone excess ``|F_T| - mu F_N`` (N), zero up to round-off when the law holds.
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels.records import OPEN, P_NEW, SLIDING
from rubdiag._numba import njit

__all__ = ["E_TRIAL", "PARAMS", "STATE", "E", "books", "gap_at", "parameters", "record"]

#: a contact element's parameter row, by name (the law reads these columns)
PARAMS = ("gap", "gap_start", "t_ramp", "k_n", "k_t", "mu", "speed", "centre_y", "centre_z")
GAP, GAP_START, T_RAMP, K_N, K_T, MU, SPEED, CENTRE_Y, CENTRE_Z = range(len(PARAMS))
#: its state: the elastic tangential displacement (m) and, for the books, its trial value
STATE = ("e", "e_trial")
E, E_TRIAL = range(len(STATE))


def parameters(**values: float) -> np.ndarray:
    """A contact element's parameter row from its values by name (every name of
    :data:`PARAMS`)."""
    missing = set(PARAMS) - set(values)
    if missing or set(values) - set(PARAMS):
        raise ValueError(f"contact parameters {sorted(values)}: expected exactly {PARAMS}")
    return np.array([float(values[name]) for name in PARAMS])


@njit(error_model="numpy", inline="always")
def gap_at(parameters, e, t, h):
    """Element ``e``'s gap g0 at time t: on the gap ramp (t < t_ramp) linearly from its start
    value at t = 0; at rest (``h`` = 0: the state at t = 0 before any step) the start value
    itself.

    Parameters
    ----------
    parameters : ndarray (n_e, n_par)
        The elements' parameter rows (:data:`PARAMS`).
    e : int
        The element.
    t : float
        The time (s).
    h : float
        The step (s; 0 at rest).

    Returns
    -------
    float
        The gap (m).
    """
    g0 = parameters[e, GAP]
    t_ramp = parameters[e, T_RAMP]
    ramp = t_ramp > 0.0 and t < t_ramp
    frac = 1.0 - t / t_ramp if ramp else 0.0
    g = g0 + (parameters[e, GAP_START] - g0) * frac if ramp else g0
    return g if h > 0.0 else parameters[e, GAP_START]


@njit(error_model="numpy", inline="always")
def record(e, r, local_work, jacobian, element_state, trial, out, slip):
    """What element ``e`` keeps of its law's outputs: the force, the Jacobian, the trial
    record and its new state (``e``, 0 when open; the trial one for the books).

    Parameters
    ----------
    e : int
        The element.
    r : int
        Its first local row (it has two).
    local_work : ndarray (WC_SIZE, m)
        The force goes to row ``P_NEW`` (N).
    jacobian : ndarray (m, N_LOCAL_MAX)
        Its block of dp/dx (N/m), written.
    element_state : ndarray (2, n_e, n_s)
        Its trial state (``[1]``), written.
    trial : ndarray (n_e) records.TRIAL
        Its trial record, written.
    out : tuple
        The kind's ``force``: p (N), dp/dx (N/m), status, F_N, F_T (N), the new and the
        trial elastic tangential displacement, gap (m), z (N).
    slip : float
        Its slip record (m).
    """
    local_work[P_NEW, r] = out[0]
    local_work[P_NEW, r + 1] = out[1]
    jacobian[r, 0] = out[2]
    jacobian[r, 1] = out[3]
    jacobian[r + 1, 0] = out[4]
    jacobian[r + 1, 1] = out[5]
    status = out[6]
    trial[e].status = status
    trial[e].fn = out[7]
    trial[e].ft = out[8]
    trial[e].gap = out[11]
    trial[e].z = out[12]
    trial[e].slip = slip
    element_state[1, e, E] = out[9] if status != OPEN else 0.0
    element_state[1, e, E_TRIAL] = out[10]


@njit(error_model="numpy")
def books(e, elements, parameters, element_state, track, trial, progress):
    """Element ``e``'s energy terms (J) and cone excess (N) of the accepted step (module
    docstring), from its trial record and state, into ``trial[e]``. (Every array is read on
    every path: an array read in one branch only brings Numba's reference counting into the
    caller.)

    Parameters
    ----------
    e : int
        The element.
    elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`rubdiag._kernels.elements.element_books`.
    """
    t_n = progress[0].t_n
    t_1 = progress[0].t_1
    h = progress[0].h
    t_ramp = parameters[e, T_RAMP]
    k_n = parameters[e, K_N]
    k_t = parameters[e, K_T]
    speed = parameters[e, SPEED]
    mu = parameters[e, MU]
    status = trial[e].status
    fn = trial[e].fn
    ft = trial[e].ft
    fn_n = track[e].fn
    e_tr = element_state[1, e, E_TRIAL]
    e_new = element_state[1, e, E]
    g_1 = gap_at(parameters, e, t_1, h)
    g_n = gap_at(parameters, e, t_n, h)
    ramp = t_ramp > 0.0 and t_n < t_ramp
    engaged = status != OPEN
    trial[e].w_ramp = 0.5 * (fn + fn_n) * (g_1 - g_n) if ramp else 0.0
    trial[e].elastic = 0.5 * fn * fn / k_n + 0.5 * ft * ft / k_t if engaged else 0.0
    trial[e].w_surface = ft * speed * h if engaged else 0.0
    trial[e].dissipated = abs(ft) * abs(e_tr - e_new) if status == SLIDING else 0.0
    trial[e].cone = abs(ft) - mu * fn
