"""Point–point contact (kind 1, the study's Conta178): a blade tip against a casing node.

Local coordinates (2): the relative displacement ``u_a - u_b`` of the tip (body a) and the
casing node (body b, or ground) on the element's fixed normal ``n`` (x0, from a towards b)
and tangent ``t`` (x1). Gap ``g = g0 - x0``; relative tangential displacement ``s = x1``.

Normal law (the study's eqs (1)–(2)): with the multiplier ``lam`` (0 for pure penalty),
``z = lam - k_N g`` and ``F_N = max(0, z)`` (compressive magnitude); for ``lam = 0`` exactly
eq. (1), ``F_N = -k_N g`` when ``g <= 0``.

Tangential law: elastic-slip Coulomb return mapping. ``e`` is the elastic tangential
displacement (the relative tangential displacement minus the stick anchor); trial
``e_tr = e_n + Δs``, ``F_T,tr = -k_T e_tr``. Sticking (status 3) if ``mu > 0`` and
``|F_T,tr| <= mu F_N``; otherwise sliding (status 2) with ``F_T = -mu F_N sign(e_tr)`` and
``e = -F_T / k_T``. ``F_T`` is the tangential component of the force on body a along ``t``;
the force on a is ``-F_N n + F_T t``, on b the opposite. Open (status 1): no force, ``e``
reset to 0. The generalised force on the local rows is ``p = (-F_N, F_T)``.

Parameters and books: :mod:`rubdiag._kernels.contact_books`; the slip record is ``x1``.
"""

from __future__ import annotations

from rubdiag._kernels.contact_books import K_N, K_T, MU, E, books, gap_at, record
from rubdiag._kernels.records import D_NEW, OPEN, SLIDING, STICKING, X_N
from rubdiag._numba import njit

__all__ = ["KIND", "N_LOCAL", "books", "force", "law"]

KIND = 1
N_LOCAL = 2


@njit(error_model="numpy", inline="always")
def force(x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n):
    """The law at the local displacement (x0, x1) (module docstring).

    Parameters
    ----------
    x0, x1 : float
        The relative displacement along the normal and the tangent (m).
    x0n, x1n : float
        The same at the step's start (m).
    g0 : float
        The gap parameter (m).
    kn, kt : float
        The normal and tangential stiffness (N/m).
    mu : float
        The Coulomb coefficient.
    lam : float
        The multiplier (N; 0 for pure penalty).
    e_n : float
        The elastic tangential displacement at the step's start (m).

    Returns
    -------
    tuple
        ``(p0, p1, j00, j01, j10, j11, status, fn, ft, e_new, e_tr, gap, z)``: the
        generalised force (N), its Jacobian ``dp/dx`` (N/m), the status, F_N (>= 0), F_T
        (signed) (N), the new and the trial elastic tangential displacement (m), the gap (m)
        and ``z = lam - k_N gap`` (N).
    """
    gap = g0 - x0
    z = lam - kn * gap
    if z <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, OPEN, 0.0, 0.0, 0.0, 0.0, gap, z
    fn = z
    e_tr = e_n + (x1 - x1n)
    ft_tr = -kt * e_tr
    if mu > 0.0 and abs(ft_tr) <= mu * fn:
        return -fn, ft_tr, -kn, 0.0, 0.0, -kt, STICKING, fn, ft_tr, e_tr, e_tr, gap, z
    sg = 1.0 if e_tr > 0.0 else (-1.0 if e_tr < 0.0 else 0.0)
    ft = -mu * fn * sg
    return -fn, ft, -kn, 0.0, -mu * kn * sg, 0.0, SLIDING, fn, ft, -ft / kt, e_tr, gap, z


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
    g1 = gap_at(parameters, e, progress[0].t_1, progress[0].h)
    x0 = local_work[D_NEW, r]
    x1 = local_work[D_NEW, r + 1]
    out = force(x0, x1, local_state[X_N, r], local_state[X_N, r + 1], g1, parameters[e, K_N],
                parameters[e, K_T], parameters[e, MU], trial[e].lam, element_state[0, e, E])
    record(e, r, local_work, jacobian, element_state, trial, out, x1)
    return out[6]

