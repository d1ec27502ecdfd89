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
def gap_at(par, e, t, h):
    """Element ``e``'s gap g0 at time t: on the gap ramp (t < t_ramp) linearly from its start
    value at t = 0; at rest (``h`` = 0: the state at t = 0 before any step) the start value
    itself."""
    g0 = par[e, GAP]
    t_ramp = par[e, T_RAMP]
    ramp = t_ramp > 0.0 and t < t_ramp
    frac = 1.0 - t / t_ramp if ramp else 0.0
    g = g0 + (par[e, GAP_START] - g0) * frac if ramp else g0
    return g if h > 0.0 else par[e, GAP_START]


@njit(error_model="numpy", inline="always")
def record(e, r, wc, jac, es, trial, out, slip):
    """What element ``e`` (local rows r, r + 1) keeps of its law's outputs ``out`` (the
    kinds' ``force``: p, dp/dx, status, F_N, F_T, the new and the trial elastic tangential
    displacement, gap, z) and its slip record: the force ``wc[P_NEW]``, the Jacobian, the
    trial record and its new state (``e``, 0 when open; the trial one for the books)."""
    wc[P_NEW, r] = out[0]
    wc[P_NEW, r + 1] = out[1]
    jac[r, 0] = out[2]
    jac[r, 1] = out[3]
    jac[r + 1, 0] = out[4]
    jac[r + 1, 1] = out[5]
    status = out[6]
    trial[e].status = status
    trial[e].fn = out[7]
    trial[e].ft = out[8]
    trial[e].gap = out[11]
    trial[e].z = out[12]
    trial[e].slip = slip
    es[1, e, E] = out[9] if status != OPEN else 0.0
    es[1, e, E_TRIAL] = out[10]


@njit(error_model="numpy")
def books(e, el, par, es, track, trial, prog):
    """Element ``e``'s energy terms and cone excess of the accepted step (module
    docstring), from its trial record and state. (Every array is read on every path: an
    array read in one branch only brings Numba's reference counting into the caller.)"""
    t_n = prog[0].t_n
    t_1 = prog[0].t_1
    h = prog[0].h
    t_ramp = par[e, T_RAMP]
    k_n = par[e, K_N]
    k_t = par[e, K_T]
    speed = par[e, SPEED]
    mu = par[e, MU]
    status = trial[e].status
    fn = trial[e].fn
    ft = trial[e].ft
    fn_n = track[e].fn
    e_tr = es[1, e, E_TRIAL]
    e_new = es[1, e, E]
    g_1 = gap_at(par, e, t_1, h)
    g_n = gap_at(par, e, t_n, h)
    ramp = t_ramp > 0.0 and t_n < t_ramp
    engaged = status != OPEN
    trial[e].w_ramp = 0.5 * (fn + fn_n) * (g_1 - g_n) if ramp else 0.0
    trial[e].elastic = 0.5 * fn * fn / k_n + 0.5 * ft * ft / k_t if engaged else 0.0
    trial[e].w_surface = ft * speed * h if engaged else 0.0
    trial[e].dissipated = abs(ft) * abs(e_tr - e_new) if status == SLIDING else 0.0
    trial[e].cone = abs(ft) - mu * fn
