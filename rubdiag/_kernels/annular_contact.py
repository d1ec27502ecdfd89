"""Shaft–stator annular clearance (kind 2): a shaft node inside a circular stator.

Local coordinates (2): the Cartesian relative displacement of the shaft node (body a) and
the stator (body b, or ground), x0 = y, x1 = z, measured from the clearance's centre
``(centre_y, centre_z)`` (a stator aligned on the loaded rotor is centred on its static
deflection, not on the bearing line). ``r = |x|``, outward normal ``n = x / r``,
tangent ``t = (-n_z, n_y)``; gap ``g = c - r`` for the radial clearance c (the gap
parameter). The normal and tangential laws are the point contact's
(:mod:`rubdiag._kernels.point_contact`) along the turning normal; the tangential slip of a
step includes the shaft's surface travel ``Ω R h`` (the ``speed`` parameter Ω R times the
step), so a rubbing shaft is dragged backwards by friction. The generalised force is
``p = -F_N n + F_T t``; its Jacobian includes the turning of the normal.

Parameters and books: :mod:`rubdiag._kernels.contact_books`; the slip record adds up the
trial tangential increments of the engaged steps.
"""

from __future__ import annotations

import math

from rubdiag._kernels.contact_books import (
    CENTRE_Y,
    CENTRE_Z,
    K_N,
    K_T,
    MU,
    SPEED,
    E,
    books,
    gap_at,
    record,
)
from rubdiag._kernels.records import D_NEW, OPEN, SLIDING, STICKING, X_N
from rubdiag._numba import njit

__all__ = ["KIND", "N_LOCAL", "books", "force", "law"]

KIND = 2
N_LOCAL = 2


@njit(error_model="numpy", inline="always")
def force(x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n, drive):
    """The law (module docstring) at the relative displacement (x0, x1).

    Parameters
    ----------
    x0, x1 : float
        The shaft's displacement from the clearance's centre, y and z (m).
    x0n, x1n : float
        The same at the step's start (m).
    g0 : float
        The radial clearance (m).
    kn, kt : float
        The normal and tangential stiffness (N/m).
    mu : float
        The Coulomb coefficient.
    lam : float
        The multiplier (N; 0 for pure penalty).
    e_n : float
        The elastic tangential displacement at the step's start (m).
    drive : float
        The surface travel Ω R h of the step (m).

    Returns
    -------
    tuple
        As :func:`rubdiag._kernels.point_contact.force`.
    """
    r = math.sqrt(x0 * x0 + x1 * x1)
    gap = g0 - r
    z = lam - kn * gap
    if z <= 0.0 or r == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, OPEN, 0.0, 0.0, 0.0, 0.0, gap, z
    fn = z
    n0 = x0 / r
    n1 = x1 / r
    t0 = -n1
    t1 = n0
    dx0 = x0 - x0n
    dx1 = x1 - x1n
    e_tr = e_n + t0 * dx0 + t1 * dx1 + drive
    ft_tr = -kt * e_tr
    if mu > 0.0 and abs(ft_tr) <= mu * fn:
        ft = ft_tr
        st = STICKING
        e_new = e_tr
        # dF_T/dx = -k_T t (1 - n.(x - x_n)/r)
        fac = -kt * (1.0 - (n0 * dx0 + n1 * dx1) / r)
        g0x = fac * t0
        g1x = fac * t1
    else:
        sg = 1.0 if e_tr > 0.0 else (-1.0 if e_tr < 0.0 else 0.0)
        ft = -mu * fn * sg
        st = SLIDING
        e_new = -ft / kt
        g0x = -mu * sg * kn * n0
        g1x = -mu * sg * kn * n1
    p0 = -fn * n0 + ft * t0
    p1 = -fn * n1 + ft * t1
    # J = -k_N n n^T - (F_N / r) t t^T + t (grad F_T)^T - (F_T / r) n t^T
    a = fn / r
    b = ft / r
    j00 = -kn * n0 * n0 - a * t0 * t0 + t0 * g0x - b * n0 * t0
    j01 = -kn * n0 * n1 - a * t0 * t1 + t0 * g1x - b * n0 * t1
    j10 = -kn * n1 * n0 - a * t1 * t0 + t1 * g0x - b * n1 * t0
    j11 = -kn * n1 * n1 - a * t1 * t1 + t1 * g1x - b * n1 * t1
    return p0, p1, j00, j01, j10, j11, st, fn, ft, e_new, e_tr, gap, z


@njit(error_model="numpy", inline="always")
def law(e, elements, local_work, local_state, parameters, element_state, track, trial, progress,
        jacobian):
    """The seam's law for element ``e`` (module docstring).

    Parameters
    ----------
    e : int
        The element.
    elements, local_work, local_state, parameters, element_state : ndarray
        As for :func:`rubdiag._kernels.elements.element_laws`.
    track, trial, progress, jacobian : ndarray
        As for :func:`rubdiag._kernels.elements.element_laws`.

    Returns
    -------
    int
        The element's status.
    """
    r = elements[e].row
    h = progress[0].h
    g1 = gap_at(parameters, e, progress[0].t_1, h)
    e_n = element_state[0, e, E]
    c0 = parameters[e, CENTRE_Y]
    c1 = parameters[e, CENTRE_Z]
    out = force(local_work[D_NEW, r] - c0, local_work[D_NEW, r + 1] - c1,
                local_state[X_N, r] - c0, local_state[X_N, r + 1] - c1, g1, parameters[e, K_N],
                parameters[e, K_T], parameters[e, MU], trial[e].lam, e_n,
                parameters[e, SPEED] * h)
    slip = track[e].slip
    if out[6] != OPEN:
        slip += out[10] - e_n
    record(e, r, local_work, jacobian, element_state, trial, out, slip)
    return out[6]

