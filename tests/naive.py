"""Plain NumPy twins of the kernels, written from the definitions the kernels implement (not
from the kernels' code): ``tests/kernels/test_naive.py`` compares each kernel with its twin on
seeded random inputs.

* :func:`point_contact`, :func:`annular_contact` — the contact laws: a penalty normal force
  with the augmented Lagrangian's multiplier, ``F_N = max(0, λ - k_N g)``, and Coulomb
  friction by an elastic tangential spring with a return map onto the cone ``|F_T| <= μ F_N``
  (:func:`coulomb`), vectorized over samples;
* :func:`lu_solve` — ``A x = b`` from SuperLU's factors ``Pr A Pc = L U`` by dense triangular
  solves;
* :func:`newmark_step` — one step of Newmark's method in its textbook (total) form: the new
  displacement from the effective stiffness, then the acceleration and velocity.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.linalg import solve_triangular

from rubdiag._kernels.records import OPEN, SLIDING, STICKING

__all__ = ["Law", "annular_contact", "coulomb", "lu_solve", "newmark_step", "point_contact"]


class Law(NamedTuple):
    """A contact law's outputs per sample."""

    p: np.ndarray           # (N, 2) the generalised force on the local coordinates (N)
    status: np.ndarray      # OPEN, SLIDING or STICKING
    f_n: np.ndarray         # normal force, >= 0 (N)
    f_t: np.ndarray         # tangential force (N)
    e: np.ndarray           # the new elastic tangential displacement (m)
    e_trial: np.ndarray     # the trial one (m)
    gap: np.ndarray         # (m)


def coulomb(e_trial, f_n, k_t, mu):
    """Coulomb friction on an elastic tangential spring.

    The spring k_T carries the elastic tangential displacement e: the trial force ``-k_T
    e_trial`` holds (sticking) while it is inside the cone ``μ F_N`` (μ > 0); otherwise the
    contact slides with ``F_T = -μ F_N sign(e_trial)`` and the spring relaxes to what that
    force stretches, ``e = -F_T / k_T``.

    Returns ``(F_T, e, status)`` per sample.
    """
    f_trial = -k_t * e_trial
    stick = (mu > 0.0) & (np.abs(f_trial) <= mu * f_n)
    f_t = np.where(stick, f_trial, -mu * f_n * np.sign(e_trial))
    e = np.where(stick, e_trial, -f_t / k_t)
    return f_t, e, np.where(stick, STICKING, SLIDING)


def _law(normal, tangent, gap, lam, k_n, k_t, mu, e_trial):
    """The law along a normal and a tangent (N, 2) per sample: an open contact (no normal
    force) has no friction and a relaxed spring."""
    f_n = np.maximum(lam - k_n * gap, 0.0)
    f_t, e, status = coulomb(e_trial, f_n, k_t, mu)
    engaged = f_n > 0.0
    f_t = np.where(engaged, f_t, 0.0)
    p = -f_n[:, None] * normal + f_t[:, None] * tangent
    return Law(p, np.where(engaged, status, OPEN), f_n, f_t, np.where(engaged, e, 0.0),
               e_trial, gap)


def point_contact(x, x_start, gap0, k_n, k_t, mu, lam, e_start):
    """A point contact along a fixed normal (local coordinate 0) and tangent (1).

    ``x``, ``x_start`` (N, 2) the relative displacement now and at the step's start (m); the
    gap is ``g = gap0 - x_0``, the slip of the step ``x_1`` - its start. Returns a
    :class:`Law` with ``p = (-F_N, F_T)``.
    """
    ones = np.ones_like(x[:, 0])
    normal = np.column_stack([ones, 0.0 * ones])
    tangent = np.column_stack([0.0 * ones, ones])
    return _law(normal, tangent, gap0 - x[:, 0], lam, k_n, k_t, mu,
                e_start + (x[:, 1] - x_start[:, 1]))


def annular_contact(x, x_start, clearance, k_n, k_t, mu, lam, e_start, travel):
    """A shaft in a circular clearance; ``x``, ``x_start`` (N, 2) its displacement from the
    clearance's centre now and at the step's start (m).

    The normal turns with the shaft, ``n = x / |x|``, the tangent is n turned by +90°, the
    gap ``g = clearance - |x|``; the tangential slip of the step is the tangent's share of
    the displacement plus the surface ``travel`` Ω R h (m). Returns a :class:`Law` with
    ``p = -F_N n + F_T t``.
    """
    r = np.hypot(x[:, 0], x[:, 1])
    normal = x / r[:, None]
    tangent = np.column_stack([-normal[:, 1], normal[:, 0]])
    slip = np.einsum("ij,ij->i", tangent, x - x_start) + travel
    return _law(normal, tangent, clearance - r, lam, k_n, k_t, mu, e_start + slip)


def lu_solve(factors, b):
    """``A x = b`` from the SuperLU factors of A (:func:`rubdiag._kernels.sparse_lu.factorize`):
    ``Pr A Pc = L U``, so ``x = Pc U⁻¹ L⁻¹ Pr b``, with dense triangular solves."""
    lu = factors.splu
    n = b.shape[0]
    pr = sp.csc_matrix((np.ones(n), (lu.perm_r, np.arange(n))), shape=(n, n))
    pc = sp.csc_matrix((np.ones(n), (np.arange(n), lu.perm_c)), shape=(n, n))
    y = solve_triangular(lu.L.toarray(), pr @ b, lower=True)
    return pc @ solve_triangular(lu.U.toarray(), y, lower=False)


def newmark_step(M, C, K, f_end, q, v, a, h, beta=0.25, gamma=0.5):
    """One Newmark step of ``M q'' + C q' + K q = f`` from (q, v, a) in the textbook form.

    With ``a_1 = (q_1 - q - h v) / (β h²) - (1/(2β) - 1) a`` and ``v_1 = v + h ((1 - γ) a
    + γ a_1)``, equilibrium at the step's end is ``K_eff q_1 = f_1 + M (q / (β h²) + v / (β
    h) + (1/(2β) - 1) a) + C (γ / (β h) q + (γ/β - 1) v + h (γ / (2β) - 1) a)`` with ``K_eff
    = K + γ / (β h) C + M / (β h²)``. Returns ``(q_1, v_1, a_1)``.
    """
    k_eff = K + gamma / (beta * h) * C + M / (beta * h * h)
    rhs = (f_end + M @ (q / (beta * h * h) + v / (beta * h) + (0.5 / beta - 1.0) * a)
           + C @ (gamma / (beta * h) * q + (gamma / beta - 1.0) * v
                  + h * (0.5 * gamma / beta - 1.0) * a))
    q1 = np.linalg.solve(k_eff, rhs)
    a1 = (q1 - q - h * v) / (beta * h * h) - (0.5 / beta - 1.0) * a
    v1 = v + h * ((1.0 - gamma) * a + gamma * a1)
    return q1, v1, a1
