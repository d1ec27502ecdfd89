"""The external load's factors: each group of load terms turns with its order k of the shaft.

A load term ``f(t) = Re(F z(t))`` (N) at one DOF has a complex amplitude F and a factor z(t)
that it shares with the other terms of its group (same order, law and table). At constant
speed z = e^{iωt}, ω = kΩ, and the amplitude law is already in F (the caller scales it).
Along a speed profile Ω(t) (piecewise linear, φ = ∫Ω dt exact) z follows the shaft angle,
z = a(t) e^{ikφ(t)}, with the amplitude law a(t) by ``LAW_*`` code:

* ``LAW_UNBALANCE``: ``a = (Ω² - iΩ'/k) / Ω₀²``. A mass eccentricity at angle kφ moves as
  ``e^{ikφ}``; its inertia force is ``-m e d²/dt² e^{ikφ} = m e (k²Ω² - ikΩ') e^{ikφ}``.
  Divided by its value at the reference speed Ω₀ (the profile's start, where F is given),
  ``(k²Ω₀²)``, this is ``(Ω² - iΩ'/k) / Ω₀² e^{ikφ}``; for k = 1 the unbalance of a shaft,
  ``(Ω² - iΩ') / Ω₀² e^{iφ}``, computed with the same operations as before orders existed
  (k = 1.0 multiplies and divides exactly), so today's runs keep their bits.
* ``LAW_CONSTANT``: ``a = 1`` (a load of fixed magnitude turning with kφ).
* ``LAW_TABLE``: ``a = A(Ω)``, linear in a table of (Ω, factor) knots, held constant
  outside it.

Constant speed is a profile of one knot (the factors are e^{iωt}, ω = kΩ in the group's row).
:func:`load_factors` evaluates every group's z at both ends of a step into ``group_factors``
(G, 4):
(Re z(t_n), Im z(t_n), Re z(t_1), Im z(t_1)), once per step (trigonometry once per group,
not per term: a projected load has a term per coordinate but one group).
"""

from __future__ import annotations

import math

from rubdiag._numba import njit

__all__ = ["LAW_CONSTANT", "LAW_TABLE", "LAW_UNBALANCE", "LW_CODE", "LW_OMEGA", "LW_ORDER",
           "load_factors", "shaft_at"]

LAW_UNBALANCE = 0
LAW_CONSTANT = 1
LAW_TABLE = 2

#: columns of a group's ``law`` row: ω = kΩ at constant speed (rad/s), the order k, the code
LW_OMEGA = 0
LW_ORDER = 1
LW_CODE = 2


@njit(error_model="numpy", inline="always")
def shaft_at(knots, t):
    """The shaft's speed, acceleration and angle at time t: Ω linear between the speed
    profile's knots, constant after the last, φ exact.

    Parameters
    ----------
    knots : ndarray (n_knots, 3)
        The profile's knots, rows (t (s), Ω (rad/s), φ (rad)).
    t : float
        The time (s).

    Returns
    -------
    tuple of float
        ``(Ω (rad/s), Ω' (rad/s²), φ (rad))``.
    """
    k = knots.shape[0] - 1
    while k > 0 and knots[k, 0] > t:  # the knots are few: a linear search from the end
        k -= 1
    tau = t - knots[k, 0]
    alpha = 0.0
    if k < knots.shape[0] - 1 and tau > 0.0:
        alpha = (knots[k + 1, 1] - knots[k, 1]) / (knots[k + 1, 0] - knots[k, 0])
    w = knots[k, 1] + alpha * tau
    phi = knots[k, 2] + knots[k, 1] * tau + 0.5 * alpha * tau * tau
    return w, alpha, phi


@njit(error_model="numpy", inline="always")
def _table(group_tables, g, w):
    """a(Ω) of group g at the speed w (rad/s): linear between the knots ``group_tables[g]``
    (n >= 2, 2) rows (Ω (rad/s), factor), Ω increasing strictly, constant outside them (the
    caller pads a table with knots of its last factor at higher speeds)."""
    n = group_tables.shape[1]
    j = 1
    while j < n - 1 and group_tables[g, j, 0] < w:
        j += 1
    x0, x1 = group_tables[g, j - 1, 0], group_tables[g, j, 0]
    a0, a1 = group_tables[g, j - 1, 1], group_tables[g, j, 1]
    u = min(max((w - x0) / (x1 - x0), 0.0), 1.0)
    return a0 + (a1 - a0) * u


@njit(error_model="numpy", inline="always")
def _factor(group_laws, group_tables, rotating, g, t, w, alpha, phi, w0):
    """``(Re z, Im z)`` of group g at time t (s) (module docstring): ``w``, ``alpha``, ``phi``
    the profile's Ω, Ω', φ there and ``w0`` = Ω₀². Every array is read on every path (a
    table lookup even where unused): an array read in one branch only brings Numba's
    reference counting back (6 increfs per call)."""
    k = group_laws[g, LW_ORDER]
    code = group_laws[g, LW_CODE]
    a_table = _table(group_tables, g, w)
    phase = group_laws[g, LW_OMEGA] * t
    if rotating:
        phase = k * phi
    c, s = math.cos(phase), math.sin(phase)
    if rotating:
        g_re, g_im = 1.0, 0.0
        if code == LAW_UNBALANCE:
            g_re, g_im = w * w / w0, -alpha / (k * w0)
        elif code == LAW_TABLE:
            g_re = a_table
        c, s = g_re * c - g_im * s, g_re * s + g_im * c
    return c, s


@njit(error_model="numpy")
def load_factors(group_laws, group_tables, speed_knots, t_n, t_1, group_factors):
    """Each group's factor z at t_n and t_1: e^{iωt} at constant speed (one knot), else
    following the profile's knots (module docstring).

    Parameters
    ----------
    group_laws : ndarray (G, 3)
        Each group's row (ω (rad/s), order k, ``LAW_*`` code).
    group_tables : ndarray (G, n_knots, 2)
        Each group's (Ω (rad/s), factor) knots.
    speed_knots : ndarray (n_knots, 3)
        The shaft's speed profile (:func:`shaft_at`).
    t_n, t_1 : float
        The step's ends (s).
    group_factors : ndarray (G, 4)
        ``(Re z(t_n), Im z(t_n), Re z(t_1), Im z(t_1))`` per group, written.
    """
    rotating = speed_knots.shape[0] > 1
    w0 = speed_knots[0, 1] * speed_knots[0, 1]
    w_n, alpha_n, phi_n = shaft_at(speed_knots, t_n)
    w_1, alpha_1, phi_1 = shaft_at(speed_knots, t_1)
    for g in range(group_factors.shape[0]):
        group_factors[g, 0], group_factors[g, 1] = _factor(group_laws, group_tables, rotating,
                                                           g, t_n, w_n, alpha_n, phi_n, w0)
        group_factors[g, 2], group_factors[g, 3] = _factor(group_laws, group_tables, rotating,
                                                           g, t_1, w_1, alpha_1, phi_1, w0)
