"""Contact-law kernels: one element's law and the per-step Schur-complement contact solve.

Element kinds (int codes, see :mod:`rubdiag.simulate.system` for the Python description):

* ``KIND_POINT = 1`` — point–point element (the study's Conta178). Local coordinates are the
  relative displacement ``u_a - u_b`` projected on the fixed normal ``n`` (``x0``) and tangent
  ``t`` (``x1``); gap ``g = g0 - x0``; relative tangential displacement ``s = x1``.
* ``KIND_ANNULAR = 2`` — shaft–stator annular clearance. Local coordinates are the Cartesian
  relative displacement (``x0 = y``, ``x1 = z``); ``r = |x|``, normal ``n = x / r`` (outward),
  tangent ``t = (-n_z, n_y)``; gap ``g = c - r``. The tangential slip per step includes the
  shaft surface travel ``Omega R dt`` (``drive`` below).

Normal law (paper eqs (1)–(2)): with the multiplier ``lam`` (0 for pure penalty),
``z = lam - k_N g`` and ``F_N = max(0, z)`` (compressive magnitude). For ``lam = 0`` this is
exactly eq. (1): ``F_N = 0`` if ``g > 0`` else ``-k_N g``.

Tangential law: elastic-slip Coulomb return mapping. ``e`` is the elastic tangential
displacement (relative tangential displacement minus the stick anchor). Trial
``e_tr = e_n + Δs``; ``F_T,tr = -k_T e_tr``. Stick (status 3) if ``mu > 0`` and
``|F_T,tr| <= mu F_N``; otherwise slip (status 2) with ``F_T = -mu F_N sign(e_tr)`` and
``e = -F_T / k_T``. ``F_T`` is the signed tangential component of the force *on body a*
(blade tip / shaft) along ``t``; the force on a is ``-F_N n + F_T t`` and on b the opposite.
Status 1 (open) means ``F_N = F_T = 0`` and resets ``e`` to 0.

In the local coordinates the generalized contact force on the B rows is
``p = (-F_N, F_T)`` (kind 1) or ``p = -F_N n + F_T t`` (kind 2).
"""

from __future__ import annotations

import math

import numpy as np

from rubdiag._numba import njit

KIND_POINT = 1
KIND_ANNULAR = 2

OPEN = 1
SLIDING = 2
STICKING = 3

# codes returned by solve_contact
CONVERGED = 0
NEWTON_FAILED = 1
AUGMENT_FAILED = 2
SINGULAR = 3
AUGMENT_PENDING = 4  # accepted although the band was not reached (aug_strict off)
NONFINITE = 5  # non-finite contact displacements or forces

__all__ = [
    "AUGMENT_FAILED",
    "AUGMENT_PENDING",
    "CONVERGED",
    "KIND_ANNULAR",
    "KIND_POINT",
    "NEWTON_FAILED",
    "NONFINITE",
    "OPEN",
    "SINGULAR",
    "SLIDING",
    "STICKING",
    "element_law",
    "solve_contact",
]


_PLAIN_NEWTON = 8          # full Newton steps before some relaxed ones
_RELAX = (0.5, 0.3, 0.7)   # varied, so that a relaxed step cannot fall into a cycle of its own


@njit
def element_law(kind, x0, x1, x0n, x1n, g0, kn, kt, mu, lam, e_n, drive):
    """Evaluate one element's contact law.

    Arguments: kind code; local relative displacement at the end of the step (x0, x1) and at
    its start (x0n, x1n) (m); current gap/clearance g0 (m); k_N, k_T (N/m); mu; multiplier lam
    (N); elastic tangential displacement at the step start e_n (m); drive = Omega R dt (m,
    kind 2 only).

    Returns ``(p0, p1, j00, j01, j10, j11, status, fn, ft, e_new, e_tr, gap, z)``: the
    generalized force on the two local rows, its Jacobian ``dp/dx``, the status code, F_N (N,
    >= 0), F_T (N, signed), the new elastic tangential displacement, the trial one, the gap
    (m) and the normal trial force ``z = lam - k_N gap`` (closed iff z > 0).
    """
    if kind == KIND_POINT:
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
    # annular clearance
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


@njit
def _dense_solve(A, b, m, piv):
    """Solve the leading m x m block ``A x = b`` in place (b <- x) by LU with partial pivoting.

    Returns False if A is numerically singular.
    """
    for k in range(m):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        if amax == 0.0 or not np.isfinite(amax):
            return False
        piv[k] = p
        if p != k:
            for j in range(m):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, m):
            f = A[i, k] * inv
            if f != 0.0:
                A[i, k] = f
                for j in range(k + 1, m):
                    A[i, j] -= f * A[k, j]
                b[i] -= f * b[k]
    for i in range(m - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, m):
            acc -= A[i, j] * b[j]
        b[i] = acc / A[i, i]
    return True


@njit
def solve_contact(
    W, d_lin, p_n, d_n, kind, g0, kn, kt, mu, aug, eps, lam, e_n, drive, aug_k, aug_shift,
    max_newton, max_aug, aug_strict, tol,
    d, p, jac, cres, status, iwork, wm, wv, wv2,
):
    """Solve the contact problem of one Newmark step in the Schur complement.

    Unknown: the local contact displacements ``d`` (2 n_c). With ``d_lin`` the contact
    displacements of the linear predictor (contact forces frozen at ``p_n``) and ``W = B
    K_eff^-1 B^T``, the step's contact problem is ``R(d) = d - d_lin - W (p(d) - p_n) = 0``,
    solved by (semi-smooth) Newton with ``J = I - W dp/dd``. Only the rows of elements whose law
    has a non-zero Jacobian enter the dense solve; the other rows are updated explicitly.

    Augmented Lagrangian (eq. 2): after each converged Newton solve, every closed element
    with ``aug[e] != 0`` and ``|gap| >= eps[e]`` updates ``lam[e] <- max(0, lam[e] -
    aug_k[e] (gap + aug_shift eps[e]))`` and the Newton solve is repeated, until every closed
    augmented element is in the band ``-eps < g <= 0`` (or ``max_aug`` updates; then
    ``AUGMENT_FAILED`` if ``aug_strict`` else ``AUGMENT_PENDING``). Eq. (2) literally is
    ``aug_k = k_N``, ``aug_shift = 0``: its iterates creep towards ``g = 0`` by a factor
    ``1 / (1 + k_N W_ee)`` per update and stop just inside the band. A larger ``aug_k`` (up to
    the step's dynamic stiffness at the contact) gets there in a few updates; aiming at
    ``-aug_shift eps`` instead of 0 keeps the landing point near where eq. (2) stops instead
    of pulling the contact to ``g = 0`` within one step (which, with the trapezoidal rule,
    injects a large spurious rebound).
    ``lam`` is updated in place (the caller passes a scratch copy).

    Outputs (preallocated): ``d``, ``p`` (2 n_c); ``cres`` (7, n_c) rows
    ``fn, ft, e_new, e_tr, gap, z, unused``; ``status`` (n_c); work ``iwork`` (>= 2 n_c + 2 n_c),
    ``wm`` (2 n_c, 2 n_c), ``jac`` (n_c, 4), ``wv``, ``wv2`` (2 n_c).

    Returns ``(code, newton_iterations, augment_updates, worst_row)``.
    """
    m2 = d_lin.shape[0]
    nc = m2 // 2
    for i in range(m2):
        d[i] = d_lin[i]
    n_it = 0
    n_aug = 0
    worst = -1
    act = iwork[:m2]
    piv = iwork[m2 : 2 * m2]
    while True:
        it = 0
        while True:
            # law evaluation
            na = 0
            for e in range(nc):
                out = element_law(
                    kind[e], d[2 * e], d[2 * e + 1], d_n[2 * e], d_n[2 * e + 1],
                    g0[e], kn[e], kt[e], mu[e], lam[e], e_n[e], drive[e],
                )
                p[2 * e] = out[0]
                p[2 * e + 1] = out[1]
                jac[e, 0] = out[2]
                jac[e, 1] = out[3]
                jac[e, 2] = out[4]
                jac[e, 3] = out[5]
                status[e] = out[6]
                cres[0, e] = out[7]
                cres[1, e] = out[8]
                cres[2, e] = out[9]
                cres[3, e] = out[10]
                cres[4, e] = out[11]
                cres[5, e] = out[12]
                if out[6] != OPEN:
                    act[na] = e
                    na += 1
            # residual R = d - d_lin - W (p - p_n)
            for i in range(m2):
                wv2[i] = p[i] - p_n[i]
            rmax = 0.0
            worst = -1
            for i in range(m2):
                acc = d[i] - d_lin[i]
                for j in range(m2):
                    if wv2[j] != 0.0:
                        acc -= W[i, j] * wv2[j]
                wv[i] = -acc
                if not abs(acc) <= rmax:  # also catches NaN
                    rmax = abs(acc)
                    worst = i
            if rmax <= tol:
                break
            if not np.isfinite(rmax):
                return NONFINITE, n_it, n_aug, worst
            if it >= max_newton:
                return NEWTON_FAILED, n_it, n_aug, worst
            # Newton step: (I - W Jp) delta = -R ; Jp nonzero only in active 2x2 blocks
            ma = 2 * na
            for ii in range(ma):
                ei = act[ii // 2]
                ri = 2 * ei + (ii % 2)
                for jj in range(ma):
                    ej = act[jj // 2]
                    cj = jj % 2
                    # (W Jp)[ri, 2 ej + cj] = W[ri, 2ej] J[ej][0, cj] + W[ri, 2ej+1] J[ej][1, cj]
                    v = W[ri, 2 * ej] * jac[ej, cj] + W[ri, 2 * ej + 1] * jac[ej, 2 + cj]
                    wm[ii, jj] = -v
                wm[ii, ii] += 1.0
            # right-hand side for the active rows (stored in the first ma slots of wv2)
            for ii in range(ma):
                ei = act[ii // 2]
                wv2[ii] = wv[2 * ei + (ii % 2)]
            if ma > 0:
                if not _dense_solve(wm, wv2, ma, piv):
                    return SINGULAR, n_it, n_aug, worst
            # explicit rows: delta_i = -R_i + sum_active (W Jp)_ij delta_j
            for i in range(m2):
                acc = wv[i]
                for jj in range(ma):
                    ej = act[jj // 2]
                    cj = jj % 2
                    wj = W[i, 2 * ej] * jac[ej, cj] + W[i, 2 * ej + 1] * jac[ej, 2 + cj]
                    acc += wj * wv2[jj]
                wv[i] = acc
            # active rows take the solved values (identical up to round-off)
            for ii in range(ma):
                ei = act[ii // 2]
                wv[2 * ei + (ii % 2)] = wv2[ii]
            # Semi-smooth Newton can cycle between stick and slip at the Coulomb kink;
            # relaxed steps after the first few iterations break the cycle.
            relax = _RELAX[(it // 3) % 3] if it >= _PLAIN_NEWTON and it % 3 == 2 else 1.0
            for i in range(m2):
                d[i] += relax * wv[i]
            it += 1
            n_it += 1
        # augmentation
        changed = False
        for e in range(nc):
            g = cres[4, e]
            if aug[e] != 0 and status[e] != OPEN and (g <= -eps[e] or g > 0.0):
                # aim inside the band -eps < g <= 0 rather than at g = 0 (see docstring)
                newlam = lam[e] - aug_k[e] * (g + aug_shift * eps[e])
                lam[e] = newlam if newlam > 0.0 else 0.0
                changed = True
        if not changed:
            return CONVERGED, n_it, n_aug, -1
        if n_aug >= max_aug and not aug_strict:
            # the updated multipliers act from the next step on
            return AUGMENT_PENDING, n_it, n_aug, -1
        if n_aug >= max_aug:
            worst = -1
            pmax = -1.0
            for e in range(nc):
                if status[e] != OPEN and abs(cres[4, e]) > pmax:
                    pmax = abs(cres[4, e])
                    worst = 2 * e
            return AUGMENT_FAILED, n_it, n_aug, worst
        n_aug += 1
